//! Calls (user function instances, builtins, constructors), method receivers, operator
//! impls, and the compiler-derived `clone`, `==` and `default`.

use super::{internal, LResult, Lowerer, V};
use crate::ops::BinOp;
use crate::resolve::FnId;
use crate::span::Spanned;
use crate::ty::{LangTrait, TraitKind, Ty};
use crate::typeck::{key, Callee, OpCall, RecvAdj};
use inkwell::values::{BasicValueEnum, IntValue, PointerValue};
use inkwell::IntPredicate;
use syn::Expr;

impl<'ctx> Lowerer<'ctx, '_, '_> {
    /// The type of `r` after `derefs` dereferences.
    fn deref_ty(&self, r: &Expr, derefs: u32) -> Ty {
        let mut t = self.ty_of(r);
        for _ in 0..derefs {
            if let Ty::Ref(_, inner) = t {
                t = *inner;
            }
        }
        t
    }

    /// The receiver argument of a method call after its adjustment.
    fn recv_value(&mut self, r: &Expr, adj: RecvAdj) -> LResult<(BasicValueEnum<'ctx>, Ty)> {
        let t = self.deref_ty(r, adj.derefs);
        match adj.autoref {
            Some(m) => {
                if let Ty::Slice(_) = t {
                    // A sub-slice `a[i..j]` receiver, or the fat reference one
                    // dereference short.
                    if adj.derefs == 0 {
                        let v = self
                            .slice_ref(r)?
                            .ok_or_else(|| internal("unsized receiver"))?;
                        return Ok((v, t));
                    }
                    let v = self.deref_value(r, adj.derefs - 1)?;
                    return Ok((v, t));
                }
                let p = self.deref_base(r, adj.derefs)?;
                Ok((p.into(), Ty::Ref(m, Box::new(t))))
            }
            None => Ok((self.deref_value(r, adj.derefs)?, t)),
        }
    }

    fn arg_values(&mut self, args: &[&Expr]) -> LResult<(Vec<BasicValueEnum<'ctx>>, Vec<Ty>)> {
        let mut vals = Vec::new();
        let mut tys = Vec::new();
        for a in args {
            let t = self.ty_of(a);
            let v = self.expr(a)?;
            vals.push(self.val(v, &t));
            tys.push(t);
        }
        Ok((vals, tys))
    }

    pub(super) fn call(
        &mut self,
        e: &Expr,
        recv: Option<&Expr>,
        args: &[&Expr],
        ty: &Ty,
    ) -> LResult<V<'ctx>> {
        let callee = self
            .body
            .callees
            .get(&key(e))
            .cloned()
            .ok_or_else(|| internal("unresolved call"))?;
        match callee {
            Callee::Fn {
                func,
                substs,
                recv: adj,
            } => {
                let mut vals = Vec::new();
                if let Some(r) = recv {
                    vals.push(self.recv_value(r, adj)?.0);
                }
                vals.extend(self.arg_values(args)?.0);
                self.set_loc(e.span());
                self.call_fn(func, &substs, vals, ty)
            }
            Callee::Builtin { b, recv: adj } => {
                let mut vals = Vec::new();
                let mut tys = Vec::new();
                if let Some(r) = recv {
                    let (v, t) = self.recv_value(r, adj)?;
                    // Sequence builtins see the array or slice type itself.
                    let t = match (&t, adj.autoref) {
                        (Ty::Ref(_, inner), Some(_)) => (**inner).clone(),
                        _ => t,
                    };
                    vals.push(v);
                    tys.push(t);
                }
                let (av, at) = self.arg_values(args)?;
                vals.extend(av);
                tys.extend(at);
                self.set_loc(e.span());
                self.builtin(b, &vals, &tys, ty)
            }
            Callee::Ctor { variant, .. } => {
                let (vals, _) = self.arg_values(args)?;
                let vals: Vec<Option<BasicValueEnum>> = vals.into_iter().map(Some).collect();
                self.set_loc(e.span());
                Ok(Some(self.build_adt(ty, variant, &vals)?))
            }
            Callee::Derived {
                tr,
                method,
                ty: st,
                recv: adj,
            } => {
                let mut vals = Vec::new();
                if let Some(r) = recv {
                    vals.push(self.recv_value(r, adj)?.0);
                }
                vals.extend(self.arg_values(args)?.0);
                self.set_loc(e.span());
                self.derived(tr, method, &st, &vals)
            }
            Callee::Closure { .. } => Err(internal("closure call reached the call lowering")),
        }
    }

    /// Calls a user function instance.
    pub(super) fn call_fn(
        &mut self,
        f: FnId,
        substs: &[Ty],
        args: Vec<BasicValueEnum<'ctx>>,
        ty: &Ty,
    ) -> LResult<V<'ctx>> {
        let fv = self.declare_fn(f, substs);
        let args: Vec<_> = args.into_iter().map(Into::into).collect();
        let cs = self.b.build_call(fv, &args, "")?;
        if matches!(ty, Ty::Never) {
            self.b.build_unreachable()?;
            return Ok(None);
        }
        Ok(cs.try_as_basic_value().basic())
    }

    /// A derived method on `st`: `clone(&self)`, `eq(&self, &other)`, `ne`, `default()`.
    fn derived(
        &mut self,
        tr: LangTrait,
        method: &str,
        st: &Ty,
        vals: &[BasicValueEnum<'ctx>],
    ) -> LResult<V<'ctx>> {
        match (tr, method) {
            (LangTrait::Clone, _) => {
                if st.is_zst() {
                    return Ok(None);
                }
                Ok(Some(self.b.build_load(vals[0].into_pointer_value(), "")?))
            }
            (LangTrait::PartialEq, m) => {
                let r = self.derived_eq(
                    vals[0].into_pointer_value(),
                    vals[1].into_pointer_value(),
                    st,
                )?;
                let r = if m == "ne" {
                    self.b.build_not(r, "")?
                } else {
                    r
                };
                Ok(Some(r.into()))
            }
            (LangTrait::Default, _) => self.default_value(st),
            _ => Err(internal(format!("derived {}::{method}", tr.name()))),
        }
    }

    /// The user impl of `PartialEq` (or `Default`) for `t`, if any.
    fn user_impl(&self, tr: LangTrait, t: &Ty, method: &str) -> Option<(FnId, Vec<Ty>)> {
        for im in &self.p.impls {
            let Some(itr) = &im.trait_ else { continue };
            if itr.kind != TraitKind::Lang(tr) {
                continue;
            }
            let mut substs = vec![None; im.generics.len()];
            if !self.p.match_ty(&im.self_ty, t, &mut substs) {
                continue;
            }
            if let Some(rhs) = itr.args.first() {
                if !self.p.match_ty(rhs, t, &mut substs) {
                    continue;
                }
            }
            let f = *im.fns.get(method)?;
            let substs: Vec<Ty> = substs.into_iter().map(|s| s.unwrap_or(Ty::Unit)).collect();
            return Some((f, substs));
        }
        None
    }

    /// Structural `==` of the values at `a` and `b` (derived `PartialEq`; fields with a
    /// user impl call it).
    pub(super) fn derived_eq(
        &mut self,
        a: PointerValue<'ctx>,
        b: PointerValue<'ctx>,
        t: &Ty,
    ) -> LResult<IntValue<'ctx>> {
        let tru = self.ctx.bool_type().const_int(1, false);
        if t.is_zst() {
            return Ok(tru);
        }
        if let Some((f, substs)) = self.user_impl(LangTrait::PartialEq, t, "eq") {
            let r = self.call_fn(f, &substs, vec![a.into(), b.into()], &Ty::Bool)?;
            return Ok(self.val(r, &Ty::Bool).into_int_value());
        }
        match t {
            Ty::Int(_) | Ty::Bool | Ty::Char | Ty::Float(_) => {
                let x = self.b.build_load(a, "")?;
                let y = self.b.build_load(b, "")?;
                self.values_eq(x, y, t)
            }
            Ty::Ptr(..) => {
                let i32t = self.ctx.i32_type();
                let x = self.b.build_load(a, "")?.into_pointer_value();
                let y = self.b.build_load(b, "")?.into_pointer_value();
                let x = self.b.build_ptr_to_int(x, i32t, "")?;
                let y = self.b.build_ptr_to_int(y, i32t, "")?;
                Ok(self.b.build_int_compare(IntPredicate::EQ, x, y, "")?)
            }
            Ty::Ref(_, inner) => {
                if matches!(**inner, Ty::Slice(_)) {
                    return Err(internal("slice equality"));
                }
                let x = self.b.build_load(a, "")?.into_pointer_value();
                let y = self.b.build_load(b, "")?.into_pointer_value();
                self.derived_eq(x, y, inner)
            }
            Ty::Tuple(ts) => {
                let mut acc = tru;
                for (i, ft) in ts.iter().enumerate() {
                    let fa = self.b.build_struct_gep(a, i as u32, "")?;
                    let fb = self.b.build_struct_gep(b, i as u32, "")?;
                    let c = self.derived_eq(fa, fb, ft)?;
                    acc = self.b.build_and(acc, c, "")?;
                }
                Ok(acc)
            }
            Ty::Array(el, n) => {
                let i32t = self.ctx.i32_type();
                let mut acc = tru;
                for i in 0..*n {
                    let idx = [i32t.const_zero(), i32t.const_int(i as u64, false)];
                    // SAFETY: `i < n`.
                    let (fa, fb) = unsafe {
                        (
                            self.b.build_in_bounds_gep(a, &idx, "")?,
                            self.b.build_in_bounds_gep(b, &idx, "")?,
                        )
                    };
                    let c = self.derived_eq(fa, fb, el)?;
                    acc = self.b.build_and(acc, c, "")?;
                }
                Ok(acc)
            }
            Ty::Adt(adt, _) => {
                let def = &self.p.adts[*adt];
                if !def.is_enum {
                    let ftys = self.field_tys(t, 0);
                    let mut acc = tru;
                    for (i, ft) in ftys.iter().enumerate() {
                        let fa = self.field_ptr(a, t, 0, i)?;
                        let fb = self.field_ptr(b, t, 0, i)?;
                        let c = self.derived_eq(fa, fb, ft)?;
                        acc = self.b.build_and(acc, c, "")?;
                    }
                    return Ok(acc);
                }
                let adt = *adt;
                let ta = self.tag_ptr(a, t)?;
                let tb = self.tag_ptr(b, t)?;
                let xa = self.b.build_load(ta, "")?.into_int_value();
                let xb = self.b.build_load(tb, "")?.into_int_value();
                let same = self.b.build_int_compare(IntPredicate::EQ, xa, xb, "")?;
                if def.is_fieldless_enum() {
                    return Ok(same);
                }
                // Same variant: compare that variant's fields.
                let slot = self.alloca(&Ty::Bool, "eq")?;
                self.b.build_store(slot, same)?;
                let end = self.new_block("eq.end");
                let cmp = self.new_block("eq.fields");
                self.b.build_conditional_branch(same, cmp, end)?;
                self.b.position_at_end(cmp);
                let nv = self.p.adts[adt].variants.len();
                for v in 0..nv {
                    let ftys = self.field_tys(t, v);
                    if ftys.is_empty() {
                        continue;
                    }
                    let next = self.new_block("eq.next");
                    let this = self.new_block("eq.variant");
                    let want = self.tag_val(adt, v);
                    let is_v = self.b.build_int_compare(IntPredicate::EQ, xa, want, "")?;
                    self.b.build_conditional_branch(is_v, this, next)?;
                    self.b.position_at_end(this);
                    let mut acc = tru;
                    for (i, ft) in ftys.iter().enumerate() {
                        let fa = self.field_ptr(a, t, v, i)?;
                        let fb = self.field_ptr(b, t, v, i)?;
                        let c = self.derived_eq(fa, fb, ft)?;
                        acc = self.b.build_and(acc, c, "")?;
                    }
                    self.b.build_store(slot, acc)?;
                    self.b.build_unconditional_branch(end)?;
                    self.b.position_at_end(next);
                }
                self.b.build_unconditional_branch(end)?;
                self.b.position_at_end(end);
                Ok(self.b.build_load(slot, "")?.into_int_value())
            }
            other => Err(internal(format!("equality of {}", self.p.ty_str(other)))),
        }
    }

    /// `Default::default()` derived or builtin for `t`.
    pub(super) fn default_value(&mut self, t: &Ty) -> LResult<V<'ctx>> {
        if t.is_zst() {
            return Ok(None);
        }
        if let Some((f, substs)) = self.user_impl(LangTrait::Default, t, "default") {
            return self.call_fn(f, &substs, Vec::new(), t);
        }
        let lt = self.llty(t);
        Ok(Some(match t {
            Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Simd(_) => super::zero(lt),
            Ty::Tuple(ts) => {
                let mut agg = lt.into_struct_type().get_undef();
                for (i, ft) in ts.iter().enumerate() {
                    let v = self.default_value(ft)?;
                    let v = self.val(v, ft);
                    agg = self
                        .b
                        .build_insert_value(agg, v, i as u32, "")?
                        .into_struct_value();
                }
                agg.into()
            }
            Ty::Array(el, n) => {
                let v = self.default_value(el)?;
                let v = self.val(v, el);
                if super::is_const(v) {
                    let vals = vec![v; *n as usize];
                    super::expr::const_array(self.llty(el), &vals)
                } else {
                    let slot = self.alloca(t, "default")?;
                    self.fill_loop(slot, *n, v)?;
                    self.b.build_load(slot, "")?
                }
            }
            Ty::Adt(a, _) => {
                let def = &self.p.adts[*a];
                if def.is_enum {
                    let v = def
                        .default_variant
                        .ok_or_else(|| internal("enum default"))?;
                    self.build_adt(t, v, &[])?
                } else {
                    let ftys = self.field_tys(t, 0);
                    let mut vals = Vec::new();
                    for ft in &ftys {
                        let v = self.default_value(ft)?;
                        vals.push(Some(self.val(v, ft)));
                    }
                    self.build_adt(t, 0, &vals)?
                }
            }
            other => return Err(internal(format!("default of {}", self.p.ty_str(other)))),
        }))
    }

    /// An overloaded operator.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn op_call(
        &mut self,
        e: &Expr,
        o: &OpCall,
        left: &Expr,
        right: &Expr,
        op: BinOp,
        assign: bool,
        ty: &Ty,
    ) -> LResult<V<'ctx>> {
        match o {
            OpCall::DerivedEq { ty: t, negate } => {
                let a = self.place_or_temp(left)?;
                let b = self.place_or_temp(right)?;
                self.set_loc(e.span());
                let r = self.derived_eq(a, b, t)?;
                let r = if *negate { self.b.build_not(r, "")? } else { r };
                Ok(Some(r.into()))
            }
            OpCall::Fn {
                func,
                substs,
                by_ref,
                via_partial_cmp,
                negate,
            } => {
                if assign {
                    let rt = self.ty_of(right);
                    let r = self.expr(right)?;
                    let r = self.val(r, &rt);
                    let p = self.place(left)?;
                    self.set_loc(e.span());
                    return self.call_fn(*func, substs, vec![p.into(), r], &Ty::Unit);
                }
                let (l, r) = if *by_ref {
                    let a = self.place_or_temp(left)?;
                    let b = self.place_or_temp(right)?;
                    (a.into(), b.into())
                } else {
                    let lt = self.ty_of(left);
                    let rt = self.ty_of(right);
                    let l = self.expr(left)?;
                    let l = self.val(l, &lt);
                    let r = self.expr(right)?;
                    let r = self.val(r, &rt);
                    (l, r)
                };
                self.set_loc(e.span());
                let fd = &self.p.fns[*func];
                let ret = self.p.normalize(&fd.ret.subst(substs)).unwrap_or(Ty::Unit);
                let v = self.call_fn(*func, substs, vec![l, r], &ret)?;
                if *via_partial_cmp {
                    let c = self.ordering_test(v, &ret, op)?;
                    return Ok(Some(c.into()));
                }
                if *negate {
                    let v = self.val(v, &Ty::Bool).into_int_value();
                    return Ok(Some(self.b.build_not(v, "")?.into()));
                }
                let _ = ty;
                Ok(v)
            }
        }
    }

    /// `partial_cmp`'s `Option<Ordering>` tested for `<`, `<=`, `>` or `>=`.
    fn ordering_test(&mut self, v: V<'ctx>, ret: &Ty, op: BinOp) -> LResult<IntValue<'ctx>> {
        let v = self.val(v, ret);
        let slot = self.alloca(ret, "cmp")?;
        self.b.build_store(slot, v)?;
        let Ty::Adt(opt, args) = ret else {
            return Err(internal("partial_cmp result"));
        };
        let some = self.p.adts[*opt]
            .variant("Some")
            .ok_or_else(|| internal("Some"))?;
        let tp = self.tag_ptr(slot, ret)?;
        let tag = self.b.build_load(tp, "")?.into_int_value();
        let is_some =
            self.b
                .build_int_compare(IntPredicate::EQ, tag, self.tag_val(*opt, some), "")?;
        let ord_t = args[0].clone();
        let Ty::Adt(ord, _) = &ord_t else {
            return Err(internal("Ordering"));
        };
        let fp = self.field_ptr(slot, ret, some, 0)?;
        let o = self.b.build_load(fp, "")?.into_int_value();
        let var = |l: &Self, n: &str| -> LResult<IntValue<'ctx>> {
            let v = l.p.adts[*ord]
                .variant(n)
                .ok_or_else(|| internal("Ordering variant"))?;
            Ok(l.tag_val(*ord, v))
        };
        let (less, greater) = (var(self, "Less")?, var(self, "Greater")?);
        let c = match op {
            BinOp::Lt => self.b.build_int_compare(IntPredicate::EQ, o, less, "")?,
            BinOp::Gt => self.b.build_int_compare(IntPredicate::EQ, o, greater, "")?,
            BinOp::Le => self.b.build_int_compare(IntPredicate::NE, o, greater, "")?,
            _ => self.b.build_int_compare(IntPredicate::NE, o, less, "")?,
        };
        Ok(self.b.build_and(is_some, c, "")?)
    }
}
