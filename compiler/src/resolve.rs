//! Stage 2: collect items of the kernel and prelude crates into a [`Program`], resolve
//! paths (modules, `use`, `crate`/`self`/`super`/`trax`/`std`), struct fields, function
//! signatures and operator-trait impls. Rejects items outside the TRaX-Rust subset.

use crate::diag::{DResult, Diagnostic, FileId, SourceMap};
use crate::parse::{cfg_enabled, ParsedCrate};
use crate::ty::{FloatTy, IntTy, SimdTy, StructId, Ty, TyDisplay};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::spanned::Spanned;
use syn::{Attribute, Block, Expr, FnArg, ImplItem, Item, Meta, Pat, ReturnType, Signature, Type};

/// Index of a module.
pub type ModId = usize;
/// Index of a function.
pub type FnId = usize;
/// Index of a `const` or `static`.
pub type GlobalId = usize;

/// Overloadable operator traits of `std::ops`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OpTrait {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Neg,
    AddAssign,
    SubAssign,
    MulAssign,
    DivAssign,
    RemAssign,
}

impl OpTrait {
    fn from_name(s: &str) -> Option<OpTrait> {
        Some(match s {
            "Add" => OpTrait::Add,
            "Sub" => OpTrait::Sub,
            "Mul" => OpTrait::Mul,
            "Div" => OpTrait::Div,
            "Rem" => OpTrait::Rem,
            "Neg" => OpTrait::Neg,
            "AddAssign" => OpTrait::AddAssign,
            "SubAssign" => OpTrait::SubAssign,
            "MulAssign" => OpTrait::MulAssign,
            "DivAssign" => OpTrait::DivAssign,
            "RemAssign" => OpTrait::RemAssign,
            _ => return None,
        })
    }

    /// The method name the trait requires.
    pub fn method(self) -> &'static str {
        match self {
            OpTrait::Add => "add",
            OpTrait::Sub => "sub",
            OpTrait::Mul => "mul",
            OpTrait::Div => "div",
            OpTrait::Rem => "rem",
            OpTrait::Neg => "neg",
            OpTrait::AddAssign => "add_assign",
            OpTrait::SubAssign => "sub_assign",
            OpTrait::MulAssign => "mul_assign",
            OpTrait::DivAssign => "div_assign",
            OpTrait::RemAssign => "rem_assign",
        }
    }

    /// True for the compound-assignment traits.
    pub fn is_assign(self) -> bool {
        matches!(
            self,
            OpTrait::AddAssign
                | OpTrait::SubAssign
                | OpTrait::MulAssign
                | OpTrait::DivAssign
                | OpTrait::RemAssign
        )
    }
}

/// What a path names.
#[derive(Clone, Debug, PartialEq)]
pub enum PathRes {
    Mod(ModId),
    Struct(StructId),
    Simd(SimdTy),
    Prim(Ty),
    OpTrait(OpTrait),
    Fn(FnId),
    Global(GlobalId),
    /// `Type::name` where the type is builtin (`f32::MAX`, `f32x4::splat`).
    PrimAssoc(Ty, String),
    /// `std::f32::consts::PI` and friends.
    FloatConst(FloatTy, String),
    /// `std::ptr::read_volatile` and friends.
    StdFn(String),
}

/// Which namespace a path's last segment is looked up in.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Ns {
    Type,
    Value,
}

/// A `use` declaration (one leaf of a use tree).
#[derive(Clone, Debug)]
pub struct UseDecl {
    /// Path segments.
    pub segs: Vec<String>,
    /// Bound name (`None` for a glob import).
    pub name: Option<String>,
    /// Span for errors.
    pub span: Span,
}

/// A module.
pub struct Module {
    /// Display path (`crate::a::b` style, with the crate's name first).
    pub path: String,
    /// Parent module.
    pub parent: Option<ModId>,
    /// File holding the module's items.
    pub file: FileId,
    /// Root module of its crate.
    pub crate_root: ModId,
    types: HashMap<String, PathRes>,
    values: HashMap<String, PathRes>,
    uses: Vec<UseDecl>,
}

/// A struct definition.
pub struct StructDef<'a> {
    /// Name.
    pub name: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// The item.
    pub item: &'a syn::ItemStruct,
    /// Fields in declaration order (layout order, like `repr(C)`).
    pub fields: Vec<(String, Ty)>,
}

/// How a method takes `self`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recv {
    Value,
    Ref,
    RefMut,
}

/// Inlining hint from `#[inline]` attributes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InlineHint {
    None,
    Hint,
    Always,
    Never,
}

/// A function or method with a body.
pub struct FnDef<'a> {
    /// Name for DWARF and messages (`Vec3::dot` for methods).
    pub name: String,
    /// Unique symbol name.
    pub symbol: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Signature.
    pub sig: &'a Signature,
    /// Body.
    pub body: &'a Block,
    /// `Self` type for methods and associated functions.
    pub self_ty: Option<Ty>,
    /// Receiver kind for methods.
    pub receiver: Option<Recv>,
    /// Parameter types, `self` first for methods.
    pub params: Vec<Ty>,
    /// Return type.
    pub ret: Ty,
    /// Inline hint.
    pub inline: InlineHint,
}

/// A `const` or `static`.
pub struct GlobalDef<'a> {
    /// Name.
    pub name: String,
    /// Unique symbol name.
    pub symbol: String,
    /// Defining module.
    pub module: ModId,
    /// Defining file.
    pub file: FileId,
    /// Declared type.
    pub ty: Ty,
    /// Initializer.
    pub expr: &'a Expr,
    /// `None` for `const`, `Some(mutable)` for `static`.
    pub is_static: Option<bool>,
    /// `Self` type for associated consts.
    pub self_ty: Option<Ty>,
    /// Type syntax (for errors).
    pub ty_span: Span,
    /// Declared type syntax.
    pub decl_ty: &'a Type,
}

/// An `impl std::ops::Trait<Rhs> for Lhs`.
#[derive(Clone, Debug)]
pub struct OpImpl {
    /// Trait.
    pub op: OpTrait,
    /// `Self`.
    pub lhs: Ty,
    /// Right operand type (`Self` for `Neg`).
    pub rhs: Ty,
    /// The implementing method.
    pub func: FnId,
}

/// The whole program after name collection.
pub struct Program<'a> {
    /// Source files.
    pub sources: &'a SourceMap,
    /// Modules.
    pub modules: Vec<Module>,
    /// Structs.
    pub structs: Vec<StructDef<'a>>,
    /// Functions.
    pub fns: Vec<FnDef<'a>>,
    /// Consts and statics.
    pub globals: Vec<GlobalDef<'a>>,
    /// Operator impls.
    pub op_impls: Vec<OpImpl>,
    /// Inherent associated items per struct: name → fn or const.
    pub inherent: HashMap<StructId, HashMap<String, PathRes>>,
    /// Kernel crate root.
    pub kernel_root: ModId,
    /// Prelude crate root.
    pub trax_root: Option<ModId>,
}

struct PendingImpl<'a> {
    module: ModId,
    item: &'a syn::ItemImpl,
}

struct PendingFn<'a> {
    id: FnId,
    module: ModId,
    self_ty: Option<Ty>,
    attrs: &'a [Attribute],
}

/// Builds the program from the parsed kernel crate and (optionally) the prelude crate.
pub fn collect<'a>(
    sources: &'a SourceMap,
    kernel: &'a ParsedCrate,
    kernel_name: &str,
    prelude: Option<&'a ParsedCrate>,
) -> Result<Program<'a>, Vec<Diagnostic>> {
    let mut p = Program {
        sources,
        modules: Vec::new(),
        structs: Vec::new(),
        fns: Vec::new(),
        globals: Vec::new(),
        op_impls: Vec::new(),
        inherent: HashMap::new(),
        kernel_root: 0,
        trax_root: None,
    };
    let mut errs = Vec::new();
    let mut impls = Vec::new();
    let mut fns = Vec::new();
    let k_items = &kernel.files[&kernel.root].items;
    p.kernel_root = p.add_module(kernel_name.to_string(), None, kernel.root, None);
    p.walk(
        kernel,
        p.kernel_root,
        kernel.root,
        k_items,
        &mut impls,
        &mut fns,
        &mut errs,
    );
    if let Some(pre) = prelude {
        let root = p.add_module("trax".into(), None, pre.root, None);
        p.trax_root = Some(root);
        p.walk(
            pre,
            root,
            pre.root,
            &pre.files[&pre.root].items,
            &mut impls,
            &mut fns,
            &mut errs,
        );
    }
    // Builtin `trax::simd` module on the TRaX side.
    let simd_parent = p.trax_root.unwrap_or(p.kernel_root);
    if !p.modules[simd_parent].types.contains_key("simd") {
        let file = p.modules[simd_parent].file;
        let m = p.add_module("simd".into(), Some(simd_parent), file, None);
        p.modules[m]
            .types
            .insert("f32x4".into(), PathRes::Simd(SimdTy::F32x4));
        p.modules[m]
            .types
            .insert("i32x4".into(), PathRes::Simd(SimdTy::I32x4));
        p.modules[simd_parent]
            .types
            .insert("simd".into(), PathRes::Mod(m));
    }
    // Struct fields.
    for sid in 0..p.structs.len() {
        let s = &p.structs[sid];
        let (module, file, item) = (s.module, s.file, s.item);
        let mut fields = Vec::new();
        match &item.fields {
            syn::Fields::Named(n) => {
                for f in &n.named {
                    match p.resolve_type(module, file, &f.ty, None) {
                        Ok(t) => fields.push((
                            f.ident.as_ref().map(|i| i.to_string()).unwrap_or_default(),
                            t,
                        )),
                        Err(e) => errs.push(e),
                    }
                }
            }
            syn::Fields::Unit => {}
            syn::Fields::Unnamed(u) => errs.push(p.err(
                file,
                u.span(),
                "unsupported-tuple-struct",
                "tuple structs are not supported in TRaX-Rust; use named fields",
            )),
        }
        p.structs[sid].fields = fields;
    }
    if let Err(e) = p.check_recursive_structs() {
        errs.push(e);
    }
    for im in impls {
        if let Err(e) = p.collect_impl(im, &mut fns) {
            errs.push(e);
        }
    }
    for pf in fns {
        if let Err(e) = p.resolve_sig(pf) {
            errs.push(e);
        }
    }
    for g in 0..p.globals.len() {
        let gd = &p.globals[g];
        match p.resolve_type(gd.module, gd.file, gd.decl_ty, gd.self_ty.as_ref()) {
            Ok(t) => p.globals[g].ty = t,
            Err(e) => errs.push(e),
        }
    }
    if errs.is_empty() {
        Ok(p)
    } else {
        Err(errs)
    }
}

impl Module {
    /// A value-namespace item defined directly in this module.
    pub fn values_get(&self, name: &str) -> Option<PathRes> {
        self.values.get(name).cloned()
    }
}

impl<'a> Program<'a> {
    fn add_module(
        &mut self,
        name: String,
        parent: Option<ModId>,
        file: FileId,
        root: Option<ModId>,
    ) -> ModId {
        let id = self.modules.len();
        let path = match parent {
            Some(pm) => format!("{}::{name}", self.modules[pm].path),
            None => name,
        };
        self.modules.push(Module {
            path,
            parent,
            file,
            crate_root: root.unwrap_or(id),
            types: HashMap::new(),
            values: HashMap::new(),
            uses: Vec::new(),
        });
        id
    }

    /// Creates a diagnostic.
    pub fn err(
        &self,
        file: FileId,
        span: Span,
        id: &'static str,
        msg: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic::new(self.sources, file, span, id, msg)
    }

    /// Display string of a type.
    pub fn ty_str(&self, t: &Ty) -> String {
        let names = |s: StructId| self.structs[s].name.clone();
        TyDisplay {
            ty: t,
            names: &names,
        }
        .to_string()
    }

    #[allow(clippy::too_many_arguments)]
    fn walk(
        &mut self,
        pc: &'a ParsedCrate,
        module: ModId,
        file: FileId,
        items: &'a [Item],
        impls: &mut Vec<PendingImpl<'a>>,
        fns: &mut Vec<PendingFn<'a>>,
        errs: &mut Vec<Diagnostic>,
    ) {
        for item in items {
            if let Err(e) = self.walk_item(pc, module, file, item, impls, fns, errs) {
                errs.push(e);
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn walk_item(
        &mut self,
        pc: &'a ParsedCrate,
        module: ModId,
        file: FileId,
        item: &'a Item,
        impls: &mut Vec<PendingImpl<'a>>,
        fns: &mut Vec<PendingFn<'a>>,
        errs: &mut Vec<Diagnostic>,
    ) -> DResult<()> {
        let attrs: &[Attribute] = match item {
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
        };
        if !cfg_enabled(attrs) || attrs.iter().any(|a| a.path().is_ident("test")) {
            return Ok(());
        }
        self.check_attrs(file, attrs)?;
        let root = self.modules[module].crate_root;
        match item {
            Item::Fn(f) => {
                no_generics(self, file, &f.sig.generics, "generic functions")?;
                let id = self.fns.len();
                let name = f.sig.ident.to_string();
                let symbol = if name == "trax_main" && module == self.kernel_root {
                    name.clone()
                } else {
                    format!("{}::{name}", self.modules[module].path)
                };
                self.fns.push(FnDef {
                    name: name.clone(),
                    symbol,
                    module,
                    file,
                    sig: &f.sig,
                    body: &f.block,
                    self_ty: None,
                    receiver: None,
                    params: Vec::new(),
                    ret: Ty::Unit,
                    inline: InlineHint::None,
                });
                fns.push(PendingFn {
                    id,
                    module,
                    self_ty: None,
                    attrs: &f.attrs,
                });
                self.define(module, file, &f.sig.ident, Ns::Value, PathRes::Fn(id))?;
            }
            Item::Struct(s) => {
                no_generics(self, file, &s.generics, "generic structs")?;
                self.check_derive(file, &s.attrs)?;
                let id = self.structs.len();
                self.structs.push(StructDef {
                    name: s.ident.to_string(),
                    module,
                    file,
                    item: s,
                    fields: Vec::new(),
                });
                self.define(module, file, &s.ident, Ns::Type, PathRes::Struct(id))?;
                if matches!(s.fields, syn::Fields::Unit) {
                    self.define(module, file, &s.ident, Ns::Value, PathRes::Struct(id))?;
                }
            }
            Item::Const(c) => {
                no_generics(self, file, &c.generics, "generic consts")?;
                let id = self.add_global(module, file, &c.ident, &c.ty, &c.expr, None, None)?;
                self.define(module, file, &c.ident, Ns::Value, PathRes::Global(id))?;
            }
            Item::Static(s) => {
                let m = matches!(s.mutability, syn::StaticMutability::Mut(_));
                let id = self.add_global(module, file, &s.ident, &s.ty, &s.expr, Some(m), None)?;
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
                let id = self.add_module(m.ident.to_string(), Some(module), child_file, Some(root));
                self.define(module, file, &m.ident, Ns::Type, PathRes::Mod(id))?;
                self.walk(pc, id, child_file, items, impls, fns, errs);
            }
            Item::Use(u) => {
                let mut out = Vec::new();
                flatten_use(&u.tree, &mut Vec::new(), &mut out);
                self.modules[module].uses.extend(out);
            }
            Item::Impl(i) => impls.push(PendingImpl { module, item: i }),
            Item::Enum(e) => {
                return Err(self.err(
                    file,
                    e.ident.span(),
                    "unsupported-enum",
                    "enums are not supported in TRaX-Rust (use integer constants)",
                ))
            }
            Item::Trait(t) => {
                return Err(self.err(
                    file,
                    t.ident.span(),
                    "unsupported-trait",
                    "trait definitions are not supported in TRaX-Rust",
                ))
            }
            Item::Type(t) => {
                return Err(self.err(
                    file,
                    t.ident.span(),
                    "unsupported-type-alias",
                    "type aliases are not supported in TRaX-Rust",
                ))
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
                return Err(self.err(
                    file,
                    e.span(),
                    "unsupported-extern-block",
                    "`extern` blocks are not supported in TRaX-Rust",
                ))
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

    #[allow(clippy::too_many_arguments)]
    fn add_global(
        &mut self,
        module: ModId,
        file: FileId,
        ident: &syn::Ident,
        ty: &'a Type,
        expr: &'a Expr,
        is_static: Option<bool>,
        self_ty: Option<Ty>,
    ) -> DResult<GlobalId> {
        let id = self.globals.len();
        let prefix = match &self_ty {
            Some(t) => format!("{}::{}", self.modules[module].path, self.ty_str(t)),
            None => self.modules[module].path.clone(),
        };
        self.globals.push(GlobalDef {
            name: ident.to_string(),
            symbol: format!("{prefix}::{ident}"),
            module,
            file,
            ty: Ty::Unit,
            decl_ty: ty,
            expr,
            is_static,
            self_ty,
            ty_span: ty.span(),
        });
        Ok(id)
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
            Ns::Type => &mut self.modules[module].types,
            Ns::Value => &mut self.modules[module].values,
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

    fn check_derive(&self, file: FileId, attrs: &[Attribute]) -> DResult<()> {
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
                if !matches!(n.as_str(), "Clone" | "Copy" | "Debug") {
                    return Err(self.err(file, p.span(), "unsupported-derive", format!("`#[derive({n})]` is not supported in TRaX-Rust (only Clone, Copy, Debug)")));
                }
            }
        }
        Ok(())
    }

    fn check_recursive_structs(&self) -> DResult<()> {
        fn contains(p: &Program, t: &Ty, target: StructId, depth: usize) -> bool {
            if depth > 64 {
                return true;
            }
            match t {
                Ty::Struct(s) => {
                    *s == target
                        || p.structs[*s]
                            .fields
                            .iter()
                            .any(|(_, f)| contains(p, f, target, depth + 1))
                }
                Ty::Array(e, _) => contains(p, e, target, depth + 1),
                _ => false,
            }
        }
        for (i, s) in self.structs.iter().enumerate() {
            if s.fields.iter().any(|(_, f)| contains(self, f, i, 0)) {
                return Err(self.err(
                    s.file,
                    s.item.ident.span(),
                    "recursive-struct",
                    format!("struct `{}` contains itself (use a raw pointer)", s.name),
                ));
            }
        }
        Ok(())
    }

    fn collect_impl(&mut self, im: PendingImpl<'a>, fns: &mut Vec<PendingFn<'a>>) -> DResult<()> {
        let item = im.item;
        let module = im.module;
        let file = self.modules[module].file;
        no_generics(self, file, &item.generics, "generic impl blocks")?;
        let self_ty = self.resolve_type(module, file, &item.self_ty, None)?;
        let sid = match &self_ty {
            Ty::Struct(s) => Some(*s),
            _ => None,
        };
        let type_name = self.ty_str(&self_ty);
        let mut op = None;
        if let Some((path, _)) = &item.trait_ {
            let last = path.segments.last().expect("paths are non-empty");
            let res = self.resolve_path_segs(module, file, &path_segs(path), Ns::Type, path.span());
            match res {
                Ok(PathRes::OpTrait(t)) => {
                    let rhs = match &last.arguments {
                        syn::PathArguments::None => self_ty.clone(),
                        syn::PathArguments::AngleBracketed(a) if a.args.len() == 1 => match &a.args[0] {
                            syn::GenericArgument::Type(t) => self.resolve_type(module, file, t, Some(&self_ty))?,
                            other => return Err(self.err(file, other.span(), "unsupported-generics", "unsupported generic argument")),
                        },
                        other => return Err(self.err(file, other.span(), "unsupported-generics", "unsupported trait arguments")),
                    };
                    op = Some((t, rhs));
                }
                _ => {
                    return Err(self.err(
                        file,
                        path.span(),
                        "unsupported-trait-impl",
                        format!("implementing trait `{}` is not supported in TRaX-Rust (only std::ops operator traits)", last.ident),
                    ))
                }
            }
            if sid.is_none() && !matches!(self_ty, Ty::Float(_) | Ty::Int(_)) {
                return Err(self.err(
                    file,
                    item.self_ty.span(),
                    "unsupported-impl",
                    format!(
                        "operator impls are supported for structs and numbers, not `{type_name}`"
                    ),
                ));
            }
        } else if sid.is_none() {
            return Err(self.err(
                file,
                item.self_ty.span(),
                "unsupported-impl",
                format!("inherent impl blocks are only supported for structs, not `{type_name}`"),
            ));
        }
        let mut op_fn = None;
        for ii in &item.items {
            match ii {
                ImplItem::Fn(f) => {
                    if !cfg_enabled(&f.attrs) {
                        continue;
                    }
                    self.check_attrs(file, &f.attrs)?;
                    no_generics(self, file, &f.sig.generics, "generic methods")?;
                    let id = self.fns.len();
                    let name = format!("{type_name}::{}", f.sig.ident);
                    let symbol = match &op {
                        Some((t, rhs)) => format!(
                            "{}::<{type_name} as {t:?}<{}>>::{}",
                            self.modules[module].path,
                            self.ty_str(rhs),
                            f.sig.ident
                        ),
                        None => format!("{}::{name}", self.modules[module].path),
                    };
                    self.fns.push(FnDef {
                        name,
                        symbol,
                        module,
                        file,
                        sig: &f.sig,
                        body: &f.block,
                        self_ty: Some(self_ty.clone()),
                        receiver: None,
                        params: Vec::new(),
                        ret: Ty::Unit,
                        inline: InlineHint::None,
                    });
                    fns.push(PendingFn {
                        id,
                        module,
                        self_ty: Some(self_ty.clone()),
                        attrs: &f.attrs,
                    });
                    match (&op, sid) {
                        (Some((t, _)), _) => {
                            if f.sig.ident != t.method() {
                                return Err(self.err(file, f.sig.ident.span(), "unknown-trait-method", format!("`{}` is not a method of the operator trait (expected `{}`)", f.sig.ident, t.method())));
                            }
                            op_fn = Some(id);
                        }
                        (None, Some(s)) => {
                            let map = self.inherent.entry(s).or_default();
                            if map
                                .insert(f.sig.ident.to_string(), PathRes::Fn(id))
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
                        (None, None) => unreachable!("checked above"),
                    }
                }
                ImplItem::Const(c) if op.is_none() => {
                    let g = self.add_global(
                        module,
                        file,
                        &c.ident,
                        &c.ty,
                        &c.expr,
                        None,
                        Some(self_ty.clone()),
                    )?;
                    let s = sid.expect("inherent impls are on structs");
                    self.inherent
                        .entry(s)
                        .or_default()
                        .insert(c.ident.to_string(), PathRes::Global(g));
                }
                ImplItem::Type(t) if op.is_some() && t.ident == "Output" => {
                    // The output type is taken from the method's return type.
                }
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
        if let Some((t, rhs)) = op {
            let Some(func) = op_fn else {
                return Err(self.err(
                    file,
                    item.span(),
                    "missing-trait-method",
                    format!("missing method `{}` in operator impl", t.method()),
                ));
            };
            self.op_impls.push(OpImpl {
                op: t,
                lhs: self_ty,
                rhs,
                func,
            });
        }
        Ok(())
    }

    fn resolve_sig(&mut self, pf: PendingFn<'a>) -> DResult<()> {
        let file = self.modules[pf.module].file;
        let sig = self.fns[pf.id].sig;
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
            return Err(self.err(
                file,
                abi.span(),
                "unsupported-extern-fn",
                "`extern` functions are not supported in TRaX-Rust",
            ));
        }
        let mut params = Vec::new();
        let mut receiver = None;
        for (i, arg) in sig.inputs.iter().enumerate() {
            match arg {
                FnArg::Receiver(r) => {
                    let Some(st) = &pf.self_ty else {
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
                        _ => {
                            return Err(self.err(
                                file,
                                r.span(),
                                "unsupported-receiver",
                                "only `self`, `&self` and `&mut self` receivers are supported",
                            ))
                        }
                    };
                    debug_assert_eq!(i, 0);
                    receiver = Some(kind);
                    params.push(ty);
                }
                FnArg::Typed(pt) => {
                    match &*pt.pat {
                        Pat::Ident(pi) if pi.subpat.is_none() && pi.by_ref.is_none() => {}
                        Pat::Wild(_) => {}
                        other => {
                            return Err(self.err(
                                file,
                                other.span(),
                                "unsupported-pattern",
                                "only plain identifiers are supported as parameter patterns",
                            ))
                        }
                    }
                    params.push(self.resolve_type(pf.module, file, &pt.ty, pf.self_ty.as_ref())?);
                }
            }
        }
        let ret = match &sig.output {
            ReturnType::Default => Ty::Unit,
            ReturnType::Type(_, t) => self.resolve_type(pf.module, file, t, pf.self_ty.as_ref())?,
        };
        let mut inline = InlineHint::None;
        for a in pf.attrs.iter().filter(|a| a.path().is_ident("inline")) {
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
        let f = &mut self.fns[pf.id];
        f.params = params;
        f.ret = ret;
        f.receiver = receiver;
        f.inline = inline;
        Ok(())
    }

    /// Resolves a syntactic type in `module`.
    pub fn resolve_type(
        &self,
        module: ModId,
        file: FileId,
        ty: &Type,
        self_ty: Option<&Ty>,
    ) -> DResult<Ty> {
        match ty {
            Type::Paren(p) => self.resolve_type(module, file, &p.elem, self_ty),
            Type::Group(g) => self.resolve_type(module, file, &g.elem, self_ty),
            Type::Never(_) => Ok(Ty::Never),
            Type::Tuple(t) if t.elems.is_empty() => Ok(Ty::Unit),
            Type::Tuple(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-tuple",
                "tuple types are not supported in TRaX-Rust",
            )),
            Type::Array(a) => {
                let elem = self.resolve_type(module, file, &a.elem, self_ty)?;
                let n = self.eval_len(module, file, &a.len)?;
                if !(0..=(1 << 24)).contains(&n) {
                    return Err(self.err(
                        file,
                        a.len.span(),
                        "invalid-array-length",
                        format!("array length {n} is out of range"),
                    ));
                }
                Ok(Ty::Array(Box::new(elem), n as u32))
            }
            Type::Reference(r) => {
                if let Type::Path(tp) = &*r.elem {
                    if tp.path.is_ident("str") {
                        return Ok(Ty::Str);
                    }
                }
                Ok(Ty::Ref(
                    r.mutability.is_some(),
                    Box::new(self.resolve_type(module, file, &r.elem, self_ty)?),
                ))
            }
            Type::Ptr(p) => Ok(Ty::Ptr(
                matches!(p.mutability, syn::PointerMutability::Mut(_)),
                Box::new(self.resolve_type(module, file, &p.elem, self_ty)?),
            )),
            Type::Path(tp) => {
                if tp.qself.is_some() {
                    return Err(self.err(
                        file,
                        tp.span(),
                        "unsupported-qualified-path",
                        "qualified paths (`<T as Trait>::X`) are not supported",
                    ));
                }
                for s in &tp.path.segments {
                    let heap = [
                        "Vec", "String", "Box", "Rc", "Arc", "HashMap", "Option", "Result",
                    ];
                    if heap.iter().any(|h| s.ident == h) && tp.path.segments.len() == 1 {
                        let what = if matches!(s.ident.to_string().as_str(), "Option" | "Result") {
                            "enums"
                        } else {
                            "heap types"
                        };
                        return Err(self.err(
                            file,
                            tp.span(),
                            "unsupported-heap-type",
                            format!(
                                "`{}` is not supported in TRaX-Rust ({what} are not available)",
                                s.ident
                            ),
                        ));
                    }
                    if !matches!(s.arguments, syn::PathArguments::None) {
                        return Err(self.err(
                            file,
                            s.arguments.span(),
                            "unsupported-generics",
                            format!(
                                "generic type arguments are not supported in TRaX-Rust (`{}<...>`)",
                                s.ident
                            ),
                        ));
                    }
                }
                if tp.path.is_ident("Self") {
                    return self_ty.cloned().ok_or_else(|| {
                        self.err(
                            file,
                            tp.span(),
                            "self-outside-impl",
                            "`Self` outside an impl block",
                        )
                    });
                }
                let segs = path_segs(&tp.path);
                match self.resolve_path_segs(module, file, &segs, Ns::Type, tp.span()) {
                    Ok(PathRes::Struct(s)) => Ok(Ty::Struct(s)),
                    Ok(PathRes::Prim(t)) => Ok(t),
                    Ok(PathRes::Simd(s)) => Ok(Ty::Simd(s)),
                    Ok(_) => Err(self.err(
                        file,
                        tp.span(),
                        "not-a-type",
                        format!("`{}` is not a type", segs.join("::")),
                    )),
                    Err(_) => {
                        let name = segs.join("::");
                        let hint = match segs.last().map(String::as_str) {
                            Some("String" | "Vec" | "Box" | "Rc" | "Arc" | "HashMap") => {
                                " (heap types are not supported in TRaX-Rust)"
                            }
                            Some("Option" | "Result") => " (enums are not supported in TRaX-Rust)",
                            _ => "",
                        };
                        Err(self.err(
                            file,
                            tp.span(),
                            "unknown-type",
                            format!("unknown type `{name}`{hint}"),
                        ))
                    }
                }
            }
            Type::Slice(s) => Err(self.err(
                file,
                s.span(),
                "unsupported-slice",
                "slice types are not supported in TRaX-Rust; use arrays `[T; N]`",
            )),
            Type::TraitObject(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-trait-object",
                "trait objects are not supported in TRaX-Rust",
            )),
            Type::ImplTrait(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-impl-trait",
                "`impl Trait` types are not supported in TRaX-Rust",
            )),
            Type::FnPtr(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-fn-pointer",
                "function pointers are not supported in TRaX-Rust",
            )),
            Type::Infer(t) => Err(self.err(
                file,
                t.span(),
                "unsupported-infer-type",
                "`_` types are not supported here; write the type",
            )),
            other => Err(self.err(
                file,
                other.span(),
                "unsupported-type",
                "this kind of type is not supported in TRaX-Rust",
            )),
        }
    }

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

    fn resolve_from(&self, module: ModId, segs: &[String], ns: Ns, depth: u32) -> Option<PathRes> {
        if depth > 16 || segs.is_empty() {
            return None;
        }
        let first = segs[0].as_str();
        let only = segs.len() == 1;
        let first_ns = if only { ns } else { Ns::Type };
        let mut cur = match first {
            "crate" => PathRes::Mod(self.modules[module].crate_root),
            "self" => PathRes::Mod(module),
            "super" => PathRes::Mod(self.modules[module].parent?),
            "std" | "core" => return resolve_std(&segs[1..], ns),
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
                    s => self.lookup(m, s, want, depth + 1)?,
                },
                PathRes::Struct(s) if last => self.inherent.get(&s)?.get(seg)?.clone(),
                PathRes::Simd(t) if last => PathRes::PrimAssoc(Ty::Simd(t), seg.clone()),
                PathRes::Prim(t) if last => PathRes::PrimAssoc(t, seg.clone()),
                _ => return None,
            };
        }
        Some(cur)
    }

    /// Looks a single name up in a module: its items, then its `use`s, then glob imports.
    fn lookup(&self, module: ModId, name: &str, ns: Ns, depth: u32) -> Option<PathRes> {
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
                if let Some(PathRes::Mod(g)) =
                    self.resolve_from(module, &u.segs, Ns::Type, depth + 1)
                {
                    if g != module {
                        if let Some(r) = self.lookup(g, name, ns, depth + 1) {
                            return Some(r);
                        }
                    }
                }
            }
        }
        None
    }

    /// Evaluates an array length: a `usize` constant expression, with rustc's const
    /// evaluation errors ("attempt to compute `3_usize - 4_usize`, which would overflow",
    /// "attempt to divide `1_usize` by zero") at the failing operation, which may be in a
    /// `const` the length names.
    pub fn eval_len(&self, module: ModId, file: FileId, e: &Expr) -> DResult<i128> {
        self.eval_typed(module, file, e, IntTy::Usize, "the array length", 0)
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
            Expr::Path(p) => match self.resolve_from(module, &path_segs(&p.path), Ns::Value, 0) {
                Some(PathRes::Global(g)) => match self.globals[g].decl_ty {
                    Type::Path(tp) => tp
                        .path
                        .get_ident()
                        .and_then(|i| IntTy::from_name(&i.to_string())),
                    _ => None,
                },
                Some(PathRes::PrimAssoc(Ty::Int(t), _)) => Some(t),
                _ => None,
            },
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
                use syn::BinOp::*;
                let op = match b.op {
                    Add(_) => "+",
                    Sub(_) => "-",
                    Mul(_) => "*",
                    Div(_) => "/",
                    Rem(_) => "%",
                    Shl(_) => "<<",
                    Shr(_) => ">>",
                    BitAnd(_) => "&",
                    BitOr(_) => "|",
                    BitXor(_) => "^",
                    _ => return Err(bad()),
                };
                let l = self.eval_typed(module, file, &b.left, t, what, depth + 1)?;
                let rt = if matches!(op, "<<" | ">>") {
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
                let segs = path_segs(&p.path);
                match self.resolve_from(module, &segs, Ns::Value, 0) {
                    Some(PathRes::Global(g)) if self.globals[g].is_static.is_none() => {
                        let gd = &self.globals[g];
                        let gt = self.natural_int_type(module, e).unwrap_or(t);
                        let name = format!("`{}`", gd.name);
                        self.eval_typed(gd.module, gd.file, gd.expr, gt, &name, depth + 1)
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
                let segs = path_segs(&p.path);
                match self.resolve_from(module, &segs, Ns::Value, 0) {
                    Some(PathRes::Global(g)) if self.globals[g].is_static.is_none() => {
                        let gd = &self.globals[g];
                        self.eval_int(gd.module, gd.file, gd.expr, depth + 1)
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
}

fn no_generics(p: &Program, file: FileId, g: &syn::Generics, what: &str) -> DResult<()> {
    if !g.params.is_empty() {
        return Err(p.err(
            file,
            g.params.span(),
            "unsupported-generics",
            format!("{what} are not supported in TRaX-Rust"),
        ));
    }
    if let Some(w) = &g.where_clause {
        return Err(p.err(
            file,
            w.span(),
            "unsupported-generics",
            "where clauses are not supported in TRaX-Rust",
        ));
    }
    Ok(())
}

fn flatten_use(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut Vec<UseDecl>) {
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

fn resolve_std(rest: &[String], ns: Ns) -> Option<PathRes> {
    let r: Vec<&str> = rest.iter().map(String::as_str).collect();
    match r.as_slice() {
        ["ops", t] if ns == Ns::Type => OpTrait::from_name(t).map(PathRes::OpTrait),
        ["ptr", f @ ("read" | "write" | "read_volatile" | "write_volatile" | "null" | "null_mut")]
            if ns == Ns::Value =>
        {
            Some(PathRes::StdFn(f.to_string()))
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
