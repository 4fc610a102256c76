//! The objects a registered async leaf is made of: one per node kind, shared by every node
//! and instance of it.

use std::future::Future;
use std::sync::Arc;

use neurotree_core::{Handle, Status};

/// A registered async closure, shared by every node of its kind.
pub(super) struct SharedAsync<F>(pub(super) Arc<F>);

impl<C, F, Fut> neurotree_core::AsyncAction<C> for SharedAsync<F>
where
    F: Fn(&mut Handle<'_, C>) -> Fut + Send + Sync,
    Fut: Future<Output = Status> + Send + 'static,
{
    fn start(&self, h: &mut Handle<'_, C>) -> neurotree_core::ActionFuture {
        Box::pin((self.0)(h))
    }
}

/// A registered [`AsyncAction`](neurotree_core::AsyncAction) object, one per node kind.
pub(super) struct SharedAsyncAction<A>(pub(super) Arc<A>);

impl<C, A> neurotree_core::AsyncAction<C> for SharedAsyncAction<A>
where
    A: neurotree_core::AsyncAction<C>,
{
    fn start(&self, h: &mut Handle<'_, C>) -> neurotree_core::ActionFuture {
        self.0.start(h)
    }

    fn on_halt_requested(
        &self,
        run: neurotree_core::ActionFuture,
        h: &mut Handle<'_, C>,
    ) -> Option<neurotree_core::HaltFuture> {
        self.0.on_halt_requested(run, h)
    }
}
