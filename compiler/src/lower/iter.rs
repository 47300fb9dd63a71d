//! `for` loops. A plain integer range (optionally `.rev()`/`.step_by(n)`) is a counted
//! loop on the range's own type (no overflow at the type's bounds). Every other
//! iterator — arrays and slices by value or reference, `iter()`/`iter_mut()`, and the
//! adapters `rev`, `step_by`, `enumerate`, `zip`, `skip`, `take`, `copied` — is a loop
//! over a logical index `k < len`, each adapter mapping `k` to its source's index.

use super::place::Seq;
use super::{internal, LResult, LoopTarget, Lowerer, V};
use crate::ty::{IntTy, Ty};
use crate::typeck::{classify_iter, key, BindMode, IterInfo, IterSyn, SeqMode};
use inkwell::values::{BasicValueEnum, IntValue};
use inkwell::IntPredicate;
use syn::{Expr, Pat};
use trax_runtime::isa::AbortKind;

/// An evaluated iterator node.
enum Node<'ctx> {
    Range { start: IntValue<'ctx>, ty: Ty },
    Seq { seq: Seq<'ctx>, mode: SeqMode },
    Rev(Box<It<'ctx>>),
    StepBy(Box<It<'ctx>>, IntValue<'ctx>),
    Enumerate(Box<It<'ctx>>),
    Zip(Box<It<'ctx>>, Box<It<'ctx>>),
    Skip(Box<It<'ctx>>, IntValue<'ctx>),
    Take(Box<It<'ctx>>),
    Copied(Box<It<'ctx>>),
}

struct It<'ctx> {
    node: Node<'ctx>,
    /// Number of elements (`u32`).
    len: IntValue<'ctx>,
    /// Element type.
    elem: Ty,
}

impl<'ctx> Lowerer<'ctx, '_, '_> {
    /// Binds a loop or parameter pattern to a value.
    fn bind_value(&mut self, pat: &Pat, v: BasicValueEnum<'ctx>, ty: &Ty) -> LResult<()> {
        if let Pat::Ident(pi) = pat {
            if pi.subpat.is_none() {
                if let Some((id, BindMode::Value)) = self.body.binds.get(&key(pi)).copied() {
                    let lt = self.body.locals[id].ty.clone();
                    let slot = self.local_slot(id, &lt, pi)?;
                    self.b.build_store(slot, v)?;
                    return Ok(());
                }
            }
        }
        if matches!(pat, Pat::Wild(_)) {
            return Ok(());
        }
        let tmp = self.alloca(ty, "for.item")?;
        self.b.build_store(tmp, v)?;
        let fail = self.new_block("for.nomatch");
        self.match_pat(pat, tmp, ty, fail)?;
        let cont = self
            .b
            .get_insert_block()
            .ok_or_else(|| internal("no block"))?;
        self.b.position_at_end(fail);
        self.b.build_unreachable()?;
        self.b.position_at_end(cont);
        Ok(())
    }

    pub(super) fn for_loop(&mut self, e: &Expr, f: &syn::ExprForLoop) -> LResult<V<'ctx>> {
        let infos = self
            .body
            .fors
            .get(&key(e))
            .cloned()
            .ok_or_else(|| internal("for kind"))?;
        let it = classify_iter(&f.expr).map_err(|_| internal("for iter"))?;
        let label = f.label.as_ref().map(|l| l.name.ident.to_string());
        let prev = self.push_scope(f.for_token.span);
        if crate::typeck::is_simple_range(&it) {
            self.range_loop(&it, &infos, f, label)?;
        } else {
            let mut idx = 0;
            let root = self.build_iter(&it, &infos, &mut idx)?;
            self.index_loop(root, f, label)?;
        }
        self.pop_scope(prev);
        Ok(None)
    }

    fn build_iter(
        &mut self,
        it: &IterSyn,
        infos: &[IterInfo],
        idx: &mut usize,
    ) -> LResult<It<'ctx>> {
        let info = infos
            .get(*idx)
            .cloned()
            .ok_or_else(|| internal("iter info"))?;
        *idx += 1;
        let i32t = self.ctx.i32_type();
        let usize_t = Ty::Int(IntTy::Usize);
        let arg = |l: &mut Self, x: &Expr| -> LResult<IntValue<'ctx>> {
            let v = l.expr(x)?;
            Ok(l.val(v, &usize_t).into_int_value())
        };
        let r = match it {
            IterSyn::Range {
                start,
                end,
                inclusive,
            } => {
                let ty = info.elem.clone();
                let signed = matches!(ty, Ty::Int(i) if i.signed());
                let s = self.expr(start)?;
                let s = self.val(s, &ty).into_int_value();
                let en = self.expr(end)?;
                let en = self.val(en, &ty).into_int_value();
                let pred = match (*inclusive, signed) {
                    (true, true) => IntPredicate::SLE,
                    (true, false) => IntPredicate::ULE,
                    (false, true) => IntPredicate::SLT,
                    (false, false) => IntPredicate::ULT,
                };
                let nonempty = self.b.build_int_compare(pred, s, en, "")?;
                let mut d = self.b.build_int_sub(en, s, "")?;
                if *inclusive {
                    d = self
                        .b
                        .build_int_add(d, d.get_type().const_int(1, false), "")?;
                }
                let d = self.b.build_int_cast_sign_flag(d, i32t, false, "")?;
                let len = self
                    .b
                    .build_select(nonempty, d, i32t.const_zero(), "")?
                    .into_int_value();
                It {
                    node: Node::Range {
                        start: s,
                        ty: ty.clone(),
                    },
                    len,
                    elem: ty,
                }
            }
            IterSyn::Seq { base, mode } => {
                let s = self.seq(base, info.derefs)?;
                // `for x in slice_ref` iterates by reference.
                let mode = match (*mode, &info.elem) {
                    (SeqMode::Value, Ty::Ref(m, _)) if info.len.is_none() || info.derefs > 0 => {
                        if *m {
                            SeqMode::RefMut
                        } else {
                            SeqMode::Ref
                        }
                    }
                    (m, _) => m,
                };
                let len = s.len;
                It {
                    node: Node::Seq { seq: s, mode },
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::Rev(i) => {
                let inner = self.build_iter(i, infos, idx)?;
                let len = inner.len;
                It {
                    node: Node::Rev(Box::new(inner)),
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::StepBy(i, n) => {
                let inner = self.build_iter(i, infos, idx)?;
                let step = arg(self, n)?;
                let nz = self
                    .b
                    .build_int_compare(IntPredicate::NE, step, i32t.const_zero(), "")?;
                self.check(nz, AbortKind::Panic, "assertion failed: step != 0")?;
                // ceil(len / step) without overflow: (len - 1) / step + 1 when len > 0.
                let empty =
                    self.b
                        .build_int_compare(IntPredicate::EQ, inner.len, i32t.const_zero(), "")?;
                let lm1 = self
                    .b
                    .build_int_sub(inner.len, i32t.const_int(1, false), "")?;
                let q = self.b.build_int_unsigned_div(lm1, step, "")?;
                let q1 = self.b.build_int_add(q, i32t.const_int(1, false), "")?;
                let len = self
                    .b
                    .build_select(empty, i32t.const_zero(), q1, "")?
                    .into_int_value();
                It {
                    node: Node::StepBy(Box::new(inner), step),
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::Enumerate(i) => {
                let inner = self.build_iter(i, infos, idx)?;
                let len = inner.len;
                It {
                    node: Node::Enumerate(Box::new(inner)),
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::Zip(a, b) => {
                let ia = self.build_iter(a, infos, idx)?;
                let ib = self.build_iter(b, infos, idx)?;
                let lt = self
                    .b
                    .build_int_compare(IntPredicate::ULT, ia.len, ib.len, "")?;
                let len = self
                    .b
                    .build_select(lt, ia.len, ib.len, "")?
                    .into_int_value();
                It {
                    node: Node::Zip(Box::new(ia), Box::new(ib)),
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::Skip(i, n) => {
                let inner = self.build_iter(i, infos, idx)?;
                let n = arg(self, n)?;
                let lt = self
                    .b
                    .build_int_compare(IntPredicate::ULT, n, inner.len, "")?;
                let skip = self.b.build_select(lt, n, inner.len, "")?.into_int_value();
                let len = self.b.build_int_sub(inner.len, skip, "")?;
                It {
                    node: Node::Skip(Box::new(inner), skip),
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::Take(i, n) => {
                let inner = self.build_iter(i, infos, idx)?;
                let n = arg(self, n)?;
                let lt = self
                    .b
                    .build_int_compare(IntPredicate::ULT, n, inner.len, "")?;
                let len = self.b.build_select(lt, n, inner.len, "")?.into_int_value();
                It {
                    node: Node::Take(Box::new(inner)),
                    len,
                    elem: info.elem.clone(),
                }
            }
            IterSyn::Copied(i) => {
                let inner = self.build_iter(i, infos, idx)?;
                let len = inner.len;
                It {
                    node: Node::Copied(Box::new(inner)),
                    len,
                    elem: info.elem.clone(),
                }
            }
        };
        Ok(r)
    }

    /// The element at logical index `k`.
    fn iter_at(&mut self, it: &It<'ctx>, k: IntValue<'ctx>) -> LResult<BasicValueEnum<'ctx>> {
        let i32t = self.ctx.i32_type();
        Ok(match &it.node {
            Node::Range { start, ty } => {
                let signed = matches!(ty, Ty::Int(i) if i.signed());
                let _ = signed;
                let kk = self
                    .b
                    .build_int_cast_sign_flag(k, start.get_type(), false, "")?;
                self.b.build_int_add(*start, kk, "")?.into()
            }
            Node::Seq { seq, mode } => {
                let p = self.seq_elem(seq, k)?;
                match mode {
                    SeqMode::Value => self.b.build_load(p, "")?,
                    _ => p.into(),
                }
            }
            Node::Rev(inner) => {
                let last = self
                    .b
                    .build_int_sub(inner.len, i32t.const_int(1, false), "")?;
                let j = self.b.build_int_sub(last, k, "")?;
                self.iter_at(inner, j)?
            }
            Node::StepBy(inner, step) => {
                let j = self.b.build_int_mul(k, *step, "")?;
                self.iter_at(inner, j)?
            }
            Node::Skip(inner, n) => {
                let j = self.b.build_int_add(k, *n, "")?;
                self.iter_at(inner, j)?
            }
            Node::Take(inner) => self.iter_at(inner, k)?,
            Node::Copied(inner) => {
                let p = self.iter_at(inner, k)?;
                self.b.build_load(p.into_pointer_value(), "")?
            }
            Node::Enumerate(inner) => {
                let v = self.iter_at(inner, k)?;
                let kv: BasicValueEnum = k.into();
                self.tuple_value(&it.elem, &[kv, v])?
            }
            Node::Zip(a, b) => {
                let va = self.iter_at(a, k)?;
                let vb = self.iter_at(b, k)?;
                self.tuple_value(&it.elem, &[va, vb])?
            }
        })
    }

    fn tuple_value(
        &mut self,
        t: &Ty,
        vals: &[BasicValueEnum<'ctx>],
    ) -> LResult<BasicValueEnum<'ctx>> {
        let st = self.llty(t).into_struct_type();
        let mut agg = st.get_undef();
        for (i, v) in vals.iter().enumerate() {
            agg = self
                .b
                .build_insert_value(agg, *v, i as u32, "")?
                .into_struct_value();
        }
        Ok(agg.into())
    }

    fn index_loop(
        &mut self,
        root: It<'ctx>,
        f: &syn::ExprForLoop,
        label: Option<String>,
    ) -> LResult<()> {
        let i32t = self.ctx.i32_type();
        let idx = self.alloca(&Ty::Int(IntTy::Usize), "for.idx")?;
        self.b.build_store(idx, i32t.const_zero())?;
        let head = self.new_block("for.cond");
        let body = self.new_block("for.body");
        let latch = self.new_block("for.next");
        let exit = self.new_block("for.end");
        self.b.build_unconditional_branch(head)?;
        self.b.position_at_end(head);
        let k = self.b.build_load(idx, "")?.into_int_value();
        let c = self
            .b
            .build_int_compare(IntPredicate::ULT, k, root.len, "")?;
        self.b.build_conditional_branch(c, body, exit)?;
        self.b.position_at_end(body);
        let v = self.iter_at(&root, k)?;
        self.bind_value(&f.pat, v, &root.elem)?;
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
        let k = self.b.build_load(idx, "")?.into_int_value();
        let nx = self.b.build_int_add(k, i32t.const_int(1, false), "")?;
        self.b.build_store(idx, nx)?;
        self.b.build_unconditional_branch(head)?;
        self.b.position_at_end(exit);
        Ok(())
    }

    /// A counted loop over `a..b` / `a..=b`, optionally reversed or stepped.
    fn range_loop(
        &mut self,
        it: &IterSyn,
        infos: &[IterInfo],
        f: &syn::ExprForLoop,
        label: Option<String>,
    ) -> LResult<()> {
        let (rev, step_e, inner) = match it {
            IterSyn::Rev(i) => (true, None, &**i),
            IterSyn::StepBy(i, s) => (false, Some(*s), &**i),
            other => (false, None, other),
        };
        let IterSyn::Range {
            start,
            end,
            inclusive,
        } = inner
        else {
            return Err(internal("range loop"));
        };
        let inclusive = *inclusive;
        let ty = infos
            .last()
            .map(|i| i.elem.clone())
            .ok_or_else(|| internal("range type"))?;
        let signed = matches!(ty, Ty::Int(i) if i.signed());
        let s = self.expr(start)?;
        let s = self.val(s, &ty).into_int_value();
        let en = self.expr(end)?;
        let en = self.val(en, &ty).into_int_value();
        let step = match step_e {
            Some(st) => {
                let v = self.expr(st)?;
                let v = self.val(v, &Ty::Int(IntTy::Usize)).into_int_value();
                let nz =
                    self.b
                        .build_int_compare(IntPredicate::NE, v, v.get_type().const_zero(), "")?;
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
        let nonempty = self
            .b
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
        self.bind_value(&f.pat, v, &ty)?;
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
                let done = self.b.build_int_compare(IntPredicate::EQ, c, last, "")?;
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
        Ok(())
    }
}
