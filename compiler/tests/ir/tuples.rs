fn split(p: (u32, f32)) -> (f32, u32) {
    let (a, b) = p;
    (b, a)
}

fn trax_main() {
    let (x, y) = split((trax::global_id(), 1.5));
    trax::store_f32(0, x + y as f32);
}
