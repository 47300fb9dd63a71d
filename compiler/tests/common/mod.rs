//! Helpers shared by the compiler's integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use trax_compiler::{compile_file, CompileOptions, Emit, Prelude};

/// Directory of this crate.
pub fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch directory under cargo's target tmp dir (reused across runs).
pub fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("trax-compiler-{name}"));
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

/// Compiles `path` with the runtime prelude; panics with the rendered diagnostics on error.
pub fn build(path: &Path, opt: u8, emit: Emit) -> Vec<u8> {
    let opts = CompileOptions {
        opt_level: opt,
        emit,
        prelude: Some(Prelude::runtime()),
    };
    match compile_file(path, &opts) {
        Ok(o) => o.bytes,
        Err(e) => panic!("compiling {} at -O{opt} failed:\n{e}", path.display()),
    }
}

/// Compiles to an object file in `dir` and returns its path.
pub fn build_obj(path: &Path, opt: u8, dir: &Path) -> PathBuf {
    let bytes = build(path, opt, Emit::Obj);
    let out = dir.join(format!(
        "{}-O{opt}.o",
        path.file_stem().unwrap().to_string_lossy()
    ));
    std::fs::write(&out, bytes).expect("write object");
    out
}

/// Runs a tool and returns stdout; panics if it fails.
pub fn tool(name: &str, args: &[&str]) -> String {
    let out = Command::new(name)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("running {name}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{name} {args:?} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// Asserts `llvm-dwarfdump --verify` accepts the object.
pub fn verify_dwarf(obj: &Path) {
    let out = tool("llvm-dwarfdump", &["--verify", obj.to_str().unwrap()]);
    assert!(
        out.contains("No errors."),
        "dwarfdump --verify on {}:\n{out}",
        obj.display()
    );
}

/// Asserts the object has no `$gp`-relative relocations.
pub fn no_gprel(obj: &Path) {
    let out = tool("llvm-objdump", &["-r", obj.to_str().unwrap()]);
    assert!(
        !out.contains("GPREL"),
        "GPREL relocation in {}:\n{out}",
        obj.display()
    );
}

/// Asserts every undefined symbol is a linker-provided `__trax_*` symbol (no libc calls).
pub fn only_trax_undefined(obj: &Path) {
    let out = tool("llvm-objdump", &["-t", obj.to_str().unwrap()]);
    for line in out.lines().filter(|l| l.contains("*UND*")) {
        let sym = line.split_whitespace().last().unwrap_or("");
        assert!(
            sym.is_empty() || sym.starts_with("__trax_"),
            "{}: undefined symbol {sym}",
            obj.display()
        );
    }
}
