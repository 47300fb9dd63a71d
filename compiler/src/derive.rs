//! `#[derive(PartialOrd)]`, expanded while parsing into the `impl PartialOrd` that Rust's
//! derive writes, so the rest of the compiler sees an ordinary impl: a struct's fields are
//! compared in declaration order with `partial_cmp` and the first result that is not
//! `Some(Equal)` is returned (`None` for a NaN field); enum values are ordered by variant
//! (by discriminant: declaration order, or the explicit values of a fieldless enum), then
//! by the fields of the variant. Type parameters get a `PartialOrd` bound, as rustc's
//! derive adds. The impl's tokens carry the span of the `PartialOrd` in the derive, so its
//! code is attributed to that line, and `#[automatically_derived]`: resolve leaves it out
//! without a diagnostic of its own when its header does not resolve (the type's own
//! diagnostics say why). The other derives are the compiler's own (resolve,
//! `typeck/traits.rs`, `lower/call.rs`).

use proc_macro2::{Group, Span, TokenStream, TokenTree};
use quote::{format_ident, quote};
use syn::punctuated::Punctuated;
use syn::visit_mut::VisitMut;
use syn::{Fields, Item, Stmt, Token};

use crate::diag::{DResult, Diagnostic, FileId, SourceMap};
use crate::parse::cfg_enabled;

/// Adds after every struct and enum of `file` that derives `PartialOrd` (at any depth:
/// modules, function bodies) its `impl PartialOrd`.
pub fn expand(file: &mut syn::File, sources: &SourceMap, id: FileId) -> DResult<()> {
    let mut v = Expander {
        sources,
        file: id,
        error: None,
    };
    v.visit_file_mut(file);
    match v.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct Expander<'s> {
    sources: &'s SourceMap,
    file: FileId,
    error: Option<Diagnostic>,
}

impl Expander<'_> {
    /// The derived impls for `items`, each placed after its type.
    fn expand_items(&mut self, items: &mut Vec<Item>) {
        if !items.iter().any(derives_partial_ord) {
            return;
        }
        let mut out = Vec::with_capacity(items.len() + 1);
        for item in items.drain(..) {
            let derived = self.derived(&item);
            out.push(item);
            out.extend(derived);
        }
        *items = out;
    }

    /// The derived impl of `item`, if it derives `PartialOrd`.
    fn derived(&mut self, item: &Item) -> Option<Item> {
        let span = partial_ord_span(item)?;
        match partial_ord_impl(item, span) {
            Ok(i) => Some(i),
            Err(message) => {
                if self.error.is_none() {
                    self.error = Some(Diagnostic::new(
                        self.sources,
                        self.file,
                        span,
                        "unsupported-derive",
                        message,
                    ));
                }
                None
            }
        }
    }
}

impl VisitMut for Expander<'_> {
    fn visit_file_mut(&mut self, f: &mut syn::File) {
        self.expand_items(&mut f.items);
        syn::visit_mut::visit_file_mut(self, f);
    }

    fn visit_item_mod_mut(&mut self, m: &mut syn::ItemMod) {
        if let Some((_, items)) = &mut m.content {
            self.expand_items(items);
        }
        syn::visit_mut::visit_item_mod_mut(self, m);
    }

    fn visit_block_mut(&mut self, b: &mut syn::Block) {
        if b.stmts
            .iter()
            .any(|s| matches!(s, Stmt::Item(i) if derives_partial_ord(i)))
        {
            let mut out = Vec::with_capacity(b.stmts.len() + 1);
            for s in b.stmts.drain(..) {
                let derived = match &s {
                    Stmt::Item(i) => self.derived(i),
                    _ => None,
                };
                out.push(s);
                out.extend(derived.map(Stmt::Item));
            }
            b.stmts = out;
        }
        syn::visit_mut::visit_block_mut(self, b);
    }
}

fn derives_partial_ord(item: &Item) -> bool {
    partial_ord_span(item).is_some()
}

/// The span of `PartialOrd` in the derive attribute of an enabled struct or enum.
fn partial_ord_span(item: &Item) -> Option<Span> {
    let attrs = match item {
        Item::Struct(s) => &s.attrs,
        Item::Enum(e) => &e.attrs,
        _ => return None,
    };
    if !cfg_enabled(attrs) {
        return None;
    }
    attrs
        .iter()
        .filter(|a| a.path().is_ident("derive"))
        .filter_map(|a| {
            a.parse_args_with(Punctuated::<syn::Path, Token![,]>::parse_terminated)
                .ok()
        })
        .flatten()
        .find(|p| p.segments.last().is_some_and(|s| s.ident == "PartialOrd"))
        .map(|p| syn::spanned::Spanned::span(&p))
}

/// `match a.partial_cmp(b) { Some(Equal) => {} c => return c }` for each pair.
fn chain(pairs: &[(TokenStream, TokenStream)]) -> TokenStream {
    let steps = pairs.iter().map(|(a, b)| {
        quote! {
            match (#a).partial_cmp(#b) {
                core::option::Option::Some(core::cmp::Ordering::Equal) => {}
                c => return c,
            }
        }
    });
    quote! {
        #(#steps)*
        core::option::Option::Some(core::cmp::Ordering::Equal)
    }
}

/// The members of `fields` (`x` or `0`).
fn members(fields: &Fields) -> Vec<syn::Member> {
    fields
        .iter()
        .enumerate()
        .map(|(i, f)| match &f.ident {
            Some(id) => syn::Member::Named(id.clone()),
            None => syn::Member::Unnamed(syn::Index::from(i)),
        })
        .collect()
}

/// A pattern binding every field of variant `path` to `prefix0, prefix1, ...`, and the
/// bound names.
fn bind(path: &TokenStream, fields: &Fields, prefix: &str) -> (TokenStream, Vec<syn::Ident>) {
    let names: Vec<syn::Ident> = (0..fields.len())
        .map(|i| format_ident!("{prefix}{i}"))
        .collect();
    let pat = match fields {
        Fields::Unit => quote! { #path },
        Fields::Unnamed(_) => quote! { #path(#(#names),*) },
        Fields::Named(n) => {
            let ids = n.named.iter().map(|f| f.ident.clone());
            quote! { #path { #(#ids: #names),* } }
        }
    };
    (pat, names)
}

/// The `impl PartialOrd` Rust derives for `item`, spanned at `span`; an error message for
/// what TRaX-Rust cannot derive.
fn partial_ord_impl(item: &Item, span: Span) -> Result<Item, String> {
    let (ident, generics) = match item {
        Item::Struct(s) => (&s.ident, &s.generics),
        Item::Enum(e) => (&e.ident, &e.generics),
        _ => unreachable!("only structs and enums derive"),
    };
    let body = match item {
        Item::Struct(s) => {
            let pairs: Vec<_> = members(&s.fields)
                .into_iter()
                .map(|m| (quote! { self.#m }, quote! { &other.#m }))
                .collect();
            chain(&pairs)
        }
        Item::Enum(e) => {
            let fieldless = e.variants.iter().all(|v| v.fields.is_empty());
            if !fieldless && e.variants.iter().any(|v| v.discriminant.is_some()) {
                return Err(format!(
                    "`#[derive(PartialOrd)]` on `{ident}`, an enum with data and explicit discriminants, is not supported in TRaX-Rust (write `impl PartialOrd for {ident}`)"
                ));
            }
            if e.variants.is_empty() {
                quote! { core::option::Option::Some(core::cmp::Ordering::Equal) }
            } else if fieldless {
                // Fieldless: the discriminants (explicit values included) order them.
                quote! { (*self as i64).partial_cmp(&(*other as i64)) }
            } else {
                let mut same = Vec::new();
                let mut rank = Vec::new();
                for (i, v) in e.variants.iter().enumerate() {
                    let vi = &v.ident;
                    let path = quote! { #ident::#vi };
                    let i = i as isize;
                    let any = match v.fields {
                        Fields::Unit => quote! { #path },
                        Fields::Unnamed(_) => quote! { #path(..) },
                        Fields::Named(_) => quote! { #path { .. } },
                    };
                    rank.push(quote! { #any => #i });
                    if !v.fields.is_empty() {
                        let (pa, a) = bind(&path, &v.fields, "__self_");
                        let (pb, b) = bind(&path, &v.fields, "__other_");
                        let pairs: Vec<_> = a
                            .iter()
                            .zip(&b)
                            .map(|(a, b)| (quote! { #a }, quote! { #b }))
                            .collect();
                        let c = chain(&pairs);
                        same.push(quote! { (#pa, #pb) => { #c } });
                    }
                }
                quote! {
                    match (self, other) {
                        #(#same)*
                        _ => {
                            let __self_rank: isize = match self { #(#rank),* };
                            let __other_rank: isize = match other { #(#rank),* };
                            __self_rank.partial_cmp(&__other_rank)
                        }
                    }
                }
            }
        }
        _ => unreachable!("only structs and enums derive"),
    };
    let mut g = generics.clone();
    for p in g.type_params_mut() {
        p.bounds.push(syn::parse_quote!(PartialOrd));
    }
    let (impl_g, ty_g, where_c) = g.split_for_impl();
    let tokens = quote! {
        #[automatically_derived]
        impl #impl_g PartialOrd for #ident #ty_g #where_c {
            fn partial_cmp(&self, other: &Self) -> core::option::Option<core::cmp::Ordering> {
                #body
            }
        }
    };
    syn::parse2(respan(tokens, span)).map_err(|e| format!("deriving `PartialOrd`: {e}"))
}

/// `ts` with every token at `span`.
fn respan(ts: TokenStream, span: Span) -> TokenStream {
    ts.into_iter()
        .map(|tt| match tt {
            TokenTree::Group(g) => {
                let mut n = Group::new(g.delimiter(), respan(g.stream(), span));
                n.set_span(span);
                TokenTree::Group(n)
            }
            mut other => {
                other.set_span(span);
                other
            }
        })
        .collect()
}
