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

/// Index of a struct or enum definition.
pub type AdtId = usize;
/// Index of a trait definition.
pub type TraitId = usize;

/// Traits the compiler knows (Rust's prelude and `core::ops`/`core::cmp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LangTrait {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Neg,
    Not,
    BitAnd,
    BitOr,
    BitXor,
    Shl,
    Shr,
    AddAssign,
    SubAssign,
    MulAssign,
    DivAssign,
    RemAssign,
    BitAndAssign,
    BitOrAssign,
    BitXorAssign,
    ShlAssign,
    ShrAssign,
    Index,
    IndexMut,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Clone,
    Copy,
    Default,
    Debug,
    Sized,
    Fn,
    FnMut,
    FnOnce,
}

impl LangTrait {
    /// Every lang trait.
    pub const ALL: &'static [LangTrait] = &[
        LangTrait::Add,
        LangTrait::Sub,
        LangTrait::Mul,
        LangTrait::Div,
        LangTrait::Rem,
        LangTrait::Neg,
        LangTrait::Not,
        LangTrait::BitAnd,
        LangTrait::BitOr,
        LangTrait::BitXor,
        LangTrait::Shl,
        LangTrait::Shr,
        LangTrait::AddAssign,
        LangTrait::SubAssign,
        LangTrait::MulAssign,
        LangTrait::DivAssign,
        LangTrait::RemAssign,
        LangTrait::BitAndAssign,
        LangTrait::BitOrAssign,
        LangTrait::BitXorAssign,
        LangTrait::ShlAssign,
        LangTrait::ShrAssign,
        LangTrait::Index,
        LangTrait::IndexMut,
        LangTrait::PartialEq,
        LangTrait::Eq,
        LangTrait::PartialOrd,
        LangTrait::Ord,
        LangTrait::Clone,
        LangTrait::Copy,
        LangTrait::Default,
        LangTrait::Debug,
        LangTrait::Sized,
        LangTrait::Fn,
        LangTrait::FnMut,
        LangTrait::FnOnce,
    ];

    /// Source name.
    pub fn name(self) -> &'static str {
        match self {
            LangTrait::Add => "Add",
            LangTrait::Sub => "Sub",
            LangTrait::Mul => "Mul",
            LangTrait::Div => "Div",
            LangTrait::Rem => "Rem",
            LangTrait::Neg => "Neg",
            LangTrait::Not => "Not",
            LangTrait::BitAnd => "BitAnd",
            LangTrait::BitOr => "BitOr",
            LangTrait::BitXor => "BitXor",
            LangTrait::Shl => "Shl",
            LangTrait::Shr => "Shr",
            LangTrait::AddAssign => "AddAssign",
            LangTrait::SubAssign => "SubAssign",
            LangTrait::MulAssign => "MulAssign",
            LangTrait::DivAssign => "DivAssign",
            LangTrait::RemAssign => "RemAssign",
            LangTrait::BitAndAssign => "BitAndAssign",
            LangTrait::BitOrAssign => "BitOrAssign",
            LangTrait::BitXorAssign => "BitXorAssign",
            LangTrait::ShlAssign => "ShlAssign",
            LangTrait::ShrAssign => "ShrAssign",
            LangTrait::Index => "Index",
            LangTrait::IndexMut => "IndexMut",
            LangTrait::PartialEq => "PartialEq",
            LangTrait::Eq => "Eq",
            LangTrait::PartialOrd => "PartialOrd",
            LangTrait::Ord => "Ord",
            LangTrait::Clone => "Clone",
            LangTrait::Copy => "Copy",
            LangTrait::Default => "Default",
            LangTrait::Debug => "Debug",
            LangTrait::Sized => "Sized",
            LangTrait::Fn => "Fn",
            LangTrait::FnMut => "FnMut",
            LangTrait::FnOnce => "FnOnce",
        }
    }

    /// The trait of a name.
    pub fn from_name(s: &str) -> Option<LangTrait> {
        LangTrait::ALL.iter().copied().find(|t| t.name() == s)
    }

    /// The module of `core` that defines the trait (`ops`, `cmp`, `clone`, ...).
    pub fn core_module(self) -> &'static str {
        match self {
            LangTrait::PartialEq | LangTrait::Eq | LangTrait::PartialOrd | LangTrait::Ord => "cmp",
            LangTrait::Clone => "clone",
            LangTrait::Copy | LangTrait::Sized => "marker",
            LangTrait::Fn | LangTrait::FnMut | LangTrait::FnOnce => "ops",
            LangTrait::Default => "default",
            LangTrait::Debug => "fmt",
            _ => "ops",
        }
    }

    /// True for the traits in Rust's prelude (usable without a path).
    pub fn in_prelude(self) -> bool {
        matches!(
            self,
            LangTrait::PartialEq
                | LangTrait::Eq
                | LangTrait::PartialOrd
                | LangTrait::Ord
                | LangTrait::Clone
                | LangTrait::Copy
                | LangTrait::Default
                | LangTrait::Sized
                | LangTrait::Fn
                | LangTrait::FnMut
                | LangTrait::FnOnce
        )
    }

    /// True for `Fn`, `FnMut` and `FnOnce`.
    pub fn is_fn(self) -> bool {
        matches!(self, LangTrait::Fn | LangTrait::FnMut | LangTrait::FnOnce)
    }

    /// The methods an impl provides (required first) and whether each is required.
    pub fn methods(self) -> &'static [(&'static str, bool)] {
        match self {
            LangTrait::Add => &[("add", true)],
            LangTrait::Sub => &[("sub", true)],
            LangTrait::Mul => &[("mul", true)],
            LangTrait::Div => &[("div", true)],
            LangTrait::Rem => &[("rem", true)],
            LangTrait::Neg => &[("neg", true)],
            LangTrait::Not => &[("not", true)],
            LangTrait::BitAnd => &[("bitand", true)],
            LangTrait::BitOr => &[("bitor", true)],
            LangTrait::BitXor => &[("bitxor", true)],
            LangTrait::Shl => &[("shl", true)],
            LangTrait::Shr => &[("shr", true)],
            LangTrait::AddAssign => &[("add_assign", true)],
            LangTrait::SubAssign => &[("sub_assign", true)],
            LangTrait::MulAssign => &[("mul_assign", true)],
            LangTrait::DivAssign => &[("div_assign", true)],
            LangTrait::RemAssign => &[("rem_assign", true)],
            LangTrait::BitAndAssign => &[("bitand_assign", true)],
            LangTrait::BitOrAssign => &[("bitor_assign", true)],
            LangTrait::BitXorAssign => &[("bitxor_assign", true)],
            LangTrait::ShlAssign => &[("shl_assign", true)],
            LangTrait::ShrAssign => &[("shr_assign", true)],
            LangTrait::Index => &[("index", true)],
            LangTrait::IndexMut => &[("index_mut", true)],
            LangTrait::PartialEq => &[("eq", true), ("ne", false)],
            LangTrait::PartialOrd => &[
                ("partial_cmp", true),
                ("lt", false),
                ("le", false),
                ("gt", false),
                ("ge", false),
            ],
            LangTrait::Ord => &[
                ("cmp", true),
                ("max", false),
                ("min", false),
                ("clamp", false),
            ],
            LangTrait::Clone => &[("clone", true)],
            LangTrait::Default => &[("default", true)],
            LangTrait::Eq
            | LangTrait::Copy
            | LangTrait::Debug
            | LangTrait::Sized
            | LangTrait::Fn
            | LangTrait::FnMut
            | LangTrait::FnOnce => &[],
        }
    }

    /// Associated types an impl defines.
    pub fn assoc_types(self) -> &'static [&'static str] {
        match self {
            LangTrait::Add
            | LangTrait::Sub
            | LangTrait::Mul
            | LangTrait::Div
            | LangTrait::Rem
            | LangTrait::Neg
            | LangTrait::Not
            | LangTrait::BitAnd
            | LangTrait::BitOr
            | LangTrait::BitXor
            | LangTrait::Shl
            | LangTrait::Shr
            | LangTrait::Index => &["Output"],
            _ => &[],
        }
    }

    /// True for the binary operator traits whose right operand defaults to `Self`.
    pub fn has_rhs(self) -> bool {
        !matches!(
            self,
            LangTrait::Neg
                | LangTrait::Not
                | LangTrait::Clone
                | LangTrait::Copy
                | LangTrait::Default
                | LangTrait::Debug
                | LangTrait::Sized
                | LangTrait::Eq
                | LangTrait::Ord
                | LangTrait::Index
                | LangTrait::IndexMut
                | LangTrait::Fn
                | LangTrait::FnMut
                | LangTrait::FnOnce
        )
    }
}

/// A trait: user-defined or known to the compiler.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TraitKind {
    User(TraitId),
    Lang(LangTrait),
}

/// A trait with its generic arguments (`Add<f32>`, `Shape`).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct TraitRef {
    /// The trait.
    pub kind: TraitKind,
    /// Its generic arguments (without `Self`).
    pub args: Vec<Ty>,
    /// Associated type constraints (`Output = T`).
    pub bindings: Vec<(String, Ty)>,
}

/// The type of one closure expression: where it is defined (a function instance and the
/// expression's key) and its signature.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ClosureTy {
    /// The function whose body holds the closure.
    pub def_fn: usize,
    /// That function instance's generic arguments.
    pub def_substs: Vec<Ty>,
    /// Key (address) of the closure expression.
    pub key: usize,
    /// Parameter types.
    pub params: Vec<Ty>,
    /// Result type.
    pub ret: Ty,
}

/// A type. `Var` is an inference variable; `Param` a generic parameter of the item
/// being checked (replaced by the instance's type before a body is checked).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    Unit,
    Never,
    Bool,
    Char,
    Int(IntTy),
    Float(FloatTy),
    /// A struct or enum with its generic arguments.
    Adt(AdtId, Vec<Ty>),
    /// A tuple of two or more elements, or `(T,)`.
    Tuple(Vec<Ty>),
    Array(Box<Ty>, u32),
    /// `[T]` (only behind a reference or pointer).
    Slice(Box<Ty>),
    /// `&T` (`true` = `&mut T`).
    Ref(bool, Box<Ty>),
    /// `*const T` / `*mut T` (`true` = mut).
    Ptr(bool, Box<Ty>),
    Simd(SimdTy),
    /// `&'static str` (only string literals).
    Str,
    /// Generic parameter by index.
    Param(u32),
    /// Associated type `<T as Trait>::Name` of a type that is not known yet.
    Proj(Box<Ty>, Option<Box<TraitRef>>, String),
    /// `_` written in a type (an inference variable in bodies).
    Infer,
    /// A closure (its captures are found from its definition).
    Closure(Box<ClosureTy>),
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

    /// True for types without a runtime value (structural: `()`, `!`, `[T; 0]`).
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

    /// True if the type mentions a generic parameter, projection or `_`.
    pub fn has_params(&self) -> bool {
        match self {
            Ty::Param(_) | Ty::Proj(..) | Ty::Infer => true,
            Ty::Adt(_, a) | Ty::Tuple(a) => a.iter().any(Ty::has_params),
            Ty::Array(e, _) | Ty::Slice(e) | Ty::Ref(_, e) | Ty::Ptr(_, e) => e.has_params(),
            Ty::Closure(c) => c.params.iter().any(Ty::has_params) || c.ret.has_params(),
            _ => false,
        }
    }

    /// True if the type mentions an inference variable.
    pub fn has_vars(&self) -> bool {
        match self {
            Ty::Var(_) => true,
            Ty::Adt(_, a) | Ty::Tuple(a) => a.iter().any(Ty::has_vars),
            Ty::Array(e, _) | Ty::Slice(e) | Ty::Ref(_, e) | Ty::Ptr(_, e) => e.has_vars(),
            Ty::Closure(c) => c.params.iter().any(Ty::has_vars) || c.ret.has_vars(),
            Ty::Proj(t, tr, _) => {
                t.has_vars()
                    || tr
                        .as_ref()
                        .is_some_and(|tr| tr.args.iter().any(Ty::has_vars))
            }
            _ => false,
        }
    }

    /// Replaces generic parameters by `substs` (projections are left for the caller
    /// to normalise).
    pub fn subst(&self, substs: &[Ty]) -> Ty {
        if substs.is_empty() {
            return self.clone();
        }
        self.map(&mut |t| match t {
            Ty::Param(i) => substs.get(*i as usize).cloned(),
            _ => None,
        })
    }

    /// Rebuilds the type bottom-up, replacing every node for which `f` returns a type.
    pub fn map(&self, f: &mut impl FnMut(&Ty) -> Option<Ty>) -> Ty {
        if let Some(t) = f(self) {
            return t;
        }
        match self {
            Ty::Adt(a, args) => Ty::Adt(*a, args.iter().map(|t| t.map(f)).collect()),
            Ty::Tuple(ts) => Ty::Tuple(ts.iter().map(|t| t.map(f)).collect()),
            Ty::Array(e, n) => Ty::Array(Box::new(e.map(f)), *n),
            Ty::Slice(e) => Ty::Slice(Box::new(e.map(f))),
            Ty::Ref(m, e) => Ty::Ref(*m, Box::new(e.map(f))),
            Ty::Ptr(m, e) => Ty::Ptr(*m, Box::new(e.map(f))),
            Ty::Closure(c) => Ty::Closure(Box::new(ClosureTy {
                def_fn: c.def_fn,
                def_substs: c.def_substs.clone(),
                key: c.key,
                params: c.params.iter().map(|t| t.map(f)).collect(),
                ret: c.ret.map(f),
            })),
            Ty::Proj(t, tr, n) => Ty::Proj(
                Box::new(t.map(f)),
                tr.as_ref().map(|tr| {
                    Box::new(TraitRef {
                        kind: tr.kind,
                        args: tr.args.iter().map(|t| t.map(f)).collect(),
                        bindings: tr
                            .bindings
                            .iter()
                            .map(|(n, t)| (n.clone(), t.map(f)))
                            .collect(),
                    })
                }),
                n.clone(),
            ),
            other => other.clone(),
        }
    }
}

/// Displays a type with ADT names supplied by `names`.
pub struct TyDisplay<'a> {
    /// The type.
    pub ty: &'a Ty,
    /// ADT names by id.
    pub names: &'a dyn Fn(AdtId) -> String,
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
            Ty::Adt(s, args) => {
                write!(f, "{}", (self.names)(*s))?;
                if !args.is_empty() {
                    write!(f, "<")?;
                    for (i, a) in args.iter().enumerate() {
                        if i > 0 {
                            write!(f, ", ")?;
                        }
                        write!(f, "{}", sub(a))?;
                    }
                    write!(f, ">")?;
                }
                Ok(())
            }
            Ty::Tuple(ts) => {
                write!(f, "(")?;
                for (i, a) in ts.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{}", sub(a))?;
                }
                if ts.len() == 1 {
                    write!(f, ",")?;
                }
                write!(f, ")")
            }
            Ty::Array(t, n) => write!(f, "[{}; {n}]", sub(t)),
            Ty::Slice(t) => write!(f, "[{}]", sub(t)),
            Ty::Ref(m, t) => write!(f, "&{}{}", if *m { "mut " } else { "" }, sub(t)),
            Ty::Ptr(m, t) => write!(f, "*{} {}", if *m { "mut" } else { "const" }, sub(t)),
            Ty::Simd(SimdTy::F32x4) => write!(f, "f32x4"),
            Ty::Simd(SimdTy::I32x4) => write!(f, "i32x4"),
            Ty::Str => write!(f, "&str"),
            Ty::Param(i) => write!(f, "T{i}"),
            Ty::Proj(t, _, n) => write!(f, "{}::{n}", sub(t)),
            Ty::Infer => write!(f, "_"),
            Ty::Closure(c) => {
                write!(f, "closure(")?;
                for (i, p) in c.params.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{}", sub(p))?;
                }
                write!(f, ") -> {}", sub(&c.ret))
            }
            Ty::Var(_) => write!(f, "{{number}}"),
        }
    }
}
