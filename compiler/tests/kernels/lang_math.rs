//! TRaX-Rust language suite, part 5: float and integer helpers without libm —
//! `rem_euclid`, `div_euclid`, `signum`, `copysign`, `to_radians`, `to_degrees`,
//! `clamp`, `total_cmp`, `partial_cmp`, `f32::consts`/`f64::consts`, `abs_diff`,
//! integer `signum`/`rem_euclid`/`pow`/`cmp`, `core::cmp::min`/`max`.

use std::f32::consts::{FRAC_PI_2, PI};

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    let xs = [7.5f32, -7.5, 0.0, -0.0, 3.0, f32::INFINITY, f32::NAN, 1e-40];
    for x in xs {
        println!(
            "{:?}: rem {:?} {:?} div {:?} {:?} signum {:?} copysign {:?} rad {:?} deg {:?} clamp {:?}",
            x,
            x.rem_euclid(2.0),
            x.rem_euclid(-2.0),
            x.div_euclid(2.0),
            x.div_euclid(-2.0),
            x.signum(),
            1.5f32.copysign(x),
            x.to_radians(),
            x.to_degrees(),
            x.clamp(-1.0, 1.0),
        );
    }
    let ys = [7.5f64, -7.25, 1e300, -0.0];
    for y in ys {
        println!("{:?}: {:?} {:?} {:?} {:?} {:?}", y, y.rem_euclid(3.0), y.div_euclid(3.0), y.signum(), y.to_radians(), y.to_degrees());
    }
    println!("consts {:?} {:?} {:?} {:?} {:?}", PI, FRAC_PI_2, std::f64::consts::E, std::f32::consts::TAU, core::f32::consts::SQRT_2);
    println!("cmp {:?} {:?} {:?} {:?}", 1.0f32.total_cmp(&-0.0), (-0.0f32).total_cmp(&0.0), f32::NAN.total_cmp(&1.0), 2.0f64.partial_cmp(&2.0));
    for i in [-7i32, 7, 0, i32::MIN + 1] {
        println!("{}: {} {} {} {} {}", i, i.signum(), i.rem_euclid(3), i.div_euclid(3), i.abs_diff(5), i.rem_euclid(-4));
    }
    println!("u {} {} {:?} {:?}", 7u32.abs_diff(10), 3u8.pow(5), 4u32.cmp(&9), 'b'.cmp(&'a'));
    println!("minmax {} {} {} {}", core::cmp::min(3, -2), std::cmp::max(3u8, 9), std::cmp::min('x', 'c'), 5i64.max(-9).min(2));
}
