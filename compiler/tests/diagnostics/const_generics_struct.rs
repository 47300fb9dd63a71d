// One error for the struct's const parameter (it was reported twice).
struct Buffer<const N: usize> {
    data: [u32; N],
}

fn trax_main() {}
