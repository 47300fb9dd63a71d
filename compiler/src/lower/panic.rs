//! Panics: `panic!`/`assert!`/`assert_eq!`/`unreachable!`/`todo!`/`unimplemented!` and the
//! compiler's bounds checks stop the program with `trax.abort` and Rust's own message.
//! Messages with run-time values pass an argument record (`trax_runtime::abortmsg`) that
//! the machine renders with `Display`/`Debug`; the record is filled on the failing path
//! only, so a check that passes costs its compare and branch, nothing more.

use super::{LResult, LowerError, Lowerer};
use crate::ty::{FloatTy, IntTy, Ty};
use crate::typeck::{FmtPiece, MacroCall};
use inkwell::values::{BasicValueEnum, IntValue};
use syn::spanned::Spanned;
use trax_runtime::abortmsg::{ArgKind, ABORT_FORMATTED, ESCAPE};
use trax_runtime::isa::{instr, AbortKind, TraxOp};

/// One part of a panic message.
pub(super) enum Part<'ctx> {
    /// Constant text.
    Text(String),
    /// A run-time value of a type, rendered with `Debug` when the flag is set.
    Value(BasicValueEnum<'ctx>, Ty, bool),
}

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
        let mut template = String::new();
        let mut values = Vec::new();
        for p in parts {
            match p {
                Part::Text(t) => {
                    for c in t.chars() {
                        if c == ESCAPE as char {
                            template.push(c);
                        }
                        template.push(c);
                    }
                }
                Part::Value(v, t, debug) => {
                    let (words, k) = self.arg_words(v, &t, debug)?;
                    template.push(ESCAPE as char);
                    template.push(k as u8 as char);
                    values.push(words);
                }
            }
        }
        if values.is_empty() {
            // Constant text: the plain form (no record, the escapes undone).
            let text = template.replace("\0\0", "\0");
            return self.abort(kind, &text);
        }
        let i32t = self.ctx.i32_type();
        let n_words = 2 + 2 * values.len() as u32;
        // One record per function, as large as its largest message needs.
        let record = match self.fs().panic_args {
            Some((r, n)) if n >= n_words => r,
            _ => {
                let r = self.alloca(
                    &Ty::Array(Box::new(Ty::Int(IntTy::U32)), n_words),
                    "panic.args",
                )?;
                self.fs().panic_args = Some((r, n_words));
                r
            }
        };
        let g = self.string_global(&template);
        let tpl_addr = g.as_pointer_value().const_to_int(i32t);
        let tpl_len = i32t.const_int(template.len() as u64, false);
        let mut words: Vec<(u32, IntValue<'ctx>)> = vec![(0, tpl_addr), (1, tpl_len)];
        for (i, (lo, hi)) in values.into_iter().enumerate() {
            let slot = 2 + 2 * i as u32;
            words.push((slot, lo));
            if let Some(hi) = hi {
                words.push((slot + 1, hi));
            }
        }
        for (i, w) in words {
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
        let addr = self.b.build_ptr_to_int(record, i32t, "")?;
        let code = i32t.const_int(kind as u64 | ABORT_FORMATTED as u64, false);
        let len = i32t.const_int(4 * n_words as u64, false);
        self.trax(
            instr(TraxOp::Abort),
            &[code.into(), addr.into(), len.into()],
            &[],
        )?;
        self.b.build_unreachable()?;
        Ok(())
    }

    /// The slot words (low, optional high) and template kind of an argument.
    fn arg_words(
        &mut self,
        v: BasicValueEnum<'ctx>,
        t: &Ty,
        debug: bool,
    ) -> LResult<((IntValue<'ctx>, Option<IntValue<'ctx>>), ArgKind)> {
        let i32t = self.ctx.i32_type();
        Ok(match t {
            Ty::Ref(_, inner) => {
                let x = self.b.build_load(v.into_pointer_value(), "")?;
                return self.arg_words(x, inner, debug);
            }
            Ty::Int(it) if it.bits() == 64 => {
                let x = v.into_int_value();
                let lo = self.b.build_int_truncate(x, i32t, "")?;
                let sh = x.get_type().const_int(32, false);
                let hi = self.b.build_right_shift(x, sh, false, "")?;
                let hi = self.b.build_int_truncate(hi, i32t, "")?;
                let k = if it.signed() {
                    ArgKind::I64
                } else {
                    ArgKind::U64
                };
                ((lo, Some(hi)), k)
            }
            Ty::Int(it) => {
                let x = v.into_int_value();
                let x = self.b.build_int_cast_sign_flag(x, i32t, it.signed(), "")?;
                let k = if it.signed() {
                    ArgKind::I32
                } else {
                    ArgKind::U32
                };
                ((x, None), k)
            }
            Ty::Float(FloatTy::F32) => {
                let x = self.b.build_bit_cast(v, i32t, "")?.into_int_value();
                let k = if debug {
                    ArgKind::F32Debug
                } else {
                    ArgKind::F32
                };
                ((x, None), k)
            }
            Ty::Float(FloatTy::F64) => {
                let i64t = self.ctx.i64_type();
                let x = self.b.build_bit_cast(v, i64t, "")?.into_int_value();
                let lo = self.b.build_int_truncate(x, i32t, "")?;
                let hi = self
                    .b
                    .build_right_shift(x, i64t.const_int(32, false), false, "")?;
                let hi = self.b.build_int_truncate(hi, i32t, "")?;
                let k = if debug {
                    ArgKind::F64Debug
                } else {
                    ArgKind::F64
                };
                ((lo, Some(hi)), k)
            }
            Ty::Bool => {
                let x = self.b.build_int_z_extend(v.into_int_value(), i32t, "")?;
                ((x, None), ArgKind::Bool)
            }
            Ty::Char => {
                let k = if debug {
                    ArgKind::CharDebug
                } else {
                    ArgKind::Char
                };
                ((v.into_int_value(), None), k)
            }
            Ty::Str => {
                let sv = v.into_struct_value();
                let a = self.b.build_extract_value(sv, 0, "")?.into_int_value();
                let l = self.b.build_extract_value(sv, 1, "")?.into_int_value();
                let k = if debug {
                    ArgKind::StrDebug
                } else {
                    ArgKind::Str
                };
                ((a, Some(l)), k)
            }
            other => {
                return Err(LowerError::Internal(format!(
                    "panic message argument of type {}",
                    self.p.ty_str(other)
                )))
            }
        })
    }

    /// The parts of a formatted message; arguments are evaluated here (on the failing
    /// path, as Rust evaluates them only when it panics).
    fn message_parts(&mut self, pieces: &[FmtPiece]) -> LResult<Vec<Part<'ctx>>> {
        let mut parts = Vec::new();
        for p in pieces {
            match p {
                FmtPiece::Lit(s) => parts.push(Part::Text(s.clone())),
                FmtPiece::Arg(e) | FmtPiece::Debug(e) => {
                    let t = self.ty_of(e);
                    let v = self.expr(e)?;
                    if let Some(v) = v {
                        parts.push(Part::Value(v, t, matches!(p, FmtPiece::Debug(_))));
                    }
                }
            }
        }
        Ok(parts)
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
            return Err(LowerError::Internal("not a panicking macro".into()));
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
                let va = self.expr(a)?;
                let va = self.val(va, &ta);
                let vb = self.expr(b)?;
                let vb = self.val(vb, &ta);
                let op = if *ne { "!=" } else { "==" };
                let c = self.arith(op, va, vb, &ta, &ta)?.into_int_value();
                self.set_loc(m.span());
                self.check_with(c, |l| {
                    let mut parts = l.message_parts(pieces)?;
                    parts.push(Part::Text("\n  left: ".into()));
                    parts.push(Part::Value(va, ta.clone(), true));
                    parts.push(Part::Text("\n right: ".into()));
                    parts.push(Part::Value(vb, ta.clone(), true));
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

    /// Aborts with Rust's bounds-check message for index `idx` (a `usize`) into `len`.
    pub(super) fn bounds_abort(&mut self, len: u32, idx: IntValue<'ctx>) -> LResult<()> {
        let parts = vec![
            Part::Text(format!(
                "index out of bounds: the len is {len} but the index is "
            )),
            Part::Value(idx.into(), Ty::Int(IntTy::Usize), false),
        ];
        self.abort_msg(AbortKind::Bounds, parts)
    }
}
