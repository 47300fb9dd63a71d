//! The per-body checking context: inference variables, unification, coercions, locals
//! and scopes, syntactic types in bodies, and the final resolution of a body.

use super::{Adjust, Body, Callee, LocalId, LocalInfo, Res};
use crate::diag::{DResult, Diagnostic, FileId};
use crate::resolve::{FnId, FnParent, GlobalId, ModId, Program, TyScope};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, TraitKind, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::Stmt;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum VarKind {
    Any,
    Int,
    Float,
}

pub(super) struct LoopCx {
    pub label: Option<String>,
    /// `Some` for `loop` (type of break values so far).
    pub brk: Option<Option<Ty>>,
}

/// A trait item whose `Self` type is only known after inference (`Default::default()`).
pub(super) struct Deferred {
    /// Key of the call or path expression.
    pub key: usize,
    /// The trait.
    pub tr: TraitKind,
    /// Item name.
    pub name: String,
    /// `Self` (an inference variable when deferred).
    pub self_ty: Ty,
    /// The trait's generic arguments.
    pub trait_args: Vec<Ty>,
    /// The method's own generic arguments.
    pub own: Vec<Ty>,
    /// For errors.
    pub span: Span,
    /// A call (else a path to an associated const).
    pub is_call: bool,
}

pub(super) struct Cx<'p, 'a> {
    pub p: &'p Program<'a>,
    pub module: ModId,
    pub file: FileId,
    /// The instance's generic arguments.
    pub substs: Vec<Ty>,
    /// Generic parameter names of the item.
    pub params: Vec<String>,
    /// `Self` as written (with parameters) and as instantiated.
    pub self_syn: Option<Ty>,
    pub self_ty: Option<Ty>,
    pub impl_types: Option<HashMap<String, Ty>>,
    pub in_trait: Option<usize>,
    pub ret: Ty,
    pub body: Body,
    pub scopes: Vec<HashMap<String, LocalId>>,
    pub loops: Vec<LoopCx>,
    pub vars: Vec<(VarKind, Option<Ty>)>,
    /// Whether each local may be assigned (`mut`, or declared without initializer).
    pub local_mut: Vec<bool>,
    pub deferred: Vec<Deferred>,
    /// `const fn` bodies and initializers (for messages).
    pub in_const: bool,
    /// Spans of calls and method calls (for errors found when the body is finished).
    pub call_spans: HashMap<usize, Span>,
    /// The function instance being checked (closures are defined in it).
    pub cur_fn: Option<(FnId, Vec<Ty>)>,
    /// Closures being checked, innermost last.
    pub closure_frames: Vec<ClosureFrame>,
    /// Signatures a variable must have as a closure (from `F: Fn(A) -> R` bounds of the
    /// generic function whose argument it stands for).
    pub hints: HashMap<u32, (Vec<Ty>, Ty)>,
}

/// A closure whose body is being checked.
pub(super) struct ClosureFrame {
    /// Locals before this index belong to enclosing scopes (uses are captures).
    pub locals_base: usize,
    /// Captured locals in order of first use.
    pub captures: Vec<LocalId>,
}

/// Type-checks a function instance.
pub(super) fn check_fn(p: &Program, f: FnId, substs: &[Ty]) -> DResult<Body> {
    let fd = &p.fns[f];
    let body = fd.body.expect("checked functions have bodies");
    let impl_types = match fd.parent {
        FnParent::Impl(i) => Some(p.impls[i].types.clone()),
        _ => None,
    };
    let in_trait = match fd.parent {
        FnParent::Trait(t) => Some(t),
        _ => None,
    };
    let mut cx = Cx::new(p, fd.module, substs.to_vec(), fd.generics.names.clone());
    cx.self_syn = fd.self_ty.clone();
    cx.self_ty = match &fd.self_ty {
        Some(t) => Some(cx.inst(t, fd.sig.ident.span())?),
        None => None,
    };
    cx.impl_types = impl_types;
    cx.in_trait = in_trait;
    cx.in_const = fd.is_const;
    cx.cur_fn = Some((f, substs.to_vec()));
    cx.ret = cx.inst(&fd.ret, fd.sig.output.span())?;
    cx.scopes.push(HashMap::new());
    for (i, arg) in fd.sig.inputs.iter().enumerate() {
        let ty = cx.inst(&fd.params[i], arg.span())?;
        match arg {
            syn::FnArg::Receiver(r) => {
                let id = cx.new_local("self", ty, r.self_token.span);
                cx.local_mut[id] = r.mutability.is_some();
                cx.scopes[0].insert("self".into(), id);
            }
            syn::FnArg::Typed(pt) => {
                cx.bind_param(&pt.pat, &ty)?;
            }
        }
    }
    let t = cx.block(body)?;
    let ret = cx.ret.clone();
    let tail = block_tail_expr(body);
    match tail {
        Some(e) => cx.coerce(e, &t, &ret, e.span())?,
        None => cx.unify(&t, &ret, block_tail_span(body))?,
    }
    cx.finish()
}

/// Type-checks the initializer of a const or static instance.
pub(super) fn check_global(p: &Program, g: GlobalId, substs: &[Ty]) -> DResult<Body> {
    let gd = &p.globals[g];
    let expr = gd.expr.expect("checked globals have initializers");
    let mut cx = Cx::new(p, gd.module, substs.to_vec(), gd.generics.names.clone());
    cx.self_syn = gd.self_ty.clone();
    cx.self_ty = match &gd.self_ty {
        Some(t) => Some(cx.inst(t, gd.span)?),
        None => None,
    };
    cx.in_trait = p
        .traits
        .iter()
        .position(|t| t.consts.iter().any(|(_, x)| *x == g));
    cx.impl_types = p
        .impls
        .iter()
        .find(|im| im.consts.values().any(|x| *x == g))
        .map(|im| im.types.clone());
    cx.in_const = true;
    cx.scopes.push(HashMap::new());
    let want = cx.inst(&gd.ty, gd.ty_span)?;
    let t = cx.expr(expr)?;
    cx.coerce(expr, &t, &want, expr.span())?;
    cx.finish()
}

pub(super) fn block_tail_span(b: &syn::Block) -> Span {
    match b.stmts.last() {
        Some(Stmt::Expr(e, None)) => e.span(),
        _ => b.brace_token.span.close(),
    }
}

pub(super) fn block_tail_expr(b: &syn::Block) -> Option<&syn::Expr> {
    match b.stmts.last() {
        Some(Stmt::Expr(e, None)) => Some(e),
        _ => None,
    }
}

impl<'p, 'a> Cx<'p, 'a> {
    pub fn new(p: &'p Program<'a>, module: ModId, substs: Vec<Ty>, params: Vec<String>) -> Self {
        Cx {
            p,
            module,
            file: p.modules[module].file,
            substs,
            params,
            self_syn: None,
            self_ty: None,
            impl_types: None,
            in_trait: None,
            ret: Ty::Unit,
            body: Body::default(),
            scopes: Vec::new(),
            loops: Vec::new(),
            vars: Vec::new(),
            local_mut: Vec::new(),
            deferred: Vec::new(),
            in_const: false,
            call_spans: HashMap::new(),
            cur_fn: None,
            closure_frames: Vec::new(),
            hints: HashMap::new(),
        }
    }

    pub fn err(&self, span: Span, id: &'static str, msg: impl Into<String>) -> Diagnostic {
        self.p.err(self.file, span, id, msg)
    }

    pub fn new_local(&mut self, name: &str, ty: Ty, span: Span) -> LocalId {
        self.body.locals.push(LocalInfo {
            name: name.to_string(),
            ty,
            span,
        });
        self.local_mut.push(false);
        self.body.locals.len() - 1
    }

    pub fn fresh(&mut self, k: VarKind) -> Ty {
        self.vars.push((k, None));
        Ty::Var(self.vars.len() as u32 - 1)
    }

    /// Instantiates a type written with the item's generic parameters: substitutes the
    /// instance's arguments and normalises associated types.
    pub fn inst(&mut self, t: &Ty, span: Span) -> DResult<Ty> {
        let t = t.subst(&self.substs);
        self.norm(&t, span)
    }

    /// Normalises projections whose base is known; `_` becomes a fresh variable.
    pub fn norm(&mut self, t: &Ty, span: Span) -> DResult<Ty> {
        let mut has_infer = false;
        t.map(&mut |x| {
            if matches!(x, Ty::Infer) {
                has_infer = true;
            }
            None
        });
        let t = if has_infer {
            let mut vars = Vec::new();
            let n = t.map(&mut |x| match x {
                Ty::Infer => {
                    vars.push(());
                    Some(Ty::Var(u32::MAX))
                }
                _ => None,
            });
            // Replace the placeholders with fresh variables, in order.
            n.map(&mut |x| match x {
                Ty::Var(u32::MAX) => Some(self.fresh(VarKind::Any)),
                _ => None,
            })
        } else {
            t.clone()
        };
        let t = self.deep_keep(&t);
        self.p
            .normalize(&t)
            .map_err(|m| self.err(span, "unresolved-assoc-type", m))
    }

    /// Resolves a syntactic type written in the body.
    pub fn resolve_ty(&mut self, t: &syn::Type) -> DResult<Ty> {
        let params = self.params.clone();
        let impl_types = self.impl_types.clone();
        let self_syn = self.self_syn.clone();
        let scope = TyScope {
            self_ty: self_syn.as_ref(),
            params: &params,
            impl_types: impl_types.as_ref(),
            in_trait: self.in_trait,
        };
        let r = self.p.resolve_type(self.module, self.file, t, &scope)?;
        self.inst(&r, t.span())
    }

    /// Shallow resolution of inference variables.
    pub fn shallow(&self, t: &Ty) -> Ty {
        let mut t = t.clone();
        while let Ty::Var(v) = t {
            match self.vars.get(v as usize).and_then(|x| x.1.clone()) {
                Some(b) => t = b,
                None => return t,
            }
        }
        t
    }

    /// Full resolution keeping unbound variables.
    pub fn deep_keep(&self, t: &Ty) -> Ty {
        t.map(&mut |x| match x {
            Ty::Var(_) => {
                let s = self.shallow(x);
                match s {
                    Ty::Var(_) => Some(s),
                    other => Some(self.deep_keep(&other)),
                }
            }
            _ => None,
        })
    }

    /// Full resolution, defaulting unbound variables (integers to `i32`, floats to `f64`).
    pub fn deep(&self, t: &Ty) -> Ty {
        t.map(&mut |x| match x {
            Ty::Var(_) => match self.shallow(x) {
                Ty::Var(v) => Some(match self.vars[v as usize].0 {
                    VarKind::Int | VarKind::Any => Ty::Int(IntTy::I32),
                    VarKind::Float => Ty::Float(FloatTy::F64),
                }),
                other => Some(self.deep(&other)),
            },
            _ => None,
        })
    }

    /// True if `t` still has a variable that is not an integer or float literal's.
    pub fn has_unknown(&self, t: &Ty) -> bool {
        let mut found = false;
        self.deep_keep(t).map(&mut |x| {
            if let Ty::Var(v) = x {
                if self.vars[*v as usize].0 == VarKind::Any {
                    found = true;
                }
            }
            None
        });
        found
    }

    pub fn show(&self, t: &Ty) -> String {
        let t = self.deep_keep(t);
        let names = |s: usize| self.p.adts[s].name.clone();
        let shown = t.map(&mut |x| match x {
            Ty::Var(_) => None,
            _ => None,
        });
        let mut s = crate::ty::TyDisplay {
            ty: &shown,
            names: &names,
        }
        .to_string();
        // Variables: `{integer}`, `{float}`, `_`.
        if shown.has_vars() {
            s = String::new();
            self.show_into(&shown, &mut s);
        }
        s
    }

    fn show_into(&self, t: &Ty, out: &mut String) {
        match t {
            Ty::Var(v) => out.push_str(match self.vars[*v as usize].0 {
                VarKind::Int => "{integer}",
                VarKind::Float => "{float}",
                VarKind::Any => "_",
            }),
            Ty::Adt(a, args) => {
                out.push_str(&self.p.adts[*a].name);
                if !args.is_empty() {
                    out.push('<');
                    for (i, x) in args.iter().enumerate() {
                        if i > 0 {
                            out.push_str(", ");
                        }
                        self.show_into(x, out);
                    }
                    out.push('>');
                }
            }
            Ty::Tuple(ts) => {
                out.push('(');
                for (i, x) in ts.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    self.show_into(x, out);
                }
                if ts.len() == 1 {
                    out.push(',');
                }
                out.push(')');
            }
            Ty::Array(e, n) => {
                out.push('[');
                self.show_into(e, out);
                out.push_str(&format!("; {n}]"));
            }
            Ty::Slice(e) => {
                out.push('[');
                self.show_into(e, out);
                out.push(']');
            }
            Ty::Ref(m, e) => {
                out.push_str(if *m { "&mut " } else { "&" });
                self.show_into(e, out);
            }
            Ty::Ptr(m, e) => {
                out.push_str(if *m { "*mut " } else { "*const " });
                self.show_into(e, out);
            }
            other => out.push_str(&self.p.ty_str(other)),
        }
    }

    pub fn mismatch(&self, span: Span, expected: &Ty, found: &Ty) -> Diagnostic {
        if let (Ty::Closure(a), Ty::Closure(b)) = (self.shallow(expected), self.shallow(found)) {
            if a.key != b.key {
                return self
                    .err(
                        span,
                        "type-mismatch",
                        "mismatched types: expected closure, found a different closure",
                    )
                    .with_note("no two closures, even if identical, have the same type");
            }
        }
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

    /// Unifies `found` with `expected` (an error names both).
    pub fn unify(&mut self, found: &Ty, expected: &Ty, span: Span) -> DResult<()> {
        if !self.try_unify(found, expected) {
            return Err(self.mismatch(span, expected, found));
        }
        Ok(())
    }

    /// Unifies, or coerces `e`'s value (`&[T; N]` to `&[T]`).
    pub fn coerce(&mut self, e: &syn::Expr, found: &Ty, expected: &Ty, span: Span) -> DResult<()> {
        let f = self.shallow(found);
        let x = self.shallow(expected);
        if let (Ty::Ref(m1, fi), Ty::Ref(m2, xi)) = (&f, &x) {
            if let (Ty::Array(el, n), Ty::Slice(sel)) = (self.shallow(fi), self.shallow(xi)) {
                if *m1 || !*m2 {
                    self.unify(&el, &sel, span)?;
                    self.body.adjust.insert(super::key(e), Adjust::Unsize(n));
                    return Ok(());
                }
            }
        }
        self.unify(found, expected, span)
    }

    pub fn try_unify(&mut self, a: &Ty, b: &Ty) -> bool {
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
                    VarKind::Any => !occurs(*x, t, self),
                    VarKind::Int => t.is_int(),
                    VarKind::Float => t.is_float(),
                };
                if ok {
                    self.vars[*x as usize].1 = Some(t.clone());
                }
                ok
            }
            (Ty::Proj(..), _) | (_, Ty::Proj(..)) => {
                let na = self.deep_keep(&a);
                let nb = self.deep_keep(&b);
                match (self.p.normalize(&na), self.p.normalize(&nb)) {
                    (Ok(x), Ok(y)) if !matches!(x, Ty::Proj(..)) || !matches!(y, Ty::Proj(..)) => {
                        if x == na && y == nb {
                            return x == y;
                        }
                        self.try_unify(&x, &y)
                    }
                    _ => na == nb,
                }
            }
            (Ty::Adt(x, xs), Ty::Adt(y, ys)) => {
                x == y && xs.len() == ys.len() && {
                    let pairs: Vec<(Ty, Ty)> = xs.iter().cloned().zip(ys.iter().cloned()).collect();
                    pairs.iter().all(|(p, q)| self.try_unify(p, q))
                }
            }
            (Ty::Tuple(xs), Ty::Tuple(ys)) => {
                xs.len() == ys.len() && {
                    let pairs: Vec<(Ty, Ty)> = xs.iter().cloned().zip(ys.iter().cloned()).collect();
                    pairs.iter().all(|(p, q)| self.try_unify(p, q))
                }
            }
            (Ty::Closure(x), Ty::Closure(y)) => {
                x.key == y.key
                    && x.def_fn == y.def_fn
                    && x.def_substs == y.def_substs
                    && x.params.len() == y.params.len()
                    && {
                        let pairs: Vec<(Ty, Ty)> = x
                            .params
                            .iter()
                            .cloned()
                            .zip(y.params.iter().cloned())
                            .collect();
                        pairs.iter().all(|(p, q)| self.try_unify(p, q))
                    }
                    && self.try_unify(&x.ret, &y.ret)
            }
            (Ty::Array(x, n), Ty::Array(y, m)) => n == m && self.try_unify(x, y),
            (Ty::Slice(x), Ty::Slice(y)) => self.try_unify(x, y),
            (Ty::Ref(m1, x), Ty::Ref(m2, y)) => (m1 == m2 || (*m1 && !*m2)) && self.try_unify(x, y),
            (Ty::Ptr(m1, x), Ty::Ptr(m2, y)) => m1 == m2 && self.try_unify(x, y),
            // Coercion of a reference to a raw pointer (same machine value).
            (Ty::Ref(m1, x), Ty::Ptr(m2, y)) => (*m1 || !*m2) && self.try_unify(x, y),
            _ => a == b,
        }
    }

    /// Trial unification that leaves no trace.
    pub fn can_unify(&mut self, a: &Ty, b: &Ty) -> bool {
        let snap = self.vars.clone();
        let ok = self.try_unify(a, b);
        self.vars = snap;
        ok
    }

    pub fn lookup_local(&self, name: &str) -> Option<LocalId> {
        self.scopes.iter().rev().find_map(|s| s.get(name).copied())
    }

    /// Records a use of local `id` in the closures being checked (a capture of those
    /// defined after it).
    pub fn note_use(&mut self, id: LocalId) {
        for f in &mut self.closure_frames {
            if id < f.locals_base && !f.captures.contains(&id) {
                f.captures.push(id);
            }
        }
    }

    pub fn record(&mut self, e: &syn::Expr, t: Ty) -> Ty {
        self.body.tys.insert(super::key(e), t.clone());
        t
    }

    /// Declares a local in the innermost scope.
    pub fn declare(&mut self, name: &str, id: LocalId) {
        self.scopes
            .last_mut()
            .expect("scope")
            .insert(name.to_string(), id);
    }

    /// Resolves everything that waited for inference, defaults literal variables and
    /// returns the body.
    pub fn finish(mut self) -> DResult<Body> {
        let deferred = std::mem::take(&mut self.deferred);
        for d in deferred {
            let st = self.deep(&d.self_ty);
            if self.has_unknown(&d.self_ty) {
                return Err(self.err(
                    d.span,
                    "type-annotation-needed",
                    format!(
                        "type annotations needed: cannot infer the `Self` type of `{}::{}`",
                        self.p.trait_name(d.tr),
                        d.name
                    ),
                ));
            }
            let args: Vec<Ty> = d.trait_args.iter().map(|t| self.deep(t)).collect();
            let own: Vec<Ty> = d.own.iter().map(|t| self.deep(t)).collect();
            self.resolve_deferred(&d, st, args, own)?;
        }
        for l in 0..self.body.locals.len() {
            let t = self.body.locals[l].ty.clone();
            if self.has_unknown(&t) {
                let l = &self.body.locals[l];
                return Err(self.err(
                    l.span,
                    "type-annotation-needed",
                    format!("type annotations needed for `{}`", l.name),
                ));
            }
            self.body.locals[l].ty = self.deep(&t);
        }
        let keys: Vec<usize> = self.body.tys.keys().copied().collect();
        for k in keys {
            let t = self.deep(&self.body.tys[&k]);
            self.body.tys.insert(k, t);
        }
        let keys: Vec<usize> = self.body.callees.keys().copied().collect();
        for k in keys {
            let c = self.body.callees[&k].clone();
            let c = match c {
                Callee::Fn { func, substs, recv } => {
                    if substs.iter().any(|t| self.has_unknown(t)) {
                        let fd = &self.p.fns[func];
                        let span = self
                            .call_spans
                            .get(&k)
                            .copied()
                            .unwrap_or_else(|| fd.sig.ident.span());
                        return Err(self.err(
                            span,
                            "type-annotation-needed",
                            format!("type annotations needed: cannot infer the generic arguments of `{}`", fd.name),
                        ));
                    }
                    let substs: Vec<Ty> = substs.iter().map(|t| self.deep(t)).collect();
                    // Bounds on user traits must hold (`T: Shape`).
                    for b in &self.p.fns[func].generics.bounds {
                        if let crate::ty::TraitKind::User(tr) = b.tr.kind {
                            let bt = self.p.normalize(&b.ty.subst(&substs)).unwrap_or(Ty::Unit);
                            if !bt.has_params() && !self.implements(&bt, b.tr.kind, 0) {
                                let span = self
                                    .call_spans
                                    .get(&k)
                                    .copied()
                                    .unwrap_or_else(|| self.p.fns[func].sig.ident.span());
                                return Err(self.err(
                                    span,
                                    "unsatisfied-bound",
                                    format!(
                                        "the trait bound `{}: {}` is not satisfied (required by `{}`)",
                                        self.p.ty_str(&bt),
                                        self.p.traits[tr].name,
                                        self.p.fns[func].name
                                    ),
                                ));
                            }
                        }
                    }
                    Callee::Fn { func, substs, recv }
                }
                Callee::Derived {
                    tr,
                    method,
                    ty,
                    recv,
                } => Callee::Derived {
                    tr,
                    method,
                    ty: self.deep(&ty),
                    recv,
                },
                Callee::Closure { ty, derefs } => Callee::Closure {
                    ty: crate::ty::ClosureTy {
                        params: ty.params.iter().map(|t| self.deep(t)).collect(),
                        ret: self.deep(&ty.ret),
                        ..ty
                    },
                    derefs,
                },
                other => other,
            };
            self.body.callees.insert(k, c);
        }
        let keys: Vec<usize> = self.body.ops.keys().copied().collect();
        for k in keys {
            let o = match self.body.ops[&k].clone() {
                super::OpCall::Fn {
                    func,
                    substs,
                    by_ref,
                    via_partial_cmp,
                    negate,
                } => super::OpCall::Fn {
                    func,
                    substs: substs.iter().map(|t| self.deep(t)).collect(),
                    by_ref,
                    via_partial_cmp,
                    negate,
                },
                super::OpCall::DerivedEq { ty, negate } => super::OpCall::DerivedEq {
                    ty: self.deep(&ty),
                    negate,
                },
            };
            self.body.ops.insert(k, o);
        }
        let keys: Vec<usize> = self.body.res.keys().copied().collect();
        for k in keys {
            if let Res::Global(g, s) = &self.body.res[&k] {
                let r = Res::Global(*g, s.iter().map(|t| self.deep(t)).collect());
                self.body.res.insert(k, r);
            }
        }
        let keys: Vec<usize> = self.body.pats.keys().copied().collect();
        for k in keys {
            let mut pi = self.body.pats[&k].clone();
            pi.ty = self.deep(&pi.ty);
            self.body.pats.insert(k, pi);
        }
        let keys: Vec<usize> = self.body.fors.keys().copied().collect();
        for k in keys {
            let mut v = self.body.fors[&k].clone();
            for i in &mut v {
                i.elem = self.deep(&i.elem);
            }
            self.body.fors.insert(k, v);
        }
        let keys: Vec<usize> = self.body.tries.keys().copied().collect();
        for k in keys {
            let t = self.deep(&self.body.tries[&k]);
            self.body.tries.insert(k, t);
        }
        Ok(self.body)
    }
}

/// True if variable `v` occurs in `t` (no infinite types).
fn occurs(v: u32, t: &Ty, cx: &Cx) -> bool {
    let mut found = false;
    cx.deep_keep(t).map(&mut |x| {
        if *x == Ty::Var(v) {
            found = true;
        }
        None
    });
    found
}
