//! Running one generated kernel both ways, shared by the differential tests
//! (`libm_differential.rs`, `simd_differential.rs`): on the functional emulator (one
//! thread, the default chip) and through `trax native`.

use std::path::{Path, PathBuf};
use std::process::Command;

use ::trax::native::check::RustcCheck;
use ::trax::pipeline::build_executable_checked;
use trax_emulator::timing::{ChipConfig, DEFAULT_CHIP};
use trax_emulator::{run, Mode, RunRequest};

/// The repository root (where `trax` runs).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch directory `name` under the target's temporary directory.
pub fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Compiles, links and runs `kernel` on the functional emulator (one thread); returns
/// its output and the instructions of each profile region. Not checked by rustc: the
/// kernels that also run natively are checked by that build, and the cost measurements
/// mark profile regions with the machine-only `__trax_op!`.
pub fn emulate(kernel: &Path, opt: u8) -> (String, Vec<u64>) {
    let elf = build_executable_checked(&[kernel.to_path_buf()], opt, RustcCheck::Off)
        .unwrap_or_else(|e| panic!("-O{opt}: {e}"));
    let mut chip = ChipConfig::preset(DEFAULT_CHIP).unwrap();
    chip.tms = 1;
    chip.threads_per_tm = 1;
    let mut out = Vec::new();
    let name = kernel.with_extension("elf").display().to_string();
    let result = run(
        RunRequest::new(&name, &elf, &chip, Mode::Functional),
        &mut out,
    )
    .unwrap_or_else(|e| panic!("-O{opt}: {e}"));
    assert!(
        result.finished(),
        "-O{opt}: {:?}\n{}",
        result.outcome,
        result.failure.unwrap_or_default()
    );
    let profile = result.machine.shared.profile.to_vec();
    (String::from_utf8(out).unwrap(), profile)
}

/// Runs `kernel` with `trax native` (one thread; the build cached in `cache`); returns
/// its output.
pub fn native(kernel: &Path, cache: &Path) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_trax"))
        .arg("native")
        .arg(kernel)
        .args(["--scene", "cornell", "--width", "4", "--height", "4"])
        .args(["--tms", "1", "--threads", "1"])
        .env("TRAX_CACHE_DIR", cache)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "trax native: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}
