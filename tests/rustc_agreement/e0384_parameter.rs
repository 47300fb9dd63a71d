// Function parameters are immutable unless declared `mut`.
fn clamp_depth(depth: u32) -> u32 {
    if depth > 8 {
        depth = 8; //~ E0384
    }
    depth
}

fn trax_main() {
    println!("{}", clamp_depth(10));
}
