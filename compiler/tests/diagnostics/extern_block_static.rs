// C globals are not importable: pass data through functions or the scene.
extern "C" {
    static TABLE: [f32; 4];
}

fn trax_main() {}
