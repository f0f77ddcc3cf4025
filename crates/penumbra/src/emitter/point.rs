//! `point`: a point light of `intensity` (W/sr per channel) in every
//! direction. It has no surface: its one shadow ray goes to its position,
//! under both penumbra models.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `position` | vector | **required** | where it is |
//! | `intensity` | colour ≥ 0 | **required** | radiant intensity |

use super::sample::LightSample;
use crate::math::{Rgb, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub position: Vec3,
    pub intensity: Rgb,
}

impl Point {
    /// The shadow ray's target and the irradiance weight `I / r²` at `p`.
    #[inline]
    pub(super) fn sample(&self, p: Vec3) -> Option<LightSample> {
        let to = self.position - p;
        let r2 = to.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        Some(LightSample {
            target: self.position,
            dir: to.normalize_or_zero(),
            weight: self.intensity / r2,
        })
    }
}
