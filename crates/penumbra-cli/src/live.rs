//! Where a render shows itself while it runs: the live preview page
//! (`--preview`) and the tev viewer (`--display-server`), both fed the
//! image after each pass and at the end. A viewer that goes away is
//! warned about once and then left alone; the render goes on.

use std::net::IpAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use clap::Args;
use std::time::Duration;

use penumbra::io::tev::TevClient;
use penumbra::render::{Ended, Image, PassView, RenderStats};

use crate::error::{input, CliError};
use crate::preview::{Frame, Preview, DEFAULT_BIND};

/// How long connecting to tev and each write to it may take.
const TEV_TIMEOUT: Duration = Duration::from_secs(5);

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Options of the live views of `penumbra render`.
#[derive(Args, Clone, Debug)]
pub struct LiveArgs {
    /// Serve a page showing the image refining pass by pass, its ray
    /// statistics and a Stop button, on this port (any free port when none
    /// is given); its address, with the run's token, is printed at start.
    #[arg(long, value_name = "PORT", num_args = 0..=1, default_missing_value = "0")]
    pub preview: Option<u16>,
    /// The address the preview listens on (loopback unless told).
    #[arg(long, value_name = "ADDR", default_value_t = DEFAULT_BIND, requires = "preview")]
    pub bind: IpAddr,
    /// Stream the image after each pass to the tev viewer listening at
    /// HOST:PORT (its network protocol; tev's port is 14158).
    #[arg(long, value_name = "HOST:PORT")]
    pub display_server: Option<String>,
}

/// The views of one render.
pub struct Live {
    preview: Option<Preview>,
    /// The tev connection and the image's name there, until it fails.
    tev: Mutex<Option<(TevClient, String)>>,
    stop: Arc<AtomicBool>,
    /// The passes finished and in all, as the last pass said.
    passes: Mutex<(u32, u32)>,
}

impl Live {
    /// Starts the views `args` ask for.
    pub fn start(args: &LiveArgs, image_name: &str) -> Result<Live, CliError> {
        let preview = match args.preview {
            Some(port) => {
                let p = Preview::start(args.bind, port).map_err(input)?;
                eprintln!("preview: {}", p.url());
                Some(p)
            }
            None => None,
        };
        let tev = match &args.display_server {
            Some(addr) => {
                let client = TevClient::connect(addr, TEV_TIMEOUT).map_err(input)?;
                Some((client, image_name.to_string()))
            }
            None => None,
        };
        let stop = preview
            .as_ref()
            .map_or_else(|| Arc::new(AtomicBool::new(false)), Preview::stop_requested);
        Ok(Live {
            preview,
            tev: Mutex::new(tev),
            stop,
            passes: Mutex::new((0, 1)),
        })
    }

    /// True if a view asked the render to stop.
    pub fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// True if any view wants the image after each pass.
    pub fn wants_passes(&self) -> bool {
        self.preview.is_some() || lock(&self.tev).is_some()
    }

    /// Shows the image after a pass.
    pub fn pass(&self, view: &PassView<'_>) {
        let elapsed = view.stats.render_time.as_secs_f64();
        *lock(&self.passes) = (view.pass, view.passes);
        let per_pass = elapsed / f64::from(view.pass.max(1));
        let eta = Some(per_pass * f64::from(view.passes.saturating_sub(view.pass)));
        self.show(view.image, view.stats, (view.pass, view.passes), eta);
    }

    /// Shows the final image and tells the views the render ended. A render
    /// ended early shows the passes it finished, not its last.
    pub fn finish(&self, image: &Image, stats: &RenderStats, message: &str) {
        let (done, passes) = *lock(&self.passes);
        let done = if stats.ended == Ended::Complete {
            passes
        } else {
            done
        };
        self.show(image, stats, (done, passes), Some(0.0));
        if let Some(p) = &self.preview {
            p.finish(message);
        }
    }

    fn show(
        &self,
        image: &Image,
        stats: &RenderStats,
        (pass, passes): (u32, u32),
        eta: Option<f64>,
    ) {
        let mut tev = lock(&self.tev);
        if let Some((client, name)) = tev.as_mut() {
            if let Err(e) = client.show(name, image) {
                eprintln!("warning: {e}; the render goes on without tev");
                *tev = None;
            }
        }
        drop(tev);
        let Some(p) = &self.preview else { return };
        let mut rgb = Vec::with_capacity(3 * image.pixels.len());
        for p in &image.pixels {
            rgb.extend_from_slice(&p.to_array());
        }
        p.publish(Frame {
            width: image.width,
            height: image.height,
            rgb,
            pass,
            passes,
            elapsed_s: stats.render_time.as_secs_f64(),
            rays: stats.rays.total(),
            stats: serde_json::to_value(stats.rays).unwrap_or_default(),
            eta_s: eta,
            info: serde_json::Value::Null,
        });
    }
}
