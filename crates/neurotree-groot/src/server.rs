//! The network side: a background thread with a small tokio runtime, a ZeroMQ socket for
//! requests and a PUB socket on the next port, as BehaviorTree.CPP binds them.
//!
//! Requests arrive on a ROUTER socket that answers as a REP socket would (the reply goes
//! back with the request's envelope), because the `zeromq` crate's ROUTER lets a peer whose
//! connection fails go, where its REP stops at a `todo!()`. A panic in the crate's decoder
//! on bytes that are not ZeroMQ is caught, and costs only that peer its connection.

use std::net::{IpAddr, Ipv4Addr};
use std::panic::AssertUnwindSafe;
use std::sync::mpsc;
use std::thread::JoinHandle;

use futures_util::FutureExt;
use tokio::sync::oneshot;
use zeromq::{Endpoint, PubSocket, RouterSocket, Socket, SocketRecv, SocketSend, ZmqMessage};

use super::monitor::Groot2Monitor;

/// Why a monitor could not be served.
#[derive(Debug, thiserror::Error)]
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

/// A running Groot2 server, made by [`Groot2Monitor::serve`]; it stops when dropped.
#[derive(Debug)]
pub struct Groot2Server {
    port: u16,
    stop: Option<oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

/// Attempts at finding two free neighbouring ports when asked for any port.
const PORT_PAIR_ATTEMPTS: usize = 32;

impl Groot2Monitor {
    /// Serves this monitor on all IPv4 interfaces: requests on `port`, notifications on
    /// `port + 1`, as BehaviorTree.CPP's `Groot2Publisher(tree, port)` does (Groot2's
    /// default is 1667). Port 0 picks a free pair; [`Groot2Server::port`] tells which.
    pub fn serve(&self, port: u16) -> Result<Groot2Server, GrootError> {
        self.serve_on(IpAddr::V4(Ipv4Addr::UNSPECIFIED), port)
    }

    /// Serves this monitor on one address (`127.0.0.1` keeps it to this machine).
    ///
    /// Returns once both sockets are bound. Requests are answered on a thread of the
    /// server's own, which reads the monitor's state under its lock and never waits for
    /// the tree, so the tree's ticks never wait for the network.
    pub fn serve_on(&self, ip: IpAddr, port: u16) -> Result<Groot2Server, GrootError> {
        let (ready_tx, ready_rx) = mpsc::channel();
        let (stop_tx, stop_rx) = oneshot::channel();
        let monitor = self.clone();
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
                runtime.block_on(async move {
                    match bind(ip, port).await {
                        Ok(sockets) => {
                            let _ = ready_tx.send(Ok(sockets.port));
                            sockets.serve(&monitor, stop_rx).await;
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
        let port = ready_rx.recv().map_err(|_| ended())??;
        Ok(Groot2Server {
            port,
            stop: Some(stop_tx),
            thread: Some(thread),
        })
    }
}

impl Groot2Server {
    /// The request port; notifications (PUB) are on the next one.
    pub fn port(&self) -> u16 {
        self.port
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

struct Sockets {
    requests: RouterSocket,
    // Kept open for clients that subscribe, though breakpoints, which it would announce,
    // are not supported.
    publisher: PubSocket,
    port: u16,
}

async fn bind(ip: IpAddr, port: u16) -> Result<Sockets, GrootError> {
    if port != 0 {
        let next = port.checked_add(1).ok_or(GrootError::NoNextPort(port))?;
        let (requests, port) = bind_requests(ip, port).await?;
        let publisher = bind_pub(ip, next).await?;
        return Ok(Sockets {
            requests,
            publisher,
            port,
        });
    }
    let mut last = GrootError::NoNextPort(u16::MAX);
    for _ in 0..PORT_PAIR_ATTEMPTS {
        let (requests, port) = bind_requests(ip, 0).await?;
        let Some(next) = port.checked_add(1) else {
            continue;
        };
        match bind_pub(ip, next).await {
            Ok(publisher) => {
                return Ok(Sockets {
                    requests,
                    publisher,
                    port,
                })
            }
            Err(e) => {
                let _ = requests.close().await;
                last = e;
            }
        }
    }
    Err(last)
}

fn endpoint(ip: IpAddr, port: u16) -> String {
    match ip {
        IpAddr::V4(ip) => format!("tcp://{ip}:{port}"),
        IpAddr::V6(ip) => format!("tcp://[{ip}]:{port}"),
    }
}

async fn bind_requests(ip: IpAddr, port: u16) -> Result<(RouterSocket, u16), GrootError> {
    let address = endpoint(ip, port);
    let mut requests = RouterSocket::new();
    match requests.bind(&address).await {
        Ok(Endpoint::Tcp(_, bound)) => Ok((requests, bound)),
        Ok(_) => Ok((requests, port)),
        Err(e) => Err(GrootError::Bind {
            socket: "request",
            address,
            reason: e.to_string(),
        }),
    }
}

async fn bind_pub(ip: IpAddr, port: u16) -> Result<PubSocket, GrootError> {
    let address = endpoint(ip, port);
    let mut publisher = PubSocket::new();
    match publisher.bind(&address).await {
        Ok(_) => Ok(publisher),
        Err(e) => Err(GrootError::Bind {
            socket: "publisher",
            address,
            reason: e.to_string(),
        }),
    }
}

impl Sockets {
    /// Answers requests until told to stop (or until the [`Groot2Server`] is gone).
    async fn serve(mut self, monitor: &Groot2Monitor, mut stop: oneshot::Receiver<()>) {
        loop {
            let received = tokio::select! {
                _ = &mut stop => break,
                received = AssertUnwindSafe(self.requests.recv()).catch_unwind() => received,
            };
            // A panic is the decoder's, on a peer's bad bytes: that peer's stream was taken
            // out of the queue, the others are still served.
            let Ok(Ok(message)) = received else { continue };
            let Some(reply) = reply_to(monitor, message) else {
                continue;
            };
            tokio::select! {
                _ = &mut stop => break,
                // A client gone before its reply needs none.
                _ = self.requests.send(reply) => {}
            }
        }
        let _ = self.requests.close().await;
        let _ = self.publisher.close().await;
    }
}

/// The reply to a message from the ROUTER socket: its routing id and the REQ envelope, up to
/// the empty delimiter frame, then the answer. A message without a delimiter did not come
/// from a REQ socket, and gets no reply, as a REP socket would drop it.
fn reply_to(monitor: &Groot2Monitor, message: ZmqMessage) -> Option<ZmqMessage> {
    let mut frames = message.into_vec();
    let delimiter = 1 + frames.iter().skip(1).position(|f| f.is_empty())?;
    let request = frames.split_off(delimiter + 1);
    let mut reply = ZmqMessage::try_from(frames).ok()?;
    for frame in monitor.answer(&request) {
        reply.push_back(frame.into());
    }
    Some(reply)
}
