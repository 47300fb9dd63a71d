fn trax_main() {
    let x = 1;
}
}
