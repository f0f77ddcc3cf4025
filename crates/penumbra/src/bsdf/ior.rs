//! Indices of refraction by name: dielectrics (a real index, at the sodium
//! D line, 589 nm, near room temperature) and conductor presets (a complex
//! index `eta + i·k` per RGB channel), under Mitsuba 3's names, and the
//! reader of the dielectric parameters that take them (`int_ior`,
//! `ext_ior`; the conductors' `material` is read in
//! [`conductor`](super::conductor)).
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
//! The conductor presets are every material of Mitsuba 3's table: the
//! measured spectral optical constants Mitsuba ships (its data's
//! `ior/<name>.eta.spd` and `ior/<name>.k.spd`: the Luxpop compilation of
//! Palik and LLNL–CXRO data, the same pbrt ships), 71 materials, reduced to
//! linear sRGB exactly as Mitsuba 3's RGB variants reduce a named material
//! (its `spectrum_list_to_srgb` with neither the D65 weighting nor the [0, 1]
//! bound: see [`spectrum`](crate::description::mitsuba::spectrum)), and
//! `none`, Mitsuba's ideal mirror, `eta = 0`, `k = 1` (reflectance exactly
//! 1). The table, [`MEASURED`], is written by `scripts/conductor_ior.py`
//! from those files; every value equals Mitsuba 3.9's in single precision.
//! A few of them:
//!
//! | name | `eta` (R, G, B) | `k` (R, G, B) | normal reflectance |
//! |---|---|---|---|
//! | `none` | 0, 0, 0 | 1, 1, 1 | 1, 1, 1 |
//! | `Au` (gold) | 0.1430, 0.3753, 1.4420 | 3.9830, 2.3856, 1.6034 | 0.967, 0.802, 0.324 |
//! | `Ag` (silver) | 0.1553, 0.1167, 0.1384 | 4.8284, 3.1222, 2.1469 | 0.975, 0.958, 0.906 |
//! | `Al` (aluminium) | 1.6575, 0.8804, 0.5212 | 9.2238, 6.2695, 4.8370 | 0.928, 0.918, 0.919 |
//! | `Cu` (copper) | 0.2010, 0.9237, 1.1022 | 3.9133, 2.4530, 2.1421 | 0.952, 0.620, 0.511 |
//! | `Cr` (chromium) | 4.3697, 2.9165, 1.6549 | 5.2065, 4.2313, 3.7547 | 0.688, 0.649, 0.687 |
//!
//! Names are matched exactly (Mitsuba opens the file of that name).

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

include!("ior_table.rs");

/// The number of conductor presets: `none` and [`MEASURED`].
const CONDUCTOR_COUNT: usize = MEASURED.len() + 1;

/// The names of the conductor presets, as scenes write them: `none`, then
/// those of [`MEASURED`].
pub const CONDUCTOR_NAMES: [&str; CONDUCTOR_COUNT] = {
    let mut names = ["none"; CONDUCTOR_COUNT];
    let mut i = 0;
    while i < MEASURED.len() {
        names[i + 1] = MEASURED[i].0;
        i += 1;
    }
    names
};

/// The index of the dielectric `name`.
pub fn dielectric(name: &str) -> Option<f32> {
    DIELECTRICS.iter().find(|(n, _)| *n == name).map(|e| e.1)
}

/// The conductor preset `name`.
pub fn conductor(name: &str) -> Option<Conductor> {
    if name == "none" {
        return Some(Conductor {
            eta: Rgb::ZERO,
            k: Rgb::ONE,
        });
    }
    MEASURED
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|&(_, eta, k)| Conductor {
            eta: Rgb::from_array(eta),
            k: Rgb::from_array(k),
        })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel;
    use crate::description::mitsuba::spectrum::{parse_file, to_rgb, Use};

    /// The materials of the table in Mitsuba 3's documentation of
    /// `conductor`, and the six more its data holds files for (`Se-e`,
    /// `Te-e`, `TiO2-e`, with their `_palik` versions), which Mitsuba
    /// loads as well.
    const MITSUBA_NAMES: [&str; 72] = [
        "a-C",
        "Ag",
        "Al",
        "AlAs",
        "AlAs_palik",
        "AlSb",
        "AlSb_palik",
        "Au",
        "Be",
        "Be_palik",
        "Cr",
        "CsI",
        "CsI_palik",
        "Cu",
        "Cu_palik",
        "Cu2O",
        "Cu2O_palik",
        "CuO",
        "CuO_palik",
        "d-C",
        "d-C_palik",
        "Hg",
        "Hg_palik",
        "HgTe",
        "HgTe_palik",
        "Ir",
        "Ir_palik",
        "K",
        "K_palik",
        "Li",
        "Li_palik",
        "MgO",
        "MgO_palik",
        "Mo",
        "Mo_palik",
        "Na_palik",
        "Nb",
        "Nb_palik",
        "Ni_palik",
        "Rh",
        "Rh_palik",
        "Se",
        "Se_palik",
        "SiC",
        "SiC_palik",
        "SnTe",
        "SnTe_palik",
        "Ta",
        "Ta_palik",
        "Te",
        "Te_palik",
        "ThF4",
        "ThF4_palik",
        "TiC",
        "TiC_palik",
        "TiN",
        "TiN_palik",
        "TiO2",
        "TiO2_palik",
        "VC",
        "VC_palik",
        "V_palik",
        "VN",
        "VN_palik",
        "W",
        "none",
        "Se-e",
        "Se-e_palik",
        "Te-e",
        "Te-e_palik",
        "TiO2-e",
        "TiO2-e_palik",
    ];

    #[test]
    fn dielectric_names_are_found() {
        assert_eq!(dielectric("bk7"), Some(1.5046));
        assert_eq!(dielectric("air"), Some(1.000277));
        assert_eq!(dielectric("acrylic glass"), Some(1.49));
        assert_eq!(dielectric("glass"), None);
        assert_eq!(DIELECTRIC_NAMES.len(), DIELECTRICS.len());
        assert!(DIELECTRICS.iter().all(|(_, v)| (1.0..2.5).contains(v)));
    }

    #[test]
    fn every_conductor_of_mitsubas_table_is_known_and_nothing_else() {
        let mut ours = CONDUCTOR_NAMES.to_vec();
        let mut theirs = MITSUBA_NAMES.to_vec();
        ours.sort_unstable();
        theirs.sort_unstable();
        assert_eq!(ours, theirs);
        for name in MITSUBA_NAMES {
            let c = conductor(name).unwrap();
            let all = [c.eta.to_array(), c.k.to_array()].concat();
            assert!(
                all.iter().all(|x| x.is_finite() && *x >= 0.0),
                "{name}: {c:?}"
            );
            // Every measured material reflects something and no more than 1.
            let r = fresnel::conductor(1.0, c.eta, c.k);
            assert!(
                r.min_element() >= 0.0 && r.max_element() <= 1.0,
                "{name}: {r:?}"
            );
        }
        assert_eq!(
            conductor("none"),
            Some(Conductor {
                eta: Rgb::ZERO,
                k: Rgb::ONE
            })
        );
        // Names are exact, as Mitsuba's file names.
        assert_eq!(conductor("au"), None);
        assert_eq!(conductor("Gold"), None);
    }

    /// Values Mitsuba 3.9.1's `scalar_rgb` gives (`mi.traverse` of a
    /// `conductor` with that `material`, printed to 6 digits).
    #[test]
    fn presets_are_mitsubas_numbers() {
        let cases = [
            (
                "Au",
                [0.143036, 0.375307, 1.44205],
                [3.983, 2.38556, 1.60336],
            ),
            (
                "Cu",
                [0.201005, 0.92375, 1.10222],
                [3.91326, 2.45305, 2.14209],
            ),
            (
                "W",
                [4.37082, 3.30025, 2.99841],
                [3.50064, 2.60487, 2.27323],
            ),
            (
                "Hg",
                [2.39894, 1.44003, 0.90957],
                [6.32759, 4.37192, 3.42176],
            ),
            (
                "a-C",
                [2.94405, 2.22714, 1.96816],
                [0.887465, 0.799299, 0.81529],
            ),
            // A negative green channel of k, set to 0.
            (
                "AlAs",
                [3.6053, 3.23294, 2.21632],
                [0.000679437, 0.0, 0.00751271],
            ),
        ];
        for (name, eta, k) in cases {
            let c = conductor(name).unwrap();
            for (ours, theirs) in [(c.eta.to_array(), eta), (c.k.to_array(), k)] {
                for (a, b) in ours.iter().zip(theirs) {
                    assert!(
                        (a - b).abs() <= 6e-6 * b.max(1.0),
                        "{name}: {ours:?} {theirs:?}"
                    );
                }
            }
        }
        // The module table's normal reflectances.
        let au = conductor("Au").unwrap();
        let r = fresnel::conductor(1.0, au.eta, au.k);
        assert!(
            (r - Rgb::new(0.967, 0.802, 0.324)).abs().max_element() < 1e-3,
            "{r:?}"
        );
    }

    /// The generated table is the crate's own reduction (as an emission: no
    /// D65, negatives to 0) of Mitsuba's gold files, to the bit in single
    /// precision.
    #[test]
    fn the_table_is_the_reduction_of_the_measured_files() {
        let au = conductor("Au").unwrap();
        for (text, want) in [
            (include_str!("../../tests/data/ior/Au.eta.spd"), au.eta),
            (include_str!("../../tests/data/ior/Au.k.spd"), au.k),
        ] {
            let rgb = to_rgb(&parse_file(text).unwrap(), Use::Emission);
            assert_eq!(rgb.map(|c| c as f32), want.to_array());
        }
    }
}
