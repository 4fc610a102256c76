//! One client connection, served by a task of its own: the handshake, then requests
//! answered one at a time, as a REP socket answers them.
//!
//! A task per connection keeps peers apart: a peer that sends requests and never reads
//! the replies stalls only its own task, whose write gives up after the send timeout and
//! drops it, while the other tasks go on answering. Since a request is read only once the
//! previous reply is written, each peer has at most one reply outstanding: nothing queues
//! up for a peer that does not read.

use std::time::Duration;

use tokio::net::TcpStream;

use super::monitor::Groot2Monitor;
use super::zmtp::{self, Incoming, WireError, GREETING_LEN};

/// Which of the two sockets a connection came to.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Role {
    /// The request port: REQ clients (and DEALER or ROUTER ones, which speak the same).
    Requests,
    /// The publisher port: SUB clients, which are sent nothing, as no breakpoint is ever
    /// announced, and whose subscriptions are read and dropped.
    Publisher,
}

impl Role {
    /// The socket type this side announces.
    fn socket_type(self) -> &'static str {
        match self {
            Role::Requests => "REP",
            Role::Publisher => "PUB",
        }
    }

    /// Whether a peer of `socket_type` may talk to this side, as libzmq decides.
    fn accepts(self, socket_type: &[u8]) -> bool {
        let accepted: &[&[u8]] = match self {
            Role::Requests => &[b"REQ", b"DEALER", b"ROUTER"],
            Role::Publisher => &[b"SUB", b"XSUB"],
        };
        accepted.contains(&socket_type)
    }
}

/// The limits a connection is served under (see [`Groot2Options`](super::Groot2Options)).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    pub(crate) max_message_bytes: usize,
    pub(crate) send_timeout: Duration,
    pub(crate) handshake_timeout: Duration,
}

/// Serves one connection until the peer leaves or breaks a rule; the error says which rule.
pub(crate) async fn serve_peer(
    mut stream: TcpStream,
    role: Role,
    monitor: &Groot2Monitor,
    limits: Limits,
) -> Result<(), WireError> {
    // Replies are small and awaited one at a time: each should go out at once.
    stream.set_nodelay(true)?;
    match tokio::time::timeout(
        limits.handshake_timeout,
        handshake(&mut stream, role, limits),
    )
    .await
    {
        Ok(shaken) => shaken?,
        Err(_) => return Err(WireError::TimedOut),
    }
    loop {
        let incoming = match zmtp::read_incoming(&mut stream, limits.max_message_bytes).await {
            Err(WireError::Io(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(()),
            incoming => incoming?,
        };
        let reply = match (incoming, role) {
            (Incoming::Message(frames), Role::Requests) => reply_to(monitor, frames),
            (Incoming::Message(_), Role::Publisher) => None,
            (Incoming::Command { name, data }, _) => answer_command(&name, &data)?,
        };
        if let Some(reply) = reply {
            zmtp::send(&mut stream, &reply, limits.send_timeout).await?;
        }
    }
}

/// Greetings both ways, then READY both ways, checking that the peer's socket type fits.
async fn handshake(stream: &mut TcpStream, role: Role, limits: Limits) -> Result<(), WireError> {
    use tokio::io::AsyncReadExt;

    zmtp::send(stream, &zmtp::greeting(), limits.send_timeout).await?;
    let mut greeting = [0; GREETING_LEN];
    stream.read_exact(&mut greeting).await?;
    zmtp::check_greeting(&greeting)?;
    zmtp::send(
        stream,
        &zmtp::ready(role.socket_type()),
        limits.send_timeout,
    )
    .await?;
    match zmtp::read_incoming(stream, limits.max_message_bytes).await? {
        Incoming::Command { name, data } if name == b"READY" => {
            let socket_type = zmtp::ready_property(&data, "Socket-Type")?.unwrap_or_default();
            if role.accepts(socket_type) {
                Ok(())
            } else {
                Err(WireError::SocketType(
                    String::from_utf8_lossy(socket_type).into_owned(),
                ))
            }
        }
        _ => Err(WireError::Command),
    }
}

/// What a command after the handshake gets: a PING its PONG, an ERROR the end of the
/// connection, and the rest (subscriptions as ZMTP 3.1 sends them, a stray PONG) nothing.
fn answer_command(name: &[u8], data: &[u8]) -> Result<Option<Vec<u8>>, WireError> {
    match name {
        b"PING" => zmtp::pong(data).map(Some).ok_or(WireError::Command),
        b"ERROR" => Err(WireError::PeerError),
        _ => Ok(None),
    }
}

/// The reply to a request, as a REP socket sends it: the envelope, up to and with the empty
/// delimiter frame, then the answer. A message without a delimiter did not come from a REQ
/// socket, and gets no reply, as a REP socket would drop it.
fn reply_to(monitor: &Groot2Monitor, mut frames: Vec<Vec<u8>>) -> Option<Vec<u8>> {
    let delimiter = frames.iter().position(Vec::is_empty)?;
    let request = frames.split_off(delimiter + 1);
    frames.extend(monitor.answer(&request));
    Some(zmtp::message(&frames))
}
