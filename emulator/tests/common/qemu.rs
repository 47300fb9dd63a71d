//! Shared by the scalar differential tests against QEMU (`qemu_diff.rs`, `fpu_qemu.rs`):
//! building a Linux-style MIPS32r6 program with clang-14 and ld.lld-14, running it on
//! QEMU and on the emulator up to its first `syscall`.

use std::path::{Path, PathBuf};
use std::process::Command;

use trax_emulator::Fault;
use trax_emulator::Outcome;
use trax_emulator::{Machine, MachineConfig};

/// The FPU format conversions (`cvt`, `round`, `trunc`, `ceil`, `floor`); the source
/// format is the last letter.
pub const FPU_CONVERSIONS: [&str; 26] = [
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

/// The `cmp.cond.fmt` conditions.
pub const FPU_CONDITIONS: [&str; 16] = [
    "af", "un", "eq", "ueq", "lt", "ult", "le", "ule", "saf", "sun", "seq", "sueq", "slt", "sult",
    "sle", "sule",
];

/// Assembles and links `asm` (entry `__start`, text at 0x100000) into `dir/name.elf`.
pub fn build(dir: &Path, name: &str, asm: &str) -> PathBuf {
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

/// The program as QEMU must see it. LLVM 14 encodes `max.fmt` with funct 0x1D and
/// `mina.fmt` with 0x1E, the reverse of the architecture (and QEMU): MINA = 0x1D,
/// MAX = 0x1E. The emulator follows LLVM 14, the only producer of code for this machine
/// (see `decode.rs`), so the QEMU build swaps the two mnemonics to get the same operation.
pub fn for_qemu(asm: &str) -> String {
    asm.lines()
        .map(|l| {
            let t = l.trim_start();
            if let Some(rest) = t.strip_prefix("max.") {
                format!("    mina.{rest}")
            } else if let Some(rest) = t.strip_prefix("mina.") {
                format!("    max.{rest}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// Runs `elf` on QEMU (`mips32r6-generic`); returns its stdout.
pub fn run_qemu(elf: &Path) -> Vec<u8> {
    let q = Command::new("qemu-mipsel")
        .args(["-cpu", "mips32r6-generic"])
        .arg(elf)
        .output()
        .expect("qemu-mipsel (package qemu-user) must be installed");
    assert!(
        q.status.success(),
        "qemu failed on {}: {}",
        elf.display(),
        String::from_utf8_lossy(&q.stderr)
    );
    q.stdout
}

/// Runs `elf` on the emulator, which has no operating system and stops at the first
/// `syscall`; returns the `len` bytes at the address in `$25` then.
pub fn run_emulator(elf: &Path, len: u32) -> Result<Vec<u8>, String> {
    let data = std::fs::read(elf).unwrap();
    let exe = trax_emulator::Executable::parse("diff", &data).map_err(|e| e.to_string())?;
    let mut m = Machine::new(
        &exe.segments,
        exe.text_start,
        exe.text_end,
        exe.entry,
        MachineConfig::default(),
    )
    .map_err(|e| e.to_string())?;
    let summary = m.run(&mut std::io::sink());
    match summary.outcome {
        Outcome::Crashed(c) if matches!(c.fault, Fault::Syscall(_)) => m
            .shared
            .mem
            .global_slice(c.regs.gpr[25], len)
            .map(|s| s.to_vec())
            .ok_or_else(|| "dump unmapped".into()),
        Outcome::Crashed(c) => Err(format!("emulator crashed at {:#x}: {}", c.pc, c.fault)),
        o => Err(format!("emulator ended with {o:?}")),
    }
}
