//! `trax compare A B [--size WxH] [--json]`: the error of image A against the reference B
//! (PNG or raw framebuffer; metrics in [`trax::compare`]).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use trax::compare::{compare, non_finite, read_image, Image, Metrics, NonFinite};

/// Arguments of `trax compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The image to measure: PNG, or a raw framebuffer (`--raw-framebuffer` output).
    pub a: PathBuf,
    /// The reference image (relative MSE divides by its values).
    pub b: PathBuf,
    /// Width and height of raw framebuffers, which do not record them (default: the
    /// other image's size if it is a PNG; otherwise only the pixel counts must agree).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?}: expected WIDTHxHEIGHT, e.g. 64x48"))?;
    let dim = |v: &str| match v.trim().parse::<u32>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("{s:?}: {v:?} is not a positive integer")),
    };
    Ok((dim(w)?, dim(h)?))
}

#[derive(serde::Serialize)]
struct ImageReport<'a> {
    file: &'a str,
    format: trax::compare::Format,
    width: Option<u32>,
    height: Option<u32>,
    #[serde(flatten)]
    non_finite: NonFinite,
}

#[derive(serde::Serialize)]
struct Report<'a> {
    a: ImageReport<'a>,
    b: ImageReport<'a>,
    #[serde(flatten)]
    metrics: Metrics,
}

fn image_report(img: &Image) -> ImageReport<'_> {
    ImageReport {
        file: &img.source,
        format: img.format,
        width: img.size.map(|s| s.0),
        height: img.size.map(|s| s.1),
        non_finite: non_finite(img),
    }
}

/// Runs `trax compare`.
pub fn run(a: CompareArgs) -> ExitCode {
    match compare_cmd(&a) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => super::run::fail(e),
    }
}

/// Reads both images; a raw one takes the size from `--size` or the other (PNG) image.
fn read_pair(a: &CompareArgs) -> Result<(Image, Image), String> {
    let mut ia = read_image(&a.a, a.size)?;
    let mut ib = read_image(&a.b, a.size)?;
    let (sa, sb) = (ia.size, ib.size);
    for (raw, other) in [(&mut ia, sb), (&mut ib, sa)] {
        if raw.size.is_none() {
            if let Some((w, h)) = other {
                if raw.pixels.len() as u64 == w as u64 * h as u64 {
                    raw.size = Some((w, h));
                }
            }
        }
    }
    Ok((ia, ib))
}

fn compare_cmd(a: &CompareArgs) -> Result<String, String> {
    let (ia, ib) = read_pair(a)?;
    let metrics = compare(&ia, &ib)?;
    let report = Report {
        a: image_report(&ia),
        b: image_report(&ib),
        metrics,
    };
    if a.json {
        return serde_json::to_string_pretty(&report)
            .map(|s| s + "\n")
            .map_err(|e| e.to_string());
    }
    let mut s = String::new();
    for (tag, r) in [("A", &report.a), ("B (reference)", &report.b)] {
        let size = match (r.width, r.height) {
            (Some(w), Some(h)) => format!("{w}x{h}"),
            _ => "size not recorded".into(),
        };
        let fmt = match r.format {
            trax::compare::Format::Png => "PNG",
            trax::compare::Format::Raw => "raw f32",
        };
        s += &format!(
            "{tag}: {} ({fmt}, {size}): {} NaN pixel(s), {} infinite pixel(s)\n",
            r.file, r.non_finite.nan_pixels, r.non_finite.inf_pixels
        );
    }
    let m = &report.metrics;
    s += &format!(
        "pixels compared: {} ({} left out: NaN or infinite in A or B)\n",
        m.pixels, m.left_out
    );
    s += &format!("RMSE:          {:.6e}\n", m.rmse);
    s += &format!(
        "relative MSE:  {:.6e}  (mean over channels of (A-B)^2/(B^2+0.01))\n",
        m.rel_mse
    );
    s += &match m.psnr_db {
        Some(p) => format!("PSNR:          {p:.3} dB  (peak 1.0)\n"),
        None if m.pixels > 0 => "PSNR:          inf (identical)\n".into(),
        None => "PSNR:          none (no pixel compared)\n".into(),
    };
    s += &format!("max abs error: {:.6e}\n", m.max_abs_error);
    Ok(s)
}
