//! Golden diagnostics: every `tests/diagnostics/NAME.rs` must fail to compile with exactly
//! the text in `NAME.stderr`. Run with `TRAX_BLESS=1` to rewrite the expected files.

use std::path::Path;
use trax_compiler::{compile_file, CompileError, CompileOptions};

#[test]
fn golden_diagnostics() {
    let bless = std::env::var_os("TRAX_BLESS").is_some();
    // Paths are given relative to the crate so the rendered file names are stable.
    let dir = Path::new("tests/diagnostics");
    let mut cases: Vec<_> = std::fs::read_dir(dir)
        .expect("diagnostics dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    cases.sort();
    assert!(cases.len() >= 20, "expected the golden inputs");
    let mut failures = Vec::new();
    for case in &cases {
        let opts = CompileOptions {
            opt_level: 0,
            ..Default::default()
        };
        let got = match compile_file(case, &opts) {
            Ok(_) => format!("unexpected success for {}\n", case.display()),
            Err(e @ CompileError::Diagnostics(_)) => e.to_string(),
            Err(e @ CompileError::Internal(_)) => {
                format!("INTERNAL (exit {}): {e}\n", e.exit_code())
            }
        };
        let expected_path = case.with_extension("stderr");
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
        "{} golden mismatches (TRAX_BLESS=1 to update):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn every_diagnostic_has_an_id_and_location() {
    let dir = Path::new("tests/diagnostics");
    for e in std::fs::read_dir(dir).expect("dir") {
        let p = e.expect("entry").path();
        if p.extension().is_some_and(|x| x == "rs") {
            let Err(CompileError::Diagnostics(ds)) = compile_file(&p, &CompileOptions::default())
            else {
                panic!("{} must fail with diagnostics", p.display());
            };
            for d in ds {
                assert!(
                    !d.id.is_empty() && d.id.chars().all(|c| c.is_ascii_lowercase() || c == '-'),
                    "{}: id {:?}",
                    p.display(),
                    d.id
                );
                assert!(
                    d.loc.line >= 1 && d.loc.col >= 1,
                    "{}: location {:?}",
                    p.display(),
                    d.loc
                );
            }
        }
    }
}
