//! Stage 2: collect the items of the kernel and prelude crates into a [`Program`].
//!
//! - [`items`]: walks modules (and items nested in function bodies), defines names,
//!   rejects items outside the TRaX-Rust subset, collects structs, enums, traits, impls,
//!   functions, consts and statics;
//! - [`paths`]: name lookup (modules, `use`, `crate`/`self`/`super`/`trax`/`std`,
//!   Rust's prelude names);
//! - [`types`]: syntactic types to [`Ty`] (generic parameters, `Self`, aliases,
//!   associated types), impl matching and associated-type normalisation;
//! - [`consts`]: integer constant expressions (array lengths, discriminants, immediates).

mod consts;
mod items;
mod paths;
mod types;

pub use paths::{path_segs, prim_type};
pub use types::TyScope;

use crate::diag::{Diagnostic, FileId, SourceMap};
use crate::parse::ParsedCrate;
use crate::ty::TyDisplay;
use crate::ty::{AdtId, FloatTy, IntTy, LangTrait, SimdTy, TraitId, TraitKind, TraitRef, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::{Block, Expr, Signature, Type};

/// Index of a module.
pub type ModId = usize;
/// Index of a function.
pub type FnId = usize;
/// Index of a `const` or `static`.
pub type GlobalId = usize;
/// Index of an impl block.
pub type ImplId = usize;
/// Index of a type alias.
pub type AliasId = usize;

/// What a path names.
#[derive(Clone, Debug, PartialEq)]
pub enum PathRes {
    Mod(ModId),
    Adt(AdtId),
    /// An enum variant.
    Variant(AdtId, usize),
    Alias(AliasId),
    Trait(TraitKind),
    Simd(SimdTy),
    Prim(Ty),
    Fn(FnId),
    Global(GlobalId),
    /// `Type::name` where the type is builtin (`f32::MAX`, `f32x4::splat`).
    PrimAssoc(Ty, String),
    /// `Struct::name` / `Enum::name`: an associated item, found by the type checker.
    AdtAssoc(AdtId, String),
    /// `Alias::name`.
    AliasAssoc(AliasId, String),
    /// `Trait::name` (`Default::default`).
    TraitAssoc(TraitKind, String),
    /// `std::f32::consts::PI` and friends.
    FloatConst(FloatTy, String),
    /// `std::ptr::read_volatile`, `core::mem::swap` and friends (`module::name`).
    StdFn(&'static str, &'static str),
}

/// Which namespace a path's last segment is looked up in.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Ns {
    Type,
    Value,
}

/// A `use` declaration (one leaf of a use tree).
#[derive(Clone, Debug)]
pub struct UseDecl {
    /// Path segments.
    pub segs: Vec<String>,
    /// Bound name (`None` for a glob import).
    pub name: Option<String>,
    /// Span for errors.
    pub span: Span,
}

/// A module (or the items of a block, which see the enclosing scope's names).
pub struct Module {
    /// Display path (`crate::a::b` style, with the crate's name first).
    pub path: String,
    /// Parent module.
    pub parent: Option<ModId>,
    /// File holding the module's items.
    pub file: FileId,
    /// Root module of its crate.
    pub crate_root: ModId,
    /// For a block's items: the enclosing scope, whose names stay visible.
    pub enclosing: Option<ModId>,
    pub(crate) types: HashMap<String, PathRes>,
    pub(crate) values: HashMap<String, PathRes>,
    pub(crate) uses: Vec<UseDecl>,
}

impl Module {
    /// A value-namespace item defined directly in this module.
    pub fn values_get(&self, name: &str) -> Option<PathRes> {
        self.values.get(name).cloned()
    }

    /// The module `self`/`super` refer to (a block's items use their enclosing module).
    pub fn real(&self, id: ModId, p: &Program) -> ModId {
        match self.enclosing {
            Some(e) => p.modules[e].real(e, p),
            None => id,
        }
    }
}

/// A bound `T: Trait` on a generic parameter (or on `Self`).
#[derive(Clone, Debug)]
pub struct Bound {
    /// The bounded type (usually `Param(i)`).
    pub ty: Ty,
    /// The trait.
    pub tr: TraitRef,
}

/// Generic parameters in scope of an item: the parent's (impl or trait, `Self` first
/// for traits) followed by the item's own.
#[derive(Clone, Debug, Default)]
pub struct Generics {
    /// Parameter names (`Self` for a trait's self type).
    pub names: Vec<String>,
    /// Number of parameters inherited from the impl or trait.
    pub parent: usize,
    /// Bounds from `<T: Tr>` and `where` clauses.
    pub bounds: Vec<Bound>,
}

impl Generics {
    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// True without parameters.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// How a struct or variant is constructed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ctor {
    /// `S { a: .. }`.
    Named,
    /// `S(..)`.
    Tuple,
    /// `S`.
    Unit,
}

/// A field of a struct or variant.
#[derive(Clone, Debug)]
pub struct FieldDef {
    /// Name (`0`, `1`, ... for tuple fields).
    pub name: String,
    /// Type (may mention the ADT's generic parameters).
    pub ty: Ty,
    /// Span of the field's name (or type, for tuple fields).
    pub span: Span,
}

/// A struct (one variant) or an enum variant.
#[derive(Clone, Debug)]
pub struct VariantDef {
    /// Name (the struct's name for structs).
    pub name: String,
    /// Constructor form.
    pub ctor: Ctor,
    /// Fields in declaration (layout) order.
    pub fields: Vec<FieldDef>,
    /// Discriminant value (enums).
    pub discr: i128,
    /// Span of the name.
    pub span: Span,
}

/// Derived traits of an ADT.
#[derive(Clone, Debug, Default)]
pub struct Derives(pub Vec<LangTrait>);

impl Derives {
    /// True if `t` is derived.
    pub fn has(&self, t: LangTrait) -> bool {
        self.0.contains(&t)
    }
}

/// A struct or enum definition.
pub struct AdtDef<'a> {
    /// Name.
    pub name: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Span of the name.
    pub span: Span,
    /// True for enums.
    pub is_enum: bool,
    /// Generic parameters.
    pub generics: Generics,
    /// Variants (one for a struct).
    pub variants: Vec<VariantDef>,
    /// `#[derive(..)]`.
    pub derives: Derives,
    /// Discriminant type (`#[repr(u8)]`...; `isize` by default).
    pub repr: IntTy,
    /// The `#[default]` variant of an enum deriving `Default`.
    pub default_variant: Option<usize>,
    /// The syntax item (fields' types are resolved after every ADT is known).
    pub(crate) syntax: AdtSyntax<'a>,
}

/// Syntax of an ADT.
#[derive(Clone, Copy)]
pub(crate) enum AdtSyntax<'a> {
    Struct(&'a syn::ItemStruct),
    Enum(&'a syn::ItemEnum),
}

impl AdtDef<'_> {
    /// Fields of a struct.
    pub fn fields(&self) -> &[FieldDef] {
        &self.variants[0].fields
    }

    /// True for an enum whose variants carry no data.
    pub fn is_fieldless_enum(&self) -> bool {
        self.is_enum && self.variants.iter().all(|v| v.fields.is_empty())
    }

    /// The variant with a name.
    pub fn variant(&self, name: &str) -> Option<usize> {
        self.variants.iter().position(|v| v.name == name)
    }
}

/// How a method takes `self`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recv {
    Value,
    Ref,
    RefMut,
}

/// Inlining hint from `#[inline]` attributes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InlineHint {
    None,
    Hint,
    Always,
    Never,
}

/// Where a function is defined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FnParent {
    /// A free function.
    Free,
    /// A method or associated function of an impl block.
    Impl(ImplId),
    /// A trait method (a declaration or a default body).
    Trait(TraitId),
}

/// A function or method.
pub struct FnDef<'a> {
    /// Name for DWARF and messages (`Vec3::dot` for methods).
    pub name: String,
    /// Unique symbol name (instances of generic functions append their arguments).
    pub symbol: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Signature.
    pub sig: &'a Signature,
    /// Body (`None` for a trait method without a default).
    pub body: Option<&'a Block>,
    /// `Self` type for methods and associated functions (`Param(0)` in traits).
    pub self_ty: Option<Ty>,
    /// Receiver kind for methods.
    pub receiver: Option<Recv>,
    /// Parameter types, `self` first for methods.
    pub params: Vec<Ty>,
    /// Return type.
    pub ret: Ty,
    /// Inline hint.
    pub inline: InlineHint,
    /// Generic parameters in scope.
    pub generics: Generics,
    /// Where it is defined.
    pub parent: FnParent,
    /// `const fn`.
    pub is_const: bool,
    /// Attributes (for `#[inline]`).
    pub(crate) attrs: &'a [syn::Attribute],
    /// Declared in an `extern "C"` block: C code defines it (no body, its own name).
    pub foreign: bool,
}

/// A `const` or `static`.
pub struct GlobalDef<'a> {
    /// Name.
    pub name: String,
    /// Unique symbol name.
    pub symbol: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Declared type.
    pub ty: Ty,
    /// Initializer (`None` for a trait's const without a default).
    pub expr: Option<&'a Expr>,
    /// `None` for `const`, `Some(mutable)` for `static`.
    pub is_static: Option<bool>,
    /// `Self` type for associated consts.
    pub self_ty: Option<Ty>,
    /// Name span.
    pub span: Span,
    /// Type syntax span (for errors).
    pub ty_span: Span,
    /// Declared type syntax.
    pub decl_ty: &'a Type,
    /// Generic parameters in scope (of the impl or trait).
    pub generics: Generics,
}

/// A trait definition.
pub struct TraitDef<'a> {
    /// Name.
    pub name: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Name span.
    pub span: Span,
    /// Generic parameters, `Self` first.
    pub generics: Generics,
    /// Supertraits of `Self`.
    pub supertraits: Vec<TraitRef>,
    /// Methods (with or without a default body).
    pub methods: Vec<(String, FnId)>,
    /// Associated consts (with or without a default).
    pub consts: Vec<(String, GlobalId)>,
    /// Associated types.
    pub types: Vec<String>,
    pub(crate) item: &'a syn::ItemTrait,
}

/// An impl block.
pub struct ImplDef<'a> {
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Generic parameters.
    pub generics: Generics,
    /// The implementing type (may mention the impl's parameters).
    pub self_ty: Ty,
    /// The implemented trait.
    pub trait_: Option<TraitRef>,
    /// Methods and associated functions.
    pub fns: HashMap<String, FnId>,
    /// Associated consts.
    pub consts: HashMap<String, GlobalId>,
    /// Associated types.
    pub types: HashMap<String, Ty>,
    /// The syntax.
    pub item: &'a syn::ItemImpl,
}

/// A type alias.
pub struct AliasDef<'a> {
    /// Name.
    pub name: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Generic parameter names.
    pub params: Vec<String>,
    /// Aliased type.
    pub ty: &'a Type,
}

/// ADTs of the prelude's language module the compiler refers to.
#[derive(Clone, Copy, Debug, Default)]
pub struct LangItems {
    /// `Option<T>`.
    pub option: Option<AdtId>,
    /// `Result<T, E>`.
    pub result: Option<AdtId>,
    /// `core::cmp::Ordering`.
    pub ordering: Option<AdtId>,
    /// The prelude's `lang` module (Rust's prelude names fall back to it).
    pub module: Option<ModId>,
    /// The prelude's `libm` module (float methods call its functions).
    pub libm: Option<ModId>,
}

/// The whole program after name collection.
pub struct Program<'a> {
    /// Source files.
    pub sources: &'a SourceMap,
    /// Modules.
    pub modules: Vec<Module>,
    /// Structs and enums.
    pub adts: Vec<AdtDef<'a>>,
    /// Functions.
    pub fns: Vec<FnDef<'a>>,
    /// Consts and statics.
    pub globals: Vec<GlobalDef<'a>>,
    /// Traits.
    pub traits: Vec<TraitDef<'a>>,
    /// Impl blocks.
    pub impls: Vec<ImplDef<'a>>,
    /// Type aliases.
    pub aliases: Vec<AliasDef<'a>>,
    /// The module holding the items of each block that has items (by block address).
    pub block_mods: HashMap<usize, ModId>,
    /// Kernel crate root.
    pub kernel_root: ModId,
    /// Prelude crate root.
    pub trax_root: Option<ModId>,
    /// Language items.
    pub lang: LangItems,
}

impl<'a> Program<'a> {
    /// Creates a diagnostic.
    pub fn err(
        &self,
        file: FileId,
        span: Span,
        id: &'static str,
        msg: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic::new(self.sources, file, span, id, msg)
    }

    /// Display string of a type.
    pub fn ty_str(&self, t: &Ty) -> String {
        let names = |s: AdtId| self.adts[s].name.clone();
        TyDisplay {
            ty: t,
            names: &names,
        }
        .to_string()
    }

    /// Display string of a trait.
    pub fn trait_name(&self, t: TraitKind) -> String {
        match t {
            TraitKind::User(id) => self.traits[id].name.clone(),
            TraitKind::Lang(l) => l.name().to_string(),
        }
    }

    /// The function `name` of the prelude's `lang` module, if present.
    pub fn lang_fn(&self, name: &str) -> Option<FnId> {
        match self.modules[self.lang.module?].values.get(name) {
            Some(PathRes::Fn(f)) => Some(*f),
            _ => None,
        }
    }

    /// The function `name` of the prelude's `libm` module, if present.
    pub fn libm_fn(&self, name: &str) -> Option<FnId> {
        match self.modules[self.lang.libm?].values.get(name) {
            Some(PathRes::Fn(f)) => Some(*f),
            _ => None,
        }
    }
}

/// Builds the program from the parsed kernel crate and (optionally) the prelude crate.
pub fn collect<'a>(
    sources: &'a SourceMap,
    kernel: &'a ParsedCrate,
    kernel_name: &str,
    prelude: Option<&'a ParsedCrate>,
) -> Result<Program<'a>, Vec<Diagnostic>> {
    items::collect(sources, kernel, kernel_name, prelude)
}
