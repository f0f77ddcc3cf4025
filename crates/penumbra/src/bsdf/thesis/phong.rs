//! The thesis's local surface: a Lambertian base (`albedo / π`) plus an
//! energy-normalised Phong highlight `specular · (s + 2)/(2π) · cos^s α`, α
//! between `wo` and the mirrored `wi`, both scaled by the material's local
//! weight. Diffuse and glossy; reflection only.
//!
//! Sampling picks the diffuse part (cosine-weighted hemisphere) or the
//! highlight (`cos^s` lobe around the mirror direction) in proportion to
//! their albedos, and its pdf is the mixture's.

use std::f32::consts::PI;

use crate::bsdf::sample::{BsdfFlags, BsdfSample};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};

#[derive(Clone, Copy, Debug)]
pub struct Phong {
    /// `albedo / π`.
    diffuse: Rgb,
    specular: f32,
    shininess: f32,
    /// The local weight `1 − reflectivity − transparency`.
    weight: f32,
}

impl Phong {
    pub fn new(albedo: Rgb, specular: f32, shininess: f32, weight: f32) -> Phong {
        Phong {
            diffuse: albedo * (1.0 / PI),
            specular,
            shininess,
            weight,
        }
    }

    /// The local weight it was made with.
    pub fn weight(&self) -> f32 {
        self.weight
    }

    /// True if it reflects anything at all.
    pub fn is_black(&self) -> bool {
        !(self.weight > 0.0 && (self.diffuse.max_element() > 0.0 || self.specular > 0.0))
    }

    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE | BsdfFlags::GLOSSY | BsdfFlags::REFLECTION
    }

    /// The BSDF for unit vectors `wo` (toward the viewer) and `wi` (toward
    /// the light) around the unit normal `n`, without the cosine.
    #[inline]
    pub fn eval(&self, n: Vec3, wo: Vec3, wi: Vec3) -> Rgb {
        let mut f = self.diffuse;
        if self.specular > 0.0 {
            let r = 2.0 * wi.dot(n) * n - wi;
            let cos_a = r.dot(wo).max(0.0);
            let s = self.shininess;
            f += Rgb::splat(self.specular * (s + 2.0) / (2.0 * PI) * cos_a.powf(s));
        }
        f * self.weight
    }

    /// Probability of choosing the highlight when sampling.
    fn glossy_share(&self) -> f32 {
        let d = self.diffuse.max_element() * PI;
        if d + self.specular > 0.0 {
            self.specular / (d + self.specular)
        } else {
            0.0
        }
    }

    /// Solid-angle density of [`sample`](Self::sample) choosing `wi`.
    pub fn pdf(&self, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        let cos_i = wi.dot(n);
        if cos_i <= 0.0 || wo.dot(n) <= 0.0 {
            return 0.0;
        }
        let g = self.glossy_share();
        let diffuse = square_to_cosine_hemisphere_pdf(Vec3::new(0.0, 0.0, cos_i));
        let r = 2.0 * wo.dot(n) * n - wo;
        let cos_a = r.dot(wi).max(0.0);
        let s = self.shininess;
        let glossy = (s + 1.0) / (2.0 * PI) * cos_a.powf(s);
        (1.0 - g) * diffuse + g * glossy
    }

    /// A direction `wi` from `u` (two uniform numbers in [0, 1)), with the
    /// weight `eval · cos θ / pdf`.
    pub fn sample(&self, n: Vec3, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.dot(n) <= 0.0 || self.is_black() {
            return None;
        }
        let g = self.glossy_share();
        let wi = if u.x < g {
            let u = Vec2::new(u.x / g, u.y);
            let r = 2.0 * wo.dot(n) * n - wo;
            let s = self.shininess;
            let cos_a = (1.0 - u.x).powf(1.0 / (s + 1.0));
            let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            Frame::from_normal(r).to_world(Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a))
        } else {
            let u = Vec2::new((u.x - g) / (1.0 - g), u.y);
            Frame::from_normal(n).to_world(square_to_cosine_hemisphere(u))
        };
        let pdf = self.pdf(n, wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(n, wo, wi) * (wi.dot(n) / pdf);
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags: if u.x < g {
                BsdfFlags::GLOSSY | BsdfFlags::REFLECTION
            } else {
                BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION
            },
            lobe: 0,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The integral of `f` over the hemisphere around +z by the midpoint
    /// rule in (θ, φ), `n` × `n` cells.
    fn hemisphere(n: u32, f: impl Fn(Vec3) -> f32) -> f32 {
        let (dt, dp) = (PI / 2.0 / n as f32, 2.0 * PI / n as f32);
        let mut sum = 0.0;
        for i in 0..n {
            let theta = (i as f32 + 0.5) * dt;
            for j in 0..n {
                let phi = (j as f32 + 0.5) * dp;
                let w = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                sum += f(w) * theta.sin() * dt * dp;
            }
        }
        sum
    }

    /// Directional albedo: the integral of `eval · cos θ`.
    fn albedo(p: &Phong, n: Vec3, wo: Vec3) -> f32 {
        hemisphere(400, |wi| p.eval(n, wo, wi).r * wi.z)
    }

    #[test]
    fn the_highlight_does_not_create_energy() {
        let p = Phong::new(Rgb::ZERO, 1.0, 20.0, 1.0);
        let a = albedo(&p, Vec3::Z, Vec3::Z);
        assert!(a <= 1.0 && a > 0.85, "directional albedo {a}");
    }

    /// The pdf integrates to one over the hemisphere, and every sample's
    /// weight is `eval · cos / pdf` at its direction; the mean weight is the
    /// directional albedo (a Monte Carlo estimate of the same integral).
    #[test]
    fn sampling_matches_its_pdf_and_weights() {
        let n = Vec3::Z;
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let p = Phong::new(Rgb::new(0.5, 0.4, 0.3), 0.4, 30.0, 0.9);
        let total = hemisphere(600, |wi| p.pdf(n, wo, wi));
        assert!((total - 1.0).abs() < 0.01, "pdf integrates to {total}");
        let mut rng = Rng::new(3);
        let count = 200_000;
        let mut mean = 0.0f64;
        for _ in 0..count {
            let s = p
                .sample(n, wo, Vec2::new(rng.next_f32(), rng.next_f32()))
                .unwrap();
            let want = p.eval(n, wo, s.wi) * (s.wi.dot(n) / s.pdf);
            assert!((s.weight - want).abs().max_element() < 1e-4 * want.max_element().max(1.0));
            mean += f64::from(s.weight.r);
        }
        let mean = mean / f64::from(count);
        let want = f64::from(albedo(&p, n, wo));
        assert!(
            (mean - want).abs() < 0.01 * want,
            "mean weight {mean}, albedo {want}"
        );
    }
}
