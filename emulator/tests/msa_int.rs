//! MSA integer, bit, shuffle, element-move, load/store and branch semantics checked
//! against a reference model written here from the MSA specification's pseudo-code
//! (per-lane scalar code on i128), over random inputs with edge values.

mod msa_common;

use msa_common::*;
use trax_emulator::msa::MsaOutcome;
use trax_emulator::RegFile;

type LaneFn = fn(u32, u64, u64, u64) -> u64;

fn s(x: u64, n: u32) -> i128 {
    let v = x as i128 & ((1i128 << n) - 1);
    if v >= 1i128 << (n - 1) {
        v - (1i128 << n)
    } else {
        v
    }
}

fn u(x: u64, n: u32) -> i128 {
    x as i128 & ((1i128 << n) - 1)
}

fn wrap(v: i128, n: u32) -> u64 {
    (v & ((1i128 << n) - 1)) as u64
}

fn sat_signed(v: i128, n: u32) -> u64 {
    let hi = (1i128 << (n - 1)) - 1;
    let lo = -(1i128 << (n - 1));
    wrap(v.max(lo).min(hi), n)
}

fn sat_unsigned(v: i128, n: u32) -> u64 {
    wrap(v.max(0).min((1i128 << n) - 1), n)
}

fn all(c: bool, n: u32) -> u64 {
    if c {
        wrap(-1, n)
    } else {
        0
    }
}

fn shamt(b: u64, n: u32) -> u32 {
    (b as u32) & (n - 1)
}

/// Rounding right shift (srar/srlr): adds the last bit shifted out.
fn shr_round(v: i128, sh: u32) -> i128 {
    if sh == 0 {
        v
    } else {
        (v >> sh) + ((v >> (sh - 1)) & 1)
    }
}

fn halves(x: u64, n: u32, signed: bool) -> (i128, i128) {
    let h = n / 2;
    if signed {
        (s(x, h), s(x >> h, h))
    } else {
        (u(x, h), u(x >> h, h))
    }
}

/// (name, minor, op3, min element bits, reference) for 3R per-lane ops.
/// Reference arguments: (n, ws lane, wt lane, wd lane).
const R3_OPS: &[(&str, u32, u32, u32, LaneFn)] = &[
    ("sll", 0x0D, 0, 8, |n, a, b, _| {
        wrap(u(a, n) << shamt(b, n), n)
    }),
    ("sra", 0x0D, 1, 8, |n, a, b, _| {
        wrap(s(a, n) >> shamt(b, n), n)
    }),
    ("srl", 0x0D, 2, 8, |n, a, b, _| {
        wrap(u(a, n) >> shamt(b, n), n)
    }),
    ("bclr", 0x0D, 3, 8, |n, a, b, _| {
        wrap(u(a, n) & !(1i128 << shamt(b, n)), n)
    }),
    ("bset", 0x0D, 4, 8, |n, a, b, _| {
        wrap(u(a, n) | (1i128 << shamt(b, n)), n)
    }),
    ("bneg", 0x0D, 5, 8, |n, a, b, _| {
        wrap(u(a, n) ^ (1i128 << shamt(b, n)), n)
    }),
    ("binsl", 0x0D, 6, 8, |n, a, b, c| {
        // Copy the (b mod n) + 1 most significant bits of ws into wd.
        let k = shamt(b, n) + 1;
        let mut r = u(c, n);
        for bit in (n - k)..n {
            r = (r & !(1i128 << bit)) | (u(a, n) & (1i128 << bit));
        }
        wrap(r, n)
    }),
    ("binsr", 0x0D, 7, 8, |n, a, b, c| {
        let k = shamt(b, n) + 1;
        let mut r = u(c, n);
        for bit in 0..k {
            r = (r & !(1i128 << bit)) | (u(a, n) & (1i128 << bit));
        }
        wrap(r, n)
    }),
    ("addv", 0x0E, 0, 8, |n, a, b, _| wrap(u(a, n) + u(b, n), n)),
    ("subv", 0x0E, 1, 8, |n, a, b, _| wrap(u(a, n) - u(b, n), n)),
    (
        "max_s",
        0x0E,
        2,
        8,
        |n, a, b, _| if s(a, n) >= s(b, n) { a } else { b },
    ),
    (
        "max_u",
        0x0E,
        3,
        8,
        |n, a, b, _| if u(a, n) >= u(b, n) { a } else { b },
    ),
    (
        "min_s",
        0x0E,
        4,
        8,
        |n, a, b, _| if s(a, n) <= s(b, n) { a } else { b },
    ),
    (
        "min_u",
        0x0E,
        5,
        8,
        |n, a, b, _| if u(a, n) <= u(b, n) { a } else { b },
    ),
    ("max_a", 0x0E, 6, 8, |n, a, b, _| {
        if s(a, n).abs() > s(b, n).abs() {
            a
        } else {
            b
        }
    }),
    ("min_a", 0x0E, 7, 8, |n, a, b, _| {
        if s(a, n).abs() < s(b, n).abs() {
            a
        } else {
            b
        }
    }),
    ("ceq", 0x0F, 0, 8, |n, a, b, _| all(a == b, n)),
    ("clt_s", 0x0F, 2, 8, |n, a, b, _| all(s(a, n) < s(b, n), n)),
    ("clt_u", 0x0F, 3, 8, |n, a, b, _| all(u(a, n) < u(b, n), n)),
    ("cle_s", 0x0F, 4, 8, |n, a, b, _| all(s(a, n) <= s(b, n), n)),
    ("cle_u", 0x0F, 5, 8, |n, a, b, _| all(u(a, n) <= u(b, n), n)),
    ("add_a", 0x10, 0, 8, |n, a, b, _| {
        wrap(s(a, n).abs() + s(b, n).abs(), n)
    }),
    ("adds_a", 0x10, 1, 8, |n, a, b, _| {
        sat_signed(s(a, n).abs() + s(b, n).abs(), n)
    }),
    ("adds_s", 0x10, 2, 8, |n, a, b, _| {
        sat_signed(s(a, n) + s(b, n), n)
    }),
    ("adds_u", 0x10, 3, 8, |n, a, b, _| {
        sat_unsigned(u(a, n) + u(b, n), n)
    }),
    ("ave_s", 0x10, 4, 8, |n, a, b, _| {
        wrap((s(a, n) + s(b, n)).div_euclid(2), n)
    }),
    ("ave_u", 0x10, 5, 8, |n, a, b, _| {
        wrap((u(a, n) + u(b, n)) / 2, n)
    }),
    ("aver_s", 0x10, 6, 8, |n, a, b, _| {
        wrap((s(a, n) + s(b, n) + 1).div_euclid(2), n)
    }),
    ("aver_u", 0x10, 7, 8, |n, a, b, _| {
        wrap((u(a, n) + u(b, n) + 1) / 2, n)
    }),
    ("subs_s", 0x11, 0, 8, |n, a, b, _| {
        sat_signed(s(a, n) - s(b, n), n)
    }),
    ("subs_u", 0x11, 1, 8, |n, a, b, _| {
        sat_unsigned(u(a, n) - u(b, n), n)
    }),
    ("subsus_u", 0x11, 2, 8, |n, a, b, _| {
        sat_unsigned(u(a, n) - s(b, n), n)
    }),
    ("subsuu_s", 0x11, 3, 8, |n, a, b, _| {
        sat_signed(u(a, n) - u(b, n), n)
    }),
    ("asub_s", 0x11, 4, 8, |n, a, b, _| {
        wrap((s(a, n) - s(b, n)).abs(), n)
    }),
    ("asub_u", 0x11, 5, 8, |n, a, b, _| {
        wrap((u(a, n) - u(b, n)).abs(), n)
    }),
    ("mulv", 0x12, 0, 8, |n, a, b, _| {
        wrap(u(a, n).wrapping_mul(u(b, n)), n)
    }),
    ("maddv", 0x12, 1, 8, |n, a, b, c| {
        wrap(u(c, n).wrapping_add(u(a, n).wrapping_mul(u(b, n))), n)
    }),
    ("msubv", 0x12, 2, 8, |n, a, b, c| {
        wrap(u(c, n).wrapping_sub(u(a, n).wrapping_mul(u(b, n))), n)
    }),
    ("div_s", 0x12, 4, 8, |n, a, b, _| match s(b, n) {
        0 => wrap(if s(a, n) < 0 { 1 } else { -1 }, n),
        d => wrap(s(a, n) / d, n),
    }),
    ("div_u", 0x12, 5, 8, |n, a, b, _| match u(b, n) {
        0 => wrap(-1, n),
        d => wrap(u(a, n) / d, n),
    }),
    ("mod_s", 0x12, 6, 8, |n, a, b, _| match s(b, n) {
        0 => a,
        d => wrap(s(a, n) % d, n),
    }),
    ("mod_u", 0x12, 7, 8, |n, a, b, _| match u(b, n) {
        0 => a,
        d => wrap(u(a, n) % d, n),
    }),
    ("dotp_s", 0x13, 0, 16, |n, a, b, _| {
        let (a0, a1) = halves(a, n, true);
        let (b0, b1) = halves(b, n, true);
        wrap(a0 * b0 + a1 * b1, n)
    }),
    ("dotp_u", 0x13, 1, 16, |n, a, b, _| {
        let (a0, a1) = halves(a, n, false);
        let (b0, b1) = halves(b, n, false);
        wrap(a0 * b0 + a1 * b1, n)
    }),
    ("dpadd_s", 0x13, 2, 16, |n, a, b, c| {
        let (a0, a1) = halves(a, n, true);
        let (b0, b1) = halves(b, n, true);
        wrap(u(c, n) + a0 * b0 + a1 * b1, n)
    }),
    ("dpadd_u", 0x13, 3, 16, |n, a, b, c| {
        let (a0, a1) = halves(a, n, false);
        let (b0, b1) = halves(b, n, false);
        wrap(u(c, n) + a0 * b0 + a1 * b1, n)
    }),
    ("dpsub_s", 0x13, 4, 16, |n, a, b, c| {
        let (a0, a1) = halves(a, n, true);
        let (b0, b1) = halves(b, n, true);
        wrap(u(c, n) - (a0 * b0 + a1 * b1), n)
    }),
    ("dpsub_u", 0x13, 5, 16, |n, a, b, c| {
        let (a0, a1) = halves(a, n, false);
        let (b0, b1) = halves(b, n, false);
        wrap(u(c, n) - (a0 * b0 + a1 * b1), n)
    }),
    ("srar", 0x15, 1, 8, |n, a, b, _| {
        wrap(shr_round(s(a, n), shamt(b, n)), n)
    }),
    ("srlr", 0x15, 2, 8, |n, a, b, _| {
        wrap(shr_round(u(a, n), shamt(b, n)), n)
    }),
    ("hadd_s", 0x15, 4, 16, |n, a, b, _| {
        wrap(halves(a, n, true).1 + halves(b, n, true).0, n)
    }),
    ("hadd_u", 0x15, 5, 16, |n, a, b, _| {
        wrap(halves(a, n, false).1 + halves(b, n, false).0, n)
    }),
    ("hsub_s", 0x15, 6, 16, |n, a, b, _| {
        wrap(halves(a, n, true).1 - halves(b, n, true).0, n)
    }),
    ("hsub_u", 0x15, 7, 16, |n, a, b, _| {
        wrap(halves(a, n, false).1 - halves(b, n, false).0, n)
    }),
];

const ITERS: usize = 300;

/// Runs `word` with w1 = ws, w2 = wt, w3 = wd (initial); returns the new w3.
fn run3(word: u32, ws: u128, wt: u128, wd: u128) -> u128 {
    let mut regs = RegFile::default();
    regs.fpr[1] = ws;
    regs.fpr[2] = wt;
    regs.fpr[3] = wd;
    let out = run(word, &mut regs, &mut FlatMem(vec![]));
    assert_eq!(out, MsaOutcome::Done, "{}", mnemonic(word));
    regs.fpr[3]
}

fn check_lanes(word: u32, n: u32, ws: u128, wt: u128, wd: u128, got: u128, f: impl Fn(u32) -> u64) {
    for i in 0..128 / n {
        let want = f(i);
        assert_eq!(
            get(got, n, i),
            want,
            "{} lane {i}: ws={:#x} wt={:#x} wd={:#x}",
            mnemonic(word),
            get(ws, n, i),
            get(wt, n, i),
            get(wd, n, i)
        );
    }
}

#[test]
fn three_register_integer_ops() {
    let mut rng = Rng(7);
    for &(name, minor, op3, min_bits, reference) in R3_OPS {
        for (df, &n) in DF_BITS.iter().enumerate() {
            if n < min_bits {
                continue;
            }
            let word = enc_3r(minor, op3, df as u32, 2, 1, 3);
            assert!(
                mnemonic(word).starts_with(&format!("{name}.")),
                "encoder: {}",
                mnemonic(word)
            );
            for _ in 0..ITERS {
                let (a, b, c) = (rng.int_vec(n), rng.int_vec(n), rng.int_vec(n));
                let got = run3(word, a, b, c);
                check_lanes(word, n, a, b, c, got, |i| {
                    reference(n, get(a, n, i), get(b, n, i), get(c, n, i))
                });
            }
        }
    }
}

#[test]
fn immediate_integer_ops() {
    let mut rng = Rng(8);
    // (minor, op3, signed immediate, reference op name in R3_OPS)
    let i5: &[(u32, u32, bool, &str)] = &[
        (6, 0, false, "addv"),
        (6, 1, false, "subv"),
        (6, 2, true, "max_s"),
        (6, 3, false, "max_u"),
        (6, 4, true, "min_s"),
        (6, 5, false, "min_u"),
        (7, 0, true, "ceq"),
        (7, 2, true, "clt_s"),
        (7, 3, false, "clt_u"),
        (7, 4, true, "cle_s"),
        (7, 5, false, "cle_u"),
    ];
    for &(minor, op3, signed, refname) in i5 {
        let reference = R3_OPS.iter().find(|o| o.0 == refname).unwrap().4;
        for (df, &n) in DF_BITS.iter().enumerate() {
            for imm5 in 0..32u32 {
                let word = enc_i5(minor, op3, df as u32, imm5, 1, 3);
                let imm = if signed {
                    ((imm5 << 27) as i32 >> 27) as i64
                } else {
                    imm5 as i64
                };
                let b = wrap(imm as i128, n);
                for _ in 0..8 {
                    let (a, c) = (rng.int_vec(n), rng.int_vec(n));
                    let got = run3(word, a, 0, c);
                    check_lanes(word, n, a, 0, c, got, |i| reference(n, get(a, n, i), b, 0));
                }
            }
        }
    }
    // BIT format: shifts and bit ops by immediate, sat_s/sat_u.
    let bit: &[(u32, u32, &str)] = &[
        (9, 0, "sll"),
        (9, 1, "sra"),
        (9, 2, "srl"),
        (9, 3, "bclr"),
        (9, 4, "bset"),
        (9, 5, "bneg"),
        (9, 6, "binsl"),
        (9, 7, "binsr"),
        (10, 2, "srar"),
        (10, 3, "srlr"),
    ];
    for &(minor, op3, refname) in bit {
        let reference = R3_OPS.iter().find(|o| o.0 == refname).unwrap().4;
        for &n in &DF_BITS {
            for m in 0..n {
                let word = enc_bit(minor, op3, n, m, 1, 3);
                for _ in 0..4 {
                    let (a, c) = (rng.int_vec(n), rng.int_vec(n));
                    let got = run3(word, a, 0, c);
                    check_lanes(word, n, a, 0, c, got, |i| {
                        reference(n, get(a, n, i), m as u64, get(c, n, i))
                    });
                }
            }
        }
    }
    for &n in &DF_BITS {
        for m in 0..n {
            for (op3, signed) in [(0u32, true), (1, false)] {
                let word = enc_bit(10, op3, n, m, 1, 3);
                for _ in 0..4 {
                    let a = rng.int_vec(n);
                    let got = run3(word, a, 0, 0);
                    check_lanes(word, n, a, 0, 0, got, |i| {
                        let x = get(a, n, i);
                        if signed {
                            // Saturate to a signed (m+1)-bit range.
                            wrap(s(x, n).clamp(-(1i128 << m), (1i128 << m) - 1), n)
                        } else {
                            wrap(u(x, n).min((1i128 << (m + 1)) - 1), n)
                        }
                    });
                }
            }
        }
    }
}

#[test]
fn count_ops_and_ldi_fill() {
    let mut rng = Rng(9);
    for (df, &n) in DF_BITS.iter().enumerate() {
        for (op8, what) in [(0xC1u32, "pcnt"), (0xC2, "nloc"), (0xC3, "nlzc")] {
            let word = enc_2r(op8, df as u32, 1, 3);
            assert!(mnemonic(word).starts_with(what));
            for _ in 0..ITERS {
                let a = rng.int_vec(n);
                let got = run3(word, a, 0, 0);
                check_lanes(word, n, a, 0, 0, got, |i| {
                    let x = get(a, n, i);
                    let bits: Vec<bool> = (0..n).rev().map(|k| x >> k & 1 == 1).collect();
                    match what {
                        "pcnt" => bits.iter().filter(|&&b| b).count() as u64,
                        "nloc" => bits.iter().take_while(|&&b| b).count() as u64,
                        _ => bits.iter().take_while(|&&b| !b).count() as u64,
                    }
                });
            }
        }
        // ldi: sign-extended s10 in every lane.
        for imm in [-512i32, -300, -1, 0, 1, 77, 511] {
            let word =
                0x7800_0007 | 6 << 23 | (df as u32) << 21 | ((imm as u32) & 0x3FF) << 11 | 3 << 6;
            let got = run3(word, 0, 0, rng.int_vec(n));
            check_lanes(word, n, 0, 0, 0, got, |_| wrap(imm as i128, n));
        }
        // fill from a GPR (no fill.d on MIPS32).
        if n < 64 {
            let word = enc_2r(0xC0, df as u32, 5, 3);
            let mut regs = RegFile::default();
            regs.gpr[5] = 0x8765_4321;
            run(word, &mut regs, &mut FlatMem(vec![]));
            check_lanes(word, n, 0, 0, 0, regs.fpr[3], |_| wrap(0x8765_4321, n));
        }
    }
}

#[test]
fn whole_vector_bit_ops() {
    let mut rng = Rng(10);
    for _ in 0..ITERS {
        let (a, b, c) = (rng.int_vec(64), rng.int_vec(64), rng.int_vec(64));
        let imm = rng.below(256) as u32;
        let ib = u128::from_ne_bytes([imm as u8; 16]);
        // Bit-by-bit reference: r[k] from (ws[k], wt[k], wd[k]).
        let bitwise = |f: &dyn Fn(bool, bool, bool) -> bool, t: u128| -> u128 {
            (0..128).fold(0u128, |r, k| {
                r | ((f(a >> k & 1 == 1, t >> k & 1 == 1, c >> k & 1 == 1) as u128) << k)
            })
        };
        let cases: [(u32, u128); 14] = [
            (enc_vec(0, 2, 1, 3), bitwise(&|x, y, _| x && y, b)),
            (enc_vec(1, 2, 1, 3), bitwise(&|x, y, _| x || y, b)),
            (enc_vec(2, 2, 1, 3), bitwise(&|x, y, _| !(x || y), b)),
            (enc_vec(3, 2, 1, 3), bitwise(&|x, y, _| x != y, b)),
            (
                enc_vec(4, 2, 1, 3),
                bitwise(&|x, y, d| if y { x } else { d }, b),
            ), // bmnz
            (
                enc_vec(5, 2, 1, 3),
                bitwise(&|x, y, d| if y { d } else { x }, b),
            ), // bmz
            (
                enc_vec(6, 2, 1, 3),
                bitwise(&|x, y, d| if d { y } else { x }, b),
            ), // bsel
            (enc_i8(0, 0, imm, 1, 3), bitwise(&|x, y, _| x && y, ib)),
            (enc_i8(0, 1, imm, 1, 3), bitwise(&|x, y, _| x || y, ib)),
            (enc_i8(0, 2, imm, 1, 3), bitwise(&|x, y, _| !(x || y), ib)),
            (enc_i8(0, 3, imm, 1, 3), bitwise(&|x, y, _| x != y, ib)),
            (
                enc_i8(1, 0, imm, 1, 3),
                bitwise(&|x, y, d| if y { x } else { d }, ib),
            ),
            (
                enc_i8(1, 1, imm, 1, 3),
                bitwise(&|x, y, d| if y { d } else { x }, ib),
            ),
            (
                enc_i8(1, 2, imm, 1, 3),
                bitwise(&|x, y, d| if d { y } else { x }, ib),
            ),
        ];
        for (word, want) in cases {
            assert_eq!(run3(word, a, b, c), want, "{}", mnemonic(word));
        }
        // move.v
        let mv = 0x7800_0019 | 2 << 22 | 0x3E << 16 | 1 << 11 | 3 << 6;
        assert_eq!(run3(mv, a, b, c), a);
    }
}

/// Lane-array view for the shuffle reference.
fn lanes_of(v: u128, n: u32) -> Vec<u64> {
    (0..128 / n).map(|i| get(v, n, i)).collect()
}

#[test]
fn shuffles() {
    let mut rng = Rng(11);
    for (df, &n) in DF_BITS.iter().enumerate() {
        let k = (128 / n) as usize;
        for _ in 0..ITERS {
            let (a, b, c) = (rng.int_vec(n), rng.int_vec(n), rng.int_vec(n));
            let (la, lb, lc) = (lanes_of(a, n), lanes_of(b, n), lanes_of(c, n));
            let h = k / 2;
            // pckev/pckod: wt supplies the right (low) half, ws the left (high) half.
            let pckev: Vec<u64> = (0..h)
                .map(|i| lb[2 * i])
                .chain((0..h).map(|i| la[2 * i]))
                .collect();
            let pckod: Vec<u64> = (0..h)
                .map(|i| lb[2 * i + 1])
                .chain((0..h).map(|i| la[2 * i + 1]))
                .collect();
            let mut ilvl = vec![];
            let mut ilvr = vec![];
            let mut ilvev = vec![];
            let mut ilvod = vec![];
            for i in 0..h {
                ilvl.extend([lb[h + i], la[h + i]]);
                ilvr.extend([lb[i], la[i]]);
                ilvev.extend([lb[2 * i], la[2 * i]]);
                ilvod.extend([lb[2 * i + 1], la[2 * i + 1]]);
            }
            // vshf: control in wd; index into wt (low) : ws (high); bits 6/7 give zero.
            let vshf: Vec<u64> = lc
                .iter()
                .map(|&ctl| {
                    if ctl & 0xC0 != 0 {
                        0
                    } else {
                        let j = (ctl as usize) % (2 * k);
                        if j < k {
                            lb[j]
                        } else {
                            la[j - k]
                        }
                    }
                })
                .collect();
            let cases = [
                (enc_3r(0x14, 2, df as u32, 2, 1, 3), pckev),
                (enc_3r(0x14, 3, df as u32, 2, 1, 3), pckod),
                (enc_3r(0x14, 4, df as u32, 2, 1, 3), ilvl),
                (enc_3r(0x14, 5, df as u32, 2, 1, 3), ilvr),
                (enc_3r(0x14, 6, df as u32, 2, 1, 3), ilvev),
                (enc_3r(0x14, 7, df as u32, 2, 1, 3), ilvod),
                (enc_3r(0x15, 0, df as u32, 2, 1, 3), vshf),
            ];
            for (word, want) in cases {
                assert_eq!(lanes_of(run3(word, a, b, c), n), want, "{}", mnemonic(word));
            }
            // shf (imm8 selects within each group of 4); only .b/.h/.w exist.
            if n < 64 {
                let imm = rng.below(256) as u32;
                let word = enc_i8(2, df as u32, imm, 1, 3);
                let want: Vec<u64> = (0..k)
                    .map(|i| la[4 * (i / 4) + ((imm as usize >> (2 * (i % 4))) & 3)])
                    .collect();
                assert_eq!(lanes_of(run3(word, a, b, c), n), want, "{}", mnemonic(word));
            }
            // splat / splati / sld / sldi.
            let idx = rng.below(64) as u32;
            let mut regs = RegFile::default();
            regs.fpr[1] = a;
            regs.fpr[3] = c;
            regs.gpr[6] = idx;
            run(
                enc_3r(0x14, 1, df as u32, 6, 1, 3),
                &mut regs,
                &mut FlatMem(vec![]),
            );
            assert_eq!(
                lanes_of(regs.fpr[3], n),
                vec![la[idx as usize % k]; k],
                "splat"
            );
            let ni = idx % k as u32;
            let got = run3(enc_elm(1, n, ni, 1, 3), a, b, c);
            assert_eq!(lanes_of(got, n), vec![la[ni as usize]; k], "splati");
            // sld: byte slide inside each of n/8 slices of 16/(n/8) bytes over wd:ws.
            let slice = 16 / (n as usize / 8);
            let slide = |amount: usize| -> u128 {
                let (ab, cb) = (a.to_le_bytes(), c.to_le_bytes());
                let mut out = [0u8; 16];
                for p in 0..16 / slice {
                    let cat: Vec<u8> = ab[p * slice..(p + 1) * slice]
                        .iter()
                        .chain(&cb[p * slice..(p + 1) * slice])
                        .copied()
                        .collect();
                    out[p * slice..(p + 1) * slice].copy_from_slice(&cat[amount..amount + slice]);
                }
                u128::from_le_bytes(out)
            };
            let mut regs = RegFile::default();
            regs.fpr[1] = a;
            regs.fpr[3] = c;
            regs.gpr[6] = idx;
            run(
                enc_3r(0x14, 0, df as u32, 6, 1, 3),
                &mut regs,
                &mut FlatMem(vec![]),
            );
            assert_eq!(regs.fpr[3], slide(idx as usize % slice), "sld.{n} by {idx}");
            let got = run3(enc_elm(0, n, ni, 1, 3), a, b, c);
            assert_eq!(got, slide(ni as usize), "sldi.{n} by {ni}");
        }
    }
}

#[test]
fn element_moves() {
    let mut rng = Rng(12);
    for &n in &DF_BITS {
        let k = 128 / n;
        for _ in 0..50 {
            let (a, c) = (rng.int_vec(n), rng.int_vec(n));
            let idx = rng.below(k as u64) as u32;
            let g = rng.u64() as u32;
            let mut regs = RegFile::default();
            regs.fpr[1] = a;
            regs.fpr[3] = c;
            regs.gpr[7] = g;
            let mut mem = FlatMem(vec![]);
            if n < 64 {
                // copy_s / copy_u (copy_u.w does not exist on MIPS32) / insert.
                run(enc_elm(2, n, idx, 1, 9), &mut regs, &mut mem);
                assert_eq!(regs.gpr[9], s(get(a, n, idx), n) as u32, "copy_s");
                if n < 32 {
                    run(enc_elm(3, n, idx, 1, 10), &mut regs, &mut mem);
                    assert_eq!(regs.gpr[10], get(a, n, idx) as u32, "copy_u");
                }
                run(enc_elm(4, n, idx, 7, 3), &mut regs, &mut mem);
                let mut want = lanes_of(c, n);
                want[idx as usize] = wrap(g as i128, n);
                assert_eq!(lanes_of(regs.fpr[3], n), want, "insert");
            }
            // insve: lane idx of wd = lane 0 of ws.
            regs.fpr[3] = c;
            run(enc_elm(5, n, idx, 1, 3), &mut regs, &mut mem);
            let mut want = lanes_of(c, n);
            want[idx as usize] = get(a, n, 0);
            assert_eq!(lanes_of(regs.fpr[3], n), want, "insve");
        }
    }
    // Writes to $zero are discarded.
    let mut regs = RegFile::default();
    regs.fpr[1] = u128::MAX;
    run(enc_elm(2, 32, 0, 1, 0), &mut regs, &mut FlatMem(vec![]));
    assert_eq!(regs.gpr[0], 0);
}

#[test]
fn control_registers() {
    let mut regs = RegFile::default();
    let mut mem = FlatMem(vec![]);
    regs.gpr[4] = 0xFFFF_FFFF;
    // ctcmsa $1, $4 ; cfcmsa $5, $1
    run(
        0x7800_0019 | 0x3E << 16 | 4 << 11 | 1 << 6,
        &mut regs,
        &mut mem,
    );
    assert_eq!(
        regs.msacsr, 0x0107_FFFF,
        "only writable MSACSR bits are set"
    );
    run(
        0x7800_0019 | 1 << 22 | 0x3E << 16 | 1 << 11 | 5 << 6,
        &mut regs,
        &mut mem,
    );
    assert_eq!(regs.gpr[5], 0x0107_FFFF);
    // MSAIR reads as 0.
    run(
        0x7800_0019 | 1 << 22 | 0x3E << 16 | 6 << 6,
        &mut regs,
        &mut mem,
    );
    assert_eq!(regs.gpr[6], 0);
}

#[test]
fn loads_and_stores() {
    let mut rng = Rng(13);
    let mut mem = FlatMem((0..4096).map(|i| (i * 7 + 3) as u8).collect());
    for (df, &n) in DF_BITS.iter().enumerate() {
        for _ in 0..100 {
            let s10 = rng.below(64) as i32 - 32;
            let base = MEM_BASE + 2048 + rng.below(64) as u32; // unaligned allowed
            let addr = base.wrapping_add((s10 * (n as i32 / 8)) as u32);
            let mut regs = RegFile::default();
            regs.gpr[4] = base;
            let word = enc_mi10(false, df as u32, s10, 4, 3);
            assert_eq!(
                mnemonic(word),
                format!(
                    "ld.{} $w3, {}($4)",
                    ["b", "h", "w", "d"][df],
                    s10 * (n as i32 / 8)
                )
            );
            assert_eq!(run(word, &mut regs, &mut mem), MsaOutcome::Done);
            let off = (addr - MEM_BASE) as usize;
            let want = u128::from_le_bytes(mem.0[off..off + 16].try_into().unwrap());
            assert_eq!(regs.fpr[3], want);
            let v = rng.int_vec(n);
            regs.fpr[3] = v;
            assert_eq!(
                run(enc_mi10(true, df as u32, s10, 4, 3), &mut regs, &mut mem),
                MsaOutcome::Done
            );
            for i in 0..128 / n {
                let bytes = &mem.0[off + (i * n / 8) as usize..][..(n / 8) as usize];
                let mut lane = 0u64;
                for (j, b) in bytes.iter().enumerate() {
                    lane |= (*b as u64) << (8 * j);
                }
                assert_eq!(lane, get(v, n, i));
            }
        }
    }
    // A failing access is reported, and a faulting load leaves the register alone.
    let mut regs = RegFile::default();
    regs.fpr[3] = 42;
    let out = run(enc_mi10(false, 2, 0, 0, 3), &mut regs, &mut mem);
    assert!(matches!(
        out,
        MsaOutcome::Fault(trax_emulator::msa::MsaFault::Memory(0))
    ));
    assert_eq!(regs.fpr[3], 42);
}

#[test]
fn branches() {
    let mut rng = Rng(14);
    for _ in 0..200 {
        let mut regs = RegFile::default();
        let n = DF_BITS[rng.below(4) as usize];
        let mut v = rng.int_vec(n);
        if rng.below(3) == 0 {
            v = 0;
        }
        regs.fpr[5] = v;
        let lanes = lanes_of(v, n);
        let df = DF_BITS.iter().position(|&b| b == n).unwrap() as u32;
        let off = (rng.below(200) as i32 - 100) as u32 & 0xFFFF;
        let cases = [
            (0x4560_0000u32, v == 0),                      // bz.v
            (0x45E0_0000, v != 0),                         // bnz.v
            (0x4700_0000 | df << 21, lanes.contains(&0)),  // bz.df
            (0x4780_0000 | df << 21, !lanes.contains(&0)), // bnz.df
        ];
        for (base, taken) in cases {
            let word = base | 5 << 16 | off;
            assert_eq!(
                run(word, &mut regs, &mut FlatMem(vec![])),
                MsaOutcome::Branch(taken),
                "{}",
                mnemonic(word)
            );
            let inst = trax_emulator::msa::decode(word).unwrap();
            assert_eq!(inst.imm, ((off << 16) as i32 >> 14), "byte offset");
            assert!(inst.is_branch());
        }
    }
}

#[test]
fn hand_computed_vectors() {
    // addv.w: lane-wise wrap.
    let a = from_lanes(32, &[1, 0xFFFF_FFFF, 0x7FFF_FFFF, 5]);
    let b = from_lanes(32, &[2, 1, 1, 0xFFFF_FFFB]);
    assert_eq!(
        run3(enc_3r(0x0E, 0, 2, 2, 1, 3), a, b, 0),
        from_lanes(32, &[3, 0, 0x8000_0000, 0])
    );
    // adds_s.h saturates; subs_u.b clamps at 0.
    let a = from_lanes(16, &[0x7FFF, 0x8000, 100, 0, 0, 0, 0, 0]);
    let b = from_lanes(16, &[1, 0xFFFF, 0xFF9C, 0, 0, 0, 0, 0]);
    assert_eq!(
        run3(enc_3r(0x10, 2, 1, 2, 1, 3), a, b, 0),
        from_lanes(16, &[0x7FFF, 0x8000, 0, 0, 0, 0, 0, 0])
    );
    // div_s.w INT_MIN / -1 = INT_MIN; mod_s.w INT_MIN mod -1 = 0; 7 / -2 = -3; -7 mod 2 = -1.
    let a = from_lanes(32, &[0x8000_0000, 0x8000_0000, 7, 0xFFFF_FFF9]);
    let b = from_lanes(32, &[0xFFFF_FFFF, 0xFFFF_FFFF, 0xFFFF_FFFE, 2]);
    assert_eq!(
        get(run3(enc_3r(0x12, 4, 2, 2, 1, 3), a, b, 0), 32, 0),
        0x8000_0000
    );
    assert_eq!(get(run3(enc_3r(0x12, 6, 2, 2, 1, 3), a, b, 0), 32, 1), 0);
    assert_eq!(
        get(run3(enc_3r(0x12, 4, 2, 2, 1, 3), a, b, 0), 32, 2),
        0xFFFF_FFFD
    );
    assert_eq!(
        get(run3(enc_3r(0x12, 6, 2, 2, 1, 3), a, b, 0), 32, 3),
        0xFFFF_FFFF
    );
    // dotp_s.h: (-2*3) + (4*5) = 14 in the first lane.
    let a = from_lanes(8, &[0xFE, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    let b = from_lanes(8, &[3, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(get(run3(enc_3r(0x13, 0, 1, 2, 1, 3), a, b, 0), 16, 0), 14);
    // srar.w by 1 rounds: 3 >> 1 = 2 (1.5 rounds up), -3 >> 1 = -1.
    let a = from_lanes(32, &[3, 0xFFFF_FFFD, 0, 0]);
    let got = run3(
        enc_3r(0x15, 1, 2, 2, 1, 3),
        a,
        from_lanes(32, &[1, 1, 0, 0]),
        0,
    );
    assert_eq!((get(got, 32, 0), get(got, 32, 1)), (2, 0xFFFF_FFFF));
    // nlzc.w of 1 is 31; pcnt.b of 0xFF is 8.
    assert_eq!(get(run3(enc_2r(0xC3, 2, 1, 3), 1, 0, 0), 32, 0), 31);
    assert_eq!(get(run3(enc_2r(0xC1, 0, 1, 3), 0xFF, 0, 0), 8, 0), 8);
    // ilvr.w: wt0 ws0 wt1 ws1.
    let a = from_lanes(32, &[10, 11, 12, 13]);
    let b = from_lanes(32, &[20, 21, 22, 23]);
    assert_eq!(
        run3(enc_3r(0x14, 5, 2, 2, 1, 3), a, b, 0),
        from_lanes(32, &[20, 10, 21, 11])
    );
    // shf.w 0x1B reverses the four words.
    assert_eq!(
        run3(enc_i8(2, 2, 0x1B, 1, 3), a, 0, 0),
        from_lanes(32, &[13, 12, 11, 10])
    );
}

/// Every decodable word executes without panicking (debug builds also trap arithmetic
/// overflow) on random registers, MSACSR values and memory.
#[test]
fn random_words_never_panic() {
    let mut rng = Rng(15);
    let mut mem = FlatMem(vec![0; 4096]);
    let mut executed = 0;
    for _ in 0..60_000 {
        let word = match rng.below(3) {
            0 => 0x4400_0000 | (rng.u64() as u32 & 0x03FF_FFFF), // COP1 incl. MSA branches
            _ => 0x7800_0000 | (rng.u64() as u32 & 0x03FF_FFFF),
        };
        let Some(inst) = trax_emulator::msa::decode(word) else {
            continue;
        };
        let mut regs = RegFile::default();
        for r in 1..32 {
            regs.gpr[r] = if rng.below(2) == 0 {
                MEM_BASE + rng.below(4096) as u32
            } else {
                rng.u64() as u32
            };
        }
        for w in regs.fpr.iter_mut() {
            *w = match rng.below(3) {
                0 => rng.int_vec(8),
                1 => rng.int_vec(64),
                _ => (rng.u64() as u128) << 64 | rng.u64() as u128,
            };
        }
        regs.msacsr = rng.u64() as u32 & 0x0107_FFFF;
        let _ = trax_emulator::msa::execute(&inst, &mut regs, &mut mem);
        let _ = inst.to_string();
        let _ = inst.unit();
        executed += 1;
    }
    assert!(executed > 20_000, "only {executed} words decoded");
}
