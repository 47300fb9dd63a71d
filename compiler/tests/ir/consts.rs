const fn cube(x: u32) -> u32 {
    x * x * x
}

const TABLE: [u32; 3] = [cube(1), cube(2), cube(3)];
static LIMIT: u32 = cube(4) + 1;

fn trax_main() {
    let i = trax::global_id() as usize % 3;
    trax::store_u32(0, TABLE[i] + LIMIT);
}
