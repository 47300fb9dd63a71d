//! Per-construct IR snapshots: every `tests/ir/NAME.rs` is compiled at -O0 (the lowering's
//! own output) and its kernel functions' LLVM IR, without debug metadata, must equal
//! `tests/ir/NAME.ll`. Run with `TRAX_BLESS=1` to rewrite the expected files after an
//! intended change of the lowering (and review the diff).

use std::path::Path;
use trax_compiler::{compile_file, CompileOptions, Emit, Prelude};

/// The kernel's own function definitions (`define` ... `}`), with debug locations,
/// metadata attachments and attribute-group references removed.
fn kernel_functions(ir: &str, kernel: &str) -> String {
    let mut out = String::new();
    let mut keep = false;
    for line in ir.lines() {
        if line.starts_with("define ") {
            keep = line.contains(&format!("@\"{kernel}::")) || line.contains("@trax_main(");
        }
        if !keep {
            continue;
        }
        if line.trim_start().starts_with("call void @llvm.dbg.") {
            continue;
        }
        let mut l = line.to_string();
        // `, !dbg !12`, `!srcloc !3` and friends.
        while let Some(i) = l.find(", !") {
            let rest = &l[i + 3..];
            let end = rest.find([',', '\n']).map(|j| i + 3 + j).unwrap_or(l.len());
            l.replace_range(i..end, "");
        }
        // Attribute groups `#3` and metadata on `define` lines.
        if l.starts_with("define ") {
            let cut = l.find(" #").or_else(|| l.find(" !dbg"));
            if let Some(c) = cut {
                l = format!("{} {{", &l[..c]);
            }
        }
        out.push_str(l.trim_end());
        out.push('\n');
        if line == "}" {
            keep = false;
            out.push('\n');
        }
    }
    out
}

#[test]
fn ir_snapshots() {
    let bless = std::env::var_os("TRAX_BLESS").is_some();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ir");
    let mut cases: Vec<_> = std::fs::read_dir(&dir)
        .expect("ir dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    cases.sort();
    assert!(cases.len() >= 7, "expected the IR inputs");
    let mut failures = Vec::new();
    for case in &cases {
        let opts = CompileOptions {
            opt_level: 0,
            emit: Emit::LlvmIr,
            prelude: Some(Prelude::runtime()),
        };
        let out = compile_file(case, &opts).unwrap_or_else(|e| panic!("{}: {e}", case.display()));
        let ir = String::from_utf8(out.bytes).unwrap();
        let stem = case.file_stem().unwrap().to_string_lossy().into_owned();
        let got = kernel_functions(&ir, &stem);
        assert!(
            got.contains("define"),
            "{}: no kernel functions in\n{ir}",
            case.display()
        );
        let expected_path = case.with_extension("ll");
        if bless {
            std::fs::write(&expected_path, &got).expect("write expected");
            continue;
        }
        let expected = std::fs::read_to_string(&expected_path).unwrap_or_default();
        if got != expected {
            failures.push(format!(
                "--- {}\nexpected:\n{expected}\ngot:\n{got}",
                case.display()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} IR snapshot mismatches (TRAX_BLESS=1 to update):\n{}",
        failures.len(),
        failures.join("\n")
    );
}
