//! The little HTTP/1.1 the viewer speaks: one request per connection, its
//! head read with a bound and parsed by `httparse`, no request bodies, and
//! responses that close the connection.
//!
//! Refusals: a head over [`MAX_HEAD`] bytes or with more than
//! [`MAX_HEADERS`] headers is answered 431, a malformed one 400, a request
//! with a body 413; a peer that sends nothing for the read timeout, or
//! hangs up mid-head, is dropped without an answer.

use std::io::{ErrorKind, Read, Write};

/// The most bytes a request's head (request line and headers) may take.
pub const MAX_HEAD: usize = 16 * 1024;

/// The most headers a request may carry.
pub const MAX_HEADERS: usize = 64;

/// A request's head: what routing needs of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Head {
    /// GET, POST, …
    pub method: String,
    /// The path, without the query.
    pub path: String,
    /// The query, after '?', or empty.
    pub query: String,
    /// Header names (lower case) and values, in order.
    pub headers: Vec<Header>,
}

/// One request header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header {
    /// Lower case.
    pub name: String,
    pub value: String,
}

impl Head {
    /// The value of header `name` (lower case), if present.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|header| header.name == name)
            .map(|header| header.value.as_str())
    }

    /// Whether header `name` lists `token` (comma-separated, any case).
    pub fn header_has_token(&self, name: &str, token: &str) -> bool {
        self.header(name).is_some_and(|value| {
            value
                .split(',')
                .any(|part| part.trim().eq_ignore_ascii_case(token))
        })
    }

    /// Whether the request announces a body (which the viewer never takes).
    pub fn has_body(&self) -> bool {
        let length = self.header("content-length").map(str::trim);
        self.header("transfer-encoding").is_some() || length.is_some_and(|l| l != "0")
    }

    /// The query's parameter `name`, as given (the viewer's parameters are
    /// numbers, which need no percent-decoding).
    pub fn parameter(&self, name: &str) -> Option<&str> {
        self.query
            .split('&')
            .filter_map(|pair| pair.split_once('='))
            .find(|(key, _)| *key == name)
            .map(|(_, value)| value)
    }
}

/// Why no head was read.
#[derive(Debug, PartialEq, Eq)]
pub enum HeadError {
    /// Over [`MAX_HEAD`] bytes or [`MAX_HEADERS`] headers: answer 431.
    TooLarge,
    /// Not HTTP/1.x: answer 400.
    Malformed,
    /// The peer hung up or went quiet: answer nothing.
    Gone,
}

/// Reads and parses one request head from `stream`. Reads no further than
/// the head's end, so a WebSocket's first frame stays in the stream.
pub fn read_head(stream: &mut impl Read) -> Result<Head, HeadError> {
    let mut buffer = Vec::with_capacity(1024);
    let mut byte = [0u8; 1];
    // Byte by byte up to the blank line: heads are small, and nothing past
    // them may be consumed.
    loop {
        match stream.read(&mut byte) {
            Ok(0) => return Err(HeadError::Gone),
            Ok(_) => buffer.push(byte[0]),
            Err(error) if error.kind() == ErrorKind::Interrupted => continue,
            Err(_) => return Err(HeadError::Gone),
        }
        if buffer.ends_with(b"\r\n\r\n") || buffer.ends_with(b"\n\n") {
            return parse_head(&buffer);
        }
        if buffer.len() >= MAX_HEAD {
            return Err(HeadError::TooLarge);
        }
    }
}

/// Parses a complete head.
fn parse_head(bytes: &[u8]) -> Result<Head, HeadError> {
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut request = httparse::Request::new(&mut headers);
    match request.parse(bytes) {
        Ok(httparse::Status::Complete(_)) => {}
        Ok(httparse::Status::Partial) => return Err(HeadError::Malformed),
        Err(httparse::Error::TooManyHeaders) => return Err(HeadError::TooLarge),
        Err(_) => return Err(HeadError::Malformed),
    }
    let (Some(method), Some(target)) = (request.method, request.path) else {
        return Err(HeadError::Malformed);
    };
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let headers = request
        .headers
        .iter()
        .map(|header| Header {
            name: header.name.to_ascii_lowercase(),
            value: String::from_utf8_lossy(header.value).into_owned(),
        })
        .collect();
    Ok(Head {
        method: method.to_owned(),
        path: path.to_owned(),
        query: query.to_owned(),
        headers,
    })
}

/// A response: status, content type, body, and any further headers.
pub struct Response {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
    pub extra_headers: Vec<Header>,
}

impl Response {
    /// A response with a body of `content_type`.
    pub fn new(status: u16, content_type: &'static str, body: Vec<u8>) -> Response {
        Response {
            status,
            content_type,
            body,
            extra_headers: Vec::new(),
        }
    }

    /// A JSON response.
    pub fn json(status: u16, json: String) -> Response {
        Response::new(status, "application/json", json.into_bytes())
    }

    /// A JSON error: `{"error": message}`.
    pub fn error(status: u16, message: &str) -> Response {
        Response::json(status, serde_json::json!({ "error": message }).to_string())
    }

    /// The response with header `name: value` added.
    pub fn with_header(mut self, name: &str, value: &str) -> Response {
        self.extra_headers.push(Header {
            name: name.to_owned(),
            value: value.to_owned(),
        });
        self
    }

    /// Writes the response (without its body for HEAD), closing the
    /// connection after it. Errors are the peer's loss and are dropped.
    pub fn send(&self, stream: &mut impl Write, head_only: bool) {
        let mut text = format!(
            "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\n\
             Connection: close\r\nCache-Control: no-store\r\n\
             X-Content-Type-Options: nosniff\r\nReferrer-Policy: no-referrer\r\n\
             Content-Security-Policy: default-src 'self'; img-src 'self' data: blob:; \
             style-src 'self' 'unsafe-inline'; connect-src 'self'\r\n",
            self.status,
            reason(self.status),
            self.content_type,
            self.body.len()
        );
        for header in &self.extra_headers {
            text.push_str(&format!("{}: {}\r\n", header.name, header.value));
        }
        text.push_str("\r\n");
        let _ = stream.write_all(text.as_bytes());
        if !head_only {
            let _ = stream.write_all(&self.body);
        }
        let _ = stream.flush();
    }
}

/// The reason phrase of the statuses the viewer sends.
fn reason(status: u16) -> &'static str {
    match status {
        101 => "Switching Protocols",
        200 => "OK",
        204 => "No Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        413 => "Content Too Large",
        422 => "Unprocessable Content",
        426 => "Upgrade Required",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Error",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_head_and_stops_at_its_end() {
        let mut input: &[u8] =
            b"GET /probe?x=1&y=2.5 HTTP/1.1\r\nHost: 127.0.0.1:8\r\nUpgrade: WebSocket\r\n\r\nFRAME";
        let head = read_head(&mut input).expect("a head");
        assert_eq!(head.method, "GET");
        assert_eq!(head.path, "/probe");
        assert_eq!(head.parameter("y"), Some("2.5"));
        assert_eq!(head.parameter("z"), None);
        assert_eq!(head.header("upgrade"), Some("WebSocket"));
        assert!(head.header_has_token("upgrade", "websocket"));
        assert_eq!(input, b"FRAME");
    }

    #[test]
    fn refuses_huge_heads_garbage_and_hang_ups() {
        let huge = format!("GET / HTTP/1.1\r\nX: {}\r\n\r\n", "a".repeat(MAX_HEAD));
        assert_eq!(read_head(&mut huge.as_bytes()), Err(HeadError::TooLarge));
        let many: String = (0..=MAX_HEADERS).map(|i| format!("H{i}: v\r\n")).collect();
        let many = format!("GET / HTTP/1.1\r\n{many}\r\n");
        assert_eq!(read_head(&mut many.as_bytes()), Err(HeadError::TooLarge));
        let garbage: &[u8] = b"\x00\x01\x02 nonsense\r\n\r\n";
        assert_eq!(read_head(&mut &garbage[..]), Err(HeadError::Malformed));
        let cut: &[u8] = b"GET / HTTP/1.1\r\nHost: a";
        assert_eq!(read_head(&mut &cut[..]), Err(HeadError::Gone));
    }

    #[test]
    fn bodies_are_noticed() {
        let with_body: &[u8] = b"POST /control/stop HTTP/1.1\r\nContent-Length: 5\r\n\r\n";
        assert!(read_head(&mut &with_body[..]).expect("a head").has_body());
        let empty: &[u8] = b"POST /control/stop HTTP/1.1\r\nContent-Length: 0\r\n\r\n";
        assert!(!read_head(&mut &empty[..]).expect("a head").has_body());
    }

    #[test]
    fn responses_close_and_carry_their_length() {
        let mut out = Vec::new();
        Response::error(404, "no such page").send(&mut out, false);
        let text = String::from_utf8(out).expect("text");
        assert!(text.starts_with("HTTP/1.1 404 Not Found\r\n"), "{text}");
        assert!(text.contains("Connection: close\r\n"));
        assert!(text.ends_with("{\"error\":\"no such page\"}"), "{text}");
        let mut out = Vec::new();
        Response::new(200, "text/plain", b"abc".to_vec()).send(&mut out, true);
        assert!(String::from_utf8(out).expect("text").ends_with("\r\n\r\n"));
    }
}
