//! The parsed form of a script.

/// A node of the expression tree, with the byte offset errors about it point to.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Expr {
    pub(crate) kind: ExprKind,
    /// Where the expression starts in the source.
    pub(crate) start: usize,
    /// Height of this subtree (a leaf is 1); bounded by the parser so that evaluating and
    /// dropping the tree cannot exhaust the stack.
    pub(crate) depth: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum ExprKind {
    Int(i64),
    Real(f64),
    Bool(bool),
    Str(Box<str>),
    /// An identifier: an enum value or a blackboard key (`@key` for the root scope).
    Name(Box<str>),
    /// `op` and its offset, then the operand.
    Unary(UnOp, usize, Box<Expr>),
    /// `op` and its offset, then the operands.
    Binary(BinOp, usize, Box<Expr>, Box<Expr>),
    /// `a < b <= c ...`: n + 1 operands and n operators with their offsets.
    Compare(Vec<Expr>, Vec<(CmpOp, usize)>),
    /// `cond ? then : else`.
    Ternary(Box<Expr>, Box<Expr>, Box<Expr>),
    /// `key op value`: the operator and its offset, the key and its offset, the value.
    Assign(AssignOp, usize, Box<str>, usize, Box<Expr>),
}

impl Expr {
    pub(crate) fn leaf(kind: ExprKind, start: usize) -> Self {
        Self {
            kind,
            start,
            depth: 1,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum UnOp {
    Neg,
    BitNot,
    Not,
}

impl UnOp {
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            UnOp::Neg => "-",
            UnOp::BitNot => "~",
            UnOp::Not => "!",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Concat,
    BitAnd,
    BitOr,
    BitXor,
    And,
    Or,
}

impl BinOp {
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Concat => "..",
            BinOp::BitAnd => "&",
            BinOp::BitOr => "|",
            BinOp::BitXor => "^",
            BinOp::And => "&&",
            BinOp::Or => "||",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CmpOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum AssignOp {
    /// `:=`: creates the entry if it is missing.
    Create,
    /// `=`: the entry must exist.
    Existing,
    /// `+=`, `-=`, `*=`, `/=`: the binary operator, applied to the entry and the value.
    Compound(BinOp),
}

impl AssignOp {
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            AssignOp::Create => ":=",
            AssignOp::Existing => "=",
            AssignOp::Compound(BinOp::Add) => "+=",
            AssignOp::Compound(BinOp::Sub) => "-=",
            AssignOp::Compound(BinOp::Mul) => "*=",
            AssignOp::Compound(_) => "/=",
        }
    }
}
