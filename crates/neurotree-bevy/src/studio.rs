//! The studio on the plugin's agents (feature `studio`, on by default): a browser page that
//! lists the agents by entity, with a search, and watches one of them (its statuses, its
//! blackboard, editable, its Utility scores, why it is awake, breakpoints, pause and step),
//! holding that agent alone, or the whole crowd, when it stops
//! ([`NeuroTreePlugin::with_studio`](crate::NeuroTreePlugin::with_studio)).
//!
//! Unwatched agents cost nothing: the watched agent's tree alone carries the studio's
//! observer, the list of agents is rebuilt only when agents join or leave, and the page is
//! sent a page of it at a time.

use std::marker::PhantomData;
use std::net::{IpAddr, Ipv4Addr};
use std::sync::{Mutex, PoisonError};

use bevy_ecs::entity::Entity;
use bevy_ecs::resource::Resource;
use bevy_ecs::system::ResMut;
use neurotree::crowd::Crowd;
use neurotree::studio::{AgentEntry, Agents, CrowdWatch, Studio, StudioError, StudioOptions};
use neurotree::{Observer, Registry, Tree};

use crate::context::AgentContext;
use crate::crowd::AgentCrowd;

/// The studio serving the plugin's agents of context `C`: its address, for the program to
/// print ([`url`](Self::url)).
#[derive(Resource)]
pub struct TreeStudio<C> {
    studio: Studio,
    /// A `Mutex` only because a resource must be `Sync`: reached through `&mut` alone.
    watch: Mutex<CrowdWatch>,
    _context: PhantomData<fn(C)>,
}

impl<C> TreeStudio<C> {
    /// Serves the studio on 127.0.0.1:`port` (0: a free port), naming the crowd `name`.
    pub(crate) fn serve(port: u16, name: &str) -> Result<Self, StudioError> {
        let options = StudioOptions {
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port,
            ..StudioOptions::default()
        };
        let studio = Studio::serve(options, Registry::new)?;
        let watch = Mutex::new(studio.watch_crowd(name));
        Ok(Self {
            studio,
            watch,
            _context: PhantomData,
        })
    }

    /// Where the page is: `http://127.0.0.1:PORT/`, which opens on the first agent.
    pub fn url(&self) -> String {
        self.studio.url()
    }

    /// The server, to ask how many pages are attached.
    pub fn studio(&self) -> &Studio {
        &self.studio
    }
}

/// The plugin's crowd as the studio sees it: each agent by its entity.
struct ByEntity<'a, C> {
    crowd: &'a mut Crowd<C>,
    entities: &'a [Option<Entity>],
}

impl<C: Send> Agents for ByEntity<'_, C> {
    type Context = C;

    fn membership(&self) -> u64 {
        self.crowd.membership()
    }

    fn list(&self, out: &mut Vec<AgentEntry>) {
        out.extend(self.crowd.iter().map(|m| {
            let slot = m.id().slot();
            let id = match self.entities.get(slot).copied().flatten() {
                Some(entity) => entity.to_string(),
                None => format!("member {slot}"),
            };
            AgentEntry {
                key: neurotree::crowd_studio::agent_key(m.id()),
                id,
                label: String::new(),
            }
        }));
    }

    fn tree(&self, key: u64) -> Option<&Tree<C>> {
        Agents::tree(&*self.crowd, key)
    }

    fn tree_mut(&mut self, key: u64) -> Option<&mut Tree<C>> {
        Agents::tree_mut(self.crowd, key)
    }

    fn set_observer(
        &mut self,
        key: u64,
        observer: Option<Box<dyn Observer>>,
    ) -> Option<Box<dyn Observer>> {
        Agents::set_observer(self.crowd, key, observer)
    }

    fn hold(&mut self, key: u64, held: bool) {
        Agents::hold(self.crowd, key, held);
    }
}

/// `frame` with the studio's watch and the crowd as the studio sees it.
fn with_watch<C: AgentContext, R>(
    studio: &mut TreeStudio<C>,
    crowd: &mut AgentCrowd<C>,
    frame: impl FnOnce(&mut CrowdWatch, &mut ByEntity<'_, C>) -> R,
) -> R {
    let watch = studio
        .watch
        .get_mut()
        .unwrap_or_else(PoisonError::into_inner);
    let (members, entities) = crowd.crowd_and_entities();
    frame(
        watch,
        &mut ByEntity {
            crowd: members,
            entities,
        },
    )
}

/// Before the tick: the page's choices applied; the frame skipped while the page stands
/// the whole crowd still.
pub(crate) fn before<C: AgentContext>(
    mut studio: ResMut<TreeStudio<C>>,
    mut crowd: ResMut<AgentCrowd<C>>,
) {
    let go = with_watch(&mut studio, &mut crowd, |watch, agents| {
        watch.before_frame(agents)
    });
    crowd.stands_still = !go;
}

/// After the tick: the watched agent's blackboard and why it is awake, for the page.
pub(crate) fn after<C: AgentContext>(
    mut studio: ResMut<TreeStudio<C>>,
    mut crowd: ResMut<AgentCrowd<C>>,
) {
    with_watch(&mut studio, &mut crowd, |watch, agents| {
        watch.after_frame(&*agents)
    });
}
