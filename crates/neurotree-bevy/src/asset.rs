//! Tree files as Bevy assets: BehaviorTree.CPP XML loaded with the app's registry.
//!
//! A file's `<include path="...">`s are read through the asset server, from the same
//! asset source, at the include's path relative to the including file's directory (as
//! BehaviorTree.CPP resolves them), and so on down; they are the asset's loader
//! dependencies, so that a change to an included file reloads every tree asset that
//! includes it (and, with it, the agents running them). An include that cannot be read
//! fails the asset, naming it.

use std::collections::BTreeMap;
use std::sync::Arc;

use bevy_asset::io::Reader;
use bevy_asset::{
    Asset, AssetLoader, AssetPath, LoadContext, ReadAssetBytesError, UntypedAssetId,
    VisitAssetDependencies,
};
use bevy_reflect::utility::GenericTypePathCell;
use bevy_reflect::TypePath;
use neurotree::xml::{LoadError, XmlLoader};
use neurotree::LoadErrors;
use neurotree::{Blueprint, Registry};

/// A tree loaded from a BehaviorTree.CPP XML file: the blueprint of its main tree, which
/// agents instantiate.
///
/// Changing it in `Assets` (or, with the `file_watcher` feature, changing its file)
/// reloads every agent that runs it, keeping the state of the nodes that did not change
/// ([`Tree::reload`](neurotree::Tree::reload)).
pub struct TreeAsset<C> {
    blueprint: Arc<Blueprint<C>>,
}

impl<C> TreeAsset<C> {
    /// An asset holding `blueprint`, e.g. to replace a loaded one in `Assets`.
    pub fn new(blueprint: Arc<Blueprint<C>>) -> Self {
        Self { blueprint }
    }

    /// The blueprint agents instantiate.
    pub fn blueprint(&self) -> &Arc<Blueprint<C>> {
        &self.blueprint
    }
}

impl<C: Send + Sync + 'static> Asset for TreeAsset<C> {}

impl<C> VisitAssetDependencies for TreeAsset<C> {
    fn visit_dependencies(&self, _visit: &mut impl FnMut(UntypedAssetId)) {}
}

/// Named after the context type, so that two contexts' assets are told apart; written by
/// hand because the derive would ask every context type to implement `TypePath`.
impl<C: 'static> TypePath for TreeAsset<C> {
    fn type_path() -> &'static str {
        static CELL: GenericTypePathCell = GenericTypePathCell::new();
        CELL.get_or_insert::<Self, _>(|| {
            format!("neurotree_bevy::TreeAsset<{}>", std::any::type_name::<C>())
        })
    }

    fn short_type_path() -> &'static str {
        static CELL: GenericTypePathCell = GenericTypePathCell::new();
        CELL.get_or_insert::<Self, _>(|| format!("TreeAsset<{}>", std::any::type_name::<C>()))
    }
}

/// Loads [`TreeAsset`]s (files ending in `.xml`) with the app's [`Registry`].
pub struct TreeAssetLoader<C> {
    registry: Arc<Registry<C>>,
}

impl<C> TreeAssetLoader<C> {
    /// A loader that builds trees from the nodes `registry` knows.
    pub fn new(registry: Arc<Registry<C>>) -> Self {
        Self { registry }
    }
}

impl<C: 'static> TypePath for TreeAssetLoader<C> {
    fn type_path() -> &'static str {
        static CELL: GenericTypePathCell = GenericTypePathCell::new();
        CELL.get_or_insert::<Self, _>(|| {
            format!(
                "neurotree_bevy::TreeAssetLoader<{}>",
                std::any::type_name::<C>()
            )
        })
    }

    fn short_type_path() -> &'static str {
        static CELL: GenericTypePathCell = GenericTypePathCell::new();
        CELL.get_or_insert::<Self, _>(|| format!("TreeAssetLoader<{}>", std::any::type_name::<C>()))
    }
}

/// Why a tree file did not load.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum TreeAssetError {
    /// The file could not be read.
    #[error("{path}: cannot read the file: {source}")]
    Io {
        /// The asset's path.
        path: String,
        /// What the reader said.
        source: std::io::Error,
    },
    /// The file is not UTF-8 text.
    #[error("{path}: the file is not UTF-8 text")]
    NotUtf8 {
        /// The asset's path.
        path: String,
    },
    /// A file an `<include>` names could not be read.
    #[error("{path}: cannot read the included file: {source}")]
    Include {
        /// The included file's path.
        path: String,
        /// What the asset server said.
        source: ReadAssetBytesError,
    },
    /// The XML is not a tree the registry can build: every error found, each printed on
    /// its own line as `file:line:col: error: ...`, as `neurotree check` prints them.
    #[error(transparent)]
    Load(#[from] LoadErrors),
}

neurotree::debug_shows_message!(enum TreeAssetError {
    Io { path, source },
    NotUtf8 { path },
    Include { path, source },
    Load(source),
});

impl From<LoadError> for TreeAssetError {
    fn from(e: LoadError) -> Self {
        TreeAssetError::Load(LoadErrors::from(e))
    }
}

/// Most errors a failed tree reports: as many as `neurotree check` prints.
const MOST_ERRORS: usize = 50;

impl<C: Send + Sync + 'static> AssetLoader for TreeAssetLoader<C> {
    type Asset = TreeAsset<C>;
    type Settings = ();
    type Error = TreeAssetError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        load_context: &mut LoadContext<'_>,
    ) -> Result<TreeAsset<C>, TreeAssetError> {
        let path = load_context.path().to_string();
        let mut bytes = Vec::new();
        if let Err(source) = reader.read_to_end(&mut bytes).await {
            return Err(TreeAssetError::Io { path, source });
        }
        let Ok(text) = String::from_utf8(bytes) else {
            return Err(TreeAssetError::NotUtf8 { path });
        };
        // Includes resolve against the asset's path within its source.
        let file = load_context.path().path().to_string_lossy().into_owned();
        let source = load_context.path().source().clone_owned();
        let mut included = BTreeMap::new();
        let mut wanted = XmlLoader::<C>::includes_of(&text, &file)?;
        while let Some(next) = wanted.pop() {
            if included.contains_key(&next) {
                continue;
            }
            let at = AssetPath::from(next.clone()).with_source(source.clone());
            let bytes = match load_context.read_asset_bytes(at).await {
                Ok(bytes) => bytes,
                Err(source) => return Err(TreeAssetError::Include { path: next, source }),
            };
            let Ok(text) = String::from_utf8(bytes) else {
                return Err(TreeAssetError::NotUtf8 { path: next });
            };
            wanted.extend(XmlLoader::<C>::includes_of(&text, &next)?);
            included.insert(next, text);
        }
        let mut loader = XmlLoader::new(&self.registry);
        loader.include_texts(included);
        loader.load_str(&text, &file)?;
        match loader.build_main() {
            Ok(blueprint) => Ok(TreeAsset::new(Arc::new(blueprint))),
            Err(first) => {
                // The builder stops at the first error; the others, as `check` finds them.
                let mut errors = vec![first];
                if let Some(main) = loader.main_tree() {
                    for e in loader.validate_all(main, MOST_ERRORS) {
                        if errors.len() < MOST_ERRORS && !errors.contains(&e) {
                            errors.push(e);
                        }
                    }
                }
                Err(TreeAssetError::Load(
                    LoadErrors::new(errors).expect("at least the first error"),
                ))
            }
        }
    }

    fn extensions(&self) -> &[&str] {
        &["xml"]
    }
}
