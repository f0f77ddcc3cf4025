//! Participating media: what fills the space between surfaces (smoke,
//! fog, a glass of milk), as Mitsuba 3's `Medium`.
//!
//! A medium absorbs and scatters light along a ray by its coefficients
//! at each point: the extinction `σt`, the scattering `σs = albedo · σt`,
//! and, for a medium tracked against a *majorant* `σ̄ ≥ σt` (a bound of the
//! extinction over a stretch of the ray), the null coefficient
//! `σn = σ̄ − σt`, the share of fictitious collisions that change nothing.
//! Distances are drawn by delta tracking: a tentative collision at
//! `−ln(1 − u) / σ̄` along the ray ([`Medium::sample_interaction`]); at it,
//! the integrator chooses a real collision with probability `σt / σ̄`, a
//! null one (the path goes on unchanged) otherwise. A homogeneous medium
//! is the case `σ̄ = σt` everywhere: every collision is real. The
//! transmittance of a shadow segment is [`Medium::transmittance`]: the
//! exact `exp(−σt · d)` where the extinction is constant, else ratio
//! tracking (the product of `σn / σ̄` over the tentative collisions).
//!
//! A model answers through [`MediumModel`]: where along a ray it has any
//! density (`intersect_aabb`), its majorant over a stretch (`majorant`),
//! its coefficients at a point (`coefficients`), and whether it is
//! homogeneous and its extinction varies with colour. Delta tracking and
//! ratio tracking are written once, here, over those answers; a model
//! with a majorant grid (a heterogeneous medium) overrides
//! [`MediumModel::sample_interaction`] and [`MediumModel::transmittance`]
//! to walk its grid cell by cell, each cell's majorant its own.
//!
//! Every medium has a phase function ([`phase`]), `isotropic` unless its
//! description names one, and `sample_emitters` (next-event estimation at
//! its scattering points, Mitsuba's default `true`).
//!
//! | model | what |
//! |---|---|
//! | [`homogeneous`](homogeneous::Homogeneous) | the same extinction everywhere, the albedo a number, a colour or a volume (Mitsuba 3's `homogeneous`) |
//! | [`heterogeneous`](heterogeneous::Heterogeneous) | extinction and albedo read from volumes, tracked through a grid of majorants (Mitsuba 3's `heterogeneous`) |
//!
//! Shapes bound media (their `interior` and `exterior`), and the camera
//! may sit in one (its `medium`); the `volpath` integrator tracks paths
//! through them. Other integrators ignore media, as Mitsuba's do.

pub mod phase;

use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Param, Props, Range, Schema, Type};
use crate::math::{Rgb, Vec3};
use crate::sampling::Rng;
use crate::volume::Volumes;

pub use phase::{Phase, PhaseModel, PhaseSample};

/// The parameters every medium has (Mitsuba's `Medium` base class).
pub const COMMON: [Param; 1] = [Param::new(
    "sample_emitters",
    Type::Bool,
    "true",
    "next-event estimation at the medium's scattering points",
)];

/// `scale`, a parameter of every medium its model reads.
pub(super) const SCALE: Param = Param::new(
    "scale",
    Type::Number,
    "1",
    "multiplies `sigma_t` (a change of length unit)",
)
.range(Range::NonNegative);

/// `has_spectral_extinction`, a parameter of every medium its model reads.
pub(super) const SPECTRAL_EXTINCTION: Param = Param::new(
    "has_spectral_extinction",
    Type::Bool,
    "true",
    "distances are drawn by one colour channel and weighed by all (off: the extinction is \
     taken as grey, channel by channel ratios kept)",
);

/// A tentative collision of a ray in a medium, drawn by
/// [`Medium::sample_interaction`] (Mitsuba's `MediumInteraction3f`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interaction {
    /// The distance along the (unit) ray; infinite where none was drawn
    /// before the end of the segment.
    pub t: f32,
    /// The point.
    pub p: Vec3,
    /// Where the medium's stretch of the ray begins (its tracking starts
    /// there): 0 for a medium filling space.
    pub mint: f32,
    /// The coefficients at the point.
    pub sigma: Coefficients,
    /// The majorant the distance was drawn against (Mitsuba's
    /// `combined_extinction`).
    pub majorant: Rgb,
}

impl Interaction {
    /// True if a collision was drawn within the segment.
    #[inline]
    pub fn is_valid(&self) -> bool {
        self.t.is_finite()
    }
}

/// A medium's coefficients at a point, per unit length.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coefficients {
    /// Scattering.
    pub sigma_s: Rgb,
    /// Null (fictitious) collisions: the majorant less the extinction.
    pub sigma_n: Rgb,
    /// Extinction.
    pub sigma_t: Rgb,
}

/// The channel of an RGB value a path tracks distances by (Mitsuba's
/// `index_spectrum`).
#[inline]
pub fn channel_of(v: Rgb, channel: usize) -> f32 {
    v.to_array()[channel.min(2)]
}

/// What every medium model answers (see the [module docs](self)).
/// Directions are unit vectors, distances world lengths.
pub trait MediumModel: Sized {
    /// The name scenes select the model by.
    const NAME: &'static str;

    /// Its parameters, their types and defaults ([`COMMON`] among them).
    const SCHEMA: Schema;

    /// How Mitsuba's plugin of its name maps onto it.
    const MITSUBA: Mitsuba = Mitsuba::SAME;

    /// The model of a scene's parameters (but [`COMMON`]'s, which the
    /// medium reads), checked for range, defaulted; its volume parameters
    /// read through `volumes` (the scene's named volumes, its folder).
    fn build(p: &Props, volumes: &Volumes) -> Result<Self, Invalid>;

    /// The same extinction everywhere: a tentative collision is always a
    /// real one, and transmittance is exact.
    fn is_homogeneous(&self) -> bool;

    /// The extinction differs between colour channels (Mitsuba's
    /// `has_spectral_extinction`): distances are then drawn by one
    /// channel and weighed by the densities of all.
    fn has_spectral_extinction(&self) -> bool;

    /// The stretch `(mint, maxt)` of the ray from `o` along `d` where the
    /// medium has any density (`maxt` may be infinite); `None` where it
    /// misses it.
    fn intersect_aabb(&self, o: Vec3, d: Vec3) -> Option<(f32, f32)>;

    /// A bound of the extinction over the stretch of the ray around `p`
    /// that tracking crosses next (Mitsuba's `get_majorant`).
    fn majorant(&self, p: Vec3) -> Rgb;

    /// The coefficients at `p` against the majorant there
    /// (Mitsuba's `get_scattering_coefficients`).
    fn coefficients(&self, p: Vec3) -> Coefficients;

    /// A tentative collision along the ray from `o` along `d` before
    /// `tmax`, drawn with the number `u` against the majorant's channel
    /// `channel` (Mitsuba's `Medium::sample_interaction`): `t` infinite
    /// where the draw passes `tmax` or the medium's stretch.
    fn sample_interaction(
        &self,
        (o, d): (Vec3, Vec3),
        tmax: f32,
        u: f32,
        channel: usize,
    ) -> Interaction {
        let none = |mint: f32, majorant: Rgb| Interaction {
            t: f32::INFINITY,
            p: o,
            mint,
            sigma: Coefficients::default(),
            majorant,
        };
        let Some((mint, maxt)) = self.intersect_aabb(o, d) else {
            return none(0.0, Rgb::ZERO);
        };
        let (mint, maxt) = (mint.max(0.0), maxt.min(tmax));
        let majorant = self.majorant(o + d * mint);
        let m = channel_of(majorant, channel);
        let t = mint - (1.0 - u).ln() / m;
        if t.is_nan() || t > maxt {
            return none(mint, majorant);
        }
        let p = o + d * t;
        Interaction {
            t,
            p,
            mint,
            sigma: self.coefficients(p),
            majorant,
        }
    }

    /// The fraction of light kept along the ray from `o` along `d` over
    /// `[0, tmax]`: by default ratio tracking, an unbiased estimate from
    /// tentative collisions drawn by `rng` against the majorant's first
    /// channel, each multiplying it by `σn / σ̄` (with, for a majorant that
    /// differs by channel, each channel's exponential over the first's);
    /// a homogeneous model gives the exact `exp(−σt · tmax)`.
    fn transmittance(&self, (o, d): (Vec3, Vec3), tmax: f32, rng: &mut Rng) -> Rgb {
        // Each channel's exponential over the first's, over a length.
        let rescale = |m: Rgb, len: f32| {
            let m0 = channel_of(m, 0);
            m.map(|x| (-(x - m0) * len).exp())
        };
        let mut tr = Rgb::ONE;
        let mut from = 0.0f32;
        // A bound on the collisions a segment may take: a majorant far
        // above the extinction would otherwise loop long.
        for _ in 0..100_000 {
            let origin = o + d * from;
            let mi = self.sample_interaction((origin, d), tmax - from, rng.next_f32(), 0);
            if !mi.is_valid() {
                let len = self
                    .intersect_aabb(origin, d)
                    .map_or(0.0, |(a, b)| (b.min(tmax - from) - a.max(0.0)).max(0.0));
                return tr * rescale(mi.majorant, len);
            }
            let m0 = channel_of(mi.majorant, 0);
            tr *= rescale(mi.majorant, mi.t - mi.mint) * mi.sigma.sigma_n / m0;
            if tr.max_element().is_nan() || tr.max_element() <= 0.0 {
                return Rgb::ZERO;
            }
            from += mi.t;
        }
        tr
    }
}

/// Declares the models' modules and makes [`Model`] and its dispatch.
macro_rules! media {
    ($($module:ident::$variant:ident,)*) => {
        $(pub mod $module;)*

        /// A medium model: one of the models of this layer.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Model {
            $($variant($module::$variant),)*
        }

        impl Model {
            /// The names of the models, as scenes select them.
            pub const NAMES: &'static [&'static str] = &[$(<$module::$variant as MediumModel>::NAME,)*];

            /// The models' parameters.
            pub const SCHEMAS: &'static [&'static Schema] = &[$(&<$module::$variant as MediumModel>::SCHEMA,)*];

            /// The models as the readers see them.
            pub const PLUGINS: &'static [Plugin] = &[$(Plugin::new(&<$module::$variant as MediumModel>::SCHEMA, <$module::$variant as MediumModel>::MITSUBA),)*];

            /// The model `name` of the parameters `p`; `None` for a name
            /// that is not a model's.
            pub fn build(name: &str, p: &Props, volumes: &Volumes) -> Option<Result<Model, Invalid>> {
                match name {
                    $(<$module::$variant as MediumModel>::NAME => Some(<$module::$variant>::build(p, volumes).map(Model::$variant)),)*
                    _ => None,
                }
            }

            /// The model's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Model::$variant(_) => <$module::$variant as MediumModel>::NAME,)*
                }
            }

            #[inline]
            pub fn is_homogeneous(&self) -> bool {
                match self {
                    $(Model::$variant(m) => m.is_homogeneous(),)*
                }
            }

            #[inline]
            pub fn has_spectral_extinction(&self) -> bool {
                match self {
                    $(Model::$variant(m) => m.has_spectral_extinction(),)*
                }
            }

            #[inline]
            pub fn sample_interaction(&self, ray: (Vec3, Vec3), tmax: f32, u: f32, channel: usize) -> Interaction {
                match self {
                    $(Model::$variant(m) => m.sample_interaction(ray, tmax, u, channel),)*
                }
            }

            #[inline]
            pub fn transmittance(&self, ray: (Vec3, Vec3), tmax: f32, rng: &mut Rng) -> Rgb {
                match self {
                    $(Model::$variant(m) => m.transmittance(ray, tmax, rng),)*
                }
            }
        }
    };
}

// The models: one line each.
media! {
    homogeneous::Homogeneous,
    heterogeneous::Heterogeneous,
}

/// A medium of the scene: its model, its phase function and whether its
/// scattering points sample the emitters.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    pub model: Model,
    pub phase: Phase,
    /// Next-event estimation at the medium's scattering points.
    pub sample_emitters: bool,
}

impl Medium {
    /// The names, schemas and plugins of the models.
    pub const NAMES: &'static [&'static str] = Model::NAMES;
    pub const SCHEMAS: &'static [&'static Schema] = Model::SCHEMAS;
    pub const PLUGINS: &'static [Plugin] = Model::PLUGINS;

    /// The medium `name` of the parameters `p` with the phase function
    /// `phase`, its volumes read through `volumes`; `None` for a name that
    /// is not a model's.
    pub fn build(
        name: &str,
        p: &Props,
        phase: Phase,
        volumes: &Volumes,
    ) -> Option<Result<Medium, Invalid>> {
        let model = Model::build(name, p, volumes)?;
        Some(model.and_then(|model| {
            Ok(Medium {
                model,
                phase,
                sample_emitters: p.bool("sample_emitters")?.unwrap_or(true),
            })
        }))
    }

    /// See [`MediumModel::is_homogeneous`].
    #[inline]
    pub fn is_homogeneous(&self) -> bool {
        self.model.is_homogeneous()
    }

    /// See [`MediumModel::has_spectral_extinction`].
    #[inline]
    pub fn has_spectral_extinction(&self) -> bool {
        self.model.has_spectral_extinction()
    }

    /// See [`MediumModel::sample_interaction`].
    #[inline]
    pub fn sample_interaction(
        &self,
        ray: (Vec3, Vec3),
        tmax: f32,
        u: f32,
        channel: usize,
    ) -> Interaction {
        self.model.sample_interaction(ray, tmax, u, channel)
    }

    /// See [`MediumModel::transmittance`].
    #[inline]
    pub fn transmittance(&self, ray: (Vec3, Vec3), tmax: f32, rng: &mut Rng) -> Rgb {
        self.model.transmittance(ray, tmax, rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::{Kind, Schema};

    /// A medium whose extinction varies along z (`σt = a + b·z` for z in
    /// [0, 1], none elsewhere), tracked against the constant majorant
    /// `a + b` over its slab: the shape of a heterogeneous medium, through
    /// the tracking written once in [`MediumModel`].
    struct Ramp {
        a: f32,
        b: f32,
    }

    impl MediumModel for Ramp {
        const NAME: &'static str = "ramp";
        const SCHEMA: Schema = Schema {
            kind: Kind::Medium,
            plugin: "ramp",
            what: "",
            doc: "",
            mitsuba: &[],
            params: &[],
        };

        fn build(_: &Props, _: &Volumes) -> Result<Ramp, Invalid> {
            unreachable!()
        }

        fn is_homogeneous(&self) -> bool {
            false
        }

        fn has_spectral_extinction(&self) -> bool {
            false
        }

        /// The slab 0 ≤ z ≤ 1, for a ray going up.
        fn intersect_aabb(&self, o: Vec3, d: Vec3) -> Option<(f32, f32)> {
            (d.z > 0.0).then(|| (-o.z / d.z, (1.0 - o.z) / d.z))
        }

        fn majorant(&self, _p: Vec3) -> Rgb {
            Rgb::splat(self.a + self.b)
        }

        fn coefficients(&self, p: Vec3) -> Coefficients {
            let t = Rgb::splat(self.a + self.b * p.z.clamp(0.0, 1.0));
            Coefficients {
                sigma_s: t * 0.5,
                sigma_n: self.majorant(p) - t,
                sigma_t: t,
            }
        }
    }

    /// Delta tracking against the majorant (real collisions kept with
    /// probability σt / σ̄, null ones passed) stops a ray before height h
    /// with probability `1 − exp(−∫₀ʰ σt)`; ratio tracking's estimate of the
    /// transmittance through the slab averages `exp(−∫₀¹ σt)`; the
    /// tentative collisions land only inside the medium's stretch, with
    /// the coefficients at their point.
    #[test]
    fn delta_and_ratio_tracking_follow_the_optical_depth() {
        let m = Ramp { a: 0.5, b: 2.0 };
        let (o, d) = (Vec3::new(0.0, 0.0, -1.0), Vec3::Z);
        let depth = |h: f32| m.a * h + 0.5 * m.b * h * h;
        let mut rng = Rng::new(17);
        let n = 200_000;
        let (mut before_half, mut nulls) = (0usize, 0usize);
        for _ in 0..n {
            let mut from = 0.0f32;
            loop {
                let mi = m.sample_interaction((o + d * from, d), 10.0 - from, rng.next_f32(), 0);
                if !mi.is_valid() {
                    break;
                }
                let z = mi.p.z;
                assert!((-1e-5..=1.0 + 1e-5).contains(&z), "{z}");
                assert_eq!(mi.sigma, m.coefficients(mi.p));
                let t = from + mi.t;
                if rng.next_f32() < mi.sigma.sigma_t.r / mi.majorant.r {
                    before_half += usize::from(z < 0.5);
                    break;
                }
                nulls += 1;
                from = t;
            }
        }
        let want = 1.0 - (-depth(0.5)).exp();
        let got = before_half as f32 / n as f32;
        let sd = (want * (1.0 - want) / n as f32).sqrt();
        assert!((got - want).abs() < 4.0 * sd, "{got} vs {want}");
        assert!(nulls > n / 10, "{nulls} null collisions");
        let (mut sum, mut sq) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let tr = f64::from(m.transmittance((o, d), 3.0, &mut rng).r);
            sum += tr;
            sq += tr * tr;
        }
        let mean = sum / n as f64;
        let se = ((sq / n as f64 - mean * mean) / n as f64).sqrt();
        let want = f64::from((-depth(1.0)).exp());
        assert!((mean - want).abs() < 4.0 * se, "{mean} ± {se} vs {want}");
    }
}
