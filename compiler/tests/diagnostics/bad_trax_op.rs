fn trax_main() {
    let x = __trax_op!("trax.nope");
}
