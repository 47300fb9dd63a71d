//! Exercises the compiler builtins used by the prelude's TRaX side: `__trax_op!`,
//! `__trax_mtc2!`/`__trax_mfc2!`, `__trax_symbol_addr!`, and the SIMD types.

use trax::simd::{f32x4, i32x4};

fn simd(seed: f32) -> f32 {
    let a = f32x4::new(seed, 1.0, 2.0, 3.0);
    let b = f32x4::splat(0.5);
    let c = (a + b) * b - a / f32x4::splat(4.0);
    let d = c.min(a).max(-a).sqrt().abs().mul_add(b, a);
    let m = d.lt(b) & d.le(a) | d.gt(b) ^ d.ge(a);
    let e = f32x4::select(m, d, -d);
    let i = e.to_i32x4() + i32x4::splat(1) * i32x4::new(1, 2, 3, 4) - i32x4::splat(2);
    let any = m.any() || m.all() || d.eq(a).any();
    let f = i32x4::select(m, i, i).to_f32x4();
    if any {
        f.get(0) + f.get(3)
    } else {
        e.get(1)
    }
}

fn trax_main() {
    let id: u32 = __trax_op!("trax.gid");
    let r: f32 = __trax_op!("trax.rand");
    let old = __trax_op!("trax.atominc", 3);
    let m = __trax_op!("trax.fmin", r, 0.5);
    __trax_op!("trax.stat", 7);
    __trax_mtc2!(0, r);
    __trax_mtc2!(5, m);
    let t = __trax_op!("trax.tritest");
    let u = __trax_mfc2!(21);
    let fb = __trax_symbol_addr!("__trax_scene_framebuffer");
    println!("{} {} {} {} {} {}", id, old, t, u, fb, simd(r));
    if id > 1000 {
        __trax_op!("trax.halt");
    }
}
