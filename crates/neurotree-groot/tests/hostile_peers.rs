//! The Groot2 server against peers that mean harm: each test feeds the hostile bytes over a
//! raw TCP connection (no ZeroMQ library on that side, so nothing is tidied up on the way)
//! and asserts a bounded outcome: that peer is dropped within a bounded time, the process
//! lives on, and a well-behaved client is still answered.

use std::io::{ErrorKind, Read, Write};
use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpStream};
use std::sync::Arc;
use std::time::{Duration, Instant};

use neurotree::groot::{Groot2Monitor, Groot2Options, Groot2Server};
use neurotree::{Registry, XmlLoader};

/// Long enough for a loaded machine; every wait below is bounded by it.
const TIMEOUT: Duration = Duration::from_secs(20);

/// How soon a well-behaved client must be answered while a hostile peer is connected.
const PROMPT: Duration = Duration::from_secs(2);

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

/// The shared client; each status request must be answered within [`PROMPT`].
struct Client(client::Client);

impl Client {
    fn connect(port: u16) -> Client {
        Client(client::Client::connect(port, TIMEOUT))
    }

    /// The status request's reply header, answered within [`PROMPT`].
    fn status(&mut self) -> Vec<u8> {
        let started = Instant::now();
        let reply = self.0.request_within(&[&[2, b'S', 1, 0, 0, 0]], PROMPT);
        assert!(started.elapsed() <= PROMPT);
        reply[0].clone()
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

#[test]
fn a_peer_that_never_reads_its_replies_is_dropped_while_others_are_answered() {
    let monitor = monitor();
    let send_timeout = Duration::from_secs(4);
    let server = serve(&monitor, Groot2Options::new().send_timeout(send_timeout));
    let port = server.port();

    // Thousands of requests for the whole tree, whose replies are never read: far more than
    // the socket buffers hold, so that the server's writes to this peer stall.
    let tree_reply: usize = monitor
        .answer(&[[2, b'T', 0, 0, 0, 0]])
        .iter()
        .map(Vec::len)
        .sum();
    let requests = (64 << 20) / tree_reply + 1;
    let mut hog = raw_peer(port, "REQ");
    let mut writer = hog.try_clone().unwrap();
    let flood = std::thread::spawn(move || {
        let request = [0x01, 0, 0x00, 6, 2, b'T', 0, 0, 0, 0];
        for _ in 0..requests {
            // The server stops reading this peer once its replies stall, and then drops it.
            if writer.write_all(&request).is_err() {
                break;
            }
        }
    });

    // Meanwhile, for longer than the send timeout, another client is answered promptly.
    let mut client = Client::connect(port);
    let started = Instant::now();
    for _ in 0..50 {
        assert_eq!(client.status(), status_header(&monitor));
        if started.elapsed() > send_timeout + Duration::from_secs(1) {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }

    // The hog was dropped rather than served: what it could read is less than it asked for.
    let read = closed_by_server(&mut hog, TIMEOUT + send_timeout);
    assert!(read < requests * tree_reply, "{read} bytes read");
    flood.join().unwrap();
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
