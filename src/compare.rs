//! Image error metrics (`trax compare`, `trax converge`): read a PNG or a raw framebuffer,
//! and measure one image against a reference.
//!
//! Images are linear RGB in `f32`, where 1.0 is full white: a raw framebuffer (`trax run
//! --raw-framebuffer`, `trax native --raw-framebuffer`: `width*height` pixels of 3
//! little-endian `f32`, row 0 at the top, no header) is read as it is; an 8-bit PNG is read
//! as `value / 255` (the inverse of `trax_runtime::host::framebuffer_rgb8`, no gamma).
//!
//! Metrics, over the pixels whose three channels are finite in both images (the others are
//! counted, per image, as NaN or infinite pixels, and left out):
//! - RMSE: `sqrt(mean over channels of (a - b)²)`;
//! - relative MSE: `mean over channels of (a - b)² / (b² + 0.01)`, with `b` the reference
//!   (the second image) — the relMSE of the rendering literature (e.g. Rousselle et al.
//!   2011, Bitterli's benchmark scenes); the 0.01 keeps dark pixels from dominating;
//! - PSNR: `10·log10(1 / MSE)` dB, peak 1.0 (infinite for identical images);
//! - maximum absolute channel difference.

use std::path::Path;

/// An image in linear `f32` RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Where it came from (for messages).
    pub source: String,
    /// Width and height, when known (a raw framebuffer does not record them).
    pub size: Option<(u32, u32)>,
    /// Pixels, row 0 at the top.
    pub pixels: Vec<[f32; 3]>,
    /// The file format.
    pub format: Format,
}

/// Image file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// PNG, 8 or 16 bits, grey or RGB, with or without alpha (alpha ignored).
    Png,
    /// A raw framebuffer: pixels of 3 little-endian `f32`.
    Raw,
}

/// PNG files start with these bytes.
const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";
/// Bytes per raw framebuffer pixel.
const RAW_PIXEL_BYTES: usize = 12;

/// Reads `path`: a PNG (by its signature) or else a raw framebuffer. `size` gives a raw
/// framebuffer's dimensions (its length must then match); for a PNG it must match too.
pub fn read_image(path: &Path, size: Option<(u32, u32)>) -> Result<Image, String> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| format!("{name}: {e}"))?;
    let image = if bytes.starts_with(PNG_MAGIC) {
        decode_png(&name, &bytes)?
    } else {
        decode_raw(&name, &bytes)?
    };
    if let Some((w, h)) = size {
        match image.size {
            Some(s) if s != (w, h) => {
                return Err(format!(
                    "{name}: the PNG is {}x{}, not {w}x{h} as --size says",
                    s.0, s.1
                ))
            }
            Some(_) => {}
            None if image.pixels.len() as u64 != w as u64 * h as u64 => {
                return Err(format!(
                    "{name}: {} bytes is {} pixels of 3 f32, not {w}x{h} = {} as --size says",
                    bytes.len(),
                    image.pixels.len(),
                    w as u64 * h as u64
                ))
            }
            None => {
                return Ok(Image {
                    size: Some((w, h)),
                    ..image
                })
            }
        }
    }
    Ok(image)
}

/// Decodes a raw framebuffer: its length must be a whole number of 12-byte pixels.
pub fn decode_raw(name: &str, bytes: &[u8]) -> Result<Image, String> {
    if bytes.is_empty() || !bytes.len().is_multiple_of(RAW_PIXEL_BYTES) {
        return Err(format!(
            "{name}: not a PNG, and {} bytes is not a raw framebuffer (a positive multiple of {RAW_PIXEL_BYTES}: pixels of 3 little-endian f32)",
            bytes.len()
        ));
    }
    let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let pixels = bytes
        .chunks_exact(RAW_PIXEL_BYTES)
        .map(|p| [f(&p[0..4]), f(&p[4..8]), f(&p[8..12])])
        .collect();
    Ok(Image {
        source: name.to_string(),
        size: None,
        pixels,
        format: Format::Raw,
    })
}

/// Decodes a PNG to linear RGB (`value / max`; grey is copied to the three channels).
pub fn decode_png(name: &str, bytes: &[u8]) -> Result<Image, String> {
    let err = |e: png::DecodingError| format!("{name}: bad PNG: {e}");
    let mut decoder = png::Decoder::new(bytes);
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(err)?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(err)?;
    let buf = &buf[..info.buffer_size()];
    let channels = info.color_type.samples();
    let sample = |i: usize| -> f32 {
        match info.bit_depth {
            png::BitDepth::Sixteen => {
                u16::from_be_bytes([buf[2 * i], buf[2 * i + 1]]) as f32 / 65535.0
            }
            _ => buf[i] as f32 / 255.0,
        }
    };
    let n = info.width as usize * info.height as usize;
    let pixels = (0..n)
        .map(|p| {
            let at = p * channels;
            if channels >= 3 {
                [sample(at), sample(at + 1), sample(at + 2)]
            } else {
                let g = sample(at);
                [g, g, g]
            }
        })
        .collect();
    Ok(Image {
        source: name.to_string(),
        size: Some((info.width, info.height)),
        pixels,
        format: Format::Png,
    })
}

/// Non-finite pixels of one image (a pixel counts once, by its first non-finite channel
/// kind: NaN before infinity).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct NonFinite {
    /// Pixels with a NaN channel.
    pub nan_pixels: u64,
    /// Pixels with an infinite channel and no NaN.
    pub inf_pixels: u64,
}

/// Counts the NaN and infinite pixels of `img`.
pub fn non_finite(img: &Image) -> NonFinite {
    let mut n = NonFinite::default();
    for p in &img.pixels {
        if p.iter().any(|c| c.is_nan()) {
            n.nan_pixels += 1;
        } else if p.iter().any(|c| c.is_infinite()) {
            n.inf_pixels += 1;
        }
    }
    n
}

/// The error of an image against a reference (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Pixels compared (finite in both images).
    pub pixels: u64,
    /// Pixels left out: a NaN or infinite channel in either image.
    pub left_out: u64,
    /// Root mean squared error over the channels.
    pub rmse: f64,
    /// Mean squared error over the channels.
    pub mse: f64,
    /// Mean over channels of `(a - b)² / (b² + 0.01)`, `b` the reference.
    pub rel_mse: f64,
    /// `10·log10(1 / MSE)` dB; `None` when the images are equal (infinite PSNR) or no
    /// pixel was compared.
    pub psnr_db: Option<f64>,
    /// Largest absolute channel difference.
    pub max_abs_error: f64,
}

/// The ε of relative MSE: `(a - b)² / (b² + REL_MSE_EPSILON)`.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Measures `a` against the reference `b`; the two must have the same number of pixels
/// and, when both sizes are known, the same size. Errors name the files.
pub fn compare(a: &Image, b: &Image) -> Result<Metrics, String> {
    if let (Some(sa), Some(sb)) = (a.size, b.size) {
        if sa != sb {
            return Err(format!(
                "{} is {}x{} but {} is {}x{}",
                a.source, sa.0, sa.1, b.source, sb.0, sb.1
            ));
        }
    }
    if a.pixels.len() != b.pixels.len() {
        let describe = |i: &Image| match i.size {
            Some((w, h)) => format!("{} is {w}x{h} = {} pixels", i.source, i.pixels.len()),
            None => format!("{} has {} pixels", i.source, i.pixels.len()),
        };
        return Err(format!(
            "{} but {}: the images differ in size",
            describe(a),
            describe(b)
        ));
    }
    let (mut sq, mut rel, mut max, mut pixels, mut left_out) = (0.0f64, 0.0f64, 0.0f64, 0u64, 0u64);
    for (pa, pb) in a.pixels.iter().zip(&b.pixels) {
        if !pa.iter().chain(pb).all(|c| c.is_finite()) {
            left_out += 1;
            continue;
        }
        pixels += 1;
        for (&x, &y) in pa.iter().zip(pb) {
            let (x, y) = (x as f64, y as f64);
            let d = x - y;
            sq += d * d;
            rel += d * d / (y * y + REL_MSE_EPSILON);
            max = max.max(d.abs());
        }
    }
    let channels = (pixels * 3) as f64;
    let (mse, rel_mse) = if pixels == 0 {
        (0.0, 0.0)
    } else {
        (sq / channels, rel / channels)
    };
    Ok(Metrics {
        pixels,
        left_out,
        rmse: mse.sqrt(),
        mse,
        rel_mse,
        psnr_db: (mse > 0.0).then(|| -10.0 * mse.log10()),
        max_abs_error: max,
    })
}

/// The least-squares slope of `ln y` against `ln x` over the points with positive `x`
/// and `y`; `None` with fewer than two distinct `x`.
pub fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (pts.len() >= 2 && sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(pixels: &[[f32; 3]], size: Option<(u32, u32)>) -> Image {
        Image {
            source: "t".into(),
            size,
            pixels: pixels.to_vec(),
            format: Format::Raw,
        }
    }

    /// A 2x2 image against a reference, every metric by hand: differences per channel
    /// 0.5,0,0 | 0,0,0 | 0,-0.1,0 | 0,0,0.2 (reference values 0.5, 0.0, 1.0 and 0.0 for
    /// the differing channels).
    #[test]
    fn two_by_two_metrics_by_hand() {
        let b = img(
            &[
                [0.5, 0.2, 0.3],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0],
            ],
            Some((2, 2)),
        );
        let a = img(
            &[
                [1.0, 0.2, 0.3],
                [1.0, 1.0, 1.0],
                [0.0, 0.9, 0.0],
                [0.0, 0.0, 0.2],
            ],
            Some((2, 2)),
        );
        let m = compare(&a, &b).unwrap();
        // Squared differences: 0.25 + 0.01 + 0.04 = 0.30 over 12 channels.
        let mse = 0.30 / 12.0;
        assert!((m.mse - mse).abs() < 1e-7, "{m:?}");
        assert!((m.rmse - 0.158_113_883).abs() < 1e-6, "{m:?}");
        // 0.25/(0.25+0.01) + 0.01/(1+0.01) + 0.04/(0+0.01) = 0.961538 + 0.009901 + 4.
        let rel = (0.25 / 0.26 + 0.01 / 1.01 + 4.0) / 12.0;
        assert!((m.rel_mse - rel).abs() < 1e-6, "{m:?}");
        // 10·log10(12/0.3) = 10·log10(40) = 16.0206 dB.
        assert!((m.psnr_db.unwrap() - 16.020_6).abs() < 1e-3, "{m:?}");
        assert!((m.max_abs_error - 0.5).abs() < 1e-7);
        assert_eq!((m.pixels, m.left_out), (4, 0));
        // Identical images: zero error, infinite PSNR.
        let same = compare(&b, &b).unwrap();
        assert_eq!((same.rmse, same.rel_mse, same.psnr_db), (0.0, 0.0, None));
    }

    #[test]
    fn non_finite_pixels_are_counted_and_left_out() {
        let nan = f32::NAN;
        let inf = f32::INFINITY;
        let a = img(
            &[[nan, 0.0, 0.0], [0.0, inf, nan], [0.0, -inf, 0.0], [0.5; 3]],
            None,
        );
        let b = img(&[[0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]], None);
        assert_eq!(
            non_finite(&a),
            NonFinite {
                nan_pixels: 2,
                inf_pixels: 1
            }
        );
        let m = compare(&a, &b).unwrap();
        assert_eq!((m.pixels, m.left_out), (1, 3));
        assert!((m.rmse - 0.5).abs() < 1e-7);
    }

    #[test]
    fn sizes_must_match() {
        let a = img(&[[0.0; 3]; 4], Some((2, 2)));
        let b = img(&[[0.0; 3]; 4], Some((4, 1)));
        let e = compare(&a, &b).unwrap_err();
        assert!(e.contains("2x2") && e.contains("4x1"), "{e}");
        let c = img(&[[0.0; 3]; 3], None);
        let e = compare(&a, &c).unwrap_err();
        assert!(e.contains("4 pixels") && e.contains("3 pixels"), "{e}");
    }

    #[test]
    fn raw_length_must_be_whole_pixels() {
        let e = decode_raw("x.bin", &[0; 13]).unwrap_err();
        assert!(e.contains("x.bin") && e.contains("13 bytes"), "{e}");
        assert!(decode_raw("x.bin", &[]).is_err());
        let one: Vec<u8> = [1.0f32, -2.0, 0.25]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        assert_eq!(
            decode_raw("x", &one).unwrap().pixels,
            vec![[1.0, -2.0, 0.25]]
        );
    }

    #[test]
    fn log_log_slope_of_a_power_law() {
        let pts: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0]
            .iter()
            .map(|&x| (x, 3.0 / f64::sqrt(x)))
            .collect();
        assert!((log_log_slope(&pts).unwrap() + 0.5).abs() < 1e-12);
        assert_eq!(log_log_slope(&[(1.0, 1.0)]), None);
    }
}
