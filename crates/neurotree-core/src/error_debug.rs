//! `Debug` for error types that leads with the sentence `Display` gives.
//!
//! `fn main() -> Result<(), E>` prints an error with `Debug`; a derived `Debug` shows only the
//! fields, and the sentence that says what to do is lost. The error types of every NeuroTree
//! crate implement `Debug` through [`debug_shows_message!`](crate::debug_shows_message): the
//! message first, then the fields as a derive would print them.

/// Implements `Debug` for an error type as its `Display` message followed by its fields, as a
/// derived `Debug` prints them, in parentheses.
///
/// Name every field of every variant (tuple fields get a name to bind them to): a variant or
/// field left out is a compile error, so the `Debug` stays complete as the type grows.
///
/// ```
/// #[derive(thiserror::Error)]
/// enum ParseError {
///     #[error("line {line}: expected a number; write digits only")]
///     NotANumber { line: u32 },
///     #[error("the file is empty; write at least one line")]
///     Empty,
///     #[error("could not read it: {0}")]
///     Io(String),
/// }
/// neurotree_core::debug_shows_message!(enum ParseError {
///     NotANumber { line },
///     Empty,
///     Io(reason),
/// });
///
/// let e = ParseError::NotANumber { line: 3 };
/// assert_eq!(
///     format!("{e:?}"),
///     "line 3: expected a number; write digits only (NotANumber { line: 3 })"
/// );
/// assert_eq!(format!("{:?}", ParseError::Empty), "the file is empty; write at least one line (Empty)");
/// assert_eq!(format!("{:?}", ParseError::Io("gone".into())), r#"could not read it: gone (Io("gone"))"#);
/// ```
#[macro_export]
macro_rules! debug_shows_message {
    (enum $ty:ident $(<$($lt:lifetime),+>)? {
        $( $variant:ident $( { $($field:ident),* $(,)? } )? $( ( $($bind:ident),* $(,)? ) )? ),* $(,)?
    }) => {
        impl $(<$($lt),+>)? ::core::fmt::Debug for $ty $(<$($lt),+>)? {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                write!(f, "{} (", self)?;
                match self {
                    $(
                        $ty::$variant $( { $($field),* } )? $( ( $($bind),* ) )? => {
                            $crate::debug_shows_message!(@fields f, $variant
                                $( { $($field),* } )? $( ( $($bind),* ) )?)?;
                        }
                    )*
                }
                f.write_str(")")
            }
        }
    };
    (struct $ty:ident $(<$($lt:lifetime),+>)? { $($field:ident),* $(,)? }) => {
        impl $(<$($lt),+>)? ::core::fmt::Debug for $ty $(<$($lt),+>)? {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                write!(f, "{} (", self)?;
                let $ty { $($field),* } = self;
                $crate::debug_shows_message!(@fields f, $ty { $($field),* })?;
                f.write_str(")")
            }
        }
    };
    (struct $ty:ident ( $($bind:ident),* $(,)? )) => {
        impl ::core::fmt::Debug for $ty {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                write!(f, "{} (", self)?;
                let $ty ( $($bind),* ) = self;
                $crate::debug_shows_message!(@fields f, $ty ( $($bind),* ))?;
                f.write_str(")")
            }
        }
    };
    (@fields $f:ident, $name:ident { $($field:ident),* }) => {
        $f.debug_struct(stringify!($name)) $( .field(stringify!($field), $field) )* .finish()
    };
    (@fields $f:ident, $name:ident ( $($bind:ident),* )) => {
        $f.debug_tuple(stringify!($name)) $( .field($bind) )* .finish()
    };
    (@fields $f:ident, $name:ident) => {
        $f.write_str(stringify!($name))
    };
}
