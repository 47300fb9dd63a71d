//! TRaX-Rust language suite, part 7: Rust's float methods backed by the prelude's math
//! library (`trax::libm`): `sin cos tan sin_cos asin acos atan atan2 exp exp2 ln log2
//! log10 powf powi hypot cbrt` for f32 and f64. On the machine the compiler calls
//! `trax::libm`; natively std's methods reach the same code under the C names
//! (`libm_host.rs`), so every result has the same bits.
//!
//! Inputs come from a generator seeded with global register 0 (0 at run time), so no
//! call has constant arguments (rustc would fold those with the host's libm). Each line
//! is one method: a few results with `{:?}` and a hash of 256 results' bits.

/// xorshift32, seeded at run time.
struct Gen {
    s: u32,
}

impl Gen {
    fn next(&mut self) -> u32 {
        let mut x = self.s;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.s = x;
        x
    }

    /// A float in [lo, hi).
    fn f32_in(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next() >> 8) as f32 * (1.0 / 16777216.0);
        lo + (hi - lo) * u
    }

    fn f64_in(&mut self, lo: f64, hi: f64) -> f64 {
        let u = ((self.next() as u64) << 21 ^ (self.next() as u64)) as f64 * (1.0 / 9007199254740992.0);
        lo + (hi - lo) * u
    }
}

fn mix(h: u64, bits: u64) -> u64 {
    (h ^ bits).wrapping_mul(0x100_0000_01b3).rotate_left(7)
}

/// Runs `f` on 256 inputs in [lo, hi) (and `y` in [ylo, yhi)); prints 3 results and a hash.
fn check32<F: Fn(f32, f32) -> f32>(name: &str, g: &mut Gen, lo: f32, hi: f32, ylo: f32, yhi: f32, f: F) {
    let mut h = 0u64;
    let mut shown = [0.0f32; 3];
    for i in 0..256 {
        let x = g.f32_in(lo, hi);
        let y = g.f32_in(ylo, yhi);
        let r = f(x, y);
        if i < 3 {
            shown[i] = r;
        }
        h = mix(h, r.to_bits() as u64);
    }
    println!("f32 {}: {:?} {:?} {:?} hash {:016x}", name, shown[0], shown[1], shown[2], h);
}

fn check64<F: Fn(f64, f64) -> f64>(name: &str, g: &mut Gen, lo: f64, hi: f64, ylo: f64, yhi: f64, f: F) {
    let mut h = 0u64;
    let mut shown = [0.0f64; 3];
    for i in 0..256 {
        let x = g.f64_in(lo, hi);
        let y = g.f64_in(ylo, yhi);
        let r = f(x, y);
        if i < 3 {
            shown[i] = r;
        }
        h = mix(h, r.to_bits());
    }
    println!("f64 {}: {:?} {:?} {:?} hash {:016x}", name, shown[0], shown[1], shown[2], h);
}

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let mut g = Gen {
        s: 0x9e37_79b9 ^ trax::global_read(0),
    };
    let g = &mut g;
    check32("sin", g, -10.0, 10.0, 0.0, 1.0, |x, _| x.sin());
    check32("sin big", g, -1e6, 1e6, 0.0, 1.0, |x, _| x.sin());
    check32("cos", g, -10.0, 10.0, 0.0, 1.0, |x, _| x.cos());
    check32("tan", g, -3.0, 3.0, 0.0, 1.0, |x, _| x.tan());
    check32("sin_cos", g, -7.0, 7.0, 0.0, 1.0, |x, _| {
        let (s, c) = x.sin_cos();
        s - c
    });
    check32("asin", g, -1.0, 1.0, 0.0, 1.0, |x, _| x.asin());
    check32("acos", g, -1.0, 1.0, 0.0, 1.0, |x, _| x.acos());
    check32("atan", g, -50.0, 50.0, 0.0, 1.0, |x, _| x.atan());
    check32("atan2", g, -5.0, 5.0, -5.0, 5.0, |x, y| x.atan2(y));
    check32("exp", g, -80.0, 80.0, 0.0, 1.0, |x, _| x.exp());
    check32("exp2", g, -120.0, 120.0, 0.0, 1.0, |x, _| x.exp2());
    check32("ln", g, 0.0, 1000.0, 0.0, 1.0, |x, _| x.ln());
    check32("log2", g, 0.0, 10.0, 0.0, 1.0, |x, _| x.log2());
    check32("log10", g, 0.0, 1e6, 0.0, 1.0, |x, _| x.log10());
    check32("powf", g, 0.0, 4.0, -8.0, 8.0, |x, y| x.powf(y));
    check32("powf neg", g, -4.0, 0.0, -8.0, 8.0, |x, y| x.powf(y.round()));
    check32("powi", g, -3.0, 3.0, -12.0, 12.0, |x, y| x.powi(y as i32));
    check32("hypot", g, -1e20, 1e20, -1e20, 1e20, |x, y| x.hypot(y));
    check32("cbrt", g, -1e9, 1e9, 0.0, 1.0, |x, _| x.cbrt());
    check32("sqrt", g, 0.0, 1e9, 0.0, 1.0, |x, _| x.sqrt());
    check64("sin", g, -10.0, 10.0, 0.0, 1.0, |x, _| x.sin());
    check64("sin big", g, -1e12, 1e12, 0.0, 1.0, |x, _| x.sin());
    check64("cos", g, -10.0, 10.0, 0.0, 1.0, |x, _| x.cos());
    check64("tan", g, -3.0, 3.0, 0.0, 1.0, |x, _| x.tan());
    check64("sin_cos", g, -7.0, 7.0, 0.0, 1.0, |x, _| {
        let (s, c) = x.sin_cos();
        s * 3.0 - c
    });
    check64("asin", g, -1.0, 1.0, 0.0, 1.0, |x, _| x.asin());
    check64("acos", g, -1.0, 1.0, 0.0, 1.0, |x, _| x.acos());
    check64("atan", g, -50.0, 50.0, 0.0, 1.0, |x, _| x.atan());
    check64("atan2", g, -5.0, 5.0, -5.0, 5.0, |x, y| x.atan2(y));
    check64("exp", g, -700.0, 700.0, 0.0, 1.0, |x, _| x.exp());
    check64("exp2", g, -1000.0, 1000.0, 0.0, 1.0, |x, _| x.exp2());
    check64("ln", g, 0.0, 1e10, 0.0, 1.0, |x, _| x.ln());
    check64("log2", g, 0.0, 10.0, 0.0, 1.0, |x, _| x.log2());
    check64("log10", g, 0.0, 1e6, 0.0, 1.0, |x, _| x.log10());
    check64("powf", g, 0.0, 4.0, -30.0, 30.0, |x, y| x.powf(y));
    check64("powi", g, -3.0, 3.0, -40.0, 40.0, |x, y| x.powi(y as i32));
    check64("hypot", g, -1e200, 1e200, -1e200, 1e200, |x, y| x.hypot(y));
    check64("cbrt", g, -1e300, 1e300, 0.0, 1.0, |x, _| x.cbrt());
    let x = g.f32_in(0.5, 0.6);
    let d = g.f64_in(0.5, 0.6);
    println!("{:?} {:?} {:?} {:?}", x.sin(), x.powf(2.5), d.cos(), d.powi(-3));
}
