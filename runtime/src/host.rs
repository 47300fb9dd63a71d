//! Helpers for native runs: a camera from eye and target, the header-only image a kernel
//! needs when no scene is loaded (scene header, camera, framebuffer), and framebuffer
//! conversion. The memory image itself and its file format are [`crate::image`].

use crate::abi::{self, Camera, Component, Field, SceneHeader};
use crate::image::{ImageError, MemoryImage, Perms, Segment};

/// A pinhole camera at `eye` looking at `target`, with vertical field of view `fov_y_deg`
/// and the given `aspect` (width / height), image plane at distance 1.
pub fn look_at_camera(
    eye: [f32; 3],
    target: [f32; 3],
    up: [f32; 3],
    fov_y_deg: f32,
    aspect: f32,
) -> Camera {
    let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f32; 3], b: [f32; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let norm = |a: [f32; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        [a[0] / l, a[1] / l, a[2] / l]
    };
    let w = norm(sub(target, eye));
    let u = norm(cross(w, up));
    let v = cross(u, w);
    let top = (fov_y_deg.to_radians() * 0.5).tan();
    let right = top * aspect;
    Camera {
        eye,
        u,
        v,
        w,
        left: -right,
        right,
        bottom: -top,
        top,
        distance: 1.0,
        aperture: 0.0,
    }
}

/// Parameters of a header-only image.
#[derive(Clone, Debug)]
pub struct HeaderParams {
    /// Image width in pixels (>= 1).
    pub width: u32,
    /// Image height in pixels (>= 1).
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum path depth.
    pub max_depth: u32,
    /// Seed of the random streams (per thread, and per pixel and sample).
    pub seed: u32,
    /// Ray offset epsilon.
    pub epsilon: f32,
    /// Background colour.
    pub background: [f32; 3],
    /// Camera.
    pub camera: Camera,
    /// The ray stream memory: rays, bytes per ray, buffers (all 0: none).
    pub stream: [u32; 3],
    /// The chip's `trax.setpipe` modes (header `pipe_modes`, bit m for mode m).
    pub pipe_modes: u32,
}

impl Default for HeaderParams {
    fn default() -> Self {
        HeaderParams {
            width: 128,
            height: 128,
            spp: 1,
            max_depth: 3,
            seed: 1,
            epsilon: 1e-4,
            background: [0.0; 3],
            camera: look_at_camera([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 45.0, 1.0),
            stream: [0; 3],
            pipe_modes: 1,
        }
    }
}

/// Address of the camera in a header-only image (no program text is loaded natively).
pub const HEADER_ONLY_CAMERA_ADDR: u32 = abi::TEXT_BASE;
/// Address of the framebuffer in a header-only image.
pub const HEADER_ONLY_FRAMEBUFFER_ADDR: u32 = abi::TEXT_BASE + 0x100;

/// Builds an image with only the scene header, the camera and a zeroed framebuffer.
pub fn header_only_image(p: &HeaderParams) -> Result<MemoryImage, ImageError> {
    let pixels = (p.width as u64) * (p.height as u64);
    let fb_len = pixels * abi::PIXEL_BYTES as u64;
    if p.width == 0
        || p.height == 0
        || HEADER_ONLY_FRAMEBUFFER_ADDR as u64 + fb_len >= abi::STACK_TOP as u64 / 2
    {
        return Err(ImageError::BadSegment {
            index: 2,
            addr: HEADER_ONLY_FRAMEBUFFER_ADDR,
            problem: "framebuffer size must be non-zero and under 1 GiB",
        });
    }
    let header = SceneHeader {
        spp: p.spp,
        max_depth: p.max_depth,
        epsilon: p.epsilon,
        seed: p.seed,
        background: p.background,
        stream_rays: p.stream[0],
        stream_ray_bytes: p.stream[1],
        stream_buffers: p.stream[2],
        pipe_modes: p.pipe_modes,
        camera: HEADER_ONLY_CAMERA_ADDR,
        framebuffer: Component {
            addr: HEADER_ONLY_FRAMEBUFFER_ADDR,
            count: pixels as u32,
        },
        ..SceneHeader::new(p.width, p.height)
    };
    let image = MemoryImage {
        segments: vec![
            Segment::new(
                "scene_header",
                abi::SCENE_HEADER_ADDR,
                header.to_bytes(),
                Perms::R,
            ),
            Segment::new(
                "camera",
                HEADER_ONLY_CAMERA_ADDR,
                p.camera.to_bytes(),
                Perms::R,
            ),
            Segment {
                name: "framebuffer".into(),
                addr: HEADER_ONLY_FRAMEBUFFER_ADDR,
                data: Vec::new(),
                size: fb_len as u32,
                perms: Perms::RW,
            },
        ],
    };
    image.validate()?;
    Ok(image)
}

/// Converts a framebuffer (`width*height` pixels of 3 × f32 little-endian, row 0 at the
/// top) to 8-bit RGB: each linear value is clamped to `[0, 1]` (NaN counts as 0) and
/// mapped to `round(v * 255)`; no gamma curve is applied. Missing bytes read as black.
pub fn framebuffer_rgb8(fb: &[u8], width: u32, height: u32) -> Vec<u8> {
    framebuffer_rgb8_exposed(fb, width, height, 0.0)
}

/// [`framebuffer_rgb8`] with an exposure of `ev` stops: every value is multiplied by
/// `2^ev` before clamping (the framebuffer itself is not changed).
pub fn framebuffer_rgb8_exposed(fb: &[u8], width: u32, height: u32, ev: f32) -> Vec<u8> {
    let scale = ev.exp2();
    let n = width as usize * height as usize * 3;
    (0..n)
        .map(|i| {
            let v = fb
                .get(4 * i..4 * i + 4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .unwrap_or(0.0);
            let v = if v.is_nan() {
                0.0
            } else {
                (v * scale).clamp(0.0, 1.0)
            };
            (v * 255.0 + 0.5) as u8
        })
        .collect()
}

/// The key a dark image is brightened toward by [`auto_exposure`]: the mean linear value of
/// a photographic middle grey.
pub const AUTO_EXPOSURE_KEY: f64 = 0.18;

/// The exposure `--exposure auto` gives a framebuffer, in whole stops: `floor(log2(0.18 /
/// mean))` where `mean` is the mean of every channel of every pixel (NaN and negative
/// values as 0), and never below 0. So an image whose mean is already at least 9% of white
/// is written as it is, and a darker one is brightened by the largest power of two that
/// keeps its mean at or below 18% (the brightest few pixels may clip). A black image stays
/// at 0.
pub fn auto_exposure(fb: &[u8]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0u64);
    for b in fb.chunks_exact(4) {
        let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        sum += if v.is_nan() {
            0.0
        } else {
            f64::from(v.max(0.0))
        };
        n += 1;
    }
    let mean = sum / n.max(1) as f64;
    if !(mean > 0.0 && mean.is_finite()) {
        return 0.0;
    }
    // Whole stops from 0 to 40 (beyond: a framebuffer of denormals; nothing to see).
    (AUTO_EXPOSURE_KEY / mean).log2().floor().clamp(0.0, 40.0) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fb(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|f| f.to_le_bytes()).collect()
    }

    /// Auto exposure: whole stops toward a mean of 0.18, never darker, 0 for black.
    #[test]
    fn auto_exposure_brightens_dark_images_by_whole_stops() {
        assert_eq!(auto_exposure(&fb(&[0.5, 0.2, 0.3])), 0.0);
        assert_eq!(
            auto_exposure(&fb(&[0.1, 0.1, 0.1])),
            0.0,
            "mean 0.1 >= 0.09"
        );
        assert_eq!(auto_exposure(&fb(&[0.08, 0.08, 0.08])), 1.0);
        assert_eq!(
            auto_exposure(&fb(&[0.003; 6])),
            5.0,
            "0.18 / 0.003 = 60: 2^5"
        );
        assert_eq!(auto_exposure(&fb(&[0.0, f32::NAN, -1.0])), 0.0);
        let px = fb(&[0.003, 0.01, 0.5]);
        assert_eq!(
            framebuffer_rgb8_exposed(&px, 1, 1, 5.0),
            vec![
                (0.003f32 * 32.0 * 255.0 + 0.5) as u8,
                (0.01f32 * 32.0 * 255.0 + 0.5) as u8,
                255
            ]
        );
        assert_eq!(
            framebuffer_rgb8_exposed(&px, 1, 1, 0.0),
            framebuffer_rgb8(&px, 1, 1)
        );
    }

    #[test]
    fn framebuffer_to_rgb8_clamps_and_rounds() {
        let px: Vec<u8> = [0.0f32, 0.5, 1.0, -1.0, 7.0, f32::NAN]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        assert_eq!(framebuffer_rgb8(&px, 2, 1), vec![0, 128, 255, 0, 255, 0]);
        assert_eq!(
            framebuffer_rgb8(&px[..12], 2, 1),
            vec![0, 128, 255, 0, 0, 0]
        );
    }

    #[test]
    fn header_only_image_round_trips_with_permissions() {
        let img = header_only_image(&HeaderParams::default()).unwrap();
        let back = MemoryImage::parse(&img.to_bytes()).unwrap();
        assert_eq!(back, img);
        assert_eq!(
            back.read_u32(abi::SCENE_HEADER_ADDR),
            Some(abi::SCENE_MAGIC)
        );
        assert_eq!(back.read_u32(abi::SCENE_HEADER_ADDR + 8), Some(128));
        assert_eq!(back.read_u32(0x20), None);
        let fb = back.segment("framebuffer").unwrap();
        assert_eq!(
            (fb.size, fb.perms),
            (128 * 128 * abi::PIXEL_BYTES, Perms::RW)
        );
        assert_eq!(back.read_u32(fb.addr + fb.size - 4), Some(0));
        assert_eq!(back.segment("camera").unwrap().perms, Perms::R);
        let p = HeaderParams {
            width: 0,
            ..HeaderParams::default()
        };
        assert!(header_only_image(&p).is_err());
    }
}
