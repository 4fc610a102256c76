//! Script values, and how they are read from and written to blackboard entries.

use std::any::Any;
use std::borrow::Cow;
use std::fmt;
use std::time::Duration;

use neurotree_core::{Blackboard, ScopeId};

use super::error::ScriptErrorKind;

/// The value of a script expression.
///
/// Scripts compute with 64-bit integers, 64-bit reals, booleans and strings. `Empty` is the
/// value of a script with no expression at all (such as `""` or `";"`).
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// An integer: integer literals, integer entries, enum values, and `+ - *` of integers.
    Int(i64),
    /// A real: real literals, `f64`/`f32` entries, `/`, and arithmetic mixing reals in.
    Real(f64),
    /// A boolean: `true`/`false`, comparisons, `&&`, `||` and `!`.
    Bool(bool),
    /// A string: `'literals'`, `String` entries, and `..` concatenations.
    Str(String),
    /// No value: the result of an empty script.
    Empty,
}

impl Value {
    /// The value of a blackboard entry, if scripts can use its type.
    ///
    /// Reads `i64`, `i32`, `i16`, `i8`, `u64`, `u32`, `u16`, `u8`, `isize` and `usize` as
    /// [`Value::Int`] (`None` for a `u64`/`usize` above `i64::MAX`), `f64` and `f32` as
    /// [`Value::Real`], `bool` as [`Value::Bool`] and `String` as [`Value::Str`] (a copy).
    /// Other types (including `&str`) give `None`.
    pub fn from_any(any: &dyn Any) -> Option<Value> {
        macro_rules! try_int {
            ($($t:ty),*) => {$(
                if let Some(v) = any.downcast_ref::<$t>() {
                    return i64::try_from(*v).ok().map(Value::Int);
                }
            )*};
        }
        try_int!(i64, i32, u32, u64, i16, u16, i8, u8, isize, usize);
        if let Some(v) = any.downcast_ref::<f64>() {
            return Some(Value::Real(*v));
        }
        if let Some(v) = any.downcast_ref::<f32>() {
            return Some(Value::Real(f64::from(*v)));
        }
        if let Some(v) = any.downcast_ref::<bool>() {
            return Some(Value::Bool(*v));
        }
        any.downcast_ref::<String>().map(|s| Value::Str(s.clone()))
    }

    /// How scripts name the value's type: `int`, `real`, `bool`, `string` or `empty`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Int(_) => "int",
            Value::Real(_) => "real",
            Value::Bool(_) => "bool",
            Value::Str(_) => "string",
            Value::Empty => "empty",
        }
    }

    /// Writes `value` to `key` as seen from `scope`, as a script assignment does, and
    /// returns the value as stored.
    ///
    /// An existing entry keeps its type: integer entries (`i64`, `i32`, `u8`, ...) accept
    /// integers, booleans (as 0 or 1) and reals without a fractional part, if the value
    /// fits; `f64`/`f32` entries accept any number (booleans as 0 or 1); `bool` entries
    /// accept booleans and the numbers 0 and 1; `String` entries accept strings only. A
    /// missing entry is created as `i64`, `f64`, `bool` or `String`, *untyped*
    /// ([`Blackboard::set_untyped_in`]): as in BehaviorTree.CPP, a later assignment may give
    /// it a number or boolean of another type (an integer entry takes whole numbers and
    /// booleans, a real or boolean one any number, becoming a real; text that reads as a
    /// number makes a numeric entry a real), while a text entry takes only text. Writing
    /// [`Value::Empty`] is an error, and nothing is written when an error is returned.
    pub fn store(
        self,
        blackboard: &mut Blackboard,
        scope: ScopeId,
        key: &str,
        stamp: Duration,
    ) -> Result<Value, ScriptErrorKind> {
        let v = Val::from_value(self).ok_or(ScriptErrorKind::WrongEntryType {
            key: key.into(),
            entry: entry_type_name(blackboard, scope, key),
            value: "empty",
        })?;
        store(blackboard, scope, key, v, stamp).map(Val::into_value)
    }
}

/// Prints integers and booleans as in scripts, reals as Rust prints an `f64` (`2.5`, `3`,
/// `inf`), strings without quotes and `Empty` as nothing. This is also how `..` turns a
/// number into text.
impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Int(v) => write!(f, "{v}"),
            Value::Real(v) => write!(f, "{v}"),
            Value::Bool(v) => write!(f, "{v}"),
            Value::Str(v) => f.write_str(v),
            Value::Empty => Ok(()),
        }
    }
}

impl From<i64> for Value {
    fn from(v: i64) -> Self {
        Value::Int(v)
    }
}

impl From<f64> for Value {
    fn from(v: f64) -> Self {
        Value::Real(v)
    }
}

impl From<bool> for Value {
    fn from(v: bool) -> Self {
        Value::Bool(v)
    }
}

impl From<String> for Value {
    fn from(v: String) -> Self {
        Value::Str(v)
    }
}

impl From<&str> for Value {
    fn from(v: &str) -> Self {
        Value::Str(v.into())
    }
}

/// A value during evaluation: like [`Value`] without `Empty`, and with strings that may
/// borrow from the script's literals, so that evaluating them does not allocate.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Val<'s> {
    Int(i64),
    Real(f64),
    Bool(bool),
    Str(Cow<'s, str>),
}

impl Val<'_> {
    pub(crate) fn type_name(&self) -> &'static str {
        match self {
            Val::Int(_) => "int",
            Val::Real(_) => "real",
            Val::Bool(_) => "bool",
            Val::Str(_) => "string",
        }
    }

    pub(crate) fn into_value(self) -> Value {
        match self {
            Val::Int(v) => Value::Int(v),
            Val::Real(v) => Value::Real(v),
            Val::Bool(v) => Value::Bool(v),
            Val::Str(v) => Value::Str(v.into_owned()),
        }
    }

    pub(crate) fn from_value(v: Value) -> Option<Val<'static>> {
        Some(match v {
            Value::Int(v) => Val::Int(v),
            Value::Real(v) => Val::Real(v),
            Value::Bool(v) => Val::Bool(v),
            Value::Str(v) => Val::Str(Cow::Owned(v)),
            Value::Empty => return None,
        })
    }
}

impl fmt::Display for Val<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Val::Int(v) => write!(f, "{v}"),
            Val::Real(v) => write!(f, "{v}"),
            Val::Bool(v) => write!(f, "{v}"),
            Val::Str(v) => f.write_str(v),
        }
    }
}

/// Reads `key` as seen from `scope`. Allocates only to copy a `String` entry (and to build
/// an error).
pub(crate) fn load(
    blackboard: &Blackboard,
    scope: ScopeId,
    key: &str,
) -> Result<Val<'static>, ScriptErrorKind> {
    let Some(any) = blackboard.get_any_in(scope, key) else {
        return Err(ScriptErrorKind::UnknownKey { key: key.into() });
    };
    let any: &dyn Any = any;
    Value::from_any(any)
        .and_then(Val::from_value)
        .ok_or_else(|| ScriptErrorKind::UnsupportedEntryType {
            key: key.into(),
            type_name: entry_type_name(blackboard, scope, key),
        })
}

/// The Rust type of the entry `key`, for error messages.
fn entry_type_name(blackboard: &Blackboard, scope: ScopeId, key: &str) -> &'static str {
    blackboard
        .info_in(scope, key)
        .map_or("(missing)", |i| i.type_name)
}

/// Stores `v` in `key` (see [`Value::store`]) and returns the value as stored. Allocates
/// only when creating an entry or storing a string.
pub(crate) fn store<'s>(
    blackboard: &mut Blackboard,
    scope: ScopeId,
    key: &str,
    v: Val<'s>,
    stamp: Duration,
) -> Result<Val<'s>, ScriptErrorKind> {
    let Some(any) = blackboard.get_any_in(scope, key) else {
        // Untyped, as BehaviorTree.CPP's script-created entries; an entry a port declared
        // (present, not written yet) becomes typed.
        match &v {
            Val::Int(i) => blackboard.set_untyped_in(scope, key, *i, stamp)?,
            Val::Real(r) => blackboard.set_untyped_in(scope, key, *r, stamp)?,
            Val::Bool(b) => blackboard.set_untyped_in(scope, key, *b, stamp)?,
            Val::Str(s) => blackboard.set_untyped_in(scope, key, s.clone().into_owned(), stamp)?,
        }
        return Ok(v);
    };
    let any: &dyn Any = any;
    if blackboard.is_untyped_in(scope, key) {
        return store_untyped(blackboard, scope, key, v, stamp);
    }

    macro_rules! store_int {
        ($($t:ty),*) => {$(
            if any.is::<$t>() {
                let x: $t = to_int(&v, key, stringify!($t))?;
                blackboard.set_in(scope, key, x, stamp)?;
                // Read back as `from_any` would, except for u64 values past i64::MAX.
                return Ok(match i64::try_from(x) {
                    Ok(i) => Val::Int(i),
                    Err(_) => Val::Real(x as f64),
                });
            }
        )*};
    }
    store_int!(i64, i32, u32, u64, i16, u16, i8, u8, isize, usize);

    if any.is::<f64>() {
        let x = to_real(&v, key, "f64")?;
        blackboard.set_in(scope, key, x, stamp)?;
        return Ok(Val::Real(x));
    }
    if any.is::<f32>() {
        // As BehaviorTree.CPP, narrowing to f32 rounds without complaint.
        let x = to_real(&v, key, "f32")? as f32;
        blackboard.set_in(scope, key, x, stamp)?;
        return Ok(Val::Real(f64::from(x)));
    }
    if any.is::<bool>() {
        let x = match v {
            Val::Bool(b) => b,
            Val::Int(0) => false,
            Val::Int(1) => true,
            Val::Real(0.0) => false,
            Val::Real(1.0) => true,
            Val::Int(_) | Val::Real(_) => return Err(out_of_range(&v, key, "bool")),
            Val::Str(_) => return Err(wrong_type(&v, key, "bool")),
        };
        blackboard.set_in(scope, key, x, stamp)?;
        return Ok(Val::Bool(x));
    }
    if any.is::<String>() {
        let Val::Str(s) = &v else {
            return Err(wrong_type(&v, key, "String"));
        };
        let owned = s.clone().into_owned();
        blackboard.set_in(scope, key, owned, stamp)?;
        return Ok(v);
    }
    Err(ScriptErrorKind::UnsupportedEntryType {
        key: key.into(),
        type_name: entry_type_name(blackboard, scope, key),
    })
}

/// Stores `v` in the untyped entry `key` (one a script created), as BehaviorTree.CPP's
/// `Any::copyInto` does into an entry that holds a value already: its numbers are either
/// integers or reals (a script's `true` is the real 1.0), and a number goes into the
/// entry's kind of number, which may be another Rust type than the entry's (so `a := true;
/// a := 3` leaves the real 3.0). Text that reads as a number makes a numeric entry that real
/// (BT.CPP's `StringToDouble`); a text entry takes only text.
fn store_untyped<'s>(
    blackboard: &mut Blackboard,
    scope: ScopeId,
    key: &str,
    v: Val<'s>,
    stamp: Duration,
) -> Result<Val<'s>, ScriptErrorKind> {
    let Some(any) = blackboard.get_any_in(scope, key) else {
        return Err(ScriptErrorKind::UnknownKey { key: key.into() });
    };
    if any.is::<String>() {
        let Val::Str(s) = &v else {
            return Err(wrong_type(&v, key, "String"));
        };
        blackboard.set_untyped_in(scope, key, s.clone().into_owned(), stamp)?;
        return Ok(v);
    }
    let entry = entry_type_name(blackboard, scope, key);
    // Text into a number: the real it reads as.
    if let Val::Str(s) = &v {
        let Ok(x) = s.trim().parse::<f64>() else {
            return Err(wrong_type(&v, key, entry));
        };
        blackboard.set_untyped_in(scope, key, x, stamp)?;
        return Ok(Val::Real(x));
    }
    let integer = any.is::<i64>();
    if integer {
        let x: i64 = to_int(&v, key, entry)?;
        blackboard.set_untyped_in(scope, key, x, stamp)?;
        return Ok(Val::Int(x));
    }
    // A real, or a boolean (which BehaviorTree.CPP holds as a real): the same value stays a
    // boolean, anything else becomes a real.
    if let (true, Val::Bool(b)) = (any.is::<bool>(), &v) {
        let b = *b;
        blackboard.set_untyped_in(scope, key, b, stamp)?;
        return Ok(Val::Bool(b));
    }
    let x = to_real(&v, key, entry)?;
    blackboard.set_untyped_in(scope, key, x, stamp)?;
    Ok(Val::Real(x))
}

fn wrong_type(v: &Val<'_>, key: &str, entry: &'static str) -> ScriptErrorKind {
    ScriptErrorKind::WrongEntryType {
        key: key.into(),
        entry,
        value: v.type_name(),
    }
}

fn out_of_range(v: &Val<'_>, key: &str, entry: &'static str) -> ScriptErrorKind {
    ScriptErrorKind::OutOfRange {
        key: key.into(),
        entry,
        value: v.to_string(),
    }
}

/// `v` as an integer of type `T`: integers and booleans if they fit, reals only if they have
/// no fractional part and fit (BehaviorTree.CPP refuses to truncate too).
fn to_int<T: TryFrom<i128>>(
    v: &Val<'_>,
    key: &str,
    entry: &'static str,
) -> Result<T, ScriptErrorKind> {
    let wide = match v {
        Val::Int(i) => Some(i128::from(*i)),
        Val::Bool(b) => Some(i128::from(*b)),
        // `as` saturates, and every saturated value is out of range for T.
        Val::Real(r) if r.is_finite() && r.fract() == 0.0 => Some(*r as i128),
        Val::Real(_) => None,
        Val::Str(_) => return Err(wrong_type(v, key, entry)),
    };
    wide.and_then(|w| T::try_from(w).ok())
        .ok_or_else(|| out_of_range(v, key, entry))
}

/// `v` as a real: any number, booleans as 0 or 1.
fn to_real(v: &Val<'_>, key: &str, entry: &'static str) -> Result<f64, ScriptErrorKind> {
    match v {
        Val::Int(i) => Ok(*i as f64),
        Val::Real(r) => Ok(*r),
        Val::Bool(b) => Ok(f64::from(u8::from(*b))),
        Val::Str(_) => Err(wrong_type(v, key, entry)),
    }
}
