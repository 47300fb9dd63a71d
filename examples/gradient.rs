//! A colour gradient: red grows to the right, green grows downwards, blue is constant.
//! Threads take pixels one at a time from global register 0.

fn trax_main() {
    let w = trax::scene::width();
    let h = trax::scene::height();
    let n = w * h;
    let inv_w = trax::scene::inv_width();
    let inv_h = trax::scene::inv_height();
    // Pixels come from global register 0 (sampled simulation follows it).
    trax::declare_work(0, n);
    loop {
        let i = trax::atomic_inc(0);
        if i >= n {
            break;
        }
        let x = i % w;
        let y = i / w;
        let r = (x as f32 + 0.5) * inv_w;
        let g = (y as f32 + 0.5) * inv_h;
        trax::set_pixel(x, y, trax::Vec3::new(r, g, 0.25));
    }
}
