//! A built-in node's parameters, given in the blueprint or read from its port when ticked.

use core::any::Any;
use core::time::Duration;

use super::Ticker;
use crate::blueprint::{FromPortStr, Param};
use crate::nodes::leaf::read_input;
use crate::NodeId;

impl<C> Ticker<'_, C> {
    /// A built-in node's parameter: its value, or its port read now. An unreadable port is
    /// the node's error (`None`), as BehaviorTree.CPP's nodes throw when `getInput` fails.
    #[inline(always)]
    pub(crate) fn param<T: FromPortStr + Any + Clone>(
        &mut self,
        id: NodeId,
        param: Param<T>,
        port: &'static str,
    ) -> Option<T> {
        match param {
            Param::Value(value) => Some(value),
            Param::Port => self.read_port(id, port),
        }
    }

    /// A duration parameter, whose port holds milliseconds as in BehaviorTree.CPP.
    #[inline(always)]
    pub(crate) fn millis(
        &mut self,
        id: NodeId,
        param: Param<Duration>,
        port: &'static str,
    ) -> Option<Duration> {
        match param {
            Param::Value(value) => Some(value),
            Param::Port => self.read_port::<u64>(id, port).map(Duration::from_millis),
        }
    }

    /// Reads port `port` of node `id`, converting as BehaviorTree.CPP's `Any` does.
    #[cold]
    #[inline(never)]
    fn read_port<T: FromPortStr + Any + Clone>(&mut self, id: NodeId, port: &str) -> Option<T> {
        let read = read_input(self.bb, self.bp, id, port);
        read.map_err(|e| self.fault_node(id, alloc::string::ToString::to_string(&e)))
            .ok()
    }
}
