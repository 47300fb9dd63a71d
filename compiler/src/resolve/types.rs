//! Syntactic types to [`Ty`]; impl matching and associated-type normalisation.

use super::{ImplId, ModId, Ns, PathRes, Program};
use crate::diag::{DResult, Diagnostic, FileId};
use crate::span::Spanned;
use crate::ty::{AdtId, TraitId, TraitKind, TraitRef, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::Type;

/// What `Self` and generic parameter names mean where a type is written.
#[derive(Clone, Copy, Default)]
pub struct TyScope<'s> {
    /// `Self`.
    pub self_ty: Option<&'s Ty>,
    /// Generic parameter names (`Param(i)` is `params[i]`).
    pub params: &'s [String],
    /// Associated types of the trait impl being resolved (`Self::Output`).
    pub impl_types: Option<&'s HashMap<String, Ty>>,
    /// The trait being defined (`Self::Item` is a projection on `Self`).
    pub in_trait: Option<TraitId>,
}

impl<'s> TyScope<'s> {
    /// A scope with only generic parameter names.
    pub fn params(params: &'s [String]) -> TyScope<'s> {
        TyScope {
            params,
            ..TyScope::default()
        }
    }
}

/// Generic type arguments and associated-type bindings of a path segment.
pub type TypeArgs = (Vec<Ty>, Vec<(String, Ty)>);

/// Heap types of `std` that TRaX-Rust does not have.
const HEAP_TYPES: &[&str] = &[
    "Vec", "String", "Box", "Rc", "Arc", "HashMap", "HashSet", "BTreeMap", "VecDeque",
];

impl<'a> Program<'a> {
    /// The heap type a value path goes through (`String` of `String::from`, `Vec` of
    /// `Vec::new`) when the kernel defines no type of that name.
    pub(super) fn heap_type_in(&self, module: ModId, segs: &[String]) -> Option<&'static str> {
        let (_, prefix) = segs.split_last()?;
        prefix.iter().enumerate().find_map(|(i, s)| {
            let h = HEAP_TYPES.iter().copied().find(|h| h == s)?;
            self.resolve_from(module, &segs[..=i], Ns::Type, 0)
                .is_none()
                .then_some(h)
        })
    }

    /// The error for a heap type (`Vec`, `String`, ...) named at `span`, with what to use
    /// instead.
    pub(super) fn heap_type_error(&self, file: FileId, span: Span, h: &str) -> Diagnostic {
        let instead = match h {
            "String" => "text is `&'static str` in TRaX-Rust (string literals); `print!`/`println!` format without allocating",
            "Box" | "Rc" | "Arc" => "own values directly, or borrow them (`&T`, `&mut T`)",
            _ => "use fixed-size arrays `[T; N]` and slices `&[T]`",
        };
        self.err(
            file,
            span,
            "unsupported-heap-type",
            format!("`{h}` is not supported in TRaX-Rust (heap types are not available)"),
        )
        .with_note(instead)
    }

    /// Resolves a syntactic type in `module`.
    pub fn resolve_type(
        &self,
        module: ModId,
        file: FileId,
        ty: &Type,
        scope: &TyScope,
    ) -> DResult<Ty> {
        self.resolve_type_depth(module, file, ty, scope, 0)
    }

    fn resolve_type_depth(
        &self,
        module: ModId,
        file: FileId,
        ty: &Type,
        scope: &TyScope,
        depth: u32,
    ) -> DResult<Ty> {
        if depth > 32 {
            return Err(self.err(
                file,
                ty.span(),
                "recursive-type-alias",
                "type alias expands to itself",
            ));
        }
        let sub = |t: &Type| self.resolve_type_depth(module, file, t, scope, depth + 1);
        match ty {
            Type::Paren(p) => sub(&p.elem),
            Type::Group(g) => sub(&g.elem),
            Type::Never(_) => Ok(Ty::Never),
            Type::Tuple(t) if t.elems.is_empty() => Ok(Ty::Unit),
            Type::Tuple(t) => Ok(Ty::Tuple(
                t.elems.iter().map(sub).collect::<DResult<Vec<_>>>()?,
            )),
            Type::Array(a) => {
                let elem = sub(&a.elem)?;
                let n = self.eval_len(module, file, &a.len)?;
                Ok(Ty::Array(Box::new(elem), n))
            }
            Type::Reference(r) => {
                if let Type::Path(tp) = &*r.elem {
                    if tp.path.is_ident("str") {
                        if r.mutability.is_some() {
                            return Err(self.err(
                                file,
                                r.span(),
                                "unsupported-str",
                                "`&mut str` is not supported in TRaX-Rust",
                            ));
                        }
                        return Ok(Ty::Str);
                    }
                }
                let inner = match &*r.elem {
                    Type::Slice(s) => Ty::Slice(Box::new(sub(&s.elem)?)),
                    other => sub(other)?,
                };
                Ok(Ty::Ref(r.mutability.is_some(), Box::new(inner)))
            }
            Type::Ptr(p) => {
                let inner = match &*p.elem {
                    Type::Slice(s) => Ty::Slice(Box::new(sub(&s.elem)?)),
                    other => sub(other)?,
                };
                Ok(Ty::Ptr(
                    matches!(p.mutability, syn::PointerMutability::Mut(_)),
                    Box::new(inner),
                ))
            }
            Type::Path(tp) => self.resolve_type_path(module, file, tp, scope, depth),
            Type::Slice(s) => Err(self.err(
                file,
                s.span(),
                "unsupported-slice",
                "slices `[T]` are only supported behind a reference (`&[T]`, `&mut [T]`)",
            )),
            Type::TraitObject(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-trait-object",
                "trait objects (`dyn Trait`) are not supported in TRaX-Rust; use generics",
            )),
            Type::ImplTrait(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-impl-trait",
                "`impl Trait` types are not supported in TRaX-Rust; use a generic parameter",
            )),
            Type::FnPtr(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-fn-pointer",
                "function pointers are not supported in TRaX-Rust",
            )),
            Type::Infer(_) => Ok(Ty::Infer),
            other => Err(self.err(
                file,
                other.span(),
                "unsupported-type",
                "this kind of type is not supported in TRaX-Rust",
            )),
        }
    }

    /// Generic type arguments of a path segment (lifetimes are ignored).
    pub fn type_args(
        &self,
        module: ModId,
        file: FileId,
        args: &syn::PathArguments,
        scope: &TyScope,
    ) -> DResult<TypeArgs> {
        let mut tys = Vec::new();
        let mut bindings = Vec::new();
        match args {
            syn::PathArguments::None => {}
            syn::PathArguments::AngleBracketed(a) => {
                for g in &a.args {
                    match g {
                        syn::GenericArgument::Lifetime(_) => {}
                        syn::GenericArgument::Type(t) => {
                            tys.push(self.resolve_type(module, file, t, scope)?)
                        }
                        syn::GenericArgument::AssocType(at) => bindings.push((
                            at.ident.to_string(),
                            self.resolve_type(module, file, &at.ty, scope)?,
                        )),
                        other => return Err(self.err(
                            file,
                            other.span(),
                            "unsupported-generics",
                            "only type arguments are supported in TRaX-Rust (no const generics)",
                        )),
                    }
                }
            }
            // `Fn(A, B) -> C`: the arguments as a tuple and the `Output` binding.
            syn::PathArguments::Parenthesized(p) => {
                let mut ins = Vec::new();
                for a in &p.inputs {
                    ins.push(self.resolve_type(module, file, &a.ty, scope)?);
                }
                tys.push(if ins.is_empty() {
                    Ty::Unit
                } else {
                    Ty::Tuple(ins)
                });
                let out = match &p.output {
                    syn::ReturnType::Default => Ty::Unit,
                    syn::ReturnType::Type(_, t) => self.resolve_type(module, file, t, scope)?,
                };
                bindings.push(("Output".to_string(), out));
            }
        }
        Ok((tys, bindings))
    }

    fn resolve_type_path(
        &self,
        module: ModId,
        file: FileId,
        tp: &syn::TypePath,
        scope: &TyScope,
        depth: u32,
    ) -> DResult<Ty> {
        let segs = super::path_segs(&tp.path);
        let span = tp.span();
        if let Some(q) = &tp.qself {
            // `<T as Trait>::Name`.
            let base = self.resolve_type_depth(module, file, &q.ty, scope, depth + 1)?;
            if q.position == 0 || q.position + 1 != segs.len() {
                return Err(self.err(
                    file,
                    span,
                    "unsupported-qualified-path",
                    "only `<T as Trait>::Name` qualified types are supported",
                ));
            }
            let trait_path = syn::Path {
                leading_colon: None,
                segments: tp.path.segments.iter().take(q.position).cloned().collect(),
            };
            let tr = self.resolve_trait_ref(module, file, &trait_path, scope, None)?;
            return Ok(Ty::Proj(
                Box::new(base),
                Some(Box::new(tr)),
                segs[segs.len() - 1].clone(),
            ));
        }
        let last = tp.path.segments.last().expect("paths are non-empty");
        // Generic parameters and `Self`.
        let first = &segs[0];
        let param = scope.params.iter().position(|p| p == first);
        if segs.len() == 1 {
            if let Some(i) = param {
                return Ok(Ty::Param(i as u32));
            }
            if first == "Self" {
                return scope.self_ty.cloned().ok_or_else(|| {
                    self.err(
                        file,
                        span,
                        "self-outside-impl",
                        "`Self` outside an impl block",
                    )
                });
            }
        }
        if segs.len() == 2 && (first == "Self" || param.is_some()) {
            let name = segs[1].clone();
            if first == "Self" {
                if let Some(t) = scope.impl_types.and_then(|m| m.get(&name)) {
                    return Ok(t.clone());
                }
                if let Some(tr) = scope.in_trait {
                    let n = self.traits[tr].generics.len();
                    let tref = TraitRef {
                        kind: TraitKind::User(tr),
                        args: (1..n as u32).map(Ty::Param).collect(),
                        bindings: Vec::new(),
                    };
                    return Ok(Ty::Proj(Box::new(Ty::Param(0)), Some(Box::new(tref)), name));
                }
                let st = scope.self_ty.cloned().ok_or_else(|| {
                    self.err(
                        file,
                        span,
                        "self-outside-impl",
                        "`Self` outside an impl block",
                    )
                })?;
                return Ok(Ty::Proj(Box::new(st), None, name));
            }
            return Ok(Ty::Proj(
                Box::new(Ty::Param(param.expect("checked") as u32)),
                None,
                name,
            ));
        }
        let resolved = self.resolve_from(module, &segs, Ns::Type, 0);
        let Some(res) = resolved else {
            let name = segs.join("::");
            if let Some(h) = HEAP_TYPES.iter().find(|h| **h == segs[segs.len() - 1]) {
                return Err(self.heap_type_error(file, span, h));
            }
            let hint = match segs.last().map(String::as_str) {
                Some("Option" | "Result") if self.lang.module.is_none() => {
                    " (`Option` and `Result` come from the prelude crate `trax`)"
                }
                _ => "",
            };
            return Err(self.err(
                file,
                span,
                "unknown-type",
                format!("unknown type `{name}`{hint}"),
            ));
        };
        let (args, _) = self.type_args(module, file, &last.arguments, scope)?;
        for s in tp.path.segments.iter().take(segs.len() - 1) {
            if !matches!(s.arguments, syn::PathArguments::None) {
                return Err(self.err(
                    file,
                    s.arguments.span(),
                    "unsupported-generics",
                    "generic arguments are only supported on the last segment of a type path",
                ));
            }
        }
        let no_args = |what: &str| -> DResult<()> {
            if args.is_empty() {
                Ok(())
            } else {
                Err(self.err(
                    file,
                    last.arguments.span(),
                    "wrong-generic-count",
                    format!("{what} takes no generic arguments"),
                ))
            }
        };
        match res {
            PathRes::Adt(a) => Ok(Ty::Adt(a, self.adt_args(file, span, a, args)?)),
            PathRes::Prim(t) => {
                no_args(&format!("`{}`", self.ty_str(&t)))?;
                Ok(t)
            }
            PathRes::Simd(s) => {
                no_args("a SIMD type")?;
                Ok(Ty::Simd(s))
            }
            PathRes::Alias(al) => {
                let ad = &self.aliases[al];
                if args.len() != ad.params.len() {
                    return Err(self.err(
                        file,
                        span,
                        "wrong-generic-count",
                        format!(
                            "type alias `{}` takes {} generic argument(s) but {} were supplied",
                            ad.name,
                            ad.params.len(),
                            args.len()
                        ),
                    ));
                }
                let inner = TyScope::params(&ad.params);
                let t = self.resolve_type_depth(ad.module, ad.file, ad.ty, &inner, depth + 1)?;
                Ok(t.subst(&args))
            }
            PathRes::Trait(t) => Err(self.err(
                file,
                span,
                "unsupported-trait-object",
                format!(
                    "expected a type, found trait `{}` (trait objects are not supported in TRaX-Rust)",
                    self.trait_name(t)
                ),
            )),
            _ => Err(self.err(
                file,
                span,
                "not-a-type",
                format!("`{}` is not a type", segs.join("::")),
            )),
        }
    }

    /// Checks the number of generic arguments of ADT `a`.
    pub fn adt_args(
        &self,
        file: FileId,
        span: proc_macro2::Span,
        a: AdtId,
        args: Vec<Ty>,
    ) -> DResult<Vec<Ty>> {
        let n = self.adts[a].generics.len();
        if args.len() != n {
            return Err(self.err(
                file,
                span,
                "wrong-generic-count",
                format!(
                    "`{}` takes {n} generic argument(s) but {} were supplied",
                    self.adts[a].name,
                    args.len()
                ),
            ));
        }
        Ok(args)
    }

    /// Resolves a trait path with its arguments (`Add<f32>`, `PartialEq`); `self_ty`
    /// fills a defaulted `Rhs = Self`.
    pub fn resolve_trait_ref(
        &self,
        module: ModId,
        file: FileId,
        path: &syn::Path,
        scope: &TyScope,
        self_ty: Option<&Ty>,
    ) -> DResult<TraitRef> {
        let segs = super::path_segs(path);
        let kind = match self.resolve_from(module, &segs, Ns::Type, 0) {
            Some(PathRes::Trait(k)) => k,
            Some(_) => {
                return Err(self.err(
                    file,
                    path.span(),
                    "not-a-trait",
                    format!("`{}` is not a trait", segs.join("::")),
                ))
            }
            None => {
                let name = segs.last().cloned().unwrap_or_default();
                let id = if matches!(
                    name.as_str(),
                    "Display"
                        | "Hash"
                        | "Iterator"
                        | "IntoIterator"
                        | "From"
                        | "Into"
                        | "Fn"
                        | "FnMut"
                        | "FnOnce"
                        | "Drop"
                        | "Send"
                        | "Sync"
                        | "AsRef"
                        | "Deref"
                        | "Sum"
                        | "Product"
                        | "ToString"
                        | "Write"
                ) {
                    "unsupported-trait"
                } else {
                    "unknown-trait"
                };
                return Err(self.err(
                    file,
                    path.span(),
                    id,
                    if id == "unsupported-trait" {
                        format!("the trait `{name}` is not supported in TRaX-Rust")
                    } else {
                        format!("cannot find trait `{}` in this scope", segs.join("::"))
                    },
                ));
            }
        };
        let last = path.segments.last().expect("non-empty");
        let (mut args, bindings) = self.type_args(module, file, &last.arguments, scope)?;
        match kind {
            TraitKind::Lang(l) => {
                if args.is_empty() && l.has_rhs() {
                    if let Some(st) = self_ty.or(scope.self_ty) {
                        args.push(st.clone());
                    }
                }
                if (l == crate::ty::LangTrait::Index || l == crate::ty::LangTrait::IndexMut)
                    && args.len() != 1
                {
                    return Err(self.err(
                        file,
                        path.span(),
                        "wrong-generic-count",
                        format!("`{}` takes one argument (the index type)", l.name()),
                    ));
                }
            }
            TraitKind::User(t) => {
                let want = self.traits[t].generics.len() - 1;
                if args.len() != want {
                    return Err(self.err(
                        file,
                        path.span(),
                        "wrong-generic-count",
                        format!(
                            "trait `{}` takes {want} generic argument(s) but {} were supplied",
                            self.traits[t].name,
                            args.len()
                        ),
                    ));
                }
            }
        }
        Ok(TraitRef {
            kind,
            args,
            bindings,
        })
    }

    /// Matches an impl's type pattern (mentioning its parameters) against `t`, filling
    /// `out`. Inference variables in `t` match anything.
    pub fn match_ty(&self, pat: &Ty, t: &Ty, out: &mut Vec<Option<Ty>>) -> bool {
        match (pat, t) {
            (Ty::Param(i), _) => {
                let i = *i as usize;
                if out.len() <= i {
                    out.resize(i + 1, None);
                }
                match &out[i] {
                    Some(prev) => prev == t || prev.has_vars() || t.has_vars(),
                    None => {
                        out[i] = Some(t.clone());
                        true
                    }
                }
            }
            (_, Ty::Var(_)) => true,
            (Ty::Adt(a, xs), Ty::Adt(b, ys)) => {
                a == b
                    && xs.len() == ys.len()
                    && xs.iter().zip(ys).all(|(x, y)| self.match_ty(x, y, out))
            }
            (Ty::Tuple(xs), Ty::Tuple(ys)) => {
                xs.len() == ys.len() && xs.iter().zip(ys).all(|(x, y)| self.match_ty(x, y, out))
            }
            (Ty::Array(x, n), Ty::Array(y, m)) => n == m && self.match_ty(x, y, out),
            (Ty::Slice(x), Ty::Slice(y)) => self.match_ty(x, y, out),
            (Ty::Ref(m1, x), Ty::Ref(m2, y)) | (Ty::Ptr(m1, x), Ty::Ptr(m2, y)) => {
                m1 == m2 && self.match_ty(x, y, out)
            }
            (a, b) => a == b,
        }
    }

    /// Impls of trait `tr` (`None`: inherent impls) whose self type matches `t`, with
    /// the impl parameters that matching determined.
    pub fn impls_matching(&self, tr: Option<TraitKind>, t: &Ty) -> Vec<(ImplId, Vec<Option<Ty>>)> {
        let mut out = Vec::new();
        for (i, im) in self.impls.iter().enumerate() {
            if im.trait_.as_ref().map(|r| r.kind) != tr {
                continue;
            }
            let mut substs = vec![None; im.generics.len()];
            if self.match_ty(&im.self_ty, t, &mut substs) {
                out.push((i, substs));
            }
        }
        out
    }

    /// Replaces every projection on a known type by the type the matching impl defines.
    pub fn normalize(&self, t: &Ty) -> Result<Ty, String> {
        let mut err = None;
        let r = t.map(&mut |x| match x {
            Ty::Proj(base, tr, name) if !base.has_params() && !base.has_vars() => {
                let base = match self.normalize(base) {
                    Ok(b) => b,
                    Err(e) => {
                        err = Some(e);
                        return Some(Ty::Unit);
                    }
                };
                match self.assoc_type(&base, tr.as_deref(), name) {
                    Ok(t) => Some(t),
                    Err(e) => {
                        err = Some(e);
                        Some(Ty::Unit)
                    }
                }
            }
            _ => None,
        });
        match err {
            Some(e) => Err(e),
            None => Ok(r),
        }
    }

    /// The associated type `name` of `t` (in trait `tr` when given).
    pub fn assoc_type(&self, t: &Ty, tr: Option<&TraitRef>, name: &str) -> Result<Ty, String> {
        let mut found: Vec<Ty> = Vec::new();
        for (i, im) in self.impls.iter().enumerate() {
            let Some(itr) = &im.trait_ else { continue };
            if let Some(want) = tr {
                if want.kind != itr.kind {
                    continue;
                }
            }
            let Some(at) = im.types.get(name) else {
                continue;
            };
            let mut substs = vec![None; im.generics.len()];
            if !self.match_ty(&im.self_ty, t, &mut substs) {
                continue;
            }
            if let Some(want) = tr {
                let ok = want.args.len() == itr.args.len()
                    && want
                        .args
                        .iter()
                        .zip(&itr.args)
                        .all(|(w, p)| self.match_ty(p, w, &mut substs));
                if !ok {
                    continue;
                }
            }
            let substs: Vec<Ty> = substs.into_iter().map(|s| s.unwrap_or(Ty::Infer)).collect();
            let _ = i;
            let r = self.normalize(&at.subst(&substs))?;
            if !found.contains(&r) {
                found.push(r);
            }
        }
        match found.len() {
            1 => Ok(found.pop().expect("one")),
            0 => Err(format!(
                "no associated type `{name}` for `{}`",
                self.ty_str(t)
            )),
            _ => Err(format!(
                "ambiguous associated type `{name}` for `{}` (write `<{} as Trait>::{name}`)",
                self.ty_str(t),
                self.ty_str(t)
            )),
        }
    }
}
