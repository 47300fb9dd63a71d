//! `trax::libm` (`runtime/prelude/libm.rs`) compiled by rustc, as in `trax native`:
//! accuracy against the host's libm on about two million points per f32 function, the
//! f64 functions against exact (mpmath) references, C99 Annex F special values, exact
//! cases and the NaN bits. (`tests/libm_differential.rs` in the root package shows the
//! machine gives the same bits; `benches/libm_ulp.rs` runs every f32 input.)

#[path = "../prelude/libm.rs"]
#[allow(dead_code)]
mod libm;
mod libm_ref;

use libm_ref::*;

/// Points per f32 function (plus the edge inputs).
const N32: u64 = 2_000_000;
/// Points per f64 function against the host libm.
const N64: u64 = 500_000;

/// The f32 functions evaluate in f64: polynomial errors are at most 2^-33.9 relative
/// (cosf; the others 2^-36 or better), the f64 roundings add about 2^-50, and the
/// reference (the host's f64 function) is within about 2^-28 f32 ULP. So a result is at
/// most 0.5 + 2^-9 ULP away; the bound leaves a factor of two.
const MAX32: f64 = 0.5 + 1.0 / 256.0;

fn table_row(name: &str, s: &Stats) -> String {
    format!(
        "{name:12} points {:>8}  max {:.4} ULP  mean {:.4} ULP  worst {}",
        s.n,
        s.max,
        s.mean(),
        s.worst
    )
}

fn check32(name: &str, s: &Stats, failures: &mut Vec<String>) {
    println!("{}", table_row(name, s));
    if s.special_mismatches > 0 {
        failures.push(format!(
            "{name}: {} special results differ from the host's, first {}",
            s.special_mismatches, s.first_mismatch
        ));
    }
    if s.max > MAX32 {
        failures.push(format!("{name}: {:.4} ULP at {}", s.max, s.worst));
    }
}

#[test]
fn f32_unary_functions_are_within_half_an_ulp_and_a_bit() {
    let mut failures = Vec::new();
    for (i, u) in unary32().iter().enumerate() {
        let s = measure_unary32(u, N32, 0x1000 + i as u64);
        check32(u.name, &s, &mut failures);
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn f32_binary_functions_are_within_half_an_ulp_and_a_bit() {
    let mut failures = Vec::new();
    for (i, b) in binary32().iter().enumerate() {
        let s = measure_binary32(b, N32, 0x2000 + i as u64);
        check32(b.name, &s, &mut failures);
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Against the host's f64 libm the distance is at most ours (1 ULP, see
/// `f64_functions_are_within_one_ulp_of_the_exact_value`) plus the host's own error
/// (glibc documents at most 1 ULP for these on x86_64 and aarch64): 2. Left out: the
/// hardest reduction among all doubles, x = 6381956970095103 * 2^797 (and its edge-list
/// neighbours), where glibc 2.36's cos and tan are 8 and 14 ULP away (ours are within
/// 0.5 ULP of mpmath's: `hardest_argument_reductions`); and signalling NaNs for pow,
/// where C99 gives pow(x, 0) = 1 and glibc a NaN.
#[test]
fn f64_functions_agree_with_the_host_libm() {
    let mut failures = Vec::new();
    for (i, u) in unary64().iter().enumerate() {
        let trig = matches!(u.name, "sin" | "cos" | "tan" | "sincos.sin" | "sincos.cos");
        let mut st = Stats::default();
        let mut rng = Rng(0x3000 + i as u64);
        let edges = edge_f64();
        for k in 0..N64 + edges.len() as u64 {
            let x = if (k as usize) < edges.len() {
                edges[k as usize]
            } else {
                sample_f64(&mut rng, u.lo, u.hi)
            };
            if trig && (x.abs() / 5.319372648326541e255 - 1.0).abs() < 1e-14 {
                continue;
            }
            let got = (u.f)(x);
            st.add(ulp64(got, (u.reference)(x)), || {
                format!("{}({:e} = {:#018x}) = {:e}", u.name, x, x.to_bits(), got)
            });
        }
        println!("{}", table_row(u.name, &st));
        if st.special_mismatches > 0 || st.max > 2.0 {
            failures.push(format!(
                "{}: {:.1} ULP at {}; {} special mismatches, first {}",
                u.name, st.max, st.worst, st.special_mismatches, st.first_mismatch
            ));
        }
    }
    for (i, b) in binary64().iter().enumerate() {
        let st = measure_binary64(b, N64, 0x4000 + i as u64, |x, y| {
            let snan = |v: f64| v.is_nan() && v.to_bits() & 0x0008_0000_0000_0000 == 0;
            !snan(x) && !snan(y)
        });
        println!("{}", table_row(b.name, &st));
        if st.special_mismatches > 0 || st.max > 2.0 {
            failures.push(format!(
                "{}: {:.1} ULP at {}; {} special mismatches, first {}",
                b.name, st.max, st.worst, st.special_mismatches, st.first_mismatch
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The exact references of `tests/data/libm_f64.txt` (from
/// `prelude/tools/libm_ref.py gen`: boundary and hard cases, e.g. the double closest to
/// a multiple of pi/2, and random points). The target is 1 ULP.
#[test]
fn f64_functions_are_within_one_ulp_of_the_exact_value() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/libm_f64.txt");
    let text = std::fs::read_to_string(path).unwrap();
    let unary = unary64();
    let binary = binary64();
    let mut stats: Vec<(String, Stats)> = Vec::new();
    let mut failures = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = line.split_whitespace().collect();
        let hex = |s: &str| f64::from_bits(u64::from_str_radix(s, 16).unwrap());
        let name = f[0];
        let hi = hex(f[f.len() - 2]);
        let lo: f64 = f[f.len() - 1].parse().unwrap();
        let got = if let Some(u) = unary.iter().find(|u| u.name == name) {
            (u.f)(hex(f[1]))
        } else if name == "powi" {
            libm::powi(hex(f[1]), hex(f[2]) as i32)
        } else {
            let b = binary.iter().find(|b| b.name == name).unwrap();
            (b.f)(hex(f[1]), hex(f[2]))
        };
        let err = if hi.is_infinite() || got.is_infinite() || hi == 0.0 {
            if got.to_bits() == hi.to_bits() {
                Some(0.0)
            } else if hi == 0.0 && got.abs() <= f64::from_bits(1) {
                // The exact value is below half the smallest subnormal: 0 or it.
                Some(((got - hi) - lo).abs() / f64::from_bits(1))
            } else {
                None
            }
        } else {
            // got - hi is exact when they are close; the exact value is hi + lo.
            Some(((got - hi) - lo).abs() / p2(exponent_of(hi).max(-1022) - 52))
        };
        let i = match stats.iter().position(|(n, _)| n == name) {
            Some(i) => i,
            None => {
                stats.push((name.to_string(), Stats::default()));
                stats.len() - 1
            }
        };
        stats[i]
            .1
            .add(err, || format!("{line} -> got {:016x}", got.to_bits()));
    }
    for (name, s) in &stats {
        println!("{}", table_row(name, s));
        if s.special_mismatches > 0 || s.max > 1.0 {
            failures.push(format!(
                "{name}: {:.3} ULP at {}; {} special mismatches, first {}",
                s.max, s.worst, s.special_mismatches, s.first_mismatch
            ));
        }
    }
    assert_eq!(stats.len(), 18, "every f64 function has reference points");
    assert!(failures.is_empty(), "{failures:#?}");
}

fn exponent_of(x: f64) -> i32 {
    let b = x.to_bits() & 0x7FFF_FFFF_FFFF_FFFF;
    let e = (b >> 52) as i32;
    if e == 0 {
        -1023
    } else {
        e - 1023
    }
}

// ---------------------------------------------------------------------------------------
// Special values (C99 Annex F) and the NaN bits

const QNAN32: u32 = 0x7FC0_0000;
type Fn32 = fn(f32) -> f32;
type Fn64 = fn(f64) -> f64;
const QNAN64: u64 = 0x7FF8_0000_0000_0000;

/// Compares bit for bit (a NaN result must have the given bits too).
fn same32(got: f32, want: f32, what: &str) {
    assert_eq!(
        got.to_bits(),
        want.to_bits(),
        "{what}: got {got:e} ({:#010x}), want {want:e} ({:#010x})",
        got.to_bits(),
        want.to_bits()
    );
}

fn same64(got: f64, want: f64, what: &str) {
    assert_eq!(
        got.to_bits(),
        want.to_bits(),
        "{what}: got {got:e} ({:#018x}), want {want:e} ({:#018x})",
        got.to_bits(),
        want.to_bits()
    );
}

#[test]
fn nan_inputs_come_back_quieted_and_invalid_operations_give_the_default_nan() {
    let snan32 = f32::from_bits(0xFF80_1234);
    let quieted32 = f32::from_bits(0xFFC0_1234);
    let qnan32 = f32::from_bits(QNAN32);
    let unary: [(&str, Fn32); 13] = [
        ("sinf", libm::sinf),
        ("cosf", libm::cosf),
        ("tanf", libm::tanf),
        ("asinf", libm::asinf),
        ("acosf", libm::acosf),
        ("atanf", libm::atanf),
        ("expf", libm::expf),
        ("exp2f", libm::exp2f),
        ("logf", libm::logf),
        ("log2f", libm::log2f),
        ("log10f", libm::log10f),
        ("cbrtf", libm::cbrtf),
        ("powif", |x| libm::powif(x, 3)),
    ];
    for (name, f) in unary {
        same32(f(snan32), quieted32, name);
        same32(f(quieted32), quieted32, name);
    }
    same32(libm::atan2f(snan32, 1.0), quieted32, "atan2f");
    same32(libm::atan2f(1.0, snan32), quieted32, "atan2f");
    same32(libm::powf(snan32, 2.0), quieted32, "powf");
    same32(libm::powf(2.0, snan32), quieted32, "powf");
    same32(libm::hypotf(snan32, 2.0), quieted32, "hypotf");
    for (name, v) in [
        ("sinf(inf)", libm::sinf(f32::INFINITY)),
        ("cosf(-inf)", libm::cosf(f32::NEG_INFINITY)),
        ("tanf(inf)", libm::tanf(f32::INFINITY)),
        ("asinf(1.5)", libm::asinf(1.5)),
        ("acosf(-2)", libm::acosf(-2.0)),
        ("logf(-1)", libm::logf(-1.0)),
        ("log2f(-inf)", libm::log2f(f32::NEG_INFINITY)),
        ("log10f(-0.5)", libm::log10f(-0.5)),
        ("powf(-8, 1/3)", libm::powf(-8.0, 1.0 / 3.0)),
    ] {
        same32(v, qnan32, name);
    }
    let snan64 = f64::from_bits(0xFFF0_0000_0000_1234);
    let quieted64 = f64::from_bits(0xFFF8_0000_0000_1234);
    let qnan64 = f64::from_bits(QNAN64);
    let unary64: [(&str, Fn64); 13] = [
        ("sin", libm::sin),
        ("cos", libm::cos),
        ("tan", libm::tan),
        ("asin", libm::asin),
        ("acos", libm::acos),
        ("atan", libm::atan),
        ("exp", libm::exp),
        ("exp2", libm::exp2),
        ("log", libm::log),
        ("log2", libm::log2),
        ("log10", libm::log10),
        ("cbrt", libm::cbrt),
        ("powi", |x| libm::powi(x, 3)),
    ];
    for (name, f) in unary64 {
        same64(f(snan64), quieted64, name);
        same64(f(quieted64), quieted64, name);
    }
    same64(libm::atan2(snan64, 1.0), quieted64, "atan2");
    same64(libm::atan2(1.0, snan64), quieted64, "atan2");
    same64(libm::pow(snan64, 2.0), quieted64, "pow");
    same64(libm::pow(2.0, snan64), quieted64, "pow");
    same64(libm::hypot(2.0, snan64), quieted64, "hypot");
    for (name, v) in [
        ("sin(inf)", libm::sin(f64::INFINITY)),
        ("cos(-inf)", libm::cos(f64::NEG_INFINITY)),
        ("tan(inf)", libm::tan(f64::INFINITY)),
        ("asin(1.5)", libm::asin(1.5)),
        ("acos(-2)", libm::acos(-2.0)),
        ("log(-1)", libm::log(-1.0)),
        ("log2(-inf)", libm::log2(f64::NEG_INFINITY)),
        ("log10(-0.5)", libm::log10(-0.5)),
        ("pow(-8, 1/3)", libm::pow(-8.0, 1.0 / 3.0)),
    ] {
        same64(v, qnan64, name);
    }
    let (mut s, mut c) = (0.0f32, 0.0f32);
    libm::sincosf(f32::INFINITY, &mut s, &mut c);
    same32(s, qnan32, "sincosf(inf).sin");
    same32(c, qnan32, "sincosf(inf).cos");
}

/// C99 F.9.4.4 for f32 and f64 alike: every listed case, bit for bit.
#[test]
fn pow_special_cases() {
    let inf = f64::INFINITY;
    let nan = f64::NAN;
    // (x, y, expected); expected NaN means the default NaN.
    let cases: &[(f64, f64, f64)] = &[
        (nan, 0.0, 1.0),
        (nan, -0.0, 1.0),
        (inf, 0.0, 1.0),
        (-3.0, -0.0, 1.0),
        (1.0, nan, 1.0),
        (1.0, inf, 1.0),
        (1.0, -inf, 1.0),
        (1.0, -7.5, 1.0),
        (0.0, -3.0, inf),
        (-0.0, -3.0, -inf),
        (-0.0, -4.0, inf),
        (-0.0, -0.5, inf),
        (0.0, -inf, inf),
        (-0.0, -inf, inf),
        (0.0, 3.0, 0.0),
        (-0.0, 3.0, -0.0),
        (-0.0, 4.0, 0.0),
        (-0.0, 0.5, 0.0),
        (-0.0, inf, 0.0),
        (-1.0, inf, 1.0),
        (-1.0, -inf, 1.0),
        (0.5, -inf, inf),
        (-0.5, -inf, inf),
        (2.0, -inf, 0.0),
        (-2.0, -inf, 0.0),
        (0.5, inf, 0.0),
        (-0.5, inf, 0.0),
        (2.0, inf, inf),
        (-2.0, inf, inf),
        (-inf, -3.0, -0.0),
        (-inf, -4.0, 0.0),
        (-inf, -0.5, 0.0),
        (-inf, 3.0, -inf),
        (-inf, 4.0, inf),
        (-inf, 0.5, inf),
        (inf, -2.0, 0.0),
        (inf, 0.5, inf),
        (-8.0, 1.0 / 3.0, nan),
        (-2.0, 0.5, nan),
        (-2.0, 3.0, -8.0),
        (-2.0, 4.0, 16.0),
        (-2.0, -3.0, -0.125),
        (-1.0, 3.0, -1.0),
        (-1.0, 1e300, 1.0),
        (-1.0, 9007199254740991.0, -1.0),
        (2.0, 0.5, std::f64::consts::SQRT_2),
        (4.0, 0.5, 2.0),
        (10.0, 2.0, 100.0),
        (2.0, 1023.0, 8.98846567431158e307),
        (2.0, 1024.0, inf),
        (2.0, -1074.0, 5e-324),
        (2.0, -1075.0, 0.0),
        (-2.0, -1075.0, -0.0),
        (1.0000000000000002, 1e300, inf),
        (0.9999999999999999, 1e300, 0.0),
        (nan, 1.0, nan),
        (1.5, nan, nan),
    ];
    for &(x, y, want) in cases {
        let want = if want.is_nan() {
            f64::from_bits(QNAN64)
        } else {
            want
        };
        let got = libm::pow(x, y);
        if want.is_nan() {
            assert!(got.is_nan(), "pow({x:e}, {y:e}) = {got:e}, want NaN");
        } else {
            same64(got, want, &format!("pow({x:e}, {y:e})"));
        }
        let (x32, y32) = (x as f32, y as f32);
        // Only where the f32 case is the same case (the inputs survive the conversion).
        if x32 as f64 == x && y32 as f64 == y || x.is_nan() || y.is_nan() {
            let want32 = libm_ref_pow32(x32, y32);
            let got32 = libm::powf(x32, y32);
            if want32.is_nan() {
                assert!(got32.is_nan(), "powf({x32:e}, {y32:e}) = {got32:e}");
            } else {
                same32(got32, want32, &format!("powf({x32:e}, {y32:e})"));
            }
        }
    }
    // powi/powif: pow with an integer y, including n = 0 for NaN and the i32 ends.
    same64(libm::powi(nan, 0), 1.0, "powi(NaN, 0)");
    same32(libm::powif(f32::NAN, 0), 1.0, "powif(NaN, 0)");
    same64(libm::powi(-0.0, -3), -inf, "powi(-0, -3)");
    same32(libm::powif(-0.0, -3), f32::NEG_INFINITY, "powif(-0, -3)");
    same32(libm::powif(-0.0, -4), f32::INFINITY, "powif(-0, -4)");
    same32(libm::powif(-2.0, 3), -8.0, "powif(-2, 3)");
    same32(libm::powif(-2.0, -1), -0.5, "powif(-2, -1)");
    same32(libm::powif(3.0, 2), 9.0, "powif(3, 2)");
    same32(
        libm::powif(4097.0, 2),
        16785408.0,
        "powif(4097, 2) (a tie: to even)",
    );
    same32(libm::powif(2.0, 127), 1.7014118e38, "powif(2, 127)");
    same32(libm::powif(2.0, 128), f32::INFINITY, "powif(2, 128)");
    same32(libm::powif(2.0, -149), f32::from_bits(1), "powif(2, -149)");
    same32(libm::powif(2.0, -150), 0.0, "powif(2, -150)");
    same32(libm::powif(-1.0, i32::MIN), 1.0, "powif(-1, MIN)");
    same32(libm::powif(-1.0, i32::MAX), -1.0, "powif(-1, MAX)");
    same64(libm::powi(-1.0, i32::MAX), -1.0, "powi(-1, MAX)");
    same32(
        libm::powif(1.0000001, 1 << 30),
        f32::INFINITY,
        "powif(1+ulp, 2^30)",
    );
    same32(
        libm::powif(-0.9999999, 999_999_999),
        -0.0,
        "powif(-(1-ulp), odd)",
    );
    same64(libm::powi(2.0, -1074), 5e-324, "powi(2, -1074)");
}

/// The expected powf from the f64 definition: pow of the same (exact) inputs, rounded.
fn libm_ref_pow32(x: f32, y: f32) -> f32 {
    let r = (x as f64).powf(y as f64);
    if r.is_nan() {
        f32::from_bits(QNAN32)
    } else {
        r as f32
    }
}

#[test]
fn atan2_quadrants_zeros_and_infinities() {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let inf = f64::INFINITY;
    let cases: &[(f64, f64, f64)] = &[
        (0.0, 0.0, 0.0),
        (-0.0, 0.0, -0.0),
        (0.0, -0.0, PI),
        (-0.0, -0.0, -PI),
        (0.0, 5.0, 0.0),
        (-0.0, 5.0, -0.0),
        (0.0, -5.0, PI),
        (-0.0, -5.0, -PI),
        (5.0, 0.0, FRAC_PI_2),
        (5.0, -0.0, FRAC_PI_2),
        (-5.0, 0.0, -FRAC_PI_2),
        (-5.0, -0.0, -FRAC_PI_2),
        (inf, inf, FRAC_PI_4),
        (-inf, inf, -FRAC_PI_4),
        (inf, -inf, 3.0 * FRAC_PI_4),
        (-inf, -inf, -3.0 * FRAC_PI_4),
        (inf, 5.0, FRAC_PI_2),
        (-inf, -5.0, -FRAC_PI_2),
        (5.0, inf, 0.0),
        (-5.0, inf, -0.0),
        (5.0, -inf, PI),
        (-5.0, -inf, -PI),
        (1.0, 1.0, FRAC_PI_4),
        (-1.0, -1.0, -3.0 * FRAC_PI_4),
        (1.0, -1.0, 3.0 * FRAC_PI_4),
        (1e-300, 1e300, 0.0),
        (-1e-300, -1e300, -PI),
        (f64::MAX, f64::MAX, FRAC_PI_4),
        (5e-324, 5e-324, FRAC_PI_4),
        (f64::MAX, 5e-324, FRAC_PI_2),
    ];
    for &(y, x, want) in cases {
        same64(libm::atan2(y, x), want, &format!("atan2({y:e}, {x:e})"));
        let want32 = want as f32;
        let (y32, x32) = (y as f32, x as f32);
        if y32.is_finite() == y.is_finite() && x32.is_finite() == x.is_finite() {
            let got = libm::atan2f(y32, x32);
            let want32 = (y32 as f64).atan2(x32 as f64) as f32;
            same32(got, want32, &format!("atan2f({y32:e}, {x32:e})"));
        }
        let _ = want32;
    }
}

#[test]
fn other_special_values() {
    let inf = f64::INFINITY;
    // Signed zeros pass through the odd functions.
    for (name, f) in [
        ("sin", libm::sin as fn(f64) -> f64),
        ("tan", libm::tan),
        ("asin", libm::asin),
        ("atan", libm::atan),
        ("cbrt", libm::cbrt),
    ] {
        same64(f(0.0), 0.0, name);
        same64(f(-0.0), -0.0, name);
    }
    for (name, f) in [
        ("sinf", libm::sinf as fn(f32) -> f32),
        ("tanf", libm::tanf),
        ("asinf", libm::asinf),
        ("atanf", libm::atanf),
        ("cbrtf", libm::cbrtf),
    ] {
        same32(f(0.0), 0.0, name);
        same32(f(-0.0), -0.0, name);
        if name != "cbrtf" {
            same32(
                f(f32::from_bits(0x8000_0001)),
                f32::from_bits(0x8000_0001),
                name,
            );
        }
    }
    same64(libm::cos(-0.0), 1.0, "cos(-0)");
    same32(libm::cosf(-0.0), 1.0, "cosf(-0)");
    same64(libm::acos(1.0), 0.0, "acos(1)");
    same32(libm::acosf(1.0), 0.0, "acosf(1)");
    same64(libm::acos(-1.0), std::f64::consts::PI, "acos(-1)");
    same64(libm::asin(-1.0), -std::f64::consts::FRAC_PI_2, "asin(-1)");
    same64(libm::atan(inf), std::f64::consts::FRAC_PI_2, "atan(inf)");
    same32(
        libm::atanf(f32::NEG_INFINITY),
        -std::f32::consts::FRAC_PI_2,
        "atanf(-inf)",
    );
    // exp: limits, overflow and underflow (to a correctly rounded subnormal).
    same64(libm::exp(inf), inf, "exp(inf)");
    same64(libm::exp(-inf), 0.0, "exp(-inf)");
    same64(libm::exp(-0.0), 1.0, "exp(-0)");
    same64(libm::exp(709.7827128933841), inf, "exp overflow");
    same64(
        libm::exp(-745.1332191019412),
        0.0,
        "exp(-745.1332191019412)",
    );
    same64(
        libm::exp(-745.133219101941),
        5e-324,
        "exp(-745.133219101941)",
    );
    same64(libm::exp2(-1074.0), 5e-324, "exp2(-1074)");
    same64(libm::exp2(-1075.0), 0.0, "exp2(-1075): a tie, to even");
    same64(libm::exp2(1023.0), 8.98846567431158e307, "exp2(1023)");
    same64(libm::exp2(1024.0), inf, "exp2(1024)");
    same32(libm::expf(f32::NEG_INFINITY), 0.0, "expf(-inf)");
    same32(libm::expf(88.72284), f32::INFINITY, "expf overflow");
    same32(
        libm::expf(88.72283),
        (88.72283f32 as f64).exp() as f32,
        "expf(88.72283)",
    );
    same32(libm::exp2f(-149.0), f32::from_bits(1), "exp2f(-149)");
    same32(libm::exp2f(-150.0), 0.0, "exp2f(-150): a tie, to even");
    same32(libm::exp2f(128.0), f32::INFINITY, "exp2f(128)");
    // Logarithms.
    same64(libm::log(0.0), -inf, "log(0)");
    same64(libm::log(-0.0), -inf, "log(-0)");
    same64(libm::log(inf), inf, "log(inf)");
    same64(libm::log(1.0), 0.0, "log(1)");
    same64(libm::log2(5e-324), -1074.0, "log2(min subnormal)");
    same32(
        libm::log2f(f32::from_bits(1)),
        -149.0,
        "log2f(min subnormal)",
    );
    same32(libm::logf(-0.0), f32::NEG_INFINITY, "logf(-0)");
    same32(libm::log10f(f32::INFINITY), f32::INFINITY, "log10f(inf)");
    // hypot: an infinity wins over NaN; no overflow or underflow.
    same64(libm::hypot(inf, f64::NAN), inf, "hypot(inf, NaN)");
    same64(libm::hypot(f64::NAN, -inf), inf, "hypot(NaN, -inf)");
    same32(
        libm::hypotf(f32::NAN, f32::NEG_INFINITY),
        f32::INFINITY,
        "hypotf",
    );
    same64(libm::hypot(-0.0, 0.0), 0.0, "hypot(-0, 0)");
    same64(libm::hypot(3e300, 4e300), 5e300, "hypot(3e300, 4e300)");
    same64(libm::hypot(3e-320, 4e-320), 5e-320, "hypot(3e-320, 4e-320)");
    same64(libm::hypot(f64::MAX, f64::MAX), inf, "hypot(MAX, MAX)");
    same32(libm::hypotf(3e38, 3e38), f32::INFINITY, "hypotf overflow");
    same32(libm::hypotf(3e-44, 4e-44), 5e-44, "hypotf(3e-44, 4e-44)");
    // cbrt of negatives, infinities and subnormals.
    same64(libm::cbrt(-inf), -inf, "cbrt(-inf)");
    same64(libm::cbrt(-8.0), -2.0, "cbrt(-8)");
    same32(libm::cbrtf(-27.0), -3.0, "cbrtf(-27)");
    same64(
        libm::cbrt(5e-324),
        1.7031839360032603e-108,
        "cbrt(min subnormal)",
    );
}

/// Results that are exact numbers come out exact.
#[test]
fn exact_cases() {
    for k in -1074..=1023 {
        let p = p2(k);
        same64(libm::exp2(k as f64), p, "exp2(k)");
        same64(libm::log2(p), k as f64, "log2(2^k)");
        same64(libm::pow(2.0, k as f64), p, "pow(2, k)");
    }
    for k in -149..=127 {
        let p = p2(k) as f32;
        same32(libm::exp2f(k as f32), p, "exp2f(k)");
        same32(libm::log2f(p), k as f32, "log2f(2^k)");
        same32(libm::powf(2.0, k as f32), p, "powf(2, k)");
        same32(libm::powif(2.0, k), p, "powif(2, k)");
    }
    for k in 0..=22 {
        let p = 10f64.powi(k);
        same64(libm::log10(p), k as f64, "log10(10^k)");
        same64(libm::pow(10.0, k as f64), p, "pow(10, k)");
    }
    for k in 0..=10 {
        let p = 10f32.powi(k);
        same32(libm::log10f(p), k as f32, "log10f(10^k)");
        same32(libm::powf(10.0, k as f32), p, "powf(10, k)");
    }
    for n in -100i32..=100 {
        let c = (n * n * n) as f64;
        same64(libm::cbrt(c), n as f64, "cbrt(n^3)");
        same32(libm::cbrtf(c as f32), n as f32, "cbrtf(n^3)");
    }
    same64(libm::hypot(3.0, 4.0), 5.0, "hypot(3, 4)");
    same32(libm::hypotf(5.0, 12.0), 13.0, "hypotf(5, 12)");
    same64(libm::exp(1.0), std::f64::consts::E, "exp(1)");
    same64(libm::exp(0.0), 1.0, "exp(0)");
    same32(libm::expf(1.0), std::f32::consts::E, "expf(1)");
    same64(libm::log(std::f64::consts::E), 1.0, "log(e)");
    same64(
        libm::sin(std::f64::consts::PI),
        1.2246467991473532e-16,
        "sin(pi)",
    );
    same64(libm::cos(std::f64::consts::PI), -1.0, "cos(pi)");
    same32(libm::sinf(std::f32::consts::PI), -8.742278e-8, "sinf(pi)");
    same32(
        libm::cosf(std::f32::consts::FRAC_PI_2),
        -4.371139e-8,
        "cosf(pi/2)",
    );
}

/// The hardest argument reduction among all doubles (exact values from mpmath), and every
/// f32 around the switch from Cody-Waite to Payne-Hanek reduction at 2^28.
#[test]
fn hardest_argument_reductions() {
    // x = 6381956970095103 * 2^797: x mod pi/2 is about 2^-60.9; sin x = 1 - 1.1e-37.
    let x = 6381956970095103.0 * p2(797);
    same64(
        libm::cos(x),
        -4.687165924254628e-19,
        "cos(6381956970095103 * 2^797)",
    );
    same64(libm::sin(x), 1.0, "sin(6381956970095103 * 2^797)");
    same64(
        libm::tan(x),
        -2.133485385753704e18,
        "tan(6381956970095103 * 2^797)",
    );
    // Every f32 in [1e8, 1e9), against the host in f64.
    let mut worst: f64 = 0.0;
    let mut at = 0.0f32;
    let mut b = 1e8f32.to_bits();
    while b < 1e9f32.to_bits() {
        let x = f32::from_bits(b);
        for (f, r) in [
            (libm::sinf as fn(f32) -> f32, f64::sin as fn(f64) -> f64),
            (libm::cosf, f64::cos),
        ] {
            let e = ulp32(f(x), r(x as f64)).unwrap();
            if e > worst {
                worst = e;
                at = x;
            }
        }
        b += 1;
    }
    assert!(worst <= MAX32, "{worst} ULP at {at:e}");
}

/// One reduction for both gives the same bits as the separate functions.
#[test]
fn sincos_matches_sin_and_cos() {
    let mut rng = Rng(99);
    for _ in 0..200_000 {
        let x = sample_f32(&mut rng, -1e4, 1e4);
        let (mut s, mut c) = (0.0, 0.0);
        libm::sincosf(x, &mut s, &mut c);
        assert_eq!(s.to_bits(), libm::sinf(x).to_bits(), "{x:e}");
        assert_eq!(c.to_bits(), libm::cosf(x).to_bits(), "{x:e}");
        let y = sample_f64(&mut rng, -1e4, 1e4);
        let (mut s, mut c) = (0.0, 0.0);
        libm::sincos(y, &mut s, &mut c);
        assert_eq!(s.to_bits(), libm::sin(y).to_bits(), "{y:e}");
        assert_eq!(c.to_bits(), libm::cos(y).to_bits(), "{y:e}");
    }
}
