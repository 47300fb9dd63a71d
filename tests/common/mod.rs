//! Helpers shared by the root integration tests (`mod common;` in each): the checkout,
//! scratch directories under Cargo's test temporary directory, the `trax` binary, and
//! decoding what it writes. Each test crate uses a part of them.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The checkout (the root crate's manifest directory): examples, docs and `../shared/scenes`
/// are found from here, and `trax` runs here.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `NAME` in Cargo's temporary directory for integration tests, not created: a build
/// cache keyed by content (`TRAX_CACHE_DIR`), kept between runs.
pub fn tmp_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// The scratch directory `NAME` (see [`tmp_path`]), created; what it holds is kept.
pub fn scratch_dir(name: &str) -> PathBuf {
    let d = tmp_path(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The scratch directory `NAME`, emptied and created.
pub fn fresh_dir(name: &str) -> PathBuf {
    let d = tmp_path(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Process output as text (lossy).
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The `trax` binary, to run in the checkout (arguments and environment to add).
pub fn trax_command() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_trax"));
    c.current_dir(root());
    c
}

/// Runs `trax ARGS` in the checkout.
pub fn trax(args: &[&str]) -> Output {
    trax_command().args(args).output().expect("run trax")
}

/// The JSON document in the file at `path`.
pub fn read_json(path: &Path) -> serde_json::Value {
    let s = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&s).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The build cache (`TRAX_CACHE_DIR`) the tests that build natively share: keyed by
/// content, so kept between runs.
pub fn native_cache() -> PathBuf {
    tmp_path("trax-native-cache")
}

/// Runs `trax ARGS` in the checkout with the shared native build cache ([`native_cache`])
/// and without `RUST_BACKTRACE` (so a crash report reads as a user's would).
pub fn trax_cached(args: &[&str]) -> Output {
    trax_command()
        .args(args)
        .env("TRAX_CACHE_DIR", native_cache())
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("run trax")
}
