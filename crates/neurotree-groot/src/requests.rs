//! Answering one request: frames in, frames out, as BehaviorTree.CPP's `Groot2Publisher`
//! answers them.

use std::time::{SystemTime, UNIX_EPOCH};

use serde_json::{Map, Value};

use super::monitor::{failure_entries, Groot2Monitor};
use super::protocol::{error_reply, ReplyHeader, RequestHeader, RequestType};

impl Groot2Monitor {
    /// The reply frames to the request `frames` (the first frame being the 6-byte header).
    ///
    /// The server calls this for every request; it is public so that a program with its own
    /// transport can serve the protocol too. It never fails: a request it cannot read or
    /// answer gets the protocol's error reply (`error`, then a message). Like
    /// BehaviorTree.CPP, it answers whatever protocol byte the header carries, in version 2.
    ///
    /// | request | reply after the header |
    /// |---|---|
    /// | `T` | the tree XML, with `_uid`s |
    /// | `S` | 3 bytes per node: uid (u16), status byte |
    /// | `B` + names | MessagePack map: each known name (`;`-separated) to its entries; no names: every blackboard; after a failed tick the main tree's has the [failure entries](crate::failure_entries) too |
    /// | `r` + `start` | the wall-clock time, in microseconds since 1970, as decimal text; recording starts |
    /// | `r` + `stop` | nothing; recording stops |
    /// | `t` | 9 bytes per transition recorded since the last `t` |
    /// | `D` | `[]`: no hooks are in place |
    /// | `A`, `X` | nothing: there are no hooks to remove or disable |
    /// | `I`, `R`, `U`, other | an error reply: breakpoints are not supported |
    pub fn answer<F: AsRef<[u8]>>(&self, frames: &[F]) -> Vec<Vec<u8>> {
        let Some(first) = frames.first() else {
            return error_reply("empty request");
        };
        let request = match RequestHeader::parse(first.as_ref()) {
            Ok(r) => r,
            Err(e) => return error_reply(&e.to_string()),
        };
        let header = ReplyHeader::answering(request, self.shared.uuid)
            .encode()
            .to_vec();
        let second = || match frames {
            [_, payload] => Ok(payload.as_ref()),
            _ => Err(error_reply("must be 2 parts message")),
        };
        let payload = match RequestType::from_byte(request.kind) {
            Some(RequestType::FullTree) => Some(self.shared.xml.as_bytes().to_vec()),
            Some(RequestType::Status) => Some(self.state().statuses.clone()),
            Some(RequestType::Blackboard) => match second() {
                Ok(names) => Some(self.blackboards(names)),
                Err(e) => return e,
            },
            Some(RequestType::ToggleRecording) => match second() {
                Ok(b"start") => Some(self.start_recording()),
                Ok(b"stop") => {
                    self.state().recording = false;
                    None
                }
                Ok(_) => return error_reply("recording command must be `start` or `stop`"),
                Err(e) => return e,
            },
            Some(RequestType::GetTransitions) => Some(self.take_transitions()),
            Some(RequestType::HooksDump) => Some(b"[]".to_vec()),
            Some(RequestType::RemoveAllHooks | RequestType::DisableAllHooks) => None,
            Some(
                RequestType::HookInsert
                | RequestType::HookRemove
                | RequestType::BreakpointUnlock
                | RequestType::BreakpointReached,
            ) => return error_reply("breakpoints and hooks are not supported by NeuroTree"),
            None => return error_reply("Request not recognized"),
        };
        let mut reply = vec![header];
        reply.extend(payload);
        reply
    }

    /// The MessagePack map of the blackboards named in `names`.
    fn blackboards(&self, names: &[u8]) -> Vec<u8> {
        let names = String::from_utf8_lossy(names);
        let wanted: Vec<&str> = names.split(';').filter(|n| !n.is_empty()).collect();
        let mut out = Map::new();
        let state = self.state();
        for (name, entries) in &state.blackboards {
            if !wanted.is_empty() && !wanted.contains(&name.as_str()) {
                continue;
            }
            let mut entries = entries.clone();
            if let (Some(failure), Value::Object(map)) = (&state.failure, &mut entries) {
                if *name == self.shared.main_tree {
                    // A stored entry of the same name gives way: the monitor's are the
                    // ones the crate documents.
                    map.extend(failure_entries(failure));
                }
            }
            out.insert(name.clone(), entries);
        }
        drop(state);
        // Serializing a JSON value to a Vec fails only on I/O or unrepresentable keys,
        // neither of which a JSON map of strings has; an empty map is the safe answer anyway.
        rmp_serde::to_vec(&Value::Object(out)).unwrap_or_else(|_| vec![0x80])
    }

    fn start_recording(&self) -> Vec<u8> {
        let mut state = self.state();
        state.recording = true;
        state.origin = state.latest;
        state.transitions.clear();
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_micros());
        now.to_string().into_bytes()
    }

    fn take_transitions(&self) -> Vec<u8> {
        let mut state = self.state();
        let mut out = Vec::with_capacity(state.transitions.len() * 9);
        for t in state.transitions.drain(..) {
            out.extend_from_slice(&t.encode());
        }
        out
    }
}
