//! Checks the resumable bit-stack traversal (`trax::bvh::Traversal`) against the stack
//! traversal (`trax::bvh::intersect` / `occluded`) ray by ray: camera rays, diffuse
//! bounces from each hit and shadow rays to every point light and to random points, with
//! the traversal's state stored as its two words and restored before every step (as a
//! streaming ray is). Prints the ray count and the mismatches in the hit triangle, the
//! bits of `t`, `u`, `v` and the occlusion answer.
//!
//! `BROKEN` (set by a test in a copy of this file) makes the traversal forget a pending
//! sibling now and then (it flips the stack's top bit before an up step), which the check
//! must catch.

use trax::bvh::{BvhArrays, SoftTests, Traversal};
use trax::ray::SurfacePoint;
use trax::{Hit, Ray, Vec3};

const BROKEN: bool = false;

const RAYS_REG: u32 = 0;
const BAD_REG: u32 = 1;
const DONE_REG: u32 = 2;

/// The closest (or, with `any`, some) hit by steps of a traversal restored from its words
/// before each step.
fn by_steps(ray: &Ray, t_max: f32, any: bool, broken: bool) -> Hit {
    let b = BvhArrays::load();
    let root = trax::scene::bvh_node_at(b.nodes, 0);
    let x = SoftTests::new(ray, 0.0, trax::bvh::node_bound(&root));
    let mut hit = Hit::none(t_max);
    let mut words = (Traversal::new().word, Traversal::new().stack.bits);
    let mut steps: u32 = 0;
    loop {
        let mut t = Traversal::from_words(words.0, words.1);
        if t.is_done() {
            return hit;
        }
        if broken && steps % 7 == 3 && t.word >> 30 == 3 {
            t.stack.bits ^= 1;
        }
        t.step(&x, &b, &mut hit, any);
        words = (t.word, t.stack.bits);
        steps += 1;
    }
}

fn same(a: &Hit, b: &Hit) -> bool {
    a.tri == b.tri
        && a.t.to_bits() == b.t.to_bits()
        && a.u.to_bits() == b.u.to_bits()
        && a.v.to_bits() == b.v.to_bits()
}

/// Checks one closest-hit query both ways (and through `intersect_bitstack`); returns the
/// stack traversal's hit and the mismatches.
fn check_closest(ray: &Ray) -> (Hit, u32) {
    let a = trax::bvh::intersect(ray, 0.0, trax::INFINITY);
    let b = by_steps(ray, trax::INFINITY, false, BROKEN);
    let c = trax::bvh::intersect_bitstack(ray, 0.0, trax::INFINITY);
    let bad = if same(&a, &b) && same(&a, &c) { 0 } else { 1 };
    (a, bad)
}

/// Checks one occlusion query both ways; returns the mismatches.
fn check_occluded(ray: &Ray, t_max: f32) -> u32 {
    let a = trax::bvh::occluded(ray, 0.0, t_max);
    let b = by_steps(ray, t_max, true, BROKEN).is_hit();
    let c = trax::bvh::occluded_bitstack(ray, 0.0, t_max);
    if a == b && a == c {
        0
    } else {
        1
    }
}

fn trax_main() {
    let cam = trax::Camera::load();
    let w = trax::scene::width();
    let mut share = trax::scene::pixel_share();
    let mut rays: u32 = 0;
    let mut bad: u32 = 0;
    loop {
        let i = share.next_pixel();
        if i == trax::scene::NO_PIXEL {
            break;
        }
        trax::seed_pixel(i, 0);
        let mut ray = cam.jittered_ray(i % w, i / w);
        // A camera ray and up to three diffuse bounces, shadow rays at each hit.
        for _ in 0..4 {
            let (hit, b) = check_closest(&ray);
            rays += 1;
            bad += b;
            if !hit.is_hit() {
                break;
            }
            let sp = SurfacePoint::new(&ray, &hit, &trax::scene::triangle(hit.tri));
            let o = sp.origin();
            for k in 0..trax::scene::point_light_count() {
                let to = trax::scene::point_light(k).position - o;
                bad += check_occluded(&Ray::new(o, to.normalize()), to.length());
                rays += 1;
            }
            // Towards a random point of the scene's box, unbounded and bounded.
            let root = trax::scene::bvh_node(0);
            let q = Vec3::new(
                root.min.x + (root.max.x - root.min.x) * trax::rand(),
                root.min.y + (root.max.y - root.min.y) * trax::rand(),
                root.min.z + (root.max.z - root.min.z) * trax::rand(),
            );
            let d = q - o;
            bad += check_occluded(&Ray::new(o, d), 1.0);
            bad += check_occluded(&Ray::new(o, d), trax::INFINITY);
            rays += 2;
            ray = Ray::new(o, trax::sampling::cosine_hemisphere(sp.n));
        }
    }
    trax::atomic_add(RAYS_REG, rays);
    trax::atomic_add(BAD_REG, bad);
    trax::barrier(DONE_REG);
    if trax::global_id() == 0 {
        println!(
            "rays {} mismatches {}",
            trax::global_read(RAYS_REG),
            trax::global_read(BAD_REG)
        );
    }
}
