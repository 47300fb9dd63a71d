//! Rust's prelude types on TRaX: `Option`, `Result` and `core::cmp::Ordering`, with the
//! methods kernels reach for (those without closures). Kernels name them as in Rust —
//! `Option`, `Some`, `None`, `Ok`, `Err` without imports, `std::cmp::Ordering` by path —
//! and the compiler finds them here; the host build (`trax native`) uses `core`'s, so
//! this module is compiled for the machine only. Panic messages are Rust's.

/// An optional value (`core::option::Option`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Option<T> {
    /// No value.
    None,
    /// Some value.
    Some(T),
}

impl<T> Option<T> {
    /// True for `Some`.
    pub fn is_some(&self) -> bool {
        matches!(self, Some(_))
    }

    /// True for `None`.
    pub fn is_none(&self) -> bool {
        matches!(self, None)
    }

    /// The value; panics on `None`.
    pub fn unwrap(self) -> T {
        match self {
            Some(v) => v,
            None => panic!("called `Option::unwrap()` on a `None` value"),
        }
    }

    /// The value; panics with `msg` on `None`.
    pub fn expect(self, msg: &str) -> T {
        match self {
            Some(v) => v,
            None => panic!("{}", msg),
        }
    }

    /// The value, or `default`.
    pub fn unwrap_or(self, default: T) -> T {
        match self {
            Some(v) => v,
            None => default,
        }
    }

    /// The value, or `T::default()`.
    pub fn unwrap_or_default(self) -> T
    where
        T: Default,
    {
        match self {
            Some(v) => v,
            None => T::default(),
        }
    }

    /// `Option<&T>` of the contents.
    pub fn as_ref(&self) -> Option<&T> {
        match self {
            Some(v) => Some(v),
            None => None,
        }
    }

    /// `Option<&mut T>` of the contents.
    pub fn as_mut(&mut self) -> Option<&mut T> {
        match self {
            Some(v) => Some(v),
            None => None,
        }
    }

    /// Takes the value out, leaving `None`.
    pub fn take(&mut self) -> Option<T> {
        core::mem::replace(self, None)
    }

    /// Puts `value` in, returning the old contents.
    pub fn replace(&mut self, value: T) -> Option<T> {
        core::mem::replace(self, Some(value))
    }

    /// Puts `value` in and returns a reference to it.
    pub fn insert(&mut self, value: T) -> &mut T {
        *self = Some(value);
        match self {
            Some(v) => v,
            None => unreachable!(),
        }
    }

    /// The contents, after putting `value` in if there were none.
    pub fn get_or_insert(&mut self, value: T) -> &mut T {
        if self.is_none() {
            *self = Some(value);
        }
        match self {
            Some(v) => v,
            None => unreachable!(),
        }
    }

    /// `Ok(v)` for `Some(v)`, `Err(err)` for `None`.
    pub fn ok_or<E>(self, err: E) -> Result<T, E> {
        match self {
            Some(v) => Ok(v),
            None => Err(err),
        }
    }

    /// `self` if it is `Some`, else `optb`.
    pub fn or(self, optb: Option<T>) -> Option<T> {
        match self {
            Some(x) => Some(x),
            None => optb,
        }
    }

    /// `optb` if `self` is `Some`, else `None`.
    pub fn and<U>(self, optb: Option<U>) -> Option<U> {
        match self {
            Some(_) => optb,
            None => None,
        }
    }

    /// `Some` if exactly one of `self` and `optb` is.
    pub fn xor(self, optb: Option<T>) -> Option<T> {
        match (self, optb) {
            (Some(a), None) => Some(a),
            (None, Some(b)) => Some(b),
            _ => None,
        }
    }

    /// Both values as a pair, if both are `Some`.
    pub fn zip<U>(self, other: Option<U>) -> Option<(T, U)> {
        match (self, other) {
            (Some(a), Some(b)) => Some((a, b)),
            _ => None,
        }
    }

    /// `Some(f(v))` for `Some(v)`.
    pub fn map<U, F: FnOnce(T) -> U>(self, f: F) -> Option<U> {
        match self {
            Some(v) => Some(f(v)),
            None => None,
        }
    }

    /// `f(v)` for `Some(v)`, else `default`.
    pub fn map_or<U, F: FnOnce(T) -> U>(self, default: U, f: F) -> U {
        match self {
            Some(v) => f(v),
            None => default,
        }
    }

    /// `f(v)` for `Some(v)`, else `default()`.
    pub fn map_or_else<U, D: FnOnce() -> U, F: FnOnce(T) -> U>(self, default: D, f: F) -> U {
        match self {
            Some(v) => f(v),
            None => default(),
        }
    }

    /// `f(v)` for `Some(v)`, else `None`.
    pub fn and_then<U, F: FnOnce(T) -> Option<U>>(self, f: F) -> Option<U> {
        match self {
            Some(v) => f(v),
            None => None,
        }
    }

    /// `self` if it is `Some`, else `f()`.
    pub fn or_else<F: FnOnce() -> Option<T>>(self, f: F) -> Option<T> {
        match self {
            Some(v) => Some(v),
            None => f(),
        }
    }

    /// The value, or `f()` for `None`.
    pub fn unwrap_or_else<F: FnOnce() -> T>(self, f: F) -> T {
        match self {
            Some(v) => v,
            None => f(),
        }
    }

    /// `Some(v)` if `predicate(&v)`, else `None`.
    pub fn filter<P: FnOnce(&T) -> bool>(self, predicate: P) -> Option<T> {
        match self {
            Some(v) => {
                if predicate(&v) {
                    Some(v)
                } else {
                    None
                }
            }
            None => None,
        }
    }

    /// True for `Some(v)` with `f(v)`.
    pub fn is_some_and<F: FnOnce(T) -> bool>(self, f: F) -> bool {
        match self {
            Some(v) => f(v),
            None => false,
        }
    }

    /// `Ok(v)` for `Some(v)`, `Err(err())` for `None`.
    pub fn ok_or_else<E, F: FnOnce() -> E>(self, err: F) -> Result<T, E> {
        match self {
            Some(v) => Ok(v),
            None => Err(err()),
        }
    }
}

impl<T: Copy> Option<&T> {
    /// Copies the referenced value.
    pub fn copied(self) -> Option<T> {
        match self {
            Some(&v) => Some(v),
            None => None,
        }
    }

    /// Copies the referenced value.
    pub fn cloned(self) -> Option<T> {
        match self {
            Some(&v) => Some(v),
            None => None,
        }
    }
}

impl<T> Default for Option<T> {
    fn default() -> Option<T> {
        None
    }
}

/// A value or an error (`core::result::Result`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Result<T, E> {
    /// Success.
    Ok(T),
    /// Failure.
    Err(E),
}

impl<T, E> Result<T, E> {
    /// True for `Ok`.
    pub fn is_ok(&self) -> bool {
        matches!(self, Ok(_))
    }

    /// True for `Err`.
    pub fn is_err(&self) -> bool {
        matches!(self, Err(_))
    }

    /// The success value, if any.
    pub fn ok(self) -> Option<T> {
        match self {
            Ok(v) => Some(v),
            Err(_) => None,
        }
    }

    /// The error, if any.
    pub fn err(self) -> Option<E> {
        match self {
            Ok(_) => None,
            Err(e) => Some(e),
        }
    }

    /// The success value; panics with the error on `Err`.
    pub fn unwrap(self) -> T
    where
        E: core::fmt::Debug,
    {
        match self {
            Ok(v) => v,
            Err(e) => panic!("called `Result::unwrap()` on an `Err` value: {:?}", e),
        }
    }

    /// The success value; panics with `msg` and the error on `Err`.
    pub fn expect(self, msg: &str) -> T
    where
        E: core::fmt::Debug,
    {
        match self {
            Ok(v) => v,
            Err(e) => panic!("{}: {:?}", msg, e),
        }
    }

    /// The error; panics with the value on `Ok`.
    pub fn unwrap_err(self) -> E
    where
        T: core::fmt::Debug,
    {
        match self {
            Ok(v) => panic!("called `Result::unwrap_err()` on an `Ok` value: {:?}", v),
            Err(e) => e,
        }
    }

    /// The success value, or `default`.
    pub fn unwrap_or(self, default: T) -> T {
        match self {
            Ok(v) => v,
            Err(_) => default,
        }
    }

    /// `Ok(f(v))` for `Ok(v)`.
    pub fn map<U, F: FnOnce(T) -> U>(self, f: F) -> Result<U, E> {
        match self {
            Ok(v) => Ok(f(v)),
            Err(e) => Err(e),
        }
    }

    /// `Err(f(e))` for `Err(e)`.
    pub fn map_err<G, F: FnOnce(E) -> G>(self, f: F) -> Result<T, G> {
        match self {
            Ok(v) => Ok(v),
            Err(e) => Err(f(e)),
        }
    }

    /// `f(v)` for `Ok(v)`.
    pub fn and_then<U, F: FnOnce(T) -> Result<U, E>>(self, f: F) -> Result<U, E> {
        match self {
            Ok(v) => f(v),
            Err(e) => Err(e),
        }
    }

    /// The value, or `f(e)` for `Err(e)`.
    pub fn unwrap_or_else<F: FnOnce(E) -> T>(self, f: F) -> T {
        match self {
            Ok(v) => v,
            Err(e) => f(e),
        }
    }

    /// True for `Ok(v)` with `f(v)`.
    pub fn is_ok_and<F: FnOnce(T) -> bool>(self, f: F) -> bool {
        match self {
            Ok(v) => f(v),
            Err(_) => false,
        }
    }

    /// `Result<&T, &E>` of the contents.
    pub fn as_ref(&self) -> Result<&T, &E> {
        match self {
            Ok(v) => Ok(v),
            Err(e) => Err(e),
        }
    }
}

/// The result of a comparison (`core::cmp::Ordering`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ordering {
    /// Less than.
    Less = -1,
    /// Equal.
    Equal = 0,
    /// Greater than.
    Greater = 1,
}

impl Ordering {
    /// `Equal`.
    pub fn is_eq(self) -> bool {
        matches!(self, Ordering::Equal)
    }

    /// Not `Equal`.
    pub fn is_ne(self) -> bool {
        !self.is_eq()
    }

    /// `Less`.
    pub fn is_lt(self) -> bool {
        matches!(self, Ordering::Less)
    }

    /// `Greater`.
    pub fn is_gt(self) -> bool {
        matches!(self, Ordering::Greater)
    }

    /// `Less` or `Equal`.
    pub fn is_le(self) -> bool {
        !self.is_gt()
    }

    /// `Greater` or `Equal`.
    pub fn is_ge(self) -> bool {
        !self.is_lt()
    }

    /// The opposite ordering.
    pub fn reverse(self) -> Ordering {
        match self {
            Ordering::Less => Ordering::Greater,
            Ordering::Equal => Ordering::Equal,
            Ordering::Greater => Ordering::Less,
        }
    }

    /// `self`, or `other` when `self` is `Equal`.
    pub fn then(self, other: Ordering) -> Ordering {
        match self {
            Ordering::Equal => other,
            o => o,
        }
    }
}

/// `x % y` for `f32`, exactly (IEEE fmod: the result has `x`'s sign and is exact). The
/// compiler lowers `%` on `f32` to this function.
pub fn fmodf(x: f32, y: f32) -> f32 {
    let mut ux = x.to_bits();
    let mut uy = y.to_bits();
    let mut ex = ((ux >> 23) & 0xff) as i32;
    let mut ey = ((uy >> 23) & 0xff) as i32;
    let sx = ux & 0x8000_0000;
    if uy << 1 == 0 || y.is_nan() || ex == 0xff {
        return (x * y) / (x * y);
    }
    if ux << 1 <= uy << 1 {
        if ux << 1 == uy << 1 {
            return 0.0 * x;
        }
        return x;
    }
    // Normalise the significands.
    if ex == 0 {
        let mut i = ux << 9;
        while i >> 31 == 0 {
            ex -= 1;
            i <<= 1;
        }
        ux <<= (-ex + 1) as u32;
    } else {
        ux &= u32::MAX >> 9;
        ux |= 1 << 23;
    }
    if ey == 0 {
        let mut i = uy << 9;
        while i >> 31 == 0 {
            ey -= 1;
            i <<= 1;
        }
        uy <<= (-ey + 1) as u32;
    } else {
        uy &= u32::MAX >> 9;
        uy |= 1 << 23;
    }
    // x mod y, one bit at a time.
    while ex > ey {
        let i = ux.wrapping_sub(uy);
        if i >> 31 == 0 {
            if i == 0 {
                return 0.0 * x;
            }
            ux = i;
        }
        ux <<= 1;
        ex -= 1;
    }
    let i = ux.wrapping_sub(uy);
    if i >> 31 == 0 {
        if i == 0 {
            return 0.0 * x;
        }
        ux = i;
    }
    while ux >> 23 == 0 {
        ux <<= 1;
        ex -= 1;
    }
    // Scale back.
    if ex > 0 {
        ux -= 1 << 23;
        ux |= (ex as u32) << 23;
    } else {
        ux >>= (-ex + 1) as u32;
    }
    f32::from_bits(ux | sx)
}

/// `x % y` for `f64`, exactly (see [`fmodf`]).
pub fn fmod(x: f64, y: f64) -> f64 {
    let mut ux = x.to_bits();
    let mut uy = y.to_bits();
    let mut ex = ((ux >> 52) & 0x7ff) as i32;
    let mut ey = ((uy >> 52) & 0x7ff) as i32;
    let sx = ux >> 63;
    if uy << 1 == 0 || y.is_nan() || ex == 0x7ff {
        return (x * y) / (x * y);
    }
    if ux << 1 <= uy << 1 {
        if ux << 1 == uy << 1 {
            return 0.0 * x;
        }
        return x;
    }
    if ex == 0 {
        let mut i = ux << 12;
        while i >> 63 == 0 {
            ex -= 1;
            i <<= 1;
        }
        ux <<= (-ex + 1) as u32;
    } else {
        ux &= u64::MAX >> 12;
        ux |= 1 << 52;
    }
    if ey == 0 {
        let mut i = uy << 12;
        while i >> 63 == 0 {
            ey -= 1;
            i <<= 1;
        }
        uy <<= (-ey + 1) as u32;
    } else {
        uy &= u64::MAX >> 12;
        uy |= 1 << 52;
    }
    while ex > ey {
        let i = ux.wrapping_sub(uy);
        if i >> 63 == 0 {
            if i == 0 {
                return 0.0 * x;
            }
            ux = i;
        }
        ux <<= 1;
        ex -= 1;
    }
    let i = ux.wrapping_sub(uy);
    if i >> 63 == 0 {
        if i == 0 {
            return 0.0 * x;
        }
        ux = i;
    }
    while ux >> 52 == 0 {
        ux <<= 1;
        ex -= 1;
    }
    if ex > 0 {
        ux -= 1 << 52;
        ux |= (ex as u64) << 52;
    } else {
        ux >>= (-ex + 1) as u32;
    }
    f64::from_bits(ux | (sx << 63))
}
