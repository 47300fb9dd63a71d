//! Scalar FPU instructions, one at a time, against QEMU (`qemu-mipsel -cpu
//! mips32r6-generic`) on operands chosen to sit on the boundaries where soft-float
//! implementations go wrong: results that underflow to zero or to the smallest normal,
//! overflow or stop just short of it, in all four FCSR rounding modes; signed zeros, NaNs
//! (quiet and signalling), infinities, subnormals and integer-conversion limits.
//!
//! One generated program holds every case: it loads `$f1` (fs), `$f2` (ft), `$f3` (fd)
//! and FCSR, runs the instruction, and stores `$f3` and FCSR; then `write(1, cases, N)`
//! and `exit(0)`. QEMU's stdout is the reference; the emulator stops at the `syscall`
//! and the test reads the cases back from its memory. Result bits (all 64) and FCSR
//! (Cause and Flags) must agree exactly. `qemu_diff.rs` covers instruction sequences
//! with ordinary operands; this test covers the corners of each operation.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use trax_emulator::softfloat::testgen::Rng;
use trax_emulator::softfloat::Fmt;

mod common;

use common::qemu::{build, for_qemu, run_emulator, run_qemu, FPU_CONDITIONS, FPU_CONVERSIONS};

/// Bytes per case record: fs, ft, fd (8 each), fcsr in, pad, fd out, fcsr out, pad.
const CASE_BYTES: usize = 48;

/// An integer operand for `cvt.*.w/l`, biased to rounding and range boundaries.
fn int(r: &mut Rng) -> u64 {
    let x = r.u64();
    match r.below(4) {
        0 => [0, 1, u64::MAX, 1 << 63, (1 << 63) - 1, 1 << 31, 0x7FFF_FFFF][x as usize % 7],
        1 => (x as i64 >> (x % 64)) as u64,
        2 => (1u64 << (24 + x % 40)) + (x >> 60) - 8,
        _ => x,
    }
}

struct Case {
    /// The instruction, in the emulator's (LLVM 14's) spelling.
    asm: String,
    fs: u64,
    ft: u64,
    fd: u64,
    fcsr: u32,
}

const BIN: [&str; 4] = ["add", "sub", "mul", "div"];
const UN: [&str; 6] = ["sqrt", "recip", "rsqrt", "rint", "class", "neg"];
const MINMAX: [&str; 4] = ["min", "max", "mina", "maxa"];
fn cases(seed: u64, n: usize) -> Vec<Case> {
    let mut r = Rng(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let single = r.below(2) == 0;
        let fmt = if single { "s" } else { "d" };
        // Upper halves of single-precision operands are random (results must keep fd's).
        let val = |r: &mut Rng| {
            if single {
                r.u64() << 32 | r.operand(Fmt::S)
            } else {
                r.operand(Fmt::D)
            }
        };
        let (mut fs, ft, fd) = (val(&mut r), val(&mut r), val(&mut r));
        let asm = match r.below(10) {
            0..=2 => format!("{}.{fmt} $f3, $f1, $f2", BIN[r.below(4) as usize]),
            3 => format!("{}.{fmt} $f3, $f1", UN[r.below(6) as usize]),
            4 | 5 => format!(
                "{}.{fmt} $f3, $f1, $f2",
                ["maddf", "msubf"][r.below(2) as usize]
            ),
            6 => format!("{}.{fmt} $f3, $f1, $f2", MINMAX[r.below(4) as usize]),
            7 => format!(
                "cmp.{}.{fmt} $f3, $f1, $f2",
                FPU_CONDITIONS[r.below(16) as usize]
            ),
            _ => {
                let op = FPU_CONVERSIONS[r.below(26) as usize];
                // The source format is the last letter.
                fs = match op.as_bytes()[op.len() - 1] {
                    b's' => r.u64() << 32 | r.operand(Fmt::S),
                    b'd' => r.operand(Fmt::D),
                    _ => int(&mut r),
                };
                format!("{op} $f3, $f1")
            }
        };
        out.push(Case {
            asm,
            fs,
            ft,
            fd,
            fcsr: r.below(4) as u32,
        });
    }
    out
}

fn program(cases: &[Case], qemu: bool) -> String {
    let mut s = String::from(
        "    .set noreorder\n    .set noat\n    .text\n    .globl __start\n__start:\n\
         \x20   lui $4, %hi(cases)\n    addiu $4, $4, %lo(cases)\n",
    );
    for c in cases {
        let inst = if qemu {
            for_qemu(&c.asm).trim().to_string()
        } else {
            c.asm.clone()
        };
        let _ = writeln!(
            s,
            "    ldc1 $f1, 0($4)\n    ldc1 $f2, 8($4)\n    ldc1 $f3, 16($4)\n    lw $5, 24($4)\n\
             \x20   ctc1 $5, $31\n    {inst}\n    cfc1 $5, $31\n    sdc1 $f3, 32($4)\n\
             \x20   sw $5, 40($4)\n    addiu $4, $4, {CASE_BYTES}"
        );
    }
    let _ = write!(
        s,
        "    lui $25, %hi(cases)\n    addiu $25, $25, %lo(cases)\n    li $4, 1\n    move $5, $25\n\
         \x20   li $6, {}\n    li $2, 4004\n    syscall\n    li $2, 4001\n    li $4, 0\n    syscall\n\
         \x20   .data\n    .p2align 3\ncases:\n",
        cases.len() * CASE_BYTES
    );
    for c in cases {
        let _ = writeln!(
            s,
            "    .word {:#x},{:#x},{:#x},{:#x},{:#x},{:#x},{:#x},0,0,0,0,0",
            c.fs as u32,
            c.fs >> 32,
            c.ft as u32,
            c.ft >> 32,
            c.fd as u32,
            c.fd >> 32,
            c.fcsr
        );
    }
    s
}

/// Runs `cases` on both; returns a description per mismatching mnemonic (count, example).
fn compare(name: &str, cases: &[Case]) -> BTreeMap<String, (usize, String)> {
    let dir = common::scratch("fpu_qemu");
    let len = cases.len() * CASE_BYTES;
    let ours = run_emulator(&build(&dir, name, &program(cases, false)), len as u32).unwrap();
    let qemu = run_qemu(&build(&dir, &format!("{name}_qemu"), &program(cases, true)));
    assert_eq!(qemu.len(), len, "qemu output length");
    let mut bad: BTreeMap<String, (usize, String)> = BTreeMap::new();
    for (i, c) in cases.iter().enumerate() {
        let at = |b: &[u8], o: usize| {
            let r = &b[i * CASE_BYTES + o..];
            (
                u64::from_le_bytes(r[..8].try_into().unwrap()),
                u32::from_le_bytes(r[8..12].try_into().unwrap()),
            )
        };
        let (want, got) = (at(&qemu, 32), at(&ours, 32));
        if want != got {
            let key = c.asm.split(' ').next().unwrap().to_string();
            let e = bad.entry(key).or_default();
            if e.0 == 0 {
                e.1 = format!(
                    "`{}` fs={:#018x} ft={:#018x} fd={:#018x} rm={}: qemu {:#018x} fcsr {:#x}, emulator {:#018x} fcsr {:#x}",
                    c.asm, c.fs, c.ft, c.fd, c.fcsr, want.0, want.1, got.0, got.1
                );
            }
            e.0 += 1;
        }
    }
    bad
}

/// Cases found by this test and by comparing the scalar and MSA soft-float code before
/// they were merged (`asm`, fs, ft, fd, rounding mode), kept so that every run checks them.
const FOUND: &[&str] = &[
    // Exact result tiny before rounding, the smallest normal after (tininess after rounding).
    "maddf.s 0x1d2821b0 0x8102ca1d 0x807fffff 3",
    // 2^-126 - 2^-150: a tie on the subnormal grid rounding to 2^-126, yet tiny.
    "mul.s 0x3faaaaaa 0x00600000 0 0",
    // Sums next to the overflow threshold (an error-free transform overflowing).
    "add.s 0xfeab2197 0x7f7fffff 0 2",
    "sub.s 0xf30186c1 0x7f7fffff 0 2",
    "add.d 0x7fc213c9b0ce7b5e 0xffefffffffffffff 0 0",
    "sub.d 0x7fd528dc549b6dd3 0x7fefffffffffffff 0 2",
    "add.d 0x7fc8ac230880dd8e 0xffefffffffffffff 0 1",
    // Results that underflow to zero in a directed rounding mode: the sign of the zero.
    "div.s 0x10af1d37 0x5b75eecd 0 3",
    "mul.s 0x1cba9e9c 0x17497838 0 3",
    "div.d 0x8000000000000001 0x3ff90c0d534ab347 0 1",
    "mul.d 0x8000000000000001 0x3fef07f0a81461b5 0 2",
    "cvt.s.d 0x3692fa5e7ecee4b3 0 0 1",
    "maddf.d 0xb671becb92024edb 0x003954312b95d48f 1 3",
    "msubf.s 0x00ffc04d 0x9ae305dd 0x80000001 2",
];

/// A [`FOUND`] line as a case: `mnemonic fs ft fd rm`.
fn found(line: &str) -> Case {
    let w: Vec<&str> = line.split(' ').collect();
    let n = |s: &str| u64::from_str_radix(s.trim_start_matches("0x"), 16).unwrap();
    let operands = if w[0].starts_with("cvt") {
        "$f3, $f1"
    } else {
        "$f3, $f1, $f2"
    };
    Case {
        asm: format!("{} {operands}", w[0]),
        fs: n(w[1]),
        ft: n(w[2]),
        fd: n(w[3]),
        fcsr: n(w[4]) as u32,
    }
}

#[test]
fn scalar_fpu_corners_match_qemu() {
    // `TRAX_FPU_QEMU_CASES=N` runs more cases (a longer hunt for differences).
    let n = std::env::var("TRAX_FPU_QEMU_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(30_000usize);
    let mut all: Vec<Case> = FOUND.iter().map(|l| found(l)).collect();
    all.extend(cases(0xF00D_F00D_1234_5678, n));
    let mut bad = BTreeMap::new();
    // Programs of at most 10000 cases keep the assembler quick.
    for (k, chunk) in all.chunks(10_000).enumerate() {
        for (op, (c, ex)) in compare(&format!("p{k}"), chunk) {
            let e = bad.entry(op).or_insert((0, ex));
            e.0 += c;
        }
    }
    assert!(
        bad.is_empty(),
        "{} mnemonics differ from QEMU:\n{}",
        bad.len(),
        bad.iter()
            .map(|(k, (n, ex))| format!("{k} ({n} cases): {ex}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}
