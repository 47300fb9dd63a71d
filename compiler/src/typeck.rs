//! Stage 3: type checking of function bodies and global initializers.
//!
//! Produces a [`Body`] per function: the type of every expression, what every path and
//! method call resolves to, locals, and the parsed contents of builtin macros. Unsuffixed
//! literals get inference variables that default to `i32`/`f64` like rustc.

use crate::diag::{DResult, Diagnostic, FileId};
use crate::resolve::{path_segs, FnId, GlobalId, ModId, Ns, OpTrait, PathRes, Program, Recv};
use crate::ty::{FloatTy, IntTy, SimdTy, StructId, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::punctuated::Punctuated;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, Pat, Stmt, Token, UnOp};
use trax_runtime::isa::{AbortKind, OperandKind, TraxInstr, TRAX_INSTRUCTIONS};

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
    Global(GlobalId),
    UnitStruct(StructId),
    Int(IntTy, i128),
    Float(FloatTy, f64),
}

/// Builtin functions and methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// Float method by name (`sqrt`, `min`, ...).
    Float(&'static str),
    /// `f32::from_bits` / `f64::from_bits`.
    FromBits(FloatTy),
    /// Integer method by name.
    Int(&'static str),
    /// Raw pointer method by name (`add`, `offset`, `is_null`, `read`, `write`, ...).
    Ptr(&'static str),
    /// `std::ptr::*` functions.
    StdPtr(&'static str),
    /// SIMD associated function or method by name.
    Simd(SimdTy, &'static str),
    /// `array.len()`.
    Len(u32),
}

/// Resolved callee of a call or method call.
#[derive(Clone, Copy, Debug)]
pub enum Callee {
    /// A user function; arguments in order (receiver first for methods).
    Fn {
        /// Function.
        func: FnId,
        /// For method-call syntax: number of derefs applied to the receiver.
        derefs: u32,
        /// For method-call syntax: pass the receiver by reference.
        autoref: bool,
    },
    /// A builtin; for method syntax the receiver (after `derefs` derefs) is the first argument.
    Builtin {
        /// Which builtin.
        b: Builtin,
        /// Derefs applied to the receiver.
        derefs: u32,
    },
}

/// A piece of a `print!` format string.
#[derive(Debug)]
pub enum FmtPiece {
    /// Literal text.
    Lit(String),
    /// A `{}` argument.
    Arg(Box<Expr>),
    /// A `{:?}` argument (panic messages render it with `Debug`; `print!` as `{}`).
    Debug(Box<Expr>),
}

/// Operand of a `__trax_op!`.
#[derive(Debug)]
pub enum TraxArg {
    /// Register operand.
    Reg(Box<Expr>),
    /// Immediate.
    Imm(u32),
}

/// A builtin macro invocation, parsed.
#[derive(Debug)]
pub enum MacroCall {
    /// `print!`/`println!`.
    Print(Vec<FmtPiece>),
    /// `panic!`, `unreachable!`, `todo!`, `unimplemented!`, `assert!`, `assert_eq!`,
    /// `assert_ne!`.
    Abort {
        /// Kind reported to the emulator.
        kind: AbortKind,
        /// The panic message as Rust formats it; for `assert_eq!`/`assert_ne!` without the
        /// `left:`/`right:` lines, which the lowering appends from the compared values.
        pieces: Vec<FmtPiece>,
        /// Condition that must hold (assert).
        cond: Option<Box<Expr>>,
        /// Values compared (assert_eq/ne) and whether they must differ.
        cmp: Option<(Box<Expr>, Box<Expr>, bool)>,
    },
    /// A macro that generates no code: the `debug_assert!` family (debug assertions are
    /// off, as in `trax native`); its arguments are type-checked only.
    Nothing,
    /// `__trax_op!`.
    TraxOp {
        /// Instruction.
        instr: &'static TraxInstr,
        /// Use operands in operand order.
        args: Vec<TraxArg>,
    },
    /// `__trax_mtc2!(n, x)`.
    Mtc2(u32, Box<Expr>),
    /// `__trax_mfc2!(n)`.
    Mfc2(u32),
    /// `__trax_symbol_addr!("name")`.
    SymbolAddr(String),
}

/// How a `for` loop iterates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForKind {
    /// `a..b` / `a..=b`, optionally `.rev()`, optionally `.step_by(n)`.
    Range {
        /// `..=`.
        inclusive: bool,
        /// `.rev()`.
        rev: bool,
    },
    /// Over an array by value or by reference (`&arr`, `arr.iter()`), with derefs of the base.
    Array {
        /// Elements are references.
        by_ref: bool,
        /// Derefs to reach the array.
        derefs: u32,
    },
}

/// The syntactic parts of a `for` loop's iterator.
pub struct ForIter<'e> {
    /// Kind.
    pub kind: ForKind,
    /// Range start, or the array expression.
    pub start: &'e Expr,
    /// Range end.
    pub end: Option<&'e Expr>,
    /// `.step_by(n)`.
    pub step: Option<&'e Expr>,
}

/// Results of checking one body.
#[derive(Default, Debug)]
pub struct Body {
    /// Type of every expression.
    pub tys: HashMap<usize, Ty>,
    /// Path resolutions.
    pub res: HashMap<usize, Res>,
    /// Calls and method calls.
    pub callees: HashMap<usize, Callee>,
    /// Overloaded operators (binary, unary, compound assignment).
    pub ops: HashMap<usize, FnId>,
    /// Auto-derefs applied to the base of field and index expressions.
    pub derefs: HashMap<usize, u32>,
    /// Builtin macros by address of their `syn::Macro`.
    pub macros: HashMap<usize, MacroCall>,
    /// Locals (parameters first).
    pub locals: Vec<LocalInfo>,
    /// Local bound by each `PatIdent`.
    pub pat_locals: HashMap<usize, LocalId>,
    /// `for` loop kinds by loop expression.
    pub fors: HashMap<usize, ForKind>,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum VarKind {
    Any,
    Int,
    Float,
}

struct LoopCx {
    label: Option<String>,
    /// `Some` for `loop` (type of break values so far).
    brk: Option<Option<Ty>>,
}

struct Cx<'p, 'a> {
    p: &'p Program<'a>,
    module: ModId,
    file: FileId,
    self_ty: Option<Ty>,
    ret: Ty,
    body: Body,
    scopes: Vec<HashMap<String, LocalId>>,
    loops: Vec<LoopCx>,
    vars: Vec<(VarKind, Option<Ty>)>,
    /// Whether each local may be assigned (`mut`, or declared without initializer).
    local_mut: Vec<bool>,
}

/// Type-checks a function body.
pub fn check_fn(p: &Program, f: FnId) -> DResult<Body> {
    let fd = &p.fns[f];
    let mut cx = Cx::new(p, fd.module, fd.self_ty.clone(), fd.ret.clone());
    cx.scopes.push(HashMap::new());
    for (i, arg) in fd.sig.inputs.iter().enumerate() {
        let ty = fd.params[i].clone();
        match arg {
            syn::FnArg::Receiver(r) => {
                let id = cx.new_local("self", ty, r.self_token.span);
                cx.local_mut[id] = r.mutability.is_some();
                cx.scopes[0].insert("self".into(), id);
            }
            syn::FnArg::Typed(pt) => match &*pt.pat {
                Pat::Ident(pi) => {
                    let id = cx.new_local(&pi.ident.to_string(), ty, pi.ident.span());
                    cx.local_mut[id] = pi.mutability.is_some();
                    cx.body.pat_locals.insert(key(pi), id);
                    cx.scopes[0].insert(pi.ident.to_string(), id);
                }
                _ => {
                    cx.new_local("_", ty, pt.span());
                }
            },
        }
    }
    if fd.receiver.is_some() {
        debug_assert!(matches!(
            fd.sig.inputs.first(),
            Some(syn::FnArg::Receiver(_))
        ));
    }
    let _ = Recv::Value;
    let t = cx.block(fd.body)?;
    let ret = fd.ret.clone();
    cx.unify(&t, &ret, block_tail_span(fd.body))?;
    cx.finish()
}

/// Type-checks the initializer of a const or static.
pub fn check_global(p: &Program, g: GlobalId) -> DResult<Body> {
    let gd = &p.globals[g];
    let mut cx = Cx::new(p, gd.module, gd.self_ty.clone(), Ty::Unit);
    cx.scopes.push(HashMap::new());
    let t = cx.expr(gd.expr)?;
    cx.unify(&t, &gd.ty, gd.expr.span())?;
    cx.finish()
}

fn block_tail_span(b: &syn::Block) -> Span {
    match b.stmts.last() {
        Some(Stmt::Expr(e, None)) => e.span(),
        _ => b.brace_token.span.close(),
    }
}

/// Classifies a `for` loop iterator expression.
pub fn classify_for<'e>(e: &'e Expr) -> Option<ForIter<'e>> {
    match e {
        Expr::Paren(p) => classify_for(&p.expr),
        Expr::Range(r) => Some(ForIter {
            kind: ForKind::Range {
                inclusive: matches!(r.limits, syn::RangeLimits::Closed(_)),
                rev: false,
            },
            start: r.start.as_deref()?,
            end: Some(r.end.as_deref()?),
            step: None,
        }),
        Expr::MethodCall(m) if m.method == "rev" && m.args.is_empty() => {
            let mut inner = classify_for(&m.receiver)?;
            match &mut inner.kind {
                ForKind::Range { rev, .. } if !*rev && inner.step.is_none() => *rev = true,
                _ => return None,
            }
            Some(inner)
        }
        Expr::MethodCall(m) if m.method == "step_by" && m.args.len() == 1 => {
            let mut inner = classify_for(&m.receiver)?;
            match inner.kind {
                ForKind::Range { rev: false, .. } if inner.step.is_none() => {
                    inner.step = Some(&m.args[0])
                }
                _ => return None,
            }
            Some(inner)
        }
        Expr::MethodCall(m) if m.method == "iter" && m.args.is_empty() => Some(ForIter {
            kind: ForKind::Array {
                by_ref: true,
                derefs: 0,
            },
            start: &m.receiver,
            end: None,
            step: None,
        }),
        Expr::Reference(r) if r.mutability.is_none() => Some(ForIter {
            kind: ForKind::Array {
                by_ref: true,
                derefs: 0,
            },
            start: &r.expr,
            end: None,
            step: None,
        }),
        other => Some(ForIter {
            kind: ForKind::Array {
                by_ref: false,
                derefs: 0,
            },
            start: other,
            end: None,
            step: None,
        }),
    }
}

const FLOAT_METHODS: &[&str] = &[
    "sqrt",
    "abs",
    "min",
    "max",
    "floor",
    "ceil",
    "round",
    "trunc",
    "fract",
    "clamp",
    "powi",
    "mul_add",
    "is_nan",
    "is_finite",
    "is_infinite",
    "is_sign_negative",
    "is_sign_positive",
    "to_bits",
    "signum",
    "recip",
    "copysign",
    "to_degrees",
    "to_radians",
];
const LIBM_METHODS: &[&str] = &[
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "atan2",
    "exp",
    "exp2",
    "ln",
    "log",
    "log2",
    "log10",
    "powf",
    "sinh",
    "cosh",
    "tanh",
    "cbrt",
    "hypot",
    "sin_cos",
    "exp_m1",
    "ln_1p",
    "rem_euclid",
    "div_euclid",
];
const INT_METHODS: &[&str] = &[
    "min",
    "max",
    "abs",
    "wrapping_add",
    "wrapping_sub",
    "wrapping_mul",
    "wrapping_neg",
    "pow",
    "count_ones",
    "leading_zeros",
    "trailing_zeros",
    "clamp",
    "is_power_of_two",
    "rotate_left",
    "rotate_right",
    "swap_bytes",
];
const PTR_METHODS: &[&str] = &[
    "add",
    "sub",
    "offset",
    "is_null",
    "read",
    "write",
    "read_volatile",
    "write_volatile",
];
const SIMD_METHODS: &[&str] = &[
    "get", "min", "max", "sqrt", "abs", "mul_add", "lt", "le", "gt", "ge", "eq", "to_i32x4", "any",
    "all", "to_f32x4",
];

fn intern(list: &[&'static str], name: &str) -> Option<&'static str> {
    list.iter().copied().find(|m| *m == name)
}

impl<'p, 'a> Cx<'p, 'a> {
    fn new(p: &'p Program<'a>, module: ModId, self_ty: Option<Ty>, ret: Ty) -> Self {
        Cx {
            p,
            module,
            file: p.modules[module].file,
            self_ty,
            ret,
            body: Body::default(),
            scopes: Vec::new(),
            loops: Vec::new(),
            vars: Vec::new(),
            local_mut: Vec::new(),
        }
    }

    fn err(&self, span: Span, id: &'static str, msg: impl Into<String>) -> Diagnostic {
        self.p.err(self.file, span, id, msg)
    }

    fn new_local(&mut self, name: &str, ty: Ty, span: Span) -> LocalId {
        self.body.locals.push(LocalInfo {
            name: name.to_string(),
            ty,
            span,
        });
        self.local_mut.push(false);
        self.body.locals.len() - 1
    }

    fn fresh(&mut self, k: VarKind) -> Ty {
        self.vars.push((k, None));
        Ty::Var(self.vars.len() as u32 - 1)
    }

    /// Shallow resolution of inference variables.
    fn shallow(&self, t: &Ty) -> Ty {
        let mut t = t.clone();
        while let Ty::Var(v) = t {
            match &self.vars[v as usize].1 {
                Some(b) => t = b.clone(),
                None => return t,
            }
        }
        t
    }

    /// Full resolution, defaulting unbound variables.
    fn deep(&self, t: &Ty) -> Ty {
        match self.shallow(t) {
            Ty::Var(v) => match self.vars[v as usize].0 {
                VarKind::Int | VarKind::Any => Ty::Int(IntTy::I32),
                VarKind::Float => Ty::Float(FloatTy::F64),
            },
            Ty::Array(e, n) => Ty::Array(Box::new(self.deep(&e)), n),
            Ty::Ref(m, e) => Ty::Ref(m, Box::new(self.deep(&e))),
            Ty::Ptr(m, e) => Ty::Ptr(m, Box::new(self.deep(&e))),
            other => other,
        }
    }

    fn show(&self, t: &Ty) -> String {
        match self.shallow(t) {
            Ty::Var(v) => match self.vars[v as usize].0 {
                VarKind::Int => "{integer}".into(),
                VarKind::Float => "{float}".into(),
                VarKind::Any => "_".into(),
            },
            t => self.p.ty_str(&self.deep(&t)),
        }
    }

    fn mismatch(&self, span: Span, expected: &Ty, found: &Ty) -> Diagnostic {
        self.err(
            span,
            "type-mismatch",
            format!(
                "mismatched types: expected `{}`, found `{}`",
                self.show(expected),
                self.show(found)
            ),
        )
    }

    fn unify(&mut self, a: &Ty, b: &Ty, span: Span) -> DResult<()> {
        if !self.try_unify(a, b) {
            return Err(self.mismatch(span, b, a));
        }
        Ok(())
    }

    fn try_unify(&mut self, a: &Ty, b: &Ty) -> bool {
        let a = self.shallow(a);
        let b = self.shallow(b);
        match (&a, &b) {
            (Ty::Never, _) | (_, Ty::Never) => true,
            (Ty::Var(x), Ty::Var(y)) => {
                if x == y {
                    return true;
                }
                let (kx, ky) = (self.vars[*x as usize].0, self.vars[*y as usize].0);
                let k = match (kx, ky) {
                    (VarKind::Any, k) | (k, VarKind::Any) => k,
                    (k1, k2) if k1 == k2 => k1,
                    _ => return false,
                };
                self.vars[*y as usize].0 = k;
                self.vars[*x as usize].1 = Some(b.clone());
                true
            }
            (Ty::Var(x), t) | (t, Ty::Var(x)) => {
                let ok = match self.vars[*x as usize].0 {
                    VarKind::Any => true,
                    VarKind::Int => t.is_int(),
                    VarKind::Float => t.is_float(),
                };
                if ok {
                    self.vars[*x as usize].1 = Some(t.clone());
                }
                ok
            }
            (Ty::Array(x, n), Ty::Array(y, m)) => n == m && self.try_unify(x, y),
            (Ty::Ref(m1, x), Ty::Ref(m2, y)) => (m1 == m2 || (*m1 && !*m2)) && self.try_unify(x, y),
            (Ty::Ptr(m1, x), Ty::Ptr(m2, y)) => m1 == m2 && self.try_unify(x, y),
            // Coercion of a reference to a raw pointer (same LLVM type).
            (Ty::Ref(m1, x), Ty::Ptr(m2, y)) => (*m1 || !*m2) && self.try_unify(x, y),
            _ => a == b,
        }
    }

    fn finish(mut self) -> DResult<Body> {
        for l in 0..self.body.locals.len() {
            let t = self.body.locals[l].ty.clone();
            if let Ty::Var(v) = self.shallow(&t) {
                if self.vars[v as usize].0 == VarKind::Any {
                    let l = &self.body.locals[l];
                    return Err(self.err(
                        l.span,
                        "type-annotation-needed",
                        format!("type annotations needed for `{}`", l.name),
                    ));
                }
            }
            self.body.locals[l].ty = self.deep(&t);
        }
        let keys: Vec<usize> = self.body.tys.keys().copied().collect();
        for k in keys {
            let t = self.deep(&self.body.tys[&k]);
            self.body.tys.insert(k, t);
        }
        Ok(self.body)
    }

    fn lookup_local(&self, name: &str) -> Option<LocalId> {
        self.scopes.iter().rev().find_map(|s| s.get(name).copied())
    }

    fn record(&mut self, e: &Expr, t: Ty) -> Ty {
        self.body.tys.insert(key(e), t.clone());
        t
    }

    // ---------------------------------------------------------------- blocks, statements

    fn block(&mut self, b: &syn::Block) -> DResult<Ty> {
        self.scopes.push(HashMap::new());
        let r = self.block_inner(b);
        self.scopes.pop();
        r
    }

    fn block_inner(&mut self, b: &syn::Block) -> DResult<Ty> {
        let mut diverges = false;
        let n = b.stmts.len();
        for (i, s) in b.stmts.iter().enumerate() {
            let last = i + 1 == n;
            match s {
                Stmt::Local(l) => {
                    self.let_stmt(l)?;
                }
                Stmt::Expr(e, semi) => {
                    let t = self.expr(e)?;
                    if last && semi.is_none() {
                        return Ok(if diverges { Ty::Never } else { t });
                    }
                    if matches!(self.shallow(&t), Ty::Never) {
                        diverges = true;
                    } else if semi.is_none() && !matches!(self.shallow(&t), Ty::Unit) {
                        return Err(self.mismatch(e.span(), &Ty::Unit, &t));
                    }
                }
                Stmt::Macro(m) => {
                    let t = self.mac(&m.mac, m.span())?;
                    if last && m.semi_token.is_none() {
                        return Ok(if diverges { Ty::Never } else { t });
                    }
                    if matches!(t, Ty::Never) {
                        diverges = true;
                    }
                }
                Stmt::Item(it) => {
                    return Err(self.err(it.span(), "unsupported-nested-item", "items inside function bodies are not supported in TRaX-Rust; move them to module level"));
                }
            }
        }
        Ok(if diverges { Ty::Never } else { Ty::Unit })
    }

    fn let_stmt(&mut self, l: &syn::Local) -> DResult<()> {
        let (pat, ann) = match &l.pat {
            Pat::Type(pt) => (
                &*pt.pat,
                Some(
                    self.p
                        .resolve_type(self.module, self.file, &pt.ty, self.self_ty.as_ref())?,
                ),
            ),
            other => (other, None),
        };
        let ty = match ann {
            Some(t) => t,
            None => self.fresh(VarKind::Any),
        };
        if let Some(init) = &l.init {
            if let Some((e, _)) = &init.diverge {
                return Err(self.err(
                    e.span(),
                    "unsupported-let-else",
                    "`let ... else` is not supported in TRaX-Rust",
                ));
            }
            let t = self.expr(&init.expr)?;
            self.unify(&t, &ty, init.expr.span())?;
        }
        match pat {
            Pat::Ident(pi) if pi.subpat.is_none() && pi.by_ref.is_none() => {
                let id = self.new_local(&pi.ident.to_string(), ty, pi.ident.span());
                self.local_mut[id] = pi.mutability.is_some() || l.init.is_none();
                self.body.pat_locals.insert(key(pi), id);
                self.scopes
                    .last_mut()
                    .expect("scope")
                    .insert(pi.ident.to_string(), id);
                Ok(())
            }
            Pat::Wild(_) => Ok(()),
            Pat::Tuple(t) => Err(self.err(
                t.span(),
                "unsupported-tuple",
                "tuple patterns are not supported in TRaX-Rust",
            )),
            other => Err(self.err(
                other.span(),
                "unsupported-pattern",
                "only identifier patterns are supported in `let`",
            )),
        }
    }

    // ---------------------------------------------------------------- expressions

    fn expr(&mut self, e: &Expr) -> DResult<Ty> {
        let t = self.expr_inner(e)?;
        Ok(self.record(e, t))
    }

    fn expr_inner(&mut self, e: &Expr) -> DResult<Ty> {
        match e {
            Expr::Lit(l) => self.lit(&l.lit),
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Block(b) => {
                if let Some(l) = &b.label {
                    return Err(self.err(
                        l.span(),
                        "unsupported-labeled-block",
                        "labeled blocks are not supported in TRaX-Rust",
                    ));
                }
                self.block(&b.block)
            }
            Expr::Unsafe(u) => self.block(&u.block),
            Expr::Path(p) => self.path_expr(e, p),
            Expr::Binary(b) => self.binary(e, b),
            Expr::Unary(u) => self.unary(e, u),
            Expr::Assign(a) => {
                let lt = self.place_expr(&a.left)?;
                let rt = self.expr(&a.right)?;
                self.unify(&rt, &lt, a.right.span())?;
                Ok(Ty::Unit)
            }
            Expr::Cast(c) => self.cast(c),
            Expr::If(i) => self.if_expr(i),
            Expr::While(w) => {
                let c = self.expr(&w.cond)?;
                if let Expr::Let(l) = &*w.cond {
                    return Err(self.err(
                        l.span(),
                        "unsupported-while-let",
                        "`while let` is not supported in TRaX-Rust",
                    ));
                }
                self.unify(&c, &Ty::Bool, w.cond.span())?;
                self.loops.push(LoopCx {
                    label: w.label.as_ref().map(|l| l.name.ident.to_string()),
                    brk: None,
                });
                let b = self.block(&w.body);
                self.loops.pop();
                let b = b?;
                self.unify(&b, &Ty::Unit, w.body.brace_token.span.close())?;
                Ok(Ty::Unit)
            }
            Expr::Loop(l) => {
                self.loops.push(LoopCx {
                    label: l.label.as_ref().map(|l| l.name.ident.to_string()),
                    brk: Some(None),
                });
                let b = self.block(&l.body);
                let cx = self.loops.pop().expect("loop");
                let b = b?;
                self.unify(&b, &Ty::Unit, l.body.brace_token.span.close())?;
                Ok(cx.brk.flatten().unwrap_or(Ty::Never))
            }
            Expr::ForLoop(f) => self.for_loop(e, f),
            Expr::Break(b) => {
                let label = b.label.as_ref().map(|l| l.ident.to_string());
                let vt = match &b.expr {
                    Some(v) => Some(self.expr(v)?),
                    None => None,
                };
                let idx = self.loop_index(label.as_deref(), b.span())?;
                match (&self.loops[idx].brk, vt) {
                    (None, Some(_)) => {
                        return Err(self.err(
                            b.span(),
                            "break-value-outside-loop",
                            "`break` with a value is only allowed in `loop`",
                        ))
                    }
                    (None, None) => {}
                    (Some(prev), vt) => {
                        let vt = vt.unwrap_or(Ty::Unit);
                        match prev.clone() {
                            Some(p) => self.unify(&vt, &p, b.span())?,
                            None => self.loops[idx].brk = Some(Some(vt)),
                        }
                    }
                }
                Ok(Ty::Never)
            }
            Expr::Continue(c) => {
                let label = c.label.as_ref().map(|l| l.ident.to_string());
                self.loop_index(label.as_deref(), c.span())?;
                Ok(Ty::Never)
            }
            Expr::Return(r) => {
                let t = match &r.expr {
                    Some(v) => self.expr(v)?,
                    None => Ty::Unit,
                };
                let ret = self.ret.clone();
                self.unify(&t, &ret, r.span())?;
                Ok(Ty::Never)
            }
            Expr::Call(c) => self.call(e, c),
            Expr::MethodCall(m) => self.method_call(e, m),
            Expr::Field(f) => {
                let bt = self.expr(&f.base)?;
                let (bt, derefs) = self.autoderef(&bt);
                self.body.derefs.insert(key(e), derefs);
                let name = match &f.member {
                    syn::Member::Named(n) => n.to_string(),
                    syn::Member::Unnamed(i) => i.index.to_string(),
                };
                match bt {
                    Ty::Struct(s) => {
                        match self.p.structs[s].fields.iter().find(|(n, _)| *n == name) {
                            Some((_, t)) => Ok(t.clone()),
                            None => Err(self.err(
                                f.member.span(),
                                "unknown-field",
                                format!(
                                    "struct `{}` has no field `{name}`",
                                    self.p.structs[s].name
                                ),
                            )),
                        }
                    }
                    other => Err(self.err(
                        f.member.span(),
                        "unknown-field",
                        format!("type `{}` has no field `{name}`", self.show(&other)),
                    )),
                }
            }
            Expr::Index(i) => {
                let bt = self.expr(&i.expr)?;
                let (bt, derefs) = self.autoderef(&bt);
                self.body.derefs.insert(key(e), derefs);
                let it = self.expr(&i.index)?;
                if let Expr::Range(r) = &*i.index {
                    return Err(self.err(
                        r.span(),
                        "unsupported-slice",
                        "slicing is not supported in TRaX-Rust",
                    ));
                }
                self.unify(&it, &Ty::Int(IntTy::Usize), i.index.span())?;
                match bt {
                    Ty::Array(el, _) => Ok(*el),
                    other => Err(self.err(
                        i.expr.span(),
                        "not-indexable",
                        format!(
                            "cannot index a value of type `{}` (only arrays can be indexed)",
                            self.show(&other)
                        ),
                    )),
                }
            }
            Expr::Reference(r) => {
                let t = self.expr(&r.expr)?;
                if r.mutability.is_some() {
                    self.check_place(&r.expr)?;
                }
                Ok(Ty::Ref(r.mutability.is_some(), Box::new(t)))
            }
            Expr::Array(a) => {
                let el = self.fresh(VarKind::Any);
                for x in &a.elems {
                    let t = self.expr(x)?;
                    self.unify(&t, &el, x.span())?;
                }
                Ok(Ty::Array(Box::new(el), a.elems.len() as u32))
            }
            Expr::Repeat(r) => {
                let t = self.expr(&r.expr)?;
                let n = self.p.eval_len(self.module, self.file, &r.len)?;
                if !(0..=(1 << 24)).contains(&n) {
                    return Err(self.err(
                        r.len.span(),
                        "invalid-array-length",
                        format!("array length {n} is out of range"),
                    ));
                }
                Ok(Ty::Array(Box::new(t), n as u32))
            }
            Expr::Struct(s) => self.struct_lit(s),
            Expr::Tuple(t) if t.elems.is_empty() => Ok(Ty::Unit),
            Expr::Tuple(t) => Err(self.err(
                t.span(),
                "unsupported-tuple",
                "tuples are not supported in TRaX-Rust",
            )),
            Expr::Match(m) => self.match_expr(m),
            Expr::Macro(m) => self.mac(&m.mac, m.span()),
            Expr::Range(r) => Err(self.err(
                r.span(),
                "unsupported-range",
                "range expressions are only supported as `for` loop iterators",
            )),
            Expr::Closure(c) => Err(self.err(
                c.span(),
                "unsupported-closure",
                "closures are not supported in TRaX-Rust",
            )),
            Expr::Async(c) => Err(self.err(
                c.span(),
                "unsupported-async",
                "async blocks are not supported in TRaX-Rust",
            )),
            Expr::Await(c) => Err(self.err(
                c.span(),
                "unsupported-async",
                "`.await` is not supported in TRaX-Rust",
            )),
            Expr::Try(c) => Err(self.err(
                c.span(),
                "unsupported-try",
                "the `?` operator is not supported in TRaX-Rust",
            )),
            Expr::TryBlock(c) => Err(self.err(
                c.span(),
                "unsupported-try",
                "try blocks are not supported in TRaX-Rust",
            )),
            Expr::Let(c) => Err(self.err(
                c.span(),
                "unsupported-if-let",
                "`if let`/`let` expressions are not supported in TRaX-Rust",
            )),
            Expr::Yield(c) => Err(self.err(
                c.span(),
                "unsupported-yield",
                "`yield` is not supported in TRaX-Rust",
            )),
            Expr::RawAddr(c) => Err(self.err(
                c.span(),
                "unsupported-raw-addr",
                "`&raw` is not supported in TRaX-Rust; use `&x as *const T`",
            )),
            Expr::Const(c) => Err(self.err(
                c.span(),
                "unsupported-const-block",
                "const blocks are not supported in TRaX-Rust",
            )),
            other => Err(self.err(
                other.span(),
                "unsupported-expression",
                "this kind of expression is not supported in TRaX-Rust",
            )),
        }
    }

    fn loop_index(&self, label: Option<&str>, span: Span) -> DResult<usize> {
        let found = match label {
            None => self.loops.len().checked_sub(1),
            Some(l) => self
                .loops
                .iter()
                .rposition(|c| c.label.as_deref() == Some(l)),
        };
        found.ok_or_else(|| match label {
            None => self.err(
                span,
                "break-outside-loop",
                "`break`/`continue` outside of a loop",
            ),
            Some(l) => self.err(
                span,
                "unknown-label",
                format!("use of undeclared label `'{l}`"),
            ),
        })
    }

    fn lit(&mut self, l: &Lit) -> DResult<Ty> {
        match l {
            Lit::Int(i) => {
                i.base10_parse::<i128>().map_err(|_| {
                    self.err(i.span(), "invalid-literal", "integer literal is too large")
                })?;
                match i.suffix() {
                    "" => Ok(self.fresh(VarKind::Int)),
                    "f32" => Ok(Ty::Float(FloatTy::F32)),
                    "f64" => Ok(Ty::Float(FloatTy::F64)),
                    // Range checks (a negated literal may reach `MIN`) come after inference,
                    // in `consteval`.
                    s => match IntTy::from_name(s) {
                        Some(t) => Ok(Ty::Int(t)),
                        None => Err(self.err(
                            i.span(),
                            "invalid-literal",
                            format!("invalid suffix `{s}`"),
                        )),
                    },
                }
            }
            Lit::Float(f) => match f.suffix() {
                "" => Ok(self.fresh(VarKind::Float)),
                "f32" => Ok(Ty::Float(FloatTy::F32)),
                "f64" => Ok(Ty::Float(FloatTy::F64)),
                s => Err(self.err(f.span(), "invalid-literal", format!("invalid suffix `{s}`"))),
            },
            Lit::Bool(_) => Ok(Ty::Bool),
            Lit::Char(_) => Ok(Ty::Char),
            Lit::Byte(_) => Ok(Ty::Int(IntTy::U8)),
            Lit::Str(_) => Ok(Ty::Str),
            other => Err(self.err(
                other.span(),
                "unsupported-literal",
                "this kind of literal is not supported in TRaX-Rust",
            )),
        }
    }

    fn path_expr(&mut self, e: &Expr, p: &syn::ExprPath) -> DResult<Ty> {
        if p.qself.is_some() {
            return Err(self.err(
                p.span(),
                "unsupported-qualified-path",
                "qualified paths are not supported in TRaX-Rust",
            ));
        }
        if let Some(id) = p
            .path
            .get_ident()
            .and_then(|i| self.lookup_local(&i.to_string()))
        {
            self.body.res.insert(key(e), Res::Local(id));
            return Ok(self.body.locals[id].ty.clone());
        }
        let r = self.resolve_value_path(&p.path)?;
        let (res, ty) = match r {
            PathRes::Global(g) => (Res::Global(g), self.p.globals[g].ty.clone()),
            PathRes::Struct(s) => (Res::UnitStruct(s), Ty::Struct(s)),
            PathRes::PrimAssoc(Ty::Int(t), n) if n == "MAX" => (Res::Int(t, t.max()), Ty::Int(t)),
            PathRes::PrimAssoc(Ty::Int(t), n) if n == "MIN" => (Res::Int(t, t.min()), Ty::Int(t)),
            PathRes::PrimAssoc(Ty::Int(t), n) if n == "BITS" => {
                (Res::Int(IntTy::U32, t.bits() as i128), Ty::Int(IntTy::U32))
            }
            PathRes::PrimAssoc(Ty::Float(f), n) => match float_const(f, &n) {
                Some(v) => (Res::Float(f, v), Ty::Float(f)),
                None => {
                    return Err(self.err(
                        p.span(),
                        "unresolved-path",
                        format!("no associated constant `{n}` on `{}`", f.name()),
                    ))
                }
            },
            PathRes::FloatConst(f, n) => match float_const(f, &n) {
                Some(v) => (Res::Float(f, v), Ty::Float(f)),
                None => {
                    return Err(self.err(
                        p.span(),
                        "unresolved-path",
                        format!("unknown constant `{n}`"),
                    ))
                }
            },
            PathRes::Fn(_) | PathRes::StdFn(_) => return Err(self.err(
                p.span(),
                "unsupported-fn-pointer",
                "functions can only be called; function pointers are not supported in TRaX-Rust",
            )),
            _ => {
                return Err(self.err(
                    p.span(),
                    "unresolved-path",
                    format!("`{}` is not a value", path_segs(&p.path).join("::")),
                ))
            }
        };
        self.body.res.insert(key(e), res);
        Ok(ty)
    }

    fn resolve_value_path(&self, path: &syn::Path) -> DResult<PathRes> {
        for s in &path.segments {
            if !matches!(s.arguments, syn::PathArguments::None) {
                return Err(self.err(
                    s.arguments.span(),
                    "unsupported-generics",
                    "generic arguments are not supported in TRaX-Rust",
                ));
            }
        }
        let segs = path_segs(path);
        if segs.len() == 2 && segs[0] == "Self" {
            return match &self.self_ty {
                Some(Ty::Struct(s)) => self
                    .p
                    .inherent
                    .get(s)
                    .and_then(|m| m.get(&segs[1]))
                    .cloned()
                    .ok_or_else(|| {
                        self.err(
                            path.span(),
                            "unresolved-path",
                            format!("no associated item `{}` on `Self`", segs[1]),
                        )
                    }),
                Some(t) => Ok(PathRes::PrimAssoc(t.clone(), segs[1].clone())),
                None => Err(self.err(
                    path.span(),
                    "self-outside-impl",
                    "`Self` outside an impl block",
                )),
            };
        }
        if segs.len() == 1 && segs[0] == "Self" {
            if let Some(Ty::Struct(s)) = &self.self_ty {
                return Ok(PathRes::Struct(*s));
            }
        }
        self.p
            .resolve_path_segs(self.module, self.file, &segs, Ns::Value, path.span())
    }

    fn autoderef(&self, t: &Ty) -> (Ty, u32) {
        let mut t = self.shallow(t);
        let mut n = 0;
        while let Ty::Ref(_, inner) = t {
            t = self.shallow(&inner);
            n += 1;
        }
        (t, n)
    }

    /// Checks an assignable place expression and returns its type.
    fn place_expr(&mut self, e: &Expr) -> DResult<Ty> {
        let t = self.expr(e)?;
        self.check_place(e)?;
        Ok(t)
    }

    fn check_place(&self, e: &Expr) -> DResult<()> {
        match e {
            Expr::Path(_) => match self.body.res.get(&key(e)) {
                Some(Res::Local(id)) if self.local_mut[*id] => Ok(()),
                Some(Res::Local(id)) => Err(self.err(
                    e.span(),
                    "immutable-variable",
                    format!(
                        "cannot assign to or mutably borrow immutable variable `{}` (declare it with `mut`)",
                        self.body.locals[*id].name
                    ),
                )),
                Some(Res::Global(g)) if self.p.globals[*g].is_static == Some(true) => Ok(()),
                _ => Err(self.err(
                    e.span(),
                    "not-assignable",
                    "this expression cannot be assigned to or borrowed mutably",
                )),
            },
            Expr::Field(f) => {
                if self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 {
                    Ok(())
                } else {
                    self.check_place(&f.base)
                }
            }
            Expr::Index(i) => {
                if self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 {
                    Ok(())
                } else {
                    self.check_place(&i.expr)
                }
            }
            Expr::Paren(p) => self.check_place(&p.expr),
            Expr::Unary(u) if matches!(u.op, UnOp::Deref(_)) => Ok(()),
            _ => Err(self.err(
                e.span(),
                "not-assignable",
                "this expression cannot be assigned to or borrowed mutably",
            )),
        }
    }

    fn binary(&mut self, e: &Expr, b: &syn::ExprBinary) -> DResult<Ty> {
        let lt = self.expr(&b.left)?;
        let rt = self.expr(&b.right)?;
        let (l, r) = (self.shallow(&lt), self.shallow(&rt));
        use BinOp::*;
        let assign_op = match b.op {
            AddAssign(_) => Some(OpTrait::AddAssign),
            SubAssign(_) => Some(OpTrait::SubAssign),
            MulAssign(_) => Some(OpTrait::MulAssign),
            DivAssign(_) => Some(OpTrait::DivAssign),
            RemAssign(_) => Some(OpTrait::RemAssign),
            _ => None,
        };
        let is_assign = assign_op.is_some()
            || matches!(
                b.op,
                BitAndAssign(_) | BitOrAssign(_) | BitXorAssign(_) | ShlAssign(_) | ShrAssign(_)
            );
        if is_assign {
            self.check_place(&b.left)?;
        }
        let overloadable = matches!(l, Ty::Struct(_)) || matches!(r, Ty::Struct(_));
        if overloadable {
            let op = match b.op {
                Add(_) => OpTrait::Add,
                Sub(_) => OpTrait::Sub,
                Mul(_) => OpTrait::Mul,
                Div(_) => OpTrait::Div,
                Rem(_) => OpTrait::Rem,
                _ => match assign_op {
                    Some(o) => o,
                    None => {
                        return Err(self.err(b.op.span(), "unsupported-operator", format!("operator `{}` is not supported for `{}` and `{}` (only arithmetic operator traits can be implemented)", op_str(&b.op), self.show(&l), self.show(&r))))
                    }
                },
            };
            return self.overloaded(e, op, &lt, &rt, b.op.span());
        }
        if let (Ty::Simd(s1), Ty::Simd(s2)) = (&l, &r) {
            if s1 != s2 {
                return Err(self.mismatch(b.right.span(), &l, &r));
            }
            let ok = match b.op {
                Add(_) | Sub(_) | Mul(_) | AddAssign(_) | SubAssign(_) | MulAssign(_) => true,
                Div(_) | DivAssign(_) => *s1 == SimdTy::F32x4,
                BitAnd(_) | BitOr(_) | BitXor(_) | BitAndAssign(_) | BitOrAssign(_)
                | BitXorAssign(_) => *s1 == SimdTy::I32x4,
                _ => false,
            };
            if !ok {
                return Err(self.err(
                    b.op.span(),
                    "unsupported-operator",
                    format!(
                        "operator `{}` is not supported on `{}`",
                        op_str(&b.op),
                        self.show(&l)
                    ),
                ));
            }
            return Ok(if is_assign { Ty::Unit } else { l });
        }
        match b.op {
            And(_) | Or(_) => {
                self.unify(&lt, &Ty::Bool, b.left.span())?;
                self.unify(&rt, &Ty::Bool, b.right.span())?;
                Ok(Ty::Bool)
            }
            Eq(_) | Ne(_) | Lt(_) | Le(_) | Gt(_) | Ge(_) => {
                self.unify(&rt, &lt, b.right.span())?;
                let t = self.shallow(&lt);
                let ok = matches!(
                    t,
                    Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Var(_) | Ty::Ptr(..)
                );
                if !ok {
                    return Err(self.err(b.op.span(), "unsupported-operator", format!("cannot compare values of type `{}` (only numbers, bool, char and raw pointers)", self.show(&t))));
                }
                Ok(Ty::Bool)
            }
            Shl(_) | Shr(_) | ShlAssign(_) | ShrAssign(_) => {
                for (t, s) in [(&l, b.left.span()), (&r, b.right.span())] {
                    if !(t.is_int()
                        || matches!(t, Ty::Var(v) if self.vars[*v as usize].0 == VarKind::Int))
                    {
                        return Err(self.err(
                            s,
                            "type-mismatch",
                            format!("shift operands must be integers, found `{}`", self.show(t)),
                        ));
                    }
                }
                Ok(if is_assign { Ty::Unit } else { lt })
            }
            BitAnd(_) | BitOr(_) | BitXor(_) | BitAndAssign(_) | BitOrAssign(_)
            | BitXorAssign(_) => {
                self.unify(&rt, &lt, b.right.span())?;
                let t = self.shallow(&lt);
                let ok = t.is_int()
                    || t == Ty::Bool
                    || matches!(t, Ty::Var(v) if self.vars[v as usize].0 != VarKind::Float);
                if !ok {
                    return Err(self.err(
                        b.op.span(),
                        "type-mismatch",
                        format!("bitwise operator on `{}`", self.show(&t)),
                    ));
                }
                if let Ty::Var(v) = t {
                    self.vars[v as usize].0 = VarKind::Int;
                }
                Ok(if is_assign { Ty::Unit } else { lt })
            }
            _ => {
                // Arithmetic.
                self.unify(&rt, &lt, b.right.span())?;
                let t = self.shallow(&lt);
                let ok = t.is_int()
                    || t.is_float()
                    || matches!(t, Ty::Var(v) if self.vars[v as usize].0 != VarKind::Any);
                if !ok {
                    return Err(self.err(
                        b.op.span(),
                        "unsupported-operator",
                        format!("cannot apply `{}` to `{}`", op_str(&b.op), self.show(&t)),
                    ));
                }
                Ok(if is_assign { Ty::Unit } else { lt })
            }
        }
    }

    fn overloaded(&mut self, e: &Expr, op: OpTrait, lt: &Ty, rt: &Ty, span: Span) -> DResult<Ty> {
        let mut found = None;
        for im in &self.p.op_impls {
            if im.op != op {
                continue;
            }
            // Trial unification on a snapshot.
            let snap = self.vars.clone();
            let ok = self.try_unify(lt, &im.lhs) && self.try_unify(rt, &im.rhs);
            self.vars = snap;
            if ok {
                if found.is_some() {
                    return Err(self.err(
                        span,
                        "ambiguous-operator",
                        format!(
                            "ambiguous operator `{op:?}` for `{}` and `{}`",
                            self.show(lt),
                            self.show(rt)
                        ),
                    ));
                }
                found = Some(im.clone());
            }
        }
        let Some(im) = found else {
            return Err(self.err(
                span,
                "missing-operator-impl",
                format!(
                    "no implementation of `{op:?}` for `{}` and `{}`",
                    self.show(lt),
                    self.show(rt)
                ),
            ));
        };
        self.try_unify(lt, &im.lhs);
        self.try_unify(rt, &im.rhs);
        self.body.ops.insert(key(e), im.func);
        let f = &self.p.fns[im.func];
        if op.is_assign() && f.receiver != Some(Recv::RefMut) {
            return Err(self.err(
                span,
                "invalid-operator-impl",
                format!("`{}` must take `&mut self`", f.name),
            ));
        }
        Ok(if op.is_assign() {
            Ty::Unit
        } else {
            f.ret.clone()
        })
    }

    fn unary(&mut self, e: &Expr, u: &syn::ExprUnary) -> DResult<Ty> {
        let t = self.expr(&u.expr)?;
        let s = self.shallow(&t);
        match u.op {
            UnOp::Deref(_) => match s {
                Ty::Ref(_, inner) | Ty::Ptr(_, inner) => Ok(*inner),
                other => Err(self.err(
                    u.span(),
                    "invalid-deref",
                    format!("type `{}` cannot be dereferenced", self.show(&other)),
                )),
            },
            UnOp::Not(_) => match s {
                Ty::Bool | Ty::Int(_) => Ok(t),
                Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int => Ok(t),
                other => Err(self.err(
                    u.span(),
                    "unsupported-operator",
                    format!("cannot apply `!` to `{}`", self.show(&other)),
                )),
            },
            UnOp::Neg(_) => match s {
                Ty::Int(_) | Ty::Float(_) | Ty::Simd(_) => Ok(t),
                Ty::Var(v) if self.vars[v as usize].0 != VarKind::Any => Ok(t),
                Ty::Struct(_) => {
                    let func = self
                        .p
                        .op_impls
                        .iter()
                        .find(|im| im.op == OpTrait::Neg && im.lhs == s)
                        .map(|im| im.func);
                    match func {
                        Some(f) => {
                            self.body.ops.insert(key(e), f);
                            Ok(self.p.fns[f].ret.clone())
                        }
                        None => Err(self.err(
                            u.span(),
                            "missing-operator-impl",
                            format!("no implementation of `Neg` for `{}`", self.show(&s)),
                        )),
                    }
                }
                other => Err(self.err(
                    u.span(),
                    "unsupported-operator",
                    format!("cannot negate `{}`", self.show(&other)),
                )),
            },
            _ => Err(self.err(
                u.span(),
                "unsupported-operator",
                "unsupported unary operator",
            )),
        }
    }

    fn cast(&mut self, c: &syn::ExprCast) -> DResult<Ty> {
        let from = self.expr(&c.expr)?;
        let to = self
            .p
            .resolve_type(self.module, self.file, &c.ty, self.self_ty.as_ref())?;
        // Like rustc, an unsuffixed literal operand (through parentheses and `-`) takes the
        // target's type: `300 as u8` is an out-of-range `u8` literal, `-1 as u32` negates
        // a `u32`, `1e40 as f32` overflows `f32`.
        let mut lit = &*c.expr;
        loop {
            lit = match lit {
                Expr::Paren(p) => &p.expr,
                Expr::Group(g) => &g.expr,
                Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => &u.expr,
                _ => break,
            };
        }
        if let (Expr::Lit(l), Ty::Var(v)) = (lit, self.shallow(&from)) {
            let target = match (&l.lit, &to, self.vars[v as usize].0) {
                (Lit::Int(_), Ty::Int(_), VarKind::Int) => Some(to.clone()),
                (Lit::Int(_), Ty::Char, VarKind::Int) => Some(Ty::Int(IntTy::U8)),
                (Lit::Int(_), Ty::Ptr(..), VarKind::Int) => Some(Ty::Int(IntTy::Usize)),
                (Lit::Float(_), Ty::Float(_), VarKind::Float) => Some(to.clone()),
                _ => None,
            };
            if let Some(t) = target {
                self.unify(&from, &t, c.expr.span())?;
            }
        }
        let f = self.shallow(&from);
        if let Ty::Var(v) = f {
            // The operand's type is inferred from its other uses (defaulting like rustc);
            // any numeric operand can be cast to a number.
            let k = self.vars[v as usize].0;
            if matches!(to, Ty::Int(_) | Ty::Float(_)) && k != VarKind::Any {
                return Ok(to);
            }
        }
        let ok = match (&f, &to) {
            (Ty::Int(_) | Ty::Float(_), Ty::Int(_) | Ty::Float(_)) => true,
            (Ty::Bool | Ty::Char, Ty::Int(_)) => true,
            (Ty::Int(IntTy::U8), Ty::Char) => true,
            (Ty::Ptr(..) | Ty::Ref(..), Ty::Ptr(..)) => true,
            (Ty::Ptr(..), Ty::Int(IntTy::Usize | IntTy::U32 | IntTy::Isize | IntTy::I32)) => true,
            (Ty::Int(IntTy::Usize | IntTy::U32 | IntTy::Isize | IntTy::I32), Ty::Ptr(..)) => true,
            (a, b) => a == b,
        };
        if !ok {
            return Err(self.err(
                c.span(),
                "invalid-cast",
                format!(
                    "cannot cast `{}` as `{}`",
                    self.show(&f),
                    self.p.ty_str(&to)
                ),
            ));
        }
        Ok(to)
    }

    fn if_expr(&mut self, i: &syn::ExprIf) -> DResult<Ty> {
        if let Expr::Let(l) = &*i.cond {
            return Err(self.err(
                l.span(),
                "unsupported-if-let",
                "`if let` is not supported in TRaX-Rust",
            ));
        }
        let c = self.expr(&i.cond)?;
        self.unify(&c, &Ty::Bool, i.cond.span())?;
        let tt = self.block(&i.then_branch)?;
        match &i.else_branch {
            None => {
                self.unify(&tt, &Ty::Unit, block_tail_span(&i.then_branch))?;
                Ok(Ty::Unit)
            }
            Some((_, els)) => {
                let et = self.expr(els)?;
                if matches!(self.shallow(&tt), Ty::Never) {
                    return Ok(et);
                }
                self.unify(&et, &tt, els.span())?;
                Ok(tt)
            }
        }
    }

    fn for_loop(&mut self, e: &Expr, f: &syn::ExprForLoop) -> DResult<Ty> {
        let Some(it) = classify_for(&f.expr) else {
            return Err(self.err(f.expr.span(), "unsupported-iterator", "`for` loops iterate over ranges `a..b`, `a..=b` (optionally `.rev()`/`.step_by(n)`) or arrays"));
        };
        let mut kind = it.kind;
        let elem = match &mut kind {
            ForKind::Range { .. } => {
                let st = self.expr(it.start)?;
                let en = self.expr(it.end.expect("range end"))?;
                self.unify(&en, &st, it.end.expect("range end").span())?;
                if let Some(step) = it.step {
                    let s = self.expr(step)?;
                    self.unify(&s, &Ty::Int(IntTy::Usize), step.span())?;
                }
                let t = self.shallow(&st);
                if !(t.is_int()
                    || matches!(t, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int))
                {
                    return Err(self.err(
                        f.expr.span(),
                        "type-mismatch",
                        format!("range bounds must be integers, found `{}`", self.show(&t)),
                    ));
                }
                st
            }
            ForKind::Array { by_ref, derefs } => {
                let t = self.expr(it.start)?;
                let (bt, n) = self.autoderef(&t);
                *derefs = n;
                if n > 0 && !*by_ref {
                    *by_ref = true;
                }
                match bt {
                    Ty::Array(el, _) => {
                        if *by_ref {
                            Ty::Ref(false, el)
                        } else {
                            *el
                        }
                    }
                    other => {
                        return Err(self.err(
                            f.expr.span(),
                            "unsupported-iterator",
                            format!(
                                "cannot iterate over `{}` (ranges and arrays only)",
                                self.show(&other)
                            ),
                        ))
                    }
                }
            }
        };
        self.body.fors.insert(key(e), kind);
        self.scopes.push(HashMap::new());
        match &*f.pat {
            Pat::Ident(pi) if pi.subpat.is_none() && pi.by_ref.is_none() => {
                let id = self.new_local(&pi.ident.to_string(), elem, pi.ident.span());
                self.local_mut[id] = pi.mutability.is_some();
                self.body.pat_locals.insert(key(pi), id);
                self.scopes
                    .last_mut()
                    .expect("scope")
                    .insert(pi.ident.to_string(), id);
            }
            Pat::Wild(_) => {}
            other => {
                self.scopes.pop();
                return Err(self.err(
                    other.span(),
                    "unsupported-pattern",
                    "only identifier patterns are supported in `for` loops",
                ));
            }
        }
        self.loops.push(LoopCx {
            label: f.label.as_ref().map(|l| l.name.ident.to_string()),
            brk: None,
        });
        let b = self.block(&f.body);
        self.loops.pop();
        self.scopes.pop();
        let b = b?;
        self.unify(&b, &Ty::Unit, f.body.brace_token.span.close())?;
        Ok(Ty::Unit)
    }

    fn struct_lit(&mut self, s: &syn::ExprStruct) -> DResult<Ty> {
        if s.qself.is_some() {
            return Err(self.err(
                s.span(),
                "unsupported-qualified-path",
                "qualified paths are not supported",
            ));
        }
        let sid = if s.path.is_ident("Self") {
            match &self.self_ty {
                Some(Ty::Struct(id)) => *id,
                _ => {
                    return Err(self.err(
                        s.path.span(),
                        "self-outside-impl",
                        "`Self` outside an impl block",
                    ))
                }
            }
        } else {
            match self.p.resolve_type(
                self.module,
                self.file,
                &syn::Type::Path(syn::TypePath {
                    attrs: vec![],
                    qself: None,
                    path: s.path.clone(),
                }),
                self.self_ty.as_ref(),
            )? {
                Ty::Struct(id) => id,
                other => {
                    return Err(self.err(
                        s.path.span(),
                        "not-a-struct",
                        format!("`{}` is not a struct", self.p.ty_str(&other)),
                    ))
                }
            }
        };
        let def = &self.p.structs[sid];
        let mut seen = Vec::new();
        for fv in &s.fields {
            let name = match &fv.member {
                syn::Member::Named(n) => n.to_string(),
                syn::Member::Unnamed(i) => i.index.to_string(),
            };
            let Some((_, ft)) = def.fields.iter().find(|(n, _)| *n == name) else {
                return Err(self.err(
                    fv.member.span(),
                    "unknown-field",
                    format!("struct `{}` has no field `{name}`", def.name),
                ));
            };
            if seen.contains(&name) {
                return Err(self.err(
                    fv.member.span(),
                    "duplicate-field",
                    format!("field `{name}` specified more than once"),
                ));
            }
            seen.push(name);
            let t = self.expr(&fv.expr)?;
            self.unify(&t, ft, fv.expr.span())?;
        }
        match &s.rest {
            Some(r) => {
                let t = self.expr(r)?;
                self.unify(&t, &Ty::Struct(sid), r.span())?;
            }
            None => {
                if let Some((missing, _)) = def.fields.iter().find(|(n, _)| !seen.contains(n)) {
                    return Err(self.err(
                        s.path.span(),
                        "missing-field",
                        format!("missing field `{missing}` in initializer of `{}`", def.name),
                    ));
                }
            }
        }
        Ok(Ty::Struct(sid))
    }

    fn match_expr(&mut self, m: &syn::ExprMatch) -> DResult<Ty> {
        let st = self.expr(&m.expr)?;
        let s = self.shallow(&st);
        let ok = s.is_int()
            || matches!(s, Ty::Bool | Ty::Char)
            || matches!(s, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int);
        if !ok {
            return Err(self.err(
                m.expr.span(),
                "unsupported-match",
                format!(
                    "`match` is supported on integers, bool and char, not `{}`",
                    self.show(&s)
                ),
            ));
        }
        let mut result: Option<Ty> = None;
        for arm in &m.arms {
            self.scopes.push(HashMap::new());
            let r = self.arm(arm, &st, &mut result);
            self.scopes.pop();
            r?;
        }
        Ok(result.unwrap_or(Ty::Never))
    }

    fn arm(&mut self, arm: &syn::Arm, st: &Ty, result: &mut Option<Ty>) -> DResult<()> {
        let (pat, guard) = match &arm.pat {
            Pat::Guard(g) => (&*g.pat, Some(&*g.guard)),
            p => (p, None),
        };
        self.pattern(pat, st)?;
        if let Some(g) = guard {
            let gt = self.expr(g)?;
            self.unify(&gt, &Ty::Bool, g.span())?;
        }
        let bt = self.expr(&arm.body)?;
        match result.clone() {
            None => {
                if !matches!(self.shallow(&bt), Ty::Never) {
                    *result = Some(bt);
                }
            }
            Some(r) => self.unify(&bt, &r, arm.body.span())?,
        }
        Ok(())
    }

    fn pattern(&mut self, pat: &Pat, st: &Ty) -> DResult<()> {
        match pat {
            Pat::Wild(_) => Ok(()),
            Pat::Ident(pi) if pi.subpat.is_none() && pi.by_ref.is_none() => {
                // A constant in scope, or a binding.
                let name = pi.ident.to_string();
                if let Ok(PathRes::Global(g)) = self.p.resolve_path_segs(
                    self.module,
                    self.file,
                    std::slice::from_ref(&name),
                    Ns::Value,
                    pi.span(),
                ) {
                    if self.p.globals[g].is_static.is_none() {
                        let gt = self.p.globals[g].ty.clone();
                        return self.unify(&gt, st, pi.span());
                    }
                }
                let id = self.new_local(&name, st.clone(), pi.ident.span());
                self.local_mut[id] = pi.mutability.is_some();
                self.body.pat_locals.insert(key(pi), id);
                self.scopes.last_mut().expect("scope").insert(name, id);
                Ok(())
            }
            Pat::Or(o) => {
                for c in &o.cases {
                    if matches!(c, Pat::Ident(_)) {
                        return Err(self.err(
                            c.span(),
                            "unsupported-pattern",
                            "bindings inside `|` patterns are not supported",
                        ));
                    }
                    self.pattern(c, st)?;
                }
                Ok(())
            }
            Pat::Paren(p) => self.pattern(&p.pat, st),
            Pat::Lit(l) => {
                let t = self.expr_of_pat(pat, l)?;
                self.unify(&t, st, l.span())
            }
            Pat::Range(r) => {
                for b in [&r.start, &r.end].into_iter().flatten() {
                    let t = self.expr(b)?;
                    self.unify(&t, st, b.span())?;
                }
                if r.start.is_none() && r.end.is_none() {
                    return Err(self.err(
                        r.span(),
                        "unsupported-pattern",
                        "unbounded range pattern",
                    ));
                }
                Ok(())
            }
            Pat::Path(p) => {
                let t = self.expr_of_pat_path(p)?;
                self.unify(&t, st, p.span())
            }
            other => Err(self.err(
                other.span(),
                "unsupported-pattern",
                "only literal, range, constant, `_` and binding patterns are supported in `match`",
            )),
        }
    }

    fn expr_of_pat(&mut self, _pat: &Pat, l: &syn::ExprLit) -> DResult<Ty> {
        let t = self.lit(&l.lit)?;
        self.body.tys.insert(key(l), t.clone());
        Ok(t)
    }

    fn expr_of_pat_path(&mut self, p: &syn::ExprPath) -> DResult<Ty> {
        match self.resolve_value_path(&p.path)? {
            PathRes::Global(g) if self.p.globals[g].is_static.is_none() => {
                Ok(self.p.globals[g].ty.clone())
            }
            PathRes::PrimAssoc(Ty::Int(t), _) => Ok(Ty::Int(t)),
            _ => Err(self.err(
                p.span(),
                "unsupported-pattern",
                "only constants can be used as path patterns",
            )),
        }
    }

    // ---------------------------------------------------------------- calls

    fn args(
        &mut self,
        args: &Punctuated<Expr, Token![,]>,
        params: &[Ty],
        span: Span,
        what: &str,
    ) -> DResult<()> {
        if args.len() != params.len() {
            return Err(self.err(
                span,
                "wrong-argument-count",
                format!(
                    "{what} takes {} argument(s) but {} were supplied",
                    params.len(),
                    args.len()
                ),
            ));
        }
        for (a, p) in args.iter().zip(params) {
            let t = self.expr(a)?;
            self.unify(&t, p, a.span())?;
        }
        Ok(())
    }

    fn call(&mut self, e: &Expr, c: &syn::ExprCall) -> DResult<Ty> {
        let Expr::Path(fp) = &*c.func else {
            return Err(self.err(
                c.func.span(),
                "unsupported-call",
                "only calls of named functions are supported (no function pointers or closures)",
            ));
        };
        if fp
            .path
            .get_ident()
            .is_some_and(|i| self.lookup_local(&i.to_string()).is_some())
        {
            return Err(self.err(
                c.func.span(),
                "unsupported-call",
                "calling a local variable is not supported (no closures or function pointers)",
            ));
        }
        match self.resolve_value_path(&fp.path)? {
            PathRes::Fn(f) => {
                let fd = &self.p.fns[f];
                let params = fd.params.clone();
                let ret = fd.ret.clone();
                let name = format!("function `{}`", fd.name);
                self.args(&c.args, &params, c.span(), &name)?;
                self.body.callees.insert(
                    key(e),
                    Callee::Fn {
                        func: f,
                        derefs: 0,
                        autoref: false,
                    },
                );
                Ok(ret)
            }
            PathRes::PrimAssoc(t, name) => self.builtin_assoc_call(e, c, t, &name),
            PathRes::StdFn(name) => {
                let name: &'static str = intern(
                    &[
                        "read",
                        "write",
                        "read_volatile",
                        "write_volatile",
                        "null",
                        "null_mut",
                    ],
                    &name,
                )
                .expect("resolve_std filters names");
                let b = Builtin::StdPtr(name);
                self.body
                    .callees
                    .insert(key(e), Callee::Builtin { b, derefs: 0 });
                match name {
                    "null" | "null_mut" => {
                        if !c.args.is_empty() {
                            return Err(self.err(
                                c.span(),
                                "wrong-argument-count",
                                format!("`ptr::{name}` takes no arguments"),
                            ));
                        }
                        let el = self.fresh(VarKind::Any);
                        let _ = el;
                        Err(self.err(
                            c.span(),
                            "unsupported-call",
                            format!("`ptr::{name}` needs a type; write `0 as *const T` instead"),
                        ))
                    }
                    "read" | "read_volatile" => {
                        if c.args.len() != 1 {
                            return Err(self.err(
                                c.span(),
                                "wrong-argument-count",
                                format!("`ptr::{name}` takes 1 argument"),
                            ));
                        }
                        let t = self.expr(&c.args[0])?;
                        match self.shallow(&t) {
                            Ty::Ptr(_, inner) | Ty::Ref(_, inner) => Ok(*inner),
                            other => Err(self.mismatch(
                                c.args[0].span(),
                                &Ty::Ptr(false, Box::new(Ty::Unit)),
                                &other,
                            )),
                        }
                    }
                    _ => {
                        if c.args.len() != 2 {
                            return Err(self.err(
                                c.span(),
                                "wrong-argument-count",
                                format!("`ptr::{name}` takes 2 arguments"),
                            ));
                        }
                        let t = self.expr(&c.args[0])?;
                        let v = self.expr(&c.args[1])?;
                        match self.shallow(&t) {
                            Ty::Ptr(true, inner) | Ty::Ref(true, inner) => {
                                self.unify(&v, &inner, c.args[1].span())?;
                                Ok(Ty::Unit)
                            }
                            other => Err(self.mismatch(
                                c.args[0].span(),
                                &Ty::Ptr(true, Box::new(v)),
                                &other,
                            )),
                        }
                    }
                }
            }
            PathRes::Struct(s) => Err(self.err(
                c.func.span(),
                "unsupported-tuple-struct",
                format!(
                    "`{}` is not a function (tuple structs are not supported)",
                    self.p.structs[s].name
                ),
            )),
            _ => Err(self.err(
                c.func.span(),
                "unresolved-path",
                format!("`{}` is not a function", path_segs(&fp.path).join("::")),
            )),
        }
    }

    fn builtin_assoc_call(
        &mut self,
        e: &Expr,
        c: &syn::ExprCall,
        t: Ty,
        name: &str,
    ) -> DResult<Ty> {
        match &t {
            Ty::Simd(s) => {
                let f32t = Ty::Float(FloatTy::F32);
                let lane = match s {
                    SimdTy::F32x4 => f32t,
                    SimdTy::I32x4 => Ty::Int(IntTy::I32),
                };
                let (nm, params): (&'static str, Vec<Ty>) = match name {
                    "splat" => ("splat", vec![lane]),
                    "new" => ("new", vec![lane.clone(), lane.clone(), lane.clone(), lane]),
                    "select" => (
                        "select",
                        vec![Ty::Simd(SimdTy::I32x4), t.clone(), t.clone()],
                    ),
                    _ => {
                        // UFCS method call: `f32x4::sqrt(x)`.
                        return self.ufcs_builtin(e, c, t.clone(), name);
                    }
                };
                self.args(
                    &c.args,
                    &params,
                    c.span(),
                    &format!("`{}::{nm}`", self.p.ty_str(&t)),
                )?;
                self.body.callees.insert(
                    key(e),
                    Callee::Builtin {
                        b: Builtin::Simd(*s, nm),
                        derefs: 0,
                    },
                );
                Ok(t)
            }
            Ty::Float(f) if name == "from_bits" => {
                let it = Ty::Int(if *f == FloatTy::F32 {
                    IntTy::U32
                } else {
                    IntTy::U64
                });
                self.args(&c.args, &[it], c.span(), "`from_bits`")?;
                self.body.callees.insert(
                    key(e),
                    Callee::Builtin {
                        b: Builtin::FromBits(*f),
                        derefs: 0,
                    },
                );
                Ok(t)
            }
            Ty::Float(_) | Ty::Int(_) => self.ufcs_builtin(e, c, t.clone(), name),
            _ => Err(self.err(
                c.func.span(),
                "unresolved-path",
                format!("no function `{name}` on `{}`", self.p.ty_str(&t)),
            )),
        }
    }

    fn ufcs_builtin(&mut self, e: &Expr, c: &syn::ExprCall, t: Ty, name: &str) -> DResult<Ty> {
        if c.args.is_empty() {
            return Err(self.err(
                c.span(),
                "wrong-argument-count",
                format!("`{}::{name}` needs a receiver argument", self.p.ty_str(&t)),
            ));
        }
        let rt = self.expr(&c.args[0])?;
        self.unify(&rt, &t, c.args[0].span())?;
        let rest: Vec<&Expr> = c.args.iter().skip(1).collect();
        let (b, ret) = self.builtin_method(&t, name, &rest, c.func.span())?;
        self.body
            .callees
            .insert(key(e), Callee::Builtin { b, derefs: 0 });
        Ok(ret)
    }

    fn method_call(&mut self, e: &Expr, m: &syn::ExprMethodCall) -> DResult<Ty> {
        if let Some(t) = &m.turbofish {
            return Err(self.err(
                t.span(),
                "unsupported-generics",
                "turbofish generic arguments are not supported in TRaX-Rust",
            ));
        }
        let rt = self.expr(&m.receiver)?;
        let name = m.method.to_string();
        let mut t = self.shallow(&rt);
        let mut derefs = 0;
        loop {
            match &t {
                Ty::Struct(s) => {
                    let Some(PathRes::Fn(f)) =
                        self.p.inherent.get(s).and_then(|m| m.get(&name)).cloned()
                    else {
                        return Err(self.err(
                            m.method.span(),
                            "unknown-method",
                            format!("no method `{name}` on `{}`", self.p.structs[*s].name),
                        ));
                    };
                    let fd = &self.p.fns[f];
                    let Some(recv) = fd.receiver else {
                        return Err(self.err(m.method.span(), "not-a-method", format!("`{}` is an associated function, not a method; call it as `{}(...)`", fd.name, fd.name)));
                    };
                    let autoref = recv != Recv::Value;
                    if recv == Recv::RefMut && derefs == 0 {
                        self.check_place(&m.receiver)?;
                    }
                    let params = fd.params[1..].to_vec();
                    let ret = fd.ret.clone();
                    let what = format!("method `{}`", fd.name);
                    self.args(&m.args, &params, m.span(), &what)?;
                    self.body.callees.insert(
                        key(e),
                        Callee::Fn {
                            func: f,
                            derefs,
                            autoref,
                        },
                    );
                    return Ok(ret);
                }
                Ty::Ref(_, inner) => {
                    t = self.shallow(inner);
                    derefs += 1;
                }
                Ty::Var(v) => {
                    let d = match self.vars[*v as usize].0 {
                        VarKind::Float => Ty::Float(FloatTy::F64),
                        VarKind::Int => Ty::Int(IntTy::I32),
                        VarKind::Any => {
                            return Err(self.err(
                                m.receiver.span(),
                                "type-annotation-needed",
                                "type annotations needed for the receiver",
                            ))
                        }
                    };
                    self.try_unify(&t, &d);
                    t = d;
                }
                _ => {
                    let args: Vec<&Expr> = m.args.iter().collect();
                    let (b, ret) =
                        self.builtin_method(&t.clone(), &name, &args, m.method.span())?;
                    self.body
                        .callees
                        .insert(key(e), Callee::Builtin { b, derefs });
                    return Ok(ret);
                }
            }
        }
    }

    /// Types a builtin method on `t` with the given (non-receiver) arguments.
    fn builtin_method(
        &mut self,
        t: &Ty,
        name: &str,
        args: &[&Expr],
        span: Span,
    ) -> DResult<(Builtin, Ty)> {
        let arity = |cx: &Self, n: usize| -> DResult<()> {
            if args.len() != n {
                return Err(cx.err(
                    span,
                    "wrong-argument-count",
                    format!(
                        "method `{name}` takes {n} argument(s) but {} were supplied",
                        args.len()
                    ),
                ));
            }
            Ok(())
        };
        let check = |cx: &mut Self, i: usize, want: &Ty| -> DResult<()> {
            let at = cx.expr(args[i])?;
            cx.unify(&at, want, args[i].span())
        };
        match t {
            Ty::Float(f) => {
                let Some(nm) = intern(FLOAT_METHODS, name) else {
                    if LIBM_METHODS.contains(&name) {
                        return Err(self.err(span, "unsupported-float-method", format!("`{}::{name}` is not supported on TRaX (there is no libm); use sqrt/min/max/abs/floor/ceil or write it in the kernel", f.name())));
                    }
                    return Err(self.err(
                        span,
                        "unknown-method",
                        format!("no method `{name}` on `{}`", f.name()),
                    ));
                };
                let ret = match nm {
                    "min" | "max" | "copysign" => {
                        arity(self, 1)?;
                        check(self, 0, t)?;
                        t.clone()
                    }
                    "clamp" | "mul_add" => {
                        arity(self, 2)?;
                        check(self, 0, t)?;
                        check(self, 1, t)?;
                        t.clone()
                    }
                    "powi" => {
                        arity(self, 1)?;
                        check(self, 0, &Ty::Int(IntTy::I32))?;
                        t.clone()
                    }
                    "is_nan" | "is_finite" | "is_infinite" | "is_sign_negative"
                    | "is_sign_positive" => {
                        arity(self, 0)?;
                        Ty::Bool
                    }
                    "to_bits" => {
                        arity(self, 0)?;
                        Ty::Int(if *f == FloatTy::F32 {
                            IntTy::U32
                        } else {
                            IntTy::U64
                        })
                    }
                    _ => {
                        arity(self, 0)?;
                        t.clone()
                    }
                };
                Ok((Builtin::Float(nm), ret))
            }
            Ty::Int(it) => {
                let Some(nm) = intern(INT_METHODS, name) else {
                    return Err(self.err(
                        span,
                        "unknown-method",
                        format!("no method `{name}` on `{}`", it.name()),
                    ));
                };
                let ret = match nm {
                    "min" | "max" | "wrapping_add" | "wrapping_sub" | "wrapping_mul" => {
                        arity(self, 1)?;
                        check(self, 0, t)?;
                        t.clone()
                    }
                    "clamp" => {
                        arity(self, 2)?;
                        check(self, 0, t)?;
                        check(self, 1, t)?;
                        t.clone()
                    }
                    "pow" | "rotate_left" | "rotate_right" => {
                        arity(self, 1)?;
                        check(self, 0, &Ty::Int(IntTy::U32))?;
                        t.clone()
                    }
                    "count_ones" | "leading_zeros" | "trailing_zeros" => {
                        arity(self, 0)?;
                        Ty::Int(IntTy::U32)
                    }
                    "is_power_of_two" => {
                        arity(self, 0)?;
                        Ty::Bool
                    }
                    "abs" if !it.signed() => {
                        return Err(self.err(
                            span,
                            "unknown-method",
                            format!("no method `abs` on `{}`", it.name()),
                        ))
                    }
                    _ => {
                        arity(self, 0)?;
                        t.clone()
                    }
                };
                Ok((Builtin::Int(nm), ret))
            }
            Ty::Ptr(mutbl, inner) => {
                let Some(nm) = intern(PTR_METHODS, name) else {
                    return Err(self.err(
                        span,
                        "unknown-method",
                        format!("no method `{name}` on raw pointers"),
                    ));
                };
                let ret = match nm {
                    "add" | "sub" => {
                        arity(self, 1)?;
                        check(self, 0, &Ty::Int(IntTy::Usize))?;
                        t.clone()
                    }
                    "offset" => {
                        arity(self, 1)?;
                        check(self, 0, &Ty::Int(IntTy::Isize))?;
                        t.clone()
                    }
                    "is_null" => {
                        arity(self, 0)?;
                        Ty::Bool
                    }
                    "read" | "read_volatile" => {
                        arity(self, 0)?;
                        (**inner).clone()
                    }
                    _ => {
                        if !mutbl {
                            return Err(self.err(
                                span,
                                "invalid-pointer-write",
                                "cannot write through a `*const` pointer",
                            ));
                        }
                        arity(self, 1)?;
                        check(self, 0, inner)?;
                        Ty::Unit
                    }
                };
                Ok((Builtin::Ptr(nm), ret))
            }
            Ty::Simd(s) => {
                let Some(nm) = intern(SIMD_METHODS, name) else {
                    return Err(self.err(
                        span,
                        "unknown-method",
                        format!("no method `{name}` on `{}`", self.p.ty_str(t)),
                    ));
                };
                let f = *s == SimdTy::F32x4;
                let ret = match (nm, f) {
                    ("get", _) => {
                        arity(self, 1)?;
                        check(self, 0, &Ty::Int(IntTy::Usize))?;
                        if f {
                            Ty::Float(FloatTy::F32)
                        } else {
                            Ty::Int(IntTy::I32)
                        }
                    }
                    ("min" | "max", true) => {
                        arity(self, 1)?;
                        check(self, 0, t)?;
                        t.clone()
                    }
                    ("sqrt" | "abs", true) => {
                        arity(self, 0)?;
                        t.clone()
                    }
                    ("mul_add", true) => {
                        arity(self, 2)?;
                        check(self, 0, t)?;
                        check(self, 1, t)?;
                        t.clone()
                    }
                    ("lt" | "le" | "gt" | "ge" | "eq", true) => {
                        arity(self, 1)?;
                        check(self, 0, t)?;
                        Ty::Simd(SimdTy::I32x4)
                    }
                    ("to_i32x4", true) => {
                        arity(self, 0)?;
                        Ty::Simd(SimdTy::I32x4)
                    }
                    ("any" | "all", false) => {
                        arity(self, 0)?;
                        Ty::Bool
                    }
                    ("to_f32x4", false) => {
                        arity(self, 0)?;
                        Ty::Simd(SimdTy::F32x4)
                    }
                    _ => {
                        return Err(self.err(
                            span,
                            "unknown-method",
                            format!("no method `{name}` on `{}`", self.p.ty_str(t)),
                        ))
                    }
                };
                Ok((Builtin::Simd(*s, nm), ret))
            }
            Ty::Array(_, n) if name == "len" => {
                arity(self, 0)?;
                Ok((Builtin::Len(*n), Ty::Int(IntTy::Usize)))
            }
            other => Err(self.err(
                span,
                "unknown-method",
                format!("no method `{name}` on `{}`", self.show(other)),
            )),
        }
    }

    // ---------------------------------------------------------------- macros

    fn mac(&mut self, m: &syn::Macro, span: Span) -> DResult<Ty> {
        let name = m
            .path
            .segments
            .last()
            .map(|s| s.ident.to_string())
            .unwrap_or_default();
        let parse_args = |m: &syn::Macro| -> DResult<Vec<Expr>> {
            let p = m
                .parse_body_with(Punctuated::<Expr, Token![,]>::parse_terminated)
                .map_err(|e| {
                    self.err(
                        e.span(),
                        "invalid-macro-arguments",
                        format!("cannot parse macro arguments: {e}"),
                    )
                })?;
            Ok(p.into_iter().collect())
        };
        let (call, ty) = match name.as_str() {
            "println" | "print" | "eprintln" | "eprint" => {
                let args = parse_args(m)?;
                let mut pieces = self.format(args, span)?;
                if name.ends_with("ln") {
                    pieces.push(FmtPiece::Lit("\n".into()));
                }
                self.check_fmt_args(&pieces)?;
                (MacroCall::Print(pieces), Ty::Unit)
            }
            "panic" | "unreachable" | "todo" | "unimplemented" => {
                let args = parse_args(m)?;
                let (kind, default) = match name.as_str() {
                    "panic" => (AbortKind::Panic, "explicit panic"),
                    "unreachable" => (
                        AbortKind::Unreachable,
                        "internal error: entered unreachable code",
                    ),
                    "todo" => (AbortKind::Panic, "not yet implemented"),
                    _ => (AbortKind::Panic, "not implemented"),
                };
                // Rust: the default message alone, or (except `panic!`) followed by `: ` and
                // the formatted arguments.
                let pieces = if args.is_empty() {
                    vec![FmtPiece::Lit(default.into())]
                } else {
                    let mut p = self.format(args, span)?;
                    if name != "panic" {
                        p.insert(0, FmtPiece::Lit(format!("{default}: ")));
                    }
                    p
                };
                self.check_fmt_args(&pieces)?;
                (
                    MacroCall::Abort {
                        kind,
                        pieces,
                        cond: None,
                        cmp: None,
                    },
                    Ty::Never,
                )
            }
            "assert" | "debug_assert" => {
                let mut args = parse_args(m)?;
                if args.is_empty() {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        format!("`{name}!` needs a condition"),
                    ));
                }
                let cond = Box::new(args.remove(0));
                let t = self.expr(&cond)?;
                self.unify(&t, &Ty::Bool, cond.span())?;
                let pieces = if args.is_empty() {
                    vec![FmtPiece::Lit(format!(
                        "assertion failed: {}",
                        crate::pretty::expr(&cond)
                    ))]
                } else {
                    self.format(args, span)?
                };
                self.check_fmt_args(&pieces)?;
                let call = if name == "debug_assert" {
                    MacroCall::Nothing
                } else {
                    MacroCall::Abort {
                        kind: AbortKind::Assert,
                        pieces,
                        cond: Some(cond),
                        cmp: None,
                    }
                };
                (call, Ty::Unit)
            }
            "assert_eq" | "assert_ne" | "debug_assert_eq" | "debug_assert_ne" => {
                let mut args = parse_args(m)?;
                if args.len() < 2 {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        format!("`{name}!` needs two values"),
                    ));
                }
                let a = Box::new(args.remove(0));
                let b = Box::new(args.remove(0));
                let ta = self.expr(&a)?;
                let tb = self.expr(&b)?;
                self.unify(&tb, &ta, b.span())?;
                let t = self.shallow(&ta);
                if !(t.is_int() || t.is_float() || matches!(t, Ty::Bool | Ty::Char | Ty::Var(_))) {
                    return Err(self.err(
                        a.span(),
                        "unsupported-operator",
                        format!("cannot compare values of type `{}`", self.show(&t)),
                    ));
                }
                let ne = name.ends_with("ne");
                let op = if ne { "!=" } else { "==" };
                let mut pieces = vec![FmtPiece::Lit(format!("assertion `left {op} right` failed"))];
                if !args.is_empty() {
                    pieces.push(FmtPiece::Lit(": ".into()));
                    pieces.extend(self.format(args, span)?);
                }
                self.check_fmt_args(&pieces)?;
                let call = if name.starts_with("debug_") {
                    MacroCall::Nothing
                } else {
                    MacroCall::Abort {
                        kind: AbortKind::Assert,
                        pieces,
                        cond: None,
                        cmp: Some((a, b, ne)),
                    }
                };
                (call, Ty::Unit)
            }
            "__trax_op" => self.trax_op(parse_args(m)?, span)?,
            "__trax_mtc2" => {
                let args = parse_args(m)?;
                if args.len() != 2 {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        "`__trax_mtc2!(n, x)` takes 2 arguments",
                    ));
                }
                let n = self.imm5(&args[0])?;
                let x = Box::new(args.into_iter().nth(1).expect("two args"));
                let t = self.expr(&x)?;
                self.unify(&t, &Ty::Float(FloatTy::F32), x.span())?;
                (MacroCall::Mtc2(n, x), Ty::Unit)
            }
            "__trax_mfc2" => {
                let args = parse_args(m)?;
                if args.len() != 1 {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        "`__trax_mfc2!(n)` takes 1 argument",
                    ));
                }
                (
                    MacroCall::Mfc2(self.imm5(&args[0])?),
                    Ty::Float(FloatTy::F32),
                )
            }
            "__trax_symbol_addr" => {
                let args = parse_args(m)?;
                match args.as_slice() {
                    [Expr::Lit(syn::ExprLit {
                        lit: Lit::Str(s), ..
                    })] => (MacroCall::SymbolAddr(s.value()), Ty::Int(IntTy::U32)),
                    _ => {
                        return Err(self.err(
                            span,
                            "invalid-macro-arguments",
                            "`__trax_symbol_addr!` takes one string literal",
                        ))
                    }
                }
            }
            "format" | "vec" | "write" | "writeln" | "format_args" | "matches" | "dbg" => {
                return Err(self.err(
                    m.path.span(),
                    "unsupported-macro",
                    format!("macro `{name}!` is not supported in TRaX-Rust"),
                ))
            }
            _ => {
                return Err(self.err(
                    m.path.span(),
                    "unsupported-macro",
                    format!("unknown macro `{name}!` (user macros are not supported in TRaX-Rust)"),
                ))
            }
        };
        self.body.macros.insert(key(m), call);
        Ok(ty)
    }

    fn imm5(&self, e: &Expr) -> DResult<u32> {
        let v = self.p.eval_int(self.module, self.file, e, 0)?;
        if !(0..32).contains(&v) {
            return Err(self.err(
                e.span(),
                "immediate-out-of-range",
                format!("immediate {v} is out of range 0..=31"),
            ));
        }
        Ok(v as u32)
    }

    fn trax_op(&mut self, args: Vec<Expr>, span: Span) -> DResult<(MacroCall, Ty)> {
        let mut it = args.into_iter();
        let Some(Expr::Lit(syn::ExprLit {
            lit: Lit::Str(mn), ..
        })) = it.next()
        else {
            return Err(self.err(
                span,
                "invalid-macro-arguments",
                "`__trax_op!` takes an instruction mnemonic string first",
            ));
        };
        let Some(instr) = TRAX_INSTRUCTIONS.iter().find(|i| i.mnemonic == mn.value()) else {
            return Err(self.err(
                mn.span(),
                "unknown-instruction",
                format!("unknown TRaX instruction `{}`", mn.value()),
            ));
        };
        let rest: Vec<Expr> = it.collect();
        let uses: Vec<_> = instr.operands.iter().filter(|o| !o.kind.is_def()).collect();
        if rest.len() != uses.len() {
            return Err(self.err(
                span,
                "wrong-argument-count",
                format!(
                    "`{}` takes {} operand(s) but {} were supplied",
                    instr.mnemonic,
                    uses.len(),
                    rest.len()
                ),
            ));
        }
        let mut out = Vec::new();
        for (a, o) in rest.into_iter().zip(uses) {
            match o.kind {
                OperandKind::Imm5 => out.push(TraxArg::Imm(self.imm5(&a)?)),
                OperandKind::FprUse => {
                    let a = Box::new(a);
                    let t = self.expr(&a)?;
                    let want = if instr.mnemonic == "trax.printd" {
                        FloatTy::F64
                    } else {
                        FloatTy::F32
                    };
                    self.unify(&t, &Ty::Float(want), a.span())?;
                    out.push(TraxArg::Reg(a));
                }
                _ => {
                    let a = Box::new(a);
                    let t = self.expr(&a)?;
                    let s = self.shallow(&t);
                    match s {
                        Ty::Int(i) if i.bits() <= 32 => {}
                        Ty::Bool | Ty::Char | Ty::Ptr(..) | Ty::Ref(..) => {}
                        Ty::Var(_) => self.unify(&t, &Ty::Int(IntTy::U32), a.span())?,
                        other => return Err(self.err(a.span(), "type-mismatch", format!("register operand must be a 32-bit integer, bool or pointer, found `{}`", self.show(&other)))),
                    }
                    out.push(TraxArg::Reg(a));
                }
            }
        }
        let ty = match instr
            .operands
            .iter()
            .find(|o| o.kind.is_def())
            .map(|o| o.kind)
        {
            Some(OperandKind::GprDef) => Ty::Int(IntTy::U32),
            Some(OperandKind::FprDef) => Ty::Float(FloatTy::F32),
            _ => Ty::Unit,
        };
        Ok((MacroCall::TraxOp { instr, args: out }, ty))
    }

    fn check_printable(&self, t: &Ty, span: Span) -> DResult<()> {
        match self.shallow(t) {
            Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Str | Ty::Var(_) => Ok(()),
            Ty::Ref(_, inner) => self.check_printable(&inner, span),
            other => Err(self.err(span, "unsupported-format-argument", format!("cannot print a value of type `{}` (integers, floats, bool, char and string literals only)", self.show(&other)))),
        }
    }

    /// Type-checks the arguments of formatted text: each must be printable.
    fn check_fmt_args(&mut self, pieces: &[FmtPiece]) -> DResult<()> {
        for p in pieces {
            if let FmtPiece::Arg(a) | FmtPiece::Debug(a) = p {
                let t = self.expr(a)?;
                self.check_printable(&t, a.span())?;
            }
        }
        Ok(())
    }

    fn format(&mut self, args: Vec<Expr>, span: Span) -> DResult<Vec<FmtPiece>> {
        let mut it = args.into_iter();
        let Some(first) = it.next() else {
            return Ok(Vec::new());
        };
        let Expr::Lit(syn::ExprLit {
            lit: Lit::Str(fmt), ..
        }) = &first
        else {
            return Err(self.err(
                first.span(),
                "invalid-format-string",
                "format argument must be a string literal",
            ));
        };
        let mut rest: Vec<Option<Expr>> = it.map(Some).collect();
        let text = fmt.value();
        let mut pieces = Vec::new();
        let mut lit = String::new();
        let mut next_arg = 0;
        let mut chars = text.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '{' if chars.peek() == Some(&'{') => {
                    chars.next();
                    lit.push('{');
                }
                '}' if chars.peek() == Some(&'}') => {
                    chars.next();
                    lit.push('}');
                }
                '{' => {
                    let mut spec = String::new();
                    loop {
                        match chars.next() {
                            Some('}') => break,
                            Some(c) => spec.push(c),
                            None => {
                                return Err(self.err(
                                    fmt.span(),
                                    "invalid-format-string",
                                    "unterminated `{` in format string",
                                ))
                            }
                        }
                    }
                    let (name, fmtspec) = match spec.split_once(':') {
                        Some((a, b)) => (a.trim().to_string(), b.to_string()),
                        None => (spec.trim().to_string(), String::new()),
                    };
                    if !fmtspec.is_empty() && fmtspec != "?" {
                        return Err(self.err(fmt.span(), "unsupported-format-spec", format!("format spec `{{:{fmtspec}}}` is not supported in TRaX-Rust (only `{{}}`)")));
                    }
                    if !lit.is_empty() {
                        pieces.push(FmtPiece::Lit(std::mem::take(&mut lit)));
                    }
                    let arg = if name.is_empty() {
                        next_arg += 1;
                        rest.get_mut(next_arg - 1).and_then(Option::take)
                    } else if let Ok(i) = name.parse::<usize>() {
                        rest.get(i).and_then(|e| e.clone())
                    } else {
                        let id = syn::Ident::new(&name, fmt.span());
                        Some(Expr::Path(syn::ExprPath {
                            attrs: vec![],
                            qself: None,
                            path: id.into(),
                        }))
                    };
                    match arg {
                        Some(a) if fmtspec == "?" => pieces.push(FmtPiece::Debug(Box::new(a))),
                        Some(a) => pieces.push(FmtPiece::Arg(Box::new(a))),
                        None => {
                            return Err(self.err(
                                fmt.span(),
                                "invalid-format-string",
                                "format string references a missing argument",
                            ))
                        }
                    }
                }
                '}' => {
                    return Err(self.err(
                        fmt.span(),
                        "invalid-format-string",
                        "unmatched `}` in format string",
                    ))
                }
                c => lit.push(c),
            }
        }
        if !lit.is_empty() {
            pieces.push(FmtPiece::Lit(lit));
        }
        if rest.iter().any(Option::is_some) && next_arg < rest.len() {
            return Err(self.err(
                span,
                "invalid-format-string",
                "argument never used in format string",
            ));
        }
        Ok(pieces)
    }
}

fn op_str(op: &BinOp) -> String {
    use quote::ToTokens;
    op.to_token_stream().to_string()
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
        (_, "SQRT_2") => c::SQRT_2,
        (_, "FRAC_1_SQRT_2") => c::FRAC_1_SQRT_2,
        (_, "LN_2") => c::LN_2,
        (_, "LN_10") => c::LN_10,
        _ => return None,
    };
    Some(v)
}
