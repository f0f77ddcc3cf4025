//! The preview server over real connections: an HTTP client (ureq) for the
//! ordinary requests, raw sockets for the hostile ones. Timeouts here only
//! turn a hang into a failure; nothing is timed.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::atomic::Ordering;
use std::sync::mpsc;
use std::time::Duration;

use serde_json::{json, Value};

use super::{Frame, Preview, DEFAULT_BIND};

pub(crate) const PATIENCE: Duration = Duration::from_secs(30);

fn start() -> Preview {
    Preview::start(DEFAULT_BIND, 0).unwrap()
}

pub(crate) fn agent() -> ureq::Agent {
    ureq::Agent::config_builder()
        .http_status_as_error(false)
        .timeout_global(Some(PATIENCE))
        .build()
        .into()
}

fn addr(p: &Preview) -> SocketAddr {
    p.server.addr()
}

fn token(p: &Preview) -> String {
    p.server.token().to_string()
}

fn frame(pass: u32) -> Frame {
    Frame {
        width: 3,
        height: 2,
        rgb: (0..18).map(|i| i as f32 * 0.37 - 1.5).collect(),
        pass,
        passes: 8,
        elapsed_s: 2.0,
        rays: 1234,
        stats: json!({ "primary": 6, "shadow": { "traced": 4 } }),
        eta_s: Some(6.0),
        info: Value::Null,
    }
}

/// Sends `request` as written and returns the status and the whole response.
pub(crate) fn raw(addr: SocketAddr, request: &str) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    // The server may answer and close before reading a body it refuses.
    let _ = stream.write_all(request.as_bytes());
    let mut out = Vec::new();
    let _ = stream.read_to_end(&mut out);
    let text = String::from_utf8_lossy(&out).into_owned();
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status line in {text:?}"));
    (status, text)
}

/// The next server-sent event as (name, data); `None` at the stream's end.
pub(crate) fn next_event(reader: &mut impl BufRead) -> Option<(String, String)> {
    let (mut name, mut data) = (String::new(), String::new());
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end_matches(['\r', '\n']);
        if line.is_empty() {
            if !data.is_empty() {
                return Some((name, data));
            }
        } else if let Some(v) = line.strip_prefix("event:") {
            name = v.trim_start().to_string();
        } else if let Some(v) = line.strip_prefix("data:") {
            data.push_str(v.trim_start());
        }
    }
}

/// Opens /events and returns once the server has answered with its headers.
fn subscribe(p: &Preview) -> impl BufRead {
    let url = format!("http://{}/events?token={}", addr(p), token(p));
    let response = agent().get(&url).call().unwrap();
    assert_eq!(response.status(), 200);
    let kind = response.headers()["content-type"].to_str().unwrap();
    assert!(kind.starts_with("text/event-stream"), "{kind}");
    BufReader::new(response.into_body().into_reader())
}

#[test]
fn preview_url_is_loopback_with_a_token() {
    let p = start();
    let url = p.url();
    let expected = format!("http://127.0.0.1:{}/?token={}", addr(&p).port(), token(&p));
    assert_eq!(url, expected);
    assert_eq!(token(&p).len(), 32);
    assert!(addr(&p).ip().is_loopback());
}

#[test]
fn preview_page_needs_the_token() {
    let p = start();
    let mut ok = agent().get(&p.url()).call().unwrap();
    assert_eq!(ok.status(), 200);
    let csp = ok.headers()["content-security-policy"]
        .to_str()
        .unwrap()
        .to_string();
    let page = ok.body_mut().read_to_string().unwrap();
    assert!(page.contains("<canvas id=\"image\""));
    assert!(page.contains("new EventSource(\"/events?\""));
    // The inline script and style run under the per-run nonce, nothing else does.
    let nonce = csp
        .split("'nonce-")
        .nth(1)
        .unwrap()
        .split('\'')
        .next()
        .unwrap();
    assert_eq!(page.matches(&format!("nonce=\"{nonce}\"")).count(), 2);
    assert!(!page.contains("{{"), "a placeholder was left in the page");

    let base = format!("http://{}", addr(&p));
    for path in [
        "/",
        "/?token=",
        "/?token=0123",
        "/events",
        "/image",
        "/nope",
    ] {
        let r = agent().get(&format!("{base}{path}")).call().unwrap();
        assert_eq!(r.status(), 403, "{path}");
    }
    let wrong = format!("{base}/?token={}", "0".repeat(32));
    assert_eq!(agent().get(&wrong).call().unwrap().status(), 403);
    let by_header = agent()
        .get(&format!("{base}/"))
        .header("X-Penumbra-Token", &token(&p))
        .call()
        .unwrap();
    assert_eq!(by_header.status(), 200);
}

#[test]
fn preview_host_must_be_the_server() {
    let p = start();
    let (a, t, port) = (addr(&p), token(&p), addr(&p).port());
    let get = |host: &str| {
        let request =
            format!("GET /?token={t} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n");
        raw(a, &request).0
    };
    assert_eq!(get(&format!("127.0.0.1:{port}")), 200);
    assert_eq!(get(&format!("localhost:{port}")), 200);
    assert_eq!(get(&format!("[::1]:{port}")), 200);
    assert_eq!(get(&format!("attacker.example:{port}")), 403);
    assert_eq!(get(&format!("127.0.0.1:{}", port.wrapping_add(1))), 403);
    assert_eq!(get("127.0.0.1"), 403);
    let no_host = format!("GET /?token={t} HTTP/1.0\r\n\r\n");
    assert_eq!(raw(a, &no_host).0, 403);
}

#[test]
fn preview_unknown_paths_and_traversal_are_404() {
    let p = start();
    let (a, t, port) = (addr(&p), token(&p), addr(&p).port());
    for path in [
        "/../etc/passwd",
        "/%2e%2e/etc/passwd",
        "/%2e%2e/",
        "/..%2fetc%2fpasswd",
        "/page.js",
        "/image/../../etc/passwd",
        "//etc/passwd",
        "/index.html",
    ] {
        let request = format!(
            "GET {path}?token={t} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n"
        );
        let (status, text) = raw(a, &request);
        assert_eq!(status, 404, "{path}");
        assert!(!text.contains("root:"), "{path}");
    }
}

#[test]
fn preview_stop_sets_the_flag_from_its_own_origin() {
    let p = start();
    let flag = p.stop_requested();
    let url = format!("http://{}/stop?token={}", addr(&p), token(&p));
    let origin = format!("http://{}", addr(&p));
    let r = agent().post(&url).header("Origin", &origin).send_empty();
    assert_eq!(r.unwrap().status(), 200);
    assert!(flag.load(Ordering::SeqCst));
}

#[test]
fn preview_stop_refuses_other_origins() {
    let p = start();
    let flag = p.stop_requested();
    let url = format!("http://{}/stop?token={}", addr(&p), token(&p));
    for origin in ["http://attacker.example", "null", "https://127.0.0.1"] {
        let r = agent().post(&url).header("Origin", origin).send_empty();
        assert_eq!(r.unwrap().status(), 403, "{origin}");
    }
    // No Origin: the token must come in the header, which a form cannot set.
    assert_eq!(agent().post(&url).send_empty().unwrap().status(), 403);
    assert!(!flag.load(Ordering::SeqCst));
    let bare = format!("http://{}/stop", addr(&p));
    let r = agent()
        .post(&bare)
        .header("X-Penumbra-Token", &token(&p))
        .send_empty();
    assert_eq!(r.unwrap().status(), 200);
    assert!(flag.load(Ordering::SeqCst));
}

#[test]
fn preview_stop_is_post_only_and_bodies_are_small() {
    let p = start();
    let (a, t, port) = (addr(&p), token(&p), addr(&p).port());
    let get = agent()
        .get(&format!("http://{a}/stop?token={t}"))
        .call()
        .unwrap();
    assert_eq!(get.status(), 405);
    let head = format!(
        "POST /stop?token={t} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: http://127.0.0.1:{port}\r\nConnection: close\r\n"
    );
    let (status, _) = raw(a, &format!("{head}Content-Length: 1000000\r\n\r\n"));
    assert_eq!(status, 413);
    let chunk = "x".repeat(4000);
    let chunked = format!(
        "{head}Transfer-Encoding: chunked\r\n\r\n{:x}\r\n{chunk}\r\n0\r\n\r\n",
        chunk.len()
    );
    assert_eq!(raw(a, &chunked).0, 413);
    assert!(!p.stop_requested().load(Ordering::SeqCst));
}

#[test]
fn preview_events_deliver_a_frame_published_after_connecting() {
    let p = start();
    let mut events = subscribe(&p);
    p.publish(frame(3));
    let (name, data) = next_event(&mut events).unwrap();
    assert_eq!(name, "frame");
    let d: Value = serde_json::from_str(&data).unwrap();
    assert_eq!(d["pass"], 3);
    assert_eq!(d["passes"], 8);
    assert_eq!(d["rays"], 1234);
    assert_eq!(d["rays_per_s"], 617.0);
    assert_eq!(d["eta_s"], 6.0);
    assert_eq!(d["stats"]["shadow"]["traced"], 4);
    p.publish(frame(4));
    let (_, data) = next_event(&mut events).unwrap();
    assert_eq!(serde_json::from_str::<Value>(&data).unwrap()["pass"], 4);
}

#[test]
fn preview_finish_sends_the_end_and_closes_the_stream() {
    let p = start();
    let mut events = subscribe(&p);
    p.publish(frame(8));
    assert_eq!(next_event(&mut events).unwrap().0, "frame");
    p.finish("8 passes in 2 s");
    let (name, data) = next_event(&mut events).unwrap();
    assert_eq!(name, "end");
    let d: Value = serde_json::from_str(&data).unwrap();
    assert_eq!(d["message"], "8 passes in 2 s");
    assert_eq!(d["stopped"], false);
    assert!(next_event(&mut events).is_none());
    // A page opened later sees the last frame, then the end.
    let mut late = subscribe(&p);
    assert_eq!(next_event(&mut late).unwrap().0, "frame");
    assert_eq!(next_event(&mut late).unwrap().0, "end");
}

#[test]
fn preview_dropped_after_the_end_lets_the_page_fetch_the_last_image() {
    let p = start();
    let url = format!("http://{}/image?token={}", addr(&p), token(&p));
    let mut events = subscribe(&p);
    p.publish(frame(8));
    p.finish("finished");
    assert_eq!(next_event(&mut events).unwrap().0, "frame");
    assert_eq!(next_event(&mut events).unwrap().0, "end");
    // The process exits as soon as the render ends: the server is dropped
    // while the page has yet to fetch the frame it was told of.
    let dropping = std::thread::spawn(move || drop(p));
    let mut r = agent().get(&url).call().unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(&r.body_mut().read_to_vec().unwrap()[..4], b"PNB1");
    dropping.join().unwrap();
}

#[test]
fn preview_image_is_the_published_floats() {
    let p = start();
    let url = format!("http://{}/image?token={}", addr(&p), token(&p));
    assert_eq!(agent().get(&url).call().unwrap().status(), 204);
    let published = frame(5);
    p.publish(published.clone());
    let mut r = agent().get(&url).call().unwrap();
    assert_eq!(r.status(), 200);
    let bytes = r.body_mut().read_to_vec().unwrap();
    let word = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap());
    assert_eq!(&bytes[..4], b"PNB1");
    assert_eq!((word(4), word(8), word(12)), (3, 2, 5));
    let floats: Vec<f32> = bytes[16..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert_eq!(floats, published.rgb);
}

#[test]
fn preview_serves_fifty_viewers_at_once() {
    const VIEWERS: usize = 50;
    let p = start();
    let (connected, connections) = mpsc::channel();
    let (passes, results) = mpsc::channel();
    let url = format!("http://{}/events?token={}", addr(&p), token(&p));
    let threads: Vec<_> = (0..VIEWERS)
        .map(|_| {
            let (url, connected, passes) = (url.clone(), connected.clone(), passes.clone());
            std::thread::spawn(move || {
                let response = agent().get(&url).call().unwrap();
                connected.send(()).unwrap();
                let mut events = BufReader::new(response.into_body().into_reader());
                let (_, data) = next_event(&mut events).unwrap();
                let d: Value = serde_json::from_str(&data).unwrap();
                passes.send(d["pass"].as_u64().unwrap()).unwrap();
            })
        })
        .collect();
    for _ in 0..VIEWERS {
        connections.recv_timeout(PATIENCE).unwrap();
    }
    // With fifty streams open the page still loads.
    assert_eq!(agent().get(&p.url()).call().unwrap().status(), 200);
    p.publish(frame(6));
    for _ in 0..VIEWERS {
        assert_eq!(results.recv_timeout(PATIENCE).unwrap(), 6);
    }
    for t in threads {
        t.join().unwrap();
    }
}

#[test]
fn preview_drop_shuts_the_server_down() {
    let p = start();
    let a = addr(&p);
    let _open_stream = subscribe(&p);
    drop(p);
    assert!(TcpStream::connect(a).is_err());
}

#[test]
fn preview_start_error_names_the_address() {
    let p = start();
    let port = addr(&p).port();
    let err = Preview::start(DEFAULT_BIND, port).err().unwrap();
    assert!(
        err.to_string().contains(&format!("127.0.0.1:{port}")),
        "{err}"
    );
}
