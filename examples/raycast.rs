//! Ray caster: one primary ray per pixel through the BVH, Lambertian shading by every point
//! light with a hard shadow ray each, plus a small ambient term and emission. Point lights
//! are not attenuated with distance (simtrax ray-caster style).

use trax::ray::SurfacePoint;
use trax::{Ray, Vec3};

/// Ambient fraction of the diffuse colour.
const AMBIENT: f32 = 0.1;

/// Colour seen along `ray`.
fn trace(ray: &Ray) -> Vec3 {
    let hit = trax::bvh::intersect(ray, 0.0, trax::INFINITY);
    if !hit.is_hit() {
        return trax::scene::background();
    }
    let mat = trax::scene::triangle_material(hit.tri);
    // Hit point and geometric normal facing the viewer; shadow rays start just off the
    // surface, by the hit point's rounding error.
    let sp = SurfacePoint::new(ray, &hit, &trax::scene::triangle(hit.tri));
    let n = sp.n;
    let origin = sp.origin();
    let mut c = mat.emission + mat.diffuse.scale(AMBIENT);
    let lights = trax::scene::point_light_count();
    for k in 0..lights {
        let light = trax::scene::point_light(k);
        let to_light = light.position - origin;
        let dist = to_light.length();
        let l = to_light.scale(1.0 / dist);
        let cos = n.dot(l);
        if cos > 0.0 {
            let shadow = Ray::new(origin, l);
            if !trax::bvh::occluded(&shadow, 0.0, dist) {
                c += mat.diffuse * light.color.scale(cos);
            }
        }
    }
    c
}

fn trax_main() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let n = w * trax::scene::height();
    // Pixels come from global register 0 (sampled simulation follows it).
    trax::declare_work(0, n);
    loop {
        let i = trax::atomic_inc(0);
        if i >= n {
            break;
        }
        let ray = cam.pixel_ray(i % w, i / w);
        trax::scene::set_pixel_index(i, trace(&ray));
    }
}
