//! End-to-end tests of `trax compare` (image error metrics, by hand on tiny images) and
//! `trax converge` (Monte Carlo convergence of the path tracer).

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{scratch_dir, text, trax};

fn scratch(name: &str) -> PathBuf {
    scratch_dir(&format!("compare-{name}"))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn write_png(path: &Path, w: u32, h: u32, rgb: &[u8]) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(file, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(rgb).unwrap();
}

fn write_raw(path: &Path, pixels: &[[f32; 3]]) {
    let bytes: Vec<u8> = pixels
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    std::fs::write(path, bytes).unwrap();
}

fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "{}", text(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn close(v: &serde_json::Value, want: f64) {
    let got = v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"));
    assert!((got - want).abs() < 1e-6, "got {got}, want {want}");
}

/// A 2x2 PNG against a 2x2 raw reference. Only the red channel of pixel 0 differs:
/// 255/255 = 1.0 against 0.5. Over 12 channels: MSE = 0.25/12, RMSE = 0.5/√12,
/// relative MSE = 0.25/(0.5² + 0.01)/12, PSNR = 10·log10(12/0.25) = 10·log10(48) dB.
#[test]
fn png_against_raw_every_metric_by_hand() {
    let d = scratch("by-hand");
    let (a, b) = (d.join("a.png"), d.join("b.bin"));
    write_png(&a, 2, 2, &[255, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 255]);
    write_raw(&b, &[[0.5, 0.0, 0.0], [0.0; 3], [0.0; 3], [0.0, 0.0, 1.0]]);
    let v = json(&trax(&["compare", s(&a), s(&b), "--json"]));
    close(&v["rmse"], 0.5 / 12f64.sqrt());
    close(&v["mse"], 0.25 / 12.0);
    close(&v["rel_mse"], 0.25 / 0.26 / 12.0);
    close(&v["psnr_db"], 10.0 * 48f64.log10());
    close(&v["max_abs_error"], 0.5);
    assert_eq!(v["pixels"], 4);
    assert_eq!(v["left_out"], 0);
    // The raw reference takes the PNG's size.
    assert_eq!(
        (v["b"]["width"].clone(), v["b"]["height"].clone()),
        (2.into(), 2.into())
    );
    assert_eq!(v["a"]["format"], "png");
    assert_eq!(v["b"]["format"], "raw");

    let out = trax(&["compare", s(&a), s(&b)]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let t = text(&out.stdout);
    assert!(t.contains("PSNR:          16.812 dB"), "{t}");
    assert!(t.contains("max abs error: 5.000000e-1"), "{t}");

    // An image against itself: zero error, infinite PSNR (null in JSON).
    let v = json(&trax(&["compare", s(&b), s(&b), "--json"]));
    assert_eq!(v["rmse"], 0.0);
    assert!(v["psnr_db"].is_null(), "{v}");
    let t = text(&trax(&["compare", s(&a), s(&a)]).stdout);
    assert!(t.contains("PSNR:          inf (identical)"), "{t}");
}

/// NaN and infinite pixels are counted per image (a pixel once) and left out of the error.
#[test]
fn nan_and_inf_pixels_of_a_raw_framebuffer() {
    let d = scratch("nan");
    let (a, b) = (d.join("a.bin"), d.join("b.bin"));
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    write_raw(
        &a,
        &[
            [nan, nan, 0.0],
            [0.0, inf, 0.0],
            [0.0, -inf, nan],
            [0.25, 0.25, 0.25],
        ],
    );
    write_raw(&b, &[[0.0; 3], [0.0; 3], [0.0; 3], [0.0, 0.0, 0.0]]);
    let v = json(&trax(&["compare", s(&a), s(&b), "--json", "--size", "2x2"]));
    assert_eq!(v["a"]["nan_pixels"], 2);
    assert_eq!(v["a"]["inf_pixels"], 1);
    assert_eq!(v["b"]["nan_pixels"], 0);
    assert_eq!(v["a"]["width"], 2);
    assert_eq!(v["pixels"], 1);
    assert_eq!(v["left_out"], 3);
    close(&v["rmse"], 0.25);
    let t = text(&trax(&["compare", s(&a), s(&b)]).stdout);
    assert!(t.contains("2 NaN pixel(s), 1 infinite pixel(s)"), "{t}");
    assert!(t.contains("size not recorded"), "{t}");
}

/// Bad input: a clear error naming the file, a failure exit, no panic.
#[test]
fn errors_name_the_file() {
    let d = scratch("errors");
    let png = d.join("a.png");
    write_png(&png, 2, 2, &[0; 12]);
    let three = d.join("three.bin");
    write_raw(&three, &[[0.0; 3]; 3]);
    let odd = d.join("odd.bin");
    std::fs::write(&odd, [0u8; 13]).unwrap();
    let wide = d.join("wide.png");
    write_png(&wide, 4, 1, &[0; 12]);
    let broken = d.join("broken.png");
    let mut bytes = std::fs::read(&png).unwrap();
    bytes.truncate(20);
    std::fs::write(&broken, bytes).unwrap();
    let missing = d.join("missing.png");
    let cases: Vec<(Vec<&str>, Vec<String>)> = vec![
        (
            vec![s(&png), s(&three)],
            vec![
                "a.png is 2x2 = 4 pixels".into(),
                "three.bin has 3 pixels".into(),
            ],
        ),
        (
            vec![s(&png), s(&wide)],
            vec!["2x2".into(), "wide.png is 4x1".into()],
        ),
        (
            vec![s(&odd), s(&png)],
            vec!["odd.bin".into(), "13 bytes".into()],
        ),
        (
            vec![s(&broken), s(&png)],
            vec!["broken.png: bad PNG".into()],
        ),
        (vec![s(&missing), s(&png)], vec!["missing.png".into()]),
        (
            vec![s(&three), s(&three), "--size", "2x2"],
            vec!["three.bin".into(), "2x2".into()],
        ),
        (
            vec![s(&png), s(&png), "--size", "4x1"],
            vec!["a.png: the PNG is 2x2".into()],
        ),
    ];
    for (args, wants) in cases {
        let out = trax(&[&["compare"], args.as_slice()].concat());
        let err = text(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!err.contains("panicked"), "{err}");
        for w in wants {
            assert!(err.contains(&w), "{args:?}: want {w:?} in {err}");
        }
    }
}

/// The path tracer's error against a 512-spp reference falls as spp^-1/2: it is an
/// unbiased Monte Carlo estimator (variance σ²/spp). With five levels (1..16 spp) on a
/// 16x16 image the fitted slope scatters around −0.5: the path tracer's error is
/// heavy-tailed (a few bright paths dominate), so each level is the mean MSE of 4 seeds,
/// and the reference's own noise (σ²/512) flattens the slope slightly. Base seeds 1, 11,
/// .., 51 gave slopes −0.36 .. −0.57, hence [−0.7, −0.3].
#[test]
fn path_tracer_converges_at_the_monte_carlo_rate() {
    let d = scratch("converge");
    let out = trax(&[
        "converge",
        "examples/pathtracer.rs",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "1,2,4,8,16",
        "--reference-spp",
        "512",
        "--repeats",
        "4",
        "-o",
        s(&d),
    ]);
    let t = text(&out.stdout);
    assert!(out.status.success(), "{t}\n{}", text(&out.stderr));
    let rows: Vec<Vec<&str>> = t
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|w| w.first().is_some_and(|c| c.parse::<u32>().is_ok()))
        .collect();
    let spps: Vec<&str> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(spps, ["1", "2", "4", "8", "16"], "{t}");
    let rmse: Vec<f64> = rows.iter().map(|r| r[1].parse().unwrap()).collect();
    assert!(rmse[0] > 2.0 * rmse[4], "{t}");
    let slope: f64 = t
        .lines()
        .find_map(|l| l.strip_prefix("slope of log RMSE vs log spp: "))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no slope in {t}"));
    assert!((-0.7..=-0.3).contains(&slope), "slope {slope}\n{t}");
    let csv = std::fs::read_to_string(d.join("convergence.csv")).unwrap();
    assert_eq!(csv.lines().count(), 6, "{csv}");
    let png = std::fs::read(d.join("convergence.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(
        std::fs::metadata(d.join("reference.bin")).unwrap().len(),
        16 * 16 * 12
    );

    // Timing mode, against the reference just rendered: simulated cycles per frame grow
    // with the samples (twice the samples, about twice the work).
    let out = trax(&[
        "converge",
        "examples/pathtracer.rs",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "1,2",
        "--timing",
        "--reference",
        s(&d.join("reference.bin")),
        "-o",
        s(&d.join("timing")),
    ]);
    let t = text(&out.stdout);
    assert!(out.status.success(), "{t}\n{}", text(&out.stderr));
    let cycles: Vec<f64> = t
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|w| w.first().is_some_and(|c| c.parse::<u32>().is_ok()))
        .map(|w| w[3].parse().unwrap())
        .collect();
    assert_eq!(cycles.len(), 2, "{t}");
    assert!((1.5..2.5).contains(&(cycles[1] / cycles[0])), "{t}");
}

#[test]
fn converge_rejects_bad_levels_and_references() {
    let d = scratch("converge-errors");
    let out = trax(&[
        "converge",
        "examples/pathtracer.rs",
        "--spp",
        "1,0",
        "-o",
        s(&d),
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("--spp"), "{}", text(&out.stderr));
    let odd = d.join("odd.bin");
    std::fs::write(&odd, [0u8; 24]).unwrap();
    let out = trax(&[
        "converge",
        "examples/pathtracer.rs",
        "--width",
        "4",
        "--height",
        "4",
        "--spp",
        "1",
        "--reference",
        s(&odd),
        "-o",
        s(&d),
    ]);
    let err = text(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("odd.bin has 2 pixels, not 4x4") && !err.contains("panicked"),
        "{err}"
    );
}
