//! Expressions printed as rustc's pretty-printer prints them, for `assert!`'s default
//! message ("assertion failed: a.len() == 4"): binary operators spaced, everything else
//! tight, whatever the source's spacing and line breaks. Forms rustc would print in ways
//! not reproduced here (blocks, closures, macros) fall back to their tokens.

use quote::ToTokens;
use syn::{Expr, Type};

/// `e` as rustc's `pprust::expr_to_string` prints it.
pub fn expr(e: &Expr) -> String {
    let mut s = String::new();
    write_expr(&mut s, e);
    s
}

fn list<'a>(s: &mut String, items: impl IntoIterator<Item = &'a Expr>) {
    for (i, x) in items.into_iter().enumerate() {
        if i > 0 {
            s.push_str(", ");
        }
        write_expr(s, x);
    }
}

fn tokens(s: &mut String, t: &impl ToTokens) {
    s.push_str(&t.to_token_stream().to_string());
}

fn write_expr(s: &mut String, e: &Expr) {
    match e {
        Expr::Lit(l) => tokens(s, &l.lit),
        Expr::Path(p) if p.qself.is_none() => path(s, &p.path),
        Expr::Paren(p) => {
            s.push('(');
            write_expr(s, &p.expr);
            s.push(')');
        }
        Expr::Group(g) => write_expr(s, &g.expr),
        Expr::Binary(b) => {
            write_expr(s, &b.left);
            s.push(' ');
            tokens(s, &b.op);
            s.push(' ');
            write_expr(s, &b.right);
        }
        Expr::Unary(u) => {
            tokens(s, &u.op);
            write_expr(s, &u.expr);
        }
        Expr::Reference(r) => {
            s.push('&');
            if r.mutability.is_some() {
                s.push_str("mut ");
            }
            write_expr(s, &r.expr);
        }
        Expr::Cast(c) => {
            write_expr(s, &c.expr);
            s.push_str(" as ");
            ty(s, &c.ty);
        }
        Expr::Call(c) => {
            write_expr(s, &c.func);
            s.push('(');
            list(s, &c.args);
            s.push(')');
        }
        Expr::MethodCall(m) => {
            write_expr(s, &m.receiver);
            s.push('.');
            s.push_str(&m.method.to_string());
            if let Some(t) = &m.turbofish {
                s.push_str("::");
                generic_args(s, &t.args);
            }
            s.push('(');
            list(s, &m.args);
            s.push(')');
        }
        Expr::Field(f) => {
            write_expr(s, &f.base);
            s.push('.');
            tokens(s, &f.member);
        }
        Expr::Index(i) => {
            write_expr(s, &i.expr);
            s.push('[');
            write_expr(s, &i.index);
            s.push(']');
        }
        Expr::Array(a) => {
            s.push('[');
            list(s, &a.elems);
            s.push(']');
        }
        Expr::Repeat(r) => {
            s.push('[');
            write_expr(s, &r.expr);
            s.push_str("; ");
            write_expr(s, &r.len);
            s.push(']');
        }
        Expr::Tuple(t) => {
            s.push('(');
            list(s, &t.elems);
            if t.elems.len() == 1 {
                s.push(',');
            }
            s.push(')');
        }
        Expr::Range(r) => {
            if let Some(a) = &r.start {
                write_expr(s, a);
            }
            tokens(s, &r.limits);
            if let Some(b) = &r.end {
                write_expr(s, b);
            }
        }
        other => tokens(s, other),
    }
}

fn path(s: &mut String, p: &syn::Path) {
    if p.leading_colon.is_some() {
        s.push_str("::");
    }
    for (i, seg) in p.segments.iter().enumerate() {
        if i > 0 {
            s.push_str("::");
        }
        s.push_str(&seg.ident.to_string());
        if let syn::PathArguments::AngleBracketed(a) = &seg.arguments {
            if a.colon2_token.is_some() {
                s.push_str("::");
            }
            generic_args(s, &a.args);
        }
    }
}

fn generic_args(
    s: &mut String,
    args: &syn::punctuated::Punctuated<syn::GenericArgument, syn::Token![,]>,
) {
    s.push('<');
    for (i, a) in args.iter().enumerate() {
        if i > 0 {
            s.push_str(", ");
        }
        match a {
            syn::GenericArgument::Type(t) => ty(s, t),
            other => tokens(s, other),
        }
    }
    s.push('>');
}

fn ty(s: &mut String, t: &Type) {
    match t {
        Type::Path(p) if p.qself.is_none() => path(s, &p.path),
        Type::Ptr(p) => {
            s.push('*');
            s.push_str(match p.mutability {
                syn::PointerMutability::Mut(_) => "mut ",
                syn::PointerMutability::Const(_) => "const ",
            });
            ty(s, &p.elem);
        }
        Type::Reference(r) => {
            s.push('&');
            if r.mutability.is_some() {
                s.push_str("mut ");
            }
            ty(s, &r.elem);
        }
        Type::Paren(p) => {
            s.push('(');
            ty(s, &p.elem);
            s.push(')');
        }
        other => tokens(s, other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The expected strings are what rustc 1.95's `assert!` prints for these conditions.
    #[test]
    fn prints_like_rustc() {
        for (src, want) in [
            ("a.len() == 4", "a.len() == 4"),
            ("x<3", "x < 3"),
            ("  x  <  3  &&  !false ", "x < 3 && !false"),
            (
                "a[0] as f32 > 2.0 * (x as f32)",
                "a[0] as f32 > 2.0 * (x as f32)",
            ),
            ("-x > 0 || x*2 == 11", "-x > 0 || x * 2 == 11"),
            (
                "a\n        .iter()\n        .len() == 0",
                "a.iter().len() == 0",
            ),
            ("trax::thread_id() < N", "trax::thread_id() < N"),
            ("v.x >= 0.0f32 && *p != 1u8", "v.x >= 0.0f32 && *p != 1u8"),
            ("f(a, &mut b, (1,))", "f(a, &mut b, (1,))"),
            ("x as *const u32 == q", "x as *const u32 == q"),
        ] {
            let e: Expr = syn::parse_str(src).unwrap();
            assert_eq!(expr(&e), want, "{src}");
        }
    }
}
