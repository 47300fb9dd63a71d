//! Differential test of every `f32x4`/`i32x4` method and operator: a generated TRaX-Rust
//! kernel applies each one to random and edge inputs (NaNs with signs and payloads,
//! signalling NaNs, ±0, ±inf, subnormals, the i32 range ends, conversion boundaries)
//! and prints every result's bits. It runs on the emulator compiled at -O0 and -O2 and
//! natively (`trax native`); each output is compared with the host prelude's own
//! `f32x4`/`i32x4` (`runtime/prelude/simd.rs`, included here) evaluated on the same
//! inputs.
//!
//! The inputs live in static tables XORed with a global register that holds 0 at run
//! time, so the optimiser cannot fold any operation (LLVM 14's MSA lowering of `fabs`
//! and `fma` was wrong only for values it could not fold).
//!
//! Comparison rule: bit for bit, except for the results Rust leaves unspecified: when
//! `+ - * /`, `sqrt` or `mul_add` (and the assigning operators) give NaN, any quiet NaN
//! whose bits other than the sign are the default NaN's (`0x7FC00000`) or one of the NaN
//! inputs' quieted is accepted (Rust's rule for the NaN an arithmetic operation returns).
//! `neg`, `abs`, `select`, `splat`, `new`, `get` move bits and are exact on NaNs too;
//! `min`/`max` are exact as well, since their host semantics (`trax_runtime::fops`,
//! IEEE minNum/maxNum, `min(-0, +0) = -0`, two NaNs give the first, quieted) are fully
//! specified. Conversions are exact (`as`: truncating, saturating, NaN to 0; round to
//! nearest even).
//!
//! A second test makes the coverage complete: every public method and operator impl of
//! the host types, every name in the compiler's SIMD method table and every operator the
//! compiler accepts on the SIMD types must have a line in the kernel.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use ::trax::native::check::RustcCheck;
use ::trax::pipeline::compile_object_checked;
use trax_compiler::Emit;

mod differential;
use differential::{emulate, native, root};

/// What `runtime/prelude/simd.rs` reaches as `super::hw`.
mod hw {
    pub use trax_runtime::fops::{fmax, fmin};
}

/// The host implementation itself: the oracle.
#[allow(dead_code)]
#[path = "../runtime/prelude/simd.rs"]
mod simd;

use simd::{f32x4, i32x4};

fn tmp() -> PathBuf {
    differential::scratch("simd-differential")
}

// ------------------------------------------------------------------ the operations

/// How a result is compared.
#[derive(Clone, Copy, PartialEq)]
enum Rule {
    /// Bit for bit.
    Exact,
    /// Bit for bit unless the expected lane is NaN (see the module docs).
    ArithNan,
}

/// How the kernel prints a result: `f` an `f32x4`'s lane bits, `i` an `i32x4`'s lanes,
/// `s` one `u32`.
#[derive(Clone, Copy)]
enum Print {
    F,
    I,
    S,
}

/// One kernel line: tag (`type::api`, `#...` distinguishes repeats), how it prints, the
/// kernel expression and the comparison rule. In the kernel, `a`, `b`, `c` are the
/// operands, `m` an `i32x4` mask and `idx` a lane index in 0..4, all unknown at compile
/// time.
struct Op {
    tag: &'static str,
    print: Print,
    expr: &'static str,
    rule: Rule,
}

const fn op(tag: &'static str, print: Print, expr: &'static str, rule: Rule) -> Op {
    Op {
        tag,
        print,
        expr,
        rule,
    }
}

use Print::{F, I, S};
use Rule::{ArithNan, Exact};

/// Operations on `f32x4` operands `a`, `b`, `c`.
const FLOAT_OPS: &[Op] = &[
    op("f32x4::Add", F, "a + b", ArithNan),
    op("f32x4::Sub", F, "a - b", ArithNan),
    op("f32x4::Mul", F, "a * b", ArithNan),
    op("f32x4::Div", F, "a / b", ArithNan),
    op("f32x4::Neg", F, "-a", Exact),
    op("f32x4::abs", F, "a.abs()", Exact),
    op("f32x4::sqrt", F, "a.sqrt()", ArithNan),
    op("f32x4::min", F, "a.min(b)", Exact),
    op("f32x4::max", F, "a.max(b)", Exact),
    op("f32x4::mul_add", F, "a.mul_add(b, c)", ArithNan),
    op("f32x4::lt", I, "a.lt(b)", Exact),
    op("f32x4::le", I, "a.le(b)", Exact),
    op("f32x4::gt", I, "a.gt(b)", Exact),
    op("f32x4::ge", I, "a.ge(b)", Exact),
    op("f32x4::eq", I, "a.eq(b)", Exact),
    op("f32x4::to_i32x4", I, "a.to_i32x4()", Exact),
    op("f32x4::select", F, "f32x4::select(m, a, b)", Exact),
    op("f32x4::splat", F, "f32x4::splat(a.get(idx))", Exact),
    op(
        "f32x4::new",
        F,
        "f32x4::new(c.get(idx), a.get(1), b.get(2), a.get(idx ^ 1))",
        Exact,
    ),
    op("f32x4::get", S, "a.get(idx).to_bits()", Exact),
    op(
        "f32x4::AddAssign",
        F,
        "{ let mut t = a; t += b; t }",
        ArithNan,
    ),
    op(
        "f32x4::SubAssign",
        F,
        "{ let mut t = a; t -= b; t }",
        ArithNan,
    ),
    op(
        "f32x4::MulAssign",
        F,
        "{ let mut t = a; t *= b; t }",
        ArithNan,
    ),
    op(
        "f32x4::DivAssign",
        F,
        "{ let mut t = a; t /= b; t }",
        ArithNan,
    ),
];

/// Operations on `i32x4` operands `a`, `b` (and mask `m`).
const INT_OPS: &[Op] = &[
    op("i32x4::Add", I, "a + b", Exact),
    op("i32x4::Sub", I, "a - b", Exact),
    op("i32x4::Mul", I, "a * b", Exact),
    op("i32x4::BitAnd", I, "a & b", Exact),
    op("i32x4::BitOr", I, "a | b", Exact),
    op("i32x4::BitXor", I, "a ^ b", Exact),
    op("i32x4::Neg", I, "-a", Exact),
    op("i32x4::to_f32x4", F, "a.to_f32x4()", Exact),
    op("i32x4::select", I, "i32x4::select(m, a, b)", Exact),
    op("i32x4::any", S, "if m.any() { 1 } else { 0 }", Exact),
    op("i32x4::all", S, "if m.all() { 1 } else { 0 }", Exact),
    op("i32x4::any#a", S, "if a.any() { 1 } else { 0 }", Exact),
    op("i32x4::all#a", S, "if a.all() { 1 } else { 0 }", Exact),
    op("i32x4::splat", I, "i32x4::splat(a.get(idx))", Exact),
    op(
        "i32x4::new",
        I,
        "i32x4::new(b.get(idx), a.get(1), b.get(2), a.get(idx ^ 1))",
        Exact,
    ),
    op("i32x4::get", S, "a.get(idx) as u32", Exact),
    op("i32x4::AddAssign", I, "{ let mut t = a; t += b; t }", Exact),
    op("i32x4::SubAssign", I, "{ let mut t = a; t -= b; t }", Exact),
    op("i32x4::MulAssign", I, "{ let mut t = a; t *= b; t }", Exact),
    op(
        "i32x4::BitAndAssign",
        I,
        "{ let mut t = a; t &= b; t }",
        Exact,
    ),
    op(
        "i32x4::BitOrAssign",
        I,
        "{ let mut t = a; t |= b; t }",
        Exact,
    ),
    op(
        "i32x4::BitXorAssign",
        I,
        "{ let mut t = a; t ^= b; t }",
        Exact,
    ),
];

fn fv(l: [u32; 4]) -> f32x4 {
    f32x4::new(
        f32::from_bits(l[0]),
        f32::from_bits(l[1]),
        f32::from_bits(l[2]),
        f32::from_bits(l[3]),
    )
}

fn iv(l: [i32; 4]) -> i32x4 {
    i32x4::new(l[0], l[1], l[2], l[3])
}

fn fbits(v: f32x4) -> Vec<u32> {
    (0..4).map(|i| v.get(i).to_bits()).collect()
}

fn ibits(v: i32x4) -> Vec<u32> {
    (0..4).map(|i| v.get(i) as u32).collect()
}

/// The host's result of float operation `tag`.
fn eval_float(tag: &str, a: f32x4, b: f32x4, c: f32x4, m: i32x4, idx: usize) -> Vec<u32> {
    let assign = |f: &dyn Fn(&mut f32x4)| {
        let mut t = a;
        f(&mut t);
        fbits(t)
    };
    match tag {
        "f32x4::Add" => fbits(a + b),
        "f32x4::Sub" => fbits(a - b),
        "f32x4::Mul" => fbits(a * b),
        "f32x4::Div" => fbits(a / b),
        "f32x4::Neg" => fbits(-a),
        "f32x4::abs" => fbits(a.abs()),
        "f32x4::sqrt" => fbits(a.sqrt()),
        "f32x4::min" => fbits(a.min(b)),
        "f32x4::max" => fbits(a.max(b)),
        "f32x4::mul_add" => fbits(a.mul_add(b, c)),
        "f32x4::lt" => ibits(a.lt(b)),
        "f32x4::le" => ibits(a.le(b)),
        "f32x4::gt" => ibits(a.gt(b)),
        "f32x4::ge" => ibits(a.ge(b)),
        "f32x4::eq" => ibits(a.eq(b)),
        "f32x4::to_i32x4" => ibits(a.to_i32x4()),
        "f32x4::select" => fbits(f32x4::select(m, a, b)),
        "f32x4::splat" => fbits(f32x4::splat(a.get(idx))),
        "f32x4::new" => fbits(f32x4::new(c.get(idx), a.get(1), b.get(2), a.get(idx ^ 1))),
        "f32x4::get" => vec![a.get(idx).to_bits()],
        "f32x4::AddAssign" => assign(&|t| *t += b),
        "f32x4::SubAssign" => assign(&|t| *t -= b),
        "f32x4::MulAssign" => assign(&|t| *t *= b),
        "f32x4::DivAssign" => assign(&|t| *t /= b),
        _ => panic!("no oracle for {tag}"),
    }
}

/// The host's result of integer operation `tag`.
fn eval_int(tag: &str, a: i32x4, b: i32x4, m: i32x4, idx: usize) -> Vec<u32> {
    let assign = |f: &dyn Fn(&mut i32x4)| {
        let mut t = a;
        f(&mut t);
        ibits(t)
    };
    match tag {
        "i32x4::Add" => ibits(a + b),
        "i32x4::Sub" => ibits(a - b),
        "i32x4::Mul" => ibits(a * b),
        "i32x4::BitAnd" => ibits(a & b),
        "i32x4::BitOr" => ibits(a | b),
        "i32x4::BitXor" => ibits(a ^ b),
        "i32x4::Neg" => ibits(-a),
        "i32x4::to_f32x4" => fbits(a.to_f32x4()),
        "i32x4::select" => ibits(i32x4::select(m, a, b)),
        "i32x4::any" => vec![m.any() as u32],
        "i32x4::all" => vec![m.all() as u32],
        "i32x4::any#a" => vec![a.any() as u32],
        "i32x4::all#a" => vec![a.all() as u32],
        "i32x4::splat" => ibits(i32x4::splat(a.get(idx))),
        "i32x4::new" => ibits(i32x4::new(b.get(idx), a.get(1), b.get(2), a.get(idx ^ 1))),
        "i32x4::get" => vec![a.get(idx) as u32],
        "i32x4::AddAssign" => assign(&|t| *t += b),
        "i32x4::SubAssign" => assign(&|t| *t -= b),
        "i32x4::MulAssign" => assign(&|t| *t *= b),
        "i32x4::BitAndAssign" => assign(&|t| *t &= b),
        "i32x4::BitOrAssign" => assign(&|t| *t |= b),
        "i32x4::BitXorAssign" => assign(&|t| *t ^= b),
        _ => panic!("no oracle for {tag}"),
    }
}

// ------------------------------------------------------------------ the inputs

/// SplitMix64: a fixed, dependency-free input stream.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    fn u32(&mut self) -> u32 {
        self.next() as u32
    }
}

/// f32 edge values (bit patterns).
const F_EDGES: &[u32] = &[
    0x0000_0000, // +0
    0x8000_0000, // -0
    0x7F80_0000, // +inf
    0xFF80_0000, // -inf
    0x7FC0_0000, // default quiet NaN
    0xFFC0_0000, // negative quiet NaN
    0x7FC1_2345, // quiet NaN with payload
    0xFFE5_4321, // negative quiet NaN with payload
    0x7F80_0001, // signalling NaN
    0xFF81_2345, // negative signalling NaN with payload
    0x0000_0001, // smallest subnormal
    0x8000_0001,
    0x007F_FFFF, // largest subnormal
    0x803F_FFFF,
    0x0080_0000, // smallest normal
    0x8080_0000,
    0x3F80_0000, // 1
    0xBF80_0000, // -1
    0x3F00_0000, // 0.5
    0xBFC0_0000, // -1.5
    0x3FC0_0000, // 1.5
    0x4040_0000, // 3
    0x3F80_0001, // 1 + ulp
    0x7F7F_FFFF, // largest finite
    0xFF7F_FFFF,
    0x4F00_0000, // 2^31
    0xCF00_0000, // -2^31
    0x4EFF_FFFF, // 2^31 - 128: largest f32 below 2^31
    0xCF00_0001, // just below -2^31
    0x1E3C_E508, // 1e-20
    0x5F80_0000, // 2^64
    0xC2F6_E979, // -123.456
];

/// i32 edge values.
const I_EDGES: &[i32] = &[
    0,
    1,
    -1,
    2,
    -2,
    i32::MIN,
    i32::MAX,
    i32::MIN + 1,
    i32::MAX - 1,
    0x5555_5555,
    0xAAAA_AAAAu32 as i32,
    0x1_0000,
    -0x1_0000,
    46341,      // squares past i32::MAX
    16_777_217, // 2^24 + 1: not an f32
    16_777_219, // rounds up to even
    -16_777_217,
    0x7FFF_FFC0, // tie between two f32s: to even
    0x7FFF_FF80,
    -0x7FFF_FFC0,
];

/// A random f32 bit pattern from a mix of distributions.
fn rand_f32(r: &mut Rng) -> u32 {
    let sign = (r.u32() & 1) << 31;
    match r.below(7) {
        0 => r.u32(),
        1 | 2 => sign | (r.below(40) as u32 + 107) << 23 | (r.u32() & 0x7F_FFFF),
        3 => sign | (r.below(3) as u32) << 23 | (r.u32() & 0x7F_FFFF),
        4 => {
            // Around the i32 range, halves included: conversions.
            let x = (r.next() % 6_000_000_000) as i64 - 3_000_000_000;
            let f = if r.below(2) == 0 {
                x as f32
            } else {
                (x % 100_000) as f32 + 0.5
            };
            f.to_bits()
        }
        5 => sign | (r.below(5) as u32 + 250) << 23 | (r.u32() & 0x7F_FFFF),
        _ => F_EDGES[r.below(F_EDGES.len() as u64) as usize],
    }
}

fn rand_i32(r: &mut Rng) -> i32 {
    match r.below(5) {
        0 | 1 => r.u32() as i32,
        2 => r.below(2001) as i32 - 1000,
        3 => (1i32.wrapping_shl(r.below(32) as u32)).wrapping_add(r.below(3) as i32 - 1),
        _ => I_EDGES[r.below(I_EDGES.len() as u64) as usize],
    }
}

fn rand_mask(r: &mut Rng) -> i32 {
    match r.below(8) {
        0..=3 => 0,
        4 => -1,
        5 => 1,
        6 => i32::MIN,
        _ => r.u32() as i32,
    }
}

fn chunks<T: Copy + Default>(v: &[T]) -> Vec<[T; 4]> {
    v.chunks(4)
        .map(|c| {
            let mut l = [T::default(); 4];
            l[..c.len()].copy_from_slice(c);
            l
        })
        .collect()
}

/// The kernel's input tables.
struct Inputs {
    fa: Vec<[u32; 4]>,
    fb: Vec<[u32; 4]>,
    fc: Vec<[u32; 4]>,
    fm: Vec<[i32; 4]>,
    ia: Vec<[i32; 4]>,
    ib: Vec<[i32; 4]>,
    im: Vec<[i32; 4]>,
}

fn inputs() -> Inputs {
    let mut r = Rng(0x7EA5_2016);
    let (mut fa, mut fb, mut fc, mut fm) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let e = F_EDGES.len();
    // Every ordered pair of edge values; the addend cycles through the edges too.
    for i in 0..e {
        for j in 0..e {
            fa.push(F_EDGES[i]);
            fb.push(F_EDGES[j]);
            fc.push(F_EDGES[(i * 5 + j * 3 + 1) % e]);
            fm.push(rand_mask(&mut r));
        }
    }
    // Random operands, some with related second operands (equal, negated, one ulp
    // apart, doubled) so equality, cancellation and ties are common.
    for _ in 0..1600 {
        let a = rand_f32(&mut r);
        let b = match r.below(6) {
            0 => a,
            1 => a ^ 0x8000_0000,
            2 => a.wrapping_add(1),
            3 => (f32::from_bits(a) * 2.0).to_bits(),
            _ => rand_f32(&mut r),
        };
        fa.push(a);
        fb.push(b);
        fc.push(rand_f32(&mut r));
        fm.push(rand_mask(&mut r));
    }
    // Fused multiply-add where fusing matters: c = -(a * b) rounded, so the fused result
    // is the product's rounding error (zero when unfused).
    for _ in 0..256 {
        let a = f32::from_bits(0x3F80_0000 | (r.u32() & 0x7F_FFFF));
        let b = f32::from_bits((r.below(20) as u32 + 117) << 23 | (r.u32() & 0x7F_FFFF));
        let c = -(a * b);
        let c = if r.below(4) == 0 {
            f32::from_bits(c.to_bits().wrapping_add(1))
        } else {
            c
        };
        fa.push(a.to_bits());
        fb.push(b.to_bits());
        fc.push(c.to_bits());
        fm.push(rand_mask(&mut r));
    }
    let (mut ia, mut ib, mut im) = (Vec::new(), Vec::new(), Vec::new());
    for &x in I_EDGES {
        for &y in I_EDGES {
            ia.push(x);
            ib.push(y);
            im.push(rand_mask(&mut r));
        }
    }
    for _ in 0..800 {
        ia.push(rand_i32(&mut r));
        ib.push(rand_i32(&mut r));
        im.push(rand_mask(&mut r));
    }
    // Masks of every zero/non-zero pattern for `any`/`all`, twice.
    for p in 0..32 {
        for lane in 0..4 {
            im.push(if p >> lane & 1 != 0 {
                rand_mask(&mut r) | 4
            } else {
                0
            });
            ia.push(if (p + 7) >> lane & 1 != 0 {
                rand_i32(&mut r) | 8
            } else {
                0
            });
            ib.push(rand_i32(&mut r));
        }
    }
    Inputs {
        fa: chunks(&fa),
        fb: chunks(&fb),
        fc: chunks(&fc),
        fm: chunks(&fm),
        ia: chunks(&ia),
        ib: chunks(&ib),
        im: chunks(&im),
    }
}

// ------------------------------------------------------------------ kernel and oracle

fn table<T: std::fmt::Display>(out: &mut String, name: &str, ty: &str, v: &[[T; 4]]) {
    writeln!(out, "static {name}: [{ty}; {}] = [", v.len() * 4).unwrap();
    for l in v {
        writeln!(out, "    {}, {}, {}, {},", l[0], l[1], l[2], l[3]).unwrap();
    }
    out.push_str("];\n");
}

fn kernel_line(out: &mut String, o: &Op) {
    let p = match o.print {
        F => "pf",
        I => "pi",
        S => "ps",
    };
    writeln!(out, "        {p}(\"{}\", {});", o.tag, o.expr).unwrap();
}

/// The kernel source.
fn kernel(inp: &Inputs) -> String {
    let mut s = String::from(
        "//! Generated by tests/simd_differential.rs.\n\
         use trax::simd::{f32x4, i32x4};\n\n",
    );
    let nf = inp.fa.len() * 4;
    let ni = inp.ia.len() * 4;
    table(&mut s, "FA", "u32", &inp.fa);
    table(&mut s, "FB", "u32", &inp.fb);
    table(&mut s, "FC", "u32", &inp.fc);
    table(&mut s, "FM", "i32", &inp.fm);
    table(&mut s, "IA", "i32", &inp.ia);
    table(&mut s, "IB", "i32", &inp.ib);
    table(&mut s, "IM", "i32", &inp.im);
    write!(
        s,
        r#"
fn fv(t: &[u32; {nf}], k: usize, z: u32) -> f32x4 {{
    f32x4::new(
        f32::from_bits(t[4 * k] ^ z),
        f32::from_bits(t[4 * k + 1] ^ z),
        f32::from_bits(t[4 * k + 2] ^ z),
        f32::from_bits(t[4 * k + 3] ^ z),
    )
}}

fn iv(t: &[i32; {ni}], k: usize, z: i32) -> i32x4 {{
    i32x4::new(t[4 * k] ^ z, t[4 * k + 1] ^ z, t[4 * k + 2] ^ z, t[4 * k + 3] ^ z)
}}

fn ivf(t: &[i32; {nf}], k: usize, z: i32) -> i32x4 {{
    i32x4::new(t[4 * k] ^ z, t[4 * k + 1] ^ z, t[4 * k + 2] ^ z, t[4 * k + 3] ^ z)
}}

fn pf(tag: &str, v: f32x4) {{
    println!("{{}} {{}} {{}} {{}} {{}}", tag, v.get(0).to_bits(), v.get(1).to_bits(), v.get(2).to_bits(), v.get(3).to_bits());
}}

fn pi(tag: &str, v: i32x4) {{
    println!("{{}} {{}} {{}} {{}} {{}}", tag, v.get(0), v.get(1), v.get(2), v.get(3));
}}

fn ps(tag: &str, v: u32) {{
    println!("{{}} {{}}", tag, v);
}}

fn trax_main() {{
    if trax::global_id() != 0 {{
        return;
    }}
    // Global register 0 is 0 at run time, unknown to the optimiser.
    let z = trax::global_read(0);
    let zi = z as i32;
    let mut k = 0usize;
    while k < {vf} {{
        let a = fv(&FA, k, z);
        let b = fv(&FB, k, z);
        let c = fv(&FC, k, z);
        let m = ivf(&FM, k, zi);
        let idx = (k + z as usize) & 3;
"#,
        vf = inp.fa.len()
    )
    .unwrap();
    for o in FLOAT_OPS {
        kernel_line(&mut s, o);
    }
    write!(
        s,
        r#"        k += 1;
    }}
    k = 0;
    while k < {vi} {{
        let a = iv(&IA, k, zi);
        let b = iv(&IB, k, zi);
        let m = iv(&IM, k, zi);
        let idx = (k + z as usize) & 3;
"#,
        vi = inp.ia.len()
    )
    .unwrap();
    for o in INT_OPS {
        kernel_line(&mut s, o);
    }
    s.push_str("        k += 1;\n    }\n}\n");
    s
}

/// One expected output line.
struct Expect {
    tag: &'static str,
    rule: Rule,
    /// The operands' lanes (for the NaN rule).
    operands: Vec<[u32; 4]>,
    bits: Vec<u32>,
}

fn expected(inp: &Inputs) -> Vec<Expect> {
    let mut out = Vec::new();
    for k in 0..inp.fa.len() {
        let (a, b, c) = (fv(inp.fa[k]), fv(inp.fb[k]), fv(inp.fc[k]));
        let m = iv(inp.fm[k]);
        for o in FLOAT_OPS {
            let operands = match o.tag {
                "f32x4::sqrt" => vec![inp.fa[k]],
                "f32x4::mul_add" => vec![inp.fa[k], inp.fb[k], inp.fc[k]],
                _ => vec![inp.fa[k], inp.fb[k]],
            };
            out.push(Expect {
                tag: o.tag,
                rule: o.rule,
                operands,
                bits: eval_float(o.tag, a, b, c, m, k & 3),
            });
        }
    }
    for k in 0..inp.ia.len() {
        let (a, b, m) = (iv(inp.ia[k]), iv(inp.ib[k]), iv(inp.im[k]));
        for o in INT_OPS {
            out.push(Expect {
                tag: o.tag,
                rule: o.rule,
                operands: Vec::new(),
                bits: eval_int(o.tag, a, b, m, k & 3),
            });
        }
    }
    out
}

fn is_nan(x: u32) -> bool {
    x & 0x7F80_0000 == 0x7F80_0000 && x & 0x7F_FFFF != 0
}

/// Whether `got` is an acceptable result for lane `lane` of `e` (see the module docs).
fn lane_ok(e: &Expect, lane: usize, got: u32) -> bool {
    let want = e.bits[lane];
    if got == want {
        return true;
    }
    if e.rule != ArithNan || !is_nan(want) {
        return false;
    }
    if !is_nan(got) || got & 0x0040_0000 == 0 {
        return false;
    }
    let body = got & 0x7FFF_FFFF;
    body == 0x7FC0_0000
        || e.operands
            .iter()
            .map(|o| o[lane])
            .any(|x| is_nan(x) && (x | 0x0040_0000) & 0x7FFF_FFFF == body)
}

/// Compares printed output with the oracle; returns a description of every mismatch.
fn compare(what: &str, stdout: &str, exp: &[Expect]) -> Vec<String> {
    let lines: Vec<&str> = stdout.lines().filter(|l| !l.is_empty()).collect();
    let mut bad = Vec::new();
    if lines.len() != exp.len() {
        bad.push(format!(
            "{what}: {} output lines, expected {}",
            lines.len(),
            exp.len()
        ));
    }
    for (n, (line, e)) in lines.iter().zip(exp).enumerate() {
        let mut f = line.split_whitespace();
        let tag = f.next().unwrap_or("");
        let got: Vec<u32> = f
            .map(|x| x.parse::<i64>().map(|v| v as u32).unwrap_or(u32::MAX))
            .collect();
        if tag != e.tag || got.len() != e.bits.len() {
            bad.push(format!(
                "{what}: line {n}: `{line}`, expected a `{}` line",
                e.tag
            ));
            break;
        }
        for (lane, &g) in got.iter().enumerate() {
            if !lane_ok(e, lane, g) {
                let ops: Vec<String> = e
                    .operands
                    .iter()
                    .map(|o| format!("{:#010x}", o[lane]))
                    .collect();
                bad.push(format!(
                    "{what}: {} lane {lane}: got {g:#010x} want {:#010x} (operands {})",
                    e.tag,
                    e.bits[lane],
                    ops.join(" ")
                ));
            }
        }
    }
    bad
}

// ------------------------------------------------------------------ running

#[test]
fn every_simd_operation_matches_the_host_on_random_and_edge_inputs() {
    let inp = inputs();
    let src = kernel(&inp);
    let path = tmp().join("simd_kernel.rs");
    std::fs::write(&path, &src).unwrap();
    let exp = expected(&inp);
    let mut bad = Vec::new();
    for opt in [0, 2] {
        bad.extend(compare(
            &format!("emulator -O{opt}"),
            &emulate(&path, opt).0,
            &exp,
        ));
    }
    bad.extend(compare(
        "native",
        &native(&path, &tmp().join("native-cache")),
        &exp,
    ));
    if !bad.is_empty() {
        // Summarise by (run, tag), then show the first few of each.
        let mut shown = std::collections::BTreeMap::<String, (usize, Vec<&String>)>::new();
        for b in &bad {
            let key: String = b.split(" lane").next().unwrap_or(b).to_string();
            let e = shown.entry(key).or_default();
            e.0 += 1;
            if e.1.len() < 3 {
                e.1.push(b);
            }
        }
        let mut msg = format!("{} mismatching lanes ({})\n", bad.len(), path.display());
        for (k, (n, ex)) in &shown {
            writeln!(msg, "{k}: {n}").unwrap();
            for e in ex {
                writeln!(msg, "    {e}").unwrap();
            }
        }
        panic!("{msg}");
    }
    // Not vacuous: every operation ran on NaN, infinite and subnormal lanes.
    assert!(exp.len() > 20_000, "{}", exp.len());
}

// ------------------------------------------------------------------ coverage

/// `(type, api)` of every public method and operator impl in the host prelude's
/// `simd.rs`.
fn host_api() -> BTreeSet<(String, String)> {
    let src = std::fs::read_to_string(root().join("runtime/prelude/simd.rs")).unwrap();
    let mut api = BTreeSet::new();
    let mut cur: Option<String> = None;
    for line in src.lines() {
        let t = line.trim();
        for ty in ["f32x4", "i32x4"] {
            if t == format!("impl {ty} {{") {
                cur = Some(ty.to_string());
            }
            // `impl Trait for T` and `macro!(T, Trait, ...)`.
            if let Some(rest) = t.strip_prefix("impl ") {
                if let Some(tr) = rest.strip_suffix(&format!(" for {ty} {{")) {
                    api.insert((ty.to_string(), tr.to_string()));
                }
            }
            if let Some(i) = t.find(&format!("!({ty}, ")) {
                let rest = &t[i + ty.len() + 4..];
                let tr = rest.split(',').next().unwrap().trim();
                api.insert((ty.to_string(), tr.to_string()));
            }
        }
        if line.starts_with('}') {
            cur = None;
        }
        if let (Some(ty), Some(rest)) = (&cur, t.strip_prefix("pub fn ")) {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            api.insert((ty.clone(), name));
        }
    }
    api
}

/// `(type, api)` of every kernel line.
fn covered() -> BTreeSet<(String, String)> {
    FLOAT_OPS
        .iter()
        .chain(INT_OPS)
        .map(|o| {
            let t = o.tag.split('#').next().unwrap();
            let (ty, api) = t.split_once("::").unwrap();
            (ty.to_string(), api.to_string())
        })
        .collect()
}

/// The compiler's SIMD methods and associated functions (its builtin catalogue).
fn compiler_methods() -> Vec<String> {
    use trax_compiler::builtins::{On, ASSOC_FNS, METHODS};
    let names: Vec<String> = METHODS
        .iter()
        .chain(ASSOC_FNS)
        .filter(|m| matches!(m.on, On::F32x4 | On::I32x4))
        .map(|m| m.name.to_string())
        .collect();
    assert!(
        names.len() > 5,
        "no SIMD builtins in the catalogue: {names:?}"
    );
    names
}

/// Whether the trax compiler accepts `stmt` in a kernel with `a`, `b` of type `ty` (the
/// compiler alone: rustc's check would hide an operator the compiler has and the host
/// prelude lacks).
fn compiles(dir: &Path, n: usize, ty: &str, stmt: &str) -> bool {
    let lane = if ty == "f32x4" { "f32" } else { "i32" };
    let src = format!(
        "use trax::simd::{{f32x4, i32x4}};\n\
         fn trax_main() {{\n\
             let z = trax::global_read(0);\n\
             let mut a = {ty}::splat(z as {lane});\n\
             let b = {ty}::splat(1 as {lane});\n\
             {stmt};\n\
             println!(\"{{}}\", a.get(0) == b.get(1));\n\
         }}\n"
    );
    let path = dir.join(format!("probe{n}.rs"));
    std::fs::write(&path, src).unwrap();
    compile_object_checked(&path, 0, Emit::Obj, RustcCheck::Off).is_ok()
}

/// Every public SIMD method and operator (host prelude, compiler method table, operators
/// the compiler accepts) has a line in the differential kernel, and the compiler accepts
/// exactly the operators the host implements.
#[test]
fn differential_kernel_covers_every_simd_method_and_operator() {
    let cov = covered();
    let host = host_api();
    let missing: Vec<_> = host.difference(&cov).collect();
    assert!(
        missing.is_empty(),
        "host f32x4/i32x4 API not covered by the differential kernel: {missing:?}"
    );
    let extra: Vec<_> = cov.difference(&host).collect();
    assert!(
        extra.is_empty(),
        "covered but missing from the host prelude: {extra:?}"
    );
    for m in compiler_methods() {
        assert!(
            cov.iter().any(|(_, api)| *api == m),
            "compiler SIMD method `{m}` not covered"
        );
    }
    let dir = tmp().join("operator-probes");
    std::fs::create_dir_all(&dir).unwrap();
    let binary = [
        ("+", "Add"),
        ("-", "Sub"),
        ("*", "Mul"),
        ("/", "Div"),
        ("%", "Rem"),
        ("&", "BitAnd"),
        ("|", "BitOr"),
        ("^", "BitXor"),
        ("<<", "Shl"),
        (">>", "Shr"),
    ];
    let mut n = 0;
    for ty in ["f32x4", "i32x4"] {
        let mut probes: Vec<(String, String)> = Vec::new();
        for (o, tr) in binary {
            probes.push((format!("let _r = a {o} b"), tr.to_string()));
            probes.push((format!("a {o}= b"), format!("{tr}Assign")));
        }
        probes.push(("let _r = -a".into(), "Neg".into()));
        probes.push(("let _r = !a".into(), "Not".into()));
        for (o, tr) in [
            ("==", "PartialEq"),
            ("!=", "PartialEq"),
            ("<", "PartialOrd"),
            (">=", "PartialOrd"),
        ] {
            probes.push((format!("let _r = a {o} b"), tr.into()));
        }
        for (stmt, tr) in probes {
            n += 1;
            let accepted = compiles(&dir, n, ty, &stmt);
            let cov_has = cov.contains(&(ty.to_string(), tr.clone()));
            assert_eq!(
                accepted, cov_has,
                "`{stmt}` on {ty}: compiler accepts: {accepted}, covered: {cov_has}"
            );
        }
    }
    // The probe itself works: a plain kernel compiles.
    assert!(compiles(&dir, 0, "f32x4", "a = a + b"));
}
