//! A light as the scene describes it: its shape, power, penumbra model and
//! shadow-ray budget; validated, no behaviour. The emitter
//! layer samples and evaluates it.

use super::material::EffectSpec;
use crate::geometry::quad::Quad;
use crate::math::{Frame, Rgb, Vec3};

/// How shadow rays toward an area light are aimed and weighted (see the
/// emitter module).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PenumbraModel {
    Thesis,
    Surface,
}

#[derive(Clone, Copy, Debug)]
pub enum LightShape {
    /// Emits `intensity` (W/sr per channel) in every direction.
    Point {
        position: Vec3,
    },
    /// One-sided parallelogram emitting along its normal.
    Rect(Quad),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// One-sided disk emitting along `frame.n`.
    Disk {
        center: Vec3,
        frame: Frame,
        radius: f32,
    },
}

#[derive(Clone, Debug)]
pub struct Light {
    pub shape: LightShape,
    /// Intensity for a point light, radiance for area lights.
    pub power: Rgb,
    pub model: PenumbraModel,
    pub shadow: EffectSpec,
}

impl Light {
    /// A point light has no extent: every shadow ray toward it is the same.
    pub fn is_delta(&self) -> bool {
        matches!(self.shape, LightShape::Point { .. })
    }
}
