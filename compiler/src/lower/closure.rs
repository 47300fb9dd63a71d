//! Closures. A closure's value is its environment: a struct of pointers to the captured
//! locals' slots (copies of their values for `move` closures). Each closure type is one
//! function taking the environment's address first, then the closure's arguments; inside
//! it the captured locals are the environment's pointers (or fields), so the enclosing
//! body's code for places and paths applies unchanged.

use super::{internal, LResult, Lowerer, Work, V};
use crate::diag::Loc;
use crate::span::Spanned;
use crate::ty::{ClosureTy, Ty};
use crate::typeck::{key, Body, ClosureInfo};
use inkwell::attributes::{Attribute, AttributeLoc};
use inkwell::debug_info::{AsDIScope, DIType};
use inkwell::module::Linkage;
use inkwell::types::{BasicType, BasicTypeEnum, StructType};
use inkwell::values::{BasicValueEnum, FunctionValue, PointerValue};
use inkwell::AddressSpace;
use syn::visit::Visit;
use syn::Expr;

/// Finds a closure expression by its key in a function body and its macros' arguments.
struct FindClosure<'p> {
    key: usize,
    found: Option<&'p syn::ExprClosure>,
}

impl<'p> Visit<'p> for FindClosure<'p> {
    fn visit_expr(&mut self, e: &'p Expr) {
        if self.found.is_some() {
            return;
        }
        if let Expr::Closure(c) = e {
            if key(e) == self.key {
                self.found = Some(c);
                return;
            }
        }
        syn::visit::visit_expr(self, e);
    }

    // Items nested in the body have bodies of their own.
    fn visit_item(&mut self, _: &'p syn::Item) {}
}

impl<'ctx, 'p, 'a> Lowerer<'ctx, 'p, 'a> {
    /// The body defining closure `c` and what it captures.
    fn closure_def(&self, c: &ClosureTy) -> LResult<(&'p Body, &'p ClosureInfo)> {
        let body = self
            .checked
            .fn_body(c.def_fn, &c.def_substs)
            .ok_or_else(|| internal("closure of an unchecked function"))?;
        let info = body
            .closures
            .get(&c.key)
            .ok_or_else(|| internal("closure without capture information"))?;
        Ok((body, info))
    }

    /// Types of a closure's environment fields: pointers to the captured locals, or their
    /// values for `move` closures.
    fn env_tys(&self, c: &ClosureTy) -> Vec<Ty> {
        let Ok((body, info)) = self.closure_def(c) else {
            return Vec::new();
        };
        info.captures
            .iter()
            .map(|id| {
                let t = body.locals[*id].ty.clone();
                if info.by_move {
                    t
                } else {
                    Ty::Ptr(true, Box::new(t))
                }
            })
            .collect()
    }

    /// LLVM type of a closure's environment.
    pub(super) fn closure_ty(&mut self, c: &ClosureTy) -> StructType<'ctx> {
        let fields: Vec<BasicTypeEnum> = self.env_tys(c).iter().map(|t| self.llty(t)).collect();
        self.ctx.struct_type(&fields, false)
    }

    /// DWARF type of a closure's environment (a structure of its captures).
    pub(super) fn closure_di(&mut self, c: &ClosureTy) -> DIType<'ctx> {
        let lt = self.closure_ty(c);
        let size = self.td.get_bit_size(&lt);
        let align = self.td.get_abi_alignment(&lt) * 8;
        let file = self.di_file(self.file);
        self.dib
            .create_struct_type(
                file.as_debug_info_scope(),
                "{closure}",
                file,
                0,
                size,
                align,
                0,
                None,
                &[],
                0,
                None,
                "{closure}",
            )
            .as_type()
    }

    /// The value of a closure expression: its environment.
    pub(super) fn closure_value(&mut self, e: &Expr, ty: &Ty) -> LResult<V<'ctx>> {
        let Ty::Closure(c) = ty else {
            return Err(internal("closure expression of a non-closure type"));
        };
        let info = self
            .body
            .closures
            .get(&key(e))
            .cloned()
            .ok_or_else(|| internal("closure without capture information"))?;
        self.declare_closure(c);
        let lt = self.closure_ty(c);
        let mut agg = lt.get_undef();
        for (i, id) in info.captures.iter().enumerate() {
            let slot = self
                .fs()
                .locals
                .get(id)
                .copied()
                .ok_or_else(|| internal(format!("captured local {id} has no slot")))?;
            let v: BasicValueEnum = if info.by_move {
                self.b.build_load(slot, "")?
            } else {
                slot.into()
            };
            agg = self
                .b
                .build_insert_value(agg, v, i as u32, "")?
                .into_struct_value();
        }
        Ok(Some(agg.into()))
    }

    /// Calls the closure reached from `func` by `derefs` dereferences.
    pub(super) fn closure_call(
        &mut self,
        e: &Expr,
        c: &syn::ExprCall,
        ct: &ClosureTy,
        derefs: u32,
        ty: &Ty,
    ) -> LResult<V<'ctx>> {
        let env = self.deref_base(&c.func, derefs)?;
        let mut vals: Vec<BasicValueEnum> = vec![env.into()];
        for a in &c.args {
            let t = self.ty_of(a);
            let v = self.expr(a)?;
            vals.push(self.val(v, &t));
        }
        self.set_loc(e.span());
        let f = self.declare_closure(ct);
        let env_ptr = self.closure_ty(ct).ptr_type(AddressSpace::default());
        vals[0] = self.b.build_pointer_cast(env, env_ptr, "")?.into();
        let args: Vec<_> = vals.into_iter().map(Into::into).collect();
        let cs = self.b.build_call(f, &args, "")?;
        if matches!(ty, Ty::Never) {
            self.b.build_unreachable()?;
            return Ok(None);
        }
        Ok(cs.try_as_basic_value().basic())
    }

    /// Symbol of a closure: its function instance's, then where it is written.
    fn closure_name(&self, c: &ClosureTy, symbol: bool) -> LResult<String> {
        let fd = &self.p.fns[c.def_fn];
        let syn_c = self.find_closure(c)?;
        let l = Loc::of(syn_c.inputs_begin.span);
        let base = if symbol { &fd.symbol } else { &fd.name };
        Ok(format!(
            "{}::{{closure@{}:{}}}",
            self.inst_name(base, &c.def_substs),
            l.line,
            l.col
        ))
    }

    /// The closure expression of `c` in its defining function.
    fn find_closure(&self, c: &ClosureTy) -> LResult<&'p syn::ExprClosure> {
        let fd = &self.p.fns[c.def_fn];
        let mut v = FindClosure {
            key: c.key,
            found: None,
        };
        if let Some(b) = fd.body {
            v.visit_block(b);
        }
        if v.found.is_none() {
            let (body, _) = self.closure_def(c)?;
            for m in body.macros.values() {
                for e in m.exprs() {
                    v.visit_expr(e);
                }
            }
        }
        v.found
            .ok_or_else(|| internal("closure expression not found in its function"))
    }

    /// The function of closure type `c` (declared and queued on first use).
    pub(super) fn declare_closure(&mut self, c: &ClosureTy) -> FunctionValue<'ctx> {
        if let Some(f) = self.closures.get(c) {
            return *f;
        }
        let env = self.closure_ty(c).ptr_type(AddressSpace::default());
        let mut params = vec![env.into()];
        for t in &c.params {
            params.push(self.llty(t).into());
        }
        let fty = match &c.ret {
            Ty::Unit | Ty::Never => self.ctx.void_type().fn_type(&params, false),
            t => self.llty(t).fn_type(&params, false),
        };
        let symbol = self
            .closure_name(c, true)
            .unwrap_or_else(|_| "{closure}".to_string());
        let f = self
            .module
            .add_function(&symbol, fty, Some(Linkage::Internal));
        let add = |n: &str| {
            f.add_attribute(
                AttributeLoc::Function,
                self.ctx
                    .create_enum_attribute(Attribute::get_named_enum_kind_id(n), 0),
            )
        };
        add("nounwind");
        if self.optimized {
            add("inlinehint");
        } else {
            add("noinline");
            add("optnone");
        }
        self.closures.insert(c.clone(), f);
        self.queue.push(Work::Closure(c.clone()));
        f
    }

    /// Emits the function of closure type `c`.
    pub(super) fn lower_closure(&mut self, c: ClosureTy) -> LResult<()> {
        let f = self.closures[&c];
        let (body, info) = self.closure_def(&c)?;
        let syn_c = self.find_closure(&c)?;
        let fd = &self.p.fns[c.def_fn];
        self.body = body;
        self.file = fd.file;
        self.module_id = fd.module;
        let di_file = self.di_file(fd.file);
        let loc = Loc::of(syn_c.inputs_begin.span);
        let ret_di = match &c.ret {
            Ty::Unit | Ty::Never => None,
            t => Some(self.di_type(t)),
        };
        let env_di = self.closure_di(&c);
        let env_ptr_di = self
            .dib
            .create_pointer_type(
                "&{closure}",
                env_di,
                32,
                32,
                inkwell::AddressSpace::default(),
            )
            .as_type();
        let mut param_di = vec![env_ptr_di];
        for t in &c.params {
            param_di.push(self.di_type(t));
        }
        let sty = self
            .dib
            .create_subroutine_type(di_file, ret_di, &param_di, 0);
        let name = self.closure_name(&c, false)?;
        let symbol = self.closure_name(&c, true)?;
        let sp = self.dib.create_function(
            di_file.as_debug_info_scope(),
            &name,
            Some(&symbol),
            di_file,
            loc.line,
            sty,
            true,
            true,
            loc.line,
            0,
            self.optimized,
        );
        let start = self.begin_body(f, sp, c.ret.clone())?;
        // Captured locals: the environment's pointers (or its fields for `move`).
        let env = f
            .get_nth_param(0)
            .ok_or_else(|| internal("closure without environment"))?
            .into_pointer_value();
        for (i, id) in info.captures.iter().enumerate() {
            let field = self.b.build_struct_gep(env, i as u32, "")?;
            let slot: PointerValue = if info.by_move {
                field
            } else {
                self.b.build_load(field, "")?.into_pointer_value()
            };
            self.fs().locals.insert(*id, slot);
        }
        let mut pending = Vec::new();
        for (i, input) in syn_c.inputs.iter().enumerate() {
            let pat = match input {
                syn::Pat::Type(pt) => &*pt.pat,
                other => other,
            };
            let ty = c.params[i].clone();
            let pv = f
                .get_nth_param(i as u32 + 1)
                .ok_or_else(|| internal("missing closure parameter"))?;
            match pat {
                syn::Pat::Ident(pi) if pi.subpat.is_none() && pi.by_ref.is_none() => {
                    let name = pi.ident.to_string();
                    let slot = self.alloca(&ty, &name)?;
                    self.b.build_store(slot, pv)?;
                    self.declare_var(slot, &name, &ty, pi.ident.span(), Some(i as u32 + 2));
                    if let Some((l, _)) = self.body.binds.get(&key(pi)).copied() {
                        self.fs().locals.insert(l, slot);
                    }
                }
                other => {
                    let slot = self.alloca(&ty, "arg")?;
                    self.b.build_store(slot, pv)?;
                    self.declare_var(slot, "_", &ty, other.span(), Some(i as u32 + 2));
                    pending.push((other, slot, ty));
                }
            }
        }
        self.b.position_at_end(start);
        self.set_loc(syn_c.body.span());
        for (pat, slot, ty) in pending {
            let fail = self.new_block("param.fail");
            self.match_pat(pat, slot, &ty, fail)?;
            let cont = self
                .b
                .get_insert_block()
                .ok_or_else(|| internal("no block"))?;
            self.b.position_at_end(fail);
            self.b.build_unreachable()?;
            self.b.position_at_end(cont);
        }
        let v = self.expr(&syn_c.body)?;
        if !self.terminated() {
            match &c.ret {
                Ty::Unit | Ty::Never => {
                    self.b.build_return(None)?;
                }
                t => {
                    let v = self.val(v, t);
                    self.b.build_return(Some(&v))?;
                }
            }
        }
        self.finish_fn();
        self.f = None;
        Ok(())
    }
}
