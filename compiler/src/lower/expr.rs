//! Lowering of blocks, statements and expressions.

use super::{int_of, internal, LResult, LoopTarget, Lowerer, V};
use crate::ops::{BinOp, UnOp};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, SimdTy, Ty};
use crate::typeck::{key, Adjust, OpCall, Res};
use inkwell::types::BasicTypeEnum;
use inkwell::values::{BasicValueEnum, IntValue};
use inkwell::{FloatPredicate, IntPredicate};
use syn::{Expr, Lit, Pat, Stmt};
use trax_runtime::isa::AbortKind;

/// Elements above which `let a = [v; N]` is filled in place by a loop instead of built as
/// an aggregate value (local arrays of the examples and the prelude have at most 64).
const LARGE_REPEAT: u32 = 1024;

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

    /// A `let` statement: its bindings' slots, filled from the initializer.
    fn let_stmt(&mut self, l: &syn::Local) -> LResult<()> {
        let pat = match &l.pat {
            Pat::Type(pt) => &*pt.pat,
            p => p,
        };
        let Some(init) = &l.init else {
            // `let x;`: declare the bindings' slots.
            return self.declare_pat(pat);
        };
        self.set_loc(init.expr.span());
        // A plain binding keeps its value in its own slot.
        if let Pat::Ident(pi) = pat {
            if pi.subpat.is_none() {
                if let Some((id, crate::typeck::BindMode::Value)) =
                    self.body.binds.get(&key(pi)).copied()
                {
                    let ty = self.body.locals[id].ty.clone();
                    if let (Expr::Repeat(r), Ty::Array(et, n)) = (&*init.expr, &ty) {
                        if *n > LARGE_REPEAT && self.ty_of(&init.expr) == ty {
                            // `let a = [v; N]` with a large N: filled in place by a loop,
                            // never an N-element aggregate value (LLVM's backend expands
                            // those element by element: N = 10^6 took 32 s and 1.3 GB,
                            // 4·10^6 crashed it).
                            let v = self.expr(&r.expr)?;
                            self.set_loc(pi.ident.span());
                            let slot = self.alloca(&ty, &pi.ident.to_string())?;
                            self.declare_var(
                                slot,
                                &pi.ident.to_string(),
                                &ty,
                                pi.ident.span(),
                                None,
                            );
                            if let Some(v) = v {
                                if !self.terminated() {
                                    let v = self.val(Some(v), et);
                                    self.fill_loop(slot, *n, v)?;
                                }
                            }
                            self.fs().locals.insert(id, slot);
                            return Ok(());
                        }
                    }
                    let v = self.expr(&init.expr)?;
                    self.set_loc(pi.ident.span());
                    let slot = self.alloca(&ty, &pi.ident.to_string())?;
                    self.declare_var(slot, &pi.ident.to_string(), &ty, pi.ident.span(), None);
                    if let Some(v) = v {
                        if !self.terminated() {
                            self.b.build_store(slot, v)?;
                        }
                    }
                    self.fs().locals.insert(id, slot);
                    return Ok(());
                }
            }
        }
        let ty = self.ty_of(&init.expr);
        let place = self.place_or_temp(&init.expr)?;
        if self.terminated() {
            return self.declare_pat(pat);
        }
        let fail = self.new_block("let.else");
        self.match_pat(pat, place, &ty, fail)?;
        let cont = self
            .b
            .get_insert_block()
            .ok_or_else(|| internal("no block"))?;
        self.b.position_at_end(fail);
        match &init.diverge {
            Some((_, els)) => {
                self.expr(els)?;
                if !self.terminated() {
                    self.b.build_unreachable()?;
                }
            }
            None => {
                self.b.build_unreachable()?;
            }
        }
        self.b.position_at_end(cont);
        Ok(())
    }

    // ---------------------------------------------------------------- expressions

    /// Lowers an expression to its value (after its coercion, if any).
    pub(super) fn expr(&mut self, e: &Expr) -> LResult<V<'ctx>> {
        self.set_loc(e.span());
        let ty = self.raw_ty(e);
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
        self.adjust(e, v, &ty)
    }

    /// Applies the coercion recorded for `e` to its value.
    fn adjust(&mut self, e: &Expr, v: V<'ctx>, ty: &Ty) -> LResult<V<'ctx>> {
        match self.body.adjust.get(&key(e)) {
            None => Ok(v),
            Some(Adjust::Deref(n)) => {
                let mut v = self.val(v, ty);
                for _ in 0..*n {
                    v = self.b.build_load(v.into_pointer_value(), "")?;
                }
                Ok(Some(v))
            }
            Some(Adjust::Unsize(n)) => {
                let Ty::Ref(_, inner) = ty else {
                    return Err(internal("unsize of a non-reference"));
                };
                let Ty::Array(el, _) = &**inner else {
                    return Err(internal("unsize of a non-array"));
                };
                let p = self.val(v, ty).into_pointer_value();
                Ok(Some(
                    self.make_slice(p, el, self.ctx.i32_type().const_int(*n as u64, false))?
                        .into(),
                ))
            }
        }
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
                let prev = self.push_scope(w.while_token.span);
                self.cond(&w.cond, exit)?;
                self.br(body)?;
                self.b.position_at_end(body);
                self.fs().loops.push(LoopTarget {
                    label: w.label.as_ref().map(|l| l.name.ident.to_string()),
                    brk: exit,
                    cont: head,
                    slot: None,
                });
                let r = self.block(&w.body, true);
                self.fs().loops.pop();
                self.pop_scope(prev);
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
                if let Some(crate::typeck::Callee::Closure { ty: ct, derefs }) =
                    self.body.callees.get(&key(e)).cloned()
                {
                    return self.closure_call(e, c, &ct, derefs, ty);
                }
                let args: Vec<&Expr> = c.args.iter().collect();
                self.call(e, None, &args, ty)
            }
            Expr::Closure(_) => self.closure_value(e, ty),
            Expr::MethodCall(m) => {
                let args: Vec<&Expr> = m.args.iter().collect();
                self.call(e, Some(&m.receiver), &args, ty)
            }
            Expr::Field(_) | Expr::Index(_) => {
                let p = self.place(e)?;
                Ok(Some(self.b.build_load(p, "")?))
            }
            Expr::Reference(r) => {
                if let Some(v) = self.slice_ref(&r.expr)? {
                    return Ok(Some(v));
                }
                let p = self.place_or_temp(&r.expr)?;
                Ok(Some(p.into()))
            }
            Expr::Array(a) => {
                let lt = self.llty(ty);
                let mut agg = super::undef(lt).into_array_value();
                let Ty::Array(et, _) = ty else {
                    return Err(internal("array type"));
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
                    return Err(internal("repeat type"));
                };
                let v = self.expr(&r.expr)?;
                let v = self.val(v, et);
                if super::is_const(v) {
                    let vals = vec![v; *n as usize];
                    return Ok(Some(const_array(self.llty(et), &vals)));
                }
                // Runtime element: fill a stack slot with a loop.
                let slot = self.alloca(ty, "repeat")?;
                self.fill_loop(slot, *n, v)?;
                Ok(Some(self.b.build_load(slot, "")?))
            }
            Expr::Struct(s) => self.struct_lit(e, s, ty),
            Expr::Tuple(t) => {
                let Ty::Tuple(ts) = ty else {
                    return Ok(None);
                };
                let lt = self.llty(ty).into_struct_type();
                let mut agg = lt.get_undef();
                for (i, x) in t.elems.iter().enumerate() {
                    let v = self.expr(x)?;
                    let v = self.val(v, &ts[i]);
                    agg = self
                        .b
                        .build_insert_value(agg, v, i as u32, "")?
                        .into_struct_value();
                }
                Ok(Some(agg.into()))
            }
            Expr::Match(m) => self.match_expr(m, ty),
            Expr::Macro(m) => self.mac(&m.mac),
            Expr::Try(t) => self.try_expr(e, t, ty),
            other => Err(internal(format!(
                "unsupported expression reached lowering at line {}",
                crate::diag::Loc::of(other.span()).line
            ))),
        }
    }

    /// Stores `v` into each of the `n` elements of the array at `slot`.
    /// Fills the `n` elements of the array at `slot` with `v`, in a loop.
    pub(super) fn fill_loop(
        &mut self,
        slot: inkwell::values::PointerValue<'ctx>,
        n: u32,
        v: BasicValueEnum<'ctx>,
    ) -> LResult<()> {
        let i32t = self.ctx.i32_type();
        let idx = self.alloca(&Ty::Int(IntTy::U32), "fill.i")?;
        self.b.build_store(idx, i32t.const_zero())?;
        let head = self.new_block("fill.cond");
        let body = self.new_block("fill.body");
        let exit = self.new_block("fill.end");
        self.b.build_unconditional_branch(head)?;
        self.b.position_at_end(head);
        let iv = self.b.build_load(idx, "")?.into_int_value();
        let c =
            self.b
                .build_int_compare(IntPredicate::ULT, iv, i32t.const_int(n as u64, false), "")?;
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
        Ok(())
    }

    fn loop_target(
        &mut self,
        label: Option<&str>,
    ) -> LResult<(
        inkwell::basic_block::BasicBlock<'ctx>,
        inkwell::basic_block::BasicBlock<'ctx>,
        Option<inkwell::values::PointerValue<'ctx>>,
    )> {
        let loops = &self.fs().loops;
        let t = match label {
            None => loops.last(),
            Some(l) => loops.iter().rev().find(|t| t.label.as_deref() == Some(l)),
        };
        t.map(|t| (t.brk, t.cont, t.slot))
            .ok_or_else(|| internal("loop target"))
    }

    pub(super) fn lit(&mut self, l: &Lit, ty: &Ty) -> LResult<BasicValueEnum<'ctx>> {
        Ok(match (l, ty) {
            (Lit::Int(i), Ty::Int(it)) => {
                let v: i128 = i
                    .base10_parse()
                    .map_err(|_| internal("bad integer literal"))?;
                self.int_ty(it.bits()).const_int(v as u64, false).into()
            }
            (Lit::Int(i), Ty::Float(f)) => {
                let v = i
                    .base10_parse::<i128>()
                    .map(|v| v as f64)
                    .map_err(|_| internal("bad literal"))?;
                self.float_const(*f, v)
            }
            (Lit::Float(x), Ty::Float(f)) => {
                let v: f64 = match f {
                    FloatTy::F32 => x.base10_parse::<f32>().map(|v| v as f64),
                    FloatTy::F64 => x.base10_parse::<f64>(),
                }
                .map_err(|_| internal("bad float literal"))?;
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
            _ => return Err(internal("unsupported literal")),
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
            Some(Res::Unit(_, v)) => Ok(Some(self.build_adt(ty, v, &[])?)),
            Some(Res::Global(g, substs))
                if self.p.globals[g].is_static.is_none() && is_scalar(ty) =>
            {
                if let Some(v) = self.consts.get(&(g, substs.clone())) {
                    if let Some(c) = self.const_val(ty, v)? {
                        return Ok(Some(c));
                    }
                }
                let gd = &self.p.globals[g];
                if self.const_depth > 64 {
                    return Err(internal(format!("constant `{}` refers to itself", gd.name)));
                }
                let expr = gd.expr.ok_or_else(|| internal("const without value"))?;
                self.const_depth += 1;
                let r = self.with_body(g, &substs, |l| l.expr(expr));
                self.const_depth -= 1;
                r
            }
            _ => {
                let p = self.place(e)?;
                Ok(Some(self.b.build_load(p, "")?))
            }
        }
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
        let (op, assign) = BinOp::of(&b.op);
        if let Some(o) = self.body.ops.get(&key(e)).cloned() {
            return self.op_call(e, &o, &b.left, &b.right, op, assign, ty);
        }
        if matches!(op, BinOp::And | BinOp::Or) {
            let is_and = op == BinOp::And;
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
            return Ok(Some(self.b.build_load(slot, "")?));
        }
        if assign {
            let lt = self.raw_ty(&b.left);
            let rt = self.ty_of(&b.right);
            let r = self.expr(&b.right)?;
            let r = self.val(r, &rt);
            let p = self.place(&b.left)?;
            let l = self.b.build_load(p, "")?;
            self.set_loc(e.span());
            let v = self.arith(op, l, r, &lt, &rt)?;
            self.b.build_store(p, v)?;
            return Ok(None);
        }
        let lt = self.ty_of(&b.left);
        let rt = self.ty_of(&b.right);
        let l = self.expr(&b.left)?;
        let l = self.val(l, &lt);
        let r = self.expr(&b.right)?;
        let r = self.val(r, &rt);
        self.set_loc(e.span());
        Ok(Some(self.arith(op, l, r, &lt, &rt)?))
    }

    /// Applies a primitive binary operator.
    pub(super) fn arith(
        &mut self,
        op: BinOp,
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
                    BinOp::Add => b.build_float_add(l, r, "")?.into(),
                    BinOp::Sub => b.build_float_sub(l, r, "")?.into(),
                    BinOp::Mul => b.build_float_mul(l, r, "")?.into(),
                    BinOp::Div => b.build_float_div(l, r, "")?.into(),
                    BinOp::Rem => {
                        // Exact fmod: the prelude's `lang::fmodf`/`fmod`.
                        let name = if matches!(lt, Ty::Float(FloatTy::F64)) {
                            "fmod"
                        } else {
                            "fmodf"
                        };
                        if let Some(f) = self.p.lang_fn(name) {
                            let v = self.call_fn(f, &[], vec![l.into(), r.into()], lt)?;
                            return v.ok_or_else(|| internal("fmod"));
                        }
                        // Without the prelude: l - trunc(l / r) * r.
                        let q = b.build_float_div(l, r, "")?;
                        let t = self
                            .float_unary(crate::builtins::Builtin::FTrunc, q.into(), lt)?
                            .into_float_value();
                        let m = self.b.build_float_mul(t, r, "")?;
                        self.b.build_float_sub(l, m, "")?.into()
                    }
                    _ => {
                        let pred = match op {
                            BinOp::Eq => FloatPredicate::OEQ,
                            BinOp::Ne => FloatPredicate::UNE,
                            BinOp::Lt => FloatPredicate::OLT,
                            BinOp::Le => FloatPredicate::OLE,
                            BinOp::Gt => FloatPredicate::OGT,
                            _ => FloatPredicate::OGE,
                        };
                        b.build_float_compare(pred, l, r, "")?.into()
                    }
                })
            }
            Ty::Simd(_) => {
                let (l, r) = (l.into_vector_value(), r.into_vector_value());
                let fl = matches!(lt, Ty::Simd(SimdTy::F32x4));
                Ok(match (op, fl) {
                    (BinOp::Add, true) => b.build_float_add(l, r, "")?.into(),
                    (BinOp::Sub, true) => b.build_float_sub(l, r, "")?.into(),
                    (BinOp::Mul, true) => b.build_float_mul(l, r, "")?.into(),
                    (BinOp::Div, true) => b.build_float_div(l, r, "")?.into(),
                    (BinOp::Add, false) => b.build_int_add(l, r, "")?.into(),
                    (BinOp::Sub, false) => b.build_int_sub(l, r, "")?.into(),
                    (BinOp::Mul, false) => b.build_int_mul(l, r, "")?.into(),
                    (BinOp::BitAnd, false) => b.build_and(l, r, "")?.into(),
                    (BinOp::BitOr, false) => b.build_or(l, r, "")?.into(),
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
                    BinOp::Add => b.build_int_add(l, r, "")?.into(),
                    BinOp::Sub => b.build_int_sub(l, r, "")?.into(),
                    BinOp::Mul => b.build_int_mul(l, r, "")?.into(),
                    BinOp::BitAnd => b.build_and(l, r, "")?.into(),
                    BinOp::BitOr => b.build_or(l, r, "")?.into(),
                    BinOp::BitXor => b.build_xor(l, r, "")?.into(),
                    BinOp::Shl | BinOp::Shr => {
                        let bits = l.get_type().get_bit_width();
                        let rs = int_of(rt).map(IntTy::signed).unwrap_or(false);
                        let amt = b.build_int_cast_sign_flag(r, l.get_type(), rs, "")?;
                        let amt =
                            b.build_and(amt, l.get_type().const_int(bits as u64 - 1, false), "")?;
                        if op == BinOp::Shl {
                            b.build_left_shift(l, amt, "")?.into()
                        } else {
                            b.build_right_shift(l, amt, signed, "")?.into()
                        }
                    }
                    BinOp::Div | BinOp::Rem => self.int_div(op, l, r, signed)?.into(),
                    _ => self.int_cmp(op, l, r, signed)?,
                })
            }
        }
    }

    pub(super) fn int_cmp(
        &mut self,
        op: BinOp,
        l: IntValue<'ctx>,
        r: IntValue<'ctx>,
        signed: bool,
    ) -> LResult<BasicValueEnum<'ctx>> {
        let pred = match (op, signed) {
            (BinOp::Eq, _) => IntPredicate::EQ,
            (BinOp::Ne, _) => IntPredicate::NE,
            (BinOp::Lt, true) => IntPredicate::SLT,
            (BinOp::Lt, false) => IntPredicate::ULT,
            (BinOp::Le, true) => IntPredicate::SLE,
            (BinOp::Le, false) => IntPredicate::ULE,
            (BinOp::Gt, true) => IntPredicate::SGT,
            (BinOp::Gt, false) => IntPredicate::UGT,
            (BinOp::Ge, true) => IntPredicate::SGE,
            _ => IntPredicate::UGE,
        };
        Ok(self.b.build_int_compare(pred, l, r, "")?.into())
    }

    pub(super) fn int_div(
        &mut self,
        op: BinOp,
        l: IntValue<'ctx>,
        r: IntValue<'ctx>,
        signed: bool,
    ) -> LResult<IntValue<'ctx>> {
        let t = l.get_type();
        let nonzero = self
            .b
            .build_int_compare(IntPredicate::NE, r, t.const_zero(), "")?;
        let what = if op == BinOp::Div {
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
            let what = if op == BinOp::Div {
                "attempt to divide with overflow"
            } else {
                "attempt to calculate the remainder with overflow"
            };
            self.check(ok, AbortKind::Overflow, what)?;
        }
        Ok(match (op, signed) {
            (BinOp::Div, true) => self.b.build_int_signed_div(l, r, "")?,
            (BinOp::Div, false) => self.b.build_int_unsigned_div(l, r, "")?,
            (_, true) => self.b.build_int_signed_rem(l, r, "")?,
            _ => self.b.build_int_unsigned_rem(l, r, "")?,
        })
    }

    fn unary(&mut self, e: &Expr, u: &syn::ExprUnary, ty: &Ty) -> LResult<V<'ctx>> {
        if let Some(OpCall::Fn { func, substs, .. }) = self.body.ops.get(&key(e)).cloned() {
            let it = self.ty_of(&u.expr);
            let v = self.expr(&u.expr)?;
            let v = self.val(v, &it);
            self.set_loc(e.span());
            return self.call_fn(func, &substs, vec![v], ty);
        }
        match UnOp::of(&u.op) {
            UnOp::Deref => {
                let p = self.place(e)?;
                Ok(Some(self.b.build_load(p, "")?))
            }
            UnOp::Not => {
                let v = self.expr(&u.expr)?;
                let v = self.val(v, ty).into_int_value();
                Ok(Some(self.b.build_not(v, "")?.into()))
            }
            UnOp::Neg => {
                let v = self.expr(&u.expr)?;
                let v = self.val(v, ty);
                Ok(Some(match ty {
                    Ty::Float(_) => self.b.build_float_neg(v.into_float_value(), "")?.into(),
                    Ty::Simd(SimdTy::F32x4) => self.simd_sign_bit(v.into_vector_value(), true)?,
                    Ty::Simd(_) => self.b.build_int_neg(v.into_vector_value(), "")?.into(),
                    _ => self.b.build_int_neg(v.into_int_value(), "")?.into(),
                }))
            }
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
            (Ty::Adt(a, _), Ty::Int(_)) => {
                let signed = self.p.adts[*a].repr.signed();
                b.build_int_cast_sign_flag(v.into_int_value(), tl.into_int_type(), signed, "")?
                    .into()
            }
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
                    .ok_or_else(|| internal("cast call"))?
            }
            (Ty::Ptr(..) | Ty::Ref(..), Ty::Ptr(..)) => match v {
                BasicValueEnum::PointerValue(p) => {
                    b.build_pointer_cast(p, tl.into_pointer_type(), "")?.into()
                }
                other => other,
            },
            (Ty::Ptr(..), Ty::Int(_)) => b
                .build_ptr_to_int(v.into_pointer_value(), tl.into_int_type(), "")?
                .into(),
            (Ty::Int(_), Ty::Ptr(..)) => b
                .build_int_to_ptr(v.into_int_value(), tl.into_pointer_type(), "")?
                .into(),
            _ => {
                return Err(internal(format!(
                    "cast {} as {}",
                    self.p.ty_str(from),
                    self.p.ty_str(to)
                )))
            }
        })
    }

    // ---------------------------------------------------------------- control flow

    /// Lowers a condition: branches to `fail` when it is false (or the `let` pattern does
    /// not match); continues in the current block otherwise, with the bindings made.
    pub(super) fn cond(
        &mut self,
        c: &Expr,
        fail: inkwell::basic_block::BasicBlock<'ctx>,
    ) -> LResult<()> {
        match c {
            Expr::Let(l) => {
                let ty = self.ty_of(&l.expr);
                let place = self.place_or_temp(&l.expr)?;
                if self.terminated() {
                    return Ok(());
                }
                self.match_pat(&l.pat, place, &ty, fail)
            }
            other => {
                let v = self.expr(other)?;
                let v = self.val(v, &Ty::Bool).into_int_value();
                let ok = self.new_block("cond.true");
                if !self.terminated() {
                    self.b.build_conditional_branch(v, ok, fail)?;
                }
                self.b.position_at_end(ok);
                Ok(())
            }
        }
    }

    fn if_expr(&mut self, i: &syn::ExprIf, ty: &Ty) -> LResult<V<'ctx>> {
        let slot = if ty.is_zst() {
            None
        } else {
            Some(self.alloca(ty, "if.value")?)
        };
        let else_bb = self.new_block("if.else");
        let end = self.new_block("if.end");
        let prev = self.push_scope(i.if_token.span);
        self.cond(&i.cond, else_bb)?;
        let tv = self.block(&i.then_branch, true);
        self.pop_scope(prev);
        let tv = tv?;
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

    /// `expr?`: returns early with the `None`/`Err`, else yields the value.
    fn try_expr(&mut self, e: &Expr, t: &syn::ExprTry, ty: &Ty) -> LResult<V<'ctx>> {
        let vt = self.ty_of(&t.expr);
        let ret = self
            .body
            .tries
            .get(&key(e))
            .cloned()
            .ok_or_else(|| internal("unchecked `?`"))?;
        let place = self.place_or_temp(&t.expr)?;
        let Ty::Adt(a, _) = &vt else {
            return Err(internal("`?` on a non-ADT"));
        };
        let is_option = Some(*a) == self.p.lang.option;
        // Option: None = 0, Some = 1; Result: Ok = 0, Err = 1 (by name).
        let ok_v = self.p.adts[*a]
            .variant(if is_option { "Some" } else { "Ok" })
            .ok_or_else(|| internal("lang variant"))?;
        let tag_p = self.tag_ptr(place, &vt)?;
        let tag = self.b.build_load(tag_p, "")?.into_int_value();
        let want = self.tag_val(*a, ok_v);
        let is_ok = self.b.build_int_compare(IntPredicate::EQ, tag, want, "")?;
        let bail = self.new_block("try.bail");
        let cont = self.new_block("try.ok");
        self.b.build_conditional_branch(is_ok, cont, bail)?;
        self.b.position_at_end(bail);
        let Ty::Adt(ra, _) = &ret else {
            return Err(internal("`?` return type"));
        };
        let out = if is_option {
            let nv = self.p.adts[*ra]
                .variant("None")
                .ok_or_else(|| internal("None"))?;
            self.build_adt(&ret, nv, &[])?
        } else {
            let ev = self.p.adts[*a]
                .variant("Err")
                .ok_or_else(|| internal("Err"))?;
            let fp = self.field_ptr(place, &vt, ev, 0)?;
            let err = self.b.build_load(fp, "")?;
            let rv = self.p.adts[*ra]
                .variant("Err")
                .ok_or_else(|| internal("Err"))?;
            self.build_adt(&ret, rv, &[Some(err)])?
        };
        self.set_loc(t.question_token.span);
        self.b.build_return(Some(&out))?;
        self.b.position_at_end(cont);
        if ty.is_zst() {
            return Ok(None);
        }
        let fp = self.field_ptr(place, &vt, ok_v, 0)?;
        Ok(Some(self.b.build_load(fp, "")?))
    }

    /// A struct literal, for structs and enum struct variants.
    fn struct_lit(&mut self, e: &Expr, s: &syn::ExprStruct, ty: &Ty) -> LResult<V<'ctx>> {
        let (_, v) = *self
            .body
            .structs
            .get(&key(e))
            .ok_or_else(|| internal("unchecked struct literal"))?;
        let ftys = self.field_tys(ty, v);
        let mut vals: Vec<Option<BasicValueEnum<'ctx>>> = vec![None; ftys.len()];
        // `..base`: start from the base's fields.
        let base = match &s.rest {
            Some(r) => {
                let bv = self.expr(r)?;
                Some(self.val(bv, ty))
            }
            None => None,
        };
        for fv in &s.fields {
            let i = *self
                .body
                .fields
                .get(&key(fv))
                .ok_or_else(|| internal("field index"))?;
            let x = self.expr(&fv.expr)?;
            vals[i] = Some(self.val(x, &ftys[i]));
        }
        if let Some(bv) = base {
            let sv = bv.into_struct_value();
            for (i, slot) in vals.iter_mut().enumerate() {
                if slot.is_none() {
                    *slot = Some(self.b.build_extract_value(sv, i as u32, "")?);
                }
            }
        }
        Ok(Some(self.build_adt(ty, v, &vals)?))
    }

    /// Builds a value of ADT type `t`, variant `v`, from its field values.
    pub(super) fn build_adt(
        &mut self,
        t: &Ty,
        v: usize,
        fields: &[Option<BasicValueEnum<'ctx>>],
    ) -> LResult<BasicValueEnum<'ctx>> {
        let Ty::Adt(a, _) = t else {
            return Err(internal("build_adt of a non-ADT"));
        };
        let a = *a;
        let lt = self.llty(t);
        if self.p.adts[a].is_fieldless_enum() {
            return Ok(self.tag_val(a, v).into());
        }
        let ftys = self.field_tys(t, v);
        if !self.p.adts[a].is_enum {
            let mut agg = lt.into_struct_type().get_undef();
            for (i, f) in fields.iter().enumerate() {
                let x = match f {
                    Some(x) => *x,
                    None => super::undef(self.llty(&ftys[i])),
                };
                agg = self
                    .b
                    .build_insert_value(agg, x, i as u32, "")?
                    .into_struct_value();
            }
            return Ok(agg.into());
        }
        // One variant with data: build the value directly (constants fold).
        if let Some(dv) = self.single_data_variant(a) {
            let st = lt.into_struct_type();
            let mut agg = st.get_undef();
            agg = self
                .b
                .build_insert_value(agg, self.tag_val(a, v), 0, "")?
                .into_struct_value();
            let vt = self.variant_ty(t, dv);
            let payload = if v == dv {
                let mut pv = vt.get_undef();
                for (i, f) in fields.iter().enumerate() {
                    let x = match f {
                        Some(x) => *x,
                        None => super::undef(self.llty(&ftys[i])),
                    };
                    pv = self
                        .b
                        .build_insert_value(pv, x, i as u32, "")?
                        .into_struct_value();
                }
                pv
            } else {
                vt.const_zero()
            };
            agg = self
                .b
                .build_insert_value(agg, payload, 1, "")?
                .into_struct_value();
            return Ok(agg.into());
        }
        // Enum: through a stack slot (the payload is reinterpreted).
        let slot = self.alloca_ll(lt, "variant")?;
        if let Some(st) = lt.into_struct_type().get_field_type_at_index(1) {
            // Start from zero so padding and unused payload bytes are defined.
            let zp = self.b.build_struct_gep(slot, 1, "")?;
            self.b.build_store(zp, super::zero(st))?;
        }
        let tp = self.tag_ptr(slot, t)?;
        self.b.build_store(tp, self.tag_val(a, v))?;
        for (i, f) in fields.iter().enumerate() {
            if let Some(x) = f {
                if ftys[i].is_zst() {
                    continue;
                }
                let fp = self.field_ptr(slot, t, v, i)?;
                self.b.build_store(fp, *x)?;
            }
        }
        Ok(self.b.build_load(slot, "")?)
    }
}

pub(super) fn is_scalar(t: &Ty) -> bool {
    !matches!(t, Ty::Array(..) | Ty::Adt(..) | Ty::Tuple(_))
}

pub(super) fn const_array<'ctx>(
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
