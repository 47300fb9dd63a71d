fn trax_main() {
    3 = 4;
}
