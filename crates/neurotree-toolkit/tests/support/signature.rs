//! Everything a blueprint is made of, as comparable text.

use neurotree::Blueprint;

/// Each node in pre-order: parent, type, name, kind with its parameters, ports and hooks.
pub fn signature<C: 'static>(bp: &Blueprint<C>) -> Vec<String> {
    bp.ids()
        .map(|id| {
            let mut hooks = Vec::new();
            if let Some(h) = bp.node_hooks(id) {
                h.attributes(&mut |k, v| hooks.push(format!("{k}={v}")));
            }
            format!(
                "{} parent={:?} type={} name={} kind={:?} ports={:?} hooks={:?}",
                id.0,
                bp.parent(id).map(|p| p.0),
                bp.type_id(id),
                bp.name(id),
                bp.kind(id),
                bp.ports(id),
                hooks
            )
        })
        .collect()
}
