//! The pinhole camera (`abi::Camera` semantics) and primary-ray generation.

use super::layout;
use super::math::Vec3;
use super::ray::Ray;
use super::scene;

/// The scene camera plus the image size, ready to generate primary rays.
#[derive(Clone, Copy)]
pub struct Camera {
    pub eye: Vec3,
    pub u: Vec3,
    pub v: Vec3,
    pub w: Vec3,
    pub left: f32,
    pub right: f32,
    pub bottom: f32,
    pub top: f32,
    pub distance: f32,
    pub inv_width: f32,
    pub inv_height: f32,
}

impl Camera {
    /// Loads the scene's camera (header field `camera`) and image size.
    pub fn load() -> Camera {
        let a = scene::camera_addr();
        Camera {
            eye: scene::load_vec3(a + layout::CAM_EYE),
            u: scene::load_vec3(a + layout::CAM_U),
            v: scene::load_vec3(a + layout::CAM_V),
            w: scene::load_vec3(a + layout::CAM_W),
            left: super::hw::load_f32(a + layout::CAM_LEFT),
            right: super::hw::load_f32(a + layout::CAM_RIGHT),
            bottom: super::hw::load_f32(a + layout::CAM_BOTTOM),
            top: super::hw::load_f32(a + layout::CAM_TOP),
            distance: super::hw::load_f32(a + layout::CAM_DISTANCE),
            inv_width: scene::inv_width(),
            inv_height: scene::inv_height(),
        }
    }

    /// The ray through image position `(px, py)` in pixel units, `px` from the left edge
    /// and `py` from the TOP edge (row 0 is the top row), so `(x + 0.5, y + 0.5)` is the
    /// centre of pixel `(x, y)`. Image-plane coordinates: `s = left + (right-left)*px/W`,
    /// `t = top - (top-bottom)*py/H` (equivalently `abi::Camera`'s formula with rows
    /// counted from the bottom).
    pub fn ray(&self, px: f32, py: f32) -> Ray {
        let s = self.left + (self.right - self.left) * (px * self.inv_width);
        let t = self.top - (self.top - self.bottom) * (py * self.inv_height);
        let d = self.w.scale(self.distance) + self.u.scale(s) + self.v.scale(t);
        Ray::new(self.eye, d.normalize())
    }

    /// The ray through the centre of pixel `(x, y)` (row 0 at the top).
    pub fn pixel_ray(&self, x: u32, y: u32) -> Ray {
        self.ray(x as f32 + 0.5, y as f32 + 0.5)
    }

    /// A ray through a uniformly random point of pixel `(x, y)` (uses `trax::rand`).
    pub fn jittered_ray(&self, x: u32, y: u32) -> Ray {
        let jx = super::rand();
        let jy = super::rand();
        self.ray(x as f32 + jx, y as f32 + jy)
    }
}
