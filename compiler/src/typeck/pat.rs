//! Patterns: bindings (`ref`, `mut`, `@`), default binding modes, literals, ranges,
//! constants, tuples, structs, enum variants, slices and arrays, `|`, `&`.

use super::infer::{Cx, VarKind};
use super::{key, BindMode, PatInfo, PatKind};
use crate::diag::DResult;
use crate::resolve::{Ctor, Ns, PathRes};
use crate::span::Spanned;
use crate::ty::{AdtId, Ty};
use std::collections::HashMap;
use syn::{Expr, Pat};

/// What a pattern path names.
pub(super) enum PatPath {
    /// A variant (or a struct: variant 0) with the ADT's generic arguments.
    Ctor(AdtId, usize, Vec<Ty>),
    /// A constant: its type and integer value.
    Const(Ty, i128),
}

impl<'p, 'a> Cx<'p, 'a> {
    /// Checks `pat` against a value of type `expected` and declares its bindings in the
    /// current scope (`uninit`: a `let` without initializer, bindings assignable once).
    pub fn pattern(&mut self, pat: &Pat, expected: &Ty, uninit: bool) -> DResult<()> {
        let mut names = HashMap::new();
        self.pat(pat, expected, BindMode::Value, uninit, &mut names)
    }

    fn info(&mut self, pat: &Pat, ty: &Ty, derefs: u32, kind: PatKind) {
        self.body.pats.insert(
            key(pat),
            PatInfo {
                ty: ty.clone(),
                derefs,
                kind,
            },
        );
    }

    /// Peels references for a non-reference pattern (default binding modes).
    fn peel(&self, expected: &Ty, mode: BindMode) -> (Ty, u32, BindMode) {
        let mut t = self.shallow(expected);
        let mut n = 0;
        let mut mode = mode;
        while let Ty::Ref(m, inner) = t {
            mode = match mode {
                BindMode::Ref(false) => BindMode::Ref(false),
                _ => BindMode::Ref(m),
            };
            t = self.shallow(&inner);
            n += 1;
        }
        (t, n, mode)
    }

    fn pat(
        &mut self,
        pat: &Pat,
        expected: &Ty,
        mode: BindMode,
        uninit: bool,
        names: &mut HashMap<String, usize>,
    ) -> DResult<()> {
        match pat {
            Pat::Wild(_) => {
                self.info(pat, expected, 0, PatKind::Plain);
                Ok(())
            }
            Pat::Paren(p) => {
                self.info(pat, expected, 0, PatKind::Plain);
                self.pat(&p.pat, expected, mode, uninit, names)
            }
            Pat::Ident(pi) => {
                if pi.by_ref.is_none() && pi.mutability.is_none() && pi.subpat.is_none() {
                    let segs = vec![pi.ident.to_string()];
                    if let Some(pp) = self.pat_path_res(&segs, pi.span(), true)? {
                        return self.path_pat(pat, pp, expected, mode);
                    }
                }
                let bmode = match (&pi.by_ref, &pi.mutability) {
                    (Some(_), m) => BindMode::Ref(m.is_some()),
                    // `mut x` binds by value (edition 2021).
                    (None, Some(_)) => BindMode::Value,
                    (None, None) => mode,
                };
                let lty = match bmode {
                    BindMode::Value => expected.clone(),
                    BindMode::Ref(m) => Ty::Ref(m, Box::new(expected.clone())),
                };
                let name = pi.ident.to_string();
                let id = match names.get(&name) {
                    Some(&id) => {
                        let prev = self.body.locals[id].ty.clone();
                        self.unify(&lty, &prev, pi.ident.span())?;
                        id
                    }
                    None => {
                        let id = self.new_local(&name, lty, pi.ident.span());
                        self.local_mut[id] =
                            (pi.mutability.is_some() && pi.by_ref.is_none()) || uninit;
                        names.insert(name.clone(), id);
                        id
                    }
                };
                self.declare(&name, id);
                self.body.binds.insert(key(pi), (id, bmode));
                self.info(pat, expected, 0, PatKind::Binding);
                if let Some((_, sub)) = &pi.subpat {
                    if !matches!(**sub, Pat::Rest(_)) {
                        self.pat(sub, expected, mode, uninit, names)?;
                    }
                }
                Ok(())
            }
            Pat::Reference(r) => {
                let t = self.shallow(expected);
                let inner = match t.clone() {
                    Ty::Ref(m, inner) => {
                        if r.mutability.is_some() && !m {
                            return Err(self.mismatch(r.span(), &t, &Ty::Ref(true, inner)));
                        }
                        *inner
                    }
                    Ty::Var(_) => {
                        let v = self.fresh(VarKind::Any);
                        let rt = Ty::Ref(r.mutability.is_some(), Box::new(v.clone()));
                        self.unify(&rt, expected, r.span())?;
                        v
                    }
                    other => {
                        return Err(self.err(
                            r.span(),
                            "type-mismatch",
                            format!(
                                "mismatched types: expected `{}`, found `&_` pattern",
                                self.show(&other)
                            ),
                        ))
                    }
                };
                self.info(pat, expected, 0, PatKind::Plain);
                self.pat(&r.pat, &inner, BindMode::Value, uninit, names)
            }
            Pat::Or(o) => {
                self.info(pat, expected, 0, PatKind::Plain);
                for c in &o.cases {
                    self.pat(c, expected, mode, uninit, names)?;
                }
                Ok(())
            }
            Pat::Lit(l) => {
                let (t, n, _) = self.peel(expected, mode);
                if matches!(l.lit, syn::Lit::Str(_)) {
                    return Err(self.err(
                        l.span(),
                        "unsupported-pattern",
                        "string literal patterns are not supported in TRaX-Rust",
                    ));
                }
                let lt = self.lit(&l.lit)?;
                self.body.tys.insert(key(l), lt.clone());
                self.unify(&lt, &t, l.span())?;
                self.info(pat, &t, n, PatKind::Plain);
                Ok(())
            }
            Pat::Range(r) => {
                let (t, n, _) = self.peel(expected, mode);
                for b in [&r.start, &r.end].into_iter().flatten() {
                    let bt = self.pat_bound(b)?;
                    self.unify(&bt, &t, b.span())?;
                }
                if r.start.is_none() && r.end.is_none() {
                    return Err(self.err(
                        r.span(),
                        "unsupported-pattern",
                        "unbounded range pattern",
                    ));
                }
                let st = self.shallow(&t);
                if !(st.is_int() || matches!(st, Ty::Char | Ty::Var(_)) || st.is_float()) {
                    return Err(self.err(
                        r.span(),
                        "unsupported-pattern",
                        format!(
                            "range patterns need integers or `char`, found `{}`",
                            self.show(&st)
                        ),
                    ));
                }
                self.info(pat, &t, n, PatKind::Plain);
                Ok(())
            }
            Pat::Path(p) => {
                if p.qself.is_some() {
                    return Err(self.err(
                        p.span(),
                        "unsupported-qualified-path",
                        "qualified paths are not supported in patterns",
                    ));
                }
                let segs = crate::resolve::path_segs(&p.path);
                match self.pat_path_res(&segs, p.span(), false)? {
                    Some(pp) => self.path_pat(pat, pp, expected, mode),
                    None => Err(self.err(
                        p.span(),
                        "unresolved-path",
                        format!("cannot find `{}` in this scope", segs.join("::")),
                    )),
                }
            }
            Pat::TupleStruct(ts) => {
                let (t, n, mode) = self.peel(expected, mode);
                let segs = crate::resolve::path_segs(&ts.path);
                let Some(PatPath::Ctor(a, v, args)) =
                    self.pat_path_res(&segs, ts.path.span(), false)?
                else {
                    return Err(self.err(
                        ts.path.span(),
                        "not-a-variant",
                        format!(
                            "`{}` is not a tuple struct or tuple variant",
                            segs.join("::")
                        ),
                    ));
                };
                let vd = &self.p.adts[a].variants[v];
                if vd.ctor != Ctor::Tuple {
                    return Err(self.err(
                        ts.path.span(),
                        "not-a-variant",
                        format!(
                            "`{}` is not a tuple struct or tuple variant",
                            segs.join("::")
                        ),
                    ));
                }
                let at = Ty::Adt(a, args.clone());
                self.unify(&at, &t, ts.span())?;
                let ftys: Vec<Ty> = vd.fields.iter().map(|f| f.ty.subst(&args)).collect();
                let ftys: Vec<Ty> = ftys
                    .iter()
                    .map(|f| self.norm(f, ts.span()))
                    .collect::<DResult<_>>()?;
                self.info(pat, &at, n, PatKind::Variant(a, v));
                self.seq_pats(&ts.elems, &ftys, mode, uninit, names, ts.span())
            }
            Pat::Struct(s) => {
                let (t, n, mode) = self.peel(expected, mode);
                if s.qself.is_some() {
                    return Err(self.err(
                        s.span(),
                        "unsupported-qualified-path",
                        "qualified paths are not supported in patterns",
                    ));
                }
                let segs = crate::resolve::path_segs(&s.path);
                let Some(PatPath::Ctor(a, v, args)) =
                    self.pat_path_res(&segs, s.path.span(), false)?
                else {
                    return Err(self.err(
                        s.path.span(),
                        "not-a-struct",
                        format!("`{}` is not a struct or struct variant", segs.join("::")),
                    ));
                };
                let at = Ty::Adt(a, args.clone());
                self.unify(&at, &t, s.span())?;
                self.info(pat, &at, n, PatKind::Variant(a, v));
                let fields = self.p.adts[a].variants[v].fields.clone();
                for fp in &s.fields {
                    let name = match &fp.member {
                        syn::Member::Named(i) => i.to_string(),
                        syn::Member::Unnamed(i) => i.index.to_string(),
                    };
                    let Some(i) = fields.iter().position(|f| f.name == name) else {
                        return Err(self.err(
                            fp.member.span(),
                            "unknown-field",
                            format!("`{}` has no field `{name}`", segs.join("::")),
                        ));
                    };
                    self.body.fields.insert(key(fp), i);
                    let ft = self.norm(&fields[i].ty.subst(&args), fp.span())?;
                    self.pat(&fp.pat, &ft, mode, uninit, names)?;
                }
                if s.rest.is_none() {
                    if let Some(f) = fields.iter().find(|f| {
                        !s.fields.iter().any(|fp| match &fp.member {
                            syn::Member::Named(i) => *i == f.name,
                            syn::Member::Unnamed(i) => i.index.to_string() == f.name,
                        })
                    }) {
                        return Err(self.err(
                            s.span(),
                            "missing-field",
                            format!("pattern does not mention field `{}` (add `..`)", f.name),
                        ));
                    }
                }
                Ok(())
            }
            Pat::Tuple(tp) => {
                let (t, n, mode) = self.peel(expected, mode);
                let has_rest = tp.elems.iter().any(|p| matches!(p, Pat::Rest(_)));
                let tys = match self.shallow(&t) {
                    Ty::Tuple(ts) => ts,
                    Ty::Unit if tp.elems.is_empty() => Vec::new(),
                    Ty::Var(_) if !has_rest => {
                        let ts: Vec<Ty> =
                            tp.elems.iter().map(|_| self.fresh(VarKind::Any)).collect();
                        let tt = if ts.is_empty() {
                            Ty::Unit
                        } else {
                            Ty::Tuple(ts.clone())
                        };
                        self.unify(&tt, &t, tp.span())?;
                        ts
                    }
                    other => {
                        return Err(self.err(
                            tp.span(),
                            "type-mismatch",
                            format!(
                                "mismatched types: expected `{}`, found a tuple pattern",
                                self.show(&other)
                            ),
                        ))
                    }
                };
                self.info(pat, &t, n, PatKind::Plain);
                self.seq_pats(&tp.elems, &tys, mode, uninit, names, tp.span())
            }
            Pat::Slice(sp) => {
                let (t, n, mode) = self.peel(expected, mode);
                let st = self.shallow(&t);
                let (el, len) = match &st {
                    Ty::Array(el, len) => ((**el).clone(), Some(*len)),
                    Ty::Slice(el) => ((**el).clone(), None),
                    other => {
                        return Err(self.err(
                            sp.span(),
                            "type-mismatch",
                            format!("expected an array or slice, found `{}`", self.show(other)),
                        ))
                    }
                };
                let rest_at = sp.elems.iter().position(is_rest);
                let fixed = sp.elems.len() - rest_at.map_or(0, |_| 1);
                if let Some(len) = len {
                    let ok = match rest_at {
                        Some(_) => fixed as u32 <= len,
                        None => fixed as u32 == len,
                    };
                    if !ok {
                        return Err(self.err(
                            sp.span(),
                            "type-mismatch",
                            format!("pattern requires {fixed} elements but the array has {len}"),
                        ));
                    }
                }
                self.info(pat, &st, n, PatKind::Plain);
                for (i, e) in sp.elems.iter().enumerate() {
                    if Some(i) == rest_at {
                        if let Pat::Ident(pi) = e {
                            // `rest @ ..`: a sub-array or sub-slice.
                            let sub = match len {
                                Some(l) => Ty::Array(Box::new(el.clone()), l - fixed as u32),
                                None => Ty::Slice(Box::new(el.clone())),
                            };
                            let bmode = if pi.by_ref.is_some() {
                                BindMode::Ref(pi.mutability.is_some())
                            } else {
                                mode
                            };
                            if len.is_none() && bmode == BindMode::Value {
                                return Err(self.err(
                                    pi.span(),
                                    "unsupported-pattern",
                                    "a slice's rest is bound by reference",
                                ));
                            }
                            self.pat(e, &sub, mode, uninit, names)?;
                        } else {
                            self.info(e, &el, 0, PatKind::Plain);
                        }
                        continue;
                    }
                    self.pat(e, &el, mode, uninit, names)?;
                }
                Ok(())
            }
            Pat::Rest(r) => Err(self.err(
                r.span(),
                "unsupported-pattern",
                "`..` is only allowed in tuple, tuple-struct and slice patterns",
            )),
            Pat::Type(t) => Err(self.err(
                t.span(),
                "unsupported-pattern",
                "type ascription is only allowed in `let` and parameters",
            )),
            other => Err(self.err(
                other.span(),
                "unsupported-pattern",
                "this kind of pattern is not supported in TRaX-Rust",
            )),
        }
    }

    /// Tuple and tuple-struct elements with an optional `..`.
    fn seq_pats(
        &mut self,
        elems: &syn::punctuated::Punctuated<Pat, syn::Token![,]>,
        tys: &[Ty],
        mode: BindMode,
        uninit: bool,
        names: &mut HashMap<String, usize>,
        span: proc_macro2::Span,
    ) -> DResult<()> {
        let rest_at = elems.iter().position(is_rest);
        let fixed = elems.len() - rest_at.map_or(0, |_| 1);
        let ok = match rest_at {
            Some(_) => fixed <= tys.len(),
            None => fixed == tys.len(),
        };
        if !ok {
            return Err(self.err(
                span,
                "wrong-field-count",
                format!(
                    "this pattern has {fixed} fields, but the type has {}",
                    tys.len()
                ),
            ));
        }
        for (i, e) in elems.iter().enumerate() {
            let ti = match rest_at {
                Some(r) if i == r => {
                    self.info(e, &Ty::Unit, 0, PatKind::Plain);
                    continue;
                }
                Some(r) if i > r => tys.len() - (elems.len() - i),
                _ => i,
            };
            self.pat(e, &tys[ti], mode, uninit, names)?;
        }
        Ok(())
    }

    fn path_pat(&mut self, pat: &Pat, pp: PatPath, expected: &Ty, mode: BindMode) -> DResult<()> {
        let (t, n, _) = self.peel(expected, mode);
        match pp {
            PatPath::Ctor(a, v, args) => {
                if self.p.adts[a].variants[v].ctor != Ctor::Unit {
                    return Err(self.err(pat.span(), "not-a-variant", format!("`{}` is not a unit variant or unit struct (write `{0}(..)` or `{0} {{ .. }}`)", self.p.adts[a].variants[v].name)));
                }
                let at = Ty::Adt(a, args);
                self.unify(&at, &t, pat.span())?;
                self.info(pat, &at, n, PatKind::Variant(a, v));
            }
            PatPath::Const(ct, v) => {
                self.unify(&ct, &t, pat.span())?;
                self.info(pat, &t, n, PatKind::Const(v));
            }
        }
        Ok(())
    }

    /// A range pattern bound: a literal (possibly negative) or a constant path.
    fn pat_bound(&mut self, e: &Expr) -> DResult<Ty> {
        match e {
            Expr::Lit(l) => {
                let t = self.lit(&l.lit)?;
                self.body.tys.insert(key(e), t.clone());
                Ok(t)
            }
            Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => {
                let t = self.pat_bound(&u.expr)?;
                self.body.tys.insert(key(e), t.clone());
                Ok(t)
            }
            Expr::Path(p) => {
                let segs = crate::resolve::path_segs(&p.path);
                match self.pat_path_res(&segs, p.span(), false)? {
                    Some(PatPath::Const(t, v)) => {
                        self.body.pats.insert(
                            key(e),
                            PatInfo {
                                ty: t.clone(),
                                derefs: 0,
                                kind: PatKind::Const(v),
                            },
                        );
                        self.body.tys.insert(key(e), t.clone());
                        Ok(t)
                    }
                    _ => Err(self.err(
                        e.span(),
                        "unsupported-pattern",
                        "range bounds must be literals or constants",
                    )),
                }
            }
            other => Err(self.err(
                other.span(),
                "unsupported-pattern",
                "range bounds must be literals or constants",
            )),
        }
    }

    /// Resolves a path in a pattern. For a single identifier (`ident_only`), `None` means
    /// a fresh binding.
    pub(super) fn pat_path_res(
        &mut self,
        segs: &[String],
        span: proc_macro2::Span,
        ident_only: bool,
    ) -> DResult<Option<PatPath>> {
        let res = if !segs.is_empty() && segs[0] == "Self" {
            match (&self.self_ty.clone(), segs.len()) {
                (Some(Ty::Adt(a, args)), 1) => return Ok(Some(PatPath::Ctor(*a, 0, args.clone()))),
                (Some(Ty::Adt(a, args)), 2) => match self.p.adts[*a].variant(&segs[1]) {
                    Some(v) if self.p.adts[*a].is_enum => {
                        return Ok(Some(PatPath::Ctor(*a, v, args.clone())))
                    }
                    _ => {
                        let t = Ty::Adt(*a, args.clone());
                        return self.assoc_const_pat(&t, &segs[1], span).map(Some);
                    }
                },
                (Some(t), 2) => {
                    let t = t.clone();
                    return self.assoc_const_pat(&t, &segs[1], span).map(Some);
                }
                _ => {
                    return Err(self.err(span, "self-outside-impl", "`Self` outside an impl block"))
                }
            }
        } else if ident_only {
            match self.p.try_resolve(self.module, segs, Ns::Value) {
                Some(r) => r,
                None => return Ok(None),
            }
        } else {
            match self.p.try_resolve(self.module, segs, Ns::Value) {
                Some(r) => r,
                None => self
                    .p
                    .resolve_path_segs(self.module, self.file, segs, Ns::Type, span)?,
            }
        };
        match res {
            PathRes::Variant(a, v) => {
                let args: Vec<Ty> = (0..self.p.adts[a].generics.len()).map(|_| self.fresh(VarKind::Any)).collect();
                Ok(Some(PatPath::Ctor(a, v, args)))
            }
            PathRes::Adt(a) if !self.p.adts[a].is_enum => {
                let args: Vec<Ty> = (0..self.p.adts[a].generics.len()).map(|_| self.fresh(VarKind::Any)).collect();
                Ok(Some(PatPath::Ctor(a, 0, args)))
            }
            PathRes::Global(g) if self.p.globals[g].is_static.is_none() => {
                let gd = &self.p.globals[g];
                let Some(x) = gd.expr else {
                    return Err(self.err(span, "unsupported-pattern", "this constant has no value"));
                };
                let v = self.const_pat_value(&gd.ty.clone(), gd.module, gd.file, x, span)?;
                Ok(Some(PatPath::Const(gd.ty.clone(), v)))
            }
            PathRes::Global(_) if ident_only => Ok(None),
            PathRes::Fn(_) | PathRes::Global(_) | PathRes::Mod(_) if ident_only => Ok(None),
            PathRes::PrimAssoc(t @ crate::ty::Ty::Int(it), n) => {
                let v = match n.as_str() {
                    "MAX" => it.max(),
                    "MIN" => it.min(),
                    _ => return Err(self.err(span, "unsupported-pattern", format!("`{}::{n}` cannot be used in a pattern", it.name()))),
                };
                Ok(Some(PatPath::Const(t, v)))
            }
            PathRes::AdtAssoc(a, name) => {
                let args: Vec<Ty> = (0..self.p.adts[a].generics.len()).map(|_| self.fresh(VarKind::Any)).collect();
                self.assoc_const_pat(&Ty::Adt(a, args), &name, span).map(Some)
            }
            _ if ident_only => Ok(None),
            _ => Err(self.err(span, "unsupported-pattern", format!("`{}` cannot be used in a pattern (only constants, unit structs and enum variants)", segs.join("::")))),
        }
    }

    fn assoc_const_pat(&mut self, t: &Ty, name: &str, span: proc_macro2::Span) -> DResult<PatPath> {
        match self.assoc_const(t, name, span)? {
            Some((g, substs)) => {
                let gd = &self.p.globals[g];
                let ty = self.norm(&gd.ty.subst(&substs), span)?;
                let Some(x) = gd.expr else {
                    return Err(self.err(
                        span,
                        "unsupported-pattern",
                        "this constant has no value",
                    ));
                };
                let v = self.const_pat_value(&ty, gd.module, gd.file, x, span)?;
                Ok(PatPath::Const(ty, v))
            }
            None => Err(self.err(
                span,
                "unresolved-path",
                format!("no associated constant `{name}` on `{}`", self.show(t)),
            )),
        }
    }

    /// The integer value of a constant used as a pattern.
    fn const_pat_value(
        &self,
        ty: &Ty,
        module: crate::resolve::ModId,
        file: crate::diag::FileId,
        e: &Expr,
        span: proc_macro2::Span,
    ) -> DResult<i128> {
        match ty {
            Ty::Int(_) => self.p.eval_int(module, file, e, 0),
            Ty::Bool => match e {
                Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Bool(b),
                    ..
                }) => Ok(b.value as i128),
                _ => Err(self.err(
                    span,
                    "unsupported-pattern",
                    "only literal `bool` constants can be patterns",
                )),
            },
            Ty::Char => match e {
                Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Char(c),
                    ..
                }) => Ok(c.value() as i128),
                _ => Err(self.err(
                    span,
                    "unsupported-pattern",
                    "only literal `char` constants can be patterns",
                )),
            },
            other => Err(self.err(
                span,
                "unsupported-pattern",
                format!(
                    "constants of type `{}` cannot be patterns in TRaX-Rust",
                    self.p.ty_str(other)
                ),
            )),
        }
    }

    /// True if `pat` (already checked) matches every value of its type.
    pub fn irrefutable(&self, pat: &Pat) -> bool {
        let info = self.body.pats.get(&key(pat));
        match pat {
            Pat::Wild(_) | Pat::Rest(_) => true,
            Pat::Ident(pi) => {
                matches!(info.map(|i| &i.kind), Some(PatKind::Binding))
                    && pi.subpat.as_ref().is_none_or(|(_, s)| self.irrefutable(s))
                    || matches!(info.map(|i| &i.kind), Some(PatKind::Variant(a, _)) if self.single_variant(*a))
            }
            Pat::Paren(p) => self.irrefutable(&p.pat),
            Pat::Reference(r) => self.irrefutable(&r.pat),
            Pat::Tuple(t) => t.elems.iter().all(|e| self.irrefutable(e)),
            Pat::TupleStruct(ts) => {
                matches!(info.map(|i| &i.kind), Some(PatKind::Variant(a, _)) if self.single_variant(*a))
                    && ts.elems.iter().all(|e| self.irrefutable(e))
            }
            Pat::Struct(s) => {
                matches!(info.map(|i| &i.kind), Some(PatKind::Variant(a, _)) if self.single_variant(*a))
                    && s.fields.iter().all(|f| self.irrefutable(&f.pat))
            }
            Pat::Path(_) => {
                matches!(info.map(|i| &i.kind), Some(PatKind::Variant(a, _)) if self.single_variant(*a))
            }
            Pat::Slice(s) => {
                matches!(info.map(|i| &i.ty), Some(Ty::Array(..)))
                    && s.elems.iter().all(|e| self.irrefutable(e))
            }
            Pat::Or(o) => o.cases.iter().any(|c| self.irrefutable(c)),
            _ => false,
        }
    }

    fn single_variant(&self, a: AdtId) -> bool {
        self.p.adts[a].variants.len() == 1
    }
}

fn is_rest(p: &Pat) -> bool {
    match p {
        Pat::Rest(_) => true,
        Pat::Ident(pi) => matches!(pi.subpat.as_ref().map(|(_, s)| &**s), Some(Pat::Rest(_))),
        _ => false,
    }
}
