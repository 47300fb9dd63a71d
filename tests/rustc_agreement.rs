//! trax accepts only what rustc accepts (`trax::native::check`): every kernel of
//! `tests/rustc_agreement/` is invalid Rust (moves, borrows, initialisation,
//! exhaustiveness, `unsafe`, types, privacy, ...) and must be refused with rustc's error
//! code at the line marked `//~ CODE`; every example and test kernel must still be
//! accepted; the check's cache follows the kernel's files; a missing rustc behaves as
//! documented.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use trax::native::check::{self, RustcCheck, Verdict};
use trax::pipeline::{compile_object_checked, PrepareError};
use trax_compiler::{CompileError, Emit};

mod common;
use common::{fresh_dir, root, text, tmp_path, trax_command};

fn scratch(name: &str) -> PathBuf {
    fresh_dir(&format!("rustc-agreement-{name}"))
}

fn trax(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = trax_command();
    c.args(args)
        .env("TRAX_CACHE_DIR", scratch_cache())
        .env_remove("TRAX_RUSTC_CHECK");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run trax")
}

/// A build cache for the CLI runs of this test (kept between runs: keyed by content).
fn scratch_cache() -> PathBuf {
    tmp_path("rustc-agreement-cache")
}

/// The `.rs` files of `dir`, relative to the checkout (the tests' working directory, so
/// paths read as a user's would), sorted.
fn rust_files(dir: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .map(|p| p.strip_prefix(root()).unwrap().to_path_buf())
        .collect();
    v.sort();
    v
}

/// The expected error of a corpus kernel: (code, line) of its `//~ CODE` marker.
fn expected(path: &Path) -> (String, u32) {
    let src = std::fs::read_to_string(root().join(path)).unwrap();
    let mut found = src.lines().enumerate().filter_map(|(i, l)| {
        l.split_once("//~ ")
            .map(|(_, c)| (c.trim().to_string(), i as u32 + 1))
    });
    let first = found
        .next()
        .unwrap_or_else(|| panic!("{}: no //~ marker", path.display()));
    assert!(found.next().is_none(), "{}: one marker", path.display());
    first
}

/// rustc's verdicts on `kernels`, checked on two host threads.
fn verdicts(kernels: &[PathBuf]) -> Vec<Result<Verdict, check::CheckError>> {
    let half = kernels.len().div_ceil(2);
    std::thread::scope(|s| {
        let parts: Vec<_> = kernels
            .chunks(half.max(1))
            .map(|part| {
                s.spawn(move || {
                    part.iter()
                        .map(|k| check::start(k, RustcCheck::Require).and_then(|p| p.finish()))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        parts.into_iter().flat_map(|h| h.join().unwrap()).collect()
    })
}

#[test]
fn every_rustc_rejected_kernel_is_rejected_with_its_code_and_line() {
    let corpus = rust_files("tests/rustc_agreement");
    assert!(corpus.len() >= 40, "{} kernels", corpus.len());
    let mut codes: Vec<String> = Vec::new();
    let mut failures = Vec::new();
    for (k, verdict) in corpus.iter().zip(verdicts(&corpus)) {
        let (code, line) = expected(k);
        codes.push(code.clone());
        let ds = match verdict {
            Ok(Verdict::Rejected(ds)) => ds,
            other => {
                failures.push(format!("{}: {other:?}", k.display()));
                continue;
            }
        };
        let hit = ds.iter().any(|d| {
            d.extra.code.as_deref() == Some(code.as_str()) && d.loc.line == line && d.file == *k
        });
        if !hit {
            let got: Vec<String> = ds
                .iter()
                .map(|d| format!("{}@{}:{}", d.code_or_id(), d.file.display(), d.loc.line))
                .collect();
            failures.push(format!(
                "{}: expected {code} at line {line}, got {got:?}",
                k.display()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    codes.sort();
    codes.dedup();
    for c in [
        "E0382", "E0499", "E0502", "E0505", "E0506", "E0384", "E0004", "E0005", "E0308", "E0133",
        "E0596", "E0597", "E0716", "E0381", "E0503",
    ] {
        assert!(codes.iter().any(|x| x == c), "no kernel for {c}");
    }
}

/// The pipeline's rule: when rustc rejects a kernel, rustc's errors are the errors,
/// also where the trax compiler alone would have refused it differently (here its
/// `type-mismatch`) or accepted it (the borrow error).
#[test]
fn rustc_errors_win_in_the_pipeline() {
    for (k, code) in [
        ("tests/rustc_agreement/e0308_let_type.rs", "E0308"),
        ("tests/rustc_agreement/e0506_assign_borrowed.rs", "E0506"),
    ] {
        match compile_object_checked(Path::new(k), 0, Emit::Obj, RustcCheck::Require) {
            Err(PrepareError::Compile(CompileError::Diagnostics(ds))) => {
                assert_eq!(ds.len(), 1, "{k}");
                assert_eq!(ds[0].extra.code.as_deref(), Some(code), "{k}");
            }
            other => panic!("{k}: {:?}", other.map(|_| ())),
        }
        // Without rustc's check the trax compiler decides alone.
        let alone = compile_object_checked(Path::new(k), 0, Emit::Obj, RustcCheck::Off);
        match code {
            "E0308" => assert!(
                matches!(&alone, Err(PrepareError::Compile(CompileError::Diagnostics(ds))) if ds[0].id == "type-mismatch"),
                "{k}"
            ),
            _ => assert!(alone.is_ok(), "{k}: the gap this check closes"),
        }
    }
}

/// The kernels trax itself builds and runs (examples, the end-to-end kernels, the
/// compiler's language suite) are Rust that rustc accepts. The one exception is the
/// compiler's test of the machine-side intrinsics the prelude is written with
/// (`__trax_op!` & co.), which only the trax compiler knows.
#[test]
fn every_example_and_test_kernel_is_accepted_by_rustc() {
    let mut kernels = rust_files("examples");
    kernels.extend(rust_files("tests/kernels"));
    kernels.extend(
        rust_files("compiler/tests/kernels")
            .into_iter()
            .filter(|k| !k.ends_with("intrinsics.rs")),
    );
    assert!(kernels.len() >= 25, "{kernels:?}");
    let mut failures = Vec::new();
    for (k, verdict) in kernels.iter().zip(verdicts(&kernels)) {
        match verdict {
            Ok(Verdict::Accepted) => {}
            Ok(Verdict::Rejected(ds)) => {
                failures.push(format!("{}:\n{}", k.display(), trax_compiler::render(&ds)))
            }
            other => failures.push(format!("{}: {other:?}", k.display())),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The exception is real: rustc refuses it, with a hint at the prelude's API.
    let intrinsics = Path::new("compiler/tests/kernels/intrinsics.rs");
    let v = check::start(intrinsics, RustcCheck::Require).and_then(|p| p.finish());
    let Ok(Verdict::Rejected(ds)) = v else {
        panic!("intrinsics.rs: {v:?}")
    };
    assert!(ds[0].to_string().contains("trax::stat::add"), "{}", ds[0]);
}

/// The CLI renders rustc's errors as trax's own (`error[CODE]`, `file:line:col`, the
/// source line and carets), exit status 1; a kernel rustc accepts but the subset lacks
/// gets the trax compiler's diagnostic.
#[test]
fn the_cli_renders_rustc_errors_like_its_own() {
    let out = trax(
        &[
            "build",
            "tests/rustc_agreement/e0506_assign_borrowed.rs",
            "-o",
            "/dev/null",
        ],
        &[],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.starts_with("error[E0506]: cannot assign to `v[_]` because it is borrowed\n"),
        "{err}"
    );
    assert!(
        err.contains("--> tests/rustc_agreement/e0506_assign_borrowed.rs:5:5\n"),
        "{err}"
    );
    assert!(err.contains("5 |     v[0] = 5; //~ E0506\n"), "{err}");
    assert!(
        err.contains("|     ^^^^^^^^ `v[_]` is assigned to here"),
        "{err}"
    );
    assert!(err.contains("- `v[_]` is borrowed here"), "{err}");
    assert!(
        err.ends_with("error: could not compile due to 1 previous error\n"),
        "{err}"
    );

    // Valid Rust outside the subset: the trax compiler says what it lacks.
    let dir = scratch("subset");
    let k = dir.join("heap.rs");
    std::fs::write(
        &k,
        "fn trax_main() {\n    let v: Vec<u32> = Vec::new();\n    println!(\"{}\", v.len());\n}\n",
    )
    .unwrap();
    let out = trax(&["build", k.to_str().unwrap(), "-o", "/dev/null"], &[]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.starts_with("error[unsupported-"), "{err}");
    assert!(!err.contains("error[E"), "{err}");
}

/// Without rustc, `auto` (the default) warns once and builds with the trax compiler's
/// own checks; `require` refuses; a bad setting names the variable; `off` builds the
/// corpus's borrow error as before.
#[test]
fn a_missing_rustc_is_a_warning_or_an_error_as_chosen() {
    let hello = "examples/hello.rs";
    let no_rustc = [("RUSTC", "/nonexistent/rustc")];
    let out = trax(&["build", hello, "-o", "/dev/null"], &no_rustc);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("warning: cannot run `/nonexistent/rustc`"),
        "{err}"
    );
    assert_eq!(err.matches("warning:").count(), 1, "{err}");
    assert!(err.contains("TRAX_RUSTC_CHECK=off"), "{err}");

    let out = trax(
        &["build", hello, "-o", "/dev/null"],
        &[no_rustc[0], ("TRAX_RUSTC_CHECK", "require")],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("examples/hello.rs: TRAX_RUSTC_CHECK=require, but rustc cannot be run"),
        "{err}"
    );

    let out = trax(
        &["build", hello, "-o", "/dev/null"],
        &[("TRAX_RUSTC_CHECK", "sometimes")],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("TRAX_RUSTC_CHECK=\"sometimes\": expected"),
        "{}",
        text(&out.stderr)
    );

    let bad = "tests/rustc_agreement/e0506_assign_borrowed.rs";
    let out = trax(
        &["build", bad, "-o", "/dev/null"],
        &[("TRAX_RUSTC_CHECK", "off")],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// A kernel rustc accepted is not checked again until one of its files changes (a
/// `mod` file too); rustc's runs are counted by a wrapper.
#[test]
fn the_check_is_cached_by_the_content_of_every_file_rustc_read() {
    let dir = scratch("cache");
    let log = dir.join("rustc.log");
    let wrapper = dir.join("rustc");
    let real = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/sh\necho \"$@\" >> '{}'\nexec '{real}' \"$@\"\n",
            log.display()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();
    let k = dir.join("k.rs");
    std::fs::write(
        &k,
        "mod m;\n\nfn trax_main() {\n    println!(\"{}\", m::f());\n}\n",
    )
    .unwrap();
    std::fs::write(dir.join("m.rs"), "pub fn f() -> u32 {\n    1\n}\n").unwrap();
    let cache = dir.join("cache");
    let build = || {
        let out = Command::new(env!("CARGO_BIN_EXE_trax"))
            .args(["build", k.to_str().unwrap(), "-o", "/dev/null"])
            .env("RUSTC", &wrapper)
            .env("TRAX_CACHE_DIR", &cache)
            .env_remove("TRAX_RUSTC_CHECK")
            .output()
            .unwrap();
        let checks = std::fs::read_to_string(&log)
            .unwrap_or_default()
            .lines()
            .filter(|l| l.contains("trax_kernel"))
            .count();
        (out, checks)
    };
    let (out, checks) = build();
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(checks, 1);
    let (_, checks) = build();
    assert_eq!(checks, 1, "unchanged: no second check");
    // A borrow error in the module file: checked again, refused.
    std::fs::write(
        dir.join("m.rs"),
        "pub fn f() -> u32 {\n    let mut a = 1;\n    let r = &a;\n    a = 2;\n    *r + a\n}\n",
    )
    .unwrap();
    let (out, checks) = build();
    assert_eq!(checks, 2);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(err.starts_with("error[E0506]"), "{err}");
    assert!(err.contains("m.rs:4:5"), "{err}");
}
