//! Structural invariants of `docs/ARCHITECTURE.md` that no behaviour test would notice
//! breaking: which crate links what, where files are read, and that programs are prepared
//! and run one way.

use std::path::{Path, PathBuf};

mod common;
use common::root;

/// Every `.rs` file under `dir` (relative to the workspace root), with its text.
fn sources(dir: &str) -> Vec<(String, String)> {
    fn walk(p: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(p).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(&root().join(dir), &mut files);
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(root()).unwrap().display().to_string();
            (rel, std::fs::read_to_string(&p).unwrap())
        })
        .collect()
}

/// The `[dependencies]` and `[dev-dependencies]` names of a crate's manifest.
fn dependencies(manifest: &str) -> Vec<String> {
    let text = std::fs::read_to_string(root().join(manifest)).unwrap();
    let doc: toml::Table = toml::from_str(&text).unwrap();
    ["dependencies", "dev-dependencies"]
        .iter()
        .filter_map(|s| doc.get(*s).and_then(|d| d.as_table()))
        .flat_map(|t| t.keys().cloned())
        .collect()
}

const MANIFESTS: [&str; 5] = [
    "Cargo.toml",
    "compiler/Cargo.toml",
    "assembler/Cargo.toml",
    "emulator/Cargo.toml",
    "runtime/Cargo.toml",
];

#[test]
fn only_the_compiler_links_llvm_and_object_is_the_one_elf_library() {
    for m in MANIFESTS {
        let deps = dependencies(m);
        let llvm = deps
            .iter()
            .any(|d| d == "inkwell" || d.starts_with("llvm-sys"));
        assert_eq!(llvm, m == "compiler/Cargo.toml", "{m} and LLVM: {deps:?}");
        for other in ["goblin", "elf", "xmas-elf", "elf_rs", "elf-utilities"] {
            assert!(!deps.iter().any(|d| d == other), "{m} uses {other}");
        }
    }
}

#[test]
fn the_emulator_reads_files_only_for_configs_and_source_lines() {
    // The execution core writes output to the caller's writer and reads nothing; the chip
    // config loader reads TOML files, crash reports and the profiler read source lines.
    let allowed = ["emulator/src/timing/config.rs", "emulator/src/debuginfo.rs"];
    for (file, text) in sources("emulator/src") {
        if allowed.contains(&file.as_str()) {
            continue;
        }
        for pat in ["std::fs", "File::open", "File::create", "OpenOptions"] {
            assert!(!text.contains(pat), "{file} does file I/O ({pat})");
        }
    }
}

#[test]
fn programs_are_prepared_and_run_one_way() {
    // Compiling, linking and laying out memory happen in `trax::pipeline`; the root crate's
    // CLI, tests and benchmarks run programs through `trax_emulator::run`.
    let stages = [
        "compile_file(",
        "build_image(",
        "build_image_from_symbols(",
        "link(&",
        "Machine::new(",
    ];
    let mut files = sources("src");
    files.extend(sources("tests"));
    files.extend(sources("benches"));
    for (file, text) in files {
        if file == "src/pipeline.rs" || file == "tests/architecture.rs" {
            continue;
        }
        for s in stages {
            assert!(
                !text.contains(s),
                "{file} calls {s}..) itself: use trax::pipeline"
            );
        }
    }
}

#[test]
fn one_executable_reader_one_memory_image_type_one_scene_contract() {
    // Executables are read only by `trax_runtime::exe::Executable::parse` (the emulator's
    // debug-info index parses the ELF for its DWARF sections only); memory images have one
    // type, `trax_runtime::image::{MemoryImage, Segment}`; the scene contract's symbol
    // prefix is defined once, in `trax_runtime::abi`.
    let mut files = Vec::new();
    for dir in [
        "src",
        "compiler/src",
        "assembler/src",
        "emulator/src",
        "runtime/src",
    ] {
        files.extend(sources(dir));
    }
    for (file, text) in &files {
        let reader = ["runtime/src/exe.rs", "emulator/src/debuginfo.rs"];
        if !reader.contains(&file.as_str()) {
            assert!(
                !text.contains("object::File::parse("),
                "{file} reads an executable itself: use trax_runtime::exe::Executable"
            );
        }
        if file != "runtime/src/image.rs" {
            for def in ["pub struct Segment ", "pub struct MemoryImage "] {
                assert!(
                    !text.contains(def),
                    "{file} defines its own `{def}`: use trax_runtime::image"
                );
            }
        }
        if file != "runtime/src/abi.rs" {
            assert!(
                !text.contains("\"__trax_scene_\""),
                "{file} spells the scene symbol prefix: use abi::SCENE_SYMBOL_PREFIX"
            );
        }
    }
}
