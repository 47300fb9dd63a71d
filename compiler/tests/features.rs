//! The all-features kernel compiles at every level, with valid DWARF that describes
//! locals (at -O0) and inlined calls (at -O2).

mod common;

use common::*;
use trax_compiler::Emit;

fn kernel() -> std::path::PathBuf {
    crate_dir().join("tests/kernels/features.rs")
}

#[test]
fn features_kernel_compiles_at_all_levels() {
    let out = scratch("features");
    for opt in 0..=3 {
        let obj = build_obj(&kernel(), opt, &out);
        verify_dwarf(&obj);
        no_gprel(&obj);
        only_trax_undefined(&obj);
    }
}

#[test]
fn dwarf_describes_locals_and_types_at_o0() {
    let out = scratch("features-dwarf0");
    let obj = build_obj(&kernel(), 0, &out);
    let info = tool("llvm-dwarfdump", &["--debug-info", obj.to_str().unwrap()]);
    for needle in [
        "DW_TAG_variable",
        "DW_TAG_formal_parameter",
        "DW_TAG_lexical_block",
        "DW_TAG_structure_type",
        "DW_TAG_array_type",
        "DW_TAG_pointer_type",
        "\"Vec3::dot\"",
        "\"Counter::record\"",
        "\"trax_main\"",
        "\"cnt\"",
        "\"tri\"",
    ] {
        assert!(
            info.contains(needle),
            "missing {needle} in DWARF:\n{}",
            &info[..info.len().min(4000)]
        );
    }
    // Columns are 1-based: the line table has a row at the `fib(n - 1)` call.
    let lines = tool("llvm-dwarfdump", &["--debug-line", obj.to_str().unwrap()]);
    assert!(lines.contains("features.rs"), "line table names the file");
    let src = std::fs::read_to_string(kernel()).unwrap();
    let (ln, text) = src
        .lines()
        .enumerate()
        .find(|(_, l)| l.contains("fib(n - 1) + fib(n - 2)"))
        .expect("fib line");
    let col = text.find("fib(n - 1)").unwrap() + 1;
    let want = (ln as u32 + 1, col as u32);
    let found = lines.lines().filter(|l| l.starts_with("0x")).any(|l| {
        let f: Vec<&str> = l.split_whitespace().collect();
        f.len() > 2
            && f[1].parse::<u32>().ok() == Some(want.0)
            && f[2].parse::<u32>().ok() == Some(want.1)
    });
    assert!(
        found,
        "no line-table row at line {} column {}:\n{lines}",
        want.0, want.1
    );
}

#[test]
fn dwarf_has_inlined_subroutines_at_o2() {
    let out = scratch("features-dwarf2");
    let obj = build_obj(&kernel(), 2, &out);
    let info = tool("llvm-dwarfdump", &["--debug-info", obj.to_str().unwrap()]);
    assert!(
        info.contains("DW_TAG_inlined_subroutine"),
        "no inlined subroutine records at -O2"
    );
    // `classify` is `#[inline(never)]`: it stays a real function.
    let syms = tool("llvm-objdump", &["-t", obj.to_str().unwrap()]);
    assert!(syms.contains("classify"), "{syms}");
}

#[test]
fn only_reachable_functions_are_emitted() {
    let ir = String::from_utf8(build(&kernel(), 0, Emit::LlvmIr)).unwrap();
    let main_def = ir
        .lines()
        .find(|l| l.starts_with("define") && l.contains("@trax_main()"))
        .expect("trax_main defined");
    assert!(
        !main_def.contains("internal"),
        "trax_main must be external: {main_def}"
    );
    assert!(
        ir.contains("define internal i32 @\"features::fib\""),
        "other functions are internal with readable names"
    );
    // The prelude's scene accessors are not used by this kernel.
    assert!(
        !ir.contains("hdr_width"),
        "unreachable prelude function emitted"
    );
    assert!(!ir.contains("__trax_scene_"), "unreferenced scene symbol");
}

#[test]
fn emits_assembly_and_ir() {
    let asm = String::from_utf8(build(&kernel(), 2, Emit::Asm)).unwrap();
    assert!(asm.contains("trax_main:"), "{asm}");
    let ir = String::from_utf8(build(&kernel(), 2, Emit::LlvmIr)).unwrap();
    assert!(ir.contains("mipsel"), "{ir}");
}
