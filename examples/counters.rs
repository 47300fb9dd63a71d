//! Custom statistics counters (`trax::stat`): a ray caster that counts what its rays do
//! — primary hits and misses, shadow rays and the occluded ones — in counters 1 to 4.
//! `trax run` reports them in its summary (`counters: [1] ...`) and in the stats
//! document (`counters`), `trax native` in its summary; they are the same on every chip,
//! in functional and timing mode, and natively. Counter 0 counts every ray the BVH
//! traversal casts (`rays`).

use trax::ray::SurfacePoint;
use trax::{stat, Ray, Vec3};

/// Primary rays that hit the scene.
const HITS: u32 = 1;
/// Primary rays that leave it.
const MISSES: u32 = 2;
/// Shadow rays cast towards the first point light.
const SHADOW_RAYS: u32 = 3;
/// Shadow rays that found something in the way.
const SHADOWED: u32 = 4;

/// Grey by the cosine to the light, zero in shadow; the background on a miss.
fn shade(ray: &Ray) -> Vec3 {
    let hit = trax::bvh::intersect(ray, 0.0, trax::INFINITY);
    if !hit.is_hit() {
        stat::inc(MISSES);
        return trax::scene::background();
    }
    stat::inc(HITS);
    let sp = SurfacePoint::new(ray, &hit, &trax::scene::triangle(hit.tri));
    let light = trax::scene::point_light(0);
    let to_light = light.position - sp.origin();
    let dist = to_light.length();
    let l = to_light.scale(1.0 / dist);
    let cos = sp.n.dot(l);
    if cos <= 0.0 {
        return Vec3::zero();
    }
    stat::inc(SHADOW_RAYS);
    if trax::bvh::occluded(&Ray::new(sp.origin(), l), 0.0, dist) {
        stat::inc(SHADOWED);
        return Vec3::zero();
    }
    Vec3::splat(cos)
}

fn trax_main() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let n = w * trax::scene::height();
    loop {
        let i = trax::atomic_inc(0);
        if i >= n {
            break;
        }
        let c = shade(&cam.pixel_ray(i % w, i / w));
        trax::scene::set_pixel_index(i, c);
    }
}
