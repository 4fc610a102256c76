//! What the hub does for a run that goes back and forth through its kept ticks, and for
//! the scene of its world: what pages are shown of a kept tick, what they are told of the
//! window, and a page's request to travel, checked before it reaches the run.

use std::sync::atomic::Ordering;

use neurotree_core::Tree;
use serde_json::Value;

use super::hub::{scores, Hub, Request, NO_SCORE};
use super::rewind::{Shown, Travel};

impl Hub {
    /// What pages are shown of the latest tick, to keep beside its state.
    pub fn shown_now(&self) -> Option<Shown> {
        let inner = self.lock();
        let run = inner.run.as_ref()?;
        let cell = &run.cell;
        let statuses = if self.pages() > 0 {
            cell.shown
                .iter()
                .map(|s| s.load(Ordering::Acquire))
                .collect()
        } else {
            // Nothing keeps `shown` while no page is attached: the statuses as they stand.
            cell.statuses
                .iter()
                .map(|s| s.load(Ordering::Acquire))
                .collect()
        };
        Some(Shown {
            tick: cell.tick.load(Ordering::Acquire),
            statuses,
            scores: scores(cell).into(),
            failure: inner.failure.1.clone(),
        })
    }

    /// Shows pages a kept tick the tree was restored to: its statuses, its scores, its
    /// failure chain, the tree's blackboards; the tick count goes back to it.
    pub(super) fn show_kept<C>(&self, tree: &Tree<C>, shown: Shown) {
        let mut inner = self.lock();
        if let Some(run) = &inner.run {
            let cell = &run.cell;
            for (cell, status) in cell.statuses.iter().zip(tree.statuses()) {
                cell.store(*status as u8, Ordering::Release);
            }
            for (cell, status) in cell.shown.iter().zip(&*shown.statuses) {
                cell.store(*status, Ordering::Release);
            }
            for score in &*cell.scores {
                score.store(NO_SCORE, Ordering::Release);
            }
            for &(i, bits) in &*shown.scores {
                if let Some(score) = cell.scores.get(i) {
                    score.store(bits, Ordering::Release);
                }
            }
            cell.tick.store(shown.tick, Ordering::Release);
            cell.shown_tick.store(shown.tick, Ordering::Release);
        }
        if inner.failure.1 != shown.failure {
            inner.failure = (inner.failure.0 + 1, shown.failure);
        }
        drop(inner);
        self.bump();
    }

    /// Tells every page that the run refused a request, and why.
    pub fn refuse(&self, why: String) {
        let mut inner = self.lock();
        inner.refusal = (inner.refusal.0 + 1, why);
        drop(inner);
        self.count_refused();
        self.bump();
    }

    /// Tells pages the kept ticks (when they changed).
    pub fn set_rewind(&self, rewind: Value) {
        let mut inner = self.lock();
        if inner.rewind.1 != rewind {
            inner.rewind = (inner.rewind.0 + 1, rewind);
            drop(inner);
            self.bump();
        }
    }

    /// Shows pages `scene` (JSON, or why none is shown), when it changed.
    pub fn set_scene(&self, scene: Result<String, String>) {
        let mut inner = self.lock();
        let same = match (&inner.scene.1, &scene) {
            (Ok(a), Ok(b)) => **a == **b,
            (Err(a), Err(b)) => a == b,
            _ => false,
        };
        if !same {
            inner.scene = (inner.scene.0 + 1, scene.map(Into::into));
            drop(inner);
            self.bump();
        }
    }

    /// A page asked to see an earlier or later kept tick: refused, with the reason, unless
    /// the run is paused between ticks and the window has such a tick.
    pub fn travel(&self, travel: Travel) -> Result<(), String> {
        let mut inner = self.lock();
        match &inner.paused {
            None => {
                return Err("the run goes back and forth only while paused: pause it first".into())
            }
            Some(p) if p.why == "breakpoint" => {
                return Err(
                    "the run is held inside a tick at a breakpoint: step to the end \
                            of the tick to go back"
                        .into(),
                )
            }
            Some(_) => {}
        }
        let rewind = &inner.rewind.1;
        let tick = inner
            .run
            .as_ref()
            .map_or(0, |r| r.cell.shown_tick.load(Ordering::Acquire));
        let window = rewind["window"].as_u64().unwrap_or(0);
        if window == 0 {
            return Err("this run keeps no ticks to go back to (its rewind window is 0)".into());
        }
        let at = rewind["at"].as_u64();
        if let (Some(why), None) = (rewind["blocked"].as_str(), at) {
            return Err(format!("the run cannot go back from this tick: {why}"));
        }
        let from = at.unwrap_or(tick);
        match travel {
            Travel::Back => {
                let oldest = rewind["oldest"].as_u64();
                if oldest.is_none_or(|o| from <= o) {
                    return Err(format!(
                        "tick {from} is the oldest kept: the run keeps its last {window} ticks \
                         (--rewind-window)"
                    ));
                }
            }
            Travel::Forward => {
                if at.is_none() {
                    return Err(format!("tick {from} is the latest"));
                }
            }
        }
        inner.requests.push(Request::Travel(travel));
        drop(inner);
        self.resume.notify_all();
        Ok(())
    }
}
