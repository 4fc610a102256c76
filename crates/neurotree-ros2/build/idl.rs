//! ROS 2's interface definitions (`.msg`, `.srv`, `.action`), the subset the bridge's
//! packages use: fields of primitive, string and message types, fixed arrays and bounded or
//! unbounded sequences, default values, constants, comments, and `---` between a service's
//! or an action's parts.

use std::fmt;
use std::path::{Path, PathBuf};

/// What a definition file declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `msg/Name.msg`: one message.
    Message,
    /// `srv/Name.srv`: a request and a response.
    Service,
    /// `action/Name.action`: a goal, a result and a feedback.
    Action,
}

impl Kind {
    /// The folder and extension of this kind of file.
    pub fn folder(self) -> &'static str {
        match self {
            Kind::Message => "msg",
            Kind::Service => "srv",
            Kind::Action => "action",
        }
    }

    /// How many `---`-separated parts the file has.
    fn parts(self) -> usize {
        match self {
            Kind::Message => 1,
            Kind::Service => 2,
            Kind::Action => 3,
        }
    }
}

/// A field's type as written: a primitive or a message, possibly an array of them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldType {
    /// `float64`, `string`, `Header`, `geometry_msgs/Pose`, …
    pub base: String,
    /// Whether and how it repeats.
    pub array: Array,
}

/// How a field repeats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Array {
    /// One value.
    None,
    /// `T[N]`: exactly N, no length on the wire.
    Fixed(usize),
    /// `T[]` or `T[<=N]`: a sequence (counted: its length first on the wire).
    Counted,
}

/// One field of a part.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Field {
    /// Its name.
    pub name: String,
    /// Its type.
    pub ty: FieldType,
    /// The default value as written, if any.
    pub default: Option<String>,
    /// Its comments.
    pub doc: Vec<String>,
}

/// One constant of a part.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Constant {
    /// Its name.
    pub name: String,
    /// Its primitive type.
    pub ty: String,
    /// Its value as written.
    pub value: String,
    /// Its comments.
    pub doc: Vec<String>,
}

/// One part: the message itself, or a service's or an action's request, response, goal,
/// result or feedback.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Part {
    /// The comments that open the part.
    pub doc: Vec<String>,
    /// Its constants, in order.
    pub constants: Vec<Constant>,
    /// Its fields, in order: the wire format.
    pub fields: Vec<Field>,
}

impl Part {
    /// Whether two parts have the same layout and constants, whatever their comments.
    pub fn same_layout(&self, other: &Part) -> bool {
        let fields = |p: &Part| {
            p.fields
                .iter()
                .map(|f| (f.name.clone(), f.ty.clone(), f.default.clone()))
                .collect::<Vec<_>>()
        };
        let constants = |p: &Part| {
            p.constants
                .iter()
                .map(|c| (c.name.clone(), c.ty.clone(), c.value.clone()))
                .collect::<Vec<_>>()
        };
        fields(self) == fields(other) && constants(self) == constants(other)
    }
}

/// A parsed definition file.
#[derive(Clone, Debug)]
pub struct Interface {
    /// Message, service or action.
    pub kind: Kind,
    /// Its name: the file's stem.
    pub name: String,
    /// The file, for messages.
    pub file: PathBuf,
    /// The comments that open the file, before its first blank line.
    pub doc: Vec<String>,
    /// Its parts, in order.
    pub parts: Vec<Part>,
}

/// A mistake in a definition file, with where it is.
#[derive(Debug)]
pub struct IdlError {
    /// The file.
    pub file: PathBuf,
    /// The line, from 1 (0: the file as a whole).
    pub line: usize,
    /// What is wrong and what to do.
    pub message: String,
}

impl fmt::Display for IdlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: error: {}", self.file.display(), self.message)
        } else {
            let (file, line, message) = (self.file.display(), self.line, &self.message);
            write!(f, "{file}:{line}:1: error: {message}")
        }
    }
}

/// The primitive types of ROS 2's IDL that the generator maps (`wstring` is not one).
pub const PRIMITIVES: [&str; 14] = [
    "bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
    "uint64", "float32", "float64", "string",
];

/// Reads `file`, a definition of `kind`.
pub fn parse(file: &Path, kind: Kind, text: &str) -> Result<Interface, IdlError> {
    let name = file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default()
        .to_owned();
    let error = |line: usize, message: String| IdlError {
        file: file.to_owned(),
        line,
        message,
    };
    if !name.chars().next().is_some_and(|c| c.is_ascii_uppercase())
        || !name.chars().all(|c| c.is_ascii_alphanumeric())
    {
        let message = format!("`{name}` is not a type name: name the file in CamelCase");
        return Err(error(0, message));
    }
    let mut parts = vec![Part::default()];
    let mut doc = Vec::new();
    let mut pending: Vec<String> = Vec::new();
    // The file's opening comments are its doc until a blank line ends them.
    let mut opening = true;
    for (index, raw) in text.lines().enumerate() {
        let number = index + 1;
        let (code, comment) = split_comment(raw);
        let code = code.trim();
        if code.is_empty() {
            match comment {
                Some(comment) => pending.push(comment),
                None if opening && !pending.is_empty() && parts.len() == 1 => {
                    doc = std::mem::take(&mut pending);
                    opening = false;
                }
                None => {
                    let part = parts.last_mut().expect("one part at least");
                    end_paragraph(&mut pending, part);
                }
            }
            continue;
        }
        opening = false;
        if code == "---" {
            if parts.len() == kind.parts() {
                let message = format!(
                    "a .{} file has {} parts: one `---` too many",
                    kind.folder(),
                    kind.parts()
                );
                return Err(error(number, message));
            }
            parts.push(Part::default());
            pending.clear();
            continue;
        }
        let mut line_doc = std::mem::take(&mut pending);
        line_doc.extend(comment);
        let part = parts.last_mut().expect("one part at least");
        parse_line(code, line_doc, part).map_err(|m| error(number, m))?;
    }
    if parts.len() != kind.parts() {
        let message = format!(
            "a .{} file has {} parts separated by `---`; this one has {}",
            kind.folder(),
            kind.parts(),
            parts.len()
        );
        return Err(error(0, message));
    }
    Ok(Interface {
        kind,
        name,
        file: file.to_owned(),
        doc,
        parts,
    })
}

/// A blank line ends a comment paragraph: the part's doc if nothing came before it in the
/// part, else nobody's.
fn end_paragraph(pending: &mut Vec<String>, part: &mut Part) {
    if part.fields.is_empty() && part.constants.is_empty() && part.doc.is_empty() {
        part.doc = std::mem::take(pending);
    }
    pending.clear();
}

/// The code of a line and its comment, if any.
fn split_comment(line: &str) -> (&str, Option<String>) {
    match line.find('#') {
        Some(at) => (&line[..at], Some(line[at + 1..].trim().to_owned())),
        None => (line, None),
    }
}

/// A field (`type name [default]`) or a constant (`type NAME=value`), added to `part`.
fn parse_line(code: &str, doc: Vec<String>, part: &mut Part) -> Result<(), String> {
    let (ty, rest) = code
        .split_once(char::is_whitespace)
        .ok_or_else(|| format!("`{code}` is not `TYPE NAME`: a field needs a name"))?;
    let rest = rest.trim();
    if let Some((name, value)) = rest.split_once('=') {
        let (name, value) = (name.trim(), value.trim());
        if !PRIMITIVES.contains(&ty) {
            return Err(format!(
                "the constant `{name}` has type `{ty}`: constants are of a primitive type"
            ));
        }
        check_name(name, true)?;
        part.constants.push(Constant {
            name: name.to_owned(),
            ty: ty.to_owned(),
            value: value.to_owned(),
            doc,
        });
        return Ok(());
    }
    let (name, default) = match rest.split_once(char::is_whitespace) {
        Some((name, default)) => (name, Some(default.trim().to_owned())),
        None => (rest, None),
    };
    check_name(name, false)?;
    let ty = parse_type(ty)?;
    if default.is_some() && ty.array != Array::None {
        return Err(format!(
            "`{name}` gives an array a default value: only single values have defaults here"
        ));
    }
    part.fields.push(Field {
        name: name.to_owned(),
        ty,
        default,
        doc,
    });
    Ok(())
}

fn check_name(name: &str, constant: bool) -> Result<(), String> {
    let first = name.chars().next();
    let valid = first.is_some_and(|c| c.is_ascii_alphabetic())
        && name.chars().all(|c| {
            c == '_'
                || c.is_ascii_digit()
                || if constant {
                    c.is_ascii_uppercase()
                } else {
                    c.is_ascii_lowercase()
                }
        });
    if valid {
        Ok(())
    } else if constant {
        Err(format!(
            "`{name}` is not a constant name: use upper case, digits and `_`"
        ))
    } else {
        Err(format!(
            "`{name}` is not a field name: use lower case, digits and `_`"
        ))
    }
}

/// `T`, `T[N]`, `T[]`, `T[<=N]`, and bounded strings `string<=N`.
fn parse_type(text: &str) -> Result<FieldType, String> {
    let (base, array) = match text.split_once('[') {
        None => (text, Array::None),
        Some((base, bracket)) => {
            let inside = bracket
                .strip_suffix(']')
                .ok_or_else(|| format!("`{text}`: an array type ends with `]`"))?;
            let array = if inside.is_empty() {
                Array::Counted
            } else if let Some(bound) = inside.strip_prefix("<=") {
                bound
                    .parse::<usize>()
                    .map_err(|_| format!("`{text}`: the bound of a sequence is a number"))?;
                Array::Counted
            } else {
                let n = inside
                    .parse::<usize>()
                    .map_err(|_| format!("`{text}`: the length of an array is a number"))?;
                Array::Fixed(n)
            };
            (base, array)
        }
    };
    // A bounded string is a string on the wire.
    let base = match base.split_once("<=") {
        Some(("string", bound)) if bound.parse::<usize>().is_ok() => "string",
        Some(_) => return Err(format!("`{text}`: only strings take a `<=` bound")),
        None => base,
    };
    if base == "wstring" {
        return Err("`wstring` is not read here: use `string` (UTF-8)".to_owned());
    }
    let message = base
        .split('/')
        .all(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        && base.split('/').count() <= 2;
    if !PRIMITIVES.contains(&base) && !message {
        return Err(format!(
            "`{base}` is neither a primitive type nor `package/Message`"
        ));
    }
    Ok(FieldType {
        base: base.to_owned(),
        array,
    })
}
