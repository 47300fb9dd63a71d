//! Lowering of blocks, statements and expressions.

use super::{int_of, LResult, LoopTarget, LowerError, Lowerer, V};
use crate::resolve::Recv;
use crate::ty::{FloatTy, IntTy, Ty};
use crate::typeck::{classify_for, key, Callee, ForKind, Res};
use inkwell::types::BasicTypeEnum;
use inkwell::values::{BasicValue, BasicValueEnum, IntValue, PointerValue};
use inkwell::{FloatPredicate, IntPredicate};
use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, Pat, Stmt, UnOp};
use trax_runtime::isa::AbortKind;

impl<'ctx> Lowerer<'ctx, '_, '_> {
    // ---------------------------------------------------------------- blocks

    pub(super) fn block(&mut self, b: &syn::Block, scoped: bool) -> LResult<V<'ctx>> {
        let prev = if scoped {
            Some(self.push_scope(b.brace_token.span.open()))
        } else {
            None
        };
        let r = self.block_inner(b);
        if let Some(p) = prev {
            self.pop_scope(p);
        }
        r
    }

    fn block_inner(&mut self, b: &syn::Block) -> LResult<V<'ctx>> {
        let n = b.stmts.len();
        for (i, s) in b.stmts.iter().enumerate() {
            let last = i + 1 == n;
            match s {
                Stmt::Local(l) => self.let_stmt(l)?,
                Stmt::Expr(e, semi) => {
                    let v = self.expr(e)?;
                    if last && semi.is_none() {
                        return Ok(v);
                    }
                }
                Stmt::Macro(m) => {
                    self.set_loc(m.span());
                    let v = self.mac(&m.mac)?;
                    if last && m.semi_token.is_none() {
                        return Ok(v);
                    }
                }
                Stmt::Item(_) => {}
            }
        }
        Ok(None)
    }

    fn let_stmt(&mut self, l: &syn::Local) -> LResult<()> {
        let pat = match &l.pat {
            Pat::Type(pt) => &*pt.pat,
            p => p,
        };
        let v = match &l.init {
            Some(init) => {
                self.set_loc(init.expr.span());
                Some(self.expr(&init.expr)?)
            }
            None => None,
        };
        if let Pat::Ident(pi) = pat {
            if let Some(&id) = self.body.pat_locals.get(&key(pi)) {
                let ty = self.body.locals[id].ty.clone();
                self.set_loc(pi.ident.span());
                let slot = self.alloca(&ty, &pi.ident.to_string())?;
                self.declare_var(slot, &pi.ident.to_string(), &ty, pi.ident.span(), None);
                if let Some(Some(v)) = v {
                    self.b.build_store(slot, v)?;
                }
                self.fs().locals.insert(id, slot);
            }
        }
        Ok(())
    }

    // ---------------------------------------------------------------- expressions

    /// Lowers an expression to its value.
    pub(super) fn expr(&mut self, e: &Expr) -> LResult<V<'ctx>> {
        self.set_loc(e.span());
        let ty = self.ty_of(e);
        let v = self.expr_inner(e, &ty)?;
        if matches!(ty, Ty::Never) && !self.terminated() {
            self.b.build_unreachable()?;
        }
        if self.terminated() {
            self.dead_block();
        }
        if ty.is_zst() {
            return Ok(None);
        }
        Ok(v)
    }

    fn expr_inner(&mut self, e: &Expr, ty: &Ty) -> LResult<V<'ctx>> {
        match e {
            Expr::Lit(l) => Ok(Some(self.lit(&l.lit, ty)?)),
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Block(b) => self.block(&b.block, true),
            Expr::Unsafe(u) => self.block(&u.block, true),
            Expr::Path(_) => self.path_value(e, ty),
            Expr::Binary(b) => self.binary(e, b, ty),
            Expr::Unary(u) => self.unary(e, u, ty),
            Expr::Assign(a) => {
                let v = self.expr(&a.right)?;
                let place = self.place(&a.left)?;
                if let Some(v) = v {
                    self.b.build_store(place, v)?;
                }
                Ok(None)
            }
            Expr::Cast(c) => {
                let from = self.ty_of(&c.expr);
                let v = self.expr(&c.expr)?;
                let v = self.val(v, &from);
                Ok(Some(self.cast(v, &from, ty)?))
            }
            Expr::If(i) => self.if_expr(i, ty),
            Expr::While(w) => {
                let head = self.new_block("while.cond");
                let body = self.new_block("while.body");
                let exit = self.new_block("while.end");
                self.br(head)?;
                self.b.position_at_end(head);
                let c = self.expr(&w.cond)?;
                let c = self.val(c, &Ty::Bool).into_int_value();
                self.b.build_conditional_branch(c, body, exit)?;
                self.b.position_at_end(body);
                self.fs().loops.push(LoopTarget {
                    label: w.label.as_ref().map(|l| l.name.ident.to_string()),
                    brk: exit,
                    cont: head,
                    slot: None,
                });
                let r = self.block(&w.body, true);
                self.fs().loops.pop();
                r?;
                self.br(head)?;
                self.b.position_at_end(exit);
                Ok(None)
            }
            Expr::Loop(l) => {
                let body = self.new_block("loop.body");
                let exit = self.new_block("loop.end");
                let slot = if ty.is_zst() {
                    None
                } else {
                    Some(self.alloca(ty, "loop.value")?)
                };
                self.br(body)?;
                self.b.position_at_end(body);
                self.fs().loops.push(LoopTarget {
                    label: l.label.as_ref().map(|l| l.name.ident.to_string()),
                    brk: exit,
                    cont: body,
                    slot,
                });
                let r = self.block(&l.body, true);
                self.fs().loops.pop();
                r?;
                self.br(body)?;
                self.b.position_at_end(exit);
                match slot {
                    Some(s) => Ok(Some(self.b.build_load(s, "loop.value")?)),
                    None => Ok(None),
                }
            }
            Expr::ForLoop(f) => self.for_loop(e, f),
            Expr::Break(b) => {
                let label = b.label.as_ref().map(|l| l.ident.to_string());
                let v = match &b.expr {
                    Some(x) => self.expr(x)?,
                    None => None,
                };
                let t = self.loop_target(label.as_deref())?;
                if let (Some(slot), Some(v)) = (t.2, v) {
                    self.b.build_store(slot, v)?;
                }
                self.b.build_unconditional_branch(t.0)?;
                Ok(None)
            }
            Expr::Continue(c) => {
                let label = c.label.as_ref().map(|l| l.ident.to_string());
                let t = self.loop_target(label.as_deref())?;
                self.b.build_unconditional_branch(t.1)?;
                Ok(None)
            }
            Expr::Return(r) => {
                let v = match &r.expr {
                    Some(x) => self.expr(x)?,
                    None => None,
                };
                if self.terminated() {
                    return Ok(None);
                }
                let ret = self.fs().ret.clone();
                self.set_loc(r.span());
                if ret.is_zst() {
                    self.b.build_return(None)?;
                } else {
                    let v = self.val(v, &ret);
                    self.b.build_return(Some(&v))?;
                }
                Ok(None)
            }
            Expr::Call(c) => {
                let args: Vec<&Expr> = c.args.iter().collect();
                self.call(e, None, &args, ty)
            }
            Expr::MethodCall(m) => {
                let args: Vec<&Expr> = m.args.iter().collect();
                self.call(e, Some(&m.receiver), &args, ty)
            }
            Expr::Field(_) | Expr::Index(_) => {
                let p = self.place(e)?;
                Ok(Some(self.b.build_load(p, "")?))
            }
            Expr::Reference(r) => {
                let p = self.place_or_temp(&r.expr)?;
                Ok(Some(p.into()))
            }
            Expr::Array(a) => {
                let lt = self.llty(ty);
                let mut agg = super::undef(lt).into_array_value();
                let Ty::Array(et, _) = ty else {
                    return Err(LowerError::Internal("array type".into()));
                };
                for (i, x) in a.elems.iter().enumerate() {
                    let v = self.expr(x)?;
                    let v = self.val(v, et);
                    agg = self
                        .b
                        .build_insert_value(agg, v, i as u32, "")?
                        .into_array_value();
                }
                Ok(Some(agg.into()))
            }
            Expr::Repeat(r) => {
                let Ty::Array(et, n) = ty else {
                    return Err(LowerError::Internal("repeat type".into()));
                };
                let v = self.expr(&r.expr)?;
                let v = self.val(v, et);
                if super::is_const(v) {
                    let vals = vec![v; *n as usize];
                    return Ok(Some(const_array(self.llty(et), &vals)));
                }
                // Runtime element: fill a stack slot with a loop.
                let slot = self.alloca(ty, "repeat")?;
                let i32t = self.ctx.i32_type();
                let idx = self.alloca(&Ty::Int(IntTy::U32), "repeat.i")?;
                self.b.build_store(idx, i32t.const_zero())?;
                let head = self.new_block("repeat.cond");
                let body = self.new_block("repeat.body");
                let exit = self.new_block("repeat.end");
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(head);
                let iv = self.b.build_load(idx, "")?.into_int_value();
                let c = self.b.build_int_compare(
                    IntPredicate::ULT,
                    iv,
                    i32t.const_int(*n as u64, false),
                    "",
                )?;
                self.b.build_conditional_branch(c, body, exit)?;
                self.b.position_at_end(body);
                // SAFETY: `iv < n` on this path, so the GEP is in bounds of the array slot.
                let ep = unsafe {
                    self.b
                        .build_in_bounds_gep(slot, &[i32t.const_zero(), iv], "")?
                };
                self.b.build_store(ep, v)?;
                let nx = self.b.build_int_add(iv, i32t.const_int(1, false), "")?;
                self.b.build_store(idx, nx)?;
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(exit);
                Ok(Some(self.b.build_load(slot, "")?))
            }
            Expr::Struct(s) => {
                let Ty::Struct(sid) = ty else {
                    return Err(LowerError::Internal("struct type".into()));
                };
                let def = &self.p.structs[*sid];
                let st = self.struct_ty(*sid);
                let mut agg = match &s.rest {
                    Some(r) => self
                        .expr(r)?
                        .map(|v| v.into_struct_value())
                        .unwrap_or_else(|| st.get_undef()),
                    None => st.get_undef(),
                };
                for fv in &s.fields {
                    let name = match &fv.member {
                        syn::Member::Named(n) => n.to_string(),
                        syn::Member::Unnamed(i) => i.index.to_string(),
                    };
                    let idx = def
                        .fields
                        .iter()
                        .position(|(n, _)| *n == name)
                        .ok_or_else(|| LowerError::Internal("field".into()))?;
                    let ft = def.fields[idx].1.clone();
                    let v = self.expr(&fv.expr)?;
                    let v = self.val(v, &ft);
                    agg = self
                        .b
                        .build_insert_value(agg, v, idx as u32, "")?
                        .into_struct_value();
                }
                Ok(Some(agg.into()))
            }
            Expr::Tuple(_) => Ok(None),
            Expr::Match(m) => self.match_expr(m, ty),
            Expr::Macro(m) => self.mac(&m.mac),
            other => Err(self.err(
                other.span(),
                "unsupported-expression",
                "this expression is not supported in TRaX-Rust",
            )),
        }
    }

    fn loop_target(
        &mut self,
        label: Option<&str>,
    ) -> LResult<(
        inkwell::basic_block::BasicBlock<'ctx>,
        inkwell::basic_block::BasicBlock<'ctx>,
        Option<PointerValue<'ctx>>,
    )> {
        let loops = &self.fs().loops;
        let t = match label {
            None => loops.last(),
            Some(l) => loops.iter().rev().find(|t| t.label.as_deref() == Some(l)),
        };
        t.map(|t| (t.brk, t.cont, t.slot))
            .ok_or_else(|| LowerError::Internal("loop target".into()))
    }

    fn lit(&mut self, l: &Lit, ty: &Ty) -> LResult<BasicValueEnum<'ctx>> {
        Ok(match (l, ty) {
            (Lit::Int(i), Ty::Int(it)) => {
                let v: i128 = i
                    .base10_parse()
                    .map_err(|_| self.err(i.span(), "invalid-literal", "bad integer literal"))?;
                self.int_ty(it.bits()).const_int(v as u64, false).into()
            }
            (Lit::Int(i), Ty::Float(f)) => {
                let v: f64 = i
                    .base10_parse::<i128>()
                    .map(|v| v as f64)
                    .map_err(|_| self.err(i.span(), "invalid-literal", "bad literal"))?;
                self.float_const(*f, v)
            }
            (Lit::Float(x), Ty::Float(f)) => {
                let v: f64 = match f {
                    FloatTy::F32 => x.base10_parse::<f32>().map(|v| v as f64),
                    FloatTy::F64 => x.base10_parse::<f64>(),
                }
                .map_err(|_| self.err(x.span(), "invalid-literal", "bad float literal"))?;
                self.float_const(*f, v)
            }
            (Lit::Bool(b), _) => self.ctx.bool_type().const_int(b.value as u64, false).into(),
            (Lit::Char(c), _) => self
                .ctx
                .i32_type()
                .const_int(c.value() as u64, false)
                .into(),
            (Lit::Byte(c), _) => self.ctx.i8_type().const_int(c.value() as u64, false).into(),
            (Lit::Str(s), _) => self.str_value(&s.value()),
            _ => return Err(self.err(l.span(), "unsupported-literal", "unsupported literal")),
        })
    }

    pub(super) fn float_const(&self, f: FloatTy, v: f64) -> BasicValueEnum<'ctx> {
        match f {
            FloatTy::F32 => self.ctx.f32_type().const_float(v as f32 as f64).into(),
            FloatTy::F64 => self.ctx.f64_type().const_float(v).into(),
        }
    }

    /// A `&str` value `{address, length}` for a string constant.
    pub(super) fn str_value(&mut self, s: &str) -> BasicValueEnum<'ctx> {
        let g = self.string_global(s);
        let i32t = self.ctx.i32_type();
        let addr = g.as_pointer_value().const_to_int(i32t);
        self.ctx
            .const_struct(
                &[addr.into(), i32t.const_int(s.len() as u64, false).into()],
                false,
            )
            .into()
    }

    fn path_value(&mut self, e: &Expr, ty: &Ty) -> LResult<V<'ctx>> {
        match self.body.res.get(&key(e)).cloned() {
            Some(Res::Int(it, v)) => Ok(Some(
                self.int_ty(it.bits()).const_int(v as u64, false).into(),
            )),
            Some(Res::Float(f, v)) => Ok(Some(self.float_const(f, v))),
            Some(Res::UnitStruct(s)) => Ok(Some(self.struct_ty(s).const_named_struct(&[]).into())),
            Some(Res::Global(g)) if self.p.globals[g].is_static.is_none() && is_scalar(ty) => {
                let gd = &self.p.globals[g];
                if self.const_depth > 64 {
                    return Err(self.err(
                        e.span(),
                        "recursive-constant",
                        format!("constant `{}` refers to itself", gd.name),
                    ));
                }
                self.const_depth += 1;
                let r = self.with_body(g, |l| l.expr(gd.expr));
                self.const_depth -= 1;
                r
            }
            _ => {
                let p = self.place(e)?;
                Ok(Some(self.b.build_load(p, "")?))
            }
        }
    }

    /// True for expressions that denote memory.
    fn is_place(&self, e: &Expr) -> bool {
        match e {
            Expr::Path(_) => match self.body.res.get(&key(e)) {
                Some(Res::Local(_)) => true,
                Some(Res::Global(g)) => {
                    self.p.globals[*g].is_static.is_some() || !is_scalar(&self.p.globals[*g].ty)
                }
                _ => false,
            },
            Expr::Field(f) => {
                self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 || self.is_place(&f.base)
            }
            Expr::Index(i) => {
                self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 || self.is_place(&i.expr)
            }
            Expr::Paren(p) => self.is_place(&p.expr),
            Expr::Unary(u) => matches!(u.op, UnOp::Deref(_)),
            _ => false,
        }
    }

    /// The address of a place expression, or of a temporary holding the value.
    pub(super) fn place_or_temp(&mut self, e: &Expr) -> LResult<PointerValue<'ctx>> {
        if self.is_place(e) {
            return self.place(e);
        }
        let t = self.ty_of(e);
        let v = self.expr(e)?;
        let v = self.val(v, &t);
        let slot = self.alloca(&t, "tmp")?;
        self.b.build_store(slot, v)?;
        Ok(slot)
    }

    /// Address of the value reached by dereferencing `e` `derefs` times (0: `e` itself).
    fn deref_base(&mut self, e: &Expr, derefs: u32) -> LResult<PointerValue<'ctx>> {
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
                    .ok_or_else(|| LowerError::Internal(format!("local {id} has no slot"))),
                Some(Res::Global(g)) => Ok(self.global(g)?.as_pointer_value()),
                Some(_) => self.place_or_temp_value(e),
                None => {
                    let l = crate::diag::Loc::of(e.span());
                    Err(LowerError::Internal(format!(
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
                let bt = self.ty_of(&f.base);
                let mut st = bt;
                while let Ty::Ref(_, inner) = st {
                    st = *inner;
                }
                let Ty::Struct(sid) = st else {
                    return Err(LowerError::Internal("field of non-struct".into()));
                };
                let name = match &f.member {
                    syn::Member::Named(n) => n.to_string(),
                    syn::Member::Unnamed(i) => i.index.to_string(),
                };
                let idx = self.p.structs[sid]
                    .fields
                    .iter()
                    .position(|(n, _)| *n == name)
                    .ok_or_else(|| LowerError::Internal("field".into()))?;
                Ok(self.b.build_struct_gep(base, idx as u32, &name)?)
            }
            Expr::Index(i) => {
                let derefs = self.body.derefs.get(&key(e)).copied().unwrap_or(0);
                let base = self.deref_base(&i.expr, derefs)?;
                let mut at = self.ty_of(&i.expr);
                while let Ty::Ref(_, inner) = at {
                    at = *inner;
                }
                let Ty::Array(_, n) = at else {
                    return Err(LowerError::Internal("index of non-array".into()));
                };
                let idx = self.expr(&i.index)?;
                let idx = self.val(idx, &Ty::Int(IntTy::Usize)).into_int_value();
                self.set_loc(e.span());
                let i32t = self.ctx.i32_type();
                let ok = self.b.build_int_compare(
                    IntPredicate::ULT,
                    idx,
                    i32t.const_int(n as u64, false),
                    "inbounds",
                )?;
                self.check_with(ok, |l| l.bounds_abort(n, idx))?;
                // SAFETY: the bounds check above guarantees `idx < n`.
                Ok(unsafe {
                    self.b
                        .build_in_bounds_gep(base, &[i32t.const_zero(), idx], "")?
                })
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Deref(_)) => {
                let t = self.ty_of(&u.expr);
                let v = self.expr(&u.expr)?;
                Ok(self.val(v, &t).into_pointer_value())
            }
            _ => self.place_or_temp_value(e),
        }
    }

    fn place_or_temp_value(&mut self, e: &Expr) -> LResult<PointerValue<'ctx>> {
        let t = self.ty_of(e);
        let v = self.expr(e)?;
        let v = self.val(v, &t);
        let slot = self.alloca(&t, "tmp")?;
        self.b.build_store(slot, v)?;
        Ok(slot)
    }

    /// Aborts the program with `kind` unless `ok` holds.
    pub(super) fn check(&mut self, ok: IntValue<'ctx>, kind: AbortKind, msg: &str) -> LResult<()> {
        if let Some(c) = ok.get_zero_extended_constant() {
            if c == 1 {
                return Ok(());
            }
        }
        let fail = self.new_block("check.fail");
        let cont = self.new_block("check.ok");
        self.b.build_conditional_branch(ok, cont, fail)?;
        self.b.position_at_end(fail);
        self.abort(kind, msg)?;
        self.b.position_at_end(cont);
        Ok(())
    }

    // ---------------------------------------------------------------- operators

    fn binary(&mut self, e: &Expr, b: &syn::ExprBinary, ty: &Ty) -> LResult<V<'ctx>> {
        use BinOp::*;
        if let Some(&f) = self.body.ops.get(&key(e)) {
            let fd = &self.p.fns[f];
            if fd.receiver == Some(Recv::RefMut) {
                let r = self.expr(&b.right)?;
                let rt = self.ty_of(&b.right);
                let r = self.val(r, &rt);
                let p = self.place(&b.left)?;
                self.set_loc(e.span());
                return self.call_fn(f, vec![p.into(), r], &Ty::Unit);
            }
            let lt = self.ty_of(&b.left);
            let rt = self.ty_of(&b.right);
            let l = self.expr(&b.left)?;
            let l = self.val(l, &lt);
            let r = self.expr(&b.right)?;
            let r = self.val(r, &rt);
            self.set_loc(e.span());
            return self.call_fn(f, vec![l, r], ty);
        }
        match b.op {
            And(_) | Or(_) => {
                let is_and = matches!(b.op, And(_));
                let slot = self.alloca(&Ty::Bool, "sc")?;
                let l = self.expr(&b.left)?;
                let l = self.val(l, &Ty::Bool).into_int_value();
                self.b.build_store(slot, l)?;
                let rhs = self.new_block(if is_and { "and.rhs" } else { "or.rhs" });
                let end = self.new_block("sc.end");
                if is_and {
                    self.b.build_conditional_branch(l, rhs, end)?;
                } else {
                    self.b.build_conditional_branch(l, end, rhs)?;
                }
                self.b.position_at_end(rhs);
                let r = self.expr(&b.right)?;
                if let Some(r) = r {
                    self.b.build_store(slot, r)?;
                }
                self.br(end)?;
                self.b.position_at_end(end);
                Ok(Some(self.b.build_load(slot, "")?))
            }
            AddAssign(_) | SubAssign(_) | MulAssign(_) | DivAssign(_) | RemAssign(_)
            | BitAndAssign(_) | BitOrAssign(_) | BitXorAssign(_) | ShlAssign(_) | ShrAssign(_) => {
                let lt = self.ty_of(&b.left);
                let rt = self.ty_of(&b.right);
                let r = self.expr(&b.right)?;
                let r = self.val(r, &rt);
                let p = self.place(&b.left)?;
                let l = self.b.build_load(p, "")?;
                self.set_loc(e.span());
                let op = match b.op {
                    AddAssign(_) => "+",
                    SubAssign(_) => "-",
                    MulAssign(_) => "*",
                    DivAssign(_) => "/",
                    RemAssign(_) => "%",
                    BitAndAssign(_) => "&",
                    BitOrAssign(_) => "|",
                    BitXorAssign(_) => "^",
                    ShlAssign(_) => "<<",
                    _ => ">>",
                };
                let v = self.arith(op, l, r, &lt, &rt)?;
                self.b.build_store(p, v)?;
                Ok(None)
            }
            _ => {
                let lt = self.ty_of(&b.left);
                let rt = self.ty_of(&b.right);
                let l = self.expr(&b.left)?;
                let l = self.val(l, &lt);
                let r = self.expr(&b.right)?;
                let r = self.val(r, &rt);
                self.set_loc(e.span());
                let op = match b.op {
                    Add(_) => "+",
                    Sub(_) => "-",
                    Mul(_) => "*",
                    Div(_) => "/",
                    Rem(_) => "%",
                    BitAnd(_) => "&",
                    BitOr(_) => "|",
                    BitXor(_) => "^",
                    Shl(_) => "<<",
                    Shr(_) => ">>",
                    Eq(_) => "==",
                    Ne(_) => "!=",
                    Lt(_) => "<",
                    Le(_) => "<=",
                    Gt(_) => ">",
                    _ => ">=",
                };
                Ok(Some(self.arith(op, l, r, &lt, &rt)?))
            }
        }
    }

    /// Applies a primitive binary operator.
    pub(super) fn arith(
        &mut self,
        op: &str,
        l: BasicValueEnum<'ctx>,
        r: BasicValueEnum<'ctx>,
        lt: &Ty,
        rt: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let b = &self.b;
        match lt {
            Ty::Float(_) => {
                let (l, r) = (l.into_float_value(), r.into_float_value());
                Ok(match op {
                    "+" => b.build_float_add(l, r, "")?.into(),
                    "-" => b.build_float_sub(l, r, "")?.into(),
                    "*" => b.build_float_mul(l, r, "")?.into(),
                    "/" => b.build_float_div(l, r, "")?.into(),
                    "%" => {
                        // fmod without libm: l - trunc(l / r) * r.
                        let q = b.build_float_div(l, r, "")?;
                        let t = self.float_unary("trunc", q.into(), lt)?.into_float_value();
                        let m = self.b.build_float_mul(t, r, "")?;
                        self.b.build_float_sub(l, m, "")?.into()
                    }
                    _ => {
                        let pred = match op {
                            "==" => FloatPredicate::OEQ,
                            "!=" => FloatPredicate::UNE,
                            "<" => FloatPredicate::OLT,
                            "<=" => FloatPredicate::OLE,
                            ">" => FloatPredicate::OGT,
                            _ => FloatPredicate::OGE,
                        };
                        b.build_float_compare(pred, l, r, "")?.into()
                    }
                })
            }
            Ty::Simd(_) => {
                let (l, r) = (l.into_vector_value(), r.into_vector_value());
                let fl = matches!(lt, Ty::Simd(crate::ty::SimdTy::F32x4));
                Ok(match (op, fl) {
                    ("+", true) => b.build_float_add(l, r, "")?.into(),
                    ("-", true) => b.build_float_sub(l, r, "")?.into(),
                    ("*", true) => b.build_float_mul(l, r, "")?.into(),
                    ("/", true) => b.build_float_div(l, r, "")?.into(),
                    ("+", false) => b.build_int_add(l, r, "")?.into(),
                    ("-", false) => b.build_int_sub(l, r, "")?.into(),
                    ("*", false) => b.build_int_mul(l, r, "")?.into(),
                    ("&", false) => b.build_and(l, r, "")?.into(),
                    ("|", false) => b.build_or(l, r, "")?.into(),
                    _ => b.build_xor(l, r, "")?.into(),
                })
            }
            Ty::Ptr(..) => {
                let i32t = self.ctx.i32_type();
                let l = b.build_ptr_to_int(l.into_pointer_value(), i32t, "")?;
                let r = b.build_ptr_to_int(r.into_pointer_value(), i32t, "")?;
                self.int_cmp(op, l, r, false)
            }
            _ => {
                let signed = int_of(lt).map(IntTy::signed).unwrap_or(false);
                let (l, r) = (l.into_int_value(), r.into_int_value());
                Ok(match op {
                    "+" => b.build_int_add(l, r, "")?.into(),
                    "-" => b.build_int_sub(l, r, "")?.into(),
                    "*" => b.build_int_mul(l, r, "")?.into(),
                    "&" => b.build_and(l, r, "")?.into(),
                    "|" => b.build_or(l, r, "")?.into(),
                    "^" => b.build_xor(l, r, "")?.into(),
                    "<<" | ">>" => {
                        let bits = l.get_type().get_bit_width();
                        let rs = int_of(rt).map(IntTy::signed).unwrap_or(false);
                        let amt = b.build_int_cast_sign_flag(r, l.get_type(), rs, "")?;
                        let amt =
                            b.build_and(amt, l.get_type().const_int(bits as u64 - 1, false), "")?;
                        if op == "<<" {
                            b.build_left_shift(l, amt, "")?.into()
                        } else {
                            b.build_right_shift(l, amt, signed, "")?.into()
                        }
                    }
                    "/" | "%" => self.int_div(op, l, r, signed)?.into(),
                    _ => self.int_cmp(op, l, r, signed)?,
                })
            }
        }
    }

    fn int_cmp(
        &mut self,
        op: &str,
        l: IntValue<'ctx>,
        r: IntValue<'ctx>,
        signed: bool,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let pred = match (op, signed) {
            ("==", _) => IntPredicate::EQ,
            ("!=", _) => IntPredicate::NE,
            ("<", true) => IntPredicate::SLT,
            ("<", false) => IntPredicate::ULT,
            ("<=", true) => IntPredicate::SLE,
            ("<=", false) => IntPredicate::ULE,
            (">", true) => IntPredicate::SGT,
            (">", false) => IntPredicate::UGT,
            (">=", true) => IntPredicate::SGE,
            _ => IntPredicate::UGE,
        };
        Ok(self.b.build_int_compare(pred, l, r, "")?.into())
    }

    fn int_div(
        &mut self,
        op: &str,
        l: IntValue<'ctx>,
        r: IntValue<'ctx>,
        signed: bool,
    ) -> LResult<IntValue<'ctx>> {
        let t = l.get_type();
        let nonzero = self
            .b
            .build_int_compare(IntPredicate::NE, r, t.const_zero(), "")?;
        let what = if op == "/" {
            "attempt to divide by zero"
        } else {
            "attempt to calculate the remainder with a divisor of zero"
        };
        self.check(nonzero, AbortKind::DivideByZero, what)?;
        if signed {
            let bits = t.get_bit_width();
            let min = t.const_int(1u64 << (bits - 1), false);
            let is_min = self.b.build_int_compare(IntPredicate::EQ, l, min, "")?;
            let is_m1 = self
                .b
                .build_int_compare(IntPredicate::EQ, r, t.const_all_ones(), "")?;
            let both = self.b.build_and(is_min, is_m1, "")?;
            let ok = self.b.build_not(both, "")?;
            let what = if op == "/" {
                "attempt to divide with overflow"
            } else {
                "attempt to calculate the remainder with overflow"
            };
            self.check(ok, AbortKind::Overflow, what)?;
        }
        Ok(match (op, signed) {
            ("/", true) => self.b.build_int_signed_div(l, r, "")?,
            ("/", false) => self.b.build_int_unsigned_div(l, r, "")?,
            (_, true) => self.b.build_int_signed_rem(l, r, "")?,
            _ => self.b.build_int_unsigned_rem(l, r, "")?,
        })
    }

    fn unary(&mut self, e: &Expr, u: &syn::ExprUnary, ty: &Ty) -> LResult<V<'ctx>> {
        if let Some(&f) = self.body.ops.get(&key(e)) {
            let it = self.ty_of(&u.expr);
            let v = self.expr(&u.expr)?;
            let v = self.val(v, &it);
            self.set_loc(e.span());
            return self.call_fn(f, vec![v], ty);
        }
        match u.op {
            UnOp::Deref(_) => {
                let p = self.place(e)?;
                Ok(Some(self.b.build_load(p, "")?))
            }
            UnOp::Not(_) => {
                let v = self.expr(&u.expr)?;
                let v = self.val(v, ty).into_int_value();
                Ok(Some(self.b.build_not(v, "")?.into()))
            }
            UnOp::Neg(_) => {
                let v = self.expr(&u.expr)?;
                let v = self.val(v, ty);
                Ok(Some(match ty {
                    Ty::Float(_) => self.b.build_float_neg(v.into_float_value(), "")?.into(),
                    Ty::Simd(crate::ty::SimdTy::F32x4) => {
                        self.simd_sign_bit(v.into_vector_value(), true)?
                    }
                    Ty::Simd(_) => self.b.build_int_neg(v.into_vector_value(), "")?.into(),
                    _ => self.b.build_int_neg(v.into_int_value(), "")?.into(),
                }))
            }
            _ => Err(LowerError::Internal("unary op".into())),
        }
    }

    /// `as` casts.
    pub(super) fn cast(
        &mut self,
        v: BasicValueEnum<'ctx>,
        from: &Ty,
        to: &Ty,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let tl = self.llty(to);
        let b = &self.b;
        Ok(match (from, to) {
            (a, b2) if a == b2 => v,
            (Ty::Int(f), Ty::Int(_)) => b
                .build_int_cast_sign_flag(v.into_int_value(), tl.into_int_type(), f.signed(), "")?
                .into(),
            (Ty::Bool | Ty::Char, Ty::Int(_)) => b
                .build_int_cast_sign_flag(v.into_int_value(), tl.into_int_type(), false, "")?
                .into(),
            (Ty::Int(_), Ty::Char) => b
                .build_int_z_extend(v.into_int_value(), tl.into_int_type(), "")?
                .into(),
            (Ty::Int(f), Ty::Float(_)) => {
                if f.signed() {
                    b.build_signed_int_to_float(v.into_int_value(), tl.into_float_type(), "")?
                        .into()
                } else {
                    b.build_unsigned_int_to_float(v.into_int_value(), tl.into_float_type(), "")?
                        .into()
                }
            }
            (Ty::Float(_), Ty::Float(_)) => b
                .build_float_cast(v.into_float_value(), tl.into_float_type(), "")?
                .into(),
            (Ty::Float(f), Ty::Int(i)) => {
                // Saturating, NaN → 0, like Rust.
                let name = format!(
                    "llvm.fpto{}i.sat.i{}.{}",
                    if i.signed() { "s" } else { "u" },
                    i.bits(),
                    if *f == FloatTy::F32 { "f32" } else { "f64" }
                );
                let fty = tl.into_int_type().fn_type(&[self.llty(from).into()], false);
                let func = self
                    .module
                    .get_function(&name)
                    .unwrap_or_else(|| self.module.add_function(&name, fty, None));
                self.b
                    .build_call(func, &[v.into()], "")?
                    .try_as_basic_value()
                    .basic()
                    .ok_or_else(|| LowerError::Internal("cast call".into()))?
            }
            (Ty::Ptr(..) | Ty::Ref(..), Ty::Ptr(..)) => b
                .build_pointer_cast(v.into_pointer_value(), tl.into_pointer_type(), "")?
                .into(),
            (Ty::Ptr(..), Ty::Int(_)) => b
                .build_ptr_to_int(v.into_pointer_value(), tl.into_int_type(), "")?
                .into(),
            (Ty::Int(_), Ty::Ptr(..)) => b
                .build_int_to_ptr(v.into_int_value(), tl.into_pointer_type(), "")?
                .into(),
            _ => {
                return Err(LowerError::Internal(format!(
                    "cast {} as {}",
                    self.p.ty_str(from),
                    self.p.ty_str(to)
                )))
            }
        })
    }

    // ---------------------------------------------------------------- control flow

    fn if_expr(&mut self, i: &syn::ExprIf, ty: &Ty) -> LResult<V<'ctx>> {
        let c = self.expr(&i.cond)?;
        let c = self.val(c, &Ty::Bool).into_int_value();
        let slot = if ty.is_zst() {
            None
        } else {
            Some(self.alloca(ty, "if.value")?)
        };
        let then_bb = self.new_block("if.then");
        let else_bb = self.new_block("if.else");
        let end = self.new_block("if.end");
        self.b.build_conditional_branch(c, then_bb, else_bb)?;
        self.b.position_at_end(then_bb);
        let tv = self.block(&i.then_branch, true)?;
        if let (Some(s), Some(v)) = (slot, tv) {
            if !self.terminated() {
                self.b.build_store(s, v)?;
            }
        }
        self.br(end)?;
        self.b.position_at_end(else_bb);
        if let Some((_, els)) = &i.else_branch {
            let ev = self.expr(els)?;
            if let (Some(s), Some(v)) = (slot, ev) {
                if !self.terminated() {
                    self.b.build_store(s, v)?;
                }
            }
        }
        self.br(end)?;
        self.b.position_at_end(end);
        match slot {
            Some(s) => Ok(Some(self.b.build_load(s, "")?)),
            None => Ok(None),
        }
    }

    fn bind_loop_var(&mut self, pat: &Pat, ty: &Ty, v: BasicValueEnum<'ctx>) -> LResult<()> {
        if let Pat::Ident(pi) = pat {
            if let Some(&id) = self.body.pat_locals.get(&key(pi)) {
                let slot = match self.fs().locals.get(&id) {
                    Some(s) => *s,
                    None => {
                        let s = self.alloca(ty, &pi.ident.to_string())?;
                        self.declare_var(s, &pi.ident.to_string(), ty, pi.ident.span(), None);
                        self.fs().locals.insert(id, s);
                        s
                    }
                };
                self.b.build_store(slot, v)?;
            }
        }
        Ok(())
    }

    fn for_loop(&mut self, e: &Expr, f: &syn::ExprForLoop) -> LResult<V<'ctx>> {
        let kind = self
            .body
            .fors
            .get(&key(e))
            .copied()
            .ok_or_else(|| LowerError::Internal("for kind".into()))?;
        let it = classify_for(&f.expr).ok_or_else(|| LowerError::Internal("for iter".into()))?;
        let label = f.label.as_ref().map(|l| l.name.ident.to_string());
        let prev = self.push_scope(f.for_token.span);
        match kind {
            ForKind::Range { inclusive, rev } => {
                let ty = self.ty_of(it.start);
                let signed = int_of(&ty).map(IntTy::signed).unwrap_or(false);
                let s = self.expr(it.start)?;
                let s = self.val(s, &ty).into_int_value();
                let en = self.expr(it.end.expect("range end"))?;
                let en = self.val(en, &ty).into_int_value();
                let step = match it.step {
                    Some(st) => {
                        let v = self.expr(st)?;
                        let v = self.val(v, &Ty::Int(IntTy::Usize)).into_int_value();
                        let nz = self.b.build_int_compare(
                            IntPredicate::NE,
                            v,
                            v.get_type().const_zero(),
                            "",
                        )?;
                        self.check(nz, AbortKind::Panic, "assertion failed: step != 0")?;
                        Some(
                            self.b
                                .build_int_cast_sign_flag(v, s.get_type(), false, "")?,
                        )
                    }
                    None => None,
                };
                let one = s.get_type().const_int(1, false);
                let cur = self.alloca(&ty, "for.cur")?;
                // Empty check and first value.
                let lt = if signed {
                    IntPredicate::SLT
                } else {
                    IntPredicate::ULT
                };
                let le = if signed {
                    IntPredicate::SLE
                } else {
                    IntPredicate::ULE
                };
                let nonempty =
                    self.b
                        .build_int_compare(if inclusive { le } else { lt }, s, en, "")?;
                let first = if rev {
                    if inclusive {
                        en
                    } else {
                        self.b.build_int_sub(en, one, "")?
                    }
                } else {
                    s
                };
                self.b.build_store(cur, first)?;
                let body = self.new_block("for.body");
                let latch = self.new_block("for.next");
                let exit = self.new_block("for.end");
                self.b.build_conditional_branch(nonempty, body, exit)?;
                self.b.position_at_end(body);
                let v = self.b.build_load(cur, "")?;
                self.bind_loop_var(&f.pat, &ty, v)?;
                self.fs().loops.push(LoopTarget {
                    label,
                    brk: exit,
                    cont: latch,
                    slot: None,
                });
                let r = self.block(&f.body, true);
                self.fs().loops.pop();
                r?;
                self.br(latch)?;
                self.b.position_at_end(latch);
                let c = self.b.build_load(cur, "")?.into_int_value();
                // Last value reached? (avoids overflow at the type's bounds)
                let last = if rev {
                    s
                } else if inclusive {
                    en
                } else {
                    self.b.build_int_sub(en, one, "")?
                };
                match step {
                    None => {
                        let done =
                            self.b
                                .build_int_compare(inkwell::IntPredicate::EQ, c, last, "")?;
                        let nx = if rev {
                            self.b.build_int_sub(c, one, "")?
                        } else {
                            self.b.build_int_add(c, one, "")?
                        };
                        self.b.build_store(cur, nx)?;
                        self.b.build_conditional_branch(done, exit, body)?;
                    }
                    Some(stp) => {
                        // Continue while last - c >= step (unsigned distance).
                        let dist = self.b.build_int_sub(last, c, "")?;
                        let more = self.b.build_int_compare(IntPredicate::UGE, dist, stp, "")?;
                        let nx = self.b.build_int_add(c, stp, "")?;
                        self.b.build_store(cur, nx)?;
                        self.b.build_conditional_branch(more, body, exit)?;
                    }
                }
                self.b.position_at_end(exit);
            }
            ForKind::Array { by_ref, derefs } => {
                let base = self.deref_base(it.start, derefs)?;
                let mut at = self.ty_of(it.start);
                while let Ty::Ref(_, inner) = at {
                    at = *inner;
                }
                let Ty::Array(et, n) = at else {
                    return Err(LowerError::Internal("for over non-array".into()));
                };
                let i32t = self.ctx.i32_type();
                let idx = self.alloca(&Ty::Int(IntTy::Usize), "for.idx")?;
                self.b.build_store(idx, i32t.const_zero())?;
                let head = self.new_block("for.cond");
                let body = self.new_block("for.body");
                let latch = self.new_block("for.next");
                let exit = self.new_block("for.end");
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(head);
                let iv = self.b.build_load(idx, "")?.into_int_value();
                let c = self.b.build_int_compare(
                    IntPredicate::ULT,
                    iv,
                    i32t.const_int(n as u64, false),
                    "",
                )?;
                self.b.build_conditional_branch(c, body, exit)?;
                self.b.position_at_end(body);
                // SAFETY: `iv < n` on this path.
                let ep = unsafe {
                    self.b
                        .build_in_bounds_gep(base, &[i32t.const_zero(), iv], "")?
                };
                let (vt, v) = if by_ref {
                    (Ty::Ref(false, et.clone()), ep.as_basic_value_enum())
                } else {
                    (*et.clone(), self.b.build_load(ep, "")?)
                };
                self.bind_loop_var(&f.pat, &vt, v)?;
                self.fs().loops.push(LoopTarget {
                    label,
                    brk: exit,
                    cont: latch,
                    slot: None,
                });
                let r = self.block(&f.body, true);
                self.fs().loops.pop();
                r?;
                self.br(latch)?;
                self.b.position_at_end(latch);
                let iv = self.b.build_load(idx, "")?.into_int_value();
                let nx = self.b.build_int_add(iv, i32t.const_int(1, false), "")?;
                self.b.build_store(idx, nx)?;
                self.b.build_unconditional_branch(head)?;
                self.b.position_at_end(exit);
            }
        }
        self.pop_scope(prev);
        Ok(None)
    }

    fn match_expr(&mut self, m: &syn::ExprMatch, ty: &Ty) -> LResult<V<'ctx>> {
        let st = self.ty_of(&m.expr);
        let sv = self.expr(&m.expr)?;
        let sv = self.val(sv, &st).into_int_value();
        let slot = if ty.is_zst() {
            None
        } else {
            Some(self.alloca(ty, "match.value")?)
        };
        let end = self.new_block("match.end");
        for arm in &m.arms {
            let (pat, guard) = match &arm.pat {
                Pat::Guard(g) => (&*g.pat, Some(&*g.guard)),
                p => (p, None),
            };
            let body_bb = self.new_block("arm.body");
            let next = self.new_block("arm.next");
            self.set_loc(arm.pat.span());
            let c = self.pattern_test(pat, sv, &st)?;
            let test_ok = self.new_block("arm.bind");
            self.b.build_conditional_branch(c, test_ok, next)?;
            self.b.position_at_end(test_ok);
            let prev = self.push_scope(arm.pat.span());
            self.bind_pattern(pat, sv, &st)?;
            match guard {
                Some(g) => {
                    let gv = self.expr(g)?;
                    let gv = self.val(gv, &Ty::Bool).into_int_value();
                    self.b.build_conditional_branch(gv, body_bb, next)?;
                }
                None => {
                    self.b.build_unconditional_branch(body_bb)?;
                }
            }
            self.b.position_at_end(body_bb);
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

    fn pat_const(&mut self, e: &Expr, t: &Ty) -> LResult<IntValue<'ctx>> {
        let it = self.llty(t).into_int_type();
        let v: i128 = match e {
            Expr::Lit(l) => match &l.lit {
                Lit::Bool(b) => b.value as i128,
                Lit::Char(c) => c.value() as i128,
                Lit::Byte(c) => c.value() as i128,
                _ => self.p.eval_int(self.module_id, self.file, e, 0)?,
            },
            _ => self.p.eval_int(self.module_id, self.file, e, 0)?,
        };
        Ok(it.const_int(v as u64, false))
    }

    fn pattern_test(&mut self, pat: &Pat, v: IntValue<'ctx>, t: &Ty) -> LResult<IntValue<'ctx>> {
        let tru = self.ctx.bool_type().const_int(1, false);
        let signed = int_of(t).map(IntTy::signed).unwrap_or(false);
        Ok(match pat {
            Pat::Wild(_) => tru,
            Pat::Ident(pi) => match self.body.pat_locals.get(&key(pi)) {
                Some(_) => tru,
                None => {
                    let e = Expr::Path(syn::ExprPath {
                        attrs: vec![],
                        qself: None,
                        path: pi.ident.clone().into(),
                    });
                    let c = self.pat_const(&e, t)?;
                    self.b.build_int_compare(IntPredicate::EQ, v, c, "")?
                }
            },
            Pat::Paren(p) => self.pattern_test(&p.pat, v, t)?,
            Pat::Or(o) => {
                let mut acc = self.ctx.bool_type().const_zero();
                for c in &o.cases {
                    let x = self.pattern_test(c, v, t)?;
                    acc = self.b.build_or(acc, x, "")?;
                }
                acc
            }
            Pat::Lit(l) => {
                let e = Expr::Lit(l.clone());
                let c = self.pat_const(&e, t)?;
                self.b.build_int_compare(IntPredicate::EQ, v, c, "")?
            }
            Pat::Path(p) => {
                let e = Expr::Path(p.clone());
                let c = self.pat_const(&e, t)?;
                self.b.build_int_compare(IntPredicate::EQ, v, c, "")?
            }
            Pat::Range(r) => {
                let mut acc = tru;
                if let Some(s) = &r.start {
                    let c = self.pat_const(s, t)?;
                    let x = self.b.build_int_compare(
                        if signed {
                            IntPredicate::SGE
                        } else {
                            IntPredicate::UGE
                        },
                        v,
                        c,
                        "",
                    )?;
                    acc = self.b.build_and(acc, x, "")?;
                }
                if let Some(e) = &r.end {
                    let c = self.pat_const(e, t)?;
                    let pred = match (&r.limits, signed) {
                        (syn::RangeLimits::Closed(_), true) => IntPredicate::SLE,
                        (syn::RangeLimits::Closed(_), false) => IntPredicate::ULE,
                        (_, true) => IntPredicate::SLT,
                        (_, false) => IntPredicate::ULT,
                    };
                    let x = self.b.build_int_compare(pred, v, c, "")?;
                    acc = self.b.build_and(acc, x, "")?;
                }
                acc
            }
            other => {
                return Err(self.err(other.span(), "unsupported-pattern", "unsupported pattern"))
            }
        })
    }

    fn bind_pattern(&mut self, pat: &Pat, v: IntValue<'ctx>, t: &Ty) -> LResult<()> {
        if let Pat::Ident(pi) = pat {
            if let Some(&id) = self.body.pat_locals.get(&key(pi)) {
                let slot = self.alloca(t, &pi.ident.to_string())?;
                self.declare_var(slot, &pi.ident.to_string(), t, pi.ident.span(), None);
                self.b.build_store(slot, v)?;
                self.fs().locals.insert(id, slot);
            }
        }
        Ok(())
    }

    // ---------------------------------------------------------------- calls

    fn call(&mut self, e: &Expr, recv: Option<&Expr>, args: &[&Expr], ty: &Ty) -> LResult<V<'ctx>> {
        let callee = *self
            .body
            .callees
            .get(&key(e))
            .ok_or_else(|| LowerError::Internal("unresolved call".into()))?;
        let mut vals = Vec::new();
        match callee {
            Callee::Fn {
                func,
                derefs,
                autoref,
            } => {
                if let Some(r) = recv {
                    if autoref {
                        vals.push(self.deref_base(r, derefs)?.into());
                    } else if derefs > 0 {
                        let p = self.deref_base(r, derefs)?;
                        vals.push(self.b.build_load(p, "")?);
                    } else {
                        let t = self.ty_of(r);
                        let v = self.expr(r)?;
                        vals.push(self.val(v, &t));
                    }
                }
                for a in args {
                    let t = self.ty_of(a);
                    let v = self.expr(a)?;
                    vals.push(self.val(v, &t));
                }
                self.set_loc(e.span());
                self.call_fn(func, vals, ty)
            }
            Callee::Builtin { b, derefs } => {
                let mut tys = Vec::new();
                if let Some(r) = recv {
                    let mut t = self.ty_of(r);
                    if derefs > 0 {
                        let p = self.deref_base(r, derefs)?;
                        vals.push(self.b.build_load(p, "")?);
                        for _ in 0..derefs {
                            if let Ty::Ref(_, inner) = t {
                                t = *inner;
                            }
                        }
                    } else {
                        let v = self.expr(r)?;
                        vals.push(self.val(v, &t));
                    }
                    tys.push(t);
                }
                for a in args {
                    let t = self.ty_of(a);
                    let v = self.expr(a)?;
                    vals.push(self.val(v, &t));
                    tys.push(t);
                }
                self.set_loc(e.span());
                self.builtin(b, &vals, &tys, ty)
            }
        }
    }

    /// Calls a user function.
    pub(super) fn call_fn(
        &mut self,
        f: crate::resolve::FnId,
        args: Vec<BasicValueEnum<'ctx>>,
        ty: &Ty,
    ) -> LResult<V<'ctx>> {
        let fv = self.declare_fn(f);
        let args: Vec<_> = args.into_iter().map(Into::into).collect();
        let cs = self.b.build_call(fv, &args, "")?;
        if matches!(ty, Ty::Never) {
            self.b.build_unreachable()?;
            return Ok(None);
        }
        Ok(cs.try_as_basic_value().basic())
    }
}

fn is_scalar(t: &Ty) -> bool {
    !matches!(t, Ty::Array(..) | Ty::Struct(_))
}

fn const_array<'ctx>(
    et: BasicTypeEnum<'ctx>,
    vals: &[BasicValueEnum<'ctx>],
) -> BasicValueEnum<'ctx> {
    match et {
        BasicTypeEnum::IntType(t) => t
            .const_array(&vals.iter().map(|v| v.into_int_value()).collect::<Vec<_>>())
            .into(),
        BasicTypeEnum::FloatType(t) => t
            .const_array(
                &vals
                    .iter()
                    .map(|v| v.into_float_value())
                    .collect::<Vec<_>>(),
            )
            .into(),
        BasicTypeEnum::StructType(t) => t
            .const_array(
                &vals
                    .iter()
                    .map(|v| v.into_struct_value())
                    .collect::<Vec<_>>(),
            )
            .into(),
        BasicTypeEnum::ArrayType(t) => t
            .const_array(
                &vals
                    .iter()
                    .map(|v| v.into_array_value())
                    .collect::<Vec<_>>(),
            )
            .into(),
        BasicTypeEnum::PointerType(t) => t
            .const_array(
                &vals
                    .iter()
                    .map(|v| v.into_pointer_value())
                    .collect::<Vec<_>>(),
            )
            .into(),
        BasicTypeEnum::VectorType(t) => t
            .const_array(
                &vals
                    .iter()
                    .map(|v| v.into_vector_value())
                    .collect::<Vec<_>>(),
            )
            .into(),
        BasicTypeEnum::ScalableVectorType(_) => unreachable!("TRaX has no scalable vectors"),
    }
}

#[allow(dead_code)]
fn span_of(e: &Expr) -> Span {
    e.span()
}
