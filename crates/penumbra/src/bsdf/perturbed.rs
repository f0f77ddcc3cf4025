//! What [`normalmap`](super::normalmap) and [`bumpmap`](super::bumpmap)
//! share: a held model seen through a perturbed shading normal, as
//! Mitsuba 3's adapters do (its `PerturbedBSDF`, since version 3.7).
//!
//! Each model gives its perturbation `p`, a normal in the shading frame
//! (tangent `dp/du`, bitangent, normal). With `flip_invalid_normals`, a
//! perturbation facing away from the view (`wo` on opposite sides of the
//! shading normal and of `p`) is mirrored about the shading normal, `(−x,
//! −y, z)` (Schüssler et al. 2017). The held model is asked with the
//! interaction's shading normal replaced by `n' = normalize(p)` (its frame's
//! first tangent `dp/du` made orthogonal to `n'`; the geometric normal
//! kept). A direction `wi` is answered only where it lies on the same side
//! of both normals; `eval` is the held model's times `|wi·n'| / |wi·n|`, so
//! that a renderer multiplying it by the cosine to the interaction's own
//! shading normal `n` gets the held model's cosine to `n'`, as Mitsuba
//! (whose `eval` holds the cosine) does. With `use_shadowing_function`,
//! values and sample weights are also multiplied by the shadowing term of
//! Conty Estevez et al. 2019, `G = 2 / (1 + √(1 + α² tan²θi))` with
//! `α² = min(tan²θ' / 8, 1)` (θi of `wi` and θ' of `n'` to the shading
//! normal), which darkens light grazing a strongly tilted normal. A sample's
//! weight is then `eval · |cos| / pdf`, and `pdf` is the held model's.

use super::sample::BsdfSample;
use super::Bsdf;
use crate::description::{Invalid, Param, Props, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;

/// Mitsuba's two options of the perturbed models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    pub flip_invalid_normals: bool,
    pub use_shadowing_function: bool,
}

impl Options {
    /// Both on, Mitsuba's defaults.
    pub const DEFAULT: Options = Options {
        flip_invalid_normals: true,
        use_shadowing_function: true,
    };

    /// The options of a scene's parameters.
    pub fn read(p: &Props) -> Result<Options, Invalid> {
        Ok(Options {
            flip_invalid_normals: p.bool("flip_invalid_normals")?.unwrap_or(true),
            use_shadowing_function: p.bool("use_shadowing_function")?.unwrap_or(true),
        })
    }
}

/// The schema entries of the options.
pub const PARAMS: [Param; 2] = [
    Param::new(
        "flip_invalid_normals",
        Type::Bool,
        "true",
        "mirror a perturbed normal facing away from the view about the shading normal",
    ),
    Param::new(
        "use_shadowing_function",
        Type::Bool,
        "true",
        "darken light grazing a tilted normal (the microfacet shadowing of Conty Estevez et al. 2019)",
    ),
];

/// The perturbed normal at a point, for one view.
#[derive(Clone, Copy, Debug)]
pub struct Normal {
    /// In world space (unit).
    pub world: Vec3,
    /// In the shading frame (unit).
    pub local: Vec3,
}

/// The perturbed normal of the perturbation `p` (in the shading frame, any
/// length) seen from `wo`; the shading normal itself, exactly, for `p`
/// along the normal, or where `p` gives no direction.
pub fn normal(si: &SurfaceInteraction, wo: Vec3, p: Vec3, o: Options) -> Normal {
    let frame = si.shading_frame();
    let mut p = p;
    if o.flip_invalid_normals {
        let v = frame.to_local(wo);
        if v.z * v.dot(p) <= 0.0 {
            p = Vec3::new(-p.x, -p.y, p.z);
        }
    }
    let local = p.normalize_or_zero();
    if !local.is_finite() || local == Vec3::ZERO || local == Vec3::Z {
        return Normal {
            world: si.n,
            local: Vec3::Z,
        };
    }
    Normal {
        world: frame.to_world(local),
        local,
    }
}

/// The shadowing term for light from `wi` (world) under the normal `n`.
pub fn shadowing(si: &SurfaceInteraction, n: &Normal, wi: Vec3) -> f32 {
    let tan2 = |c: f32| (1.0 - c * c).max(0.0) / (c * c);
    let alpha2 = (0.125 * tan2(n.local.z)).min(1.0);
    if alpha2 <= 0.0 {
        return 1.0;
    }
    let c = wi.dot(si.n);
    let g = 2.0 / (1.0 + (1.0 + alpha2 * tan2(c)).sqrt());
    if g.is_finite() {
        g
    } else {
        0.0
    }
}

/// The interaction as the held model sees it: shading normal `n` (unit).
#[inline]
pub fn with_normal(si: &SurfaceInteraction, n: Vec3) -> SurfaceInteraction {
    SurfaceInteraction { n, ..*si }
}

/// True if `w` lies strictly on the same side of both normals.
#[inline]
fn same_side(si: &SurfaceInteraction, n: Vec3, w: Vec3) -> bool {
    w.dot(si.n) * w.dot(n) > 0.0
}

/// The held model's value through the normal `n`.
pub fn eval(
    bsdf: &Bsdf,
    si: &SurfaceInteraction,
    n: &Normal,
    o: Options,
    wo: Vec3,
    wi: Vec3,
) -> Rgb {
    if !same_side(si, n.world, wi) {
        return Rgb::ZERO;
    }
    let f = bsdf.eval(&with_normal(si, n.world), wo, wi);
    let g = if o.use_shadowing_function {
        shadowing(si, n, wi)
    } else {
        1.0
    };
    f * ((wi.dot(n.world) / wi.dot(si.n)).abs() * g)
}

/// The held model's density through the normal `n`.
pub fn pdf(bsdf: &Bsdf, si: &SurfaceInteraction, n: &Normal, wo: Vec3, wi: Vec3) -> f32 {
    if !same_side(si, n.world, wi) {
        return 0.0;
    }
    bsdf.pdf(&with_normal(si, n.world), wo, wi)
}

/// A sample of the held model through the normal `n`; `None` where the
/// direction drawn lies on opposite sides of the two normals.
pub fn sample(
    bsdf: &Bsdf,
    si: &SurfaceInteraction,
    n: &Normal,
    o: Options,
    wo: Vec3,
    lobe: Option<usize>,
    u: SetPoint,
) -> Option<BsdfSample> {
    let mut s = bsdf.sample(&with_normal(si, n.world), wo, lobe, u)?;
    if !same_side(si, n.world, s.wi) {
        return None;
    }
    if o.use_shadowing_function {
        s.weight *= shadowing(si, n, s.wi);
    }
    Some(s)
}

/// The [`BsdfModel`](super::BsdfModel) methods of a model that holds a
/// model `bsdf` (an `Arc<Bsdf>`) seen through the normal its
/// `self.normal(si, wo)` gives, with its `options`: its lobes, value,
/// density and samples are the held model's through that normal, and
/// shadow rays pass it as they pass the held model.
macro_rules! through_perturbed_normal {
    () => {
        /// Mitsuba's `eval_diffuse_reflectance`: the held model's, at the
        /// unperturbed interaction.
        fn diffuse_reflectance(
            &self,
            si: &$crate::geometry::SurfaceInteraction,
            wo: $crate::math::Vec3,
        ) -> $crate::math::Rgb {
            self.bsdf.diffuse_reflectance(si, wo)
        }

        fn lobes(&self) -> $crate::bsdf::Lobes {
            self.bsdf.lobes()
        }

        /// The perturbed normal (Mitsuba's `sh_frame`).
        fn shading_normal(
            &self,
            si: &$crate::geometry::SurfaceInteraction,
            wo: $crate::math::Vec3,
        ) -> $crate::math::Vec3 {
            self.normal(si, wo).world
        }

        fn eval(
            &self,
            si: &$crate::geometry::SurfaceInteraction,
            wo: $crate::math::Vec3,
            wi: $crate::math::Vec3,
        ) -> $crate::math::Rgb {
            let n = self.normal(si, wo);
            $crate::bsdf::perturbed::eval(&self.bsdf, si, &n, self.options, wo, wi)
        }

        fn sample(
            &self,
            si: &$crate::geometry::SurfaceInteraction,
            wo: $crate::math::Vec3,
            lobe: Option<usize>,
            u: $crate::sampling::SetPoint,
        ) -> Option<$crate::bsdf::BsdfSample> {
            let n = self.normal(si, wo);
            $crate::bsdf::perturbed::sample(&self.bsdf, si, &n, self.options, wo, lobe, u)
        }

        fn pdf(
            &self,
            si: &$crate::geometry::SurfaceInteraction,
            wo: $crate::math::Vec3,
            wi: $crate::math::Vec3,
        ) -> f32 {
            $crate::bsdf::perturbed::pdf(&self.bsdf, si, &self.normal(si, wo), wo, wi)
        }

        fn shadow_transmittance(&self, si: &$crate::geometry::SurfaceInteraction) -> f32 {
            self.bsdf.shadow_transmittance(si)
        }

        fn uniform_shadow_transmittance(&self) -> Option<f32> {
            self.bsdf.uniform_shadow_transmittance()
        }
    };
}
pub(super) use through_perturbed_normal;
