//! A tree's node state in one block of memory, reached through one thin pointer: the
//! nodes' slots, their statuses, the tick's failure bits, and the per-instance objects of
//! the stateful leaves and custom nodes.
//!
//! A crowd holds up to a million small trees, and each member pays every byte of this
//! block and every trip to memory its tick makes. So the parts share one allocation (one
//! allocator header, one trip to memory for a tick, one stretch for a runner that knows
//! which tree comes next to prefetch), the tree holds one 8-byte pointer to it rather than
//! a 16-byte slice per part (the block's first words give its shape), and each part is as
//! narrow as its values allow:
//!
//! ```text
//! [nodes | slots | objects | slot × slots | status × nodes | pad | failure bits | object × objects]
//!  u32     u32     u32       u32            u8                     u64 × ⌈nodes/64⌉   Object
//! ```
//!
//! - The first three words give the block's shape, so the block alone says how to read
//!   it (and how to drop it).
//! - A slot is 32 bits: the cursors, counters and flags nodes keep fit. A kind that keeps a
//!   64-bit value (the moment a wait began) takes two slots, read through [`get64`] and
//!   written through [`set64`]; a kind says how many it takes ([`aux_slots`]).
//! - A status takes one byte per node, not rounded up to words: the failure bits after them
//!   begin at the next 8-byte boundary, so at most 7 bytes are padding.
//! - The parts a tick reads on every node (the shape, the slots, the statuses) come first,
//!   together; the failure bits (written when a node fails) and the objects (read by the
//!   stateful leaves) follow, each at its type's alignment.
//!
//! - A block is allocated zeroed: every slot 0, every status Idle, every bit clear. Its
//!   objects are written once, by `new`, replaced in place, and dropped with it.
//!
//! For the bench's 50-node agent tree (21 slots: 13 controls and decorators of one, 4
//! waits of two; one stateful leaf): 12 + 84 + 50 + 6 + 8 + 24 = 184 bytes, where slots of
//! 64 bits, statuses in whole words and the objects apart took 208 + 24 and two 16-byte
//! pointers.
//!
//! [`aux_slots`]: crate::blueprint::NodeKind::aux_slots

use alloc::alloc::{alloc_zeroed, dealloc, handle_alloc_error};
use alloc::vec::Vec;
use core::alloc::Layout;
use core::marker::PhantomData;
use core::mem::{align_of, size_of};
use core::ptr::NonNull;

use super::objects::Object;
use crate::NodeStatus;

/// The `u32` words the block begins with: its nodes, slots and objects.
const HEAD: usize = 3;

/// The failure bits, slots, statuses and objects of a tree's nodes (see the
/// [module docs](self)).
pub(crate) struct NodeState<C> {
    /// The block, laid out by its [`Shape`]; allocated by `new`, freed by `drop`.
    block: NonNull<u8>,
    /// The block owns the objects.
    owns: PhantomData<Object<C>>,
}

// SAFETY: the block is owned by the state alone (no other pointer to it is kept), and holds
// plain integers and `Object<C>`s: sending or sharing the state sends or shares those
// objects, as a `Box<[Object<C>]>` would, under the same bounds.
unsafe impl<C> Send for NodeState<C> where Object<C>: Send {}
// SAFETY: as for `Send`; `&NodeState` gives only shared views of the parts.
unsafe impl<C> Sync for NodeState<C> where Object<C>: Sync {}

/// The parts of a [`NodeState`], borrowed side by side.
pub(crate) struct Parts<'a, C> {
    pub(crate) statuses: &'a mut [NodeStatus],
    pub(crate) failed: &'a mut [u64],
    pub(crate) aux: &'a mut [u32],
    pub(crate) objects: &'a mut [Object<C>],
}

/// How many of each part a block holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Shape {
    nodes: usize,
    slots: usize,
    objects: usize,
}

/// Where each part of a block begins (bytes from its start), and the block's size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Offsets {
    statuses: usize,
    failed: usize,
    objects: usize,
    size: usize,
}

/// `at` rounded up to a multiple of `align` (a power of two).
#[inline(always)]
const fn align_up(at: usize, align: usize) -> usize {
    (at + align - 1) & !(align - 1)
}

impl Shape {
    /// The block's layout and parts, computed with overflow checks: `None` for a shape no
    /// block can hold.
    fn layout<C>(self) -> Option<(Layout, Offsets)> {
        let head = Layout::array::<u32>(HEAD.checked_add(self.slots)?).ok()?;
        let (block, statuses) = head
            .extend(Layout::array::<NodeStatus>(self.nodes).ok()?)
            .ok()?;
        let (block, failed) = block
            .extend(Layout::array::<u64>(self.nodes.div_ceil(64)).ok()?)
            .ok()?;
        let (block, objects) = block
            .extend(Layout::array::<Object<C>>(self.objects).ok()?)
            .ok()?;
        let block = block.pad_to_align();
        let offsets = Offsets {
            statuses,
            failed,
            objects,
            size: block.size(),
        };
        Some((block, offsets))
    }

    /// The same offsets as [`layout`](Self::layout), without its checks: for a shape a block
    /// was made for, whose layout was checked then.
    #[inline(always)]
    fn offsets<C>(self) -> Offsets {
        let statuses = (HEAD + self.slots) * size_of::<u32>();
        let failed = align_up(statuses + self.nodes, align_of::<u64>());
        let objects = align_up(
            failed + self.nodes.div_ceil(64) * size_of::<u64>(),
            align_of::<Object<C>>(),
        );
        let align = align_of::<u32>()
            .max(align_of::<u64>())
            .max(align_of::<Object<C>>());
        let size = align_up(objects + self.objects * size_of::<Object<C>>(), align);
        Offsets {
            statuses,
            failed,
            objects,
            size,
        }
    }
}

impl<C> NodeState<C> {
    /// The state of `nodes` nodes with `slots` slots and `objects`: every node Idle, every
    /// slot and bit 0.
    pub(crate) fn new(nodes: usize, slots: usize, objects: Vec<Object<C>>) -> Self {
        let shape = Shape {
            nodes,
            slots,
            objects: objects.len(),
        };
        let (Some((layout, at)), Ok(n), Ok(s), Ok(o)) = (
            shape.layout::<C>(),
            u32::try_from(nodes),
            u32::try_from(slots),
            u32::try_from(objects.len()),
        ) else {
            // A blueprint has fewer than 2^32 nodes, and no more slots and objects than a
            // block of them could hold: what `Vec` says of a capacity beyond memory.
            panic!("node state beyond memory");
        };
        debug_assert_eq!(at, shape.offsets::<C>());
        // SAFETY: the layout is not zero-sized: it holds the shape's words.
        let raw = unsafe { alloc_zeroed(layout) };
        let Some(block) = NonNull::new(raw) else {
            handle_alloc_error(layout)
        };
        // SAFETY: the block is `layout.size()` bytes, aligned for its parts (`Layout::extend`
        // keeps the largest alignment); the head's words lie at its start (alignment 4),
        // the objects at `at.objects` (aligned for them), `shape.objects` of them, within
        // it. The zeroed bytes are the slots 0, the statuses Idle (`NodeStatus` is
        // `repr(u8)` with `Idle = 0`) and the failure bits 0.
        unsafe {
            block.cast::<[u32; HEAD]>().as_ptr().write([n, s, o]);
            let first = block.as_ptr().add(at.objects).cast::<Object<C>>();
            for (i, object) in objects.into_iter().enumerate() {
                first.add(i).write(object);
            }
        }
        Self {
            block,
            owns: PhantomData,
        }
    }

    /// Bytes a block of this shape takes: what [`NodeState::bytes`] will say of it.
    pub(crate) fn bytes_for(nodes: usize, slots: usize, objects: usize) -> usize {
        let shape = Shape {
            nodes,
            slots,
            objects,
        };
        shape.offsets::<C>().size
    }

    /// The block's shape, from its first words.
    #[inline(always)]
    fn shape(&self) -> Shape {
        // SAFETY: the block begins with `HEAD` `u32`s (`new`), aligned, never written after.
        let [nodes, slots, objects] = unsafe { self.block.cast::<[u32; HEAD]>().as_ptr().read() };
        Shape {
            nodes: nodes as usize,
            slots: slots as usize,
            objects: objects as usize,
        }
    }

    /// Bytes the block takes.
    pub(crate) fn bytes(&self) -> usize {
        self.shape().offsets::<C>().size
    }

    /// The block's start, for [`prefetch`](crate::hint::prefetch_bytes): its length is
    /// the blueprint's to say, since reading it here would wait for the very memory a
    /// prefetch asks for.
    #[inline]
    pub(crate) fn block(&self) -> *const u8 {
        self.block.as_ptr()
    }

    /// The parts, to change.
    #[inline(always)]
    pub(crate) fn parts(&mut self) -> Parts<'_, C> {
        let shape = self.shape();
        let at = shape.offsets::<C>();
        let base = self.block.as_ptr();
        // SAFETY: each part lies within the block at its offset (`new` laid the block out
        // with these offsets, and `shape` reads the shape it was made with), aligned for
        // its type, and apart from the others (the offsets are increasing and each part
        // ends before the next begins). Its elements are initialized: the slots, statuses
        // and bits were zeroed and are written only through these views, as values of
        // their types (every `u32` and `u64` is one, and a status view stores only
        // `NodeStatus`es); the objects were written by `new`. The views borrow the block
        // mutably, apart from each other, for as long as `self`.
        unsafe {
            Parts {
                aux: core::slice::from_raw_parts_mut(
                    base.add(HEAD * size_of::<u32>()).cast::<u32>(),
                    shape.slots,
                ),
                statuses: core::slice::from_raw_parts_mut(
                    base.add(at.statuses).cast::<NodeStatus>(),
                    shape.nodes,
                ),
                failed: core::slice::from_raw_parts_mut(
                    base.add(at.failed).cast::<u64>(),
                    shape.nodes.div_ceil(64),
                ),
                objects: core::slice::from_raw_parts_mut(
                    base.add(at.objects).cast::<Object<C>>(),
                    shape.objects,
                ),
            }
        }
    }

    /// The statuses, indexed by node.
    #[inline]
    pub(crate) fn statuses(&self) -> &[NodeStatus] {
        let shape = self.shape();
        let at = shape.offsets::<C>();
        // SAFETY: as in `parts`, shared.
        unsafe {
            core::slice::from_raw_parts(
                self.block.as_ptr().add(at.statuses).cast::<NodeStatus>(),
                shape.nodes,
            )
        }
    }

    /// The failure bits.
    #[inline]
    pub(crate) fn failed(&self) -> &[u64] {
        let shape = self.shape();
        let at = shape.offsets::<C>();
        // SAFETY: as in `parts`, shared.
        unsafe {
            core::slice::from_raw_parts(
                self.block.as_ptr().add(at.failed).cast::<u64>(),
                shape.nodes.div_ceil(64),
            )
        }
    }

    /// The slots.
    #[inline]
    pub(crate) fn aux(&self) -> &[u32] {
        let shape = self.shape();
        // SAFETY: as in `parts`, shared.
        unsafe {
            core::slice::from_raw_parts(
                self.block
                    .as_ptr()
                    .add(HEAD * size_of::<u32>())
                    .cast::<u32>(),
                shape.slots,
            )
        }
    }

    /// The per-instance objects, in slot order.
    #[inline]
    pub(crate) fn objects(&self) -> &[Object<C>] {
        let shape = self.shape();
        let at = shape.offsets::<C>();
        // SAFETY: as in `parts`, shared.
        unsafe {
            core::slice::from_raw_parts(
                self.block.as_ptr().add(at.objects).cast::<Object<C>>(),
                shape.objects,
            )
        }
    }
    /// The per-instance objects, to change.
    #[inline]
    pub(crate) fn objects_mut(&mut self) -> &mut [Object<C>] {
        let shape = self.shape();
        let at = shape.offsets::<C>();
        // SAFETY: as in `parts`, for the objects alone.
        unsafe {
            core::slice::from_raw_parts_mut(
                self.block.as_ptr().add(at.objects).cast::<Object<C>>(),
                shape.objects,
            )
        }
    }
}

impl<C> Drop for NodeState<C> {
    fn drop(&mut self) {
        let shape = self.shape();
        let Some((layout, _)) = shape.layout::<C>() else {
            // `new` made the block with this layout: it exists.
            return;
        };
        // A panic in an object's drop leaves the block allocated (leaked) rather than
        // freed under the objects still to drop.
        let objects: *mut [Object<C>] = self.objects_mut();
        // SAFETY: the objects are initialized (`new`, and only replaced through `parts`
        // since) and dropped once, here; the block was allocated by `new` with `layout`
        // and is freed once, after them, with nothing reading it after.
        unsafe {
            core::ptr::drop_in_place(objects);
            dealloc(self.block.as_ptr(), layout);
        }
    }
}

/// The 64-bit value a kind keeps in the two slots from `slot` (see the [module docs](self)).
#[inline(always)]
pub(crate) fn get64(aux: &[u32], slot: usize) -> u64 {
    u64::from(aux[slot]) | (u64::from(aux[slot + 1]) << 32)
}

/// Writes the 64-bit value a kind keeps in the two slots from `slot`.
#[inline(always)]
pub(crate) fn set64(aux: &mut [u32], slot: usize, value: u64) {
    aux[slot] = value as u32;
    aux[slot + 1] = (value >> 32) as u32;
}

impl<C> super::Ticker<'_, C> {
    /// The 64-bit value a node keeps in the two state slots from `slot`.
    #[inline(always)]
    pub(crate) fn aux64(&self, slot: usize) -> u64 {
        get64(self.aux, slot)
    }

    /// Writes the 64-bit value a node keeps in the two state slots from `slot`.
    #[inline(always)]
    pub(crate) fn set_aux64(&mut self, slot: usize, value: u64) {
        set64(self.aux, slot, value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::boxed::Box;
    use alloc::sync::Arc;
    use core::sync::atomic::{AtomicUsize, Ordering};

    use crate::nodes::leaf::{Handle, StatefulAction};
    use crate::Status;

    /// A stateful action that counts its drops, and says which it is.
    struct Counted(usize, Arc<AtomicUsize>);

    impl StatefulAction<()> for Counted {
        fn on_start(&mut self, _: &mut Handle<'_, ()>) -> Status {
            Status::Success
        }
        fn on_running(&mut self, _: &mut Handle<'_, ()>) -> Status {
            Status::Success
        }
        fn save_state(&self) -> Option<Vec<u8>> {
            Some(alloc::vec![self.0 as u8])
        }
    }

    impl Drop for Counted {
        fn drop(&mut self) {
            self.1.fetch_add(1, Ordering::Relaxed);
        }
    }

    fn which(object: &Object<()>) -> Option<usize> {
        match object {
            Object::Stateful(action) => action.save_state().map(|b| usize::from(b[0])),
            _ => None,
        }
    }

    #[test]
    fn parts_are_apart_and_keep_what_is_written() {
        for (nodes, slots, objects) in [
            (0, 0, 0),
            (1, 0, 1),
            (7, 3, 2),
            (8, 1, 0),
            (9, 2, 3),
            (50, 17, 1),
            (64, 0, 0),
            (65, 5, 4),
            (130, 17, 7),
        ] {
            let drops = Arc::new(AtomicUsize::new(0));
            let made = (0..objects)
                .map(|i| Object::Stateful(Box::new(Counted(i, Arc::clone(&drops)))))
                .collect();
            let mut state = NodeState::<()>::new(nodes, slots, made);
            let at = Shape {
                nodes,
                slots,
                objects,
            }
            .layout::<()>()
            .unwrap()
            .1;
            assert_eq!(state.bytes(), at.size);
            assert_eq!(
                state.bytes(),
                NodeState::<()>::bytes_for(nodes, slots, objects)
            );
            // The hot parts lie together, a byte per status, and nothing is wasted but
            // alignment.
            assert_eq!(at.statuses, 4 * (3 + slots));
            assert!(at.failed - (at.statuses + nodes) < 8);
            let p = state.parts();
            assert_eq!(
                (
                    p.statuses.len(),
                    p.failed.len(),
                    p.aux.len(),
                    p.objects.len()
                ),
                (nodes, nodes.div_ceil(64), slots, objects)
            );
            assert!(p.statuses.iter().all(|s| *s == NodeStatus::Idle));
            assert!(p.aux.iter().all(|a| *a == 0));
            assert!(p.failed.iter().all(|w| *w == 0));
            for (i, s) in p.statuses.iter_mut().enumerate() {
                *s = [
                    NodeStatus::Running,
                    NodeStatus::Failure,
                    NodeStatus::Skipped,
                ][i % 3];
            }
            p.failed.fill(u64::MAX);
            for (i, a) in p.aux.iter_mut().enumerate() {
                *a = u32::MAX - i as u32;
            }
            // Replacing an object drops the one it replaces, and only that one.
            if let Some(first) = p.objects.first_mut() {
                *first = Object::Stateful(Box::new(Counted(100, Arc::clone(&drops))));
                assert_eq!(drops.load(Ordering::Relaxed), 1);
            }
            for (i, s) in state.statuses().iter().enumerate() {
                assert_eq!(
                    *s,
                    [
                        NodeStatus::Running,
                        NodeStatus::Failure,
                        NodeStatus::Skipped
                    ][i % 3]
                );
            }
            assert!(state.failed().iter().all(|w| *w == u64::MAX));
            assert!(state
                .aux()
                .iter()
                .enumerate()
                .all(|(i, a)| *a == u32::MAX - i as u32));
            let kept: Vec<_> = state.objects().iter().map(which).collect();
            let expected: Vec<_> = (0..objects)
                .map(|i| Some(if i == 0 { 100 } else { i }))
                .collect();
            assert_eq!(kept, expected);
            assert_eq!(
                state.shape(),
                Shape {
                    nodes,
                    slots,
                    objects
                }
            );
            let replaced = objects.min(1);
            drop(state);
            assert_eq!(drops.load(Ordering::Relaxed), objects + replaced);
        }
    }

    #[test]
    fn the_state_and_its_tree_go_to_other_threads_as_their_objects_do() {
        // Both `Send`, as the objects are; neither `Sync`, as they are not (a stateful
        // leaf need not be).
        fn send<T: Send>() {}
        send::<Object<()>>();
        send::<NodeState<()>>();
        send::<crate::Tree<()>>();
    }

    #[test]
    fn a_wide_value_takes_two_slots_and_keeps_all_its_bits() {
        let mut state = NodeState::<()>::new(3, 5, Vec::new());
        let aux = state.parts().aux;
        aux[0] = 7;
        aux[3] = 9;
        set64(aux, 1, (5 << 32) | 0xDEAD_BEEF);
        assert_eq!(get64(aux, 1), (5 << 32) | 0xDEAD_BEEF);
        assert_eq!((aux[0], aux[1], aux[2], aux[3]), (7, 0xDEAD_BEEF, 5, 9));
        set64(aux, 3, u64::MAX - 1);
        assert_eq!(get64(state.aux(), 3), u64::MAX - 1);
        assert_eq!(get64(state.aux(), 1), (5 << 32) | 0xDEAD_BEEF);
    }
}
