//! Entries as JSON, through the blackboard's value codecs: what a person sees of a value in
//! the studio or a summary, and how an edit typed as JSON becomes a value of the entry's type.

use alloc::borrow::ToOwned;
use alloc::boxed::Box;
use alloc::string::String;
use alloc::sync::Arc;
use core::any::Any;
use core::time::Duration;

use serde_json::Value;

use super::entry::{Entry, Stored};
use super::{Blackboard, ScopeId};
use crate::state::StateCodecs;

/// Why a JSON value could not be written to an entry.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum JsonWriteError {
    /// The scope does not exist.
    #[error("no blackboard scope {scope}")]
    NoSuchScope {
        /// The scope asked for.
        scope: u32,
    },
    /// The entry holds a type no codec knows, so no JSON can become one.
    #[error(
        "`{key}` holds a `{type_name}`, which has no value codec; register the type to edit it"
    )]
    NoCodec {
        /// The entry's key.
        key: String,
        /// Its type, short.
        type_name: String,
    },
    /// The JSON does not fit the entry's type.
    #[error("`{key}` holds a `{type_name}`: {reason}")]
    DoesNotFit {
        /// The entry's key.
        key: String,
        /// Its type, short.
        type_name: String,
        /// serde's reason.
        reason: String,
    },
}

crate::debug_shows_message!(enum JsonWriteError {
    NoSuchScope { scope },
    NoCodec { key, type_name },
    DoesNotFit { key, type_name, reason },
});

/// `alloc::vec::Vec<my_robot::geometry::Pose>` as `Vec<Pose>`: every path in a type's name
/// cut to its last segment, generics kept.
pub fn short_type_name(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    let mut segment_start = 0;
    for (i, c) in name.char_indices() {
        if c.is_alphanumeric() || c == '_' || c == ':' {
            if c == ':' && name[i..].starts_with("::") {
                // Drop what was written of this path: the segment after `::` replaces it.
                out.truncate(segment_start);
            }
            if c != ':' {
                out.push(c);
            }
        } else {
            out.push(c);
            segment_start = out.len();
        }
    }
    out
}

impl Blackboard {
    /// The value codecs this blackboard was given ([`set_codecs`](Self::set_codecs)), which
    /// saved states and JSON views use for its values.
    pub fn codecs(&self) -> Option<&StateCodecs> {
        self.rare.as_deref()?.codecs.as_deref()
    }

    /// Shares `codecs` with this blackboard; a tree's blackboard gets its blueprint's.
    pub fn set_codecs(&mut self, codecs: Arc<StateCodecs>) {
        self.rare_mut().codecs = Some(codecs);
    }

    /// `key` as seen from `scope`, as JSON: `None` when the key holds no value yet or its
    /// type has no codec (neither this blackboard's nor [`StateCodecs::new`]'s types).
    pub fn json_in(&self, scope: ScopeId, key: &str) -> Option<Value> {
        let value = self.get_any_in(scope, key)?;
        match self.codecs() {
            Some(codecs) => codecs.to_json(value),
            None => StateCodecs::new().to_json(value),
        }
    }

    /// Writes `json` to `key` as seen from `scope`, converted to the type the entry holds
    /// by its codec; an entry that holds nothing yet takes JSON's own types (`bool`, `i64`
    /// when whole, else `f64`, `String`, and `serde_json::Value` for the rest). The
    /// sequence number grows by one, as for any write. A refused write changes nothing.
    ///
    /// ```
    /// use neurotree_core::{Blackboard, ScopeId};
    /// use serde_json::json;
    ///
    /// let mut bb = Blackboard::new();
    /// bb.set("speed", 1.5_f64).unwrap();
    /// bb.set_json_in(ScopeId::ROOT, "speed", json!(2), Default::default()).unwrap();
    /// assert_eq!(bb.get::<f64>("speed"), Ok(2.0));
    /// let refused = bb.set_json_in(ScopeId::ROOT, "speed", json!("fast"), Default::default());
    /// assert!(refused.unwrap_err().to_string().starts_with("`speed` holds a `f64`"));
    /// ```
    pub fn set_json_in(
        &mut self,
        scope: ScopeId,
        key: &str,
        json: Value,
        stamp: Duration,
    ) -> Result<(), JsonWriteError> {
        let held = self.get_any_in(scope, key).map(|v| {
            (
                v.type_id(),
                self.info_in(scope, key).map_or("", |i| i.type_name),
            )
        });
        let Some((id, type_name)) = held else {
            return self.set_json_natural(scope, key, json, stamp);
        };
        let default;
        let codecs = match self.codecs() {
            Some(codecs) => codecs,
            None => {
                default = StateCodecs::new();
                &default
            }
        };
        let short = || short_type_name(type_name);
        let Some(static_name) = codecs.type_name(id) else {
            return Err(JsonWriteError::NoCodec {
                key: key.to_owned(),
                type_name: short(),
            });
        };
        let value = codecs
            .from_json(id, json)
            .map_err(|reason| JsonWriteError::DoesNotFit {
                key: key.to_owned(),
                type_name: short(),
                reason,
            })?;
        self.replace_boxed_in(scope, key, value, static_name, stamp)
    }

    /// A first write from JSON: the value in JSON's own type.
    fn set_json_natural(
        &mut self,
        scope: ScopeId,
        key: &str,
        json: Value,
        stamp: Duration,
    ) -> Result<(), JsonWriteError> {
        if scope.0 as usize >= self.scope_count() {
            return Err(JsonWriteError::NoSuchScope { scope: scope.0 });
        }
        match json {
            Value::Bool(b) => self.replace_in(scope, key, b, stamp),
            Value::Number(n) => match n.as_i64() {
                Some(i) => self.replace_in(scope, key, i, stamp),
                None => self.replace_in(scope, key, n.as_f64().unwrap_or(f64::NAN), stamp),
            },
            Value::String(s) => self.replace_in(scope, key, s, stamp),
            other => self.replace_in(scope, key, other, stamp),
        }
        Ok(())
    }

    /// Replaces the value of an existing entry by a boxed one of type `type_name`.
    fn replace_boxed_in(
        &mut self,
        scope: ScopeId,
        key: &str,
        value: Box<dyn Any + Send + Sync>,
        type_name: &'static str,
        stamp: Duration,
    ) -> Result<(), JsonWriteError> {
        let Some((entries, k)) = self.place(scope, key) else {
            return Err(JsonWriteError::NoSuchScope { scope: scope.0 });
        };
        let entry = entries.get_or_insert_with(k, Entry::unwritten);
        entry.value = Stored::from_box(value);
        entry.type_name = type_name;
        entry.touch(stamp);
        self.saw(stamp);
        // A write like any other: a tree asleep on the blackboard wakes.
        self.writes = self.writes.wrapping_add(1);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Pose {
        x: f64,
        y: f64,
    }

    fn board() -> Blackboard {
        let mut bb = Blackboard::new();
        bb.set_codecs(Arc::new(StateCodecs::new().with::<Pose>()));
        bb.set("goal", Pose { x: 1.0, y: 2.0 }).unwrap();
        bb
    }

    #[test]
    fn type_names_lose_their_paths_not_their_generics() {
        assert_eq!(short_type_name("alloc::string::String"), "String");
        assert_eq!(
            short_type_name("alloc::vec::Vec<neurotree_nav2::robotics::Pose2D>"),
            "Vec<Pose2D>"
        );
        assert_eq!(
            short_type_name("core::option::Option<(f64, my::Pose)>"),
            "Option<(f64, Pose)>"
        );
        assert_eq!(short_type_name("[a::B; 3]"), "[B; 3]");
        assert_eq!(short_type_name("i64"), "i64");
    }

    #[test]
    fn registered_types_read_and_write_as_json() {
        let mut bb = board();
        assert_eq!(
            bb.json_in(ScopeId::ROOT, "goal"),
            Some(json!({"x": 1.0, "y": 2.0}))
        );
        let before = bb.info("goal").unwrap().sequence;
        bb.set_json_in(
            ScopeId::ROOT,
            "goal",
            json!({"x": 4, "y": -1.5}),
            Duration::ZERO,
        )
        .unwrap();
        assert_eq!(bb.get::<Pose>("goal"), Ok(Pose { x: 4.0, y: -1.5 }));
        let info = bb.info("goal").unwrap();
        assert_eq!(info.sequence, before + 1);
        assert_eq!(info.type_name, core::any::type_name::<Pose>());
    }

    #[test]
    fn json_that_does_not_fit_is_refused_and_changes_nothing() {
        let mut bb = board();
        let before = bb.info("goal").unwrap().sequence;
        let err = bb
            .set_json_in(ScopeId::ROOT, "goal", json!({"x": "far"}), Duration::ZERO)
            .unwrap_err();
        assert!(
            matches!(&err, JsonWriteError::DoesNotFit { type_name, .. } if type_name == "Pose"),
            "{err}"
        );
        assert_eq!(bb.get::<Pose>("goal"), Ok(Pose { x: 1.0, y: 2.0 }));
        assert_eq!(bb.info("goal").unwrap().sequence, before);
    }

    #[test]
    fn a_type_without_codec_is_shown_as_nothing_and_refuses_edits() {
        struct Opaque;
        let mut bb = board();
        bb.set("o", Opaque).unwrap();
        assert_eq!(bb.json_in(ScopeId::ROOT, "o"), None);
        let err = bb
            .set_json_in(ScopeId::ROOT, "o", json!(1), Duration::ZERO)
            .unwrap_err();
        assert!(matches!(err, JsonWriteError::NoCodec { type_name, .. } if type_name == "Opaque"));
    }

    #[test]
    fn new_entries_take_json_s_own_types() {
        let mut bb = Blackboard::new();
        for (key, value) in [
            ("b", json!(true)),
            ("i", json!(3)),
            ("f", json!(0.5)),
            ("s", json!("text")),
            ("l", json!([1, {"a": null}])),
        ] {
            bb.set_json_in(ScopeId::ROOT, key, value, Duration::ZERO)
                .unwrap();
        }
        assert_eq!(bb.get_exact::<bool>("b"), Ok(true));
        assert_eq!(bb.get_exact::<i64>("i"), Ok(3));
        assert_eq!(bb.get_exact::<f64>("f"), Ok(0.5));
        assert_eq!(bb.get_exact::<String>("s"), Ok("text".into()));
        assert_eq!(bb.get_exact::<Value>("l"), Ok(json!([1, {"a": null}])));
        assert_eq!(
            bb.json_in(ScopeId::ROOT, "l"),
            Some(json!([1, {"a": null}]))
        );
        assert!(matches!(
            bb.set_json_in(ScopeId(9), "x", json!(1), Duration::ZERO),
            Err(JsonWriteError::NoSuchScope { scope: 9 })
        ));
    }
}
