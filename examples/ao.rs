//! Ambient occlusion: one primary ray per pixel, then `spp` (at least 1) cosine-weighted
//! occlusion rays per hit point, each limited to a radius of a fifth of the scene's
//! diagonal. The pixel is the unoccluded fraction times the surface's diffuse colour.

use trax::ray::SurfacePoint;
use trax::Ray;

/// AO radius as a multiple of the header epsilon (which is 1e-4 × the scene diagonal).
const RADIUS_IN_EPSILONS: f32 = 2000.0;

fn trax_main() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let eps = trax::scene::epsilon();
    let radius = eps * RADIUS_IN_EPSILONS;
    let mut samples = trax::scene::spp();
    if samples == 0 {
        samples = 1;
    }
    // Pixels are handed out dynamically; each sample seeds its own random stream, so the
    // image is the same on every chip and natively.
    let mut share = trax::scene::pixel_share();
    loop {
        let i = share.next_pixel();
        if i == trax::scene::NO_PIXEL {
            break;
        }
        let ray = cam.pixel_ray(i % w, i / w);
        let hit = trax::bvh::intersect(&ray, 0.0, trax::INFINITY);
        let mut c = trax::scene::background();
        if hit.is_hit() {
            // Occlusion rays start just off the surface, by the hit point's rounding error.
            let sp = SurfacePoint::new(&ray, &hit, &trax::scene::triangle(hit.tri));
            let origin = sp.origin();
            let mut open = 0u32;
            for s in 0..samples {
                trax::seed_pixel(i, s);
                let d = trax::sampling::cosine_hemisphere(sp.n);
                if !trax::bvh::occluded(&Ray::new(origin, d), 0.0, radius) {
                    open += 1;
                }
            }
            let mat = trax::scene::triangle_material(hit.tri);
            c = mat.diffuse.scale(open as f32 / samples as f32) + mat.emission;
        }
        trax::scene::set_pixel_index(i, c);
    }
}
