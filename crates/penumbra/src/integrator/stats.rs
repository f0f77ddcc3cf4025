use std::ops::AddAssign;

use serde::Serialize;

/// Counts of rays by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
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
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    /// Rays a set would have traced but the metric stopped (direct members of
    /// the set only: what their descendants would have cost is unknowable).
    pub saved: RayCounts,
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
    }
}
