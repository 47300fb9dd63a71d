// `char` has no C counterpart (C's `char` is a byte, Rust's a Unicode scalar value).
#[no_mangle]
pub extern "C" fn next_letter(c: char) -> u32 {
    c as u32 + 1
}
