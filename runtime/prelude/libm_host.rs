//! Host only: `trax::libm` under the C library's names, so that `x.sin()`, `x.powf(y)`,
//! ... in a kernel built by rustc (`trax native`) run the same code as on the machine,
//! where the trax compiler calls `trax::libm` for these methods. std's float methods end
//! in calls of `sinf`, `pow`, `atan2f`, ...; these definitions in the executable take
//! precedence over the shared C library's. `sincosf`/`sincos` (LLVM joins a `sin` and a
//! `cos` of the same value into one) and `exp10f`/`exp10` (LLVM's rewrite of
//! `pow(10, x)`) give what the machine computes for the calls they replace.
//!
//! Calls whose arguments are all constants are folded by rustc with the host's libm and
//! do not reach these functions.

use super::libm;

macro_rules! unary {
    ($($c:ident => $f:ident : $t:ty),* $(,)?) => {$(
        #[no_mangle]
        pub extern "C" fn $c(x: $t) -> $t {
            libm::$f(x)
        }
    )*};
}

macro_rules! binary {
    ($($c:ident => $f:ident : $t:ty),* $(,)?) => {$(
        #[no_mangle]
        pub extern "C" fn $c(x: $t, y: $t) -> $t {
            libm::$f(x, y)
        }
    )*};
}

unary! {
    sinf => sinf: f32, cosf => cosf: f32, tanf => tanf: f32,
    asinf => asinf: f32, acosf => acosf: f32, atanf => atanf: f32,
    expf => expf: f32, exp2f => exp2f: f32, logf => logf: f32,
    log2f => log2f: f32, log10f => log10f: f32, cbrtf => cbrtf: f32,
    sin => sin: f64, cos => cos: f64, tan => tan: f64,
    asin => asin: f64, acos => acos: f64, atan => atan: f64,
    exp => exp: f64, exp2 => exp2: f64, log => log: f64,
    log2 => log2: f64, log10 => log10: f64, cbrt => cbrt: f64,
}

binary! {
    atan2f => atan2f: f32, powf => powf: f32, hypotf => hypotf: f32,
    atan2 => atan2: f64, pow => pow: f64, hypot => hypot: f64,
}

/// `pow(10, x)`, which LLVM may call `exp10f`.
#[no_mangle]
pub extern "C" fn exp10f(x: f32) -> f32 {
    libm::powf(10.0, x)
}

/// `pow(10, x)`, which LLVM may call `exp10`.
#[no_mangle]
pub extern "C" fn exp10(x: f64) -> f64 {
    libm::pow(10.0, x)
}

/// `sinf(x)` and `cosf(x)` (glibc's signature).
///
/// # Safety
/// `s` and `c` must be valid for writes; LLVM only emits this call with pointers to
/// its own stack slots.
#[no_mangle]
pub unsafe extern "C" fn sincosf(x: f32, s: *mut f32, c: *mut f32) {
    // SAFETY: the caller passes writable pointers (see above).
    unsafe {
        *s = libm::sinf(x);
        *c = libm::cosf(x);
    }
}

/// `sin(x)` and `cos(x)` (glibc's signature).
///
/// # Safety
/// As for [`sincosf`].
#[no_mangle]
pub unsafe extern "C" fn sincos(x: f64, s: *mut f64, c: *mut f64) {
    // SAFETY: the caller passes writable pointers (see above).
    unsafe {
        *s = libm::sin(x);
        *c = libm::cos(x);
    }
}
