#[derive(Clone, Copy, Debug)]
struct P {
    x: f32,
    n: u8,
}

fn trax_main() {
    let p = P { x: trax::rand(), n: 3 };
    println!("{:>8.3} {:?} {:x}", p.x, p, trax::global_id());
}
