//! Spans of syntax nodes in time proportional to the depth of their edges, not their size.
//!
//! syn's `Spanned::span` prints a node to tokens to find its first and last ones, so it
//! costs the node's whole size, and asking it for the span of every expression of a deep
//! tree costs the square of the tree's size: a 4000-term `+` chain or 3000 nested `if`s spent
//! most of their seconds of type checking and lowering printing syntax. [`Spanned`] gives
//! the same span for parsed code (the first token's span joined with the last's, as syn
//! computes it) by walking down the left edge of an expression for its first token and the
//! right edge for its last. Nodes that cannot nest expressions at their ends (paths, types,
//! patterns, literals, members, ranges' operators) are asked of syn, whose cost for them is
//! their own small size.
//!
//! A long chain (`a + b + c + ...`, `else if` after `else if`) has one first (or last) token
//! for all its links, so each walk leaves its answer in a per-thread memo keyed by the
//! position of each link's own token (its operator, keyword or brackets), and the next
//! link's query stops there: spanning every link of a chain of n costs time n, not n².
//!
//! The modules of the compiler import this trait instead of syn's; where the two could
//! differ (attributes on a binary expression, which syn prints in parentheses of no
//! location), this one gives the source's extent. `tests::same_spans_as_syn` checks that the
//! two agree on every expression, statement and block of the examples and the prelude.

use proc_macro2::Span;
use syn::{AttrStyle, Attribute, Expr, Label, Stmt};

/// The span of a syntax node: its first token's span joined with its last token's.
pub trait Spanned {
    /// The node's span (see the module documentation).
    fn span(&self) -> Span;
}

/// syn's span of a node whose size does not grow with the expressions in it.
fn syn_span<T: syn::spanned::Spanned + ?Sized>(t: &T) -> Span {
    syn::spanned::Spanned::span(t)
}

/// `first` joined with `last`, or `first` alone when they lie in different files (as syn).
fn join(first: Span, last: Span) -> Span {
    first.join(last).unwrap_or(first)
}

/// The first outer attribute's `#`, which is printed first.
fn outer_attr(attrs: &[Attribute]) -> Option<Span> {
    attrs
        .iter()
        .find(|a| matches!(a.style, AttrStyle::Outer))
        .map(|a| a.pound_token.span)
}

/// A label's first token (its apostrophe), else `or`.
fn label_or(label: &Option<Label>, or: Span) -> Span {
    label.as_ref().map_or(or, |l| l.name.apostrophe)
}

/// One end of a node: an expression to walk down, or a span that starts at the node's
/// first token (a head) or ends at its last token (a tail) and lies inside the node.
enum Edge<'a> {
    Expr(&'a Expr),
    At(Span),
}

/// A node's two ends after its outer attributes.
trait Edges {
    /// The span of a token of the node's own (not of its parts), for nodes that pass a
    /// walk on to an expression at one end: the key of their memo entries.
    fn own(&self) -> Option<Span> {
        None
    }
    /// Its attributes (the outer ones are printed first).
    fn attrs(&self) -> &[Attribute] {
        &[]
    }
    /// Where its first token is.
    fn head(&self) -> Edge<'_>;
    /// Where its last token is.
    fn tail(&self) -> Edge<'_>;
}

/// The edges of `e`'s kind (`None`: a kind whose span syn gives at its own small size).
fn edges(e: &Expr) -> Option<&dyn Edges> {
    Some(match e {
        Expr::Array(x) => x,
        Expr::Assign(x) => x,
        Expr::Async(x) => x,
        Expr::Await(x) => x,
        Expr::Binary(x) => x,
        Expr::Block(x) => x,
        Expr::Break(x) => x,
        Expr::Call(x) => x,
        Expr::Cast(x) => x,
        Expr::Closure(x) => x,
        Expr::Const(x) => x,
        Expr::Continue(x) => x,
        Expr::Field(x) => x,
        Expr::ForLoop(x) => x,
        Expr::Group(x) => x,
        Expr::If(x) => x,
        Expr::Index(x) => x,
        Expr::Let(x) => x,
        Expr::Loop(x) => x,
        Expr::Macro(x) => x,
        Expr::Match(x) => x,
        Expr::MethodCall(x) => x,
        Expr::Paren(x) => x,
        Expr::Range(x) => x,
        Expr::RawAddr(x) => x,
        Expr::Reference(x) => x,
        Expr::Repeat(x) => x,
        Expr::Return(x) => x,
        Expr::Struct(x) => x,
        Expr::Try(x) => x,
        Expr::TryBlock(x) => x,
        Expr::Tuple(x) => x,
        Expr::Unary(x) => x,
        Expr::Unsafe(x) => x,
        Expr::While(x) => x,
        Expr::Yield(x) => x,
        // Literals, paths, `_`, verbatim tokens.
        _ => return None,
    })
}

/// Which end of a node a memo entry answers.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum End {
    Head,
    Tail,
}

/// A memo key: a node's own token (start and end, line and column) and the end asked.
type Key = (proc_macro2::LineColumn, proc_macro2::LineColumn, End);

thread_local! {
    /// Answers of past walks (see the module documentation). An entry holds for the token
    /// at its position in the file of its answer: a node found by position in another
    /// file (where its answer does not join its token) is walked again. Spans without a
    /// location (line 0) are never keys.
    static MEMO: std::cell::RefCell<std::collections::HashMap<Key, Span>> =
        Default::default();
}

/// Empties this thread's memo (at the start of a compilation: a thread that compiles many
/// kernels would otherwise keep the answers of all of them).
pub(crate) fn forget() {
    MEMO.with(|m| *m.borrow_mut() = Default::default());
}

/// The memo key of `n`'s `end`, if it has one.
fn key(n: &dyn Edges, end: End) -> Option<(Span, Key)> {
    let own = n.own()?;
    let (start, stop) = (own.start(), own.end());
    (start.line > 0).then_some((own, (start, stop, end)))
}

/// The span at `end` of expression `e` (a head: starts at `e`'s first token and ends
/// inside `e`; a tail: ends at its last token and starts inside `e`), walking down that
/// edge to a node that answers, then remembering the answer for every link passed.
fn walk(mut e: &Expr, end: End) -> Span {
    let mut passed: Vec<Key> = Vec::new();
    let found = loop {
        #[cfg(test)]
        tests::STEPS.with(|c| c.set(c.get() + 1));
        let Some(n) = edges(e) else {
            break syn_span(e);
        };
        if end == End::Head {
            if let Some(s) = outer_attr(n.attrs()) {
                break s;
            }
        }
        let k = key(n, end);
        if let Some((own, k)) = k {
            let hit = MEMO.with(|m| m.borrow().get(&k).copied());
            if let Some(s) = hit.filter(|s| own.join(*s).is_some()) {
                break s;
            }
        }
        let edge = match end {
            End::Head => n.head(),
            End::Tail => n.tail(),
        };
        match edge {
            Edge::Expr(x) => {
                passed.extend(k.map(|k| k.1));
                e = x;
            }
            Edge::At(s) => break s,
        }
    };
    if !passed.is_empty() {
        MEMO.with(|m| {
            let mut m = m.borrow_mut();
            for k in passed {
                m.insert(k, found);
            }
        });
    }
    found
}

/// A span that starts at `e`'s first token and ends inside `e`: down the left edge.
fn first(e: &Expr) -> Span {
    walk(e, End::Head)
}

/// A span that ends at `e`'s last token and starts inside `e`: down the right edge.
fn last(e: &Expr) -> Span {
    walk(e, End::Tail)
}

impl<T: Edges + ?Sized> Spanned for T {
    fn span(&self) -> Span {
        let head = match (outer_attr(self.attrs()), self.head()) {
            (Some(s), _) | (None, Edge::At(s)) => s,
            (None, Edge::Expr(e)) => first(e),
        };
        let tail = match self.tail() {
            Edge::At(s) => s,
            Edge::Expr(e) => last(e),
        };
        join(head, tail)
    }
}

impl Edges for Expr {
    fn own(&self) -> Option<Span> {
        edges(self).and_then(|n| n.own())
    }
    fn attrs(&self) -> &[Attribute] {
        edges(self).map_or(&[], |n| n.attrs())
    }
    fn head(&self) -> Edge<'_> {
        edges(self).map_or_else(|| Edge::At(syn_span(self)), |n| n.head())
    }
    fn tail(&self) -> Edge<'_> {
        edges(self).map_or_else(|| Edge::At(syn_span(self)), |n| n.tail())
    }
}

/// `impl Edges` for expression kinds: `Kind, |x| head, |x| tail`.
macro_rules! expr_edges {
    ($($t:ident, |$x:ident| $head:expr, $tail:expr $(, own $own:expr)?;)*) => {$(
        impl Edges for syn::$t {
            $(
                fn own(&self) -> Option<Span> {
                    let $x = self;
                    Some($own)
                }
            )?
            fn attrs(&self) -> &[Attribute] {
                &self.attrs
            }
            fn head(&self) -> Edge<'_> {
                let $x = self;
                $head
            }
            fn tail(&self) -> Edge<'_> {
                let $x = self;
                $tail
            }
        }
    )*};
}

use Edge::{At, Expr as E};

/// An optional expression, else a span.
fn expr_or(e: &Option<Box<Expr>>, or: Span) -> Edge<'_> {
    e.as_deref().map_or(At(or), E)
}

expr_edges! {
    ExprArray, |x| At(x.bracket_token.span.join()), At(x.bracket_token.span.join());
    ExprAssign, |x| E(&x.left), E(&x.right),
        own x.eq_token.spans[0];
    ExprAsync, |x| At(x.async_token.span), At(x.block.brace_token.span.join());
    ExprAwait, |x| E(&x.base), At(x.await_token.span),
        own x.dot_token.spans[0];
    ExprBinary, |x| E(&x.left), E(&x.right),
        own syn_span(&x.op);
    ExprBlock,
        |x| At(label_or(&x.label, x.block.brace_token.span.join())),
        At(x.block.brace_token.span.join());
    ExprBreak,
        |x| At(x.break_token.span),
        expr_or(&x.expr, x.label.as_ref().map_or(x.break_token.span, syn_span)),
        own x.break_token.span;
    ExprCall, |x| E(&x.func), At(x.paren_token.span.join()),
        own x.paren_token.span.join();
    ExprCast, |x| E(&x.expr), At(syn_span(&*x.ty)),
        own x.as_token.span;
    ExprClosure,
        |x| At(x
            .lifetimes
            .as_ref()
            .map(|l| l.for_token.span)
            .or(x.constness.map(|t| t.span))
            .or(x.asyncness.map(|t| t.span))
            .or(x.capture.map(|t| t.span))
            .unwrap_or(x.inputs_begin.spans[0])),
        E(&x.body),
        own x.inputs_begin.spans[0];
    ExprConst, |x| At(x.const_token.span), At(x.block.brace_token.span.join());
    ExprContinue,
        |x| At(x.continue_token.span),
        At(x.label.as_ref().map_or(x.continue_token.span, syn_span));
    ExprField, |x| E(&x.base), At(syn_span(&x.member)),
        own x.dot_token.spans[0];
    ExprForLoop,
        |x| At(label_or(&x.label, x.for_token.span)),
        At(x.body.brace_token.span.join());
    ExprGroup, |x| At(x.group_token.span), At(x.group_token.span);
    ExprIf,
        |x| At(x.if_token.span),
        match &x.else_branch {
            Some((_, els)) => E(els),
            None => At(x.then_branch.brace_token.span.join()),
        },
        own x.if_token.span;
    ExprIndex, |x| E(&x.expr), At(x.bracket_token.span.join()),
        own x.bracket_token.span.join();
    ExprLet, |x| At(x.let_token.span), E(&x.expr),
        own x.let_token.span;
    ExprLoop,
        |x| At(label_or(&x.label, x.loop_token.span)),
        At(x.body.brace_token.span.join());
    ExprMacro, |x| x.mac.head(), x.mac.tail();
    ExprMatch, |x| At(x.match_token.span), At(x.brace_token.span.join());
    ExprMethodCall, |x| E(&x.receiver), At(x.paren_token.span.join()),
        own x.dot_token.spans[0];
    ExprParen, |x| At(x.paren_token.span.join()), At(x.paren_token.span.join());
    ExprRange,
        |x| expr_or(&x.start, syn_span(&x.limits)),
        expr_or(&x.end, syn_span(&x.limits)),
        own syn_span(&x.limits);
    ExprRawAddr, |x| At(x.and_token.spans[0]), E(&x.expr),
        own x.and_token.spans[0];
    ExprReference, |x| At(x.and_token.spans[0]), E(&x.expr),
        own x.and_token.spans[0];
    ExprRepeat, |x| At(x.bracket_token.span.join()), At(x.bracket_token.span.join());
    ExprReturn, |x| At(x.return_token.span), expr_or(&x.expr, x.return_token.span),
        own x.return_token.span;
    ExprStruct,
        |x| At(match &x.qself {
            Some(q) => q.lt_token.spans[0],
            None => syn_span(&x.path),
        }),
        At(x.brace_token.span.join());
    ExprTry, |x| E(&x.expr), At(x.question_token.spans[0]),
        own x.question_token.spans[0];
    ExprTryBlock, |x| At(x.try_token.span), At(x.block.brace_token.span.join());
    ExprTuple, |x| At(x.paren_token.span.join()), At(x.paren_token.span.join());
    ExprUnary, |x| At(syn_span(&x.op)), E(&x.expr),
        own syn_span(&x.op);
    ExprUnsafe, |x| At(x.unsafe_token.span), At(x.block.brace_token.span.join());
    ExprWhile,
        |x| At(label_or(&x.label, x.while_token.span)),
        At(x.body.brace_token.span.join());
    ExprYield, |x| At(x.yield_token.span), expr_or(&x.expr, x.yield_token.span),
        own x.yield_token.span;
    Local, |x| At(x.let_token.span), At(x.semi_token.spans[0]);
    StmtMacro,
        |x| x.mac.head(),
        x.semi_token.map_or_else(|| x.mac.tail(), |s| At(s.spans[0]));
    Arm,
        |x| At(syn_span(&x.pat)),
        x.comma.map_or_else(|| E(&x.body), |c| At(c.spans[0]));
    FieldValue,
        |x| At(syn_span(&x.member)),
        if x.colon_token.is_some() { E(&x.expr) } else { At(syn_span(&x.member)) };
}

impl Edges for syn::Macro {
    fn head(&self) -> Edge<'_> {
        At(syn_span(&self.path))
    }
    fn tail(&self) -> Edge<'_> {
        At(self.delimiter.span().join())
    }
}

impl Edges for syn::Block {
    fn head(&self) -> Edge<'_> {
        At(self.brace_token.span.join())
    }
    fn tail(&self) -> Edge<'_> {
        At(self.brace_token.span.join())
    }
}

impl Edges for Stmt {
    fn attrs(&self) -> &[Attribute] {
        match self {
            Stmt::Local(l) => &l.attrs,
            Stmt::Expr(e, _) => e.attrs(),
            Stmt::Macro(m) => &m.attrs,
            Stmt::Item(_) => &[],
        }
    }
    fn head(&self) -> Edge<'_> {
        match self {
            Stmt::Local(l) => l.head(),
            Stmt::Expr(e, _) => E(e),
            Stmt::Macro(m) => m.head(),
            Stmt::Item(i) => At(syn_span(i)),
        }
    }
    fn tail(&self) -> Edge<'_> {
        match self {
            Stmt::Local(l) => l.tail(),
            Stmt::Expr(e, semi) => semi.map_or(E(e), |s| At(s.spans[0])),
            Stmt::Macro(m) => m.tail(),
            Stmt::Item(i) => At(syn_span(i)),
        }
    }
}

/// Nodes that do not nest expressions at their ends (or are items, spanned once each):
/// syn's span.
macro_rules! by_syn {
    ($($t:ident),* $(,)?) => {$(
        impl Spanned for syn::$t {
            fn span(&self) -> Span {
                syn_span(self)
            }
        }
    )*};
}

by_syn!(
    Abi,
    Attribute,
    BinOp,
    BoundLifetimes,
    ConstParam,
    FieldPat,
    FnArg,
    ForeignItem,
    GenericArgument,
    Generics,
    Ident,
    ImplItem,
    ImplItemType,
    Item,
    ItemExternCrate,
    ItemImpl,
    Label,
    Lit,
    Member,
    Pat,
    PatIdent,
    PatReference,
    PatRest,
    PatSlice,
    PatStruct,
    PatTuple,
    PatTupleStruct,
    PatType,
    Path,
    PathArguments,
    Receiver,
    ReturnType,
    Signature,
    TraitItem,
    TraitItemType,
    Type,
    TypeFnPtr,
    TypeImplTrait,
    TypeParamBound,
    TypePath,
    TypeReference,
    TypeSlice,
    TypeTraitObject,
    Variadic,
    WherePredicate,
);

/// Literal and path expressions: syn's span (their size is their own).
macro_rules! leaf_exprs {
    ($($t:ident),*) => {$(
        impl Edges for syn::$t {
            fn attrs(&self) -> &[Attribute] {
                &self.attrs
            }
            fn head(&self) -> Edge<'_> {
                At(syn_span(self))
            }
            fn tail(&self) -> Edge<'_> {
                At(syn_span(self))
            }
        }
    )*};
}

leaf_exprs!(ExprLit, ExprPath);

impl Spanned for syn::punctuated::Punctuated<syn::GenericParam, syn::token::Comma> {
    fn span(&self) -> Span {
        syn_span(self)
    }
}

impl Spanned for syn::token::Or {
    fn span(&self) -> Span {
        self.spans[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use syn::visit::Visit;

    thread_local! {
        /// Links walked by [`walk`] on this thread.
        pub(super) static STEPS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    }

    /// Spanning every expression of long chains walks each link a bounded number of times
    /// (the memo): a 5000-term `+` chain and a 5000-link `else if` chain walked about n²/2
    /// links, 12.5 million each, before it.
    #[test]
    fn long_chains_are_spanned_in_linear_time() {
        const N: usize = 5000;
        let add = format!("fn f() {{ x{} }}", " + 1".repeat(N));
        let elif = format!(
            "fn f() {{ if a {{ 0 }}{} else {{ 1 }} }}",
            " else if a { 0 }".repeat(N)
        );
        // Deep trees recurse (in the visitor, and in syn's drop): a big stack.
        std::thread::Builder::new()
            .stack_size(256 << 20)
            .spawn(move || {
                for text in [add, elif] {
                    let file = syn::parse_file(&text).unwrap();
                    struct All(usize);
                    impl<'ast> Visit<'ast> for All {
                        fn visit_expr(&mut self, e: &'ast Expr) {
                            let s = e.span();
                            assert!(s.start().line == 1 && s.end().column > s.start().column);
                            self.0 += 1;
                            syn::visit::visit_expr(self, e);
                        }
                    }
                    let before = STEPS.with(|c| c.get());
                    let mut all = All(0);
                    all.visit_file(&file);
                    let steps = STEPS.with(|c| c.get()) - before;
                    assert!(all.0 > N, "{}", all.0);
                    assert!(
                        steps < 4 * all.0 as u64,
                        "{steps} links walked for {} nodes",
                        all.0
                    );
                }
            })
            .unwrap()
            .join()
            .unwrap();
    }

    /// Compares this module's spans with syn's on every expression, statement, block and
    /// arm it visits, counting them.
    #[derive(Default)]
    struct Compare {
        checked: usize,
        differ: Vec<String>,
    }

    impl Compare {
        fn check(&mut self, ours: Span, theirs: Span, what: &dyn std::fmt::Debug) {
            self.checked += 1;
            let range = |s: Span| (s.start(), s.end());
            if range(ours) != range(theirs) && self.differ.len() < 10 {
                self.differ.push(format!(
                    "{:?} vs syn's {:?}: {:.200}",
                    range(ours),
                    range(theirs),
                    format!("{what:?}")
                ));
            }
        }
    }

    impl<'ast> Visit<'ast> for Compare {
        fn visit_expr(&mut self, e: &'ast Expr) {
            self.check(e.span(), syn_span(e), e);
            syn::visit::visit_expr(self, e);
        }
        fn visit_stmt(&mut self, s: &'ast Stmt) {
            self.check(s.span(), syn_span(s), s);
            syn::visit::visit_stmt(self, s);
        }
        fn visit_block(&mut self, b: &'ast syn::Block) {
            self.check(b.span(), syn_span(b), b);
            syn::visit::visit_block(self, b);
        }
        fn visit_arm(&mut self, a: &'ast syn::Arm) {
            self.check(a.span(), syn_span(a), a);
            syn::visit::visit_arm(self, a);
        }
        fn visit_local(&mut self, l: &'ast syn::Local) {
            self.check(l.span(), syn_span(l), l);
            syn::visit::visit_local(self, l);
        }
    }

    /// The spans agree with syn's on every node of the example kernels, the compiler's test
    /// kernels, the fuzz seeds and the prelude, and on constructs they may lack.
    #[test]
    fn same_spans_as_syn() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut files = Vec::new();
        for dir in [
            "examples",
            "compiler/tests/kernels",
            "tests/kernels",
            "fuzz/seeds/kernel",
            "runtime/src",
        ] {
            let mut stack = vec![root.join(dir)];
            while let Some(d) = stack.pop() {
                let Ok(entries) = std::fs::read_dir(&d) else {
                    continue;
                };
                for e in entries.flatten() {
                    let p = e.path();
                    if p.is_dir() {
                        stack.push(p);
                    } else if p.extension().is_some_and(|x| x == "rs")
                        // syn's own spans of the deep seeds take the square of their size
                        // (what this module avoids): seconds, and deep recursion.
                        && !p.file_name().unwrap().to_string_lossy().starts_with("deep_")
                    {
                        files.push(std::fs::read_to_string(&p).unwrap());
                    }
                }
            }
        }
        // Constructs the kernels may not use.
        let extra = syn::parse_file(
            r#"fn f() {
                let c = move |a: u32, b| -> u32 { a + b };
                let d = async move { 1 };
                let e = const { 2 };
                let g = 'outer: loop { break 'outer 5; };
                'w: while x < 3 { continue 'w; }
                for i in 0..n { x += i; }
                let r = ..;
                let s = a..=b;
                let t = ..b;
                let u = a..;
                let v = S { a: 1, ..Default::default() };
                let w = <T as Tr>::f(1);
                let y = x?.await;
                let z = &raw const x;
                let q = try { 1 };
                let p = unsafe { *ptr };
                let k = [0u8; 4].len() as u64;
                let m = match x { 0 => 1, _ if y => { 2 } 1 | 2 => 3 };
                if a { b } else if c { d } else { e }
                return;
                break;
                yield 3;
                let (a, b) = (1, (2,));
                x.0.field[3] = -!*y;
                println!("{}", x);
                vec![1, 2];
                f::<u32>(x).g::<i8>(y)
            }"#,
        )
        .expect("the extra constructs parse");
        let mut cmp = Compare::default();
        cmp.visit_file(&extra);
        for text in &files {
            // (Kernels that do not parse are the diagnostics tests' business.)
            if let Ok(file) = syn::parse_file(text) {
                cmp.visit_file(&file);
            }
        }
        assert!(cmp.differ.is_empty(), "{:#?}", cmp.differ);
        assert!(cmp.checked > 10_000, "{}", cmp.checked);
    }
}
