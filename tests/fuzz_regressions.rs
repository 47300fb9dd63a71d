//! Replays the fuzz targets' committed inputs on stable Rust: the seeds
//! (`fuzz/seeds/TARGET/`, and the files elsewhere that seed a target: [`extra_seeds`])
//! and every input a fuzzer once failed on
//! (`fuzz/regressions/TARGET/`, named for what it caught). The targets' bodies are the
//! library functions called here; `.ci/fuzz` runs the fuzzers themselves (nightly).

use std::path::PathBuf;

mod common;
use common::root;

type Body = fn(&[u8]);

const TARGETS: [(&str, Body); 8] = [
    ("decode", trax_emulator::fuzzing::decode_words),
    ("elf", trax_emulator::fuzzing::elf),
    ("chip_toml", trax_emulator::fuzzing::chip_toml),
    ("link", trax_assembler::fuzzing::link),
    ("obj", trax_assembler::fuzzing::obj),
    ("view", trax_assembler::fuzzing::view),
    ("kernel", trax_compiler::fuzzing::kernel),
    ("sweep_file", trax::fuzzing::sweep_file),
];

/// Seeds kept elsewhere in the repository, by target (`.ci/fuzz` passes the same files to
/// the fuzzer): the sweep files of `experiments/` seed `sweep_file`; the examples and the
/// compiler's test kernels seed `kernel`.
fn extra_seeds(target: &str) -> Vec<PathBuf> {
    let (dirs, ext): (&[&str], &str) = match target {
        "sweep_file" => (&["experiments"], "toml"),
        "kernel" => (&["examples", "compiler/tests/kernels"], "rs"),
        _ => return Vec::new(),
    };
    let mut v = Vec::new();
    for d in dirs {
        let dir = root().join(d);
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == ext))
            .collect();
        assert!(!files.is_empty(), "no .{ext} seeds in {}", dir.display());
        files.sort();
        v.extend(files);
    }
    v
}

fn inputs(kind: &str, target: &str) -> Vec<PathBuf> {
    let dir = root().join("fuzz").join(kind).join(target);
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && !p.file_name().unwrap().to_string_lossy().starts_with('.'))
        .collect();
    v.sort();
    v
}

fn replay(kind: &str) -> usize {
    let mut n = 0;
    for (target, body) in TARGETS {
        let extra = if kind == "seeds" {
            extra_seeds(target)
        } else {
            Vec::new()
        };
        for path in inputs(kind, target).into_iter().chain(extra) {
            let data = std::fs::read(&path).unwrap();
            let r = std::panic::catch_unwind(|| body(&data));
            assert!(
                r.is_ok(),
                "fuzz target {target} panicked on {}",
                path.display()
            );
            n += 1;
        }
    }
    n
}

#[test]
fn fuzz_seeds_run_clean() {
    assert!(replay("seeds") >= TARGETS.len(), "every target has a seed");
}

#[test]
fn fuzz_regressions_run_clean() {
    replay("regressions");
}
