struct Scene {
    names: Vec<u32>,
}

fn trax_main() {}
