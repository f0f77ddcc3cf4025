use std::ops::AddAssign;

use serde::{Deserialize, Serialize};

/// Counts of rays by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RayCounts {
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection + self.refraction
    }
}

impl AddAssign for RayCounts {
    fn add_assign(&mut self, o: RayCounts) {
        self.primary += o.primary;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
    }
}

/// Rays traced, by kind, and the rays of their sets that the metrics skipped.
/// Counted in a per-worker value and merged with `+=` (never a shared counter
/// in the hot path); the thesis evaluates everything by these counts
/// (Tables 4.1–4.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    /// Rays a set would have traced but the metric stopped (direct members of
    /// the set only: what their descendants would have cost is unknowable).
    pub saved: RayCounts,
    /// The collisions paths met in participating media (`volpath`, `volpathmis`).
    pub media: MediumEvents,
}

/// The collisions drawn in participating media: real ones (a path
/// scattered, or was absorbed) and null ones (a collision against the
/// majorant that changed nothing: where the majorant exceeds the
/// extinction).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MediumEvents {
    pub scatterings: u64,
    pub null_collisions: u64,
    /// The rays leaving real collisions in directions drawn from the
    /// phase function: one per scattering under `volpath`, a set under
    /// `distributed`.
    pub scattered: u64,
    /// The phase directions of sets the reflection metric stopped, left
    /// untraced (`distributed`).
    pub saved: u64,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection + self.refraction
    }
}

impl AddAssign for RayStats {
    fn add_assign(&mut self, o: RayStats) {
        self.primary += o.primary;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.saved += o.saved;
        self.media.scatterings += o.media.scatterings;
        self.media.null_collisions += o.media.null_collisions;
        self.media.scattered += o.media.scattered;
        self.media.saved += o.media.saved;
    }
}

/// Calls of one stage of the wavefront and the items they took.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Batches {
    pub calls: u64,
    pub items: u64,
}

impl Batches {
    /// Counts one call over `items` items.
    #[inline]
    pub fn add(&mut self, items: usize) {
        self.calls += 1;
        self.items += items as u64;
    }

    /// The mean items per call (0 without calls).
    pub fn mean(&self) -> f64 {
        if self.calls == 0 {
            0.0
        } else {
            self.items as f64 / self.calls as f64
        }
    }
}

impl AddAssign for Batches {
    fn add_assign(&mut self, o: Batches) {
        self.calls += o.calls;
        self.items += o.items;
    }
}

/// The batches of the wavefront's stages: closest-hit calls and their
/// rays, occlusion calls and their shadow rays, shading calls (one per
/// material a bounce meets) and their vertices. They depend on the tiles
/// and passes a frame is cut into, unlike the ray counts; all zero for an
/// integrator that traces ray by ray (`whitted`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageBatches {
    pub closest_hit: Batches,
    pub occlusion: Batches,
    pub shading: Batches,
}

impl AddAssign for StageBatches {
    fn add_assign(&mut self, o: StageBatches) {
        self.closest_hit += o.closest_hit;
        self.occlusion += o.occlusion;
        self.shading += o.shading;
    }
}
