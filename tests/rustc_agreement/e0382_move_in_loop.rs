// A value moved in one iteration of a loop is gone in the next.
struct Photon {
    power: f32,
}

fn absorb(p: Photon) -> f32 {
    p.power
}

fn trax_main() {
    let p = Photon { power: 2.0 };
    let mut total = 0.0;
    for _ in 0..3 {
        total += absorb(p); //~ E0382
    }
    println!("{}", total);
}
