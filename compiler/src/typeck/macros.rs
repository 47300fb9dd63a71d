//! Builtin macros: `print!`/`println!` (with Rust's format specs), `panic!` and friends,
//! the `assert!` family, `matches!`, and the TRaX intrinsics (`__trax_op!`, ...).

use super::infer::{Cx, VarKind};
use crate::diag::DResult;
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, LangTrait, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::punctuated::Punctuated;
use syn::{Expr, Lit, Token};
use trax_runtime::isa::{AbortKind, OperandKind, TraxInstr, TRAX_INSTRUCTIONS};

/// Alignment of a formatted argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// The type's default.
    None,
    Left,
    Center,
    Right,
}

/// A width or precision.
#[derive(Debug)]
pub enum Count {
    /// Not given.
    None,
    /// A literal number.
    Is(u32),
    /// The value of a `usize` argument (`{:1$}`, `{:w$}`, `{:.*}`).
    Arg(Box<Expr>),
}

/// The formatting trait of an argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmtTrait {
    Display,
    Debug,
    LowerHex,
    UpperHex,
    Octal,
    Binary,
    LowerExp,
    UpperExp,
}

/// A parsed `{:...}` format spec.
#[derive(Debug)]
pub struct FmtSpec {
    /// Fill character (with an alignment).
    pub fill: char,
    /// Alignment.
    pub align: Align,
    /// `+`.
    pub plus: bool,
    /// `#`.
    pub alternate: bool,
    /// `0`.
    pub zero: bool,
    /// Width.
    pub width: Count,
    /// Precision.
    pub precision: Count,
    /// Trait.
    pub tr: FmtTrait,
    /// `{:x?}`/`{:X?}`: debug integers in hex (`Some(upper)`).
    pub debug_hex: Option<bool>,
}

impl FmtSpec {
    /// `{}`.
    pub fn display() -> FmtSpec {
        FmtSpec {
            fill: ' ',
            align: Align::None,
            plus: false,
            alternate: false,
            zero: false,
            width: Count::None,
            precision: Count::None,
            tr: FmtTrait::Display,
            debug_hex: None,
        }
    }

    /// `{:?}`.
    pub fn debug() -> FmtSpec {
        FmtSpec {
            tr: FmtTrait::Debug,
            ..FmtSpec::display()
        }
    }

    /// True for `{}` and `{:?}` without options.
    pub fn is_plain(&self) -> bool {
        self.align == Align::None
            && !self.plus
            && !self.alternate
            && !self.zero
            && matches!(self.width, Count::None)
            && matches!(self.precision, Count::None)
            && self.debug_hex.is_none()
    }
}

/// A piece of formatted text.
#[derive(Debug)]
pub enum FmtPiece {
    /// Literal text.
    Lit(String),
    /// An argument with its spec.
    Arg(Box<Expr>, FmtSpec),
}

/// Operand of a `__trax_op!`.
#[derive(Debug)]
pub enum TraxArg {
    /// Register operand.
    Reg(Box<Expr>),
    /// Immediate.
    Imm(u32),
}

/// A builtin macro invocation, parsed.
#[derive(Debug)]
pub enum MacroCall {
    /// `print!`/`println!`.
    Print(Vec<FmtPiece>),
    /// `panic!`, `unreachable!`, `todo!`, `unimplemented!`, `assert!`, `assert_eq!`,
    /// `assert_ne!`.
    Abort {
        /// Kind reported to the emulator.
        kind: AbortKind,
        /// The panic message as Rust formats it; for `assert_eq!`/`assert_ne!` without the
        /// `left:`/`right:` lines, which the lowering appends from the compared values.
        pieces: Vec<FmtPiece>,
        /// Condition that must hold (assert).
        cond: Option<Box<Expr>>,
        /// Values compared (assert_eq/ne) and whether they must differ.
        cmp: Option<(Box<Expr>, Box<Expr>, bool)>,
    },
    /// `matches!(expr, pat if guard)`.
    Matches {
        /// The scrutinee.
        expr: Box<Expr>,
        /// The pattern.
        pat: Box<syn::Pat>,
        /// The guard.
        guard: Option<Box<Expr>>,
    },
    /// A macro that generates no code: the `debug_assert!` family (debug assertions are
    /// off, as in `trax native`); its arguments are type-checked only.
    Nothing,
    /// `__trax_op!`.
    TraxOp {
        /// Instruction.
        instr: &'static TraxInstr,
        /// Use operands in operand order.
        args: Vec<TraxArg>,
    },
    /// `__trax_mtc2!(n, x)`.
    Mtc2(u32, Box<Expr>),
    /// `__trax_mfc2!(n)`.
    Mfc2(u32),
    /// `__trax_symbol_addr!("name")`.
    SymbolAddr(String),
}

impl MacroCall {
    /// The expressions the macro call holds (parsed from its tokens).
    pub fn exprs(&self) -> Vec<&Expr> {
        fn pieces(ps: &[FmtPiece]) -> Vec<&Expr> {
            ps.iter()
                .filter_map(|p| match p {
                    FmtPiece::Arg(e, _) => Some(&**e),
                    FmtPiece::Lit(_) => None,
                })
                .collect()
        }
        match self {
            MacroCall::Print(ps) => pieces(ps),
            MacroCall::Abort {
                pieces: ps,
                cond,
                cmp,
                ..
            } => {
                let mut v = pieces(ps);
                v.extend(cond.as_deref());
                if let Some((a, b, _)) = cmp {
                    v.push(a);
                    v.push(b);
                }
                v
            }
            MacroCall::Matches { expr, guard, .. } => {
                let mut v = vec![&**expr];
                v.extend(guard.as_deref());
                v
            }
            MacroCall::TraxOp { args, .. } => args
                .iter()
                .filter_map(|a| match a {
                    TraxArg::Reg(e) => Some(&**e),
                    TraxArg::Imm(_) => None,
                })
                .collect(),
            MacroCall::Mtc2(_, e) => vec![&**e],
            MacroCall::Nothing | MacroCall::Mfc2(_) | MacroCall::SymbolAddr(_) => Vec::new(),
        }
    }
}

impl<'p, 'a> Cx<'p, 'a> {
    pub fn mac(&mut self, m: &syn::Macro, span: Span) -> DResult<Ty> {
        let name = m
            .path
            .segments
            .last()
            .map(|s| s.ident.to_string())
            .unwrap_or_default();
        let parse_args = |m: &syn::Macro| -> DResult<Vec<Expr>> {
            let p = m
                .parse_body_with(Punctuated::<Expr, Token![,]>::parse_terminated)
                .map_err(|e| {
                    self.err(
                        e.span(),
                        "invalid-macro-arguments",
                        format!("cannot parse macro arguments: {e}"),
                    )
                })?;
            Ok(p.into_iter().collect())
        };
        let (call, ty) = match name.as_str() {
            "println" | "print" | "eprintln" | "eprint" => {
                let args = parse_args(m)?;
                let mut pieces = self.format(args, span)?;
                if name.ends_with("ln") {
                    pieces.push(FmtPiece::Lit("\n".into()));
                }
                self.check_fmt_args(&pieces)?;
                (MacroCall::Print(pieces), Ty::Unit)
            }
            "panic" | "unreachable" | "todo" | "unimplemented" => {
                let args = parse_args(m)?;
                let (kind, default) = match name.as_str() {
                    "panic" => (AbortKind::Panic, "explicit panic"),
                    "unreachable" => (
                        AbortKind::Unreachable,
                        "internal error: entered unreachable code",
                    ),
                    "todo" => (AbortKind::Panic, "not yet implemented"),
                    _ => (AbortKind::Panic, "not implemented"),
                };
                // Rust: the default message alone, or (except `panic!`) followed by `: ` and
                // the formatted arguments.
                let pieces = if args.is_empty() {
                    vec![FmtPiece::Lit(default.into())]
                } else {
                    let mut p = self.format(args, span)?;
                    if name != "panic" {
                        p.insert(0, FmtPiece::Lit(format!("{default}: ")));
                    }
                    p
                };
                self.check_fmt_args(&pieces)?;
                (
                    MacroCall::Abort {
                        kind,
                        pieces,
                        cond: None,
                        cmp: None,
                    },
                    Ty::Never,
                )
            }
            "assert" | "debug_assert" => {
                let mut args = parse_args(m)?;
                if args.is_empty() {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        format!("`{name}!` needs a condition"),
                    ));
                }
                let cond = Box::new(args.remove(0));
                let t = self.expr(&cond)?;
                self.unify(&t, &Ty::Bool, cond.span())?;
                let pieces = if args.is_empty() {
                    vec![FmtPiece::Lit(format!(
                        "assertion failed: {}",
                        crate::pretty::expr(&cond)
                    ))]
                } else {
                    self.format(args, span)?
                };
                self.check_fmt_args(&pieces)?;
                let call = if name == "debug_assert" {
                    MacroCall::Nothing
                } else {
                    MacroCall::Abort {
                        kind: AbortKind::Assert,
                        pieces,
                        cond: Some(cond),
                        cmp: None,
                    }
                };
                (call, Ty::Unit)
            }
            "assert_eq" | "assert_ne" | "debug_assert_eq" | "debug_assert_ne" => {
                let mut args = parse_args(m)?;
                if args.len() < 2 {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        format!("`{name}!` needs two values"),
                    ));
                }
                let a = Box::new(args.remove(0));
                let b = Box::new(args.remove(0));
                let ta = self.expr(&a)?;
                let tb = self.expr(&b)?;
                self.unify(&tb, &ta, b.span())?;
                let t = self.deep_keep(&ta);
                let prim =
                    t.is_int() || t.is_float() || matches!(t, Ty::Bool | Ty::Char | Ty::Var(_));
                if !prim {
                    if !self.derives_eq(&t) {
                        return Err(self.err(
                            a.span(),
                            "unsupported-operator",
                            format!(
                                "cannot compare values of type `{}` (derive `PartialEq`)",
                                self.show(&t)
                            ),
                        ));
                    }
                    if !self.debuggable(&t) {
                        return Err(self.err(
                            a.span(),
                            "unsupported-format-argument",
                            format!("`{}` does not implement `Debug` (derive it)", self.show(&t)),
                        ));
                    }
                }
                let ne = name.ends_with("ne");
                let op = if ne { "!=" } else { "==" };
                let mut pieces = vec![FmtPiece::Lit(format!("assertion `left {op} right` failed"))];
                if !args.is_empty() {
                    pieces.push(FmtPiece::Lit(": ".into()));
                    pieces.extend(self.format(args, span)?);
                }
                self.check_fmt_args(&pieces)?;
                let call = if name.starts_with("debug_") {
                    MacroCall::Nothing
                } else {
                    MacroCall::Abort {
                        kind: AbortKind::Assert,
                        pieces,
                        cond: None,
                        cmp: Some((a, b, ne)),
                    }
                };
                (call, Ty::Unit)
            }
            "matches" => {
                let parsed = m
                    .parse_body_with(|input: syn::parse::ParseStream| {
                        let e: Expr = input.parse()?;
                        input.parse::<Token![,]>()?;
                        let pat = syn::Pat::parse_multi_with_leading_vert(input)?;
                        let guard = if input.peek(Token![if]) {
                            input.parse::<Token![if]>()?;
                            Some(input.parse::<Expr>()?)
                        } else {
                            None
                        };
                        if input.peek(Token![,]) {
                            input.parse::<Token![,]>()?;
                        }
                        Ok((e, pat, guard))
                    })
                    .map_err(|e| {
                        self.err(
                            e.span(),
                            "invalid-macro-arguments",
                            format!("cannot parse `matches!`: {e}"),
                        )
                    })?;
                let (e, pat, guard) = parsed;
                let (e, pat, guard) = (Box::new(e), Box::new(pat), guard.map(Box::new));
                let t = self.expr(&e)?;
                self.scopes.push(HashMap::new());
                let r = self.pattern(&pat, &t, false).and_then(|_| match &guard {
                    Some(g) => {
                        let gt = self.expr(g)?;
                        self.unify(&gt, &Ty::Bool, g.span())
                    }
                    None => Ok(()),
                });
                self.scopes.pop();
                r?;
                (
                    MacroCall::Matches {
                        expr: e,
                        pat,
                        guard,
                    },
                    Ty::Bool,
                )
            }
            "__trax_op" => self.trax_op(parse_args(m)?, span)?,
            "__trax_mtc2" => {
                let args = parse_args(m)?;
                if args.len() != 2 {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        "`__trax_mtc2!(n, x)` takes 2 arguments",
                    ));
                }
                let n = self.imm5(&args[0])?;
                let x = Box::new(args.into_iter().nth(1).expect("two args"));
                let t = self.expr(&x)?;
                self.unify(&t, &Ty::Float(FloatTy::F32), x.span())?;
                (MacroCall::Mtc2(n, x), Ty::Unit)
            }
            "__trax_mfc2" => {
                let args = parse_args(m)?;
                if args.len() != 1 {
                    return Err(self.err(
                        span,
                        "invalid-macro-arguments",
                        "`__trax_mfc2!(n)` takes 1 argument",
                    ));
                }
                (
                    MacroCall::Mfc2(self.imm5(&args[0])?),
                    Ty::Float(FloatTy::F32),
                )
            }
            "__trax_symbol_addr" => {
                let args = parse_args(m)?;
                match args.as_slice() {
                    [Expr::Lit(syn::ExprLit {
                        lit: Lit::Str(s), ..
                    })] => (MacroCall::SymbolAddr(s.value()), Ty::Int(IntTy::U32)),
                    _ => {
                        return Err(self.err(
                            span,
                            "invalid-macro-arguments",
                            "`__trax_symbol_addr!` takes one string literal",
                        ))
                    }
                }
            }
            "format" | "vec" | "write" | "writeln" | "format_args" | "dbg" => {
                return Err(self.err(
                    m.path.span(),
                    "unsupported-macro",
                    format!("macro `{name}!` is not supported in TRaX-Rust"),
                ))
            }
            _ => {
                return Err(self.err(
                    m.path.span(),
                    "unsupported-macro",
                    format!("unknown macro `{name}!` (user macros are not supported in TRaX-Rust)"),
                ))
            }
        };
        self.body.macros.insert(super::key(m), call);
        Ok(ty)
    }

    fn imm5(&self, e: &Expr) -> DResult<u32> {
        let v = self.p.eval_int(self.module, self.file, e, 0)?;
        if !(0..32).contains(&v) {
            return Err(self.err(
                e.span(),
                "immediate-out-of-range",
                format!("immediate {v} is out of range 0..=31"),
            ));
        }
        Ok(v as u32)
    }

    fn trax_op(&mut self, args: Vec<Expr>, span: Span) -> DResult<(MacroCall, Ty)> {
        let mut it = args.into_iter();
        let Some(Expr::Lit(syn::ExprLit {
            lit: Lit::Str(mn), ..
        })) = it.next()
        else {
            return Err(self.err(
                span,
                "invalid-macro-arguments",
                "`__trax_op!` takes an instruction mnemonic string first",
            ));
        };
        let Some(instr) = TRAX_INSTRUCTIONS.iter().find(|i| i.mnemonic == mn.value()) else {
            return Err(self.err(
                mn.span(),
                "unknown-instruction",
                format!("unknown TRaX instruction `{}`", mn.value()),
            ));
        };
        let rest: Vec<Expr> = it.collect();
        let uses: Vec<_> = instr.operands.iter().filter(|o| !o.kind.is_def()).collect();
        if rest.len() != uses.len() {
            return Err(self.err(
                span,
                "wrong-argument-count",
                format!(
                    "`{}` takes {} operand(s) but {} were supplied",
                    instr.mnemonic,
                    uses.len(),
                    rest.len()
                ),
            ));
        }
        let mut out = Vec::new();
        for (a, o) in rest.into_iter().zip(uses) {
            match o.kind {
                OperandKind::Imm5 => out.push(TraxArg::Imm(self.imm5(&a)?)),
                OperandKind::FprUse => {
                    let a = Box::new(a);
                    let t = self.expr(&a)?;
                    let want = if instr.mnemonic == "trax.printd" {
                        FloatTy::F64
                    } else {
                        FloatTy::F32
                    };
                    self.unify(&t, &Ty::Float(want), a.span())?;
                    out.push(TraxArg::Reg(a));
                }
                _ => {
                    let a = Box::new(a);
                    let t = self.expr(&a)?;
                    let s = self.shallow(&t);
                    match s {
                        Ty::Int(i) if i.bits() <= 32 => {}
                        Ty::Bool | Ty::Char | Ty::Ptr(..) => {}
                        Ty::Ref(_, ref inner) if !matches!(**inner, Ty::Slice(_)) => {}
                        Ty::Var(_) => self.unify(&t, &Ty::Int(IntTy::U32), a.span())?,
                        other => {
                            return Err(self.err(
                                a.span(),
                                "type-mismatch",
                                format!("register operand must be a 32-bit integer, bool or pointer, found `{}`", self.show(&other)),
                            ))
                        }
                    }
                    out.push(TraxArg::Reg(a));
                }
            }
        }
        let ty = match instr
            .operands
            .iter()
            .find(|o| o.kind.is_def())
            .map(|o| o.kind)
        {
            Some(OperandKind::GprDef) => Ty::Int(IntTy::U32),
            Some(OperandKind::FprDef) => Ty::Float(FloatTy::F32),
            _ => Ty::Unit,
        };
        Ok((MacroCall::TraxOp { instr, args: out }, ty))
    }

    /// True if values of `t` can be formatted with `{:?}`.
    pub fn debuggable(&self, t: &Ty) -> bool {
        match self.shallow(t) {
            Ty::Int(_)
            | Ty::Float(_)
            | Ty::Bool
            | Ty::Char
            | Ty::Str
            | Ty::Unit
            | Ty::Var(_)
            | Ty::Ptr(..) => true,
            Ty::Ref(_, inner) => self.debuggable(&inner),
            Ty::Tuple(ts) => ts.iter().all(|x| self.debuggable(x)),
            Ty::Array(e, _) | Ty::Slice(e) => self.debuggable(&e),
            Ty::Adt(a, args) => {
                self.p.adts[a].derives.has(LangTrait::Debug)
                    && self.p.adts[a]
                        .variants
                        .iter()
                        .flat_map(|v| &v.fields)
                        .all(|f| self.debuggable(&f.ty.subst(&args)))
            }
            _ => false,
        }
    }

    fn check_printable(&self, t: &Ty, spec: &FmtSpec, span: Span) -> DResult<()> {
        let s = self.deep_keep(t);
        let mut base = s.clone();
        while let Ty::Ref(_, inner) = base {
            base = *inner;
        }
        let int_like =
            base.is_int() || matches!(base, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int);
        let float_like = base.is_float()
            || matches!(base, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Float);
        let ok = match spec.tr {
            FmtTrait::Display => {
                int_like || float_like || matches!(base, Ty::Bool | Ty::Char | Ty::Str)
            }
            FmtTrait::Debug => self.debuggable(&s),
            FmtTrait::LowerHex | FmtTrait::UpperHex | FmtTrait::Octal | FmtTrait::Binary => {
                int_like
            }
            FmtTrait::LowerExp | FmtTrait::UpperExp => int_like || float_like,
        };
        if ok {
            return Ok(());
        }
        let what = match spec.tr {
            FmtTrait::Display => match &base {
                Ty::Adt(..) | Ty::Tuple(_) | Ty::Array(..) | Ty::Slice(_) | Ty::Unit => {
                    " (`Display` is for numbers, bool, char and strings; use `{:?}` with `#[derive(Debug)]`)"
                }
                _ => "",
            },
            FmtTrait::Debug => " (derive `Debug` for it)",
            _ => "",
        };
        let tr = match spec.tr {
            FmtTrait::Display => "Display",
            FmtTrait::Debug => "Debug",
            FmtTrait::LowerHex => "LowerHex",
            FmtTrait::UpperHex => "UpperHex",
            FmtTrait::Octal => "Octal",
            FmtTrait::Binary => "Binary",
            FmtTrait::LowerExp => "LowerExp",
            FmtTrait::UpperExp => "UpperExp",
        };
        Err(self.err(
            span,
            "unsupported-format-argument",
            format!("`{}` cannot be formatted with `{tr}`{what}", self.show(&s)),
        ))
    }

    /// Type-checks the arguments of formatted text.
    fn check_fmt_args(&mut self, pieces: &[FmtPiece]) -> DResult<()> {
        for p in pieces {
            if let FmtPiece::Arg(a, spec) = p {
                for c in [&spec.width, &spec.precision] {
                    if let Count::Arg(x) = c {
                        let t = self.expr(x)?;
                        self.unify(&t, &Ty::Int(IntTy::Usize), x.span())?;
                    }
                }
                let t = self.expr(a)?;
                self.check_printable(&t, spec, a.span())?;
            }
        }
        Ok(())
    }

    /// Parses a format string and its arguments into pieces (Rust's syntax: positional,
    /// indexed, named and captured arguments; fill, alignment, sign, `#`, `0`, width and
    /// precision (literal, `N$`, `name$`, `.*`), and the `?`, `x`, `X`, `o`, `b`, `e`, `E`,
    /// `x?`, `X?` types).
    pub fn format(&mut self, args: Vec<Expr>, span: Span) -> DResult<Vec<FmtPiece>> {
        let mut it = args.into_iter();
        let Some(first) = it.next() else {
            return Ok(Vec::new());
        };
        let Expr::Lit(syn::ExprLit {
            lit: Lit::Str(fmt), ..
        }) = &first
        else {
            return Err(self.err(
                first.span(),
                "invalid-format-string",
                "format argument must be a string literal",
            ));
        };
        let fspan = fmt.span();
        let mut positional: Vec<Expr> = Vec::new();
        let mut named: Vec<(String, Expr)> = Vec::new();
        for a in it {
            match a {
                Expr::Assign(asg) => match &*asg.left {
                    Expr::Path(p) if p.path.get_ident().is_some() => {
                        named.push((p.path.get_ident().expect("ident").to_string(), *asg.right));
                    }
                    _ => {
                        return Err(self.err(
                            asg.span(),
                            "invalid-format-string",
                            "invalid named argument",
                        ))
                    }
                },
                other => {
                    if !named.is_empty() {
                        return Err(self.err(
                            other.span(),
                            "invalid-format-string",
                            "positional arguments cannot follow named arguments",
                        ));
                    }
                    positional.push(other)
                }
            }
        }
        let mut used = vec![false; positional.len()];
        let mut named_used = vec![false; named.len()];
        let err = |cx: &Self, msg: String| cx.err(fspan, "invalid-format-string", msg);
        // An argument by index or name; a name not among the named arguments is captured.
        let arg_ref = |cx: &mut Self,
                       r: &str,
                       used: &mut Vec<bool>,
                       named_used: &mut Vec<bool>|
         -> DResult<Expr> {
            if let Ok(i) = r.parse::<usize>() {
                return match positional.get(i) {
                    Some(e) => {
                        used[i] = true;
                        Ok(e.clone())
                    }
                    None => Err(err(
                        cx,
                        format!(
                            "invalid reference to positional argument {i} (there are {} arguments)",
                            positional.len()
                        ),
                    )),
                };
            }
            if let Some(i) = named.iter().position(|(n, _)| n == r) {
                named_used[i] = true;
                return Ok(named[i].1.clone());
            }
            if !r
                .chars()
                .next()
                .is_some_and(|c| c.is_alphabetic() || c == '_')
                || !r.chars().all(|c| c.is_alphanumeric() || c == '_')
            {
                return Err(err(cx, format!("invalid format argument name `{r}`")));
            }
            let id = syn::Ident::new(r, fspan);
            Ok(Expr::Path(syn::ExprPath {
                attrs: vec![],
                qself: None,
                path: id.into(),
            }))
        };
        let text = fmt.value();
        let mut pieces = Vec::new();
        let mut lit = String::new();
        let mut next_arg = 0usize;
        let mut chars = text.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '{' if chars.peek() == Some(&'{') => {
                    chars.next();
                    lit.push('{');
                }
                '}' if chars.peek() == Some(&'}') => {
                    chars.next();
                    lit.push('}');
                }
                '{' => {
                    let mut inner = String::new();
                    loop {
                        match chars.next() {
                            Some('}') => break,
                            Some(c) => inner.push(c),
                            None => {
                                return Err(err(self, "unterminated `{` in format string".into()))
                            }
                        }
                    }
                    let (arg, spec_text) = match inner.split_once(':') {
                        Some((a, b)) => (a.trim().to_string(), b.to_string()),
                        None => (inner.trim().to_string(), String::new()),
                    };
                    let mut spec = FmtSpec::display();
                    let mut sc: Vec<char> = spec_text.chars().collect();
                    let mut i = 0;
                    // [[fill]align]
                    let is_align = |c: char| matches!(c, '<' | '^' | '>');
                    let align_of = |c: char| match c {
                        '<' => Align::Left,
                        '^' => Align::Center,
                        _ => Align::Right,
                    };
                    if sc.len() >= 2 && is_align(sc[1]) {
                        spec.fill = sc[0];
                        spec.align = align_of(sc[1]);
                        i = 2;
                    } else if !sc.is_empty() && is_align(sc[0]) {
                        spec.align = align_of(sc[0]);
                        i = 1;
                    }
                    if i < sc.len() && (sc[i] == '+' || sc[i] == '-') {
                        spec.plus = sc[i] == '+';
                        i += 1;
                    }
                    if i < sc.len() && sc[i] == '#' {
                        spec.alternate = true;
                        i += 1;
                    }
                    if i < sc.len() && sc[i] == '0' && !(i + 1 < sc.len() && sc[i + 1] == '$') {
                        spec.zero = true;
                        i += 1;
                    }
                    // Width: digits, or `N$`/`name$`.
                    let read_count = |sc: &[char], i: &mut usize| -> Option<String> {
                        let start = *i;
                        while *i < sc.len() && (sc[*i].is_alphanumeric() || sc[*i] == '_') {
                            *i += 1;
                        }
                        (start < *i).then(|| sc[start..*i].iter().collect())
                    };
                    let save = i;
                    if let Some(w) = read_count(&sc, &mut i) {
                        if i < sc.len() && sc[i] == '$' {
                            i += 1;
                            spec.width = Count::Arg(Box::new(arg_ref(
                                self,
                                &w,
                                &mut used,
                                &mut named_used,
                            )?));
                        } else {
                            // Digits only: what follows is the type (`{:8e}`).
                            let digits: String =
                                w.chars().take_while(|c| c.is_ascii_digit()).collect();
                            i = save + digits.len();
                            if !digits.is_empty() {
                                spec.width = Count::Is(
                                    digits
                                        .parse()
                                        .map_err(|_| err(self, "width too large".into()))?,
                                );
                            }
                        }
                    }
                    let mut star = false;
                    if i < sc.len() && sc[i] == '.' {
                        i += 1;
                        if i < sc.len() && sc[i] == '*' {
                            star = true;
                            i += 1;
                        } else {
                            let start = i;
                            let Some(p) = read_count(&sc, &mut i) else {
                                return Err(err(
                                    self,
                                    format!(
                                        "invalid format spec `{{:{spec_text}}}`: expected a precision"
                                    ),
                                ));
                            };
                            if i < sc.len() && sc[i] == '$' {
                                i += 1;
                                spec.precision = Count::Arg(Box::new(arg_ref(
                                    self,
                                    &p,
                                    &mut used,
                                    &mut named_used,
                                )?));
                            } else {
                                let digits: String =
                                    p.chars().take_while(|c| c.is_ascii_digit()).collect();
                                if digits.is_empty() {
                                    return Err(err(
                                        self,
                                        format!("invalid format spec `{{:{spec_text}}}`"),
                                    ));
                                }
                                i = start + digits.len();
                                spec.precision = Count::Is(
                                    digits
                                        .parse()
                                        .map_err(|_| err(self, "precision too large".into()))?,
                                );
                            }
                        }
                    }
                    let ty: String = sc.drain(i..).collect();
                    match ty.as_str() {
                        "" => {}
                        "?" => spec.tr = FmtTrait::Debug,
                        "x?" => {
                            spec.tr = FmtTrait::Debug;
                            spec.debug_hex = Some(false);
                        }
                        "X?" => {
                            spec.tr = FmtTrait::Debug;
                            spec.debug_hex = Some(true);
                        }
                        "x" => spec.tr = FmtTrait::LowerHex,
                        "X" => spec.tr = FmtTrait::UpperHex,
                        "o" => spec.tr = FmtTrait::Octal,
                        "b" => spec.tr = FmtTrait::Binary,
                        "e" => spec.tr = FmtTrait::LowerExp,
                        "E" => spec.tr = FmtTrait::UpperExp,
                        "p" => {
                            return Err(self.err(fspan, "unsupported-format-spec", "`{:p}` is not supported in TRaX-Rust (addresses differ between the machine and the host)"))
                        }
                        other => return Err(err(self, format!("unknown format trait `{other}`"))),
                    }
                    if star {
                        // `.*` takes the precision from the next positional argument.
                        let Some(e) = positional.get(next_arg).cloned() else {
                            return Err(err(
                                self,
                                "format string references a missing argument".into(),
                            ));
                        };
                        used[next_arg] = true;
                        next_arg += 1;
                        spec.precision = Count::Arg(Box::new(e));
                    }
                    if !lit.is_empty() {
                        pieces.push(FmtPiece::Lit(std::mem::take(&mut lit)));
                    }
                    let value = if arg.is_empty() {
                        let Some(e) = positional.get(next_arg).cloned() else {
                            return Err(err(self, format!("{} positional argument(s) in format string, but there are {} argument(s)", next_arg + 1, positional.len())));
                        };
                        used[next_arg] = true;
                        next_arg += 1;
                        e
                    } else {
                        arg_ref(self, &arg, &mut used, &mut named_used)?
                    };
                    pieces.push(FmtPiece::Arg(Box::new(value), spec));
                }
                '}' => return Err(err(self, "unmatched `}` in format string".into())),
                c => lit.push(c),
            }
        }
        if !lit.is_empty() {
            pieces.push(FmtPiece::Lit(lit));
        }
        if used.iter().any(|u| !u) || named_used.iter().any(|u| !u) {
            return Err(self.err(
                span,
                "invalid-format-string",
                "argument never used in format string",
            ));
        }
        Ok(pieces)
    }
}
