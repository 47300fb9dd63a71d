const A: u32 = B + 1;
const B: u32 = A;

fn trax_main() {
    let x = A;
}
