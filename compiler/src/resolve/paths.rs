//! Name lookup: module items, `use` declarations, glob imports, `crate`/`self`/`super`/
//! `trax`/`std`/`core` paths and Rust's prelude names.

use super::{ModId, Ns, PathRes, Program, UseDecl};
use crate::diag::{DResult, FileId};
use crate::ty::{FloatTy, IntTy, LangTrait, TraitKind, Ty};
use proc_macro2::Span;

/// The segment names of a path.
pub fn path_segs(p: &syn::Path) -> Vec<String> {
    p.segments.iter().map(|s| s.ident.to_string()).collect()
}

/// Primitive type by name.
pub fn prim_type(s: &str) -> Option<Ty> {
    Some(match s {
        "bool" => Ty::Bool,
        "char" => Ty::Char,
        "f32" => Ty::Float(FloatTy::F32),
        "f64" => Ty::Float(FloatTy::F64),
        _ => Ty::Int(IntTy::from_name(s)?),
    })
}

/// Names of Rust's prelude that the prelude's `lang` module defines on TRaX.
const LANG_PRELUDE: &[&str] = &["Option", "Some", "None", "Result", "Ok", "Err"];

/// Functions of `core` the compiler provides: `(module, name)`.
const STD_FNS: &[(&str, &str)] = &[
    ("ptr", "read"),
    ("ptr", "write"),
    ("ptr", "read_volatile"),
    ("ptr", "write_volatile"),
    ("ptr", "null"),
    ("ptr", "null_mut"),
    ("mem", "swap"),
    ("mem", "replace"),
    ("mem", "take"),
    ("cmp", "min"),
    ("cmp", "max"),
];

pub(super) fn flatten_use(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut Vec<UseDecl>) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten_use(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let name = n.ident.to_string();
            let mut segs = prefix.clone();
            let bound = if name == "self" {
                prefix.last().cloned().unwrap_or_default()
            } else {
                name.clone()
            };
            segs.push(name);
            out.push(UseDecl {
                segs,
                name: Some(bound),
                span: n.ident.span(),
            });
        }
        syn::UseTree::Rename(r) => {
            let mut segs = prefix.clone();
            segs.push(r.ident.to_string());
            out.push(UseDecl {
                segs,
                name: Some(r.rename.to_string()),
                span: r.rename.span(),
            });
        }
        syn::UseTree::Glob(g) => out.push(UseDecl {
            segs: prefix.clone(),
            name: None,
            span: g.star_token.span,
        }),
        syn::UseTree::Group(g) => {
            for t in &g.items {
                flatten_use(t, prefix, out);
            }
        }
    }
}

impl<'a> Program<'a> {
    /// Resolves a path given as segment names, from `module`.
    pub fn resolve_path_segs(
        &self,
        module: ModId,
        file: FileId,
        segs: &[String],
        ns: Ns,
        span: Span,
    ) -> DResult<PathRes> {
        self.resolve_from(module, segs, ns, 0).ok_or_else(|| {
            const OS: &[&str] = &[
                "io",
                "fs",
                "env",
                "process",
                "thread",
                "collections",
                "vec",
                "string",
                "boxed",
                "rc",
                "sync",
                "net",
                "time",
                "path",
                "ffi",
                "os",
                "alloc",
            ];
            if segs.len() >= 2
                && matches!(segs[0].as_str(), "std" | "core" | "alloc")
                && OS.contains(&segs[1].as_str())
            {
                return self.err(
                    file,
                    span,
                    "unsupported-std",
                    format!(
                        "`std::{}` is not available in TRaX-Rust (no operating system, no heap)",
                        segs[1]
                    ),
                );
            }
            if let Some(h) = self.heap_type_in(module, segs) {
                return self.heap_type_error(file, span, h);
            }
            self.err(
                file,
                span,
                if ns == Ns::Type {
                    "unknown-type"
                } else {
                    "unresolved-path"
                },
                format!("cannot find `{}` in this scope", segs.join("::")),
            )
        })
    }

    /// Resolves a path without reporting errors.
    pub fn try_resolve(&self, module: ModId, segs: &[String], ns: Ns) -> Option<PathRes> {
        self.resolve_from(module, segs, ns, 0)
    }

    pub(super) fn resolve_from(
        &self,
        module: ModId,
        segs: &[String],
        ns: Ns,
        depth: u32,
    ) -> Option<PathRes> {
        if depth > 16 || segs.is_empty() {
            return None;
        }
        let first = segs[0].as_str();
        let only = segs.len() == 1;
        let first_ns = if only { ns } else { Ns::Type };
        let real = self.modules[module].real(module, self);
        let mut cur = match first {
            "crate" => PathRes::Mod(self.modules[module].crate_root),
            "self" => PathRes::Mod(real),
            "super" => PathRes::Mod(self.modules[real].parent?),
            "std" | "core" if self.lookup(module, first, Ns::Type, depth).is_none() => {
                return self.resolve_std(&segs[1..], ns)
            }
            _ => match self.lookup(module, first, first_ns, depth) {
                Some(r) => r,
                None if first == "trax" && self.trax_root.is_some() => {
                    PathRes::Mod(self.trax_root?)
                }
                None => match prim_type(first) {
                    Some(t) if first_ns == Ns::Type => PathRes::Prim(t),
                    Some(t) if segs.len() == 2 => {
                        return Some(PathRes::PrimAssoc(t, segs[1].clone()))
                    }
                    _ => return None,
                },
            },
        };
        for (i, seg) in segs.iter().enumerate().skip(1) {
            let last = i + 1 == segs.len();
            let want = if last { ns } else { Ns::Type };
            cur = match cur {
                PathRes::Mod(m) => match seg.as_str() {
                    "super" => PathRes::Mod(self.modules[m].parent?),
                    "self" => PathRes::Mod(m),
                    s => self.lookup_local(m, s, want, depth + 1)?,
                },
                PathRes::Adt(a) if last => match self.adts[a].variant(seg) {
                    Some(v) if self.adts[a].is_enum => PathRes::Variant(a, v),
                    _ => PathRes::AdtAssoc(a, seg.clone()),
                },
                PathRes::Alias(a) if last => PathRes::AliasAssoc(a, seg.clone()),
                PathRes::Simd(t) if last => PathRes::PrimAssoc(Ty::Simd(t), seg.clone()),
                PathRes::Prim(t) if last => PathRes::PrimAssoc(t, seg.clone()),
                PathRes::Trait(t) if last => PathRes::TraitAssoc(t, seg.clone()),
                _ => return None,
            };
        }
        Some(cur)
    }

    /// Looks a single name up in a module: its items, then its `use`s, then glob
    /// imports, then (for a block's items) the enclosing scope, then Rust's prelude.
    pub(super) fn lookup(&self, module: ModId, name: &str, ns: Ns, depth: u32) -> Option<PathRes> {
        if let Some(r) = self.lookup_local(module, name, ns, depth) {
            return Some(r);
        }
        let mut m = module;
        while let Some(e) = self.modules[m].enclosing {
            if let Some(r) = self.lookup_local(e, name, ns, depth) {
                return Some(r);
            }
            m = e;
        }
        self.rust_prelude(name, ns)
    }

    /// Rust's prelude: `Option`, `Some`, ..., and traits such as `Clone` and `Default`.
    fn rust_prelude(&self, name: &str, ns: Ns) -> Option<PathRes> {
        if LANG_PRELUDE.contains(&name) {
            let lm = self.lang.module?;
            let m = &self.modules[lm];
            return match ns {
                Ns::Type => m.types.get(name).cloned(),
                Ns::Value => m.values.get(name).cloned(),
            };
        }
        match LangTrait::from_name(name) {
            Some(t) if t.in_prelude() && ns == Ns::Type => Some(PathRes::Trait(TraitKind::Lang(t))),
            _ => None,
        }
    }

    fn lookup_local(&self, module: ModId, name: &str, ns: Ns, depth: u32) -> Option<PathRes> {
        if depth > 16 {
            return None;
        }
        let m = &self.modules[module];
        let direct = match ns {
            Ns::Type => m.types.get(name),
            Ns::Value => m.values.get(name),
        };
        if let Some(r) = direct {
            return Some(r.clone());
        }
        for u in &m.uses {
            if u.name.as_deref() == Some(name) {
                let mut segs = u.segs.clone();
                // `use a::b as name;` — the last segment is the original name.
                if segs.last().map(String::as_str) == Some("self") {
                    segs.pop();
                }
                if let Some(r) = self.resolve_from(module, &segs, ns, depth + 1) {
                    return Some(r);
                }
            }
        }
        for u in &m.uses {
            if u.name.is_none() {
                match self.resolve_from(module, &u.segs, Ns::Type, depth + 1) {
                    Some(PathRes::Mod(g)) if g != module => {
                        if let Some(r) = self.lookup_local(g, name, ns, depth + 1) {
                            return Some(r);
                        }
                    }
                    // `use Enum::*;` imports the variants.
                    Some(PathRes::Adt(a)) if self.adts[a].is_enum => {
                        if let Some(v) = self.adts[a].variant(name) {
                            return Some(PathRes::Variant(a, v));
                        }
                    }
                    _ => {}
                }
            }
        }
        None
    }

    /// `std::...`/`core::...` paths.
    fn resolve_std(&self, rest: &[String], ns: Ns) -> Option<PathRes> {
        let r: Vec<&str> = rest.iter().map(String::as_str).collect();
        let lang_item = |name: &str, ns: Ns| -> Option<PathRes> {
            let m = &self.modules[self.lang.module?];
            match ns {
                Ns::Type => m.types.get(name).cloned(),
                Ns::Value => m.values.get(name).cloned(),
            }
        };
        let lang_trait = |module: &str, name: &str| -> Option<PathRes> {
            let t = LangTrait::from_name(name)?;
            (t.core_module() == module).then_some(PathRes::Trait(TraitKind::Lang(t)))
        };
        match r.as_slice() {
            [m, t] if ns == Ns::Type && lang_trait(m, t).is_some() => lang_trait(m, t),
            [m, t, item] if lang_trait(m, t).is_some() => {
                let PathRes::Trait(k) = lang_trait(m, t)? else {
                    return None;
                };
                Some(PathRes::TraitAssoc(k, item.to_string()))
            }
            [m, f] if ns == Ns::Value && STD_FNS.contains(&(*m, *f)) => {
                let (m, f) = STD_FNS.iter().find(|(a, b)| a == m && b == f)?;
                Some(PathRes::StdFn(m, f))
            }
            ["option", "Option"] | ["result", "Result"] | ["cmp", "Ordering"] => {
                lang_item(r[1], Ns::Type)
            }
            ["option", "Option", v] | ["result", "Result", v] | ["cmp", "Ordering", v] => {
                match lang_item(r[1], Ns::Type)? {
                    PathRes::Adt(a) => match self.adts[a].variant(v) {
                        Some(i) => Some(PathRes::Variant(a, i)),
                        None => Some(PathRes::AdtAssoc(a, v.to_string())),
                    },
                    _ => None,
                }
            }
            ["option", v @ ("Some" | "None")] | ["result", v @ ("Ok" | "Err")] => {
                lang_item(v, Ns::Value)
            }
            [p] => prim_type(p).map(PathRes::Prim),
            [p, name] => prim_type(p).map(|t| PathRes::PrimAssoc(t, name.to_string())),
            [p @ ("f32" | "f64"), "consts", name] => {
                let ft = if *p == "f32" {
                    FloatTy::F32
                } else {
                    FloatTy::F64
                };
                Some(PathRes::FloatConst(ft, name.to_string()))
            }
            _ => None,
        }
    }
}
