// `Option` matched without `None`.
fn first(a: Option<u32>) -> u32 {
    match a { //~ E0004
        Some(x) => x,
    }
}

fn trax_main() {
    println!("{}", first(None));
}
