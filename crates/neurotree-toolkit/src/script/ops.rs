//! What the operators do to values.

use std::borrow::Cow;
use std::cmp::Ordering;
use std::fmt::Write as _;

use super::ast::{BinOp, CmpOp, UnOp};
use super::error::ScriptErrorKind;
use super::value::Val;
use super::Enums;

/// Reals closer than this are `==` (BehaviorTree.CPP compares with `f32::EPSILON` too).
pub(crate) const REAL_EPSILON: f64 = f32::EPSILON as f64;

/// A number operand: booleans count as the integers 0 and 1, as in BehaviorTree.CPP.
#[derive(Clone, Copy)]
enum Num {
    I(i64),
    R(f64),
}

impl Num {
    fn of(v: &Val<'_>) -> Option<Num> {
        match v {
            Val::Int(i) => Some(Num::I(*i)),
            Val::Bool(b) => Some(Num::I(i64::from(*b))),
            Val::Real(r) => Some(Num::R(*r)),
            Val::Str(_) => None,
        }
    }

    fn real(self) -> f64 {
        match self {
            Num::I(i) => i as f64,
            Num::R(r) => r,
        }
    }
}

/// Truth of an operand of `&&`, `||` and `!`: booleans, and numbers other than zero.
/// `None` for strings.
pub(crate) fn truthy(v: &Val<'_>) -> Option<bool> {
    match v {
        Val::Bool(b) => Some(*b),
        Val::Int(i) => Some(*i != 0),
        Val::Real(r) => Some(*r != 0.0),
        Val::Str(_) => None,
    }
}

/// Truth of the condition of `?:`: as [`truthy`], and a string is true when not empty (as
/// in BehaviorTree.CPP).
pub(crate) fn condition(v: &Val<'_>) -> bool {
    match v {
        Val::Str(s) => !s.is_empty(),
        v => truthy(v).unwrap_or(false),
    }
}

/// `op v`.
pub(crate) fn unary<'s>(op: UnOp, v: Val<'s>) -> Result<Val<'s>, ScriptErrorKind> {
    let err = |v: &Val<'_>| ScriptErrorKind::UnaryType {
        op: op.symbol(),
        operand: v.type_name(),
    };
    match (op, Num::of(&v)) {
        (UnOp::Neg, Some(Num::I(i))) => i
            .checked_neg()
            .map(Val::Int)
            .ok_or(ScriptErrorKind::Overflow("-")),
        (UnOp::Neg, Some(Num::R(r))) => Ok(Val::Real(-r)),
        (UnOp::BitNot, Some(Num::I(i))) => Ok(Val::Int(!i)),
        (UnOp::Not, _) => truthy(&v).map(|b| Val::Bool(!b)).ok_or_else(|| err(&v)),
        _ => Err(err(&v)),
    }
}

/// `l op r`; a string result longer than `max_string` bytes is an error.
pub(crate) fn binary<'s>(
    op: BinOp,
    l: Val<'s>,
    r: Val<'s>,
    max_string: usize,
) -> Result<Val<'s>, ScriptErrorKind> {
    // Checked before joining two strings, so that the long one is never made; a number
    // adds at most a few dozen bytes, checked after.
    let too_long = |len: usize| ScriptErrorKind::StringTooLong {
        len,
        max: max_string,
    };
    let err = |l: &Val<'_>, r: &Val<'_>, hint: &'static str| ScriptErrorKind::BinaryType {
        op: op.symbol(),
        left: l.type_name(),
        right: r.type_name(),
        hint,
    };
    match op {
        BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div => {
            if let (Some(a), Some(b)) = (Num::of(&l), Num::of(&r)) {
                return arithmetic(op, a, b);
            }
            match (op, l, r) {
                // As in BehaviorTree.CPP, `+` also joins two strings.
                (BinOp::Add, Val::Str(a), Val::Str(b)) => {
                    let len = a.len().saturating_add(b.len());
                    if len > max_string {
                        return Err(too_long(len));
                    }
                    Ok(Val::Str(Cow::Owned(a.into_owned() + &b)))
                }
                (BinOp::Add, l, r) => Err(err(&l, &r, ": use `..` to join a string and a number")),
                (_, l, r) => Err(err(&l, &r, "")),
            }
        }
        BinOp::Concat => match (&l, &r) {
            (Val::Str(a), Val::Str(b)) if a.len().saturating_add(b.len()) > max_string => {
                Err(too_long(a.len().saturating_add(b.len())))
            }
            (Val::Str(_), _) | (_, Val::Str(_)) => {
                let joined = concat(l, &r);
                if joined.len() > max_string {
                    return Err(too_long(joined.len()));
                }
                Ok(Val::Str(Cow::Owned(joined)))
            }
            _ => Err(err(&l, &r, ": `..` needs at least one string operand")),
        },
        BinOp::BitAnd | BinOp::BitOr | BinOp::BitXor => match (Num::of(&l), Num::of(&r)) {
            (Some(Num::I(a)), Some(Num::I(b))) => Ok(Val::Int(match op {
                BinOp::BitAnd => a & b,
                BinOp::BitOr => a | b,
                _ => a ^ b,
            })),
            _ => Err(err(&l, &r, ": bitwise operators need integers")),
        },
        BinOp::And | BinOp::Or => match (truthy(&l), truthy(&r)) {
            (Some(a), Some(b)) => Ok(Val::Bool(if op == BinOp::And { a && b } else { a || b })),
            _ => Err(err(&l, &r, ": logical operators need booleans or numbers")),
        },
    }
}

/// `l .. r` as text: strings as they are, numbers as [`Value`](super::Value) prints them.
fn concat(l: Val<'_>, r: &Val<'_>) -> String {
    let mut s = match l {
        Val::Str(s) => s.into_owned(),
        l => l.to_string(),
    };
    let _ = write!(s, "{r}");
    s
}

/// `+ - * /` of numbers: integers stay integers for `+ - *` (overflow is an error); `/` and
/// anything involving a real give a real.
fn arithmetic<'s>(op: BinOp, a: Num, b: Num) -> Result<Val<'s>, ScriptErrorKind> {
    if let (Num::I(x), Num::I(y)) = (a, b) {
        let r = match op {
            BinOp::Add => x.checked_add(y),
            BinOp::Sub => x.checked_sub(y),
            BinOp::Mul => x.checked_mul(y),
            _ => return Ok(Val::Real(x as f64 / y as f64)),
        };
        return r
            .map(Val::Int)
            .ok_or(ScriptErrorKind::Overflow(op.symbol()));
    }
    let (x, y) = (a.real(), b.real());
    Ok(Val::Real(match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        _ => x / y,
    }))
}

/// `l op r` for one link of a comparison chain.
///
/// Numbers compare as numbers (integers exactly; with a real involved, `==` and `!=` allow a
/// difference up to [`REAL_EPSILON`]); strings compare by their bytes; a string and a
/// number compare after the string is read as a number (`true`, `false`, an enum name or a
/// decimal number), and it is an error if it is none of these.
pub(crate) fn compare(
    op: CmpOp,
    l: &Val<'_>,
    r: &Val<'_>,
    enums: &Enums,
) -> Result<bool, ScriptErrorKind> {
    let (a, b) = match (l, r) {
        (Val::Str(a), Val::Str(b)) => return Ok(ordered(op, a.as_bytes().cmp(b.as_bytes()))),
        (Val::Str(s), n) => (Some(string_number(s, enums)?), Num::of(n)),
        (n, Val::Str(s)) => (Num::of(n), Some(string_number(s, enums)?)),
        (a, b) => (Num::of(a), Num::of(b)),
    };
    let (Some(a), Some(b)) = (a, b) else {
        // Unreachable: every non-string value is a number.
        return Ok(false);
    };
    Ok(match (a, b) {
        (Num::I(x), Num::I(y)) => ordered(op, x.cmp(&y)),
        (a, b) => {
            let (x, y) = (a.real(), b.real());
            let same = x == y || (x - y).abs() <= REAL_EPSILON;
            match op {
                CmpOp::Eq => same,
                CmpOp::Ne => !same,
                CmpOp::Lt => x < y,
                CmpOp::Le => x <= y,
                CmpOp::Gt => x > y,
                CmpOp::Ge => x >= y,
            }
        }
    })
}

fn ordered(op: CmpOp, o: Ordering) -> bool {
    match op {
        CmpOp::Eq => o == Ordering::Equal,
        CmpOp::Ne => o != Ordering::Equal,
        CmpOp::Lt => o == Ordering::Less,
        CmpOp::Le => o != Ordering::Greater,
        CmpOp::Gt => o == Ordering::Greater,
        CmpOp::Ge => o != Ordering::Less,
    }
}

/// A string compared with a number, read as a number.
fn string_number(s: &str, enums: &Enums) -> Result<Num, ScriptErrorKind> {
    if let Some(v) = enums.get(s) {
        return Ok(Num::I(v));
    }
    let t = s.trim();
    match t {
        "true" => Ok(Num::I(1)),
        "false" => Ok(Num::I(0)),
        _ => t.parse::<i64>().map(Num::I).or_else(|_| {
            t.parse::<f64>()
                .map(Num::R)
                .map_err(|_| ScriptErrorKind::NotANumber { text: s.into() })
        }),
    }
}
