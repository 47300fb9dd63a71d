fn sum(xs: &[f32]) -> f32 {
    let mut s = 0.0;
    for (i, x) in xs.iter().enumerate() {
        s += x * i as f32;
    }
    s
}

fn trax_main() {
    let a = [1.0f32, 2.0, 3.0, 4.0];
    let k = trax::global_id() as usize;
    trax::store_f32(0, sum(&a[..k]) + a[k]);
}
