//! Light samplers: which emitter a shading point sends its next-event
//! estimation toward, and with what probability (pbrt-v4's light samplers;
//! Mitsuba 3 chooses uniformly, or by each emitter's `sampling_weight`).
//!
//! | sampler | chooses | built from |
//! |---|---|---|
//! | [`uniform`] | every emitter with the same probability | the count |
//! | [`power`] | in proportion to the emitter's power, wherever the point is | a table over the powers |
//! | [`bvh`] | down a tree of the bounded emitters by how much each half may light the point; those at infinity beside the tree | a BVH over [`LightBounds`](super::bounds::LightBounds) |
//!
//! Each answers [`LightSampler::sample`] (an emitter and its probability
//! for a point, its surface's normal and a uniform number) and
//! [`LightSampler::pmf`] (the probability that `sample` chooses a given
//! emitter from that point), the two always agreeing: multiple importance
//! sampling weighs the emission a path meets by the probability the vertex
//! it left would have chosen that emitter with. Built once per scene,
//! shared by every worker.

pub mod bvh;
pub mod power;
pub mod uniform;

use crate::emitter::Emitter;
use crate::math::Vec3;

pub use bvh::LightBvh;
pub use power::PowerSampler;
pub use uniform::UniformSampler;

/// Which light sampler a path tracer uses, by name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightChoice {
    Uniform,
    Power,
    /// The default, as in pbrt-v4.
    #[default]
    Bvh,
}

impl LightChoice {
    pub const ALL: [LightChoice; 3] = [LightChoice::Uniform, LightChoice::Power, LightChoice::Bvh];
    pub const NAMES: [&'static str; 3] = ["uniform", "power", "bvh"];

    pub fn name(self) -> &'static str {
        match self {
            LightChoice::Uniform => "uniform",
            LightChoice::Power => "power",
            LightChoice::Bvh => "bvh",
        }
    }

    pub fn from_name(s: &str) -> Option<LightChoice> {
        LightChoice::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// A light sampler over a scene's emitters.
#[derive(Clone, Debug)]
pub enum LightSampler {
    Uniform(UniformSampler),
    Power(PowerSampler),
    Bvh(LightBvh),
}

impl LightSampler {
    /// The sampler `choice` over `emitters`; `radius` is the radius of the
    /// scene's bounding sphere, which the power of an emitter at infinity
    /// is measured through.
    pub fn new(choice: LightChoice, emitters: &[Emitter], radius: f32) -> LightSampler {
        match choice {
            LightChoice::Uniform => LightSampler::Uniform(UniformSampler::new(emitters.len())),
            LightChoice::Power => LightSampler::Power(PowerSampler::new(emitters, radius)),
            LightChoice::Bvh => LightSampler::Bvh(LightBvh::new(emitters)),
        }
    }

    /// The emitter chosen for the point `p` with normal `n` (zero: no
    /// surface) by the uniform number `u` in [0, 1), and the probability
    /// of that choice; `None` when no emitter can be chosen (none, or none
    /// that may light `p`).
    #[inline]
    pub fn sample(&self, p: Vec3, n: Vec3, u: f32) -> Option<(u32, f32)> {
        match self {
            LightSampler::Uniform(s) => s.sample(u),
            LightSampler::Power(s) => s.sample(u),
            LightSampler::Bvh(s) => s.sample(p, n, u),
        }
    }

    /// The probability that [`sample`](Self::sample) chooses `emitter`
    /// for the point `p` with normal `n`.
    #[inline]
    pub fn pmf(&self, p: Vec3, n: Vec3, emitter: u32) -> f32 {
        match self {
            LightSampler::Uniform(s) => s.pmf(emitter),
            LightSampler::Power(s) => s.pmf(emitter),
            LightSampler::Bvh(s) => s.pmf(p, n, emitter),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::emitter::bounds::tests::random_unit;
    use crate::emitter::{Area, Constant, Directional, PenumbraModel, Point, Spot};
    use crate::geometry::quad::Quad;
    use crate::geometry::surface::tests::{still, triangles};
    use crate::geometry::{Disk, Shape, Sphere, Surface};
    use crate::math::{Frame, Rgb};
    use crate::sampling::Rng;

    pub(crate) fn area(shape: Shape, radiance: f32) -> Emitter {
        surface_area(still(shape), radiance)
    }

    pub(crate) fn surface_area(surface: Surface, radiance: f32) -> Emitter {
        Emitter::Area(Area::new(
            surface,
            crate::texture::Texture::Constant(Rgb::splat(radiance)),
            PenumbraModel::Surface,
        ))
    }

    /// Emitters of every kind, of powers over four orders of magnitude,
    /// facing every way: rectangles, disks, spheres, a tube, a mesh, point
    /// and spot lights, and two at infinity.
    pub(crate) fn many_emitters(with_infinite: bool) -> Vec<Emitter> {
        let mut rng = Rng::new(41);
        let mut out = Vec::new();
        for k in 0..24 {
            let at = Vec3::new(
                rng.range(-4.0, 4.0),
                rng.range(0.0, 3.0),
                rng.range(-4.0, 4.0),
            );
            let size = rng.range(0.05, 0.8);
            let radiance = 10f32.powf(rng.range(-1.0, 3.0));
            let n = random_unit(&mut rng);
            let frame = Frame::from_normal(n);
            let e = match k % 6 {
                0 => area(
                    Shape::Quad(Quad::new(at, frame.u * size, frame.v * size)),
                    radiance,
                ),
                1 => area(Shape::Disk(Disk::new(at, frame, size)), radiance),
                2 => area(Shape::Sphere(Sphere::new(at, size)), radiance),
                3 => Emitter::Point(Point {
                    position: at,
                    intensity: Rgb::splat(radiance),
                }),
                4 => Emitter::Spot(Spot::new(at, n, Rgb::splat(radiance), 40.0, 25.0)),
                _ => surface_area(
                    triangles(&[
                        [at, at + frame.u * size, at + frame.v * size],
                        [at, at + frame.v * size, at + (frame.n - frame.u) * size],
                    ]),
                    radiance,
                ),
            };
            out.push(e);
        }
        out.push(area(
            Shape::Cylinder(
                crate::geometry::Cylinder::new(
                    Vec3::new(-1.0, 1.0, 0.0),
                    Vec3::new(1.0, 1.5, 0.0),
                    0.2,
                )
                .unwrap(),
            ),
            5.0,
        ));
        // One that emits nothing.
        out.push(area(Shape::Sphere(Sphere::new(Vec3::ZERO, 0.3)), 0.0));
        if with_infinite {
            out.push(Emitter::Constant(Constant {
                radiance: Rgb::splat(0.2),
            }));
            out.push(Emitter::Directional(Directional::new(
                Vec3::new(0.3, -1.0, 0.2),
                Rgb::splat(2.0),
            )));
        }
        out
    }

    fn samplers(emitters: &[Emitter]) -> Vec<(LightChoice, LightSampler)> {
        LightChoice::ALL
            .into_iter()
            .map(|c| (c, LightSampler::new(c, emitters, 6.0)))
            .collect()
    }

    /// A shading point among the lights, with a normal (or none).
    fn point(rng: &mut Rng) -> (Vec3, Vec3) {
        let p = Vec3::new(
            rng.range(-5.0, 5.0),
            rng.range(-1.0, 4.0),
            rng.range(-5.0, 5.0),
        );
        let n = if rng.next_f32() < 0.2 {
            Vec3::ZERO
        } else {
            random_unit(rng)
        };
        (p, n)
    }

    /// Over every emitter, the probabilities sum to the probability that
    /// `sample` chooses one at all, counted over a stratified set of
    /// numbers: 1 for `uniform` and `power`; for `bvh`, 1 less the numbers
    /// that find both halves of some node unable to light the point.
    /// Where every bounded emitter lights every direction (spheres and
    /// points), that is 1 for `bvh` too.
    #[test]
    fn probabilities_sum_to_the_chance_of_a_choice() {
        let mut rng = Rng::new(5);
        for with_infinite in [false, true] {
            let emitters = many_emitters(with_infinite);
            for (choice, s) in samplers(&emitters) {
                for _ in 0..100 {
                    let (p, n) = point(&mut rng);
                    let sum: f32 = (0..emitters.len() as u32).map(|e| s.pmf(p, n, e)).sum();
                    let draws = 20_000;
                    let chosen = (0..draws)
                        .filter(|k| {
                            let u = (*k as f32 + 0.5) / draws as f32;
                            s.sample(p, n, u).is_some()
                        })
                        .count();
                    let share = chosen as f32 / draws as f32;
                    assert!(
                        (sum - share).abs() < 3e-3,
                        "{choice:?}: Σ pmf = {sum}, chosen {share}"
                    );
                    if choice != LightChoice::Bvh {
                        assert!((sum - 1.0).abs() < 1e-5, "{choice:?}: Σ pmf = {sum}");
                    }
                }
            }
        }
        let everywhere: Vec<Emitter> = many_emitters(true)
            .into_iter()
            .filter(|e| match e {
                Emitter::Area(a) => a.surface.shape().as_sphere().is_some(),
                other => matches!(other, Emitter::Point(_) | Emitter::Constant(_)),
            })
            .collect();
        assert!(everywhere.len() > 8);
        let bvh = LightSampler::new(LightChoice::Bvh, &everywhere, 6.0);
        for _ in 0..500 {
            let (p, _) = point(&mut rng);
            let sum: f32 = (0..everywhere.len() as u32)
                .map(|e| bvh.pmf(p, Vec3::ZERO, e))
                .sum();
            assert!((sum - 1.0).abs() < 1e-5, "Σ pmf = {sum}");
        }
    }

    /// The probability `sample` returns is `pmf` of the emitter it chose,
    /// for every sampler, point and number; an emitter that emits nothing
    /// is never chosen by `power` or `bvh`.
    #[test]
    fn sample_gives_the_pmf_of_its_choice() {
        let mut rng = Rng::new(9);
        let emitters = many_emitters(true);
        let dark = emitters.iter().position(|e| e.power(6.0) == 0.0).unwrap() as u32;
        for (choice, s) in samplers(&emitters) {
            let mut chosen = 0;
            for _ in 0..20_000 {
                let (p, n) = point(&mut rng);
                let u = rng.next_f32();
                let Some((k, pmf)) = s.sample(p, n, u) else {
                    continue;
                };
                chosen += 1;
                let want = s.pmf(p, n, k);
                assert!(pmf > 0.0, "{choice:?}");
                assert!(
                    (pmf - want).abs() <= 1e-6 * want,
                    "{choice:?}: emitter {k}: {pmf} from sample, {want} from pmf"
                );
                if choice != LightChoice::Uniform {
                    assert_ne!(k, dark, "{choice:?} chose an emitter of no power");
                }
            }
            assert!(chosen > 15_000, "{choice:?}: {chosen}");
        }
    }

    /// Pearson's χ² of the emitters chosen (and of no choice) at a point
    /// against the probabilities `pmf` gives, bins of fewer than 5
    /// expected pooled: below the 0.999 quantile, at several points for
    /// every sampler. Counts drawn by `bvh` tested against `uniform`'s
    /// probabilities fail it, so the test can tell samplers apart.
    #[test]
    fn choices_follow_the_pmf() {
        let emitters = many_emitters(true);
        let mut rng = Rng::new(13);
        let samplers = samplers(&emitters);
        let draws = 100_000;
        for t in 0..4 {
            let (p, n) = point(&mut rng);
            for (choice, s) in &samplers {
                let mut counts = vec![0u32; emitters.len() + 1];
                for _ in 0..draws {
                    match s.sample(p, n, rng.next_f32()) {
                        Some((k, _)) => counts[k as usize] += 1,
                        None => counts[emitters.len()] += 1,
                    }
                }
                let (x2, dof) = chi2(&counts, |k| pmf_or_none(s, &emitters, p, n, k));
                assert!(
                    x2 < chi2_999(dof),
                    "{choice:?} at point {t}: χ² {x2} with {dof} degrees of freedom"
                );
                if *choice == LightChoice::Bvh {
                    let uniform = &samplers[0].1;
                    let (x2, dof) = chi2(&counts, |k| pmf_or_none(uniform, &emitters, p, n, k));
                    assert!(x2 > chi2_999(dof), "uniform's pmf passes for bvh's choices");
                }
            }
        }
    }

    /// The probability of bin `k`: emitter `k`, or no choice past the last.
    fn pmf_or_none(s: &LightSampler, emitters: &[Emitter], p: Vec3, n: Vec3, k: usize) -> f64 {
        let all = 0..emitters.len() as u32;
        if k == emitters.len() {
            (1.0 - all.map(|e| f64::from(s.pmf(p, n, e))).sum::<f64>()).max(0.0)
        } else {
            f64::from(s.pmf(p, n, k as u32))
        }
    }

    /// Pearson's χ² of `counts` against the probabilities `pmf` of their
    /// bins, bins expecting fewer than 5 pooled into one; and its degrees
    /// of freedom. A count in a bin of probability 0 gives infinity.
    pub(crate) fn chi2(counts: &[u32], pmf: impl Fn(usize) -> f64) -> (f64, usize) {
        let total: f64 = counts.iter().map(|&c| f64::from(c)).sum();
        let (mut chi2, mut bins) = (0.0, 0);
        let (mut pooled_e, mut pooled_c) = (0.0, 0.0);
        for (k, &c) in counts.iter().enumerate() {
            let e = pmf(k) * total;
            if e == 0.0 && c > 0 {
                return (f64::INFINITY, 1);
            }
            if e < 5.0 {
                pooled_e += e;
                pooled_c += f64::from(c);
            } else {
                chi2 += (f64::from(c) - e).powi(2) / e;
                bins += 1;
            }
        }
        if pooled_e > 0.0 {
            chi2 += (pooled_c - pooled_e).powi(2) / pooled_e;
            bins += 1;
        }
        (chi2, bins.max(2) - 1)
    }

    /// The 0.999 quantile of χ² with `dof` degrees of freedom
    /// (Wilson–Hilferty).
    pub(crate) fn chi2_999(dof: usize) -> f64 {
        let k = dof as f64;
        let z = 3.090_232;
        k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3)
    }
}
