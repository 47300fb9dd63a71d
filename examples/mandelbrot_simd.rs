//! The Mandelbrot set four pixels at a time with `f32x4` (MSA on TRaX): one
//! `atomic_inc` hands out four consecutive pixels. Same image as `mandelbrot.rs`.

use trax::simd::{f32x4, i32x4};

const MAX_ITER: u32 = 100;

fn palette(n: u32) -> trax::Vec3 {
    if n >= MAX_ITER {
        return trax::Vec3::zero();
    }
    let t = n as f32 / MAX_ITER as f32;
    trax::Vec3::new(t.sqrt(), t, 0.5 + 0.5 * t)
}

fn trax_main() {
    let w = trax::scene::width();
    let h = trax::scene::height();
    let n = w * h;
    let groups = (n + 3) / 4;
    let sx = 3.0 * trax::scene::inv_width();
    let sy = 2.5 * trax::scene::inv_height();
    // Groups of four pixels come from global register 0 (sampled simulation follows it).
    trax::declare_work(0, groups);
    loop {
        let g = trax::atomic_inc(0);
        if g >= groups {
            break;
        }
        let base = g * 4;
        let mut cxs = [0.0f32; 4];
        let mut cys = [0.0f32; 4];
        for k in 0..4usize {
            let i = base + k as u32;
            let x = i % w;
            let y = i / w;
            cxs[k] = -2.25 + (x as f32 + 0.5) * sx;
            cys[k] = 1.25 - (y as f32 + 0.5) * sy;
        }
        let cx = f32x4::new(cxs[0], cxs[1], cxs[2], cxs[3]);
        let cy = f32x4::new(cys[0], cys[1], cys[2], cys[3]);
        let four = f32x4::splat(4.0);
        let one = i32x4::splat(1);
        let mut zx = f32x4::splat(0.0);
        let mut zy = f32x4::splat(0.0);
        let mut count = i32x4::splat(0);
        let mut iter = 0u32;
        while iter < MAX_ITER {
            let zx2 = zx * zx;
            let zy2 = zy * zy;
            // Lanes still iterating: |z|^2 <= 4 (as the scalar loop's `> 4` exit).
            let active = (zx2 + zy2).le(four);
            if !active.any() {
                break;
            }
            count = count + (active & one);
            let nzx = zx2 - zy2 + cx;
            let nzy = (zx + zx) * zy + cy;
            zx = f32x4::select(active, nzx, zx);
            zy = f32x4::select(active, nzy, zy);
            iter += 1;
        }
        for k in 0..4usize {
            let i = base + k as u32;
            if i < n {
                trax::set_pixel(i % w, i / w, palette(count.get(k) as u32));
            }
        }
    }
}
