//! BehaviorTree.CPP's script language: the code of `Script`, `ScriptCondition` and of the
//! `_skipIf`, `_successIf`, `_onSuccess`, ... attributes.
//!
//! A script is parsed once, when a tree is loaded ([`Script::parse`]), and evaluated on
//! each tick against the tree's blackboard ([`Script::eval`]). Evaluating reads and writes
//! blackboard entries, and never allocates for numeric and boolean expressions.
//!
//! ```
//! use neurotree::script::{Enums, Script, ScriptEnv, Value};
//! use neurotree::{Blackboard, ScopeId};
//! use std::time::Duration;
//!
//! let mut bb = Blackboard::new();
//! bb.set("battery", 42.5_f64).unwrap();
//! let mut enums = Enums::new();
//! enums.insert("DOCKING", 2);
//!
//! let script = Script::parse("low := battery < 50; mode := low ? DOCKING : 0; mode * 10")
//!     .unwrap();
//! let mut env = ScriptEnv {
//!     blackboard: &mut bb,
//!     scope: ScopeId::ROOT,
//!     enums: &enums,
//!     stamp: Duration::from_millis(10),
//!     max_string_len: 1 << 20,
//! };
//! // The value of a script is the value of its last expression.
//! assert_eq!(script.eval(&mut env), Ok(Value::Int(20)));
//! assert_eq!(bb.get::<bool>("low"), Ok(true));
//! assert_eq!(bb.get::<i64>("mode"), Ok(2));
//!
//! // Errors say where, and what.
//! let err = Script::parse("a := (1 + 2").unwrap_err();
//! assert_eq!(err.to_string(), "1:12: expected `)`, found end of script");
//! let err = Script::parse("mode = 'idle'").unwrap().eval(&mut ScriptEnv::new(&mut bb));
//! assert!(err.unwrap_err().to_string().starts_with("1:1: blackboard entry `mode` has type `i64`"));
//! ```
//!
//! # The language
//!
//! A script is a list of expressions separated by `;` (empty ones are allowed); its value
//! is that of the last expression, or [`Value::Empty`] if there is none. Whitespace,
//! newlines included, separates tokens anywhere.
//!
//! **Values** are integers (`i64`), reals (`f64`), booleans and strings. Literals: `42`,
//! `0x2A`, `1.5`, `1e3`, `2.5e-3`, `true`, `false`, `'text'` (or `"text"`; no escapes).
//! A name (`[A-Za-z_][A-Za-z0-9_]*`) is an enum value if the [`Enums`] table has it, else a
//! blackboard key looked up from [`ScriptEnv::scope`]; `@name` is the root scope's `name`.
//!
//! **Operators**, from the loosest to the tightest binding:
//!
//! | operators | meaning |
//! |---|---|
//! | `k := v`, `k = v`, `k += v`, `k -= v`, `k *= v`, `k /= v` | assignment (right-associative) |
//! | `c ? a : b` | `a` if `c` is true, else `b` (right-associative) |
//! | `a \|\| b` | logical or |
//! | `a && b` | logical and |
//! | `==` `!=` `<` `<=` `>` `>=` | comparison; `a < b < c` means `a < b && b < c` |
//! | `a \| b`, `a ^ b` | bitwise or, xor |
//! | `a & b` | bitwise and |
//! | `a + b`, `a - b`, `a .. b` | sum, difference, string concatenation |
//! | `a * b`, `a / b` | product, quotient |
//! | `-a`, `~a`, `!a` | negation, bitwise not, logical not |
//!
//! - `+ - *` of two integers give an integer (overflow is an error); `/` always gives a real
//!   (so `7 / 2` is `3.5` and `1 / 0` is infinity), and so does any operation with a real.
//!   Booleans count as the integers 0 and 1 in arithmetic, bitwise operations and
//!   comparisons, as in BehaviorTree.CPP. `+` also joins two strings.
//! - Bitwise operators need integers (or booleans); a real, even `4.0`, is an error.
//! - `&&`, `||` and `!` take booleans or numbers (non-zero is true) and give a boolean.
//!   **Both operands of `&&` and `||` are always evaluated**, as in BehaviorTree.CPP, so an
//!   assignment on the right happens whatever the left is. Every operand of a comparison
//!   chain is evaluated too, each once. Only `?:` skips the branch it does not take; its
//!   condition may also be a string, true when not empty.
//! - Comparisons: numbers as numbers (integers exactly; when a real is involved, `==` and
//!   `!=` treat values closer than `f32::EPSILON` as equal, as BehaviorTree.CPP does);
//!   strings by their bytes; a string and a number after reading the string as a number
//!   (`'true'`, `'false'`, an enum name or a decimal number; anything else is an error).
//! - `..` joins a string with a string or a number (at least one operand must be a string);
//!   numbers are written as [`Value`]'s `Display` does (`2.5`, `3` for `3.0`).
//!
//! **Assignment** writes the blackboard, stamped [`ScriptEnv::stamp`]. `:=` creates a
//! missing entry (as `i64`, `f64`, `bool` or `String`); `=` and the compound operators need
//! an existing one, and say so, naming the key. An entry's type is fixed by its first write:
//! assigning converts the value to the entry's type when it fits and is an error otherwise.
//! Integer entries take integers, booleans (0 or 1) and whole reals within their range (`4.0`
//! into an `i32` is `4`; `2.5`, or `300` into a `u8`, is an error, so `x /= 2` on an integer
//! entry works when the quotient is whole); real entries take any number; `bool` entries
//! take booleans, 0 and 1; `String` entries take strings only. Scripts read and write the
//! entry types `i64`,
//! `i32`, `i16`, `i8`, `u64`, `u32`, `u16`, `u8`, `isize`, `usize`, `f64`, `f32`, `bool` and
//! `String` (see [`Value::from_any`] and [`Value::store`]). An assignment's value is the
//! value stored, so `a := b := 0` sets both. Names in the enum table cannot be assigned.
//!
//! # Differences from BehaviorTree.CPP
//!
//! - BehaviorTree.CPP computes every number as a `double`. Here `+ - *` of two integers give
//!   an exact integer, and overflow is an error rather than a rounded `double`; `/` gives a
//!   real, as there (so division by zero is infinity or NaN, not an error).
//! - Mixing arithmetic and bitwise operators needs parentheses there; here they follow the
//!   precedence table.
//! - A comparison chain there stops evaluating at its first false link; here every operand
//!   is evaluated, like the operands of `&&` and `||` in both.
//! - There, a string assigned to a numeric entry is parsed as a number; here it is an error,
//!   since the entry's type is fixed. A number assigned to a `bool` entry must be 0 or 1.
//! - `..` writes a real the way Rust does (`3`, `2.5`), not as `std::to_string` (`3.000000`).
//! - Identifiers are ASCII only; strings may hold any UTF-8 text; newlines may separate
//!   tokens anywhere.
//!
//! # Errors
//!
//! Nothing panics, whatever the input. [`Script::parse`] reports unexpected characters and
//! tokens, unterminated strings, malformed or out-of-range numbers, assignments to things
//! that are not keys, and expressions nested more than 64 levels deep. [`Script::eval`]
//! reports unknown keys, type mismatches (naming the types), integer overflow and values
//! that do not fit their entry. Every [`ScriptError`] carries its byte offset, line and
//! column; [`ScriptError::render`] shows the line with a caret.

pub(crate) mod ast;
mod error;
mod eval;
mod lexer;
mod ops;
mod parser;
mod value;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_errors;

use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{Blackboard, BlackboardError, ScopeId};

pub use error::{ScriptError, ScriptErrorKind, EXCERPT_CHARS};
pub use value::Value;

/// A parsed script: immutable, cheap to clone (clones share the parsed program), `Send`
/// and `Sync`. See the [module docs](self) for the language.
#[derive(Clone)]
pub struct Script {
    source: Arc<str>,
    program: Arc<[ast::Expr]>,
}

impl Script {
    /// Parses `source`. Call it once, when the tree is loaded; an empty script (or one of
    /// only `;`) is valid and evaluates to [`Value::Empty`].
    pub fn parse(source: &str) -> Result<Script, ScriptError> {
        let program = parser::parse_program(source)
            .map_err(|(kind, offset)| ScriptError::new(kind, offset, source))?;
        Ok(Script {
            source: source.into(),
            program: program.into(),
        })
    }

    /// Its expressions, in order: what the linter follows entries through.
    pub(crate) fn program(&self) -> &[ast::Expr] {
        &self.program
    }

    /// The text this script was parsed from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Runs the script's expressions in order and returns the value of the last one.
    ///
    /// Stops at the first error; the writes of the expressions before it remain. Allocates
    /// only when strings are involved, when an entry is created, or to report an error.
    pub fn eval(&self, env: &mut ScriptEnv<'_>) -> Result<Value, ScriptError> {
        if env.scope.0 as usize >= env.blackboard.scope_count() {
            let kind =
                ScriptErrorKind::Blackboard(BlackboardError::NoSuchScope { scope: env.scope.0 });
            return Err(ScriptError::new(kind, 0, &self.source));
        }
        let mut last = Value::Empty;
        for (i, expr) in self.program.iter().enumerate() {
            let v = eval::eval(expr, env)
                .map_err(|(kind, offset)| ScriptError::new(kind, offset, &self.source))?;
            if i + 1 == self.program.len() {
                last = v.into_value();
            }
        }
        Ok(last)
    }
}

impl fmt::Debug for Script {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("Script").field(&&*self.source).finish()
    }
}

/// What a script runs against: the blackboard, the scope its keys are looked up from, the
/// enum table, and the stamp its writes carry.
#[derive(Debug)]
pub struct ScriptEnv<'a> {
    /// The blackboard that names resolve in and assignments write to.
    pub blackboard: &'a mut Blackboard,
    /// The scope keys are looked up from (a SubTree's scope for a node inside it).
    pub scope: ScopeId,
    /// Names that resolve to integers before the blackboard is consulted.
    pub enums: &'a Enums,
    /// The stamp of every write (normally the tree's clock).
    pub stamp: Duration,
    /// The longest string, in bytes, that `+` or `..` may make: past it the script fails
    /// with [`ScriptErrorKind::StringTooLong`] instead of doubling a string until memory
    /// runs out. [`DEFAULT_MAX_STRING_LEN`] unless set.
    pub max_string_len: usize,
}

/// The longest string a script makes unless its [`ScriptEnv`] says otherwise: 1 MiB.
pub const DEFAULT_MAX_STRING_LEN: usize = 1 << 20;

/// The table [`ScriptEnv::new`] uses.
static NO_ENUMS: Enums = Enums::new();

impl<'a> ScriptEnv<'a> {
    /// An environment on `blackboard`'s root scope, with no enums and writes stamped zero.
    pub fn new(blackboard: &'a mut Blackboard) -> Self {
        Self {
            blackboard,
            scope: ScopeId::ROOT,
            enums: &NO_ENUMS,
            stamp: Duration::ZERO,
            max_string_len: DEFAULT_MAX_STRING_LEN,
        }
    }
}

/// Enum values that scripts may name, such as `DOCKING` for `2`. They resolve before
/// blackboard keys, and cannot be assigned.
#[derive(Default, Clone, Debug)]
pub struct Enums {
    values: BTreeMap<String, i64>,
}

impl Enums {
    /// An empty table.
    pub const fn new() -> Self {
        Self {
            values: BTreeMap::new(),
        }
    }

    /// Defines `name` as `value`, returning the value it had before, if any.
    pub fn insert(&mut self, name: impl Into<String>, value: i64) -> Option<i64> {
        self.values.insert(name.into(), value)
    }

    /// The value of `name`, if defined. Does not allocate.
    pub fn get(&self, name: &str) -> Option<i64> {
        self.values.get(name).copied()
    }

    /// Number of names defined.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// `true` if no name is defined.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The names and their values, sorted by name.
    pub fn iter(&self) -> impl Iterator<Item = (&str, i64)> + '_ {
        self.values.iter().map(|(k, v)| (k.as_str(), *v))
    }
}

impl<S: Into<String>> FromIterator<(S, i64)> for Enums {
    fn from_iter<I: IntoIterator<Item = (S, i64)>>(iter: I) -> Self {
        let mut e = Enums::new();
        e.extend(iter);
        e
    }
}

impl<S: Into<String>> Extend<(S, i64)> for Enums {
    fn extend<I: IntoIterator<Item = (S, i64)>>(&mut self, iter: I) {
        for (k, v) in iter {
            self.insert(k, v);
        }
    }
}
