//! The `tree!` macro: a blueprint written the way it reads.

/// Builds a blueprint from a nested description; returns `Result<Blueprint<C>, BuildError>`.
///
/// Each item is a [`Builder`](crate::Builder) method call: its name and arguments in
/// parentheses, then its children in braces for nodes that have some. Items are separated by
/// commas.
///
/// ```
/// use neurotree_core::{tree, ManualClock, Status, Tree};
///
/// struct Robot { battery: u32, moved: u32 }
///
/// let blueprint = tree! {
///     fallback("root") {
///         sequence("patrol") {
///             condition("battery_ok", |r: &Robot| r.battery > 20),
///             repeat("three_steps", 3) {
///                 action("step", |r: &mut Robot| { r.moved += 1; r.battery -= 10; Status::Success }),
///             },
///         },
///         action("charge", |r: &mut Robot| { r.battery = 100; Status::Success }),
///     }
/// }
/// .unwrap();
///
/// let mut tree = Tree::with_clock(std::sync::Arc::new(blueprint), ManualClock::new());
/// let mut robot = Robot { battery: 50, moved: 0 };
/// assert_eq!(tree.tick_once(&mut robot), Ok(Status::Success));
/// assert_eq!((robot.moved, robot.battery), (3, 20));
/// assert_eq!(tree.tick_once(&mut robot), Ok(Status::Success));
/// assert_eq!(robot.battery, 100);
/// ```
#[macro_export]
macro_rules! tree {
    ($($body:tt)+) => {
        $crate::__tree_items!($crate::Builder::new(); $($body)+).build()
    };
}

/// Expands the items of [`tree!`]; not for direct use.
#[doc(hidden)]
#[macro_export]
macro_rules! __tree_items {
    ($b:expr;) => { $b };
    ($b:expr; $method:ident ( $($args:tt)* ) { $($children:tt)* } $(, $($rest:tt)*)?) => {
        $crate::__tree_items!(
            $b.$method($($args)*, |__nt_b| $crate::__tree_items!(__nt_b; $($children)*));
            $($($rest)*)?
        )
    };
    ($b:expr; $method:ident ( $($args:tt)* ) $(, $($rest:tt)*)?) => {
        $crate::__tree_items!($b.$method($($args)*); $($($rest)*)?)
    };
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn macro_and_builder_make_the_same_tree() {
        let from_macro = tree! {
            sequence("root") {
                always_success("a"),
                parallel("p", 1, 1) { always_failure("b"), sleep("c", ms(5)) },
                inverter("not") { always_failure("d") }
            }
        }
        .map(|bp: crate::Blueprint<()>| format!("{bp:?}"))
        .unwrap();
        let from_builder = crate::Builder::<()>::new()
            .sequence("root", |s| {
                s.always_success("a")
                    .parallel("p", 1, 1, |p| p.always_failure("b").sleep("c", ms(5)))
                    .inverter("not", |i| i.always_failure("d"))
            })
            .build()
            .map(|bp| format!("{bp:?}"))
            .unwrap();
        assert_eq!(from_macro, from_builder);
    }

    #[test]
    fn macro_reports_build_errors() {
        let e = tree! { inverter("bad") { always_success("a"), always_success("b") } }
            .map(|_: crate::Blueprint<()>| ())
            .unwrap_err();
        assert_eq!(e.path, "bad");
    }
}
