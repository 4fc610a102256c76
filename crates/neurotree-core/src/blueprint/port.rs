//! Ports: the named inputs and outputs of a node, bound to text or to a blackboard entry.
//!
//! A BehaviorTree.CPP file gives a node its parameters as attributes:
//! `<MoveTo goal="{target}" speed="0.5"/>`. Each attribute is a [`Port`]: `speed` is bound
//! to the literal text `0.5`, converted to the type the node asks for when it reads it;
//! `goal` is bound to the blackboard entry `target`, read or written through the node's
//! scope (so a SubTree's remapping applies, and `{@key}` reaches the root). Leaves read them
//! through [`Handle::input`](crate::Handle::input) and
//! [`Handle::output`](crate::Handle::output).

use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::any::{Any, TypeId};
use core::str::FromStr;

use crate::blackboard::BlackboardError;
use crate::PortDirection;

/// What a port is bound to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PortValue {
    /// Text, converted to the reader's type on each read.
    Literal(String),
    /// A blackboard entry, by key as seen from the node's scope (`@key`: the root's).
    Entry(String),
}

/// One port of a node and its binding.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Port {
    /// The port's name (the XML attribute).
    pub name: String,
    /// What it is bound to.
    pub value: PortValue,
    /// The type its node declares for it; a read or write as an incompatible type is a
    /// [`PortError::TypeMismatch`]. [`PortType::ANY`] unless declared.
    pub declared: PortType,
}

impl Port {
    /// A port bound to literal text, of no declared type.
    pub fn literal(name: &str, text: &str) -> Self {
        Self {
            name: String::from(name),
            value: PortValue::Literal(String::from(text)),
            declared: PortType::ANY,
        }
    }

    /// A port bound to a blackboard entry, of no declared type.
    pub fn entry(name: &str, key: &str) -> Self {
        Self {
            name: String::from(name),
            value: PortValue::Entry(String::from(key)),
            declared: PortType::ANY,
        }
    }

    /// The same port, declared of type `declared`.
    ///
    /// ```
    /// use neurotree_core::{Port, PortType};
    ///
    /// let port = Port::literal("speed", "2").with_type(PortType::of::<u8>());
    /// assert!(port.declared.reads_as::<f64>());
    /// assert!(!port.declared.reads_as::<Vec<u8>>());
    /// ```
    pub fn with_type(self, declared: PortType) -> Self {
        Self { declared, ..self }
    }
}

/// The type a node declares for a port, as reads and writes are checked against it.
///
/// Compatibility follows what BehaviorTree.CPP's `Any` converts between (`Any::cast`, and
/// `Blackboard::set` for writes):
///
/// | declared | read as | written as |
/// |---|---|---|
/// | untyped ([`ANY`](Self::ANY), BehaviorTree.CPP's `AnyTypeAllowed`) | any type | any type |
/// | a number or `bool` | any number or `bool` (converted with range checks), `String` | any number or `bool`, `String` |
/// | `String` | `String`, any number or `bool` (parsed) | `String` |
/// | any other type | that type | that type |
///
/// The value itself is still checked when it is converted: a number that does not fit, or
/// text that does not parse, is its own error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PortType {
    class: TypeClass,
    name: &'static str,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TypeClass {
    Any,
    Number,
    Text,
    Exact(TypeId),
}

impl PortType {
    /// Untyped: read and written as any type.
    pub const ANY: PortType = PortType {
        class: TypeClass::Any,
        name: "AnyTypeAllowed",
    };

    /// The port type of values of `T`.
    pub fn of<T: Any>() -> PortType {
        let id = TypeId::of::<T>();
        let class = if is_number(id) {
            TypeClass::Number
        } else if id == TypeId::of::<String>() {
            TypeClass::Text
        } else {
            TypeClass::Exact(id)
        };
        PortType {
            class,
            name: core::any::type_name::<T>(),
        }
    }

    /// The port type a built-in declaration names (one of
    /// [`PORT_TYPES`](crate::nodes::PORT_TYPES): `"i32"`, `"u64"`, `"bool"`, `"f64"` or
    /// `"String"`); untyped for any other name.
    pub const fn named(name: &'static str) -> PortType {
        let class = match name.as_bytes() {
            b"i32" | b"u64" | b"bool" | b"f64" => TypeClass::Number,
            b"String" => TypeClass::Text,
            _ => return PortType::ANY,
        };
        PortType { class, name }
    }

    /// The declared type's name, as errors print it.
    pub const fn name(&self) -> &'static str {
        self.name
    }

    /// `true` for an untyped port.
    pub const fn is_any(&self) -> bool {
        matches!(self.class, TypeClass::Any)
    }

    /// `true` if the port may be read as `T`.
    #[inline]
    pub fn reads_as<T: Any>(&self) -> bool {
        match self.class {
            TypeClass::Any => true,
            TypeClass::Exact(id) => id == TypeId::of::<T>(),
            TypeClass::Number | TypeClass::Text => {
                let id = TypeId::of::<T>();
                is_number(id) || id == TypeId::of::<String>()
            }
        }
    }

    /// `true` if the port may be written as `T`.
    #[inline]
    pub fn writes_as<T: Any>(&self) -> bool {
        match self.class {
            TypeClass::Any => true,
            TypeClass::Exact(id) => id == TypeId::of::<T>(),
            TypeClass::Number => {
                let id = TypeId::of::<T>();
                is_number(id) || id == TypeId::of::<String>()
            }
            // BehaviorTree.CPP's `Blackboard::set` refuses a number in a text entry.
            TypeClass::Text => TypeId::of::<T>() == TypeId::of::<String>(),
        }
    }
}

/// `true` for Rust's number types and `bool`: the types [`Number`] converts among.
fn is_number(id: TypeId) -> bool {
    [
        TypeId::of::<i8>(),
        TypeId::of::<i16>(),
        TypeId::of::<i32>(),
        TypeId::of::<i64>(),
        TypeId::of::<i128>(),
        TypeId::of::<isize>(),
        TypeId::of::<u8>(),
        TypeId::of::<u16>(),
        TypeId::of::<u32>(),
        TypeId::of::<u64>(),
        TypeId::of::<u128>(),
        TypeId::of::<usize>(),
        TypeId::of::<f32>(),
        TypeId::of::<f64>(),
        TypeId::of::<bool>(),
    ]
    .contains(&id)
}

/// Why a port could not be read or written.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PortError {
    /// The node has no port of this name.
    #[error("no port `{port}` on this node")]
    NoSuchPort {
        /// The port asked for.
        port: String,
    },
    /// The text does not convert to the type asked for.
    #[error("port `{port}`: cannot read `{text}` as {type_name}")]
    Convert {
        /// The port.
        port: String,
        /// The text that failed.
        text: String,
        /// The type asked for.
        type_name: &'static str,
    },
    /// An output port bound to a literal has nowhere to write.
    #[error("port `{port}` is bound to a literal; bind it to an entry (`{{key}}`) to write it")]
    NotAnEntry {
        /// The port.
        port: String,
    },
    /// The entry holds a number (or bool) of another type that does not fit the type asked
    /// for: out of range, or a real with a fraction where an integer is wanted.
    #[error("port `{port}`: the entry's value {value} does not fit {type_name}")]
    OutOfRange {
        /// The port.
        port: String,
        /// The value, printed.
        value: String,
        /// The type asked for.
        type_name: &'static str,
    },
    /// The node reads or writes the port as a type its declaration does not allow (see
    /// [`PortType`]).
    #[error(
        "node `{node}`: port `{port}` is declared as {declared}; it cannot be {} as {requested}",
        if *.written { "written" } else { "read" }
    )]
    TypeMismatch {
        /// The node's path.
        node: String,
        /// The port.
        port: String,
        /// The declared type.
        declared: &'static str,
        /// The type the node read or wrote it as.
        requested: &'static str,
        /// `true` for a write, `false` for a read.
        written: bool,
    },
    /// The bound entry could not be read or written.
    #[error("port `{port}`: {source}")]
    Blackboard {
        /// The port.
        port: String,
        /// What the blackboard said.
        source: BlackboardError,
    },
}

crate::debug_shows_message!(enum PortError {
    NoSuchPort { port },
    Convert { port, text, type_name },
    NotAnEntry { port },
    OutOfRange { port, value, type_name },
    TypeMismatch { node, port, declared, requested, written },
    Blackboard { port, source },
});

/// Conversion from the text of a port (an XML attribute, or a text blackboard entry).
///
/// Implemented for the integers, floats, `bool` (`true`/`false` in any case, `1`/`0`),
/// `String` and `Vec<T>` (`;`-separated). Implement it for your own types to read them from
/// ports.
pub trait FromPortStr: Sized {
    /// Converts `text`, or says it is none: the caller's error names the port, the text
    /// and the type, which is all there is to say.
    #[allow(clippy::result_unit_err)]
    fn from_port_str(text: &str) -> Result<Self, ()>;

    /// Converts a blackboard entry's value of another type, as BehaviorTree.CPP's `Any`
    /// converts: `None` if this type does not convert from that one, `Err` with the value
    /// printed if it does but the value does not fit. The numbers and `bool` convert among
    /// themselves (see [`Number`]); other types convert from nothing but text.
    fn from_other(_value: &dyn Any) -> Option<Result<Self, String>> {
        None
    }
}

/// A number or boolean held by a blackboard entry of any of Rust's number types, as one
/// value that converts to each of them: integers between widths and signedness with a range
/// check, integers to reals when exact, reals to integers when whole and in range, and
/// `bool` to and from 0 and 1, as BehaviorTree.CPP's `Any` does. Nothing wraps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Number {
    /// Any integer type.
    Int(i128),
    /// `f32` or `f64`.
    Real(f64),
    /// `bool`.
    Bool(bool),
}

impl Number {
    /// The number `value` holds, if its type is one of Rust's numbers or `bool`.
    pub fn of(value: &dyn Any) -> Option<Number> {
        macro_rules! int {
            ($($t:ty),*) => {$(
                if let Some(v) = value.downcast_ref::<$t>() {
                    return Some(Number::Int(*v as i128));
                }
            )*};
        }
        int!(i64, i32, u32, u64, usize, isize, i8, i16, u8, u16, i128);
        if let Some(v) = value.downcast_ref::<u128>() {
            return Some(Number::Int(i128::try_from(*v).unwrap_or(i128::MAX)));
        }
        if let Some(v) = value.downcast_ref::<f64>() {
            return Some(Number::Real(*v));
        }
        if let Some(v) = value.downcast_ref::<f32>() {
            return Some(Number::Real(f64::from(*v)));
        }
        value.downcast_ref::<bool>().map(|b| Number::Bool(*b))
    }

    /// As an integer: reals only when whole, `bool` as 0 or 1.
    fn integer(self) -> Option<i128> {
        match self {
            Number::Int(i) => Some(i),
            // Within ±2^127 the cast is exact for a whole real (no `fract` without std).
            Number::Real(r) if r > -1.7e38 && r < 1.7e38 && (r as i128) as f64 == r => {
                Some(r as i128)
            }
            Number::Real(_) => None,
            Number::Bool(b) => Some(i128::from(b)),
        }
    }

    /// As a real: integers only when exact (within ±2^53).
    fn real(self) -> Option<f64> {
        match self {
            Number::Int(i) if i.unsigned_abs() <= 1 << 53 => Some(i as f64),
            Number::Int(_) => None,
            Number::Real(r) => Some(r),
            Number::Bool(b) => Some(f64::from(u8::from(b))),
        }
    }
}

impl core::fmt::Display for Number {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Number::Int(i) => write!(f, "{i}"),
            // Debug: short exponents for very large or small reals.
            Number::Real(r) => write!(f, "{r:?}"),
            Number::Bool(b) => write!(f, "{b}"),
        }
    }
}

macro_rules! from_port_str_integer {
    ($($t:ty),*) => {$(
        impl FromPortStr for $t {
            fn from_port_str(text: &str) -> Result<Self, ()> {
                <$t>::from_str(text.trim()).map_err(|_| ())
            }

            fn from_other(value: &dyn Any) -> Option<Result<Self, String>> {
                let n = Number::of(value)?;
                Some(n.integer().and_then(|i| <$t>::try_from(i).ok()).ok_or_else(|| n.to_string()))
            }
        }
    )*};
}

from_port_str_integer!(i8, i16, i32, i64, i128, isize, u8, u16, u32, u64, u128, usize);

impl FromPortStr for f64 {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        f64::from_str(text.trim()).map_err(|_| ())
    }

    fn from_other(value: &dyn Any) -> Option<Result<Self, String>> {
        let n = Number::of(value)?;
        Some(n.real().ok_or_else(|| n.to_string()))
    }
}

impl FromPortStr for f32 {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        f32::from_str(text.trim()).map_err(|_| ())
    }

    fn from_other(value: &dyn Any) -> Option<Result<Self, String>> {
        let n = Number::of(value)?;
        let max = f64::from(f32::MAX);
        let fits = |r: f64| !r.is_finite() || (-max..=max).contains(&r);
        Some(
            n.real()
                .filter(|r| fits(*r))
                .map(|r| r as f32)
                .ok_or_else(|| n.to_string()),
        )
    }
}

impl FromPortStr for bool {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        match text.trim() {
            "1" => Ok(true),
            "0" => Ok(false),
            t if t.eq_ignore_ascii_case("true") => Ok(true),
            t if t.eq_ignore_ascii_case("false") => Ok(false),
            _ => Err(()),
        }
    }

    fn from_other(value: &dyn Any) -> Option<Result<Self, String>> {
        let n = Number::of(value)?;
        Some(match n.integer() {
            Some(0) => Ok(false),
            Some(1) => Ok(true),
            _ => Err(n.to_string()),
        })
    }
}

impl FromPortStr for String {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        Ok(String::from(text))
    }

    /// A number or boolean entry read as text, as BehaviorTree.CPP's `Any` converts one to
    /// a string (reals in their shortest form).
    fn from_other(value: &dyn Any) -> Option<Result<Self, String>> {
        Number::of(value).map(|n| {
            Ok(match n {
                Number::Real(r) => r.to_string(),
                n => n.to_string(),
            })
        })
    }
}

/// A SubTree's literal port value as BehaviorTree.CPP 4.10 stores it in the subtree's
/// blackboard, so that scripts can do arithmetic with it: an integer (as `std::from_chars`
/// reads one: the whole text, no `+`, no spaces, no `.` or exponent) as an `i32` when it fits,
/// else an `i64`; else a real, read the same strict way; else the text.
pub enum Literal {
    /// Fits `i32`.
    Int(i32),
    /// An integer past `i32`.
    Long(i64),
    /// A real.
    Real(f64),
    /// Anything else.
    Text(String),
}

impl Literal {
    /// Reads `text` as BehaviorTree.CPP types a SubTree's literal.
    pub fn parse(text: &str) -> Literal {
        let strict = !text.is_empty()
            && !text.starts_with('+')
            && !text.contains(|c: char| c.is_whitespace());
        if strict && !text.contains(['.', 'e', 'E']) {
            if let Ok(i) = text.parse::<i64>() {
                return match i32::try_from(i) {
                    Ok(i) => Literal::Int(i),
                    Err(_) => Literal::Long(i),
                };
            }
        }
        // `from_chars` reads no hexadecimal real and no word but inf and nan.
        let looks_real = text.trim_start_matches('-').starts_with(|c: char| {
            c.is_ascii_digit() || c == '.' || c == 'i' || c == 'n' || c == 'I' || c == 'N'
        });
        if strict && looks_real {
            if let Ok(r) = text.parse::<f64>() {
                return Literal::Real(r);
            }
        }
        Literal::Text(String::from(text))
    }
}

impl<T: FromPortStr> FromPortStr for Vec<T> {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        if text.trim().is_empty() {
            return Ok(Vec::new());
        }
        text.split(';').map(T::from_port_str).collect()
    }
}

/// Which way the ports of node types carry data, by type name, as the types declare them
/// (a registry's node types, a `TreeNodesModel`): what a picture of a tree marks each port
/// with. A built-in node's ports need no entry ([`Blueprint::port_direction`] reads its
/// declaration).
///
/// ```
/// use neurotree_core::{PortDirection, PortDirections};
///
/// let mut directions = PortDirections::new();
/// directions.insert("ComputePathToPose", "path", PortDirection::Output);
/// assert_eq!(directions.get("ComputePathToPose", "path"), Some(PortDirection::Output));
/// assert_eq!(directions.get("ComputePathToPose", "goal"), None);
/// ```
///
/// [`Blueprint::port_direction`]: crate::Blueprint::port_direction
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PortDirections {
    types: alloc::collections::BTreeMap<String, Vec<(String, PortDirection)>>,
}

impl PortDirections {
    /// No type's ports.
    pub fn new() -> Self {
        Self::default()
    }

    /// Declares port `port` of type `type_name` to carry data `direction`.
    pub fn insert(&mut self, type_name: &str, port: &str, direction: PortDirection) {
        let ports = self.types.entry(type_name.to_string()).or_default();
        match ports.iter_mut().find(|(name, _)| name == port) {
            Some(known) => known.1 = direction,
            None => ports.push((port.to_string(), direction)),
        }
    }

    /// Which way port `port` of type `type_name` carries data, if declared.
    pub fn get(&self, type_name: &str, port: &str) -> Option<PortDirection> {
        self.types
            .get(type_name)?
            .iter()
            .find(|(name, _)| name == port)
            .map(|(_, direction)| *direction)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn numbers_bools_strings_and_lists() {
        assert_eq!(i32::from_port_str(" 42 "), Ok(42));
        assert_eq!(u8::from_port_str("-1"), Err(()));
        assert_eq!(f64::from_port_str("0.5"), Ok(0.5));
        for (text, b) in [("true", true), ("TRUE", true), ("True", true), ("1", true)] {
            assert_eq!(bool::from_port_str(text), Ok(b), "{text}");
        }
        assert_eq!(bool::from_port_str("0"), Ok(false));
        assert_eq!(bool::from_port_str("yes"), Err(()));
        assert_eq!(String::from_port_str("a b"), Ok(String::from("a b")));
        assert_eq!(Vec::<i32>::from_port_str("1;2;3"), Ok(vec![1, 2, 3]));
        assert_eq!(Vec::<i32>::from_port_str(""), Ok(vec![]));
        assert_eq!(Vec::<i32>::from_port_str("1;x"), Err(()));
    }

    #[test]
    fn entries_of_other_number_types_convert_as_any_does() {
        let from = |v: &dyn Any| i32::from_other(v);
        assert_eq!(from(&3_i64), Some(Ok(3)));
        assert_eq!(from(&3_u8), Some(Ok(3)));
        assert_eq!(from(&true), Some(Ok(1)));
        assert_eq!(from(&4.0_f64), Some(Ok(4)));
        // Never a wrap or a truncation: out of range and fractions are errors.
        assert_eq!(from(&3_000_000_000_i64), Some(Err("3000000000".into())));
        assert_eq!(from(&4.5_f64), Some(Err("4.5".into())));
        assert_eq!(u32::from_other(&-1_i64), Some(Err("-1".into())));
        assert_eq!(usize::from_other(&7_i64), Some(Ok(7)));
        // Integers to reals when exact, reals to f32 within range.
        assert_eq!(f64::from_other(&3_i64), Some(Ok(3.0)));
        assert_eq!(
            f64::from_other(&(1_i64 << 60)),
            Some(Err("1152921504606846976".into()))
        );
        assert_eq!(f32::from_other(&0.5_f64), Some(Ok(0.5)));
        assert_eq!(f32::from_other(&1e300_f64), Some(Err("1e300".into())));
        // bool from 0 and 1 only.
        assert_eq!(bool::from_other(&1_i64), Some(Ok(true)));
        assert_eq!(bool::from_other(&2_i64), Some(Err("2".into())));
        // Types that are no number convert from nothing but text.
        assert_eq!(i32::from_other(&String::from("3")), None);
        assert_eq!(Vec::<i32>::from_other(&3_i64), None);
        // Numbers read as text, as Any converts them to a string.
        assert_eq!(String::from_other(&3_i64), Some(Ok("3".into())));
        assert_eq!(String::from_other(&0.5_f64), Some(Ok("0.5".into())));
    }

    #[test]
    fn subtree_literals_are_typed_as_bt_cpp_types_them() {
        let kind = |text: &str| match Literal::parse(text) {
            Literal::Int(i) => alloc::format!("int {i}"),
            Literal::Long(i) => alloc::format!("long {i}"),
            Literal::Real(r) => alloc::format!("real {r}"),
            Literal::Text(t) => alloc::format!("text {t}"),
        };
        assert_eq!(kind("3"), "int 3");
        assert_eq!(kind("-7"), "int -7");
        assert_eq!(kind("3000000000"), "long 3000000000");
        assert_eq!(kind("0.5"), "real 0.5");
        assert_eq!(kind("1e3"), "real 1000");
        // What from_chars does not read whole stays text.
        for text in ["+3", " 3", "3 ", "1;2;3", "2.2;2.4", "0x10", "hello", ""] {
            assert_eq!(kind(text), alloc::format!("text {text}"), "{text:?}");
        }
    }
}
