// A reference to a temporary kept past the statement.
fn make() -> [u32; 2] {
    [1, 2]
}

fn first(a: &[u32; 2]) -> &u32 {
    &a[0]
}

fn trax_main() {
    let r = first(&make()); //~ E0716
    println!("{}", r);
}
