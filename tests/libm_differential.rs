//! `trax::libm` gives the same bits on the machine and natively: a generated kernel
//! applies every function to a few thousand inputs (edge cases: ±0, subnormals, ±inf,
//! NaNs with payloads, overflow and underflow thresholds, multiples of pi/4, powers of
//! two; and random points, small to huge) and prints every result's bits. It runs on
//! the emulator compiled at -O0 and -O2 and natively (`trax native`); each output must
//! equal, bit for bit (NaNs included: libm never lets arithmetic make a NaN), the host
//! build of the same `runtime/prelude/libm.rs` evaluated here.
//!
//! The inputs live in static tables XORed with global register 0, which holds 0 at run
//! time, so the optimiser cannot fold any call.
//!
//! A second test measures the cost of each function on the simulator (instructions per
//! call, through `trax.profbegin`/`profend` regions) and prints the table.

use std::fmt::Write as _;
use std::path::PathBuf;

mod differential;
use differential::{emulate, native};

/// The host build of the library: the oracle.
#[allow(dead_code)]
#[path = "../runtime/prelude/libm.rs"]
mod libm;
#[path = "../runtime/tests/libm_ref/mod.rs"]
mod libm_ref;

use libm_ref::{edge_f32, edge_f64, sample_f32, sample_f64, Rng};

fn tmp() -> PathBuf {
    differential::scratch("libm-differential")
}

/// Kernel expressions, in output order. `a`, `b`: f32 operands; `c`, `d`: f64
/// operands; `n`: an i32.
const F32_CALLS: &[&str] = &[
    "libm::sinf(a)",
    "libm::cosf(a)",
    "libm::tanf(a)",
    "libm::asinf(a)",
    "libm::acosf(a)",
    "libm::atanf(a)",
    "libm::atan2f(a, b)",
    "libm::expf(a)",
    "libm::exp2f(a)",
    "libm::logf(a)",
    "libm::log2f(a)",
    "libm::log10f(a)",
    "libm::powf(a, b)",
    "libm::powif(a, n)",
    "libm::hypotf(a, b)",
    "libm::cbrtf(a)",
];

const F64_CALLS: &[&str] = &[
    "libm::sin(c)",
    "libm::cos(c)",
    "libm::tan(c)",
    "libm::asin(c)",
    "libm::acos(c)",
    "libm::atan(c)",
    "libm::atan2(c, d)",
    "libm::exp(c)",
    "libm::exp2(c)",
    "libm::log(c)",
    "libm::log2(c)",
    "libm::log10(c)",
    "libm::pow(c, d)",
    "libm::powi(c, n)",
    "libm::hypot(c, d)",
    "libm::cbrt(c)",
];

/// The host value of one kernel expression.
fn host32(call: &str, a: f32, b: f32, n: i32) -> u32 {
    let v = match call {
        "libm::sinf(a)" => libm::sinf(a),
        "libm::cosf(a)" => libm::cosf(a),
        "libm::tanf(a)" => libm::tanf(a),
        "libm::asinf(a)" => libm::asinf(a),
        "libm::acosf(a)" => libm::acosf(a),
        "libm::atanf(a)" => libm::atanf(a),
        "libm::atan2f(a, b)" => libm::atan2f(a, b),
        "libm::expf(a)" => libm::expf(a),
        "libm::exp2f(a)" => libm::exp2f(a),
        "libm::logf(a)" => libm::logf(a),
        "libm::log2f(a)" => libm::log2f(a),
        "libm::log10f(a)" => libm::log10f(a),
        "libm::powf(a, b)" => libm::powf(a, b),
        "libm::powif(a, n)" => libm::powif(a, n),
        "libm::hypotf(a, b)" => libm::hypotf(a, b),
        "libm::cbrtf(a)" => libm::cbrtf(a),
        _ => unreachable!("{call}"),
    };
    v.to_bits()
}

fn host64(call: &str, c: f64, d: f64, n: i32) -> u64 {
    let v = match call {
        "libm::sin(c)" => libm::sin(c),
        "libm::cos(c)" => libm::cos(c),
        "libm::tan(c)" => libm::tan(c),
        "libm::asin(c)" => libm::asin(c),
        "libm::acos(c)" => libm::acos(c),
        "libm::atan(c)" => libm::atan(c),
        "libm::atan2(c, d)" => libm::atan2(c, d),
        "libm::exp(c)" => libm::exp(c),
        "libm::exp2(c)" => libm::exp2(c),
        "libm::log(c)" => libm::log(c),
        "libm::log2(c)" => libm::log2(c),
        "libm::log10(c)" => libm::log10(c),
        "libm::pow(c, d)" => libm::pow(c, d),
        "libm::powi(c, n)" => libm::powi(c, n),
        "libm::hypot(c, d)" => libm::hypot(c, d),
        "libm::cbrt(c)" => libm::cbrt(c),
        _ => unreachable!("{call}"),
    };
    v.to_bits()
}

/// The operand tables.
struct Inputs {
    a: Vec<f32>,
    b: Vec<f32>,
    c: Vec<f64>,
    d: Vec<f64>,
    n: Vec<i32>,
}

const N: usize = 2000;

fn inputs() -> Inputs {
    let mut rng = Rng(0x11b_2026);
    let e32 = edge_f32();
    let e64 = edge_f64();
    // Ranges where the functions are interesting (trig, inverse trig, exp/log, pow).
    let ranges = [
        (-1.0, 1.0),
        (-10.0, 10.0),
        (-200.0, 200.0),
        (0.0, 4.0),
        (-1e6, 1e6),
    ];
    let mut inp = Inputs {
        a: Vec::new(),
        b: Vec::new(),
        c: Vec::new(),
        d: Vec::new(),
        n: Vec::new(),
    };
    for i in 0..N {
        let (lo, hi) = ranges[i % ranges.len()];
        // Edge values first (every third of them), then random points.
        let a = if 3 * i < e32.len() {
            e32[3 * i]
        } else {
            sample_f32(&mut rng, lo, hi)
        };
        let c = if 5 * i < e64.len() && i < 1000 {
            e64[5 * i]
        } else {
            sample_f64(&mut rng, lo, hi)
        };
        let b = if rng.next().is_multiple_of(4) {
            e32[(rng.next() % e32.len() as u64) as usize]
        } else {
            sample_f32(&mut rng, lo, hi)
        };
        let d = if rng.next().is_multiple_of(4) {
            e64[(rng.next() % e64.len() as u64) as usize]
        } else {
            sample_f64(&mut rng, lo, hi)
        };
        let n = match rng.next() % 4 {
            0 => rng.next() as i32,
            1 => (rng.next() % 2001) as i32 - 1000,
            _ => (rng.next() % 41) as i32 - 20,
        };
        inp.a.push(a);
        inp.b.push(b);
        inp.c.push(c);
        inp.d.push(d);
        inp.n.push(n);
    }
    inp
}

fn table<T: std::fmt::LowerHex>(s: &mut String, name: &str, ty: &str, v: &[T]) {
    writeln!(s, "static {name}: [{ty}; {}] = [", v.len()).unwrap();
    for x in v {
        writeln!(s, "    {x:#x},").unwrap();
    }
    s.push_str("];\n\n");
}

fn kernel(inp: &Inputs) -> String {
    let mut s = String::from("//! Generated by tests/libm_differential.rs.\n\nuse trax::libm;\n\n");
    let a: Vec<u32> = inp.a.iter().map(|x| x.to_bits()).collect();
    let b: Vec<u32> = inp.b.iter().map(|x| x.to_bits()).collect();
    let c: Vec<u64> = inp.c.iter().map(|x| x.to_bits()).collect();
    let d: Vec<u64> = inp.d.iter().map(|x| x.to_bits()).collect();
    let n: Vec<u32> = inp.n.iter().map(|&x| x as u32).collect();
    table(&mut s, "A", "u32", &a);
    table(&mut s, "B", "u32", &b);
    table(&mut s, "C", "u64", &c);
    table(&mut s, "D", "u64", &d);
    table(&mut s, "NN", "u32", &n);
    s.push_str(
        "fn trax_main() {\n    if trax::global_id() != 0 {\n        return;\n    }\n    \
         // Global register 0 is 0 at run time, unknown to the optimiser.\n    \
         let z = trax::global_read(0);\n    let z64 = z as u64;\n    let mut i = 0usize;\n    \
         while i < A.len() {\n        let a = f32::from_bits(A[i] ^ z);\n        \
         let b = f32::from_bits(B[i] ^ z);\n        let c = f64::from_bits(C[i] ^ z64);\n        \
         let d = f64::from_bits(D[i] ^ z64);\n        let n = (NN[i] ^ z) as i32;\n",
    );
    for (k, call) in F32_CALLS.iter().enumerate() {
        writeln!(s, "        println!(\"f{k} {{}}\", {call}.to_bits());").unwrap();
    }
    writeln!(
        s,
        "        let mut s = 0.0f32;\n        let mut co = 0.0f32;\n        \
         libm::sincosf(a, &mut s, &mut co);\n        \
         println!(\"sincosf {{}} {{}}\", s.to_bits(), co.to_bits());"
    )
    .unwrap();
    for (k, call) in F64_CALLS.iter().enumerate() {
        writeln!(s, "        println!(\"d{k} {{}}\", {call}.to_bits());").unwrap();
    }
    writeln!(
        s,
        "        let mut s = 0.0f64;\n        let mut co = 0.0f64;\n        \
         libm::sincos(c, &mut s, &mut co);\n        \
         println!(\"sincos {{}} {{}}\", s.to_bits(), co.to_bits());"
    )
    .unwrap();
    s.push_str("        i += 1;\n    }\n}\n");
    s
}

/// The expected output, line by line.
fn expected(inp: &Inputs) -> Vec<String> {
    let mut out = Vec::new();
    for i in 0..inp.a.len() {
        let (a, b, c, d, n) = (inp.a[i], inp.b[i], inp.c[i], inp.d[i], inp.n[i]);
        for (k, call) in F32_CALLS.iter().enumerate() {
            out.push(format!("f{k} {}", host32(call, a, b, n)));
        }
        let (mut s, mut co) = (0.0f32, 0.0f32);
        libm::sincosf(a, &mut s, &mut co);
        out.push(format!("sincosf {} {}", s.to_bits(), co.to_bits()));
        for (k, call) in F64_CALLS.iter().enumerate() {
            out.push(format!("d{k} {}", host64(call, c, d, n)));
        }
        let (mut s, mut co) = (0.0f64, 0.0f64);
        libm::sincos(c, &mut s, &mut co);
        out.push(format!("sincos {} {}", s.to_bits(), co.to_bits()));
    }
    out
}

/// Describes every line where `stdout` differs from `exp`, naming the call and inputs.
fn compare(what: &str, stdout: &str, exp: &[String], inp: &Inputs) -> Vec<String> {
    let lines: Vec<&str> = stdout.lines().filter(|l| !l.is_empty()).collect();
    let mut bad = Vec::new();
    if lines.len() != exp.len() {
        bad.push(format!(
            "{what}: {} output lines, expected {}",
            lines.len(),
            exp.len()
        ));
    }
    let per = exp.len() / inp.a.len();
    for (k, (got, want)) in lines.iter().zip(exp).enumerate() {
        if got != want {
            let i = k / per;
            bad.push(format!(
                "{what}: `{got}`, want `{want}` (a={:e} b={:e} c={:e} d={:e} n={})",
                inp.a[i], inp.b[i], inp.c[i], inp.d[i], inp.n[i]
            ));
        }
    }
    bad
}

#[test]
fn every_libm_function_gives_the_same_bits_on_the_machine_and_natively() {
    let inp = inputs();
    let path = tmp().join("libm_kernel.rs");
    std::fs::write(&path, kernel(&inp)).unwrap();
    let exp = expected(&inp);
    let mut bad = Vec::new();
    for opt in [0, 2] {
        let (out, _) = emulate(&path, opt);
        bad.extend(compare(&format!("emulator -O{opt}"), &out, &exp, &inp));
    }
    bad.extend(compare(
        "native",
        &native(&path, &tmp().join("native-cache")),
        &exp,
        &inp,
    ));
    assert!(
        bad.is_empty(),
        "{} mismatches ({}); first:\n{}",
        bad.len(),
        path.display(),
        bad.iter().take(20).cloned().collect::<Vec<_>>().join("\n")
    );
    // Not vacuous: NaN, infinite, zero and subnormal results all occur.
    let kinds = |bits: &str| -> Option<&'static str> {
        let v: u64 = bits.parse().ok()?;
        let f = f32::from_bits(v as u32);
        Some(if f.is_nan() {
            "nan"
        } else if f.is_infinite() {
            "inf"
        } else if f == 0.0 {
            "zero"
        } else if f.is_subnormal() {
            "subnormal"
        } else {
            "normal"
        })
    };
    let mut seen = std::collections::BTreeSet::new();
    for l in exp.iter().filter(|l| l.starts_with('f')) {
        if let Some(k) = l.split_whitespace().nth(1).and_then(kinds) {
            seen.insert(k);
        }
    }
    assert_eq!(seen.len(), 5, "{seen:?}");
}

/// Instructions per call on the simulator (-O2), over inputs typical of rendering
/// (angles in [-pi, pi], ...): one loop per function between `trax.profbegin k` and
/// `trax.profend k`, minus the same loop without the call. Printed as a table; the
/// bound checked is issue 18's budget for ray tracing, sinf and cosf at most 40. The
/// functions are `#[inline]` and LLVM inlines these loops' calls (and hoists the
/// constant loads, two instructions per f64 constant, out of the loop); the `called`
/// rows go through a `#[inline(never)]` wrapper, the cost of a call site outside a loop.
#[test]
fn instruction_counts_per_call() {
    // (label, call, range of x); `y` is a second operand in [0.5, 2].
    let pi = "3.14159";
    let f32_fns: Vec<(&str, String, &str, &str)> = vec![
        ("sinf", "libm::sinf(x)".into(), "-3.14159", pi),
        ("cosf", "libm::cosf(x)".into(), "-3.14159", pi),
        ("sinf big", "libm::sinf(x)".into(), "-100.0", "100.0"),
        ("sinf called", "called_sinf(x)".into(), "-3.14159", pi),
        ("tanf", "libm::tanf(x)".into(), "-3.14159", pi),
        (
            "sincosf",
            "{ let mut s = 0.0; let mut c = 0.0; libm::sincosf(x, &mut s, &mut c); s + c }".into(),
            "-3.14159",
            pi,
        ),
        ("asinf", "libm::asinf(x)".into(), "-1.0", "1.0"),
        ("acosf", "libm::acosf(x)".into(), "-1.0", "1.0"),
        ("atanf", "libm::atanf(x)".into(), "-10.0", "10.0"),
        (
            "atan2f",
            "libm::atan2f(x, y - 1.25)".into(),
            "-10.0",
            "10.0",
        ),
        ("expf", "libm::expf(x)".into(), "-10.0", "10.0"),
        ("exp2f", "libm::exp2f(x)".into(), "-10.0", "10.0"),
        ("logf", "libm::logf(x)".into(), "0.001", "100.0"),
        ("log2f", "libm::log2f(x)".into(), "0.001", "100.0"),
        ("log10f", "libm::log10f(x)".into(), "0.001", "100.0"),
        ("powf", "libm::powf(x, y)".into(), "0.001", "10.0"),
        ("powif", "libm::powif(x, 5)".into(), "-2.0", "2.0"),
        ("hypotf", "libm::hypotf(x, y)".into(), "-10.0", "10.0"),
        ("cbrtf", "libm::cbrtf(x)".into(), "-100.0", "100.0"),
    ];
    // The same with the f64 functions on the same (widened) inputs.
    let f64_fns: Vec<(String, String, &str, &str)> = f32_fns
        .iter()
        .map(|(label, call, lo, hi)| {
            let name = label.split(' ').next().unwrap();
            let name64 = &name[..name.len() - 1];
            let call = call
                .replace(&format!("libm::{name}("), &format!("libm::{name64}("))
                .replace(&format!("called_{name}("), &format!("called_{name64}("))
                .replace("0.0;", "0.0f64;")
                .replace("(x", "(x as f64")
                .replace(", y", ", y as f64");
            (label.replacen(name, name64, 1), call, *lo, *hi)
        })
        .collect();
    let f32_fns: Vec<(String, String, &str, &str)> = f32_fns
        .into_iter()
        .map(|(l, c, lo, hi)| (l.to_string(), c, lo, hi))
        .collect();
    const ITERS: u32 = 256;
    let mut rows = Vec::new();
    for (group, fns) in [("f32", f32_fns), ("f64", f64_fns)] {
        let mut s = String::from(
            "use trax::libm;\n\n\
             #[inline(never)]\nfn called_sinf(x: f32) -> f32 {\n    libm::sinf(x)\n}\n\n\
             #[inline(never)]\nfn called_sin(x: f64) -> f64 {\n    libm::sin(x)\n}\n\n\
             fn trax_main() {\n    let z = trax::global_read(0) as f32;\n    \
             let mut acc = 0.0f64;\n",
        );
        // Region 0: the loop without a call.
        let base = (String::new(), "x".to_string(), "0.0", "1.0");
        for (k, (_, call, lo, hi)) in std::iter::once(&base).chain(fns.iter()).enumerate() {
            let lo: f32 = lo.parse().unwrap();
            let hi: f32 = hi.parse().unwrap();
            let step = (hi - lo) / ITERS as f32;
            writeln!(
                s,
                "    __trax_op!(\"trax.profbegin\", {k});\n    let mut x = {lo:?}f32 + z;\n    \
                 let mut y = 0.5f32 + z;\n    let mut i = 0u32;\n    while i < {ITERS} {{\n        \
                 acc += ({call}) as f64;\n        x += {step:?};\n        y += 0.005859375;\n        \
                 i += 1;\n    }}\n    __trax_op!(\"trax.profend\", {k});"
            )
            .unwrap();
        }
        s.push_str("    println!(\"{}\", acc);\n}\n");
        let path = tmp().join(format!("libm_cost_{group}.rs"));
        std::fs::write(&path, &s).unwrap();
        let (_, profile) = emulate(&path, 2);
        let base = profile[0] as f64 / ITERS as f64;
        for (k, (label, _, lo, hi)) in fns.iter().enumerate() {
            let per = profile[k + 1] as f64 / ITERS as f64 - base;
            rows.push((label.clone(), lo.to_string(), hi.to_string(), per));
        }
    }
    println!("instructions per call (trax -O2, functional, {ITERS} calls each):");
    for (label, lo, hi, per) in &rows {
        println!("  {label:18} x in [{lo}, {hi}]  {per:6.1}");
    }
    for (label, _, _, per) in &rows {
        if label == "sinf" || label == "cosf" {
            assert!(*per <= 40.0, "{label}: {per} instructions per call");
        }
        assert!(*per > 3.0, "{label}: {per}: the call was optimised away?");
    }
}
