//! Just enough of ZMTP 3 (ZeroMQ's wire protocol) to be the server end of REQ and SUB
//! connections with the NULL mechanism: the greeting, the READY and PING commands, and
//! frames.
//!
//! Written here rather than taken from the `zeromq` crate because that crate's decoder
//! reserves whatever length a peer's frame header claims before a byte of the frame
//! arrives: one header claiming 2^62 bytes aborted the whole process on a failed
//! allocation, which no `catch_unwind` stops, and one claiming 100 MB pinned that much per
//! connection. Here a frame's length is checked against the message's budget before its
//! body is read, and the body's buffer grows only as its bytes arrive.
//!
//! Every malformed input is a [`WireError`]; the caller drops that peer.

use std::time::Duration;

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};

/// The greeting's length, each way.
pub(crate) const GREETING_LEN: usize = 64;

/// What each frame costs a message's budget besides its bytes: the bookkeeping a zero-length
/// frame still needs, so that a stream of empty frames is bounded too.
const FRAME_COST: usize = 64;

/// Why a peer's bytes cannot be served; the connection is closed on any of them.
#[derive(Debug, thiserror::Error)]
pub(crate) enum WireError {
    #[error("not a ZMTP 3 greeting")]
    Greeting,
    #[error("mechanism other than NULL")]
    Mechanism,
    #[error("frame flags {0:#04x} have reserved bits set")]
    Flags(u8),
    #[error("a frame of {claimed} bytes exceeds the message's remaining {budget} bytes")]
    TooLong { claimed: u64, budget: usize },
    #[error("malformed command")]
    Command,
    #[error("a command in the middle of a message")]
    CommandInMessage,
    #[error("the peer's socket type {0:?} cannot talk to this socket")]
    SocketType(String),
    #[error("the peer reported an error")]
    PeerError,
    #[error("timed out")]
    TimedOut,
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// This side's greeting: version 3.0 (what a 3.1 peer falls back to), NULL, not as server
/// (NULL has no server role).
pub(crate) fn greeting() -> [u8; GREETING_LEN] {
    let mut out = [0; GREETING_LEN];
    out[0] = 0xff;
    out[9] = 0x7f;
    out[10] = 3;
    out[12..16].copy_from_slice(b"NULL");
    out
}

/// Checks a peer's greeting: the signature, a major version of at least 3 (ZMTP 1 and 2
/// peers are not served), and the NULL mechanism.
pub(crate) fn check_greeting(peer: &[u8; GREETING_LEN]) -> Result<(), WireError> {
    if peer[0] != 0xff || peer[9] & 1 == 0 || peer[10] < 3 {
        return Err(WireError::Greeting);
    }
    let mechanism = &peer[12..32];
    if &mechanism[..4] != b"NULL" || mechanism[4..].iter().any(|&b| b != 0) {
        return Err(WireError::Mechanism);
    }
    Ok(())
}

/// What a peer sent: a command, or a whole message (every frame up to one without MORE).
pub(crate) enum Incoming {
    /// A command's name and its data.
    Command { name: Vec<u8>, data: Vec<u8> },
    /// A message's frames.
    Message(Vec<Vec<u8>>),
}

/// Reads the next command or message, refusing any whose frames add up to more than
/// `max_message_bytes` (each frame counting its length plus a fixed cost) before reading
/// the frame that would pass it.
pub(crate) async fn read_incoming<R: AsyncRead + Unpin>(
    stream: &mut R,
    max_message_bytes: usize,
) -> Result<Incoming, WireError> {
    let mut budget = max_message_bytes;
    let mut frames = Vec::new();
    loop {
        let flags = stream.read_u8().await?;
        if flags & !0b111 != 0 {
            return Err(WireError::Flags(flags));
        }
        let (more, long, command) = (flags & 1 != 0, flags & 2 != 0, flags & 4 != 0);
        let claimed = if long {
            stream.read_u64().await?
        } else {
            u64::from(stream.read_u8().await?)
        };
        let len = usize::try_from(claimed)
            .ok()
            .filter(|len| len.saturating_add(FRAME_COST) <= budget)
            .ok_or(WireError::TooLong { claimed, budget })?;
        budget -= len + FRAME_COST;
        let body = read_body(stream, len).await?;
        if command {
            // A command is one frame, and never splits a message.
            if more || !frames.is_empty() {
                return Err(WireError::CommandInMessage);
            }
            return parse_command(body);
        }
        frames.push(body);
        if !more {
            return Ok(Incoming::Message(frames));
        }
    }
}

/// Reads `len` bytes into a buffer that grows as they come, so that a peer which announces
/// a long frame and then trickles costs memory for what it sent, not what it promised.
async fn read_body<R: AsyncRead + Unpin>(stream: &mut R, len: usize) -> Result<Vec<u8>, WireError> {
    let mut body = Vec::new();
    // `len` fits in a u64 on every platform Rust supports.
    let read = (&mut *stream)
        .take(len as u64)
        .read_to_end(&mut body)
        .await?;
    if read < len {
        return Err(std::io::Error::from(std::io::ErrorKind::UnexpectedEof).into());
    }
    Ok(body)
}

fn parse_command(mut body: Vec<u8>) -> Result<Incoming, WireError> {
    let name_len = usize::from(*body.first().ok_or(WireError::Command)?);
    if body.len() < 1 + name_len {
        return Err(WireError::Command);
    }
    let data = body.split_off(1 + name_len);
    body.remove(0);
    Ok(Incoming::Command { name: body, data })
}

/// The value of `property` in a READY command's data, if the data is well formed and has it.
pub(crate) fn ready_property<'a>(
    mut data: &'a [u8],
    property: &str,
) -> Result<Option<&'a [u8]>, WireError> {
    let mut found = None;
    while let Some((&name_len, rest)) = data.split_first() {
        let name_len = usize::from(name_len);
        let name = rest.get(..name_len).ok_or(WireError::Command)?;
        let rest = &rest[name_len..];
        let value_len: [u8; 4] = rest
            .get(..4)
            .and_then(|b| b.try_into().ok())
            .ok_or(WireError::Command)?;
        let value_len =
            usize::try_from(u32::from_be_bytes(value_len)).map_err(|_| WireError::Command)?;
        let end = value_len.checked_add(4).ok_or(WireError::Command)?;
        let value = rest.get(4..end).ok_or(WireError::Command)?;
        // Property names are case-insensitive.
        if name.eq_ignore_ascii_case(property.as_bytes()) {
            found = Some(value);
        }
        data = &rest[end..];
    }
    Ok(found)
}

/// A READY command announcing `socket_type`, as a frame.
pub(crate) fn ready(socket_type: &str) -> Vec<u8> {
    let mut body = vec![5];
    body.extend_from_slice(b"READY");
    body.push(11);
    body.extend_from_slice(b"Socket-Type");
    // Socket type names are a few letters.
    body.extend_from_slice(&(socket_type.len() as u32).to_be_bytes());
    body.extend_from_slice(socket_type.as_bytes());
    let mut out = Vec::with_capacity(body.len() + 9);
    push_frame(&mut out, &body, false, true);
    out
}

/// The PONG answering a PING's data (its TTL, then a context of up to 16 bytes to echo), as
/// a frame; `None` if the PING is malformed.
pub(crate) fn pong(ping: &[u8]) -> Option<Vec<u8>> {
    let context = ping.get(2..).filter(|c| c.len() <= 16)?;
    let mut body = vec![4];
    body.extend_from_slice(b"PONG");
    body.extend_from_slice(context);
    let mut out = Vec::with_capacity(body.len() + 2);
    push_frame(&mut out, &body, false, true);
    Some(out)
}

/// A message's frames, encoded.
pub(crate) fn message<F: AsRef<[u8]>>(frames: &[F]) -> Vec<u8> {
    let size = frames.iter().map(|f| f.as_ref().len() + 9).sum();
    let mut out = Vec::with_capacity(size);
    for (i, frame) in frames.iter().enumerate() {
        push_frame(&mut out, frame.as_ref(), i + 1 < frames.len(), false);
    }
    out
}

fn push_frame(out: &mut Vec<u8>, body: &[u8], more: bool, command: bool) {
    let mut flags = u8::from(more) | if command { 4 } else { 0 };
    if let Ok(short) = u8::try_from(body.len()) {
        out.push(flags);
        out.push(short);
    } else {
        flags |= 2;
        out.push(flags);
        // A slice's length fits in a u64 on every platform Rust supports.
        out.extend_from_slice(&(body.len() as u64).to_be_bytes());
    }
    out.extend_from_slice(body);
}

/// Writes `bytes` within `timeout`: a peer that does not read what it is sent is not waited
/// for longer than that.
pub(crate) async fn send<W: AsyncWrite + Unpin>(
    stream: &mut W,
    bytes: &[u8],
    timeout: Duration,
) -> Result<(), WireError> {
    match tokio::time::timeout(timeout, stream.write_all(bytes)).await {
        Ok(written) => Ok(written?),
        Err(_) => Err(WireError::TimedOut),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    async fn incoming(bytes: &[u8], max: usize) -> Result<Incoming, WireError> {
        read_incoming(&mut &bytes[..], max).await
    }

    fn block_on<F: std::future::Future>(future: F) -> F::Output {
        tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap()
            .block_on(future)
    }

    #[test]
    fn a_message_round_trips_through_short_and_long_frames() {
        let long = vec![7; 300];
        let bytes = message(&[&b""[..], b"abc", &long]);
        assert_eq!(bytes[..2], [0x01, 0]);
        assert_eq!(bytes[2..5], [0x01, 3, b'a']);
        assert_eq!(bytes[7..16], [0x02, 0, 0, 0, 0, 0, 0, 1, 44]);
        let Ok(Incoming::Message(frames)) = block_on(incoming(&bytes, 1 << 20)) else {
            panic!("not a message");
        };
        assert_eq!(frames, [vec![], b"abc".to_vec(), long]);
    }

    #[test]
    fn lengths_past_the_budget_are_refused_before_reading() {
        // Only the header is there: the refusal cannot have waited for the body.
        let mut header = vec![0x02];
        header.extend_from_slice(&(1_u64 << 62).to_be_bytes());
        assert!(matches!(
            block_on(incoming(&header, 1 << 20)),
            Err(WireError::TooLong { claimed, .. }) if claimed == 1 << 62
        ));
        assert!(matches!(
            block_on(incoming(&[0x00, 200], 200)),
            Err(WireError::TooLong {
                claimed: 200,
                budget: 200
            })
        ));
        assert!(matches!(
            block_on(incoming(&[0x08, 0], 200)),
            Err(WireError::Flags(0x08))
        ));
    }

    #[test]
    fn commands_are_parsed_and_checked() {
        let ready = ready("REP");
        let Ok(Incoming::Command { name, data }) = block_on(incoming(&ready, 1024)) else {
            panic!("not a command");
        };
        assert_eq!(name, b"READY");
        assert_eq!(
            ready_property(&data, "socket-type").unwrap(),
            Some(&b"REP"[..])
        );
        assert_eq!(ready_property(&data, "Identity").unwrap(), None);
        // A property whose value runs past the end.
        assert!(ready_property(&[1, b'a', 0, 0, 0, 9, b'x'], "a").is_err());
        // A name longer than the command.
        assert!(matches!(
            block_on(incoming(&[0x04, 1, 0xff], 1024)),
            Err(WireError::Command)
        ));
        // A command inside a message.
        assert!(matches!(
            block_on(incoming(&[0x01, 0, 0x04, 1, 0], 1024)),
            Err(WireError::CommandInMessage)
        ));
        assert_eq!(
            pong(&[0, 10, b'c']).unwrap(),
            [0x04, 6, 4, b'P', b'O', b'N', b'G', b'c']
        );
    }

    #[test]
    fn greetings_other_than_zmtp_3_null_are_refused() {
        let mut peer = greeting();
        assert!(check_greeting(&peer).is_ok());
        peer[10] = 2;
        assert!(matches!(check_greeting(&peer), Err(WireError::Greeting)));
        peer[10] = 3;
        peer[12..17].copy_from_slice(b"CURVE");
        assert!(matches!(check_greeting(&peer), Err(WireError::Mechanism)));
    }
}
