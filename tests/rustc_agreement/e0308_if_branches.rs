// `if` branches of different types.
fn trax_main() {
    let c = trax::global_id() > 3;
    let v = if c { 1u32 } else { 2.0f32 }; //~ E0308
    println!("{}", v);
}
