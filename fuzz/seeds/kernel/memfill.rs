//! Zero- and byte-filled, copied and shifted local arrays of several sizes and alignments:
//! exercises the compiler-provided `memset`, `memcpy` and `memmove` (word loops for aligned
//! whole words, byte loops otherwise, memmove backwards when the destination is above).

#[inline(never)]
fn words(seed: u32) -> u32 {
    let mut a = [0u32; 64];
    a[(seed % 64) as usize] = seed;
    let mut s = 0u32;
    for i in 0..64 {
        s = s.wrapping_mul(31).wrapping_add(a[i]);
    }
    s
}

#[inline(never)]
fn bytes(seed: u32) -> u32 {
    let mut a = [7u8; 67];
    a[(seed % 67) as usize] = seed as u8;
    let mut s = 0u32;
    for i in 0..67 {
        s = s.wrapping_mul(31).wrapping_add(a[i] as u32);
    }
    s
}

#[inline(never)]
fn odd_offset(seed: u32) -> u32 {
    let mut a = [[0u8; 13]; 5];
    a[(seed % 5) as usize][(seed % 13) as usize] = 1;
    let mut s = 0u32;
    for i in 0..5 {
        for j in 0..13 {
            s = s.wrapping_mul(3).wrapping_add(a[i][j] as u32);
        }
    }
    s
}

#[inline(never)]
fn copies(seed: u32) -> u32 {
    let mut a = [0u32; 64];
    let mut c = [0u8; 67];
    for i in 0..64 {
        a[i] = seed.wrapping_mul(i as u32 + 3);
    }
    for i in 0..67 {
        c[i] = (seed as u8).wrapping_add(i as u8);
    }
    let mut b = a;
    let mut d = c;
    b[(seed % 64) as usize] = 1;
    d[(seed % 67) as usize] = 2;
    let mut s = 0u32;
    for i in 0..64 {
        s = s.wrapping_mul(31).wrapping_add(a[i] ^ b[i]);
    }
    for i in 0..67 {
        s = s.wrapping_mul(31).wrapping_add((c[i] ^ d[i]) as u32 + c[i] as u32);
    }
    s
}

#[inline(never)]
fn shifts(seed: u32) -> u32 {
    let mut w = [0u32; 40];
    let mut c = [0u8; 41];
    for i in 0..40 {
        w[i] = seed.wrapping_add(i as u32 * 977);
    }
    for i in 0..41 {
        c[i] = (seed as u8).wrapping_mul(i as u8 + 1);
    }
    // Up by one (overlapping, destination above the source).
    let mut i = 39;
    while i > 0 {
        w[i] = w[i - 1];
        i -= 1;
    }
    let mut i = 40;
    while i > 0 {
        c[i] = c[i - 1];
        i -= 1;
    }
    // Down by one (overlapping, destination below the source).
    for i in 0..39 {
        w[i] = w[i + 1];
    }
    for i in 0..40 {
        c[i] = c[i + 1];
    }
    let mut s = 0u32;
    for i in 0..40 {
        s = s.wrapping_mul(31).wrapping_add(w[i]);
    }
    for i in 0..41 {
        s = s.wrapping_mul(31).wrapping_add(c[i] as u32);
    }
    s
}

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    for k in 0..12u32 {
        println!("{} {} {} {}", k, words(k * 7 + 1), bytes(k * 5 + 2), odd_offset(k));
        println!("{} {}", copies(k * 11 + 5), shifts(k * 13 + 1));
    }
}
