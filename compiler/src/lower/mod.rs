//! Stage 4: lowering of checked bodies to LLVM IR with debug info (inkwell).
//!
//! Function instances are emitted on demand, starting from `trax_main`, so the object
//! only holds code reachable from the entry point (generic functions once per instance).
//! Every local lives in an `alloca` described with `dbg.declare`; LLVM's mem2reg/SROA
//! promote them at -O1 and above.
//!
//! - `layout`: LLVM types of structs, enums (tag + payload), tuples and slices;
//! - `expr`: blocks, statements, expressions, operators, control flow;
//! - `place`: places (fields, indices, dereferences, slices) and value adjustments;
//! - `pat`: patterns, `match`, `if let`, `while let`, `let` destructuring;
//! - `iter`: `for` loops over ranges, arrays, slices and iterator adapters;
//! - `call`: calls, constructors, derived `clone`/`eq`/`default`, operator impls;
//! - `closure`: closure environments, closure functions and calls;
//! - `builtins`: the builtin catalogue's lowering and the TRaX macros;
//! - `fmt`: formatted prints (argument records and `Debug` type descriptors);
//! - `panic`: panics and bounds checks with Rust's messages;
//! - `debug`: DWARF.

mod builtins;
mod call;
mod closure;
mod debug;
mod expr;
mod fmt;
mod iter;
mod layout;
mod panic;
mod pat;
mod place;

use crate::consteval::interp::Val;
use crate::diag::{FileId, Loc};
use crate::resolve::{FnId, GlobalId, InlineHint, Program};
use crate::ty::{FloatTy, IntTy, SimdTy, Ty};
use crate::typeck::{key, Body, Checked, LocalId};
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

/// Error during lowering: always a compiler bug (the type checker and the compile-time
/// interpreter reject what the lowering cannot handle).
#[derive(Debug)]
pub enum LowerError {
    /// A compiler bug.
    Internal(String),
}

impl From<BuilderError> for LowerError {
    fn from(e: BuilderError) -> Self {
        LowerError::Internal(format!("LLVM builder: {e}"))
    }
}

/// Lowering result.
pub type LResult<T> = Result<T, LowerError>;

/// A lowered value: `None` for `()` and `!`.
pub type V<'ctx> = Option<BasicValueEnum<'ctx>>;

fn internal(s: impl Into<String>) -> LowerError {
    LowerError::Internal(s.into())
}

/// A function to emit.
enum Work {
    /// A function instance.
    Fn(FnId, Vec<Ty>),
    /// The function of a closure type.
    Closure(crate::ty::ClosureTy),
}

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
    /// Lexical blocks open around the current point ([`Self::scope`] is the innermost of
    /// the first `debug::MAX_SCOPE_DEPTH`).
    scope_depth: u32,
    ret: Ty,
    /// False while evaluating constant initializers (no subprogram to describe).
    debug: bool,
    /// The function's message argument record and its size in words, shared by every
    /// panic site and formatted print (`lower/panic.rs`, `lower/fmt.rs`).
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
    checked: &'p Checked,
    /// Values of consts and statics from the compile-time interpreter.
    consts: &'p HashMap<(GlobalId, Vec<Ty>), Val>,
    optimized: bool,
    fns: HashMap<(FnId, Vec<Ty>), FunctionValue<'ctx>>,
    queue: Vec<Work>,
    closures: HashMap<crate::ty::ClosureTy, FunctionValue<'ctx>>,
    globals: HashMap<(GlobalId, Vec<Ty>), GlobalValue<'ctx>>,
    adt_tys: HashMap<Ty, StructType<'ctx>>,
    variant_tys: HashMap<(Ty, usize), StructType<'ctx>>,
    di_files: HashMap<FileId, DIFile<'ctx>>,
    di_types: HashMap<Ty, DIType<'ctx>>,
    di_in_progress: Vec<Ty>,
    strings: HashMap<String, GlobalValue<'ctx>>,
    descriptors: HashMap<Ty, GlobalValue<'ctx>>,
    // Current body context.
    body: &'p Body,
    file: FileId,
    module_id: usize,
    f: Option<FnState<'ctx>>,
    /// Nesting of inlined `const` initializers (guards against cycles).
    const_depth: u32,
}

impl<'ctx, 'p, 'a> Lowerer<'ctx, 'p, 'a> {
    /// Creates a lowerer for `p` whose bodies were checked into `checked`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &'ctx Context,
        name: &str,
        td: TargetData,
        triple: &inkwell::targets::TargetTriple,
        p: &'p Program<'a>,
        checked: &'p Checked,
        consts: &'p HashMap<(GlobalId, Vec<Ty>), Val>,
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
            checked,
            consts,
            optimized,
            fns: HashMap::new(),
            queue: Vec::new(),
            closures: HashMap::new(),
            globals: HashMap::new(),
            adt_tys: HashMap::new(),
            variant_tys: HashMap::new(),
            di_files: HashMap::new(),
            di_types: HashMap::new(),
            di_in_progress: Vec::new(),
            strings: HashMap::new(),
            descriptors: HashMap::new(),
            body: empty,
            file: p.modules[p.kernel_root].file,
            module_id: p.kernel_root,
            f: None,
            const_depth: 0,
        }
    }

    /// Lowers `roots` (`trax_main` and the functions exported to C) and everything they
    /// reach; returns the finished module.
    pub fn run(mut self, roots: &[FnId]) -> LResult<Module<'ctx>> {
        for &root in roots {
            let f = self.declare_fn(root, &[]);
            f.set_linkage(Linkage::External);
        }
        while let Some(w) = self.queue.pop() {
            match w {
                Work::Fn(id, substs) => self.lower_fn(id, substs)?,
                Work::Closure(c) => self.lower_closure(c)?,
            }
        }
        self.dib.finalize();
        Ok(self.module)
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
            Ty::Adt(..) => self.adt_ty(t),
            Ty::Tuple(ts) => {
                let fields: Vec<BasicTypeEnum> = ts.iter().map(|x| self.llty(x)).collect();
                c.struct_type(&fields, false).into()
            }
            Ty::Array(e, n) => self.llty(e).array_type(*n).into(),
            Ty::Ref(_, e) | Ty::Ptr(_, e) => match &**e {
                Ty::Slice(el) => self.slice_ty(el).into(),
                _ => {
                    let inner = self.llty(e);
                    inner.ptr_type(AddressSpace::default()).into()
                }
            },
            // An unsized slice has no value of its own; its element type stands in.
            Ty::Slice(e) => self.llty(e),
            Ty::Simd(SimdTy::F32x4) => c.f32_type().vec_type(4).into(),
            Ty::Simd(SimdTy::I32x4) => c.i32_type().vec_type(4).into(),
            Ty::Str => c
                .struct_type(&[c.i32_type().into(), c.i32_type().into()], false)
                .into(),
            Ty::Closure(cl) => self.closure_ty(cl).into(),
            Ty::Var(_) | Ty::Param(_) | Ty::Proj(..) | Ty::Infer => c.i32_type().into(),
        }
    }

    /// `{ T*, i32 }`: a slice reference.
    pub(crate) fn slice_ty(&mut self, el: &Ty) -> StructType<'ctx> {
        let p = self.llty(el).ptr_type(AddressSpace::default());
        self.ctx
            .struct_type(&[p.into(), self.ctx.i32_type().into()], false)
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

    // ---------------------------------------------------------------- functions

    /// Symbol of a function instance (generic arguments appended).
    fn inst_name(&self, base: &str, substs: &[Ty]) -> String {
        if substs.is_empty() {
            return base.to_string();
        }
        let args: Vec<String> = substs.iter().map(|t| self.p.ty_str(t)).collect();
        format!("{base}::<{}>", args.join(", "))
    }

    fn declare_fn(&mut self, id: FnId, substs: &[Ty]) -> FunctionValue<'ctx> {
        let k = (id, substs.to_vec());
        if let Some(f) = self.fns.get(&k) {
            return *f;
        }
        let fd = &self.p.fns[id];
        let inst = |t: &Ty| self.p.normalize(&t.subst(substs)).unwrap_or(Ty::Unit);
        let param_tys: Vec<Ty> = fd.params.iter().map(inst).collect();
        let ret = inst(&fd.ret);
        let params: Vec<_> = param_tys.iter().map(|t| self.llty(t).into()).collect();
        let fty = match &ret {
            Ty::Unit | Ty::Never => self.ctx.void_type().fn_type(&params, false),
            t => self.llty(t).fn_type(&params, false),
        };
        let symbol = self.inst_name(&fd.symbol, substs);
        let f = self
            .module
            .add_function(&symbol, fty, Some(Linkage::Internal));
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
        if fd.sig.abi.is_some() || fd.foreign {
            self.c_abi_attributes(f, &param_tys, &ret);
        }
        if fd.foreign {
            // Defined by C code of the same link: a declaration only.
            f.set_linkage(Linkage::External);
            self.fns.insert(k, f);
            return f;
        }
        if !self.optimized {
            // Keep every call at -O0 so the debugger sees each function.
            if fd.inline != InlineHint::Always {
                add("noinline");
                add("optnone");
            }
        }
        self.fns.insert(k.clone(), f);
        self.queue.push(Work::Fn(k.0, k.1));
        f
    }

    /// The extension attributes clang-14 gives a C function of these types on mipsel
    /// (`MipsABIInfo`): a caller widens an argument to its register (unsigned 32-bit
    /// values sign-extended, as MIPS keeps them) and a callee widens a return value
    /// narrower than `int`; the other side relies on it.
    fn c_abi_attributes(&self, f: FunctionValue<'ctx>, params: &[Ty], ret: &Ty) {
        let ext = |t: &Ty, is_ret: bool| match t {
            Ty::Bool => Some("zeroext"),
            Ty::Int(i) if is_ret && i.bits() >= 32 => None,
            Ty::Int(i) if i.signed() || i.bits() == 32 => Some("signext"),
            Ty::Int(_) => Some("zeroext"),
            _ => None,
        };
        let attr = |n: &str| {
            self.ctx
                .create_enum_attribute(Attribute::get_named_enum_kind_id(n), 0)
        };
        for (i, t) in params.iter().enumerate() {
            if let Some(n) = ext(t, false) {
                f.add_attribute(AttributeLoc::Param(i as u32), attr(n));
            }
        }
        if let Some(n) = ext(ret, true) {
            f.add_attribute(AttributeLoc::Return, attr(n));
        }
    }

    fn lower_fn(&mut self, id: FnId, substs: Vec<Ty>) -> LResult<()> {
        let fd = &self.p.fns[id];
        let f = self.fns[&(id, substs.clone())];
        self.body = self
            .checked
            .fn_body(id, &substs)
            .ok_or_else(|| internal(format!("no checked body for {}", fd.name)))?;
        let block = fd
            .body
            .ok_or_else(|| internal(format!("{} has no body", fd.name)))?;
        self.file = fd.file;
        self.module_id = fd.module;
        let di_file = self.di_file(fd.file);
        let loc = Loc::of(fd.sig.ident.span());
        let inst = |t: &Ty| self.p.normalize(&t.subst(&substs)).unwrap_or(Ty::Unit);
        let ret = inst(&fd.ret);
        let params: Vec<Ty> = fd.params.iter().map(inst).collect();
        let ret_di = match &ret {
            Ty::Unit | Ty::Never => None,
            t => Some(self.di_type(t)),
        };
        let param_di: Vec<DIType> = params.iter().map(|t| self.di_type(t)).collect();
        let sty = self
            .dib
            .create_subroutine_type(di_file, ret_di, &param_di, 0);
        let external = f.get_linkage() == Linkage::External;
        let name = self.inst_name(&fd.name, &substs);
        let symbol = self.inst_name(&fd.symbol, &substs);
        let sp = self.dib.create_function(
            di_file.as_debug_info_scope(),
            &name,
            Some(&symbol),
            di_file,
            loc.line,
            sty,
            !external,
            true,
            loc.line,
            0,
            self.optimized,
        );
        let start = self.begin_body(f, sp, ret.clone())?;
        let mut pending_pats = Vec::new();
        for (i, arg) in fd.sig.inputs.iter().enumerate() {
            let ty = params[i].clone();
            let pv = f
                .get_nth_param(i as u32)
                .ok_or_else(|| internal("missing parameter"))?;
            match arg {
                syn::FnArg::Receiver(r) => {
                    let slot = self.alloca(&ty, "self")?;
                    self.b.build_store(slot, pv)?;
                    self.declare_var(slot, "self", &ty, r.self_token.span, Some(i as u32 + 1));
                    // `self` is local 0 of a method body.
                    self.fs().locals.insert(0, slot);
                }
                syn::FnArg::Typed(pt) => match &*pt.pat {
                    syn::Pat::Ident(pi) if pi.subpat.is_none() && pi.by_ref.is_none() => {
                        let name = pi.ident.to_string();
                        let slot = self.alloca(&ty, &name)?;
                        self.b.build_store(slot, pv)?;
                        self.declare_var(slot, &name, &ty, pi.ident.span(), Some(i as u32 + 1));
                        if let Some((l, _)) = self.body.binds.get(&key(pi)).copied() {
                            self.fs().locals.insert(l, slot);
                        }
                    }
                    other => {
                        let slot = self.alloca(&ty, "arg")?;
                        self.b.build_store(slot, pv)?;
                        self.declare_var(
                            slot,
                            "_",
                            &ty,
                            crate::span::Spanned::span(pt),
                            Some(i as u32 + 1),
                        );
                        pending_pats.push((other, slot, ty));
                    }
                },
            }
        }
        self.b.position_at_end(start);
        self.set_loc(fd.sig.ident.span());
        // Destructuring parameters bind their parts at the start of the body.
        for (pat, slot, ty) in pending_pats {
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
        let v = self.block(block, false)?;
        if !self.terminated() {
            self.set_loc(block.brace_token.span.close());
            match &ret {
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
    /// Starts lowering the body of `f` (debug subprogram `sp`, returning `ret`): an `entry`
    /// block for allocas and parameter spills, branching to the body's `start` block, with
    /// the builder positioned before that branch; returns `start`. Parameters are spilled there with no
    /// source location (as clang does), so the first located instruction, which LLVM
    /// marks `prologue_end`, is the body's: a debugger's `break FUNC` stops where every
    /// argument is already in its slot.
    fn begin_body(
        &mut self,
        f: FunctionValue<'ctx>,
        sp: inkwell::debug_info::DISubprogram<'ctx>,
        ret: Ty,
    ) -> LResult<BasicBlock<'ctx>> {
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
            scope_depth: 0,
            ret,
            debug: true,
            panic_args: None,
        });
        self.b.position_before(&br);
        Ok(start)
    }

    fn br(&mut self, bb: BasicBlock<'ctx>) -> LResult<()> {
        if !self.terminated() {
            self.b.build_unconditional_branch(bb)?;
        }
        Ok(())
    }

    /// Stack slot in the entry block.
    fn alloca(&mut self, t: &Ty, name: &str) -> LResult<PointerValue<'ctx>> {
        let lt = self.llty(t);
        self.alloca_ll(lt, name)
    }

    fn alloca_ll(&mut self, lt: BasicTypeEnum<'ctx>, name: &str) -> LResult<PointerValue<'ctx>> {
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
        self.bytes_global(s.as_bytes(), s)
    }

    /// A private constant byte array (deduplicated by `key`).
    fn bytes_global(&mut self, bytes: &[u8], k: &str) -> GlobalValue<'ctx> {
        if let Some(g) = self.strings.get(k) {
            return *g;
        }
        let data = self.ctx.const_string(bytes, false);
        let g = self.module.add_global(
            data.get_type(),
            None,
            &format!(".str.{}", self.strings.len()),
        );
        g.set_initializer(&data);
        g.set_constant(true);
        g.set_linkage(Linkage::Private);
        g.set_unnamed_addr(true);
        g.set_alignment(1);
        self.strings.insert(k.to_string(), g);
        g
    }

    /// The address of a static, or of a const aggregate placed in read-only data.
    fn global(&mut self, g: GlobalId, substs: &[Ty]) -> LResult<GlobalValue<'ctx>> {
        let k = (g, substs.to_vec());
        if let Some(v) = self.globals.get(&k) {
            return Ok(*v);
        }
        let gd = &self.p.globals[g];
        let ty = self.p.normalize(&gd.ty.subst(substs)).unwrap_or(Ty::Unit);
        let lt = self.llty(&ty);
        let gv = self
            .module
            .add_global(lt, None, &self.inst_name(&gd.symbol, substs));
        gv.set_linkage(Linkage::Internal);
        self.globals.insert(k, gv);
        let init = self.const_init(g, substs, &ty)?;
        gv.set_initializer(&init);
        gv.set_constant(gd.is_static != Some(true));
        let di_ty = self.di_type(&ty);
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

    /// Evaluates a global's initializer to an LLVM constant: the interpreter's value, or
    /// (for what it does not model, such as addresses of statics) the initializer
    /// lowered and folded.
    fn const_init(&mut self, g: GlobalId, substs: &[Ty], ty: &Ty) -> LResult<BasicValueEnum<'ctx>> {
        if let Some(v) = self.consts.get(&(g, substs.to_vec())) {
            if let Some(c) = self.const_val(ty, v)? {
                return Ok(c);
            }
        }
        let gd = &self.p.globals[g];
        let expr = gd
            .expr
            .ok_or_else(|| internal(format!("const `{}` has no value", gd.name)))?;
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
            scope_depth: 0,
            ret: Ty::Unit,
            debug: false,
            panic_args: None,
        });
        let r = self.with_body(g, substs, |l| l.expr(expr));
        self.f = saved_f;
        // SAFETY: the scratch function's instructions may only be used by each other and
        // by the constant value we keep, which is a constant (not an instruction).
        unsafe { scratch.delete() };
        if let Some(bb) = saved_pos {
            self.b.position_at_end(bb);
        }
        match saved_loc {
            Some(l) => self.b.set_current_debug_location(l),
            None => self.b.unset_current_debug_location(),
        }
        let v = r?;
        let v = self.val(v, ty);
        if !is_const(v) {
            let l = Loc::of(crate::span::Spanned::span(expr));
            return Err(internal(format!(
                "initializer of `{}` at {}:{} did not fold to a constant",
                gd.name,
                self.p.sources.get(gd.file).display.display(),
                l.line
            )));
        }
        Ok(v)
    }

    /// An LLVM constant of type `t` for an interpreter value (`None`: not expressible
    /// as a constant of `t`'s LLVM type).
    pub(super) fn const_val(&mut self, t: &Ty, v: &Val) -> LResult<Option<BasicValueEnum<'ctx>>> {
        let lt = self.llty(t);
        Ok(Some(match (t, v) {
            (_, Val::Unit) => undef(lt),
            (Ty::Int(_), Val::Int(_, x)) => lt.into_int_type().const_int(*x as u64, true).into(),
            (Ty::Float(f), Val::Float(_, x)) => self.float_const(*f, *x),
            (Ty::Bool, Val::Bool(b)) => lt.into_int_type().const_int(*b as u64, false).into(),
            (Ty::Char, Val::Char(c)) => lt.into_int_type().const_int(*c as u64, false).into(),
            (Ty::Str, Val::Str(s)) => self.str_value(s),
            (Ty::Ptr(..), Val::Ptr(a)) => self
                .ctx
                .i32_type()
                .const_int(*a as u64, false)
                .const_to_pointer(lt.into_pointer_type())
                .into(),
            (Ty::Array(el, _), Val::Agg(xs)) => {
                let mut vals = Vec::new();
                for x in xs {
                    match self.const_val(el, x)? {
                        Some(c) => vals.push(c),
                        None => return Ok(None),
                    }
                }
                let elt = self.llty(el);
                expr::const_array(elt, &vals)
            }
            (Ty::Tuple(ts), Val::Agg(xs)) => {
                let mut vals = Vec::new();
                for (et, x) in ts.iter().zip(xs) {
                    match self.const_val(et, x)? {
                        Some(c) => vals.push(c),
                        None => return Ok(None),
                    }
                }
                lt.into_struct_type().const_named_struct(&vals).into()
            }
            (Ty::Adt(a, _), _) => {
                let a = *a;
                let def = &self.p.adts[a];
                let (v, xs) = match v {
                    Val::Agg(xs) => (0, xs),
                    Val::Enum(v, xs) => (*v, xs),
                    _ => return Ok(None),
                };
                if def.is_fieldless_enum() {
                    return Ok(Some(self.tag_val(a, v).into()));
                }
                let ftys = self.field_tys(t, v);
                let mut vals = Vec::new();
                for (ft, x) in ftys.iter().zip(xs) {
                    match self.const_val(ft, x)? {
                        Some(c) => vals.push(c),
                        None => return Ok(None),
                    }
                }
                if !def.is_enum {
                    return Ok(Some(lt.into_struct_type().const_named_struct(&vals).into()));
                }
                let Some(dv) = self.single_data_variant(a) else {
                    return Ok(None);
                };
                let vt = self.variant_ty(t, dv);
                let payload = if v == dv {
                    vt.const_named_struct(&vals)
                } else {
                    vt.const_zero()
                };
                let tag = self.tag_val(a, v);
                lt.into_struct_type()
                    .const_named_struct(&[tag.into(), payload.into()])
                    .into()
            }
            _ => return Ok(None),
        }))
    }

    /// Runs `f` with the body and file of global instance `g` as the current context.
    fn with_body<T>(
        &mut self,
        g: GlobalId,
        substs: &[Ty],
        f: impl FnOnce(&mut Self) -> LResult<T>,
    ) -> LResult<T> {
        let gd = &self.p.globals[g];
        let Some(body) = self.checked.global_body(g, substs) else {
            return Err(internal(format!("no checked body for const `{}`", gd.name)));
        };
        let saved = (self.body, self.file, self.module_id);
        self.body = body;
        self.file = gd.file;
        self.module_id = gd.module;
        let r = f(self);
        (self.body, self.file, self.module_id) = saved;
        r
    }

    /// Type of an expression after its coercion.
    fn ty_of(&self, e: &syn::Expr) -> Ty {
        self.body.ty_of(e)
    }

    /// Type of an expression before its coercion.
    fn raw_ty(&self, e: &syn::Expr) -> Ty {
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

/// The zero value of any basic type.
pub(crate) fn zero(t: BasicTypeEnum<'_>) -> BasicValueEnum<'_> {
    match t {
        BasicTypeEnum::ArrayType(t) => t.const_zero().into(),
        BasicTypeEnum::FloatType(t) => t.const_zero().into(),
        BasicTypeEnum::IntType(t) => t.const_zero().into(),
        BasicTypeEnum::PointerType(t) => t.const_zero().into(),
        BasicTypeEnum::StructType(t) => t.const_zero().into(),
        BasicTypeEnum::VectorType(t) => t.const_zero().into(),
        BasicTypeEnum::ScalableVectorType(t) => t.const_zero().into(),
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
