// Integer ranges that leave values out.
fn class(x: u8) -> u32 {
    match x { //~ E0004
        0..=9 => 0,
        10..=99 => 1,
        101..=255 => 2,
    }
}

fn trax_main() {
    println!("{}", class(100));
}
