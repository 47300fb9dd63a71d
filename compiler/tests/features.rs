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

fn basetypes_kernel() -> std::path::PathBuf {
    crate_dir().join("tests/kernels/basetypes.rs")
}

/// `(name, encoding, byte size)` of every `DW_TAG_base_type` in llvm-dwarfdump's output.
fn base_types(info: &str) -> Vec<(String, String, u64)> {
    let mut out = Vec::new();
    let mut cur: Option<(String, String, u64)> = None;
    for line in info.lines() {
        let t = line.trim();
        if t.contains("DW_TAG_") {
            out.extend(cur.take());
            if t.ends_with("DW_TAG_base_type") {
                cur = Some((String::new(), String::new(), 0));
            }
            continue;
        }
        let Some(c) = cur.as_mut() else { continue };
        let value = |t: &str| {
            let a = t.find('(').map_or(t.len(), |i| i + 1);
            let b = t.rfind(')').unwrap_or(t.len());
            t[a.min(b)..b].trim_matches('"').to_string()
        };
        if t.starts_with("DW_AT_name") {
            c.0 = value(t);
        } else if t.starts_with("DW_AT_encoding") {
            c.1 = value(t);
        } else if t.starts_with("DW_AT_byte_size") {
            c.2 = u64::from_str_radix(value(t).trim_start_matches("0x"), 16).unwrap();
        }
    }
    out.extend(cur);
    out
}

/// Every scalar type has its own DWARF encoding and size (unsigned integers were once
/// `DW_ATE_unsigned_char`, which gdb prints as characters, truncating a `u64` to 32 bits).
#[test]
fn dwarf_base_types_have_their_encodings_and_sizes() {
    let out = scratch("basetypes");
    let want: &[(&str, &str, u64)] = &[
        ("u8", "DW_ATE_unsigned", 1),
        ("u16", "DW_ATE_unsigned", 2),
        ("u32", "DW_ATE_unsigned", 4),
        ("u64", "DW_ATE_unsigned", 8),
        ("usize", "DW_ATE_unsigned", 4),
        ("i8", "DW_ATE_signed", 1),
        ("i16", "DW_ATE_signed", 2),
        ("i32", "DW_ATE_signed", 4),
        ("i64", "DW_ATE_signed", 8),
        ("isize", "DW_ATE_signed", 4),
        ("f32", "DW_ATE_float", 4),
        ("f64", "DW_ATE_float", 8),
        ("bool", "DW_ATE_boolean", 1),
        ("char", "DW_ATE_UTF", 4),
    ];
    for opt in [0, 2] {
        let obj = build_obj(&basetypes_kernel(), opt, &out);
        verify_dwarf(&obj);
        let info = tool("llvm-dwarfdump", &["--debug-info", obj.to_str().unwrap()]);
        let found = base_types(&info);
        for (name, enc, size) in want {
            if opt > 0 && !found.iter().any(|f| f.0 == *name) {
                continue; // optimised away
            }
            let got: Vec<_> = found.iter().filter(|f| f.0 == *name).collect();
            assert_eq!(got.len(), 1, "-O{opt}: base type {name}: {found:?}");
            assert_eq!(
                (got[0].1.as_str(), got[0].2),
                (*enc, *size),
                "-O{opt}: base type {name}"
            );
        }
        for f in &found {
            assert!(
                want.iter().any(|w| w.0 == f.0),
                "-O{opt}: unexpected base type {f:?}"
            );
        }
        if opt == 0 {
            assert_eq!(found.len(), want.len(), "{found:?}");
        }
    }
}

/// At -O0 each function's `prologue_end` row is its first body statement, after the
/// parameters are stored to their stack slots: `break FUNC` in a debugger stops there
/// and sees the arguments (it stopped on the signature line, before the stores, before).
#[test]
fn prologue_end_is_the_first_body_statement_at_o0() {
    let out = scratch("basetypes-prologue");
    let obj = build_obj(&basetypes_kernel(), 0, &out);
    let src = std::fs::read_to_string(basetypes_kernel()).unwrap();
    let line_of = |pat: &str| {
        src.lines()
            .position(|l| l.contains(pat))
            .unwrap_or_else(|| panic!("{pat}")) as u64
            + 1
    };
    let lines = tool("llvm-dwarfdump", &["--debug-line", obj.to_str().unwrap()]);
    let ends: Vec<u64> = lines
        .lines()
        .filter(|l| l.starts_with("0x") && l.contains("prologue_end"))
        .map(|l| l.split_whitespace().nth(1).unwrap().parse().unwrap())
        .collect();
    let want = [line_of("// BODY"), line_of("let v8: u8")];
    assert_eq!(ends.len(), 2, "one prologue_end per function:\n{lines}");
    for w in want {
        assert!(ends.contains(&w), "no prologue_end at line {w}:\n{lines}");
    }
}

/// The language suite's kernels (enums, traits, generics, slices, format records) compile
/// at -O0 and -O2 to objects with valid DWARF, no `$gp`-relative data and no libc calls.
#[test]
fn language_suite_objects_are_valid() {
    let out = scratch("lang-suite");
    for k in [
        "lang_enums",
        "lang_traits",
        "lang_slices",
        "lang_format",
        "lang_math",
        "lang_closures",
        "lang_libm",
    ] {
        let path = crate_dir().join(format!("tests/kernels/{k}.rs"));
        for opt in [0, 2] {
            let obj = build_obj(&path, opt, &out);
            verify_dwarf(&obj);
            no_gprel(&obj);
            only_trax_undefined(&obj);
        }
    }
}

/// With the prelude, Rust's float methods that `trax::libm` provides compile to calls of
/// it, and one it lacks (`sinh`) is an error naming the method at its span.
#[test]
fn float_methods_outside_the_math_library_are_named() {
    let dir = scratch("libm-methods");
    let path = dir.join("sinh.rs");
    std::fs::write(
        &path,
        "fn trax_main() {\n    let a = trax::global_read(0) as f32;\n    trax::global_write(1, (a.sin() + a.sinh()) as u32);\n}\n",
    )
    .unwrap();
    let opts = trax_compiler::CompileOptions {
        opt_level: 0,
        emit: Emit::Obj,
        prelude: Some(trax_compiler::Prelude::runtime()),
    };
    let err = match trax_compiler::compile_file(&path, &opts) {
        Ok(_) => panic!("sinh is not in trax::libm"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("error[unsupported-float-method]: `f32::sinh` is not supported in TRaX-Rust: the prelude's math library has no `trax::libm::sinhf`"),
        "{err}"
    );
    assert!(err.contains("sinh.rs:3:"), "{err}");
    assert!(!err.contains("`f32::sin`"), "{err}");
}
