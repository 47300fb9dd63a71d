//! Item collection: modules, structs, enums, traits, impls, functions, consts, statics,
//! type aliases and `use` declarations (also items nested in function bodies), with the
//! subset's rejections of items TRaX-Rust does not have.

use super::paths::flatten_use;
use super::{
    AdtDef, AdtSyntax, AliasDef, Bound, Ctor, Derives, FieldDef, FnDef, FnId, FnParent, GlobalDef,
    GlobalId, ImplDef, InlineHint, LangItems, ModId, Module, Ns, PathRes, Program, Recv, TraitDef,
    TyScope, VariantDef,
};
use crate::diag::{DResult, Diagnostic, FileId, SourceMap};
use crate::parse::{cfg_enabled, ParsedCrate};
use crate::span::Spanned;
use crate::ty::{IntTy, LangTrait, SimdTy, TraitKind, TraitRef, Ty};
use std::collections::HashMap;
use syn::visit::Visit;
use syn::{Attribute, Expr, FnArg, Item, Meta, Pat, ReturnType, Type};

/// A function whose signature is resolved after every type is known.
struct PendingFn {
    id: FnId,
}

/// An impl block whose items are collected after every type is known.
struct PendingImpl<'a> {
    module: ModId,
    item: &'a syn::ItemImpl,
}

struct Collector<'a> {
    p: Program<'a>,
    errs: Vec<Diagnostic>,
    impls: Vec<PendingImpl<'a>>,
    fns: Vec<PendingFn>,
}

/// Builds the program (see [`super::collect`]).
pub(super) fn collect<'a>(
    sources: &'a SourceMap,
    kernel: &'a ParsedCrate,
    kernel_name: &str,
    prelude: Option<&'a ParsedCrate>,
) -> Result<Program<'a>, Vec<Diagnostic>> {
    let p = Program {
        sources,
        modules: Vec::new(),
        adts: Vec::new(),
        fns: Vec::new(),
        globals: Vec::new(),
        traits: Vec::new(),
        impls: Vec::new(),
        aliases: Vec::new(),
        block_mods: HashMap::new(),
        kernel_root: 0,
        trax_root: None,
        lang: LangItems::default(),
    };
    let mut c = Collector {
        p,
        errs: Vec::new(),
        impls: Vec::new(),
        fns: Vec::new(),
    };
    c.p.kernel_root = c.add_module(kernel_name.to_string(), None, kernel.root, None, None);
    let root = c.p.kernel_root;
    c.walk(kernel, root, kernel.root, &kernel.files[&kernel.root].items);
    if let Some(pre) = prelude {
        let root = c.add_module("trax".into(), None, pre.root, None, None);
        c.p.trax_root = Some(root);
        c.walk(pre, root, pre.root, &pre.files[&pre.root].items);
    }
    // Builtin `trax::simd` module on the TRaX side.
    let simd_parent = c.p.trax_root.unwrap_or(c.p.kernel_root);
    if !c.p.modules[simd_parent].types.contains_key("simd") {
        let file = c.p.modules[simd_parent].file;
        let m = c.add_module("simd".into(), Some(simd_parent), file, None, None);
        let md = &mut c.p.modules[m];
        md.types
            .insert("f32x4".into(), PathRes::Simd(SimdTy::F32x4));
        md.types
            .insert("i32x4".into(), PathRes::Simd(SimdTy::I32x4));
        c.p.modules[simd_parent]
            .types
            .insert("simd".into(), PathRes::Mod(m));
    }
    c.lang_items();
    c.resolve_adts();
    c.check_recursive_adts();
    c.resolve_traits();
    let impls = std::mem::take(&mut c.impls);
    for im in impls {
        // A derived impl (`crate::derive`) whose header does not resolve (its type was
        // refused) is left out silently: the type's own diagnostics say what is wrong.
        // Without the prelude there is no `Option` for its result: left out too (a
        // comparison then reports the missing prelude).
        let derived = im
            .item
            .attrs
            .iter()
            .any(|a| a.path().is_ident("automatically_derived"));
        if derived && c.p.lang.module.is_none() {
            continue;
        }
        if let Err(e) = c.collect_impl(im) {
            if !derived {
                c.errs.push(e);
            }
        }
    }
    let fns = std::mem::take(&mut c.fns);
    for pf in fns {
        if let Err(e) = c.resolve_sig(pf.id) {
            c.errs.push(e);
        }
    }
    for g in 0..c.p.globals.len() {
        if let Err(e) = c.resolve_global(g) {
            c.errs.push(e);
        }
    }
    c.check_uses();
    c.check_derives();
    if c.errs.is_empty() {
        Ok(c.p)
    } else {
        Err(c.errs)
    }
}

/// Finds the blocks of a body that hold items, innermost last, with the index of the
/// enclosing found block.
struct BlockScan<'a> {
    found: Vec<(&'a syn::Block, Option<usize>)>,
    stack: Vec<usize>,
}

impl<'a> Visit<'a> for BlockScan<'a> {
    fn visit_block(&mut self, b: &'a syn::Block) {
        if b.stmts.iter().any(|s| matches!(s, syn::Stmt::Item(_))) {
            self.found.push((b, self.stack.last().copied()));
            self.stack.push(self.found.len() - 1);
            syn::visit::visit_block(self, b);
            self.stack.pop();
        } else {
            syn::visit::visit_block(self, b);
        }
    }

    // Nested items' own bodies are scanned when the items are walked.
    fn visit_item(&mut self, _: &'a Item) {}
}

fn item_attrs(item: &Item) -> &[Attribute] {
    match item {
        Item::Const(i) => &i.attrs,
        Item::Fn(i) => &i.attrs,
        Item::Impl(i) => &i.attrs,
        Item::Mod(i) => &i.attrs,
        Item::Static(i) => &i.attrs,
        Item::Struct(i) => &i.attrs,
        Item::Use(i) => &i.attrs,
        Item::Enum(i) => &i.attrs,
        Item::Trait(i) => &i.attrs,
        Item::Macro(i) => &i.attrs,
        Item::Type(i) => &i.attrs,
        _ => &[],
    }
}

impl<'a> Collector<'a> {
    fn err(
        &self,
        file: FileId,
        span: proc_macro2::Span,
        id: &'static str,
        msg: impl Into<String>,
    ) -> Diagnostic {
        self.p.err(file, span, id, msg)
    }

    fn add_module(
        &mut self,
        name: String,
        parent: Option<ModId>,
        file: FileId,
        root: Option<ModId>,
        enclosing: Option<ModId>,
    ) -> ModId {
        let id = self.p.modules.len();
        let path = match parent {
            Some(pm) => format!("{}::{name}", self.p.modules[pm].path),
            None => name,
        };
        self.p.modules.push(Module {
            path,
            parent,
            file,
            crate_root: root.unwrap_or(id),
            enclosing,
            types: HashMap::new(),
            values: HashMap::new(),
            uses: Vec::new(),
        });
        id
    }

    fn walk(&mut self, pc: &'a ParsedCrate, module: ModId, file: FileId, items: &'a [Item]) {
        for item in items {
            if let Err(e) = self.walk_item(pc, module, file, item) {
                self.errs.push(e);
            }
        }
    }

    /// Collects the items of `body`'s blocks into block modules under `module`.
    fn scan_body(
        &mut self,
        pc: &'a ParsedCrate,
        module: ModId,
        file: FileId,
        name: &str,
        body: &'a syn::Block,
    ) {
        let mut scan = BlockScan {
            found: Vec::new(),
            stack: Vec::new(),
        };
        scan.visit_block(body);
        let mut mods = Vec::new();
        let many = scan.found.len() > 1;
        for (i, (b, parent)) in scan.found.iter().enumerate() {
            let enclosing = parent.map_or(module, |pi| mods[pi]);
            let real = self.p.modules[module].real(module, &self.p);
            let label = if many {
                format!("{name}{{{i}}}")
            } else {
                name.to_string()
            };
            let root = self.p.modules[module].crate_root;
            let m = self.add_module(label, Some(real), file, Some(root), Some(enclosing));
            self.p
                .block_mods
                .insert(*b as *const syn::Block as usize, m);
            mods.push(m);
            for s in &b.stmts {
                if let syn::Stmt::Item(it) = s {
                    if let Err(e) = self.walk_item(pc, m, file, it) {
                        self.errs.push(e);
                    }
                }
            }
        }
    }

    fn walk_item(
        &mut self,
        pc: &'a ParsedCrate,
        module: ModId,
        file: FileId,
        item: &'a Item,
    ) -> DResult<()> {
        let attrs = item_attrs(item);
        if !cfg_enabled(attrs) || attrs.iter().any(|a| a.path().is_ident("test")) {
            return Ok(());
        }
        self.check_attrs(file, attrs)?;
        let root = self.p.modules[module].crate_root;
        match item {
            Item::Fn(f) => {
                let name = f.sig.ident.to_string();
                // `trax_main` at the kernel's root and `#[no_mangle] extern "C"` exports
                // keep their names (C code calls them); others get their path.
                let export = f.sig.abi.is_some() && has_no_mangle(attrs);
                let symbol = if export || (name == "trax_main" && module == self.p.kernel_root) {
                    name.clone()
                } else {
                    format!("{}::{name}", self.p.modules[module].path)
                };
                let id = self.add_fn(FnDef {
                    name: name.clone(),
                    symbol,
                    module,
                    file,
                    sig: &f.sig,
                    body: Some(&f.block),
                    self_ty: None,
                    receiver: None,
                    params: Vec::new(),
                    ret: Ty::Unit,
                    inline: InlineHint::None,
                    generics: super::Generics::default(),
                    parent: FnParent::Free,
                    is_const: f.sig.constness.is_some(),
                    attrs: &f.attrs,
                    foreign: false,
                });
                self.define(module, file, &f.sig.ident, Ns::Value, PathRes::Fn(id))?;
                self.scan_body(pc, module, file, &name, &f.block);
            }
            Item::Struct(s) => {
                let derives = self.derives(file, &s.attrs)?;
                let ctor = match &s.fields {
                    syn::Fields::Named(_) => Ctor::Named,
                    syn::Fields::Unnamed(_) => Ctor::Tuple,
                    syn::Fields::Unit => Ctor::Unit,
                };
                let id = self.p.adts.len();
                self.p.adts.push(AdtDef {
                    name: s.ident.to_string(),
                    module,
                    file,
                    span: s.ident.span(),
                    is_enum: false,
                    generics: super::Generics::default(),
                    variants: vec![VariantDef {
                        name: s.ident.to_string(),
                        ctor,
                        fields: Vec::new(),
                        discr: 0,
                        span: s.ident.span(),
                    }],
                    derives,
                    repr: IntTy::Isize,
                    default_variant: None,
                    syntax: AdtSyntax::Struct(s),
                });
                self.define(module, file, &s.ident, Ns::Type, PathRes::Adt(id))?;
                if ctor != Ctor::Named {
                    self.define(module, file, &s.ident, Ns::Value, PathRes::Adt(id))?;
                }
            }
            Item::Enum(e) => {
                let derives = self.derives(file, &e.attrs)?;
                let repr = self.repr(file, &e.attrs)?;
                let id = self.p.adts.len();
                let mut variants = Vec::new();
                for v in &e.variants {
                    self.check_attrs(file, &v.attrs)?;
                    let ctor = match &v.fields {
                        syn::Fields::Named(_) => Ctor::Named,
                        syn::Fields::Unnamed(_) => Ctor::Tuple,
                        syn::Fields::Unit => Ctor::Unit,
                    };
                    if variants.iter().any(|x: &VariantDef| v.ident == x.name) {
                        return Err(self.err(
                            file,
                            v.ident.span(),
                            "duplicate-definition",
                            format!("variant `{}` is defined more than once", v.ident),
                        ));
                    }
                    variants.push(VariantDef {
                        name: v.ident.to_string(),
                        ctor,
                        fields: Vec::new(),
                        discr: 0,
                        span: v.ident.span(),
                    });
                }
                self.p.adts.push(AdtDef {
                    name: e.ident.to_string(),
                    module,
                    file,
                    span: e.ident.span(),
                    is_enum: true,
                    generics: super::Generics::default(),
                    variants,
                    derives,
                    repr: repr.unwrap_or(IntTy::Isize),
                    default_variant: None,
                    syntax: AdtSyntax::Enum(e),
                });
                self.define(module, file, &e.ident, Ns::Type, PathRes::Adt(id))?;
            }
            Item::Trait(t) => {
                if let Some(u) = &t.unsafety {
                    return Err(self.err(
                        file,
                        u.span,
                        "unsupported-unsafe-trait",
                        "unsafe traits are not supported in TRaX-Rust",
                    ));
                }
                let id = self.p.traits.len();
                self.p.traits.push(TraitDef {
                    name: t.ident.to_string(),
                    module,
                    file,
                    span: t.ident.span(),
                    generics: super::Generics::default(),
                    supertraits: Vec::new(),
                    methods: Vec::new(),
                    consts: Vec::new(),
                    types: Vec::new(),
                    item: t,
                });
                self.define(
                    module,
                    file,
                    &t.ident,
                    Ns::Type,
                    PathRes::Trait(TraitKind::User(id)),
                )?;
                // Default method bodies may hold items.
                for ti in &t.items {
                    if let syn::TraitItem::Fn(f) = ti {
                        if let Some(b) = &f.default {
                            let n = format!("{}::{}", t.ident, f.sig.ident);
                            self.scan_body(pc, module, file, &n, b);
                        }
                    }
                }
            }
            Item::Type(t) => {
                let params = self.param_names(file, &t.generics, &[])?;
                let id = self.p.aliases.len();
                self.p.aliases.push(AliasDef {
                    name: t.ident.to_string(),
                    module,
                    file,
                    params,
                    ty: &t.ty,
                });
                self.define(module, file, &t.ident, Ns::Type, PathRes::Alias(id))?;
            }
            Item::Const(c) => {
                if !c.generics.params.is_empty() {
                    return Err(self.err(
                        file,
                        c.generics.params.span(),
                        "unsupported-generics",
                        "generic consts are not supported in TRaX-Rust",
                    ));
                }
                let id = self.add_global(
                    module,
                    file,
                    &c.ident,
                    &c.ty,
                    Some(&c.expr),
                    None,
                    None,
                    super::Generics::default(),
                );
                self.define(module, file, &c.ident, Ns::Value, PathRes::Global(id))?;
            }
            Item::Static(s) => {
                let m = matches!(s.mutability, syn::StaticMutability::Mut(_));
                let id = self.add_global(
                    module,
                    file,
                    &s.ident,
                    &s.ty,
                    Some(&s.expr),
                    Some(m),
                    None,
                    super::Generics::default(),
                );
                self.define(module, file, &s.ident, Ns::Value, PathRes::Global(id))?;
            }
            Item::Mod(m) => {
                let (child_file, items): (FileId, &'a [Item]) = match &m.content {
                    Some((_, items)) => (file, items),
                    None => {
                        let f = pc
                            .mod_files
                            .get(&(m as *const syn::ItemMod as usize))
                            .copied();
                        let Some(f) = f else {
                            return Err(self.err(
                                file,
                                m.ident.span(),
                                "module-file-not-found",
                                format!("file not found for module `{}`", m.ident),
                            ));
                        };
                        (f, &pc.files[&f].items)
                    }
                };
                let parent = self.p.modules[module].real(module, &self.p);
                let id = self.add_module(
                    m.ident.to_string(),
                    Some(parent),
                    child_file,
                    Some(root),
                    None,
                );
                self.define(module, file, &m.ident, Ns::Type, PathRes::Mod(id))?;
                self.walk(pc, id, child_file, items);
            }
            Item::Use(u) => {
                let mut out = Vec::new();
                flatten_use(&u.tree, &mut Vec::new(), &mut out);
                self.p.modules[module].uses.extend(out);
            }
            Item::Impl(i) => {
                for ii in &i.items {
                    if let syn::ImplItem::Fn(f) = ii {
                        let n = format!("impl::{}", f.sig.ident);
                        self.scan_body(pc, module, file, &n, &f.block);
                    }
                }
                self.impls.push(PendingImpl { module, item: i });
            }
            Item::Macro(m) => {
                return Err(self.err(
                    file,
                    m.mac.path.span(),
                    "unsupported-macro-definition",
                    "macro definitions and item macros are not supported in TRaX-Rust",
                ))
            }
            Item::Union(u) => {
                return Err(self.err(
                    file,
                    u.ident.span(),
                    "unsupported-union",
                    "unions are not supported in TRaX-Rust",
                ))
            }
            Item::ExternCrate(e) => {
                return Err(self.err(
                    file,
                    e.span(),
                    "unsupported-extern-crate",
                    "`extern crate` is not supported in TRaX-Rust",
                ))
            }
            Item::ForeignMod(e) => {
                // `extern "C" { fn f(..); }`: functions C code of the same link defines.
                let c_abi = e.abi.name.as_ref().is_none_or(|n| n.value() == "C");
                let kernel = root == self.p.modules[self.p.kernel_root].crate_root;
                if !c_abi || !kernel {
                    return Err(self.err(
                        file,
                        e.abi.span(),
                        "unsupported-extern-block",
                        "TRaX-Rust supports `extern` blocks only as `extern \"C\" { fn name(..); }` in the kernel (functions the C or C++ files of the link define)",
                    ));
                }
                for fi in &e.items {
                    let syn::ForeignItem::Fn(f) = fi else {
                        return Err(self.err(
                            file,
                            fi.span(),
                            "unsupported-extern-block",
                            "`extern \"C\"` blocks may declare only functions here (no statics or types)",
                        ));
                    };
                    if !cfg_enabled(&f.attrs) {
                        continue;
                    }
                    self.check_attrs(file, &f.attrs)?;
                    if !f.sig.generics.params.is_empty() {
                        return Err(self.err(
                            file,
                            f.sig.generics.span(),
                            "unsupported-extern-block",
                            "functions declared in `extern \"C\"` blocks cannot be generic",
                        ));
                    }
                    let name = f.sig.ident.to_string();
                    let id = self.add_fn(FnDef {
                        name: name.clone(),
                        symbol: name,
                        module,
                        file,
                        sig: &f.sig,
                        body: None,
                        self_ty: None,
                        receiver: None,
                        params: Vec::new(),
                        ret: Ty::Unit,
                        inline: InlineHint::None,
                        generics: super::Generics::default(),
                        parent: FnParent::Free,
                        is_const: false,
                        attrs: &f.attrs,
                        foreign: true,
                    });
                    self.define(module, file, &f.sig.ident, Ns::Value, PathRes::Fn(id))?;
                }
            }
            other => {
                return Err(self.err(
                    file,
                    other.span(),
                    "unsupported-item",
                    "this kind of item is not supported in TRaX-Rust",
                ))
            }
        }
        Ok(())
    }

    /// A derived trait needs its fields' types to have it (rustc's E0277 for
    /// `#[derive(Debug)]` on a struct with a field that is not `Debug`).
    fn check_derives(&mut self) {
        for a in 0..self.p.adts.len() {
            let derives = self.p.adts[a].derives.0.clone();
            for tr in derives {
                if matches!(tr, LangTrait::Eq) {
                    continue;
                }
                for v in &self.p.adts[a].variants {
                    for f in &v.fields {
                        if !self.supports(&f.ty, tr, 0) {
                            let (name, ty) = (&self.p.adts[a].name, self.p.ty_str(&f.ty));
                            let message = if tr == LangTrait::PartialOrd
                                && !matches!(f.ty, Ty::Adt(..))
                            {
                                format!("`#[derive(PartialOrd)]` on `{name}` cannot compare a field of type `{ty}`: TRaX-Rust compares numbers, `bool`, `char` and types that are `PartialOrd` themselves (write `impl PartialOrd for {name}`)")
                            } else {
                                format!(
                                    "the trait `{}` is not implemented for `{ty}` (needed by `#[derive({0})]` on `{name}`)",
                                    tr.name(),
                                )
                            };
                            let d = self.err(self.p.adts[a].file, f.span, "derive-field", message);
                            self.errs.push(d);
                            return;
                        }
                    }
                }
            }
        }
    }

    /// True if type `t` (of a field) has trait `tr` (derived, implemented or builtin).
    fn supports(&self, t: &Ty, tr: LangTrait, depth: u32) -> bool {
        if depth > 32 {
            return true;
        }
        let has_impl = |t: &Ty| {
            self.p.impls.iter().any(|im| {
                im.trait_
                    .as_ref()
                    .is_some_and(|r| r.kind == TraitKind::Lang(tr))
                    && {
                        let mut s = vec![None; im.generics.len()];
                        self.p.match_ty(&im.self_ty, t, &mut s)
                    }
            })
        };
        if tr == LangTrait::PartialOrd {
            // What `partial_cmp` is defined on in TRaX-Rust (the derive calls it).
            return match t {
                Ty::Adt(a, _) => self.p.adts[*a].derives.has(tr) || has_impl(t),
                Ty::Int(_) | Ty::Float(_) | Ty::Bool | Ty::Char => true,
                Ty::Param(_) | Ty::Proj(..) | Ty::Infer | Ty::Var(_) => true,
                _ => false,
            };
        }
        match t {
            Ty::Param(_) | Ty::Proj(..) | Ty::Infer | Ty::Var(_) => true,
            Ty::Adt(a, _) => self.p.adts[*a].derives.has(tr) || has_impl(t),
            Ty::Tuple(ts) => ts.iter().all(|x| self.supports(x, tr, depth + 1)),
            Ty::Array(e, n) => {
                (tr != LangTrait::Default || *n <= 32) && self.supports(e, tr, depth + 1)
            }
            Ty::Ref(m, e) => match tr {
                LangTrait::Default => false,
                LangTrait::Copy | LangTrait::Clone => !m,
                _ => self.supports(e, tr, depth + 1),
            },
            Ty::Slice(e) => self.supports(e, tr, depth + 1),
            Ty::Ptr(..) => tr != LangTrait::Default,
            Ty::Str => tr != LangTrait::Default,
            Ty::Simd(_) => true,
            _ => true,
        }
    }

    /// Every `use` must name something.
    fn check_uses(&mut self) {
        for m in 0..self.p.modules.len() {
            let file = self.p.modules[m].file;
            for u in self.p.modules[m].uses.clone() {
                let mut segs = u.segs.clone();
                if segs.last().map(String::as_str) == Some("self") {
                    segs.pop();
                }
                let ok = match u.name {
                    Some(_) => {
                        self.p.resolve_from(m, &segs, Ns::Type, 0).is_some()
                            || self.p.resolve_from(m, &segs, Ns::Value, 0).is_some()
                    }
                    None => matches!(
                        self.p.resolve_from(m, &segs, Ns::Type, 0),
                        Some(PathRes::Mod(_)) | Some(PathRes::Adt(_))
                    ),
                };
                if !ok {
                    let e = match self.p.resolve_path_segs(m, file, &segs, Ns::Type, u.span) {
                        Err(e) if e.id == "unsupported-std" => e,
                        _ => self.err(
                            file,
                            u.span,
                            "unresolved-import",
                            format!("unresolved import `{}`", u.segs.join("::")),
                        ),
                    };
                    self.errs.push(e);
                }
            }
        }
    }

    fn add_fn(&mut self, f: FnDef<'a>) -> FnId {
        let id = self.p.fns.len();
        self.p.fns.push(f);
        self.fns.push(PendingFn { id });
        id
    }

    #[allow(clippy::too_many_arguments)]
    fn add_global(
        &mut self,
        module: ModId,
        file: FileId,
        ident: &syn::Ident,
        ty: &'a Type,
        expr: Option<&'a Expr>,
        is_static: Option<bool>,
        self_ty: Option<(Ty, String)>,
        generics: super::Generics,
    ) -> GlobalId {
        let id = self.p.globals.len();
        let prefix = match &self_ty {
            Some((_, name)) => format!("{}::{name}", self.p.modules[module].path),
            None => self.p.modules[module].path.clone(),
        };
        self.p.globals.push(GlobalDef {
            name: ident.to_string(),
            symbol: format!("{prefix}::{ident}"),
            module,
            file,
            ty: Ty::Unit,
            decl_ty: ty,
            expr,
            is_static,
            self_ty: self_ty.map(|(t, _)| t),
            span: ident.span(),
            ty_span: ty.span(),
            generics,
        });
        id
    }

    fn define(
        &mut self,
        module: ModId,
        file: FileId,
        ident: &syn::Ident,
        ns: Ns,
        r: PathRes,
    ) -> DResult<()> {
        let name = ident.to_string();
        let map = match ns {
            Ns::Type => &mut self.p.modules[module].types,
            Ns::Value => &mut self.p.modules[module].values,
        };
        if map.insert(name.clone(), r).is_some() {
            return Err(self.err(
                file,
                ident.span(),
                "duplicate-definition",
                format!("`{name}` is defined more than once in this module"),
            ));
        }
        Ok(())
    }

    fn check_attrs(&self, file: FileId, attrs: &[Attribute]) -> DResult<()> {
        for a in attrs {
            let name = a
                .path()
                .segments
                .iter()
                .map(|s| s.ident.to_string())
                .collect::<Vec<_>>()
                .join("::");
            let ok = matches!(
                name.as_str(),
                "cfg"
                    | "path"
                    | "inline"
                    | "derive"
                    | "allow"
                    | "warn"
                    | "deny"
                    | "doc"
                    | "repr"
                    | "must_use"
                    | "cold"
                    | "rustfmt::skip"
                    | "no_mangle"
                    | "expect"
                    | "cfg_attr"
                    | "default"
                    | "track_caller"
                    | "non_exhaustive"
                    | "automatically_derived"
            );
            if !ok {
                return Err(self.err(
                    file,
                    a.span(),
                    "unsupported-attribute",
                    format!("attribute `#[{name}]` is not supported in TRaX-Rust"),
                ));
            }
            if name == "cfg" {
                let valid = a
                    .parse_args::<Meta>()
                    .ok()
                    .and_then(|m| crate::parse::eval_cfg(&m))
                    .is_some();
                if !valid {
                    return Err(self.err(file, a.span(), "invalid-cfg", "unsupported `#[cfg]` predicate (use target_arch, target_os, not, all, any)"));
                }
            }
        }
        Ok(())
    }

    fn derives(&self, file: FileId, attrs: &[Attribute]) -> DResult<Derives> {
        let mut out = Vec::new();
        for a in attrs.iter().filter(|a| a.path().is_ident("derive")) {
            let list = a
                .parse_args_with(
                    syn::punctuated::Punctuated::<syn::Path, syn::Token![,]>::parse_terminated,
                )
                .map_err(|e| {
                    self.err(
                        file,
                        e.span(),
                        "invalid-derive",
                        format!("malformed derive: {e}"),
                    )
                })?;
            for p in list {
                let n = p
                    .segments
                    .last()
                    .map(|s| s.ident.to_string())
                    .unwrap_or_default();
                let t = match n.as_str() {
                    "Clone" => LangTrait::Clone,
                    "Copy" => LangTrait::Copy,
                    "Debug" => LangTrait::Debug,
                    "PartialEq" => LangTrait::PartialEq,
                    "Eq" => LangTrait::Eq,
                    "Default" => LangTrait::Default,
                    // Expanded into an impl while parsing (`crate::derive`).
                    "PartialOrd" => LangTrait::PartialOrd,
                    _ => {
                        return Err(self.err(file, p.span(), "unsupported-derive", format!("`#[derive({n})]` is not supported in TRaX-Rust (only Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Default)")))
                    }
                };
                out.push(t);
            }
        }
        Ok(Derives(out))
    }

    fn repr(&self, file: FileId, attrs: &[Attribute]) -> DResult<Option<IntTy>> {
        let mut r = None;
        for a in attrs.iter().filter(|a| a.path().is_ident("repr")) {
            let list = a
                .parse_args_with(
                    syn::punctuated::Punctuated::<syn::Ident, syn::Token![,]>::parse_terminated,
                )
                .map_err(|e| {
                    self.err(
                        file,
                        e.span(),
                        "invalid-repr",
                        format!("malformed repr: {e}"),
                    )
                })?;
            for i in list {
                let s = i.to_string();
                match IntTy::from_name(&s) {
                    Some(t) => r = Some(t),
                    None if s == "C" => {}
                    None => {
                        return Err(self.err(
                            file,
                            i.span(),
                            "unsupported-repr",
                            format!("`#[repr({s})]` is not supported in TRaX-Rust"),
                        ))
                    }
                }
            }
        }
        Ok(r)
    }

    /// Generic parameter names (`parent` first); rejects const generics.
    fn param_names(
        &self,
        file: FileId,
        g: &syn::Generics,
        parent: &[String],
    ) -> DResult<Vec<String>> {
        let mut names: Vec<String> = parent.to_vec();
        for gp in &g.params {
            match gp {
                syn::GenericParam::Lifetime(_) => {}
                syn::GenericParam::Type(t) => {
                    if let Some((_, d)) = &t.default {
                        return Err(self.err(file, d.span(), "unsupported-generics", "default type parameters are not supported in TRaX-Rust"));
                    }
                    names.push(t.ident.to_string())
                }
                syn::GenericParam::Const(c) => {
                    return Err(self.err(file, c.span(), "unsupported-const-generics", "const generics are not supported in TRaX-Rust (pass a slice `&[T]` instead of `[T; N]`)"))
                }
            }
        }
        Ok(names)
    }

    /// Bounds of `g`'s parameters and where clause, resolved in `scope`.
    fn bounds(
        &self,
        module: ModId,
        file: FileId,
        g: &syn::Generics,
        scope: &TyScope,
    ) -> DResult<Vec<Bound>> {
        let mut out = Vec::new();
        let mut add = |this: &Self,
                       ty: Ty,
                       bounds: &syn::punctuated::Punctuated<
            syn::TypeParamBound,
            syn::Token![+],
        >|
         -> DResult<()> {
            for b in bounds {
                match b {
                    syn::TypeParamBound::Trait(tb) => {
                        if tb.maybe.is_some() {
                            continue; // `?Sized`
                        }
                        let tr =
                            this.p
                                .resolve_trait_ref(module, file, &tb.path, scope, Some(&ty))?;
                        out.push(Bound { ty: ty.clone(), tr });
                    }
                    syn::TypeParamBound::Lifetime(_) => {}
                    other => {
                        return Err(this.err(
                            file,
                            other.span(),
                            "unsupported-generics",
                            "unsupported bound",
                        ))
                    }
                }
            }
            Ok(())
        };
        for gp in &g.params {
            if let syn::GenericParam::Type(t) = gp {
                let i = scope.params.iter().rposition(|n| t.ident == n).unwrap_or(0);
                add(self, Ty::Param(i as u32), &t.bounds)?;
            }
        }
        if let Some(w) = &g.where_clause {
            for pred in &w.predicates {
                match pred {
                    syn::WherePredicate::Type(pt) => {
                        let ty = self.p.resolve_type(module, file, &pt.bounded_ty, scope)?;
                        add(self, ty, &pt.bounds)?;
                    }
                    syn::WherePredicate::Lifetime(_) => {}
                    other => {
                        return Err(self.err(
                            file,
                            other.span(),
                            "unsupported-generics",
                            "unsupported where clause",
                        ))
                    }
                }
            }
        }
        Ok(out)
    }

    /// Finds the prelude's language module (`Option`, `Result`, `Ordering`) and `libm`.
    fn lang_items(&mut self) {
        let Some(root) = self.p.trax_root else { return };
        let module = |name: &str| match self.p.modules[root].types.get(name) {
            Some(PathRes::Mod(m)) => Some(*m),
            _ => None,
        };
        self.p.lang.libm = module("libm");
        let Some(lm) = module("lang") else { return };
        self.p.lang.module = Some(lm);
        let adt = |name: &str| match self.p.modules[lm].types.get(name) {
            Some(PathRes::Adt(a)) => Some(*a),
            _ => None,
        };
        self.p.lang.option = adt("Option");
        self.p.lang.result = adt("Result");
        self.p.lang.ordering = adt("Ordering");
        // `Some`/`None`/`Ok`/`Err` as values.
        let mut vals = Vec::new();
        for (a, names) in [
            (self.p.lang.option, ["Some", "None"]),
            (self.p.lang.result, ["Ok", "Err"]),
        ] {
            if let Some(a) = a {
                for n in names {
                    if let Some(v) = self.p.adts[a].variant(n) {
                        vals.push((n, PathRes::Variant(a, v)));
                    }
                }
            }
        }
        for (n, r) in vals {
            self.p.modules[lm].values.entry(n.to_string()).or_insert(r);
        }
    }

    /// Generic parameters, field types and discriminants of every struct and enum.
    fn resolve_adts(&mut self) {
        // Parameter names first: field types name other ADTs with their arguments.
        let mut bad = vec![false; self.p.adts.len()];
        for (a, bad) in bad.iter_mut().enumerate() {
            let (file, syntax) = (self.p.adts[a].file, self.p.adts[a].syntax);
            let generics = match syntax {
                AdtSyntax::Struct(s) => &s.generics,
                AdtSyntax::Enum(e) => &e.generics,
            };
            match self.param_names(file, generics, &[]) {
                Ok(n) => self.p.adts[a].generics.names = n,
                Err(e) => {
                    self.errs.push(e);
                    *bad = true;
                }
            }
        }
        // (An ADT whose parameters are refused is reported once, above.)
        for a in (0..self.p.adts.len()).filter(|&a| !bad[a]) {
            if let Err(e) = self.resolve_adt(a) {
                self.errs.push(e);
            }
        }
    }

    fn resolve_adt(&mut self, a: usize) -> DResult<()> {
        let (module, file, syntax) = {
            let d = &self.p.adts[a];
            (d.module, d.file, d.syntax)
        };
        let generics = match syntax {
            AdtSyntax::Struct(s) => &s.generics,
            AdtSyntax::Enum(e) => &e.generics,
        };
        let names = self.param_names(file, generics, &[])?;
        self.p.adts[a].generics.names = names.clone();
        let self_ty = Ty::Adt(a, (0..names.len() as u32).map(Ty::Param).collect());
        let scope = TyScope {
            self_ty: Some(&self_ty),
            params: &names,
            ..TyScope::default()
        };
        let bounds = self.bounds(module, file, generics, &scope)?;
        self.p.adts[a].generics.bounds = bounds;
        let fields_of = |this: &Self, f: &syn::Fields| -> DResult<Vec<FieldDef>> {
            let mut out = Vec::new();
            match f {
                syn::Fields::Named(n) => {
                    for fd in &n.named {
                        let ty = this.field_ty(module, file, &fd.ty, &scope)?;
                        let ident = fd.ident.as_ref().expect("named field");
                        out.push(FieldDef {
                            name: ident.to_string(),
                            ty,
                            span: ident.span(),
                        });
                    }
                }
                syn::Fields::Unnamed(u) => {
                    for (i, fd) in u.unnamed.iter().enumerate() {
                        let ty = this.field_ty(module, file, &fd.ty, &scope)?;
                        out.push(FieldDef {
                            name: i.to_string(),
                            ty,
                            span: fd.ty.span(),
                        });
                    }
                }
                syn::Fields::Unit => {}
            }
            Ok(out)
        };
        match syntax {
            AdtSyntax::Struct(s) => {
                let fields = fields_of(self, &s.fields)?;
                self.p.adts[a].variants[0].fields = fields;
            }
            AdtSyntax::Enum(e) => {
                let repr = self.p.adts[a].repr;
                let mut next: i128 = 0;
                let mut default_variant = None;
                for (i, v) in e.variants.iter().enumerate() {
                    let fields = fields_of(self, &v.fields)?;
                    let discr = match &v.discriminant {
                        Some((_, ex)) => self.p.eval_discr(module, file, ex, repr)?,
                        None => next,
                    };
                    if discr > repr.max() || discr < repr.min() {
                        return Err(self.err(
                            file,
                            v.ident.span(),
                            "discriminant-overflow",
                            format!(
                                "enum discriminant overflowed: `{}` does not fit `{}`",
                                discr,
                                repr.name()
                            ),
                        ));
                    }
                    if let Some(prev) = self.p.adts[a].variants[..i]
                        .iter()
                        .find(|x| x.discr == discr)
                    {
                        return Err(self.err(
                            file,
                            v.ident.span(),
                            "duplicate-discriminant",
                            format!(
                                "discriminant value `{discr}` assigned more than once (also `{}`)",
                                prev.name
                            ),
                        ));
                    }
                    next = discr + 1;
                    let vd = &mut self.p.adts[a].variants[i];
                    vd.fields = fields;
                    vd.discr = discr;
                    if v.attrs.iter().any(|a| a.path().is_ident("default")) {
                        default_variant = Some(i);
                    }
                }
                if self.p.adts[a].derives.has(LangTrait::Default) {
                    match default_variant {
                        Some(i) if self.p.adts[a].variants[i].fields.is_empty() => {
                            self.p.adts[a].default_variant = Some(i);
                        }
                        _ => {
                            return Err(self.err(
                                file,
                                e.ident.span(),
                                "invalid-derive",
                                "`#[derive(Default)]` on an enum needs a `#[default]` unit variant",
                            ))
                        }
                    }
                }
            }
        }
        Ok(())
    }

    fn field_ty(&self, module: ModId, file: FileId, t: &Type, scope: &TyScope) -> DResult<Ty> {
        let ty = self.p.resolve_type(module, file, t, scope)?;
        if contains_infer(&ty) {
            return Err(self.err(
                file,
                t.span(),
                "unsupported-type",
                "this field type is not supported in TRaX-Rust",
            ));
        }
        Ok(ty)
    }

    fn check_recursive_adts(&mut self) {
        fn contains(p: &Program, t: &Ty, target: usize, depth: usize) -> bool {
            if depth > 64 {
                return true;
            }
            match t {
                Ty::Adt(s, args) => {
                    *s == target
                        || args.iter().any(|a| contains(p, a, target, depth + 1))
                        || p.adts[*s]
                            .variants
                            .iter()
                            .flat_map(|v| &v.fields)
                            .any(|f| contains(p, &f.ty, target, depth + 1))
                }
                Ty::Array(e, _) => contains(p, e, target, depth + 1),
                Ty::Tuple(ts) => ts.iter().any(|e| contains(p, e, target, depth + 1)),
                _ => false,
            }
        }
        for (i, s) in self.p.adts.iter().enumerate() {
            if s.variants
                .iter()
                .flat_map(|v| &v.fields)
                .any(|f| contains(&self.p, &f.ty, i, 0))
            {
                let what = if s.is_enum { "enum" } else { "struct" };
                self.errs.push(self.err(
                    s.file,
                    s.span,
                    "recursive-type",
                    format!("{what} `{}` contains itself (use a raw pointer)", s.name),
                ));
                return;
            }
        }
    }

    /// Generics, supertraits and items of every trait.
    fn resolve_traits(&mut self) {
        for t in 0..self.p.traits.len() {
            if let Err(e) = self.resolve_trait(t) {
                self.errs.push(e);
            }
        }
    }

    fn resolve_trait(&mut self, t: usize) -> DResult<()> {
        let (module, file, item) = {
            let d = &self.p.traits[t];
            (d.module, d.file, d.item)
        };
        let names = self.param_names(file, &item.generics, &["Self".to_string()])?;
        self.p.traits[t].generics.names = names.clone();
        self.p.traits[t].generics.parent = 0;
        let self_ty = Ty::Param(0);
        let scope = TyScope {
            self_ty: Some(&self_ty),
            params: &names,
            impl_types: None,
            in_trait: Some(t),
        };
        let mut bounds = self.bounds(module, file, &item.generics, &scope)?;
        let mut supers = Vec::new();
        for b in &item.supertraits {
            if let syn::TypeParamBound::Trait(tb) = b {
                if tb.maybe.is_some() {
                    continue;
                }
                let tr =
                    self.p
                        .resolve_trait_ref(module, file, &tb.path, &scope, Some(&self_ty))?;
                supers.push(tr.clone());
                bounds.push(Bound {
                    ty: self_ty.clone(),
                    tr,
                });
            }
        }
        self.p.traits[t].supertraits = supers;
        self.p.traits[t].generics.bounds = bounds.clone();
        let tname = item.ident.to_string();
        for ti in &item.items {
            match ti {
                syn::TraitItem::Fn(f) => {
                    if !cfg_enabled(&f.attrs) {
                        continue;
                    }
                    self.check_attrs(file, &f.attrs)?;
                    let own = self.param_names(file, &f.sig.generics, &names)?;
                    let generics = super::Generics {
                        names: own,
                        parent: names.len(),
                        bounds: Vec::new(),
                    };
                    let name = format!("{tname}::{}", f.sig.ident);
                    let id = self.add_fn(FnDef {
                        name: name.clone(),
                        symbol: format!("{}::{name}", self.p.modules[module].path),
                        module,
                        file,
                        sig: &f.sig,
                        body: f.default.as_ref(),
                        self_ty: Some(self_ty.clone()),
                        receiver: None,
                        params: Vec::new(),
                        ret: Ty::Unit,
                        inline: InlineHint::None,
                        generics,
                        parent: FnParent::Trait(t),
                        is_const: false,
                        attrs: &f.attrs,
                        foreign: false,
                    });
                    if self.p.traits[t]
                        .methods
                        .iter()
                        .any(|(n, _)| f.sig.ident == n)
                    {
                        return Err(self.err(
                            file,
                            f.sig.ident.span(),
                            "duplicate-definition",
                            format!(
                                "`{}` is defined more than once in trait `{tname}`",
                                f.sig.ident
                            ),
                        ));
                    }
                    self.p.traits[t].methods.push((f.sig.ident.to_string(), id));
                }
                syn::TraitItem::Const(c) => {
                    let generics = super::Generics {
                        names: names.clone(),
                        parent: names.len(),
                        bounds: bounds.clone(),
                    };
                    let g = self.add_global(
                        module,
                        file,
                        &c.ident,
                        &c.ty,
                        c.default.as_ref().map(|(_, e)| e),
                        None,
                        Some((self_ty.clone(), tname.clone())),
                        generics,
                    );
                    self.p.traits[t].consts.push((c.ident.to_string(), g));
                }
                syn::TraitItem::Type(ty) => {
                    if ty.default.is_some() {
                        return Err(self.err(
                            file,
                            ty.span(),
                            "unsupported-generics",
                            "associated type defaults are not supported",
                        ));
                    }
                    self.p.traits[t].types.push(ty.ident.to_string());
                }
                other => {
                    return Err(self.err(
                        file,
                        other.span(),
                        "unsupported-trait-item",
                        "this kind of trait item is not supported in TRaX-Rust",
                    ))
                }
            }
        }
        Ok(())
    }

    fn collect_impl(&mut self, im: PendingImpl<'a>) -> DResult<()> {
        let item = im.item;
        let module = im.module;
        let file = self.p.modules[module].file;
        if let Some(u) = &item.unsafety {
            return Err(self.err(
                file,
                u.span,
                "unsupported-unsafe-trait",
                "unsafe impls are not supported in TRaX-Rust",
            ));
        }
        let names = self.param_names(file, &item.generics, &[])?;
        let scope0 = TyScope::params(&names);
        let self_ty = self.p.resolve_type(module, file, &item.self_ty, &scope0)?;
        let scope = TyScope {
            self_ty: Some(&self_ty),
            params: &names,
            ..TyScope::default()
        };
        let bounds = self.bounds(module, file, &item.generics, &scope)?;
        let trait_ = match &item.trait_ {
            Some((path, _)) => {
                Some(
                    self.p
                        .resolve_trait_ref(module, file, path, &scope, Some(&self_ty))?,
                )
            }
            None => None,
        };
        let type_name = self.p.ty_str(&self_ty);
        match (&trait_, &self_ty) {
            (None, Ty::Adt(a, args)) => {
                if self.p.adts[*a].module != module
                    && self.p.modules[self.p.adts[*a].module].crate_root != self.p.modules[module].crate_root
                {
                    return Err(self.err(file, item.self_ty.span(), "foreign-impl", format!("inherent impls for `{type_name}` must be in the crate that defines it")));
                }
                let _ = args;
            }
            (None, _) => {
                return Err(self.err(file, item.self_ty.span(), "unsupported-impl", format!("inherent impl blocks are only supported for structs and enums, not `{type_name}`")))
            }
            (Some(_), _) => {}
        }
        let id = self.p.impls.len();
        let generics = super::Generics {
            names: names.clone(),
            parent: 0,
            bounds,
        };
        // Associated types first: method signatures may name them.
        let mut types = HashMap::new();
        for ii in &item.items {
            if let syn::ImplItem::Type(t) = ii {
                if trait_.is_none() {
                    return Err(self.err(
                        file,
                        t.span(),
                        "unsupported-impl-item",
                        "inherent associated types are not supported",
                    ));
                }
                let ty = self.p.resolve_type(module, file, &t.ty, &scope)?;
                types.insert(t.ident.to_string(), ty);
            }
        }
        let trait_label = trait_.as_ref().map(|t| self.p.trait_name(t.kind));
        self.p.impls.push(ImplDef {
            module,
            file,
            generics: generics.clone(),
            self_ty: self_ty.clone(),
            trait_: trait_.clone(),
            fns: HashMap::new(),
            consts: HashMap::new(),
            types,
            item,
        });
        for ii in &item.items {
            match ii {
                syn::ImplItem::Fn(f) => {
                    if !cfg_enabled(&f.attrs) {
                        continue;
                    }
                    self.check_attrs(file, &f.attrs)?;
                    let own = self.param_names(file, &f.sig.generics, &names)?;
                    let name = format!("{type_name}::{}", f.sig.ident);
                    let symbol = match &trait_label {
                        Some(t) => format!(
                            "{}::<{type_name} as {t}>::{}",
                            self.p.modules[module].path, f.sig.ident
                        ),
                        None => format!("{}::{name}", self.p.modules[module].path),
                    };
                    let fid = self.add_fn(FnDef {
                        name,
                        symbol,
                        module,
                        file,
                        sig: &f.sig,
                        body: Some(&f.block),
                        self_ty: Some(self_ty.clone()),
                        receiver: None,
                        params: Vec::new(),
                        ret: Ty::Unit,
                        inline: InlineHint::None,
                        generics: super::Generics {
                            names: own,
                            parent: names.len(),
                            bounds: Vec::new(),
                        },
                        parent: FnParent::Impl(id),
                        is_const: f.sig.constness.is_some(),
                        attrs: &f.attrs,
                        foreign: false,
                    });
                    if self.p.impls[id]
                        .fns
                        .insert(f.sig.ident.to_string(), fid)
                        .is_some()
                    {
                        return Err(self.err(
                            file,
                            f.sig.ident.span(),
                            "duplicate-definition",
                            format!(
                                "`{}` is defined more than once for `{type_name}`",
                                f.sig.ident
                            ),
                        ));
                    }
                }
                syn::ImplItem::Const(c) => {
                    let g = self.add_global(
                        module,
                        file,
                        &c.ident,
                        &c.ty,
                        Some(&c.expr),
                        None,
                        Some((self_ty.clone(), type_name.clone())),
                        generics.clone(),
                    );
                    self.p.impls[id].consts.insert(c.ident.to_string(), g);
                }
                syn::ImplItem::Type(_) => {}
                other => {
                    return Err(self.err(
                        file,
                        other.span(),
                        "unsupported-impl-item",
                        "this kind of impl item is not supported in TRaX-Rust",
                    ))
                }
            }
        }
        // Trait impls provide the trait's required items and no others.
        if let Some(tr) = &trait_ {
            self.check_trait_impl(id, tr, file, item)?;
        }
        Ok(())
    }

    fn check_trait_impl(
        &self,
        id: usize,
        tr: &TraitRef,
        file: FileId,
        item: &syn::ItemImpl,
    ) -> DResult<()> {
        let im = &self.p.impls[id];
        let span = item
            .trait_
            .as_ref()
            .map(|(p, _)| p.span())
            .unwrap_or_else(|| item.span());
        match tr.kind {
            TraitKind::Lang(l) => {
                if matches!(l, LangTrait::Debug | LangTrait::Sized) {
                    return Err(self.err(file, span, "unsupported-trait-impl", format!("implementing `{}` is not supported in TRaX-Rust (use `#[derive({0})]`)", l.name())));
                }
                for (name, f) in &im.fns {
                    if !l.methods().iter().any(|(m, _)| m == name) {
                        let sig_span = self.p.fns[*f].sig.ident.span();
                        return Err(self.err(
                            file,
                            sig_span,
                            "unknown-trait-method",
                            format!("`{name}` is not a method of trait `{}`", l.name()),
                        ));
                    }
                }
                for (m, required) in l.methods() {
                    if *required && !im.fns.contains_key(*m) {
                        return Err(self.err(
                            file,
                            span,
                            "missing-trait-method",
                            format!("missing method `{m}` in impl of `{}`", l.name()),
                        ));
                    }
                }
                for t in l.assoc_types() {
                    if !im.types.contains_key(*t) {
                        return Err(self.err(
                            file,
                            span,
                            "missing-trait-item",
                            format!("missing associated type `{t}` in impl of `{}`", l.name()),
                        ));
                    }
                }
            }
            TraitKind::User(t) => {
                let td = &self.p.traits[t];
                for (name, f) in &im.fns {
                    if !td.methods.iter().any(|(m, _)| m == name) {
                        let sig_span = self.p.fns[*f].sig.ident.span();
                        return Err(self.err(
                            file,
                            sig_span,
                            "unknown-trait-method",
                            format!("method `{name}` is not a member of trait `{}`", td.name),
                        ));
                    }
                }
                for (m, f) in &td.methods {
                    if self.p.fns[*f].body.is_none() && !im.fns.contains_key(m) {
                        return Err(self.err(
                            file,
                            span,
                            "missing-trait-method",
                            format!("missing method `{m}` in impl of `{}`", td.name),
                        ));
                    }
                }
                for (c, g) in &td.consts {
                    if self.p.globals[*g].expr.is_none() && !im.consts.contains_key(c) {
                        return Err(self.err(
                            file,
                            span,
                            "missing-trait-item",
                            format!("missing associated const `{c}` in impl of `{}`", td.name),
                        ));
                    }
                }
                for ty in &td.types {
                    if !im.types.contains_key(ty) {
                        return Err(self.err(
                            file,
                            span,
                            "missing-trait-item",
                            format!("missing associated type `{ty}` in impl of `{}`", td.name),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    fn resolve_sig(&mut self, id: FnId) -> DResult<()> {
        let fd = &self.p.fns[id];
        let (module, file, sig, parent) = (fd.module, fd.file, fd.sig, fd.parent);
        let self_ty = fd.self_ty.clone();
        // Generic parameter names of free functions (impl and trait items have theirs).
        if parent == FnParent::Free {
            let names = self.param_names(file, &sig.generics, &[])?;
            self.p.fns[id].generics.names = names;
        }
        let names = self.p.fns[id].generics.names.clone();
        let impl_types = match parent {
            FnParent::Impl(i) => Some(self.p.impls[i].types.clone()),
            _ => None,
        };
        let in_trait = match parent {
            FnParent::Trait(t) => Some(t),
            _ => None,
        };
        let scope = TyScope {
            self_ty: self_ty.as_ref(),
            params: &names,
            impl_types: impl_types.as_ref(),
            in_trait,
        };
        let mut bounds = match parent {
            FnParent::Impl(i) => self.p.impls[i].generics.bounds.clone(),
            FnParent::Trait(t) => self.p.traits[t].generics.bounds.clone(),
            FnParent::Free => Vec::new(),
        };
        bounds.extend(self.bounds(module, file, &sig.generics, &scope)?);
        if sig.asyncness.is_some() {
            return Err(self.err(
                file,
                sig.span(),
                "unsupported-async",
                "async functions are not supported in TRaX-Rust",
            ));
        }
        if let Some(v) = &sig.variadic {
            return Err(self.err(
                file,
                v.span(),
                "unsupported-variadic",
                "variadic functions are not supported",
            ));
        }
        if let Some(abi) = &sig.abi {
            let c_abi = abi.name.as_ref().is_none_or(|n| n.value() == "C");
            let kernel =
                self.p.modules[module].crate_root == self.p.modules[self.p.kernel_root].crate_root;
            if !(c_abi
                && parent == FnParent::Free
                && kernel
                && sig.generics.params.is_empty()
                && has_no_mangle(self.p.fns[id].attrs))
            {
                return Err(self.err(
                    file,
                    abi.span(),
                    "unsupported-extern-fn",
                    "TRaX-Rust supports `extern` only as `#[no_mangle] extern \"C\" fn` (a non-generic free function of the kernel that C code calls)",
                ));
            }
        }
        let mut params = Vec::new();
        let mut receiver = None;
        for arg in sig.inputs.iter() {
            match arg {
                FnArg::Receiver(r) => {
                    let Some(st) = &self_ty else {
                        return Err(self.err(
                            file,
                            r.span(),
                            "self-outside-impl",
                            "`self` parameter outside an impl block",
                        ));
                    };
                    let (kind, ty) = match &r.kind {
                        syn::ReceiverKind::Value => (Recv::Value, st.clone()),
                        syn::ReceiverKind::Reference(_, _, None) => {
                            (Recv::Ref, Ty::Ref(false, Box::new(st.clone())))
                        }
                        syn::ReceiverKind::Reference(_, _, Some(_)) => {
                            (Recv::RefMut, Ty::Ref(true, Box::new(st.clone())))
                        }
                        syn::ReceiverKind::Typed(_, t) => {
                            let ty = self.p.resolve_type(module, file, t, &scope)?;
                            let kind = match &ty {
                                t if t == st => Recv::Value,
                                Ty::Ref(false, t) if **t == *st => Recv::Ref,
                                Ty::Ref(true, t) if **t == *st => Recv::RefMut,
                                _ => return Err(self.err(
                                    file,
                                    r.span(),
                                    "unsupported-receiver",
                                    "only `self`, `&self` and `&mut self` receivers are supported",
                                )),
                            };
                            (kind, ty)
                        }
                        _ => {
                            return Err(self.err(
                                file,
                                r.span(),
                                "unsupported-receiver",
                                "only `self`, `&self` and `&mut self` receivers are supported",
                            ))
                        }
                    };
                    receiver = Some(kind);
                    params.push(ty);
                }
                FnArg::Typed(pt) => {
                    check_param_pat(&self.p, file, &pt.pat)?;
                    let t = self.p.resolve_type(module, file, &pt.ty, &scope)?;
                    if contains_infer(&t) {
                        return Err(self.err(
                            file,
                            pt.ty.span(),
                            "unsupported-infer-type",
                            "`_` is not allowed in function signatures",
                        ));
                    }
                    params.push(t);
                }
            }
        }
        let ret = match &sig.output {
            ReturnType::Default => Ty::Unit,
            ReturnType::Type(_, t) => {
                let t2 = self.p.resolve_type(module, file, t, &scope)?;
                if contains_infer(&t2) {
                    return Err(self.err(
                        file,
                        t.span(),
                        "unsupported-infer-type",
                        "`_` is not allowed in function signatures",
                    ));
                }
                t2
            }
        };
        if sig.abi.is_some() || self.p.fns[id].foreign {
            // C passes scalars and pointers the same way; aggregates and slices it does not.
            let spans = sig.inputs.iter().map(|a| a.span());
            let ret_span = match &sig.output {
                ReturnType::Type(_, t) => t.span(),
                ReturnType::Default => sig.ident.span(),
            };
            for (t, span) in params.iter().zip(spans).chain([(&ret, ret_span)]) {
                if !c_compatible(t) {
                    return Err(self.err(
                        file,
                        span,
                        "unsupported-extern-fn",
                        format!(
                            "`extern \"C\"` functions take and return integers, `bool`, floats and pointers or references to sized values (pass structs and slices by pointer); `{}` is not one",
                            self.p.ty_str(t)
                        ),
                    ));
                }
            }
        }
        let mut inline = InlineHint::None;
        for a in self.p.fns[id]
            .attrs
            .iter()
            .filter(|a| a.path().is_ident("inline"))
        {
            inline = match &a.meta {
                Meta::Path(_) => InlineHint::Hint,
                Meta::List(l) => match l.tokens.to_string().as_str() {
                    "always" => InlineHint::Always,
                    "never" => InlineHint::Never,
                    _ => {
                        return Err(self.err(
                            file,
                            a.span(),
                            "invalid-inline",
                            "expected `#[inline]`, `#[inline(always)]` or `#[inline(never)]`",
                        ))
                    }
                },
                Meta::NameValue(_) => {
                    return Err(self.err(file, a.span(), "invalid-inline", "malformed `#[inline]`"))
                }
            };
        }
        let f = &mut self.p.fns[id];
        f.params = params;
        f.ret = ret;
        f.receiver = receiver;
        f.inline = inline;
        f.generics.bounds = bounds;
        Ok(())
    }

    fn resolve_global(&mut self, g: usize) -> DResult<()> {
        let gd = &self.p.globals[g];
        let impl_types = self
            .p
            .impls
            .iter()
            .find(|im| im.consts.values().any(|x| *x == g))
            .map(|im| im.types.clone());
        let in_trait = self
            .p
            .traits
            .iter()
            .position(|t| t.consts.iter().any(|(_, x)| *x == g));
        let scope = TyScope {
            self_ty: gd.self_ty.as_ref(),
            params: &gd.generics.names,
            impl_types: impl_types.as_ref(),
            in_trait,
        };
        let t = self
            .p
            .resolve_type(gd.module, gd.file, gd.decl_ty, &scope)?;
        if contains_infer(&t) {
            return Err(self.err(
                gd.file,
                gd.ty_span,
                "unsupported-infer-type",
                "`_` is not allowed in the type of a const or static",
            ));
        }
        self.p.globals[g].ty = t;
        Ok(())
    }
}

fn contains_infer(t: &Ty) -> bool {
    let mut found = false;
    t.map(&mut |x| {
        if matches!(x, Ty::Infer) {
            found = true;
        }
        None
    });
    found
}

/// Parameter patterns: identifiers, `_`, and irrefutable destructuring.
fn check_param_pat(p: &Program, file: FileId, pat: &Pat) -> DResult<()> {
    match pat {
        Pat::Ident(pi) if pi.subpat.is_none() => Ok(()),
        Pat::Wild(_) => Ok(()),
        Pat::Tuple(t) => t.elems.iter().try_for_each(|e| check_param_pat(p, file, e)),
        Pat::Struct(s) => s
            .fields
            .iter()
            .try_for_each(|f| check_param_pat(p, file, &f.pat)),
        Pat::TupleStruct(s) => s.elems.iter().try_for_each(|e| check_param_pat(p, file, e)),
        Pat::Reference(r) => check_param_pat(p, file, &r.pat),
        Pat::Slice(s) => s.elems.iter().try_for_each(|e| check_param_pat(p, file, e)),
        Pat::Rest(_) => Ok(()),
        Pat::Paren(x) => check_param_pat(p, file, &x.pat),
        other => Err(p.err(
            file,
            other.span(),
            "unsupported-pattern",
            "this pattern is not supported as a parameter",
        )),
    }
}

/// Whether `#[no_mangle]` is among `attrs`.
fn has_no_mangle(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| a.path().is_ident("no_mangle"))
}

/// Whether `t` has a C counterpart passed the same way: integers (with clang's
/// extension attributes, see `Lowerer::c_abi_attributes`), `bool`, floats, the unit
/// return, and pointers or references to sized values. Aggregates by value, slices,
/// `str`, `char` and `!` do not.
fn c_compatible(t: &Ty) -> bool {
    match t {
        Ty::Unit | Ty::Float(_) | Ty::Bool | Ty::Int(_) => true,
        Ty::Ref(_, e) | Ty::Ptr(_, e) => !matches!(**e, Ty::Slice(_) | Ty::Str),
        _ => false,
    }
}
