//! Formatted text: `print!`/`println!` and panic messages become one argument record
//! (`trax_runtime::abortmsg`) that the machine renders with Rust's own formatting — one
//! `trax.printfmt` per print, so output is byte-identical to `trax native` by
//! construction. Values shown with `{:?}` that are not scalars (structs, enums, tuples,
//! arrays, slices) are passed by address with a *type descriptor* the compiler emits
//! into read-only data.

use super::{internal, LResult, Lowerer};
use crate::ty::{FloatTy, Ty};
use crate::typeck::{Count, FmtPiece, FmtSpec, FmtTrait};
use inkwell::module::Linkage;
use inkwell::values::{BasicValueEnum, GlobalValue, IntValue, PointerValue};
use trax_runtime::abortmsg::{self, desc, Spec, ValueKind};
use trax_runtime::isa::{instr, TraxOp};

/// A run-time argument of a message.
pub(super) struct MsgArg<'ctx> {
    /// The value, or its address when `by_addr`.
    pub v: BasicValueEnum<'ctx>,
    /// Its type.
    pub ty: Ty,
    /// Format spec.
    pub spec: Spec,
    /// Width and precision given by arguments.
    pub width: Option<IntValue<'ctx>>,
    pub prec: Option<IntValue<'ctx>>,
    /// `v` is the address of the value.
    pub by_addr: bool,
}

/// One part of a message.
pub(super) enum Part<'ctx> {
    /// Constant text.
    Text(String),
    /// A run-time value.
    Arg(MsgArg<'ctx>),
}

/// The runtime spec of a checked format spec.
pub(super) fn spec_of(s: &FmtSpec) -> Spec {
    use abortmsg::{Align as A, Count as C, Trait as T};
    let align = match s.align {
        crate::typeck::Align::None => A::None,
        crate::typeck::Align::Left => A::Left,
        crate::typeck::Align::Center => A::Center,
        crate::typeck::Align::Right => A::Right,
    };
    let count = |c: &Count| match c {
        Count::None => C::None,
        Count::Is(n) => C::Is(*n),
        Count::Arg(_) => C::Slot,
    };
    let tr = match (s.tr, s.debug_hex) {
        (FmtTrait::Debug, Some(false)) => T::DebugLowerHex,
        (FmtTrait::Debug, Some(true)) => T::DebugUpperHex,
        (FmtTrait::Debug, None) => T::Debug,
        (FmtTrait::Display, _) => T::Display,
        (FmtTrait::LowerHex, _) => T::LowerHex,
        (FmtTrait::UpperHex, _) => T::UpperHex,
        (FmtTrait::Octal, _) => T::Octal,
        (FmtTrait::Binary, _) => T::Binary,
        (FmtTrait::LowerExp, _) => T::LowerExp,
        (FmtTrait::UpperExp, _) => T::UpperExp,
    };
    Spec {
        fill: s.fill,
        align,
        plus: s.plus,
        alternate: s.alternate,
        zero: s.zero,
        width: count(&s.width),
        precision: count(&s.precision),
        tr,
    }
}

/// True for types whose values go into a slot directly.
fn is_leaf(t: &Ty) -> bool {
    matches!(
        t,
        Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Str | Ty::Unit
    )
}

impl<'ctx> Lowerer<'ctx, '_, '_> {
    /// Evaluates the arguments of formatted text (in order) into message parts.
    pub(super) fn message_parts(&mut self, pieces: &[FmtPiece]) -> LResult<Vec<Part<'ctx>>> {
        let mut parts = Vec::new();
        let usize_t = Ty::Int(crate::ty::IntTy::Usize);
        for p in pieces {
            match p {
                FmtPiece::Lit(s) => parts.push(Part::Text(s.clone())),
                FmtPiece::Arg(e, fs) => {
                    let count = |l: &mut Self, c: &Count| -> LResult<Option<IntValue<'ctx>>> {
                        match c {
                            Count::Arg(x) => {
                                let v = l.expr(x)?;
                                Ok(Some(l.val(v, &usize_t).into_int_value()))
                            }
                            _ => Ok(None),
                        }
                    };
                    let width = count(self, &fs.width)?;
                    let prec = count(self, &fs.precision)?;
                    let t = self.ty_of(e);
                    let mut base = t.clone();
                    while let Ty::Ref(_, inner) = &base {
                        if matches!(**inner, Ty::Slice(_)) {
                            break;
                        }
                        base = (**inner).clone();
                    }
                    let (v, by_addr) = if is_leaf(&base) {
                        let mut v = self.expr(e)?;
                        let mut cur = t.clone();
                        while let Ty::Ref(_, inner) = cur {
                            let p = self
                                .val(v, &Ty::Ref(false, inner.clone()))
                                .into_pointer_value();
                            v = if inner.is_zst() {
                                None
                            } else {
                                Some(self.b.build_load(p, "")?)
                            };
                            cur = *inner;
                        }
                        (self.val(v, &base), false)
                    } else if t != base {
                        // A reference to a composite: its value is the address.
                        let mut v = self.expr(e)?;
                        let mut cur = t.clone();
                        while let Ty::Ref(_, inner) = cur {
                            if *inner == base {
                                break;
                            }
                            let p = self
                                .val(v, &Ty::Ref(false, inner.clone()))
                                .into_pointer_value();
                            v = Some(self.b.build_load(p, "")?);
                            cur = *inner;
                        }
                        (self.val(v, &Ty::Ref(false, Box::new(base.clone()))), true)
                    } else {
                        (self.place_or_temp(e)?.into(), true)
                    };
                    parts.push(Part::Arg(MsgArg {
                        v,
                        ty: base,
                        spec: spec_of(fs),
                        width,
                        prec,
                        by_addr,
                    }));
                }
            }
        }
        Ok(parts)
    }

    /// Prints formatted text: constant text with `trax.prints`, anything else with one
    /// `trax.printfmt`.
    pub(super) fn print_pieces(&mut self, pieces: &[FmtPiece]) -> LResult<()> {
        let parts = self.message_parts(pieces)?;
        match self.record(parts)? {
            Err(text) => self.print_str(&text),
            Ok((rec, bytes)) => {
                let i32t = self.ctx.i32_type();
                let addr = self.b.build_ptr_to_int(rec, i32t, "")?;
                let len = i32t.const_int(bytes as u64, false);
                self.trax(instr(TraxOp::PrintFmt), &[addr.into(), len.into()], &[])?;
                Ok(())
            }
        }
    }

    /// Prints constant text.
    pub(super) fn print_str(&mut self, s: &str) -> LResult<()> {
        if s.is_empty() {
            return Ok(());
        }
        let i32t = self.ctx.i32_type();
        let g = self.string_global(s);
        let addr = g.as_pointer_value().const_to_int(i32t);
        let len = i32t.const_int(s.len() as u64, false);
        self.trax(instr(TraxOp::PrintStr), &[addr.into(), len.into()], &[])?;
        Ok(())
    }

    /// Builds a message's argument record in the function's record slot: `Ok((record,
    /// length in bytes))`, or `Err(text)` when the message is constant.
    pub(super) fn record(
        &mut self,
        parts: Vec<Part<'ctx>>,
    ) -> LResult<Result<(PointerValue<'ctx>, u32), String>> {
        let mut template = Vec::new();
        let mut words: Vec<(IntValue<'ctx>, Option<IntValue<'ctx>>)> = Vec::new();
        let mut any = false;
        let i32t = self.ctx.i32_type();
        for p in parts {
            match p {
                Part::Text(t) => abortmsg::push_text(&t, &mut template),
                Part::Arg(a) => {
                    any = true;
                    let (kind, size, w) = self.slot_words(&a)?;
                    a.spec.encode(kind, size, &mut template);
                    for c in [a.width, a.prec].into_iter().flatten() {
                        words.push((c, None));
                    }
                    words.push(w);
                }
            }
        }
        if !any {
            let text = String::from_utf8_lossy(&template).replace("\0\0", "\0");
            return Ok(Err(text));
        }
        let n_words = 2 + 2 * words.len() as u32;
        // One record per function, as large as its largest message needs.
        let record = match self.fs().panic_args {
            Some((r, n)) if n >= n_words => r,
            _ => {
                let r = self.alloca(
                    &Ty::Array(Box::new(Ty::Int(crate::ty::IntTy::U32)), n_words),
                    "msg.args",
                )?;
                self.fs().panic_args = Some((r, n_words));
                r
            }
        };
        let k = format!(
            "tpl:{}",
            template
                .iter()
                .map(|b| format!("{b:02x}"))
                .collect::<String>()
        );
        let g = self.bytes_global(&template, &k);
        let tpl_addr = g.as_pointer_value().const_to_int(i32t);
        let tpl_len = i32t.const_int(template.len() as u64, false);
        let mut all: Vec<(u32, IntValue<'ctx>)> = vec![(0, tpl_addr), (1, tpl_len)];
        for (i, (lo, hi)) in words.into_iter().enumerate() {
            let slot = 2 + 2 * i as u32;
            all.push((slot, lo));
            if let Some(hi) = hi {
                all.push((slot + 1, hi));
            }
        }
        for (i, w) in all {
            // SAFETY: `i < n_words`, the length of the record array.
            let p = unsafe {
                self.b.build_in_bounds_gep(
                    record,
                    &[i32t.const_zero(), i32t.const_int(i as u64, false)],
                    "",
                )?
            };
            self.b.build_store(p, w)?;
        }
        // The record's address as the slot array's first element.
        let rp = self.b.build_pointer_cast(
            record,
            i32t.ptr_type(inkwell::AddressSpace::default()),
            "",
        )?;
        Ok(Ok((rp, 4 * n_words)))
    }

    /// The value kind, integer size and slot words of an argument.
    fn slot_words(
        &mut self,
        a: &MsgArg<'ctx>,
    ) -> LResult<(ValueKind, u8, (IntValue<'ctx>, Option<IntValue<'ctx>>))> {
        let i32t = self.ctx.i32_type();
        let i64t = self.ctx.i64_type();
        let split64 = |l: &mut Self,
                       x: IntValue<'ctx>|
         -> LResult<(IntValue<'ctx>, Option<IntValue<'ctx>>)> {
            let lo = l.b.build_int_truncate(x, i32t, "")?;
            let hi =
                l.b.build_right_shift(x, i64t.const_int(32, false), false, "")?;
            let hi = l.b.build_int_truncate(hi, i32t, "")?;
            Ok((lo, Some(hi)))
        };
        if a.by_addr {
            let d = self.descriptor(&a.ty)?;
            let addr = self
                .b
                .build_ptr_to_int(a.v.into_pointer_value(), i32t, "")?;
            let da = d.as_pointer_value().const_to_int(i32t);
            return Ok((ValueKind::Described, 0, (addr, Some(da))));
        }
        Ok(match &a.ty {
            Ty::Int(it) if it.bits() == 64 => {
                let k = if it.signed() {
                    ValueKind::Int
                } else {
                    ValueKind::Uint
                };
                (k, 8, split64(self, a.v.into_int_value())?)
            }
            Ty::Int(it) => {
                let k = if it.signed() {
                    ValueKind::Int
                } else {
                    ValueKind::Uint
                };
                let x =
                    self.b
                        .build_int_cast_sign_flag(a.v.into_int_value(), i32t, it.signed(), "")?;
                (k, (it.bits() / 8) as u8, (x, None))
            }
            Ty::Float(FloatTy::F32) => {
                let x = self.b.build_bit_cast(a.v, i32t, "")?.into_int_value();
                (ValueKind::F32, 0, (x, None))
            }
            Ty::Float(FloatTy::F64) => {
                let x = self.b.build_bit_cast(a.v, i64t, "")?.into_int_value();
                (ValueKind::F64, 0, split64(self, x)?)
            }
            Ty::Bool => {
                let x = self.b.build_int_z_extend(a.v.into_int_value(), i32t, "")?;
                (ValueKind::Bool, 0, (x, None))
            }
            Ty::Char => (ValueKind::Char, 0, (a.v.into_int_value(), None)),
            Ty::Str => {
                let sv = a.v.into_struct_value();
                let p = self.b.build_extract_value(sv, 0, "")?.into_int_value();
                let l = self.b.build_extract_value(sv, 1, "")?.into_int_value();
                (ValueKind::Str, 0, (p, Some(l)))
            }
            Ty::Unit => (ValueKind::Unit, 0, (i32t.const_zero(), None)),
            other => {
                return Err(internal(format!(
                    "message argument of type {}",
                    self.p.ty_str(other)
                )))
            }
        })
    }

    /// The type descriptor of `t` (emitted once per type).
    pub(super) fn descriptor(&mut self, t: &Ty) -> LResult<GlobalValue<'ctx>> {
        if let Some(g) = self.descriptors.get(t) {
            return Ok(*g);
        }
        let mut node = Vec::new();
        self.desc_node(t, &mut node, 0)?;
        let mut bytes = (node.len() as u32).to_le_bytes().to_vec();
        bytes.extend_from_slice(&node);
        let data = self.ctx.const_string(&bytes, false);
        let g = self.module.add_global(
            data.get_type(),
            None,
            &format!(".desc.{}", self.descriptors.len()),
        );
        g.set_initializer(&data);
        g.set_constant(true);
        g.set_linkage(Linkage::Private);
        g.set_alignment(1);
        self.descriptors.insert(t.clone(), g);
        Ok(g)
    }

    fn desc_node(&mut self, t: &Ty, out: &mut Vec<u8>, depth: u32) -> LResult<()> {
        if depth > 64 {
            return Err(internal("type descriptor too deep"));
        }
        match t {
            Ty::Int(it) => {
                out.push(if it.signed() { desc::INT } else { desc::UINT });
                out.push((it.bits() / 8) as u8);
            }
            Ty::Float(FloatTy::F32) => out.push(desc::F32),
            Ty::Float(FloatTy::F64) => out.push(desc::F64),
            Ty::Bool => out.push(desc::BOOL),
            Ty::Char => out.push(desc::CHAR),
            Ty::Str => out.push(desc::STR),
            Ty::Unit | Ty::Never => out.push(desc::UNIT),
            Ty::Ptr(..) => out.push(desc::PTR),
            Ty::Ref(_, inner) => match &**inner {
                Ty::Slice(el) => {
                    out.push(desc::SLICE);
                    let lt = self.llty(el);
                    out.extend_from_slice(&(self.td.get_abi_size(&lt) as u32).to_le_bytes());
                    self.desc_node(el, out, depth + 1)?;
                }
                other => {
                    out.push(desc::REF);
                    self.desc_node(other, out, depth + 1)?;
                }
            },
            Ty::Array(el, n) => {
                out.push(desc::ARRAY);
                out.extend_from_slice(&n.to_le_bytes());
                let lt = self.llty(el);
                out.extend_from_slice(&(self.td.get_abi_size(&lt) as u32).to_le_bytes());
                self.desc_node(el, out, depth + 1)?;
            }
            Ty::Tuple(ts) => {
                out.push(desc::TUPLE);
                out.extend_from_slice(&(ts.len() as u16).to_le_bytes());
                let st = self.llty(t).into_struct_type();
                for (i, et) in ts.iter().enumerate() {
                    let off = self.td.offset_of_element(&st, i as u32).unwrap_or(0) as u32;
                    out.extend_from_slice(&off.to_le_bytes());
                    self.desc_node(et, out, depth + 1)?;
                }
            }
            Ty::Adt(a, _) => {
                let a = *a;
                let def = &self.p.adts[a];
                if !def.is_enum {
                    let st = self.llty(t).into_struct_type();
                    self.variant_node(t, 0, st, 0, out, depth)?;
                    return Ok(());
                }
                let repr = def.repr;
                let nv = def.variants.len();
                out.push(desc::ENUM);
                out.extend_from_slice(&0u32.to_le_bytes());
                out.push((repr.bits() / 8) as u8);
                out.push(repr.signed() as u8);
                out.extend_from_slice(&(nv as u16).to_le_bytes());
                let fieldless = def.is_fieldless_enum();
                let payload_off = if fieldless {
                    0
                } else {
                    let et = self.llty(t).into_struct_type();
                    self.td.offset_of_element(&et, 1).unwrap_or(0) as u32
                };
                for v in 0..nv {
                    let discr = self.p.adts[a].variants[v].discr as i64;
                    out.extend_from_slice(&discr.to_le_bytes());
                    let vt = self.variant_ty(t, v);
                    self.variant_node(t, v, vt, payload_off, out, depth)?;
                }
            }
            other => {
                return Err(internal(format!(
                    "no Debug descriptor for {}",
                    self.p.ty_str(other)
                )))
            }
        }
        Ok(())
    }

    /// A struct or variant node: fields at `base` + their offset in `st`.
    fn variant_node(
        &mut self,
        t: &Ty,
        v: usize,
        st: inkwell::types::StructType<'ctx>,
        base: u32,
        out: &mut Vec<u8>,
        depth: u32,
    ) -> LResult<()> {
        let Ty::Adt(a, _) = t else {
            return Err(internal("variant node"));
        };
        let vd = self.p.adts[*a].variants[v].clone();
        let ftys = self.field_tys(t, v);
        let s16 = |out: &mut Vec<u8>, s: &str| {
            out.extend_from_slice(&(s.len() as u16).to_le_bytes());
            out.extend_from_slice(s.as_bytes());
        };
        match vd.ctor {
            crate::resolve::Ctor::Unit => {
                out.push(desc::UNIT_STRUCT);
                s16(out, &vd.name);
            }
            crate::resolve::Ctor::Named => {
                out.push(desc::STRUCT);
                s16(out, &vd.name);
                out.extend_from_slice(&(ftys.len() as u16).to_le_bytes());
                for (i, ft) in ftys.iter().enumerate() {
                    s16(out, &vd.fields[i].name);
                    let off = base + self.td.offset_of_element(&st, i as u32).unwrap_or(0) as u32;
                    out.extend_from_slice(&off.to_le_bytes());
                    self.desc_node(ft, out, depth + 1)?;
                }
            }
            crate::resolve::Ctor::Tuple => {
                out.push(desc::TUPLE_STRUCT);
                s16(out, &vd.name);
                out.extend_from_slice(&(ftys.len() as u16).to_le_bytes());
                for (i, ft) in ftys.iter().enumerate() {
                    let off = base + self.td.offset_of_element(&st, i as u32).unwrap_or(0) as u32;
                    out.extend_from_slice(&off.to_le_bytes());
                    self.desc_node(ft, out, depth + 1)?;
                }
            }
        }
        Ok(())
    }
}
