#[derive(Clone, Copy, Hash)]
struct Key {
    id: u32,
}

fn trax_main() {}
