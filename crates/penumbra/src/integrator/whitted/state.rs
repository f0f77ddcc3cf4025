//! What a tile keeps between the passes of a render.

use serde::{Deserialize, Serialize};

use crate::integrator::stopping::Block;

/// What a tile keeps between passes.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub enum TileState {
    /// Nothing: every sample of every pixel is traced.
    #[default]
    Plain,
    /// Under the pixel metric: which pixels it stopped.
    Stopped(Vec<bool>),
    /// Under adaptive sampling: the rule's tallies and schedule.
    Adaptive(Box<Schedule>),
}

/// Where a tile is in the rule's schedule: its tallies, the rays of the
/// schedule done, and the end of the rule's pass in progress when a range
/// of the render ended within one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Schedule {
    pub block: Block,
    pub(super) done: u32,
    pub(super) pass_end: Option<u32>,
    pub(super) finished: bool,
}

impl Schedule {
    /// Whether the schedule's place is within a render of `spp` rays per
    /// pixel (a schedule read from a checkpoint).
    pub(super) fn fits(&self, spp: u32) -> bool {
        self.done <= spp && self.pass_end.is_none_or(|e| e <= spp)
    }
}
