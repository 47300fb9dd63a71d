//! Shared by the benches: building a C kernel and its start-up stub into an executable
//! for the emulator with clang-14 and ld.lld-14.

use std::path::{Path, PathBuf};
use std::process::Command;

#[allow(dead_code)] // not every bench uses it
pub mod functional;

/// Start-up stub of a bare-metal kernel: stack at the top of the local store, call
/// `trax_main`, then `trax.halt`.
#[allow(dead_code)] // not every bench uses it
pub const TRAX_START: &str = "
    .text
    .globl __trax_start
__trax_start:
    lui $sp, 0x8000
    jal trax_main
    nop
    .word 0x70000007
";

/// clang flags for MIPS32r6 kernels the emulator runs (no PIC, no `$gp`-relative data).
#[allow(dead_code)] // not every bench uses it
pub const FLAGS: [&str; 8] = [
    "--target=mipsel-unknown-linux-gnu",
    "-march=mips32r6",
    "-mfp64",
    "-O2",
    "-fno-pic",
    "-mno-abicalls",
    "-G0",
    "-nostdlib",
];

/// Runs `cmd`; whether it ran and succeeded.
pub fn succeeds(cmd: &mut Command) -> bool {
    cmd.output().map(|o| o.status.success()).unwrap_or(false)
}

/// Writes each `(file, text, extra flags)` source into `dir`, compiles it with `flags`,
/// and links the objects in order into `dir/{name}.elf` with entry `entry` and the text at
/// 0x100000. `None` if a tool is missing or fails.
pub fn build(
    dir: &Path,
    name: &str,
    entry: &str,
    flags: &[&str],
    sources: &[(&str, &str, &[&str])],
) -> Option<PathBuf> {
    std::fs::create_dir_all(dir).ok()?;
    let mut objects = Vec::new();
    for (file, text, extra) in sources {
        std::fs::write(dir.join(file), text).ok()?;
        let obj = dir.join(format!("{file}.o"));
        let ok = succeeds(
            Command::new("clang-14")
                .args(flags)
                .args(*extra)
                .arg("-c")
                .arg(dir.join(file))
                .arg("-o")
                .arg(&obj),
        );
        if !ok {
            return None;
        }
        objects.push(obj);
    }
    let elf = dir.join(format!("{name}.elf"));
    succeeds(
        Command::new("ld.lld-14")
            .args(["-static", "-e", entry, "-Ttext=0x100000"])
            .args(&objects)
            .arg("-o")
            .arg(&elf),
    )
    .then_some(elf)
}
