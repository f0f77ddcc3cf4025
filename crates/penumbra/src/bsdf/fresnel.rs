//! Fresnel reflectance of smooth interfaces: a dielectric of real relative
//! index (with total internal reflection) and a conductor of complex index
//! `eta + i·k`, per RGB channel (the unpolarised averages of the two
//! polarisations, as Mitsuba 3's `fresnel` and `fresnel_conductor`).
//!
//! | function | for | returns |
//! |---|---|---|
//! | [`dielectric`] | cosine of the incident angle (signed by side), `eta = int / ext` | reflectance, cosine of the refracted angle, the indices' ratios |
//! | [`conductor`] | cosine of the incident angle, `eta`, `k` (RGB) | reflectance per channel |

use crate::math::Rgb;

/// What a dielectric interface does to light arriving at cosine `cos_i`
/// (see [`dielectric`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// The fraction reflected (1 under total internal reflection).
    pub r: f32,
    /// Cosine of the refracted direction with the normal, of the sign
    /// opposite to `cos_i` (0 under total internal reflection).
    pub cos_t: f32,
    /// Index of the far side over the index of the near side.
    pub eta_it: f32,
    /// Index of the near side over the far side (`1 / eta_it`): the
    /// refracted direction's `eta` and the square root of the radiance
    /// scale of light refracted toward the near side.
    pub eta_ti: f32,
}

/// The unpolarised Fresnel reflectance of a dielectric interface of
/// relative index `eta` (inside over outside: the normal points outside),
/// for light arriving at cosine `cos_i` with the normal: positive from
/// outside, negative from inside. Index-matched (`eta = 1`) interfaces
/// reflect nothing; grazing light (`cos_i = 0`) is all reflected.
pub fn dielectric(cos_i: f32, eta: f32) -> Dielectric {
    let outside = cos_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let ci = cos_i.abs().min(1.0);
    // Snell: sin_t = eta_ti · sin_i.
    let sin2_t = eta_ti * eta_ti * (1.0 - ci * ci);
    if sin2_t >= 1.0 {
        return Dielectric {
            r: 1.0,
            cos_t: 0.0,
            eta_it,
            eta_ti,
        };
    }
    let ct = (1.0 - sin2_t).sqrt();
    let r = if eta == 1.0 {
        0.0
    } else if ci == 0.0 {
        1.0
    } else {
        // Amplitude ratios of the two polarisations.
        let s = (ci - eta_it * ct) / (ci + eta_it * ct);
        let p = (eta_it * ci - ct) / (eta_it * ci + ct);
        0.5 * (s * s + p * p)
    };
    Dielectric {
        r,
        cos_t: if outside { -ct } else { ct },
        eta_it,
        eta_ti,
    }
}

/// The unpolarised Fresnel reflectance of a conductor of complex index
/// `eta + i·k` (relative to the outside), per channel, at the incident
/// cosine `cos_i` (its magnitude is used).
pub fn conductor(cos_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    let c = cos_i.abs().min(1.0);
    let one = |eta: f32, k: f32| -> f32 {
        let (c2, s2) = (c * c, 1.0 - c * c);
        // |n̂² − sin²| and the real part a of the refracted "cosine".
        let t0 = eta * eta - k * k - s2;
        let a2b2 = (t0 * t0 + 4.0 * eta * eta * k * k).sqrt();
        let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
        let t1 = a2b2 + c2;
        let t2 = 2.0 * c * a;
        let rs = (t1 - t2) / (t1 + t2);
        let t3 = c2 * a2b2 + s2 * s2;
        let t4 = t2 * s2;
        let rp = rs * (t3 - t4) / (t3 + t4);
        let r = 0.5 * (rs + rp);
        if r.is_finite() {
            r.clamp(0.0, 1.0)
        } else {
            1.0
        }
    };
    Rgb::new(one(eta.r, k.r), one(eta.g, k.g), one(eta.b, k.b))
}

/// The diffuse Fresnel reflectance of an interface of relative index
/// `eta` (`η_far / η_near`): the reflectance [`dielectric`] averaged over
/// the hemisphere under cosine-weighted light, `2 ∫ F(μ) μ dμ`. Evaluated,
/// as Mitsuba 3 does, by two published polynomial fits: Egan and
/// Hilgeman's (1973) below 1, d'Eon and Irving's (2011) above (relative
/// errors of a few tenths of a percent for indices up to 2).
pub fn diffuse_reflectance(eta: f32) -> f32 {
    if eta < 1.0 {
        -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta
    } else {
        let x = 1.0 / eta;
        // 0.919317 − 3.4793 x + 6.75335 x² − 7.80989 x³ + 4.98554 x⁴ − 1.36881 x⁵.
        let c = [0.919317, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881f32];
        c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Normal incidence gives ((η − 1)/(η + 1))² from both sides; past the
    /// critical angle everything is reflected; the refracted cosine obeys
    /// Snell's law.
    #[test]
    fn dielectric_known_values() {
        let f = dielectric(1.0, 1.5);
        assert!((f.r - 0.04).abs() < 1e-6, "{f:?}");
        assert_eq!((f.eta_it, f.cos_t), (1.5, -1.0));
        let inside = dielectric(-1.0, 1.5);
        assert!((inside.r - 0.04).abs() < 1e-6 && inside.cos_t == 1.0);
        // The critical angle from inside glass: sin θc = 1/1.5.
        let c = (1.0f32 - 1.0 / 2.25).sqrt();
        assert_eq!(dielectric(-(c - 1e-3), 1.5).r, 1.0);
        assert!(dielectric(-(c + 1e-3), 1.5).r < 1.0);
        let f = dielectric(0.6, 1.33);
        let sin_t = (1.0f32 - f.cos_t * f.cos_t).sqrt();
        assert!((sin_t * 1.33 - 0.8).abs() < 1e-5);
        assert_eq!(dielectric(0.3, 1.0).r, 0.0);
        assert_eq!(dielectric(0.0, 1.5).r, 1.0);
        // Symmetric in the two directions of one pair of angles (Stokes).
        let a = dielectric(0.8, 1.5);
        let b = dielectric(a.cos_t, 1.5);
        assert!((a.r - b.r).abs() < 1e-5, "{a:?} {b:?}");
    }

    /// A conductor of index 0 + 1i is a perfect mirror; one of real index is
    /// a dielectric; at normal incidence R = ((η−1)² + k²)/((η+1)² + k²).
    #[test]
    fn conductor_known_values() {
        for c in [0.0, 0.3, 1.0] {
            assert_eq!(conductor(c, Rgb::ZERO, Rgb::ONE), Rgb::ONE);
        }
        for c in [0.2, 0.7, 1.0] {
            let r = conductor(c, Rgb::splat(1.5), Rgb::ZERO).r;
            assert!((r - dielectric(c, 1.5).r).abs() < 1e-5, "{c}");
        }
        let (eta, k) = (Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.5, 2.1));
        let r = conductor(1.0, eta, k);
        let want = |e: f32, k: f32| ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
        assert!((r.r - want(0.2, 3.9)).abs() < 1e-5);
        assert!((r.b - want(1.1, 2.1)).abs() < 1e-5);
        assert_eq!(conductor(0.0, eta, k), Rgb::ONE);
    }

    /// The fits of the diffuse reflectance agree with the integral of the
    /// exact reflectance (a midpoint rule) to 1% of the reflectance for
    /// indices seen from both sides.
    #[test]
    fn diffuse_reflectance_matches_the_integral() {
        for eta in [
            1.1f32,
            1.33,
            1.49,
            1.5,
            1.8,
            2.4,
            1.0 / 1.1,
            1.0 / 1.33,
            1.0 / 1.49,
            1.0 / 2.0,
        ] {
            let n = 20_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let mu = (i as f64 + 0.5) / n as f64;
                sum += 2.0 * f64::from(dielectric(mu as f32, eta).r) * mu / n as f64;
            }
            let fit = f64::from(diffuse_reflectance(eta));
            assert!(
                (fit - sum).abs() <= 0.01 * sum,
                "η = {eta}: fit {fit}, integral {sum}"
            );
        }
    }
}
