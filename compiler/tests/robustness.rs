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
