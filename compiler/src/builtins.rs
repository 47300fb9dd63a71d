//! The builtin catalogue: every method and associated function the compiler provides on
//! primitive, pointer, SIMD, array and slice types, with its signature (for the type
//! checker) and its [`Builtin`] (for lowering). One table, used by both stages.

use crate::ty::{FloatTy, IntTy, SimdTy, Ty};

/// What a builtin computes (lowering dispatches on it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    // ---- floats
    FSqrt,
    FAbs,
    FMin,
    FMax,
    FFloor,
    FCeil,
    FRound,
    FTrunc,
    FFract,
    FClamp,
    FPowi,
    FMulAdd,
    FIsNan,
    FIsFinite,
    FIsInfinite,
    FIsSignNegative,
    FIsSignPositive,
    FToBits,
    FFromBits,
    FSignum,
    FRecip,
    FCopysign,
    FToDegrees,
    FToRadians,
    FRemEuclid,
    FDivEuclid,
    FPartialCmp,
    FTotalCmp,
    /// A float function of the prelude's `libm` module (`f32` name, `f64` name).
    Libm(&'static str, &'static str),
    /// `x.log(base)`: `ln(x) / ln(base)`.
    FLogBase,
    /// `x.sin_cos()`.
    FSinCos,
    // ---- integers
    IMin,
    IMax,
    IAbs,
    IClamp,
    IWrappingAdd,
    IWrappingSub,
    IWrappingMul,
    IWrappingNeg,
    IPow,
    ICountOnes,
    ILeadingZeros,
    ITrailingZeros,
    IIsPowerOfTwo,
    IRotateLeft,
    IRotateRight,
    ISwapBytes,
    IRemEuclid,
    IDivEuclid,
    ISignum,
    IAbsDiff,
    IIsPositive,
    IIsNegative,
    /// `partial_cmp` of integers, `bool` and `char`.
    IPartialCmp,
    /// `cmp` of integers, `bool` and `char`.
    ICmp,
    // ---- raw pointers
    PtrAdd,
    PtrSub,
    PtrOffset,
    PtrIsNull,
    PtrRead,
    PtrWrite,
    PtrReadVolatile,
    PtrWriteVolatile,
    // ---- `core` functions
    StdNull,
    MemSwap,
    MemReplace,
    MemTake,
    CmpMin,
    CmpMax,
    // ---- SIMD
    SimdSplat,
    SimdNew,
    SimdSelect,
    SimdGet,
    SimdMin,
    SimdMax,
    SimdSqrt,
    SimdAbs,
    SimdMulAdd,
    SimdLt,
    SimdLe,
    SimdGt,
    SimdGe,
    SimdEq,
    SimdToI32x4,
    SimdToF32x4,
    SimdAny,
    SimdAll,
    // ---- arrays and slices (the receiver is passed by reference)
    Len,
    IsEmpty,
    First,
    Last,
    Swap,
    Fill,
    Contains,
    AsSlice,
}

/// The receiver class of a builtin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum On {
    Float,
    Int,
    SInt,
    UInt,
    /// `bool`, `char` and integers (ordering).
    Ordered,
    Ptr,
    PtrMut,
    F32x4,
    I32x4,
    /// Arrays and slices, by shared reference.
    Seq,
    /// Arrays and slices, by mutable reference.
    SeqMut,
}

/// A parameter or result type, relative to the receiver type `S`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum P {
    /// The receiver's type.
    S,
    /// `&S`.
    RefS,
    Unit,
    Bool,
    U32,
    I32,
    Usize,
    Isize,
    /// The unsigned integer of the receiver's width.
    Unsigned,
    /// `u32` for `f32`, `u64` for `f64`.
    Bits,
    /// A SIMD type's lane.
    Lane,
    F32x4,
    I32x4,
    /// The element (or pointee) type.
    Elem,
    /// `&T` of the element.
    RefElem,
    /// `Option<&T>` of the element.
    OptRefElem,
    /// `(S, S)`.
    PairS,
    /// `core::cmp::Ordering`.
    Ordering,
    /// `Option<Ordering>`.
    OptOrdering,
    /// `&[T]` of the element.
    SliceRef,
}

/// One catalogue entry.
#[derive(Clone, Copy, Debug)]
pub struct Method {
    /// Receiver class.
    pub on: On,
    /// Method name.
    pub name: &'static str,
    /// Parameters after the receiver.
    pub params: &'static [P],
    /// Result.
    pub ret: P,
    /// Lowering.
    pub b: Builtin,
}

macro_rules! m {
    ($on:ident, $name:literal, [$($p:ident),*], $ret:ident, $b:expr) => {
        Method { on: On::$on, name: $name, params: &[$(P::$p),*], ret: P::$ret, b: $b }
    };
}

use Builtin as B;

/// Methods (receiver first).
pub static METHODS: &[Method] = &[
    m!(Float, "sqrt", [], S, B::FSqrt),
    m!(Float, "abs", [], S, B::FAbs),
    m!(Float, "min", [S], S, B::FMin),
    m!(Float, "max", [S], S, B::FMax),
    m!(Float, "floor", [], S, B::FFloor),
    m!(Float, "ceil", [], S, B::FCeil),
    m!(Float, "round", [], S, B::FRound),
    m!(Float, "trunc", [], S, B::FTrunc),
    m!(Float, "fract", [], S, B::FFract),
    m!(Float, "clamp", [S, S], S, B::FClamp),
    m!(Float, "powi", [I32], S, B::FPowi),
    m!(Float, "mul_add", [S, S], S, B::FMulAdd),
    m!(Float, "is_nan", [], Bool, B::FIsNan),
    m!(Float, "is_finite", [], Bool, B::FIsFinite),
    m!(Float, "is_infinite", [], Bool, B::FIsInfinite),
    m!(Float, "is_sign_negative", [], Bool, B::FIsSignNegative),
    m!(Float, "is_sign_positive", [], Bool, B::FIsSignPositive),
    m!(Float, "to_bits", [], Bits, B::FToBits),
    m!(Float, "signum", [], S, B::FSignum),
    m!(Float, "recip", [], S, B::FRecip),
    m!(Float, "copysign", [S], S, B::FCopysign),
    m!(Float, "to_degrees", [], S, B::FToDegrees),
    m!(Float, "to_radians", [], S, B::FToRadians),
    m!(Float, "rem_euclid", [S], S, B::FRemEuclid),
    m!(Float, "div_euclid", [S], S, B::FDivEuclid),
    m!(Float, "partial_cmp", [RefS], OptOrdering, B::FPartialCmp),
    m!(Float, "total_cmp", [RefS], Ordering, B::FTotalCmp),
    m!(Float, "sin", [], S, B::Libm("sinf", "sin")),
    m!(Float, "cos", [], S, B::Libm("cosf", "cos")),
    m!(Float, "tan", [], S, B::Libm("tanf", "tan")),
    m!(Float, "asin", [], S, B::Libm("asinf", "asin")),
    m!(Float, "acos", [], S, B::Libm("acosf", "acos")),
    m!(Float, "atan", [], S, B::Libm("atanf", "atan")),
    m!(Float, "atan2", [S], S, B::Libm("atan2f", "atan2")),
    m!(Float, "exp", [], S, B::Libm("expf", "exp")),
    m!(Float, "exp2", [], S, B::Libm("exp2f", "exp2")),
    m!(Float, "ln", [], S, B::Libm("logf", "log")),
    m!(Float, "log2", [], S, B::Libm("log2f", "log2")),
    m!(Float, "log10", [], S, B::Libm("log10f", "log10")),
    m!(Float, "log", [S], S, B::FLogBase),
    m!(Float, "powf", [S], S, B::Libm("powf", "pow")),
    m!(Float, "cbrt", [], S, B::Libm("cbrtf", "cbrt")),
    m!(Float, "hypot", [S], S, B::Libm("hypotf", "hypot")),
    m!(Float, "sinh", [], S, B::Libm("sinhf", "sinh")),
    m!(Float, "cosh", [], S, B::Libm("coshf", "cosh")),
    m!(Float, "tanh", [], S, B::Libm("tanhf", "tanh")),
    m!(Float, "exp_m1", [], S, B::Libm("expm1f", "expm1")),
    m!(Float, "ln_1p", [], S, B::Libm("log1pf", "log1p")),
    m!(Float, "sin_cos", [], PairS, B::FSinCos),
    m!(Int, "min", [S], S, B::IMin),
    m!(Int, "max", [S], S, B::IMax),
    m!(SInt, "abs", [], S, B::IAbs),
    m!(Int, "clamp", [S, S], S, B::IClamp),
    m!(Int, "wrapping_add", [S], S, B::IWrappingAdd),
    m!(Int, "wrapping_sub", [S], S, B::IWrappingSub),
    m!(Int, "wrapping_mul", [S], S, B::IWrappingMul),
    m!(Int, "wrapping_neg", [], S, B::IWrappingNeg),
    m!(Int, "pow", [U32], S, B::IPow),
    m!(Int, "count_ones", [], U32, B::ICountOnes),
    m!(Int, "leading_zeros", [], U32, B::ILeadingZeros),
    m!(Int, "trailing_zeros", [], U32, B::ITrailingZeros),
    m!(UInt, "is_power_of_two", [], Bool, B::IIsPowerOfTwo),
    m!(Int, "rotate_left", [U32], S, B::IRotateLeft),
    m!(Int, "rotate_right", [U32], S, B::IRotateRight),
    m!(Int, "swap_bytes", [], S, B::ISwapBytes),
    m!(Int, "rem_euclid", [S], S, B::IRemEuclid),
    m!(Int, "div_euclid", [S], S, B::IDivEuclid),
    m!(SInt, "signum", [], S, B::ISignum),
    m!(Int, "abs_diff", [S], Unsigned, B::IAbsDiff),
    m!(SInt, "is_positive", [], Bool, B::IIsPositive),
    m!(SInt, "is_negative", [], Bool, B::IIsNegative),
    m!(Ordered, "partial_cmp", [RefS], OptOrdering, B::IPartialCmp),
    m!(Ordered, "cmp", [RefS], Ordering, B::ICmp),
    m!(Ptr, "add", [Usize], S, B::PtrAdd),
    m!(Ptr, "sub", [Usize], S, B::PtrSub),
    m!(Ptr, "offset", [Isize], S, B::PtrOffset),
    m!(Ptr, "is_null", [], Bool, B::PtrIsNull),
    m!(Ptr, "read", [], Elem, B::PtrRead),
    m!(Ptr, "read_volatile", [], Elem, B::PtrReadVolatile),
    m!(PtrMut, "write", [Elem], Unit, B::PtrWrite),
    m!(PtrMut, "write_volatile", [Elem], Unit, B::PtrWriteVolatile),
    m!(F32x4, "get", [Usize], Lane, B::SimdGet),
    m!(I32x4, "get", [Usize], Lane, B::SimdGet),
    m!(F32x4, "min", [S], S, B::SimdMin),
    m!(F32x4, "max", [S], S, B::SimdMax),
    m!(F32x4, "sqrt", [], S, B::SimdSqrt),
    m!(F32x4, "abs", [], S, B::SimdAbs),
    m!(F32x4, "mul_add", [S, S], S, B::SimdMulAdd),
    m!(F32x4, "lt", [S], I32x4, B::SimdLt),
    m!(F32x4, "le", [S], I32x4, B::SimdLe),
    m!(F32x4, "gt", [S], I32x4, B::SimdGt),
    m!(F32x4, "ge", [S], I32x4, B::SimdGe),
    m!(F32x4, "eq", [S], I32x4, B::SimdEq),
    m!(F32x4, "to_i32x4", [], I32x4, B::SimdToI32x4),
    m!(I32x4, "to_f32x4", [], F32x4, B::SimdToF32x4),
    m!(I32x4, "any", [], Bool, B::SimdAny),
    m!(I32x4, "all", [], Bool, B::SimdAll),
    m!(Seq, "len", [], Usize, B::Len),
    m!(Seq, "is_empty", [], Bool, B::IsEmpty),
    m!(Seq, "first", [], OptRefElem, B::First),
    m!(Seq, "last", [], OptRefElem, B::Last),
    m!(Seq, "contains", [RefElem], Bool, B::Contains),
    m!(Seq, "as_slice", [], SliceRef, B::AsSlice),
    m!(SeqMut, "swap", [Usize, Usize], Unit, B::Swap),
    m!(SeqMut, "fill", [Elem], Unit, B::Fill),
];

/// Associated functions called by path (`f32::from_bits`, `f32x4::splat`).
pub static ASSOC_FNS: &[Method] = &[
    m!(Float, "from_bits", [Bits], S, B::FFromBits),
    m!(F32x4, "splat", [Lane], S, B::SimdSplat),
    m!(I32x4, "splat", [Lane], S, B::SimdSplat),
    m!(F32x4, "new", [Lane, Lane, Lane, Lane], S, B::SimdNew),
    m!(I32x4, "new", [Lane, Lane, Lane, Lane], S, B::SimdNew),
    m!(F32x4, "select", [I32x4, S, S], S, B::SimdSelect),
    m!(I32x4, "select", [I32x4, S, S], S, B::SimdSelect),
];

/// True if a receiver of type `t` belongs to class `on`.
pub fn applies(on: On, t: &Ty) -> bool {
    match (on, t) {
        (On::Float, Ty::Float(_)) => true,
        (On::Int, Ty::Int(_)) => true,
        (On::SInt, Ty::Int(i)) => i.signed(),
        (On::UInt, Ty::Int(i)) => !i.signed(),
        (On::Ordered, Ty::Int(_) | Ty::Bool | Ty::Char) => true,
        (On::Ptr, Ty::Ptr(..)) => true,
        (On::PtrMut, Ty::Ptr(true, _)) => true,
        (On::F32x4, Ty::Simd(SimdTy::F32x4)) => true,
        (On::I32x4, Ty::Simd(SimdTy::I32x4)) => true,
        (On::Seq | On::SeqMut, Ty::Array(..) | Ty::Slice(_)) => true,
        _ => false,
    }
}

/// The method `name` on a receiver of type `t`, if the catalogue has one.
pub fn method(t: &Ty, name: &str) -> Option<&'static Method> {
    METHODS.iter().find(|m| m.name == name && applies(m.on, t))
}

/// A method of `name` on some class, when `t` does not have it (for messages such as
/// "`abs` is only defined on signed integers").
pub fn method_anywhere(name: &str) -> Option<&'static Method> {
    METHODS.iter().find(|m| m.name == name)
}

/// The associated function `name` of type `t`.
pub fn assoc_fn(t: &Ty, name: &str) -> Option<&'static Method> {
    ASSOC_FNS
        .iter()
        .find(|m| m.name == name && applies(m.on, t))
}

/// The element type of a pointer, array or slice receiver, or the lane type of a SIMD
/// type.
pub fn elem_of(t: &Ty) -> Option<Ty> {
    match t {
        Ty::Ptr(_, e) | Ty::Array(e, _) | Ty::Slice(e) => Some((**e).clone()),
        Ty::Simd(SimdTy::F32x4) => Some(Ty::Float(FloatTy::F32)),
        Ty::Simd(SimdTy::I32x4) => Some(Ty::Int(IntTy::I32)),
        _ => None,
    }
}

/// The unsigned integer type of `t`'s width.
pub fn unsigned_of(t: IntTy) -> IntTy {
    match t {
        IntTy::I8 | IntTy::U8 => IntTy::U8,
        IntTy::I16 | IntTy::U16 => IntTy::U16,
        IntTy::I32 | IntTy::U32 => IntTy::U32,
        IntTy::I64 | IntTy::U64 => IntTy::U64,
        IntTy::Isize | IntTy::Usize => IntTy::Usize,
    }
}
