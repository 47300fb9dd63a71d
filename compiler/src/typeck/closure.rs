//! Closures: closure expressions (parameters typed from annotations, from the `Fn(A) ->
//! R` bound of the generic function they are passed to, or by inference; captures are the
//! enclosing body's locals the closure uses) and calls of closures. Each closure
//! expression of a function instance has its own type ([`ClosureTy`]); generic functions
//! taking `F: Fn(..)` are instantiated per closure type, so every call is static.

use super::infer::{ClosureFrame, Cx, VarKind};
use super::{key, Callee, ClosureInfo};
use crate::diag::DResult;
use crate::resolve::FnId;
use crate::span::Spanned;
use crate::ty::{ClosureTy, TraitKind, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::{Expr, Pat};

impl<'p, 'a> Cx<'p, 'a> {
    /// Checks a closure expression; `expected` is the type of the parameter it is passed
    /// to, if any (a variable with a signature hint gives the parameters their types).
    pub(super) fn closure(
        &mut self,
        e: &Expr,
        c: &syn::ExprClosure,
        expected: Option<&Ty>,
    ) -> DResult<Ty> {
        let Some((def_fn, def_substs)) = self.cur_fn.clone() else {
            return Err(self.err(
                c.span(),
                "unsupported-closure",
                "closures are not supported in const and static initializers",
            ));
        };
        if self.in_const {
            return Err(self.err(
                c.span(),
                "unsupported-closure",
                "closures in `const fn` are not supported in TRaX-Rust",
            ));
        }
        if let Some(l) = &c.lifetimes {
            return Err(self.err(
                l.span(),
                "unsupported-closure",
                "higher-ranked closures (`for<'a> |..|`) are not supported in TRaX-Rust",
            ));
        }
        if c.constness.is_some() || c.asyncness.is_some() {
            return Err(self.err(
                c.span(),
                "unsupported-closure",
                "const and async closures are not supported in TRaX-Rust",
            ));
        }
        let hint = expected.and_then(|t| match self.shallow(t) {
            Ty::Var(v) => self.hints.get(&v).cloned(),
            _ => None,
        });
        let locals_base = self.body.locals.len();
        let mut pats = Vec::new();
        let mut params = Vec::new();
        for input in &c.inputs {
            let (pat, t) = match input {
                Pat::Type(pt) => (&*pt.pat, self.resolve_ty(&pt.ty)?),
                other => (other, self.fresh(VarKind::Any)),
            };
            pats.push(pat);
            params.push(t);
        }
        let ret = match &c.output {
            syn::ReturnType::Default => self.fresh(VarKind::Any),
            syn::ReturnType::Type(_, t) => self.resolve_ty(t)?,
        };
        if let Some((hp, hr)) = &hint {
            if hp.len() != params.len() {
                return Err(self.err(
                    c.inputs_begin.span(),
                    "closure-arity",
                    format!(
                        "expected a closure that takes {} argument(s), but this closure takes {}",
                        hp.len(),
                        params.len()
                    ),
                ));
            }
            for ((t, h), pat) in params.iter().zip(hp).zip(&pats) {
                self.unify(t, h, pat.span())?;
            }
            self.unify(&ret, hr, c.body.span())?;
        }
        self.scopes.push(HashMap::new());
        let saved_ret = std::mem::replace(&mut self.ret, ret.clone());
        let saved_loops = std::mem::take(&mut self.loops);
        self.closure_frames.push(ClosureFrame {
            locals_base,
            captures: Vec::new(),
        });
        let r = self.closure_body(c, &pats, &params, &ret);
        let frame = self.closure_frames.pop().expect("closure frame");
        self.loops = saved_loops;
        self.ret = saved_ret;
        self.scopes.pop();
        r?;
        self.body.closures.insert(
            key(e),
            ClosureInfo {
                captures: frame.captures,
                by_move: c.capture.is_some(),
            },
        );
        Ok(Ty::Closure(Box::new(ClosureTy {
            def_fn,
            def_substs,
            key: key(e),
            params,
            ret,
        })))
    }

    fn closure_body(
        &mut self,
        c: &syn::ExprClosure,
        pats: &[&Pat],
        params: &[Ty],
        ret: &Ty,
    ) -> DResult<()> {
        for (pat, t) in pats.iter().zip(params) {
            self.bind_param(pat, t)?;
        }
        let t = self.expr(&c.body)?;
        self.coerce(&c.body, &t, ret, c.body.span())
    }

    /// A call whose callee is an expression (a local or field holding a closure).
    pub(super) fn closure_call(&mut self, e: &Expr, c: &syn::ExprCall) -> DResult<Ty> {
        let t = self.expr(&c.func)?;
        let (inner, derefs) = self.autoderef(&t);
        let args: Vec<&Expr> = c.args.iter().collect();
        match inner {
            Ty::Closure(ct) => {
                self.args(&args, &ct.params, c.span(), "this closure")?;
                let ret = ct.ret.clone();
                self.body
                    .callees
                    .insert(key(e), Callee::Closure { ty: *ct, derefs });
                Ok(ret)
            }
            Ty::Var(v) if self.vars[v as usize].0 == VarKind::Any => Err(self.err(
                c.func.span(),
                "type-annotation-needed",
                "type annotations needed: the type of the called value is not known yet",
            )),
            other => Err(self.err(
                c.func.span(),
                "not-a-function",
                format!(
                    "expected function, found `{}` (only named functions and closures can be called; no function pointers)",
                    self.show(&other)
                ),
            )),
        }
    }

    /// Registers the closure signatures `f`'s `F: Fn(A) -> R` bounds ask of the variables
    /// standing for its generic arguments.
    pub(super) fn fn_bound_hints(&mut self, f: FnId, substs: &[Ty], span: Span) -> DResult<()> {
        let p = self.p;
        for b in &p.fns[f].generics.bounds {
            let TraitKind::Lang(l) = b.tr.kind else {
                continue;
            };
            if !l.is_fn() {
                continue;
            }
            let Ty::Var(v) = self.shallow(&b.ty.subst(substs)) else {
                continue;
            };
            let ins = match b.tr.args.first() {
                Some(a) => self.norm(&a.subst(substs), span)?,
                None => Ty::Unit,
            };
            let ins = match ins {
                Ty::Tuple(xs) => xs,
                Ty::Unit => Vec::new(),
                other => vec![other],
            };
            let out = match b.tr.bindings.iter().find(|(n, _)| n == "Output") {
                Some((_, t)) => self.norm(&t.subst(substs), span)?,
                None => Ty::Unit,
            };
            self.hints.insert(v, (ins, out));
        }
        Ok(())
    }

    /// After an argument was checked against parameter type `param`: if the parameter
    /// stands for a generic `F: Fn(A) -> R`, the argument must be a closure of that
    /// signature.
    pub(super) fn check_fn_hint(&mut self, param: &Ty, span: Span) -> DResult<()> {
        let v = match param {
            Ty::Var(v) => *v,
            Ty::Ref(_, inner) => match **inner {
                Ty::Var(v) => v,
                _ => return Ok(()),
            },
            _ => return Ok(()),
        };
        let Some((hp, hr)) = self.hints.get(&v).cloned() else {
            return Ok(());
        };
        match self.shallow(&Ty::Var(v)) {
            Ty::Closure(ct) => {
                let found = Ty::Closure(ct.clone());
                let ok = ct.params.len() == hp.len()
                    && ct
                        .params
                        .iter()
                        .zip(&hp)
                        .all(|(a, b)| self.try_unify(a, b))
                    && self.try_unify(&ct.ret, &hr);
                if !ok {
                    let want = Ty::Closure(Box::new(ClosureTy {
                        params: hp,
                        ret: hr,
                        ..(*ct).clone()
                    }));
                    return Err(self.mismatch(span, &want, &found));
                }
                Ok(())
            }
            Ty::Var(_) => Ok(()),
            other => Err(self.err(
                span,
                "expected-closure",
                format!(
                    "expected a closure, found `{}` (function pointers are not supported in TRaX-Rust)",
                    self.show(&other)
                ),
            )),
        }
    }
}
