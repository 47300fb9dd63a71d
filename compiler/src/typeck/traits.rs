//! Method and trait resolution: inherent impls, trait impls and defaults (with their
//! generic arguments and bounds), associated functions and consts, operator, `Index` and
//! `PartialEq`/`PartialOrd` impls, and the compiler-derived `clone`/`eq`/`default`.

use super::infer::{Cx, VarKind};
use crate::builtins::{self, Method};
use crate::diag::DResult;
use crate::resolve::{FnId, GlobalId, ImplId, Recv};
use crate::ty::{LangTrait, TraitKind, Ty};
use proc_macro2::Span;
use std::collections::HashMap;

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
    pub(super) fn method_pick(&mut self, t: &Ty, name: &str, span: Span) -> DResult<Option<Pick>> {
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
    pub(super) fn inherent_fn(
        &mut self,
        t: &Ty,
        name: &str,
        method: bool,
    ) -> DResult<Option<Pick>> {
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
    pub(super) fn impl_substs(&mut self, _i: ImplId, substs: Vec<Option<Ty>>) -> Vec<Ty> {
        substs
            .into_iter()
            .map(|s| s.unwrap_or_else(|| self.fresh(VarKind::Any)))
            .collect()
    }

    /// A method of a trait implemented for `t` (a method of the impl, or the trait's
    /// default).
    pub(super) fn trait_fn(
        &mut self,
        t: &Ty,
        name: &str,
        method: bool,
        span: Span,
    ) -> DResult<Option<Pick>> {
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
    pub(super) fn impl_bounds_hold(&self, i: ImplId, t: &Ty) -> bool {
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
                LangTrait::Sized => true,
                LangTrait::Debug => !matches!(t, Ty::Closure(_)),
                LangTrait::Fn | LangTrait::FnMut | LangTrait::FnOnce => {
                    matches!(t, Ty::Closure(_))
                }
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

    pub(super) fn has_impl(&self, t: &Ty, k: TraitKind) -> bool {
        self.p.impls.iter().enumerate().any(|(i, im)| {
            im.trait_.as_ref().is_some_and(|tr| tr.kind == k) && self.impl_bounds_hold(i, t)
        })
    }

    /// `clone`/`eq`/`ne`/`default` the compiler provides for a type.
    pub(super) fn derived_fn(&self, t: &Ty, name: &str, method: bool) -> Option<Pick> {
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

    pub(super) fn derives(&self, t: &Ty, tr: LangTrait) -> bool {
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
    pub(super) fn assoc_fn(&mut self, t: &Ty, name: &str, span: Span) -> DResult<Option<Pick>> {
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
    pub(super) fn trait_item_fn(
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
    pub(super) fn trait_const(
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
}

/// An operator impl: method, generic arguments, result type and the impl's methods.
pub(super) type OpImpl = (FnId, Vec<Ty>, Ty, HashMap<String, FnId>);
