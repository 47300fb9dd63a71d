//! Ray for ray, what the prelude's ray tracing answers (`tests/cpp_kernels.rs` compares it
//! with `hits.cpp`, the same rays through `trax.hpp`): 2048 rays of four kinds — camera
//! rays, rays from random points of the scene's box in random directions, diffuse rays
//! leaving a surface point (`SurfacePoint::origin`, the conservative `t` bound keeps them
//! off their own triangle) and shadow rays towards a random point of a random triangle
//! (`emitter_geometry`, `t_max` short of it) — each with its closest hit, any-hit over the
//! same interval and before the closest hit, and the hit's surface point, as f32 bits.

use trax::ray::SurfacePoint;
use trax::{Camera, Hit, Ray, Vec3};

const RAYS: u32 = 2048;

/// The surface point of `hit` (one call site of `SurfacePoint::new`).
fn surface_point(ray: &Ray, hit: &Hit) -> SurfacePoint {
    SurfacePoint::new(ray, hit, &trax::scene::triangle(hit.tri))
}

fn v3(v: Vec3) {
    print!(" {} {} {}", v.x.to_bits(), v.y.to_bits(), v.z.to_bits());
}

/// What a shadow ray (kind 3) also prints: the emitter geometry it was built from.
struct Extra {
    miss: bool,
    eg: Option<trax::sampling::EmitterGeometry>,
}

const NONE: Extra = Extra {
    miss: false,
    eg: None,
};

/// One line: ray, closest hit, any-hit, surface point.
fn record(r: u32, ray: &Ray, t_max: f32, extra: &Extra) {
    let hit = trax::bvh::intersect(ray, 0.0, t_max);
    let any = trax::bvh::occluded(ray, 0.0, t_max) as u32;
    let before = trax::bvh::occluded(ray, 0.0, hit.t) as u32;
    print!("{r} ray");
    v3(ray.origin);
    v3(ray.dir);
    print!(" tmax {} hit {}", t_max.to_bits(), hit.tri);
    print!(" {} {} {}", hit.t.to_bits(), hit.u.to_bits(), hit.v.to_bits());
    print!(" any {any} {before}");
    if hit.is_hit() {
        let s = surface_point(ray, &hit);
        print!(" p");
        v3(s.p);
        print!(" n");
        v3(s.n);
        print!(" o {}", s.offset.to_bits());
    }
    if extra.miss {
        print!(" miss");
    }
    if let Some(eg) = &extra.eg {
        print!(" eg");
        v3(eg.dir);
        print!(" {} {} {}", eg.dist.to_bits(), eg.dist2.to_bits(), eg.area.to_bits());
        v3(eg.normal);
    }
    println!();
}

fn trax_main() {
    let cam = Camera::load();
    let (w, h) = (trax::scene::width() as f32, trax::scene::height() as f32);
    let root = trax::scene::bvh_node(0);
    let n = trax::scene::triangle_count();
    loop {
        let r = trax::atomic_inc(0);
        if r >= RAYS {
            break;
        }
        trax::seed_pixel(r, 7);
        let px = trax::rand() * w;
        let py = trax::rand() * h;
        let camera_ray = cam.ray(px, py);
        match r % 4 {
            0 => record(r, &camera_ray, trax::INFINITY, &NONE),
            1 => {
                let fx = trax::rand();
                let fy = trax::rand();
                let fz = trax::rand();
                let o = root.min + (root.max - root.min) * Vec3::new(fx, fy, fz);
                let d = trax::sampling::unit_sphere();
                record(r, &Ray::new(o, d), trax::INFINITY, &NONE);
            }
            k => {
                let hit = trax::bvh::intersect(&camera_ray, 0.0, trax::INFINITY);
                if !hit.is_hit() {
                    record(r, &camera_ray, trax::INFINITY, &Extra { miss: true, eg: None });
                    continue;
                }
                let sp = surface_point(&camera_ray, &hit);
                let origin = sp.origin();
                if k == 2 {
                    let d = trax::sampling::cosine_hemisphere(sp.n);
                    record(r, &Ray::new(origin, d), trax::INFINITY, &NONE);
                } else {
                    let j = ((trax::rand() * n as f32) as u32).min(n - 1);
                    let tri = trax::scene::triangle(j);
                    let q = trax::sampling::triangle_point(&tri);
                    let eg = trax::sampling::emitter_geometry(&tri, origin, q);
                    let extra = Extra {
                        miss: false,
                        eg: Some(eg),
                    };
                    record(r, &Ray::new(origin, eg.dir), eg.dist * (1.0 - 1e-4), &extra);
                }
            }
        }
    }
}
