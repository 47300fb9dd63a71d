//! Places: locals, statics, fields, array and slice elements (bounds-checked with Rust's
//! messages), dereferences and `Index` impls; slices (`{ptr, len}`) and sub-slicing.

use super::{internal, LResult, Lowerer};
use crate::span::Spanned;
use crate::ty::{IntTy, Ty};
use crate::typeck::{key, OpCall, Res};
use inkwell::types::BasicType;
use inkwell::values::{BasicValueEnum, IntValue, PointerValue, StructValue};
use inkwell::AddressSpace;
use inkwell::IntPredicate;
use syn::{Expr, UnOp};

/// A sequence reached from an expression: an array (pointer to it) or a slice (pointer
/// to its first element and its length).
pub(super) struct Seq<'ctx> {
    /// Pointer to the array, or to the slice's first element.
    pub ptr: PointerValue<'ctx>,
    /// The length: constant for arrays.
    pub len: IntValue<'ctx>,
    /// Element type.
    pub elem: Ty,
    /// True for arrays (`ptr` points to `[T; N]`).
    pub array: bool,
}

impl<'ctx> Lowerer<'ctx, '_, '_> {
    /// True for expressions that denote memory.
    pub(super) fn is_place(&self, e: &Expr) -> bool {
        match e {
            Expr::Path(_) => match self.body.res.get(&key(e)) {
                Some(Res::Local(_)) => true,
                Some(Res::Global(g, _)) => {
                    self.p.globals[*g].is_static.is_some()
                        || !super::expr::is_scalar(&self.p.globals[*g].ty)
                }
                _ => false,
            },
            // Field and element addresses are computed from the base (a temporary
            // when the base is a value).
            Expr::Field(_) | Expr::Index(_) => true,
            Expr::Paren(p) => self.is_place(&p.expr),
            Expr::Group(p) => self.is_place(&p.expr),
            Expr::Unary(u) => matches!(u.op, syn::UnOp::Deref(_)),
            _ => false,
        }
    }

    /// The address of a place expression, or of a temporary holding the value.
    pub(super) fn place_or_temp(&mut self, e: &Expr) -> LResult<PointerValue<'ctx>> {
        if self.is_place(e) && !self.body.adjust.contains_key(&key(e)) {
            return self.place(e);
        }
        self.temp(e)
    }

    fn temp(&mut self, e: &Expr) -> LResult<PointerValue<'ctx>> {
        let t = self.ty_of(e);
        let v = self.expr(e)?;
        let v = self.val(v, &t);
        let slot = self.alloca(&t, "tmp")?;
        if !self.terminated() {
            self.b.build_store(slot, v)?;
        }
        Ok(slot)
    }

    /// Address of the value reached by dereferencing `e` `derefs` times (0: `e` itself).
    pub(super) fn deref_base(&mut self, e: &Expr, derefs: u32) -> LResult<PointerValue<'ctx>> {
        if derefs == 0 {
            return self.place_or_temp(e);
        }
        let t = self.ty_of(e);
        let v = self.expr(e)?;
        let mut p = self.val(v, &t).into_pointer_value();
        for _ in 1..derefs {
            p = self.b.build_load(p, "")?.into_pointer_value();
        }
        Ok(p)
    }

    /// The value of `e` after `derefs` dereferences.
    pub(super) fn deref_value(&mut self, e: &Expr, derefs: u32) -> LResult<BasicValueEnum<'ctx>> {
        if derefs == 0 {
            let t = self.ty_of(e);
            let v = self.expr(e)?;
            return Ok(self.val(v, &t));
        }
        let p = self.deref_base(e, derefs)?;
        Ok(self.b.build_load(p, "")?)
    }

    /// The array or slice reached from `e` with `derefs` dereferences.
    pub(super) fn seq(&mut self, e: &Expr, derefs: u32) -> LResult<Seq<'ctx>> {
        let mut t = self.ty_of(e);
        for _ in 0..derefs {
            if let Ty::Ref(_, inner) = t {
                t = *inner;
            }
        }
        match t {
            Ty::Array(el, n) => {
                let ptr = self.deref_base(e, derefs)?;
                Ok(Seq {
                    ptr,
                    len: self.ctx.i32_type().const_int(n as u64, false),
                    elem: *el,
                    array: true,
                })
            }
            Ty::Slice(el) => {
                // The fat reference is the value one dereference short.
                let fat = self.deref_value(e, derefs - 1)?.into_struct_value();
                let (ptr, len) = self.slice_parts(fat)?;
                Ok(Seq {
                    ptr,
                    len,
                    elem: *el,
                    array: false,
                })
            }
            other => Err(internal(format!(
                "not a sequence: {}",
                self.p.ty_str(&other)
            ))),
        }
    }

    /// Data pointer and length of a slice reference.
    pub(super) fn slice_parts(
        &mut self,
        fat: StructValue<'ctx>,
    ) -> LResult<(PointerValue<'ctx>, IntValue<'ctx>)> {
        let ptr = self
            .b
            .build_extract_value(fat, 0, "ptr")?
            .into_pointer_value();
        let len = self.b.build_extract_value(fat, 1, "len")?.into_int_value();
        Ok((ptr, len))
    }

    /// `{ptr, len}` from a pointer to an array or to a first element.
    pub(super) fn make_slice(
        &mut self,
        p: PointerValue<'ctx>,
        el: &Ty,
        len: IntValue<'ctx>,
    ) -> LResult<StructValue<'ctx>> {
        let st = self.slice_ty(el);
        let ep = self.llty(el).ptr_type(AddressSpace::default());
        let p = self.b.build_pointer_cast(p, ep, "")?;
        let mut v = st.get_undef();
        v = self.b.build_insert_value(v, p, 0, "")?.into_struct_value();
        v = self
            .b
            .build_insert_value(v, len, 1, "")?
            .into_struct_value();
        Ok(v)
    }

    /// Pointer to element `i` of a sequence (no bounds check).
    pub(super) fn seq_elem(
        &mut self,
        s: &Seq<'ctx>,
        i: IntValue<'ctx>,
    ) -> LResult<PointerValue<'ctx>> {
        let i32t = self.ctx.i32_type();
        // SAFETY: callers check `i < len` (or iterate below it).
        Ok(unsafe {
            if s.array {
                self.b
                    .build_in_bounds_gep(s.ptr, &[i32t.const_zero(), i], "")?
            } else {
                self.b.build_in_bounds_gep(s.ptr, &[i], "")?
            }
        })
    }

    /// `&seq[lo..hi]` (any range form), with Rust's bounds checks, as a slice reference;
    /// `None` when `inner` is not a range index.
    pub(super) fn slice_ref(&mut self, inner: &Expr) -> LResult<Option<BasicValueEnum<'ctx>>> {
        let Expr::Index(ix) = strip(inner) else {
            return Ok(None);
        };
        let Expr::Range(r) = strip(&ix.index) else {
            return Ok(None);
        };
        let derefs = self
            .body
            .derefs
            .get(&key(strip(inner)))
            .copied()
            .unwrap_or(0);
        let s = self.seq(&ix.expr, derefs)?;
        let usize_t = Ty::Int(IntTy::Usize);
        let i32t = self.ctx.i32_type();
        let lo = match &r.start {
            Some(x) => {
                let v = self.expr(x)?;
                self.val(v, &usize_t).into_int_value()
            }
            None => i32t.const_zero(),
        };
        let hi = match &r.end {
            Some(x) => {
                let v = self.expr(x)?;
                let v = self.val(v, &usize_t).into_int_value();
                if matches!(r.limits, syn::RangeLimits::Closed(_)) {
                    let max =
                        self.b
                            .build_int_compare(IntPredicate::EQ, v, i32t.const_all_ones(), "")?;
                    let ok = self.b.build_not(max, "")?;
                    self.set_loc(ix.bracket_token.span.open());
                    self.check_with(ok, |l| {
                        l.abort(
                            trax_runtime::isa::AbortKind::Bounds,
                            "attempted to index slice up to maximum usize",
                        )
                    })?;
                    self.b.build_int_add(v, i32t.const_int(1, false), "")?
                } else {
                    v
                }
            }
            None => s.len,
        };
        self.set_loc(ix.bracket_token.span.open());
        let len = s.len;
        let end_ok = self.b.build_int_compare(IntPredicate::ULE, hi, len, "")?;
        self.check_with(end_ok, |l| l.slice_end_abort(hi, len))?;
        let order_ok = self.b.build_int_compare(IntPredicate::ULE, lo, hi, "")?;
        self.check_with(order_ok, |l| l.slice_order_abort(lo, hi))?;
        let first = self.seq_elem(&s, lo)?;
        let n = self.b.build_int_sub(hi, lo, "")?;
        Ok(Some(self.make_slice(first, &s.elem, n)?.into()))
    }

    /// Lowers a place expression to its address.
    pub(super) fn place(&mut self, e: &Expr) -> LResult<PointerValue<'ctx>> {
        match e {
            Expr::Paren(p) => self.place(&p.expr),
            Expr::Group(p) => self.place(&p.expr),
            Expr::Path(_) => match self.body.res.get(&key(e)).cloned() {
                Some(Res::Local(id)) => self
                    .fs()
                    .locals
                    .get(&id)
                    .copied()
                    .ok_or_else(|| internal(format!("local {id} has no slot"))),
                Some(Res::Global(g, substs)) => Ok(self.global(g, &substs)?.as_pointer_value()),
                Some(_) => self.temp(e),
                None => {
                    let l = crate::diag::Loc::of(e.span());
                    Err(internal(format!(
                        "unresolved path at {}:{}:{}",
                        self.p.sources.get(self.file).display.display(),
                        l.line,
                        l.col
                    )))
                }
            },
            Expr::Field(f) => {
                let derefs = self.body.derefs.get(&key(e)).copied().unwrap_or(0);
                let base = self.deref_base(&f.base, derefs)?;
                let mut st = self.ty_of(&f.base);
                while let Ty::Ref(_, inner) = st {
                    st = *inner;
                }
                let idx = *self
                    .body
                    .fields
                    .get(&key(e))
                    .ok_or_else(|| internal("field index"))?;
                self.field_ptr(base, &st, 0, idx)
            }
            Expr::Index(i) => {
                if let Some(OpCall::Fn { func, substs, .. }) = self.body.ops.get(&key(e)).cloned() {
                    // `*Index::index(&base, idx)` / `*IndexMut::index_mut(&mut base, idx)`.
                    let derefs = self.body.derefs.get(&key(e)).copied().unwrap_or(0);
                    let base = self.deref_base(&i.expr, derefs)?;
                    let it = self.ty_of(&i.index);
                    let idx = self.expr(&i.index)?;
                    let idx = self.val(idx, &it);
                    self.set_loc(i.bracket_token.span.open());
                    let fd = &self.p.fns[func];
                    let ret = self.p.normalize(&fd.ret.subst(&substs)).unwrap_or(Ty::Unit);
                    let r = self.call_fn(func, &substs, vec![base.into(), idx], &ret)?;
                    return Ok(self.val(r, &ret).into_pointer_value());
                }
                let derefs = self.body.derefs.get(&key(e)).copied().unwrap_or(0);
                let s = self.seq(&i.expr, derefs)?;
                let idx = self.expr(&i.index)?;
                let idx = self.val(idx, &Ty::Int(IntTy::Usize)).into_int_value();
                self.set_loc(e.span());
                let ok = self
                    .b
                    .build_int_compare(IntPredicate::ULT, idx, s.len, "inbounds")?;
                let len = s.len;
                self.check_with(ok, |l| l.bounds_abort(len, idx))?;
                self.seq_elem(&s, idx)
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Deref(_)) => {
                let t = self.ty_of(&u.expr);
                let v = self.expr(&u.expr)?;
                Ok(self.val(v, &t).into_pointer_value())
            }
            _ => self.temp(e),
        }
    }
}

/// Strips parentheses and groups.
pub(super) fn strip(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip(&p.expr),
        Expr::Group(g) => strip(&g.expr),
        other => other,
    }
}
