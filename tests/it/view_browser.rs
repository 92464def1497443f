//! `isorad view` as a browser sees it: headless Chromium (software WebGL)
//! loads the page, waits for the solve to finish, and the test checks that
//! the canvas is drawn, that it matches `isorad render`'s PNG of the same
//! camera, and that a click reads the probe's value.
//!
//! Chromium is driven over the DevTools protocol with the WebSocket crate
//! the viewer itself uses. `.ci/run` installs Debian's `chromium` and sets
//! `ISORAD_BROWSER_TESTS=1`, under which a missing browser fails the test;
//! elsewhere the test says it skipped.

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use tungstenite::{Message, WebSocket, stream::MaybeTlsStream};

use super::view_server::Viewer;

/// The largest mean per-pixel luminance difference, relative to the mean
/// luminance, between the page and `isorad render`'s PNG: the 3 %.
const IMAGE_TOLERANCE: f64 = 0.03;

/// The Cornell box camera's size, at which the page is compared.
const SIZE: u32 = 512;

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A DevTools session on one page.
struct DevTools {
    socket: WebSocket<MaybeTlsStream<TcpStream>>,
    session: String,
    next_id: u64,
}

impl DevTools {
    /// Sends `method` with `params` to the browser (or, with the session,
    /// the page) and returns the result.
    fn call(&mut self, method: &str, params: Value, on_page: bool) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut message = json!({"id": id, "method": method, "params": params});
        if on_page {
            message["sessionId"] = json!(self.session);
        }
        self.socket
            .send(Message::text(message.to_string()))
            .expect("send to Chromium");
        loop {
            let Message::Text(text) = self.socket.read().expect("Chromium answers") else {
                continue;
            };
            let answer: Value = serde_json::from_str(&text).expect("JSON from Chromium");
            if answer["id"] == json!(id) {
                assert!(answer["error"].is_null(), "{method}: {answer}");
                return answer["result"].clone();
            }
        }
    }

    /// Evaluates a JavaScript expression in the page, awaiting promises.
    fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
            true,
        );
        result["result"]["value"].clone()
    }

    /// Polls `expression` until it is true.
    fn wait_for(&mut self, expression: &str, limit: Duration) {
        let start = Instant::now();
        while self.eval(expression) != json!(true) {
            let state = self.eval("JSON.stringify(window.isorad && window.isorad.status)");
            assert!(
                start.elapsed() < limit,
                "{expression} never held; status {state}"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

fn chromium() -> Option<&'static str> {
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .into_iter()
        .find(|path| Path::new(path).exists())
}

/// Starts headless Chromium with software WebGL; returns it and its
/// DevTools address.
fn start_chromium(binary: &str, profile: &Path) -> (Killed, String) {
    let mut child = Command::new(binary)
        .args([
            "--headless",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--ignore-gpu-blocklist",
            "--disable-gpu-sandbox",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--remote-debugging-port=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={SIZE},{SIZE}"))
        .arg("about:blank")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("Chromium starts");
    let stderr = child.stderr.take().expect("stderr");
    let mut lines = BufReader::new(stderr).lines();
    let address = loop {
        let line = lines
            .next()
            .expect("Chromium prints its address")
            .expect("a line");
        if let Some(address) = line.split("DevTools listening on ").nth(1) {
            break address.trim().to_owned();
        }
    };
    // Keep draining stderr so Chromium never blocks on it.
    std::thread::spawn(move || lines.for_each(drop));
    (Killed(child), address)
}

/// Opens a page at `url` at the test's size.
fn open_page(address: &str, url: &str) -> DevTools {
    let (socket, _) = tungstenite::connect(address).expect("DevTools WebSocket");
    let mut tools = DevTools {
        socket,
        session: String::new(),
        next_id: 0,
    };
    let target = tools.call("Target.createTarget", json!({"url": "about:blank"}), false);
    let attached = tools.call(
        "Target.attachToTarget",
        json!({"targetId": target["targetId"], "flatten": true}),
        false,
    );
    tools.session = attached["sessionId"]
        .as_str()
        .expect("a session")
        .to_owned();
    tools.call(
        "Emulation.setDeviceMetricsOverride",
        json!({"width": SIZE, "height": SIZE, "deviceScaleFactor": 1, "mobile": false}),
        true,
    );
    tools.call("Page.enable", json!({}), true);
    tools.call("Page.navigate", json!({"url": url}), true);
    tools
}

/// Decodes standard base64 (the data URL's payload).
fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let sextets: Vec<u8> = text.bytes().filter_map(value).collect();
    sextets
        .chunks(4)
        .flat_map(|chunk| {
            let bits = chunk
                .iter()
                .enumerate()
                .fold(0u32, |acc, (i, &s)| acc | (u32::from(s) << (18 - 6 * i)));
            let bytes = bits.to_be_bytes();
            bytes[1..chunk.len()].to_vec()
        })
        .collect()
}

/// Rec. 709 luminance of an 8-bit sRGB pixel, linear.
fn luminance(pixel: &[u8]) -> f64 {
    let linear = |v: u8| {
        let c = f64::from(v) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * linear(pixel[0]) + 0.7152 * linear(pixel[1]) + 0.0722 * linear(pixel[2])
}

fn pixels(png: &[u8]) -> image::RgbImage {
    image::load_from_memory(png).expect("a PNG").to_rgb8()
}

#[test]
fn the_page_draws_the_render_and_reads_a_click() {
    let required = std::env::var_os("ISORAD_BROWSER_TESTS").is_some();
    let Some(binary) = chromium() else {
        assert!(
            !required,
            "ISORAD_BROWSER_TESTS is set but Chromium is not installed"
        );
        eprintln!("skipped: no Chromium (install Debian's chromium to run this test)");
        return;
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let isorad = env!("CARGO_BIN_EXE_isorad");
    let size = SIZE.to_string();
    let scene = ["cornell"];
    // The renderer's picture of the scene camera.
    let png = dir.path().join("render.png");
    let rendered = Command::new(isorad)
        .arg("render")
        .args(scene)
        .args(["--quiet", "--width", &size, "--height", &size, "-o"])
        .arg(dir.path().join("render.exr"))
        .arg("--png")
        .arg(&png)
        .status()
        .expect("isorad render");
    assert!(rendered.success());
    let viewer = Viewer::start(&scene);
    let url = format!("http://{}/", viewer.address);
    let (_browser, address) = start_chromium(binary, &dir.path().join("profile"));
    let mut page = open_page(&address, &url);
    page.wait_for(
        "window.isorad !== undefined && window.isorad.settled === true",
        Duration::from_secs(180),
    );

    // The canvas fills the window at the camera's size.
    let data_url = page.eval("window.isorad.canvasDataURL()");
    let data_url = data_url.as_str().expect("a data URL");
    let canvas = pixels(&base64(data_url.split(',').nth(1).expect("base64")));
    assert_eq!(
        canvas.dimensions(),
        (SIZE, SIZE),
        "the canvas is the camera's size"
    );
    // The page as the browser shows it (the panel hides while nobody
    // works it) is drawn, and it is the renderer's picture.
    let screenshot = page.call("Page.captureScreenshot", json!({"format": "png"}), true);
    let screenshot = screenshot["data"].as_str().expect("a screenshot");
    let shown = pixels(&base64(screenshot));
    assert_eq!(
        shown.dimensions(),
        (SIZE, SIZE),
        "the screenshot is the window's size"
    );
    let reference = pixels(&std::fs::read(&png).expect("the render"));
    let lit = shown.pixels().filter(|p| luminance(&p.0) > 0.01).count();
    assert!(
        lit > (SIZE * SIZE / 2) as usize,
        "the canvas is blank: {lit} lit pixels"
    );
    let (mut difference, mut total) = (0.0, 0.0);
    for (a, b) in shown.pixels().zip(reference.pixels()) {
        difference += (luminance(&a.0) - luminance(&b.0)).abs();
        total += luminance(&b.0);
    }
    let relative = difference / total;
    eprintln!(
        "page against render: mean per-pixel luminance difference {:.2} %",
        100.0 * relative
    );
    assert!(
        relative < IMAGE_TOLERANCE,
        "page and render differ by {:.2} %",
        100.0 * relative
    );

    // A click on the floor, near the bottom of the picture, reads the probe.
    for kind in ["mousePressed", "mouseReleased"] {
        page.call(
            "Input.dispatchMouseEvent",
            json!({"type": kind, "x": SIZE / 2, "y": SIZE - 12, "button": "left", "clickCount": 1}),
            true,
        );
    }
    page.wait_for(
        "!!(window.isorad.lastProbe && window.isorad.lastProbe.response)",
        Duration::from_secs(60),
    );
    let shown = page.eval(
        "(() => { const p = document.querySelector('#probe'); return {lux: Number(p.dataset.illuminanceLx), surface: p.dataset.surface, request: window.isorad.lastProbe.request}; })()",
    );
    assert_eq!(shown["surface"], "floor", "{shown}");
    let request = &shown["request"];
    let query: Vec<String> = ["x", "y", "z", "nx", "ny", "nz"]
        .iter()
        .map(|k| format!("{k}={}", request[k]))
        .collect();
    let answer = viewer.get(&format!("/probe?{}", query.join("&")));
    let answer = answer.split("\r\n\r\n").nth(1).unwrap_or("").to_owned();
    let expected: Value = serde_json::from_str(&answer).expect("probe JSON");
    let lux = shown["lux"].as_f64().expect("lux shown");
    let expected_lux = expected["illuminance_lx"].as_f64().expect("lux");
    assert!(
        lux > 0.0 && (lux - expected_lux).abs() <= 1e-6 * expected_lux,
        "{lux} against {expected_lux}"
    );
}
