fn apply<F: Fn(f32) -> f32>(f: F, x: f32) -> f32 {
    f(x)
}

fn trax_main() {
    let k = trax::rand();
    let mut n = 0u32;
    let mut bump = |by: u32| n += by;
    bump(2);
    trax::store_f32(0, apply(|x| x * k, 2.0));
    trax::store_u32(4, n);
}
