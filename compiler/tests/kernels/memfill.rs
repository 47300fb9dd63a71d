//! Zero- and byte-filled local arrays of several sizes and alignments: exercises the
//! compiler-provided `memset` (word loop for aligned whole words, byte loop otherwise).

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

fn trax_main() {
    if trax::global_id() != 0 {
        return;
    }
    for k in 0..12u32 {
        println!("{} {} {} {}", k, words(k * 7 + 1), bytes(k * 5 + 2), odd_offset(k));
    }
}
