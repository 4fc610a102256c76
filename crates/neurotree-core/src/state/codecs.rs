//! How blackboard values of each type become bytes and come back.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec::Vec;
use core::any::{type_name, Any, TypeId};
use core::time::Duration;

use serde::de::DeserializeOwned;
use serde::Serialize;

/// A value as bytes, if it is of the codec's type.
type Encode = fn(&(dyn Any + Send + Sync)) -> Option<Vec<u8>>;
/// A value of the codec's type from bytes.
type Decode = fn(&[u8]) -> Option<Box<dyn Any + Send + Sync>>;

struct Codec {
    id: TypeId,
    name: &'static str,
    encode: Encode,
    decode: Decode,
}

/// The types whose blackboard values a saved state can hold, each with its encoding.
///
/// [`StateCodecs::new`] knows the numbers, `bool`, `char`, `String` and `Duration`; add the
/// types your leaves write with [`with`](Self::with):
///
/// ```
/// use neurotree_core::state::StateCodecs;
///
/// #[derive(Clone, serde::Serialize, serde::Deserialize)]
/// struct Pose { x: f64, y: f64 }
///
/// let codecs = StateCodecs::new().with::<Pose>();
/// assert!(codecs.knows::<Pose>() && codecs.knows::<i64>());
/// ```
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
    }

    /// These codecs and one for `T`, which values of type `T` are saved with.
    pub fn with<T: Serialize + DeserializeOwned + Any + Send + Sync>(mut self) -> Self {
        let id = TypeId::of::<T>();
        self.codecs.retain(|c| c.id != id);
        self.codecs.push(Codec {
            id,
            name: type_name::<T>(),
            encode: encode::<T>,
            decode: decode::<T>,
        });
        self
    }

    /// `true` if values of type `T` can be saved.
    pub fn knows<T: Any>(&self) -> bool {
        self.codecs.iter().any(|c| c.id == TypeId::of::<T>())
    }

    /// The bytes of `value`, if its type has a codec.
    pub(crate) fn encode(&self, value: &(dyn Any + Send + Sync)) -> Option<Vec<u8>> {
        let id = value.type_id();
        let codec = self.codecs.iter().find(|c| c.id == id)?;
        (codec.encode)(value)
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
