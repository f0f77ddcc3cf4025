//! The live preview of `penumbra render --preview`: a page on the loopback
//! address that shows the image refining pass by pass.
//!
//! The render driver publishes a [`Frame`] after each pass; the server keeps
//! the latest and tells every open page, which fetches the floats and
//! tone-maps them itself (exposure in stops, the sRGB curve), so the server
//! never converts an image. The page's Stop button sets the flag from
//! [`Preview::stop_requested`]; [`Preview::finish`] tells the pages that the
//! render ended.
//!
//! Routes (each needs the token and the server's own Host, see `security`):
//! - `GET /` the page;
//! - `GET /events` server-sent events: `frame` (JSON: seq, width, height,
//!   pass, passes, elapsed_s, rays, rays_per_s, eta_s, stats) and `end`
//!   (JSON: message, stopped);
//! - `GET /image` the latest frame: 16 bytes of header (`PNB1`, then width,
//!   height, pass as little-endian u32), then width x height x 3 little-endian
//!   f32, linear RGB, top row first; 204 before the first frame;
//! - `POST /stop` asks the render to stop after the current pass.

mod frame;
pub(crate) mod security;
pub(crate) mod server;
#[cfg(test)]
pub(crate) mod tests;

use std::fmt;
use std::io;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

pub use frame::Frame;
use server::{Server, Site};

/// The preview's page.
const SITE: Site = Site {
    title: "penumbra preview",
    body: include_str!("page.html"),
    css: "",
    js: include_str!("page.js"),
};

/// The address the preview binds unless told another.
pub const DEFAULT_BIND: IpAddr = IpAddr::V4(Ipv4Addr::LOCALHOST);

/// A running preview server. Dropping it shuts the server down.
pub struct Preview {
    server: Server,
}

/// The server could not start.
#[derive(Debug)]
pub struct PreviewError {
    pub addr: SocketAddr,
    pub source: io::Error,
}

impl fmt::Display for PreviewError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "cannot start the preview server on {}: {}",
            self.addr, self.source
        )
    }
}

impl std::error::Error for PreviewError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}

impl Preview {
    /// Starts serving on `bind:port` (port 0: any free port).
    pub fn start(bind: IpAddr, port: u16) -> Result<Preview, PreviewError> {
        let server = Server::start(bind, port, &SITE, server::stop_route).map_err(|source| {
            PreviewError {
                addr: SocketAddr::new(bind, port),
                source,
            }
        })?;
        Ok(Preview { server })
    }

    /// The address to open, token included.
    pub fn url(&self) -> String {
        self.server.url()
    }

    /// Shows `frame` to every page, open now or later.
    pub fn publish(&self, frame: Frame) {
        self.server.publish(&frame);
    }

    /// The flag the page's Stop button sets.
    pub fn stop_requested(&self) -> Arc<AtomicBool> {
        self.server.stop_flag()
    }

    /// Tells the pages that the render ended, with `message`.
    pub fn finish(&self, message: &str) {
        self.server.finish(message);
    }
}
