//! What BehaviorTree.CPP refuses of a ReactiveSequence when it loads a file.

use neurotree_core::nodes::control::sequence;

use super::{Element, LoadError, LoadErrorKind};

/// Refuses a ReactiveSequence `el` with more than one asynchronous child, as
/// BehaviorTree.CPP does, counting the children written as `<AsyncSequence>` (the
/// asynchronous control it registers).
pub(super) fn check_reactive(el: Element<'_>) -> Result<(), LoadError> {
    let async_child = sequence::ASYNC_SEQUENCE.name;
    if el.children().filter(|c| c.tag() == async_child).count() > 1 {
        return Err(el.error(
            LoadErrorKind::ReactiveAsync,
            "a ReactiveSequence cannot have more than one async child \
             (AsyncSequence), as BehaviorTree.CPP refuses: only one child of a \
             ReactiveSequence may be Running; use a Sequence, or move all but one \
             into another branch",
        ));
    }
    Ok(())
}
