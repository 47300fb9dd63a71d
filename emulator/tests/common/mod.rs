//! Test support: building small C programs for the machine with clang-14 and ld.lld-14,
//! with a start-up stub and a C header for the TRaX extension generated from the
//! instruction table (`trax_runtime::isa`).
#![allow(dead_code)]

pub mod qemu;

use std::path::{Path, PathBuf};
use std::process::Command;

use trax_emulator::timing::{ChipConfig, DEFAULT_CHIP};
use trax_emulator::{run, Mode, RunReport, RunRequest};
use trax_runtime::isa::{Field, OperandKind, TraxOp, TRAX_INSTRUCTIONS};

/// Scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("trax-emu-tests")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// C declarations of every TRaX instruction as `trax_<name>` (fixed registers: GPR
/// operands in $4, $5, $6, results in $2; FPU operands in $f12, $f14, results in $f0;
/// `sa`-immediate instructions as macros taking a constant).
pub fn trax_header() -> String {
    let mut h = String::from("#pragma once\n");
    for i in TRAX_INSTRUCTIONS {
        let name = i.mnemonic.trim_start_matches("trax.");
        let mut vals = Vec::new();
        let mut params = Vec::new();
        let mut binds = Vec::new();
        let mut ins = Vec::new();
        let mut ret = "void";
        let mut out = String::new();
        let (mut g, mut f) = (4, 12);
        let mut imm = false;
        for o in i.operands {
            match o.kind {
                OperandKind::GprDef => {
                    vals.push(2);
                    ret = "unsigned";
                    binds.push("register unsigned r asm(\"$2\");".to_string());
                    out = "\"=r\"(r)".into();
                }
                OperandKind::FprDef => {
                    vals.push(0);
                    ret = "float";
                    binds.push("register float r asm(\"$f0\");".to_string());
                    out = "\"=f\"(r)".into();
                }
                OperandKind::GprUse => {
                    vals.push(g);
                    let n = params.len();
                    params.push(format!("unsigned a{n}"));
                    binds.push(format!("register unsigned b{n} asm(\"${g}\") = a{n};"));
                    ins.push(format!("\"r\"(b{n})"));
                    g += 1;
                }
                OperandKind::FprUse => {
                    vals.push(f);
                    let n = params.len();
                    let ty = if i.op == TraxOp::PrintF64 {
                        "double"
                    } else {
                        "float"
                    };
                    params.push(format!("{ty} a{n}"));
                    binds.push(format!("register {ty} b{n} asm(\"$f{f}\") = a{n};"));
                    ins.push(format!("\"f\"(b{n})"));
                    f += 2;
                }
                OperandKind::Imm5 => {
                    assert_eq!(o.field, Field::Sa);
                    vals.push(0);
                    imm = true;
                }
            }
        }
        let word = i.encode(&vals);
        if imm {
            h += &format!(
                "#define trax_{name}(n) __asm__ volatile(\".word \" #n \"*64 + {word:#x}\")\n"
            );
            continue;
        }
        let params = if params.is_empty() {
            "void".to_string()
        } else {
            params.join(", ")
        };
        h += &format!(
            "static inline {ret} trax_{name}({params}) {{ {} __asm__ volatile(\".word {word:#x}\" : {out} : {} : \"memory\"); {} }}\n",
            binds.join(" "),
            ins.join(", "),
            if ret == "void" { "" } else { "return r;" }
        );
    }
    h
}

const START: &str = "
    .text
    .globl __trax_start
    .ent __trax_start
__trax_start:
    lui $sp, 0x8000
    lui $gp, %hi(_gp)
    addiu $gp, $gp, %lo(_gp)
    jal trax_main
    nop
    .word 0x70000007
    .end __trax_start
";

/// Common clang flags for the machine.
pub const CFLAGS: &[&str] = &[
    "--target=mipsel-unknown-linux-gnu",
    "-march=mips32r6",
    "-mfp64",
    "-mabi=32",
    "-g",
    "-fno-pic",
    "-mno-abicalls",
    "-nostdlib",
    "-ffreestanding",
    "-fno-builtin",
    "-Wno-unused-command-line-argument",
];

fn check(cmd: &mut Command) {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("running {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Compiles `src` (C, includes "trax.h") at `opt` and links it with the start-up stub.
pub fn build_c(name: &str, src: &str, opt: &str) -> PathBuf {
    let d = scratch(name);
    std::fs::write(d.join("trax.h"), trax_header()).unwrap();
    std::fs::write(d.join("start.s"), START).unwrap();
    let c = d.join(format!("{name}.c"));
    std::fs::write(&c, src).unwrap();
    for (s, o) in [
        (c.clone(), d.join("k.o")),
        (d.join("start.s"), d.join("start.o")),
    ] {
        check(
            Command::new("clang-14")
                .args(CFLAGS)
                .arg(opt)
                .arg("-c")
                .arg(&s)
                .arg("-o")
                .arg(&o),
        );
    }
    let elf = d.join(format!("{name}.elf"));
    check(
        Command::new("ld.lld-14")
            .args(["-static", "-e", "__trax_start", "-Ttext=0x100000"])
            .arg(d.join("start.o"))
            .arg(d.join("k.o"))
            .arg("-o")
            .arg(&elf),
    );
    elf
}

/// Compiles a TRaX-Rust kernel at `opt` and links it with the runtime start-up code, as
/// `trax build` does; returns the executable.
pub fn build_rust(kernel: &Path, opt: u8) -> Vec<u8> {
    use trax_assembler::link::{link, Input, LinkOptions};
    use trax_compiler::{compile_file, CompileOptions, Emit, Prelude};
    let copts = CompileOptions {
        opt_level: opt,
        emit: Emit::Obj,
        prelude: Some(Prelude::runtime()),
    };
    let obj = compile_file(kernel, &copts)
        .unwrap_or_else(|e| panic!("compile {}: {e}", kernel.display()));
    let input = Input {
        name: kernel.file_name().unwrap().to_string_lossy().into_owned(),
        bytes: obj.bytes,
    };
    link(&[input], &LinkOptions::default())
        .unwrap_or_else(|e| panic!("link {}: {e}", kernel.display()))
        .elf
}

/// The default chip reshaped to `tms` x `threads` (one L2 for all).
pub fn chip(tms: u32, threads: u32) -> ChipConfig {
    let mut c = ChipConfig::preset(DEFAULT_CHIP).unwrap();
    c.tms = tms;
    c.threads_per_tm = threads;
    c.tms_per_l2 = tms;
    c
}

/// Runs an ELF functionally with `tms` x `threads`; returns the report and the printed
/// output.
pub fn run_elf(elf: &Path, tms: u32, threads: u32) -> (RunReport, String) {
    let data = std::fs::read(elf).unwrap();
    let path = elf.display().to_string();
    let chip = chip(tms, threads);
    let mut out = Vec::new();
    let r = run(
        RunRequest::new(&path, &data, &chip, Mode::Functional),
        &mut out,
    )
    .unwrap();
    (r, String::from_utf8(out).unwrap())
}
