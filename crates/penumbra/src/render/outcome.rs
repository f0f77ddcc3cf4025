//! What a render is asked (its options and progress callback) and what it
//! gives back: its statistics, or why it failed.

use std::time::Duration;

use serde::Serialize;

use super::checkpoint::CheckpointError;
use super::region::Region;
use crate::description::SceneError;
use crate::integrator::stopping::PixelSamples;
use crate::integrator::{BadSample, RayStats, StageBatches};

/// How to run a render (what to render is the scene's business).
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Render only this part of the frame (pixels keep their full-frame
    /// values); `None` renders the scene's crop window, the whole frame
    /// when it has none.
    pub region: Option<Region>,
}

/// What a render measured.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RenderStats {
    pub rays: RayStats,
    /// The mean batches of the wavefront's stages (see [`StageBatches`]).
    pub batches: StageBatches,
    pub render_time: Duration,
    pub threads: usize,
    /// Number of non-finite samples discarded, and the first few of them.
    pub bad_samples: u64,
    pub first_bad_samples: Vec<BadSample>,
    /// With adaptive sampling, how each pixel of the rendered region ended
    /// (its camera rays, the calibrated rule's interval), row by row; empty
    /// without it.
    #[serde(skip)]
    pub pixel_samples: Vec<PixelSamples>,
    /// How the render ended: every pass done, or early.
    pub ended: Ended,
    /// Why a checkpoint could not be saved (the first failure), if one
    /// could not: the render goes on and its image is made all the same.
    #[serde(skip)]
    pub checkpoint_error: Option<String>,
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("cannot start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
    #[error("region [{x0}, {x1}) x [{y0}, {y1}) is empty or outside the {1}x{2} image", x0 = .0.x0, x1 = .0.x1, y0 = .0.y0, y1 = .0.y1)]
    Region(Region, u32, u32),
    #[error("render cancelled")]
    Cancelled,
    /// A checkpoint could not be resumed or saved.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    /// The scene's integrator does not read (a description changed after
    /// the scene was built).
    #[error("{0}")]
    Integrator(SceneError),
    /// The film asks for an alpha channel the integrator cannot give.
    #[error("the film's `alpha` (Mitsuba's `pixel_format` `rgba`) is not supported with this integrator: {0}")]
    Alpha(&'static str),
}

/// Progress callback: (tiles done, tiles in all).
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// How a render ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Ended {
    /// Every pass of every tile.
    #[default]
    Complete,
    /// At its time limit.
    TimeLimit,
    /// Interrupted.
    Interrupted,
}
