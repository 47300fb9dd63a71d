// A reference that outlives the value it points to.
fn trax_main() {
    let r;
    {
        let x = 5u32;
        r = &x; //~ E0597
    }
    println!("{}", r);
}
