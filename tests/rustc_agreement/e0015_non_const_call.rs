// A non-`const` function called in a constant.
fn tile_size() -> u32 {
    16
}

const TILE: u32 = tile_size(); //~ E0015

fn trax_main() {
    println!("{}", TILE);
}
