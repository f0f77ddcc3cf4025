//! Spectra to RGB, as Mitsuba 3's RGB variants turn a `<spectrum>` into a
//! colour.
//!
//! A constant spectrum (`value="0.5"`) is that value on every channel for a
//! reflectance; for an emitter it is the value times the sRGB image of the
//! XYZ colour (1, 1, 1), the colour a flat spectrum has against sRGB's D65
//! white. A list of `wavelength:value` pairs (or a file of them) is
//! interpolated linearly between its wavelengths (and is zero outside them),
//! integrated against the CIE 1931 colour matching functions at 1000 evenly
//! spaced wavelengths from 360 nm to 830 nm, scaled so that a flat spectrum
//! of 1 has luminance 1 and converted from XYZ to linear sRGB. For a
//! reflectance the spectrum is first multiplied by the D65 illuminant
//! (normalised the same way) and the result is clamped to [0, 1]; for an
//! emitter negative channels are clamped to 0.

/// Shortest and longest wavelength integrated over, in nanometres.
const CIE_MIN: f64 = 360.0;
const CIE_MAX: f64 = 830.0;
/// Wavelengths the integral is taken at.
const STEPS: usize = 1000;

/// A spectrum as a file or an attribute wrote it.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f64),
    /// Values at increasing wavelengths (at least two), in nanometres.
    Samples(Vec<(f64, f64)>),
}

/// What a spectrum colours: a surface's reflectance or an emitter's
/// radiance or intensity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    Reflectance,
    Emission,
}

/// Linear sRGB of XYZ (the Rec. 709 primaries, D65 white).
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.240479, -1.537150, -0.498535],
    [-0.969256, 1.875991, 0.041556],
    [0.055648, -0.204043, 1.057311],
];

fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    XYZ_TO_SRGB.map(|row| row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2])
}

/// The tables' x̄, ȳ, z̄ and D65 at a wavelength, interpolated linearly
/// (zero outside 360–830 nm).
fn cie(w: f64) -> [f64; 4] {
    if !(CIE_MIN..=CIE_MAX).contains(&w) {
        return [0.0; 4];
    }
    let t = (w - CIE_MIN) / 5.0;
    let i = (t as usize).min(CIE_5NM.len() - 2);
    let f = t - i as f64;
    let (a, b) = (CIE_5NM[i], CIE_5NM[i + 1]);
    [0, 1, 2, 3].map(|k| a[k] * (1.0 - f) + b[k] * f)
}

/// The `i`-th wavelength of the integral.
fn wavelength(i: usize) -> f64 {
    CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN)
}

/// Σ ȳ and Σ ȳ·D65 over the integral's wavelengths: what a flat spectrum
/// of 1 gives, so that it has luminance 1, with and without D65.
fn norms() -> (f64, f64) {
    (0..STEPS)
        .map(|i| cie(wavelength(i)))
        .fold((0.0, 0.0), |(y, yd), c| (y + c[1], yd + c[1] * c[3]))
}

/// The RGB colour Mitsuba 3's RGB variants give a spectrum used as `usage`.
pub fn to_rgb(spectrum: &Spectrum, usage: Use) -> [f64; 3] {
    match spectrum {
        Spectrum::Constant(v) => match usage {
            Use::Reflectance => [*v; 3],
            Use::Emission => xyz_to_srgb([1.0; 3]).map(|c| c * v),
        },
        Spectrum::Samples(samples) => samples_to_rgb(samples, usage),
    }
}

fn samples_to_rgb(samples: &[(f64, f64)], usage: Use) -> [f64; 3] {
    let (y_norm, yd_norm) = norms();
    let d65 = usage == Use::Reflectance;
    let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
    let mut xyz = [0.0; 3];
    for i in 0..STEPS {
        let w = wavelength(i);
        if w < first || w > last {
            continue;
        }
        let j = samples
            .partition_point(|s| s.0 <= w)
            .clamp(1, samples.len() - 1);
        let ((w0, v0), (w1, v1)) = (samples[j - 1], samples[j]);
        let v = v0 + (v1 - v0) * (w - w0) / (w1 - w0);
        let c = cie(w);
        let weight = if d65 { v * c[3] * y_norm / yd_norm } else { v };
        for k in 0..3 {
            xyz[k] += c[k] * weight;
        }
    }
    let rgb = xyz_to_srgb(xyz.map(|c| c / y_norm));
    match usage {
        Use::Reflectance => rgb.map(|c| c.clamp(0.0, 1.0)),
        Use::Emission => rgb.map(|c| c.max(0.0)),
    }
}

/// Reads `wavelength:value` pairs separated by spaces or commas, or one
/// number. The error says what is wrong with the text.
pub fn parse(text: &str) -> Result<Spectrum, String> {
    let tokens: Vec<&str> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
        .collect();
    if tokens.len() == 1 && !tokens[0].contains(':') {
        return Ok(Spectrum::Constant(super::number::number(tokens[0])?));
    }
    let mut samples = Vec::with_capacity(tokens.len());
    for t in tokens {
        let Some((w, v)) = t.split_once(':') else {
            return Err(format!(
                "`{}` is not a wavelength:value pair",
                crate::input::quote::clip(t, crate::input::quote::MAX_QUOTED_CHARS)
            ));
        };
        samples.push((super::number::number(w)?, super::number::number(v)?));
    }
    samples_checked(samples)
}

/// Reads a spectrum file: a `wavelength value` pair on each line, `#`
/// comments and blank lines skipped.
pub fn parse_file(text: &str) -> Result<Spectrum, String> {
    let mut samples = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut parts = line.split_whitespace();
        let (Some(w), Some(v)) = (parts.next(), parts.next()) else {
            return Err(format!("line {}: expected a wavelength and a value", n + 1));
        };
        let pair = (super::number::number(w), super::number::number(v));
        match pair {
            (Ok(w), Ok(v)) => samples.push((w, v)),
            (Err(e), _) | (_, Err(e)) => return Err(format!("line {}: {e}", n + 1)),
        }
    }
    samples_checked(samples)
}

pub fn samples_checked(samples: Vec<(f64, f64)>) -> Result<Spectrum, String> {
    if samples.len() < 2 {
        return Err("a spectrum needs at least two wavelength:value pairs".into());
    }
    if samples.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err("the wavelengths of a spectrum must increase".into());
    }
    Ok(Spectrum::Samples(samples))
}

include!("cie_table.rs");

#[cfg(test)]
mod tests {
    use super::*;

    /// x̄, ȳ, z̄ from the CIE's 1 nm table taken every 10 nm (not the 5 nm
    /// table the conversion interpolates), to check its integral independently.
    const CIE_10NM: [(f64, [f64; 3]); 47] = [
        (360.0, [0.0001299, 3.917e-06, 0.0006061]),
        (370.0, [0.0004149, 1.239e-05, 0.001946]),
        (380.0, [0.001368, 3.9e-05, 0.006450001]),
        (390.0, [0.004243, 0.00012, 0.02005001]),
        (400.0, [0.01431, 0.000396, 0.06785001]),
        (410.0, [0.04351, 0.00121, 0.2074]),
        (420.0, [0.13438, 0.004, 0.6456]),
        (430.0, [0.2839, 0.0116, 1.3856]),
        (440.0, [0.34828, 0.023, 1.74706]),
        (450.0, [0.3362, 0.038, 1.77211]),
        (460.0, [0.2908, 0.06, 1.6692]),
        (470.0, [0.19536, 0.09098, 1.28764]),
        (480.0, [0.09564, 0.13902, 0.8129501]),
        (490.0, [0.03201, 0.20802, 0.46518]),
        (500.0, [0.0049, 0.323, 0.272]),
        (510.0, [0.0093, 0.503, 0.1582]),
        (520.0, [0.06327, 0.71, 0.07824999]),
        (530.0, [0.1655, 0.862, 0.04216]),
        (540.0, [0.2904, 0.954, 0.0203]),
        (550.0, [0.4334499, 0.9949501, 0.008749999]),
        (560.0, [0.5945, 0.995, 0.0039]),
        (570.0, [0.7621, 0.952, 0.0021]),
        (580.0, [0.9163, 0.87, 0.001650001]),
        (590.0, [1.0263, 0.757, 0.0011]),
        (600.0, [1.0622, 0.631, 0.0008]),
        (610.0, [1.0026, 0.503, 0.00034]),
        (620.0, [0.8544499, 0.381, 0.00019]),
        (630.0, [0.6424, 0.265, 4.999999e-05]),
        (640.0, [0.4479, 0.175, 2e-05]),
        (650.0, [0.2835, 0.107, 0.0]),
        (660.0, [0.1649, 0.061, 0.0]),
        (670.0, [0.0874, 0.032, 0.0]),
        (680.0, [0.04677, 0.017, 0.0]),
        (690.0, [0.0227, 0.00821, 0.0]),
        (700.0, [0.01135916, 0.004102, 0.0]),
        (710.0, [0.005790346, 0.002091, 0.0]),
        (720.0, [0.002899327, 0.001047, 0.0]),
        (730.0, [0.001439971, 0.00052, 0.0]),
        (740.0, [0.0006900786, 0.0002492, 0.0]),
        (750.0, [0.0003323011, 0.00012, 0.0]),
        (760.0, [0.0001661505, 6e-05, 0.0]),
        (770.0, [8.307527e-05, 3e-05, 0.0]),
        (780.0, [4.150994e-05, 1.499e-05, 0.0]),
        (790.0, [2.067383e-05, 7.4657e-06, 0.0]),
        (800.0, [1.025398e-05, 3.7029e-06, 0.0]),
        (810.0, [5.085868e-06, 1.8366e-06, 0.0]),
        (820.0, [2.522525e-06, 9.1093e-07, 0.0]),
    ];

    /// XYZ of a spectrum by Simpson's rule on the 10 nm table, normalised
    /// so that Y of a flat 1 is 1: no D65, no 1000-point sum.
    fn simpson_xyz(f: impl Fn(f64) -> f64) -> [f64; 3] {
        // 46 intervals from 360 to 820 nm (the curves are below 1e-5 past it).
        let n = CIE_10NM.len() - 1;
        let mut xyz = [0.0; 3];
        let mut y1 = 0.0;
        for (i, (w, c)) in CIE_10NM.iter().enumerate() {
            let weight = match i {
                0 => 1.0,
                _ if i == n => 1.0,
                _ if i % 2 == 1 => 4.0,
                _ => 2.0,
            };
            for k in 0..3 {
                xyz[k] += weight * c[k] * f(*w);
            }
            y1 += weight * c[1];
        }
        xyz.map(|c| c / y1)
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn a_constant_reflectance_is_grey_and_a_constant_emission_is_srgb_of_xyz_white() {
        assert_eq!(to_rgb(&Spectrum::Constant(0.5), Use::Reflectance), [0.5; 3]);
        let e = to_rgb(&Spectrum::Constant(2.0), Use::Emission);
        // 2 × (row sums of the XYZ → sRGB matrix).
        let by_hand = [2.0 * 1.204794, 2.0 * 0.948291, 2.0 * 0.908916];
        assert!(close(e, by_hand, 1e-12), "{e:?}");
    }

    #[test]
    fn a_flat_reflectance_over_the_visible_range_is_white() {
        // Against D65, a perfect reflector is sRGB white.
        let s = parse("360:1, 830:1").unwrap();
        let rgb = to_rgb(&s, Use::Reflectance);
        assert!(close(rgb, [1.0, 1.0, 1.0], 2e-3), "{rgb:?}");
        let half = to_rgb(&parse("360:0.25 830:0.25").unwrap(), Use::Reflectance);
        assert!(close(half, [0.25; 3], 1e-3), "{half:?}");
    }

    #[test]
    fn a_flat_emission_matches_the_constant_one() {
        let s = to_rgb(&parse("360:3, 830:3").unwrap(), Use::Emission);
        let c = to_rgb(&Spectrum::Constant(3.0), Use::Emission);
        assert!(close(s, c, 1e-2), "{s:?} {c:?}");
    }

    #[test]
    fn emission_spectra_agree_with_an_independent_integral() {
        // A ramp and a bump, integrated by Simpson's rule on a 10 nm table.
        let ramp = |w: f64| (w - 360.0) / 470.0;
        let bump = |w: f64| (-((w - 550.0) / 40.0).powi(2)).exp();
        for f in [&ramp as &dyn Fn(f64) -> f64, &bump] {
            let pairs: Vec<String> = (0..=94)
                .map(|i| {
                    let w = 360.0 + 5.0 * i as f64;
                    format!("{w}:{}", f(w))
                })
                .collect();
            let rgb = to_rgb(&parse(&pairs.join(", ")).unwrap(), Use::Emission);
            let expect = xyz_to_srgb(simpson_xyz(f)).map(|c| c.max(0.0));
            assert!(close(rgb, expect, 0.02), "{rgb:?} {expect:?}");
        }
    }

    #[test]
    fn a_narrow_reflectance_out_of_gamut_is_clamped_and_outside_the_range_is_black() {
        let green = to_rgb(&parse("520:0, 530:1, 540:0").unwrap(), Use::Reflectance);
        assert!(green.iter().all(|c| (0.0..=1.0).contains(c)), "{green:?}");
        assert_eq!(green[0], 0.0);
        let infrared = to_rgb(&parse("900:1, 950:1").unwrap(), Use::Emission);
        assert_eq!(infrared, [0.0; 3]);
    }

    #[test]
    fn malformed_spectra_are_refused() {
        for bad in [
            "400:0.5",
            "500:1, 400:1",
            "400:x",
            "abc",
            "400:nan, 500:1",
            "1e999",
        ] {
            assert!(parse(bad).is_err(), "{bad}");
        }
        assert!(parse_file("# c\n400 0.5\n\n500 0.6\n").is_ok());
        assert!(parse_file("400 0.5\n500\n").unwrap_err().contains("line 2"));
    }
}
