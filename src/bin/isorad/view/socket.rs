//! One page's WebSocket: the handshake's answer, then the published state
//! pushed as it changes. The page sends nothing the server needs; what it
//! does send is read (pings are answered, a close ends the socket) and
//! bounded by [`MAX_INCOMING`].

use std::io::{ErrorKind, Write};
use std::net::TcpStream;
use std::time::Duration;

use tungstenite::protocol::{Role, WebSocketConfig};
use tungstenite::{Message, WebSocket, handshake::derive_accept_key};

use super::broadcast::{Broadcast, Published, Seen};

/// The largest message or frame a page may send, bytes.
pub const MAX_INCOMING: usize = 4096;

/// How long the socket waits for the published state to change before it
/// reads the page again.
const POLL: Duration = Duration::from_millis(40);

/// How long a send may take before the page counts as gone.
const WRITE_TIMEOUT: Duration = Duration::from_secs(10);

/// Answers a WebSocket handshake whose `key` was checked, then pushes the
/// published state until the page leaves.
pub fn serve_socket(mut stream: TcpStream, key: &str, broadcast: &Broadcast) {
    let answer = format!(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Accept: {}\r\n\r\n",
        derive_accept_key(key.as_bytes())
    );
    if stream.write_all(answer.as_bytes()).is_err()
        || stream.set_read_timeout(Some(POLL)).is_err()
        || stream.set_write_timeout(Some(WRITE_TIMEOUT)).is_err()
    {
        return;
    }
    let config = WebSocketConfig::default()
        .max_message_size(Some(MAX_INCOMING))
        .max_frame_size(Some(MAX_INCOMING));
    let mut socket = WebSocket::from_raw_socket(stream, Role::Server, Some(config));
    broadcast.connect();
    let mut seen = Seen::default();
    while read_page(&mut socket) {
        let state = broadcast.wait_for_change(&seen, POLL);
        if send_changes(&mut socket, &state, &mut seen).is_err() {
            break;
        }
    }
    broadcast.disconnect();
}

/// Reads what the page sent, if anything; false once the socket is closed
/// or broken (a malformed or oversized frame among them).
fn read_page(socket: &mut WebSocket<TcpStream>) -> bool {
    loop {
        match socket.read() {
            Ok(Message::Close(_)) => {
                // The close reply is queued; send it, then end.
                let _ = socket.flush();
                return false;
            }
            Ok(_) => continue,
            Err(tungstenite::Error::Io(error))
                if matches!(error.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) =>
            {
                return true;
            }
            Err(_) => return false,
        }
    }
}

/// Sends the parts of `state` the page has not seen: hello, mesh, light,
/// status, in that order.
fn send_changes(
    socket: &mut WebSocket<TcpStream>,
    state: &Published,
    seen: &mut Seen,
) -> tungstenite::Result<()> {
    if let Some(hello) = state.hello.as_ref().filter(|_| !seen.hello) {
        socket.write(Message::text(hello.clone()))?;
        seen.hello = true;
    }
    for (part, sent) in [
        (&state.mesh, &mut seen.mesh),
        (&state.light, &mut seen.light),
    ] {
        if let Some(part) = part.as_ref().filter(|part| *sent != Some(part.serial)) {
            socket.write(Message::Binary(part.message.clone()))?;
            *sent = Some(part.serial);
        }
    }
    if seen.status != state.status.serial {
        socket.write(Message::text(state.status.message.clone()))?;
        seen.status = state.status.serial;
    }
    socket.flush()
}
