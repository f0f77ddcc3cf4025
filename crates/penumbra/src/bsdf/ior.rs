//! Indices of refraction by name: dielectrics (a real index, at the sodium
//! D line, 589 nm, near room temperature) and conductor presets (a complex
//! index `eta + i·k` per RGB channel), under Mitsuba 3's names, and the
//! readers of the parameters that take them (`int_ior`, `ext_ior`;
//! `material`, `eta`, `k`).
//!
//! The dielectric values are physical constants from published tables
//! (Hecht, *Optics*, and the handbooks it draws on), the ones Mitsuba 3
//! lists:
//!
//! | name | index | name | index |
//! |---|---|---|---|
//! | `vacuum` | 1.0 | `water ice` | 1.31 |
//! | `helium` | 1.000036 | `fused quartz` | 1.458 |
//! | `hydrogen` | 1.000132 | `pyrex` | 1.470 |
//! | `air` | 1.000277 | `acrylic glass` | 1.49 |
//! | `carbon dioxide` | 1.00045 | `polypropylene` | 1.49 |
//! | `water` | 1.3330 | `bk7` | 1.5046 |
//! | `acetone` | 1.36 | `sodium chloride` | 1.544 |
//! | `ethanol` | 1.361 | `amber` | 1.55 |
//! | `carbon tetrachloride` | 1.461 | `pet` | 1.5750 |
//! | `glycerol` | 1.4729 | `diamond` | 2.419 |
//! | `benzene` | 1.501 | `silicone oil` | 1.52045 |
//! | `bromine` | 1.661 | | |
//!
//! The conductor presets are measured spectral optical constants (the
//! Palik / LLNL–CXRO compilation of the Luxpop database, the data Mitsuba
//! and pbrt ship) reduced to linear sRGB the way Mitsuba 3 reduces a
//! spectrum in its RGB modes: `eta(λ)` and `k(λ)` each integrated against
//! the CIE 1931 2° colour matching functions over 360–830 nm under an
//! equal-energy illuminant, normalised by ∫ȳ, taken from XYZ to linear
//! sRGB, and negative channels clamped to 0. `none` is Mitsuba's ideal
//! mirror, `eta = 0`, `k = 1` (reflectance exactly 1).
//!
//! | name | `eta` (R, G, B) | `k` (R, G, B) | normal reflectance |
//! |---|---|---|---|
//! | `none` | 0, 0, 0 | 1, 1, 1 | 1, 1, 1 |
//! | `Au` (gold) | 0.1431, 0.3749, 1.4424 | 3.9831, 2.3857, 1.6031 | 0.967, 0.802, 0.324 |
//! | `Ag` (silver) | 0.1553, 0.1167, 0.1384 | 4.8283, 3.1223, 2.1468 | 0.975, 0.958, 0.906 |
//! | `Al` (aluminium) | 1.6574, 0.8804, 0.5212 | 9.2238, 6.2696, 4.8366 | 0.928, 0.918, 0.919 |
//! | `Cu` (copper) | 0.2004, 0.9241, 1.1021 | 3.9129, 2.4529, 2.1420 | 0.952, 0.620, 0.511 |
//! | `Cr` (chromium) | 4.3697, 2.9167, 1.6546 | 5.2064, 4.2314, 3.7547 | 0.688, 0.649, 0.687 |

use crate::description::check::finite3_value;
use crate::description::{Invalid, NumberOr, Props};
use crate::math::Rgb;

/// The named dielectric indices (see the [module docs](self)).
pub const DIELECTRICS: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The names of [`DIELECTRICS`], as scenes write them.
pub const DIELECTRIC_NAMES: [&str; 23] = {
    let mut names = [""; 23];
    let mut i = 0;
    while i < 23 {
        names[i] = DIELECTRICS[i].0;
        i += 1;
    }
    names
};

/// A conductor's complex index by channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub eta: Rgb,
    pub k: Rgb,
}

/// The conductor presets (see the [module docs](self)).
pub const CONDUCTORS: [(&str, Conductor); 6] = [
    (
        "none",
        Conductor {
            eta: Rgb::ZERO,
            k: Rgb::ONE,
        },
    ),
    (
        "Au",
        Conductor {
            eta: Rgb::new(0.1431, 0.3749, 1.4424),
            k: Rgb::new(3.9831, 2.3857, 1.6031),
        },
    ),
    (
        "Ag",
        Conductor {
            eta: Rgb::new(0.1553, 0.1167, 0.1384),
            k: Rgb::new(4.8283, 3.1223, 2.1468),
        },
    ),
    (
        "Al",
        Conductor {
            eta: Rgb::new(1.6574, 0.8804, 0.5212),
            k: Rgb::new(9.2238, 6.2696, 4.8366),
        },
    ),
    (
        "Cu",
        Conductor {
            eta: Rgb::new(0.2004, 0.9241, 1.1021),
            k: Rgb::new(3.9129, 2.4529, 2.1420),
        },
    ),
    (
        "Cr",
        Conductor {
            eta: Rgb::new(4.3697, 2.9167, 1.6546),
            k: Rgb::new(5.2064, 4.2314, 3.7547),
        },
    ),
];

/// The names of [`CONDUCTORS`].
pub const CONDUCTOR_NAMES: [&str; 6] = ["none", "Au", "Ag", "Al", "Cu", "Cr"];

/// The index of the dielectric `name`.
pub fn dielectric(name: &str) -> Option<f32> {
    DIELECTRICS.iter().find(|(n, _)| *n == name).map(|e| e.1)
}

/// The conductor preset `name`.
pub fn conductor(name: &str) -> Option<Conductor> {
    CONDUCTORS.iter().find(|(n, _)| *n == name).map(|e| e.1)
}

/// The index of refraction `name` of a dielectric: a number > 0 or a name
/// of [`DIELECTRICS`], `default` (a name) when absent.
pub fn read_dielectric(p: &Props, name: &str, default: &str) -> Result<f32, Invalid> {
    let v = match p.number_or_choice(name, "index of refraction", &DIELECTRIC_NAMES)? {
        None => dielectric(default).expect("a known default"),
        Some(NumberOr::Name(n)) => dielectric(n).expect("a listed name"),
        Some(NumberOr::Number(x)) => x,
    };
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(p.error(name, format!("must be a positive number, got {v}")))
    }
}

/// A conductor's index as Mitsuba 3 reads it: the preset `material`
/// (default `none`), or `eta` and `k` (defaults 0 and 1), not both.
/// `eta` and `k` must not be negative.
pub fn read_conductor(p: &Props) -> Result<Conductor, Invalid> {
    let material = p.choice("material", "conductor material", &CONDUCTOR_NAMES)?;
    let given = p.has("eta") || p.has("k");
    if let (Some(m), true) = (material, given) {
        if m != "none" {
            let at = if p.has("eta") { "eta" } else { "k" };
            return Err(p.error(
                at,
                format!("give either `material` or `eta` and `k`, not both (`material` is `{m}`)"),
            ));
        }
    }
    let preset = conductor(material.unwrap_or("none")).expect("a listed name");
    let read = |name: &str, default: Rgb| -> Result<Rgb, Invalid> {
        let Some(v) = p.numbers::<3>(name)? else {
            return Ok(default);
        };
        let x = Rgb::from_array(finite3_value(p, name, v)?.to_array());
        if x.min_element() < 0.0 {
            return Err(p.error(name, format!("must not be negative, got {v:?}")));
        }
        Ok(x)
    };
    Ok(Conductor {
        eta: read("eta", preset.eta)?,
        k: read("k", preset.k)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel;

    #[test]
    fn names_are_found_and_presets_match_their_table() {
        assert_eq!(dielectric("bk7"), Some(1.5046));
        assert_eq!(dielectric("air"), Some(1.000277));
        assert_eq!(dielectric("acrylic glass"), Some(1.49));
        assert_eq!(dielectric("glass"), None);
        assert_eq!(DIELECTRIC_NAMES.len(), DIELECTRICS.len());
        assert!(DIELECTRICS.iter().all(|(_, v)| (1.0..2.5).contains(v)));
        for (name, c) in CONDUCTORS {
            assert_eq!(conductor(name), Some(c));
            assert!(CONDUCTOR_NAMES.contains(&name));
        }
        // The normal reflectances the module table lists.
        let r = fresnel::conductor(
            1.0,
            conductor("Au").unwrap().eta,
            conductor("Au").unwrap().k,
        );
        assert!(
            (r - Rgb::new(0.967, 0.802, 0.324)).abs().max_element() < 1e-3,
            "{r:?}"
        );
        let c = conductor("Cr").unwrap();
        let r = fresnel::conductor(1.0, c.eta, c.k);
        assert!(
            (r - Rgb::new(0.688, 0.649, 0.687)).abs().max_element() < 1e-3,
            "{r:?}"
        );
    }
}
