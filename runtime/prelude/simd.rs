//! Host implementation of the 4-lane SIMD types. On TRaX, `trax::simd::{f32x4, i32x4}`
//! are compiler builtins lowered to MSA with the same semantics as this file.

#![allow(non_camel_case_types)]

use std::ops::{
    Add, AddAssign, BitAnd, BitAndAssign, BitOr, BitOrAssign, BitXor, BitXorAssign, Div, DivAssign,
    Mul, MulAssign, Neg, Sub, SubAssign,
};

/// Four f32 lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct f32x4([f32; 4]);

/// Four i32 lanes (also comparison masks: -1 true, 0 false).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct i32x4([i32; 4]);

impl f32x4 {
    /// All lanes `x`.
    pub fn splat(x: f32) -> f32x4 {
        f32x4([x; 4])
    }

    /// Lanes `a, b, c, d` (lane 0 first).
    pub fn new(a: f32, b: f32, c: f32, d: f32) -> f32x4 {
        f32x4([a, b, c, d])
    }

    /// Lane `i` (panics if `i >= 4`).
    pub fn get(self, i: usize) -> f32 {
        self.0[i]
    }

    fn map(self, f: impl Fn(f32) -> f32) -> f32x4 {
        f32x4([f(self.0[0]), f(self.0[1]), f(self.0[2]), f(self.0[3])])
    }

    fn zip(self, o: f32x4, f: impl Fn(f32, f32) -> f32) -> f32x4 {
        f32x4([
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ])
    }

    fn cmp(self, o: f32x4, f: impl Fn(f32, f32) -> bool) -> i32x4 {
        let m = |i: usize| if f(self.0[i], o.0[i]) { -1 } else { 0 };
        i32x4([m(0), m(1), m(2), m(3)])
    }

    /// Lane-wise minimum, as `trax::min`: IEEE minNum (a NaN loses to a number, two
    /// NaNs give the first, quieted) with `min(-0, +0) = -0`.
    pub fn min(self, o: f32x4) -> f32x4 {
        self.zip(o, super::hw::fmin)
    }

    /// Lane-wise maximum, as `trax::max`: IEEE maxNum with `max(-0, +0) = +0`.
    pub fn max(self, o: f32x4) -> f32x4 {
        self.zip(o, super::hw::fmax)
    }

    /// Lane-wise square root.
    pub fn sqrt(self) -> f32x4 {
        self.map(f32::sqrt)
    }

    /// Lane-wise absolute value.
    pub fn abs(self) -> f32x4 {
        self.map(f32::abs)
    }

    /// `self * a + b`, fused (one rounding) per lane.
    pub fn mul_add(self, a: f32x4, b: f32x4) -> f32x4 {
        f32x4([
            self.0[0].mul_add(a.0[0], b.0[0]),
            self.0[1].mul_add(a.0[1], b.0[1]),
            self.0[2].mul_add(a.0[2], b.0[2]),
            self.0[3].mul_add(a.0[3], b.0[3]),
        ])
    }

    /// Lane-wise `<` (false for NaN).
    pub fn lt(self, o: f32x4) -> i32x4 {
        self.cmp(o, |a, b| a < b)
    }

    /// Lane-wise `<=`.
    pub fn le(self, o: f32x4) -> i32x4 {
        self.cmp(o, |a, b| a <= b)
    }

    /// Lane-wise `>`.
    pub fn gt(self, o: f32x4) -> i32x4 {
        self.cmp(o, |a, b| a > b)
    }

    /// Lane-wise `>=`.
    pub fn ge(self, o: f32x4) -> i32x4 {
        self.cmp(o, |a, b| a >= b)
    }

    /// Lane-wise `==`.
    pub fn eq(self, o: f32x4) -> i32x4 {
        self.cmp(o, |a, b| a == b)
    }

    /// Lane = `mask != 0 ? a : b`.
    pub fn select(mask: i32x4, a: f32x4, b: f32x4) -> f32x4 {
        let s = |i: usize| if mask.0[i] != 0 { a.0[i] } else { b.0[i] };
        f32x4([s(0), s(1), s(2), s(3)])
    }

    /// Truncates toward zero, saturating at the i32 range; NaN becomes 0.
    pub fn to_i32x4(self) -> i32x4 {
        i32x4([
            self.0[0] as i32,
            self.0[1] as i32,
            self.0[2] as i32,
            self.0[3] as i32,
        ])
    }
}

impl i32x4 {
    /// All lanes `x`.
    pub fn splat(x: i32) -> i32x4 {
        i32x4([x; 4])
    }

    /// Lanes `a, b, c, d` (lane 0 first).
    pub fn new(a: i32, b: i32, c: i32, d: i32) -> i32x4 {
        i32x4([a, b, c, d])
    }

    /// Lane `i` (panics if `i >= 4`).
    pub fn get(self, i: usize) -> i32 {
        self.0[i]
    }

    fn zip(self, o: i32x4, f: impl Fn(i32, i32) -> i32) -> i32x4 {
        i32x4([
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ])
    }

    /// Lane = `mask != 0 ? a : b`.
    pub fn select(mask: i32x4, a: i32x4, b: i32x4) -> i32x4 {
        let s = |i: usize| if mask.0[i] != 0 { a.0[i] } else { b.0[i] };
        i32x4([s(0), s(1), s(2), s(3)])
    }

    /// True if any lane is non-zero.
    pub fn any(self) -> bool {
        self.0.iter().any(|&x| x != 0)
    }

    /// True if every lane is non-zero.
    pub fn all(self) -> bool {
        self.0.iter().all(|&x| x != 0)
    }

    /// Lane-wise conversion to f32 (round to nearest even).
    pub fn to_f32x4(self) -> f32x4 {
        f32x4([
            self.0[0] as f32,
            self.0[1] as f32,
            self.0[2] as f32,
            self.0[3] as f32,
        ])
    }
}

macro_rules! binop {
    ($t:ident, $tr:ident, $m:ident, $f:expr) => {
        impl $tr for $t {
            type Output = $t;
            fn $m(self, o: $t) -> $t {
                self.zip(o, $f)
            }
        }
    };
}

binop!(f32x4, Add, add, |a, b| a + b);
binop!(f32x4, Sub, sub, |a, b| a - b);
binop!(f32x4, Mul, mul, |a, b| a * b);
binop!(f32x4, Div, div, |a, b| a / b);
binop!(i32x4, Add, add, i32::wrapping_add);
binop!(i32x4, Sub, sub, i32::wrapping_sub);
binop!(i32x4, Mul, mul, i32::wrapping_mul);
binop!(i32x4, BitAnd, bitand, |a, b| a & b);
binop!(i32x4, BitOr, bitor, |a, b| a | b);
binop!(i32x4, BitXor, bitxor, |a, b| a ^ b);

impl Neg for f32x4 {
    type Output = f32x4;
    fn neg(self) -> f32x4 {
        self.map(|x| -x)
    }
}

impl Neg for i32x4 {
    type Output = i32x4;
    fn neg(self) -> i32x4 {
        i32x4(self.0.map(i32::wrapping_neg))
    }
}

/// `a op= b` is `a = a op b`, as the compiler lowers it on TRaX.
macro_rules! assignop {
    ($t:ident, $tr:ident, $m:ident, $op:tt) => {
        impl $tr for $t {
            fn $m(&mut self, o: $t) {
                *self = *self $op o;
            }
        }
    };
}

assignop!(f32x4, AddAssign, add_assign, +);
assignop!(f32x4, SubAssign, sub_assign, -);
assignop!(f32x4, MulAssign, mul_assign, *);
assignop!(f32x4, DivAssign, div_assign, /);
assignop!(i32x4, AddAssign, add_assign, +);
assignop!(i32x4, SubAssign, sub_assign, -);
assignop!(i32x4, MulAssign, mul_assign, *);
assignop!(i32x4, BitAndAssign, bitand_assign, &);
assignop!(i32x4, BitOrAssign, bitor_assign, |);
assignop!(i32x4, BitXorAssign, bitxor_assign, ^);
