//! Compile-time evaluation of `const`/`static` initializers: an interpreter over checked
//! bodies that runs `const fn` calls, loops, `match`, struct/enum/tuple/array values and
//! references to locals, with rustc's evaluation errors (overflow, division by zero,
//! bounds, panics, calls of non-`const` functions). The lowering turns the values into
//! LLVM constants. Constructs it does not model (addresses of statics, raw pointers
//! into memory) report `Unsupported`; the lowering then folds the initializer itself.

use super::{cast, int_binop, show_int, wrap, CVal};
use crate::diag::{Diagnostic, FileId};
use crate::ops::{BinOp, UnOp};
use crate::resolve::{GlobalId, Program, Recv};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, Ty};
use crate::typeck::{key, Adjust, BindMode, Body, Callee, Checked, MacroCall, PatKind, Res};
use proc_macro2::Span;
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;
use syn::{Expr, Lit, Pat, Stmt};

/// A compile-time value.
#[derive(Clone, Debug, PartialEq)]
pub enum Val {
    Int(IntTy, i128),
    Float(FloatTy, f64),
    Bool(bool),
    Char(u32),
    Unit,
    Str(String),
    /// A raw pointer holding an address.
    Ptr(u32),
    /// Struct fields, tuple elements or array elements.
    Agg(Vec<Val>),
    /// An enum value: variant index and fields.
    Enum(usize, Vec<Val>),
    /// A reference to (part of) a local.
    Ref(Place),
}

/// A memory location: a cell and a path of field/element indices into it.
#[derive(Clone, Debug)]
pub struct Place {
    root: Rc<RefCell<Val>>,
    path: Vec<usize>,
}

impl PartialEq for Place {
    fn eq(&self, o: &Place) -> bool {
        Rc::ptr_eq(&self.root, &o.root) && self.path == o.path
    }
}

/// Why evaluation stopped.
pub enum Stop {
    /// A user error (rustc's E0080/E0015).
    Err(Diagnostic),
    /// Something the interpreter does not model.
    Unsupported(String),
    Break(Option<String>, Val),
    Continue(Option<String>),
    Return(Val),
}

type R<T> = Result<T, Stop>;

fn unsupported<T>(what: impl Into<String>) -> R<T> {
    Err(Stop::Unsupported(what.into()))
}

struct Frame<'b> {
    body: &'b Body,
    file: FileId,
    locals: HashMap<usize, Rc<RefCell<Val>>>,
}

/// Most interpreter steps per initializer (a loop that never ends is an error).
const MAX_STEPS: u64 = 50_000_000;

/// The interpreter.
pub struct Interp<'p, 'a> {
    p: &'p Program<'a>,
    checked: &'p Checked,
    memo: HashMap<(GlobalId, Vec<Ty>), Val>,
    active: Vec<(GlobalId, Vec<Ty>)>,
    steps: u64,
    depth: u32,
    /// What is being evaluated, for messages ("`NAME`").
    what: String,
    /// "statics" or "constants".
    kind: &'static str,
}

impl<'p, 'a> Interp<'p, 'a> {
    /// An interpreter for the program.
    pub fn new(p: &'p Program<'a>, checked: &'p Checked) -> Self {
        Interp {
            p,
            checked,
            memo: HashMap::new(),
            active: Vec::new(),
            steps: 0,
            depth: 0,
            what: String::new(),
            kind: "constants",
        }
    }

    fn fail(&self, file: FileId, span: Span, message: String) -> Stop {
        Stop::Err(
            self.p
                .err(file, span, "const-evaluation-failed", message)
                .with_label(format!("evaluation of {} failed here", self.what)),
        )
    }

    /// rustc's E0015 for a call the interpreter may not make.
    fn non_const(&self, file: FileId, span: Span, what: &str) -> Stop {
        let kind = self.kind;
        Stop::Err(self.p.err(
            file,
            span,
            "non-const-call",
            format!("cannot call non-const {what} in {kind}"),
        ))
    }

    /// Evaluates const or static instance `g`.
    pub fn global(&mut self, g: GlobalId, substs: &[Ty]) -> R<Val> {
        let k = (g, substs.to_vec());
        if let Some(v) = self.memo.get(&k) {
            return Ok(v.clone());
        }
        if self.active.contains(&k) {
            return unsupported("recursive constant");
        }
        let gd = &self.p.globals[g];
        let Some(expr) = gd.expr else {
            return unsupported("const without value");
        };
        let Some(body) = self.checked.global_body(g, substs) else {
            return unsupported("unchecked const");
        };
        if self.active.is_empty() {
            self.what = format!("`{}`", gd.name);
            self.kind = if gd.is_static.is_some() {
                "statics"
            } else {
                "constants"
            };
            self.steps = 0;
        }
        self.active.push(k.clone());
        let mut f = Frame {
            body,
            file: gd.file,
            locals: HashMap::new(),
        };
        let r = self.expr(&mut f, expr);
        self.active.pop();
        let v = match r {
            Ok(v) => v,
            Err(Stop::Return(v)) => v,
            Err(e) => return Err(e),
        };
        if contains_ref(&v) {
            return unsupported("reference in a constant");
        }
        self.memo.insert(k, v.clone());
        Ok(v)
    }

    fn tick(&mut self, f: &Frame, span: Span) -> R<()> {
        self.steps += 1;
        if self.steps > MAX_STEPS {
            return Err(self.fail(
                f.file,
                span,
                "constant evaluation is taking too long (more than 50 million steps)".into(),
            ));
        }
        Ok(())
    }

    fn ty(&self, f: &Frame, e: &Expr) -> Ty {
        f.body.tys.get(&key(e)).cloned().unwrap_or(Ty::Unit)
    }

    // ---------------------------------------------------------------- statements

    fn block(&mut self, f: &mut Frame, b: &syn::Block) -> R<Val> {
        let n = b.stmts.len();
        let mut last = Val::Unit;
        for (i, s) in b.stmts.iter().enumerate() {
            match s {
                Stmt::Local(l) => {
                    let pat = match &l.pat {
                        Pat::Type(pt) => &*pt.pat,
                        p => p,
                    };
                    match &l.init {
                        Some(init) => {
                            let v = self.expr(f, &init.expr)?;
                            let cell = Rc::new(RefCell::new(v));
                            let place = Place {
                                root: cell,
                                path: Vec::new(),
                            };
                            if !self.pat(f, pat, &place)? {
                                match &init.diverge {
                                    Some((_, els)) => {
                                        self.expr(f, els)?;
                                        return unsupported("let-else fell through");
                                    }
                                    None => return unsupported("refutable let"),
                                }
                            }
                        }
                        None => self.declare(f, pat),
                    }
                }
                Stmt::Expr(e, semi) => {
                    let v = self.expr(f, e)?;
                    if i + 1 == n && semi.is_none() {
                        last = v;
                    }
                }
                Stmt::Macro(m) => {
                    let v = self.mac(f, &m.mac)?;
                    if i + 1 == n && m.semi_token.is_none() {
                        last = v;
                    }
                }
                Stmt::Item(_) => {}
            }
        }
        Ok(last)
    }

    fn declare(&mut self, f: &mut Frame, pat: &Pat) {
        if let Pat::Ident(pi) = pat {
            if let Some((id, _)) = f.body.binds.get(&key(pi)) {
                f.locals.insert(*id, Rc::new(RefCell::new(Val::Unit)));
            }
        }
    }

    // ---------------------------------------------------------------- expressions

    fn expr(&mut self, f: &mut Frame, e: &Expr) -> R<Val> {
        self.tick(f, e.span())?;
        let v = self.expr_inner(f, e)?;
        Ok(match f.body.adjust.get(&key(e)) {
            Some(Adjust::Deref(n)) => {
                let mut v = v;
                for _ in 0..*n {
                    v = match v {
                        Val::Ref(p) => load(&p),
                        other => other,
                    };
                }
                v
            }
            Some(Adjust::Unsize(_)) => return unsupported("slice reference in a constant"),
            None => v,
        })
    }

    fn expr_inner(&mut self, f: &mut Frame, e: &Expr) -> R<Val> {
        let ty = self.ty(f, e);
        match e {
            Expr::Lit(l) => lit(&l.lit, &ty),
            Expr::Paren(p) => self.expr(f, &p.expr),
            Expr::Group(g) => self.expr(f, &g.expr),
            Expr::Block(b) if b.label.is_none() => self.block(f, &b.block),
            Expr::Unsafe(u) => self.block(f, &u.block),
            Expr::Path(_) => self.path(f, e, &ty),
            Expr::Binary(b) => self.binary(f, e, b),
            Expr::Unary(u) => {
                if f.body.ops.contains_key(&key(e)) {
                    return Err(self.non_const(f.file, u.span(), "operator"));
                }
                let v = self.expr(f, &u.expr)?;
                match (UnOp::of(&u.op), v) {
                    (UnOp::Deref, Val::Ref(p)) => Ok(load(&p)),
                    (UnOp::Deref, _) => unsupported("dereference of a raw pointer"),
                    (UnOp::Not, Val::Bool(b)) => Ok(Val::Bool(!b)),
                    (UnOp::Not, Val::Int(t, x)) => {
                        Ok(Val::Int(t, if t.signed() { !x } else { t.max() - x }))
                    }
                    (UnOp::Neg, Val::Float(t, x)) => Ok(Val::Float(t, -x)),
                    (UnOp::Neg, Val::Int(t, x)) => {
                        if x == t.min() && t.signed() {
                            return Err(self.fail(
                                f.file,
                                e.span(),
                                format!(
                                    "attempt to negate `{}`, which would overflow",
                                    show_int(t, x)
                                ),
                            ));
                        }
                        Ok(Val::Int(t, -x))
                    }
                    _ => unsupported("unary operator"),
                }
            }
            Expr::Assign(a) => {
                let v = self.expr(f, &a.right)?;
                let p = self.place(f, &a.left)?;
                store(&p, v);
                Ok(Val::Unit)
            }
            Expr::Cast(c) => {
                let from = self.expr(f, &c.expr)?;
                if let (Val::Enum(v, _), Ty::Adt(a, _), Ty::Int(t)) =
                    (&from, self.ty(f, &c.expr), &ty)
                {
                    let d = self.p.adts[a].variants[*v].discr;
                    return Ok(Val::Int(*t, wrap(*t, d)));
                }
                self.cast(f, from, &ty, c.span())
            }
            Expr::If(i) => {
                let saved = f.locals.len();
                let _ = saved;
                if self.cond(f, &i.cond)? {
                    self.block(f, &i.then_branch)
                } else if let Some((_, els)) = &i.else_branch {
                    self.expr(f, els)
                } else {
                    Ok(Val::Unit)
                }
            }
            Expr::While(w) => {
                let label = w.label.as_ref().map(|l| l.name.ident.to_string());
                while self.cond(f, &w.cond)? {
                    match self.block(f, &w.body) {
                        Ok(_) => {}
                        Err(Stop::Break(l, _)) if l.is_none() || l == label => break,
                        Err(Stop::Continue(l)) if l.is_none() || l == label => continue,
                        Err(other) => return Err(other),
                    }
                }
                Ok(Val::Unit)
            }
            Expr::Loop(l) => {
                let label = l.label.as_ref().map(|l| l.name.ident.to_string());
                loop {
                    match self.block(f, &l.body) {
                        Ok(_) => {}
                        Err(Stop::Break(lb, v)) if lb.is_none() || lb == label => return Ok(v),
                        Err(Stop::Continue(lb)) if lb.is_none() || lb == label => continue,
                        Err(other) => return Err(other),
                    }
                }
            }
            Expr::ForLoop(fl) => self.for_loop(f, fl),
            Expr::Break(b) => {
                let v = match &b.expr {
                    Some(x) => self.expr(f, x)?,
                    None => Val::Unit,
                };
                Err(Stop::Break(
                    b.label.as_ref().map(|l| l.ident.to_string()),
                    v,
                ))
            }
            Expr::Continue(c) => Err(Stop::Continue(
                c.label.as_ref().map(|l| l.ident.to_string()),
            )),
            Expr::Return(r) => {
                let v = match &r.expr {
                    Some(x) => self.expr(f, x)?,
                    None => Val::Unit,
                };
                Err(Stop::Return(v))
            }
            Expr::Call(c) => {
                let args: Vec<&Expr> = c.args.iter().collect();
                self.call(f, e, None, &args, &ty)
            }
            Expr::MethodCall(m) => {
                let args: Vec<&Expr> = m.args.iter().collect();
                self.call(f, e, Some(&m.receiver), &args, &ty)
            }
            Expr::Field(_) | Expr::Index(_) => {
                let p = self.place(f, e)?;
                Ok(load(&p))
            }
            Expr::Reference(r) => {
                let p = self.place_or_temp(f, &r.expr)?;
                Ok(Val::Ref(p))
            }
            Expr::Array(a) => {
                let mut vs = Vec::new();
                for x in &a.elems {
                    vs.push(self.expr(f, x)?);
                }
                Ok(Val::Agg(vs))
            }
            Expr::Repeat(r) => {
                let v = self.expr(f, &r.expr)?;
                let Ty::Array(_, n) = ty else {
                    return unsupported("repeat");
                };
                Ok(Val::Agg(vec![v; n as usize]))
            }
            Expr::Tuple(t) => {
                if t.elems.is_empty() {
                    return Ok(Val::Unit);
                }
                let mut vs = Vec::new();
                for x in &t.elems {
                    vs.push(self.expr(f, x)?);
                }
                Ok(Val::Agg(vs))
            }
            Expr::Struct(s) => {
                let Some(&(a, v)) = f.body.structs.get(&key(e)) else {
                    return unsupported("struct literal");
                };
                let n = self.p.adts[a].variants[v].fields.len();
                let mut vals: Vec<Option<Val>> = vec![None; n];
                if let Some(r) = &s.rest {
                    if let Val::Agg(base) = self.expr(f, r)? {
                        for (i, b) in base.into_iter().enumerate() {
                            vals[i] = Some(b);
                        }
                    }
                }
                for fv in &s.fields {
                    let i = *f
                        .body
                        .fields
                        .get(&key(fv))
                        .ok_or(Stop::Unsupported("field".into()))?;
                    vals[i] = Some(self.expr(f, &fv.expr)?);
                }
                let vals: Vec<Val> = vals.into_iter().map(|v| v.unwrap_or(Val::Unit)).collect();
                Ok(if self.p.adts[a].is_enum {
                    Val::Enum(v, vals)
                } else {
                    Val::Agg(vals)
                })
            }
            Expr::Match(m) => {
                let scrut = self.place_or_temp(f, &m.expr)?;
                for arm in &m.arms {
                    let (pat, guard) = crate::typeck::split_guard(&arm.pat);
                    if !self.pat(f, pat, &scrut)? {
                        continue;
                    }
                    if let Some(g) = guard {
                        if self.expr(f, g)? != Val::Bool(true) {
                            continue;
                        }
                    }
                    return self.expr(f, &arm.body);
                }
                Err(self.fail(
                    f.file,
                    m.span(),
                    "entered unreachable code: no match arm matched".into(),
                ))
            }
            Expr::Macro(m) => self.mac(f, &m.mac),
            _ => unsupported("expression"),
        }
    }

    fn cond(&mut self, f: &mut Frame, c: &Expr) -> R<bool> {
        match c {
            Expr::Let(l) => {
                let p = self.place_or_temp(f, &l.expr)?;
                self.pat(f, &l.pat, &p)
            }
            other => Ok(self.expr(f, other)? == Val::Bool(true)),
        }
    }

    fn for_loop(&mut self, f: &mut Frame, fl: &syn::ExprForLoop) -> R<Val> {
        let Expr::Range(r) = crate::typeck::strip_expr(&fl.expr) else {
            return unsupported("for loop over a non-range in a constant");
        };
        let (Some(s), Some(en)) = (&r.start, &r.end) else {
            return unsupported("open range");
        };
        let (Val::Int(t, a), Val::Int(_, b)) = (self.expr(f, s)?, self.expr(f, en)?) else {
            return unsupported("range");
        };
        let b = if matches!(r.limits, syn::RangeLimits::Closed(_)) {
            b + 1
        } else {
            b
        };
        let label = fl.label.as_ref().map(|l| l.name.ident.to_string());
        let mut i = a;
        while i < b {
            let cell = Rc::new(RefCell::new(Val::Int(t, i)));
            self.pat(
                f,
                &fl.pat,
                &Place {
                    root: cell,
                    path: Vec::new(),
                },
            )?;
            match self.block(f, &fl.body) {
                Ok(_) => {}
                Err(Stop::Break(l, _)) if l.is_none() || l == label => break,
                Err(Stop::Continue(l)) if l.is_none() || l == label => {}
                Err(other) => return Err(other),
            }
            i += 1;
        }
        Ok(Val::Unit)
    }

    fn path(&mut self, f: &mut Frame, e: &Expr, ty: &Ty) -> R<Val> {
        match f.body.res.get(&key(e)).cloned() {
            Some(Res::Local(id)) => match f.locals.get(&id) {
                Some(c) => Ok(c.borrow().clone()),
                None => unsupported("unbound local"),
            },
            Some(Res::Global(g, s)) => {
                if self.p.globals[g].is_static.is_some() {
                    return unsupported("a static's value");
                }
                self.depth += 1;
                let r = self.global(g, &s);
                self.depth -= 1;
                r
            }
            Some(Res::Unit(a, v)) => Ok(if self.p.adts[a].is_enum {
                Val::Enum(v, Vec::new())
            } else {
                Val::Agg(Vec::new())
            }),
            Some(Res::Int(t, v)) => Ok(Val::Int(t, v)),
            Some(Res::Float(t, v)) => Ok(Val::Float(t, round(t, v))),
            None => {
                let _ = ty;
                unsupported("path")
            }
        }
    }

    fn binary(&mut self, f: &mut Frame, e: &Expr, b: &syn::ExprBinary) -> R<Val> {
        let (op, assign) = BinOp::of(&b.op);
        if f.body.ops.contains_key(&key(e)) {
            return Err(self.non_const(f.file, b.span(), "operator"));
        }
        if op == BinOp::And || op == BinOp::Or {
            let l = self.expr(f, &b.left)? == Val::Bool(true);
            if (op == BinOp::And) != l {
                return Ok(Val::Bool(l));
            }
            return self.expr(f, &b.right);
        }
        let r = self.expr(f, &b.right)?;
        if assign {
            let p = self.place(f, &b.left)?;
            let l = load(&p);
            let v = self.arith(f, op, l, r, b.span())?;
            store(&p, v);
            return Ok(Val::Unit);
        }
        let l = self.expr(f, &b.left)?;
        self.arith(f, op, l, r, b.span())
    }

    fn arith(&mut self, f: &Frame, op: BinOp, l: Val, r: Val, span: Span) -> R<Val> {
        use std::cmp::Ordering as O;
        if op.is_cmp() {
            let ord = match (&l, &r) {
                (Val::Int(_, x), Val::Int(_, y)) => x.partial_cmp(y),
                (Val::Float(_, x), Val::Float(_, y)) => x.partial_cmp(y),
                (Val::Bool(x), Val::Bool(y)) => x.partial_cmp(y),
                (Val::Char(x), Val::Char(y)) => x.partial_cmp(y),
                _ => {
                    if op == BinOp::Eq || op == BinOp::Ne {
                        let eq = l == r;
                        return Ok(Val::Bool(eq == (op == BinOp::Eq)));
                    }
                    return unsupported("comparison");
                }
            };
            return Ok(Val::Bool(match (op, ord) {
                (BinOp::Ne, o) => o != Some(O::Equal),
                (_, None) => false,
                (BinOp::Eq, Some(o)) => o == O::Equal,
                (BinOp::Lt, Some(o)) => o == O::Less,
                (BinOp::Le, Some(o)) => o != O::Greater,
                (BinOp::Gt, Some(o)) => o == O::Greater,
                (_, Some(o)) => o != O::Less,
            }));
        }
        match (l, r) {
            (Val::Int(t, x), Val::Int(rt, y)) => match int_binop(op, t, Some(x), rt, Some(y)) {
                Ok(Some(v)) => Ok(Val::Int(t, v)),
                Ok(None) => unsupported("integer operation"),
                Err(fl) => Err(self.fail(f.file, span, fl.message)),
            },
            (Val::Float(t, x), Val::Float(_, y)) => {
                let v = match op {
                    BinOp::Add => x + y,
                    BinOp::Sub => x - y,
                    BinOp::Mul => x * y,
                    BinOp::Div => x / y,
                    BinOp::Rem => x % y,
                    _ => return unsupported("float operation"),
                };
                Ok(Val::Float(t, round(t, v)))
            }
            (Val::Bool(x), Val::Bool(y)) => Ok(Val::Bool(match op {
                BinOp::BitAnd => x & y,
                BinOp::BitOr => x | y,
                BinOp::BitXor => x ^ y,
                _ => return unsupported("bool operation"),
            })),
            _ => unsupported("operation"),
        }
    }

    fn cast(&mut self, _f: &Frame, v: Val, to: &Ty, _span: Span) -> R<Val> {
        let cv = match &v {
            Val::Int(t, x) => CVal::Int(*t, *x),
            Val::Float(t, x) => CVal::Float(*t, *x),
            Val::Bool(b) => CVal::Bool(*b),
            Val::Char(c) => CVal::Char(*c),
            Val::Enum(..) => return unsupported("enum cast"),
            Val::Ptr(a) => {
                return match to {
                    Ty::Int(t) => Ok(Val::Int(*t, wrap(*t, *a as i128))),
                    Ty::Ptr(..) => Ok(v),
                    _ => unsupported("pointer cast"),
                }
            }
            _ => return unsupported("cast"),
        };
        if let (CVal::Int(_, x), Ty::Ptr(..)) = (cv, to) {
            return Ok(Val::Ptr(x as u32));
        }
        match cast(cv, to) {
            Some(CVal::Int(t, x)) => Ok(Val::Int(t, x)),
            Some(CVal::Float(t, x)) => Ok(Val::Float(t, x)),
            Some(CVal::Bool(b)) => Ok(Val::Bool(b)),
            Some(CVal::Char(c)) => Ok(Val::Char(c)),
            None => unsupported("cast"),
        }
    }

    // ---------------------------------------------------------------- places

    fn place_or_temp(&mut self, f: &mut Frame, e: &Expr) -> R<Place> {
        match crate::typeck::strip_expr(e) {
            Expr::Path(_) | Expr::Field(_) | Expr::Index(_) | Expr::Unary(_) => {
                if let Ok(p) = self.place(f, e) {
                    return Ok(p);
                }
            }
            _ => {}
        }
        let v = self.expr(f, e)?;
        Ok(Place {
            root: Rc::new(RefCell::new(v)),
            path: Vec::new(),
        })
    }

    fn place(&mut self, f: &mut Frame, e: &Expr) -> R<Place> {
        match e {
            Expr::Paren(p) => self.place(f, &p.expr),
            Expr::Group(g) => self.place(f, &g.expr),
            Expr::Path(_) => match f.body.res.get(&key(e)) {
                Some(Res::Local(id)) => match f.locals.get(id) {
                    Some(c) => Ok(Place {
                        root: c.clone(),
                        path: Vec::new(),
                    }),
                    None => unsupported("unbound local"),
                },
                _ => {
                    let v = self.expr(f, e)?;
                    Ok(Place {
                        root: Rc::new(RefCell::new(v)),
                        path: Vec::new(),
                    })
                }
            },
            Expr::Field(fe) => {
                let derefs = f.body.derefs.get(&key(e)).copied().unwrap_or(0);
                let base = self.deref_place(f, &fe.base, derefs)?;
                let i = *f
                    .body
                    .fields
                    .get(&key(e))
                    .ok_or(Stop::Unsupported("field".into()))?;
                Ok(base.child(i))
            }
            Expr::Index(ix) => {
                if f.body.ops.contains_key(&key(e)) {
                    return Err(self.non_const(f.file, e.span(), "`Index` impl"));
                }
                let derefs = f.body.derefs.get(&key(e)).copied().unwrap_or(0);
                let base = self.deref_place(f, &ix.expr, derefs)?;
                let Val::Int(_, i) = self.expr(f, &ix.index)? else {
                    return unsupported("slice index");
                };
                let len = match &load(&base) {
                    Val::Agg(v) => v.len(),
                    _ => return unsupported("index of a non-array"),
                };
                if i < 0 || i as usize >= len {
                    return Err(self.fail(
                        f.file,
                        e.span(),
                        format!("index out of bounds: the length is {len} but the index is {i}"),
                    ));
                }
                Ok(base.child(i as usize))
            }
            Expr::Unary(u) if matches!(u.op, syn::UnOp::Deref(_)) => match self.expr(f, &u.expr)? {
                Val::Ref(p) => Ok(p),
                _ => unsupported("dereference of a raw pointer"),
            },
            other => {
                let v = self.expr(f, other)?;
                Ok(Place {
                    root: Rc::new(RefCell::new(v)),
                    path: Vec::new(),
                })
            }
        }
    }

    fn deref_place(&mut self, f: &mut Frame, e: &Expr, derefs: u32) -> R<Place> {
        let mut p = self.place_or_temp(f, e)?;
        for _ in 0..derefs {
            p = match load(&p) {
                Val::Ref(q) => q,
                _ => return unsupported("dereference"),
            };
        }
        Ok(p)
    }

    // ---------------------------------------------------------------- calls

    fn call(
        &mut self,
        f: &mut Frame,
        e: &Expr,
        recv: Option<&Expr>,
        args: &[&Expr],
        ty: &Ty,
    ) -> R<Val> {
        let Some(c) = f.body.callees.get(&key(e)).cloned() else {
            return unsupported("call");
        };
        let mut vals = Vec::new();
        if let Some(r) = recv {
            let adj = match &c {
                Callee::Fn { recv, .. }
                | Callee::Builtin { recv, .. }
                | Callee::Derived { recv, .. } => *recv,
                Callee::Ctor { .. } | Callee::Closure { .. } => Default::default(),
            };
            let base = self.deref_place(f, r, adj.derefs)?;
            vals.push(match adj.autoref {
                Some(_) => Val::Ref(base),
                None => load(&base),
            });
        }
        for a in args {
            vals.push(self.expr(f, a)?);
        }
        match c {
            Callee::Ctor { adt, variant } => Ok(if self.p.adts[adt].is_enum {
                Val::Enum(variant, vals)
            } else {
                Val::Agg(vals)
            }),
            Callee::Fn { func, substs, .. } => {
                let fd = &self.p.fns[func];
                if !fd.is_const {
                    let kind = self.kind;
                    return Err(Stop::Err(
                        self.p
                            .err(f.file, e.span(), "non-const-call", format!("cannot call non-const function `{}` in {kind}", fd.name))
                            .with_note(format!("calls in {kind} are limited to constant functions, tuple structs and tuple variants")),
                    ));
                }
                let Some(block) = fd.body else {
                    return unsupported("function without body");
                };
                let Some(body) = self.checked.fn_body(func, &substs) else {
                    return unsupported("unchecked function");
                };
                if self.depth > 200 {
                    return Err(self.fail(
                        f.file,
                        e.span(),
                        "reached the recursion limit during constant evaluation".into(),
                    ));
                }
                let mut frame = Frame {
                    body,
                    file: fd.file,
                    locals: HashMap::new(),
                };
                for (i, (arg, v)) in fd.sig.inputs.iter().zip(vals).enumerate() {
                    let cell = Rc::new(RefCell::new(v));
                    match arg {
                        syn::FnArg::Receiver(_) => {
                            frame.locals.insert(0, cell);
                        }
                        syn::FnArg::Typed(pt) => {
                            let _ = i;
                            let place = Place {
                                root: cell,
                                path: Vec::new(),
                            };
                            self.pat(&mut frame, &pt.pat, &place)?;
                        }
                    }
                }
                let _ = Recv::Value;
                self.depth += 1;
                let r = self.block(&mut frame, block);
                self.depth -= 1;
                match r {
                    Ok(v) | Err(Stop::Return(v)) => Ok(v),
                    Err(other) => Err(other),
                }
            }
            Callee::Derived { method, ty: st, .. } => match method {
                "clone" => Ok(match vals.into_iter().next() {
                    Some(Val::Ref(p)) => load(&p),
                    Some(v) => v,
                    None => Val::Unit,
                }),
                "default" => self.default_of(&st),
                _ => unsupported("derived method"),
            },
            Callee::Closure { .. } => unsupported("closure call"),
            Callee::Builtin { b, .. } => {
                let _ = ty;
                builtin(b, vals).map_or_else(|| unsupported("builtin"), Ok)
            }
        }
    }

    fn default_of(&mut self, t: &Ty) -> R<Val> {
        Ok(match t {
            Ty::Int(i) => Val::Int(*i, 0),
            Ty::Float(x) => Val::Float(*x, 0.0),
            Ty::Bool => Val::Bool(false),
            Ty::Char => Val::Char(0),
            Ty::Unit => Val::Unit,
            Ty::Tuple(ts) => Val::Agg(
                ts.iter()
                    .map(|x| self.default_of(x))
                    .collect::<R<Vec<_>>>()?,
            ),
            Ty::Array(e, n) => {
                let d = self.default_of(e)?;
                Val::Agg(vec![d; *n as usize])
            }
            Ty::Adt(a, args) => {
                let def = &self.p.adts[*a];
                if def.is_enum {
                    Val::Enum(
                        def.default_variant
                            .ok_or(Stop::Unsupported("enum default".into()))?,
                        Vec::new(),
                    )
                } else {
                    let ftys: Vec<Ty> = def
                        .fields()
                        .iter()
                        .map(|f| self.p.normalize(&f.ty.subst(args)).unwrap_or(Ty::Unit))
                        .collect();
                    for im in &self.p.impls {
                        if im.trait_.as_ref().is_some_and(|t| {
                            t.kind == crate::ty::TraitKind::Lang(crate::ty::LangTrait::Default)
                        }) {
                            let mut s = vec![None; im.generics.len()];
                            if self.p.match_ty(&im.self_ty, t, &mut s) {
                                return unsupported("user Default impl");
                            }
                        }
                    }
                    Val::Agg(
                        ftys.iter()
                            .map(|x| self.default_of(x))
                            .collect::<R<Vec<_>>>()?,
                    )
                }
            }
            _ => return unsupported("default"),
        })
    }

    fn mac(&mut self, f: &mut Frame, m: &syn::Macro) -> R<Val> {
        match f.body.macros.get(&key(m)) {
            Some(MacroCall::Matches { expr, pat, guard }) => {
                let p = self.place_or_temp(f, expr)?;
                if !self.pat(f, pat, &p)? {
                    return Ok(Val::Bool(false));
                }
                if let Some(g) = guard {
                    return self.expr(f, g);
                }
                Ok(Val::Bool(true))
            }
            Some(MacroCall::Abort {
                cond, cmp, pieces, ..
            }) => {
                if let Some(c) = cond {
                    if self.expr(f, c)? == Val::Bool(true) {
                        return Ok(Val::Unit);
                    }
                }
                if let Some((a, b, ne)) = cmp {
                    let eq = self.expr(f, a)? == self.expr(f, b)?;
                    if eq != *ne {
                        return Ok(Val::Unit);
                    }
                }
                let text: String = pieces
                    .iter()
                    .map(|p| match p {
                        crate::typeck::FmtPiece::Lit(s) => s.clone(),
                        crate::typeck::FmtPiece::Arg(..) => "{..}".into(),
                    })
                    .collect();
                Err(self.fail(f.file, m.span(), format!("evaluation panicked: {text}")))
            }
            Some(MacroCall::Nothing) => Ok(Val::Unit),
            _ => unsupported("macro"),
        }
    }

    // ---------------------------------------------------------------- patterns

    /// Matches the value at `p` against `pat`, binding locals; false on a mismatch.
    fn pat(&mut self, f: &mut Frame, pat: &Pat, p: &Place) -> R<bool> {
        let info = f.body.pats.get(&key(pat)).cloned();
        let mut p = p.clone();
        if let Some(i) = &info {
            for _ in 0..i.derefs {
                p = match load(&p) {
                    Val::Ref(q) => q,
                    _ => return unsupported("pattern dereference"),
                };
            }
        }
        match pat {
            Pat::Wild(_) | Pat::Rest(_) => Ok(true),
            Pat::Paren(x) => self.pat(f, &x.pat, &p),
            Pat::Ident(pi) => match info.map(|i| i.kind) {
                Some(PatKind::Variant(_, v)) => Ok(matches!(load(&p), Val::Enum(x, _) if x == v)
                    || !matches!(load(&p), Val::Enum(..))),
                Some(PatKind::Const(c)) => Ok(int_of(&load(&p)) == Some(c)),
                _ => {
                    if let Some((_, sub)) = &pi.subpat {
                        if !matches!(**sub, Pat::Rest(_)) && !self.pat(f, sub, &p)? {
                            return Ok(false);
                        }
                    }
                    if let Some((id, mode)) = f.body.binds.get(&key(pi)).copied() {
                        let v = match mode {
                            BindMode::Value => load(&p),
                            BindMode::Ref(_) => Val::Ref(p.clone()),
                        };
                        f.locals.insert(id, Rc::new(RefCell::new(v)));
                    }
                    Ok(true)
                }
            },
            Pat::Reference(r) => match load(&p) {
                Val::Ref(q) => self.pat(f, &r.pat, &q),
                _ => unsupported("reference pattern"),
            },
            Pat::Or(o) => {
                for c in &o.cases {
                    if self.pat(f, c, &p)? {
                        return Ok(true);
                    }
                }
                Ok(false)
            }
            Pat::Lit(l) => {
                let lt = f.body.tys.get(&key(l)).cloned().unwrap_or(Ty::Unit);
                Ok(load(&p) == lit(&l.lit, &lt)?)
            }
            Pat::Range(r) => {
                let v = load(&p);
                let bound = |s: &mut Self, f: &mut Frame, e: &Expr| -> R<Val> {
                    if let Some(crate::typeck::PatInfo {
                        kind: PatKind::Const(c),
                        ty,
                        ..
                    }) = f.body.pats.get(&key(e)).cloned()
                    {
                        return Ok(match ty {
                            Ty::Int(t) => Val::Int(t, c),
                            Ty::Char => Val::Char(c as u32),
                            _ => Val::Int(IntTy::I32, c),
                        });
                    }
                    s.expr(f, e)
                };
                if let Some(s) = &r.start {
                    let b = bound(self, f, s)?;
                    if self.arith(f, BinOp::Ge, v.clone(), b, s.span())? != Val::Bool(true) {
                        return Ok(false);
                    }
                }
                if let Some(e) = &r.end {
                    let b = bound(self, f, e)?;
                    let op = if matches!(r.limits, syn::RangeLimits::Closed(_)) {
                        BinOp::Le
                    } else {
                        BinOp::Lt
                    };
                    if self.arith(f, op, v, b, e.span())? != Val::Bool(true) {
                        return Ok(false);
                    }
                }
                Ok(true)
            }
            Pat::Path(_) => match info.map(|i| i.kind) {
                Some(PatKind::Variant(_, v)) => Ok(match load(&p) {
                    Val::Enum(x, _) => x == v,
                    _ => true,
                }),
                Some(PatKind::Const(c)) => Ok(int_of(&load(&p)) == Some(c)),
                _ => unsupported("path pattern"),
            },
            Pat::TupleStruct(ts) => {
                let Some(PatKind::Variant(_, v)) = info.map(|i| i.kind) else {
                    return unsupported("tuple-struct pattern");
                };
                if let Val::Enum(x, _) = load(&p) {
                    if x != v {
                        return Ok(false);
                    }
                }
                self.seq_pats(f, ts.elems.iter().collect(), &p)
            }
            Pat::Struct(s) => {
                let Some(PatKind::Variant(_, v)) = info.map(|i| i.kind) else {
                    return unsupported("struct pattern");
                };
                if let Val::Enum(x, _) = load(&p) {
                    if x != v {
                        return Ok(false);
                    }
                }
                for fp in &s.fields {
                    let i = *f
                        .body
                        .fields
                        .get(&key(fp))
                        .ok_or(Stop::Unsupported("field".into()))?;
                    if !self.pat(f, &fp.pat, &p.child(i))? {
                        return Ok(false);
                    }
                }
                Ok(true)
            }
            Pat::Tuple(t) => self.seq_pats(f, t.elems.iter().collect(), &p),
            Pat::Slice(_) => unsupported("slice pattern in a constant"),
            _ => unsupported("pattern"),
        }
    }

    fn seq_pats(&mut self, f: &mut Frame, elems: Vec<&Pat>, p: &Place) -> R<bool> {
        let n = match load(p) {
            Val::Agg(v) | Val::Enum(_, v) => v.len(),
            _ => 0,
        };
        let rest = elems.iter().position(|e| matches!(e, Pat::Rest(_)));
        for (i, e) in elems.iter().enumerate() {
            let fi = match rest {
                Some(r) if i == r => continue,
                Some(r) if i > r => n - (elems.len() - i),
                _ => i,
            };
            if !self.pat(f, e, &p.child(fi))? {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

impl Place {
    fn child(&self, i: usize) -> Place {
        let mut path = self.path.clone();
        path.push(i);
        Place {
            root: self.root.clone(),
            path,
        }
    }
}

fn load(p: &Place) -> Val {
    let v = p.root.borrow();
    let mut cur: &Val = &v;
    for &i in &p.path {
        cur = match cur {
            Val::Agg(xs) | Val::Enum(_, xs) => match xs.get(i) {
                Some(x) => x,
                None => return Val::Unit,
            },
            _ => return Val::Unit,
        };
    }
    cur.clone()
}

fn store(p: &Place, val: Val) {
    let mut v = p.root.borrow_mut();
    let mut cur: &mut Val = &mut v;
    for &i in &p.path {
        cur = match cur {
            Val::Agg(xs) | Val::Enum(_, xs) => match xs.get_mut(i) {
                Some(x) => x,
                None => return,
            },
            _ => return,
        };
    }
    *cur = val;
}

fn contains_ref(v: &Val) -> bool {
    match v {
        Val::Ref(_) => true,
        Val::Agg(xs) | Val::Enum(_, xs) => xs.iter().any(contains_ref),
        _ => false,
    }
}

fn int_of(v: &Val) -> Option<i128> {
    match v {
        Val::Int(_, x) => Some(*x),
        Val::Bool(b) => Some(*b as i128),
        Val::Char(c) => Some(*c as i128),
        _ => None,
    }
}

fn round(f: FloatTy, x: f64) -> f64 {
    match f {
        FloatTy::F32 => x as f32 as f64,
        FloatTy::F64 => x,
    }
}

fn lit(l: &Lit, ty: &Ty) -> R<Val> {
    Ok(match (l, ty) {
        (Lit::Int(i), Ty::Int(t)) => {
            let v: i128 = i
                .base10_parse()
                .map_err(|_| Stop::Unsupported("literal".into()))?;
            Val::Int(*t, v)
        }
        (Lit::Int(i), Ty::Float(t)) => {
            let v: i128 = i
                .base10_parse()
                .map_err(|_| Stop::Unsupported("literal".into()))?;
            Val::Float(*t, round(*t, v as f64))
        }
        (Lit::Float(x), Ty::Float(t)) => {
            let v = match t {
                FloatTy::F32 => x.base10_parse::<f32>().map(|v| v as f64),
                FloatTy::F64 => x.base10_parse::<f64>(),
            }
            .map_err(|_| Stop::Unsupported("literal".into()))?;
            Val::Float(*t, v)
        }
        (Lit::Bool(b), _) => Val::Bool(b.value),
        (Lit::Char(c), _) => Val::Char(c.value() as u32),
        (Lit::Byte(b), _) => Val::Int(IntTy::U8, b.value() as i128),
        (Lit::Str(s), _) => Val::Str(s.value()),
        _ => return unsupported("literal"),
    })
}

/// The integer builtins that are `const fn` in Rust.
fn builtin(b: crate::builtins::Builtin, vals: Vec<Val>) -> Option<Val> {
    use crate::builtins::Builtin as B;
    let ints: Vec<(IntTy, i128)> = vals
        .iter()
        .filter_map(|v| match v {
            Val::Int(t, x) => Some((*t, *x)),
            _ => None,
        })
        .collect();
    let (t, x) = *ints.first()?;
    let y = ints.get(1).map(|p| p.1);
    Some(Val::Int(
        t,
        match b {
            B::IMin => x.min(y?),
            B::IMax => x.max(y?),
            B::IAbs => x.abs(),
            B::IWrappingAdd => wrap(t, x + y?),
            B::IWrappingSub => wrap(t, x - y?),
            B::IWrappingMul => wrap(t, x.wrapping_mul(y?)),
            B::IWrappingNeg => wrap(t, -x),
            B::ICountOnes => {
                return Some(Val::Int(
                    IntTy::U32,
                    ((x as u128) & mask(t)).count_ones() as i128,
                ))
            }
            B::IPow => {
                let mut r: i128 = 1;
                for _ in 0..y? {
                    r = r.checked_mul(x)?;
                }
                if r > t.max() || r < t.min() {
                    return None;
                }
                r
            }
            _ => return None,
        },
    ))
}

fn mask(t: IntTy) -> u128 {
    (1u128 << t.bits()) - 1
}

/// Evaluates the values of every const and static that the interpreter can: `Ok` values
/// by instance, or the first evaluation error.
pub fn evaluate_all(
    p: &Program,
    checked: &Checked,
) -> Result<HashMap<(GlobalId, Vec<Ty>), Val>, Diagnostic> {
    let mut it = Interp::new(p, checked);
    let mut keys: Vec<(GlobalId, Vec<Ty>)> = checked
        .bodies
        .keys()
        .filter_map(|k| match k {
            crate::typeck::Item::Global(g, s) => Some((*g, s.clone())),
            _ => None,
        })
        .collect();
    keys.sort_by_key(|(g, s)| (*g, format!("{s:?}")));
    let mut out = HashMap::new();
    for (g, s) in keys {
        it.active.clear();
        it.depth = 0;
        match it.global(g, &s) {
            Ok(v) => {
                out.insert((g, s), v);
            }
            Err(Stop::Err(d)) => return Err(d),
            Err(_) => {}
        }
    }
    Ok(out)
}
