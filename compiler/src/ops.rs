//! Operators as enums, shared by type checking, constant evaluation and lowering.

use crate::ty::LangTrait;

/// A binary operator (the plain form of a compound assignment).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    BitAnd,
    BitOr,
    BitXor,
    Shl,
    Shr,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
}

impl BinOp {
    /// Classifies a `syn` operator: the operator and whether it is a compound assignment.
    pub fn of(op: &syn::BinOp) -> (BinOp, bool) {
        use syn::BinOp as S;
        match op {
            S::Add(_) => (BinOp::Add, false),
            S::Sub(_) => (BinOp::Sub, false),
            S::Mul(_) => (BinOp::Mul, false),
            S::Div(_) => (BinOp::Div, false),
            S::Rem(_) => (BinOp::Rem, false),
            S::And(_) => (BinOp::And, false),
            S::Or(_) => (BinOp::Or, false),
            S::BitXor(_) => (BinOp::BitXor, false),
            S::BitAnd(_) => (BinOp::BitAnd, false),
            S::BitOr(_) => (BinOp::BitOr, false),
            S::Shl(_) => (BinOp::Shl, false),
            S::Shr(_) => (BinOp::Shr, false),
            S::Eq(_) => (BinOp::Eq, false),
            S::Lt(_) => (BinOp::Lt, false),
            S::Le(_) => (BinOp::Le, false),
            S::Ne(_) => (BinOp::Ne, false),
            S::Ge(_) => (BinOp::Ge, false),
            S::Gt(_) => (BinOp::Gt, false),
            S::AddAssign(_) => (BinOp::Add, true),
            S::SubAssign(_) => (BinOp::Sub, true),
            S::MulAssign(_) => (BinOp::Mul, true),
            S::DivAssign(_) => (BinOp::Div, true),
            S::RemAssign(_) => (BinOp::Rem, true),
            S::BitXorAssign(_) => (BinOp::BitXor, true),
            S::BitAndAssign(_) => (BinOp::BitAnd, true),
            S::BitOrAssign(_) => (BinOp::BitOr, true),
            S::ShlAssign(_) => (BinOp::Shl, true),
            S::ShrAssign(_) => (BinOp::Shr, true),
            _ => (BinOp::Add, false),
        }
    }

    /// Source text.
    pub fn text(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Rem => "%",
            BinOp::BitAnd => "&",
            BinOp::BitOr => "|",
            BinOp::BitXor => "^",
            BinOp::Shl => "<<",
            BinOp::Shr => ">>",
            BinOp::Eq => "==",
            BinOp::Ne => "!=",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::And => "&&",
            BinOp::Or => "||",
        }
    }

    /// True for `== != < <= > >=`.
    pub fn is_cmp(self) -> bool {
        matches!(
            self,
            BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge
        )
    }

    /// True for `+ - * / %`.
    pub fn is_arith(self) -> bool {
        matches!(
            self,
            BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Rem
        )
    }

    /// True for `& | ^`.
    pub fn is_bit(self) -> bool {
        matches!(self, BinOp::BitAnd | BinOp::BitOr | BinOp::BitXor)
    }

    /// True for `<< >>`.
    pub fn is_shift(self) -> bool {
        matches!(self, BinOp::Shl | BinOp::Shr)
    }

    /// The operator trait of `a op b` (`a op= b` when `assign`).
    pub fn lang_trait(self, assign: bool) -> Option<LangTrait> {
        use LangTrait as L;
        Some(match (self, assign) {
            (BinOp::Add, false) => L::Add,
            (BinOp::Sub, false) => L::Sub,
            (BinOp::Mul, false) => L::Mul,
            (BinOp::Div, false) => L::Div,
            (BinOp::Rem, false) => L::Rem,
            (BinOp::BitAnd, false) => L::BitAnd,
            (BinOp::BitOr, false) => L::BitOr,
            (BinOp::BitXor, false) => L::BitXor,
            (BinOp::Shl, false) => L::Shl,
            (BinOp::Shr, false) => L::Shr,
            (BinOp::Add, true) => L::AddAssign,
            (BinOp::Sub, true) => L::SubAssign,
            (BinOp::Mul, true) => L::MulAssign,
            (BinOp::Div, true) => L::DivAssign,
            (BinOp::Rem, true) => L::RemAssign,
            (BinOp::BitAnd, true) => L::BitAndAssign,
            (BinOp::BitOr, true) => L::BitOrAssign,
            (BinOp::BitXor, true) => L::BitXorAssign,
            (BinOp::Shl, true) => L::ShlAssign,
            (BinOp::Shr, true) => L::ShrAssign,
            (BinOp::Eq | BinOp::Ne, false) => L::PartialEq,
            (BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge, false) => L::PartialOrd,
            _ => return None,
        })
    }
}

/// A unary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnOp {
    Neg,
    Not,
    Deref,
}

impl UnOp {
    /// Classifies a `syn` operator.
    pub fn of(op: &syn::UnOp) -> UnOp {
        match op {
            syn::UnOp::Neg(_) => UnOp::Neg,
            syn::UnOp::Not(_) => UnOp::Not,
            _ => UnOp::Deref,
        }
    }
}
