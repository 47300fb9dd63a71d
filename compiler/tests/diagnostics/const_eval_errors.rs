const DIV: i32 = 1 / 0;
const REM: i32 = 5 % 0;
const ADD: u8 = 255 + 1;
const SHIFT: u32 = 1 << 32;
const MIN_DIV: i32 = i32::MIN / -1;
static NEG: i32 = -i32::MIN;
const LEN: usize = 3 - 4;

struct S;

impl S {
    const MUL: u16 = 300 * 300;
}

fn trax_main() {
    let a = [0u32; LEN];
    println!("{} {} {} {} {} {} {} {}", DIV, REM, ADD, SHIFT, MIN_DIV, NEG, a.len(), S::MUL);
}
