//! Every example of `docs/LANGUAGE.md` is a test. A fenced ```` ```rust ```` block is a
//! whole kernel: it is built and run on the emulator (functional mode, one thread, the
//! default scene) and with `trax native`, and both must print the same text — the
//! ```` ```text ```` block that follows it, when there is one. A block marked
//! ```` ```rust,refused=CODE ```` must be refused with `error[CODE]` (rustc's code or
//! the trax compiler's id); ```` ```rust,panics=MESSAGE ```` must stop with that panic
//! message on both sides.

use std::path::Path;
use std::process::Output;

mod common;
use common::{native_cache, root, text, tmp_path, trax_command};

fn trax(args: &[&str]) -> Output {
    trax_command()
        .args(args)
        .env("TRAX_CACHE_DIR", native_cache())
        .env_remove("TRAX_RUSTC_CHECK")
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("run trax")
}

/// What a block must do.
#[derive(Debug)]
enum Expect {
    /// Run on both sides; print this (when given).
    Run(Option<String>),
    /// Be refused with this code or id.
    Refused(String),
    /// Stop with this panic message on both sides.
    Panics(String),
}

/// One example: its line in the document, source and expectation.
#[derive(Debug)]
struct Example {
    line: usize,
    src: String,
    expect: Expect,
}

/// The examples of `doc`, in order.
fn examples(doc: &str) -> Vec<Example> {
    let lines: Vec<&str> = doc.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    // The fenced block starting at `i` (its info string and body) and the line after it.
    let block = |i: usize| -> (String, String, usize) {
        let info = lines[i].trim_start_matches("```").trim().to_string();
        let mut j = i + 1;
        let mut body = String::new();
        while j < lines.len() && lines[j].trim_end() != "```" {
            body.push_str(lines[j]);
            body.push('\n');
            j += 1;
        }
        assert!(j < lines.len(), "LANGUAGE.md:{}: unclosed block", i + 1);
        (info, body, j + 1)
    };
    while i < lines.len() {
        if !lines[i].starts_with("```rust") {
            i += 1;
            continue;
        }
        let (info, src, next) = block(i);
        let line = i + 1;
        i = next;
        let expect = if let Some(code) = info.strip_prefix("rust,refused=") {
            Expect::Refused(code.to_string())
        } else if let Some(msg) = info.strip_prefix("rust,panics=") {
            Expect::Panics(msg.to_string())
        } else {
            assert_eq!(info, "rust", "LANGUAGE.md:{line}: unknown block kind");
            // The expected output: a `text` block after blank lines.
            let mut k = i;
            while k < lines.len() && lines[k].trim().is_empty() {
                k += 1;
            }
            if k < lines.len() && lines[k].trim_end() == "```text" {
                let (_, out, next) = block(k);
                i = next;
                Expect::Run(Some(out))
            } else {
                Expect::Run(None)
            }
        };
        out.push(Example { line, src, expect });
    }
    out
}

/// Checks one example; the failure text, if it fails.
fn check(dir: &Path, ex: &Example) -> Option<String> {
    let path = dir.join(format!("line{}.rs", ex.line));
    std::fs::write(&path, &ex.src).unwrap();
    let k = path.to_str().unwrap();
    let at = format!("LANGUAGE.md:{}", ex.line);
    let one = ["--tms", "1", "--threads", "1"];
    match &ex.expect {
        Expect::Refused(code) => {
            let out = trax(&["build", k, "-o", "/dev/null"]);
            let err = text(&out.stderr);
            if out.status.code() != Some(1) || !err.contains(&format!("error[{code}]")) {
                return Some(format!("{at}: expected error[{code}], got:\n{err}"));
            }
        }
        Expect::Run(expected) => {
            let emu = trax(&[&["run", k, "--functional"][..], &one].concat());
            let nat = trax(&[&["native", k][..], &one].concat());
            for (what, o) in [("trax run", &emu), ("trax native", &nat)] {
                if !o.status.success() {
                    return Some(format!("{at}: {what} failed:\n{}", text(&o.stderr)));
                }
            }
            let (e, n) = (text(&emu.stdout), text(&nat.stdout));
            if e != n {
                return Some(format!("{at}: machine printed\n{e}natively\n{n}"));
            }
            if let Some(x) = expected {
                if e != *x {
                    return Some(format!("{at}: printed\n{e}the document says\n{x}"));
                }
            }
        }
        Expect::Panics(msg) => {
            let emu = trax(&[&["run", k, "--functional"][..], &one].concat());
            let nat = trax(&[&["native", k][..], &one].concat());
            for (what, o) in [("trax run", &emu), ("trax native", &nat)] {
                let err = text(&o.stderr);
                if o.status.success() || !err.contains(msg.as_str()) {
                    return Some(format!("{at}: {what}: expected the panic {msg:?}:\n{err}"));
                }
            }
        }
    }
    None
}

#[test]
fn every_example_of_the_language_document_runs_as_it_says() {
    let doc = std::fs::read_to_string(root().join("docs/LANGUAGE.md")).unwrap();
    let exs = examples(&doc);
    assert!(exs.len() >= 20, "{} examples", exs.len());
    assert!(exs.iter().any(|e| matches!(e.expect, Expect::Refused(_))));
    let dir = tmp_path("language-doc");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Two host threads: each example is a few processes.
    let half = exs.len().div_ceil(2);
    let failures: Vec<String> = std::thread::scope(|s| {
        let parts: Vec<_> = exs
            .chunks(half)
            .map(|part| {
                let dir = &dir;
                s.spawn(move || {
                    part.iter()
                        .filter_map(|e| check(dir, e))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        parts.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The extraction itself: kinds, expected output, line numbers.
#[test]
fn examples_are_extracted_with_their_expectations() {
    let doc = "# t\n\n```rust\nfn trax_main() {}\n```\n\n```text\nhi\n```\n\n```rust,refused=E0382\nx\n```\n```rust,panics=boom\ny\n```\n```rust\nz\n```\n";
    let e = examples(doc);
    assert_eq!(e.len(), 4);
    assert!(matches!(&e[0].expect, Expect::Run(Some(o)) if o == "hi\n"));
    assert_eq!(e[0].line, 3);
    assert!(matches!(&e[1].expect, Expect::Refused(c) if c == "E0382"));
    assert!(matches!(&e[2].expect, Expect::Panics(m) if m == "boom"));
    assert!(matches!(&e[3].expect, Expect::Run(None)));
}
