//! Compile-time evaluation and the checks rustc makes with it, run on every type-checked
//! body:
//! - `overflowing_literals` (deny): an integer literal outside its type's range (a negated
//!   literal may reach `MIN`), a float literal that rounds to infinity;
//! - E0600: `-` applied to an unsigned integer;
//! - E0080: a `const`/`static` initializer whose evaluation fails (division by zero,
//!   overflow, shift by the bit width or more, index out of bounds);
//! - `arithmetic_overflow` and `unconditional_panic` (deny): the same failures in function
//!   bodies when the operands are known: literals, consts, associated consts, immutable
//!   locals bound to a known value, and `x / 0`, `x % 0`, `x << 32` whatever `x` is.
//!
//! Messages are rustc's (e.g. "attempt to compute `u8::MAX + 1_u8`, which would overflow").

pub mod interp;

use crate::diag::{DResult, Diagnostic, FileId};
use crate::ops::BinOp as Op;
use crate::resolve::{GlobalId, Program};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, Ty};
use crate::typeck::{key, Body, Checked, Count, FmtPiece, LocalId, MacroCall, Res, TraxArg};
use std::collections::HashMap;
use syn::visit::Visit;
use syn::{BinOp, Expr, Lit, Pat, UnOp};

/// A value known at compile time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CVal {
    /// Integer of a type (always within its range).
    Int(IntTy, i128),
    /// Float (an `f32` is held exactly in the `f64`).
    Float(FloatTy, f64),
    /// Boolean.
    Bool(bool),
    /// Character (code point).
    Char(u32),
}

/// An operation that fails: which lint rustc files it under, and rustc's message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// `unconditional_panic` (division by zero, division overflow, bounds) rather than
    /// `arithmetic_overflow`.
    pub panics: bool,
    /// rustc's assertion message.
    pub message: String,
}

fn overflow(message: String) -> Failure {
    Failure {
        panics: false,
        message,
    }
}

fn panic(message: String) -> Failure {
    Failure {
        panics: true,
        message,
    }
}

/// An integer as rustc shows it in messages: `200_u8`, `u8::MAX`, `i32::MIN`, `-1_i32`.
pub fn show_int(t: IntTy, v: i128) -> String {
    if t.signed() && v == t.min() {
        format!("{}::MIN", t.name())
    } else if v == t.max() {
        format!("{}::MAX", t.name())
    } else {
        format!("{v}_{}", t.name())
    }
}

fn show_opt(t: IntTy, v: Option<i128>) -> String {
    v.map_or_else(|| "_".to_string(), |v| show_int(t, v))
}

/// `v` wrapped into `t`'s range (two's complement).
pub fn wrap(t: IntTy, v: i128) -> i128 {
    let bits = t.bits();
    let m = v & ((1i128 << bits) - 1);
    if t.signed() && m >> (bits - 1) & 1 == 1 {
        m - (1i128 << bits)
    } else {
        m
    }
}

/// The arithmetic binary operators: `+ - * / % << >> & | ^` (compound forms included),
/// with whether the operator is a compound assignment.
fn arith_op(op: &syn::BinOp) -> Option<(Op, bool)> {
    let (o, assign) = Op::of(op);
    (o.is_arith() || o.is_bit() || o.is_shift()).then_some((o, assign))
}

/// Integer operation `l op r` in type `t` (the shift amount `r` has its own type `rt`),
/// with rustc's run-time checks. `None` operands are unknown; the result is known when
/// both are.
pub fn int_binop(
    op: Op,
    t: IntTy,
    l: Option<i128>,
    rt: IntTy,
    r: Option<i128>,
) -> Result<Option<i128>, Failure> {
    let (ls, rs) = (show_opt(t, l), show_opt(rt, r));
    match op {
        Op::Div | Op::Rem => {
            if r == Some(0) {
                return Err(panic(if op == Op::Div {
                    format!("attempt to divide `{ls}` by zero")
                } else {
                    format!("attempt to calculate the remainder of `{ls}` with a divisor of zero")
                }));
            }
            if t.signed() && r == Some(-1) && l == Some(t.min()) {
                return Err(panic(if op == Op::Div {
                    format!("attempt to compute `{ls} / {rs}`, which would overflow")
                } else {
                    format!(
                        "attempt to compute the remainder of `{ls} % {rs}`, which would overflow"
                    )
                }));
            }
        }
        Op::Shl | Op::Shr => {
            if let Some(r) = r {
                if r < 0 || r >= t.bits() as i128 {
                    let dir = if op == Op::Shl { "left" } else { "right" };
                    return Err(overflow(format!(
                        "attempt to shift {dir} by `{rs}`, which would overflow"
                    )));
                }
            }
        }
        _ => {}
    }
    let (Some(l), Some(r)) = (l, r) else {
        return Ok(None);
    };
    let v = match op {
        Op::Add => l.checked_add(r),
        Op::Sub => l.checked_sub(r),
        Op::Mul => l.checked_mul(r),
        Op::Div => Some(l / r),
        Op::Rem => Some(l % r),
        Op::Shl => return Ok(Some(wrap(t, l << r))),
        Op::Shr => return Ok(Some(l >> r)),
        Op::BitAnd => Some(l & r),
        Op::BitOr => Some(l | r),
        Op::BitXor => Some(l ^ r),
        _ => return Ok(None),
    };
    let op = op.text();
    match v {
        Some(v) if (t.min()..=t.max()).contains(&v) => Ok(Some(v)),
        _ => Err(overflow(format!(
            "attempt to compute `{ls} {op} {rs}`, which would overflow"
        ))),
    }
}

/// Converts `v` as the `as` operator does.
pub fn cast(v: CVal, to: &Ty) -> Option<CVal> {
    Some(match (v, to) {
        (CVal::Int(_, x), Ty::Int(t)) => CVal::Int(*t, wrap(*t, x)),
        (CVal::Bool(b), Ty::Int(t)) => CVal::Int(*t, b as i128),
        (CVal::Char(c), Ty::Int(t)) => CVal::Int(*t, wrap(*t, c as i128)),
        (CVal::Int(IntTy::U8, x), Ty::Char) => CVal::Char(x as u32),
        (CVal::Int(_, x), Ty::Float(f)) => CVal::Float(*f, round(*f, x as f64)),
        (CVal::Float(_, x), Ty::Float(f)) => CVal::Float(*f, round(*f, x)),
        (CVal::Float(_, x), Ty::Int(t)) => {
            // Saturating, NaN to 0.
            let v = if x.is_nan() {
                0
            } else if x <= t.min() as f64 {
                t.min()
            } else if x >= t.max() as f64 {
                t.max()
            } else {
                x.trunc() as i128
            };
            CVal::Int(*t, v)
        }
        _ => return None,
    })
}

fn round(f: FloatTy, x: f64) -> f64 {
    match f {
        FloatTy::F32 => x as f32 as f64,
        FloatTy::F64 => x,
    }
}

/// The value of an integer literal's digits (`None` when it exceeds 128 bits).
fn int_lit_value(l: &syn::LitInt) -> Option<i128> {
    l.base10_parse::<u128>()
        .ok()
        .and_then(|v| i128::try_from(v).ok())
}

/// Evaluates expressions of one body; results are cached per expression.
struct Eval<'p, 'a> {
    p: &'p Program<'a>,
    globals: &'p Checked,
    body: &'p Body,
    /// Immutable locals bound to a known value.
    locals: HashMap<LocalId, CVal>,
    memo: HashMap<usize, Option<CVal>>,
    depth: u32,
}

impl<'p, 'a> Eval<'p, 'a> {
    fn new(p: &'p Program<'a>, globals: &'p Checked, body: &'p Body, depth: u32) -> Self {
        Eval {
            p,
            globals,
            body,
            locals: HashMap::new(),
            memo: HashMap::new(),
            depth,
        }
    }

    fn ty(&self, e: &Expr) -> Ty {
        self.body.tys.get(&key(e)).cloned().unwrap_or(Ty::Unit)
    }

    fn value(&mut self, e: &Expr) -> Option<CVal> {
        if let Some(v) = self.memo.get(&key(e)) {
            return *v;
        }
        let v = self.compute(e);
        self.memo.insert(key(e), v);
        v
    }

    fn int(&mut self, e: &Expr) -> Option<i128> {
        match self.value(e) {
            Some(CVal::Int(_, v)) => Some(v),
            _ => None,
        }
    }

    fn compute(&mut self, e: &Expr) -> Option<CVal> {
        match e {
            Expr::Lit(l) => match (&l.lit, self.ty(e)) {
                (Lit::Int(i), Ty::Int(t)) => {
                    let v = int_lit_value(i)?;
                    (v <= t.max()).then_some(CVal::Int(t, v))
                }
                (Lit::Int(i), Ty::Float(f)) => {
                    Some(CVal::Float(f, round(f, int_lit_value(i)? as f64)))
                }
                (Lit::Float(x), Ty::Float(f)) => {
                    let v = x.base10_parse::<f64>().ok()?;
                    let v = match f {
                        FloatTy::F32 => x.base10_parse::<f32>().ok()? as f64,
                        FloatTy::F64 => v,
                    };
                    v.is_finite().then_some(CVal::Float(f, v))
                }
                (Lit::Bool(b), _) => Some(CVal::Bool(b.value)),
                (Lit::Char(c), _) => Some(CVal::Char(c.value() as u32)),
                (Lit::Byte(b), _) => Some(CVal::Int(IntTy::U8, b.value() as i128)),
                _ => None,
            },
            Expr::Paren(p) => self.value(&p.expr),
            Expr::Group(g) => self.value(&g.expr),
            Expr::Cast(c) => {
                let v = self.value(&c.expr)?;
                cast(v, &self.ty(e))
            }
            Expr::Unary(u) if !self.body.ops.contains_key(&key(e)) => {
                // `-2147483648`: the literal alone is out of range, its negation is `MIN`.
                if let (UnOp::Neg(_), Expr::Lit(l), Ty::Int(t)) =
                    (u.op, strip_parens(&u.expr), self.ty(e))
                {
                    if let Lit::Int(i) = &l.lit {
                        if t.signed() && int_lit_value(i) == Some(t.max() + 1) {
                            return Some(CVal::Int(t, t.min()));
                        }
                    }
                }
                match (u.op, self.value(&u.expr)?) {
                    (UnOp::Neg(_), CVal::Int(t, v)) if t.signed() && v != t.min() => {
                        Some(CVal::Int(t, -v))
                    }
                    (UnOp::Neg(_), CVal::Float(f, v)) => Some(CVal::Float(f, -v)),
                    (UnOp::Not(_), CVal::Bool(b)) => Some(CVal::Bool(!b)),
                    (UnOp::Not(_), CVal::Int(t, v)) if t.signed() => Some(CVal::Int(t, !v)),
                    (UnOp::Not(_), CVal::Int(t, v)) => Some(CVal::Int(t, t.max() - v)),
                    _ => None,
                }
            }
            Expr::Binary(b) if !self.body.ops.contains_key(&key(e)) => self.binary(b),
            Expr::Path(_) => match self.body.res.get(&key(e))? {
                Res::Int(t, v) => Some(CVal::Int(*t, *v)),
                Res::Float(f, v) => Some(CVal::Float(*f, *v)),
                Res::Local(l) => self.locals.get(l).copied(),
                Res::Global(g, s) if s.is_empty() => self.global(*g),
                Res::Global(..) | Res::Unit(..) => None,
            },
            _ => None,
        }
    }

    /// The value of const `g` (statics are not known: rustc does not read them).
    fn global(&mut self, g: GlobalId) -> Option<CVal> {
        let gd = &self.p.globals[g];
        if gd.is_static.is_some() || self.depth > 32 {
            return None;
        }
        let body = self.globals.global_body(g, &[])?;
        Eval::new(self.p, self.globals, body, self.depth + 1).value(gd.expr?)
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> Option<CVal> {
        use BinOp::*;
        if let Some((op, false)) = arith_op(&b.op) {
            let (l, r) = (self.value(&b.left)?, self.value(&b.right)?);
            return match (l, r) {
                (CVal::Int(t, x), CVal::Int(rt, y)) => int_binop(op, t, Some(x), rt, Some(y))
                    .ok()?
                    .map(|v| CVal::Int(t, v)),
                (CVal::Float(f, x), CVal::Float(_, y)) => {
                    let v = match op {
                        Op::Add => x + y,
                        Op::Sub => x - y,
                        Op::Mul => x * y,
                        Op::Div => x / y,
                        Op::Rem => x % y,
                        _ => return None,
                    };
                    Some(CVal::Float(f, round(f, v)))
                }
                (CVal::Bool(x), CVal::Bool(y)) => Some(CVal::Bool(match op {
                    Op::BitAnd => x & y,
                    Op::BitOr => x | y,
                    Op::BitXor => x ^ y,
                    _ => return None,
                })),
                _ => None,
            };
        }
        match b.op {
            And(_) => match self.value(&b.left)? {
                CVal::Bool(false) => Some(CVal::Bool(false)),
                _ => self.value(&b.right),
            },
            Or(_) => match self.value(&b.left)? {
                CVal::Bool(true) => Some(CVal::Bool(true)),
                _ => self.value(&b.right),
            },
            Eq(_) | Ne(_) | Lt(_) | Le(_) | Gt(_) | Ge(_) => {
                let (l, r) = (self.value(&b.left)?, self.value(&b.right)?);
                let ord = match (l, r) {
                    (CVal::Int(_, x), CVal::Int(_, y)) => x.partial_cmp(&y),
                    (CVal::Float(_, x), CVal::Float(_, y)) => x.partial_cmp(&y),
                    (CVal::Bool(x), CVal::Bool(y)) => x.partial_cmp(&y),
                    (CVal::Char(x), CVal::Char(y)) => x.partial_cmp(&y),
                    _ => return None,
                };
                use std::cmp::Ordering::*;
                Some(CVal::Bool(match (b.op, ord) {
                    (Ne(_), o) => o != Some(Equal),
                    (_, None) => false,
                    (Eq(_), Some(o)) => o == Equal,
                    (Lt(_), Some(o)) => o == Less,
                    (Le(_), Some(o)) => o != Greater,
                    (Gt(_), Some(o)) => o == Greater,
                    (_, Some(o)) => o != Less,
                }))
            }
            _ => None,
        }
    }
}

/// What the body being checked is.
enum Mode {
    /// A function: failures are lints on known operands.
    Fn,
    /// A const or static initializer, named as rustc names it: failures are evaluation
    /// errors.
    Const(String),
}

struct Checker<'p, 'a> {
    ev: Eval<'p, 'a>,
    file: FileId,
    mode: Mode,
    /// The expression a unary minus applies to (through parentheses), as rustc tracks it
    /// for literals: `-128i8` is in range, `-(-128i8)` is not.
    negated: Option<usize>,
    /// The span of the `-` expression applying to `negated` (rustc reports a negated
    /// literal with its minus sign).
    negated_span: Option<proc_macro2::Span>,
    err: Option<Diagnostic>,
}

fn strip_parens(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip_parens(&p.expr),
        Expr::Group(g) => strip_parens(&g.expr),
        other => other,
    }
}

impl Checker<'_, '_> {
    fn report(&mut self, d: Diagnostic) {
        if self.err.is_none() {
            self.err = Some(d);
        }
    }

    fn diag(
        &self,
        span: proc_macro2::Span,
        id: &'static str,
        msg: impl Into<String>,
    ) -> Diagnostic {
        self.ev.p.err(self.file, span, id, msg)
    }

    fn fail(&mut self, span: proc_macro2::Span, f: Failure) {
        let d = match &self.mode {
            Mode::Const(name) => self
                .diag(span, "const-evaluation-failed", f.message)
                .with_label(format!("evaluation of `{name}` failed here")),
            Mode::Fn if f.panics => self
                .diag(
                    span,
                    "unconditional-panic",
                    "this operation will panic at runtime",
                )
                .with_label(f.message),
            Mode::Fn => self
                .diag(
                    span,
                    "arithmetic-overflow",
                    "this arithmetic operation will overflow",
                )
                .with_label(f.message),
        };
        self.report(d);
    }

    /// Checks literal `l` of type `ty`; `k` is the key of its expression (for negation).
    fn literal(&mut self, k: usize, l: &Lit, ty: Ty) {
        let mut negated = self.negated == Some(k);
        let span = match self.negated_span {
            Some(s) if negated => s,
            _ => l.span(),
        };
        let text = span.source_text().unwrap_or_default();
        match (l, ty) {
            (Lit::Int(i), Ty::Int(t)) => {
                // A literal pattern or range bound holds its own minus sign (`-1 =>`).
                let digits = i.base10_digits();
                let v = match digits.strip_prefix('-') {
                    Some(abs) => {
                        negated = true;
                        if !t.signed() {
                            let d = self
                                .diag(
                                    l.span(),
                                    "cannot-negate-unsigned",
                                    format!(
                                        "cannot apply unary operator `-` to type `{}`",
                                        t.name()
                                    ),
                                )
                                .with_note("unsigned values cannot be negated");
                            self.report(d);
                            return;
                        }
                        abs.parse::<u128>()
                            .ok()
                            .and_then(|v| i128::try_from(v).ok())
                    }
                    None => int_lit_value(i),
                };
                let Some(v) = v else {
                    return;
                };
                let limit = if negated { t.max() + 1 } else { t.max() };
                if v > limit {
                    let digits = i.base10_digits();
                    let lit_text = l.span().source_text().unwrap_or_default();
                    let note = if lit_text.starts_with("0x")
                        || lit_text.starts_with("0o")
                        || lit_text.starts_with("0b")
                    {
                        format!(
                            "the literal `{lit_text}` (decimal `{digits}`) does not fit into the type `{}`",
                            t.name()
                        )
                    } else {
                        format!(
                            "the literal `{text}` does not fit into the type `{}` whose range is `{}..={}`",
                            t.name(),
                            t.min(),
                            t.max()
                        )
                    };
                    let d = self
                        .diag(
                            span,
                            "literal-out-of-range",
                            format!("literal out of range for `{}`", t.name()),
                        )
                        .with_note(note);
                    self.report(d);
                }
            }
            (Lit::Float(x), Ty::Float(f)) => {
                let inf = match f {
                    FloatTy::F32 => x.base10_parse::<f32>().is_ok_and(f32::is_infinite),
                    FloatTy::F64 => x.base10_parse::<f64>().is_ok_and(f64::is_infinite),
                };
                if inf {
                    let d = self
                        .diag(span, "literal-out-of-range", format!("literal out of range for `{}`", f.name()))
                        .with_note(format!(
                            "the literal `{text}` does not fit into the type `{0}` and will be converted to `{0}::INFINITY`",
                            f.name()
                        ));
                    self.report(d);
                }
            }
            _ => {}
        }
    }

    fn check(&mut self, e: &Expr) {
        match e {
            Expr::Lit(l) => self.literal(key(e), &l.lit, self.ev.ty(e)),
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
                if self.negated != Some(key(e)) {
                    self.negated = Some(key(strip_parens(&u.expr)));
                    self.negated_span = Some(e.span());
                }
                if self.ev.body.ops.contains_key(&key(e)) {
                    return;
                }
                match self.ev.ty(e) {
                    Ty::Int(t) if !t.signed() => {
                        let d = self
                            .diag(
                                u.span(),
                                "cannot-negate-unsigned",
                                format!("cannot apply unary operator `-` to type `{}`", t.name()),
                            )
                            .with_label("cannot apply unary operator `-`")
                            .with_note("unsigned values cannot be negated");
                        self.report(d);
                    }
                    Ty::Int(t) if self.ev.int(&u.expr) == Some(t.min()) => {
                        let msg = format!(
                            "attempt to negate `{}`, which would overflow",
                            show_int(t, t.min())
                        );
                        self.fail(e.span(), overflow(msg));
                    }
                    _ => {}
                }
            }
            Expr::Binary(b) if !self.ev.body.ops.contains_key(&key(e)) => {
                let Some((op, assign)) = arith_op(&b.op) else {
                    return;
                };
                let (Ty::Int(t), Ty::Int(rt)) = (self.ev.ty(&b.left), self.ev.ty(&b.right)) else {
                    return;
                };
                // A compound assignment's left side is a place, not a known value.
                let l = if assign { None } else { self.ev.int(&b.left) };
                let r = self.ev.int(&b.right);
                if let Err(f) = int_binop(op, t, l, rt, r) {
                    self.fail(e.span(), f);
                }
            }
            Expr::Index(ix) => {
                let mut base = self.ev.ty(&ix.expr);
                while let Ty::Ref(_, inner) = base {
                    base = *inner;
                }
                if let (Ty::Array(_, n), Some(i)) = (base, self.ev.int(&ix.index)) {
                    if i >= n as i128 {
                        let msg =
                            format!("index out of bounds: the length is {n} but the index is {i}");
                        self.fail(e.span(), panic(msg));
                    }
                }
            }
            _ => {}
        }
    }
}

impl<'p> Visit<'p> for Checker<'p, '_> {
    fn visit_expr(&mut self, e: &'p Expr) {
        if self.err.is_some() {
            return;
        }
        self.check(e);
        // A branch a known condition never takes is not checked (rustc's lint follows the
        // taken branch only).
        if let Expr::If(i) = e {
            if let Some(CVal::Bool(c)) = self.ev.value(&i.cond) {
                self.visit_expr(&i.cond);
                if c {
                    self.visit_block(&i.then_branch);
                } else if let Some((_, els)) = &i.else_branch {
                    self.visit_expr(els);
                }
                return;
            }
        }
        syn::visit::visit_expr(self, e);
    }

    fn visit_local(&mut self, l: &'p syn::Local) {
        syn::visit::visit_local(self, l);
        let pat = match &l.pat {
            Pat::Type(t) => &*t.pat,
            p => p,
        };
        if let (Pat::Ident(pi), Some(init)) = (pat, &l.init) {
            if pi.mutability.is_none() && pi.by_ref.is_none() && init.diverge.is_none() {
                if let (Some(&id), Some(v)) = (
                    self.ev.body.binds.get(&key(pi)).map(|(id, _)| id),
                    self.ev.value(&init.expr),
                ) {
                    self.ev.locals.insert(id, v);
                }
            }
        }
    }

    fn visit_macro(&mut self, m: &'p syn::Macro) {
        let body = self.ev.body;
        let Some(call) = body.macros.get(&key(m)) else {
            return;
        };
        let args = |pieces: &'p [FmtPiece]| {
            pieces.iter().flat_map(|p| match p {
                FmtPiece::Arg(e, spec) => {
                    let mut v = vec![&**e];
                    for c in [&spec.width, &spec.precision] {
                        if let Count::Arg(x) = c {
                            v.push(&**x);
                        }
                    }
                    v
                }
                FmtPiece::Lit(_) => Vec::new(),
            })
        };
        let mut exprs: Vec<&Expr> = Vec::new();
        match call {
            MacroCall::Print(pieces) => exprs.extend(args(pieces)),
            MacroCall::Abort {
                cond, cmp, pieces, ..
            } => {
                exprs.extend(cond.as_deref());
                if let Some((a, b, _)) = cmp {
                    exprs.push(a);
                    exprs.push(b);
                }
                exprs.extend(args(pieces));
            }
            MacroCall::TraxOp { args, .. } => exprs.extend(args.iter().filter_map(|a| match a {
                TraxArg::Reg(e) => Some(&**e),
                TraxArg::Imm(_) => None,
            })),
            MacroCall::Mtc2(_, x) => exprs.push(x),
            MacroCall::Matches { expr, guard, .. } => {
                exprs.push(expr);
                exprs.extend(guard.as_deref());
            }
            _ => {}
        }
        for e in exprs {
            self.visit_expr(e);
        }
    }

    fn visit_pat(&mut self, p: &'p Pat) {
        // Literal patterns are typed by their `ExprLit` (match arms against the scrutinee).
        if let Pat::Lit(l) = p {
            let ty = self.ev.body.tys.get(&key(l)).cloned().unwrap_or(Ty::Unit);
            self.literal(key(l), &l.lit, ty);
        }
        syn::visit::visit_pat(self, p);
    }

    // Nested items are bodies of their own.
    fn visit_item(&mut self, _: &'p syn::Item) {}
}

/// Checks function `f`'s body (already type-checked into `body`).
pub fn check_fn(p: &Program, globals: &Checked, f: usize, body: &Body) -> DResult<()> {
    let fd = &p.fns[f];
    let Some(block) = fd.body else { return Ok(()) };
    let mut c = Checker {
        ev: Eval::new(p, globals, body, 0),
        file: fd.file,
        mode: Mode::Fn,
        negated: None,
        negated_span: None,
        err: None,
    };
    c.visit_block(block);
    c.err.map_or(Ok(()), Err)
}

/// Evaluates the initializer of const or static `g` (type-checked into `globals`).
pub fn check_global(p: &Program, globals: &Checked, g: GlobalId, body: &Body) -> DResult<()> {
    let gd = &p.globals[g];
    let Some(expr) = gd.expr else { return Ok(()) };
    // rustc evaluates an associated const only where it is used, but lints its body.
    let mode = match gd.self_ty {
        Some(_) => Mode::Fn,
        None => Mode::Const(gd.name.clone()),
    };
    let mut c = Checker {
        ev: Eval::new(p, globals, body, 0),
        file: gd.file,
        mode,
        negated: None,
        negated_span: None,
        err: None,
    };
    c.visit_expr(expr);
    c.err.map_or(Ok(()), Err)
}

/// Finds a `const` whose value depends on itself: reported at the first reference, in
/// declaration order, that leads back to the const being evaluated.
pub fn check_const_cycles(p: &Program, checked: &Checked) -> Option<Diagnostic> {
    struct Refs<'b> {
        body: &'b Body,
        out: Vec<(proc_macro2::Span, GlobalId)>,
    }
    impl<'v> Visit<'v> for Refs<'_> {
        fn visit_expr(&mut self, e: &'v Expr) {
            if let Expr::Path(_) = e {
                if let Some(Res::Global(g, _)) = self.body.res.get(&key(e)) {
                    self.out.push((e.span(), *g));
                }
            }
            syn::visit::visit_expr(self, e);
        }
    }
    let refs = |g: GlobalId| -> Vec<(proc_macro2::Span, GlobalId)> {
        let gd = &p.globals[g];
        let (Some(expr), Some(body)) = (gd.expr, checked.global_body(g, &[])) else {
            return Vec::new();
        };
        let mut r = Refs {
            body,
            out: Vec::new(),
        };
        r.visit_expr(expr);
        r.out
            .into_iter()
            .filter(|(_, t)| p.globals[*t].is_static.is_none())
            .collect()
    };
    for start in 0..p.globals.len() {
        if p.globals[start].is_static.is_some() || !p.globals[start].generics.is_empty() {
            continue;
        }
        for (span, first) in refs(start) {
            // Does `first` reach `start`?
            let mut seen = vec![false; p.globals.len()];
            let mut stack = vec![first];
            while let Some(g) = stack.pop() {
                if g == start {
                    let gd = &p.globals[start];
                    return Some(p.err(
                        gd.file,
                        span,
                        "recursive-constant",
                        format!("constant `{}` refers to itself", p.globals[first].name),
                    ));
                }
                if std::mem::replace(&mut seen[g], true) {
                    continue;
                }
                stack.extend(refs(g).into_iter().map(|(_, t)| t));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_operations_fail_as_rustc_says() {
        let u8_ = IntTy::U8;
        let i32_ = IntTy::I32;
        assert_eq!(
            int_binop(Op::Add, u8_, Some(255), u8_, Some(1))
                .unwrap_err()
                .message,
            "attempt to compute `u8::MAX + 1_u8`, which would overflow"
        );
        assert_eq!(
            int_binop(Op::Sub, IntTy::Usize, Some(3), IntTy::Usize, Some(4))
                .unwrap_err()
                .message,
            "attempt to compute `3_usize - 4_usize`, which would overflow"
        );
        let f = int_binop(Op::Div, i32_, None, i32_, Some(0)).unwrap_err();
        assert!(f.panics);
        assert_eq!(f.message, "attempt to divide `_` by zero");
        assert_eq!(
            int_binop(Op::Rem, i32_, Some(5), i32_, Some(0))
                .unwrap_err()
                .message,
            "attempt to calculate the remainder of `5_i32` with a divisor of zero"
        );
        assert_eq!(
            int_binop(Op::Div, i32_, Some(i32::MIN as i128), i32_, Some(-1))
                .unwrap_err()
                .message,
            "attempt to compute `i32::MIN / -1_i32`, which would overflow"
        );
        assert_eq!(
            int_binop(Op::Shl, i32_, None, u8_, Some(32))
                .unwrap_err()
                .message,
            "attempt to shift left by `32_u8`, which would overflow"
        );
        assert_eq!(
            int_binop(Op::Shl, u8_, Some(255), i32_, Some(1)),
            Ok(Some(254))
        );
        assert_eq!(
            int_binop(Op::Shr, i32_, Some(-8), i32_, Some(1)),
            Ok(Some(-4))
        );
        assert_eq!(
            int_binop(Op::Div, i32_, Some(-7), i32_, Some(2)),
            Ok(Some(-3))
        );
        assert_eq!(
            int_binop(Op::Rem, i32_, Some(-7), i32_, Some(2)),
            Ok(Some(-1))
        );
        assert_eq!(
            int_binop(
                Op::Mul,
                IntTy::U64,
                Some(u64::MAX as i128),
                IntTy::U64,
                Some(u64::MAX as i128)
            )
            .unwrap_err()
            .message,
            "attempt to compute `u64::MAX * u64::MAX`, which would overflow"
        );
    }

    #[test]
    fn casts_wrap_and_saturate() {
        assert_eq!(
            cast(CVal::Int(IntTy::I32, 300), &Ty::Int(IntTy::U8)),
            Some(CVal::Int(IntTy::U8, 44))
        );
        assert_eq!(
            cast(CVal::Int(IntTy::I32, -1), &Ty::Int(IntTy::U32)),
            Some(CVal::Int(IntTy::U32, 0xFFFF_FFFF))
        );
        assert_eq!(
            cast(CVal::Int(IntTy::U32, 0x8000_0000), &Ty::Int(IntTy::I32)),
            Some(CVal::Int(IntTy::I32, -0x8000_0000))
        );
        assert_eq!(
            cast(CVal::Float(FloatTy::F64, 1e10), &Ty::Int(IntTy::I32)),
            Some(CVal::Int(IntTy::I32, i32::MAX as i128))
        );
        assert_eq!(
            cast(CVal::Float(FloatTy::F64, f64::NAN), &Ty::Int(IntTy::U8)),
            Some(CVal::Int(IntTy::U8, 0))
        );
        assert_eq!(
            cast(CVal::Float(FloatTy::F64, -3.7), &Ty::Int(IntTy::I8)),
            Some(CVal::Int(IntTy::I8, -3))
        );
    }
}
