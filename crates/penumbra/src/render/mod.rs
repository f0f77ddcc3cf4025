//! The parallel render driver: tiles over a rayon pool, deterministic seeding,
//! progress reporting, and the guard that keeps NaN and infinity out of images.

pub mod checkpoint;
mod driver;
pub mod film;
mod grid;
mod outcome;
mod region;
mod report;

use std::sync::atomic::AtomicBool;

pub use checkpoint::{render_digest, CheckpointError, Digest, DigestInput};
pub use driver::{render_with, Checkpointing, PassView, Progressive};
pub use film::{ExtraChannels, Image};
pub use grid::frame;
pub use outcome::{Ended, Progress, RenderError, RenderOptions, RenderStats};
pub use region::Region;
pub use report::stats_document;

use crate::integrator::aov::Aov;
use crate::integrator::{Config, Integrator, RenderWith};
use crate::scene::Scene;

/// Renders the scene (or a region of it) with the integrator it chose and
/// returns the image with its statistics.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    progress: Progress<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<(Image, RenderStats), RenderError> {
    render_progressive(scene, opts, progress, cancel, &Progressive::default())
}

/// [`render`], progressively: ended early by a time limit or an
/// interrupt, the image shown after each pass, its state saved in
/// checkpoints and resumed from one, as `run` says.
pub fn render_progressive(
    scene: &Scene,
    opts: &RenderOptions,
    progress: Progress<'_>,
    cancel: Option<&AtomicBool>,
    run: &Progressive<'_>,
) -> Result<(Image, RenderStats), RenderError> {
    let config = Config::of(scene).map_err(|e| RenderError::Integrator(e.into()))?;
    config.render_with(
        scene,
        Render {
            scene,
            opts,
            progress,
            cancel,
            run,
        },
    )
}

/// A render of a scene with whichever integrator its [`Config`] makes.
struct Render<'a> {
    scene: &'a Scene,
    opts: &'a RenderOptions,
    progress: Progress<'a>,
    cancel: Option<&'a AtomicBool>,
    run: &'a Progressive<'a>,
}

impl RenderWith for Render<'_> {
    type Output = Result<(Image, RenderStats), RenderError>;

    fn render<I: Integrator>(self, integrator: &I) -> Self::Output {
        // An integrator writing channels of its own (`aov`, whose `N.A` is
        // the alpha, `moment`) writes them without the film's alpha.
        if self.scene.settings.alpha && integrator.channels().is_empty() {
            alpha_refused(integrator)?;
            return render_with(
                &Aov::alpha(self.scene, integrator),
                self.scene,
                self.opts,
                self.progress,
                self.cancel,
                self.run,
            );
        }
        render_with(
            integrator,
            self.scene,
            self.opts,
            self.progress,
            self.cancel,
            self.run,
        )
    }
}

/// Refuses the film's alpha channel with an integrator that cannot carry
/// it: one whose samples land anywhere (`ptracer`).
fn alpha_refused<I: Integrator>(integrator: &I) -> Result<(), RenderError> {
    if integrator.splats_anywhere() {
        return Err(RenderError::Alpha(
            "its samples land anywhere on the film, not in the pixel of a camera ray",
        ));
    }
    Ok(())
}
