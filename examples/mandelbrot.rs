//! The Mandelbrot set, one pixel per `atomic_inc`, scalar f32, at most 100 iterations.
//! `mandelbrot_simd.rs` computes the same image four pixels at a time.

const MAX_ITER: u32 = 100;

/// Colour of a point that escaped after `n` iterations (black inside the set).
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
    let sx = 3.0 * trax::scene::inv_width();
    let sy = 2.5 * trax::scene::inv_height();
    // Pixels come from global register 0 (sampled simulation follows it).
    trax::declare_work(0, n);
    loop {
        let i = trax::atomic_inc(0);
        if i >= n {
            break;
        }
        let x = i % w;
        let y = i / w;
        let cx = -2.25 + (x as f32 + 0.5) * sx;
        let cy = 1.25 - (y as f32 + 0.5) * sy;
        let mut zx = 0.0f32;
        let mut zy = 0.0f32;
        let mut iter = 0u32;
        while iter < MAX_ITER {
            let zx2 = zx * zx;
            let zy2 = zy * zy;
            if zx2 + zy2 > 4.0 {
                break;
            }
            let nzx = zx2 - zy2 + cx;
            zy = (zx + zx) * zy + cy;
            zx = nzx;
            iter += 1;
        }
        trax::set_pixel(x, y, palette(iter));
    }
}
