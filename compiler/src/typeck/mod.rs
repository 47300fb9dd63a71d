//! Stage 3: type checking of function bodies and global initializers.
//!
//! Produces a [`Body`] per function instance: the type of every expression, what every
//! path, call, method and operator resolves to, coercions, pattern bindings, locals and
//! the parsed contents of builtin macros. Unsuffixed literals get inference variables
//! that default to `i32`/`f64` like rustc.
//!
//! Generic functions are checked once per instance (the generic arguments substituted
//! first), so every body the lowering sees is monomorphic; instances are discovered from
//! the calls of checked bodies ([`check_program`]). Type checking rejects everything the
//! lowering cannot handle.
//!
//! - [`infer`]: inference variables, unification, coercions, the per-body context;
//! - [`expr`]: blocks, statements, expressions, operators, control flow, `for` loops;
//! - [`pat`]: patterns (bindings, default binding modes, enums, tuples, structs, slices);
//! - [`path`]: paths (locals, consts, variants, associated consts), struct literals;
//! - [`call`]: calls, method calls, the builtin catalogue, `core` functions;
//! - [`closure`]: closure expressions (captures, signatures from `Fn` bounds), closure calls;
//! - [`traits`]: method and trait resolution, operator/`Index` impls, derived methods;
//! - [`macros`]: `print!`/`panic!`/`assert!`/`matches!`/TRaX macros and format strings.

mod call;
mod closure;
mod expr;
mod infer;
mod macros;
mod pat;
mod path;
mod traits;

pub use expr::{
    classify_iter, is_simple_range, split_guard, strip as strip_expr, IterSyn, SeqMode,
};
pub use macros::{Align, Count, FmtPiece, FmtSpec, FmtTrait, MacroCall, TraxArg};

use crate::builtins::Builtin;
use crate::diag::{DResult, Diagnostic};
use crate::resolve::{FnId, GlobalId, Program};
use crate::ty::{AdtId, ClosureTy, FloatTy, IntTy, LangTrait, Ty};
use proc_macro2::Span;
use std::collections::{HashMap, HashSet};

/// Index of a local variable in a [`Body`].
pub type LocalId = usize;

/// Key of an AST node: its address (the AST is immutable and outlives every body).
pub fn key<T>(x: &T) -> usize {
    x as *const T as usize
}

/// A local variable or parameter.
#[derive(Clone, Debug)]
pub struct LocalInfo {
    /// Source name.
    pub name: String,
    /// Type.
    pub ty: Ty,
    /// Declaration span.
    pub span: Span,
}

/// What a path expression refers to.
#[derive(Clone, Debug)]
pub enum Res {
    Local(LocalId),
    /// A const or static (with the generic arguments of an associated const).
    Global(GlobalId, Vec<Ty>),
    /// A unit struct or unit enum variant (the type is the expression's).
    Unit(AdtId, usize),
    Int(IntTy, i128),
    Float(FloatTy, f64),
}

/// How a method call's receiver is adjusted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecvAdj {
    /// Dereferences applied to the receiver expression.
    pub derefs: u32,
    /// Then borrowed (`Some(mutable)`).
    pub autoref: Option<bool>,
}

/// Resolved callee of a call, method call or overloaded operator.
#[derive(Clone, Debug)]
pub enum Callee {
    /// A user function instance; arguments in order (receiver first for methods).
    Fn {
        /// Function.
        func: FnId,
        /// Generic arguments (empty for non-generic functions).
        substs: Vec<Ty>,
        /// Method-call receiver adjustment.
        recv: RecvAdj,
    },
    /// A builtin from the catalogue; for methods the receiver is the first argument.
    Builtin {
        /// Which builtin.
        b: Builtin,
        /// Receiver adjustment.
        recv: RecvAdj,
    },
    /// A tuple struct or tuple variant constructor.
    Ctor {
        /// The ADT.
        adt: AdtId,
        /// Variant (0 for structs).
        variant: usize,
    },
    /// A closure: the callee expression (after `derefs` dereferences) is its environment.
    Closure {
        /// The closure's type.
        ty: ClosureTy,
        /// References dereferenced to reach the closure.
        derefs: u32,
    },
    /// A method the compiler derives (`clone`, `eq`, `ne`, `default`) on a type.
    Derived {
        /// The trait.
        tr: LangTrait,
        /// Method name.
        method: &'static str,
        /// `Self`.
        ty: Ty,
        /// Receiver adjustment.
        recv: RecvAdj,
    },
}

/// An overloaded operator.
#[derive(Clone, Debug)]
pub enum OpCall {
    /// Calls a user impl's method. Operands are passed by value, or by reference for
    /// `eq`/`ne`/`partial_cmp`/`lt`/... (`by_ref`).
    Fn {
        /// The method.
        func: FnId,
        /// Its generic arguments.
        substs: Vec<Ty>,
        /// Operands by reference.
        by_ref: bool,
        /// `partial_cmp` standing for `<`, `<=`, `>`, `>=`: compare its result.
        via_partial_cmp: bool,
        /// The result is negated (`!=` through `eq`).
        negate: bool,
    },
    /// Compiler-derived structural `==`/`!=` on a type.
    DerivedEq {
        /// The compared type.
        ty: Ty,
        /// `!=`.
        negate: bool,
    },
}

/// A coercion applied to an expression's value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Adjust {
    /// `&[T; N]` to `&[T]` (`&mut` too).
    Unsize(u32),
    /// Dereferenced `n` times (a reference to a primitive used as an operand).
    Deref(u32),
}

/// How a pattern binding binds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindMode {
    /// By value (a copy).
    Value,
    /// By reference (`ref`, `ref mut` or a default binding mode).
    Ref(bool),
}

/// What a pattern node matches.
#[derive(Clone, Debug)]
pub struct PatInfo {
    /// The type of the value it matches (after the dereferences).
    pub ty: Ty,
    /// References dereferenced first (default binding modes).
    pub derefs: u32,
    /// What a path, tuple-struct or struct pattern names.
    pub kind: PatKind,
}

/// The resolution of a pattern.
#[derive(Clone, Debug, PartialEq)]
pub enum PatKind {
    /// Nothing to resolve (literals, tuples, wildcards, ranges).
    Plain,
    /// A variant (or the one variant of a struct).
    Variant(AdtId, usize),
    /// A constant's value (integers, `bool`, `char`).
    Const(i128),
    /// A binding (the identifier is not a constant or unit variant).
    Binding,
}

/// Per source of a `for` loop's iterator chain (in pre-order of [`IterSyn`]).
#[derive(Clone, Debug)]
pub struct IterInfo {
    /// Element type produced by this node.
    pub elem: Ty,
    /// For sequence sources: derefs of the base to reach the array or `&[T]`.
    pub derefs: u32,
    /// For sequence sources: the array length (`None`: a slice).
    pub len: Option<u32>,
}

/// What a closure expression captures from the enclosing body.
#[derive(Clone, Debug, Default)]
pub struct ClosureInfo {
    /// Locals of enclosing scopes it uses, in order of first use.
    pub captures: Vec<LocalId>,
    /// `move`: captured by value (a copy); else by reference.
    pub by_move: bool,
}

/// Results of checking one body.
#[derive(Default, Debug)]
pub struct Body {
    /// Type of every expression (before its coercion, if any).
    pub tys: HashMap<usize, Ty>,
    /// Coercions of expression values.
    pub adjust: HashMap<usize, Adjust>,
    /// Path resolutions.
    pub res: HashMap<usize, Res>,
    /// Calls and method calls.
    pub callees: HashMap<usize, Callee>,
    /// Overloaded operators (binary, unary, compound assignment) and `Index` impls.
    pub ops: HashMap<usize, OpCall>,
    /// Auto-derefs applied to the base of field and index expressions.
    pub derefs: HashMap<usize, u32>,
    /// Field index of field expressions and struct-literal fields.
    pub fields: HashMap<usize, usize>,
    /// Struct literals: (ADT, variant).
    pub structs: HashMap<usize, (AdtId, usize)>,
    /// Builtin macros by address of their `syn::Macro`.
    pub macros: HashMap<usize, MacroCall>,
    /// Locals (parameters first).
    pub locals: Vec<LocalInfo>,
    /// Local bound by each `PatIdent`, and how.
    pub binds: HashMap<usize, (LocalId, BindMode)>,
    /// Pattern nodes.
    pub pats: HashMap<usize, PatInfo>,
    /// `for` loops: one entry per node of the iterator chain.
    pub fors: HashMap<usize, Vec<IterInfo>>,
    /// `?` expressions: the early-return constructor (the function's `Option`/`Result`).
    pub tries: HashMap<usize, Ty>,
    /// Closure expressions (their parameters' and body's types are in `tys`, `binds`).
    pub closures: HashMap<usize, ClosureInfo>,
}

impl Body {
    /// The type of an expression after its coercion.
    pub fn ty_of(&self, e: &syn::Expr) -> Ty {
        let t = self.tys.get(&key(e)).cloned().unwrap_or(Ty::Unit);
        match (self.adjust.get(&key(e)), t) {
            (Some(Adjust::Unsize(_)), Ty::Ref(m, inner)) => match *inner {
                Ty::Array(el, _) => Ty::Ref(m, Box::new(Ty::Slice(el))),
                other => Ty::Ref(m, Box::new(other)),
            },
            (Some(Adjust::Deref(n)), mut t) => {
                for _ in 0..*n {
                    if let Ty::Ref(_, inner) = t {
                        t = *inner;
                    }
                }
                t
            }
            (_, t) => t,
        }
    }
}

/// An item that has a body: a function instance or a const/static instance.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Item {
    Fn(FnId, Vec<Ty>),
    Global(GlobalId, Vec<Ty>),
}

/// The checked program: a body per reachable instance.
#[derive(Default)]
pub struct Checked {
    /// Bodies by instance.
    pub bodies: HashMap<Item, Body>,
}

impl Checked {
    /// The body of a function instance.
    pub fn fn_body(&self, f: FnId, substs: &[Ty]) -> Option<&Body> {
        self.bodies.get(&Item::Fn(f, substs.to_vec()))
    }

    /// The body of a const/static instance.
    pub fn global_body(&self, g: GlobalId, substs: &[Ty]) -> Option<&Body> {
        self.bodies.get(&Item::Global(g, substs.to_vec()))
    }
}

/// Most instances of generic items one program may create (guards polymorphic recursion).
const MAX_INSTANCES: usize = 10_000;

/// Type-checks every non-generic function and global, then every instance of a generic
/// item they use (transitively). Errors are collected per body.
pub fn check_program(p: &Program) -> (Checked, Vec<Diagnostic>) {
    let mut out = Checked::default();
    let mut errs: Vec<Diagnostic> = Vec::new();
    let mut queue: Vec<Item> = Vec::new();
    for (f, fd) in p.fns.iter().enumerate() {
        if fd.generics.is_empty() && fd.body.is_some() {
            queue.push(Item::Fn(f, Vec::new()));
        }
    }
    for (g, gd) in p.globals.iter().enumerate() {
        if gd.generics.is_empty() && gd.expr.is_some() {
            queue.push(Item::Global(g, Vec::new()));
        }
    }
    queue.reverse();
    let mut seen: HashSet<Item> = queue.iter().cloned().collect();
    while let Some(item) = queue.pop() {
        let r = match &item {
            Item::Fn(f, s) => infer::check_fn(p, *f, s),
            Item::Global(g, s) => infer::check_global(p, *g, s),
        };
        match r {
            Ok(body) => {
                for dep in instances_used(p, &body) {
                    if seen.insert(dep.clone()) {
                        if seen.len() > MAX_INSTANCES {
                            let (file, span) = match &item {
                                Item::Fn(f, _) => (p.fns[*f].file, p.fns[*f].sig.ident.span()),
                                Item::Global(g, _) => (p.globals[*g].file, p.globals[*g].span),
                            };
                            errs.push(p.err(
                                file,
                                span,
                                "instantiation-limit",
                                "reached the limit of generic instances (polymorphic recursion?)",
                            ));
                            return (out, errs);
                        }
                        queue.push(dep);
                    }
                }
                out.bodies.insert(item, body);
            }
            Err(e) => {
                if !errs.contains(&e) {
                    errs.push(e);
                }
                out.bodies.insert(item, Body::default());
            }
        }
    }
    (out, errs)
}

/// The generic instances a body uses (functions, methods, associated consts).
fn instances_used(p: &Program, b: &Body) -> Vec<Item> {
    let mut out = Vec::new();
    let mut fnc = |f: FnId, s: &Vec<Ty>| {
        if !p.fns[f].generics.is_empty() && p.fns[f].body.is_some() {
            out.push(Item::Fn(f, s.clone()));
        }
    };
    for c in b.callees.values() {
        if let Callee::Fn { func, substs, .. } = c {
            fnc(*func, substs);
        }
    }
    for o in b.ops.values() {
        if let OpCall::Fn { func, substs, .. } = o {
            fnc(*func, substs);
        }
    }
    for r in b.res.values() {
        if let Res::Global(g, s) = r {
            if !p.globals[*g].generics.is_empty() && p.globals[*g].expr.is_some() {
                out.push(Item::Global(*g, s.clone()));
            }
        }
    }
    // User impls the compiler's derived `==` and `default()` call for nested types.
    let mut lang: Vec<(LangTrait, Ty)> = Vec::new();
    for o in b.ops.values() {
        if let OpCall::DerivedEq { ty, .. } = o {
            lang.push((LangTrait::PartialEq, ty.clone()));
        }
    }
    for (k, c) in &b.callees {
        match c {
            Callee::Derived { tr, ty, .. } => lang.push((*tr, ty.clone())),
            Callee::Builtin {
                b: Builtin::MemTake,
                ..
            } => {
                if let Some(t) = b.tys.get(k) {
                    lang.push((LangTrait::Default, t.clone()));
                }
            }
            _ => {}
        }
    }
    for m in b.macros.values() {
        if let MacroCall::Abort {
            cmp: Some((a, _, _)),
            ..
        } = m
        {
            if let Some(t) = b.tys.get(&key(&**a)) {
                lang.push((LangTrait::PartialEq, t.clone()));
            }
        }
    }
    for (tr, t) in lang {
        lang_uses(p, tr, &t, &mut out, 0);
    }
    out.sort_by_key(|i| format!("{i:?}"));
    out.dedup();
    out
}

/// Generic user impls of `tr` that the compiler's derived code calls for `t` or its
/// parts.
fn lang_uses(p: &Program, tr: LangTrait, t: &Ty, out: &mut Vec<Item>, depth: u32) {
    if depth > 32 {
        return;
    }
    let method = tr.methods().first().map(|m| m.0).unwrap_or("");
    for im in &p.impls {
        let Some(itr) = &im.trait_ else { continue };
        if itr.kind != crate::ty::TraitKind::Lang(tr) {
            continue;
        }
        let mut substs = vec![None; im.generics.len()];
        if !p.match_ty(&im.self_ty, t, &mut substs) {
            continue;
        }
        if let Some(f) = im.fns.get(method) {
            if !p.fns[*f].generics.is_empty() {
                let s: Vec<Ty> = substs.into_iter().map(|x| x.unwrap_or(Ty::Unit)).collect();
                out.push(Item::Fn(*f, s));
            }
        }
        return;
    }
    match t {
        Ty::Adt(a, args) => {
            for v in &p.adts[*a].variants {
                for f in &v.fields {
                    let ft = p.normalize(&f.ty.subst(args)).unwrap_or(Ty::Unit);
                    lang_uses(p, tr, &ft, out, depth + 1);
                }
            }
        }
        Ty::Tuple(ts) => ts.iter().for_each(|x| lang_uses(p, tr, x, out, depth + 1)),
        Ty::Array(e, _) | Ty::Ref(_, e) => lang_uses(p, tr, e, out, depth + 1),
        _ => {}
    }
}

/// Value of an associated float constant.
pub fn float_const(f: FloatTy, name: &str) -> Option<f64> {
    use std::f64::consts as c;
    let v = match (f, name) {
        (FloatTy::F32, "MAX") => f32::MAX as f64,
        (FloatTy::F32, "MIN") => f32::MIN as f64,
        (FloatTy::F32, "EPSILON") => f32::EPSILON as f64,
        (FloatTy::F32, "MIN_POSITIVE") => f32::MIN_POSITIVE as f64,
        (FloatTy::F64, "MAX") => f64::MAX,
        (FloatTy::F64, "MIN") => f64::MIN,
        (FloatTy::F64, "EPSILON") => f64::EPSILON,
        (FloatTy::F64, "MIN_POSITIVE") => f64::MIN_POSITIVE,
        (_, "INFINITY") => f64::INFINITY,
        (_, "NEG_INFINITY") => f64::NEG_INFINITY,
        (_, "NAN") => f64::NAN,
        (_, "PI") => c::PI,
        (_, "TAU") => c::TAU,
        (_, "E") => c::E,
        (_, "FRAC_PI_2") => c::FRAC_PI_2,
        (_, "FRAC_PI_3") => c::FRAC_PI_3,
        (_, "FRAC_PI_4") => c::FRAC_PI_4,
        (_, "FRAC_PI_6") => c::FRAC_PI_6,
        (_, "FRAC_PI_8") => c::FRAC_PI_8,
        (_, "FRAC_1_PI") => c::FRAC_1_PI,
        (_, "FRAC_2_PI") => c::FRAC_2_PI,
        (_, "FRAC_2_SQRT_PI") => c::FRAC_2_SQRT_PI,
        (_, "SQRT_2") => c::SQRT_2,
        (_, "FRAC_1_SQRT_2") => c::FRAC_1_SQRT_2,
        (_, "LN_2") => c::LN_2,
        (_, "LN_10") => c::LN_10,
        (_, "LOG2_E") => c::LOG2_E,
        (_, "LOG10_E") => c::LOG10_E,
        (_, "LOG2_10") => c::LOG2_10,
        (_, "LOG10_2") => c::LOG10_2,
        _ => return None,
    };
    Some(v)
}

/// Type-checks one function instance (exposed for tests and tools).
pub fn check_fn(p: &Program, f: FnId, substs: &[Ty]) -> DResult<Body> {
    infer::check_fn(p, f, substs)
}
