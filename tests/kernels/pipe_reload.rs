//! The pipelines' input registers hold the ray of the thread's last pipeline load, whether
//! a `PipeTests` loaded it or `pipe::box_test`/`pipe::tri_test` did (each loads its own
//! ray): a `PipeTests` made for ray A, then a one-off test of ray B, then the `PipeTests`'
//! test again, tests ray B on the machine, so the host must too. Prints each result.

use trax::pipe::{self, PipeTests};
use trax::{Ray, Triangle, Vec3};

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let tri = Triangle {
        v0: Vec3::new(-1.0, -1.0, 0.0),
        v1: Vec3::new(1.0, -1.0, 0.0),
        v2: Vec3::new(0.0, 1.0, 0.0),
    };
    // A hits the triangle at t = 2; B passes beside it.
    let a = Ray::new(Vec3::new(0.0, 0.0, -2.0), Vec3::new(0.0, 0.0, 1.0));
    let b = Ray::new(Vec3::new(5.0, 5.0, -3.0), Vec3::new(0.0, 0.0, 1.0));
    pipe::use_triangle_pipeline();
    let tests = PipeTests::new(&a, 2);
    println!("A: {}", tests.tri(&tri).t);
    println!("B alone: {}", pipe::tri_test(&b, &tri).t);
    println!("A's tests after B: {}", tests.tri(&tri).t);
    pipe::use_box_pipeline();
    let lo = Vec3::new(-1.0, -1.0, -0.5);
    let hi = Vec3::new(1.0, 1.0, 0.5);
    let inv = |r: &Ray| Vec3::new(1.0 / r.dir.x, 1.0 / r.dir.y, 1.0 / r.dir.z);
    println!("box, A: {}", pipe::box_test(a.origin, inv(&a), lo, hi));
    println!("box, B: {}", pipe::box_test(b.origin, inv(&b), lo, hi));
    pipe::use_general_units();
}
