// A private function of an inline module.
mod shading {
    fn fresnel(c: f32) -> f32 {
        c * c
    }

    pub fn shade(c: f32) -> f32 {
        fresnel(c)
    }
}

fn trax_main() {
    println!("{} {}", shading::shade(0.5), shading::fresnel(0.5)); //~ E0603
}
