//! `isorad view`'s server, as a page and a hostile peer meet it: the page's
//! files, the status, probes (against `isorad probe`), the glTF, the
//! controls, the WebSocket's messages, refusals of bad requests, and
//! Ctrl-C.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use tungstenite::Message;

/// A running `isorad view` on a free port; killed when dropped.
pub struct Viewer {
    pub child: Child,
    pub address: String,
}

impl Viewer {
    pub fn start(args: &[&str]) -> Viewer {
        let mut child = Command::new(env!("CARGO_BIN_EXE_isorad"))
            .arg("view")
            .args(args)
            .args(["--port", "0", "--quiet"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("isorad view starts");
        let stdout = child.stdout.take().expect("stdout");
        let mut line = String::new();
        BufReader::new(stdout)
            .read_line(&mut line)
            .expect("the address line");
        let address = line
            .split("http://")
            .nth(1)
            .and_then(|rest| rest.split('/').next())
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .to_owned();
        Viewer { child, address }
    }

    /// Sends raw bytes and returns the whole answer (the server closes).
    fn raw(&self, request: &[u8]) -> String {
        let mut stream = TcpStream::connect(&self.address).expect("connect");
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .expect("timeout");
        // The server may answer and close before it has read everything.
        let _ = stream.write_all(request);
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        String::from_utf8_lossy(&answer).into_owned()
    }

    fn request(&self, method: &str, path: &str) -> String {
        let head = format!(
            "{method} {path} HTTP/1.1\r\nHost: {}\r\nContent-Length: 0\r\n\r\n",
            self.address
        );
        self.raw(head.as_bytes())
    }

    pub fn get(&self, path: &str) -> String {
        self.request("GET", path)
    }

    /// Polls `/state` until the solve is done.
    fn wait_until_done(&self) -> serde_json::Value {
        let deadline = Instant::now() + Duration::from_secs(120);
        loop {
            let status = json_body(&self.get("/state"));
            if status["state"] == "done" {
                return status;
            }
            assert!(Instant::now() < deadline, "not done: {status}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn status_code(answer: &str) -> u16 {
    answer
        .split(' ')
        .nth(1)
        .and_then(|code| code.parse().ok())
        .unwrap_or_else(|| panic!("no status in {answer:?}"))
}

fn json_body(answer: &str) -> serde_json::Value {
    let body = answer.split("\r\n\r\n").nth(1).unwrap_or("");
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {answer}"))
}

/// The Cornell box (millimetres) on a coarse mesh: solves in a second.
const SCENE: [&str; 3] = ["cornell", "--max-edge", "40"];

#[test]
fn serves_the_page_and_only_the_page() {
    let viewer = Viewer::start(&SCENE);
    let page = viewer.get("/");
    assert_eq!(status_code(&page), 200, "{page}");
    assert!(page.contains("text/html"));
    assert!(page.contains("Content-Security-Policy"));
    for path in ["/viewer.css", "/js/main.js", "/js/renderer.js"] {
        assert_eq!(status_code(&viewer.get(path)), 200, "{path}");
    }
    for path in [
        "/../Cargo.toml",
        "/%2e%2e/Cargo.toml",
        "/assets/viewer/index.html",
        "/etc/passwd",
        "//",
        "/js/",
    ] {
        assert_eq!(status_code(&viewer.get(path)), 404, "{path}");
    }
    let head = viewer.request("HEAD", "/js/main.js");
    assert_eq!(status_code(&head), 200);
    assert!(head.ends_with("\r\n\r\n"), "HEAD has no body: {head}");
}

#[test]
fn refuses_bad_requests_and_keeps_serving() {
    let viewer = Viewer::start(&SCENE);
    let huge = format!("GET / HTTP/1.1\r\nX-Big: {}\r\n\r\n", "a".repeat(64 * 1024));
    assert_eq!(status_code(&viewer.raw(huge.as_bytes())), 431);
    let many: String = (0..200).map(|i| format!("X-{i}: 1\r\n")).collect();
    let many = format!("GET / HTTP/1.1\r\n{many}\r\n");
    assert_eq!(status_code(&viewer.raw(many.as_bytes())), 431);
    assert_eq!(
        status_code(&viewer.raw(b"\x16\x03\x01 garbage\r\n\r\n")),
        400
    );
    assert_eq!(status_code(&viewer.request("DELETE", "/")), 405);
    assert_eq!(status_code(&viewer.get("/control/stop")), 405);
    let with_body = format!(
        "POST /control/pause HTTP/1.1\r\nHost: {}\r\nContent-Length: 4\r\n\r\nabcd",
        viewer.address
    );
    assert_eq!(status_code(&viewer.raw(with_body.as_bytes())), 413);
    let rebinding = b"GET /state HTTP/1.1\r\nHost: attacker.example:8750\r\n\r\n";
    assert_eq!(status_code(&viewer.raw(rebinding)), 403);
    for query in [
        "",
        "?x=1",
        "?x=a&y=0&z=0",
        "?x=0&y=0&z=0&nx=0&ny=0&nz=0",
        "?x=nan&y=0&z=0",
    ] {
        let answer = viewer.get(&format!("/probe{query}"));
        assert_eq!(status_code(&answer), 400, "{query}: {answer}");
    }
    // Peers that hang up mid-head, or open and say nothing, cost nothing.
    for _ in 0..100 {
        let mut stream = TcpStream::connect(&viewer.address).expect("connect");
        let _ = stream.write_all(b"GET / HTTP/1.1\r\nHost: loc");
    }
    let idle: Vec<TcpStream> = (0..80)
        .map(|_| TcpStream::connect(&viewer.address).expect("connect"))
        .collect();
    drop(idle);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(status_code(&viewer.get("/state")), 200);
}

#[test]
fn probes_read_what_isorad_probe_reads() {
    let viewer = Viewer::start(&SCENE);
    let status = viewer.wait_until_done();
    assert!(status["shots"].as_u64().unwrap_or(0) > 0, "{status}");
    assert!(status["exposure"].as_f64().is_some(), "{status}");
    // A point on the Cornell box's floor, seen from above, beside the blocks.
    let (x, y, z) = (100.0, 0.0, 450.0);
    let answer = viewer.get(&format!("/probe?x={x}&y={y}&z={z}&nx=0&ny=1&nz=0"));
    assert_eq!(status_code(&answer), 200, "{answer}");
    let probe = json_body(&answer);
    assert_eq!(probe["surface"], "floor", "{probe}");
    let lux = probe["illuminance_lx"].as_f64().expect("lux");
    let dir = tempfile::tempdir().expect("temp dir");
    let points = dir.path().join("points.csv");
    std::fs::write(&points, format!("{x},{y},{z},0,1,0\n")).expect("points");
    let output = Command::new(env!("CARGO_BIN_EXE_isorad"))
        .args(["probe", SCENE[0], SCENE[1], SCENE[2], "--quiet", "--points"])
        .arg(&points)
        .output()
        .expect("isorad probe");
    assert!(output.status.success());
    let csv = String::from_utf8_lossy(&output.stdout);
    let header: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    let row: Vec<&str> = csv.lines().nth(1).expect("row").split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == "illuminance_lux")
        .expect("lux column");
    let expected: f64 = row[column].parse().expect("a number");
    assert!(
        (lux - expected).abs() <= 1e-3 * expected,
        "view {lux} lx, probe {expected} lx"
    );
    // In the air, on no surface.
    let answer = viewer.get("/probe?x=278&y=300&z=300");
    assert_eq!(status_code(&answer), 422, "{answer}");
    let glb = viewer.get("/solution.glb");
    assert_eq!(status_code(&glb), 200);
    assert!(glb.contains("model/gltf-binary") && glb.contains("glTF"));
}

#[test]
fn the_socket_pushes_hello_mesh_light_and_status() {
    let viewer = Viewer::start(&SCENE);
    viewer.wait_until_done();
    let (mut socket, _) =
        tungstenite::connect(format!("ws://{}/ws", viewer.address)).expect("a WebSocket");
    let mut hello = None;
    let mut mesh: Option<Vec<u8>> = None;
    let mut light: Option<Vec<u8>> = None;
    let mut status = None;
    while hello.is_none() || mesh.is_none() || light.is_none() || status.is_none() {
        match socket.read().expect("a message") {
            Message::Text(text) => {
                let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
                match json["type"].as_str() {
                    Some("hello") => hello = Some(json),
                    Some("status") => status = Some(json),
                    other => panic!("unexpected {other:?}"),
                }
            }
            Message::Binary(bytes) if bytes[0] == 1 => mesh = Some(bytes.to_vec()),
            Message::Binary(bytes) if bytes[0] == 2 => light = Some(bytes.to_vec()),
            other => panic!("unexpected {other:?}"),
        }
    }
    let word = |bytes: &[u8], k: usize| {
        u32::from_le_bytes([
            bytes[4 * k],
            bytes[4 * k + 1],
            bytes[4 * k + 2],
            bytes[4 * k + 3],
        ])
    };
    let (mesh, light) = (mesh.unwrap_or_default(), light.unwrap_or_default());
    let (vertices, triangles) = (word(&mesh, 2) as usize, word(&mesh, 3) as usize);
    assert_eq!(mesh.len(), 16 + 12 * vertices + 12 * triangles);
    assert!(
        (16 + 12 * vertices..mesh.len())
            .step_by(4)
            .all(|at| (word(&mesh, at / 4) as usize) < vertices),
        "indices name vertices"
    );
    assert_eq!(word(&light, 1), word(&mesh, 1), "the light names its mesh");
    assert_eq!(light.len(), 16 + 16 * vertices);
    let hello = hello.unwrap_or_default();
    assert_eq!(
        hello["camera"]["vfov_deg"].as_f64().map(|v| v > 0.0),
        Some(true)
    );
    assert_eq!(
        status.unwrap_or_default()["vertices"].as_u64(),
        Some(vertices as u64)
    );
    socket.close(None).expect("close");
}

#[test]
fn bad_websockets_are_refused_and_cost_nothing() {
    let viewer = Viewer::start(&SCENE);
    let handshake = |extra: &str| {
        format!(
            "GET /ws HTTP/1.1\r\nHost: {}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n{extra}\r\n",
            viewer.address
        )
    };
    let key = "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";
    let no_version = handshake(key);
    assert_eq!(status_code(&viewer.raw(no_version.as_bytes())), 426);
    let bad_key = handshake("Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: x\r\n");
    assert_eq!(status_code(&viewer.raw(bad_key.as_bytes())), 400);
    let foreign = handshake(&format!(
        "Sec-WebSocket-Version: 13\r\n{key}Origin: http://attacker.example\r\n"
    ));
    assert_eq!(status_code(&viewer.raw(foreign.as_bytes())), 403);
    // A good handshake, then garbage frames: an unmasked frame, then one
    // that claims 1 GB.
    for garbage in [
        &b"\x81\x05hello"[..],
        &b"\x82\xff\x00\x00\x00\x00\x40\x00\x00\x00abcd"[..],
    ] {
        let mut stream = TcpStream::connect(&viewer.address).expect("connect");
        let good = handshake(&format!("Sec-WebSocket-Version: 13\r\n{key}"));
        stream.write_all(good.as_bytes()).expect("handshake");
        let mut answer = [0u8; 12];
        stream.read_exact(&mut answer).expect("an answer");
        assert_eq!(&answer, b"HTTP/1.1 101");
        stream.write_all(garbage).expect("garbage");
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .expect("timeout");
        let mut rest = Vec::new();
        // The server drops the socket: the read ends.
        let _ = stream.read_to_end(&mut rest);
    }
    assert_eq!(status_code(&viewer.get("/state")), 200);
}

#[test]
fn controls_stop_the_solve_and_ctrl_c_ends_with_130() {
    // A fine mesh that takes a while, stopped early from the page.
    let mut viewer = Viewer::start(&["cornell", "--max-edge", "5", "--tolerance", "0.00001"]);
    assert_eq!(status_code(&viewer.request("POST", "/control/pause")), 204);
    assert_eq!(status_code(&viewer.request("POST", "/control/resume")), 204);
    assert_eq!(status_code(&viewer.request("POST", "/control/stop")), 204);
    let status = viewer.wait_until_done();
    assert_eq!(status["stop_reason"], "stopped", "{status}");
    let pid = viewer.child.id().to_string();
    let sent = Instant::now();
    let killed = Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .expect("kill");
    assert!(killed.success());
    let code = loop {
        if let Some(status) = viewer.child.try_wait().expect("wait") {
            break status.code();
        }
        assert!(sent.elapsed() < Duration::from_secs(5), "still running");
        std::thread::sleep(Duration::from_millis(10));
    };
    assert_eq!(code, Some(130));
    assert!(
        sent.elapsed() < Duration::from_secs(1),
        "{:?}",
        sent.elapsed()
    );
}

#[test]
fn a_scene_that_cannot_be_loaded_ends_the_command_with_its_error() {
    let output = Command::new(env!("CARGO_BIN_EXE_isorad"))
        .args(["view", "no/such/scene.toml", "--port", "0", "--quiet"])
        .output()
        .expect("isorad view runs");
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("no/such/scene.toml"), "{stderr}");
}
