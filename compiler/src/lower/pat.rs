//! Patterns against places: tests branch to a failure block, bindings store into their
//! locals' slots. Used by `match`, `if let`, `while let`, `let` (with `else`),
//! `matches!`, `for` loop variables and destructuring parameters.

use super::{internal, LResult, Lowerer, V};
use crate::span::Spanned;
use crate::ty::Ty;
use crate::typeck::{key, BindMode, PatInfo, PatKind};
use inkwell::basic_block::BasicBlock;
use inkwell::types::BasicType;
use inkwell::values::{BasicValueEnum, IntValue, PointerValue};
use inkwell::{AddressSpace, FloatPredicate, IntPredicate};
use syn::{Expr, Pat};
use trax_runtime::isa::AbortKind;

impl<'ctx> Lowerer<'ctx, '_, '_> {
    fn pat_info(&self, pat: &Pat) -> Option<PatInfo> {
        self.body.pats.get(&key(pat)).cloned()
    }

    /// Branches to `fail` unless `c`; continues in a fresh block.
    fn test(&mut self, c: IntValue<'ctx>, fail: BasicBlock<'ctx>) -> LResult<()> {
        if c.get_zero_extended_constant() == Some(1) {
            return Ok(());
        }
        let ok = self.new_block("pat.ok");
        self.b.build_conditional_branch(c, ok, fail)?;
        self.b.position_at_end(ok);
        Ok(())
    }

    /// Matches the value at `place` (of type `ty`) against `pat`: branches to `fail` on
    /// a mismatch, makes the bindings and continues otherwise.
    pub(super) fn match_pat(
        &mut self,
        pat: &Pat,
        place: PointerValue<'ctx>,
        ty: &Ty,
        fail: BasicBlock<'ctx>,
    ) -> LResult<()> {
        let info = self.pat_info(pat);
        let (mut place, mut ty) = (place, ty.clone());
        if let Some(i) = &info {
            for _ in 0..i.derefs {
                // A slice reference stays one level up: its place holds `{ptr, len}`.
                if matches!(&ty, Ty::Ref(_, inner) if matches!(**inner, Ty::Slice(_))) {
                    break;
                }
                place = self.b.build_load(place, "")?.into_pointer_value();
                if let Ty::Ref(_, inner) = ty {
                    ty = *inner;
                }
            }
        }
        match pat {
            Pat::Wild(_) | Pat::Rest(_) => Ok(()),
            Pat::Paren(p) => self.match_pat(&p.pat, place, &ty, fail),
            Pat::Ident(pi) => match info.map(|i| i.kind) {
                Some(PatKind::Variant(_, v)) => self.variant_test(place, &ty, v, fail),
                Some(PatKind::Const(c)) => self.const_test(place, &ty, c, fail),
                _ => {
                    if let Some((_, sub)) = &pi.subpat {
                        if !matches!(**sub, Pat::Rest(_)) {
                            self.match_pat(sub, place, &ty, fail)?;
                        }
                    }
                    self.bind(pi, place, &ty)
                }
            },
            Pat::Reference(r) => {
                if matches!(&ty, Ty::Ref(_, inner) if matches!(**inner, Ty::Slice(_))) {
                    return self.match_pat(&r.pat, place, &ty, fail);
                }
                let inner = self.b.build_load(place, "")?.into_pointer_value();
                let it = match ty {
                    Ty::Ref(_, t) => *t,
                    other => other,
                };
                self.match_pat(&r.pat, inner, &it, fail)
            }
            Pat::Or(o) => {
                let ok = self.new_block("or.ok");
                let n = o.cases.len();
                for (i, c) in o.cases.iter().enumerate() {
                    let next = if i + 1 == n {
                        fail
                    } else {
                        self.new_block("or.next")
                    };
                    self.match_pat(c, place, &ty, next)?;
                    self.br(ok)?;
                    if i + 1 < n {
                        self.b.position_at_end(next);
                    }
                }
                self.b.position_at_end(ok);
                Ok(())
            }
            Pat::Lit(l) => {
                let lt = self
                    .body
                    .tys
                    .get(&key(l))
                    .cloned()
                    .unwrap_or_else(|| ty.clone());
                let v = self.b.build_load(place, "")?;
                let c = self.lit(&l.lit, &lt)?;
                let eq = self.values_eq(v, c, &lt)?;
                self.test(eq, fail)
            }
            Pat::Range(r) => {
                let v = self.b.build_load(place, "")?;
                if let Some(s) = &r.start {
                    let c = self.bound_value(s, &ty)?;
                    let ge = self.ordered(v, c, &ty, true, false)?;
                    self.test(ge, fail)?;
                }
                if let Some(e) = &r.end {
                    let c = self.bound_value(e, &ty)?;
                    let closed = matches!(r.limits, syn::RangeLimits::Closed(_));
                    let le = self.ordered(v, c, &ty, false, closed)?;
                    self.test(le, fail)?;
                }
                Ok(())
            }
            Pat::Path(_) => match info.map(|i| i.kind) {
                Some(PatKind::Variant(_, v)) => self.variant_test(place, &ty, v, fail),
                Some(PatKind::Const(c)) => self.const_test(place, &ty, c, fail),
                _ => Err(internal("unresolved path pattern")),
            },
            Pat::TupleStruct(ts) => {
                let Some(PatKind::Variant(_, v)) = info.map(|i| i.kind) else {
                    return Err(internal("unresolved tuple-struct pattern"));
                };
                self.variant_test(place, &ty, v, fail)?;
                let ftys = self.field_tys(&ty, v);
                self.seq_fields(ts.elems.iter(), place, &ty, v, &ftys, fail)
            }
            Pat::Struct(s) => {
                let Some(PatKind::Variant(_, v)) = info.map(|i| i.kind) else {
                    return Err(internal("unresolved struct pattern"));
                };
                self.variant_test(place, &ty, v, fail)?;
                let ftys = self.field_tys(&ty, v);
                for fp in &s.fields {
                    let i = *self
                        .body
                        .fields
                        .get(&key(fp))
                        .ok_or_else(|| internal("field pattern"))?;
                    let fptr = self.field_ptr(place, &ty, v, i)?;
                    self.match_pat(&fp.pat, fptr, &ftys[i], fail)?;
                }
                Ok(())
            }
            Pat::Tuple(t) => {
                let ftys = match &ty {
                    Ty::Tuple(ts) => ts.clone(),
                    _ => Vec::new(),
                };
                self.seq_fields(t.elems.iter(), place, &ty, 0, &ftys, fail)
            }
            Pat::Slice(sp) => self.slice_pat(sp, place, &ty, fail),
            other => Err(internal(format!(
                "pattern at line {}",
                crate::diag::Loc::of(other.span()).line
            ))),
        }
    }

    /// Elements of a tuple or tuple-struct pattern, with `..`.
    fn seq_fields<'e>(
        &mut self,
        elems: impl Iterator<Item = &'e Pat>,
        place: PointerValue<'ctx>,
        ty: &Ty,
        v: usize,
        ftys: &[Ty],
        fail: BasicBlock<'ctx>,
    ) -> LResult<()> {
        let elems: Vec<&Pat> = elems.collect();
        let rest = elems.iter().position(|p| matches!(p, Pat::Rest(_)));
        for (i, e) in elems.iter().enumerate() {
            let fi = match rest {
                Some(r) if i == r => continue,
                Some(r) if i > r => ftys.len() - (elems.len() - i),
                _ => i,
            };
            let fptr = self.field_ptr(place, ty, v, fi)?;
            self.match_pat(e, fptr, &ftys[fi], fail)?;
        }
        Ok(())
    }

    fn slice_pat(
        &mut self,
        sp: &syn::PatSlice,
        place: PointerValue<'ctx>,
        ty: &Ty,
        fail: BasicBlock<'ctx>,
    ) -> LResult<()> {
        let i32t = self.ctx.i32_type();
        let rest_at = sp.elems.iter().position(is_rest);
        let n = sp.elems.len();
        let fixed = n - rest_at.map_or(0, |_| 1);
        let (s, el) = match ty {
            Ty::Array(el, len) => (
                super::place::Seq {
                    ptr: place,
                    len: i32t.const_int(*len as u64, false),
                    elem: (**el).clone(),
                    array: true,
                },
                (**el).clone(),
            ),
            Ty::Slice(el) => {
                // `place` points to the fat reference's target: the caller passed the
                // reference's place (see `PatInfo::derefs`), so load the fat value.
                return Err(internal(format!(
                    "unsized slice pattern on {}",
                    self.p.ty_str(&Ty::Slice(el.clone()))
                )));
            }
            Ty::Ref(_, inner) if matches!(**inner, Ty::Slice(_)) => {
                let Ty::Slice(el) = &**inner else {
                    unreachable!()
                };
                let fat = self.b.build_load(place, "")?.into_struct_value();
                let (ptr, len) = self.slice_parts(fat)?;
                (
                    super::place::Seq {
                        ptr,
                        len,
                        elem: (**el).clone(),
                        array: false,
                    },
                    (**el).clone(),
                )
            }
            other => {
                return Err(internal(format!(
                    "slice pattern on {}",
                    self.p.ty_str(other)
                )))
            }
        };
        if !s.array {
            let want = i32t.const_int(fixed as u64, false);
            let pred = if rest_at.is_some() {
                IntPredicate::UGE
            } else {
                IntPredicate::EQ
            };
            let ok = self.b.build_int_compare(pred, s.len, want, "")?;
            self.test(ok, fail)?;
        }
        for (i, e) in sp.elems.iter().enumerate() {
            let idx: IntValue = match rest_at {
                Some(r) if i == r => {
                    if let Pat::Ident(pi) = e {
                        // `rest @ ..`.
                        let first = self.seq_elem(&s, i32t.const_int(r as u64, false))?;
                        let m =
                            self.b
                                .build_int_sub(s.len, i32t.const_int(fixed as u64, false), "")?;
                        let info = self.pat_info(e).ok_or_else(|| internal("rest binding"))?;
                        match &info.ty {
                            Ty::Array(_, k) => {
                                let at = self
                                    .llty(&Ty::Array(Box::new(el.clone()), *k))
                                    .ptr_type(AddressSpace::default());
                                let p = self.b.build_pointer_cast(first, at, "")?;
                                self.bind(pi, p, &info.ty)?;
                            }
                            _ => {
                                // A sub-slice, bound by reference.
                                let fat = self.make_slice(first, &el, m)?;
                                let (id, _) = *self
                                    .body
                                    .binds
                                    .get(&key(pi))
                                    .ok_or_else(|| internal("rest local"))?;
                                let lt = self.body.locals[id].ty.clone();
                                let slot = self.local_slot(id, &lt, pi)?;
                                self.b.build_store(slot, fat)?;
                            }
                        }
                    }
                    continue;
                }
                Some(r) if i > r => {
                    let back = (n - i) as u64;
                    self.b
                        .build_int_sub(s.len, i32t.const_int(back, false), "")?
                }
                _ => i32t.const_int(i as u64, false),
            };
            let ep = self.seq_elem(&s, idx)?;
            self.match_pat(e, ep, &el, fail)?;
        }
        Ok(())
    }

    /// Tests the tag of the enum at `place` (no test for structs and one-variant enums).
    fn variant_test(
        &mut self,
        place: PointerValue<'ctx>,
        ty: &Ty,
        v: usize,
        fail: BasicBlock<'ctx>,
    ) -> LResult<()> {
        let Ty::Adt(a, _) = ty else {
            return Ok(());
        };
        let a = *a;
        if !self.p.adts[a].is_enum || self.p.adts[a].variants.len() < 2 {
            return Ok(());
        }
        let tp = self.tag_ptr(place, ty)?;
        let tag = self.b.build_load(tp, "tag")?.into_int_value();
        let want = self.tag_val(a, v);
        let ok = self.b.build_int_compare(IntPredicate::EQ, tag, want, "")?;
        self.test(ok, fail)
    }

    fn const_test(
        &mut self,
        place: PointerValue<'ctx>,
        ty: &Ty,
        c: i128,
        fail: BasicBlock<'ctx>,
    ) -> LResult<()> {
        let v = self.b.build_load(place, "")?.into_int_value();
        let k = v.get_type().const_int(c as u64, true);
        let ok = self.b.build_int_compare(IntPredicate::EQ, v, k, "")?;
        let _ = ty;
        self.test(ok, fail)
    }

    /// A range-pattern bound's value.
    fn bound_value(&mut self, e: &Expr, ty: &Ty) -> LResult<BasicValueEnum<'ctx>> {
        if let Some(PatInfo {
            kind: PatKind::Const(c),
            ..
        }) = self.body.pats.get(&key(e)).cloned()
        {
            let lt = self.llty(ty).into_int_type();
            return Ok(lt.const_int(c as u64, true).into());
        }
        match e {
            Expr::Lit(l) => self.lit(&l.lit, ty),
            Expr::Unary(u) => {
                let v = self.bound_value(&u.expr, ty)?;
                Ok(match v {
                    BasicValueEnum::IntValue(i) => i.const_neg().into(),
                    BasicValueEnum::FloatValue(f) => f.const_neg().into(),
                    other => other,
                })
            }
            _ => Err(internal("range bound")),
        }
    }

    /// `v >= c` (`ge`) or `v <= c` / `v < c` (`closed`).
    fn ordered(
        &mut self,
        v: BasicValueEnum<'ctx>,
        c: BasicValueEnum<'ctx>,
        ty: &Ty,
        ge: bool,
        closed: bool,
    ) -> LResult<IntValue<'ctx>> {
        Ok(match ty {
            Ty::Float(_) => {
                let pred = match (ge, closed) {
                    (true, _) => FloatPredicate::OGE,
                    (false, true) => FloatPredicate::OLE,
                    (false, false) => FloatPredicate::OLT,
                };
                self.b
                    .build_float_compare(pred, v.into_float_value(), c.into_float_value(), "")?
            }
            _ => {
                let signed = matches!(ty, Ty::Int(i) if i.signed());
                let pred = match (ge, closed, signed) {
                    (true, _, true) => IntPredicate::SGE,
                    (true, _, false) => IntPredicate::UGE,
                    (false, true, true) => IntPredicate::SLE,
                    (false, true, false) => IntPredicate::ULE,
                    (false, false, true) => IntPredicate::SLT,
                    (false, false, false) => IntPredicate::ULT,
                };
                self.b
                    .build_int_compare(pred, v.into_int_value(), c.into_int_value(), "")?
            }
        })
    }

    /// `a == b` for scalar values of type `ty`.
    pub(super) fn values_eq(
        &mut self,
        a: BasicValueEnum<'ctx>,
        b: BasicValueEnum<'ctx>,
        ty: &Ty,
    ) -> LResult<IntValue<'ctx>> {
        Ok(match ty {
            Ty::Float(_) => self.b.build_float_compare(
                FloatPredicate::OEQ,
                a.into_float_value(),
                b.into_float_value(),
                "",
            )?,
            _ => self.b.build_int_compare(
                IntPredicate::EQ,
                a.into_int_value(),
                b.into_int_value(),
                "",
            )?,
        })
    }

    /// The slot of local `id` (created and described on first use).
    pub(super) fn local_slot(
        &mut self,
        id: usize,
        ty: &Ty,
        pi: &syn::PatIdent,
    ) -> LResult<PointerValue<'ctx>> {
        if let Some(s) = self.fs().locals.get(&id) {
            return Ok(*s);
        }
        let name = pi.ident.to_string();
        let s = self.alloca(ty, &name)?;
        self.declare_var(s, &name, ty, pi.ident.span(), None);
        self.fs().locals.insert(id, s);
        Ok(s)
    }

    /// Binds `pi` to the value at `place` (by value or by reference).
    fn bind(&mut self, pi: &syn::PatIdent, place: PointerValue<'ctx>, ty: &Ty) -> LResult<()> {
        let Some((id, mode)) = self.body.binds.get(&key(pi)).copied() else {
            return Ok(());
        };
        let lt = self.body.locals[id].ty.clone();
        let slot = self.local_slot(id, &lt, pi)?;
        match mode {
            BindMode::Value => {
                if !ty.is_zst() {
                    let v = self.b.build_load(place, "")?;
                    self.b.build_store(slot, v)?;
                }
            }
            BindMode::Ref(_) => {
                self.b.build_store(slot, place)?;
            }
        }
        Ok(())
    }

    /// Declares the slots of a pattern's bindings (`let x;`).
    pub(super) fn declare_pat(&mut self, pat: &Pat) -> LResult<()> {
        struct Find<'x>(Vec<&'x syn::PatIdent>);
        impl<'x> syn::visit::Visit<'x> for Find<'x> {
            fn visit_pat_ident(&mut self, i: &'x syn::PatIdent) {
                self.0.push(i);
                syn::visit::visit_pat_ident(self, i);
            }
        }
        let mut f = Find(Vec::new());
        syn::visit::Visit::visit_pat(&mut f, pat);
        for pi in f.0 {
            if let Some((id, _)) = self.body.binds.get(&key(pi)).copied() {
                let lt = self.body.locals[id].ty.clone();
                self.local_slot(id, &lt, pi)?;
            }
        }
        Ok(())
    }

    pub(super) fn match_expr(&mut self, m: &syn::ExprMatch, ty: &Ty) -> LResult<V<'ctx>> {
        let st = self.ty_of(&m.expr);
        let place = self.place_or_temp(&m.expr)?;
        if self.terminated() {
            return Ok(None);
        }
        let slot = if ty.is_zst() {
            None
        } else {
            Some(self.alloca(ty, "match.value")?)
        };
        let end = self.new_block("match.end");
        for arm in &m.arms {
            let next = self.new_block("arm.next");
            self.set_loc(arm.pat.span());
            let prev = self.push_scope(arm.pat.span());
            let (pat, guard) = crate::typeck::split_guard(&arm.pat);
            self.match_pat(pat, place, &st, next)?;
            if let Some(g) = guard {
                let gv = self.expr(g)?;
                let gv = self.val(gv, &Ty::Bool).into_int_value();
                let body_bb = self.new_block("arm.body");
                if !self.terminated() {
                    self.b.build_conditional_branch(gv, body_bb, next)?;
                }
                self.b.position_at_end(body_bb);
            }
            let v = self.expr(&arm.body)?;
            if let (Some(s), Some(v)) = (slot, v) {
                if !self.terminated() {
                    self.b.build_store(s, v)?;
                }
            }
            self.pop_scope(prev);
            self.br(end)?;
            self.b.position_at_end(next);
        }
        self.set_loc(m.match_token.span);
        self.abort(AbortKind::Unreachable, "non-exhaustive match")?;
        self.b.position_at_end(end);
        match slot {
            Some(s) => Ok(Some(self.b.build_load(s, "")?)),
            None => Ok(None),
        }
    }

    /// `matches!(e, pat if guard)`.
    pub(super) fn matches_macro(
        &mut self,
        e: &Expr,
        pat: &Pat,
        guard: Option<&Expr>,
    ) -> LResult<V<'ctx>> {
        let st = self.ty_of(e);
        let place = self.place_or_temp(e)?;
        let slot = self.alloca(&Ty::Bool, "matches")?;
        let f = self.ctx.bool_type().const_zero();
        self.b.build_store(slot, f)?;
        let no = self.new_block("matches.no");
        let end = self.new_block("matches.end");
        let prev = self.push_scope(pat.span());
        self.match_pat(pat, place, &st, no)?;
        if let Some(g) = guard {
            let gv = self.expr(g)?;
            let gv = self.val(gv, &Ty::Bool).into_int_value();
            let yes = self.new_block("matches.yes");
            self.b.build_conditional_branch(gv, yes, no)?;
            self.b.position_at_end(yes);
        }
        self.pop_scope(prev);
        let t = self.ctx.bool_type().const_int(1, false);
        self.b.build_store(slot, t)?;
        self.br(end)?;
        self.b.position_at_end(no);
        self.br(end)?;
        self.b.position_at_end(end);
        Ok(Some(self.b.build_load(slot, "")?))
    }
}

fn is_rest(p: &Pat) -> bool {
    match p {
        Pat::Rest(_) => true,
        Pat::Ident(pi) => matches!(pi.subpat.as_ref().map(|(_, s)| &**s), Some(Pat::Rest(_))),
        _ => false,
    }
}
