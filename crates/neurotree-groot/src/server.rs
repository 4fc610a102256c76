//! The network side: a background thread with a small tokio runtime, a listener for
//! requests and one for the publisher on the next port, as BehaviorTree.CPP binds them.
//!
//! Each connection is served by a task of its own ([`peer`](super::peer)) speaking ZMTP 3
//! through this crate's [`zmtp`](super::zmtp), under the limits of [`Groot2Options`]: a peer
//! that claims too long a message, stalls the handshake, or does not read its replies is
//! dropped, and costs the others nothing. The monitor's state is read under its lock for
//! each answer and never waits for the network, so neither does the tree's tick.

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::mpsc;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::sync::{oneshot, Semaphore};

use super::monitor::Groot2Monitor;
use super::peer::{serve_peer, Limits, Role};

/// Why a monitor could not be served.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum GrootError {
    /// A socket could not be bound (the port is taken, or the address is not local).
    #[error("cannot bind the Groot2 {socket} socket to {address}: {reason}")]
    Bind {
        /// `request` or `publisher` (notifications).
        socket: &'static str,
        /// The endpoint asked for.
        address: String,
        /// What the system said.
        reason: String,
    },
    /// Port 65535 leaves no port for the publisher, which takes the next one.
    #[error("port {0} leaves no next port for the Groot2 publisher")]
    NoNextPort(u16),
    /// The server thread or its runtime could not start.
    #[error("cannot start the Groot2 server: {0}")]
    Start(#[from] std::io::Error),
}

neurotree_core::debug_shows_message!(enum GrootError {
    Bind { socket, address, reason },
    NoNextPort(source),
    Start(source),
});

/// Where a Groot2 server listens and how far it trusts its peers, for
/// [`Groot2Monitor::serve_with`].
///
/// The defaults keep the server to this machine and bound what any one peer can cost:
///
/// ```
/// use std::net::{IpAddr, Ipv4Addr};
/// use std::time::Duration;
/// use neurotree::groot::Groot2Options;
///
/// let options = Groot2Options::new()
///     .bind(IpAddr::V4(Ipv4Addr::UNSPECIFIED))
///     .send_timeout(Duration::from_secs(2));
/// assert_eq!(options.bind_address(), IpAddr::V4(Ipv4Addr::UNSPECIFIED));
/// assert_eq!(Groot2Options::default().bind_address(), IpAddr::V4(Ipv4Addr::LOCALHOST));
/// ```
#[derive(Clone, Debug)]
pub struct Groot2Options {
    bind: IpAddr,
    limits: Limits,
    max_peers: usize,
}

impl Default for Groot2Options {
    fn default() -> Self {
        Groot2Options {
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            limits: Limits {
                // Groot2's requests are a few bytes to a few kilobytes (hook JSON, blackboard
                // names); 4 MiB leaves room and still bounds each peer.
                max_message_bytes: 4 << 20,
                send_timeout: Duration::from_secs(5),
                handshake_timeout: Duration::from_secs(5),
            },
            max_peers: 64,
        }
    }
}

impl Groot2Options {
    /// The defaults: loopback only, 4 MiB per message, 5 s to send a reply or finish the
    /// handshake, 64 connections.
    pub fn new() -> Self {
        Self::default()
    }

    /// The address to listen on: `127.0.0.1` (the default) keeps the server to this
    /// machine; `0.0.0.0` opens it to every network the machine is on.
    pub fn bind(mut self, ip: IpAddr) -> Self {
        self.bind = ip;
        self
    }

    /// The address the server will listen on.
    pub fn bind_address(&self) -> IpAddr {
        self.bind
    }

    /// The most bytes a peer's message (or command) may take, its frames together, each
    /// counted with a small fixed cost besides its length. A frame header that claims more
    /// closes that connection before any of the frame is read or allocated.
    pub fn max_message_bytes(mut self, bytes: usize) -> Self {
        self.limits.max_message_bytes = bytes;
        self
    }

    /// How long a reply may take to be written: a peer that does not read its replies is
    /// dropped after that long, while the others go on being answered.
    pub fn send_timeout(mut self, timeout: Duration) -> Self {
        self.limits.send_timeout = timeout;
        self
    }

    /// How long a new connection may take to greet and say READY before it is dropped.
    pub fn handshake_timeout(mut self, timeout: Duration) -> Self {
        self.limits.handshake_timeout = timeout;
        self
    }

    /// How many connections, on both ports together, are served at once; connections past
    /// that are closed as soon as they are accepted.
    pub fn max_peers(mut self, peers: usize) -> Self {
        self.max_peers = peers;
        self
    }
}

/// A running Groot2 server, made by [`Groot2Monitor::serve`]; it stops when dropped.
#[derive(Debug)]
pub struct Groot2Server {
    address: SocketAddr,
    stop: Option<oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

/// Attempts at finding two free neighbouring ports when asked for any port.
const PORT_PAIR_ATTEMPTS: usize = 32;

/// How long to wait after a failed accept (out of file descriptors, say) before the next,
/// so that the failure does not spin the thread.
const ACCEPT_BACKOFF: Duration = Duration::from_millis(50);

impl Groot2Monitor {
    /// Serves this monitor on the loopback address with the default
    /// [`Groot2Options`]: requests on `port`, notifications on `port + 1`, as
    /// BehaviorTree.CPP's `Groot2Publisher(tree, port)` does (Groot2's default is 1667).
    /// Port 0 picks a free pair; [`Groot2Server::port`] tells which.
    pub fn serve(&self, port: u16) -> Result<Groot2Server, GrootError> {
        self.serve_with(port, &Groot2Options::default())
    }

    /// Serves this monitor on one address (`0.0.0.0` opens it to the network), with the
    /// default limits.
    pub fn serve_on(&self, ip: IpAddr, port: u16) -> Result<Groot2Server, GrootError> {
        self.serve_with(port, &Groot2Options::new().bind(ip))
    }

    /// Serves this monitor as `options` say.
    ///
    /// Returns once both listeners are bound. Requests are answered on a thread of the
    /// server's own, which reads the monitor's state under its lock and never waits for
    /// the tree, so the tree's ticks never wait for the network.
    pub fn serve_with(
        &self,
        port: u16,
        options: &Groot2Options,
    ) -> Result<Groot2Server, GrootError> {
        let (ready_tx, ready_rx) = mpsc::channel();
        let (stop_tx, stop_rx) = oneshot::channel();
        let monitor = self.clone();
        let options = options.clone();
        let thread = std::thread::Builder::new()
            .name("groot2-server".into())
            .spawn(move || {
                let runtime = match tokio::runtime::Builder::new_current_thread()
                    .enable_all()
                    .build()
                {
                    Ok(rt) => rt,
                    Err(e) => {
                        let _ = ready_tx.send(Err(GrootError::Start(e)));
                        return;
                    }
                };
                // Dropping the runtime when this returns drops every connection's task, and
                // with it the connection.
                runtime.block_on(async move {
                    match bind(options.bind, port).await {
                        Ok(listeners) => {
                            let _ = ready_tx
                                .send(listeners.requests.local_addr().map_err(GrootError::Start));
                            listeners.serve(monitor, &options, stop_rx).await;
                        }
                        Err(e) => {
                            let _ = ready_tx.send(Err(e));
                        }
                    }
                });
            })?;
        let ended = || {
            GrootError::Start(std::io::Error::other(
                "the server thread ended before binding",
            ))
        };
        let address = ready_rx.recv().map_err(|_| ended())??;
        Ok(Groot2Server {
            address,
            stop: Some(stop_tx),
            thread: Some(thread),
        })
    }
}

impl Groot2Server {
    /// The request port; notifications (PUB) are on the next one.
    pub fn port(&self) -> u16 {
        self.address.port()
    }

    /// The address requests are served on, as bound (`127.0.0.1` unless asked otherwise).
    pub fn local_addr(&self) -> SocketAddr {
        self.address
    }

    /// Stops serving and waits for the server thread to end.
    pub fn stop(mut self) {
        self.shut_down();
    }

    fn shut_down(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl Drop for Groot2Server {
    fn drop(&mut self) {
        self.shut_down();
    }
}

struct Listeners {
    requests: TcpListener,
    // Kept open for clients that subscribe, though breakpoints, which it would announce,
    // are not supported.
    publisher: TcpListener,
}

async fn bind(ip: IpAddr, port: u16) -> Result<Listeners, GrootError> {
    if port != 0 {
        let next = port.checked_add(1).ok_or(GrootError::NoNextPort(port))?;
        let requests = bind_one("request", ip, port).await?;
        let publisher = bind_one("publisher", ip, next).await?;
        return Ok(Listeners {
            requests,
            publisher,
        });
    }
    let mut last = GrootError::NoNextPort(u16::MAX);
    for _ in 0..PORT_PAIR_ATTEMPTS {
        let requests = bind_one("request", ip, 0).await?;
        let bound = requests.local_addr().map_err(GrootError::Start)?.port();
        let Some(next) = bound.checked_add(1) else {
            continue;
        };
        match bind_one("publisher", ip, next).await {
            Ok(publisher) => {
                return Ok(Listeners {
                    requests,
                    publisher,
                })
            }
            Err(e) => last = e,
        }
    }
    Err(last)
}

async fn bind_one(socket: &'static str, ip: IpAddr, port: u16) -> Result<TcpListener, GrootError> {
    TcpListener::bind((ip, port))
        .await
        .map_err(|e| GrootError::Bind {
            socket,
            address: endpoint(ip, port),
            reason: e.to_string(),
        })
}

/// The address as ZeroMQ writes it, for messages.
fn endpoint(ip: IpAddr, port: u16) -> String {
    format!("tcp://{}", SocketAddr::new(ip, port))
}

impl Listeners {
    /// Accepts connections on both ports until told to stop (or until the
    /// [`Groot2Server`] is gone).
    async fn serve(
        self,
        monitor: Groot2Monitor,
        options: &Groot2Options,
        stop: oneshot::Receiver<()>,
    ) {
        let peers = Arc::new(Semaphore::new(options.max_peers));
        let requests = accept(self.requests, Role::Requests, &monitor, options, &peers);
        let publisher = accept(self.publisher, Role::Publisher, &monitor, options, &peers);
        tokio::select! {
            _ = stop => {}
            _ = requests => {}
            _ = publisher => {}
        }
    }
}

/// Gives each connection to `listener` a task of its own while there is room for it.
async fn accept(
    listener: TcpListener,
    role: Role,
    monitor: &Groot2Monitor,
    options: &Groot2Options,
    peers: &Arc<Semaphore>,
) {
    loop {
        let stream = match listener.accept().await {
            Ok((stream, _)) => stream,
            Err(_) => {
                tokio::time::sleep(ACCEPT_BACKOFF).await;
                continue;
            }
        };
        // Past the limit the connection is dropped, which closes it.
        let Ok(permit) = peers.clone().try_acquire_owned() else {
            continue;
        };
        let monitor = monitor.clone();
        let limits = options.limits;
        tokio::spawn(async move {
            // Whatever rule the peer broke, the answer is the same: its connection closes
            // when the stream is dropped here.
            let _ = serve_peer(stream, role, &monitor, limits).await;
            drop(permit);
        });
    }
}
