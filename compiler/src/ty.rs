//! Semantic types of TRaX-Rust.

use std::fmt;

/// Integer types. `usize`/`isize` are 32-bit on TRaX.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IntTy {
    I8,
    I16,
    I32,
    I64,
    Isize,
    U8,
    U16,
    U32,
    U64,
    Usize,
}

impl IntTy {
    /// Width in bits.
    pub fn bits(self) -> u32 {
        match self {
            IntTy::I8 | IntTy::U8 => 8,
            IntTy::I16 | IntTy::U16 => 16,
            IntTy::I32 | IntTy::U32 | IntTy::Isize | IntTy::Usize => 32,
            IntTy::I64 | IntTy::U64 => 64,
        }
    }

    /// True for signed types.
    pub fn signed(self) -> bool {
        matches!(
            self,
            IntTy::I8 | IntTy::I16 | IntTy::I32 | IntTy::I64 | IntTy::Isize
        )
    }

    /// Source name.
    pub fn name(self) -> &'static str {
        match self {
            IntTy::I8 => "i8",
            IntTy::I16 => "i16",
            IntTy::I32 => "i32",
            IntTy::I64 => "i64",
            IntTy::Isize => "isize",
            IntTy::U8 => "u8",
            IntTy::U16 => "u16",
            IntTy::U32 => "u32",
            IntTy::U64 => "u64",
            IntTy::Usize => "usize",
        }
    }

    /// Parses a type or literal-suffix name.
    pub fn from_name(s: &str) -> Option<IntTy> {
        Some(match s {
            "i8" => IntTy::I8,
            "i16" => IntTy::I16,
            "i32" => IntTy::I32,
            "i64" => IntTy::I64,
            "isize" => IntTy::Isize,
            "u8" => IntTy::U8,
            "u16" => IntTy::U16,
            "u32" => IntTy::U32,
            "u64" => IntTy::U64,
            "usize" => IntTy::Usize,
            _ => return None,
        })
    }

    /// Smallest value.
    pub fn min(self) -> i128 {
        if self.signed() {
            -(1i128 << (self.bits() - 1))
        } else {
            0
        }
    }

    /// Largest value.
    pub fn max(self) -> i128 {
        if self.signed() {
            (1i128 << (self.bits() - 1)) - 1
        } else {
            (1i128 << self.bits()) - 1
        }
    }
}

/// Floating-point types.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FloatTy {
    F32,
    F64,
}

impl FloatTy {
    /// Source name.
    pub fn name(self) -> &'static str {
        match self {
            FloatTy::F32 => "f32",
            FloatTy::F64 => "f64",
        }
    }
}

/// Builtin 128-bit SIMD types (MSA).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimdTy {
    /// `trax::simd::f32x4`.
    F32x4,
    /// `trax::simd::i32x4`.
    I32x4,
}

/// Index of a struct definition.
pub type StructId = usize;

/// A type. `Var` is an inference variable for an unsuffixed literal.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    Unit,
    Never,
    Bool,
    Char,
    Int(IntTy),
    Float(FloatTy),
    Struct(StructId),
    Array(Box<Ty>, u32),
    /// `&T` (`true` = `&mut T`).
    Ref(bool, Box<Ty>),
    /// `*const T` / `*mut T` (`true` = mut).
    Ptr(bool, Box<Ty>),
    Simd(SimdTy),
    /// `&'static str` (only string literals).
    Str,
    Var(u32),
}

impl Ty {
    /// True for integer types.
    pub fn is_int(&self) -> bool {
        matches!(self, Ty::Int(_))
    }

    /// True for float types.
    pub fn is_float(&self) -> bool {
        matches!(self, Ty::Float(_))
    }

    /// True for types without a runtime value.
    pub fn is_zst(&self) -> bool {
        matches!(self, Ty::Unit | Ty::Never) || matches!(self, Ty::Array(_, 0))
    }

    /// Pointee of a reference or raw pointer.
    pub fn pointee(&self) -> Option<&Ty> {
        match self {
            Ty::Ref(_, t) | Ty::Ptr(_, t) => Some(t),
            _ => None,
        }
    }
}

/// Displays a type with struct names supplied by `names`.
pub struct TyDisplay<'a> {
    /// The type.
    pub ty: &'a Ty,
    /// Struct names by id.
    pub names: &'a dyn Fn(StructId) -> String,
}

impl<'a> fmt::Display for TyDisplay<'a> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sub = |t: &'a Ty| TyDisplay {
            ty: t,
            names: self.names,
        };
        match self.ty {
            Ty::Unit => write!(f, "()"),
            Ty::Never => write!(f, "!"),
            Ty::Bool => write!(f, "bool"),
            Ty::Char => write!(f, "char"),
            Ty::Int(i) => write!(f, "{}", i.name()),
            Ty::Float(x) => write!(f, "{}", x.name()),
            Ty::Struct(s) => write!(f, "{}", (self.names)(*s)),
            Ty::Array(t, n) => write!(f, "[{}; {n}]", sub(t)),
            Ty::Ref(m, t) => write!(f, "&{}{}", if *m { "mut " } else { "" }, sub(t)),
            Ty::Ptr(m, t) => write!(f, "*{} {}", if *m { "mut" } else { "const" }, sub(t)),
            Ty::Simd(SimdTy::F32x4) => write!(f, "f32x4"),
            Ty::Simd(SimdTy::I32x4) => write!(f, "i32x4"),
            Ty::Str => write!(f, "&str"),
            Ty::Var(_) => write!(f, "{{number}}"),
        }
    }
}
