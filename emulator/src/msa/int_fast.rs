//! Fast paths for the most frequent integer MSA operations on native lane types.
//!
//! Semantically identical to the general per-lane code in [`super::exec`] (the test suite
//! checks both against the same reference model); they exist only for speed.

use super::{Df, MsaOp};
use MsaOp::*;

/// A native integer lane type.
trait Lane: Copy {
    const COUNT: usize;
    fn get(v: u128, i: usize) -> Self;
    fn put(self, i: usize) -> u128;
}

macro_rules! lane_impl {
    ($($t:ty),*) => {$(
        impl Lane for $t {
            const COUNT: usize = 16 / std::mem::size_of::<$t>();
            #[inline(always)]
            fn get(v: u128, i: usize) -> Self {
                (v >> (i * 8 * std::mem::size_of::<$t>())) as $t
            }
            #[inline(always)]
            fn put(self, i: usize) -> u128 {
                ((self as u128) & (<$t>::MAX as u128)) << (i * 8 * std::mem::size_of::<$t>())
            }
        }
    )*};
}

lane_impl!(u8, u16, u32, u64);

#[inline(always)]
fn map2<T: Lane>(a: u128, b: u128, f: impl Fn(T, T) -> T) -> u128 {
    let mut r = 0u128;
    for i in 0..T::COUNT {
        r |= f(T::get(a, i), T::get(b, i)).put(i);
    }
    r
}

/// Expands `$body` (using `$x`, `$y` of unsigned type `$u`/signed type `$s`) per format.
macro_rules! per_df {
    ($df:expr, $a:expr, $b:expr, |$x:ident, $y:ident| $u:ident, $s:ident => $body:expr) => {
        match $df {
            Df::B => {
                #[allow(dead_code)]
                type $s = i8;
                map2::<u8>($a, $b, |$x, $y| $body)
            }
            Df::H => {
                #[allow(dead_code)]
                type $s = i16;
                map2::<u16>($a, $b, |$x, $y| $body)
            }
            Df::W => {
                #[allow(dead_code)]
                type $s = i32;
                map2::<u32>($a, $b, |$x, $y| $body)
            }
            _ => {
                #[allow(dead_code)]
                type $s = i64;
                map2::<u64>($a, $b, |$x, $y| $body)
            }
        }
    };
}

/// All-ones for true.
macro_rules! mask_of {
    ($c:expr) => {
        if $c {
            !0
        } else {
            0
        }
    };
}

/// Runs `op` on `s` and `t` (`t` already holds the splatted immediate for I5/BIT forms)
/// if it has a fast path.
#[inline]
pub fn int_fast(op: MsaOp, df: Df, s: u128, t: u128) -> Option<u128> {
    let bits = df.bits();
    Some(match op {
        Addv | Addvi => per_df!(df, s, t, |x, y| U, S => x.wrapping_add(y)),
        Subv | Subvi => per_df!(df, s, t, |x, y| U, S => x.wrapping_sub(y)),
        Mulv => per_df!(df, s, t, |x, y| U, S => x.wrapping_mul(y)),
        Ceq | Ceqi => per_df!(df, s, t, |x, y| U, S => mask_of!(x == y)),
        CltS | CltiS => per_df!(df, s, t, |x, y| U, S => mask_of!((x as S) < (y as S))),
        CltU | CltiU => per_df!(df, s, t, |x, y| U, S => mask_of!(x < y)),
        CleS | CleiS => per_df!(df, s, t, |x, y| U, S => mask_of!((x as S) <= (y as S))),
        CleU | CleiU => per_df!(df, s, t, |x, y| U, S => mask_of!(x <= y)),
        MaxS | MaxiS => per_df!(df, s, t, |x, y| U, S => if (x as S) >= (y as S) { x } else { y }),
        MaxU | MaxiU => per_df!(df, s, t, |x, y| U, S => x.max(y)),
        MinS | MiniS => per_df!(df, s, t, |x, y| U, S => if (x as S) <= (y as S) { x } else { y }),
        MinU | MiniU => per_df!(df, s, t, |x, y| U, S => x.min(y)),
        Sll | Slli => per_df!(df, s, t, |x, y| U, S => x << (y as u32 % bits)),
        Srl | Srli => per_df!(df, s, t, |x, y| U, S => x >> (y as u32 % bits)),
        Sra | Srai => per_df!(df, s, t, |x, y| U, S => ((x as S) >> (y as u32 % bits)) as _),
        _ => return None,
    })
}
