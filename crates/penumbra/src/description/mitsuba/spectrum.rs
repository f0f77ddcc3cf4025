//! Spectra to RGB, as Mitsuba 3's RGB variants turn a `<spectrum>` into a
//! colour (`spectrum_list_to_srgb` in Mitsuba's `src/core/spectrum.cpp`).
//!
//! A constant spectrum (`value="0.5"`) is that value on every channel,
//! except for an emitter: there it is the value times the sRGB image of
//! the XYZ colour (1, 1, 1), the colour a flat spectrum has against sRGB's
//! D65 white.
//!
//! A list of `wavelength:value` pairs (or a file of them) is reduced in
//! double precision:
//!
//! - it is read at 1000 evenly spaced wavelengths from 360 nm to 830 nm
//!   (both included), interpolated linearly between its two neighbouring
//!   wavelengths; a wavelength outside its first and last contributes
//!   nothing;
//! - each value is weighted by the CIE 1931 2° colour matching functions,
//!   interpolated linearly in the CIE's table every 5 nm (the 95 values
//!   Mitsuba stores, in single precision) and, except for an emitter, by
//!   the CIE D65 illuminant times 1 / 98.99741751876255;
//! - the sum is scaled by 470 / 1000 / 106.7502593994140625, a constant
//!   (not the sum of ȳ over the same wavelengths), and taken from XYZ to
//!   linear sRGB;
//! - a reflectance (bounded to [0, 1]) is clamped to [0, 1], anything else
//!   (an emitter's radiance, a conductor's `eta` and `k`) has its negative
//!   channels set to 0.
//!
//! So a flat reflectance (or conductor index) of 1 over 360–830 nm is
//! (0.99899, 0.99887, 0.99880), not exactly white, and a flat emission of 1
//! is (1.20488, 0.94823, 0.90927), as in Mitsuba. Mitsuba reduces the files
//! of a named conductor `material` without D65, as an emission; a
//! `<spectrum>` given as `eta` or `k` is weighted by D65, so the same file
//! gives other numbers there.

/// Shortest and longest wavelength integrated over, in nanometres.
const CIE_MIN: f64 = 360.0;
const CIE_MAX: f64 = 830.0;
/// Wavelengths the integral is taken at.
const STEPS: usize = 1000;
/// Mitsuba's scale on x̄, ȳ, z̄ (`MI_CIE_Y_NORMALIZATION`).
/// Mitsuba writes the divisor out as 106.7502593994140625, the same double.
const Y_NORMALIZATION: f64 = 1.0 / 106.75025939941406;
/// Mitsuba's scale on the D65 table (`MI_CIE_D65_NORMALIZATION`).
const D65_NORMALIZATION: f64 = 1.0 / 98.99741751876255;

/// A spectrum as a file or an attribute wrote it.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f64),
    /// Values at increasing wavelengths (at least two), in nanometres.
    Samples(Vec<(f64, f64)>),
}

/// What a spectrum gives a value to, which decides how Mitsuba reduces it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// A surface's reflectance (or a texture's colour): weighted by D65,
    /// clamped to [0, 1].
    Reflectance,
    /// An emitter's radiance or intensity: no D65, negatives set to 0.
    Emission,
    /// Another unbounded value (a conductor's `eta` and `k`): weighted by
    /// D65, negatives set to 0.
    Unbounded,
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

/// [`XYZ_TO_SRGB`] with its entries rounded to single precision, as
/// Mitsuba's matrix holds them when it reduces a list of samples.
fn xyz_to_srgb_f32_matrix(xyz: [f64; 3]) -> [f64; 3] {
    XYZ_TO_SRGB.map(|row| {
        let r = row.map(|m| m as f32 as f64);
        r[0] * xyz[0] + r[1] * xyz[1] + r[2] * xyz[2]
    })
}

/// The tables' x̄, ȳ, z̄ and D65 (times [`D65_NORMALIZATION`]) at a
/// wavelength in 360–830 nm, interpolated linearly in the single-precision
/// tables.
fn cie(w: f64) -> [f64; 4] {
    let t = (w - CIE_MIN) * ((CIE_5NM.len() - 1) as f64 / (CIE_MAX - CIE_MIN));
    let i = (t.max(0.0) as usize).min(CIE_5NM.len() - 2);
    let w1 = t - i as f64;
    let w0 = 1.0 - w1;
    let (a, b) = (CIE_5NM[i], CIE_5NM[i + 1]);
    let at = |k: usize| w0 * (a[k] as f32 as f64) + w1 * (b[k] as f32 as f64);
    [at(0), at(1), at(2), at(3) * D65_NORMALIZATION]
}

/// The `i`-th wavelength of the integral.
fn wavelength(i: usize) -> f64 {
    CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN)
}

/// The RGB colour Mitsuba 3's RGB variants give a spectrum used as `usage`.
pub fn to_rgb(spectrum: &Spectrum, usage: Use) -> [f64; 3] {
    match spectrum {
        Spectrum::Constant(v) => match usage {
            Use::Reflectance | Use::Unbounded => [*v; 3],
            Use::Emission => xyz_to_srgb([1.0; 3]).map(|c| c * v),
        },
        Spectrum::Samples(samples) => samples_to_rgb(samples, usage),
    }
}

fn samples_to_rgb(samples: &[(f64, f64)], usage: Use) -> [f64; 3] {
    let d65 = usage != Use::Emission;
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
        let v = ((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1);
        let c = cie(w);
        let weight = if d65 { c[3] } else { 1.0 };
        for k in 0..3 {
            xyz[k] += c[k] * v * weight;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) * Y_NORMALIZATION / STEPS as f64;
    let rgb = xyz_to_srgb_f32_matrix(xyz.map(|c| c * scale));
    match usage {
        Use::Reflectance => rgb.map(|c| c.clamp(0.0, 1.0)),
        Use::Emission | Use::Unbounded => rgb.map(|c| c.max(0.0)),
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
/// comments and blank lines skipped. An error names the line.
pub fn parse_file(text: &str) -> Result<Spectrum, String> {
    let mut samples: Vec<(f64, f64)> = Vec::new();
    let mut last_line = 0;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = n + 1;
        let mut parts = line.split_whitespace();
        let (Some(w), Some(v)) = (parts.next(), parts.next()) else {
            return Err(format!("line {at}: expected a wavelength and a value"));
        };
        let (w, v) = match (super::number::number(w), super::number::number(v)) {
            (Ok(w), Ok(v)) => (w, v),
            (Err(e), _) | (_, Err(e)) => return Err(format!("line {at}: {e}")),
        };
        if let Some(&(before, _)) = samples.last() {
            if w <= before {
                return Err(format!(
                    "line {at}: the wavelength {w} does not exceed the one before it ({before}, line {last_line}); the wavelengths of a spectrum must increase"
                ));
            }
        }
        samples.push((w, v));
        last_line = at;
    }
    if samples.is_empty() {
        return Err("the file holds no `wavelength value` line".into());
    }
    samples_checked(samples).map_err(|e| format!("line {last_line}: {e}"))
}

/// The spectrum of `samples`, which need at least two increasing
/// wavelengths.
pub fn samples_checked(samples: Vec<(f64, f64)>) -> Result<Spectrum, String> {
    if samples.len() < 2 {
        return Err("a spectrum needs at least two wavelength:value pairs".into());
    }
    if let Some(i) = samples.windows(2).position(|w| w[1].0 <= w[0].0) {
        return Err(format!(
            "the wavelengths of a spectrum must increase ({} follows {})",
            samples[i + 1].0,
            samples[i].0
        ));
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

    /// XYZ of a spectrum by Simpson's rule on the 10 nm table, over
    /// 360–820 nm (the curves are below 1e-5 past it), scaled by Mitsuba's
    /// constant 1 / 106.7502593994140625: no D65, no 1000-point sum.
    fn simpson_xyz(f: impl Fn(f64) -> f64) -> [f64; 3] {
        let n = CIE_10NM.len() - 1;
        let mut xyz = [0.0; 3];
        for (i, (w, c)) in CIE_10NM.iter().enumerate() {
            let weight = match i {
                0 => 1.0,
                _ if i == n => 1.0,
                _ if i % 2 == 1 => 4.0,
                _ => 2.0,
            } * 10.0
                / 3.0;
            for k in 0..3 {
                xyz[k] += weight * c[k] * f(*w);
            }
        }
        xyz.map(|c| c / 106.75025939941406)
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn a_constant_reflectance_is_grey_and_a_constant_emission_is_srgb_of_xyz_white() {
        assert_eq!(to_rgb(&Spectrum::Constant(0.5), Use::Reflectance), [0.5; 3]);
        assert_eq!(to_rgb(&Spectrum::Constant(2.5), Use::Unbounded), [2.5; 3]);
        let e = to_rgb(&Spectrum::Constant(2.0), Use::Emission);
        // 2 × (row sums of the XYZ → sRGB matrix).
        let by_hand = [2.0 * 1.204794, 2.0 * 0.948291, 2.0 * 0.908916];
        assert!(close(e, by_hand, 1e-12), "{e:?}");
    }

    /// Sampled spectra give the numbers of Mitsuba 3.9.1's `scalar_rgb`
    /// (a `diffuse` reflectance, a `conductor`'s `eta`, a `constant`
    /// emitter's radiance given the same `<spectrum>`, read back with
    /// `mi.traverse`, in single precision).
    #[test]
    fn sampled_spectra_are_mitsubas_numbers() {
        let flat = parse("360:1, 830:1").unwrap();
        let bumpy = parse("400:0.2, 500:0.6, 600:0.4, 700:0.3").unwrap();
        let cases = [
            (
                &flat,
                Use::Reflectance,
                [0.9989852905273438, 0.9988737106323242, 0.998801589012146],
            ),
            (
                &flat,
                Use::Unbounded,
                [0.9989852905273438, 0.9988737106323242, 0.998801589012146],
            ),
            (
                &flat,
                Use::Emission,
                [1.2048836946487427, 0.9482281804084778, 0.9092668294906616],
            ),
            (
                &bumpy,
                Use::Reflectance,
                [0.3176959455013275, 0.5354747176170349, 0.40488091111183167],
            ),
            (
                &bumpy,
                Use::Unbounded,
                [0.3176959455013275, 0.5354747176170349, 0.40488091111183167],
            ),
            (
                &bumpy,
                Use::Emission,
                [0.4019722640514374, 0.5082738995552063, 0.36133360862731934],
            ),
        ];
        for (s, usage, mitsuba) in cases {
            let rgb = to_rgb(s, usage).map(|c| c as f32 as f64);
            assert_eq!(rgb, mitsuba, "{s:?} {usage:?}");
        }
        // A flat 5 is 5 times a flat 1, with no bound but for a reflectance.
        let five = parse("360:5, 830:5").unwrap();
        let one = to_rgb(&flat, Use::Unbounded);
        assert!(close(
            to_rgb(&five, Use::Unbounded),
            one.map(|c| 5.0 * c),
            1e-12
        ));
        assert_eq!(to_rgb(&five, Use::Reflectance), [1.0; 3]);
    }

    #[test]
    fn emission_spectra_agree_with_an_independent_integral() {
        // A ramp, a bump and a constant, integrated by Simpson's rule on a
        // 10 nm table and scaled by Mitsuba's constant (not by the sum of ȳ).
        let ramp = |w: f64| (w - 360.0) / 470.0;
        let bump = |w: f64| (-((w - 550.0) / 40.0).powi(2)).exp();
        let one = |_: f64| 1.0;
        for f in [&ramp as &dyn Fn(f64) -> f64, &bump, &one] {
            let pairs: Vec<String> = (0..=94)
                .map(|i| {
                    let w = 360.0 + 5.0 * i as f64;
                    format!("{w}:{}", f(w))
                })
                .collect();
            let rgb = to_rgb(&parse(&pairs.join(", ")).unwrap(), Use::Emission);
            let expect = xyz_to_srgb(simpson_xyz(f)).map(|c| c.max(0.0));
            assert!(close(rgb, expect, 3e-3), "{rgb:?} {expect:?}");
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
            "400:1, 400:2",
            "400:x",
            "abc",
            "400:nan, 500:1",
            "400:inf, 500:1",
            "1e999",
            "400:1e999, 500:1",
        ] {
            assert!(parse(bad).is_err(), "{bad}");
        }
        assert!(parse_file("# c\n400 0.5\n\n500 0.6\n").is_ok());
    }

    /// A hostile spectrum file is refused with the line at fault.
    #[test]
    fn hostile_spectrum_files_name_their_line() {
        for (text, want) in [
            (
                "400 0.5\n500\n",
                "line 2: expected a wavelength and a value",
            ),
            (
                "# a\n400 0.5\n600 0.6\n500 0.7\n",
                "line 4: the wavelength 500 does not exceed the one before it (600, line 3)",
            ),
            (
                "400 0.5\n400 0.6\n",
                "line 2: the wavelength 400 does not exceed",
            ),
            ("400 0.5\n500 nan\n", "line 2: `nan` is not a finite number"),
            ("400 0.5\nNaN 0.5\n", "line 2: `NaN` is not a finite number"),
            ("400 0.5\n500 1e999\n", "line 2: `1e999` is out of range"),
            (
                "400 0.5\n500 -inf\n",
                "line 2: `-inf` is not a finite number",
            ),
            ("400 0.5\n", "line 1: a spectrum needs at least two"),
            ("", "the file holds no `wavelength value` line"),
            (
                "# only a comment\n\n",
                "the file holds no `wavelength value` line",
            ),
            (
                "400 0.5\n500 0x10\n",
                "line 2: `0x10` is not a finite number",
            ),
        ] {
            let e = parse_file(text).unwrap_err();
            assert!(e.contains(want), "{text:?}: {e}");
        }
        // Huge but finite values are read; their colour is finite too.
        let s = parse_file("400 1e300\n500 1e300\n").unwrap();
        assert!(to_rgb(&s, Use::Emission).iter().all(|c| c.is_finite()));
    }
}
