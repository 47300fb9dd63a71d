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

use trax::ray::SurfacePoint;
use trax::{Ray, Vec3};

/// Direct light at surface point `sp` (diffuse albedo `albedo`) from one uniformly chosen
/// emissive triangle and every point light, with shadow rays.
fn direct_light(sp: &SurfacePoint, albedo: Vec3) -> Vec3 {
    let brdf = albedo.scale(1.0 / trax::PI);
    let n = sp.n;
    let origin = sp.origin();
    let mut sum = Vec3::zero();
    let emitters = trax::scene::emitter_count();
    if emitters > 0 {
        let mut k = (trax::rand() * emitters as f32) as u32;
        if k >= emitters {
            k = emitters - 1;
        }
        let tri_index = trax::scene::emitter(k);
        let tri = trax::scene::triangle(tri_index);
        let q = trax::sampling::triangle_point(&tri);
        // Direction, distance, area / distance² and the light's normal, right at every
        // scale.
        let eg = trax::sampling::emitter_geometry(&tri, origin, q);
        let l = eg.dir;
        let dist = eg.dist;
        let cos_surf = n.dot(l);
        let cos_light = eg.normal.dot(l).abs();
        if cos_surf > 0.0 && cos_light > 0.0 {
            // Stop just short of the light so its own triangle does not occlude.
            if !trax::bvh::occluded(&Ray::new(origin, l), 0.0, dist * (1.0 - 1e-4)) {
                let mat = trax::scene::triangle_material(tri_index);
                // pdf (area) = 1 / (emitters * area); solid-angle conversion cos_light / d².
                let g = cos_surf * cos_light / eg.dist2 * eg.area * emitters as f32;
                sum += brdf * mat.emission.scale(g);
            }
        }
    }
    let lights = trax::scene::point_light_count();
    for k in 0..lights {
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
    let mut depth: u32 = 0;
    loop {
        let hit = trax::bvh::intersect(&ray, 0.0, trax::INFINITY);
        if !hit.is_hit() {
            l += throughput * trax::scene::background();
            break;
        }
        let mat = trax::scene::triangle_material(hit.tri);
        if depth == 0 {
            l += mat.emission;
        }
        // New rays start just off the surface, by the hit point's rounding error.
        let sp = SurfacePoint::new(&ray, &hit, &trax::scene::triangle(hit.tri));
        l += throughput * direct_light(&sp, mat.diffuse);
        depth += 1;
        if depth >= max_depth || mat.diffuse.is_black() {
            break;
        }
        // Cosine sampling: brdf * cos / pdf = albedo.
        throughput *= mat.diffuse;
        ray = Ray::new(sp.origin(), trax::sampling::cosine_hemisphere(sp.n));
    }
    l
}

fn trax_main() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let max_depth = trax::scene::max_depth();
    let mut spp = trax::scene::spp();
    if spp == 0 {
        spp = 1;
    }
    let inv_spp = 1.0 / spp as f32;
    // Pixels are handed out dynamically; each sample seeds its own random stream, so the
    // image is the same on every chip and natively.
    let mut share = trax::scene::pixel_share();
    loop {
        let i = share.next_pixel();
        if i == trax::scene::NO_PIXEL {
            break;
        }
        let mut c = Vec3::zero();
        for s in 0..spp {
            trax::seed_pixel(i, s);
            c += radiance(cam.jittered_ray(i % w, i / w), max_depth);
        }
        trax::scene::set_pixel_index(i, c.scale(inv_spp));
    }
}
