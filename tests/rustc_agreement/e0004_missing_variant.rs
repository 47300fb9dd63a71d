// A `match` that misses an enum variant.
#[derive(Clone, Copy)]
enum Material {
    Diffuse,
    Mirror,
    Glass,
}

fn albedo(m: Material) -> f32 {
    match m { //~ E0004
        Material::Diffuse => 0.8,
        Material::Mirror => 1.0,
    }
}

fn trax_main() {
    println!("{}", albedo(Material::Glass));
}
