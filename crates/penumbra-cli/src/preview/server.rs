//! The HTTP side of the live pages (the preview's and the explorer's): the
//! checks every request passes, the page, the event stream, the image, and
//! the thread that runs them on a one-thread tokio runtime, so that the
//! render keeps every core it was given. A page's own routes (the preview's
//! Stop, the explorer's controls) are added by the one that starts it.

use std::convert::Infallible;
use std::io;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use axum::body::Bytes;
use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use futures_util::stream::{self, Stream};
use serde_json::json;
use tokio::sync::watch;

use super::frame::Frame;
use super::security::{random_token, Access, BODY_LIMIT};

/// The style every live page shares.
pub(crate) const SHARED_CSS: &str = include_str!("page.css");
/// The script every live page shares: the image (decoding, tone mapping,
/// exposure, zoom and pan), the statistics table and the event stream, as
/// `penumbraView(options)`.
pub(crate) const SHARED_JS: &str = include_str!("view.js");

/// The document every live page is: its head, then `{{BODY}}` and the script.
const SHELL: &str = include_str!("shell.html");
/// The exposure and zoom controls, where a body says `{{VIEW_CONTROLS}}`.
const VIEW_CONTROLS: &str = include_str!("view-controls.html");
/// The table of the render's progress, where a body says `{{VIEW_PROGRESS}}`.
const VIEW_PROGRESS: &str = include_str!("view-progress.html");

/// What a live page is made of: its title, its body (with the shared
/// parts' placeholders), and its own style and script, which follow the
/// shared ones.
pub(crate) struct Site {
    pub title: &'static str,
    pub body: &'static str,
    pub css: &'static str,
    pub js: &'static str,
}

impl Site {
    /// The whole page, its inline style and script under `nonce`.
    fn page(&self, nonce: &str) -> String {
        let body = self
            .body
            .replace("{{VIEW_CONTROLS}}\n", VIEW_CONTROLS)
            .replace("{{VIEW_PROGRESS}}\n", VIEW_PROGRESS);
        SHELL
            .replace("{{TITLE}}", self.title)
            .replace("{{NONCE}}", nonce)
            .replace("{{STYLE}}", &format!("{SHARED_CSS}\n{}", self.css))
            .replace("{{BODY}}", &body)
            .replace("{{SCRIPT}}", &format!("{SHARED_JS}\n{}", self.js))
    }
}

/// How long the server may take to close its connections once dropped.
const GRACE: Duration = Duration::from_secs(2);

/// How long a server dropped after the end waits for the pages told of the
/// last frame to fetch its image.
const LAST_FETCH: Duration = Duration::from_secs(2);

/// The latest publication, which every viewer catches up to: a viewer that
/// is slower than the passes skips frames rather than queueing them.
#[derive(Clone, Default)]
struct Latest {
    /// Publications so far; 0 before the first frame.
    seq: u64,
    /// The last frame's event JSON.
    event: Option<Arc<str>>,
    /// The last frame's `/image` body.
    image: Option<Bytes>,
    /// The end event's JSON, once the render ended.
    end: Option<Arc<str>>,
}

/// The frame events sent and the images served for one publication.
#[derive(Default)]
struct Fetches {
    seq: u64,
    sent: u64,
    served: u64,
}

impl Fetches {
    fn at(&mut self, seq: u64) -> &mut Fetches {
        if self.seq != seq {
            *self = Fetches {
                seq,
                ..Fetches::default()
            };
        }
        self
    }
}

pub(crate) struct Shared {
    pub access: Access,
    page: String,
    csp: HeaderValue,
    stop: Arc<AtomicBool>,
    latest: watch::Sender<Latest>,
    closing: watch::Sender<bool>,
    fetches: Mutex<Fetches>,
}

impl Shared {
    fn fetches(&self) -> std::sync::MutexGuard<'_, Fetches> {
        self.fetches.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

impl Shared {
    /// Makes `frame` the latest and wakes every viewer.
    pub fn publish(&self, frame: &Frame) {
        let image = frame.encode_image().map(Bytes::from);
        self.latest.send_modify(|latest| {
            latest.seq += 1;
            latest.event = Some(frame.event_json(latest.seq).into());
            latest.image = image;
        });
    }
}

/// A running server; dropping it closes every connection and joins its thread.
pub(crate) struct Server {
    shared: Arc<Shared>,
    addr: SocketAddr,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// Binds `bind:port` and serves `site` on a thread of its own, with
    /// the routes `routes` makes beside the shared ones (`/`, `/events`,
    /// `/image`); every route passes the checks of [`guard`].
    pub fn start(
        bind: IpAddr,
        port: u16,
        site: &Site,
        routes: impl FnOnce(Arc<Shared>) -> Router,
    ) -> io::Result<Server> {
        let token = random_token().map_err(io::Error::other)?;
        let nonce = random_token().map_err(io::Error::other)?;
        let std_listener = std::net::TcpListener::bind((bind, port))?;
        std_listener.set_nonblocking(true)?;
        let addr = std_listener.local_addr()?;
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_io()
            .enable_time()
            .build()?;
        let listener = {
            let _entered = runtime.enter();
            tokio::net::TcpListener::from_std(std_listener)?
        };
        let page = site.page(&nonce);
        let csp = format!(
            "default-src 'none'; script-src 'nonce-{nonce}'; style-src 'nonce-{nonce}'; \
             connect-src 'self'; img-src data:; base-uri 'none'; form-action 'none'; \
             frame-ancestors 'none'"
        );
        let csp = HeaderValue::from_str(&csp).map_err(io::Error::other)?;
        let shared = Arc::new(Shared {
            access: Access {
                token,
                bound: bind,
                port: addr.port(),
            },
            page,
            csp,
            stop: Arc::new(AtomicBool::new(false)),
            latest: watch::Sender::new(Latest::default()),
            closing: watch::Sender::new(false),
            fetches: Mutex::new(Fetches::default()),
        });
        let app = router(shared.clone(), routes(shared.clone()));
        let closing = shared.closing.subscribe();
        let thread = std::thread::Builder::new()
            .name("penumbra-preview".into())
            .spawn(move || runtime.block_on(serve(listener, app, closing)))?;
        Ok(Server {
            shared,
            addr,
            thread: Some(thread),
        })
    }

    #[cfg(test)]
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The address to open, token included: the bound one, or the
    /// loopback address when bound to every address.
    pub fn url(&self) -> String {
        let host = match self.addr.ip() {
            IpAddr::V4(ip) if ip.is_unspecified() => IpAddr::V4(Ipv4Addr::LOCALHOST),
            IpAddr::V6(ip) if ip.is_unspecified() => IpAddr::V6(Ipv6Addr::LOCALHOST),
            ip => ip,
        };
        let origin = SocketAddr::new(host, self.addr.port());
        format!("http://{origin}/?token={}", self.token())
    }

    pub fn token(&self) -> &str {
        &self.shared.access.token
    }

    pub fn stop_flag(&self) -> Arc<AtomicBool> {
        self.shared.stop.clone()
    }

    /// Makes `frame` the latest and wakes every viewer.
    pub fn publish(&self, frame: &Frame) {
        self.shared.publish(frame);
    }

    /// What the routes share, for a thread that publishes frames.
    pub fn shared(&self) -> Arc<Shared> {
        self.shared.clone()
    }

    /// Tells every viewer, present and future, that the render ended.
    pub fn finish(&self, message: &str) {
        let stopped = self.shared.stop.load(Ordering::SeqCst);
        let end = json!({ "message": message, "stopped": stopped }).to_string();
        self.shared
            .latest
            .send_modify(|latest| latest.end = Some(end.into()));
    }
}

impl Drop for Server {
    /// After the end, first lets every page that was sent the last frame
    /// fetch its image (for at most `LAST_FETCH`), so that a page never
    /// misses the final image for a process that exits right after it.
    fn drop(&mut self) {
        let deadline = Instant::now() + LAST_FETCH;
        let waiting = || {
            let latest = self.shared.latest.borrow();
            let f = self.shared.fetches();
            latest.end.is_some() && f.seq == latest.seq && f.served < f.sent
        };
        while waiting() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        self.shared.closing.send_replace(true);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Serves until `closing` turns true, then lets connections finish for at
/// most `GRACE`.
async fn serve(listener: tokio::net::TcpListener, app: Router, closing: watch::Receiver<bool>) {
    let mut signal = closing.clone();
    let server = axum::serve(listener, app).with_graceful_shutdown(async move {
        let _ = signal.wait_for(|c| *c).await;
    });
    let mut deadline = closing;
    let grace = async move {
        let _ = deadline.wait_for(|c| *c).await;
        tokio::time::sleep(GRACE).await;
    };
    tokio::select! {
        _ = server => {}
        _ = grace => {}
    }
}

fn router(shared: Arc<Shared>, own: Router) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/events", get(events))
        .route("/image", get(image))
        .with_state(shared.clone())
        .merge(own)
        .fallback(not_found)
        .layer(middleware::from_fn_with_state(shared, guard))
}

/// Runs before every route, the unknown ones included: host, token, body size.
async fn guard(State(shared): State<Arc<Shared>>, request: Request, next: Next) -> Response {
    let access = &shared.access;
    if !access.host_allowed(request.headers()) {
        return refuse(
            StatusCode::FORBIDDEN,
            "this server answers only to its own address",
        );
    }
    if !access.token_given(request.headers(), request.uri()) {
        return refuse(StatusCode::FORBIDDEN, "missing or wrong token");
    }
    if content_length(request.headers()).is_some_and(|n| n > BODY_LIMIT) {
        return refuse(StatusCode::PAYLOAD_TOO_LARGE, "request body too large");
    }
    let mut response = next.run(request).await;
    let headers = response.headers_mut();
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    headers.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    headers.insert(
        header::REFERRER_POLICY,
        HeaderValue::from_static("no-referrer"),
    );
    response
}

fn content_length(headers: &HeaderMap) -> Option<u64> {
    headers
        .get(header::CONTENT_LENGTH)?
        .to_str()
        .ok()?
        .parse()
        .ok()
}

pub(crate) fn refuse(status: StatusCode, why: &'static str) -> Response {
    (status, format!("{why}\n")).into_response()
}

async fn not_found() -> Response {
    refuse(StatusCode::NOT_FOUND, "not found")
}

async fn page(State(shared): State<Arc<Shared>>) -> Response {
    (
        [
            (
                header::CONTENT_TYPE,
                HeaderValue::from_static("text/html; charset=utf-8"),
            ),
            (header::CONTENT_SECURITY_POLICY, shared.csp.clone()),
            (header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY")),
        ],
        shared.page.clone(),
    )
        .into_response()
}

async fn image(State(shared): State<Arc<Shared>>) -> Response {
    let (seq, body) = {
        let latest = shared.latest.borrow();
        (latest.seq, latest.image.clone())
    };
    if body.is_some() {
        shared.fetches().at(seq).served += 1;
    }
    match body {
        Some(bytes) => {
            ([(header::CONTENT_TYPE, "application/octet-stream")], bytes).into_response()
        }
        None => StatusCode::NO_CONTENT.into_response(),
    }
}

/// The routes of the preview's page beside the shared ones: POST /stop.
pub(crate) fn stop_route(shared: Arc<Shared>) -> Router {
    Router::new().route("/stop", post(stop)).with_state(shared)
}

async fn stop(State(shared): State<Arc<Shared>>, request: Request) -> Response {
    if let Err(refused) = change_body(&shared, request).await {
        return refused;
    }
    shared.stop.store(true, Ordering::SeqCst);
    (StatusCode::OK, "stopping after this pass\n").into_response()
}

/// The body of a request that changes something, if it may: from the
/// page's own origin (see [`Access::change_allowed`]) and small.
pub(crate) async fn change_body(shared: &Shared, request: Request) -> Result<Bytes, Response> {
    if !shared.access.change_allowed(request.headers()) {
        return Err(refuse(
            StatusCode::FORBIDDEN,
            "cross-origin request refused",
        ));
    }
    axum::body::to_bytes(request.into_body(), BODY_LIMIT as usize)
        .await
        .map_err(|_| refuse(StatusCode::PAYLOAD_TOO_LARGE, "request body too large"))
}

/// One viewer's place in the stream of publications.
struct Viewer {
    shared: Arc<Shared>,
    latest: watch::Receiver<Latest>,
    closing: watch::Receiver<bool>,
    sent_seq: u64,
    queue: Vec<Event>,
    ended: bool,
}

async fn events(
    State(shared): State<Arc<Shared>>,
) -> Sse<impl Stream<Item = Result<Event, Infallible>>> {
    let viewer = Viewer {
        latest: shared.latest.subscribe(),
        closing: shared.closing.subscribe(),
        shared: shared.clone(),
        sent_seq: 0,
        queue: Vec::new(),
        ended: false,
    };
    Sse::new(stream::unfold(viewer, next_event)).keep_alive(KeepAlive::default())
}

/// The viewer's next event: the latest frame if it has not seen it, then the
/// end event, after which the stream closes; it also closes when the server does.
async fn next_event(mut v: Viewer) -> Option<(Result<Event, Infallible>, Viewer)> {
    loop {
        if !v.queue.is_empty() {
            let event = v.queue.remove(0);
            return Some((Ok(event), v));
        }
        if v.ended {
            return None;
        }
        {
            let latest = v.latest.borrow_and_update();
            if let (Some(data), true) = (&latest.event, latest.seq != v.sent_seq) {
                v.queue.push(Event::default().event("frame").data(&**data));
                v.sent_seq = latest.seq;
                v.shared.fetches().at(latest.seq).sent += 1;
            }
            if let Some(data) = &latest.end {
                v.queue.push(Event::default().event("end").data(&**data));
                v.ended = true;
            }
        }
        if !v.queue.is_empty() {
            continue;
        }
        if *v.closing.borrow() {
            return None;
        }
        tokio::select! {
            changed = v.latest.changed() => {
                if changed.is_err() {
                    return None;
                }
            }
            _ = v.closing.changed() => {}
        }
    }
}
