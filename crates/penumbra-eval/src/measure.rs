//! What one render measured, in the form the tables print.

use serde::Serialize;

use crate::runner::Rendered;

/// Ray counts by kind, the time they took, and the frame they were rendered at.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    pub total: u64,
    /// Rays the metric skipped (direct members of sets only).
    pub saved: u64,
    pub time_s: f64,
    pub mrays_per_s: f64,
    pub width: u32,
    pub height: u32,
    /// `total` scaled by pixel count to the thesis's 800×600 frame.
    pub total_at_thesis_size: f64,
}

impl Measurement {
    pub fn of(r: &Rendered) -> Measurement {
        let rays = &r.stats.rays;
        let total = rays.total();
        let time_s = r.time().as_secs_f64();
        Measurement {
            primary: rays.primary,
            shadow: rays.shadow,
            reflection: rays.reflection,
            refraction: rays.refraction,
            total,
            saved: rays.saved.total(),
            time_s,
            mrays_per_s: if time_s > 0.0 {
                total as f64 / time_s / 1e6
            } else {
                0.0
            },
            width: r.frame.0,
            height: r.frame.1,
            total_at_thesis_size: total as f64 * r.scale_to_thesis(),
        }
    }

    /// True if the counts had to be scaled to compare with the thesis.
    pub fn is_scaled(&self) -> bool {
        (self.width, self.height) != (800, 600)
    }
}

/// Percent of `without` saved by `with`.
pub fn reduction(with: f64, without: f64) -> f64 {
    if without > 0.0 {
        100.0 * (1.0 - with / without)
    } else {
        0.0
    }
}
