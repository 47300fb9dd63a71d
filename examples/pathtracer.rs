//! Path tracer (Kajiya 1986): Lambertian materials, emissive triangles and point lights,
//! next-event estimation at every vertex, cosine-weighted continuation, `max_depth`
//! bounces and `spp` jittered samples per pixel (both from the scene header). Each sample
//! draws from its own random stream (`trax::seed_pixel`), so the image does not depend on
//! which thread renders which pixel.
//!
//! Emission reaches the image either directly (camera rays) or through light sampling;
//! a continuation ray that hits an emitter adds nothing, so no light is counted twice.
//! Emitters emit from both faces. Point lights are isotropic with intensity `color`
//! (falloff 1/d²).

use core::f32::consts::{FRAC_1_PI, TAU};
use trax::ray::SurfacePoint;
use trax::sampling::Onb;
use trax::{Hit, Ray, Vec3};

/// What a triangle's material does to light.
#[derive(Clone, Copy)]
enum Surface {
    /// A Lambertian reflector.
    Diffuse { albedo: Vec3 },
    /// A light source (which may also reflect).
    Emitter { emission: Vec3, albedo: Vec3 },
}

impl Surface {
    /// The surface of triangle `tri`.
    fn of(tri: u32) -> Surface {
        let m = trax::scene::triangle_material(tri);
        if m.emission.is_black() {
            Surface::Diffuse { albedo: m.diffuse }
        } else {
            Surface::Emitter {
                emission: m.emission,
                albedo: m.diffuse,
            }
        }
    }

    fn albedo(&self) -> Vec3 {
        match *self {
            Surface::Diffuse { albedo } | Surface::Emitter { albedo, .. } => albedo,
        }
    }

    fn emission(&self) -> Option<Vec3> {
        match *self {
            Surface::Emitter { emission, .. } => Some(emission),
            Surface::Diffuse { .. } => None,
        }
    }
}

/// The closest hit along `ray`, if any.
fn trace(ray: &Ray) -> Option<Hit> {
    let hit = trax::bvh::intersect(ray, 0.0, trax::INFINITY);
    if hit.is_hit() {
        Some(hit)
    } else {
        None
    }
}

/// A cosine-weighted random direction around unit normal `n` (pdf = cos(theta) / pi),
/// by inverting the distribution: radius sqrt(u1), angle 2 pi u2.
fn cosine_sample(n: Vec3) -> Vec3 {
    let r2 = trax::rand();
    let phi = TAU * trax::rand();
    let r = r2.sqrt();
    let (s, c) = phi.sin_cos();
    let z = (1.0 - r2).max(0.0).sqrt();
    Onb::new(n).to_world(Vec3::new(r * c, r * s, z))
}

/// Direct light at surface point `sp` (diffuse albedo `albedo`) from one uniformly chosen
/// emissive triangle and every point light, with shadow rays.
fn direct_light(sp: &SurfacePoint, albedo: Vec3) -> Vec3 {
    let brdf = albedo.scale(FRAC_1_PI);
    let n = sp.n;
    let origin = sp.origin();
    let mut sum = Vec3::zero();
    let emitters = trax::scene::emitter_count();
    if emitters > 0 {
        let k = ((trax::rand() * emitters as f32) as u32).min(emitters - 1);
        let tri_index = trax::scene::emitter(k);
        let tri = trax::scene::triangle(tri_index);
        let q = trax::sampling::triangle_point(&tri);
        // Direction, distance, area / distance² and the light's normal, right at every
        // scale.
        let eg = trax::sampling::emitter_geometry(&tri, origin, q);
        let cos_surf = n.dot(eg.dir);
        let cos_light = eg.normal.dot(eg.dir).abs();
        // Stop just short of the light so its own triangle does not occlude.
        if cos_surf > 0.0
            && cos_light > 0.0
            && !trax::bvh::occluded(&Ray::new(origin, eg.dir), 0.0, eg.dist * (1.0 - 1e-4))
        {
            if let Some(emission) = Surface::of(tri_index).emission() {
                // pdf (area) = 1 / (emitters * area); solid-angle conversion cos_light / d².
                let g = cos_surf * cos_light / eg.dist2 * eg.area * emitters as f32;
                sum += brdf * emission.scale(g);
            }
        }
    }
    for k in 0..trax::scene::point_light_count() {
        let light = trax::scene::point_light(k);
        let to_light = light.position - origin;
        let dist2 = to_light.length_squared();
        // Direction and distance right at every scale (`length` rescales; `dist2` may
        // overflow, giving the contribution's limit of 0).
        let dist = to_light.length();
        let l = to_light.scale(1.0 / dist);
        let cos = n.dot(l);
        if cos > 0.0 && !trax::bvh::occluded(&Ray::new(origin, l), 0.0, dist) {
            sum += brdf * light.color.scale(cos / dist2);
        }
    }
    sum
}

/// Radiance along a camera ray.
fn radiance(camera_ray: Ray, max_depth: u32) -> Vec3 {
    let mut ray = camera_ray;
    let mut throughput = Vec3::splat(1.0);
    let mut l = Vec3::zero();
    for depth in 0..max_depth.max(1) {
        let Some(hit) = trace(&ray) else {
            l += throughput * trax::scene::background();
            break;
        };
        let surface = Surface::of(hit.tri);
        if let (0, Some(emission)) = (depth, surface.emission()) {
            l += emission;
        }
        // New rays start just off the surface, by the hit point's rounding error.
        let sp = SurfacePoint::new(&ray, &hit, &trax::scene::triangle(hit.tri));
        let albedo = surface.albedo();
        l += throughput * direct_light(&sp, albedo);
        if depth + 1 >= max_depth || albedo.is_black() {
            break;
        }
        // Cosine sampling: brdf * cos / pdf = albedo.
        throughput *= albedo;
        ray = Ray::new(sp.origin(), cosine_sample(sp.n));
    }
    l
}

/// The next pixel this thread renders, if any are left.
fn next_pixel(share: &mut trax::scene::PixelShare) -> Option<u32> {
    match share.next_pixel() {
        trax::scene::NO_PIXEL => None,
        i => Some(i),
    }
}

fn trax_main() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let max_depth = trax::scene::max_depth();
    let spp = trax::scene::spp().max(1);
    let inv_spp = 1.0 / spp as f32;
    // Pixels are handed out dynamically; each sample seeds its own random stream, so the
    // image is the same on every chip and natively.
    let mut share = trax::scene::pixel_share();
    while let Some(i) = next_pixel(&mut share) {
        let mut c = Vec3::zero();
        for s in 0..spp {
            trax::seed_pixel(i, s);
            c += radiance(cam.jittered_ray(i % w, i / w), max_depth);
        }
        trax::scene::set_pixel_index(i, c.scale(inv_spp));
    }
}
