//! Paths in expressions: locals, consts and statics, unit structs and variants,
//! associated consts of types and traits (`T::ZERO`, `<T as Tr>::K`), generic arguments
//! written on paths, and struct literals (structs, enum struct variants, `Self`, aliases).

use super::infer::{Cx, Deferred, VarKind};
use super::{key, Res};
use crate::diag::DResult;
use crate::resolve::{Ctor, FnId, GlobalId, Ns, PathRes};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, TraitKind, Ty};
use proc_macro2::Span;
use syn::Expr;

impl<'p, 'a> Cx<'p, 'a> {
    // ---------------------------------------------------------------- paths

    /// Generic arguments written on a path segment (`::<T>`), instantiated.
    pub(super) fn seg_args(&mut self, args: &syn::PathArguments) -> DResult<Option<Vec<Ty>>> {
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
    pub(super) fn adt_args(
        &mut self,
        a: usize,
        given: Option<Vec<Ty>>,
        span: Span,
    ) -> DResult<Vec<Ty>> {
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
    pub(super) fn value_path(
        &mut self,
        path: &syn::Path,
        qself: Option<&syn::QSelf>,
    ) -> DResult<ValuePath> {
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
        // `T::Assoc::f()`, `Self::Assoc::f()`: the prefix is a type.
        if n >= 3 && (segs[0] == "Self" || self.params.contains(&segs[0])) {
            let prefix = syn::Type::Path(syn::TypePath {
                attrs: vec![],
                qself: None,
                path: syn::Path {
                    leading_colon: None,
                    segments: path.segments.iter().take(n - 1).cloned().collect(),
                },
            });
            let t = self.resolve_ty(&prefix)?;
            return Ok(ValuePath::TypeAssoc(t, segs[n - 1].clone(), last_args));
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
                self.note_use(id);
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
    pub(super) fn value_or_type_ctor(
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

/// What a value path names (see [`Cx::value_path`]).
pub(super) enum ValuePath {
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
