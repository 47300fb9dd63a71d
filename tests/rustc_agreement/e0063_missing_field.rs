// A struct expression missing a field.
struct Vec2 {
    x: f32,
    y: f32,
}

fn trax_main() {
    let v = Vec2 { x: 1.0 }; //~ E0063
    println!("{} {}", v.x, v.y);
}
