#[derive(Clone, Copy)]
enum Material {
    Diffuse(f32),
    Mirror,
    Glass { ior: f32 },
}

fn albedo(m: Material) -> f32 {
    match m {
        Material::Diffuse(a) => a,
        Material::Mirror => 1.0,
        Material::Glass { ior } if ior > 1.4 => 0.9,
        Material::Glass { .. } => 0.5,
    }
}

fn trax_main() {
    let m = if trax::global_id() == 0 { Material::Diffuse(0.25) } else { Material::Glass { ior: 1.5 } };
    trax::store_f32(0, albedo(m));
}
