//! DWARF: files, types, variables and lexical scopes.

use super::Lowerer;
use crate::diag::{FileId, Loc};
use crate::ty::{FloatTy, IntTy, SimdTy, Ty};
use inkwell::debug_info::{AsDIScope, DIFile, DIScope, DIType};
use inkwell::types::BasicType;
use inkwell::values::PointerValue;
use inkwell::AddressSpace;
use proc_macro2::Span;

/// Lexical blocks nest at most this deep in a function's DWARF (a variable of a deeper
/// block is described in the deepest one; real kernels nest a few dozen). LLVM walks a
/// location's chain of scopes up to its function for each instruction it verifies: 3000
/// nested `if`s took seconds there, 10^4 most of a minute.
const MAX_SCOPE_DEPTH: u32 = 256;

const DW_ATE_BOOLEAN: u32 = 0x02;
const DW_ATE_FLOAT: u32 = 0x04;
const DW_ATE_SIGNED: u32 = 0x05;
const DW_ATE_UNSIGNED: u32 = 0x07;
const DW_ATE_UTF: u32 = 0x10;
const DI_FLAG_VECTOR: u32 = 1 << 11;

impl<'ctx> Lowerer<'ctx, '_, '_> {
    pub(super) fn di_file(&mut self, f: FileId) -> DIFile<'ctx> {
        if let Some(d) = self.di_files.get(&f) {
            return *d;
        }
        let (name, dir) = super::split_path(&self.p.sources.get(f).display);
        let d = self.dib.create_file(&name, &dir);
        self.di_files.insert(f, d);
        d
    }

    fn basic(&self, name: &str, bits: u64, enc: u32) -> DIType<'ctx> {
        self.dib
            .create_basic_type(name, bits, enc, 0)
            .expect("basic type names are non-empty")
            .as_type()
    }

    /// DWARF type of a TRaX type.
    pub(super) fn di_type(&mut self, t: &Ty) -> DIType<'ctx> {
        if let Some(d) = self.di_types.get(t) {
            return *d;
        }
        let d = match t {
            Ty::Unit
            | Ty::Never
            | Ty::Var(_)
            | Ty::Param(_)
            | Ty::Proj(..)
            | Ty::Infer
            | Ty::Slice(_) => {
                let file = self.di_file(self.file);
                self.dib
                    .create_struct_type(
                        file.as_debug_info_scope(),
                        "()",
                        file,
                        0,
                        0,
                        8,
                        0,
                        None,
                        &[],
                        0,
                        None,
                        "()",
                    )
                    .as_type()
            }
            Ty::Closure(c) => self.closure_di(c),
            Ty::Bool => self.basic("bool", 8, DW_ATE_BOOLEAN),
            Ty::Char => self.basic("char", 32, DW_ATE_UTF),
            Ty::Int(i) => self.basic(
                i.name(),
                i.bits() as u64,
                if i.signed() {
                    DW_ATE_SIGNED
                } else {
                    DW_ATE_UNSIGNED
                },
            ),
            Ty::Float(FloatTy::F32) => self.basic("f32", 32, DW_ATE_FLOAT),
            Ty::Float(FloatTy::F64) => self.basic("f64", 64, DW_ATE_FLOAT),
            Ty::Adt(a, _) => {
                let a = *a;
                let def = &self.p.adts[a];
                let file = self.di_file(def.file);
                if self.di_in_progress.contains(t) {
                    // Recursive through a pointer: describe the inner occurrence as opaque.
                    return self
                        .dib
                        .create_struct_type(
                            file.as_debug_info_scope(),
                            &def.name,
                            file,
                            0,
                            0,
                            8,
                            1 << 2,
                            None,
                            &[],
                            0,
                            None,
                            "",
                        )
                        .as_type();
                }
                if def.is_fieldless_enum() {
                    let it = def.repr;
                    let d = self.basic(
                        &def.name,
                        it.bits() as u64,
                        if it.signed() {
                            DW_ATE_SIGNED
                        } else {
                            DW_ATE_UNSIGNED
                        },
                    );
                    self.di_types.insert(t.clone(), d);
                    return d;
                }
                self.di_in_progress.push(t.clone());
                let line = Loc::of(def.span).line;
                let name = self.p.ty_str(t);
                let uid = format!("{}::{}", self.p.modules[def.module].path, name);
                let lt = self.llty(t);
                let st = lt.into_struct_type();
                let mut members = Vec::new();
                if !def.is_enum {
                    let fields = self.field_tys(t, 0);
                    let fdefs = self.p.adts[a].variants[0].fields.clone();
                    for (i, ft) in fields.iter().enumerate() {
                        let off = self.td.offset_of_element(&st, i as u32).unwrap_or(0) * 8;
                        let fline = Loc::of(fdefs[i].span).line;
                        let m = self.member(file, &fdefs[i].name, fline, ft, off);
                        members.push(m);
                    }
                } else {
                    let tag_t = Ty::Int(def.repr);
                    members.push(self.member(file, "discriminant", line, &tag_t, 0));
                    let poff = self.td.offset_of_element(&st, 1).unwrap_or(0) * 8;
                    let nv = self.p.adts[a].variants.len();
                    for v in 0..nv {
                        if self.p.adts[a].variants[v].fields.is_empty() {
                            continue;
                        }
                        let vname = self.p.adts[a].variants[v].name.clone();
                        let vt = self.variant_ty(t, v);
                        let fields = self.field_tys(t, v);
                        let fdefs = self.p.adts[a].variants[v].fields.clone();
                        let mut vm = Vec::new();
                        for (i, ft) in fields.iter().enumerate() {
                            let off = self.td.offset_of_element(&vt, i as u32).unwrap_or(0) * 8;
                            let fname = if fdefs[i].name.chars().all(|c| c.is_ascii_digit()) {
                                format!("__{}", fdefs[i].name)
                            } else {
                                fdefs[i].name.clone()
                            };
                            vm.push(self.member(file, &fname, line, ft, off));
                        }
                        let vsize = self.td.get_bit_size(&vt.as_basic_type_enum());
                        let valign = self.td.get_abi_alignment(&vt) * 8;
                        let vdi = self
                            .dib
                            .create_struct_type(
                                file.as_debug_info_scope(),
                                &vname,
                                file,
                                line,
                                vsize,
                                valign,
                                0,
                                None,
                                &vm,
                                0,
                                None,
                                &format!("{uid}::{vname}"),
                            )
                            .as_type();
                        members.push(
                            self.dib
                                .create_member_type(
                                    file.as_debug_info_scope(),
                                    &vname,
                                    file,
                                    line,
                                    vsize,
                                    valign,
                                    poff,
                                    0,
                                    vdi,
                                )
                                .as_type(),
                        );
                    }
                }
                let size = self.td.get_bit_size(&lt);
                let align = self.td.get_abi_alignment(&st) * 8;
                let d = self
                    .dib
                    .create_struct_type(
                        file.as_debug_info_scope(),
                        &name,
                        file,
                        line,
                        size,
                        align,
                        0,
                        None,
                        &members,
                        0,
                        None,
                        &uid,
                    )
                    .as_type();
                self.di_in_progress.pop();
                d
            }
            Ty::Tuple(ts) => {
                let file = self.di_file(self.file);
                let name = self.p.ty_str(t);
                let lt = self.llty(t);
                let st = lt.into_struct_type();
                let mut members = Vec::new();
                for (i, et) in ts.clone().iter().enumerate() {
                    let off = self.td.offset_of_element(&st, i as u32).unwrap_or(0) * 8;
                    members.push(self.member(file, &format!("__{i}"), 0, et, off));
                }
                let size = self.td.get_bit_size(&lt);
                let align = self.td.get_abi_alignment(&st) * 8;
                self.dib
                    .create_struct_type(
                        file.as_debug_info_scope(),
                        &name,
                        file,
                        0,
                        size,
                        align,
                        0,
                        None,
                        &members,
                        0,
                        None,
                        &name,
                    )
                    .as_type()
            }
            Ty::Array(e, n) => {
                let ed = self.di_type(e);
                let lt = self.llty(t);
                let size = self.td.get_bit_size(&lt);
                let align = self.td.get_abi_alignment(&lt) * 8;
                self.dib
                    .create_array_type(ed, size, align, std::slice::from_ref(&(0..*n as i64)))
                    .as_type()
            }
            Ty::Simd(s) => {
                let ed = match s {
                    SimdTy::F32x4 => self.di_type(&Ty::Float(FloatTy::F32)),
                    SimdTy::I32x4 => self.di_type(&Ty::Int(IntTy::I32)),
                };
                let arr = self
                    .dib
                    .create_array_type(ed, 128, 128, std::slice::from_ref(&(0..4)));
                let _ = DI_FLAG_VECTOR;
                arr.as_type()
            }
            Ty::Ref(_, e) | Ty::Ptr(_, e) if matches!(**e, Ty::Slice(_)) => {
                let Ty::Slice(el) = &**e else { unreachable!() };
                let file = self.di_file(self.file);
                let eld = self.di_type(el);
                let name = self.p.ty_str(t);
                let ptr = self
                    .dib
                    .create_pointer_type(
                        &format!("*const {}", self.p.ty_str(el)),
                        eld,
                        32,
                        32,
                        AddressSpace::default(),
                    )
                    .as_type();
                let len = self.di_type(&Ty::Int(IntTy::Usize));
                let scope = file.as_debug_info_scope();
                let m1 = self
                    .dib
                    .create_member_type(scope, "data_ptr", file, 0, 32, 32, 0, 0, ptr)
                    .as_type();
                let m2 = self
                    .dib
                    .create_member_type(scope, "length", file, 0, 32, 32, 32, 0, len)
                    .as_type();
                self.dib
                    .create_struct_type(
                        scope,
                        &name,
                        file,
                        0,
                        64,
                        32,
                        0,
                        None,
                        &[m1, m2],
                        0,
                        None,
                        &name,
                    )
                    .as_type()
            }
            Ty::Ref(_, e) | Ty::Ptr(_, e) => {
                let ed = self.di_type(e);
                let name = self.p.ty_str(t);
                self.dib
                    .create_pointer_type(&name, ed, 32, 32, AddressSpace::default())
                    .as_type()
            }
            Ty::Str => {
                let file = self.di_file(self.file);
                let u8d = self.di_type(&Ty::Int(IntTy::U8));
                let ptr = self
                    .dib
                    .create_pointer_type("*const u8", u8d, 32, 32, AddressSpace::default())
                    .as_type();
                let len = self.di_type(&Ty::Int(IntTy::Usize));
                let scope = file.as_debug_info_scope();
                let m1 = self
                    .dib
                    .create_member_type(scope, "data_ptr", file, 0, 32, 32, 0, 0, ptr)
                    .as_type();
                let m2 = self
                    .dib
                    .create_member_type(scope, "length", file, 0, 32, 32, 32, 0, len)
                    .as_type();
                self.dib
                    .create_struct_type(
                        scope,
                        "&str",
                        file,
                        0,
                        64,
                        32,
                        0,
                        None,
                        &[m1, m2],
                        0,
                        None,
                        "&str",
                    )
                    .as_type()
            }
        };
        self.di_types.insert(t.clone(), d);
        d
    }

    /// A member of a struct type at bit offset `off`.
    fn member(
        &mut self,
        file: DIFile<'ctx>,
        name: &str,
        line: u32,
        t: &Ty,
        off: u64,
    ) -> DIType<'ctx> {
        let fdi = self.di_type(t);
        let lt = self.llty(t);
        let size = self.td.get_bit_size(&lt);
        let align = self.td.get_abi_alignment(&lt) * 8;
        self.dib
            .create_member_type(
                file.as_debug_info_scope(),
                name,
                file,
                line,
                size,
                align,
                off,
                0,
                fdi,
            )
            .as_type()
    }

    /// Describes a stack slot as a local variable or parameter (`arg` is 1-based).
    pub(super) fn declare_var(
        &mut self,
        slot: PointerValue<'ctx>,
        name: &str,
        t: &Ty,
        span: Span,
        arg: Option<u32>,
    ) {
        if !self.f.as_ref().is_some_and(|f| f.debug) {
            return;
        }
        let ty = self.di_type(t);
        let file = self.di_file(self.file);
        let scope = self.fs().scope;
        let l = Loc::of(span);
        let var = match arg {
            Some(n) => self
                .dib
                .create_parameter_variable(scope, name, n, file, l.line, ty, true, 0),
            None => self
                .dib
                .create_auto_variable(scope, name, file, l.line, ty, true, 0, 0),
        };
        let loc = self
            .dib
            .create_debug_location(self.ctx, l.line, l.col, scope, None);
        if let Some(bb) = self.b.get_insert_block() {
            // Parameters are declared in the entry block, before its terminator.
            match bb.get_terminator() {
                Some(t) => {
                    self.dib
                        .insert_declare_before_instruction(slot, Some(var), None, loc, t);
                }
                None => {
                    self.dib
                        .insert_declare_at_end(slot, Some(var), None, loc, bb);
                }
            }
        }
    }

    /// Opens a lexical block at `span` (within [`MAX_SCOPE_DEPTH`] of the function's
    /// scope: deeper blocks describe their variables in the deepest one); returns the
    /// previous scope to restore.
    pub(super) fn push_scope(&mut self, span: Span) -> DIScope<'ctx> {
        let file = self.di_file(self.file);
        let l = Loc::of(span);
        let fs = self.fs();
        let prev = fs.scope;
        fs.scope_depth += 1;
        if !fs.debug || fs.scope_depth > MAX_SCOPE_DEPTH {
            return prev;
        }
        let lb = self.dib.create_lexical_block(prev, file, l.line, l.col);
        self.fs().scope = lb.as_debug_info_scope();
        prev
    }

    /// Restores a scope saved by [`Self::push_scope`].
    pub(super) fn pop_scope(&mut self, prev: DIScope<'ctx>) {
        let fs = self.fs();
        fs.scope_depth -= 1;
        fs.scope = prev;
    }
}
