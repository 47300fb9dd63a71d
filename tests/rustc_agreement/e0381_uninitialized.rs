// A variable used before it is initialised on every path.
fn trax_main() {
    let x: u32;
    if trax::global_id() == 0 {
        x = 1;
    }
    println!("{}", x); //~ E0381
}
