//! Phase functions: how a medium scatters light at a point, the medium's
//! counterpart of a BSDF (Mitsuba 3's `PhaseFunction`).
//!
//! Every model answers through [`PhaseModel`], taking its random numbers as
//! arguments: its value for a pair of directions (`eval`, which is also the
//! density of `sample` drawing the second: the models here are sampled
//! exactly), and a direction drawn from a point of the unit square. Both
//! are asked at the scattering point `p` (world space), where a model
//! that varies through space (`blendphase`'s weight) looks itself up. The
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
//! | [`rayleigh`](rayleigh::Rayleigh) | scattering by particles much smaller than the wavelength, `3 (1 + cos² θ) / 16π` (Mitsuba 3's `rayleigh`) |
//! | [`tabphase`](tabphase::TabPhase) | a table of values over `cos θ`, linear between them, normalised (Mitsuba 3's `tabphase`) |
//! | [`blendphase`](blendphase::BlendPhase) | `(1 − weight) · phase_0 + weight · phase_1`, the weight a number or a volume (Mitsuba 3's `blendphase`) |

use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Props, Schema};
use crate::math::{Frame, Vec2, Vec3};
use crate::volume::Volumes;

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

    /// The model of a scene's parameters, checked for range, defaulted;
    /// its volume parameters read through `volumes` (the scene's named
    /// volumes, its folder).
    fn build(p: &Props, volumes: &Volumes) -> Result<Self, Invalid>;

    /// The value at the point `p` for light arriving along `−wo`'s ray and
    /// leaving toward `wi` (both unit), per steradian: also the density of
    /// [`sample`](Self::sample) drawing `wi`.
    fn eval(&self, p: Vec3, wo: Vec3, wi: Vec3) -> f32;

    /// A direction drawn at the point `p` with the point `u` of the unit
    /// square.
    fn sample(&self, p: Vec3, wo: Vec3, u: Vec2) -> Option<PhaseSample>;
}

/// The unit direction at the scattering angle of cosine `cos_theta` from
/// the ray's direction `−wo`, at the azimuth `2π u_phi` about it: how the
/// models turn a drawn angle into a direction.
#[inline]
pub(crate) fn scattered(wo: Vec3, cos_theta: f32, u_phi: f32) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (sin_phi, cos_phi) = (2.0 * std::f32::consts::PI * u_phi).sin_cos();
    let frame = Frame::from_normal(-wo);
    frame
        .to_world(Vec3::new(
            sin_theta * cos_phi,
            sin_theta * sin_phi,
            cos_theta,
        ))
        .normalize()
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
            pub fn build(name: &str, p: &Props, volumes: &Volumes) -> Option<Result<Phase, Invalid>> {
                match name {
                    $(<$module::$variant as PhaseModel>::NAME => Some(<$module::$variant>::build(p, volumes).map(Phase::$variant)),)*
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
            pub fn eval(&self, p: Vec3, wo: Vec3, wi: Vec3) -> f32 {
                match self {
                    $(Phase::$variant(m) => m.eval(p, wo, wi),)*
                }
            }

            /// See [`PhaseModel::sample`].
            #[inline]
            pub fn sample(&self, p: Vec3, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
                match self {
                    $(Phase::$variant(m) => m.sample(p, wo, u),)*
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
    rayleigh::Rayleigh,
    tabphase::TabPhase,
    blendphase::BlendPhase,
}
