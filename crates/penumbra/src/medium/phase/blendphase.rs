//! `blendphase`: a linear blend of two phase functions (Mitsuba 3's
//! `blendphase`), `(1 − weight) · phase_0 + weight · phase_1`: weight 0 is
//! `phase_0` alone, 1 is `phase_1` alone. The weight is a number or a
//! volume looked up (as one value, Mitsuba's `eval_1`) at the scattering
//! point and clipped to [0, 1]: a mixture of particles that varies through
//! the medium (aerosols in a Rayleigh-scattering sky, say).
//!
//! `sample` picks `phase_1` with probability `weight` by the first
//! coordinate of its point, stretches that coordinate back over [0, 1)
//! for the picked model, and draws from it; the direction's density is the
//! blend of both densities, as its value is the blend of both values (the
//! models here are sampled exactly, so the two are equal and the weight
//! is 1).
//!
//! The held phase functions are tables (`phase_0 = { type = "hg", g = 0.5
//! }`), themselves any phase function, a blend among them; Mitsuba XML's
//! two nested `<phase>`s set them, in order.

use super::{Phase, PhaseModel, PhaseSample};
use crate::description::mitsuba::Mitsuba;
use crate::description::schema::{checked_table, typed_table};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type, Value};
use crate::math::{Rgb, Vec2, Vec3};
use crate::volume::{Volume, Volumes};

/// The blend (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct BlendPhase {
    /// The share of `phase_1`, looked up as one value.
    pub weight: Box<Volume>,
    pub phase_0: Box<Phase>,
    pub phase_1: Box<Phase>,
}

impl BlendPhase {
    /// The share of `phase_1` at `p`, clipped to [0, 1].
    #[inline]
    pub fn weight(&self, p: Vec3) -> f32 {
        let w = self.weight.eval_1(p);
        if w.is_nan() {
            0.0
        } else {
            w.clamp(0.0, 1.0)
        }
    }
}

/// The phase function the table `name` of `p` holds, built and checked
/// against its schema.
fn held(p: &Props, name: &str, volumes: &Volumes) -> Result<Phase, Invalid> {
    let Some(prop) = p.get(name) else {
        return Err(p.node_error(format!(
            "missing field `{name}` (the table of a phase function it blends)"
        )));
    };
    let v = &prop.value;
    let Value::Table(props) = &v.value else {
        return Err(v.type_error("a phase function's table"));
    };
    let (plugin, at, rest) = typed_table(props, &v.origin, Kind::Phase)?;
    let (node, schema) = checked_table(Kind::Phase, Phase::SCHEMAS, (plugin, at), &rest, &v.origin)?;
    let pp = Props::new(&node);
    let phase = Phase::build(plugin, &pp, volumes).expect("every schema has a builder")?;
    pp.finish(schema.what)?;
    Ok(phase)
}

impl PhaseModel for BlendPhase {
    const NAME: &'static str = "blendphase";

    const SCHEMA: Schema = Schema {
        kind: Kind::Phase,
        plugin: "blendphase",
        what: "blended phase function",
        doc: "a linear blend of two phase functions, by a weight that may vary through space",
        mitsuba: &["blendphase"],
        params: &[
            Param::new(
                "weight",
                Type::Volume,
                "0.5",
                "the share of `phase_1` (0: `phase_0` alone, 1: `phase_1` alone): a number in \
                 [0, 1], or a volume read as one value at the scattering point, clipped to [0, 1]",
            ),
            Param::new(
                "phase_0",
                Type::Phase,
                "required",
                "the first phase function, a table: `{ type = \"isotropic\" }`",
            ),
            Param::new(
                "phase_1",
                Type::Phase,
                "required",
                "the second phase function, a table: `{ type = \"hg\", g = 0.5 }`",
            ),
        ],
    };

    const MITSUBA: Mitsuba = Mitsuba::differs(
        "`weight` is a float or a volume, not a texture; without one it is 0.5 (as Mitsuba's \
         docs say; its code requires it); a plain `weight` outside [0, 1] is refused rather \
         than clipped",
    );

    fn build(p: &Props, volumes: &Volumes) -> Result<BlendPhase, Invalid> {
        let weight = volumes.volume(p, "weight", Rgb::splat(0.5))?;
        if let Some(prop) = p.get("weight") {
            if !matches!(prop.value.value, Value::Table(_) | Value::String(_))
                && weight.max() > 1.0
            {
                return Err(p.error(
                    "weight",
                    format!("must be between 0 and 1, got {}", weight.max()),
                ));
            }
        }
        Ok(BlendPhase {
            weight: Box::new(weight),
            phase_0: Box::new(held(p, "phase_0", volumes)?),
            phase_1: Box::new(held(p, "phase_1", volumes)?),
        })
    }

    #[inline]
    fn eval(&self, p: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        let w = self.weight(p);
        (1.0 - w) * self.phase_0.eval(p, wo, wi) + w * self.phase_1.eval(p, wo, wi)
    }

    fn sample(&self, p: Vec3, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let w = self.weight(p);
        let (picked, x) = if u.x < w {
            (&self.phase_1, u.x / w)
        } else {
            (&self.phase_0, (u.x - w) / (1.0 - w))
        };
        let x = x.clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        let s = picked.sample(p, wo, Vec2::new(x, u.y))?;
        let pdf = self.eval(p, wo, s.wi);
        (pdf > 0.0).then_some(PhaseSample {
            wi: s.wi,
            weight: 1.0,
            pdf,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::phase::chi2::{check_phase, check_phase_at, views};
    use crate::medium::phase::hg::Hg;
    use crate::medium::phase::isotropic::Isotropic;
    use crate::medium::phase::rayleigh::Rayleigh;
    use crate::medium::phase::tabphase::TabPhase;
    use crate::sampling::Rng;

    fn blend(weight: Volume, a: Phase, b: Phase) -> BlendPhase {
        BlendPhase {
            weight: Box::new(weight),
            phase_0: Box::new(a),
            phase_1: Box::new(b),
        }
    }

    fn hg(g: f32) -> Phase {
        Phase::Hg(Hg { g })
    }

    /// Weight 0 is `phase_0` and weight 1 `phase_1`, value for value and
    /// draw for draw (the stretched coordinate is the one drawn with).
    #[test]
    fn the_ends_are_the_components() {
        let (a, b) = (hg(0.7), Phase::Rayleigh(Rayleigh));
        let mut rng = Rng::new(4);
        for (w, one) in [(0.0, &a), (1.0, &b)] {
            let m = blend(Volume::constant(Rgb::splat(w)), a.clone(), b.clone());
            for wo in views() {
                for _ in 0..200 {
                    let u = Vec2::new(rng.next_f32(), rng.next_f32());
                    let s = m.sample(Vec3::ZERO, wo, u).unwrap();
                    let want = one.sample(Vec3::ZERO, wo, u).unwrap();
                    assert!((s.wi - want.wi).length() < 1e-6, "{s:?} vs {want:?}");
                    // The blend's density is looked up at the direction,
                    // the component's at its drawn angle: f32 apart.
                    assert!((s.pdf - want.pdf).abs() <= 1e-3 * want.pdf, "{s:?} vs {want:?}");
                    let v = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 0.3).normalize();
                    let (got, want) = (m.eval(Vec3::ZERO, wo, v), one.eval(Vec3::ZERO, wo, v));
                    assert!((got - want).abs() <= 1e-6 * want, "{got} vs {want}");
                }
            }
        }
    }

    /// Blends of a peaked and a flat, of a forward and a backward lobe, of
    /// a table and a blend: the sampler against the blended density by
    /// χ², which integrates to 1.
    #[test]
    fn samples_follow_the_blend() {
        let table = Phase::TabPhase(TabPhase::new(&[4.0, 0.5, 0.0, 1.0, 2.0]).unwrap());
        let inner = Phase::BlendPhase(blend(
            Volume::constant(Rgb::splat(0.5)),
            hg(-0.6),
            Phase::Isotropic(Isotropic),
        ));
        for m in [
            blend(Volume::constant(Rgb::splat(0.3)), Phase::Isotropic(Isotropic), hg(0.9)),
            blend(Volume::constant(Rgb::new(0.2, 0.5, 0.8)), hg(0.8), hg(-0.5)),
            blend(Volume::constant(Rgb::splat(0.75)), table, inner),
        ] {
            for wo in views() {
                check_phase(&m, wo);
            }
        }
    }

    /// A weight that varies through space (a grid whose two halves along
    /// x hold 0.1 and 0.9, looked up nearest): in each half the blend of
    /// that weight, sampled so.
    #[test]
    fn a_weight_volume_is_looked_up_at_the_point() {
        use crate::texture::bitmap::Wrap;
        use crate::volume::gridvolume::{Filter, GridVolume};
        use crate::volume::vol_file::VolGrid;
        let grid = VolGrid {
            resolution: [2, 1, 1],
            channels: 1,
            bbox: crate::math::Aabb::new(Vec3::ZERO, Vec3::ONE),
            data: vec![0.1, 0.9],
        };
        let weight = Volume::GridVolume(GridVolume::new(
            std::sync::Arc::new(grid),
            Filter::Nearest,
            Wrap::Clamp,
            crate::math::Mat4::IDENTITY,
        ));
        let m = blend(weight, Phase::Isotropic(Isotropic), hg(0.8));
        let (left, right) = (Vec3::new(0.25, 0.5, 0.5), Vec3::new(0.75, 0.5, 0.5));
        assert!((m.weight(left) - 0.1).abs() < 1e-6);
        assert!((m.weight(right) - 0.9).abs() < 1e-6);
        let wo = Vec3::Z;
        let ahead = -wo;
        let iso = 0.25 * std::f32::consts::FRAC_1_PI;
        let h = Hg { g: 0.8 }.value(1.0);
        for (p, w) in [(left, 0.1), (right, 0.9)] {
            let want = (1.0 - w) * iso + w * h;
            let got = m.eval(p, wo, ahead);
            assert!((got - want).abs() < 1e-5 * want, "{got} vs {want}");
            check_phase_at(&m, p, views()[1]);
        }
    }
}
