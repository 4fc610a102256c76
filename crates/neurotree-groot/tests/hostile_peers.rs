//! The Groot2 server against peers that mean harm: each test feeds the hostile bytes over a
//! raw TCP connection (no ZeroMQ library on that side, so nothing is tidied up on the way)
//! and asserts a bounded outcome: that peer is dropped, the process lives on, and a
//! well-behaved client is still answered, even while the hostile peer holds the server's
//! writes to it. Every wait is bounded by a hang catch of minutes, never by a tight time.

use std::io::{ErrorKind, Read, Write};
use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpStream};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use neurotree::groot::{Groot2Monitor, Groot2Options, Groot2Server};
use neurotree::{Registry, XmlLoader};

/// A hang catch: far longer than anything below takes on a loaded machine; every wait is
/// bounded by it.
const TIMEOUT: Duration = Duration::from_secs(180);

/// A send timeout no test outlives: a peer stalled on it is never dropped during a test.
const NEVER: Duration = Duration::from_secs(3600);

const XML: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="seq">
      <Script name="init" code="count := count + 1"/>
      <Sleep name="wait" msec="100"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

fn monitor() -> Groot2Monitor {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "hostile.xml").unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    Groot2Monitor::new(&blueprint, &registry, "Main")
}

fn serve(monitor: &Groot2Monitor, options: Groot2Options) -> Groot2Server {
    monitor.serve_with(0, &options).unwrap()
}

/// The greeting of a ZeroMQ 3.0 peer with the NULL mechanism, as a client, then its READY
/// command naming `socket_type`.
fn handshake(socket_type: &str) -> Vec<u8> {
    let mut out = vec![0xff, 0, 0, 0, 0, 0, 0, 0, 0, 0x7f, 3, 0];
    let mut mechanism = b"NULL".to_vec();
    mechanism.resize(20, 0);
    out.extend_from_slice(&mechanism);
    out.push(0); // as-server
    out.resize(64, 0); // filler
    let mut ready = vec![5];
    ready.extend_from_slice(b"READY");
    ready.push(11);
    ready.extend_from_slice(b"Socket-Type");
    ready.extend_from_slice(&(socket_type.len() as u32).to_be_bytes());
    ready.extend_from_slice(socket_type.as_bytes());
    out.extend_from_slice(&[0x04, ready.len() as u8]);
    out.extend_from_slice(&ready);
    out
}

/// A raw connection that has shaken hands as `socket_type`.
fn raw_peer(port: u16, socket_type: &str) -> TcpStream {
    let mut stream = TcpStream::connect((Ipv4Addr::LOCALHOST, port)).unwrap();
    stream.set_read_timeout(Some(TIMEOUT)).unwrap();
    stream.set_write_timeout(Some(TIMEOUT)).unwrap();
    stream.write_all(&handshake(socket_type)).unwrap();
    let mut greeting = [0; 64];
    stream.read_exact(&mut greeting).unwrap();
    assert_eq!((greeting[0], greeting[9], greeting[10]), (0xff, 0x7f, 3));
    stream
}

/// Reads until the server closes the connection (end of stream, or a reset when it closed
/// with bytes of ours unread), and returns how many bytes came first. Panics if it stays
/// open for `within`.
fn closed_by_server(stream: &mut TcpStream, within: Duration) -> usize {
    let deadline = Instant::now() + within;
    let mut buf = vec![0; 64 * 1024];
    let mut total = 0;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "the server kept the connection open");
        stream.set_read_timeout(Some(left)).unwrap();
        match stream.read(&mut buf) {
            Ok(0) => return total,
            Ok(n) => total += n,
            Err(e)
                if matches!(
                    e.kind(),
                    ErrorKind::ConnectionReset | ErrorKind::ConnectionAborted
                ) =>
            {
                return total
            }
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                panic!("the server kept the connection open for {within:?}")
            }
            Err(e) => panic!("reading: {e}"),
        }
    }
}

use crate::client;

/// The shared client; a status request not answered within [`TIMEOUT`] fails the test.
struct Client(client::Client);

impl Client {
    fn connect(port: u16) -> Client {
        Client(client::Client::connect(port, TIMEOUT))
    }

    /// The status request's reply header.
    fn status(&mut self) -> Vec<u8> {
        let reply = self.0.request_within(&[&[2, b'S', 1, 0, 0, 0]], TIMEOUT);
        reply[0].clone()
    }
}

/// A raw peer that asks for the whole tree over and over and never reads the replies, so
/// that the server's writes to it stall; and the thread writing its requests without end.
struct Hog {
    peer: TcpStream,
    /// Says once when a write first found the socket full: the server no longer keeps up.
    full: mpsc::Receiver<()>,
    /// Says, with the number of requests written, when a write failed: the server dropped
    /// the peer, or the test shut it down.
    ended: mpsc::Receiver<usize>,
    flood: std::thread::JoinHandle<()>,
}

impl Hog {
    fn start(port: u16) -> Hog {
        let peer = raw_peer(port, "REQ");
        let mut writer = peer.try_clone().unwrap();
        let (full_tx, full) = mpsc::channel();
        let (ended_tx, ended) = mpsc::channel();
        let flood = std::thread::spawn(move || {
            let request = [0x01, 0, 0x00, 6, 2, b'T', 0, 0, 0, 0];
            writer.set_nonblocking(true).unwrap();
            let mut written = 0;
            loop {
                let mut left = &request[..];
                while !left.is_empty() {
                    match writer.write(left) {
                        Ok(n) => left = &left[n..],
                        Err(e) if e.kind() == ErrorKind::WouldBlock => {
                            // Shared with the test's end of the socket, which reads blocking.
                            writer.set_nonblocking(false).unwrap();
                            let _ = full_tx.send(());
                        }
                        Err(_) => {
                            let _ = ended_tx.send(written);
                            return;
                        }
                    }
                }
                written += 1;
            }
        });
        Hog {
            peer,
            full,
            ended,
            flood,
        }
    }
}

/// The header a status request with id 1 is answered with.
fn status_header(monitor: &Groot2Monitor) -> Vec<u8> {
    let mut header = vec![2, b'S', 1, 0, 0, 0];
    header.extend_from_slice(&monitor.tree_uuid());
    header
}

/// A frame header with the long flag and `len` as its 8-byte length.
fn long_frame_header(len: u64) -> Vec<u8> {
    let mut header = vec![0x02];
    header.extend_from_slice(&len.to_be_bytes());
    header
}

#[test]
fn a_frame_claiming_2_pow_62_bytes_closes_that_peer_and_nothing_else() {
    let monitor = monitor();
    let server = serve(&monitor, Groot2Options::new());
    // The request port, and the publisher's, whose subscribers' bytes are read too.
    for (port, socket_type) in [(server.port(), "REQ"), (server.port() + 1, "SUB")] {
        let mut peer = raw_peer(port, socket_type);
        peer.write_all(&long_frame_header(1 << 62)).unwrap();
        closed_by_server(&mut peer, TIMEOUT);
    }
    // The process is alive (this line runs) and the server still answers.
    let mut client = Client::connect(server.port());
    assert_eq!(client.status(), status_header(&monitor));
}

#[test]
fn a_frame_claiming_100_mb_is_refused_before_it_arrives() {
    let monitor = monitor();
    let server = serve(&monitor, Groot2Options::new());
    let mut peer = raw_peer(server.port(), "REQ");
    // The header alone: a server that waited for the 100 MB would keep the peer open.
    peer.write_all(&long_frame_header(100_000_000)).unwrap();
    closed_by_server(&mut peer, TIMEOUT);
    let mut client = Client::connect(server.port());
    assert_eq!(client.status(), status_header(&monitor));
}

#[test]
fn a_message_of_many_small_frames_is_bounded_as_a_whole() {
    let monitor = monitor();
    let limit = 64 * 1024;
    let server = serve(&monitor, Groot2Options::new().max_message_bytes(limit));
    let mut peer = raw_peer(server.port(), "REQ");
    // Frames of 255 bytes, each with more to come: within the limit one by one, not together.
    let mut frame = vec![0x01, 255];
    frame.resize(2 + 255, b'x');
    let mut refused = false;
    for _ in 0..2 * limit / 255 {
        if peer.write_all(&frame).is_err() {
            refused = true;
            break;
        }
    }
    if !refused {
        closed_by_server(&mut peer, TIMEOUT);
    }
    let mut client = Client::connect(server.port());
    assert_eq!(client.status(), status_header(&monitor));
}

/// A peer that never reads its replies holds the server's writes to it for as long as the
/// send timeout, which here no test outlives: a server that served its peers one after
/// the other would answer no one else from then on. Once the hog's socket is full, the
/// well-behaved client is answered fifty times over.
#[test]
fn a_peer_that_never_reads_its_replies_does_not_hold_up_the_others() {
    let monitor = monitor();
    let server = serve(&monitor, Groot2Options::new().send_timeout(NEVER));
    let port = server.port();
    let hog = Hog::start(port);
    hog.full
        .recv_timeout(TIMEOUT)
        .expect("the hog's socket never filled");
    let mut client = Client::connect(port);
    for _ in 0..50 {
        assert_eq!(client.status(), status_header(&monitor));
    }
    // Not dropped meanwhile: its writes go on until the test ends them.
    assert!(hog.ended.try_recv().is_err());
    hog.peer.shutdown(std::net::Shutdown::Both).unwrap();
    hog.ended.recv_timeout(TIMEOUT).unwrap();
    hog.flood.join().unwrap();
    assert_eq!(client.status(), status_header(&monitor));
}

/// A peer that never reads its replies is dropped at the send timeout rather than served:
/// its writes fail though it still asks, and what it could read is less than it asked for.
/// The server answers others afterwards.
#[test]
fn a_peer_that_never_reads_its_replies_is_dropped() {
    let monitor = monitor();
    let send_timeout = Duration::from_secs(4);
    let server = serve(&monitor, Groot2Options::new().send_timeout(send_timeout));
    let port = server.port();
    let mut hog = Hog::start(port);
    let written = hog
        .ended
        .recv_timeout(TIMEOUT)
        .expect("the hog was never dropped");
    hog.flood.join().unwrap();
    let tree_reply: usize = monitor
        .answer(&[[2, b'T', 0, 0, 0, 0]])
        .iter()
        .map(Vec::len)
        .sum();
    let read = closed_by_server(&mut hog.peer, TIMEOUT);
    assert!(
        read < written * tree_reply,
        "{read} bytes read of {written} replies"
    );
    let mut client = Client::connect(port);
    assert_eq!(client.status(), status_header(&monitor));
}

#[test]
fn a_peer_silent_after_connecting_is_dropped() {
    let monitor = monitor();
    let options = Groot2Options::new().handshake_timeout(Duration::from_millis(300));
    let server = serve(&monitor, options);
    let mut silent = TcpStream::connect((Ipv4Addr::LOCALHOST, server.port())).unwrap();
    closed_by_server(&mut silent, TIMEOUT);
}

#[test]
fn peers_past_the_limit_are_turned_away() {
    let monitor = monitor();
    let server = serve(&monitor, Groot2Options::new().max_peers(2));
    let _first = raw_peer(server.port(), "REQ");
    let _second = raw_peer(server.port(), "REQ");
    let mut third = TcpStream::connect((Ipv4Addr::LOCALHOST, server.port())).unwrap();
    assert_eq!(closed_by_server(&mut third, TIMEOUT), 0);
}

#[test]
fn a_peer_of_the_wrong_socket_type_is_dropped() {
    let monitor = monitor();
    let server = serve(&monitor, Groot2Options::new());
    // A PUB socket cannot talk to a REP one, nor a REQ to a PUB one.
    let mut publisher = raw_peer(server.port(), "PUB");
    closed_by_server(&mut publisher, TIMEOUT);
    let mut requester = raw_peer(server.port() + 1, "REQ");
    closed_by_server(&mut requester, TIMEOUT);
}

#[test]
fn serving_binds_the_loopback_address_by_default() {
    let monitor = monitor();
    let server = monitor.serve(0).unwrap();
    assert_eq!(
        server.local_addr(),
        SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), server.port())
    );
    assert_eq!(
        Groot2Options::default().bind_address(),
        IpAddr::V4(Ipv4Addr::LOCALHOST)
    );
    // Widening is asked for, never the default; no test binds beyond loopback.
    let wide = Groot2Options::new().bind(IpAddr::V4(Ipv4Addr::UNSPECIFIED));
    assert_eq!(wide.bind_address(), IpAddr::V4(Ipv4Addr::UNSPECIFIED));
}
