//! Blocks, statements, expressions, operators, control flow and `for` loops.

use super::infer::{block_tail_expr, block_tail_span, Cx, LoopCx, VarKind};
use super::{key, Adjust, IterInfo, OpCall, Res};
use crate::diag::DResult;
use crate::ops::{BinOp, UnOp};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, LangTrait, SimdTy, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::{Expr, Lit, Pat, Stmt};

/// How a `for` loop or `zip` iterates a sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeqMode {
    /// `x` (an array by value, or a slice reference).
    Value,
    /// `&x` or `x.iter()`.
    Ref,
    /// `&mut x` or `x.iter_mut()`.
    RefMut,
}

/// The syntax of a `for` loop's iterator (and of `zip` arguments).
pub enum IterSyn<'e> {
    /// `a..b` / `a..=b`.
    Range {
        start: &'e Expr,
        end: &'e Expr,
        inclusive: bool,
    },
    /// An array or slice.
    Seq {
        base: &'e Expr,
        mode: SeqMode,
    },
    Rev(Box<IterSyn<'e>>),
    StepBy(Box<IterSyn<'e>>, &'e Expr),
    Enumerate(Box<IterSyn<'e>>),
    Zip(Box<IterSyn<'e>>, Box<IterSyn<'e>>),
    Skip(Box<IterSyn<'e>>, &'e Expr),
    Take(Box<IterSyn<'e>>, &'e Expr),
    /// `.copied()` / `.cloned()`.
    Copied(Box<IterSyn<'e>>),
}

/// Classifies a `for` loop's iterator expression; `Err` names the unsupported part.
pub fn classify_iter(e: &Expr) -> Result<IterSyn<'_>, (Span, String)> {
    match e {
        Expr::Paren(p) => classify_iter(&p.expr),
        Expr::Group(g) => classify_iter(&g.expr),
        Expr::Range(r) => match (&r.start, &r.end) {
            (Some(s), Some(en)) => Ok(IterSyn::Range {
                start: s,
                end: en,
                inclusive: matches!(r.limits, syn::RangeLimits::Closed(_)),
            }),
            _ => Err((
                r.span(),
                "open ranges cannot be iterated in TRaX-Rust".into(),
            )),
        },
        Expr::MethodCall(m) => {
            let name = m.method.to_string();
            let inner = || classify_iter(&m.receiver).map(Box::new);
            match (name.as_str(), m.args.len()) {
                ("rev", 0) => Ok(IterSyn::Rev(inner()?)),
                ("enumerate", 0) => Ok(IterSyn::Enumerate(inner()?)),
                ("copied" | "cloned", 0) => Ok(IterSyn::Copied(inner()?)),
                ("step_by", 1) => Ok(IterSyn::StepBy(inner()?, &m.args[0])),
                ("skip", 1) => Ok(IterSyn::Skip(inner()?, &m.args[0])),
                ("take", 1) => Ok(IterSyn::Take(inner()?, &m.args[0])),
                ("zip", 1) => Ok(IterSyn::Zip(inner()?, Box::new(classify_iter(&m.args[0])?))),
                ("iter", 0) => Ok(IterSyn::Seq {
                    base: &m.receiver,
                    mode: SeqMode::Ref,
                }),
                ("iter_mut", 0) => Ok(IterSyn::Seq {
                    base: &m.receiver,
                    mode: SeqMode::RefMut,
                }),
                ("into_iter", 0) => classify_iter(&m.receiver),
                (
                    "map" | "filter" | "filter_map" | "fold" | "sum" | "product" | "any" | "all"
                    | "find" | "position" | "max" | "min" | "count" | "collect" | "chain"
                    | "flat_map" | "take_while" | "skip_while" | "windows" | "chunks",
                    _,
                ) => Err((
                    m.method.span(),
                    format!("iterator adapter `{name}` is not supported in TRaX-Rust (use a `for` loop)"),
                )),
                _ => Ok(IterSyn::Seq {
                    base: e,
                    mode: SeqMode::Value,
                }),
            }
        }
        Expr::Reference(r) => Ok(IterSyn::Seq {
            base: &r.expr,
            mode: if r.mutability.is_some() {
                SeqMode::RefMut
            } else {
                SeqMode::Ref
            },
        }),
        other => Ok(IterSyn::Seq {
            base: other,
            mode: SeqMode::Value,
        }),
    }
}

/// True for a `for` loop over a plain integer range (optionally `.rev()`/`.step_by(n)`),
/// which lowers to a counted loop.
pub fn is_simple_range(it: &IterSyn) -> bool {
    match it {
        IterSyn::Range { .. } => true,
        IterSyn::Rev(i) => matches!(**i, IterSyn::Range { .. }),
        IterSyn::StepBy(i, _) => matches!(**i, IterSyn::Range { .. }),
        _ => false,
    }
}

impl<'p, 'a> Cx<'p, 'a> {
    // ---------------------------------------------------------------- blocks, statements

    pub fn block(&mut self, b: &syn::Block) -> DResult<Ty> {
        let saved = self.module;
        if let Some(m) = self.p.block_mods.get(&key(b)) {
            self.module = *m;
        }
        self.scopes.push(HashMap::new());
        let r = self.block_inner(b);
        self.scopes.pop();
        self.module = saved;
        r
    }

    fn block_inner(&mut self, b: &syn::Block) -> DResult<Ty> {
        let mut diverges = false;
        let n = b.stmts.len();
        for (i, s) in b.stmts.iter().enumerate() {
            let last = i + 1 == n;
            match s {
                Stmt::Local(l) => {
                    self.let_stmt(l)?;
                }
                Stmt::Expr(e, semi) => {
                    let t = self.expr(e)?;
                    if last && semi.is_none() {
                        return Ok(if diverges { Ty::Never } else { t });
                    }
                    if matches!(self.shallow(&t), Ty::Never) {
                        diverges = true;
                    } else if semi.is_none() && !matches!(self.shallow(&t), Ty::Unit) {
                        return Err(self.mismatch(e.span(), &Ty::Unit, &t));
                    }
                }
                Stmt::Macro(m) => {
                    let t = self.mac(&m.mac, m.span())?;
                    if last && m.semi_token.is_none() {
                        return Ok(if diverges { Ty::Never } else { t });
                    }
                    if matches!(t, Ty::Never) {
                        diverges = true;
                    }
                }
                // Items were collected into the block's module.
                Stmt::Item(_) => {}
            }
        }
        Ok(if diverges { Ty::Never } else { Ty::Unit })
    }

    fn let_stmt(&mut self, l: &syn::Local) -> DResult<()> {
        let (pat, ann) = match &l.pat {
            Pat::Type(pt) => (&*pt.pat, Some(self.resolve_ty(&pt.ty)?)),
            other => (other, None),
        };
        let ty = match ann {
            Some(t) => t,
            None => self.fresh(VarKind::Any),
        };
        let mut has_else = false;
        if let Some(init) = &l.init {
            let t = self.expr(&init.expr)?;
            self.coerce(&init.expr, &t, &ty, init.expr.span())?;
            if let Some((_, els)) = &init.diverge {
                has_else = true;
                let et = self.expr(els)?;
                if !matches!(self.shallow(&et), Ty::Never) {
                    return Err(self.err(
                        els.span(),
                        "let-else-does-not-diverge",
                        "`else` clause of `let...else` does not diverge",
                    ));
                }
            }
        }
        self.pattern(pat, &ty, l.init.is_none())?;
        if !has_else && !self.irrefutable(pat) {
            return Err(self.err(
                pat.span(),
                "refutable-pattern",
                "refutable pattern in local binding (use `if let`, `match` or `let ... else`)",
            ));
        }
        Ok(())
    }

    /// Binds a function parameter's pattern.
    pub fn bind_param(&mut self, pat: &Pat, ty: &Ty) -> DResult<()> {
        self.pattern(pat, ty, false)?;
        if !self.irrefutable(pat) {
            return Err(self.err(
                pat.span(),
                "refutable-pattern",
                "refutable pattern in function argument",
            ));
        }
        Ok(())
    }

    // ---------------------------------------------------------------- expressions

    pub fn expr(&mut self, e: &Expr) -> DResult<Ty> {
        if matches!(e, Expr::Call(_) | Expr::MethodCall(_)) {
            self.call_spans.insert(key(e), e.span());
        }
        let t = self.expr_inner(e)?;
        Ok(self.record(e, t))
    }

    /// Checks `e` against an expected type, coercing it.
    pub fn expr_coerce(&mut self, e: &Expr, want: &Ty) -> DResult<()> {
        let t = self.expr(e)?;
        self.coerce(e, &t, want, e.span())
    }

    fn expr_inner(&mut self, e: &Expr) -> DResult<Ty> {
        match e {
            Expr::Lit(l) => self.lit(&l.lit),
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Block(b) => {
                if let Some(l) = &b.label {
                    return Err(self.err(
                        l.span(),
                        "unsupported-labeled-block",
                        "labeled blocks are not supported in TRaX-Rust",
                    ));
                }
                self.block(&b.block)
            }
            Expr::Unsafe(u) => self.block(&u.block),
            Expr::Path(p) => self.path_expr(e, p),
            Expr::Binary(b) => self.binary(e, b),
            Expr::Unary(u) => self.unary(e, u),
            Expr::Assign(a) => {
                if matches!(&*a.left, Expr::Tuple(_) | Expr::Array(_) | Expr::Struct(_) | Expr::Call(_)) {
                    return Err(self.err(
                        a.left.span(),
                        "unsupported-destructuring-assignment",
                        "destructuring assignment is not supported in TRaX-Rust; use `let`",
                    ));
                }
                let lt = self.expr(&a.left)?;
                self.check_place(&a.left, true)?;
                self.expr_coerce(&a.right, &lt)?;
                Ok(Ty::Unit)
            }
            Expr::Cast(c) => self.cast(c),
            Expr::If(i) => self.if_expr(i),
            Expr::While(w) => {
                self.scopes.push(HashMap::new());
                let r = self.cond(&w.cond);
                let r = r.and_then(|_| {
                    self.loops.push(LoopCx {
                        label: w.label.as_ref().map(|l| l.name.ident.to_string()),
                        brk: None,
                    });
                    let b = self.block(&w.body);
                    self.loops.pop();
                    let b = b?;
                    self.unify(&b, &Ty::Unit, w.body.brace_token.span.close())
                });
                self.scopes.pop();
                r?;
                Ok(Ty::Unit)
            }
            Expr::Loop(l) => {
                self.loops.push(LoopCx {
                    label: l.label.as_ref().map(|l| l.name.ident.to_string()),
                    brk: Some(None),
                });
                let b = self.block(&l.body);
                let cx = self.loops.pop().expect("loop");
                let b = b?;
                self.unify(&b, &Ty::Unit, l.body.brace_token.span.close())?;
                Ok(cx.brk.flatten().unwrap_or(Ty::Never))
            }
            Expr::ForLoop(f) => self.for_loop(e, f),
            Expr::Break(b) => {
                let label = b.label.as_ref().map(|l| l.ident.to_string());
                let vt = match &b.expr {
                    Some(v) => Some(self.expr(v)?),
                    None => None,
                };
                let idx = self.loop_index(label.as_deref(), b.span())?;
                match (&self.loops[idx].brk, vt) {
                    (None, Some(_)) => {
                        return Err(self.err(
                            b.span(),
                            "break-value-outside-loop",
                            "`break` with a value is only allowed in `loop`",
                        ))
                    }
                    (None, None) => {}
                    (Some(prev), vt) => {
                        let vt = vt.unwrap_or(Ty::Unit);
                        match prev.clone() {
                            Some(p) => self.unify(&vt, &p, b.span())?,
                            None => self.loops[idx].brk = Some(Some(vt)),
                        }
                    }
                }
                Ok(Ty::Never)
            }
            Expr::Continue(c) => {
                let label = c.label.as_ref().map(|l| l.ident.to_string());
                self.loop_index(label.as_deref(), c.span())?;
                Ok(Ty::Never)
            }
            Expr::Return(r) => {
                let ret = self.ret.clone();
                match &r.expr {
                    Some(v) => {
                        let t = self.expr(v)?;
                        self.coerce(v, &t, &ret, r.span())?;
                    }
                    None => self.unify(&Ty::Unit, &ret, r.span())?,
                }
                Ok(Ty::Never)
            }
            Expr::Call(c) => self.call(e, c),
            Expr::MethodCall(m) => self.method_call(e, m),
            Expr::Field(f) => self.field(e, f),
            Expr::Index(i) => self.index(e, i),
            Expr::Reference(r) => {
                if let Expr::Index(ix) = strip(&r.expr) {
                    if matches!(strip(&ix.index), Expr::Range(_)) {
                        let t = self.expr(&r.expr)?;
                        if r.mutability.is_some() {
                            self.check_place(&r.expr, true)?;
                        }
                        return Ok(Ty::Ref(r.mutability.is_some(), Box::new(t)));
                    }
                }
                let t = self.expr(&r.expr)?;
                if matches!(self.shallow(&t), Ty::Slice(_)) {
                    return Err(self.err(r.expr.span(), "unsupported-slice", "this unsized place cannot be borrowed in TRaX-Rust"));
                }
                if r.mutability.is_some() {
                    self.check_place(&r.expr, true)?;
                }
                Ok(Ty::Ref(r.mutability.is_some(), Box::new(t)))
            }
            Expr::Array(a) => {
                let el = self.fresh(VarKind::Any);
                for x in &a.elems {
                    let t = self.expr(x)?;
                    self.coerce(x, &t, &el, x.span())?;
                }
                Ok(Ty::Array(Box::new(el), a.elems.len() as u32))
            }
            Expr::Repeat(r) => {
                let t = self.expr(&r.expr)?;
                let n = self.p.eval_len(self.module, self.file, &r.len)?;
                Ok(Ty::Array(Box::new(t), n))
            }
            Expr::Struct(s) => self.struct_lit(e, s),
            Expr::Tuple(t) if t.elems.is_empty() => Ok(Ty::Unit),
            Expr::Tuple(t) => {
                let mut tys = Vec::new();
                for x in &t.elems {
                    tys.push(self.expr(x)?);
                }
                Ok(Ty::Tuple(tys))
            }
            Expr::Match(m) => self.match_expr(m),
            Expr::Macro(m) => self.mac(&m.mac, m.span()),
            Expr::Try(t) => self.try_expr(e, t),
            Expr::Range(r) => Err(self.err(
                r.span(),
                "unsupported-range",
                "range expressions are only supported as `for` loop iterators and slice indices",
            )),
            Expr::Closure(c) => self.closure(e, c, None),
            Expr::Async(c) => Err(self.err(c.span(), "unsupported-async", "async blocks are not supported in TRaX-Rust")),
            Expr::Await(c) => Err(self.err(c.span(), "unsupported-async", "`.await` is not supported in TRaX-Rust")),
            Expr::TryBlock(c) => Err(self.err(c.span(), "unsupported-try", "try blocks are not supported in TRaX-Rust")),
            Expr::Let(c) => Err(self.err(
                c.span(),
                "unsupported-let-chain",
                "`let` is only supported as the whole condition of `if let`/`while let` (no let chains)",
            )),
            Expr::Yield(c) => Err(self.err(c.span(), "unsupported-yield", "`yield` is not supported in TRaX-Rust")),
            Expr::RawAddr(c) => Err(self.err(
                c.span(),
                "unsupported-raw-addr",
                "`&raw` is not supported in TRaX-Rust; use `&x as *const T`",
            )),
            Expr::Const(c) => Err(self.err(c.span(), "unsupported-const-block", "const blocks are not supported in TRaX-Rust")),
            other => Err(self.err(
                other.span(),
                "unsupported-expression",
                "this kind of expression is not supported in TRaX-Rust",
            )),
        }
    }

    fn loop_index(&self, label: Option<&str>, span: Span) -> DResult<usize> {
        let found = match label {
            None => self.loops.len().checked_sub(1),
            Some(l) => self
                .loops
                .iter()
                .rposition(|c| c.label.as_deref() == Some(l)),
        };
        found.ok_or_else(|| match label {
            None => self.err(
                span,
                "break-outside-loop",
                "`break`/`continue` outside of a loop",
            ),
            Some(l) => self.err(
                span,
                "unknown-label",
                format!("use of undeclared label `'{l}`"),
            ),
        })
    }

    pub fn lit(&mut self, l: &Lit) -> DResult<Ty> {
        match l {
            Lit::Int(i) => {
                i.base10_parse::<i128>().map_err(|_| {
                    self.err(i.span(), "invalid-literal", "integer literal is too large")
                })?;
                match i.suffix() {
                    "" => Ok(self.fresh(VarKind::Int)),
                    "f32" => Ok(Ty::Float(FloatTy::F32)),
                    "f64" => Ok(Ty::Float(FloatTy::F64)),
                    // Range checks (a negated literal may reach `MIN`) come after inference,
                    // in `consteval`.
                    s => match IntTy::from_name(s) {
                        Some(t) => Ok(Ty::Int(t)),
                        None => Err(self.err(
                            i.span(),
                            "invalid-literal",
                            format!("invalid suffix `{s}`"),
                        )),
                    },
                }
            }
            Lit::Float(f) => {
                f.base10_parse::<f64>()
                    .map_err(|_| self.err(f.span(), "invalid-literal", "invalid float literal"))?;
                match f.suffix() {
                    "" => Ok(self.fresh(VarKind::Float)),
                    "f32" => Ok(Ty::Float(FloatTy::F32)),
                    "f64" => Ok(Ty::Float(FloatTy::F64)),
                    s => {
                        Err(self.err(f.span(), "invalid-literal", format!("invalid suffix `{s}`")))
                    }
                }
            }
            Lit::Bool(_) => Ok(Ty::Bool),
            Lit::Char(_) => Ok(Ty::Char),
            Lit::Byte(_) => Ok(Ty::Int(IntTy::U8)),
            Lit::Str(_) => Ok(Ty::Str),
            other => Err(self.err(
                other.span(),
                "unsupported-literal",
                "this kind of literal is not supported in TRaX-Rust",
            )),
        }
    }

    /// Dereferences references (and defaults literal variables) until a non-reference.
    pub fn autoderef(&self, t: &Ty) -> (Ty, u32) {
        let mut t = self.shallow(t);
        let mut n = 0;
        while let Ty::Ref(_, inner) = t {
            t = self.shallow(&inner);
            n += 1;
        }
        (t, n)
    }

    fn field(&mut self, e: &Expr, f: &syn::ExprField) -> DResult<Ty> {
        let bt = self.expr(&f.base)?;
        let (bt, derefs) = self.autoderef(&bt);
        self.body.derefs.insert(key(e), derefs);
        let name = match &f.member {
            syn::Member::Named(n) => n.to_string(),
            syn::Member::Unnamed(i) => i.index.to_string(),
        };
        match &bt {
            Ty::Adt(a, args) if !self.p.adts[*a].is_enum => {
                let def = &self.p.adts[*a];
                match def.fields().iter().position(|fd| fd.name == name) {
                    Some(i) => {
                        self.body.fields.insert(key(e), i);
                        let t = def.fields()[i].ty.subst(args);
                        self.norm(&t, f.member.span())
                    }
                    None => Err(self.err(
                        f.member.span(),
                        "unknown-field",
                        format!("struct `{}` has no field `{name}`", def.name),
                    )),
                }
            }
            Ty::Tuple(ts) => match name.parse::<usize>() {
                Ok(i) if i < ts.len() => {
                    self.body.fields.insert(key(e), i);
                    Ok(ts[i].clone())
                }
                _ => Err(self.err(
                    f.member.span(),
                    "unknown-field",
                    format!("no field `{name}` on type `{}`", self.show(&bt)),
                )),
            },
            other => Err(self.err(
                f.member.span(),
                "unknown-field",
                format!("type `{}` has no field `{name}`", self.show(other)),
            )),
        }
    }

    fn index(&mut self, e: &Expr, i: &syn::ExprIndex) -> DResult<Ty> {
        let bt = self.expr(&i.expr)?;
        let (bt, derefs) = self.autoderef(&bt);
        self.body.derefs.insert(key(e), derefs);
        if let Expr::Range(r) = strip(&i.index) {
            // Slicing `a[lo..hi]` (unsized: only borrowed).
            for x in [&r.start, &r.end].into_iter().flatten() {
                let t = self.expr(x)?;
                self.unify(&t, &Ty::Int(IntTy::Usize), x.span())?;
            }
            if matches!(r.limits, syn::RangeLimits::Closed(_)) && r.end.is_none() {
                return Err(self.err(r.span(), "invalid-range", "inclusive range with no end"));
            }
            return match bt {
                Ty::Array(el, _) | Ty::Slice(el) => Ok(Ty::Slice(el)),
                other => Err(self.err(
                    i.expr.span(),
                    "not-indexable",
                    format!("cannot slice a value of type `{}`", self.show(&other)),
                )),
            };
        }
        match &bt {
            Ty::Array(el, _) | Ty::Slice(el) => {
                let it = self.expr(&i.index)?;
                self.unify(&it, &Ty::Int(IntTy::Usize), i.index.span())?;
                Ok((**el).clone())
            }
            Ty::Adt(..) => {
                // `Index`/`IndexMut` impls; `index_mut` is chosen by `check_place`.
                let it = self.expr(&i.index)?;
                let Some((func, substs, out)) = self.index_impl(&bt, &it, false, i.expr.span())? else {
                    return Err(self.err(
                        i.expr.span(),
                        "not-indexable",
                        format!("cannot index a value of type `{}` (no `Index` impl)", self.show(&bt)),
                    ));
                };
                self.body.ops.insert(
                    key(e),
                    OpCall::Fn {
                        func,
                        substs,
                        by_ref: true,
                        via_partial_cmp: false,
                        negate: false,
                    },
                );
                Ok(out)
            }
            other => Err(self.err(
                i.expr.span(),
                "not-indexable",
                format!(
                    "cannot index a value of type `{}` (only arrays, slices and types with an `Index` impl)",
                    self.show(other)
                ),
            )),
        }
    }

    /// Checks that `e` is a place that can be assigned or mutably borrowed.
    pub fn check_place(&mut self, e: &Expr, _write: bool) -> DResult<()> {
        match e {
            Expr::Path(_) => match self.body.res.get(&key(e)) {
                Some(Res::Local(id)) if self.local_mut[*id] => Ok(()),
                Some(Res::Local(id)) => {
                    // A `&mut` binding can be written through.
                    Err(self.err(
                        e.span(),
                        "immutable-variable",
                        format!(
                            "cannot assign to or mutably borrow immutable variable `{}` (declare it with `mut`)",
                            self.body.locals[*id].name
                        ),
                    ))
                }
                Some(Res::Global(g, _)) if self.p.globals[*g].is_static == Some(true) => Ok(()),
                _ => Err(self.err(
                    e.span(),
                    "not-assignable",
                    "this expression cannot be assigned to or borrowed mutably",
                )),
            },
            Expr::Field(f) => {
                if self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 {
                    self.check_deref_mut(&f.base, e.span())
                } else {
                    self.check_place(&f.base, _write)
                }
            }
            Expr::Index(i) => {
                if let Some(OpCall::Fn { func, substs, .. }) = self.body.ops.get(&key(e)).cloned() {
                    // Switch `index` to `index_mut`.
                    let bt = self
                        .body
                        .tys
                        .get(&key(&*i.expr))
                        .cloned()
                        .unwrap_or(Ty::Unit);
                    let (bt, _) = self.autoderef(&bt);
                    let it = self
                        .body
                        .tys
                        .get(&key(&*i.index))
                        .cloned()
                        .unwrap_or(Ty::Unit);
                    let _ = (func, substs);
                    let Some((func, substs, _)) = self.index_impl(&bt, &it, true, i.expr.span())?
                    else {
                        return Err(self.err(
                            i.expr.span(),
                            "not-assignable",
                            format!(
                                "cannot assign through an index of `{}` (no `IndexMut` impl)",
                                self.show(&bt)
                            ),
                        ));
                    };
                    self.body.ops.insert(
                        key(e),
                        OpCall::Fn {
                            func,
                            substs,
                            by_ref: true,
                            via_partial_cmp: false,
                            negate: false,
                        },
                    );
                    if self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 {
                        return self.check_deref_mut(&i.expr, e.span());
                    }
                    return self.check_place(&i.expr, _write);
                }
                if self.body.derefs.get(&key(e)).copied().unwrap_or(0) > 0 {
                    self.check_deref_mut(&i.expr, e.span())
                } else {
                    self.check_place(&i.expr, _write)
                }
            }
            Expr::Paren(p) => self.check_place(&p.expr, _write),
            Expr::Unary(u) if matches!(u.op, syn::UnOp::Deref(_)) => {
                let t = self
                    .body
                    .tys
                    .get(&key(&*u.expr))
                    .cloned()
                    .unwrap_or(Ty::Unit);
                match self.shallow(&t) {
                    Ty::Ref(false, _) => Err(self.err(
                        e.span(),
                        "immutable-borrow",
                        "cannot assign through a `&` reference (it is not `&mut`)",
                    )),
                    Ty::Ptr(false, _) => Err(self.err(
                        e.span(),
                        "immutable-borrow",
                        "cannot assign through a `*const` pointer",
                    )),
                    _ => Ok(()),
                }
            }
            _ => Err(self.err(
                e.span(),
                "not-assignable",
                "this expression cannot be assigned to or borrowed mutably",
            )),
        }
    }

    /// A place reached through auto-dereference of `base`: the outermost reference must
    /// be `&mut` (or a `*mut` pointer).
    fn check_deref_mut(&self, base: &Expr, span: Span) -> DResult<()> {
        let t = self.body.tys.get(&key(base)).cloned().unwrap_or(Ty::Unit);
        let mut t = self.shallow(&t);
        let mut all_mut = true;
        while let Ty::Ref(m, inner) = t {
            all_mut &= m;
            t = self.shallow(&inner);
        }
        if all_mut {
            Ok(())
        } else {
            Err(self.err(
                span,
                "immutable-borrow",
                "cannot assign through a `&` reference (it is not `&mut`)",
            ))
        }
    }

    fn binary(&mut self, e: &Expr, b: &syn::ExprBinary) -> DResult<Ty> {
        let (op, assign) = BinOp::of(&b.op);
        let lt = self.expr(&b.left)?;
        let rt = self.expr(&b.right)?;
        if assign {
            self.check_place(&b.left, true)?;
        }
        if matches!(op, BinOp::And | BinOp::Or) {
            self.unify(&lt, &Ty::Bool, b.left.span())?;
            self.unify(&rt, &Ty::Bool, b.right.span())?;
            return Ok(Ty::Bool);
        }
        let (l, r) = (self.shallow(&lt), self.shallow(&rt));
        // References to primitives take part in arithmetic like their values
        // (`sum += x` with `x: &f32`).
        let prim = |t: &Ty| {
            matches!(
                t,
                Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Var(_)
            )
        };
        let deref_prim = |cx: &Self, t: &Ty| -> Option<(Ty, u32)> {
            let (inner, n) = cx.autoderef(t);
            (n > 0 && prim(&inner)).then_some((inner, n))
        };
        let (l, r) = {
            let (mut l2, mut r2) = (l.clone(), r.clone());
            let both_refs = matches!(l, Ty::Ref(..)) && matches!(r, Ty::Ref(..));
            if let Some((inner, n)) = deref_prim(self, &l) {
                if (prim(&r) || both_refs) && !assign {
                    self.body.adjust.insert(key(&*b.left), Adjust::Deref(n));
                    l2 = inner;
                }
            }
            if let Some((inner, n)) = deref_prim(self, &r) {
                if prim(&l2) {
                    self.body.adjust.insert(key(&*b.right), Adjust::Deref(n));
                    r2 = inner;
                }
            }
            (l2, r2)
        };
        // References to structs and enums compare their referents (Rust's `impl
        // PartialOrd<&B> for &A`): `a < b` with `a, b: &Key` calls `Key`'s impl.
        let (l, r) = match (self.autoderef(&l), self.autoderef(&r)) {
            ((li @ Ty::Adt(..), ln), (ri @ Ty::Adt(..), rn))
                if op.is_cmp()
                    && !assign
                    && ln > 0
                    && ln == rn
                    && !(matches!(op, BinOp::Eq | BinOp::Ne) && self.derives_eq(&l)) =>
            {
                self.body.adjust.insert(key(&*b.left), Adjust::Deref(ln));
                self.body.adjust.insert(key(&*b.right), Adjust::Deref(rn));
                (li, ri)
            }
            _ => (l, r),
        };
        let user = |t: &Ty| {
            matches!(
                t,
                Ty::Adt(..) | Ty::Tuple(_) | Ty::Array(..) | Ty::Ref(..) | Ty::Str
            )
        };
        if user(&l) || user(&r) {
            return self.overloaded(e, op, assign, &l, &r, b);
        }
        if let (Ty::Simd(s1), Ty::Simd(s2)) = (&l, &r) {
            if s1 != s2 {
                return Err(self.mismatch(b.right.span(), &l, &r));
            }
            let ok = match op {
                BinOp::Add | BinOp::Sub | BinOp::Mul => true,
                BinOp::Div => *s1 == SimdTy::F32x4,
                BinOp::BitAnd | BinOp::BitOr | BinOp::BitXor => *s1 == SimdTy::I32x4,
                _ => false,
            };
            if !ok {
                return Err(self.err(
                    b.op.span(),
                    "unsupported-operator",
                    format!(
                        "operator `{}` is not supported on `{}`",
                        op_text(op, assign),
                        self.show(&l)
                    ),
                ));
            }
            return Ok(if assign { Ty::Unit } else { l });
        }
        if op.is_cmp() {
            self.unify(&r, &l, b.right.span())?;
            let t = self.shallow(&l);
            let ok = matches!(
                t,
                Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char | Ty::Var(_) | Ty::Ptr(..)
            );
            if !ok {
                return Err(self.err(
                    b.op.span(),
                    "unsupported-operator",
                    format!("cannot compare values of type `{}`", self.show(&t)),
                ));
            }
            return Ok(Ty::Bool);
        }
        if op.is_shift() {
            for (t, s) in [(&l, b.left.span()), (&r, b.right.span())] {
                if !(t.is_int()
                    || matches!(t, Ty::Var(v) if self.vars[*v as usize].0 == VarKind::Int))
                {
                    return Err(self.err(
                        s,
                        "type-mismatch",
                        format!("shift operands must be integers, found `{}`", self.show(t)),
                    ));
                }
            }
            return Ok(if assign { Ty::Unit } else { l });
        }
        if op.is_bit() {
            self.unify(&r, &l, b.right.span())?;
            let t = self.shallow(&l);
            let ok = t.is_int()
                || t == Ty::Bool
                || matches!(t, Ty::Var(v) if self.vars[v as usize].0 != VarKind::Float);
            if !ok {
                return Err(self.err(
                    b.op.span(),
                    "type-mismatch",
                    format!("bitwise operator on `{}`", self.show(&t)),
                ));
            }
            if let Ty::Var(v) = t {
                if self.vars[v as usize].0 == VarKind::Any {
                    self.vars[v as usize].0 = VarKind::Int;
                }
            }
            return Ok(if assign { Ty::Unit } else { l });
        }
        // Arithmetic.
        self.unify(&r, &l, b.right.span())?;
        let t = self.shallow(&l);
        let ok = t.is_int()
            || t.is_float()
            || matches!(t, Ty::Var(v) if self.vars[v as usize].0 != VarKind::Any);
        if !ok {
            return Err(self.err(
                b.op.span(),
                "unsupported-operator",
                format!(
                    "cannot apply `{}` to `{}`",
                    op_text(op, assign),
                    self.show(&t)
                ),
            ));
        }
        Ok(if assign { Ty::Unit } else { l })
    }

    /// Operators on structs, enums, tuples, arrays and references: trait impls, or the
    /// compiler's structural `==` for derived `PartialEq`.
    fn overloaded(
        &mut self,
        e: &Expr,
        op: BinOp,
        assign: bool,
        lt: &Ty,
        rt: &Ty,
        b: &syn::ExprBinary,
    ) -> DResult<Ty> {
        let span = b.op.span();
        let Some(tr) = op.lang_trait(assign) else {
            return Err(self.err(
                span,
                "unsupported-operator",
                format!("operator `{}` is not supported here", op_text(op, assign)),
            ));
        };
        // User impls.
        if let Some((func, substs, ret, im_fns)) = self.op_impl(tr, lt, rt, span)? {
            let (func, substs, via_partial_cmp, negate, by_ref) = match op {
                BinOp::Ne => match im_fns.get("ne") {
                    Some(&f) => (f, substs, false, false, true),
                    None => (func, substs, false, true, true),
                },
                BinOp::Eq => (func, substs, false, false, true),
                BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                    let m = match op {
                        BinOp::Lt => "lt",
                        BinOp::Le => "le",
                        BinOp::Gt => "gt",
                        _ => "ge",
                    };
                    match im_fns.get(m) {
                        Some(&f) => (f, substs, false, false, true),
                        None => {
                            if self.p.lang.ordering.is_none() || self.p.lang.option.is_none() {
                                return Err(self.err(span, "missing-lang-item", "comparisons through `PartialOrd` need the prelude's `Option` and `Ordering`"));
                            }
                            (func, substs, true, false, true)
                        }
                    }
                }
                _ => (func, substs, false, false, false),
            };
            if assign && self.p.fns[func].receiver != Some(crate::resolve::Recv::RefMut) {
                return Err(self.err(
                    span,
                    "invalid-operator-impl",
                    format!("`{}` must take `&mut self`", self.p.fns[func].name),
                ));
            }
            self.body.ops.insert(
                key(e),
                OpCall::Fn {
                    func,
                    substs,
                    by_ref,
                    via_partial_cmp,
                    negate,
                },
            );
            return Ok(if assign {
                Ty::Unit
            } else if op.is_cmp() {
                Ty::Bool
            } else {
                ret
            });
        }
        if matches!(op, BinOp::Eq | BinOp::Ne) {
            self.unify(rt, lt, b.right.span())?;
            let t = self.deep_keep(lt);
            if self.derives_eq(&t) {
                self.body.ops.insert(
                    key(e),
                    OpCall::DerivedEq {
                        ty: t,
                        negate: op == BinOp::Ne,
                    },
                );
                return Ok(Ty::Bool);
            }
            return Err(self.err(
                span,
                "missing-operator-impl",
                format!("binary operation `{}` cannot be applied to type `{}` (derive or implement `PartialEq`)", op.text(), self.show(lt)),
            ));
        }
        Err(self.err(
            span,
            "missing-operator-impl",
            format!(
                "no implementation of `{}` for `{}` and `{}`",
                tr.name(),
                self.show(lt),
                self.show(rt)
            ),
        ))
    }

    fn unary(&mut self, e: &Expr, u: &syn::ExprUnary) -> DResult<Ty> {
        let t = self.expr(&u.expr)?;
        let mut s = self.shallow(&t);
        let op = UnOp::of(&u.op);
        if op != UnOp::Deref {
            if let Ty::Ref(..) = s {
                let (inner, n) = self.autoderef(&s);
                if matches!(inner, Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Var(_)) {
                    self.body.adjust.insert(key(&*u.expr), Adjust::Deref(n));
                    s = inner;
                }
            }
        }
        match op {
            UnOp::Deref => {
                match s {
                    Ty::Ref(_, inner) | Ty::Ptr(_, inner) => {
                        if matches!(*inner, Ty::Slice(_)) {
                            return Err(self.err(u.span(), "unsupported-slice", "dereferencing a slice reference is not supported; use the reference"));
                        }
                        Ok(*inner)
                    }
                    other => Err(self.err(
                        u.span(),
                        "invalid-deref",
                        format!("type `{}` cannot be dereferenced", self.show(&other)),
                    )),
                }
            }
            UnOp::Not => match s {
                Ty::Bool | Ty::Int(_) => Ok(s),
                Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int => Ok(s),
                Ty::Adt(..) => self.unary_impl(e, u, LangTrait::Not, &s),
                other => Err(self.err(
                    u.span(),
                    "unsupported-operator",
                    format!("cannot apply `!` to `{}`", self.show(&other)),
                )),
            },
            UnOp::Neg => match s {
                Ty::Int(_) | Ty::Float(_) | Ty::Simd(_) => Ok(s),
                Ty::Var(v) if self.vars[v as usize].0 != VarKind::Any => Ok(s),
                Ty::Adt(..) => self.unary_impl(e, u, LangTrait::Neg, &s),
                other => Err(self.err(
                    u.span(),
                    "unsupported-operator",
                    format!("cannot negate `{}`", self.show(&other)),
                )),
            },
        }
    }

    fn unary_impl(&mut self, e: &Expr, u: &syn::ExprUnary, tr: LangTrait, t: &Ty) -> DResult<Ty> {
        let name = if tr == LangTrait::Neg { "neg" } else { "not" };
        match self.trait_method_on(crate::ty::TraitKind::Lang(tr), t, name, &[], u.span())? {
            Some((func, substs)) => {
                self.body.ops.insert(
                    key(e),
                    OpCall::Fn {
                        func,
                        substs: substs.clone(),
                        by_ref: false,
                        via_partial_cmp: false,
                        negate: false,
                    },
                );
                let ret = self.p.fns[func].ret.subst(&substs);
                self.norm(&ret, u.span())
            }
            None => Err(self.err(
                u.span(),
                "missing-operator-impl",
                format!(
                    "no implementation of `{}` for `{}`",
                    tr.name(),
                    self.show(t)
                ),
            )),
        }
    }

    fn cast(&mut self, c: &syn::ExprCast) -> DResult<Ty> {
        let from = self.expr(&c.expr)?;
        let to = self.resolve_ty(&c.ty)?;
        // Like rustc, an unsuffixed literal operand (through parentheses and `-`) takes the
        // target's type: `300 as u8` is an out-of-range `u8` literal, `-1 as u32` negates
        // a `u32`, `1e40 as f32` overflows `f32`.
        let mut lit = &*c.expr;
        loop {
            lit = match lit {
                Expr::Paren(p) => &p.expr,
                Expr::Group(g) => &g.expr,
                Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => &u.expr,
                _ => break,
            };
        }
        if let (Expr::Lit(l), Ty::Var(v)) = (lit, self.shallow(&from)) {
            let target = match (&l.lit, &to, self.vars[v as usize].0) {
                (Lit::Int(_), Ty::Int(_), VarKind::Int) => Some(to.clone()),
                (Lit::Int(_), Ty::Char, VarKind::Int) => Some(Ty::Int(IntTy::U8)),
                (Lit::Int(_), Ty::Ptr(..), VarKind::Int) => Some(Ty::Int(IntTy::Usize)),
                (Lit::Float(_), Ty::Float(_), VarKind::Float) => Some(to.clone()),
                _ => None,
            };
            if let Some(t) = target {
                self.unify(&from, &t, c.expr.span())?;
            }
        }
        let f = self.shallow(&from);
        if let Ty::Var(v) = f {
            // The operand's type is inferred from its other uses (defaulting like rustc);
            // any numeric operand can be cast to a number.
            let k = self.vars[v as usize].0;
            if matches!(to, Ty::Int(_) | Ty::Float(_)) && k != VarKind::Any {
                return Ok(to);
            }
        }
        let ok = match (&f, &to) {
            (Ty::Int(_) | Ty::Float(_), Ty::Int(_) | Ty::Float(_)) => true,
            (Ty::Bool | Ty::Char, Ty::Int(_)) => true,
            (Ty::Int(IntTy::U8), Ty::Char) => true,
            (Ty::Adt(a, _), Ty::Int(_)) => self.p.adts[*a].is_fieldless_enum(),
            (Ty::Ptr(..) | Ty::Ref(..), Ty::Ptr(..)) => true,
            (Ty::Ptr(..), Ty::Int(IntTy::Usize | IntTy::U32 | IntTy::Isize | IntTy::I32)) => true,
            (Ty::Int(IntTy::Usize | IntTy::U32 | IntTy::Isize | IntTy::I32), Ty::Ptr(..)) => true,
            (a, b) => a == b,
        };
        if !ok {
            return Err(self.err(
                c.span(),
                "invalid-cast",
                format!(
                    "cannot cast `{}` as `{}`",
                    self.show(&f),
                    self.p.ty_str(&to)
                ),
            ));
        }
        Ok(to)
    }

    /// A condition: a `bool` expression or `let PAT = EXPR` (bindings go to the current
    /// scope).
    fn cond(&mut self, c: &Expr) -> DResult<()> {
        match c {
            Expr::Let(l) => {
                let t = self.expr(&l.expr)?;
                self.pattern(&l.pat, &t, false)
            }
            other => {
                let t = self.expr(other)?;
                self.unify(&t, &Ty::Bool, other.span())
            }
        }
    }

    fn if_expr(&mut self, i: &syn::ExprIf) -> DResult<Ty> {
        self.scopes.push(HashMap::new());
        let r = self.cond(&i.cond).and_then(|_| self.block(&i.then_branch));
        self.scopes.pop();
        let tt = r?;
        match &i.else_branch {
            None => {
                self.unify(&tt, &Ty::Unit, block_tail_span(&i.then_branch))?;
                Ok(Ty::Unit)
            }
            Some((_, els)) => {
                let et = self.expr(els)?;
                if matches!(self.shallow(&tt), Ty::Never) {
                    return Ok(et);
                }
                if let Some(tail) = block_tail_expr(&i.then_branch) {
                    let _ = tail;
                }
                self.unify(&et, &tt, els.span())?;
                Ok(tt)
            }
        }
    }

    fn match_expr(&mut self, m: &syn::ExprMatch) -> DResult<Ty> {
        let st = self.expr(&m.expr)?;
        let mut result: Option<Ty> = None;
        for arm in &m.arms {
            self.scopes.push(HashMap::new());
            let r = self.arm(arm, &st, &mut result);
            self.scopes.pop();
            r?;
        }
        Ok(result.unwrap_or(Ty::Never))
    }

    fn arm(&mut self, arm: &syn::Arm, st: &Ty, result: &mut Option<Ty>) -> DResult<()> {
        let (pat, guard) = split_guard(&arm.pat);
        self.pattern(pat, st, false)?;
        if let Some(g) = guard {
            let gt = self.expr(g)?;
            self.unify(&gt, &Ty::Bool, g.span())?;
        }
        let bt = self.expr(&arm.body)?;
        match result.clone() {
            None => {
                if !matches!(self.shallow(&bt), Ty::Never) {
                    *result = Some(bt);
                }
            }
            Some(r) => self.unify(&bt, &r, arm.body.span())?,
        }
        Ok(())
    }

    fn try_expr(&mut self, e: &Expr, t: &syn::ExprTry) -> DResult<Ty> {
        let vt = self.expr(&t.expr)?;
        let vt = self.shallow(&vt);
        let ret = self.shallow(&self.ret.clone());
        let (opt, res) = (self.p.lang.option, self.p.lang.result);
        match (&vt, &ret) {
            (Ty::Adt(a, args), Ty::Adt(b, _)) if Some(*a) == opt && Some(*b) == opt => {
                self.body.tries.insert(key(e), ret.clone());
                Ok(args[0].clone())
            }
            (Ty::Adt(a, args), Ty::Adt(b, rargs)) if Some(*a) == res && Some(*b) == res => {
                self.unify(&args[1], &rargs[1], t.span())?;
                self.body.tries.insert(key(e), ret.clone());
                Ok(args[0].clone())
            }
            _ => Err(self.err(
                t.span(),
                "unsupported-try",
                format!(
                    "the `?` operator needs an `Option` in a function returning `Option` or a `Result` in a function returning `Result` with the same error type (found `{}` in a function returning `{}`)",
                    self.show(&vt),
                    self.show(&ret)
                ),
            )),
        }
    }

    fn for_loop(&mut self, e: &Expr, f: &syn::ExprForLoop) -> DResult<Ty> {
        let it = classify_iter(&f.expr).map_err(|(s, m)| self.err(s, "unsupported-iterator", m))?;
        let mut infos = Vec::new();
        let elem = self.iter_ty(&it, &mut infos)?;
        self.body.fors.insert(key(e), infos);
        self.scopes.push(HashMap::new());
        let r = self.pattern(&f.pat, &elem, false).and_then(|_| {
            if !self.irrefutable(&f.pat) {
                return Err(self.err(
                    f.pat.span(),
                    "refutable-pattern",
                    "refutable pattern in `for` loop",
                ));
            }
            self.loops.push(LoopCx {
                label: f.label.as_ref().map(|l| l.name.ident.to_string()),
                brk: None,
            });
            let b = self.block(&f.body);
            self.loops.pop();
            let b = b?;
            self.unify(&b, &Ty::Unit, f.body.brace_token.span.close())
        });
        self.scopes.pop();
        r?;
        Ok(Ty::Unit)
    }

    /// Types an iterator chain; pushes one [`IterInfo`] per node in pre-order.
    fn iter_ty(&mut self, it: &IterSyn, infos: &mut Vec<IterInfo>) -> DResult<Ty> {
        let idx = infos.len();
        infos.push(IterInfo {
            elem: Ty::Unit,
            derefs: 0,
            len: None,
        });
        let usize_arg = |cx: &mut Self, x: &Expr| -> DResult<()> {
            let t = cx.expr(x)?;
            cx.unify(&t, &Ty::Int(IntTy::Usize), x.span())
        };
        let elem = match it {
            IterSyn::Range { start, end, .. } => {
                let st = self.expr(start)?;
                let en = self.expr(end)?;
                self.unify(&en, &st, end.span())?;
                let t = self.shallow(&st);
                if !(t.is_int()
                    || matches!(t, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int))
                {
                    return Err(self.err(
                        start.span(),
                        "type-mismatch",
                        format!("range bounds must be integers, found `{}`", self.show(&t)),
                    ));
                }
                st
            }
            IterSyn::Seq { base, mode } => {
                let t = self.expr(base)?;
                let s = self.shallow(&t);
                // `for x in slice_ref` iterates by reference like `&arr`.
                let (mode, derefs_to) = match (&s, mode) {
                    (Ty::Ref(m, inner), SeqMode::Value) => match self.shallow(inner) {
                        Ty::Slice(_) | Ty::Array(..) => {
                            (if *m { SeqMode::RefMut } else { SeqMode::Ref }, 1)
                        }
                        _ => (SeqMode::Value, 0),
                    },
                    (_, m) => (*m, 0),
                };
                let (bt, n) = self.autoderef(&t);
                let _ = derefs_to;
                let derefs = n;
                if mode == SeqMode::RefMut {
                    if n == 0 {
                        self.check_place(base, true)?;
                    } else {
                        self.check_deref_mut(base, base.span())?;
                    }
                }
                let (el, len) = match &bt {
                    Ty::Array(el, n) => ((**el).clone(), Some(*n)),
                    Ty::Slice(el) => ((**el).clone(), None),
                    other => {
                        return Err(self.err(
                            base.span(),
                            "unsupported-iterator",
                            format!(
                                "cannot iterate over `{}` (ranges, arrays and slices only)",
                                self.show(other)
                            ),
                        ))
                    }
                };
                if mode == SeqMode::Value && len.is_none() {
                    return Err(self.err(
                        base.span(),
                        "unsupported-iterator",
                        "a slice is iterated through a reference",
                    ));
                }
                infos[idx].derefs = derefs;
                infos[idx].len = len;
                match mode {
                    SeqMode::Value => el,
                    SeqMode::Ref => Ty::Ref(false, Box::new(el)),
                    SeqMode::RefMut => Ty::Ref(true, Box::new(el)),
                }
            }
            IterSyn::Rev(i) => self.iter_ty(i, infos)?,
            IterSyn::StepBy(i, n) | IterSyn::Skip(i, n) | IterSyn::Take(i, n) => {
                let t = self.iter_ty(i, infos)?;
                usize_arg(self, n)?;
                t
            }
            IterSyn::Enumerate(i) => {
                let t = self.iter_ty(i, infos)?;
                Ty::Tuple(vec![Ty::Int(IntTy::Usize), t])
            }
            IterSyn::Zip(a, b) => {
                let ta = self.iter_ty(a, infos)?;
                let tb = self.iter_ty(b, infos)?;
                Ty::Tuple(vec![ta, tb])
            }
            IterSyn::Copied(i) => {
                let t = self.iter_ty(i, infos)?;
                match self.shallow(&t) {
                    Ty::Ref(_, inner) => *inner,
                    other => {
                        return Err(self.err(
                            Span::call_site(),
                            "unsupported-iterator",
                            format!(
                                "`copied()` needs an iterator of references, found `{}`",
                                self.show(&other)
                            ),
                        ))
                    }
                }
            }
        };
        infos[idx].elem = elem.clone();
        Ok(elem)
    }
}

/// A match arm's pattern and guard (`pat if guard`).
pub fn split_guard(p: &Pat) -> (&Pat, Option<&Expr>) {
    match p {
        Pat::Guard(g) => (&g.pat, Some(&g.guard)),
        other => (other, None),
    }
}

/// Strips parentheses and groups.
pub fn strip(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip(&p.expr),
        Expr::Group(g) => strip(&g.expr),
        other => other,
    }
}

fn op_text(op: BinOp, assign: bool) -> String {
    if assign {
        format!("{}=", op.text())
    } else {
        op.text().to_string()
    }
}
