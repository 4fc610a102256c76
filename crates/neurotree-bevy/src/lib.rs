//! # NeuroTree in Bevy
//!
//! Behavior trees for Bevy's entities, ticked on all cores: each agent is an entity with a
//! [`TreeAgent`] component; [`NeuroTreePlugin`] ticks every agent's tree through a
//! [`Crowd`](neurotree::crowd::Crowd) (with per-agent tick intervals), in one parallel
//! pass over the agents' components in the order Bevy stores them, in the [`TreeSystems`]
//! set.
//!
//! - **Leaves see components through a typed context.** An [`AgentContext`] names the
//!   components its leaves need; in the same visit of an agent, it is loaded from them,
//!   the tree ticked and what changed written back, so leaves get `&mut` plain data on
//!   any thread.
//! - **Results** come as messages ([`TreeFinished`]) and, for failures and errors with
//!   their reason, as an observer event ([`TreeFailed`]).
//! - **Tree files are assets.** With Bevy's `AssetPlugin`, `.xml` files load as
//!   [`TreeAsset`]s, built with the [`Registry`](neurotree::Registry) the app gives the
//!   plugin, following its `<include>`s (read through the asset server, relative to the
//!   including file, and watched with it); a file that fails names its `file:line:col`.
//!   When a tree asset changes (in `Assets`, or on disk with the `file_watcher` feature),
//!   every agent running it is reloaded, keeping the state of the nodes that did not
//!   change ([`TreeReloaded`]).
//! - **Sleeping agents cost nothing per frame.** A tree whose waiting leaves say what they
//!   wait on [sleeps](neurotree::tree::sleep): its agent is not visited until a deadline
//!   it declared comes (a timer node's, or a leaf's `Handle::sleep_until`), the program wakes
//!   it, or, where the app asked for it, its entity's component changes
//!   ([`NeuroTreePlugin::wake_on_change`]) or a message names it
//!   ([`NeuroTreePlugin::wake_on_message`]). With fewer than one agent in 8 awake, a frame
//!   visits the awake agents alone, by entity.
//! - **Removing** an agent's component (or replacing it, or despawning the agent) halts its
//!   running actions once.
//!
//! ```
//! use bevy_app::App;
//! use bevy_ecs::prelude::*;
//! use bevy_ecs::query::QueryItem;
//! use neurotree::prelude::*;
//! use neurotree_bevy::{AgentContext, NeuroTreePlugin, TreeAgent};
//!
//! #[derive(Component)]
//! struct Fuel(u32);
//!
//! #[derive(Default)]
//! struct Ship { fuel: u32 }
//!
//! impl AgentContext for Ship {
//!     type Components = &'static mut Fuel;
//!     type Shared = ();
//!     fn load(&mut self, fuel: &QueryItem<'_, '_, Self::Components>, _: &()) {
//!         self.fuel = fuel.0;
//!     }
//!     fn store(&self, fuel: &mut QueryItem<'_, '_, Self::Components>) {
//!         fuel.0 = self.fuel;
//!     }
//! }
//!
//! // Burn a unit of fuel per frame while there is some.
//! let fly = Blueprint::<Ship>::builder()
//!     .sequence("fly", |s| {
//!         s.condition("has_fuel", |s: &Ship| s.fuel > 0)
//!             .action("burn", |s: &mut Ship| {
//!                 s.fuel -= 1;
//!                 Status::Success
//!             })
//!     })
//!     .build_shared()
//!     .unwrap();
//!
//! let mut app = App::new();
//! app.add_plugins(NeuroTreePlugin::new(Registry::<Ship>::new()));
//! let ship = app
//!     .world_mut()
//!     .spawn((Fuel(2), TreeAgent::new(fly, Ship::default())))
//!     .id();
//! for _ in 0..3 {
//!     app.update();
//! }
//! assert_eq!(app.world().get::<Fuel>(ship).unwrap().0, 0);
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod agent;
mod asset;
pub mod awake;
mod context;
mod crowd;
mod events;
mod plugin;
#[cfg(feature = "studio")]
mod studio;
mod systems;

pub use agent::{AgentSummary, TreeAgent};
pub use asset::{TreeAsset, TreeAssetError, TreeAssetLoader};
pub use awake::AwakeAgents;
pub use context::AgentContext;
pub use crowd::AgentCrowd;
pub use events::{FailureReason, TreeFailed, TreeFinished, TreeReloaded};
pub use plugin::{task_pools, NeuroTreePlugin, TreeSystems};
#[cfg(feature = "studio")]
pub use studio::TreeStudio;
