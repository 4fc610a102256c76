//! How blackboard values of each type become bytes and JSON, and come back: the one
//! registry of value types that saved states, the studio, traces and the command line share.

use alloc::boxed::Box;
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::any::{type_name, Any, TypeId};
use core::time::Duration;

use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;

/// A value as bytes, if it is of the codec's type.
type Encode = fn(&(dyn Any + Send + Sync)) -> Option<Vec<u8>>;
/// A value of the codec's type from bytes.
type Decode = fn(&[u8]) -> Option<Box<dyn Any + Send + Sync>>;
/// A value as JSON, if it is of the codec's type.
type ToJson = fn(&(dyn Any + Send + Sync)) -> Option<Value>;
/// A value of the codec's type from JSON, or why it is none.
type FromJson = fn(Value) -> Result<Box<dyn Any + Send + Sync>, String>;

#[derive(Clone)]
struct Codec {
    id: TypeId,
    name: &'static str,
    encode: Encode,
    decode: Decode,
    to_json: ToJson,
    from_json: FromJson,
}

/// The types whose blackboard values can be saved, shown and edited, each with its
/// encodings: bytes for saved states, JSON for people and programs.
///
/// [`StateCodecs::new`] knows the numbers, `bool`, `char`, `String`, `Duration` and
/// `serde_json::Value`; add the types your leaves write with [`with`](Self::with), once.
/// A blueprint made with the codecs ([`Builder::value_codecs`](crate::Builder::value_codecs),
/// or a registry that knows the type) hands them to each tree's blackboard, and from there
/// every tool that shows a value (the studio, `run`'s summary, the Groot2 monitor, saved
/// states) writes it as JSON.
///
/// ```
/// use neurotree_core::state::StateCodecs;
///
/// #[derive(Clone, serde::Serialize, serde::Deserialize)]
/// struct Pose { x: f64, y: f64 }
///
/// let codecs = StateCodecs::new().with::<Pose>();
/// assert!(codecs.knows::<Pose>() && codecs.knows::<i64>());
/// let json = codecs.to_json(&Pose { x: 1.0, y: 2.5 }).unwrap();
/// assert_eq!(json, serde_json::json!({"x": 1.0, "y": 2.5}));
/// let back = codecs.from_json(core::any::TypeId::of::<Pose>(), json).unwrap();
/// assert_eq!(back.downcast_ref::<Pose>().map(|p| p.y), Some(2.5));
/// ```
#[derive(Clone)]
pub struct StateCodecs {
    codecs: Vec<Codec>,
}

impl Default for StateCodecs {
    fn default() -> Self {
        Self::new()
    }
}

impl core::fmt::Debug for StateCodecs {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list()
            .entries(self.codecs.iter().map(|c| c.name))
            .finish()
    }
}

fn encode<T: Serialize + Any>(value: &(dyn Any + Send + Sync)) -> Option<Vec<u8>> {
    postcard::to_allocvec(value.downcast_ref::<T>()?).ok()
}

fn decode<T: DeserializeOwned + Any + Send + Sync>(
    bytes: &[u8],
) -> Option<Box<dyn Any + Send + Sync>> {
    let value: T = postcard::from_bytes(bytes).ok()?;
    Some(Box::new(value))
}

fn to_json<T: Serialize + Any>(value: &(dyn Any + Send + Sync)) -> Option<Value> {
    serde_json::to_value(value.downcast_ref::<T>()?).ok()
}

fn from_json<T: DeserializeOwned + Any + Send + Sync>(
    json: Value,
) -> Result<Box<dyn Any + Send + Sync>, String> {
    match serde_json::from_value::<T>(json) {
        Ok(value) => Ok(Box::new(value)),
        Err(e) => Err(e.to_string()),
    }
}

/// JSON itself is saved as its text: postcard cannot read back a type that describes itself.
fn encode_json(value: &(dyn Any + Send + Sync)) -> Option<Vec<u8>> {
    serde_json::to_vec(value.downcast_ref::<Value>()?).ok()
}

fn decode_json(bytes: &[u8]) -> Option<Box<dyn Any + Send + Sync>> {
    let value: Value = serde_json::from_slice(bytes).ok()?;
    Some(Box::new(value))
}

impl StateCodecs {
    /// The codecs of the numbers, `bool`, `char`, `String` and `Duration`.
    pub fn new() -> Self {
        let empty = Self { codecs: Vec::new() };
        empty
            .with::<bool>()
            .with::<i8>()
            .with::<i16>()
            .with::<i32>()
            .with::<i64>()
            .with::<i128>()
            .with::<isize>()
            .with::<u8>()
            .with::<u16>()
            .with::<u32>()
            .with::<u64>()
            .with::<u128>()
            .with::<usize>()
            .with::<f32>()
            .with::<f64>()
            .with::<char>()
            .with::<String>()
            .with::<Duration>()
            .with_codec(Codec {
                id: TypeId::of::<Value>(),
                name: type_name::<Value>(),
                encode: encode_json,
                decode: decode_json,
                to_json: to_json::<Value>,
                from_json: from_json::<Value>,
            })
    }

    /// These codecs and one for `T`, which values of type `T` are saved with.
    pub fn with<T: Serialize + DeserializeOwned + Any + Send + Sync>(self) -> Self {
        self.with_codec(Codec {
            id: TypeId::of::<T>(),
            name: type_name::<T>(),
            encode: encode::<T>,
            decode: decode::<T>,
            to_json: to_json::<T>,
            from_json: from_json::<T>,
        })
    }

    /// Adds `T` in place: [`with`](Self::with) for codecs already shared or borrowed.
    pub fn add<T: Serialize + DeserializeOwned + Any + Send + Sync>(&mut self) {
        *self = core::mem::take(self).with::<T>();
    }

    fn with_codec(mut self, codec: Codec) -> Self {
        self.codecs.retain(|c| c.id != codec.id);
        self.codecs.push(codec);
        self
    }

    fn find(&self, id: TypeId) -> Option<&Codec> {
        self.codecs.iter().find(|c| c.id == id)
    }

    /// `value` as JSON, if its type has a codec.
    pub fn to_json(&self, value: &(dyn Any + Send + Sync)) -> Option<Value> {
        (self.find(value.type_id())?.to_json)(value)
    }

    /// A value of the type `id` from `json`; `Err` says why it is none: the type has no
    /// codec, or the JSON does not fit it (serde's reason).
    pub fn from_json(&self, id: TypeId, json: Value) -> Result<Box<dyn Any + Send + Sync>, String> {
        match self.find(id) {
            Some(codec) => (codec.from_json)(json),
            None => Err(String::from("its type has no value codec")),
        }
    }

    /// The `'static` name of the type `id`, if it has a codec.
    pub fn type_name(&self, id: TypeId) -> Option<&'static str> {
        self.find(id).map(|c| c.name)
    }

    /// `true` if values of type `T` can be saved.
    pub fn knows<T: Any>(&self) -> bool {
        self.codecs.iter().any(|c| c.id == TypeId::of::<T>())
    }

    /// The bytes of `value`, if its type has a codec.
    pub(crate) fn encode(&self, value: &(dyn Any + Send + Sync)) -> Option<Vec<u8>> {
        (self.find(value.type_id())?.encode)(value)
    }

    /// A value of the type named `name` from its bytes, with the type's `'static` name.
    pub(crate) fn decode(
        &self,
        name: &str,
        bytes: &[u8],
    ) -> Option<(&'static str, Box<dyn Any + Send + Sync>)> {
        let codec = self.codecs.iter().find(|c| c.name == name)?;
        Some((codec.name, (codec.decode)(bytes)?))
    }
}
