//! Panics: `panic!`/`assert!`/`assert_eq!`/`unreachable!`/`todo!`/`unimplemented!` and the
//! compiler's bounds checks stop the program with `trax.abort` and Rust's own message.
//! Messages with run-time values pass an argument record (`trax_runtime::abortmsg`, built
//! by `lower/fmt.rs`) that the machine renders with Rust's formatting; the record is
//! filled on the failing path only, so a check that passes costs its compare and branch,
//! nothing more.

use super::fmt::{MsgArg, Part};
use super::{internal, LResult, Lowerer};
use crate::span::Spanned;
use crate::ty::{IntTy, Ty};
use crate::typeck::MacroCall;
use inkwell::values::IntValue;
use trax_runtime::abortmsg::{Spec, ABORT_FORMATTED};
use trax_runtime::isa::{instr, AbortKind, TraxOp};

impl<'ctx> Lowerer<'ctx, '_, '_> {
    /// Aborts unless `ok` holds; the failing path runs `fail` (which must abort).
    pub(super) fn check_with(
        &mut self,
        ok: IntValue<'ctx>,
        fail: impl FnOnce(&mut Self) -> LResult<()>,
    ) -> LResult<()> {
        if ok.get_zero_extended_constant() == Some(1) {
            return Ok(());
        }
        let fail_bb = self.new_block("check.fail");
        let cont = self.new_block("check.ok");
        self.b.build_conditional_branch(ok, cont, fail_bb)?;
        self.b.position_at_end(fail_bb);
        fail(self)?;
        self.b.position_at_end(cont);
        Ok(())
    }

    /// Stops the program with `kind` and the message made of `parts`.
    pub(super) fn abort_msg(&mut self, kind: AbortKind, parts: Vec<Part<'ctx>>) -> LResult<()> {
        match self.record(parts)? {
            Err(text) => self.abort(kind, &text),
            Ok((rec, bytes)) => {
                let i32t = self.ctx.i32_type();
                let addr = self.b.build_ptr_to_int(rec, i32t, "")?;
                let code = i32t.const_int(kind as u64 | ABORT_FORMATTED as u64, false);
                let len = i32t.const_int(bytes as u64, false);
                self.trax(
                    instr(TraxOp::Abort),
                    &[code.into(), addr.into(), len.into()],
                    &[],
                )?;
                self.b.build_unreachable()?;
                Ok(())
            }
        }
    }

    /// An `usize` value shown with `{}`.
    fn usize_part(v: IntValue<'ctx>) -> Part<'ctx> {
        Part::Arg(MsgArg {
            v: v.into(),
            ty: Ty::Int(IntTy::Usize),
            spec: Spec::display(),
            width: None,
            prec: None,
            by_addr: false,
        })
    }

    /// Lowers a panicking macro (`MacroCall::Abort`) invoked as `m`. The abort is
    /// attributed to the macro's first token, where Rust reports the panic.
    pub(super) fn abort_macro(&mut self, m: &syn::Macro, call: &MacroCall) -> LResult<()> {
        let MacroCall::Abort {
            kind,
            pieces,
            cond,
            cmp,
        } = call
        else {
            return Err(internal("not a panicking macro"));
        };
        let kind = *kind;
        match (cond, cmp) {
            (Some(c), _) => {
                let v = self.expr(c)?;
                let v = self.val(v, &Ty::Bool).into_int_value();
                self.set_loc(m.span());
                self.check_with(v, |l| {
                    let parts = l.message_parts(pieces)?;
                    l.set_loc(m.span());
                    l.abort_msg(kind, parts)
                })?;
            }
            (None, Some((a, b, ne))) => {
                let ta = self.ty_of(a);
                let pa = self.place_or_temp(a)?;
                let pb = self.place_or_temp(b)?;
                let c = self.derived_eq(pa, pb, &ta)?;
                let c = if *ne { self.b.build_not(c, "")? } else { c };
                self.set_loc(m.span());
                self.check_with(c, |l| {
                    let mut parts = l.message_parts(pieces)?;
                    let show = |l: &mut Self,
                                p: inkwell::values::PointerValue<'ctx>|
                     -> LResult<Part<'ctx>> {
                        let leaf = matches!(
                            ta,
                            Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Str | Ty::Unit
                        );
                        Ok(Part::Arg(if leaf {
                            let v = if ta.is_zst() {
                                l.val(None, &ta)
                            } else {
                                l.b.build_load(p, "")?
                            };
                            MsgArg {
                                v,
                                ty: ta.clone(),
                                spec: Spec::debug(),
                                width: None,
                                prec: None,
                                by_addr: false,
                            }
                        } else {
                            MsgArg {
                                v: p.into(),
                                ty: ta.clone(),
                                spec: Spec::debug(),
                                width: None,
                                prec: None,
                                by_addr: true,
                            }
                        }))
                    };
                    parts.push(Part::Text("\n  left: ".into()));
                    parts.push(show(l, pa)?);
                    parts.push(Part::Text("\n right: ".into()));
                    parts.push(show(l, pb)?);
                    l.set_loc(m.span());
                    l.abort_msg(kind, parts)
                })?;
            }
            (None, None) => {
                let parts = self.message_parts(pieces)?;
                self.set_loc(m.span());
                self.abort_msg(kind, parts)?;
                self.dead_block();
            }
        }
        Ok(())
    }

    /// Aborts with Rust's bounds-check message for index `idx` into `len` (both `usize`).
    pub(super) fn bounds_abort(&mut self, len: IntValue<'ctx>, idx: IntValue<'ctx>) -> LResult<()> {
        let mut parts = vec![Part::Text("index out of bounds: the len is ".into())];
        match len.get_zero_extended_constant() {
            Some(n) => {
                parts[0] = Part::Text(format!(
                    "index out of bounds: the len is {n} but the index is "
                ))
            }
            None => {
                parts.push(Self::usize_part(len));
                parts.push(Part::Text(" but the index is ".into()));
            }
        }
        parts.push(Self::usize_part(idx));
        self.abort_msg(AbortKind::Bounds, parts)
    }

    /// `&s[..hi]` with `hi > len`.
    pub(super) fn slice_end_abort(
        &mut self,
        hi: IntValue<'ctx>,
        len: IntValue<'ctx>,
    ) -> LResult<()> {
        let parts = vec![
            Part::Text("range end index ".into()),
            Self::usize_part(hi),
            Part::Text(" out of range for slice of length ".into()),
            Self::usize_part(len),
        ];
        self.abort_msg(AbortKind::Bounds, parts)
    }

    /// `&s[lo..hi]` with `lo > hi`.
    pub(super) fn slice_order_abort(
        &mut self,
        lo: IntValue<'ctx>,
        hi: IntValue<'ctx>,
    ) -> LResult<()> {
        let parts = vec![
            Part::Text("slice index starts at ".into()),
            Self::usize_part(lo),
            Part::Text(" but ends at ".into()),
            Self::usize_part(hi),
        ];
        self.abort_msg(AbortKind::Bounds, parts)
    }
}
