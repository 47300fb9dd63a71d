//! End-to-end tests of the thesis-scale scene specs (`box:`, `subdivide:`, `hairball:`,
//! `vegetation:`): each renders through the path tracer with finite pixels, the same seed
//! gives the same framebuffer bytes, and bad specs fail with the spec part named.

use std::path::{Path, PathBuf};
mod common;
use common::{scratch_dir, trax};

fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("scene-specs-{name}"))
}

/// Renders `spec` with the path tracer (functional, 8×8) and returns the raw framebuffer.
fn render(spec: &str, file: &Path) -> Vec<f32> {
    let out = trax(&[
        "run",
        "examples/pathtracer.rs",
        "--functional",
        "--scene",
        spec,
        "--width",
        "8",
        "--height",
        "8",
        "--raw-framebuffer",
        file.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{spec}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(file)
        .unwrap()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

#[test]
fn new_specs_render_finite_and_seeded_ones_repeat() {
    let dir = scratch("render");
    let dragon = "../shared/scenes/dragon/dragon-100k.obj";
    let boxed_dragon = format!("box:{dragon}");
    for spec in [
        "box:icosphere:2",
        "subdivide:1:cornell",
        "hairball:3000:7",
        "vegetation:3000:7",
        boxed_dragon.as_str(),
    ] {
        let fb = render(spec, &dir.join("a.bin"));
        assert_eq!(fb.len(), 8 * 8 * 3, "{spec}");
        assert!(fb.iter().all(|c| c.is_finite()), "{spec}: non-finite pixel");
        assert!(fb.iter().any(|&c| c > 0.0), "{spec}: all black");
    }
    for spec in ["hairball:3000:7", "vegetation:3000:7"] {
        render(spec, &dir.join("b.bin"));
        render(spec, &dir.join("c.bin"));
        let (b, c) = (
            std::fs::read(dir.join("b.bin")).unwrap(),
            std::fs::read(dir.join("c.bin")).unwrap(),
        );
        assert_eq!(b, c, "{spec}: same seed, different framebuffer");
    }
}

#[test]
fn scene_info_counts_and_bad_spec_errors() {
    for (spec, triangles) in [
        ("box:cornell", "44"),
        ("subdivide:2:cornell", "512"),
        ("hairball:1000", "1000"),
        ("vegetation:1001:3", "1001"),
        ("box:subdivide:1:icosphere:2", "1292"),
    ] {
        let out = trax(&["scene", "info", spec]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{spec}");
        let line = stdout
            .lines()
            .find(|l| l.starts_with("triangles"))
            .unwrap_or_else(|| panic!("{spec}: {stdout}"));
        assert_eq!(line.split_whitespace().nth(1), Some(triangles), "{spec}");
    }
    for (spec, want) in [
        ("subdivide:x:cornell", "`x` is not a subdivision count"),
        ("box:nope", "unknown scene `nope`"),
        ("hairball:10", "at least 96"),
        ("vegetation:9:seed", "`seed` is not a seed"),
    ] {
        let out = trax(&["scene", "info", spec]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{spec} accepted");
        assert!(stderr.contains(want), "{spec}: {stderr}");
        assert!(!stderr.contains("panicked"), "{spec}: {stderr}");
    }
    let help = trax(&["scene", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    for form in [
        "hairball:N[:SEED]",
        "vegetation:N[:SEED]",
        "box:SCENE",
        "subdivide:N:SCENE",
    ] {
        assert!(help.contains(form), "`trax scene --help` lacks {form}");
    }
}
