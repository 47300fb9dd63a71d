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
    let n = width as usize * height as usize * 3;
    (0..n)
        .map(|i| {
            let v = fb
                .get(4 * i..4 * i + 4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .unwrap_or(0.0);
            let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
            (v * 255.0 + 0.5) as u8
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
