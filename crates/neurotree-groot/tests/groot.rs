//! The Groot2 monitor over the network: a client speaking the protocol on a ZeroMQ REQ
//! socket, as Groot2 does, against a monitor attached to a tree ticked on a manual clock.
//! Every reply is checked byte for byte.

use std::net::{IpAddr, Ipv4Addr};
use std::sync::Arc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use neurotree::groot::protocol::Transition;
use neurotree::groot::{Groot2Monitor, Groot2Server};
use neurotree::xml::{write_xml, SaveOptions};
use neurotree::NodeStatus::{Idle, Running, Success};
use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};

use crate::counting_alloc;
use counting_alloc::allocations;

/// Long enough for a loaded machine; a reply that never comes fails the test instead of
/// hanging it.
const TIMEOUT: Duration = Duration::from_secs(20);

const XML: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="seq">
      <Script name="init" code="count := count + 1"/>
      <SubTree ID="Sub" name="sub" value="{count}"/>
      <Sleep name="wait" msec="100"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Sub">
    <Script name="double" code="twice := value * 2"/>
  </BehaviorTree>
</root>"#;

struct Fixture {
    registry: Registry<()>,
    tree: Tree<()>,
    clock: ManualClock,
    monitor: Groot2Monitor,
    server: Groot2Server,
}

fn fixture() -> Fixture {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "monitored.xml").unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    let monitor = Groot2Monitor::new(&blueprint, &registry, "Main");
    let server = monitor
        .serve_on(IpAddr::V4(Ipv4Addr::LOCALHOST), 0)
        .unwrap();
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint, clock.clone());
    tree.blackboard_mut().set("count", 0_i64).unwrap();
    tree.set_observer(monitor.clone());
    monitor.publish_blackboard(&tree);
    Fixture {
        registry,
        tree,
        clock,
        monitor,
        server,
    }
}

use crate::client;

/// The shared client, with this file's timeout.
struct Client(client::Client);

impl Client {
    fn connect(port: u16) -> Client {
        Client(client::Client::connect(port, TIMEOUT))
    }

    fn request(&mut self, frames: &[&[u8]]) -> Vec<Vec<u8>> {
        self.0.request_within(frames, TIMEOUT)
    }
}

/// The reply header expected for a request header.
fn header(fx: &Fixture, request: [u8; 6]) -> Vec<u8> {
    let mut h = request.to_vec();
    h[0] = 2;
    h.extend_from_slice(&fx.monitor.tree_uuid());
    h
}

fn tick(fx: &mut Fixture) -> Result<Status, neurotree::TickError> {
    let status = fx.tree.tick_once(&mut ());
    fx.monitor.publish_blackboard(&fx.tree);
    status
}

// Node uids (ids plus one, in pre-order): seq 1, init 2, sub 3, double 4, wait 5.

#[test]
fn full_tree_is_the_saved_xml_with_uids() {
    let fx = fixture();
    let mut client = Client::connect(fx.server.port());
    let request = [2, b'T', 0x78, 0x56, 0x34, 0x12];
    let reply = client.request(&[&request]);
    assert_eq!(reply.len(), 2);
    assert_eq!(reply[0], header(&fx, request));
    assert_eq!(reply[0][2..6], 0x1234_5678_u32.to_le_bytes());
    let expected = write_xml(
        fx.tree.blueprint(),
        &fx.registry,
        &SaveOptions {
            tree_id: "Main".into(),
            uids: true,
            models: true,
            builtin_models: true,
        },
    );
    assert_eq!(String::from_utf8(reply[1].clone()).unwrap(), expected);
    for element in [
        r#"<Sequence name="seq" _uid="1">"#,
        r#"<Script name="init" _uid="2" code="count := count + 1"/>"#,
        r#"<SubTree ID="Sub" name="sub" _fullpath="seq/sub" value="{count}" _uid="3"/>"#,
        r#"<Script name="double" _uid="4" code="twice := value * 2"/>"#,
        r#"<Sleep name="wait" _uid="5" msec="100"/>"#,
        r#"<Action ID="Sleep">"#,
    ] {
        assert!(
            expected.contains(element),
            "{element} missing from\n{expected}"
        );
    }
}

#[test]
fn statuses_follow_the_ticks() {
    let mut fx = fixture();
    let mut client = Client::connect(fx.server.port());
    let status = [2, b'S', 9, 0, 0, 0];

    let reply = client.request(&[&status]);
    assert_eq!(reply[0], header(&fx, status));
    assert_eq!(reply[1], [1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0, 5, 0, 0]);

    // The sleep runs; the subtree finished and reset its root (idle after success: 12).
    assert_eq!(tick(&mut fx), Ok(Status::Running));
    let reply = client.request(&[&status]);
    assert_eq!(reply[1], [1, 0, 1, 2, 0, 2, 3, 0, 2, 4, 0, 12, 5, 0, 1]);

    // The sequence succeeded, and the root reset every node.
    fx.clock.advance(Duration::from_millis(100));
    assert_eq!(tick(&mut fx), Ok(Status::Success));
    let reply = client.request(&[&status]);
    assert_eq!(reply[1], [1, 0, 12, 2, 0, 12, 3, 0, 12, 4, 0, 12, 5, 0, 12]);
}

/// MessagePack of a map with one-byte-integer values: what `B` answers here.
fn msgpack(blackboards: &[(&str, &[(&str, u8)])]) -> Vec<u8> {
    fn text(out: &mut Vec<u8>, s: &str) {
        out.push(0xa0 | s.len() as u8);
        out.extend_from_slice(s.as_bytes());
    }
    let mut out = vec![0x80 | blackboards.len() as u8];
    for (name, entries) in blackboards {
        text(&mut out, name);
        out.push(0x80 | entries.len() as u8);
        for (key, value) in *entries {
            text(&mut out, key);
            out.push(*value);
        }
    }
    out
}

#[test]
fn blackboards_by_name() {
    let mut fx = fixture();
    let mut client = Client::connect(fx.server.port());
    let request = [2, b'B', 3, 0, 0, 0];

    // Before the first tick: the seeded entry, and an empty subtree scope.
    let reply = client.request(&[&request, b"Main;seq/sub"]);
    assert_eq!(reply[0], header(&fx, request));
    assert_eq!(
        reply[1],
        msgpack(&[("Main", &[("count", 0)]), ("seq/sub", &[])])
    );

    assert_eq!(tick(&mut fx), Ok(Status::Running));
    let both = msgpack(&[("Main", &[("count", 1)]), ("seq/sub", &[("twice", 2)])]);
    assert_eq!(client.request(&[&request, b"Main;seq/sub"])[1], both);
    // No names: every blackboard (BehaviorTree.CPP would send none).
    assert_eq!(client.request(&[&request, b""])[1], both);
    assert_eq!(
        client.request(&[&request, b"seq/sub"])[1],
        msgpack(&[("seq/sub", &[("twice", 2)])])
    );
    // Unknown names are left out.
    assert_eq!(
        client.request(&[&request, b"Main;nope"])[1],
        msgpack(&[("Main", &[("count", 1)])])
    );
    assert_eq!(client.request(&[&request, b"nope"])[1], [0x80]);

    // The snapshot is the latest published one, not the live blackboard.
    fx.tree.blackboard_mut().set("count", 7_i64).unwrap();
    assert_eq!(
        client.request(&[&request, b"Main"])[1],
        msgpack(&[("Main", &[("count", 1)])])
    );
}

fn transitions(client: &mut Client) -> Vec<Transition> {
    let reply = client.request(&[&[2, b't', 0, 0, 0, 0]]);
    assert_eq!(reply.len(), 2);
    Transition::parse_all(&reply[1]).unwrap()
}

fn at(micros: u64, uid: u16, status: neurotree::NodeStatus) -> Transition {
    Transition {
        micros,
        uid,
        status,
    }
}

#[test]
fn recording_returns_the_transitions_since_the_last_request() {
    let mut fx = fixture();
    let mut client = Client::connect(fx.server.port());

    // Not recording: the first tick leaves nothing to fetch.
    assert_eq!(tick(&mut fx), Ok(Status::Running));
    assert_eq!(transitions(&mut client), []);

    let start = [2, b'r', 5, 0, 0, 0];
    let before = micros_since_epoch();
    let reply = client.request(&[&start, b"start"]);
    let after = micros_since_epoch();
    assert_eq!(reply[0], header(&fx, start));
    let wall: u64 = std::str::from_utf8(&reply[1]).unwrap().parse().unwrap();
    assert!(
        before <= wall && wall <= after,
        "{before} <= {wall} <= {after}"
    );

    // Stamped from the tree time of the first tick's end (0), on the tree's clock.
    fx.clock.advance(Duration::from_millis(100));
    assert_eq!(tick(&mut fx), Ok(Status::Success));
    assert_eq!(
        transitions(&mut client),
        [
            at(100_000, 5, Success),
            at(100_000, 2, Idle),
            at(100_000, 3, Idle),
            at(100_000, 5, Idle),
            at(100_000, 1, Success),
            at(100_000, 1, Idle),
        ]
    );
    assert_eq!(transitions(&mut client), []);

    // Starting again moves the origin to the latest tree time seen (100 ms).
    client.request(&[&start, b"start"]);
    fx.clock.advance(Duration::from_millis(150));
    assert_eq!(tick(&mut fx), Ok(Status::Running));
    assert_eq!(
        transitions(&mut client),
        [
            at(150_000, 1, Running),
            at(150_000, 2, Success),
            at(150_000, 3, Running),
            at(150_000, 4, Success),
            at(150_000, 4, Idle),
            at(150_000, 3, Success),
            at(150_000, 5, Running),
        ]
    );

    let stop = [2, b'r', 6, 0, 0, 0];
    assert_eq!(client.request(&[&stop, b"stop"]), [header(&fx, stop)]);
    fx.clock.advance(Duration::from_millis(100));
    assert_eq!(tick(&mut fx), Ok(Status::Success));
    assert_eq!(transitions(&mut client), []);
}

fn micros_since_epoch() -> u64 {
    let d = SystemTime::now().duration_since(UNIX_EPOCH).unwrap();
    u64::try_from(d.as_micros()).unwrap()
}

fn error(message: &str) -> Vec<Vec<u8>> {
    vec![b"error".to_vec(), message.as_bytes().to_vec()]
}

#[test]
fn unsupported_and_malformed_requests_get_error_replies() {
    let fx = fixture();
    let mut client = Client::connect(fx.server.port());
    assert_eq!(
        client.request(&[&[2, b'S', 1]]),
        error("wrong request header: 3 bytes instead of 6")
    );
    assert_eq!(
        client.request(&[&[2, b'?', 1, 0, 0, 0]]),
        error("Request not recognized")
    );
    for hook in [b'I', b'R', b'U', b'N'] {
        assert_eq!(
            client.request(&[&[2, hook, 1, 0, 0, 0], b"{}"]),
            error("breakpoints and hooks are not supported by NeuroTree")
        );
    }
    assert_eq!(
        client.request(&[&[2, b'B', 1, 0, 0, 0]]),
        error("must be 2 parts message")
    );
    assert_eq!(
        client.request(&[&[2, b'r', 1, 0, 0, 0]]),
        error("must be 2 parts message")
    );
    assert_eq!(
        client.request(&[&[2, b'r', 1, 0, 0, 0], b"pause"]),
        error("recording command must be `start` or `stop`")
    );

    // With no hooks in place, the requests that list, remove or disable them succeed.
    let dump = [2, b'D', 1, 0, 0, 0];
    assert_eq!(
        client.request(&[&dump]),
        [header(&fx, dump), b"[]".to_vec()]
    );
    for kind in [b'A', b'X'] {
        let request = [2, kind, 2, 0, 0, 0];
        assert_eq!(client.request(&[&request]), [header(&fx, request)]);
    }

    // And the server still answers.
    let status = [2, b'S', 1, 0, 0, 0];
    assert_eq!(client.request(&[&status])[0], header(&fx, status));
}

#[test]
fn clients_come_and_go() {
    let fx = fixture();
    let status = [2, b'S', 1, 0, 0, 0];
    let mut first = Client::connect(fx.server.port());
    assert_eq!(first.request(&[&status])[0], header(&fx, status));
    drop(first);
    let mut second = Client::connect(fx.server.port());
    let mut third = Client::connect(fx.server.port());
    assert_eq!(second.request(&[&status])[0], header(&fx, status));
    assert_eq!(third.request(&[&status])[0], header(&fx, status));
}

#[test]
fn port_zero_binds_a_free_pair_and_dropping_frees_it() {
    let fx = fixture();
    let port = fx.server.port();
    assert_ne!(port, 0);
    let localhost = Ipv4Addr::LOCALHOST;
    // Both the request port and the publisher's, the next one, are taken.
    for p in [port, port + 1] {
        let err = std::net::TcpListener::bind((localhost, p)).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::AddrInUse, "port {p}");
    }
    drop(fx);
    for p in [port, port + 1] {
        std::net::TcpListener::bind((localhost, p)).unwrap();
    }
}

#[test]
fn a_taken_port_is_an_error() {
    let fx = fixture();
    let taken = fx.server.port();
    let err = fx
        .monitor
        .serve_on(IpAddr::V4(Ipv4Addr::LOCALHOST), taken)
        .unwrap_err();
    assert!(
        err.to_string().starts_with(&format!(
            "cannot bind the Groot2 request socket to tcp://127.0.0.1:{taken}: "
        )),
        "{err}"
    );
}

#[test]
fn observing_allocates_nothing_even_while_recording() {
    let mut fx = fixture();
    fx.monitor.answer(&[&[2, b'r', 1, 0, 0, 0][..], b"start"]);
    assert_eq!(fx.tree.tick_once(&mut ()), Ok(Status::Running));
    let n = allocations(|| {
        // 13 transitions per two ticks: well past the 1,000 kept, so the oldest are dropped.
        for _ in 0..200 {
            fx.clock.advance(Duration::from_millis(100));
            fx.tree.tick_once(&mut ()).unwrap();
        }
    });
    assert_eq!(n, 0);
    let reply = fx.monitor.answer(&[[2, b't', 1, 0, 0, 0]]);
    let kept = Transition::parse_all(&reply[1]).unwrap();
    assert_eq!(kept.len(), 1000);
    assert_eq!(kept.last(), Some(&at(20_000_000, 5, Running)));
}

#[test]
fn the_model_names_every_type_of_the_tree() {
    // Mocks of unknown nodes, which the registry does not know either.
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Nav">
                <Sequence><ComputePath/><IsNear/><ComputePath name="again"/></Sequence>
              </BehaviorTree></root>"#,
            "nav.xml",
        )
        .unwrap();
    let monitor = Groot2Monitor::new(&loader.build_main().unwrap(), &registry, "Nav");
    assert!(
        monitor.tree_xml().ends_with(
            "    <Action ID=\"ComputePath\"/>\n    <Action ID=\"IsNear\"/>\n  </TreeNodesModel>\n</root>\n"
        ),
        "{}",
        monitor.tree_xml()
    );

    // Leaves made from closures, written as `<Condition ID="their name"/>`.
    let blueprint = neurotree::Blueprint::<()>::builder()
        .sequence("main", |s| {
            s.condition("battery_ok", |_: &()| true)
                .action("beep", |_: &mut ()| Status::Success)
        })
        .build()
        .unwrap();
    let monitor = Groot2Monitor::new(&blueprint, &registry, "Main");
    let xml = monitor.tree_xml();
    assert!(
        xml.contains(r#"<Condition ID="battery_ok" _uid="2"/>"#),
        "{xml}"
    );
    assert!(
        xml.ends_with(
            "    <Condition ID=\"battery_ok\"/>\n    <Action ID=\"beep\"/>\n  </TreeNodesModel>\n</root>\n"
        ),
        "{xml}"
    );
}

/// The start of a ZeroMQ 3.0 connection from a REQ socket: greeting (NULL mechanism, as a
/// client) and the READY command.
fn zmtp_handshake() -> Vec<u8> {
    let mut out = vec![0xff, 0, 0, 0, 0, 0, 0, 0, 1, 0x7f, 3, 0];
    let mut mechanism = b"NULL".to_vec();
    mechanism.resize(20, 0);
    out.extend_from_slice(&mechanism);
    out.resize(64, 0);
    let mut ready = vec![5];
    ready.extend_from_slice(b"READY");
    ready.push(11);
    ready.extend_from_slice(b"Socket-Type");
    ready.extend_from_slice(&3_u32.to_be_bytes());
    ready.extend_from_slice(b"REQ");
    out.extend_from_slice(&[0x04, ready.len() as u8]);
    out.extend_from_slice(&ready);
    out
}

#[test]
fn bad_bytes_and_broken_peers_do_not_stop_the_server() {
    use std::io::{Read, Write};
    use std::net::TcpStream;

    let fx = fixture();
    let port = fx.server.port();
    let status = [2, b'S', 1, 0, 0, 0];

    // Not ZeroMQ at all.
    let mut http = TcpStream::connect((Ipv4Addr::LOCALHOST, port)).unwrap();
    http.write_all(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
        .unwrap();

    // A peer that shakes hands, then sends a command frame whose name runs past its end,
    // which the decoder must check rather than trust.
    let mut broken = TcpStream::connect((Ipv4Addr::LOCALHOST, port)).unwrap();
    broken.set_read_timeout(Some(TIMEOUT)).unwrap();
    broken.write_all(&zmtp_handshake()).unwrap();
    let mut greeting = [0; 64];
    broken.read_exact(&mut greeting).unwrap();
    assert_eq!(greeting[0], 0xff);
    broken.write_all(&[0x04, 1, 0xff]).unwrap();

    // A request sent without the REQ envelope, then a peer gone in the middle of a request.
    let mut cut = TcpStream::connect((Ipv4Addr::LOCALHOST, port)).unwrap();
    cut.write_all(&zmtp_handshake()).unwrap();
    cut.write_all(&[0x00, 6, 2, b'S', 1, 0, 0, 0]).unwrap();
    cut.write_all(&[0x01, 0, 0x00, 6]).unwrap();
    drop(cut);

    let mut client = Client::connect(port);
    assert_eq!(client.request(&[&status])[0], header(&fx, status));
    drop((http, broken));
    let mut again = Client::connect(port);
    assert_eq!(again.request(&[&status])[0], header(&fx, status));
}
