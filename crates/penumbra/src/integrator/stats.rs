use std::ops::AddAssign;

use serde::Serialize;

/// Rays traced, by kind. Counted in a per-worker value and merged with `+=`
/// (never a shared counter in the hot path); the thesis evaluates everything
/// by these counts (Tables 4.1–4.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
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
    }
}
