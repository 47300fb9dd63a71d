//! Integer constant expressions evaluated during name collection: array lengths (as
//! `usize`, with rustc's const-evaluation errors), enum discriminants and immediates.

use super::{ModId, Ns, PathRes, Program};
use crate::diag::{DResult, FileId};
use crate::span::Spanned;
use crate::ty::{IntTy, Ty};
use proc_macro2::Span;
use syn::{Expr, Type};

/// The most elements an array type or `[x; N]` may have (2^24).
pub const MAX_ARRAY_LEN: u32 = 1 << 24;

impl<'a> Program<'a> {
    /// Evaluates an array length: a `usize` constant expression, with rustc's const
    /// evaluation errors ("attempt to compute `3_usize - 4_usize`, which would overflow",
    /// "attempt to divide `1_usize` by zero") at the failing operation, which may be in a
    /// `const` the length names; a length past [`MAX_ARRAY_LEN`] is an error saying so.
    pub fn eval_len(&self, module: ModId, file: FileId, e: &Expr) -> DResult<u32> {
        let n = self.eval_typed(module, file, e, IntTy::Usize, "the array length", 0)?;
        match u32::try_from(n) {
            Ok(n) if n <= MAX_ARRAY_LEN => Ok(n),
            _ => Err(self.err(
                file,
                e.span(),
                "invalid-array-length",
                format!(
                    "array length {n} is more than TRaX-Rust allows: at most {MAX_ARRAY_LEN} (2^24) elements per array"
                ),
            )),
        }
    }

    /// The type an integer expression has on its own: a suffixed literal's, a cast's
    /// target, a named const's declared type.
    fn natural_int_type(&self, module: ModId, e: &Expr) -> Option<IntTy> {
        match e {
            Expr::Lit(l) => match &l.lit {
                syn::Lit::Int(i) => IntTy::from_name(i.suffix()),
                _ => None,
            },
            Expr::Paren(p) => self.natural_int_type(module, &p.expr),
            Expr::Cast(c) => match &*c.ty {
                Type::Path(tp) => tp
                    .path
                    .get_ident()
                    .and_then(|i| IntTy::from_name(&i.to_string())),
                _ => None,
            },
            Expr::Path(p) => {
                match self.resolve_from(module, &super::path_segs(&p.path), Ns::Value, 0) {
                    Some(PathRes::Global(g)) => match self.globals[g].decl_ty {
                        Type::Path(tp) => tp
                            .path
                            .get_ident()
                            .and_then(|i| IntTy::from_name(&i.to_string())),
                        _ => None,
                    },
                    Some(PathRes::PrimAssoc(Ty::Int(t), _)) => Some(t),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// Evaluates `e` as a constant of type `t`; `what` names what is being evaluated in
    /// errors ("the array length", "`N`").
    fn eval_typed(
        &self,
        module: ModId,
        file: FileId,
        e: &Expr,
        t: IntTy,
        what: &str,
        depth: u32,
    ) -> DResult<i128> {
        use crate::consteval::{int_binop, show_int, wrap};
        let bad = || {
            self.err(
                file,
                e.span(),
                "not-constant",
                "expected an integer constant expression",
            )
        };
        let fail = |span: Span, message: String| {
            self.err(file, span, "const-evaluation-failed", message)
                .with_label(format!("evaluation of {what} failed here"))
        };
        let lit_range = |l: &syn::LitInt, t: IntTy, negated: bool| -> DResult<i128> {
            let v = l.base10_parse::<i128>().map_err(|_| bad())?;
            let limit = if negated { t.max() + 1 } else { t.max() };
            if v > limit {
                return Err(self.err(
                    file,
                    l.span(),
                    "literal-out-of-range",
                    format!("literal out of range for `{}`", t.name()),
                ));
            }
            Ok(v)
        };
        if depth > 32 {
            return Err(bad());
        }
        match e {
            Expr::Lit(l) => match &l.lit {
                syn::Lit::Int(i) => lit_range(i, IntTy::from_name(i.suffix()).unwrap_or(t), false),
                _ => Err(bad()),
            },
            Expr::Paren(p) => self.eval_typed(module, file, &p.expr, t, what, depth + 1),
            Expr::Group(p) => self.eval_typed(module, file, &p.expr, t, what, depth + 1),
            Expr::Unary(u) => match u.op {
                syn::UnOp::Neg(_) if !t.signed() => Err(self
                    .err(
                        file,
                        u.span(),
                        "cannot-negate-unsigned",
                        format!("cannot apply unary operator `-` to type `{}`", t.name()),
                    )
                    .with_label("cannot apply unary operator `-`")
                    .with_note("unsigned values cannot be negated")),
                syn::UnOp::Neg(_) => {
                    let v = match &*u.expr {
                        Expr::Lit(syn::ExprLit {
                            lit: syn::Lit::Int(i),
                            ..
                        }) => lit_range(i, t, true)?,
                        inner => self.eval_typed(module, file, inner, t, what, depth + 1)?,
                    };
                    if v == t.min() {
                        return Err(fail(
                            u.span(),
                            format!(
                                "attempt to negate `{}`, which would overflow",
                                show_int(t, v)
                            ),
                        ));
                    }
                    Ok(-v)
                }
                syn::UnOp::Not(_) => {
                    let v = self.eval_typed(module, file, &u.expr, t, what, depth + 1)?;
                    Ok(if t.signed() { !v } else { t.max() - v })
                }
                _ => Err(bad()),
            },
            Expr::Binary(b) => {
                use crate::ops::BinOp as Op;
                let (op, assign) = Op::of(&b.op);
                if assign || !(op.is_arith() || op.is_bit() || op.is_shift()) {
                    return Err(bad());
                }
                let l = self.eval_typed(module, file, &b.left, t, what, depth + 1)?;
                let rt = if op.is_shift() {
                    self.natural_int_type(module, &b.right)
                        .unwrap_or(IntTy::I32)
                } else {
                    t
                };
                let r = self.eval_typed(module, file, &b.right, rt, what, depth + 1)?;
                match int_binop(op, t, Some(l), rt, Some(r)) {
                    Ok(Some(v)) => Ok(v),
                    Ok(None) => Err(bad()),
                    Err(f) => Err(fail(b.span(), f.message)),
                }
            }
            Expr::Cast(c) => {
                let Some(to) = self.natural_int_type(module, e) else {
                    return Err(bad());
                };
                // An unsuffixed literal operand takes the target type, as in rustc.
                let from = self.natural_int_type(module, &c.expr).unwrap_or(
                    if matches!(&*c.expr, Expr::Lit(_)) {
                        to
                    } else {
                        IntTy::I32
                    },
                );
                let v = self.eval_typed(module, file, &c.expr, from, what, depth + 1)?;
                Ok(wrap(to, v))
            }
            Expr::Path(p) => {
                let segs = super::path_segs(&p.path);
                match self.resolve_from(module, &segs, Ns::Value, 0) {
                    Some(PathRes::Global(g)) if self.globals[g].is_static.is_none() => {
                        let gd = &self.globals[g];
                        let gt = self.natural_int_type(module, e).unwrap_or(t);
                        let name = format!("`{}`", gd.name);
                        let Some(x) = gd.expr else { return Err(bad()) };
                        self.eval_typed(gd.module, gd.file, x, gt, &name, depth + 1)
                    }
                    Some(PathRes::PrimAssoc(Ty::Int(t), n)) if n == "MAX" => Ok(t.max()),
                    Some(PathRes::PrimAssoc(Ty::Int(t), n)) if n == "MIN" => Ok(t.min()),
                    Some(PathRes::PrimAssoc(Ty::Int(t), n)) if n == "BITS" => Ok(t.bits() as i128),
                    _ => Err(bad()),
                }
            }
            _ => Err(bad()),
        }
    }

    /// Evaluates an integer constant expression (immediates, patterns).
    pub fn eval_int(&self, module: ModId, file: FileId, e: &Expr, depth: u32) -> DResult<i128> {
        let bad = || {
            self.err(
                file,
                e.span(),
                "not-constant",
                "expected an integer constant expression",
            )
        };
        if depth > 32 {
            return Err(bad());
        }
        match e {
            Expr::Lit(l) => match &l.lit {
                syn::Lit::Int(i) => i.base10_parse::<i128>().map_err(|_| bad()),
                _ => Err(bad()),
            },
            Expr::Paren(p) => self.eval_int(module, file, &p.expr, depth + 1),
            Expr::Group(p) => self.eval_int(module, file, &p.expr, depth + 1),
            Expr::Cast(c) => self.eval_int(module, file, &c.expr, depth + 1),
            Expr::Unary(u) => {
                let v = self.eval_int(module, file, &u.expr, depth + 1)?;
                match u.op {
                    syn::UnOp::Neg(_) => Ok(-v),
                    syn::UnOp::Not(_) => Ok(!v),
                    _ => Err(bad()),
                }
            }
            Expr::Binary(b) => {
                let l = self.eval_int(module, file, &b.left, depth + 1)?;
                let r = self.eval_int(module, file, &b.right, depth + 1)?;
                use syn::BinOp::*;
                Ok(match b.op {
                    Add(_) => l + r,
                    Sub(_) => l - r,
                    Mul(_) => l * r,
                    Div(_) if r != 0 => l / r,
                    Rem(_) if r != 0 => l % r,
                    Shl(_) if (0..64).contains(&r) => l << r,
                    Shr(_) if (0..64).contains(&r) => l >> r,
                    BitAnd(_) => l & r,
                    BitOr(_) => l | r,
                    BitXor(_) => l ^ r,
                    _ => return Err(bad()),
                })
            }
            Expr::Path(p) => {
                let segs = super::path_segs(&p.path);
                match self.resolve_from(module, &segs, Ns::Value, 0) {
                    Some(PathRes::Global(g)) if self.globals[g].is_static.is_none() => {
                        let gd = &self.globals[g];
                        let Some(x) = gd.expr else { return Err(bad()) };
                        self.eval_int(gd.module, gd.file, x, depth + 1)
                    }
                    Some(PathRes::PrimAssoc(Ty::Int(t), n)) if n == "MAX" => Ok(t.max()),
                    Some(PathRes::PrimAssoc(Ty::Int(t), n)) if n == "MIN" => Ok(t.min()),
                    Some(PathRes::PrimAssoc(Ty::Int(t), n)) if n == "BITS" => Ok(t.bits() as i128),
                    _ => Err(bad()),
                }
            }
            _ => Err(bad()),
        }
    }

    /// Evaluates an enum discriminant of type `repr`.
    pub fn eval_discr(&self, module: ModId, file: FileId, e: &Expr, repr: IntTy) -> DResult<i128> {
        self.eval_typed(module, file, e, repr, "the discriminant", 0)
    }
}
