//! A Groot2-like client for the tests: one ZeroMQ REQ socket (from the `zeromq` crate, not
//! the server's own code), one request at a time.

use std::time::Duration;

use zeromq::{ReqSocket, Socket, SocketRecv, SocketSend, ZmqMessage};

/// A REQ socket connected to a monitor, on a runtime of its own.
pub struct Client {
    runtime: tokio::runtime::Runtime,
    socket: ReqSocket,
}

impl Client {
    /// Connects to `127.0.0.1:port`, within `timeout`.
    pub fn connect(port: u16, timeout: Duration) -> Client {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let socket = runtime.block_on(async {
            let mut socket = ReqSocket::new();
            tokio::time::timeout(timeout, socket.connect(&format!("tcp://127.0.0.1:{port}")))
                .await
                .expect("connecting timed out")
                .unwrap();
            socket
        });
        Client { runtime, socket }
    }

    /// Sends a request of `frames` and returns the reply's frames; panics if no reply comes
    /// within `timeout`.
    pub fn request_within(&mut self, frames: &[&[u8]], timeout: Duration) -> Vec<Vec<u8>> {
        let mut message = ZmqMessage::from(frames[0].to_vec());
        for frame in &frames[1..] {
            message.push_back(frame.to_vec().into());
        }
        let socket = &mut self.socket;
        self.runtime.block_on(async {
            tokio::time::timeout(timeout, async {
                socket.send(message).await.unwrap();
                socket.recv().await.unwrap()
            })
            .await
            .unwrap_or_else(|_| panic!("no reply within {timeout:?}"))
            .into_vec()
            .into_iter()
            .map(|b| b.to_vec())
            .collect()
        })
    }
}
