//! Differential testing against QEMU (`qemu-mipsel -cpu mips32r6-generic`, Linux user
//! mode): generated deterministic-random sequences of scalar integer, memory, branch and
//! FPU instructions run on both; all GPRs, FPRs (64 bits), FCSR and a memory buffer are
//! compared. Every mismatch is collected and printed with the program that produced it.
//!
//! Each program: loads registers from tables of edge-case values, sets a rounding mode,
//! runs the sequence, stores every register into `dump`, then `write(1, dump, N)` and
//! `exit(0)`. QEMU's stdout is the reference; the emulator stops at the `syscall` (it has
//! no operating system) and the test reads `dump` from its memory.

use std::fmt::Write as _;
use std::path::Path;

mod common;

use common::qemu::{build, for_qemu, run_emulator, run_qemu, FPU_CONDITIONS, FPU_CONVERSIONS};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 16) as u32
    }
    fn below(&mut self, n: u32) -> u32 {
        self.next() % n
    }
    fn pick<T: Copy>(&mut self, v: &[T]) -> T {
        v[self.below(v.len() as u32) as usize]
    }
}

const GPR_EDGE: &[u32] = &[
    0,
    1,
    2,
    3,
    31,
    32,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0xFFFF_FFFE,
    0x8000,
    0xFFFF,
    0x7FFF,
    0x1234_5678,
    0xDEAD_BEEF,
    100,
    0xFFFF_FF9C,
];
const F32_EDGE: &[u32] = &[
    0x0000_0000,
    0x8000_0000,
    0x3F80_0000,
    0xBFC0_0000,
    0x7FC0_0000,
    0x7FC0_0123,
    0xFFC0_0001,
    0x7F80_0001,
    0x7FA0_0000,
    0x7F80_0000,
    0xFF80_0000,
    0x0000_0001,
    0x807F_FFFF,
    0x0080_0000,
    0x7F7F_FFFF,
    0x3DCC_CCCD,
    0x4B80_0001,
    0x4F00_0000,
    0xCF00_0001,
    0x4040_0000,
    0x3F00_0000,
    0x4EFF_FFFF,
    0x5F00_0000,
    0x0100_0000,
    0x4049_0FDB,
    0xC2F6_E979,
];
const F64_EDGE: &[u64] = &[
    0,
    0x8000_0000_0000_0000,
    0x3FF0_0000_0000_0000,
    0xBFF8_0000_0000_0000,
    0x7FF8_0000_0000_0000,
    0x7FF8_0000_0000_0123,
    0x7FF0_0000_0000_0001,
    0x7FF4_0000_0000_0000,
    0x7FF0_0000_0000_0000,
    0xFFF0_0000_0000_0000,
    1,
    0x800F_FFFF_FFFF_FFFF,
    0x0010_0000_0000_0000,
    0x7FEF_FFFF_FFFF_FFFF,
    0x3FB9_9999_9999_999A,
    0x4340_0000_0000_0001,
    0x41E0_0000_0000_0000,
    0xC1E0_0000_0020_0000,
    0x43E0_0000_0000_0000,
    0x4008_0000_0000_0000,
    0x3FE0_0000_0000_0000,
    0x4415_AF1D_78B5_8C40,
    0x0000_0000_0000_1000,
    0x3810_0000_0000_0000,
    0x47EF_FFFF_E000_0000,
    0x3690_0000_0000_0000,
];

/// Registers the sequences may write: $2..$23 ($24 = buffer, $25 = dump base).
fn reg(r: &mut Rng) -> u32 {
    2 + r.below(22)
}
fn freg(r: &mut Rng) -> u32 {
    r.below(32)
}

fn alu(r: &mut Rng) -> String {
    let (d, s, t) = (reg(r), reg(r), reg(r));
    let three = [
        "addu", "subu", "and", "or", "xor", "nor", "slt", "sltu", "mul", "muh", "mulu", "muhu",
        "div", "mod", "divu", "modu", "seleqz", "selnez",
    ];
    match r.below(12) {
        0..=3 => format!("{} ${d}, ${s}, ${t}", r.pick(&three)),
        4 => format!(
            "{} ${d}, ${t}, ${s}",
            r.pick(&["sllv", "srlv", "srav", "rotrv"])
        ),
        5 => {
            let sa = r.below(32);
            let sa = r.pick(&[0, 1, 31, sa]);
            format!(
                "{} ${d}, ${t}, {sa}",
                r.pick(&["sll", "srl", "sra", "rotr"])
            )
        }
        6 => format!("lsa ${d}, ${s}, ${t}, {}", 1 + r.below(4)),
        7 => format!(
            "{} ${d}, ${s}",
            r.pick(&["clz", "clo", "bitswap", "wsbh", "seb", "seh"])
        ),
        8 => {
            let x = r.below(65536) as i32 - 32768;
            let imm = r.pick(&[0, 1, -1, 32767, -32768, x]);
            let op = r.pick(&["addiu", "slti", "sltiu"]);
            format!("{op} ${d}, ${s}, {imm}")
        }
        9 => format!(
            "{} ${d}, ${s}, {}",
            r.pick(&["andi", "ori", "xori"]),
            r.below(65536)
        ),
        10 => match r.below(3) {
            0 => format!("aui ${d}, ${s}, {}", r.below(65536)),
            1 => format!("lui ${d}, {}", r.below(65536)),
            _ => format!("align ${d}, ${s}, ${t}, {}", r.below(4)),
        },
        _ => {
            let pos = r.below(32);
            let size = 1 + r.below(32 - pos);
            format!("{} ${d}, ${s}, {pos}, {size}", r.pick(&["ext", "ins"]))
        }
    }
}

fn mem(r: &mut Rng) -> String {
    let d = reg(r);
    match r.below(8) {
        0 => format!("lw ${d}, {}($24)", 4 * r.below(16)),
        1 => format!("sw ${d}, {}($24)", 4 * r.below(16)),
        2 => format!("{} ${d}, {}($24)", r.pick(&["lh", "lhu"]), 2 * r.below(32)),
        3 => format!("sh ${d}, {}($24)", 2 * r.below(32)),
        4 => format!("{} ${d}, {}($24)", r.pick(&["lb", "lbu"]), r.below(64)),
        5 => format!("sb ${d}, {}($24)", r.below(64)),
        6 => format!(
            "{} $f{}, {}($24)",
            r.pick(&["lwc1", "swc1"]),
            freg(r),
            4 * r.below(16)
        ),
        _ => format!(
            "{} $f{}, {}($24)",
            r.pick(&["ldc1", "sdc1"]),
            freg(r),
            8 * r.below(8)
        ),
    }
}

fn fpu(r: &mut Rng) -> String {
    let (d, s, t) = (freg(r), freg(r), freg(r));
    let fmt = r.pick(&["s", "d"]);
    match r.below(14) {
        0..=2 => format!(
            "{}.{fmt} $f{d}, $f{s}, $f{t}",
            r.pick(&["add", "sub", "mul", "div"])
        ),
        3 => format!(
            "{}.{fmt} $f{d}, $f{s}",
            r.pick(&["sqrt", "abs", "neg", "mov", "recip", "rsqrt", "rint", "class"])
        ),
        4 => format!("{}.{fmt} $f{d}, $f{s}, $f{t}", r.pick(&["maddf", "msubf"])),
        5 => format!(
            "{}.{fmt} $f{d}, $f{s}, $f{t}",
            r.pick(&["sel", "seleqz", "selnez"])
        ),
        6 => format!(
            "{}.{fmt} $f{d}, $f{s}, $f{t}",
            r.pick(&["min", "max", "mina", "maxa"])
        ),
        7 => format!("cmp.{}.{fmt} $f{d}, $f{s}, $f{t}", r.pick(&FPU_CONDITIONS)),
        8 | 9 => format!("{} $f{d}, $f{s}", r.pick(&FPU_CONVERSIONS)),
        10 => format!(
            "{} ${}, $f{s}",
            r.pick(&["mfc1", "mtc1", "mfhc1", "mthc1"]),
            reg(r)
        ),
        _ => format!(
            "{}.{fmt} $f{d}, $f{s}, $f{t}",
            r.pick(&["add", "mul", "maddf"])
        ),
    }
}

/// A forward branch over 1..3 straight-line instructions.
fn branch(r: &mut Rng, out: &mut Vec<String>) {
    let (s, t) = (reg(r), reg(r));
    let skip = 1 + r.below(3) as usize;
    let body: Vec<String> = (0..skip + 1).map(|_| alu(r)).collect();
    let br = match r.below(10) {
        0 => format!("{} ${s}, ${t}, 1f", r.pick(&["beq", "bne"])),
        1 => format!("{} ${s}, 1f", r.pick(&["blez", "bgtz", "bltz", "bgez"])),
        2 => format!("{} $f{}, 1f", r.pick(&["bc1eqz", "bc1nez"]), freg(r)),
        3 => "bal 1f".to_string(),
        4 => format!(
            "{} ${s}, ${}, 1f",
            r.pick(&["beqc", "bnec", "bltc", "bgec", "bltuc", "bgeuc"]),
            if s == t { t % 22 + 3 } else { t }
        ),
        5 => format!("{} ${s}, ${t}, 1f", r.pick(&["bovc", "bnvc"])),
        6 => format!(
            "{} ${s}, 1f",
            r.pick(&["beqzc", "bnezc", "blezc", "bgezc", "bgtzc", "bltzc"])
        ),
        7 => format!(
            "{} ${s}, 1f",
            r.pick(&["blezalc", "bgezalc", "bgtzalc", "bltzalc", "beqzalc", "bnezalc"])
        ),
        8 => "bc 1f".to_string(),
        _ => "balc 1f".to_string(),
    };
    out.push(br);
    // The first body instruction is the delay slot or forbidden slot.
    for (i, b) in body.into_iter().enumerate() {
        if i == skip + 1 {
            out.push("1:".into());
        }
        out.push(b);
    }
    out.push("1:".into());
}

/// The program of `seed` with `units` generated units (an instruction or a branch block),
/// truncated to the first `keep` units (used to find the first diverging unit).
fn program(seed: u64, units: usize, keep: usize) -> (String, String) {
    let mut r = Rng(seed);
    let mut all: Vec<Vec<String>> = Vec::new();
    for _ in 0..units {
        let mut u = Vec::new();
        match r.below(10) {
            0..=3 => u.push(alu(&mut r)),
            4 | 5 => u.push(mem(&mut r)),
            6..=8 => u.push(fpu(&mut r)),
            _ => branch(&mut r, &mut u),
        }
        all.push(u);
    }
    let last = all
        .get(keep.wrapping_sub(1))
        .map(|u| u.join("; "))
        .unwrap_or_default();
    let body: Vec<String> = all.into_iter().take(keep).flatten().collect();
    let mut s = String::from("    .set noreorder\n    .text\n    .globl __start\n__start:\n");
    s += "    lui $25, %hi(dump)\n    addiu $25, $25, %lo(dump)\n";
    s += "    lui $24, %hi(buf)\n    addiu $24, $24, %lo(buf)\n";
    s += "    lui $2, %hi(init_fpr)\n    addiu $2, $2, %lo(init_fpr)\n";
    for f in 0..32 {
        let _ = writeln!(s, "    ldc1 $f{f}, {}($2)", 8 * f);
    }
    s += "    lui $2, %hi(init_gpr)\n    addiu $2, $2, %lo(init_gpr)\n";
    for g in (3..24).rev() {
        let _ = writeln!(s, "    lw ${g}, {}($2)", 4 * g);
    }
    let _ = writeln!(
        s,
        "    lw $2, 8($2)\n    li $1, {}\n    ctc1 $1, $31\n    move $1, $zero",
        r.below(4)
    );
    for l in &body {
        if l.ends_with(':') {
            let _ = writeln!(s, "{l}");
        } else {
            let _ = writeln!(s, "    {l}");
        }
    }
    for g in 1..32 {
        if g != 25 {
            let _ = writeln!(s, "    sw ${g}, {}($25)", 4 * g);
        }
    }
    for f in 0..32 {
        let _ = writeln!(s, "    sdc1 $f{f}, {}($25)", 128 + 8 * f);
    }
    s += "    cfc1 $2, $31\n    sw $2, 384($25)\n";
    s += "    li $4, 1\n    move $5, $25\n    li $6, 456\n    li $2, 4004\n    syscall\n";
    s += "    li $2, 4001\n    li $4, 0\n    syscall\n";
    s += "    .data\n    .align 3\ndump: .space 392\nbuf:\n";
    for _ in 0..16 {
        let c = [r.next(), r.pick(GPR_EDGE), r.pick(F32_EDGE)];
        let _ = writeln!(s, "    .word {:#x}", r.pick(&c));
    }
    s += "init_gpr:\n";
    for _ in 0..32 {
        let v = if r.below(2) == 0 {
            r.pick(GPR_EDGE)
        } else {
            r.next()
        };
        let _ = writeln!(s, "    .word {v:#x}");
    }
    s += "    .align 3\ninit_fpr:\n";
    for _ in 0..32 {
        let v = match r.below(3) {
            0 => r.pick(F64_EDGE),
            1 => ((r.pick(F32_EDGE) as u64) << 32) | r.pick(F32_EDGE) as u64,
            _ => ((r.next() as u64) << 32) | r.pick(F32_EDGE) as u64,
        };
        let _ = writeln!(s, "    .dword {v:#x}");
    }
    (s, last)
}

fn describe(off: usize) -> String {
    match off {
        0..=127 => format!("${}", off / 4),
        128..=383 => format!("$f{}", (off - 128) / 8),
        384..=391 => "fcsr".into(),
        _ => format!("buf+{}", (off - 392) / 4 * 4),
    }
}

/// Runs one program on both; returns the mismatches.
fn compare(dir: &Path, name: &str, asm: &str) -> Vec<String> {
    let elf = build(dir, name, asm);
    let qelf = build(dir, &format!("{name}_qemu"), &for_qemu(asm));
    let want = run_qemu(&qelf);
    assert_eq!(want.len(), 456, "qemu output of {name}");
    let got = match run_emulator(&elf, 456) {
        Ok(g) => g,
        Err(e) => return vec![e],
    };
    let mut out = Vec::new();
    // Compare 32-bit words for GPRs, FCSR and the buffer; 64-bit for FPRs.
    let mut off = 0;
    while off < 456 {
        let n = if (128..384).contains(&off) { 8 } else { 4 };
        // $25 holds the dump address (not stored); $29 is the OS-provided stack pointer.
        if off == 100 || off == 116 {
            off += n;
            continue;
        }
        let (w, g) = (&want[off..off + n], &got[off..off + n]);
        if w != g {
            let hex = |b: &[u8]| {
                b.iter()
                    .rev()
                    .map(|x| format!("{x:02x}"))
                    .collect::<String>()
            };
            out.push(format!(
                "{} qemu {} emulator {}",
                describe(off),
                hex(w),
                hex(g)
            ));
        }
        off += n;
    }
    out
}

#[test]
fn scalar_sequences_match_qemu() {
    let dir = common::scratch("qemu_diff");
    let mut failures = String::new();
    // `TRAX_QEMU_DIFF_PROGRAMS=N` runs more programs (a longer hunt for differences).
    let programs = std::env::var("TRAX_QEMU_DIFF_PROGRAMS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(48u64);
    let units = 100;
    for p in 0..programs {
        let seed = 0x5EED_0000 + p * 7919;
        let (asm, _) = program(seed, units, units);
        let bad = compare(&dir, &format!("p{p}"), &asm);
        if bad.is_empty() {
            continue;
        }
        // Find the first unit after which the states differ.
        let (mut lo, mut hi) = (0, units);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            let (asm, _) = program(seed, units, mid);
            if compare(&dir, &format!("p{p}_bisect"), &asm).is_empty() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (asm, culprit) = program(seed, units, hi);
        let first = compare(&dir, &format!("p{p}_first"), &asm);
        let _ = writeln!(
            failures,
            "program {p}: first divergence after unit {hi}: `{culprit}`"
        );
        for m in first {
            let _ = writeln!(failures, "    {m}");
        }
        let _ = writeln!(failures, "    (final state: {} mismatches)", bad.len());
    }
    assert!(
        failures.is_empty(),
        "mismatches (programs in {}):\n{failures}",
        dir.display()
    );
}
