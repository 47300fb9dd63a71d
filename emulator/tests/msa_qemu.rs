//! Differential test of MSA execution against QEMU (`qemu-mipsel -cpu P5600`, a MIPS32r5
//! core with MSA; the MSA encodings and semantics are the same as on r6).
//!
//! Random valid MSA words (every register-to-register format, and the branches) are run with random
//! inputs (integer lanes and float lanes with NaNs, infinities, zeros, subnormals) and
//! random MSACSR rounding mode / flush-to-zero / non-trapping enabled exceptions, inside a generated program that loads the
//! inputs, executes the word and stores the destination, MSACSR and a GPR. The same cases
//! run on our executor; destination, MSACSR (Cause and Flags) and the GPR must agree
//! exactly (our choices for architecturally open behaviour follow QEMU's).

mod msa_common;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::process::Command;

use msa_common::*;
use trax_emulator::msa::{decode, Form, MsaOutcome};
use trax_emulator::RegFile;

const CASE_BYTES: usize = 96;

struct Case {
    word: u32,
    ws: u128,
    wt: u128,
    wd: u128,
    csr: u32,
    r6: u32,
    r7: u32,
}

/// Sets the register fields of a decoded word to the harness registers
/// (ws = $w1, wt = $w2, wd = $w3, rt = $6, rs = $7, rd = $9).
fn patch(word: u32) -> Option<u32> {
    let inst = decode(word)?;
    let set = |w: u32, wd: Option<u32>, ws: Option<u32>, wt: Option<u32>| {
        let mut w = w;
        if let Some(v) = wd {
            w = (w & !(31 << 6)) | v << 6;
        }
        if let Some(v) = ws {
            w = (w & !(31 << 11)) | v << 11;
        }
        if let Some(v) = wt {
            w = (w & !(31 << 16)) | v << 16;
        }
        w
    };
    let w = match inst.op.form() {
        Form::R3 => set(word, Some(3), Some(1), Some(2)),
        Form::R3Gpr => set(word, Some(3), Some(1), Some(6)),
        Form::Imm | Form::Elm | Form::Insve | Form::R2 => set(word, Some(3), Some(1), None),
        Form::Ldi => set(word, Some(3), None, None),
        Form::Copy => set(word, Some(9), Some(1), None),
        Form::Insert | Form::Fill => set(word, Some(3), Some(7), None),
        // Branches test $w1 and skip one instruction after the delay slot when taken.
        Form::Branch => (set(word, None, None, Some(1)) & !0xFFFF) | 2,
        Form::Ctc | Form::Cfc | Form::Mem => return None,
    };
    Some(w)
}

fn random_vec(rng: &mut Rng) -> u128 {
    match rng.below(6) {
        0..=1 => from_lanes(32, &[0, 1, 2, 3].map(|_| rng.f32_bits() as u64)),
        2 => from_lanes(64, &[rng.f64_bits(), rng.f64_bits()]),
        _ => {
            let bits = DF_BITS[rng.below(4) as usize];
            rng.int_vec(bits)
        }
    }
}

fn build_program(cases: &[Case]) -> String {
    let mut s = String::new();
    s.push_str("\t.module fp=64\n\t.nan 2008\n\t.set noreorder\n\t.set noat\n\t.text\n\t.globl __start\n__start:\n");
    s.push_str("\tlui $4, %hi(cases)\n\taddiu $4, $4, %lo(cases)\n");
    for c in cases {
        // After a branch: delay slot, then an instruction skipped when taken ($9 = 1 if not).
        let tail = if decode(c.word).is_some_and(|i| i.is_branch()) {
            "\tnop\n\taddiu $9, $zero, 1\n"
        } else {
            ""
        };
        let _ = write!(
            s,
            "\tld.b $w1, 0($4)\n\tld.b $w2, 16($4)\n\tld.b $w3, 32($4)\n\tlw $5, 48($4)\n\tctcmsa $1, $5\n\
             \tlw $6, 52($4)\n\tlw $7, 56($4)\n\tmove $9, $zero\n\t.word {:#010x}\n{tail}\tcfcmsa $5, $1\n\
             \tst.b $w3, 64($4)\n\tsw $5, 80($4)\n\tsw $9, 84($4)\n\taddiu $4, $4, {CASE_BYTES}\n",
            c.word
        );
    }
    let _ = write!(
        s,
        "\tli $2, 4004\n\tli $4, 1\n\tlui $5, %hi(cases)\n\taddiu $5, $5, %lo(cases)\n\tli $6, {}\n\tsyscall\n\
         \tli $2, 4001\n\tli $4, 0\n\tsyscall\n\t.data\n\t.p2align 4\ncases:\n",
        cases.len() * CASE_BYTES
    );
    for c in cases {
        let words = |v: u128| {
            (0..4)
                .map(|i| format!("{:#x}", (v >> (32 * i)) as u32))
                .collect::<Vec<_>>()
                .join(",")
        };
        let _ = writeln!(
            s,
            "\t.word {},{},{},{:#x},{:#x},{:#x},0,0,0,0,0,0,0,0,0",
            words(c.ws),
            words(c.wt),
            words(c.wd),
            c.csr,
            c.r6,
            c.r7
        );
    }
    s
}

/// Runs the cases under QEMU; returns per case (wd, msacsr, $9).
fn run_qemu(cases: &[Case]) -> Vec<(u128, u32, u32)> {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trax-msa-qemu");
    std::fs::create_dir_all(&dir).unwrap();
    let asm = dir.join("t.s");
    let obj = dir.join("t.o");
    let exe = dir.join("t");
    std::fs::write(&asm, build_program(cases)).unwrap();
    let st = Command::new("llvm-mc")
        .args([
            "-filetype=obj",
            "-triple=mipsel",
            "-mcpu=mips32r5",
            "-mattr=+msa,+fp64",
            "-o",
        ])
        .arg(&obj)
        .arg(&asm)
        .status()
        .expect("llvm-mc (LLVM 14 tools) must be installed");
    assert!(st.success(), "assembling the harness failed");
    let st = Command::new("ld.lld-14")
        .args(["-static", "-e", "__start", "-o"])
        .arg(&exe)
        .arg(&obj)
        .status()
        .expect("ld.lld-14 must be installed");
    assert!(st.success(), "linking the harness failed");
    let out = Command::new("qemu-mipsel")
        .args(["-cpu", "P5600"])
        .arg(&exe)
        .output()
        .expect("qemu-mipsel (package qemu-user) must be installed");
    if std::env::var_os("MSA_QEMU_KEEP").is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        out.status.success(),
        "qemu failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.stdout.len(), cases.len() * CASE_BYTES);
    out.stdout
        .chunks(CASE_BYTES)
        .map(|c| {
            let wd = u128::from_le_bytes(c[64..80].try_into().unwrap());
            let csr = u32::from_le_bytes(c[80..84].try_into().unwrap());
            let r9 = u32::from_le_bytes(c[84..88].try_into().unwrap());
            (wd, csr, r9)
        })
        .collect()
}

fn run_ours(c: &Case) -> (u128, u32, u32) {
    let mut regs = RegFile::default();
    regs.fpr[1] = c.ws;
    regs.fpr[2] = c.wt;
    regs.fpr[3] = c.wd;
    regs.msacsr = c.csr;
    regs.gpr[6] = c.r6;
    regs.gpr[7] = c.r7;
    if let MsaOutcome::Branch(taken) = run(c.word, &mut regs, &mut FlatMem(vec![])) {
        assert_eq!(decode(c.word).unwrap().imm, 8, "branch byte offset");
        regs.gpr[9] = !taken as u32;
    }
    (regs.fpr[3], regs.msacsr, regs.gpr[9])
}

#[test]
fn msa_matches_qemu_p5600() {
    let mut rng = Rng(0xC0FFEE);
    let mut cases = Vec::new();
    let minors: &[u32] = &[
        0, 1, 2, 6, 7, 9, 10, 13, 14, 15, 16, 17, 18, 19, 20, 21, 25, 26, 27, 28, 30,
    ];
    while cases.len() < 12000 {
        let word = if rng.below(20) == 0 {
            // MSA branches (COP1 rs = 0x0B, 0x0F, 0x18..0x1F).
            let rs = [0x0B, 0x0F, 0x18, 0x19, 0x1A, 0x1B, 0x1C, 0x1D, 0x1E, 0x1F]
                [rng.below(10) as usize];
            0x4400_0000 | rs << 21
        } else {
            let minor = minors[rng.below(minors.len() as u64) as usize];
            0x7800_0000 | (rng.u64() as u32 & 0x03FF_FFC0) | minor
        };
        let Some(word) = patch(word) else { continue };
        let mut csr = (rng.below(4) as u32) | if rng.below(4) == 0 { 1 << 24 } else { 0 };
        if rng.below(4) == 0 {
            // Non-trapping mode (NX) with random enabled exceptions.
            csr |= 1 << 18 | (rng.below(32) as u32) << 7;
        }
        cases.push(Case {
            word,
            ws: if word >> 26 == 0x11 && rng.below(4) == 0 {
                0 // lets bz.v be taken
            } else {
                random_vec(&mut rng)
            },
            wt: random_vec(&mut rng),
            wd: random_vec(&mut rng),
            csr,
            r6: rng.int_lane(32) as u32,
            r7: rng.u64() as u32,
        });
    }
    let qemu = run_qemu(&cases);
    let mut bad: BTreeMap<String, (usize, String)> = BTreeMap::new();
    for (c, q) in cases.iter().zip(&qemu) {
        let inst = decode(c.word).unwrap();
        let ours = run_ours(c);
        if ours != *q {
            let key = format!("{}.{}", inst.op.name(), inst.df.suffix());
            let e = bad.entry(key).or_insert((0, String::new()));
            if e.0 == 0 {
                e.1 = format!(
                    "{inst}: ws={:#034x} wt={:#034x} wd={:#034x} csr={:#x} r6={:#x} r7={:#x}\n    ours wd={:#034x} csr={:#x} r9={:#x}\n    qemu wd={:#034x} csr={:#x} r9={:#x}",
                    c.ws, c.wt, c.wd, c.csr, c.r6, c.r7, ours.0, ours.1, ours.2, q.0, q.1, q.2
                );
            }
            e.0 += 1;
        }
    }
    // Both branch outcomes occurred (r9 = 1 when not taken).
    let branch_r9: Vec<u32> = cases
        .iter()
        .zip(&qemu)
        .filter(|(c, _)| c.word >> 26 == 0x11)
        .map(|(_, q)| q.2)
        .collect();
    assert!(
        branch_r9.contains(&0) && branch_r9.contains(&1),
        "branch outcomes not both covered"
    );
    assert!(
        bad.is_empty(),
        "{} ops differ from QEMU:\n{}",
        bad.len(),
        bad.iter()
            .map(|(k, (n, ex))| format!("{k} ({n} cases): {ex}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}
