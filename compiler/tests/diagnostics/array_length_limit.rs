static GRID: [u8; 1 << 25] = [0; 1 << 25];

fn trax_main() {
    println!("{}", GRID[0]);
}
