//! The viewer's server: a thread per connection (at most
//! [`MAX_CONNECTIONS`], the rest answered 503), one request each, routed
//! to the page's embedded files, the status, probes, the glTF, the solve's
//! controls and the WebSocket.
//!
//! **Safety.** Only the paths of [`ROUTES`] and the embedded files answer;
//! no part of a request reaches the file system. Heads are bounded
//! (`http.rs`), bodies refused, reads and writes time out, and a server
//! bound to loopback answers only requests whose `Host` names loopback (a
//! web page elsewhere cannot reach it by DNS rebinding) and WebSockets
//! only from its own pages' `Origin`.

use std::net::{IpAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

use glam::DVec3;
use isorad::scene::ProbePoint;

use super::assets::asset;
use super::broadcast::Broadcast;
use super::http::{Head, HeadError, Response, read_head};
use super::socket::serve_socket;
use super::solve::{Control, Request, SolveHandle};

/// The most connections served at once.
pub const MAX_CONNECTIONS: usize = 64;

/// The most pages watching over a WebSocket at once.
pub const MAX_SOCKETS: usize = 16;

/// How long a peer may take to send its request, or to take our answer.
const IO_TIMEOUT: Duration = Duration::from_secs(10);

/// How long a probe or an export may wait for the solve thread (a probe
/// waits for the shot under way; an export of a large mesh takes seconds).
const REPLY_TIMEOUT: Duration = Duration::from_secs(300);

/// The paths besides the embedded files.
pub const ROUTES: [&str; 7] = [
    "/ws",
    "/state",
    "/probe",
    "/solution.glb",
    "/control/pause",
    "/control/resume",
    "/control/stop",
];

/// What every connection's thread shares.
pub struct Context {
    pub broadcast: Arc<Broadcast>,
    pub solve: SolveHandle,
    /// Whether the server listens on loopback only.
    pub loopback: bool,
    /// Connections being served.
    pub connections: AtomicUsize,
}

/// Serves `listener` for as long as the process runs.
pub fn serve(listener: &TcpListener, context: &Arc<Context>) {
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else { continue };
        if context.connections.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            context.connections.fetch_sub(1, Ordering::SeqCst);
            let _ = stream.set_write_timeout(Some(IO_TIMEOUT));
            Response::error(503, "too many connections").send(&mut stream, false);
            continue;
        }
        let context = Arc::clone(context);
        std::thread::spawn(move || {
            handle(stream, &context);
            context.connections.fetch_sub(1, Ordering::SeqCst);
        });
    }
}

/// Reads one request from `stream` and answers it.
fn handle(mut stream: TcpStream, context: &Context) {
    if stream.set_read_timeout(Some(IO_TIMEOUT)).is_err()
        || stream.set_write_timeout(Some(IO_TIMEOUT)).is_err()
    {
        return;
    }
    let head = match read_head(&mut stream) {
        Ok(head) => head,
        Err(HeadError::TooLarge) => {
            return Response::error(431, "request head too large").send(&mut stream, false);
        }
        Err(HeadError::Malformed) => {
            return Response::error(400, "malformed request").send(&mut stream, false);
        }
        Err(HeadError::Gone) => return,
    };
    if let Err(refusal) = admissible(&head, context) {
        return refusal.send(&mut stream, false);
    }
    if head.path == "/ws" {
        return upgrade(stream, &head, context);
    }
    let head_only = head.method == "HEAD";
    route(&head, context).send(&mut stream, head_only);
}

/// Refuses requests from elsewhere than loopback's names (when bound to
/// loopback) and requests with bodies.
fn admissible(head: &Head, context: &Context) -> Result<(), Response> {
    if context.loopback
        && head
            .header("host")
            .is_some_and(|host| !is_loopback_host(host))
    {
        return Err(Response::error(
            403,
            "this viewer answers only on localhost",
        ));
    }
    if head.has_body() {
        return Err(Response::error(413, "the viewer takes no request bodies"));
    }
    Ok(())
}

/// Whether a `Host` (or an origin's host) names loopback: `localhost`,
/// 127.x.y.z or [::1], with any port.
fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        Some(rest) => rest.split(']').next().unwrap_or(""),
        None => host.rsplit_once(':').map_or(host, |(name, _)| name),
    };
    name.eq_ignore_ascii_case("localhost")
        || name.parse::<IpAddr>().is_ok_and(|ip| ip.is_loopback())
}

/// The answer to every request but the WebSocket's.
fn route(head: &Head, context: &Context) -> Response {
    let method = head.method.as_str();
    let get = matches!(method, "GET" | "HEAD");
    match head.path.as_str() {
        "/state" if get => Response::json(200, context.broadcast.status()),
        "/probe" if get => probe(head, context),
        "/solution.glb" if get => export(context),
        "/control/pause" | "/control/resume" | "/control/stop" if method == "POST" => {
            control(&head.path, context)
        }
        "/control/pause" | "/control/resume" | "/control/stop" => {
            Response::error(405, "use POST").with_header("Allow", "POST")
        }
        path => match asset(path) {
            Some(file) if get => Response::new(200, file.content_type, file.bytes.to_vec()),
            Some(_) => Response::error(405, "use GET").with_header("Allow", "GET, HEAD"),
            None if ROUTES.contains(&path) => {
                Response::error(405, "use GET").with_header("Allow", "GET, HEAD")
            }
            None => Response::error(404, "no such page"),
        },
    }
}

/// `/probe?x&y&z&nx&ny&nz`: the solution read at a point, as
/// `isorad probe --mode gather` reads it.
fn probe(head: &Head, context: &Context) -> Response {
    let number = |name: &str| {
        head.parameter(name)
            .and_then(|value| value.parse::<f64>().ok())
            .filter(|value| value.is_finite())
    };
    let coordinates = |names: [&str; 3]| -> Option<DVec3> {
        Some(DVec3::new(
            number(names[0])?,
            number(names[1])?,
            number(names[2])?,
        ))
    };
    let Some(position) = coordinates(["x", "y", "z"]) else {
        return Response::error(400, "give the point as finite numbers x, y and z");
    };
    let normal = match head.parameter("nx") {
        None => None,
        Some(_) => match coordinates(["nx", "ny", "nz"]).and_then(|n| n.try_normalize()) {
            Some(normal) => Some(normal),
            None => return Response::error(400, "give the normal as finite nx, ny, nz, not 0"),
        },
    };
    let point = ProbePoint {
        position,
        normal,
        line: 0,
    };
    let (reply, answer) = channel();
    if !context.solve.ask(Request::Probe { point, reply }) {
        return Response::error(503, "the solve has ended");
    }
    match wait(&answer) {
        Some(Ok(json)) => Response::json(200, json),
        Some(Err(message)) => Response::error(422, &message),
        None => Response::error(503, "the solve did not answer in time"),
    }
}

/// `/solution.glb`: the current solution, with the page's default
/// exposure baked into its colours.
fn export(context: &Context) -> Response {
    let (reply, answer) = channel();
    if !context.solve.ask(Request::Export { reply }) {
        return Response::error(503, "the solve has ended");
    }
    match wait(&answer) {
        Some(Ok(bytes)) => Response::new(200, "model/gltf-binary", bytes).with_header(
            "Content-Disposition",
            "attachment; filename=\"isorad-solution.glb\"",
        ),
        Some(Err(message)) => Response::error(422, &message),
        None => Response::error(503, "the solve did not answer in time"),
    }
}

/// `/control/…`: pause, resume or stop the solve.
fn control(path: &str, context: &Context) -> Response {
    let control = match path {
        "/control/pause" => Control::Pause,
        "/control/resume" => Control::Resume,
        _ => Control::Stop,
    };
    if context.solve.ask(Request::Control(control)) {
        Response::new(204, "text/plain", Vec::new())
    } else {
        Response::error(503, "the solve has ended")
    }
}

/// The solve thread's reply, or `None` when it is gone or late.
fn wait<T>(answer: &Receiver<T>) -> Option<T> {
    answer.recv_timeout(REPLY_TIMEOUT).ok()
}

/// `/ws`: checks the handshake (RFC 6455 §4.2.1) and the origin, then
/// hands the stream to the socket.
fn upgrade(mut stream: TcpStream, head: &Head, context: &Context) {
    let refusal = if head.method != "GET" {
        Some(Response::error(405, "use GET").with_header("Allow", "GET"))
    } else if !head.header_has_token("upgrade", "websocket")
        || !head.header_has_token("connection", "upgrade")
    {
        Some(Response::error(426, "this path is a WebSocket").with_header("Upgrade", "websocket"))
    } else if head.header("sec-websocket-version") != Some("13") {
        Some(
            Response::error(426, "WebSocket version 13").with_header("Sec-WebSocket-Version", "13"),
        )
    } else if !head.header("sec-websocket-key").is_some_and(valid_key) {
        Some(Response::error(400, "bad Sec-WebSocket-Key"))
    } else if !same_origin(head) {
        Some(Response::error(
            403,
            "WebSockets only from this viewer's page",
        ))
    } else if context.broadcast.clients.load(Ordering::SeqCst) >= MAX_SOCKETS {
        Some(Response::error(503, "too many pages watching"))
    } else {
        None
    };
    if let Some(response) = refusal {
        return response.send(&mut stream, false);
    }
    let key = head.header("sec-websocket-key").unwrap_or_default();
    serve_socket(stream, key, &context.broadcast);
}

/// A WebSocket key: 16 bytes in base64, 24 characters.
fn valid_key(key: &str) -> bool {
    key.len() == 24
        && key
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'+' | b'/' | b'='))
}

/// Whether the request's `Origin`, if any, is the page the server serves
/// (its host equals the request's `Host`).
fn same_origin(head: &Head) -> bool {
    let Some(origin) = head.header("origin") else {
        return true;
    };
    let host = origin
        .strip_prefix("http://")
        .or_else(|| origin.strip_prefix("https://"));
    host.is_some() && host == head.header("host")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_hosts() {
        for host in [
            "localhost",
            "localhost:8750",
            "127.0.0.1:9",
            "[::1]:80",
            "127.1.2.3",
        ] {
            assert!(is_loopback_host(host), "{host}");
        }
        for host in [
            "example.com",
            "evil.localhost.example:80",
            "10.0.0.1:8750",
            "[::2]:1",
        ] {
            assert!(!is_loopback_host(host), "{host}");
        }
    }

    #[test]
    fn websocket_keys() {
        assert!(valid_key("dGhlIHNhbXBsZSBub25jZQ=="));
        assert!(!valid_key("short"));
        assert!(!valid_key("dGhlIHNhbXBsZSBub25jZQ\r\n"));
    }
}
