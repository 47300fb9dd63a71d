// Moving a non-`Copy` element out of an array by index.
struct Light {
    power: f32,
}

fn trax_main() {
    let lights = [Light { power: 1.0 }, Light { power: 2.0 }];
    let l = lights[0]; //~ E0508
    println!("{}", l.power);
}
