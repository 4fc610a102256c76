//! The bytes of BehaviorTree.CPP's Groot2 monitor protocol, version 2 (its
//! `groot2_protocol.h`), with nothing of the network in it.
//!
//! Every exchange is one multipart ZeroMQ request and one multipart reply:
//!
//! - a request starts with a 6-byte [`RequestHeader`]: the protocol byte (2), the request
//!   type (an ASCII letter, [`RequestType`]) and a 32-bit id the client picks, little-endian;
//! - a reply starts with a 22-byte [`ReplyHeader`]: the request's header (protocol set to 2)
//!   followed by the 16-byte id of the tree, so that a client notices when the tree changed;
//! - a request the server cannot answer gets two frames, `error` and a message, and no
//!   header ([`error_reply`]).
//!
//! Payloads: the status of every node as 3-byte records ([`status_record`]); recorded
//! transitions as 9-byte records ([`Transition`]); the tree as XML; blackboards as MessagePack.
//! Integers are little-endian, as BehaviorTree.CPP copies them from memory on the machines it
//! runs on.

use neurotree_core::NodeStatus;

/// The protocol version this module speaks (`kProtocolID`).
pub const PROTOCOL: u8 = 2;

/// The first frame of every error reply.
pub const ERROR_FRAME: &[u8] = b"error";

/// What a request asks for: the type byte of its header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestType {
    /// `T`: the tree as XML, every element with its `_uid`.
    FullTree,
    /// `S`: the status of every node.
    Status,
    /// `B`: the blackboards named in the second frame (`;`-separated), as MessagePack.
    Blackboard,
    /// `I`: insert a breakpoint or a node replacement (a JSON hook).
    HookInsert,
    /// `R`: remove a hook.
    HookRemove,
    /// `N`: sent by the server on its PUB socket when a breakpoint is reached.
    BreakpointReached,
    /// `U`: let a node held at a breakpoint go on.
    BreakpointUnlock,
    /// `D`: the hooks in place, as a JSON array.
    HooksDump,
    /// `A`: remove every hook (Groot2 sends it before disconnecting).
    RemoveAllHooks,
    /// `X`: disable every hook.
    DisableAllHooks,
    /// `r`: start (`start`) or stop (`stop`) recording transitions.
    ToggleRecording,
    /// `t`: the transitions recorded since the last `t`.
    GetTransitions,
}

impl RequestType {
    /// Every request type, in the order of `groot2_protocol.h`.
    pub const ALL: [RequestType; 12] = [
        RequestType::FullTree,
        RequestType::Status,
        RequestType::Blackboard,
        RequestType::HookInsert,
        RequestType::HookRemove,
        RequestType::BreakpointReached,
        RequestType::BreakpointUnlock,
        RequestType::HooksDump,
        RequestType::RemoveAllHooks,
        RequestType::DisableAllHooks,
        RequestType::ToggleRecording,
        RequestType::GetTransitions,
    ];

    /// The type's byte on the wire.
    pub const fn byte(self) -> u8 {
        match self {
            RequestType::FullTree => b'T',
            RequestType::Status => b'S',
            RequestType::Blackboard => b'B',
            RequestType::HookInsert => b'I',
            RequestType::HookRemove => b'R',
            RequestType::BreakpointReached => b'N',
            RequestType::BreakpointUnlock => b'U',
            RequestType::HooksDump => b'D',
            RequestType::RemoveAllHooks => b'A',
            RequestType::DisableAllHooks => b'X',
            RequestType::ToggleRecording => b'r',
            RequestType::GetTransitions => b't',
        }
    }

    /// The type a byte names, if any.
    pub fn from_byte(byte: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.byte() == byte)
    }
}

/// A request header the server could not read.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ProtocolError {
    /// The first frame is not the 6 bytes of a request header.
    #[error("wrong request header: {len} bytes instead of {expected}", expected = RequestHeader::SIZE)]
    HeaderSize {
        /// The length received.
        len: usize,
    },
    /// A transitions payload is not a whole number of 9-byte records.
    #[error("transitions payload of {len} bytes is not a whole number of {size}-byte records", size = Transition::SIZE)]
    TransitionsSize {
        /// The length received.
        len: usize,
    },
    /// A transition record names a status byte that is not a status.
    #[error("unknown status byte {byte} in a transition record")]
    StatusByte {
        /// The byte received.
        byte: u8,
    },
}

neurotree_core::debug_shows_message!(enum ProtocolError {
    HeaderSize { len },
    TransitionsSize { len },
    StatusByte { byte },
});

/// The fixed first frame of a request.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RequestHeader {
    /// The protocol version the client speaks.
    pub protocol: u8,
    /// The request type's byte (see [`RequestType::from_byte`]); kept raw so that a reply can
    /// echo a type this side does not know.
    pub kind: u8,
    /// The client's id for this request, echoed in the reply.
    pub id: u32,
}

impl RequestHeader {
    /// Bytes on the wire.
    pub const SIZE: usize = 6;

    /// A version-2 header of type `kind`.
    pub const fn new(kind: RequestType, id: u32) -> Self {
        RequestHeader {
            protocol: PROTOCOL,
            kind: kind.byte(),
            id,
        }
    }

    /// Reads a header; the frame must be exactly [`SIZE`](Self::SIZE) bytes, as
    /// BehaviorTree.CPP requires.
    pub fn parse(frame: &[u8]) -> Result<Self, ProtocolError> {
        match *frame {
            [protocol, kind, a, b, c, d] => Ok(RequestHeader {
                protocol,
                kind,
                id: u32::from_le_bytes([a, b, c, d]),
            }),
            _ => Err(ProtocolError::HeaderSize { len: frame.len() }),
        }
    }

    /// The header's bytes.
    pub fn encode(&self) -> [u8; Self::SIZE] {
        let id = self.id.to_le_bytes();
        [self.protocol, self.kind, id[0], id[1], id[2], id[3]]
    }
}

/// The fixed first frame of a reply.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReplyHeader {
    /// The request answered, its protocol set to [`PROTOCOL`].
    pub request: RequestHeader,
    /// The id of the tree being served.
    pub tree_uuid: [u8; 16],
}

impl ReplyHeader {
    /// Bytes on the wire.
    pub const SIZE: usize = RequestHeader::SIZE + 16;

    /// The header answering `request` for the tree `tree_uuid`.
    pub fn answering(request: RequestHeader, tree_uuid: [u8; 16]) -> Self {
        ReplyHeader {
            request: RequestHeader {
                protocol: PROTOCOL,
                ..request
            },
            tree_uuid,
        }
    }

    /// The header's bytes.
    pub fn encode(&self) -> [u8; Self::SIZE] {
        let mut out = [0; Self::SIZE];
        out[..RequestHeader::SIZE].copy_from_slice(&self.request.encode());
        out[RequestHeader::SIZE..].copy_from_slice(&self.tree_uuid);
        out
    }
}

/// The two frames of an error reply.
pub fn error_reply(message: &str) -> Vec<Vec<u8>> {
    vec![ERROR_FRAME.to_vec(), message.as_bytes().to_vec()]
}

/// The status byte of a node that went from `from` to `to`.
///
/// A node back to Idle reports where it came from, as `10 +` that status (12: idle after
/// success, 13: after failure, 11: halted while running), so that a viewer can still show
/// what the node did in the tick that reset it.
pub const fn status_byte(from: NodeStatus, to: NodeStatus) -> u8 {
    match to {
        NodeStatus::Idle => 10 + from as u8,
        _ => to as u8,
    }
}

/// One 3-byte record of a status reply: the node's uid and its status byte.
pub const fn status_record(uid: u16, status: u8) -> [u8; 3] {
    let uid = uid.to_le_bytes();
    [uid[0], uid[1], status]
}

/// One recorded status change, as a `t` reply carries it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transition {
    /// Microseconds since recording started (48 bits on the wire).
    pub micros: u64,
    /// The node's uid.
    pub uid: u16,
    /// Its new status (plain: an Idle is 0, whatever it came from).
    pub status: NodeStatus,
}

impl Transition {
    /// Bytes of one record on the wire.
    pub const SIZE: usize = 9;

    /// The record's bytes: 6 bytes of time, 2 of uid, 1 of status.
    pub fn encode(&self) -> [u8; Self::SIZE] {
        let t = self.micros.to_le_bytes();
        let uid = self.uid.to_le_bytes();
        [
            t[0],
            t[1],
            t[2],
            t[3],
            t[4],
            t[5],
            uid[0],
            uid[1],
            self.status as u8,
        ]
    }

    /// Reads a `t` payload back into records.
    pub fn parse_all(payload: &[u8]) -> Result<Vec<Transition>, ProtocolError> {
        if !payload.len().is_multiple_of(Self::SIZE) {
            return Err(ProtocolError::TransitionsSize { len: payload.len() });
        }
        payload
            .chunks_exact(Self::SIZE)
            .map(|r| {
                let mut t = [0; 8];
                t[..6].copy_from_slice(&r[..6]);
                Ok(Transition {
                    micros: u64::from_le_bytes(t),
                    uid: u16::from_le_bytes([r[6], r[7]]),
                    status: status_of(r[8]).ok_or(ProtocolError::StatusByte { byte: r[8] })?,
                })
            })
            .collect()
    }
}

fn status_of(byte: u8) -> Option<NodeStatus> {
    [
        NodeStatus::Idle,
        NodeStatus::Running,
        NodeStatus::Success,
        NodeStatus::Failure,
        NodeStatus::Skipped,
    ]
    .into_iter()
    .find(|s| *s as u8 == byte)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn request_header_round_trips_little_endian() {
        let h = RequestHeader::new(RequestType::Status, 0x0403_0201);
        assert_eq!(h.encode(), [2, b'S', 1, 2, 3, 4]);
        assert_eq!(RequestHeader::parse(&[2, b'S', 1, 2, 3, 4]), Ok(h));
        assert_eq!(
            RequestHeader::parse(&[2, b'S', 1]),
            Err(ProtocolError::HeaderSize { len: 3 })
        );
        assert_eq!(
            RequestHeader::parse(&[0; 7]),
            Err(ProtocolError::HeaderSize { len: 7 })
        );
    }

    #[test]
    fn reply_header_is_the_request_then_the_tree_id() {
        let request = RequestHeader {
            protocol: 1,
            kind: b'T',
            id: 258,
        };
        let reply = ReplyHeader::answering(request, [7; 16]).encode();
        assert_eq!(reply[..6], [2, b'T', 2, 1, 0, 0]);
        assert_eq!(reply[6..], [7; 16]);
    }

    #[test]
    fn request_types_are_the_letters_of_groot2_protocol_h() {
        let letters: Vec<u8> = RequestType::ALL.iter().map(|t| t.byte()).collect();
        assert_eq!(letters, b"TSBIRNUDAXrt");
        assert_eq!(
            RequestType::from_byte(b'r'),
            Some(RequestType::ToggleRecording)
        );
        assert_eq!(RequestType::from_byte(b'?'), None);
    }

    #[test]
    fn idle_reports_the_status_it_left() {
        use NodeStatus::*;
        assert_eq!(status_byte(Idle, Running), 1);
        assert_eq!(status_byte(Running, Success), 2);
        assert_eq!(status_byte(Running, Failure), 3);
        assert_eq!(status_byte(Idle, Skipped), 4);
        assert_eq!(status_byte(Running, Idle), 11);
        assert_eq!(status_byte(Success, Idle), 12);
        assert_eq!(status_byte(Failure, Idle), 13);
        assert_eq!(status_byte(Skipped, Idle), 14);
        assert_eq!(status_record(0x0102, 12), [2, 1, 12]);
    }

    #[test]
    fn transitions_are_nine_bytes_with_a_48_bit_time() {
        let t = Transition {
            micros: 0x0000_0605_0403_0201,
            uid: 0x0807,
            status: NodeStatus::Failure,
        };
        assert_eq!(t.encode(), [1, 2, 3, 4, 5, 6, 7, 8, 3]);
        assert_eq!(Transition::parse_all(&t.encode()), Ok(vec![t]));
        assert_eq!(
            Transition::parse_all(&[0; 10]),
            Err(ProtocolError::TransitionsSize { len: 10 })
        );
        let mut bad = t.encode();
        bad[8] = 12;
        assert_eq!(
            Transition::parse_all(&bad),
            Err(ProtocolError::StatusByte { byte: 12 })
        );
    }
}
