// Each closure expression has its own type.
fn trax_main() {
    let fs = [|x: i32| x + 1, |x: i32| x + 2];
}
