//! Evaluates expression trees against a blackboard.
//!
//! Nothing here allocates unless strings are involved (copying a `String` entry, joining
//! strings) or an entry is created or an error built: literals are read in place, keys are
//! looked up by `&str`, and writes to existing entries replace their values in place.

use std::borrow::Cow;

use super::ast::{AssignOp, BinOp, CmpOp, Expr, ExprKind, UnOp};
use super::error::{Located, ScriptErrorKind};
use super::ops;
use super::value::{load, store, Val};
use super::ScriptEnv;

/// The value of `e`. Operands are evaluated left to right, each exactly once; only `?:`
/// skips an operand (the branch it does not take).
///
/// Each kind of node has its own function, so that this one, which every level of nesting
/// goes through, keeps a small stack frame.
pub(crate) fn eval<'s>(e: &'s Expr, env: &mut ScriptEnv<'_>) -> Result<Val<'s>, Located> {
    match &e.kind {
        ExprKind::Int(v) => Ok(Val::Int(*v)),
        ExprKind::Real(v) => Ok(Val::Real(*v)),
        ExprKind::Bool(v) => Ok(Val::Bool(*v)),
        ExprKind::Str(s) => Ok(Val::Str(Cow::Borrowed(s))),
        ExprKind::Name(name) => name_value(name, e.start, env),
        ExprKind::Unary(op, at, operand) => unary(*op, *at, operand, env),
        ExprKind::Binary(op, at, l, r) => binary(*op, *at, l, r, env),
        ExprKind::Compare(operands, links) => compare(operands, links, env),
        ExprKind::Ternary(cond, then, otherwise) => ternary(cond, then, otherwise, env),
        ExprKind::Assign(op, op_at, key, key_at, value) => {
            assign(*op, *op_at, key, *key_at, value, env)
        }
    }
}

#[inline(never)]
fn name_value(name: &str, at: usize, env: &mut ScriptEnv<'_>) -> Result<Val<'static>, Located> {
    match env.enums.get(name) {
        Some(v) => Ok(Val::Int(v)),
        None => load(env.blackboard, env.scope, name).map_err(|k| (k, at)),
    }
}

#[inline(never)]
fn unary<'s>(
    op: UnOp,
    at: usize,
    operand: &'s Expr,
    env: &mut ScriptEnv<'_>,
) -> Result<Val<'s>, Located> {
    let v = eval(operand, env)?;
    ops::unary(op, v).map_err(|k| (k, at))
}

#[inline(never)]
fn binary<'s>(
    op: BinOp,
    at: usize,
    l: &'s Expr,
    r: &'s Expr,
    env: &mut ScriptEnv<'_>,
) -> Result<Val<'s>, Located> {
    // Both sides, always: `&&` and `||` do not short-circuit.
    let l = eval(l, env)?;
    let r = eval(r, env)?;
    ops::binary(op, l, r, env.max_string_len).map_err(|k| (k, at))
}

#[inline(never)]
fn compare<'s>(
    operands: &'s [Expr],
    links: &[(CmpOp, usize)],
    env: &mut ScriptEnv<'_>,
) -> Result<Val<'s>, Located> {
    let Some((first, rest)) = operands.split_first() else {
        return Ok(Val::Bool(true));
    };
    let mut lhs = eval(first, env)?;
    let mut all = true;
    for (operand, (op, at)) in rest.iter().zip(links) {
        let rhs = eval(operand, env)?;
        all &= ops::compare(*op, &lhs, &rhs, env.enums).map_err(|k| (k, *at))?;
        lhs = rhs;
    }
    Ok(Val::Bool(all))
}

#[inline(never)]
fn ternary<'s>(
    cond: &'s Expr,
    then: &'s Expr,
    otherwise: &'s Expr,
    env: &mut ScriptEnv<'_>,
) -> Result<Val<'s>, Located> {
    let c = eval(cond, env)?;
    if ops::condition(&c) {
        eval(then, env)
    } else {
        eval(otherwise, env)
    }
}

/// `key op value`. Its value is the value stored, as the entry holds it.
#[inline(never)]
fn assign<'s>(
    op: AssignOp,
    op_at: usize,
    key: &str,
    key_at: usize,
    value: &'s Expr,
    env: &mut ScriptEnv<'_>,
) -> Result<Val<'s>, Located> {
    if env.enums.get(key).is_some() {
        return Err((ScriptErrorKind::AssignToEnum(key.into()), key_at));
    }
    // As in BehaviorTree.CPP, a missing entry is reported before the value is evaluated.
    if op != AssignOp::Create && !env.blackboard.contains_in(env.scope, key) {
        return Err((ScriptErrorKind::UnknownKey { key: key.into() }, key_at));
    }
    let v = eval(value, env)?;
    let v = match op {
        AssignOp::Create | AssignOp::Existing => v,
        AssignOp::Compound(bin) => {
            // Read after evaluating the value, which may itself have written the entry.
            let current = load(env.blackboard, env.scope, key).map_err(|k| (k, key_at))?;
            ops::binary(bin, current, v, env.max_string_len).map_err(|k| (k, op_at))?
        }
    };
    store(env.blackboard, env.scope, key, v, env.stamp).map_err(|k| (k, key_at))
}
