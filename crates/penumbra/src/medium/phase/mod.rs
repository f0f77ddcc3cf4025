//! Phase functions: how a medium scatters light at a point, the medium's
//! counterpart of a BSDF (Mitsuba 3's `PhaseFunction`).
//!
//! Every model answers through [`PhaseModel`], taking its random numbers as
//! arguments: its value for a pair of directions (`eval`, which is also the
//! density of `sample` drawing the second: the models here are sampled
//! exactly), and a direction drawn from a point of the unit square. The
//! directions are world vectors: `wo` points back along the ray that
//! reached the point (toward the viewer), `wi` is the direction the path
//! goes on in; the angle θ between the ray's direction `−wo` and `wi` is
//! the scattering angle (θ = 0: straight on).
//!
//! The models form a closed enum, [`Phase`], made by the `phases!` list at
//! the end of this file.
//!
//! | model | what |
//! |---|---|
//! | [`isotropic`](isotropic::Isotropic) | every direction alike, `1/4π` (Mitsuba 3's `isotropic`) |
//! | [`hg`](hg::Hg) | Henyey and Greenstein's lobe of mean cosine `g` (Mitsuba 3's `hg`) |

use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Props, Schema};
use crate::math::{Vec2, Vec3};

#[cfg(test)]
mod chi2;

/// A direction drawn by [`Phase::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample {
    /// The unit direction the path goes on in.
    pub wi: Vec3,
    /// `eval / pdf`: 1 for the exactly sampled models here.
    pub weight: f32,
    /// The solid-angle density of drawing `wi`.
    pub pdf: f32,
}

/// What every phase function answers (see the [module docs](self)).
pub trait PhaseModel: Sized {
    /// The name scenes select the model by.
    const NAME: &'static str;

    /// Its parameters, their types and defaults.
    const SCHEMA: Schema;

    /// How Mitsuba's plugin of its name maps onto it.
    const MITSUBA: Mitsuba = Mitsuba::SAME;

    /// The model of a scene's parameters, checked for range, defaulted.
    fn build(p: &Props) -> Result<Self, Invalid>;

    /// The value for light arriving along `−wo`'s ray and leaving toward
    /// `wi` (both unit), per steradian: also the density of
    /// [`sample`](Self::sample) drawing `wi`.
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32;

    /// A direction drawn with the point `u` of the unit square.
    fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample>;
}

/// Declares the models' modules, and makes [`Phase`] and its dispatch.
macro_rules! phases {
    ($($module:ident::$variant:ident,)*) => {
        $(pub mod $module;)*

        /// A phase function: one of the models of this layer.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Phase {
            $($variant($module::$variant),)*
        }

        impl Phase {
            /// The names of the models, as scenes select them.
            pub const NAMES: &'static [&'static str] = &[$(<$module::$variant as PhaseModel>::NAME,)*];

            /// The models' parameters.
            pub const SCHEMAS: &'static [&'static Schema] = &[$(&<$module::$variant as PhaseModel>::SCHEMA,)*];

            /// The models as the readers see them.
            pub const PLUGINS: &'static [Plugin] = &[$(Plugin::new(&<$module::$variant as PhaseModel>::SCHEMA, <$module::$variant as PhaseModel>::MITSUBA),)*];

            /// The model `name` of the parameters `p`; `None` for a name
            /// that is not a model's.
            pub fn build(name: &str, p: &Props) -> Option<Result<Phase, Invalid>> {
                match name {
                    $(<$module::$variant as PhaseModel>::NAME => Some(<$module::$variant>::build(p).map(Phase::$variant)),)*
                    _ => None,
                }
            }

            /// The model's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Phase::$variant(_) => <$module::$variant as PhaseModel>::NAME,)*
                }
            }

            /// See [`PhaseModel::eval`].
            #[inline]
            pub fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
                match self {
                    $(Phase::$variant(m) => m.eval(wo, wi),)*
                }
            }

            /// See [`PhaseModel::sample`].
            #[inline]
            pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
                match self {
                    $(Phase::$variant(m) => m.sample(wo, u),)*
                }
            }
        }
    };
}

/// The phase function a medium has when it names none.
pub const DEFAULT: &str = "isotropic";

impl Default for Phase {
    fn default() -> Phase {
        Phase::Isotropic(isotropic::Isotropic)
    }
}

// The models: one line each.
phases! {
    isotropic::Isotropic,
    hg::Hg,
}
