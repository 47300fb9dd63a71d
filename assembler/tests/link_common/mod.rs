//! Helpers shared by the linker tests: compiling test inputs with clang-14/llc and running
//! LLVM tools.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

use trax_assembler::link::Input;

/// Flags the issue fixes for clang-14 objects.
pub const CLANG_FLAGS: &[&str] = &[
    "--target=mipsel-unknown-elf",
    "-mcpu=mips32r6",
    "-G0",
    "-fno-pic",
    "-mno-abicalls",
    "-g",
    "-O2",
    "-c",
];

/// Flags of the compiler's own objects.
pub const LLC_FLAGS: &[&str] = &[
    "-march=mipsel",
    "-mcpu=mips32r6",
    "-mattr=+msa,+fp64,+noabicalls",
    "-relocation-model=static",
    "-filetype=obj",
];

/// A fresh scratch directory for one test.
pub fn scratch(test: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("trax-link-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// Path of a file in `tests/data`.
pub fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Runs a command, panicking with its stderr on failure; returns stdout.
pub fn run(cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Compiles C source `src` (in tests/data) with clang-14 and the given flags.
pub fn clang(dir: &Path, src: &str, flags: &[&str]) -> PathBuf {
    let out = dir.join(src.replace(".c", ".o"));
    run(Command::new("clang-14")
        .args(flags)
        .arg(data(src))
        .arg("-o")
        .arg(&out));
    out
}

/// Compiles C source text with clang-14 and the given flags.
pub fn clang_text(dir: &Path, name: &str, text: &str, flags: &[&str]) -> PathBuf {
    let src = dir.join(format!("{name}.c"));
    std::fs::write(&src, text).unwrap();
    let out = dir.join(format!("{name}.o"));
    run(Command::new("clang-14")
        .args(flags)
        .arg(&src)
        .arg("-o")
        .arg(&out));
    out
}

/// Compiles LLVM IR `src` (in tests/data) with llc.
pub fn llc(dir: &Path, src: &str) -> PathBuf {
    let out = dir.join(src.replace(".ll", ".o"));
    run(Command::new("llc")
        .args(LLC_FLAGS)
        .arg(data(src))
        .arg("-o")
        .arg(&out));
    out
}

/// Compiles LLVM IR text with llc.
pub fn llc_text(dir: &Path, name: &str, text: &str) -> PathBuf {
    let src = dir.join(format!("{name}.ll"));
    std::fs::write(&src, text).unwrap();
    let out = dir.join(format!("{name}.o"));
    run(Command::new("llc")
        .args(LLC_FLAGS)
        .arg(&src)
        .arg("-o")
        .arg(&out));
    out
}

/// Reads object files into linker inputs.
pub fn inputs(paths: &[PathBuf]) -> Vec<Input> {
    paths
        .iter()
        .map(|p| Input {
            name: p.display().to_string(),
            bytes: std::fs::read(p).unwrap(),
        })
        .collect()
}

/// IR module header for hand-written test modules.
pub const IR_HEADER: &str =
    "target datalayout = \"e-m:m-p:32:32-i8:8:32-i16:16:32-i64:64-n32-S64\"\n\
                             target triple = \"mipsel-unknown-none\"\n";
