//! Replays the fuzz targets' committed inputs on stable Rust: the seeds
//! (`fuzz/seeds/TARGET/`) and every input a fuzzer once failed on
//! (`fuzz/regressions/TARGET/`, named for what it caught). The targets' bodies are the
//! library functions called here; `.ci/fuzz` runs the fuzzers themselves (nightly).

use std::path::PathBuf;

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

/// Seeds kept elsewhere in the repository, by target: the sweep files of `experiments/`
/// seed `sweep_file` (`.ci/fuzz` passes the directory to the fuzzer too).
fn extra_seeds(target: &str) -> Vec<PathBuf> {
    if target != "sweep_file" {
        return Vec::new();
    }
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no sweep files in {}", dir.display());
    v
}

fn inputs(kind: &str, target: &str) -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz")
        .join(kind)
        .join(target);
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
