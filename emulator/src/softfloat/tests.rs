//! Unit tests of the soft-float core. The differential oracles are elsewhere
//! (`tests/fpu_qemu.rs`, `tests/qemu_diff.rs`, `tests/msa_qemu.rs` against QEMU;
//! `tests/msa_float.rs` against an independent host-arithmetic model); these pin the
//! boundary cases and check that every fast path agrees with the exact path.

use super::testgen::Rng;
use super::*;

const I: u32 = FLAG_I;
const U: u32 = FLAG_U;
const O: u32 = FLAG_O;
const Z: u32 = FLAG_Z;
const V: u32 = FLAG_V;

/// Rounding per `mode`, no flush to zero, underflow only when inexact.
fn env(mode: Round) -> Env {
    Env::from_fcsr(mode as u32)
}

const MODES: [Round; 4] = [Round::Nearest, Round::Zero, Round::Up, Round::Down];

/// Runs `g` in `mode` and returns (result, flags).
fn run(mode: Round, g: impl FnOnce(&mut Env) -> u64) -> (u64, u32) {
    let mut e = env(mode);
    let r = g(&mut e);
    (r, e.flags)
}

fn s(x: f32) -> u64 {
    x.to_bits() as u64
}
fn d(x: f64) -> u64 {
    x.to_bits()
}

#[test]
fn fast_paths_match_the_exact_path() {
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    // How often each fast path answered (the comparison must not be vacuous).
    let mut hits = std::collections::BTreeMap::<String, u32>::new();
    let mut hit = |k: &str| *hits.entry(k.to_string()).or_default() += 1;
    for f in [Fmt::S, Fmt::D] {
        for _ in 0..400_000 {
            let (a, b, c) = (r.operand(f), r.operand(f), r.operand(f));
            let what = |op: &str| format!("{op} {f:?} {a:#x} {b:#x} {c:#x}");
            // Arithmetic: the fast path answers only in round to nearest.
            for (op, name) in [
                (Op::Add, "add"),
                (Op::Mul, "mul"),
                (Op::Div, "div"),
                (Op::Sqrt, "sqrt"),
                (Op::Fma, "fma"),
            ] {
                if let Some((v, inexact)) = fast::lane(f, op, a, b, c) {
                    hit(&format!("{name} {f:?}"));
                    let want = run(Round::Nearest, |e| match op {
                        Op::Add => exact::add_exact(e, f, a, b),
                        Op::Mul => exact::mul_exact(e, f, a, b),
                        Op::Div => exact::div_exact(e, f, a, b),
                        Op::Sqrt => exact::sqrt_exact(e, f, a),
                        Op::Fma => exact::fma_exact(e, f, a, b, c, false),
                    });
                    assert_eq!((v, if inexact { I } else { 0 }), want, "{}", what(name));
                }
            }
            for mode in MODES {
                for signaling in [false, true] {
                    let mut e = env(mode);
                    if let Some(v) = fast::compare(&mut e, f, a, b, signaling) {
                        hit(&format!("compare {f:?}"));
                        let want =
                            run(mode, |x| exact::compare_exact(x, f, a, b, signaling) as u64);
                        assert_eq!((v as u64, e.flags), want, "{}", what("compare"));
                    }
                }
                if let Some(v) = fast::compare_ordered(f, a, b) {
                    hit(&format!("compare_ordered {f:?}"));
                    for signaling in [false, true] {
                        let want =
                            run(mode, |x| exact::compare_exact(x, f, a, b, signaling) as u64);
                        assert_eq!((v as u64, 0), want, "{}", what("compare_ordered"));
                    }
                }
                for kind in [MinMax::Max, MinMax::Min, MinMax::MaxA, MinMax::MinA] {
                    if let Some(v) = fast::min_max(f, a, b, kind) {
                        hit(&format!("min_max {f:?}"));
                        let want = run(mode, |x| exact::min_max_exact(x, f, a, b, kind));
                        assert_eq!((v, 0), want, "{} {kind:?}", what("min_max"));
                    }
                }
                let mut e = env(mode);
                if let Some(v) = fast::rint(&mut e, f, a) {
                    hit(&format!("rint {f:?}"));
                    let want = run(mode, |x| exact::rint_exact(x, f, a));
                    assert_eq!((v, e.flags), want, "{} {mode:?}", what("rint"));
                }
                for (signed, bits) in [(true, 32), (true, 64), (false, 32), (false, 64)] {
                    let mut e = env(mode);
                    if let Some(v) = fast::to_int(&mut e, f, a, mode, signed, bits) {
                        hit(&format!("to_int {f:?}"));
                        let want = run(mode, |x| exact::to_int_exact(x, f, a, mode, signed, bits));
                        assert_eq!(
                            (v, e.flags),
                            want,
                            "{} {mode:?} {signed} {bits}",
                            what("to_int")
                        );
                    }
                }
                let iv = (r.u64() as i64 >> (r.u64() % 64)) as i128;
                let mut e = env(mode);
                if let Some(v) = fast::from_int(&mut e, f, iv) {
                    hit(&format!("from_int {f:?}"));
                    let want = run(mode, |x| exact::from_int_exact(x, f, iv));
                    assert_eq!((v, e.flags), want, "from_int {f:?} {iv} {mode:?}");
                }
                let to = if f == Fmt::S { Fmt::D } else { Fmt::S };
                let mut e = env(mode);
                if let Some(v) = fast::convert(&mut e, f, to, a) {
                    hit(&format!("convert {f:?}"));
                    let want = run(mode, |x| exact::convert_exact(x, f, to, a));
                    assert_eq!((v, e.flags), want, "{} {mode:?}", what("convert"));
                }
            }
        }
    }
    println!("{hits:?}");
    assert_eq!(
        hits.len(),
        2 * 12 - 1,
        "every fast path answered (D has no fma path)"
    );
    assert!(hits.values().all(|&n| n > 1000), "{hits:?}");
}

#[test]
fn flags_and_rounding_modes() {
    let (one, tiny) = (s(1.0), s(1e-10));
    assert_eq!(run(Round::Nearest, |e| add(e, Fmt::S, one, tiny)), (one, I));
    assert_eq!(
        run(Round::Up, |e| add(e, Fmt::S, one, tiny)).0,
        s(1.0f32.next_up())
    );
    assert_eq!(
        run(Round::Zero, |e| sub(e, Fmt::S, one, tiny)).0,
        s(1.0f32.next_down())
    );
    assert_eq!(
        run(Round::Nearest, |e| add(e, Fmt::S, one, one)),
        (s(2.0), 0)
    );
    // Overflow: to infinity in nearest and away from it in the directed modes.
    let m = s(f32::MAX);
    let inf = s(f32::INFINITY);
    assert_eq!(run(Round::Nearest, |e| add(e, Fmt::S, m, m)), (inf, O | I));
    assert_eq!(run(Round::Zero, |e| add(e, Fmt::S, m, m)), (m, O | I));
    assert_eq!(run(Round::Down, |e| add(e, Fmt::S, m, m)), (m, O | I));
    assert_eq!(run(Round::Up, |e| add(e, Fmt::S, m, m)), (inf, O | I));
    // Just short of the overflow threshold: inexact, not overflow (the sum of MAX and a
    // number half its size in the other sign; an error-free transform's intermediate
    // would overflow here).
    assert_eq!(
        run(Round::Up, |e| sub(e, Fmt::S, 0xf30186c1, m)),
        (0xff7fffff, I)
    );
    assert_eq!(
        run(Round::Nearest, |e| add(
            e,
            Fmt::D,
            0x7fc213c9b0ce7b5e,
            0xffefffffffffffff
        )),
        (0xffeb7b0d93cc6128, I)
    );
    // x - x is -0 in round-down, +0 otherwise.
    assert_eq!(
        run(Round::Down, |e| sub(e, Fmt::S, one, one)),
        (0x8000_0000, 0)
    );
    assert_eq!(run(Round::Nearest, |e| sub(e, Fmt::S, one, one)), (0, 0));
    // Division by zero, 0/0, inf/0.
    assert_eq!(run(Round::Nearest, |e| div(e, Fmt::S, one, 0)), (inf, Z));
    assert_eq!(
        run(Round::Nearest, |e| div(e, Fmt::S, 0, 0)),
        (0x7FC0_0000, V)
    );
    assert_eq!(run(Round::Nearest, |e| div(e, Fmt::S, inf, 0)), (inf, 0));
    // 1/3 in double, nearest and up.
    assert_eq!(
        run(Round::Nearest, |e| div(e, Fmt::D, d(1.0), d(3.0))),
        (d(1.0 / 3.0), I)
    );
    assert_eq!(
        run(Round::Up, |e| div(e, Fmt::D, d(1.0), d(3.0))).0,
        d((1.0f64 / 3.0).next_up())
    );
    assert_eq!(
        run(Round::Down, |e| div(e, Fmt::S, s(1.0), s(3.0))).0,
        s(1.0 / 3.0) - 1
    );
}

#[test]
fn underflow_is_tininess_after_rounding() {
    // Exact tiny result: no Underflow (unless trapped).
    assert_eq!(run(Round::Nearest, |e| add(e, Fmt::S, 2, 2)), (4, 0));
    let mut e = Env {
        trap_underflow: true,
        ..env(Round::Nearest)
    };
    assert_eq!((add(&mut e, Fmt::S, 2, 2), e.flags), (4, U));
    // Inexact tiny result.
    let a = s(1e-30);
    assert_eq!(run(Round::Nearest, |e| mul(e, Fmt::S, a, a)), (0, U | I));
    // 0x3FAAAAAA (4/3 - 2^-23 * 2/3) times 0x00600000 (0.75 * 2^-126) is exactly
    // 2^-126 - 2^-150: on the subnormal grid a tie that rounds to 2^-126, but with an
    // unbounded exponent representable as it is, below 2^-126: tiny.
    let (x, y) = (0x3FAA_AAAAu64, 0x0060_0000u64);
    let (r, fl) = run(Round::Nearest, |e| mul(e, Fmt::S, x, y));
    assert_eq!(r, 0x0080_0000, "rounds to the smallest normal");
    assert_eq!(fl, U | I, "but was tiny before the exponent was bounded");
    // The fused case found against QEMU: -(2^-126 - 2^-149) - tiny, rounded down.
    assert_eq!(
        run(Round::Down, |e| fma(
            e,
            Fmt::S,
            0x1d2821b0,
            0x8102ca1d,
            0x807fffff,
            false
        )),
        (0x8080_0000, U | I)
    );
    // Not tiny: the exact value is at least the smallest normal.
    assert_eq!(
        run(Round::Nearest, |e| mul(e, Fmt::S, s(2.0), 0x0040_0000)),
        (0x0080_0000, 0)
    );
}

#[test]
fn underflow_to_zero_keeps_the_sign_of_the_exact_result() {
    // Positive tiny quotient rounded down: +0 (not -0).
    assert_eq!(
        run(Round::Down, |e| div(e, Fmt::S, 0x10af1d37, 0x5b75eecd)),
        (0, U | I)
    );
    assert_eq!(
        run(Round::Down, |e| mul(e, Fmt::S, 0x1cba9e9c, 0x17497838)),
        (0, U | I)
    );
    // Negative tiny results rounded toward zero or up: -0.
    assert_eq!(
        run(Round::Zero, |e| div(e, Fmt::D, 0x8000000000000001, d(1.5))),
        (1 << 63, U | I)
    );
    assert_eq!(
        run(Round::Up, |e| mul(e, Fmt::D, 0x8000000000000001, d(0.9))),
        (1 << 63, U | I)
    );
    // Narrowing a positive double below the binary32 range toward zero: +0.
    assert_eq!(
        run(Round::Zero, |e| convert(
            e,
            Fmt::D,
            Fmt::S,
            0x3692fa5e7ecee4b3
        )),
        (0, U | I)
    );
    // Rounded away from zero: the smallest subnormal of the right sign.
    assert_eq!(run(Round::Up, |e| mul(e, Fmt::S, 1, s(0.5))), (1, U | I));
    assert_eq!(
        run(Round::Down, |e| mul(e, Fmt::S, 1, s(-0.5))),
        (0x8000_0001, U | I)
    );
}

#[test]
fn nan_policy() {
    let qa = 0x7FC0_0001u64;
    let sb = 0x7F80_0002u64;
    // The first sNaN wins, quieted, raising Invalid; else the first qNaN.
    assert_eq!(
        run(Round::Nearest, |e| add(e, Fmt::S, qa, sb)),
        (0x7FC0_0002, V)
    );
    assert_eq!(run(Round::Nearest, |e| mul(e, Fmt::S, qa, s(1.0))), (qa, 0));
    assert_eq!(
        run(Round::Nearest, |e| sub(e, Fmt::S, s(1.0), 0xFFC0_0003)),
        (0xFFC0_0003, 0),
        "a NaN subtrahend keeps its sign"
    );
    // inf - inf is the default NaN (not the host's negative NaN).
    let inf = s(f32::INFINITY);
    assert_eq!(
        run(Round::Nearest, |e| sub(e, Fmt::S, inf, inf)),
        (0x7FC0_0000, V)
    );
    assert_eq!(
        run(Round::Nearest, |e| sqrt(e, Fmt::D, d(-1.0))),
        (0x7FF8_0000_0000_0000, V)
    );
    // Fused multiply-add: accumulator first; inf * 0 is invalid even with a qNaN
    // accumulator, whose value is the result.
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::S, sb, s(1.0), qa, false)),
        (0x7FC0_0002, V)
    );
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::S, inf, 0, qa, false)),
        (qa, V)
    );
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::S, inf, 0, s(1.0), false)),
        (0x7FC0_0000, V)
    );
    // Narrowing and widening keep the payload's top bits and quiet the NaN.
    assert_eq!(
        run(Round::Nearest, |e| convert(
            e,
            Fmt::D,
            Fmt::S,
            0x7FF0_0000_2000_0000
        )),
        (0x7FC0_0001, V)
    );
    assert_eq!(
        run(Round::Nearest, |e| convert(e, Fmt::S, Fmt::D, 0xFF80_0001)),
        (0xFFF8_0000_2000_0000, V)
    );
}

#[test]
fn fused_multiply_add_rounds_once() {
    let (a, b, c) = (s(1.5), s(2.0), s(0.25));
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::S, a, b, c, false)),
        (s(3.25), 0)
    );
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::S, a, b, c, true)),
        (s(-2.75), 0)
    );
    // (1 + 2^-12)^2 - 1 = 2^-11 + 2^-24: mul-then-add loses the 2^-24 term.
    let x = s(1.0 + 2f32.powi(-12));
    let want = 2f32.powi(-11) + 2f32.powi(-24);
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::S, x, x, s(-1.0), false)),
        (s(want), 0)
    );
    // Double: (1 + 2^-30)^2 - 1 = 2^-29 + 2^-60, exact only when fused.
    let y = d(1.0 + 2f64.powi(-30));
    assert_eq!(
        run(Round::Nearest, |e| fma(e, Fmt::D, y, y, d(-1.0), false)),
        (d(2f64.powi(-29) + 2f64.powi(-60)), 0)
    );
    // The product rounded first would be a tie (1 + 2^-11 + 2^-24 -> 1 + 2^-11) and the
    // sum 2^-11: fusing keeps the 2^-24.
    assert_ne!(
        run(Round::Nearest, |e| {
            let p = mul(e, Fmt::S, x, x);
            add(e, Fmt::S, p, s(-1.0))
        })
        .0,
        s(want)
    );
    // The binary64 sum of the exact product and the addend is itself inexact: the host
    // fast path must not round twice.
    assert_eq!(
        run(Round::Nearest, |e| fma(
            e,
            Fmt::S,
            s(1.0),
            s(1.0),
            s(1e-30),
            false
        )),
        (s(1.0), I)
    );
    // 3 * (1 + 2^-23) is a binary32 tie (3 + 2^-22 + 2^-23) that rounds up to even; minus
    // 2^-60 it lies below the tie. Its binary64 sum rounds back onto the tie, so
    // rounding that to binary32 would go up: the fused result goes down.
    assert_eq!(
        run(Round::Nearest, |e| fma(
            e,
            Fmt::S,
            s(3.0),
            s(1.0 + 2f32.powi(-23)),
            s(-(2f32.powi(-60))),
            false
        )),
        (s(3.0f32.next_up()), I)
    );
    // Directed modes: the single rounding of the exact sum.
    assert_eq!(
        run(Round::Up, |e| fma(
            e,
            Fmt::S,
            s(1.0),
            s(1.0),
            s(1e-30),
            false
        )),
        (s(1.0f32.next_up()), I)
    );
    assert_eq!(
        run(Round::Down, |e| fma(
            e,
            Fmt::S,
            s(1.0),
            s(1.0),
            s(-1e-30),
            false
        )),
        (s(1.0f32.next_down()), I)
    );
    // Exact zero sum: +0, or -0 in round-down.
    assert_eq!(
        run(Round::Nearest, |e| fma(
            e,
            Fmt::D,
            d(2.0),
            d(3.0),
            d(-6.0),
            false
        )),
        (0, 0)
    );
    assert_eq!(
        run(Round::Down, |e| fma(
            e,
            Fmt::D,
            d(2.0),
            d(3.0),
            d(-6.0),
            false
        )),
        (1 << 63, 0)
    );
}

#[test]
fn min_max_class_compare() {
    let (p0, n0) = (0u64, 0x8000_0000u64);
    let (q, sn) = (0x7FC0_0000u64, 0x7F80_0001u64);
    let mm = |a, b, k| run(Round::Nearest, |e| min_max(e, Fmt::S, a, b, k));
    // Signed zeros, both orders.
    assert_eq!(mm(p0, n0, MinMax::Min), (n0, 0));
    assert_eq!(mm(n0, p0, MinMax::Min), (n0, 0));
    assert_eq!(mm(p0, n0, MinMax::Max), (p0, 0));
    assert_eq!(mm(n0, p0, MinMax::Max), (p0, 0));
    assert_eq!(mm(n0, p0, MinMax::MaxA), (p0, 0));
    assert_eq!(mm(p0, n0, MinMax::MinA), (n0, 0));
    // A quiet NaN loses against a number; two quiet NaNs give the first.
    assert_eq!(mm(q, s(1.0), MinMax::Min), (s(1.0), 0));
    assert_eq!(mm(s(1.0), q, MinMax::MaxA), (s(1.0), 0));
    assert_eq!(mm(q | 5, q | 7, MinMax::Max), (q | 5, 0));
    // A signalling NaN wins, quieted, with Invalid.
    assert_eq!(mm(s(1.0), sn, MinMax::Max), (q | 1, V));
    assert_eq!(mm(sn, q, MinMax::Min), (q | 1, V));
    // Magnitudes; equal magnitudes fall back to the plain form.
    assert_eq!(mm(s(-3.0), s(2.0), MinMax::MinA), (s(2.0), 0));
    assert_eq!(mm(s(-3.0), s(2.0), MinMax::MaxA), (s(-3.0), 0));
    assert_eq!(mm(s(-2.0), s(2.0), MinMax::MaxA), (s(2.0), 0));
    assert_eq!(mm(s(-2.0), s(2.0), MinMax::MinA), (s(-2.0), 0));
    // Class bits, single and double.
    assert_eq!(class(Fmt::S, sn), 1);
    assert_eq!(class(Fmt::S, q), 2);
    assert_eq!(class(Fmt::S, 0xFF80_0000), 1 << 2);
    assert_eq!(class(Fmt::S, s(-1.0)), 1 << 3);
    assert_eq!(class(Fmt::S, 0x8000_0001), 1 << 4);
    assert_eq!(class(Fmt::S, n0), 1 << 5);
    assert_eq!(class(Fmt::S, 0x7F80_0000), 1 << 6);
    assert_eq!(class(Fmt::S, 1), 1 << 8);
    assert_eq!(class(Fmt::S, p0), 1 << 9);
    assert_eq!(class(Fmt::D, 0x7FF0_0000_0000_0001), 1);
    assert_eq!(class(Fmt::D, 0x0010_0000_0000_0000), 1 << 7);
    assert_eq!(class(Fmt::H, 0x7E00), 2);
    // Compares: unordered, signalling, +0 == -0.
    let cmp = |a, b, sig| run(Round::Nearest, |e| compare(e, Fmt::S, a, b, sig) as u64);
    assert_eq!(cmp(q, p0, false), (REL_UN as u64, 0));
    assert_eq!(cmp(q, p0, true), (REL_UN as u64, V));
    assert_eq!(cmp(sn, p0, false), (REL_UN as u64, V));
    assert_eq!(cmp(p0, n0, false), (REL_EQ as u64, 0));
    assert_eq!(cmp(s(-1.0), p0, false), (REL_LT as u64, 0));
    assert_eq!(cmp(s(1.0), p0, false), (0, 0));
    // Flush to zero: a subnormal equals zero, and the compare raises nothing.
    let mut e = Env {
        ftz: true,
        ..env(Round::Nearest)
    };
    assert_eq!(
        (compare(&mut e, Fmt::S, 1, p0, false), e.flags),
        (REL_EQ, 0)
    );
}

#[test]
fn integer_conversions_saturate() {
    let ti = |f, a, mode, signed, bits| run(mode, |e| to_int(e, f, a, mode, signed, bits));
    let n = Round::Nearest;
    // NaN gives 0, out of range saturates; both raise Invalid only.
    assert_eq!(ti(Fmt::S, 0x7FC0_0000, n, true, 32), (0, V));
    assert_eq!(ti(Fmt::D, 0xFFF0_0000_0000_0001, n, true, 64), (0, V));
    assert_eq!(ti(Fmt::D, d(3e9), Round::Zero, true, 32), (0x7FFF_FFFF, V));
    assert_eq!(ti(Fmt::D, d(-3e9), Round::Zero, true, 32), (0x8000_0000, V));
    assert_eq!(
        ti(Fmt::S, s(f32::INFINITY), n, true, 64),
        (i64::MAX as u64, V)
    );
    assert_eq!(ti(Fmt::S, s(f32::NEG_INFINITY), n, true, 64), (1 << 63, V));
    assert_eq!(ti(Fmt::D, d(-1.0), n, false, 32), (0, V));
    assert_eq!(ti(Fmt::D, d(4294967296.0), n, false, 32), (0xFFFF_FFFF, V));
    // The limits themselves convert exactly; just past them saturates.
    assert_eq!(
        ti(Fmt::D, d(-2147483648.0), Round::Zero, true, 32),
        (0x8000_0000, 0)
    );
    assert_eq!(ti(Fmt::D, d(2147483647.0), n, true, 32), (0x7FFF_FFFF, 0));
    assert_eq!(ti(Fmt::D, d(2147483647.5), n, true, 32), (0x7FFF_FFFF, V));
    assert_eq!(
        ti(Fmt::D, d(2147483647.5), Round::Zero, true, 32),
        (0x7FFF_FFFF, I)
    );
    assert_eq!(
        ti(Fmt::D, d(-2147483648.5), Round::Up, true, 32),
        (0x8000_0000, I)
    );
    assert_eq!(
        ti(Fmt::D, d(-2147483648.5), Round::Down, true, 32),
        (0x8000_0000, V)
    );
    assert_eq!(
        ti(Fmt::S, s(9.223372e18), n, true, 64),
        (i64::MAX as u64, V)
    );
    // Rounding modes and Inexact; a negative fraction to unsigned rounds to 0 exactly.
    assert_eq!(ti(Fmt::D, d(2.5), n, true, 32), (2, I));
    assert_eq!(
        ti(Fmt::D, d(-2.5), Round::Down, true, 32),
        (-3i32 as u32 as u64, I)
    );
    assert_eq!(ti(Fmt::D, d(2.5), Round::Up, true, 32), (3, I));
    assert_eq!(ti(Fmt::S, s(-0.5), Round::Zero, false, 32), (0, I));
    assert_eq!(ti(Fmt::S, n0(), n, true, 32), (0, 0));
    // From integers: exact, or rounded per mode.
    let fi = |f, v: i64, mode| run(mode, |e| from_int(e, f, v as i128));
    assert_eq!(fi(Fmt::S, 16_777_217, n), (s(16_777_216.0), I));
    assert_eq!(fi(Fmt::S, 16_777_217, Round::Up), (s(16_777_218.0), I));
    assert_eq!(fi(Fmt::S, -16_777_217, Round::Zero), (s(-16_777_216.0), I));
    assert_eq!(fi(Fmt::D, i64::MIN, Round::Up), (d(-(2f64.powi(63))), 0));
    assert_eq!(fi(Fmt::D, i64::MAX, Round::Zero), (d(2f64.powi(63)) - 1, I));
    assert_eq!(fi(Fmt::S, 0, Round::Down), (0, 0));
}

fn n0() -> u64 {
    0x8000_0000
}

#[test]
fn rint_and_narrowing() {
    let ri = |f, a, mode| run(mode, |e| rint(e, f, a));
    assert_eq!(ri(Fmt::S, s(-0.3), Round::Nearest), (s(-0.0), I));
    assert_eq!(ri(Fmt::S, s(0.3), Round::Down), (0, I));
    assert_eq!(ri(Fmt::D, d(2.5), Round::Nearest), (d(2.0), I));
    assert_eq!(ri(Fmt::D, d(2.5), Round::Up), (d(3.0), I));
    assert_eq!(ri(Fmt::D, d(1e300), Round::Zero), (d(1e300), 0));
    assert_eq!(ri(Fmt::S, 0x7F80_0001, Round::Nearest), (0x7FC0_0001, V));
    let nar = |a, mode| run(mode, |e| convert(e, Fmt::D, Fmt::S, a));
    assert_eq!(nar(d(0.1), Round::Nearest).1, I);
    assert_eq!(nar(d(1e300), Round::Nearest), (s(f32::INFINITY), O | I));
    assert_eq!(nar(d(1e300), Round::Zero), (s(f32::MAX), O | I));
    assert_eq!(nar(d(-1e300), Round::Up), (s(-f32::MAX), O | I));
    assert_eq!(nar(0x7FF0_0000_0000_0001, Round::Nearest).1, V);
}

#[test]
fn msa_half_precision_and_directed_rounding() {
    let mut e = env(Round::Nearest);
    assert_eq!(convert(&mut e, Fmt::S, Fmt::H, s(1.0)), 0x3C00);
    assert_eq!(convert(&mut e, Fmt::H, Fmt::S, 0x3C00), s(1.0));
    assert_eq!(convert(&mut e, Fmt::S, Fmt::H, s(65520.0)), 0x7C00);
    let (r, fl) = run(Round::Down, |e| div(e, Fmt::S, s(1.0), s(3.0)));
    assert_eq!((r, fl), (s(1.0 / 3.0) - 1, I));
    let (r, _) = run(Round::Up, |e| div(e, Fmt::S, s(1.0), s(3.0)));
    assert_eq!(r, s(1.0 / 3.0));
}
