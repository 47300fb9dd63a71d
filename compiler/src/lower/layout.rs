//! LLVM types of structs and enums.
//!
//! A struct is a named LLVM struct of its fields in declaration order (`repr(C)`-like).
//! An enum whose variants carry no data is its tag, an integer of its `repr` type
//! (`isize` by default). Other enums are `{ tag, payload }`: the payload is the variant's
//! fields as a struct when only one variant has data (`Option<T>`, `Result<T, ()>`), else
//! an integer array as large and as aligned as the largest variant, read and written
//! through the variant's struct type.

use super::{internal, LResult, Lowerer};
use crate::ty::Ty;
use inkwell::types::{BasicType, BasicTypeEnum, IntType, StructType};
use inkwell::values::{IntValue, PointerValue};
use inkwell::AddressSpace;

impl<'ctx> Lowerer<'ctx, '_, '_> {
    /// The field types of variant `v` of ADT type `t` (arguments substituted).
    pub(super) fn field_tys(&self, t: &Ty, v: usize) -> Vec<Ty> {
        match t {
            Ty::Adt(a, args) => self.p.adts[*a].variants[v]
                .fields
                .iter()
                .map(|f| self.p.normalize(&f.ty.subst(args)).unwrap_or(Ty::Unit))
                .collect(),
            Ty::Tuple(ts) => ts.clone(),
            _ => Vec::new(),
        }
    }

    /// The tag's integer type of enum `a`.
    pub(super) fn tag_ty(&self, a: usize) -> IntType<'ctx> {
        self.int_ty(self.p.adts[a].repr.bits())
    }

    /// The tag value of variant `v`.
    pub(super) fn tag_val(&self, a: usize, v: usize) -> IntValue<'ctx> {
        let d = self.p.adts[a].variants[v].discr;
        self.tag_ty(a).const_int(d as u64, true)
    }

    /// The index of the only variant with fields, if exactly one has fields.
    pub(super) fn single_data_variant(&self, a: usize) -> Option<usize> {
        let with: Vec<usize> = self.p.adts[a]
            .variants
            .iter()
            .enumerate()
            .filter(|(_, v)| !v.fields.is_empty())
            .map(|(i, _)| i)
            .collect();
        (with.len() == 1).then(|| with[0])
    }

    /// LLVM type of a struct or enum type.
    pub(super) fn adt_ty(&mut self, t: &Ty) -> BasicTypeEnum<'ctx> {
        let Ty::Adt(a, args) = t else {
            return self.ctx.i32_type().into();
        };
        let a = *a;
        let def = &self.p.adts[a];
        if def.is_fieldless_enum() {
            return self.tag_ty(a).into();
        }
        if let Some(st) = self.adt_tys.get(t) {
            return (*st).into();
        }
        let name = if args.is_empty() {
            format!("{}::{}", self.p.modules[def.module].path, def.name)
        } else {
            format!("{}::{}", self.p.modules[def.module].path, self.p.ty_str(t))
        };
        let st = self.ctx.opaque_struct_type(&name);
        self.adt_tys.insert(t.clone(), st);
        if !def.is_enum {
            let ftys = self.field_tys(t, 0);
            let fields: Vec<BasicTypeEnum> = ftys.iter().map(|f| self.llty(f)).collect();
            st.set_body(&fields, false);
            return st.into();
        }
        let tag = self.tag_ty(a);
        let payload: BasicTypeEnum = match self.single_data_variant(a) {
            Some(v) => self.variant_ty(t, v).into(),
            None => {
                let mut size = 0u64;
                let mut align = 1u32;
                for v in 0..self.p.adts[a].variants.len() {
                    let vt = self.variant_ty(t, v);
                    size = size.max(self.td.get_store_size(&vt));
                    align = align.max(self.td.get_abi_alignment(&vt));
                }
                let el: BasicTypeEnum = match align {
                    1 => self.ctx.i8_type().into(),
                    2 => self.ctx.i16_type().into(),
                    4 => self.ctx.i32_type().into(),
                    8 => self.ctx.i64_type().into(),
                    _ => self.ctx.i32_type().vec_type(4).into(),
                };
                let unit = self.td.get_store_size(&el).max(1);
                let n = size.div_ceil(unit) as u32;
                el.array_type(n).into()
            }
        };
        st.set_body(&[tag.into(), payload], false);
        st.into()
    }

    /// The fields of variant `v` of `t` as an LLVM struct.
    pub(super) fn variant_ty(&mut self, t: &Ty, v: usize) -> StructType<'ctx> {
        if let Some(s) = self.variant_tys.get(&(t.clone(), v)) {
            return *s;
        }
        let Ty::Adt(a, _) = t else {
            return self.ctx.struct_type(&[], false);
        };
        let name = format!("{}::{}", self.p.ty_str(t), self.p.adts[*a].variants[v].name);
        let st = self.ctx.opaque_struct_type(&name);
        self.variant_tys.insert((t.clone(), v), st);
        let ftys = self.field_tys(t, v);
        let fields: Vec<BasicTypeEnum> = ftys.iter().map(|f| self.llty(f)).collect();
        st.set_body(&fields, false);
        st
    }

    /// Pointer to the tag of the enum at `p`.
    pub(super) fn tag_ptr(&mut self, p: PointerValue<'ctx>, t: &Ty) -> LResult<PointerValue<'ctx>> {
        let Ty::Adt(a, _) = t else {
            return Err(internal("tag of a non-enum"));
        };
        if self.p.adts[*a].is_fieldless_enum() {
            return Ok(p);
        }
        Ok(self.b.build_struct_gep(p, 0, "tag")?)
    }

    /// Pointer to the fields of variant `v` of the ADT (or tuple) at `p`.
    pub(super) fn variant_ptr(
        &mut self,
        p: PointerValue<'ctx>,
        t: &Ty,
        v: usize,
    ) -> LResult<PointerValue<'ctx>> {
        match t {
            Ty::Adt(a, _) if self.p.adts[*a].is_enum => {
                let payload = self.b.build_struct_gep(p, 1, "payload")?;
                let vt = self.variant_ty(t, v);
                if self.single_data_variant(*a) == Some(v) {
                    return Ok(payload);
                }
                Ok(self.b.build_pointer_cast(
                    payload,
                    vt.ptr_type(AddressSpace::default()),
                    "variant",
                )?)
            }
            _ => Ok(p),
        }
    }

    /// Pointer to field `i` of variant `v` of the struct, enum or tuple at `p`.
    pub(super) fn field_ptr(
        &mut self,
        p: PointerValue<'ctx>,
        t: &Ty,
        v: usize,
        i: usize,
    ) -> LResult<PointerValue<'ctx>> {
        let base = self.variant_ptr(p, t, v)?;
        Ok(self.b.build_struct_gep(base, i as u32, "")?)
    }
}
