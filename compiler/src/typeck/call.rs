//! Paths, calls, method calls and trait resolution: user functions (generic ones get
//! their arguments inferred), tuple-struct and variant constructors, associated
//! functions and consts of impls and traits, the builtin catalogue, `core` functions,
//! and the compiler-derived `clone`/`eq`/`default`.

use super::infer::{Cx, Deferred, VarKind};
use super::{key, Callee, RecvAdj, Res};
use crate::builtins::{self, Builtin, Method, On, P};
use crate::diag::DResult;
use crate::resolve::{Ctor, FnId, FnParent, GlobalId, ImplId, Ns, PathRes, Recv};
use crate::ty::{FloatTy, IntTy, LangTrait, TraitKind, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::spanned::Spanned;
use syn::Expr;

/// A resolved associated function or method.
#[derive(Clone, Debug)]
pub(super) enum Pick {
    /// A user function with the generic arguments of its impl or trait (`Self` first).
    Fn(FnId, Vec<Ty>),
    /// A catalogue builtin.
    Builtin(&'static Method),
    /// A method the compiler derives for a type.
    Derived(LangTrait, &'static str),
}

impl<'p, 'a> Cx<'p, 'a> {
    // ---------------------------------------------------------------- paths

    /// Generic arguments written on a path segment (`::<T>`), instantiated.
    fn seg_args(&mut self, args: &syn::PathArguments) -> DResult<Option<Vec<Ty>>> {
        if matches!(args, syn::PathArguments::None) {
            return Ok(None);
        }
        let params = self.params.clone();
        let impl_types = self.impl_types.clone();
        let self_syn = self.self_syn.clone();
        let scope = crate::resolve::TyScope {
            self_ty: self_syn.as_ref(),
            params: &params,
            impl_types: impl_types.as_ref(),
            in_trait: self.in_trait,
        };
        let (tys, _) = self.p.type_args(self.module, self.file, args, &scope)?;
        let span = args.span();
        let mut out = Vec::new();
        for t in tys {
            out.push(self.inst(&t, span)?);
        }
        Ok(Some(out))
    }

    /// Fresh (or given) generic arguments for ADT `a`.
    fn adt_args(&mut self, a: usize, given: Option<Vec<Ty>>, span: Span) -> DResult<Vec<Ty>> {
        let n = self.p.adts[a].generics.len();
        match given {
            Some(g) if g.len() == n => Ok(g),
            Some(g) => Err(self.err(
                span,
                "wrong-generic-count",
                format!(
                    "`{}` takes {n} generic argument(s) but {} were supplied",
                    self.p.adts[a].name,
                    g.len()
                ),
            )),
            None => Ok((0..n).map(|_| self.fresh(VarKind::Any)).collect()),
        }
    }

    /// A value path's meaning, with generic arguments resolved. `Self` and `Self::X` are
    /// handled here.
    fn value_path(&mut self, path: &syn::Path, qself: Option<&syn::QSelf>) -> DResult<ValuePath> {
        let segs = crate::resolve::path_segs(path);
        let span = path.span();
        let n = segs.len();
        let last_args = self.seg_args(&path.segments[n - 1].arguments)?;
        if let Some(q) = qself {
            // `<T>::x` or `<T as Trait>::x`.
            let t = self.resolve_ty(&q.ty)?;
            if q.position == 0 {
                return Ok(ValuePath::TypeAssoc(t, segs[n - 1].clone(), last_args));
            }
            if q.position + 1 != n {
                return Err(self.err(
                    span,
                    "unsupported-qualified-path",
                    "unsupported qualified path",
                ));
            }
            let trait_path = syn::Path {
                leading_colon: None,
                segments: path.segments.iter().take(q.position).cloned().collect(),
            };
            let params = self.params.clone();
            let self_syn = self.self_syn.clone();
            let scope = crate::resolve::TyScope {
                self_ty: self_syn.as_ref(),
                params: &params,
                impl_types: None,
                in_trait: self.in_trait,
            };
            let tr =
                self.p
                    .resolve_trait_ref(self.module, self.file, &trait_path, &scope, Some(&t))?;
            let mut args = Vec::new();
            for a in &tr.args {
                args.push(self.inst(a, span)?);
            }
            return Ok(ValuePath::TraitItem(
                tr.kind,
                args,
                Some(t),
                segs[n - 1].clone(),
                last_args,
            ));
        }
        if segs[0] == "Self" {
            let Some(st) = self.self_ty.clone() else {
                return Err(self.err(span, "self-outside-impl", "`Self` outside an impl block"));
            };
            if n == 1 {
                return match st {
                    Ty::Adt(a, args) if !self.p.adts[a].is_enum => {
                        Ok(ValuePath::Ctor(a, 0, Some(args)))
                    }
                    _ => Err(self.err(span, "unresolved-path", "`Self` is not a value here")),
                };
            }
            if n == 2 {
                if let Ty::Adt(a, args) = &st {
                    if self.p.adts[*a].is_enum {
                        if let Some(v) = self.p.adts[*a].variant(&segs[1]) {
                            return Ok(ValuePath::Ctor(*a, v, Some(args.clone())));
                        }
                    }
                }
                return Ok(ValuePath::TypeAssoc(st, segs[1].clone(), last_args));
            }
        }
        // Generic parameters: `T::new()`.
        if n == 2 {
            if let Some(i) = self.params.iter().position(|p| *p == segs[0]) {
                let t = self.substs.get(i).cloned().unwrap_or(Ty::Unit);
                return Ok(ValuePath::TypeAssoc(t, segs[1].clone(), last_args));
            }
        }
        for s in path.segments.iter().take(n.saturating_sub(2)) {
            if !matches!(s.arguments, syn::PathArguments::None) {
                return Err(self.err(
                    s.arguments.span(),
                    "unsupported-generics",
                    "generic arguments are only supported on the last two segments of a path",
                ));
            }
        }
        let res = self
            .p
            .resolve_path_segs(self.module, self.file, &segs, Ns::Value, span)?;
        let type_args = if n >= 2 {
            self.seg_args(&path.segments[n - 2].arguments)?
        } else {
            None
        };
        Ok(match res {
            PathRes::Fn(f) => ValuePath::Fn(f, last_args),
            PathRes::Global(g) => ValuePath::Global(g),
            PathRes::Variant(a, v) => ValuePath::Ctor(a, v, type_args.or(last_args)),
            PathRes::Adt(a) => ValuePath::Ctor(a, 0, last_args),
            PathRes::AdtAssoc(a, name) => {
                let args = self.adt_args(a, type_args, span)?;
                ValuePath::TypeAssoc(Ty::Adt(a, args), name, last_args)
            }
            PathRes::AliasAssoc(al, name) => {
                let ad = &self.p.aliases[al];
                let t = self.p.resolve_type(
                    ad.module,
                    ad.file,
                    ad.ty,
                    &crate::resolve::TyScope::params(&ad.params),
                )?;
                let args: Vec<Ty> = match type_args {
                    Some(a) => a,
                    None => (0..ad.params.len())
                        .map(|_| self.fresh(VarKind::Any))
                        .collect(),
                };
                let t = t.subst(&args);
                let t = self.norm(&t, span)?;
                ValuePath::TypeAssoc(t, name, last_args)
            }
            PathRes::PrimAssoc(t, name) => ValuePath::TypeAssoc(t, name, last_args),
            PathRes::FloatConst(f, name) => ValuePath::FloatConst(f, name),
            PathRes::TraitAssoc(k, name) => {
                ValuePath::TraitItem(k, Vec::new(), None, name, last_args)
            }
            PathRes::StdFn(m, f) => ValuePath::StdFn(m, f, last_args),
            _ => {
                return Err(self.err(
                    span,
                    "unresolved-path",
                    format!("`{}` is not a value", segs.join("::")),
                ))
            }
        })
    }

    pub fn path_expr(&mut self, e: &Expr, p: &syn::ExprPath) -> DResult<Ty> {
        if p.qself.is_none() {
            if let Some(id) = p
                .path
                .get_ident()
                .and_then(|i| self.lookup_local(&i.to_string()))
            {
                self.body.res.insert(key(e), Res::Local(id));
                return Ok(self.body.locals[id].ty.clone());
            }
        }
        let span = p.span();
        let vp = self.value_path(&p.path, p.qself.as_ref())?;
        let (res, ty) = match vp {
            ValuePath::Global(g) => {
                let t = self.p.globals[g].ty.clone();
                (Res::Global(g, Vec::new()), t)
            }
            ValuePath::Ctor(a, v, args) => {
                let vd = &self.p.adts[a].variants[v];
                if vd.ctor != Ctor::Unit {
                    return Err(self.err(
                        span,
                        "unsupported-fn-pointer",
                        format!("`{}` is a constructor; call it (`{0}(..)`) — constructors as function values are not supported", vd.name),
                    ));
                }
                let args = self.adt_args(a, args, span)?;
                (Res::Unit(a, v), Ty::Adt(a, args))
            }
            ValuePath::TypeAssoc(t, name, _) => {
                let t = self.shallow(&t);
                match (&t, name.as_str()) {
                    (Ty::Int(it), "MAX") => (Res::Int(*it, it.max()), t.clone()),
                    (Ty::Int(it), "MIN") => (Res::Int(*it, it.min()), t.clone()),
                    (Ty::Int(it), "BITS") => {
                        (Res::Int(IntTy::U32, it.bits() as i128), Ty::Int(IntTy::U32))
                    }
                    (Ty::Float(f), n) if super::float_const(*f, n).is_some() => (
                        Res::Float(*f, super::float_const(*f, n).expect("checked")),
                        t.clone(),
                    ),
                    _ => match self.assoc_const(&t, &name, span)? {
                        Some((g, substs)) => {
                            let ty = self.norm(&self.p.globals[g].ty.subst(&substs), span)?;
                            (Res::Global(g, substs), ty)
                        }
                        None => {
                            if self.assoc_fn(&t, &name, span)?.is_some() {
                                return Err(self.err(span, "unsupported-fn-pointer", "functions can only be called; function pointers are not supported in TRaX-Rust"));
                            }
                            return Err(self.err(
                                span,
                                "unresolved-path",
                                format!("no associated item `{name}` on `{}`", self.show(&t)),
                            ));
                        }
                    },
                }
            }
            ValuePath::FloatConst(f, n) => match super::float_const(f, &n) {
                Some(v) => (Res::Float(f, v), Ty::Float(f)),
                None => {
                    return Err(self.err(
                        span,
                        "unresolved-path",
                        format!("unknown constant `{n}`"),
                    ))
                }
            },
            ValuePath::TraitItem(k, targs, self_t, name, _) => {
                let st = match self_t {
                    Some(t) => t,
                    None => self.fresh(VarKind::Any),
                };
                // An associated const of a trait.
                let known = !self.has_unknown(&st);
                if known {
                    if let Some((g, substs)) = self.trait_const(k, &targs, &st, &name, span)? {
                        let ty = self.norm(&self.p.globals[g].ty.subst(&substs), span)?;
                        self.body.res.insert(key(e), Res::Global(g, substs));
                        return Ok(ty);
                    }
                }
                let TraitKind::User(t) = k else {
                    return Err(self.err(span, "unsupported-fn-pointer", "functions can only be called; function pointers are not supported in TRaX-Rust"));
                };
                let Some((_, g)) = self.p.traits[t]
                    .consts
                    .iter()
                    .find(|(n, _)| *n == name)
                    .cloned()
                else {
                    return Err(self.err(
                        span,
                        "unresolved-path",
                        format!(
                            "no associated const `{name}` in trait `{}`",
                            self.p.traits[t].name
                        ),
                    ));
                };
                let mut substs = vec![st.clone()];
                substs.extend(targs.iter().cloned());
                let ty = self.norm(&self.p.globals[g].ty.subst(&substs), span)?;
                self.deferred.push(Deferred {
                    key: key(e),
                    tr: k,
                    name,
                    self_ty: st,
                    trait_args: targs,
                    own: Vec::new(),
                    span,
                    is_call: false,
                });
                return Ok(ty);
            }
            ValuePath::Fn(..) | ValuePath::StdFn(..) => return Err(self.err(
                span,
                "unsupported-fn-pointer",
                "functions can only be called; function pointers are not supported in TRaX-Rust",
            )),
        };
        self.body.res.insert(key(e), res);
        Ok(ty)
    }

    // ---------------------------------------------------------------- calls

    /// Checks call arguments against parameter types (coercing).
    pub fn args(&mut self, args: &[&Expr], params: &[Ty], span: Span, what: &str) -> DResult<()> {
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
            self.coerce(a, &t, p, a.span())?;
        }
        Ok(())
    }

    /// Instantiates function `f`'s signature: `parent` arguments (impl/trait) followed by
    /// its own (given or fresh).
    fn instantiate(
        &mut self,
        f: FnId,
        parent: Vec<Ty>,
        own: Option<Vec<Ty>>,
        span: Span,
    ) -> DResult<(Vec<Ty>, Vec<Ty>, Ty)> {
        let fd = &self.p.fns[f];
        let n_own = fd.generics.len() - fd.generics.parent;
        let own = match own {
            Some(o) if o.len() == n_own => o,
            Some(o) => {
                return Err(self.err(
                    span,
                    "wrong-generic-count",
                    format!(
                        "function `{}` takes {n_own} generic argument(s) but {} were supplied",
                        fd.name,
                        o.len()
                    ),
                ))
            }
            None => (0..n_own).map(|_| self.fresh(VarKind::Any)).collect(),
        };
        let mut substs = parent;
        substs.extend(own);
        let params: Vec<Ty> = fd.params.iter().map(|t| t.subst(&substs)).collect();
        let params = params
            .iter()
            .map(|t| self.norm(t, span))
            .collect::<DResult<Vec<_>>>()?;
        let ret = fd.ret.subst(&substs);
        let ret = self.norm(&ret, span)?;
        Ok((substs, params, ret))
    }

    /// Calls user function `f` with `args` (receiver first for UFCS/method calls).
    #[allow(clippy::too_many_arguments)]
    fn call_fn(
        &mut self,
        e: &Expr,
        f: FnId,
        parent: Vec<Ty>,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
        span: Span,
        recv: RecvAdj,
    ) -> DResult<Ty> {
        let (substs, params, ret) = self.instantiate(f, parent, own, span)?;
        let what = format!("function `{}`", self.p.fns[f].name);
        self.args(args, &params, span, &what)?;
        let ret = self.norm(&ret, span)?;
        self.body.callees.insert(
            key(e),
            Callee::Fn {
                func: f,
                substs,
                recv,
            },
        );
        Ok(ret)
    }

    pub fn call(&mut self, e: &Expr, c: &syn::ExprCall) -> DResult<Ty> {
        let Expr::Path(fp) = &*c.func else {
            return Err(self.err(
                c.func.span(),
                "unsupported-call",
                "only calls of named functions are supported (no function pointers or closures)",
            ));
        };
        if fp.qself.is_none()
            && fp
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
        let args: Vec<&Expr> = c.args.iter().collect();
        let span = c.span();
        match self.value_path(&fp.path, fp.qself.as_ref())? {
            ValuePath::Fn(f, own) => {
                let parent = match self.p.fns[f].parent {
                    FnParent::Free => Vec::new(),
                    _ => {
                        return Err(self.err(
                            c.func.span(),
                            "unresolved-path",
                            "not a free function",
                        ))
                    }
                };
                self.call_fn(e, f, parent, own, &args, span, RecvAdj::default())
            }
            ValuePath::Ctor(a, v, targs) => {
                let vd = &self.p.adts[a].variants[v];
                if vd.ctor != Ctor::Tuple {
                    return Err(self.err(
                        c.func.span(),
                        "not-a-function",
                        format!("`{}` is not a tuple struct or tuple variant", vd.name),
                    ));
                }
                let targs = self.adt_args(a, targs, span)?;
                let ftys: Vec<Ty> = self.p.adts[a].variants[v]
                    .fields
                    .iter()
                    .map(|f| f.ty.subst(&targs))
                    .collect();
                let ftys = ftys
                    .iter()
                    .map(|t| self.norm(t, span))
                    .collect::<DResult<Vec<_>>>()?;
                let what = format!("`{}`", self.p.adts[a].variants[v].name);
                self.args(&args, &ftys, span, &what)?;
                self.body
                    .callees
                    .insert(key(e), Callee::Ctor { adt: a, variant: v });
                Ok(Ty::Adt(a, targs))
            }
            ValuePath::TypeAssoc(t, name, own) => {
                let t = self.shallow(&t);
                let t = match t {
                    Ty::Var(v) if self.vars[v as usize].0 == VarKind::Float => {
                        Ty::Float(FloatTy::F64)
                    }
                    Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int => Ty::Int(IntTy::I32),
                    t => t,
                };
                match self.assoc_fn(&t, &name, c.func.span())? {
                    Some(Pick::Fn(f, parent)) => {
                        self.call_fn(e, f, parent, own, &args, span, RecvAdj::default())
                    }
                    Some(Pick::Builtin(m)) => self.builtin_call(e, m, &t, &args, span, false),
                    Some(Pick::Derived(tr, m)) => {
                        self.derived_call(e, tr, m, &t, &args, span, RecvAdj::default())
                    }
                    None => Err(self.err(
                        c.func.span(),
                        "unresolved-path",
                        format!(
                            "no function or associated item named `{name}` found for `{}`",
                            self.show(&t)
                        ),
                    )),
                }
            }
            ValuePath::TraitItem(k, targs, self_t, name, own) => {
                self.trait_call(e, k, targs, self_t, &name, own, &args, span)
            }
            ValuePath::StdFn(m, f, own) => self.std_call(e, m, f, own, &args, span),
            ValuePath::Global(_) | ValuePath::FloatConst(..) => Err(self.err(
                c.func.span(),
                "unsupported-call",
                "only calls of named functions are supported (no function pointers or closures)",
            )),
        }
    }

    /// `Trait::item(args)` / `<T as Trait>::item(args)`.
    #[allow(clippy::too_many_arguments)]
    fn trait_call(
        &mut self,
        e: &Expr,
        k: TraitKind,
        targs: Vec<Ty>,
        self_t: Option<Ty>,
        name: &str,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
        span: Span,
    ) -> DResult<Ty> {
        // Without `<T as ..>`, `Self` comes from the receiver argument or from inference.
        let st = match self_t {
            Some(t) => t,
            None => {
                let has_recv = match k {
                    TraitKind::User(t) => self.p.traits[t]
                        .methods
                        .iter()
                        .find(|(n, _)| n == name)
                        .is_some_and(|(_, f)| self.p.fns[*f].receiver.is_some()),
                    TraitKind::Lang(l) => !matches!(l, LangTrait::Default),
                };
                if has_recv && !args.is_empty() {
                    let t0 = self.expr(args[0])?;
                    let (inner, _) = self.autoderef(&t0);
                    let recv_kind = match k {
                        TraitKind::User(t) => self.p.traits[t]
                            .methods
                            .iter()
                            .find(|(n, _)| n == name)
                            .and_then(|(_, f)| self.p.fns[*f].receiver),
                        TraitKind::Lang(_) => None,
                    };
                    match recv_kind {
                        Some(Recv::Value) => t0,
                        _ => {
                            if matches!(self.shallow(&t0), Ty::Ref(..)) {
                                inner
                            } else {
                                t0
                            }
                        }
                    }
                } else {
                    self.fresh(VarKind::Any)
                }
            }
        };
        if !self.has_unknown(&st) {
            let st = self.deep_keep(&st);
            if let Some(pick) = self.trait_item_fn(k, &targs, &st, name, span)? {
                return match pick {
                    Pick::Fn(f, parent) => {
                        self.call_fn(e, f, parent, own, args, span, RecvAdj::default())
                    }
                    Pick::Builtin(m) => self.builtin_call(e, m, &st, args, span, false),
                    Pick::Derived(tr, m) => {
                        self.derived_call(e, tr, m, &st, args, span, RecvAdj::default())
                    }
                };
            }
            return Err(self.err(
                span,
                "missing-trait-impl",
                format!(
                    "the trait `{}` is not implemented for `{}` (no `{name}`)",
                    self.p.trait_name(k),
                    self.show(&st)
                ),
            ));
        }
        // Deferred: instantiate the trait's declaration with `Self` unknown.
        match k {
            TraitKind::User(t) => {
                let Some((_, f)) = self.p.traits[t]
                    .methods
                    .iter()
                    .find(|(n, _)| n == name)
                    .cloned()
                else {
                    return Err(self.err(
                        span,
                        "unresolved-path",
                        format!("no function `{name}` in trait `{}`", self.p.traits[t].name),
                    ));
                };
                let targs: Vec<Ty> = if targs.is_empty() {
                    (1..self.p.traits[t].generics.len())
                        .map(|_| self.fresh(VarKind::Any))
                        .collect()
                } else {
                    targs
                };
                let mut parent = vec![st.clone()];
                parent.extend(targs.iter().cloned());
                let (substs, params, ret) = self.instantiate(f, parent, own, span)?;
                let what = format!("function `{}`", self.p.fns[f].name);
                self.args(args, &params, span, &what)?;
                let np = self.p.fns[f].generics.parent;
                self.deferred.push(Deferred {
                    key: key(e),
                    tr: k,
                    name: name.to_string(),
                    self_ty: st,
                    trait_args: targs,
                    own: substs[np..].to_vec(),
                    span,
                    is_call: true,
                });
                Ok(ret)
            }
            TraitKind::Lang(LangTrait::Default) if name == "default" => {
                self.args(args, &[], span, "`Default::default`")?;
                self.deferred.push(Deferred {
                    key: key(e),
                    tr: k,
                    name: name.to_string(),
                    self_ty: st.clone(),
                    trait_args: Vec::new(),
                    own: Vec::new(),
                    span,
                    is_call: true,
                });
                Ok(st)
            }
            TraitKind::Lang(l) => Err(self.err(
                span,
                "type-annotation-needed",
                format!("type annotations needed for `{}::{name}`", l.name()),
            )),
        }
    }

    /// Resolves a deferred trait item now that `Self` is known.
    pub fn resolve_deferred(
        &mut self,
        d: &Deferred,
        st: Ty,
        targs: Vec<Ty>,
        own: Vec<Ty>,
    ) -> DResult<()> {
        if !d.is_call {
            match self.trait_const(d.tr, &targs, &st, &d.name, d.span)? {
                Some((g, substs)) => {
                    self.body.res.insert(d.key, Res::Global(g, substs));
                    return Ok(());
                }
                None => {
                    return Err(self.err(
                        d.span,
                        "missing-trait-impl",
                        format!(
                            "the trait `{}` is not implemented for `{}`",
                            self.p.trait_name(d.tr),
                            self.show(&st)
                        ),
                    ))
                }
            }
        }
        match self.trait_item_fn(d.tr, &targs, &st, &d.name, d.span)? {
            Some(Pick::Fn(f, mut parent)) => {
                for p in parent.iter_mut() {
                    *p = self.deep(p);
                }
                parent.extend(own);
                self.body.callees.insert(
                    d.key,
                    Callee::Fn {
                        func: f,
                        substs: parent,
                        recv: RecvAdj::default(),
                    },
                );
                Ok(())
            }
            Some(Pick::Derived(tr, m)) => {
                self.body.callees.insert(
                    d.key,
                    Callee::Derived {
                        tr,
                        method: m,
                        ty: st,
                        recv: RecvAdj::default(),
                    },
                );
                Ok(())
            }
            Some(Pick::Builtin(m)) => {
                self.body.callees.insert(
                    d.key,
                    Callee::Builtin {
                        b: m.b,
                        recv: RecvAdj::default(),
                    },
                );
                Ok(())
            }
            None => Err(self.err(
                d.span,
                "missing-trait-impl",
                format!(
                    "the trait `{}` is not implemented for `{}`",
                    self.p.trait_name(d.tr),
                    self.show(&st)
                ),
            )),
        }
    }

    fn std_call(
        &mut self,
        e: &Expr,
        m: &str,
        f: &str,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
        span: Span,
    ) -> DResult<Ty> {
        let b = match (m, f) {
            ("ptr", "read") => Builtin::PtrRead,
            ("ptr", "read_volatile") => Builtin::PtrReadVolatile,
            ("ptr", "write") => Builtin::PtrWrite,
            ("ptr", "write_volatile") => Builtin::PtrWriteVolatile,
            ("ptr", "null" | "null_mut") => Builtin::StdNull,
            ("mem", "swap") => Builtin::MemSwap,
            ("mem", "replace") => Builtin::MemReplace,
            ("mem", "take") => Builtin::MemTake,
            ("cmp", "min") => Builtin::CmpMin,
            _ => Builtin::CmpMax,
        };
        let el = match own {
            Some(mut o) if o.len() == 1 => o.remove(0),
            Some(_) => {
                return Err(self.err(
                    span,
                    "wrong-generic-count",
                    format!("`{m}::{f}` takes one generic argument"),
                ))
            }
            None => self.fresh(VarKind::Any),
        };
        let name = format!("`{m}::{f}`");
        let ret = match b {
            Builtin::PtrRead | Builtin::PtrReadVolatile => {
                self.args(args, &[Ty::Ptr(false, Box::new(el.clone()))], span, &name)?;
                el
            }
            Builtin::PtrWrite | Builtin::PtrWriteVolatile => {
                self.args(
                    args,
                    &[Ty::Ptr(true, Box::new(el.clone())), el],
                    span,
                    &name,
                )?;
                Ty::Unit
            }
            Builtin::StdNull => {
                self.args(args, &[], span, &name)?;
                Ty::Ptr(f == "null_mut", Box::new(el))
            }
            Builtin::MemSwap => {
                let r = Ty::Ref(true, Box::new(el));
                self.args(args, &[r.clone(), r], span, &name)?;
                Ty::Unit
            }
            Builtin::MemReplace => {
                self.args(
                    args,
                    &[Ty::Ref(true, Box::new(el.clone())), el.clone()],
                    span,
                    &name,
                )?;
                el
            }
            Builtin::MemTake => {
                self.args(args, &[Ty::Ref(true, Box::new(el.clone()))], span, &name)?;
                el
            }
            _ => {
                self.args(args, &[el.clone(), el.clone()], span, &name)?;
                let t = self.shallow(&el);
                if !(t.is_int()
                    || matches!(t, Ty::Bool | Ty::Char)
                    || matches!(t, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int))
                {
                    return Err(self.err(span, "unsupported-call", format!("{name} is supported on integers, `bool` and `char` (found `{}`; floats are not `Ord`)", self.show(&t))));
                }
                el
            }
        };
        self.body.callees.insert(
            key(e),
            Callee::Builtin {
                b,
                recv: RecvAdj::default(),
            },
        );
        Ok(ret)
    }

    /// A catalogue builtin called by path (`f32::from_bits(b)`, `f32::sqrt(x)`) or as a
    /// method (`recv` given: the receiver is the first argument, already checked).
    fn builtin_call(
        &mut self,
        e: &Expr,
        m: &'static Method,
        s: &Ty,
        args: &[&Expr],
        span: Span,
        _method: bool,
    ) -> DResult<Ty> {
        // By path, a method's receiver is the first argument.
        let is_assoc = builtins::ASSOC_FNS.iter().any(|x| std::ptr::eq(x, m));
        let mut params: Vec<Ty> = Vec::new();
        if !is_assoc {
            let recv_ty = if matches!(m.on, On::Seq | On::SeqMut) {
                Ty::Ref(m.on == On::SeqMut, Box::new(s.clone()))
            } else {
                s.clone()
            };
            params.push(recv_ty);
        }
        for p in m.params {
            params.push(self.param_ty(*p, s, span)?);
        }
        let what = format!("`{}::{}`", self.show(s), m.name);
        self.args(args, &params, span, &what)?;
        let b = self.libm_or(m, s, span)?;
        match b {
            Ok(b) => {
                self.body.callees.insert(
                    key(e),
                    Callee::Builtin {
                        b,
                        recv: RecvAdj::default(),
                    },
                );
            }
            Err(f) => {
                self.body.callees.insert(
                    key(e),
                    Callee::Fn {
                        func: f,
                        substs: Vec::new(),
                        recv: RecvAdj::default(),
                    },
                );
            }
        }
        self.param_ty(m.ret, s, span)
    }

    /// A libm builtin becomes a call of the prelude's function (`Err(fn)`).
    fn libm_or(&self, m: &Method, s: &Ty, span: Span) -> DResult<Result<Builtin, FnId>> {
        if let Builtin::Libm(f32n, f64n) = m.b {
            let name = if *s == Ty::Float(FloatTy::F64) {
                f64n
            } else {
                f32n
            };
            return match self.p.libm_fn(name) {
                Some(f) => Ok(Err(f)),
                None => Err(self.err(
                    span,
                    "unsupported-float-method",
                    format!(
                        "`{}::{}` needs the prelude's math library (`trax::libm::{name}`), which is not available",
                        self.p.ty_str(s),
                        m.name
                    ),
                )),
            };
        }
        Ok(Ok(m.b))
    }

    /// The type of a catalogue signature entry for receiver type `s`.
    fn param_ty(&mut self, p: P, s: &Ty, span: Span) -> DResult<Ty> {
        let opt = |cx: &Self, t: Ty| -> DResult<Ty> {
            match cx.p.lang.option {
                Some(o) => Ok(Ty::Adt(o, vec![t])),
                None => Err(cx.err(
                    span,
                    "missing-lang-item",
                    "this method returns an `Option`, which needs the prelude crate `trax`",
                )),
            }
        };
        let ordering = |cx: &Self| -> DResult<Ty> {
            match cx.p.lang.ordering {
                Some(o) => Ok(Ty::Adt(o, Vec::new())),
                None => Err(cx.err(
                    span,
                    "missing-lang-item",
                    "this method returns an `Ordering`, which needs the prelude crate `trax`",
                )),
            }
        };
        Ok(match p {
            P::S => s.clone(),
            P::RefS => Ty::Ref(false, Box::new(s.clone())),
            P::Unit => Ty::Unit,
            P::Bool => Ty::Bool,
            P::U32 => Ty::Int(IntTy::U32),
            P::I32 => Ty::Int(IntTy::I32),
            P::Usize => Ty::Int(IntTy::Usize),
            P::Isize => Ty::Int(IntTy::Isize),
            P::Unsigned => match s {
                Ty::Int(i) => Ty::Int(builtins::unsigned_of(*i)),
                _ => s.clone(),
            },
            P::Bits => Ty::Int(if *s == Ty::Float(FloatTy::F64) {
                IntTy::U64
            } else {
                IntTy::U32
            }),
            P::Lane | P::Elem => builtins::elem_of(s).unwrap_or(Ty::Unit),
            P::F32x4 => Ty::Simd(crate::ty::SimdTy::F32x4),
            P::I32x4 => Ty::Simd(crate::ty::SimdTy::I32x4),
            P::RefElem => Ty::Ref(false, Box::new(builtins::elem_of(s).unwrap_or(Ty::Unit))),
            P::OptRefElem => {
                let r = Ty::Ref(false, Box::new(builtins::elem_of(s).unwrap_or(Ty::Unit)));
                opt(self, r)?
            }
            P::PairS => Ty::Tuple(vec![s.clone(), s.clone()]),
            P::Ordering => ordering(self)?,
            P::OptOrdering => {
                let o = ordering(self)?;
                opt(self, o)?
            }
            P::SliceRef => Ty::Ref(
                false,
                Box::new(Ty::Slice(Box::new(
                    builtins::elem_of(s).unwrap_or(Ty::Unit),
                ))),
            ),
        })
    }

    /// A derived method called by path (`Foo::default()`, `Clone::clone(&x)`) or as a
    /// method.
    #[allow(clippy::too_many_arguments)]
    fn derived_call(
        &mut self,
        e: &Expr,
        tr: LangTrait,
        m: &'static str,
        s: &Ty,
        args: &[&Expr],
        span: Span,
        recv: RecvAdj,
    ) -> DResult<Ty> {
        let (params, ret) = match m {
            "default" => (Vec::new(), s.clone()),
            "clone" => (vec![Ty::Ref(false, Box::new(s.clone()))], s.clone()),
            "eq" | "ne" => (
                vec![
                    Ty::Ref(false, Box::new(s.clone())),
                    Ty::Ref(false, Box::new(s.clone())),
                ],
                Ty::Bool,
            ),
            _ => {
                return Err(self.err(
                    span,
                    "unsupported-call",
                    format!("`{m}` cannot be called here"),
                ))
            }
        };
        let params =
            if recv != RecvAdj::default() || !args.is_empty() && params.len() == args.len() + 1 {
                params[1..].to_vec()
            } else {
                params
            };
        self.args(args, &params, span, &format!("`{m}`"))?;
        self.body.callees.insert(
            key(e),
            Callee::Derived {
                tr,
                method: m,
                ty: s.clone(),
                recv,
            },
        );
        Ok(ret)
    }

    // ---------------------------------------------------------------- method calls

    pub fn method_call(&mut self, e: &Expr, m: &syn::ExprMethodCall) -> DResult<Ty> {
        let own = match &m.turbofish {
            Some(t) => {
                let args =
                    syn::PathArguments::AngleBracketed(syn::AngleBracketedGenericArguments {
                        colon2_token: None,
                        lt_token: t.lt_token,
                        args: t.args.clone(),
                        gt_token: t.gt_token,
                    });
                self.seg_args(&args)?
            }
            None => None,
        };
        let name = m.method.to_string();
        let rt = self.expr(&m.receiver)?;
        let args: Vec<&Expr> = m.args.iter().collect();
        let span = m.method.span();
        let mut t = self.shallow(&rt);
        let mut derefs = 0;
        loop {
            if let Ty::Var(v) = t {
                let d = match self.vars[v as usize].0 {
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
            if let Some(pick) = self.method_pick(&t, &name, span)? {
                return self.method_with(e, m, pick, &t, derefs, own, &args);
            }
            match &t {
                Ty::Ref(_, inner) => {
                    t = self.shallow(inner);
                    derefs += 1;
                }
                _ => break,
            }
        }
        if matches!(
            name.as_str(),
            "iter"
                | "iter_mut"
                | "into_iter"
                | "enumerate"
                | "zip"
                | "rev"
                | "step_by"
                | "map"
                | "filter"
                | "sum"
                | "fold"
                | "collect"
                | "skip"
                | "take"
                | "chain"
                | "windows"
                | "chunks"
        ) {
            return Err(self.err(
                m.method.span(),
                "unsupported-iterator",
                format!("`.{name}()` is only supported as the iterator of a `for` loop (iterators are not values in TRaX-Rust)"),
            ));
        }
        let t0 = self.deep_keep(&rt);
        if let Some(b) = builtins::method_anywhere(&name) {
            let what = match b.on {
                On::SInt => "signed integers",
                On::UInt => "unsigned integers",
                On::PtrMut => "`*mut` pointers",
                On::SeqMut => "mutable arrays and slices",
                _ => "",
            };
            if !what.is_empty() && builtins::method(&self.autoderef(&t0).0, &name).is_none() {
                let (base, _) = self.autoderef(&t0);
                if matches!(
                    (b.on, &base),
                    (On::SInt | On::UInt, Ty::Int(_)) | (On::PtrMut, Ty::Ptr(..))
                ) {
                    return Err(self.err(
                        span,
                        "unknown-method",
                        format!(
                            "no method `{name}` on `{}` (it is defined on {what})",
                            self.show(&base)
                        ),
                    ));
                }
            }
        }
        Err(self.err(
            span,
            "unknown-method",
            format!("no method `{name}` on `{}`", self.show(&t0)),
        ))
    }

    #[allow(clippy::too_many_arguments)]
    fn method_with(
        &mut self,
        e: &Expr,
        m: &syn::ExprMethodCall,
        pick: Pick,
        t: &Ty,
        derefs: u32,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
    ) -> DResult<Ty> {
        let span = m.method.span();
        match pick {
            Pick::Fn(f, parent) => {
                let fd = &self.p.fns[f];
                let Some(recv) = fd.receiver else {
                    return Err(self.err(
                        span,
                        "not-a-method",
                        format!(
                            "`{}` is an associated function, not a method; call it as `{}(...)`",
                            fd.name, fd.name
                        ),
                    ));
                };
                let autoref = match recv {
                    Recv::Value => None,
                    Recv::Ref => Some(false),
                    Recv::RefMut => Some(true),
                };
                if recv == Recv::RefMut {
                    self.check_recv_mut(&m.receiver, derefs)?;
                }
                let (substs, params, ret) = self.instantiate(f, parent, own, span)?;
                // The receiver's type matched the impl's `Self`.
                let self_param = params[0].clone();
                let recv_ty = match autoref {
                    Some(mm) => Ty::Ref(mm, Box::new(t.clone())),
                    None => t.clone(),
                };
                self.unify(&recv_ty, &self_param, m.receiver.span())?;
                let what = format!("method `{}`", self.p.fns[f].name);
                self.args(args, &params[1..], m.span(), &what)?;
                let ret = self.norm(&ret, span)?;
                self.body.callees.insert(
                    key(e),
                    Callee::Fn {
                        func: f,
                        substs,
                        recv: RecvAdj { derefs, autoref },
                    },
                );
                Ok(ret)
            }
            Pick::Builtin(b) => {
                let by_ref = matches!(b.on, On::Seq | On::SeqMut);
                if b.on == On::SeqMut {
                    self.check_recv_mut(&m.receiver, derefs)?;
                }
                let mut params = Vec::new();
                for p in b.params {
                    params.push(self.param_ty(*p, t, span)?);
                }
                let what = format!("method `{}`", b.name);
                self.args(args, &params, m.span(), &what)?;
                let bb = self.libm_or(b, t, span)?;
                let recv = RecvAdj {
                    derefs,
                    autoref: by_ref.then_some(b.on == On::SeqMut),
                };
                match bb {
                    Ok(bi) => {
                        self.body
                            .callees
                            .insert(key(e), Callee::Builtin { b: bi, recv });
                    }
                    Err(f) => {
                        self.body.callees.insert(
                            key(e),
                            Callee::Fn {
                                func: f,
                                substs: Vec::new(),
                                recv,
                            },
                        );
                    }
                }
                self.param_ty(b.ret, t, span)
            }
            Pick::Derived(tr, name) => {
                let recv = RecvAdj {
                    derefs,
                    autoref: Some(false),
                };
                self.derived_call(e, tr, name, t, args, m.span(), recv)
            }
        }
    }

    fn check_recv_mut(&mut self, recv: &Expr, derefs: u32) -> DResult<()> {
        if derefs == 0 {
            return self.check_place(recv, true);
        }
        let t = self.body.tys.get(&key(recv)).cloned().unwrap_or(Ty::Unit);
        let mut t = self.shallow(&t);
        let mut ok = true;
        for _ in 0..derefs {
            match t {
                Ty::Ref(m, inner) => {
                    ok &= m;
                    t = self.shallow(&inner);
                }
                _ => break,
            }
        }
        if ok {
            Ok(())
        } else {
            Err(self.err(
                recv.span(),
                "immutable-borrow",
                "cannot borrow data behind a `&` reference as mutable",
            ))
        }
    }

    /// The method `name` applicable to a receiver of exactly type `t` (one autoderef
    /// step): inherent impls, the builtin catalogue, trait impls, derived methods.
    fn method_pick(&mut self, t: &Ty, name: &str, span: Span) -> DResult<Option<Pick>> {
        if let Some(p) = self.inherent_fn(t, name, true)? {
            return Ok(Some(p));
        }
        if let Some(m) = builtins::method(t, name) {
            return Ok(Some(Pick::Builtin(m)));
        }
        if let Some(p) = self.trait_fn(t, name, true, span)? {
            return Ok(Some(p));
        }
        Ok(self.derived_fn(t, name, true))
    }

    /// An inherent method or associated function of `t`.
    fn inherent_fn(&mut self, t: &Ty, name: &str, method: bool) -> DResult<Option<Pick>> {
        if !matches!(t, Ty::Adt(..)) {
            return Ok(None);
        }
        let mut found = Vec::new();
        for (i, substs) in self.p.impls_matching(None, t) {
            if let Some(&f) = self.p.impls[i].fns.get(name) {
                if method && self.p.fns[f].receiver.is_none() {
                    continue;
                }
                found.push((i, f, substs));
            }
        }
        if found.is_empty() {
            return Ok(None);
        }
        // Several impls (e.g. for `Foo<f32>` and `Foo<f64>`): the one that unifies.
        for (i, f, substs) in found {
            let parent = self.impl_substs(i, substs);
            let self_ty = self.p.impls[i].self_ty.subst(&parent);
            if self.can_unify(&self_ty, t) {
                self.try_unify(&self_ty, t);
                return Ok(Some(Pick::Fn(f, parent)));
            }
        }
        Ok(None)
    }

    /// Completes matched impl arguments with fresh variables.
    fn impl_substs(&mut self, _i: ImplId, substs: Vec<Option<Ty>>) -> Vec<Ty> {
        substs
            .into_iter()
            .map(|s| s.unwrap_or_else(|| self.fresh(VarKind::Any)))
            .collect()
    }

    /// A method of a trait implemented for `t` (a method of the impl, or the trait's
    /// default).
    fn trait_fn(&mut self, t: &Ty, name: &str, method: bool, span: Span) -> DResult<Option<Pick>> {
        let mut found: Vec<Pick> = Vec::new();
        for i in 0..self.p.impls.len() {
            let Some(tr) = self.p.impls[i].trait_.clone() else {
                continue;
            };
            let mut substs = vec![None; self.p.impls[i].generics.len()];
            if !self.p.match_ty(&self.p.impls[i].self_ty, t, &mut substs) {
                continue;
            }
            let pick = match self.p.impls[i].fns.get(name) {
                Some(&f) => {
                    if method && self.p.fns[f].receiver.is_none() {
                        continue;
                    }
                    let parent = self.impl_substs(i, substs);
                    Pick::Fn(f, parent)
                }
                None => match tr.kind {
                    TraitKind::User(tid) => {
                        let Some((_, f)) = self.p.traits[tid]
                            .methods
                            .iter()
                            .find(|(n, _)| n == name)
                            .cloned()
                        else {
                            continue;
                        };
                        if self.p.fns[f].body.is_none()
                            || (method && self.p.fns[f].receiver.is_none())
                        {
                            continue;
                        }
                        let isubsts = self.impl_substs(i, substs);
                        let mut parent = vec![t.clone()];
                        for a in &tr.args {
                            parent.push(a.subst(&isubsts));
                        }
                        Pick::Fn(f, parent)
                    }
                    TraitKind::Lang(_) => continue,
                },
            };
            if !self.impl_bounds_hold(i, t) {
                continue;
            }
            found.push(pick);
        }
        match found.len() {
            0 => Ok(None),
            1 => Ok(found.pop()),
            _ => {
                // Prefer impls whose self type unifies exactly.
                let exact: Vec<Pick> = found
                    .iter()
                    .filter(|p| match p {
                        Pick::Fn(f, parent) => {
                            let st = self.p.fns[*f]
                                .self_ty
                                .clone()
                                .unwrap_or(Ty::Unit)
                                .subst(parent);
                            st == *t
                        }
                        _ => false,
                    })
                    .cloned()
                    .collect();
                if exact.len() == 1 {
                    return Ok(exact.into_iter().next());
                }
                Err(self.err(
                    span,
                    "ambiguous-method",
                    format!(
                        "multiple applicable items named `{name}` for `{}`",
                        self.show(t)
                    ),
                ))
            }
        }
    }

    /// True if the impl's bounds on its parameters plausibly hold for `t` (blanket impls
    /// such as `impl<T: Float> Vector for T` apply only to `Float` types).
    fn impl_bounds_hold(&self, i: ImplId, t: &Ty) -> bool {
        let im = &self.p.impls[i];
        let mut substs = vec![None; im.generics.len()];
        if !self.p.match_ty(&im.self_ty, t, &mut substs) {
            return false;
        }
        im.generics.bounds.iter().all(|b| {
            let Ty::Param(pi) = b.ty else { return true };
            match substs.get(pi as usize).cloned().flatten() {
                Some(at) => self.implements(&at, b.tr.kind, 0),
                None => true,
            }
        })
    }

    /// Best-effort check that `t` implements trait `k`.
    pub fn implements(&self, t: &Ty, k: TraitKind, depth: u32) -> bool {
        if depth > 8 || t.has_vars() {
            return true;
        }
        match k {
            TraitKind::Lang(l) => match l {
                LangTrait::Copy | LangTrait::Clone => self.is_copy(t) || self.has_impl(t, k),
                LangTrait::Sized | LangTrait::Debug => true,
                LangTrait::PartialEq | LangTrait::Eq => self.derives_eq(t) || self.has_impl(t, k),
                LangTrait::Default => self.has_default(t) || self.has_impl(t, k),
                LangTrait::PartialOrd | LangTrait::Ord => {
                    matches!(t, Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char)
                        || self.has_impl(t, k)
                }
                _ => matches!(t, Ty::Int(_) | Ty::Float(_)) || self.has_impl(t, k),
            },
            TraitKind::User(_) => self.has_impl(t, k),
        }
    }

    fn has_impl(&self, t: &Ty, k: TraitKind) -> bool {
        self.p.impls.iter().enumerate().any(|(i, im)| {
            im.trait_.as_ref().is_some_and(|tr| tr.kind == k) && self.impl_bounds_hold(i, t)
        })
    }

    /// `clone`/`eq`/`ne`/`default` the compiler provides for a type.
    fn derived_fn(&self, t: &Ty, name: &str, method: bool) -> Option<Pick> {
        match name {
            "clone" if self.is_copy(t) || self.derives(t, LangTrait::Clone) => {
                Some(Pick::Derived(LangTrait::Clone, "clone"))
            }
            "eq" if self.derives_eq(t) => Some(Pick::Derived(LangTrait::PartialEq, "eq")),
            "ne" if self.derives_eq(t) => Some(Pick::Derived(LangTrait::PartialEq, "ne")),
            "default" if !method && self.has_default(t) => {
                Some(Pick::Derived(LangTrait::Default, "default"))
            }
            _ => None,
        }
    }

    fn derives(&self, t: &Ty, tr: LangTrait) -> bool {
        matches!(t, Ty::Adt(a, _) if self.p.adts[*a].derives.has(tr))
    }

    /// True for types that are `Copy` (plain data; ADTs must derive it).
    pub fn is_copy(&self, t: &Ty) -> bool {
        match t {
            Ty::Adt(a, args) => {
                self.p.adts[*a].derives.has(LangTrait::Copy)
                    || self.has_impl(&Ty::Adt(*a, args.clone()), TraitKind::Lang(LangTrait::Copy))
            }
            Ty::Tuple(ts) => ts.iter().all(|x| self.is_copy(x)),
            Ty::Array(e, _) => self.is_copy(e),
            Ty::Ref(m, _) => !m,
            Ty::Slice(_) => false,
            _ => true,
        }
    }

    /// True if `==` on `t` can be the compiler's structural comparison.
    pub fn derives_eq(&self, t: &Ty) -> bool {
        match t {
            Ty::Adt(a, args) => {
                self.p.adts[*a].derives.has(LangTrait::PartialEq)
                    && self.p.adts[*a]
                        .variants
                        .iter()
                        .flat_map(|v| &v.fields)
                        .all(|f| {
                            let ft = f.ty.subst(args);
                            self.derives_eq(&ft)
                                || self.has_impl(&ft, TraitKind::Lang(LangTrait::PartialEq))
                                || ft.has_vars()
                        })
            }
            Ty::Tuple(ts) => ts.iter().all(|x| {
                self.derives_eq(x) || self.has_impl(x, TraitKind::Lang(LangTrait::PartialEq))
            }),
            Ty::Array(e, _) | Ty::Slice(e) | Ty::Ref(_, e) => {
                self.derives_eq(e) || self.has_impl(e, TraitKind::Lang(LangTrait::PartialEq))
            }
            Ty::Int(_)
            | Ty::Float(_)
            | Ty::Bool
            | Ty::Char
            | Ty::Unit
            | Ty::Ptr(..)
            | Ty::Var(_) => true,
            _ => false,
        }
    }

    /// True if the compiler provides `Default::default()` for `t`.
    pub fn has_default(&self, t: &Ty) -> bool {
        match t {
            Ty::Adt(a, args) => {
                let d = &self.p.adts[*a];
                d.derives.has(LangTrait::Default)
                    && d.variants.iter().flat_map(|v| &v.fields).all(|f| {
                        let ft = f.ty.subst(args);
                        self.has_default(&ft)
                            || self.has_impl(&ft, TraitKind::Lang(LangTrait::Default))
                    })
            }
            Ty::Tuple(ts) => ts.iter().all(|x| {
                self.has_default(x) || self.has_impl(x, TraitKind::Lang(LangTrait::Default))
            }),
            Ty::Array(e, n) => {
                *n <= 32
                    && (self.has_default(e)
                        || self.has_impl(e, TraitKind::Lang(LangTrait::Default)))
            }
            Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Unit | Ty::Simd(_) => true,
            _ => false,
        }
    }

    /// An associated function (or method, for UFCS) of type `t`.
    fn assoc_fn(&mut self, t: &Ty, name: &str, span: Span) -> DResult<Option<Pick>> {
        if let Some(p) = self.inherent_fn(t, name, false)? {
            return Ok(Some(p));
        }
        if let Some(m) = builtins::assoc_fn(t, name) {
            return Ok(Some(Pick::Builtin(m)));
        }
        if let Some(m) = builtins::method(t, name) {
            return Ok(Some(Pick::Builtin(m)));
        }
        if let Some(p) = self.trait_fn(t, name, false, span)? {
            return Ok(Some(p));
        }
        Ok(self.derived_fn(t, name, false))
    }

    /// A function of trait `k` for `Self = t` (impl method, trait default, derived).
    fn trait_item_fn(
        &mut self,
        k: TraitKind,
        targs: &[Ty],
        t: &Ty,
        name: &str,
        span: Span,
    ) -> DResult<Option<Pick>> {
        let mut found = Vec::new();
        for i in 0..self.p.impls.len() {
            let Some(tr) = self.p.impls[i].trait_.clone() else {
                continue;
            };
            if tr.kind != k {
                continue;
            }
            let mut substs = vec![None; self.p.impls[i].generics.len()];
            if !self.p.match_ty(&self.p.impls[i].self_ty, t, &mut substs) {
                continue;
            }
            if !targs.is_empty() && tr.args.len() == targs.len() {
                let ok = tr
                    .args
                    .iter()
                    .zip(targs)
                    .all(|(p, a)| self.p.match_ty(p, a, &mut substs));
                if !ok {
                    continue;
                }
            }
            if !self.impl_bounds_hold(i, t) {
                continue;
            }
            let isubsts = self.impl_substs(i, substs);
            match self.p.impls[i].fns.get(name) {
                Some(&f) => found.push(Pick::Fn(f, isubsts)),
                None => {
                    if let TraitKind::User(tid) = k {
                        if let Some((_, f)) =
                            self.p.traits[tid].methods.iter().find(|(n, _)| n == name)
                        {
                            let mut parent = vec![t.clone()];
                            for a in &tr.args {
                                parent.push(a.subst(&isubsts));
                            }
                            found.push(Pick::Fn(*f, parent));
                        }
                    }
                }
            }
        }
        if found.len() > 1 {
            return Err(self.err(
                span,
                "ambiguous-method",
                format!(
                    "multiple impls of `{}` apply to `{}`",
                    self.p.trait_name(k),
                    self.show(t)
                ),
            ));
        }
        if let Some(p) = found.pop() {
            return Ok(Some(p));
        }
        if let TraitKind::Lang(l) = k {
            if let Some(p) = self.derived_fn(t, name, false) {
                if let Pick::Derived(dl, _) = p {
                    if dl == l {
                        return Ok(Some(p));
                    }
                }
            }
            if let Some(m) = builtins::method(t, name) {
                return Ok(Some(Pick::Builtin(m)));
            }
        }
        Ok(None)
    }

    /// An associated const of `t`: inherent, then trait impls, then trait defaults.
    pub fn assoc_const(
        &mut self,
        t: &Ty,
        name: &str,
        span: Span,
    ) -> DResult<Option<(GlobalId, Vec<Ty>)>> {
        for (i, substs) in self.p.impls_matching(None, t) {
            if let Some(&g) = self.p.impls[i].consts.get(name) {
                let s = self.impl_substs(i, substs);
                let st = self.p.impls[i].self_ty.subst(&s);
                self.try_unify(&st, t);
                return Ok(Some((g, s)));
            }
        }
        let mut found = Vec::new();
        for i in 0..self.p.impls.len() {
            let Some(tr) = self.p.impls[i].trait_.clone() else {
                continue;
            };
            let TraitKind::User(tid) = tr.kind else {
                continue;
            };
            if !self.p.traits[tid].consts.iter().any(|(n, _)| n == name) {
                continue;
            }
            if let Some(r) = self.trait_const(tr.kind, &[], t, name, span)? {
                if !found.contains(&r) {
                    found.push(r);
                }
            }
        }
        match found.len() {
            0 => Ok(None),
            1 => Ok(found.pop()),
            _ => Err(self.err(
                span,
                "ambiguous-method",
                format!(
                    "multiple associated consts named `{name}` for `{}`",
                    self.show(t)
                ),
            )),
        }
    }

    /// Associated const `name` of trait `k` for `Self = t`.
    fn trait_const(
        &mut self,
        k: TraitKind,
        targs: &[Ty],
        t: &Ty,
        name: &str,
        _span: Span,
    ) -> DResult<Option<(GlobalId, Vec<Ty>)>> {
        let TraitKind::User(tid) = k else {
            return Ok(None);
        };
        for i in 0..self.p.impls.len() {
            let Some(tr) = self.p.impls[i].trait_.clone() else {
                continue;
            };
            if tr.kind != k {
                continue;
            }
            let mut substs = vec![None; self.p.impls[i].generics.len()];
            if !self.p.match_ty(&self.p.impls[i].self_ty, t, &mut substs) {
                continue;
            }
            if !targs.is_empty()
                && tr.args.len() == targs.len()
                && !tr
                    .args
                    .iter()
                    .zip(targs)
                    .all(|(p, a)| self.p.match_ty(p, a, &mut substs))
            {
                continue;
            }
            if !self.impl_bounds_hold(i, t) {
                continue;
            }
            let isubsts = self.impl_substs(i, substs);
            if let Some(&g) = self.p.impls[i].consts.get(name) {
                return Ok(Some((g, isubsts)));
            }
            if let Some((_, g)) = self.p.traits[tid].consts.iter().find(|(n, _)| n == name) {
                if self.p.globals[*g].expr.is_some() {
                    let mut parent = vec![t.clone()];
                    for a in &tr.args {
                        parent.push(a.subst(&isubsts));
                    }
                    return Ok(Some((*g, parent)));
                }
            }
        }
        Ok(None)
    }

    /// The method `name` of a trait `k` implemented for `t` (used by operators).
    pub fn trait_method_on(
        &mut self,
        k: TraitKind,
        t: &Ty,
        name: &str,
        targs: &[Ty],
        span: Span,
    ) -> DResult<Option<(FnId, Vec<Ty>)>> {
        match self.trait_item_fn(k, targs, t, name, span)? {
            Some(Pick::Fn(f, parent)) => {
                let (substs, params, _) = self.instantiate(f, parent, None, span)?;
                if let Some(p0) = params.first() {
                    let st = match self.p.fns[f].receiver {
                        Some(Recv::Ref) => Ty::Ref(false, Box::new(t.clone())),
                        Some(Recv::RefMut) => Ty::Ref(true, Box::new(t.clone())),
                        _ => t.clone(),
                    };
                    self.try_unify(&st, p0);
                }
                Ok(Some((f, substs)))
            }
            _ => Ok(None),
        }
    }

    /// The impl of operator trait `tr` for `lt op rt`: its method, generic arguments,
    /// result type and the impl's other methods (`ne`, `lt`, ...).
    pub fn op_impl(
        &mut self,
        tr: LangTrait,
        lt: &Ty,
        rt: &Ty,
        span: Span,
    ) -> DResult<Option<OpImpl>> {
        let k = TraitKind::Lang(tr);
        let method = tr.methods()[0].0;
        let mut found = Vec::new();
        for i in 0..self.p.impls.len() {
            let Some(itr) = self.p.impls[i].trait_.clone() else {
                continue;
            };
            if itr.kind != k {
                continue;
            }
            let mut substs = vec![None; self.p.impls[i].generics.len()];
            if !self.p.match_ty(&self.p.impls[i].self_ty, lt, &mut substs) {
                continue;
            }
            if let Some(rhs) = itr.args.first() {
                if !self.p.match_ty(rhs, rt, &mut substs) {
                    continue;
                }
            }
            let Some(&f) = self.p.impls[i].fns.get(method) else {
                continue;
            };
            let isubsts: Vec<Ty> = substs.into_iter().map(|s| s.unwrap_or(Ty::Infer)).collect();
            // Trial-unify the instantiated operand types.
            let st = self.p.impls[i].self_ty.subst(&isubsts);
            let rhs = itr
                .args
                .first()
                .map(|r| r.subst(&isubsts))
                .unwrap_or_else(|| st.clone());
            if st.has_params() || rhs.has_params() {
                continue;
            }
            let st = self.norm(&st, span)?;
            let rhs = self.norm(&rhs, span)?;
            if self.can_unify(&st, lt) && self.can_unify(&rhs, rt) {
                found.push((i, f, isubsts, st, rhs));
            }
        }
        if found.len() > 1 {
            return Err(self.err(
                span,
                "ambiguous-operator",
                format!(
                    "ambiguous operator `{}` for `{}` and `{}`",
                    tr.name(),
                    self.show(lt),
                    self.show(rt)
                ),
            ));
        }
        let Some((i, f, isubsts, st, rhs)) = found.pop() else {
            return Ok(None);
        };
        self.try_unify(&st, lt);
        self.try_unify(&rhs, rt);
        let ret = self.p.fns[f].ret.subst(&isubsts);
        let ret = self.norm(&ret, span)?;
        let fns = self.p.impls[i].fns.clone();
        Ok(Some((f, isubsts, ret, fns)))
    }

    /// `Index`/`IndexMut` impl for `base[idx]`: method, arguments and output type.
    pub fn index_impl(
        &mut self,
        base: &Ty,
        idx: &Ty,
        mutable: bool,
        span: Span,
    ) -> DResult<Option<(FnId, Vec<Ty>, Ty)>> {
        let tr = if mutable {
            LangTrait::IndexMut
        } else {
            LangTrait::Index
        };
        let method = if mutable { "index_mut" } else { "index" };
        for i in 0..self.p.impls.len() {
            let Some(itr) = self.p.impls[i].trait_.clone() else {
                continue;
            };
            if itr.kind != TraitKind::Lang(tr) {
                continue;
            }
            let mut substs = vec![None; self.p.impls[i].generics.len()];
            if !self.p.match_ty(&self.p.impls[i].self_ty, base, &mut substs) {
                continue;
            }
            if !self.p.match_ty(&itr.args[0], idx, &mut substs) {
                continue;
            }
            let Some(&f) = self.p.impls[i].fns.get(method) else {
                continue;
            };
            let isubsts = self.impl_substs(i, substs);
            let it = itr.args[0].subst(&isubsts);
            if !self.can_unify(idx, &it) {
                continue;
            }
            self.try_unify(idx, &it);
            let ret = self.norm(&self.p.fns[f].ret.subst(&isubsts), span)?;
            let out = match ret {
                Ty::Ref(_, o) => *o,
                other => other,
            };
            return Ok(Some((f, isubsts, out)));
        }
        Ok(None)
    }

    // ---------------------------------------------------------------- struct literals

    pub fn struct_lit(&mut self, e: &Expr, s: &syn::ExprStruct) -> DResult<Ty> {
        if s.qself.is_some() {
            return Err(self.err(
                s.span(),
                "unsupported-qualified-path",
                "qualified paths are not supported",
            ));
        }
        let segs = crate::resolve::path_segs(&s.path);
        let span = s.path.span();
        let (a, v, args) = match self.value_or_type_ctor(&s.path, &segs, span)? {
            Some(x) => x,
            None => {
                return Err(self.err(
                    span,
                    "not-a-struct",
                    format!("`{}` is not a struct or struct variant", segs.join("::")),
                ))
            }
        };
        self.body.structs.insert(key(e), (a, v));
        let def = &self.p.adts[a];
        let vd = def.variants[v].clone();
        let adt_name = if def.is_enum {
            format!("{}::{}", def.name, vd.name)
        } else {
            def.name.clone()
        };
        let mut seen = Vec::new();
        for fv in &s.fields {
            let name = match &fv.member {
                syn::Member::Named(n) => n.to_string(),
                syn::Member::Unnamed(i) => i.index.to_string(),
            };
            let Some(i) = vd.fields.iter().position(|f| f.name == name) else {
                return Err(self.err(
                    fv.member.span(),
                    "unknown-field",
                    format!("struct `{adt_name}` has no field `{name}`"),
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
            self.body.fields.insert(key(fv), i);
            let ft = self.norm(&vd.fields[i].ty.subst(&args), fv.span())?;
            self.expr_coerce(&fv.expr, &ft)?;
        }
        let st = Ty::Adt(a, args);
        match &s.rest {
            Some(r) => {
                if self.p.adts[a].is_enum {
                    return Err(self.err(
                        r.span(),
                        "unsupported-struct-update",
                        "functional update syntax is only for structs",
                    ));
                }
                let t = self.expr(r)?;
                self.unify(&t, &st, r.span())?;
            }
            None => {
                if let Some(missing) = vd.fields.iter().find(|f| !seen.contains(&f.name)) {
                    return Err(self.err(
                        span,
                        "missing-field",
                        format!(
                            "missing field `{}` in initializer of `{adt_name}`",
                            missing.name
                        ),
                    ));
                }
            }
        }
        Ok(st)
    }

    /// The struct or variant a struct-literal path names, with its generic arguments.
    fn value_or_type_ctor(
        &mut self,
        path: &syn::Path,
        segs: &[String],
        span: Span,
    ) -> DResult<Option<(usize, usize, Vec<Ty>)>> {
        if segs[0] == "Self" {
            return match (self.self_ty.clone(), segs.len()) {
                (Some(Ty::Adt(a, args)), 1) if !self.p.adts[a].is_enum => Ok(Some((a, 0, args))),
                (Some(Ty::Adt(a, args)), 2) => {
                    Ok(self.p.adts[a].variant(&segs[1]).map(|v| (a, v, args)))
                }
                _ => Err(self.err(span, "self-outside-impl", "`Self` is not a struct here")),
            };
        }
        let n = segs.len();
        let last_args = self.seg_args(&path.segments[n - 1].arguments)?;
        match self.p.try_resolve(self.module, segs, Ns::Type) {
            Some(PathRes::Adt(a)) if !self.p.adts[a].is_enum => {
                let args = self.adt_args(a, last_args.clone(), span)?;
                return Ok(Some((a, 0, args)));
            }
            Some(PathRes::Alias(al)) => {
                let ad = &self.p.aliases[al];
                let t = self.p.resolve_type(
                    ad.module,
                    ad.file,
                    ad.ty,
                    &crate::resolve::TyScope::params(&ad.params),
                )?;
                let args: Vec<Ty> = match last_args.clone() {
                    Some(a) => a,
                    None => (0..ad.params.len())
                        .map(|_| self.fresh(VarKind::Any))
                        .collect(),
                };
                if let Ty::Adt(a, aargs) = t.subst(&args) {
                    if !self.p.adts[a].is_enum {
                        return Ok(Some((a, 0, aargs)));
                    }
                }
            }
            _ => {}
        }
        match self.p.try_resolve(self.module, segs, Ns::Value) {
            Some(PathRes::Variant(a, v)) => {
                let targs = if n >= 2 {
                    self.seg_args(&path.segments[n - 2].arguments)?
                } else {
                    None
                };
                let args = self.adt_args(a, targs.or(last_args), span)?;
                Ok(Some((a, v, args)))
            }
            _ => {
                // Resolve again for the error message.
                self.p
                    .resolve_path_segs(self.module, self.file, segs, Ns::Type, span)?;
                Ok(None)
            }
        }
    }
}

/// An operator impl: method, generic arguments, result type and the impl's methods.
pub(super) type OpImpl = (FnId, Vec<Ty>, Ty, HashMap<String, FnId>);

/// What a value path names (see [`Cx::value_path`]).
enum ValuePath {
    Fn(FnId, Option<Vec<Ty>>),
    Global(GlobalId),
    /// A struct or variant constructor with the ADT's arguments if written.
    Ctor(usize, usize, Option<Vec<Ty>>),
    /// `Type::name` with the item's own generic arguments if written.
    TypeAssoc(Ty, String, Option<Vec<Ty>>),
    FloatConst(FloatTy, String),
    /// `Trait::name` / `<T as Trait>::name`: trait, its arguments, `Self` if known.
    TraitItem(TraitKind, Vec<Ty>, Option<Ty>, String, Option<Vec<Ty>>),
    StdFn(&'static str, &'static str, Option<Vec<Ty>>),
}
