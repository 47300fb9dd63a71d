//! Bad input never crashes the compiler: truncated and token-mutated versions of a valid
//! kernel produce either an object or diagnostics, never a panic or an internal error.

mod common;

use common::*;
use trax_compiler::{compile_file, CompileError, CompileOptions};

fn check(src: &str, path: &std::path::Path, what: &str) {
    std::fs::write(path, src).expect("write");
    let opts = CompileOptions {
        opt_level: 0,
        ..Default::default()
    };
    let r = std::panic::catch_unwind(|| compile_file(path, &opts));
    match r {
        Err(_) => panic!("compiler panicked on {what}:\n{src}"),
        Ok(Err(CompileError::Internal(e))) => panic!("internal error on {what}: {e}\n{src}"),
        Ok(_) => {}
    }
}

#[test]
fn truncated_and_mutated_kernels_do_not_crash() {
    let dir = scratch("robust");
    let src =
        std::fs::read_to_string(crate_dir().join("tests/kernels/features.rs")).expect("kernel");
    std::fs::copy(
        crate_dir().join("tests/kernels/geometry.rs"),
        dir.join("geometry.rs"),
    )
    .expect("copy module");
    let path = dir.join("k.rs");
    // Cut the source at many points (on char boundaries).
    let cuts: Vec<usize> = (1..60).map(|i| src.len() * i / 60).collect();
    for c in cuts {
        let mut c = c;
        while !src.is_char_boundary(c) {
            c -= 1;
        }
        check(&src[..c], &path, &format!("prefix of {c} bytes"));
    }
    // Replace single tokens with others that change types and syntax.
    let swaps = [
        ("f32", "u8"),
        ("u32", "f64"),
        ("+", "&&"),
        ("let ", "let mut "),
        ("i32", "bool"),
        ("0", "0.5"),
        ("self", "Self"),
        ("&mut", "&"),
        ("==", "="),
        ("[", "("),
    ];
    for (from, to) in swaps {
        for (n, (i, _)) in src
            .match_indices(from)
            .enumerate()
            .filter(|(n, _)| n % 7 == 0)
        {
            let mutated = format!("{}{}{}", &src[..i], to, &src[i + from.len()..]);
            check(&mutated, &path, &format!("swap #{n} {from:?} -> {to:?}"));
        }
    }
}

/// `fn trax_main` whose body is `body`, compiled alone at -O0 on the compiler's own thread.
fn compile_body(body: &str) -> Result<trax_compiler::Output, CompileError> {
    let text = format!("fn trax_main() {{\n    let x = 3u32;\n{body}\n}}\n");
    let opts = CompileOptions::default();
    trax_compiler::compile_source("deep", &text, &opts)
}

/// Each kind of nesting compiles at the compiler's nesting limit (less the few levels of
/// the function around it); 10^6 levels, which overflowed the compiler thread's stack and
/// aborted the process, are refused with a diagnostic at the line where the limit is
/// passed.
#[test]
fn nesting_compiles_up_to_the_limit_and_deeper_is_refused() {
    let n = trax_compiler::parse::MAX_NESTING - 8;
    let kinds = [
        (
            "parentheses",
            format!("let y = {}x{};", "(".repeat(n), ")".repeat(n)),
        ),
        ("+ chain", format!("let y = x{};", " + 1".repeat(n))),
        ("unary !", format!("let y = {}x;", "!".repeat(n))),
        (
            "blocks",
            format!("let y = {}x{};", "{".repeat(n), "}".repeat(n)),
        ),
        (
            "method chain",
            format!("let y = x{};", ".wrapping_add(1)".repeat(n)),
        ),
        (
            "nested ifs",
            format!(
                "{}let y = x;{}",
                "if x < 9 {\n".repeat(n / 2),
                "}\n".repeat(n / 2)
            ),
        ),
        (
            "else-if chain",
            format!(
                "let y = if x < 1 {{ 0 }}{} else {{ 2 }};",
                " else if x < 2 { 1 }".repeat(n / 2)
            ),
        ),
    ];
    for (what, body) in &kinds {
        if let Err(e) = compile_body(body) {
            panic!("{what} at the limit: {e}");
        }
    }
    let deep = format!(
        "let y = {}x{};",
        "(".repeat(1_000_000),
        ")".repeat(1_000_000)
    );
    match compile_body(&deep) {
        Err(CompileError::Diagnostics(d)) => {
            let text = trax_compiler::render(&d);
            assert_eq!(d[0].id, "nesting-too-deep", "{text:.2000}");
            assert!(
                text.contains("lib.rs:3:") && text.contains("levels deep"),
                "{text:.2000}"
            );
        }
        r => panic!("10^6 parentheses: {:.2000}", format!("{r:?}")),
    }
}
