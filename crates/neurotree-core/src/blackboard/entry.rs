//! One entry: its value and what is known about it.
//!
//! Most values a tree keeps on its blackboard are flags, counters and readings: a `bool`, an
//! integer, a float. Held in a `Box<dyn Any>`, each of them sat in a block of its own, so
//! reading a flag cost one more trip to memory after the entry's, and in a large crowd,
//! where a member's blocks are seldom cached, every awake tick paid it. These types are
//! therefore held in the entry itself ([`Stored`]); every other type is boxed as before.
//! Which way a value is held is invisible outside this module: it reads, writes and hands
//! out `&dyn Any` and `Box<dyn Any>` the same either way.

use alloc::boxed::Box;
use core::any::Any;
use core::time::Duration;

use super::{EntryInfo, UNWRITTEN};
use crate::clock::duration_to_nanos;

/// `*slot`'s value as a `U`, taken out, when `T` is `U`; `None`, leaving it, otherwise.
/// Which it is, is known when the function is compiled, so the check costs nothing.
#[inline(always)]
fn take<T: Any, U: Any>(slot: &mut Option<T>) -> Option<U> {
    (slot as &mut dyn Any).downcast_mut::<Option<U>>()?.take()
}

/// Declares [`Stored`] with one variant per type held inline, and the conversions that
/// must name each of them.
macro_rules! stored {
    ($($variant:ident($t:ty)),* $(,)?) => {
        /// An entry's value: a small plain type in the entry itself, anything else boxed.
        pub(super) enum Stored {
            /// Declared and not written yet.
            Unwritten,
            $(
                #[doc = concat!("A `", stringify!($t), "`, held inline.")]
                $variant($t),
            )*
            /// A value of any other type.
            Boxed(Box<dyn Any + Send + Sync>),
        }

        impl Stored {
            /// `value`, held inline when its type is one of those above.
            #[inline]
            pub(super) fn new<T: Any + Send + Sync>(value: T) -> Self {
                let mut slot = Some(value);
                $(
                    if let Some(v) = take::<T, $t>(&mut slot) {
                        return Self::$variant(v);
                    }
                )*
                match slot {
                    Some(v) => Self::Boxed(Box::new(v)),
                    // Only a `take` above empties the slot, and it returned.
                    None => Self::Unwritten,
                }
            }

            /// A value handed in boxed (a restored or JSON-edited one), unboxed when its type
            /// is held inline, so that it is held as a write of the same value holds it.
            pub(super) fn from_box(value: Box<dyn Any + Send + Sync>) -> Self {
                $(
                    let value = match value.downcast::<$t>() {
                        Ok(v) => return Self::$variant(*v),
                        Err(other) => other,
                    };
                )*
                Self::Boxed(value)
            }

            /// The value, whatever its type; `None` if not written yet.
            #[inline]
            pub(super) fn as_any(&self) -> Option<&(dyn Any + Send + Sync)> {
                match self {
                    Self::Unwritten => None,
                    $(Self::$variant(v) => Some(v),)*
                    Self::Boxed(b) => Some(&**b),
                }
            }

            /// The value if it is a `T`. Each arm's type is known, so for a `T` held inline
            /// this compiles to a check of the variant.
            #[inline]
            pub(super) fn downcast_ref<T: Any>(&self) -> Option<&T> {
                match self {
                    Self::Unwritten => None,
                    $(Self::$variant(v) => (v as &dyn Any).downcast_ref::<T>(),)*
                    Self::Boxed(b) => b.downcast_ref::<T>(),
                }
            }

            /// The value to change if it is a `T` (see [`downcast_ref`](Self::downcast_ref)).
            #[inline]
            pub(super) fn downcast_mut<T: Any>(&mut self) -> Option<&mut T> {
                match self {
                    Self::Unwritten => None,
                    $(Self::$variant(v) => (v as &mut dyn Any).downcast_mut::<T>(),)*
                    Self::Boxed(b) => b.downcast_mut::<T>(),
                }
            }

            /// The value boxed, as the raw views of the blackboard hand values out; `None` if
            /// not written yet.
            pub(super) fn into_box(self) -> Option<Box<dyn Any + Send + Sync>> {
                match self {
                    Self::Unwritten => None,
                    $(Self::$variant(v) => Some(Box::new(v)),)*
                    Self::Boxed(b) => Some(b),
                }
            }
        }
    };
}

stored!(
    Bool(bool),
    I8(i8),
    I16(i16),
    I32(i32),
    I64(i64),
    Isize(isize),
    U8(u8),
    U16(u16),
    U32(u32),
    U64(u64),
    Usize(usize),
    F32(f32),
    F64(f64),
    Duration(Duration),
);

impl Stored {
    /// `true` if the value is a `T`.
    #[inline]
    pub(super) fn is<T: Any>(&self) -> bool {
        self.downcast_ref::<T>().is_some()
    }

    /// `true` once a value was written.
    #[inline]
    pub(super) fn is_written(&self) -> bool {
        !matches!(self, Self::Unwritten)
    }
}

/// One value and what is known about it.
///
/// The stamp is kept as nanoseconds (saturating past 584 years) rather than a 16-byte
/// [`Duration`], which keeps an entry with its inline value as small as one that held a
/// bare box: 64 bytes, its key beside it in the scope's vector making 88.
pub(super) struct Entry {
    pub(super) value: Stored,
    /// See [`EntryInfo::sequence`].
    pub(super) sequence: u64,
    /// See [`EntryInfo::stamp`], in nanoseconds.
    pub(super) stamp: u64,
    /// See [`EntryInfo::type_name`].
    pub(super) type_name: &'static str,
    /// Created by [`Blackboard::set_untyped_in`](super::Blackboard::set_untyped_in): its
    /// type is not fixed, as a BehaviorTree.CPP entry a script created is not.
    pub(super) untyped: bool,
}

impl Entry {
    /// The first write of `value`.
    #[inline]
    pub(super) fn new<T: Any + Send + Sync>(value: T, stamp: Duration) -> Self {
        Self {
            value: Stored::new(value),
            sequence: 1,
            stamp: duration_to_nanos(stamp),
            type_name: core::any::type_name::<T>(),
            untyped: false,
        }
    }

    /// An entry declared and not written yet: sequence 0, no type.
    pub(super) fn unwritten() -> Self {
        Self {
            value: Stored::Unwritten,
            sequence: 0,
            stamp: 0,
            type_name: UNWRITTEN,
            untyped: false,
        }
    }

    /// An entry as [`info`](Self::info) described it, holding `value` (`None`: not written).
    pub(super) fn from_raw(
        info: EntryInfo,
        untyped: bool,
        value: Option<Box<dyn Any + Send + Sync>>,
    ) -> Self {
        Self {
            value: value.map_or(Stored::Unwritten, Stored::from_box),
            sequence: info.sequence,
            stamp: duration_to_nanos(info.stamp),
            type_name: info.type_name,
            untyped,
        }
    }

    /// Sequence number, stamp and type, as the public API tells them.
    #[inline]
    pub(super) fn info(&self) -> EntryInfo {
        EntryInfo {
            sequence: self.sequence,
            stamp: Duration::from_nanos(self.stamp),
            type_name: self.type_name,
        }
    }

    /// Records a write. Wrapping, because a counter that cannot overflow in practice must
    /// still not be able to panic.
    #[inline]
    pub(super) fn touch(&mut self, stamp: Duration) {
        self.sequence = self.sequence.wrapping_add(1);
        self.stamp = duration_to_nanos(stamp);
    }

    /// Replaces the value by `value`, of whatever type, fixing the entry's type to it (so
    /// the entry is typed from now on): a write, so the sequence number grows by one.
    pub(super) fn retype<T: Any + Send + Sync>(&mut self, value: T, stamp: Duration) {
        self.value = Stored::new(value);
        self.type_name = core::any::type_name::<T>();
        self.untyped = false;
        self.touch(stamp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::String;
    use alloc::vec::Vec;
    use core::fmt::Debug;

    /// `value` stored, then checked to be held as `inline` says, read back, changed in
    /// place, boxed on the way out and unboxed on the way in.
    fn round_trip<T: Any + Send + Sync + Clone + PartialEq + Debug>(value: T, other: T) -> bool {
        let mut stored = Stored::new(value.clone());
        let inline = !matches!(stored, Stored::Boxed(_) | Stored::Unwritten);
        assert_eq!(stored.downcast_ref::<T>(), Some(&value));
        assert!(stored.is::<T>() && stored.is_written());
        assert!(stored.downcast_ref::<[u8; 5]>().is_none());
        assert!(stored.downcast_mut::<Vec<T>>().is_none());
        let any = stored.as_any().map(|a| a.downcast_ref::<T>());
        assert_eq!(any, Some(Some(&value)));
        if let Some(slot) = stored.downcast_mut::<T>() {
            *slot = other.clone();
        }
        assert_eq!(stored.downcast_ref::<T>(), Some(&other));
        let boxed = stored.into_box().expect("a written value");
        assert_eq!(boxed.downcast_ref::<T>(), Some(&other));
        let back = Stored::from_box(boxed);
        assert_eq!(
            !matches!(back, Stored::Boxed(_)),
            inline,
            "unboxed as written"
        );
        assert_eq!(back.downcast_ref::<T>(), Some(&other));
        inline
    }

    #[test]
    fn small_plain_types_are_held_inline_and_others_boxed() {
        assert!(round_trip(true, false));
        assert!(round_trip(-3_i8, 4));
        assert!(round_trip(-300_i16, 4));
        assert!(round_trip(-3_i32, i32::MAX));
        assert!(round_trip(i64::MIN, 4));
        assert!(round_trip(-3_isize, 4));
        assert!(round_trip(3_u8, 4));
        assert!(round_trip(3_u16, 4));
        assert!(round_trip(3_u32, 4));
        assert!(round_trip(u64::MAX, 4));
        assert!(round_trip(3_usize, 4));
        assert!(round_trip(0.5_f32, -1.0));
        assert!(round_trip(0.5_f64, f64::INFINITY));
        assert!(round_trip(Duration::from_millis(5), Duration::MAX));
        assert!(!round_trip(String::from("text"), String::from("more")));
        assert!(!round_trip(3_i128, 4));
        assert!(!round_trip([1_u8; 3], [2; 3]));
        // A value already boxed is a value of type `Box<..>`, kept as such.
        let boxed: Box<dyn Any + Send + Sync> = Box::new(1_u8);
        let stored = Stored::new(boxed);
        assert!(stored.is::<Box<dyn Any + Send + Sync>>() && !stored.is::<u8>());
    }

    #[test]
    fn an_unwritten_value_is_nothing_to_read_or_hand_out() {
        let mut stored = Stored::Unwritten;
        assert!(!stored.is_written() && stored.as_any().is_none());
        assert!(stored.downcast_ref::<bool>().is_none() && stored.downcast_mut::<u8>().is_none());
        assert!(stored.into_box().is_none());
        let entry = Entry::unwritten();
        assert_eq!((entry.sequence, entry.type_name), (0, UNWRITTEN));
    }

    #[test]
    fn an_entry_stays_as_small_as_one_that_held_a_box() {
        assert!(core::mem::size_of::<Stored>() <= 24);
        assert!(core::mem::size_of::<Entry>() <= 64);
        assert!(core::mem::size_of::<(smol_str::SmolStr, Entry)>() <= 88);
    }

    #[test]
    fn stamps_too_far_for_nanoseconds_saturate() {
        let mut entry = Entry::new(1_u8, Duration::MAX);
        assert_eq!(entry.info().stamp, Duration::from_nanos(u64::MAX));
        entry.touch(Duration::from_secs(2));
        assert_eq!(entry.info().stamp, Duration::from_secs(2));
    }
}
