//! Accuracy measurement of `trax::libm` (the prelude's `libm.rs`, host build) against
//! the host's libm, shared by `tests/libm_host.rs` (a few million points per function)
//! and `benches/libm_ulp.rs` (every f32 input of the unary f32 functions).
//!
//! Reference: the host libm's *f64* function (Rust std, glibc on Linux) at the same
//! (exactly converted) input. For the f32 functions that is ~2^-29 f32 ULP from the
//! exact value, so the f32 error is measured as a real number of ULPs. For the f64
//! functions the reference is the host's own f64 result (glibc: within about 1 ULP, most
//! functions correctly rounded or nearly), so the figure is the distance to glibc.

#![allow(dead_code)]

/// Error figures of one function.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Points measured.
    pub n: u64,
    /// Largest error in ULPs.
    pub max: f64,
    /// Sum of errors (for the mean).
    pub sum: f64,
    /// The input of the largest error.
    pub worst: String,
    /// Points where a special result (NaN, infinity, signed zero) disagreed.
    pub special_mismatches: u64,
    /// The first such input.
    pub first_mismatch: String,
}

impl Stats {
    /// Adds one point: `err` from [`ulp32`]/[`ulp64`], `what` names the input.
    pub fn add(&mut self, err: Option<f64>, what: impl FnOnce() -> String) {
        self.n += 1;
        match err {
            Some(e) => {
                self.sum += e;
                if e > self.max {
                    self.max = e;
                    self.worst = what();
                }
            }
            None => {
                self.special_mismatches += 1;
                if self.first_mismatch.is_empty() {
                    self.first_mismatch = what();
                }
            }
        }
    }

    /// Merges another partial result.
    pub fn merge(&mut self, o: &Stats) {
        self.n += o.n;
        self.sum += o.sum;
        if o.max > self.max {
            self.max = o.max;
            self.worst = o.worst.clone();
        }
        self.special_mismatches += o.special_mismatches;
        if self.first_mismatch.is_empty() {
            self.first_mismatch = o.first_mismatch.clone();
        }
    }

    /// Mean error in ULPs.
    pub fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum / self.n as f64
        }
    }
}

/// Error of an f32 result in ULPs of the exact value `reference` (given in f64). `None`
/// when a special result disagrees: NaN vs number, an infinity vs anything else, or
/// zeros of different signs.
pub fn ulp32(got: f32, reference: f64) -> Option<f64> {
    if reference.is_nan() || got.is_nan() {
        return if reference.is_nan() && got.is_nan() {
            Some(0.0)
        } else {
            None
        };
    }
    let r32 = reference as f32;
    if r32.is_infinite() || got.is_infinite() {
        return if r32.to_bits() == got.to_bits() {
            Some(0.0)
        } else {
            None
        };
    }
    if got == 0.0 && r32 == 0.0 {
        return if got.to_bits() == r32.to_bits() {
            Some(0.0)
        } else {
            None
        };
    }
    let e = exponent(reference).max(-126);
    Some((got as f64 - reference).abs() / p2(e - 23))
}

/// Error of an f64 result in ULPs, against the f64 `reference`; `None` as in [`ulp32`].
pub fn ulp64(got: f64, reference: f64) -> Option<f64> {
    if reference.is_nan() || got.is_nan() {
        return if reference.is_nan() && got.is_nan() {
            Some(0.0)
        } else {
            None
        };
    }
    if reference.is_infinite() || got.is_infinite() {
        return if reference.to_bits() == got.to_bits() {
            Some(0.0)
        } else {
            None
        };
    }
    if got == 0.0 && reference == 0.0 {
        return if got.to_bits() == reference.to_bits() {
            Some(0.0)
        } else {
            None
        };
    }
    let e = exponent(reference).max(-1022);
    Some((got - reference).abs() / p2(e - 52))
}

/// 2^e, -1074 <= e <= 1023.
pub fn p2(e: i32) -> f64 {
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (e + 1074))
    }
}

/// floor(log2 |x|) for finite nonzero x (subnormals included).
fn exponent(x: f64) -> i32 {
    let b = x.to_bits() & 0x7FFF_FFFF_FFFF_FFFF;
    let e = (b >> 52) as i32;
    if e == 0 {
        -1022 - ((b << 12).leading_zeros() as i32) - 1
    } else {
        e - 1023
    }
}

/// SplitMix64: a small deterministic generator for test inputs.
#[derive(Clone)]
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (1.0 / 9007199254740992.0)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform magnitude in [2^lo, 2^hi) with a random sign.
    pub fn logu(&mut self, lo: f64, hi: f64) -> f64 {
        let m = self.range(lo, hi).exp2();
        if self.next() & 1 == 0 {
            m
        } else {
            -m
        }
    }
}

/// Special and boundary f32 inputs shared by every function.
pub fn edge_f32() -> Vec<f32> {
    let mut v = vec![
        0.0,
        -0.0,
        f32::from_bits(1),
        f32::from_bits(0x007F_FFFF),
        f32::MIN_POSITIVE,
        1.0,
        0.5,
        2.0,
        3.0,
        10.0,
        0.1,
        f32::MAX,
        f32::INFINITY,
        f32::NAN,
        f32::from_bits(0x7F80_0001),
        f32::from_bits(0xFFC1_2345),
        std::f32::consts::FRAC_PI_4,
        std::f32::consts::FRAC_PI_2,
        std::f32::consts::PI,
        1.0e10,
        1.0e20,
        1.0e30,
        3.0e38,
        16777216.0,
        16777217.0,
        88.72283,
        88.72284,
        88.7229,
        -87.33654,
        -103.97207,
        -103.97208,
        -150.0,
        -149.5,
        -149.0,
        127.99999,
        128.0,
        -126.0,
        0.99999994,
        1.0000001,
        1.0e-10,
        1.0e-30,
        1.0e-40,
    ];
    for k in -30..=30 {
        v.push((k as f32) * std::f32::consts::FRAC_PI_4);
    }
    for e in -149..=127 {
        v.push((2.0f64).powi(e) as f32);
    }
    let n = v.len();
    for i in 0..n {
        let x = v[i];
        v.push(-x);
        v.push(f32::from_bits(x.to_bits().wrapping_add(1)));
        v.push(f32::from_bits(x.to_bits().wrapping_sub(1)));
    }
    v
}

/// Special and boundary f64 inputs shared by every function.
pub fn edge_f64() -> Vec<f64> {
    let mut v = vec![
        0.0,
        -0.0,
        f64::from_bits(1),
        f64::from_bits(0x000F_FFFF_FFFF_FFFF),
        f64::MIN_POSITIVE,
        1.0,
        0.5,
        2.0,
        3.0,
        10.0,
        0.1,
        f64::MAX,
        f64::INFINITY,
        f64::NAN,
        f64::from_bits(0x7FF0_0000_0000_0001),
        f64::from_bits(0xFFF8_1234_5678_9ABC),
        std::f64::consts::FRAC_PI_4,
        std::f64::consts::FRAC_PI_2,
        std::f64::consts::PI,
        1.0e10,
        1.0e22,
        1.0e100,
        1.0e300,
        6381956970095103.0 * (2.0f64).powi(797),
        5.319372648326541e+255,
        1073741824.0,
        1686629713.0,
        709.782712893384,
        709.7827128933841,
        -708.3964185322641,
        -745.1332191019411,
        -745.1332191019412,
        -745.2,
        1023.9999999999999,
        1024.0,
        -1022.0,
        -1074.0,
        -1075.0,
        -1075.5,
        0.9999999999999999,
        1.0000000000000002,
        1.0e-300,
        1.0e-310,
    ];
    for k in -40..=40 {
        v.push((k as f64) * std::f64::consts::FRAC_PI_4);
    }
    for e in -1074..=1023 {
        v.push((2.0f64).powi(e));
    }
    let n = v.len();
    for i in 0..n {
        let x = v[i];
        v.push(-x);
        v.push(f64::from_bits(x.to_bits().wrapping_add(1)));
        v.push(f64::from_bits(x.to_bits().wrapping_sub(1)));
    }
    v
}

/// A random f32 for a function whose interesting inputs are about `[lo, hi]`: a third
/// uniform there, a third log-uniform over every magnitude, a third uniform bit patterns.
pub fn sample_f32(rng: &mut Rng, lo: f64, hi: f64) -> f32 {
    match rng.next() % 3 {
        0 => rng.range(lo, hi) as f32,
        1 => rng.logu(-149.0, 128.0) as f32,
        _ => f32::from_bits(rng.next() as u32),
    }
}

/// As [`sample_f32`] for f64.
pub fn sample_f64(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    match rng.next() % 3 {
        0 => rng.range(lo, hi),
        1 => rng.logu(-1074.0, 1024.0),
        _ => f64::from_bits(rng.next()),
    }
}

use crate::libm;

/// A unary f32 function, its f64 reference and the interval its inputs mostly lie in.
pub struct Unary32 {
    pub name: &'static str,
    pub f: fn(f32) -> f32,
    pub reference: fn(f64) -> f64,
    pub lo: f64,
    pub hi: f64,
}

/// A binary f32 function (powif takes its `n` as `y as i32`).
pub struct Binary32 {
    pub name: &'static str,
    pub f: fn(f32, f32) -> f32,
    pub reference: fn(f64, f64) -> f64,
    pub lo: f64,
    pub hi: f64,
}

/// A unary f64 function.
pub struct Unary64 {
    pub name: &'static str,
    pub f: fn(f64) -> f64,
    pub reference: fn(f64) -> f64,
    pub lo: f64,
    pub hi: f64,
}

/// A binary f64 function.
pub struct Binary64 {
    pub name: &'static str,
    pub f: fn(f64, f64) -> f64,
    pub reference: fn(f64, f64) -> f64,
    pub lo: f64,
    pub hi: f64,
}

fn sincosf_s(x: f32) -> f32 {
    let mut s = 0.0;
    let mut c = 0.0;
    libm::sincosf(x, &mut s, &mut c);
    s
}

fn sincosf_c(x: f32) -> f32 {
    let mut s = 0.0;
    let mut c = 0.0;
    libm::sincosf(x, &mut s, &mut c);
    c
}

fn sincos_s(x: f64) -> f64 {
    let mut s = 0.0;
    let mut c = 0.0;
    libm::sincos(x, &mut s, &mut c);
    s
}

fn sincos_c(x: f64) -> f64 {
    let mut s = 0.0;
    let mut c = 0.0;
    libm::sincos(x, &mut s, &mut c);
    c
}

fn powif_(x: f32, n: f32) -> f32 {
    libm::powif(x, n as i32)
}

fn powi_(x: f64, n: f64) -> f64 {
    libm::powi(x, n as f32 as i32)
}

/// The reference of powif/powi: `pow(x, n as i32)`, with `as` as in `powif_`/`powi_`.
fn pow_int(x: f64, n: f64) -> f64 {
    x.powf((n as f32 as i32) as f64)
}

/// Every unary f32 function.
pub fn unary32() -> Vec<Unary32> {
    let u = |name, f, reference, lo, hi| Unary32 {
        name,
        f,
        reference,
        lo,
        hi,
    };
    vec![
        u("sinf", libm::sinf, f64::sin, -100.0, 100.0),
        u("cosf", libm::cosf, f64::cos, -100.0, 100.0),
        u("sincosf.sin", sincosf_s, f64::sin, -100.0, 100.0),
        u("sincosf.cos", sincosf_c, f64::cos, -100.0, 100.0),
        u("tanf", libm::tanf, f64::tan, -100.0, 100.0),
        u("asinf", libm::asinf, f64::asin, -1.0, 1.0),
        u("acosf", libm::acosf, f64::acos, -1.0, 1.0),
        u("atanf", libm::atanf, f64::atan, -20.0, 20.0),
        u("expf", libm::expf, f64::exp, -104.0, 89.0),
        u("exp2f", libm::exp2f, f64::exp2, -151.0, 128.0),
        u("logf", libm::logf, f64::ln, 0.0, 100.0),
        u("log2f", libm::log2f, f64::log2, 0.0, 100.0),
        u("log10f", libm::log10f, f64::log10, 0.0, 100.0),
        u("cbrtf", libm::cbrtf, f64::cbrt, -100.0, 100.0),
    ]
}

/// Every binary f32 function.
pub fn binary32() -> Vec<Binary32> {
    let b = |name, f, reference, lo, hi| Binary32 {
        name,
        f,
        reference,
        lo,
        hi,
    };
    vec![
        b("atan2f", libm::atan2f, f64::atan2, -10.0, 10.0),
        b("powf", libm::powf, f64::powf, -10.0, 10.0),
        b("hypotf", libm::hypotf, f64::hypot, -1e3, 1e3),
        b("powif", powif_, pow_int, -70.0, 70.0),
    ]
}

/// Every unary f64 function.
pub fn unary64() -> Vec<Unary64> {
    let u = |name, f, reference, lo, hi| Unary64 {
        name,
        f,
        reference,
        lo,
        hi,
    };
    vec![
        u("sin", libm::sin, f64::sin, -100.0, 100.0),
        u("cos", libm::cos, f64::cos, -100.0, 100.0),
        u("sincos.sin", sincos_s, f64::sin, -100.0, 100.0),
        u("sincos.cos", sincos_c, f64::cos, -100.0, 100.0),
        u("tan", libm::tan, f64::tan, -100.0, 100.0),
        u("asin", libm::asin, f64::asin, -1.0, 1.0),
        u("acos", libm::acos, f64::acos, -1.0, 1.0),
        u("atan", libm::atan, f64::atan, -20.0, 20.0),
        u("exp", libm::exp, f64::exp, -746.0, 710.0),
        u("exp2", libm::exp2, f64::exp2, -1076.0, 1024.0),
        u("log", libm::log, f64::ln, 0.0, 100.0),
        u("log2", libm::log2, f64::log2, 0.0, 100.0),
        u("log10", libm::log10, f64::log10, 0.0, 100.0),
        u("cbrt", libm::cbrt, f64::cbrt, -100.0, 100.0),
    ]
}

/// Every binary f64 function.
pub fn binary64() -> Vec<Binary64> {
    let b = |name, f, reference, lo, hi| Binary64 {
        name,
        f,
        reference,
        lo,
        hi,
    };
    vec![
        b("atan2", libm::atan2, f64::atan2, -10.0, 10.0),
        b("pow", libm::pow, f64::powf, -10.0, 10.0),
        b("hypot", libm::hypot, f64::hypot, -1e3, 1e3),
        b("powi", powi_, pow_int, -70.0, 70.0),
    ]
}

/// Measures a unary f32 function on `n` random points plus the edge inputs.
pub fn measure_unary32(u: &Unary32, n: u64, seed: u64) -> Stats {
    let mut st = Stats::default();
    let mut rng = Rng(seed);
    let edges = edge_f32();
    for i in 0..n + edges.len() as u64 {
        let x = if (i as usize) < edges.len() {
            edges[i as usize]
        } else {
            sample_f32(&mut rng, u.lo, u.hi)
        };
        let got = (u.f)(x);
        st.add(ulp32(got, (u.reference)(x as f64)), || {
            format!("{}({:e} = {:#010x}) = {:e}", u.name, x, x.to_bits(), got)
        });
    }
    st
}

/// A pair of inputs for a binary function: edge x edge, or random (for pow: often x > 0
/// and |y log2 x| in range, so that most results are finite and nonzero).
fn pair32(rng: &mut Rng, edges: &[f32], name: &str, lo: f64, hi: f64) -> (f32, f32) {
    match rng.next() % 8 {
        0 => (
            edges[(rng.next() % edges.len() as u64) as usize],
            edges[(rng.next() % edges.len() as u64) as usize],
        ),
        1 | 2 if name == "powf" => {
            let x = rng.logu(-20.0, 20.0).abs() as f32;
            let y = (rng.range(-140.0, 140.0) / (x as f64).log2().abs().max(1e-3)) as f32;
            (x, y)
        }
        1 | 2 if name == "powif" => {
            let x = rng.range(0.25, 4.0) as f32 * if rng.next() & 1 == 0 { 1.0 } else { -1.0 };
            (x, rng.range(-300.0, 300.0).round() as f32)
        }
        3 => (rng.range(lo, hi) as f32, f32::from_bits(rng.next() as u32)),
        4 => (f32::from_bits(rng.next() as u32), rng.range(lo, hi) as f32),
        _ => (rng.range(lo, hi) as f32, rng.range(lo, hi) as f32),
    }
}

/// Measures a binary f32 function on `n` random pairs.
pub fn measure_binary32(b: &Binary32, n: u64, seed: u64) -> Stats {
    let mut st = Stats::default();
    let mut rng = Rng(seed);
    let edges = edge_f32();
    for _ in 0..n {
        let (x, y) = pair32(&mut rng, &edges, b.name, b.lo, b.hi);
        let got = (b.f)(x, y);
        st.add(ulp32(got, (b.reference)(x as f64, y as f64)), || {
            format!(
                "{}({:e}, {:e} = {:#010x}, {:#010x}) = {:e}",
                b.name,
                x,
                y,
                x.to_bits(),
                y.to_bits(),
                got
            )
        });
    }
    st
}

/// Measures a unary f64 function on `n` random points plus the edge inputs.
pub fn measure_unary64(u: &Unary64, n: u64, seed: u64) -> Stats {
    let mut st = Stats::default();
    let mut rng = Rng(seed);
    let edges = edge_f64();
    for i in 0..n + edges.len() as u64 {
        let x = if (i as usize) < edges.len() {
            edges[i as usize]
        } else {
            sample_f64(&mut rng, u.lo, u.hi)
        };
        let got = (u.f)(x);
        st.add(ulp64(got, (u.reference)(x)), || {
            format!("{}({:e} = {:#018x}) = {:e}", u.name, x, x.to_bits(), got)
        });
    }
    st
}

fn pair64(rng: &mut Rng, edges: &[f64], name: &str, lo: f64, hi: f64) -> (f64, f64) {
    match rng.next() % 8 {
        0 => (
            edges[(rng.next() % edges.len() as u64) as usize],
            edges[(rng.next() % edges.len() as u64) as usize],
        ),
        1 | 2 if name == "pow" => {
            let x = rng.logu(-60.0, 60.0).abs();
            let y = rng.range(-1070.0, 1020.0) / x.log2().abs().max(1e-6);
            (x, y)
        }
        1 | 2 if name == "powi" => {
            let x = rng.range(0.25, 4.0) * if rng.next() & 1 == 0 { 1.0 } else { -1.0 };
            (x, rng.range(-1500.0, 1500.0).round())
        }
        3 => (rng.range(lo, hi), f64::from_bits(rng.next())),
        4 => (f64::from_bits(rng.next()), rng.range(lo, hi)),
        _ => (rng.range(lo, hi), rng.range(lo, hi)),
    }
}

/// Measures a binary f64 function on `n` random pairs (those `keep` accepts).
pub fn measure_binary64(b: &Binary64, n: u64, seed: u64, keep: impl Fn(f64, f64) -> bool) -> Stats {
    let mut st = Stats::default();
    let mut rng = Rng(seed);
    let edges = edge_f64();
    for _ in 0..n {
        let (x, y) = pair64(&mut rng, &edges, b.name, b.lo, b.hi);
        if !keep(x, y) {
            continue;
        }
        let got = (b.f)(x, y);
        st.add(ulp64(got, (b.reference)(x, y)), || {
            format!(
                "{}({:e}, {:e} = {:#018x}, {:#018x}) = {:e}",
                b.name,
                x,
                y,
                x.to_bits(),
                y.to_bits(),
                got
            )
        });
    }
    st
}
