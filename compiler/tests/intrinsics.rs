//! TRaX instructions are emitted as real words that decode with the runtime's table,
//! SIMD lowers to MSA, and symbol addresses use absolute HI16/LO16 relocations.

mod common;

use common::*;
use trax_runtime::isa::{decode, TraxOp};

/// Decodes every `<unknown>` word of the disassembly with the TRaX table.
fn trax_ops(disasm: &str) -> Vec<TraxOp> {
    let mut ops = Vec::new();
    for line in disasm.lines() {
        let parts: Vec<&str> = line.split_whitespace().collect();
        if parts.len() >= 6 && parts[0].ends_with(':') && line.contains("<unknown>") {
            let bytes: Vec<u8> = parts[1..5]
                .iter()
                .filter_map(|b| u8::from_str_radix(b, 16).ok())
                .collect();
            if bytes.len() == 4 {
                let w = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
                if let Some(i) = decode(w) {
                    ops.push(i.op);
                }
            }
        }
    }
    ops
}

#[test]
fn builtins_emit_trax_words_msa_and_absolute_relocations() {
    let out = scratch("intrinsics");
    let k = crate_dir().join("tests/kernels/intrinsics.rs");
    for opt in [0, 2] {
        let obj = build_obj(&k, opt, &out);
        verify_dwarf(&obj);
        no_gprel(&obj);
        only_trax_undefined(&obj);
        let d = tool(
            "llvm-objdump",
            &["-d", "--mattr=+msa", obj.to_str().unwrap()],
        );
        let ops = trax_ops(&d);
        for want in [
            TraxOp::GlobalId,
            TraxOp::Rand,
            TraxOp::AtomicInc,
            TraxOp::FMin,
            TraxOp::Stat,
            TraxOp::TriTest,
            // `println!` with arguments: one formatted print.
            TraxOp::PrintFmt,
            TraxOp::Halt,
        ] {
            assert!(
                ops.contains(&want),
                "-O{opt}: missing {want:?} in {ops:?}\n{d}"
            );
        }
        assert!(
            d.contains("mtc2") && d.contains("mfc2"),
            "-O{opt}: cop2 moves\n{d}"
        );
        assert!(d.contains(".w\t$w"), "-O{opt}: no MSA instructions\n{d}");
        let r = tool("llvm-objdump", &["-r", obj.to_str().unwrap()]);
        assert!(
            r.contains("R_MIPS_HI16              __trax_scene_framebuffer"),
            "{r}"
        );
        assert!(
            r.contains("R_MIPS_LO16              __trax_scene_framebuffer"),
            "{r}"
        );
    }
}

#[test]
fn simd_example_uses_msa() {
    let out = scratch("msa-example");
    let k = crate_dir().join("../examples/mandelbrot_simd.rs");
    let obj = build_obj(&k, 2, &out);
    let d = tool(
        "llvm-objdump",
        &["-d", "--mattr=+msa", obj.to_str().unwrap()],
    );
    assert!(d.contains("fmul.w") && d.contains("fadd.w"), "{d}");
    assert!(trax_ops(&d).contains(&TraxOp::AtomicInc), "{d}");
}

#[test]
fn runtime_checks_abort_with_trax_abort() {
    let out = scratch("checks");
    let src = out.join("checks.rs");
    std::fs::write(
        &src,
        "fn get(a: [u32; 4], i: usize) -> u32 { a[i] }\n\
         fn div(a: i32, b: i32) -> i32 { a / b }\n\
         fn trax_main() {\n\
             let i = trax::global_id() as usize;\n\
             println!(\"{} {}\", get([1, 2, 3, 4], i), div(7, i as i32));\n\
             assert!(i < 100, \"too many\");\n\
             if i == 77 { panic!(\"boom\"); }\n\
             if i == 78 { unreachable!(); }\n\
         }\n",
    )
    .unwrap();
    let obj = build_obj(&src, 0, &out);
    let d = tool("llvm-objdump", &["-d", obj.to_str().unwrap()]);
    let aborts = trax_ops(&d).iter().filter(|o| **o == TraxOp::Abort).count();
    // bounds, divide by zero, overflow, assert, panic, unreachable
    assert!(aborts >= 6, "expected six abort sites, found {aborts}\n{d}");
    let rodata = tool("llvm-objdump", &["-s", obj.to_str().unwrap()]);
    assert!(
        rodata.contains("boom") && rodata.contains("too many"),
        "{rodata}"
    );
}
