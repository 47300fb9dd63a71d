//! Memory image files: the initial (and final) contents of simulated memory as a list of
//! `(address, bytes)` segments, exchanged between `trax native` and the host runner of the
//! kernel prelude (`prelude/hw_host.rs`, which has its own std-only reader of this format).
//!
//! File format (all integers little-endian):
//!
//! ```text
//! magic    8 bytes  "TRAXIMG1"
//! count    u32      number of segments
//! count × {
//!   addr   u32      first byte's simulated address, multiple of 4, >= NULL_GUARD_END
//!   len    u32      byte length, multiple of 4
//!   bytes  len bytes
//! }
//! ```
//!
//! Segments do not overlap. Memory outside every segment does not exist (an access is a
//! bad-address error). The header-only builder [`header_only_image`] makes the image a
//! kernel needs when no scene is loaded: scene header, camera and framebuffer.

use crate::abi::{self, Camera, Component, SceneHeader};
use std::path::Path;

/// File magic of a memory image.
pub const IMAGE_MAGIC: &[u8; 8] = b"TRAXIMG1";

/// One contiguous range of initialised simulated memory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    /// Simulated address of `bytes[0]`.
    pub addr: u32,
    /// Contents.
    pub bytes: Vec<u8>,
}

/// A whole memory image.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MemoryImage {
    /// Segments, in file order.
    pub segments: Vec<Segment>,
}

/// Why a memory image could not be read or built.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("not a trax memory image (bad magic)")]
    BadMagic,
    #[error("memory image truncated at byte {offset} (reading {what})")]
    Truncated { offset: usize, what: &'static str },
    #[error("segment {index} at {addr:#010x}: {problem}")]
    BadSegment {
        index: usize,
        addr: u32,
        problem: &'static str,
    },
    #[error("{len} trailing bytes after the last segment")]
    Trailing { len: usize },
}

impl MemoryImage {
    /// Checks alignment, the null guard and overlaps.
    pub fn validate(&self) -> Result<(), ImageError> {
        let mut ranges: Vec<(u64, u64, usize)> = Vec::new();
        for (index, s) in self.segments.iter().enumerate() {
            let bad = |problem| ImageError::BadSegment {
                index,
                addr: s.addr,
                problem,
            };
            if s.addr % 4 != 0 {
                return Err(bad("address is not a multiple of 4"));
            }
            if s.bytes.len() % 4 != 0 {
                return Err(bad("length is not a multiple of 4"));
            }
            if s.addr < abi::NULL_GUARD_END {
                return Err(bad("overlaps the null guard"));
            }
            let end = s.addr as u64 + s.bytes.len() as u64;
            if end > 1 << 32 {
                return Err(bad("extends past the 32-bit address space"));
            }
            ranges.push((s.addr as u64, end, index));
        }
        ranges.sort();
        for w in ranges.windows(2) {
            if w[1].0 < w[0].1 {
                return Err(ImageError::BadSegment {
                    index: w[1].2,
                    addr: w[1].0 as u32,
                    problem: "overlaps another segment",
                });
            }
        }
        Ok(())
    }

    /// Serialises the image.
    pub fn to_bytes(&self) -> Vec<u8> {
        let total: usize = self.segments.iter().map(|s| 8 + s.bytes.len()).sum();
        let mut out = Vec::with_capacity(12 + total);
        out.extend_from_slice(IMAGE_MAGIC);
        out.extend_from_slice(&(self.segments.len() as u32).to_le_bytes());
        for s in &self.segments {
            out.extend_from_slice(&s.addr.to_le_bytes());
            out.extend_from_slice(&(s.bytes.len() as u32).to_le_bytes());
            out.extend_from_slice(&s.bytes);
        }
        out
    }

    /// Parses and validates an image.
    pub fn parse(data: &[u8]) -> Result<MemoryImage, ImageError> {
        let mut pos = 0usize;
        let mut take = |n: usize, what: &'static str| -> Result<&[u8], ImageError> {
            let end = pos.checked_add(n).filter(|&e| e <= data.len());
            let end = end.ok_or(ImageError::Truncated { offset: pos, what })?;
            let s = &data[pos..end];
            pos = end;
            Ok(s)
        };
        if take(8, "magic")? != IMAGE_MAGIC {
            return Err(ImageError::BadMagic);
        }
        let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        let count = word(take(4, "segment count")?);
        let mut segments = Vec::new();
        for _ in 0..count {
            let addr = word(take(4, "segment address")?);
            let len = word(take(4, "segment length")?) as usize;
            let bytes = take(len, "segment bytes")?.to_vec();
            segments.push(Segment { addr, bytes });
        }
        if pos != data.len() {
            return Err(ImageError::Trailing {
                len: data.len() - pos,
            });
        }
        let image = MemoryImage { segments };
        image.validate()?;
        Ok(image)
    }

    /// Reads and parses an image file.
    pub fn read(path: &Path) -> Result<MemoryImage, ImageError> {
        let data = std::fs::read(path).map_err(|source| ImageError::Io {
            path: path.display().to_string(),
            source,
        })?;
        MemoryImage::parse(&data)
    }

    /// Writes the image to a file.
    pub fn write(&self, path: &Path) -> Result<(), ImageError> {
        std::fs::write(path, self.to_bytes()).map_err(|source| ImageError::Io {
            path: path.display().to_string(),
            source,
        })
    }

    /// The `len` bytes at `addr`, if one segment holds all of them.
    pub fn bytes_at(&self, addr: u32, len: usize) -> Option<&[u8]> {
        self.segments.iter().find_map(|s| {
            let off = addr.checked_sub(s.addr)? as usize;
            s.bytes.get(off..off.checked_add(len)?)
        })
    }

    /// The little-endian word at `addr`.
    pub fn u32_at(&self, addr: u32) -> Option<u32> {
        self.bytes_at(addr, 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
}

/// Serialises a scene header exactly as laid out by its `#[repr(C)]` definition.
pub fn header_bytes(h: &SceneHeader) -> Vec<u8> {
    let mut w: Vec<u32> = vec![
        h.magic,
        h.version,
        h.width,
        h.height,
        h.inv_width.to_bits(),
        h.inv_height.to_bits(),
        h.spp,
        h.max_depth,
        h.epsilon.to_bits(),
        h.seed,
    ];
    w.extend(h.background.iter().map(|f| f.to_bits()));
    w.push(h.camera);
    let components: [Component; 11] = [
        h.framebuffer,
        h.bvh_nodes,
        h.triangles,
        h.normals,
        h.texcoords,
        h.material_ids,
        h.materials,
        h.emitters,
        h.point_lights,
        h.bvh_parents,
        h.treelet_ids,
    ];
    for c in components {
        w.push(c.addr);
        w.push(c.count);
    }
    w.extend_from_slice(&h.reserved);
    words_to_bytes(&w)
}

/// Serialises a camera exactly as laid out by its `#[repr(C)]` definition.
pub fn camera_bytes(c: &Camera) -> Vec<u8> {
    let mut w: Vec<f32> = Vec::new();
    for v in [c.eye, c.u, c.v, c.w] {
        w.extend_from_slice(&v);
    }
    w.extend_from_slice(&[c.left, c.right, c.bottom, c.top, c.distance, c.aperture]);
    let bits: Vec<u32> = w.iter().map(|f| f.to_bits()).collect();
    words_to_bytes(&bits)
}

fn words_to_bytes(w: &[u32]) -> Vec<u8> {
    w.iter().flat_map(|x| x.to_le_bytes()).collect()
}

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
    let fb_len = pixels * 12;
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
        magic: abi::SCENE_MAGIC,
        version: abi::SCENE_VERSION,
        width: p.width,
        height: p.height,
        inv_width: 1.0 / p.width as f32,
        inv_height: 1.0 / p.height as f32,
        spp: p.spp,
        max_depth: p.max_depth,
        epsilon: p.epsilon,
        seed: p.seed,
        background: p.background,
        camera: HEADER_ONLY_CAMERA_ADDR,
        framebuffer: Component {
            addr: HEADER_ONLY_FRAMEBUFFER_ADDR,
            count: pixels as u32,
        },
        ..SceneHeader::default()
    };
    let image = MemoryImage {
        segments: vec![
            Segment {
                addr: abi::SCENE_HEADER_ADDR,
                bytes: header_bytes(&header),
            },
            Segment {
                addr: HEADER_ONLY_CAMERA_ADDR,
                bytes: camera_bytes(&p.camera),
            },
            Segment {
                addr: HEADER_ONLY_FRAMEBUFFER_ADDR,
                bytes: vec![0; fb_len as usize],
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
    use std::mem::offset_of;

    #[test]
    fn header_serialisation_matches_repr_c_offsets() {
        // Give fields distinct values, then check each lands at its offset.
        let mut reserved = [0; 8];
        reserved[7] = 44;
        let h = SceneHeader {
            magic: 1,
            version: 2,
            width: 3,
            height: 4,
            seed: 10,
            camera: 14,
            framebuffer: Component {
                addr: 15,
                count: 16,
            },
            treelet_ids: Component {
                addr: 35,
                count: 36,
            },
            reserved,
            ..SceneHeader::default()
        };
        let b = header_bytes(&h);
        assert_eq!(b.len(), abi::SCENE_HEADER_SIZE);
        let at = |off: usize| u32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        assert_eq!(at(offset_of!(SceneHeader, magic)), 1);
        assert_eq!(at(offset_of!(SceneHeader, height)), 4);
        assert_eq!(at(offset_of!(SceneHeader, seed)), 10);
        assert_eq!(at(offset_of!(SceneHeader, camera)), 14);
        assert_eq!(at(offset_of!(SceneHeader, framebuffer) + 4), 16);
        assert_eq!(at(offset_of!(SceneHeader, treelet_ids)), 35);
        assert_eq!(at(offset_of!(SceneHeader, reserved) + 28), 44);
    }

    #[test]
    fn camera_serialisation_matches_repr_c_offsets() {
        let c = look_at_camera([1.0, 2.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, 2.0);
        let b = camera_bytes(&c);
        assert_eq!(b.len(), std::mem::size_of::<Camera>());
        let at = |off: usize| f32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        assert_eq!(at(offset_of!(Camera, eye) + 8), 3.0);
        assert_eq!(at(offset_of!(Camera, right)), c.right);
        assert_eq!(at(offset_of!(Camera, distance)), 1.0);
        assert!((c.right - 2.0 * c.top).abs() < 1e-6);
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
    fn round_trip_and_lookup() {
        let img = header_only_image(&HeaderParams::default()).unwrap();
        let back = MemoryImage::parse(&img.to_bytes()).unwrap();
        assert_eq!(back, img);
        assert_eq!(back.u32_at(abi::SCENE_HEADER_ADDR), Some(abi::SCENE_MAGIC));
        assert_eq!(back.u32_at(abi::SCENE_HEADER_ADDR + 8), Some(128));
        assert_eq!(back.u32_at(0x20), None);
    }

    #[test]
    fn rejects_bad_images() {
        assert!(matches!(
            MemoryImage::parse(b"NOTANIMG\0\0\0\0"),
            Err(ImageError::BadMagic)
        ));
        let mut b = header_only_image(&HeaderParams::default())
            .unwrap()
            .to_bytes();
        b.truncate(b.len() - 1);
        assert!(matches!(
            MemoryImage::parse(&b),
            Err(ImageError::Truncated { .. })
        ));
        let overlap = MemoryImage {
            segments: vec![
                Segment {
                    addr: 0x10000,
                    bytes: vec![0; 8],
                },
                Segment {
                    addr: 0x10004,
                    bytes: vec![0; 4],
                },
            ],
        };
        assert!(matches!(
            MemoryImage::parse(&overlap.to_bytes()),
            Err(ImageError::BadSegment { index: 1, .. })
        ));
        let null = MemoryImage {
            segments: vec![Segment {
                addr: 0,
                bytes: vec![0; 4],
            }],
        };
        assert!(null.validate().is_err());
        let p = HeaderParams {
            width: 0,
            ..HeaderParams::default()
        };
        assert!(header_only_image(&p).is_err());
    }
}
