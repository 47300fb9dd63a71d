//! Stage 4: lowering of checked bodies to LLVM IR with debug info (inkwell).
//!
//! Functions are emitted on demand, starting from `trax_main`, so the object only holds
//! code reachable from the entry point. Every local lives in an `alloca` described with
//! `dbg.declare`; LLVM's mem2reg/SROA promote them at -O1 and above.

mod builtins;
mod debug;
mod expr;
mod panic;

use crate::diag::{Diagnostic, FileId, Loc};
use crate::resolve::{FnId, GlobalId, InlineHint, Program};
use crate::ty::{FloatTy, IntTy, SimdTy, StructId, Ty};
use crate::typeck::{key, Body, LocalId};
use inkwell::attributes::{Attribute, AttributeLoc};
use inkwell::basic_block::BasicBlock;
use inkwell::builder::{Builder, BuilderError};
use inkwell::context::Context;
use inkwell::debug_info::{AsDIScope, DICompileUnit, DIFile, DIScope, DIType, DebugInfoBuilder};
use inkwell::module::{Linkage, Module};
use inkwell::targets::TargetData;
use inkwell::types::{BasicType, BasicTypeEnum, StructType};
use inkwell::values::{BasicValueEnum, FunctionValue, GlobalValue, PointerValue};
use inkwell::AddressSpace;
use proc_macro2::Span;
use std::collections::HashMap;

/// Error during lowering.
#[derive(Debug)]
pub enum LowerError {
    /// A user error found late (e.g. a non-constant static initializer).
    Diag(Diagnostic),
    /// A compiler bug.
    Internal(String),
}

impl From<BuilderError> for LowerError {
    fn from(e: BuilderError) -> Self {
        LowerError::Internal(format!("LLVM builder: {e}"))
    }
}

impl From<Diagnostic> for LowerError {
    fn from(e: Diagnostic) -> Self {
        LowerError::Diag(e)
    }
}

/// Lowering result.
pub type LResult<T> = Result<T, LowerError>;

/// A lowered value: `None` for `()` and `!`.
pub type V<'ctx> = Option<BasicValueEnum<'ctx>>;

struct LoopTarget<'ctx> {
    label: Option<String>,
    brk: BasicBlock<'ctx>,
    cont: BasicBlock<'ctx>,
    slot: Option<PointerValue<'ctx>>,
}

struct FnState<'ctx> {
    func: FunctionValue<'ctx>,
    alloca_at: inkwell::values::InstructionValue<'ctx>,
    locals: HashMap<LocalId, PointerValue<'ctx>>,
    loops: Vec<LoopTarget<'ctx>>,
    scope: DIScope<'ctx>,
    ret: Ty,
    /// False while evaluating constant initializers (no subprogram to describe).
    debug: bool,
    /// The function's panic-message argument record and its size in words, shared by
    /// every panic site (`lower/panic.rs`).
    panic_args: Option<(PointerValue<'ctx>, u32)>,
}

/// Lowers a checked program to one LLVM module.
pub struct Lowerer<'ctx, 'p, 'a> {
    ctx: &'ctx Context,
    module: Module<'ctx>,
    b: Builder<'ctx>,
    dib: DebugInfoBuilder<'ctx>,
    cu: DICompileUnit<'ctx>,
    td: TargetData,
    p: &'p Program<'a>,
    fn_bodies: &'p [Body],
    global_bodies: &'p [Body],
    optimized: bool,
    fns: HashMap<FnId, FunctionValue<'ctx>>,
    queue: Vec<FnId>,
    globals: HashMap<GlobalId, GlobalValue<'ctx>>,
    structs: HashMap<StructId, StructType<'ctx>>,
    di_files: HashMap<FileId, DIFile<'ctx>>,
    di_types: HashMap<Ty, DIType<'ctx>>,
    di_in_progress: Vec<StructId>,
    strings: HashMap<String, GlobalValue<'ctx>>,
    // Current body context.
    body: &'p Body,
    file: FileId,
    module_id: usize,
    f: Option<FnState<'ctx>>,
    /// Nesting of inlined `const` initializers (guards against cycles).
    const_depth: u32,
}

impl<'ctx, 'p, 'a> Lowerer<'ctx, 'p, 'a> {
    /// Creates a lowerer for `p` whose bodies were checked into `fn_bodies`/`global_bodies`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &'ctx Context,
        name: &str,
        td: TargetData,
        triple: &inkwell::targets::TargetTriple,
        p: &'p Program<'a>,
        fn_bodies: &'p [Body],
        global_bodies: &'p [Body],
        optimized: bool,
        empty: &'p Body,
    ) -> Self {
        let module = ctx.create_module(name);
        module.set_triple(triple);
        module.set_data_layout(&td.get_data_layout());
        let root_file = p.sources.get(p.modules[p.kernel_root].file).display.clone();
        let (fname, dir) = split_path(&root_file);
        let (dib, cu) = module.create_debug_info_builder(
            true,
            inkwell::debug_info::DWARFSourceLanguage::Rust,
            &fname,
            &dir,
            "trax-compiler",
            optimized,
            "",
            0,
            "",
            inkwell::debug_info::DWARFEmissionKind::Full,
            0,
            false,
            false,
            "",
            "",
        );
        let md_ver = ctx
            .i32_type()
            .const_int(inkwell::debug_info::debug_metadata_version() as u64, false);
        module.add_basic_value_flag(
            "Debug Info Version",
            inkwell::module::FlagBehavior::Warning,
            md_ver,
        );
        let dwarf_ver = ctx.i32_type().const_int(4, false);
        module.add_basic_value_flag(
            "Dwarf Version",
            inkwell::module::FlagBehavior::Warning,
            dwarf_ver,
        );
        Lowerer {
            ctx,
            module,
            b: ctx.create_builder(),
            dib,
            cu,
            td,
            p,
            fn_bodies,
            global_bodies,
            optimized,
            fns: HashMap::new(),
            queue: Vec::new(),
            globals: HashMap::new(),
            structs: HashMap::new(),
            di_files: HashMap::new(),
            di_types: HashMap::new(),
            di_in_progress: Vec::new(),
            strings: HashMap::new(),
            body: empty,
            file: p.modules[p.kernel_root].file,
            module_id: p.kernel_root,
            f: None,
            const_depth: 0,
        }
    }

    /// Lowers `root` and everything it reaches; returns the finished module.
    pub fn run(mut self, root: FnId) -> LResult<Module<'ctx>> {
        let f = self.declare_fn(root);
        f.set_linkage(Linkage::External);
        while let Some(id) = self.queue.pop() {
            self.lower_fn(id)?;
        }
        self.dib.finalize();
        Ok(self.module)
    }

    fn err(&self, span: Span, id: &'static str, msg: impl Into<String>) -> LowerError {
        LowerError::Diag(self.p.err(self.file, span, id, msg))
    }

    // ---------------------------------------------------------------- types

    /// LLVM type of a TRaX type (unit and never are empty structs).
    pub(crate) fn llty(&mut self, t: &Ty) -> BasicTypeEnum<'ctx> {
        let c = self.ctx;
        match t {
            Ty::Unit | Ty::Never => c.struct_type(&[], false).into(),
            Ty::Bool => c.bool_type().into(),
            Ty::Char => c.i32_type().into(),
            Ty::Int(i) => self.int_ty(i.bits()).into(),
            Ty::Float(FloatTy::F32) => c.f32_type().into(),
            Ty::Float(FloatTy::F64) => c.f64_type().into(),
            Ty::Struct(s) => self.struct_ty(*s).into(),
            Ty::Array(e, n) => self.llty(e).array_type(*n).into(),
            Ty::Ref(_, e) | Ty::Ptr(_, e) => {
                let inner = self.llty(e);
                inner.ptr_type(AddressSpace::default()).into()
            }
            Ty::Simd(SimdTy::F32x4) => c.f32_type().vec_type(4).into(),
            Ty::Simd(SimdTy::I32x4) => c.i32_type().vec_type(4).into(),
            Ty::Str => c
                .struct_type(&[c.i32_type().into(), c.i32_type().into()], false)
                .into(),
            Ty::Var(_) => c.i32_type().into(),
        }
    }

    /// Integer type of a width (1, 8, 16, 32 or 64 bits).
    pub(crate) fn int_ty(&self, bits: u32) -> inkwell::types::IntType<'ctx> {
        match bits {
            1 => self.ctx.bool_type(),
            8 => self.ctx.i8_type(),
            16 => self.ctx.i16_type(),
            64 => self.ctx.i64_type(),
            _ => self.ctx.i32_type(),
        }
    }

    fn struct_ty(&mut self, s: StructId) -> StructType<'ctx> {
        if let Some(t) = self.structs.get(&s) {
            return *t;
        }
        let def = &self.p.structs[s];
        let st = self.ctx.opaque_struct_type(&format!(
            "{}::{}",
            self.p.modules[def.module].path, def.name
        ));
        self.structs.insert(s, st);
        let fields: Vec<BasicTypeEnum> = def
            .fields
            .iter()
            .map(|(_, t)| t.clone())
            .collect::<Vec<_>>()
            .iter()
            .map(|t| self.llty(t))
            .collect();
        st.set_body(&fields, false);
        st
    }

    // ---------------------------------------------------------------- functions

    fn declare_fn(&mut self, id: FnId) -> FunctionValue<'ctx> {
        if let Some(f) = self.fns.get(&id) {
            return *f;
        }
        let fd = &self.p.fns[id];
        let params: Vec<_> = fd
            .params
            .clone()
            .iter()
            .map(|t| self.llty(t).into())
            .collect();
        let fty = match &fd.ret {
            Ty::Unit | Ty::Never => self.ctx.void_type().fn_type(&params, false),
            t => self.llty(t).fn_type(&params, false),
        };
        let f = self
            .module
            .add_function(&fd.symbol, fty, Some(Linkage::Internal));
        let attr = |n: &str| Attribute::get_named_enum_kind_id(n);
        let add = |n: &str| {
            f.add_attribute(
                AttributeLoc::Function,
                self.ctx.create_enum_attribute(attr(n), 0),
            )
        };
        match fd.inline {
            InlineHint::Always => add("alwaysinline"),
            InlineHint::Never => add("noinline"),
            InlineHint::Hint => add("inlinehint"),
            InlineHint::None => {}
        }
        add("nounwind");
        if !self.optimized {
            // Keep every call at -O0 so the debugger sees each function.
            if fd.inline != InlineHint::Always {
                add("noinline");
                add("optnone");
            }
        }
        self.fns.insert(id, f);
        self.queue.push(id);
        f
    }

    fn lower_fn(&mut self, id: FnId) -> LResult<()> {
        let fd = &self.p.fns[id];
        let f = self.fns[&id];
        self.body = &self.fn_bodies[id];
        self.file = fd.file;
        self.module_id = fd.module;
        let di_file = self.di_file(fd.file);
        let loc = Loc::of(fd.sig.ident.span());
        let ret_di = match &fd.ret {
            Ty::Unit | Ty::Never => None,
            t => Some(self.di_type(t)),
        };
        let params = fd.params.clone();
        let param_di: Vec<DIType> = params.iter().map(|t| self.di_type(t)).collect();
        let sty = self
            .dib
            .create_subroutine_type(di_file, ret_di, &param_di, 0);
        let external = f.get_linkage() == Linkage::External;
        let sp = self.dib.create_function(
            di_file.as_debug_info_scope(),
            &fd.name,
            Some(&fd.symbol),
            di_file,
            loc.line,
            sty,
            !external,
            true,
            loc.line,
            0,
            self.optimized,
        );
        f.set_subprogram(sp);
        let entry = self.ctx.append_basic_block(f, "entry");
        let start = self.ctx.append_basic_block(f, "start");
        self.b.position_at_end(entry);
        self.b.unset_current_debug_location();
        let br = self.b.build_unconditional_branch(start)?;
        self.f = Some(FnState {
            func: f,
            alloca_at: br,
            locals: HashMap::new(),
            loops: Vec::new(),
            scope: sp.as_debug_info_scope(),
            ret: fd.ret.clone(),
            debug: true,
            panic_args: None,
        });
        // Parameters are spilled to their slots in the entry block with no source location
        // (as clang does), so the first located instruction, which LLVM marks
        // `prologue_end`, is the body's: a debugger's `break FUNC` stops where every
        // argument is already in its slot.
        self.b.position_before(&br);
        // Parameters.
        for (i, arg) in fd.sig.inputs.iter().enumerate() {
            let ty = params[i].clone();
            let (name, span, local) = match arg {
                syn::FnArg::Receiver(r) => ("self".to_string(), r.self_token.span, Some(i)),
                syn::FnArg::Typed(pt) => match &*pt.pat {
                    syn::Pat::Ident(pi) => (
                        pi.ident.to_string(),
                        pi.ident.span(),
                        self.body.pat_locals.get(&key(pi)).copied(),
                    ),
                    _ => ("_".to_string(), syn::spanned::Spanned::span(pt), None),
                },
            };
            let pv = f
                .get_nth_param(i as u32)
                .ok_or_else(|| LowerError::Internal("missing parameter".into()))?;
            let slot = self.alloca(&ty, &name)?;
            self.b.build_store(slot, pv)?;
            self.declare_var(slot, &name, &ty, span, Some(i as u32 + 1));
            if let Some(l) = local {
                self.fs().locals.insert(l, slot);
            }
        }
        self.b.position_at_end(start);
        self.set_loc(fd.sig.ident.span());
        let v = self.block(fd.body, false)?;
        if !self.terminated() {
            self.set_loc(fd.body.brace_token.span.close());
            match &fd.ret {
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

    /// Terminates blocks left open (dead code after diverging expressions).
    fn finish_fn(&mut self) {
        let f = self.fs().func;
        for bb in f.get_basic_blocks() {
            if bb.get_terminator().is_none() {
                self.b.position_at_end(bb);
                let _ = self.b.build_unreachable();
            }
        }
    }

    fn fs(&mut self) -> &mut FnState<'ctx> {
        self.f.as_mut().expect("inside a function")
    }

    /// True when the current block already ends in a terminator.
    fn terminated(&self) -> bool {
        self.b
            .get_insert_block()
            .and_then(|bb| bb.get_terminator())
            .is_some()
    }

    /// Starts a fresh unreachable block after a diverging instruction.
    fn dead_block(&mut self) {
        let f = self.fs().func;
        let bb = self.ctx.append_basic_block(f, "dead");
        self.b.position_at_end(bb);
    }

    fn new_block(&mut self, name: &str) -> BasicBlock<'ctx> {
        let f = self.fs().func;
        self.ctx.append_basic_block(f, name)
    }

    /// Branches to `bb` unless the current block is already terminated.
    fn br(&mut self, bb: BasicBlock<'ctx>) -> LResult<()> {
        if !self.terminated() {
            self.b.build_unconditional_branch(bb)?;
        }
        Ok(())
    }

    /// Stack slot in the entry block.
    fn alloca(&mut self, t: &Ty, name: &str) -> LResult<PointerValue<'ctx>> {
        let lt = self.llty(t);
        let at = self.fs().alloca_at;
        let tmp = self.ctx.create_builder();
        tmp.position_before(&at);
        Ok(tmp.build_alloca(lt, name)?)
    }

    /// Sets the debug location of following instructions.
    fn set_loc(&mut self, span: Span) {
        let Some(fs) = &self.f else { return };
        if !fs.debug {
            self.b.unset_current_debug_location();
            return;
        }
        let l = Loc::of(span);
        let loc = self
            .dib
            .create_debug_location(self.ctx, l.line, l.col, fs.scope, None);
        self.b.set_current_debug_location(loc);
    }

    /// A value of type `t` for a possibly-missing (unit/never) value.
    fn val(&mut self, v: V<'ctx>, t: &Ty) -> BasicValueEnum<'ctx> {
        match v {
            Some(v) => v,
            None => {
                let lt = self.llty(t);
                undef(lt)
            }
        }
    }

    fn string_global(&mut self, s: &str) -> GlobalValue<'ctx> {
        if let Some(g) = self.strings.get(s) {
            return *g;
        }
        let bytes = self.ctx.const_string(s.as_bytes(), false);
        let g = self.module.add_global(
            bytes.get_type(),
            None,
            &format!(".str.{}", self.strings.len()),
        );
        g.set_initializer(&bytes);
        g.set_constant(true);
        g.set_linkage(Linkage::Private);
        g.set_unnamed_addr(true);
        g.set_alignment(1);
        self.strings.insert(s.to_string(), g);
        g
    }

    /// The address of a static, or of a const aggregate placed in read-only data.
    fn global(&mut self, g: GlobalId) -> LResult<GlobalValue<'ctx>> {
        if let Some(v) = self.globals.get(&g) {
            return Ok(*v);
        }
        let gd = &self.p.globals[g];
        let lt = self.llty(&gd.ty);
        let gv = self.module.add_global(lt, None, &gd.symbol);
        gv.set_linkage(Linkage::Internal);
        self.globals.insert(g, gv);
        let init = self.const_init(g)?;
        gv.set_initializer(&init);
        gv.set_constant(gd.is_static != Some(true));
        let di_ty = self.di_type(&gd.ty);
        let file = self.di_file(gd.file);
        let line = Loc::of(gd.ty_span).line;
        let expr = self.dib.create_expression(vec![]);
        let gve = self.dib.create_global_variable_expression(
            self.cu.as_debug_info_scope(),
            &gd.name,
            &gd.symbol,
            file,
            line,
            di_ty,
            true,
            Some(expr),
            None,
            0,
        );
        gv.set_metadata(gve.as_metadata_value(self.ctx), self.ctx.get_kind_id("dbg"));
        Ok(gv)
    }

    /// Evaluates a global's initializer to an LLVM constant.
    fn const_init(&mut self, g: GlobalId) -> LResult<BasicValueEnum<'ctx>> {
        let gd = &self.p.globals[g];
        // Lower in a scratch function; constant operands fold in the builder.
        let saved_f = self.f.take();
        let saved_pos = self.b.get_insert_block();
        let saved_loc = self.b.get_current_debug_location();
        let scratch_ty = self.ctx.void_type().fn_type(&[], false);
        let scratch =
            self.module
                .add_function("__trax_const_eval", scratch_ty, Some(Linkage::Private));
        let entry = self.ctx.append_basic_block(scratch, "entry");
        let body_bb = self.ctx.append_basic_block(scratch, "b");
        self.b.position_at_end(entry);
        self.b.unset_current_debug_location();
        let br = self.b.build_unconditional_branch(body_bb)?;
        self.b.position_at_end(body_bb);
        let di_file = self.di_file(gd.file);
        self.f = Some(FnState {
            func: scratch,
            alloca_at: br,
            locals: HashMap::new(),
            loops: Vec::new(),
            scope: di_file.as_debug_info_scope(),
            ret: Ty::Unit,
            debug: false,
            panic_args: None,
        });
        let r = self.with_body(g, |l| l.expr(gd.expr));
        let ty = gd.ty.clone();
        self.f = saved_f;
        // SAFETY: the scratch function has no users; nothing refers to it after deletion.
        unsafe { scratch.delete() };
        if let Some(bb) = saved_pos {
            self.b.position_at_end(bb);
        }
        match saved_loc {
            Some(l) => self.b.set_current_debug_location(l),
            None => self.b.unset_current_debug_location(),
        }
        let v = r?;
        let v = self.val(v, &ty);
        if !is_const(v) {
            return Err(LowerError::Diag(self.p.err(
                gd.file,
                syn::spanned::Spanned::span(gd.expr),
                "non-constant-initializer",
                "initializer of a static or const must be a constant expression",
            )));
        }
        Ok(v)
    }

    /// Runs `f` with the body and file of global `g` as the current context.
    fn with_body<T>(&mut self, g: GlobalId, f: impl FnOnce(&mut Self) -> T) -> T {
        let gd = &self.p.globals[g];
        let saved = (self.body, self.file, self.module_id);
        self.body = &self.global_bodies[g];
        self.file = gd.file;
        self.module_id = gd.module;
        let r = f(self);
        (self.body, self.file, self.module_id) = saved;
        r
    }

    fn ty_of(&self, e: &syn::Expr) -> Ty {
        self.body.tys.get(&key(e)).cloned().unwrap_or(Ty::Unit)
    }
}

/// `undef` of any basic type.
pub(crate) fn undef(t: BasicTypeEnum<'_>) -> BasicValueEnum<'_> {
    match t {
        BasicTypeEnum::ArrayType(t) => t.get_undef().into(),
        BasicTypeEnum::FloatType(t) => t.get_undef().into(),
        BasicTypeEnum::IntType(t) => t.get_undef().into(),
        BasicTypeEnum::PointerType(t) => t.get_undef().into(),
        BasicTypeEnum::StructType(t) => t.get_undef().into(),
        BasicTypeEnum::VectorType(t) => t.get_undef().into(),
        BasicTypeEnum::ScalableVectorType(t) => t.get_undef().into(),
    }
}

fn is_const(v: BasicValueEnum<'_>) -> bool {
    match v {
        BasicValueEnum::ArrayValue(v) => v.is_const(),
        BasicValueEnum::IntValue(v) => v.is_const(),
        BasicValueEnum::FloatValue(v) => v.is_const(),
        BasicValueEnum::PointerValue(v) => v.is_const(),
        BasicValueEnum::StructValue(v) => v.is_const(),
        BasicValueEnum::VectorValue(v) => v.is_const(),
        BasicValueEnum::ScalableVectorValue(v) => v.is_const(),
    }
}

fn split_path(p: &std::path::Path) -> (String, String) {
    let name = p
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = p
        .parent()
        .map(|d| d.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = if dir.is_empty() { ".".to_string() } else { dir };
    (name, dir)
}

/// Integer type helpers shared by the lowering modules.
pub(crate) fn int_of(t: &Ty) -> Option<IntTy> {
    match t {
        Ty::Int(i) => Some(*i),
        _ => None,
    }
}
