//! Precedence-climbing parser: tokens to expression trees.
//!
//! Precedence, lowest first:
//!
//! | level | operators | associativity |
//! |---|---|---|
//! | assignment | `:=` `=` `+=` `-=` `*=` `/=` | right |
//! | conditional | `? :` | right |
//! | or | `\|\|` | left |
//! | and | `&&` | left |
//! | comparison | `==` `!=` `<` `<=` `>` `>=` | chained |
//! | bit or | `\|` `^` | left |
//! | bit and | `&` | left |
//! | additive | `+` `-` `..` | left |
//! | multiplicative | `*` `/` | left |
//! | unary | `-` `~` `!` | prefix |

use super::ast::{AssignOp, BinOp, CmpOp, Expr, ExprKind, UnOp};
use super::error::{Located, ScriptErrorKind};
use super::lexer::{tokenize, Tok, Token};

/// How deep expressions may nest, both in the source (parentheses, prefix operators,
/// right-associative chains) and in the resulting tree.
pub(crate) const MAX_DEPTH: usize = 64;

/// Parses a whole program: expressions separated by `;`, empty ones allowed.
pub(crate) fn parse_program(src: &str) -> Result<Vec<Expr>, Located> {
    let tokens = tokenize(src)?;
    let mut p = Parser {
        src,
        tokens,
        pos: 0,
        nesting: 0,
    };
    let mut program = Vec::new();
    loop {
        match p.peek() {
            Tok::Semi => p.pos += 1,
            // BehaviorTree.CPP's ParseScript refuses a script with no statement.
            Tok::Eof if program.is_empty() => return Err((ScriptErrorKind::Empty, 0)),
            Tok::Eof => return Ok(program),
            _ => {
                program.push(p.expr(BP_ASSIGN)?);
                if !matches!(p.peek(), Tok::Semi | Tok::Eof) {
                    return Err(p.expected("`;` or the end of the script"));
                }
            }
        }
    }
}

struct Parser<'s> {
    src: &'s str,
    tokens: Vec<Token>,
    pos: usize,
    /// Current recursion depth of `expr` and `unary`.
    nesting: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Tok {
        self.token().kind
    }

    fn token(&self) -> &Token {
        // The last token is always `Eof`, and `pos` never moves past it.
        &self.tokens[self.pos.min(self.tokens.len() - 1)]
    }

    /// Moves past the current token (never past `Eof`) and returns its start.
    fn bump(&mut self) -> usize {
        let start = self.token().start;
        if self.pos + 1 < self.tokens.len() {
            self.pos += 1;
        }
        start
    }

    fn text(&self, t: &Token) -> &str {
        &self.src[t.start..t.end]
    }

    /// "expected `what`, found `<current token>`", at the current token.
    fn expected(&self, what: &'static str) -> Located {
        let t = self.token();
        let found = match t.kind {
            Tok::Int(_) | Tok::Real(_) | Tok::Ident => format!("`{}`", self.text(t)),
            Tok::Str => format!("the string {}", self.text(t)),
            k => k.describe().into(),
        };
        (
            ScriptErrorKind::Expected {
                expected: what,
                found,
            },
            t.start,
        )
    }

    /// Checks the height of a freshly built node.
    fn checked(&self, e: Expr) -> Result<Expr, Located> {
        if e.depth > MAX_DEPTH {
            Err((ScriptErrorKind::TooDeep(MAX_DEPTH), e.start))
        } else {
            Ok(e)
        }
    }

    /// Runs `f` one nesting level deeper, failing beyond [`MAX_DEPTH`].
    fn nested<T>(&mut self, f: impl FnOnce(&mut Self) -> Result<T, Located>) -> Result<T, Located> {
        if self.nesting >= MAX_DEPTH {
            return Err((ScriptErrorKind::TooDeep(MAX_DEPTH), self.token().start));
        }
        self.nesting += 1;
        let r = f(self);
        self.nesting -= 1;
        r
    }

    /// An expression whose infix operators bind at least as tightly as `min_bp` (precedence
    /// climbing: one recursion per nested operand, so that deep expressions need little
    /// stack). The work is split into small functions to keep each stack frame small.
    fn expr(&mut self, min_bp: u8) -> Result<Expr, Located> {
        self.nested(|p| p.expr_at(min_bp))
    }

    fn expr_at(&mut self, min_bp: u8) -> Result<Expr, Located> {
        let mut lhs = self.unary()?;
        while let Some((bp, infix)) = infix(self.peek()) {
            if bp < min_bp {
                break;
            }
            lhs = self.infix(lhs, bp, infix)?;
        }
        Ok(lhs)
    }

    /// The rest of `lhs op ...`, at the infix operator.
    #[inline(never)]
    fn infix(&mut self, lhs: Expr, bp: u8, infix: Infix) -> Result<Expr, Located> {
        match infix {
            Infix::Binary(op) => self.binary(lhs, bp, op),
            Infix::Compare => self.comparison_chain(lhs),
            Infix::Ternary => self.ternary(lhs),
            Infix::Assign(op) => self.assignment(lhs, op),
        }
    }

    /// The rest of `lhs op rhs` for a left-associative operator of binding power `bp`.
    #[inline(never)]
    fn binary(&mut self, lhs: Expr, bp: u8, op: BinOp) -> Result<Expr, Located> {
        let op_at = self.bump();
        // Left-associative: the right operand binds tighter.
        let rhs = self.expr(bp + 1)?;
        let depth = lhs.depth.max(rhs.depth) + 1;
        let start = lhs.start;
        let kind = ExprKind::Binary(op, op_at, Box::new(lhs), Box::new(rhs));
        self.checked(Expr { kind, start, depth })
    }

    /// The rest of `first < b <= c ...`, at a comparison operator.
    #[inline(never)]
    fn comparison_chain(&mut self, first: Expr) -> Result<Expr, Located> {
        let mut operands = vec![first];
        let mut ops = Vec::new();
        while let Some(op) = comparison(self.peek()) {
            ops.push((op, self.bump()));
            operands.push(self.expr(BP_COMPARE + 1)?);
        }
        let start = operands[0].start;
        let depth = operands.iter().map(|e| e.depth).max().unwrap_or(0) + 1;
        self.checked(Expr {
            kind: ExprKind::Compare(operands, ops),
            start,
            depth,
        })
    }

    /// The rest of `cond ? a : b`, at the `?`. Both branches are full expressions, so the
    /// conditional is right-associative and `c ? x := 1 : y := 2` assigns in either branch.
    #[inline(never)]
    fn ternary(&mut self, cond: Expr) -> Result<Expr, Located> {
        self.bump();
        let then = self.expr(BP_ASSIGN)?;
        if self.peek() != Tok::Colon {
            return Err(self.expected("`:` of the conditional `c ? a : b`"));
        }
        self.bump();
        let otherwise = self.expr(BP_ASSIGN)?;
        let start = cond.start;
        let depth = cond.depth.max(then.depth).max(otherwise.depth) + 1;
        let kind = ExprKind::Ternary(Box::new(cond), Box::new(then), Box::new(otherwise));
        self.checked(Expr { kind, start, depth })
    }

    /// The rest of `key op value`, at the operator; right-associative.
    #[inline(never)]
    fn assignment(&mut self, target: Expr, op: AssignOp) -> Result<Expr, Located> {
        let ExprKind::Name(key) = target.kind else {
            return Err((
                ScriptErrorKind::InvalidAssignTarget { op: op.symbol() },
                target.start,
            ));
        };
        let op_at = self.bump();
        let rhs = self.expr(BP_ASSIGN)?;
        let start = target.start;
        let depth = rhs.depth + 1;
        self.checked(Expr {
            kind: ExprKind::Assign(op, op_at, key, start, Box::new(rhs)),
            start,
            depth,
        })
    }

    fn unary(&mut self) -> Result<Expr, Located> {
        let op = match self.peek() {
            Tok::Minus => UnOp::Neg,
            Tok::Tilde => UnOp::BitNot,
            Tok::Bang => UnOp::Not,
            _ => return self.primary(),
        };
        self.nested(|p| p.prefix(op))
    }

    /// `op operand`, at the operator.
    #[inline(never)]
    fn prefix(&mut self, op: UnOp) -> Result<Expr, Located> {
        let op_at = self.bump();
        // `-9223372036854775808` is i64::MIN, whose magnitude alone does not fit an i64.
        if let (UnOp::Neg, Tok::Int(v)) = (op, self.peek())
            && v == 1 << 63
        {
            self.bump();
            return Ok(Expr::leaf(ExprKind::Int(i64::MIN), op_at));
        }
        let operand = self.unary()?;
        let depth = operand.depth + 1;
        self.checked(Expr {
            kind: ExprKind::Unary(op, op_at, Box::new(operand)),
            start: op_at,
            depth,
        })
    }

    #[inline(never)]
    fn primary(&mut self) -> Result<Expr, Located> {
        let t = self.token().clone();
        let kind = match t.kind {
            Tok::Int(v) => match i64::try_from(v) {
                Ok(v) => ExprKind::Int(v),
                Err(_) => {
                    return Err((
                        ScriptErrorKind::BadNumber {
                            text: self.text(&t).into(),
                            reason: "larger than the largest integer (i64)",
                        },
                        t.start,
                    ))
                }
            },
            Tok::Real(v) => ExprKind::Real(v),
            Tok::True => ExprKind::Bool(true),
            Tok::False => ExprKind::Bool(false),
            Tok::Str => ExprKind::Str(self.src[t.start + 1..t.end - 1].into()),
            Tok::Ident => ExprKind::Name(self.text(&t).into()),
            Tok::LParen => {
                self.bump();
                let mut inner = self.expr(BP_ASSIGN)?;
                if self.peek() != Tok::RParen {
                    return Err(self.expected("`)`"));
                }
                self.bump();
                // A parenthesised expression starts at its `(`.
                inner.start = t.start;
                return Ok(inner);
            }
            _ => return Err(self.expected("an expression")),
        };
        self.bump();
        Ok(Expr::leaf(kind, t.start))
    }
}

// Binding powers, loosest first.
const BP_ASSIGN: u8 = 1;
const BP_TERNARY: u8 = 2;
const BP_OR: u8 = 3;
const BP_AND: u8 = 4;
const BP_COMPARE: u8 = 5;
const BP_BIT_OR: u8 = 6;
const BP_BIT_AND: u8 = 7;
const BP_ADD: u8 = 8;
const BP_MUL: u8 = 9;

/// What an infix token does.
enum Infix {
    Binary(BinOp),
    Compare,
    Ternary,
    Assign(AssignOp),
}

/// The binding power and meaning of `t` as an infix operator.
fn infix(t: Tok) -> Option<(u8, Infix)> {
    Some(match t {
        Tok::ColonAssign => (BP_ASSIGN, Infix::Assign(AssignOp::Create)),
        Tok::Assign => (BP_ASSIGN, Infix::Assign(AssignOp::Existing)),
        Tok::PlusAssign => (BP_ASSIGN, Infix::Assign(AssignOp::Compound(BinOp::Add))),
        Tok::MinusAssign => (BP_ASSIGN, Infix::Assign(AssignOp::Compound(BinOp::Sub))),
        Tok::StarAssign => (BP_ASSIGN, Infix::Assign(AssignOp::Compound(BinOp::Mul))),
        Tok::SlashAssign => (BP_ASSIGN, Infix::Assign(AssignOp::Compound(BinOp::Div))),
        Tok::Question => (BP_TERNARY, Infix::Ternary),
        Tok::OrOr => (BP_OR, Infix::Binary(BinOp::Or)),
        Tok::AndAnd => (BP_AND, Infix::Binary(BinOp::And)),
        t if comparison(t).is_some() => (BP_COMPARE, Infix::Compare),
        Tok::Pipe => (BP_BIT_OR, Infix::Binary(BinOp::BitOr)),
        Tok::Caret => (BP_BIT_OR, Infix::Binary(BinOp::BitXor)),
        Tok::Amp => (BP_BIT_AND, Infix::Binary(BinOp::BitAnd)),
        Tok::Plus => (BP_ADD, Infix::Binary(BinOp::Add)),
        Tok::Minus => (BP_ADD, Infix::Binary(BinOp::Sub)),
        Tok::DotDot => (BP_ADD, Infix::Binary(BinOp::Concat)),
        Tok::Star => (BP_MUL, Infix::Binary(BinOp::Mul)),
        Tok::Slash => (BP_MUL, Infix::Binary(BinOp::Div)),
        _ => return None,
    })
}

fn comparison(t: Tok) -> Option<CmpOp> {
    Some(match t {
        Tok::EqEq => CmpOp::Eq,
        Tok::NotEq => CmpOp::Ne,
        Tok::Lt => CmpOp::Lt,
        Tok::Le => CmpOp::Le,
        Tok::Gt => CmpOp::Gt,
        Tok::Ge => CmpOp::Ge,
        _ => return None,
    })
}
