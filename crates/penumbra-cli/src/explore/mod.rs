//! `penumbra explore`: a page for the thesis's study. It shows the image
//! refining pass by pass (the live preview's view), with controls made from
//! the render options' table: the integrator, each effect's distribution
//! and ray count, the metrics; dragging the image orbits the camera and the
//! wheel dollies it. Every change cancels the render and starts another.
//!
//! Routes, beside the preview's `/`, `/events` and `/image` (every one
//! needs the token and the server's own Host; those that change anything
//! also the page's own Origin or the token in a header):
//! - `GET /schema`: `{controls, scenes, scene}`, each control an option's
//!   name, kind (`int`, `number`, `switch`, `choice`), range or choices,
//!   default and doc;
//! - `POST /set` `{"name": ..., "value": ...}`: one control, checked as its
//!   flag is (400 and the reason when not);
//! - `POST /camera` `{"orbit": [yaw, pitch], "dolly": factor}`: degrees
//!   about the up axis and towards it, then the distance to the target
//!   times the factor (each optional);
//! - `POST /scene` `{"scene": index}` (or a listed name): another scene of
//!   the list `/schema` gives; nothing else is opened.
//!
//! A change answers with the next run's settings (the `info` every frame of
//! it carries: `run`, `scene`, `settings`, `chosen`, `camera`), or 400 with
//! the reason when it cannot be built.

mod camera;
mod catalogue;
mod controls;
mod session;
#[cfg(test)]
mod tests;

use std::net::IpAddr;
use std::sync::atomic::Ordering;
use std::sync::{mpsc, Arc};
use std::thread::JoinHandle;

use axum::extract::{Request, State};
use axum::http::header;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use penumbra::scene::{Choices, LoadOptions};
use serde_json::{json, Value};
use tokio::sync::oneshot;

pub use catalogue::Catalogue;
use session::{Change, Command, Session, Signals};

use crate::preview::server::{change_body, Server, Shared, Site};
use crate::preview::PreviewError;

const SITE: Site = Site {
    title: "penumbra explore",
    body: include_str!("page.html"),
    css: include_str!("page.css"),
    js: include_str!("page.js"),
};

/// Largest orbit of one request, in degrees.
const MAX_TURN: f64 = 3600.0;

/// What the explorer starts with.
pub struct Setup {
    pub bind: IpAddr,
    pub port: u16,
    /// The scene files and built-in names given; the first is opened.
    pub scenes: Vec<String>,
    pub load: LoadOptions,
    /// The options given as flags: the settings before any control moves.
    pub choices: Choices,
}

/// A running explorer: its server and its render session. Dropping it
/// stops both.
pub struct Explorer {
    server: Option<Server>,
    signals: Arc<Signals>,
    session: Option<JoinHandle<()>>,
}

/// What the routes of the explorer hold.
struct Routes {
    shared: Arc<Shared>,
    commands: mpsc::Sender<Command>,
    signals: Arc<Signals>,
    catalogue: Arc<Catalogue>,
}

impl Explorer {
    /// Opens the first scene (an error if it cannot be built) and starts
    /// serving and rendering.
    pub fn start(setup: Setup) -> Result<Explorer, String> {
        let (catalogue, first) = Catalogue::new(&setup.scenes)?;
        let catalogue = Arc::new(catalogue);
        let session = Session::open(catalogue.clone(), setup.load, first, setup.choices)?;
        let (send, receive) = mpsc::channel();
        let signals = Arc::new(Signals::default());
        let routes = |shared: Arc<Shared>| {
            Router::new()
                .route("/schema", get(schema))
                .route("/set", post(set))
                .route("/camera", post(camera))
                .route("/scene", post(scene))
                .with_state(Arc::new(Routes {
                    shared,
                    commands: send,
                    signals: signals.clone(),
                    catalogue,
                }))
        };
        let server = Server::start(setup.bind, setup.port, &SITE, routes).map_err(|source| {
            PreviewError {
                addr: std::net::SocketAddr::new(setup.bind, setup.port),
                source,
            }
            .to_string()
        })?;
        let shared = server.shared();
        let flags = signals.clone();
        let thread = std::thread::Builder::new()
            .name("penumbra-explore".into())
            .spawn(move || session.run(receive, &flags, &shared))
            .map_err(|e| e.to_string())?;
        Ok(Explorer {
            server: Some(server),
            signals,
            session: Some(thread),
        })
    }

    /// The address to open, token included.
    pub fn url(&self) -> String {
        self.server.as_ref().map(Server::url).unwrap_or_default()
    }

    /// Waits for the session to end (when the server does).
    pub fn wait(mut self) {
        if let Some(t) = self.session.take() {
            let _ = t.join();
        }
    }

    #[cfg(test)]
    fn server(&self) -> &Server {
        self.server.as_ref().expect("running")
    }
}

impl Drop for Explorer {
    fn drop(&mut self) {
        self.signals.close.store(true, Ordering::SeqCst);
        // The routes hold the session's channel: closing the server closes it.
        drop(self.server.take());
        if let Some(t) = self.session.take() {
            let _ = t.join();
        }
    }
}

/// `value` as a JSON response.
fn json_response(value: &Value) -> Response {
    (
        [(header::CONTENT_TYPE, "application/json")],
        value.to_string(),
    )
        .into_response()
}

async fn schema(State(r): State<Arc<Routes>>) -> Response {
    json_response(&json!({
        "controls": controls::schema(),
        "scenes": r.catalogue.json(),
        "camera": { "dolly": [camera::DOLLY_RANGE.0, camera::DOLLY_RANGE.1] },
    }))
}

fn bad(message: impl Into<String>) -> Response {
    (StatusCode::BAD_REQUEST, format!("{}\n", message.into())).into_response()
}

/// The request's JSON object, if it may change anything.
async fn body(r: &Routes, request: Request) -> Result<Value, Response> {
    let bytes = change_body(&r.shared, request).await?;
    match serde_json::from_slice::<Value>(&bytes) {
        Ok(v @ Value::Object(_)) => Ok(v),
        Ok(_) => Err(bad("expected a JSON object")),
        Err(e) => Err(bad(format!("not JSON: {e}"))),
    }
}

/// Hands `change` to the session, interrupting its render, and answers
/// what it says.
async fn send(r: &Routes, change: Change) -> Response {
    let (reply, answer) = oneshot::channel();
    // Counted first: the render stops, and the session waits for it.
    r.signals.sent.fetch_add(1, Ordering::SeqCst);
    if r.commands.send(Command { change, reply }).is_err() {
        return (StatusCode::SERVICE_UNAVAILABLE, "the session ended\n").into_response();
    }
    match answer.await {
        Ok(Ok(info)) => json_response(&info),
        Ok(Err(message)) => bad(message),
        Err(_) => (StatusCode::SERVICE_UNAVAILABLE, "the session ended\n").into_response(),
    }
}

async fn set(State(r): State<Arc<Routes>>, request: Request) -> Response {
    let v = match body(&r, request).await {
        Ok(v) => v,
        Err(refused) => return refused,
    };
    let Some(name) = v["name"].as_str() else {
        return bad("expected {\"name\": ..., \"value\": ...}");
    };
    match controls::parse(name, &v["value"]) {
        Ok((o, value)) => send(&r, Change::Set(o, value)).await,
        Err(message) => bad(message),
    }
}

async fn camera(State(r): State<Arc<Routes>>, request: Request) -> Response {
    let v = match body(&r, request).await {
        Ok(v) => v,
        Err(refused) => return refused,
    };
    let turn = |i: usize| match &v["orbit"] {
        Value::Null => Some(0.0),
        o => o[i].as_f64().filter(|d| d.abs() <= MAX_TURN),
    };
    let dolly = match &v["dolly"] {
        Value::Null => Some(1.0),
        d => d.as_f64(),
    };
    match (turn(0), turn(1), dolly, v["orbit"].as_array().map(Vec::len)) {
        (Some(yaw), Some(pitch), Some(dolly), None | Some(2)) => {
            let change = Change::Camera {
                yaw: yaw as f32,
                pitch: pitch as f32,
                dolly: dolly as f32,
            };
            send(&r, change).await
        }
        _ => bad(format!(
            "expected {{\"orbit\": [yaw, pitch], \"dolly\": factor}}: degrees of at most {MAX_TURN}, \
             a factor from {} to {}",
            camera::DOLLY_RANGE.0,
            camera::DOLLY_RANGE.1
        )),
    }
}

async fn scene(State(r): State<Arc<Routes>>, request: Request) -> Response {
    let v = match body(&r, request).await {
        Ok(v) => v,
        Err(refused) => return refused,
    };
    let index = match &v["scene"] {
        Value::Number(n) => n.as_u64().filter(|&i| i < r.catalogue.len() as u64),
        Value::String(name) => r.catalogue.find(name).map(|i| i as u64),
        _ => None,
    };
    match index {
        Some(i) => send(&r, Change::Scene(i as usize)).await,
        None => bad(format!(
            "expected {{\"scene\": index}} of one of the {} scenes /schema lists (or its name); \
             no other scene is opened",
            r.catalogue.len()
        )),
    }
}
