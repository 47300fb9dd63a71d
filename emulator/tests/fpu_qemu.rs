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
use std::path::Path;
use std::process::Command;

use trax_emulator::machine::{Machine, MachineConfig};
use trax_emulator::thread::Fault;
use trax_emulator::Outcome;

mod common;

/// Bytes per case record: fs, ft, fd (8 each), fcsr in, pad, fd out, fcsr out, pad.
const CASE_BYTES: usize = 48;

struct Rng(u64);
impl Rng {
    fn u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.u64() % n
    }

    /// An f32 biased to the boundaries: specials, subnormals, and exponents whose
    /// products, quotients and sums land near the underflow or overflow threshold.
    fn f32(&mut self) -> u32 {
        let x = self.u64();
        let sign = ((x >> 63) as u32) << 31;
        let m = (x >> 8) as u32 & 0x7F_FFFF;
        let e = |lo: u64, n: u64| ((lo + (x >> 40) % n) as u32) << 23;
        match self.below(10) {
            0 => {
                const EDGE: [u32; 12] = [
                    0,
                    1,
                    0x7F_FFFF,
                    0x80_0000,
                    0x80_0001,
                    0x7F7F_FFFF,
                    0x7F80_0000,
                    0x7FC0_0000,
                    0x7F80_0001,
                    0x3F80_0000,
                    0x4F00_0000,
                    0x5F00_0000,
                ];
                EDGE[(x >> 20) as usize % 12] | sign
            }
            1 => sign | m,                 // subnormal
            2 | 3 => sign | e(40, 30) | m, // 2^-87 .. 2^-58: products near 2^-126
            4 => sign | e(120, 8) | m,     // near 1
            5 => sign | e(245, 9) | m,     // near the largest finite
            6 => sign | e(1, 5) | m,       // just above the smallest normal
            7 => (self.below(4000) as f32 - 2000.0).to_bits() ^ sign,
            _ => x as u32,
        }
    }

    /// An f64 biased like [`Rng::f32`].
    fn f64(&mut self) -> u64 {
        let x = self.u64();
        let sign = x & (1 << 63);
        let m = self.u64() & 0xF_FFFF_FFFF_FFFF;
        let e = |lo: u64, n: u64| (lo + (x >> 40) % n) << 52;
        match self.below(10) {
            0 => {
                const EDGE: [u64; 12] = [
                    0,
                    1,
                    0xF_FFFF_FFFF_FFFF,
                    0x10_0000_0000_0000,
                    0x10_0000_0000_0001,
                    0x7FEF_FFFF_FFFF_FFFF,
                    0x7FF0_0000_0000_0000,
                    0x7FF8_0000_0000_0000,
                    0x7FF0_0000_0000_0001,
                    0x3FF0_0000_0000_0000,
                    0x41E0_0000_0000_0000,
                    0x43E0_0000_0000_0000,
                ];
                EDGE[(x >> 20) as usize % 12] | sign
            }
            1 => sign | m,
            2 | 3 => sign | e(480, 60) | m, // products near 2^-1022
            4 => sign | e(1016, 8) | m,
            5 => sign | e(2037, 10) | m,
            6 => sign | e(1, 5) | m,
            7 => (self.below(4000) as f64 - 2000.0).to_bits() ^ sign,
            8 => sign | e(860, 30) | m, // single-precision underflow range
            _ => x,
        }
    }

    /// An integer operand for `cvt.*.w/l`, biased to rounding and range boundaries.
    fn int(&mut self) -> u64 {
        let x = self.u64();
        match self.below(4) {
            0 => [0, 1, u64::MAX, 1 << 63, (1 << 63) - 1, 1 << 31, 0x7FFF_FFFF][x as usize % 7],
            1 => (x as i64 >> (x % 64)) as u64,
            2 => (1u64 << (24 + x % 40)) + (x >> 60) - 8,
            _ => x,
        }
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
const CMP: [&str; 16] = [
    "af", "un", "eq", "ueq", "lt", "ult", "le", "ule", "saf", "sun", "seq", "sueq", "slt", "sult",
    "sle", "sule",
];
const CONV: [&str; 26] = [
    "cvt.s.d",
    "cvt.d.s",
    "cvt.s.w",
    "cvt.d.w",
    "cvt.s.l",
    "cvt.d.l",
    "cvt.w.s",
    "cvt.w.d",
    "cvt.l.s",
    "cvt.l.d",
    "round.w.s",
    "round.w.d",
    "round.l.s",
    "round.l.d",
    "trunc.w.s",
    "trunc.w.d",
    "trunc.l.s",
    "trunc.l.d",
    "ceil.w.s",
    "ceil.w.d",
    "ceil.l.s",
    "ceil.l.d",
    "floor.w.s",
    "floor.w.d",
    "floor.l.s",
    "floor.l.d",
];

fn cases(seed: u64, n: usize) -> Vec<Case> {
    let mut r = Rng(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let single = r.below(2) == 0;
        let fmt = if single { "s" } else { "d" };
        // Upper halves of single-precision operands are random (results must keep fd's).
        let val = |r: &mut Rng| {
            if single {
                r.u64() << 32 | r.f32() as u64
            } else {
                r.f64()
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
            7 => format!("cmp.{}.{fmt} $f3, $f1, $f2", CMP[r.below(16) as usize]),
            _ => {
                let op = CONV[r.below(26) as usize];
                // The source format is the last letter.
                fs = match op.as_bytes()[op.len() - 1] {
                    b's' => r.u64() << 32 | r.f32() as u64,
                    b'd' => r.f64(),
                    _ => r.int(),
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

/// LLVM 14 encodes `max.fmt` and `mina.fmt` with each other's funct (see `qemu_diff.rs`):
/// the QEMU build swaps the mnemonics to run the same operation.
fn for_qemu(asm: &str) -> String {
    if let Some(rest) = asm.strip_prefix("max.") {
        format!("mina.{rest}")
    } else if let Some(rest) = asm.strip_prefix("mina.") {
        format!("max.{rest}")
    } else {
        asm.to_string()
    }
}

fn program(cases: &[Case], qemu: bool) -> String {
    let mut s = String::from(
        "    .set noreorder\n    .set noat\n    .text\n    .globl __start\n__start:\n\
         \x20   lui $4, %hi(cases)\n    addiu $4, $4, %lo(cases)\n",
    );
    for c in cases {
        let inst = if qemu {
            for_qemu(&c.asm)
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

fn build(dir: &Path, name: &str, asm: &str) -> std::path::PathBuf {
    let s = dir.join(format!("{name}.s"));
    let o = dir.join(format!("{name}.o"));
    let e = dir.join(format!("{name}.elf"));
    std::fs::write(&s, asm).unwrap();
    let st = Command::new("clang-14")
        .args([
            "--target=mipsel-unknown-linux-gnu",
            "-march=mips32r6",
            "-mfp64",
            "-c",
        ])
        .arg(&s)
        .arg("-o")
        .arg(&o)
        .output()
        .expect("clang-14 must be installed");
    assert!(
        st.status.success(),
        "assembling {name}: {}",
        String::from_utf8_lossy(&st.stderr)
    );
    let st = Command::new("ld.lld-14")
        .args(["-static", "-e", "__start", "-Ttext=0x100000"])
        .arg(&o)
        .arg("-o")
        .arg(&e)
        .output()
        .expect("ld.lld-14 must be installed");
    assert!(
        st.status.success(),
        "linking {name}: {}",
        String::from_utf8_lossy(&st.stderr)
    );
    e
}

/// Runs the program on the emulator; returns the case records (read at `$25`).
fn run_emulator(elf: &Path, len: usize) -> Vec<u8> {
    let data = std::fs::read(elf).unwrap();
    let exe = trax_emulator::elf::Executable::parse("fpu", &data).unwrap();
    let mut m = Machine::new(
        &exe.segments,
        exe.text_start,
        exe.text_end,
        exe.entry,
        MachineConfig::default(),
    )
    .unwrap();
    let summary = m.run(&mut std::io::sink());
    match summary.outcome {
        Outcome::Crashed(c) if matches!(c.fault, Fault::Syscall(_)) => m
            .shared
            .mem
            .global_slice(c.regs.gpr[25], len as u32)
            .expect("case records mapped")
            .to_vec(),
        o => panic!("emulator ended with {o:?}"),
    }
}

/// Runs `cases` on both; returns a description per mismatching mnemonic (count, example).
fn compare(name: &str, cases: &[Case]) -> BTreeMap<String, (usize, String)> {
    let dir = common::scratch("fpu_qemu");
    let len = cases.len() * CASE_BYTES;
    let ours = run_emulator(&build(&dir, name, &program(cases, false)), len);
    let qelf = build(&dir, &format!("{name}_qemu"), &program(cases, true));
    let q = Command::new("qemu-mipsel")
        .args(["-cpu", "mips32r6-generic"])
        .arg(&qelf)
        .output()
        .expect("qemu-mipsel (package qemu-user) must be installed");
    assert!(
        q.status.success(),
        "qemu failed: {}",
        String::from_utf8_lossy(&q.stderr)
    );
    assert_eq!(q.stdout.len(), len, "qemu output length");
    let mut bad: BTreeMap<String, (usize, String)> = BTreeMap::new();
    for (i, c) in cases.iter().enumerate() {
        let at = |b: &[u8], o: usize| {
            let r = &b[i * CASE_BYTES + o..];
            (
                u64::from_le_bytes(r[..8].try_into().unwrap()),
                u32::from_le_bytes(r[8..12].try_into().unwrap()),
            )
        };
        let (want, got) = (at(&q.stdout, 32), at(&ours, 32));
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
const FOUND: &[(&str, u64, u64, u64, u32)] = &[
    // Exact result tiny before rounding, the smallest normal after (tininess after rounding).
    (
        "maddf.s $f3, $f1, $f2",
        0x1d2821b0,
        0x8102ca1d,
        0x807fffff,
        3,
    ),
    // 2^-126 - 2^-150: a tie on the subnormal grid rounding to 2^-126, yet tiny.
    ("mul.s $f3, $f1, $f2", 0x3faaaaaa, 0x00600000, 0, 0),
    // Sums next to the overflow threshold (an error-free transform overflowing).
    ("add.s $f3, $f1, $f2", 0xfeab2197, 0x7f7fffff, 0, 2),
    ("sub.s $f3, $f1, $f2", 0xf30186c1, 0x7f7fffff, 0, 2),
    (
        "add.d $f3, $f1, $f2",
        0x7fc213c9b0ce7b5e,
        0xffefffffffffffff,
        0,
        0,
    ),
    (
        "sub.d $f3, $f1, $f2",
        0x7fd528dc549b6dd3,
        0x7fefffffffffffff,
        0,
        2,
    ),
    (
        "add.d $f3, $f1, $f2",
        0x7fc8ac230880dd8e,
        0xffefffffffffffff,
        0,
        1,
    ),
    // Results that underflow to zero in a directed rounding mode: the sign of the zero.
    ("div.s $f3, $f1, $f2", 0x10af1d37, 0x5b75eecd, 0, 3),
    ("mul.s $f3, $f1, $f2", 0x1cba9e9c, 0x17497838, 0, 3),
    (
        "div.d $f3, $f1, $f2",
        0x8000000000000001,
        0x3ff90c0d534ab347,
        0,
        1,
    ),
    (
        "mul.d $f3, $f1, $f2",
        0x8000000000000001,
        0x3fef07f0a81461b5,
        0,
        2,
    ),
    ("cvt.s.d $f3, $f1", 0x3692fa5e7ecee4b3, 0, 0, 1),
    (
        "maddf.d $f3, $f1, $f2",
        0xb671becb92024edb,
        0x003954312b95d48f,
        1,
        3,
    ),
    (
        "msubf.s $f3, $f1, $f2",
        0x00ffc04d,
        0x9ae305dd,
        0x80000001,
        2,
    ),
];

#[test]
fn scalar_fpu_corners_match_qemu() {
    // `TRAX_FPU_QEMU_CASES=N` runs more cases (a longer hunt for differences).
    let n = std::env::var("TRAX_FPU_QEMU_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(30_000usize);
    let mut all: Vec<Case> = FOUND
        .iter()
        .map(|&(asm, fs, ft, fd, rm)| Case {
            asm: asm.into(),
            fs,
            ft,
            fd,
            fcsr: rm,
        })
        .collect();
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
