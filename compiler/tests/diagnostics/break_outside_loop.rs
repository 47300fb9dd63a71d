fn trax_main() {
    break;
}
