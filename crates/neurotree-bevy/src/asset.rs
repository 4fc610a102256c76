//! Tree files as Bevy assets: BehaviorTree.CPP XML loaded with the app's registry.
//!
//! A tree asset is one file: its `<include>`s are not followed (an asset's path is not a
//! file system path), so a file that includes others fails to load, naming the include.

use std::sync::Arc;

use bevy_asset::io::Reader;
use bevy_asset::{Asset, AssetLoader, LoadContext, UntypedAssetId, VisitAssetDependencies};
use bevy_reflect::utility::GenericTypePathCell;
use bevy_reflect::TypePath;
use neurotree::xml::{LoadError, XmlLoader};
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
#[derive(Debug, thiserror::Error)]
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
    /// The XML is not a tree the registry can build; prints as `file:line:col: error: ...`.
    #[error(transparent)]
    Load(#[from] LoadError),
}

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
        let mut loader = XmlLoader::new(&self.registry);
        loader.load_str(&text, &path)?;
        Ok(TreeAsset::new(Arc::new(loader.build_main()?)))
    }

    fn extensions(&self) -> &[&str] {
        &["xml"]
    }
}
