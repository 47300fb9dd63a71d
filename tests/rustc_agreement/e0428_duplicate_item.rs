// Two items with one name.
fn shade() -> u32 {
    1
}

fn shade() -> u32 { //~ E0428
    2
}

fn trax_main() {
    println!("{}", shade());
}
