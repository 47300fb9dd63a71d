//! Calls and method calls: user functions (generic ones get their arguments inferred),
//! tuple-struct and variant constructors, `Trait::f(..)` (deferred until `Self` is
//! known), `core` functions, the builtin catalogue (libm methods call the prelude's
//! `trax::libm`), and method receivers (autoderef, autoref).

use super::infer::{Cx, Deferred, VarKind};
use super::path::ValuePath;
use super::traits::Pick;
use super::{key, Callee, RecvAdj, Res};
use crate::builtins::{self, Builtin, Method, On, P};
use crate::diag::DResult;
use crate::resolve::{Ctor, FnId, FnParent, Recv};
use crate::span::Spanned;
use crate::ty::{FloatTy, IntTy, LangTrait, TraitKind, Ty};
use proc_macro2::Span;
use syn::Expr;

impl<'p, 'a> Cx<'p, 'a> {
    pub fn args(&mut self, args: &[&Expr], params: &[Ty], span: Span, what: &str) -> DResult<()> {
        if args.len() != params.len() {
            return Err(self.err(
                span,
                "wrong-argument-count",
                format!(
                    "{what} takes {} argument(s) but {} were supplied",
                    params.len(),
                    args.len()
                ),
            ));
        }
        for (a, p) in args.iter().zip(params) {
            let t = match a {
                Expr::Closure(c) => {
                    let t = self.closure(a, c, Some(p))?;
                    self.record(a, t)
                }
                _ => self.expr(a)?,
            };
            self.coerce(a, &t, p, a.span())?;
            self.check_fn_hint(p, a.span())?;
        }
        Ok(())
    }

    /// Instantiates function `f`'s signature: `parent` arguments (impl/trait) followed by
    /// its own (given or fresh).
    pub(super) fn instantiate(
        &mut self,
        f: FnId,
        parent: Vec<Ty>,
        own: Option<Vec<Ty>>,
        span: Span,
    ) -> DResult<(Vec<Ty>, Vec<Ty>, Ty)> {
        let fd = &self.p.fns[f];
        let n_own = fd.generics.len() - fd.generics.parent;
        let own = match own {
            Some(o) if o.len() == n_own => o,
            Some(o) => {
                return Err(self.err(
                    span,
                    "wrong-generic-count",
                    format!(
                        "function `{}` takes {n_own} generic argument(s) but {} were supplied",
                        fd.name,
                        o.len()
                    ),
                ))
            }
            None => (0..n_own).map(|_| self.fresh(VarKind::Any)).collect(),
        };
        let mut substs = parent;
        substs.extend(own);
        self.fn_bound_hints(f, &substs, span)?;
        let fd = &self.p.fns[f];
        let params: Vec<Ty> = fd.params.iter().map(|t| t.subst(&substs)).collect();
        let params = params
            .iter()
            .map(|t| self.norm(t, span))
            .collect::<DResult<Vec<_>>>()?;
        let ret = fd.ret.subst(&substs);
        let ret = self.norm(&ret, span)?;
        Ok((substs, params, ret))
    }

    /// Calls user function `f` with `args` (receiver first for UFCS/method calls).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn call_fn(
        &mut self,
        e: &Expr,
        f: FnId,
        parent: Vec<Ty>,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
        span: Span,
        recv: RecvAdj,
    ) -> DResult<Ty> {
        let (substs, params, ret) = self.instantiate(f, parent, own, span)?;
        let what = format!("function `{}`", self.p.fns[f].name);
        self.args(args, &params, span, &what)?;
        let ret = self.norm(&ret, span)?;
        self.body.callees.insert(
            key(e),
            Callee::Fn {
                func: f,
                substs,
                recv,
            },
        );
        Ok(ret)
    }

    pub fn call(&mut self, e: &Expr, c: &syn::ExprCall) -> DResult<Ty> {
        let Expr::Path(fp) = &*c.func else {
            return self.closure_call(e, c);
        };
        if fp.qself.is_none()
            && fp
                .path
                .get_ident()
                .is_some_and(|i| self.lookup_local(&i.to_string()).is_some())
        {
            return self.closure_call(e, c);
        }
        let args: Vec<&Expr> = c.args.iter().collect();
        let span = c.span();
        match self.value_path(&fp.path, fp.qself.as_ref())? {
            ValuePath::Fn(f, own) => {
                let parent = match self.p.fns[f].parent {
                    FnParent::Free => Vec::new(),
                    _ => {
                        return Err(self.err(
                            c.func.span(),
                            "unresolved-path",
                            "not a free function",
                        ))
                    }
                };
                self.call_fn(e, f, parent, own, &args, span, RecvAdj::default())
            }
            ValuePath::Ctor(a, v, targs) => {
                let vd = &self.p.adts[a].variants[v];
                if vd.ctor != Ctor::Tuple {
                    return Err(self.err(
                        c.func.span(),
                        "not-a-function",
                        format!("`{}` is not a tuple struct or tuple variant", vd.name),
                    ));
                }
                let targs = self.adt_args(a, targs, span)?;
                let ftys: Vec<Ty> = self.p.adts[a].variants[v]
                    .fields
                    .iter()
                    .map(|f| f.ty.subst(&targs))
                    .collect();
                let ftys = ftys
                    .iter()
                    .map(|t| self.norm(t, span))
                    .collect::<DResult<Vec<_>>>()?;
                let what = format!("`{}`", self.p.adts[a].variants[v].name);
                self.args(&args, &ftys, span, &what)?;
                self.body
                    .callees
                    .insert(key(e), Callee::Ctor { adt: a, variant: v });
                Ok(Ty::Adt(a, targs))
            }
            ValuePath::TypeAssoc(t, name, own) => {
                let t = self.shallow(&t);
                let t = match t {
                    Ty::Var(v) if self.vars[v as usize].0 == VarKind::Float => {
                        Ty::Float(FloatTy::F64)
                    }
                    Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int => Ty::Int(IntTy::I32),
                    t => t,
                };
                match self.assoc_fn(&t, &name, c.func.span())? {
                    Some(Pick::Fn(f, parent)) => {
                        self.call_fn(e, f, parent, own, &args, span, RecvAdj::default())
                    }
                    Some(Pick::Builtin(m)) => self.builtin_call(e, m, &t, &args, span, false),
                    Some(Pick::Derived(tr, m)) => {
                        self.derived_call(e, tr, m, &t, &args, span, RecvAdj::default())
                    }
                    None => Err(self.err(
                        c.func.span(),
                        "unresolved-path",
                        format!(
                            "no function or associated item named `{name}` found for `{}`",
                            self.show(&t)
                        ),
                    )),
                }
            }
            ValuePath::TraitItem(k, targs, self_t, name, own) => {
                self.trait_call(e, k, targs, self_t, &name, own, &args, span)
            }
            ValuePath::StdFn(m, f, own) => self.std_call(e, m, f, own, &args, span),
            ValuePath::Global(_) | ValuePath::FloatConst(..) => Err(self.err(
                c.func.span(),
                "unsupported-call",
                "only calls of named functions and closures are supported (no function pointers)",
            )),
        }
    }

    /// `Trait::item(args)` / `<T as Trait>::item(args)`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn trait_call(
        &mut self,
        e: &Expr,
        k: TraitKind,
        targs: Vec<Ty>,
        self_t: Option<Ty>,
        name: &str,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
        span: Span,
    ) -> DResult<Ty> {
        // Without `<T as ..>`, `Self` comes from the receiver argument or from inference.
        let st = match self_t {
            Some(t) => t,
            None => {
                let has_recv = match k {
                    TraitKind::User(t) => self.p.traits[t]
                        .methods
                        .iter()
                        .find(|(n, _)| n == name)
                        .is_some_and(|(_, f)| self.p.fns[*f].receiver.is_some()),
                    TraitKind::Lang(l) => !matches!(l, LangTrait::Default),
                };
                if has_recv && !args.is_empty() {
                    let t0 = self.expr(args[0])?;
                    let (inner, _) = self.autoderef(&t0);
                    let recv_kind = match k {
                        TraitKind::User(t) => self.p.traits[t]
                            .methods
                            .iter()
                            .find(|(n, _)| n == name)
                            .and_then(|(_, f)| self.p.fns[*f].receiver),
                        TraitKind::Lang(_) => None,
                    };
                    match recv_kind {
                        Some(Recv::Value) => t0,
                        _ => {
                            if matches!(self.shallow(&t0), Ty::Ref(..)) {
                                inner
                            } else {
                                t0
                            }
                        }
                    }
                } else {
                    self.fresh(VarKind::Any)
                }
            }
        };
        if !self.has_unknown(&st) {
            let st = self.deep_keep(&st);
            if let Some(pick) = self.trait_item_fn(k, &targs, &st, name, span)? {
                return match pick {
                    Pick::Fn(f, parent) => {
                        self.call_fn(e, f, parent, own, args, span, RecvAdj::default())
                    }
                    Pick::Builtin(m) => self.builtin_call(e, m, &st, args, span, false),
                    Pick::Derived(tr, m) => {
                        self.derived_call(e, tr, m, &st, args, span, RecvAdj::default())
                    }
                };
            }
            return Err(self.err(
                span,
                "missing-trait-impl",
                format!(
                    "the trait `{}` is not implemented for `{}` (no `{name}`)",
                    self.p.trait_name(k),
                    self.show(&st)
                ),
            ));
        }
        // Deferred: instantiate the trait's declaration with `Self` unknown.
        match k {
            TraitKind::User(t) => {
                let Some((_, f)) = self.p.traits[t]
                    .methods
                    .iter()
                    .find(|(n, _)| n == name)
                    .cloned()
                else {
                    return Err(self.err(
                        span,
                        "unresolved-path",
                        format!("no function `{name}` in trait `{}`", self.p.traits[t].name),
                    ));
                };
                let targs: Vec<Ty> = if targs.is_empty() {
                    (1..self.p.traits[t].generics.len())
                        .map(|_| self.fresh(VarKind::Any))
                        .collect()
                } else {
                    targs
                };
                let mut parent = vec![st.clone()];
                parent.extend(targs.iter().cloned());
                let (substs, params, ret) = self.instantiate(f, parent, own, span)?;
                let what = format!("function `{}`", self.p.fns[f].name);
                self.args(args, &params, span, &what)?;
                let np = self.p.fns[f].generics.parent;
                self.deferred.push(Deferred {
                    key: key(e),
                    tr: k,
                    name: name.to_string(),
                    self_ty: st,
                    trait_args: targs,
                    own: substs[np..].to_vec(),
                    span,
                    is_call: true,
                });
                Ok(ret)
            }
            TraitKind::Lang(LangTrait::Default) if name == "default" => {
                self.args(args, &[], span, "`Default::default`")?;
                self.deferred.push(Deferred {
                    key: key(e),
                    tr: k,
                    name: name.to_string(),
                    self_ty: st.clone(),
                    trait_args: Vec::new(),
                    own: Vec::new(),
                    span,
                    is_call: true,
                });
                Ok(st)
            }
            TraitKind::Lang(l) => Err(self.err(
                span,
                "type-annotation-needed",
                format!("type annotations needed for `{}::{name}`", l.name()),
            )),
        }
    }

    /// Resolves a deferred trait item now that `Self` is known.
    pub fn resolve_deferred(
        &mut self,
        d: &Deferred,
        st: Ty,
        targs: Vec<Ty>,
        own: Vec<Ty>,
    ) -> DResult<()> {
        if !d.is_call {
            match self.trait_const(d.tr, &targs, &st, &d.name, d.span)? {
                Some((g, substs)) => {
                    self.body.res.insert(d.key, Res::Global(g, substs));
                    return Ok(());
                }
                None => {
                    return Err(self.err(
                        d.span,
                        "missing-trait-impl",
                        format!(
                            "the trait `{}` is not implemented for `{}`",
                            self.p.trait_name(d.tr),
                            self.show(&st)
                        ),
                    ))
                }
            }
        }
        match self.trait_item_fn(d.tr, &targs, &st, &d.name, d.span)? {
            Some(Pick::Fn(f, mut parent)) => {
                for p in parent.iter_mut() {
                    *p = self.deep(p);
                }
                parent.extend(own);
                self.body.callees.insert(
                    d.key,
                    Callee::Fn {
                        func: f,
                        substs: parent,
                        recv: RecvAdj::default(),
                    },
                );
                Ok(())
            }
            Some(Pick::Derived(tr, m)) => {
                self.body.callees.insert(
                    d.key,
                    Callee::Derived {
                        tr,
                        method: m,
                        ty: st,
                        recv: RecvAdj::default(),
                    },
                );
                Ok(())
            }
            Some(Pick::Builtin(m)) => {
                self.body.callees.insert(
                    d.key,
                    Callee::Builtin {
                        b: m.b,
                        recv: RecvAdj::default(),
                    },
                );
                Ok(())
            }
            None => Err(self.err(
                d.span,
                "missing-trait-impl",
                format!(
                    "the trait `{}` is not implemented for `{}`",
                    self.p.trait_name(d.tr),
                    self.show(&st)
                ),
            )),
        }
    }

    pub(super) fn std_call(
        &mut self,
        e: &Expr,
        m: &str,
        f: &str,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
        span: Span,
    ) -> DResult<Ty> {
        let b = match (m, f) {
            ("ptr", "read") => Builtin::PtrRead,
            ("ptr", "read_volatile") => Builtin::PtrReadVolatile,
            ("ptr", "write") => Builtin::PtrWrite,
            ("ptr", "write_volatile") => Builtin::PtrWriteVolatile,
            ("ptr", "null" | "null_mut") => Builtin::StdNull,
            ("mem", "swap") => Builtin::MemSwap,
            ("mem", "replace") => Builtin::MemReplace,
            ("mem", "take") => Builtin::MemTake,
            ("cmp", "min") => Builtin::CmpMin,
            _ => Builtin::CmpMax,
        };
        let el = match own {
            Some(mut o) if o.len() == 1 => o.remove(0),
            Some(_) => {
                return Err(self.err(
                    span,
                    "wrong-generic-count",
                    format!("`{m}::{f}` takes one generic argument"),
                ))
            }
            None => self.fresh(VarKind::Any),
        };
        let name = format!("`{m}::{f}`");
        let ret = match b {
            Builtin::PtrRead | Builtin::PtrReadVolatile => {
                self.args(args, &[Ty::Ptr(false, Box::new(el.clone()))], span, &name)?;
                el
            }
            Builtin::PtrWrite | Builtin::PtrWriteVolatile => {
                self.args(
                    args,
                    &[Ty::Ptr(true, Box::new(el.clone())), el],
                    span,
                    &name,
                )?;
                Ty::Unit
            }
            Builtin::StdNull => {
                self.args(args, &[], span, &name)?;
                Ty::Ptr(f == "null_mut", Box::new(el))
            }
            Builtin::MemSwap => {
                let r = Ty::Ref(true, Box::new(el));
                self.args(args, &[r.clone(), r], span, &name)?;
                Ty::Unit
            }
            Builtin::MemReplace => {
                self.args(
                    args,
                    &[Ty::Ref(true, Box::new(el.clone())), el.clone()],
                    span,
                    &name,
                )?;
                el
            }
            Builtin::MemTake => {
                self.args(args, &[Ty::Ref(true, Box::new(el.clone()))], span, &name)?;
                el
            }
            _ => {
                self.args(args, &[el.clone(), el.clone()], span, &name)?;
                let t = self.shallow(&el);
                if !(t.is_int()
                    || matches!(t, Ty::Bool | Ty::Char)
                    || matches!(t, Ty::Var(v) if self.vars[v as usize].0 == VarKind::Int))
                {
                    return Err(self.err(span, "unsupported-call", format!("{name} is supported on integers, `bool` and `char` (found `{}`; floats are not `Ord`)", self.show(&t))));
                }
                el
            }
        };
        self.body.callees.insert(
            key(e),
            Callee::Builtin {
                b,
                recv: RecvAdj::default(),
            },
        );
        Ok(ret)
    }

    /// A catalogue builtin called by path (`f32::from_bits(b)`, `f32::sqrt(x)`) or as a
    /// method (`recv` given: the receiver is the first argument, already checked).
    pub(super) fn builtin_call(
        &mut self,
        e: &Expr,
        m: &'static Method,
        s: &Ty,
        args: &[&Expr],
        span: Span,
        _method: bool,
    ) -> DResult<Ty> {
        // By path, a method's receiver is the first argument.
        let is_assoc = builtins::ASSOC_FNS.iter().any(|x| std::ptr::eq(x, m));
        let mut params: Vec<Ty> = Vec::new();
        if !is_assoc {
            let recv_ty = if matches!(m.on, On::Seq | On::SeqMut) {
                Ty::Ref(m.on == On::SeqMut, Box::new(s.clone()))
            } else {
                s.clone()
            };
            params.push(recv_ty);
        }
        for p in m.params {
            params.push(self.param_ty(*p, s, span)?);
        }
        let what = format!("`{}::{}`", self.show(s), m.name);
        self.args(args, &params, span, &what)?;
        let b = self.libm_or(m, s, span)?;
        match b {
            Ok(b) => {
                self.body.callees.insert(
                    key(e),
                    Callee::Builtin {
                        b,
                        recv: RecvAdj::default(),
                    },
                );
            }
            Err(f) => {
                self.body.callees.insert(
                    key(e),
                    Callee::Fn {
                        func: f,
                        substs: Vec::new(),
                        recv: RecvAdj::default(),
                    },
                );
            }
        }
        self.param_ty(m.ret, s, span)
    }

    /// A libm builtin becomes a call of the prelude's function (`Err(fn)`).
    pub(super) fn libm_or(&self, m: &Method, s: &Ty, span: Span) -> DResult<Result<Builtin, FnId>> {
        if let Builtin::Libm(f32n, f64n) = m.b {
            let name = if *s == Ty::Float(FloatTy::F64) {
                f64n
            } else {
                f32n
            };
            return match self.p.libm_fn(name) {
                Some(f) => Ok(Err(f)),
                None if self.p.lang.libm.is_none() => Err(self.err(
                    span,
                    "unsupported-float-method",
                    format!(
                        "`{}::{}` needs the prelude crate `trax` (its math library, `trax::libm::{name}`)",
                        self.p.ty_str(s),
                        m.name
                    ),
                )),
                None => Err(self.err(
                    span,
                    "unsupported-float-method",
                    format!(
                        "`{}::{}` is not supported in TRaX-Rust: the prelude's math library has no `trax::libm::{name}`",
                        self.p.ty_str(s),
                        m.name
                    ),
                )),
            };
        }
        Ok(Ok(m.b))
    }

    /// The type of a catalogue signature entry for receiver type `s`.
    pub(super) fn param_ty(&mut self, p: P, s: &Ty, span: Span) -> DResult<Ty> {
        let opt = |cx: &Self, t: Ty| -> DResult<Ty> {
            match cx.p.lang.option {
                Some(o) => Ok(Ty::Adt(o, vec![t])),
                None => Err(cx.err(
                    span,
                    "missing-lang-item",
                    "this method returns an `Option`, which needs the prelude crate `trax`",
                )),
            }
        };
        let ordering = |cx: &Self| -> DResult<Ty> {
            match cx.p.lang.ordering {
                Some(o) => Ok(Ty::Adt(o, Vec::new())),
                None => Err(cx.err(
                    span,
                    "missing-lang-item",
                    "this method returns an `Ordering`, which needs the prelude crate `trax`",
                )),
            }
        };
        Ok(match p {
            P::S => s.clone(),
            P::RefS => Ty::Ref(false, Box::new(s.clone())),
            P::Unit => Ty::Unit,
            P::Bool => Ty::Bool,
            P::U32 => Ty::Int(IntTy::U32),
            P::I32 => Ty::Int(IntTy::I32),
            P::Usize => Ty::Int(IntTy::Usize),
            P::Isize => Ty::Int(IntTy::Isize),
            P::Unsigned => match s {
                Ty::Int(i) => Ty::Int(builtins::unsigned_of(*i)),
                _ => s.clone(),
            },
            P::Bits => Ty::Int(if *s == Ty::Float(FloatTy::F64) {
                IntTy::U64
            } else {
                IntTy::U32
            }),
            P::Lane | P::Elem => builtins::elem_of(s).unwrap_or(Ty::Unit),
            P::F32x4 => Ty::Simd(crate::ty::SimdTy::F32x4),
            P::I32x4 => Ty::Simd(crate::ty::SimdTy::I32x4),
            P::RefElem => Ty::Ref(false, Box::new(builtins::elem_of(s).unwrap_or(Ty::Unit))),
            P::OptRefElem => {
                let r = Ty::Ref(false, Box::new(builtins::elem_of(s).unwrap_or(Ty::Unit)));
                opt(self, r)?
            }
            P::PairS => Ty::Tuple(vec![s.clone(), s.clone()]),
            P::Ordering => ordering(self)?,
            P::OptOrdering => {
                let o = ordering(self)?;
                opt(self, o)?
            }
            P::SliceRef => Ty::Ref(
                false,
                Box::new(Ty::Slice(Box::new(
                    builtins::elem_of(s).unwrap_or(Ty::Unit),
                ))),
            ),
        })
    }

    /// A derived method called by path (`Foo::default()`, `Clone::clone(&x)`) or as a
    /// method.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn derived_call(
        &mut self,
        e: &Expr,
        tr: LangTrait,
        m: &'static str,
        s: &Ty,
        args: &[&Expr],
        span: Span,
        recv: RecvAdj,
    ) -> DResult<Ty> {
        let (params, ret) = match m {
            "default" => (Vec::new(), s.clone()),
            "clone" => (vec![Ty::Ref(false, Box::new(s.clone()))], s.clone()),
            "eq" | "ne" => (
                vec![
                    Ty::Ref(false, Box::new(s.clone())),
                    Ty::Ref(false, Box::new(s.clone())),
                ],
                Ty::Bool,
            ),
            _ => {
                return Err(self.err(
                    span,
                    "unsupported-call",
                    format!("`{m}` cannot be called here"),
                ))
            }
        };
        let params =
            if recv != RecvAdj::default() || !args.is_empty() && params.len() == args.len() + 1 {
                params[1..].to_vec()
            } else {
                params
            };
        self.args(args, &params, span, &format!("`{m}`"))?;
        self.body.callees.insert(
            key(e),
            Callee::Derived {
                tr,
                method: m,
                ty: s.clone(),
                recv,
            },
        );
        Ok(ret)
    }

    // ---------------------------------------------------------------- method calls

    pub fn method_call(&mut self, e: &Expr, m: &syn::ExprMethodCall) -> DResult<Ty> {
        let own = match &m.turbofish {
            Some(t) => {
                let args =
                    syn::PathArguments::AngleBracketed(syn::AngleBracketedGenericArguments {
                        colon2_token: None,
                        lt_token: t.lt_token,
                        args: t.args.clone(),
                        gt_token: t.gt_token,
                    });
                self.seg_args(&args)?
            }
            None => None,
        };
        let name = m.method.to_string();
        let rt = self.expr(&m.receiver)?;
        let args: Vec<&Expr> = m.args.iter().collect();
        let span = m.method.span();
        let mut t = self.shallow(&rt);
        let mut derefs = 0;
        loop {
            if let Ty::Var(v) = t {
                let d = match self.vars[v as usize].0 {
                    VarKind::Float => Ty::Float(FloatTy::F64),
                    VarKind::Int => Ty::Int(IntTy::I32),
                    VarKind::Any => {
                        return Err(self.err(
                            m.receiver.span(),
                            "type-annotation-needed",
                            "type annotations needed for the receiver",
                        ))
                    }
                };
                self.try_unify(&t, &d);
                t = d;
            }
            if let Some(pick) = self.method_pick(&t, &name, span)? {
                return self.method_with(e, m, pick, &t, derefs, own, &args);
            }
            match &t {
                Ty::Ref(_, inner) => {
                    t = self.shallow(inner);
                    derefs += 1;
                }
                _ => break,
            }
        }
        if matches!(
            name.as_str(),
            "iter"
                | "iter_mut"
                | "into_iter"
                | "enumerate"
                | "zip"
                | "rev"
                | "step_by"
                | "map"
                | "filter"
                | "sum"
                | "fold"
                | "collect"
                | "skip"
                | "take"
                | "chain"
                | "windows"
                | "chunks"
        ) {
            return Err(self.err(
                m.method.span(),
                "unsupported-iterator",
                format!("`.{name}()` is only supported as the iterator of a `for` loop (iterators are not values in TRaX-Rust)"),
            ));
        }
        let t0 = self.deep_keep(&rt);
        if let Some(b) = builtins::method_anywhere(&name) {
            let what = match b.on {
                On::SInt => "signed integers",
                On::UInt => "unsigned integers",
                On::PtrMut => "`*mut` pointers",
                On::SeqMut => "mutable arrays and slices",
                _ => "",
            };
            if !what.is_empty() && builtins::method(&self.autoderef(&t0).0, &name).is_none() {
                let (base, _) = self.autoderef(&t0);
                if matches!(
                    (b.on, &base),
                    (On::SInt | On::UInt, Ty::Int(_)) | (On::PtrMut, Ty::Ptr(..))
                ) {
                    return Err(self.err(
                        span,
                        "unknown-method",
                        format!(
                            "no method `{name}` on `{}` (it is defined on {what})",
                            self.show(&base)
                        ),
                    ));
                }
            }
        }
        let mut d = self.err(
            span,
            "unknown-method",
            format!("no method `{name}` on `{}`", self.show(&t0)),
        );
        if matches!(self.autoderef(&t0).0, Ty::Array(..) | Ty::Slice(_)) {
            // The std slice methods TRaX-Rust lacks: say what it has and what to write.
            let have: Vec<String> = builtins::METHODS
                .iter()
                .filter(|m| matches!(m.on, On::Seq | On::SeqMut))
                .map(|m| format!("`{}`", m.name))
                .collect();
            d = d.with_note(format!(
                "arrays and slices have {} in TRaX-Rust; `for` loops iterate over them with `iter`, `iter_mut`, `enumerate`, `zip`, `rev`, `step_by`, `skip`, `take`, `copied`",
                have.join(", ")
            ));
            if name.starts_with("sort") {
                d = d.with_help(
                    "sorting is not built in: write it as a loop, e.g. an insertion sort (docs/LANGUAGE.md, \"Arrays and slices\")",
                );
            }
        }
        Err(d)
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn method_with(
        &mut self,
        e: &Expr,
        m: &syn::ExprMethodCall,
        pick: Pick,
        t: &Ty,
        derefs: u32,
        own: Option<Vec<Ty>>,
        args: &[&Expr],
    ) -> DResult<Ty> {
        let span = m.method.span();
        match pick {
            Pick::Fn(f, parent) => {
                let fd = &self.p.fns[f];
                let Some(recv) = fd.receiver else {
                    return Err(self.err(
                        span,
                        "not-a-method",
                        format!(
                            "`{}` is an associated function, not a method; call it as `{}(...)`",
                            fd.name, fd.name
                        ),
                    ));
                };
                let autoref = match recv {
                    Recv::Value => None,
                    Recv::Ref => Some(false),
                    Recv::RefMut => Some(true),
                };
                if recv == Recv::RefMut {
                    self.check_recv_mut(&m.receiver, derefs)?;
                }
                let (substs, params, ret) = self.instantiate(f, parent, own, span)?;
                // The receiver's type matched the impl's `Self`.
                let self_param = params[0].clone();
                let recv_ty = match autoref {
                    Some(mm) => Ty::Ref(mm, Box::new(t.clone())),
                    None => t.clone(),
                };
                self.unify(&recv_ty, &self_param, m.receiver.span())?;
                let what = format!("method `{}`", self.p.fns[f].name);
                self.args(args, &params[1..], m.span(), &what)?;
                let ret = self.norm(&ret, span)?;
                self.body.callees.insert(
                    key(e),
                    Callee::Fn {
                        func: f,
                        substs,
                        recv: RecvAdj { derefs, autoref },
                    },
                );
                Ok(ret)
            }
            Pick::Builtin(b) => {
                let by_ref = matches!(b.on, On::Seq | On::SeqMut);
                if b.on == On::SeqMut {
                    self.check_recv_mut(&m.receiver, derefs)?;
                }
                let mut params = Vec::new();
                for p in b.params {
                    params.push(self.param_ty(*p, t, span)?);
                }
                let what = format!("method `{}`", b.name);
                self.args(args, &params, m.span(), &what)?;
                let bb = self.libm_or(b, t, span)?;
                let recv = RecvAdj {
                    derefs,
                    autoref: by_ref.then_some(b.on == On::SeqMut),
                };
                match bb {
                    Ok(bi) => {
                        self.body
                            .callees
                            .insert(key(e), Callee::Builtin { b: bi, recv });
                    }
                    Err(f) => {
                        self.body.callees.insert(
                            key(e),
                            Callee::Fn {
                                func: f,
                                substs: Vec::new(),
                                recv,
                            },
                        );
                    }
                }
                self.param_ty(b.ret, t, span)
            }
            Pick::Derived(tr, name) => {
                let recv = RecvAdj {
                    derefs,
                    autoref: Some(false),
                };
                self.derived_call(e, tr, name, t, args, m.span(), recv)
            }
        }
    }

    pub(super) fn check_recv_mut(&mut self, recv: &Expr, derefs: u32) -> DResult<()> {
        if derefs == 0 {
            return self.check_place(recv, true);
        }
        let t = self.body.tys.get(&key(recv)).cloned().unwrap_or(Ty::Unit);
        let mut t = self.shallow(&t);
        let mut ok = true;
        for _ in 0..derefs {
            match t {
                Ty::Ref(m, inner) => {
                    ok &= m;
                    t = self.shallow(&inner);
                }
                _ => break,
            }
        }
        if ok {
            Ok(())
        } else {
            Err(self.err(
                recv.span(),
                "immutable-borrow",
                "cannot borrow data behind a `&` reference as mutable",
            ))
        }
    }
}
