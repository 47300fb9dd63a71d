fn trax_main() {
    let s = format!("{}", 1);
}
