// A value used after it was moved into a function.
#[derive(Debug)]
struct Ray {
    t: f32,
}

fn consume(r: Ray) -> f32 {
    r.t
}

fn trax_main() {
    let r = Ray { t: 1.0 };
    let a = consume(r);
    println!("{} {}", a, r.t); //~ E0382
}
