//! Pixel filters: how much a sample at an offset from a pixel's centre
//! counts toward that pixel.
//!
//! A filter is applied by importance sampling, as pbrt-v4 does: the film
//! points a pixel's distribution gives in `[-1/2, 1/2]²` are warped, axis by
//! axis, through the inverse of the cumulative distribution of the filter's
//! magnitude `|f|`, so that samples land with a density proportional to
//! `|f|`; each sample then weighs `f / pdf`, which is the sign of `f` at
//! its offset times the normaliser `∫|f| / ∫f`, per axis. The film keeps
//! `Σ w·L / Σ w` per pixel, so a pixel's value depends on its own samples
//! only (whatever the threads, tiles or workers). A filter that is never
//! negative gives every sample the weight 1 exactly. Each warp is
//! monotone, so a stratified set stays stratified. The box filter of
//! radius 1/2, the thesis's supersampling over the pixel, leaves the
//! points as they are.
//!
//! | `filter` | parameters (default) | radius | sign | module |
//! |---|---|---|---|---|
//! | `box` | none | 1/2 | ≥ 0 | [`box`](BoxFilter) |
//! | `tent` | `radius` (1) | `radius` | ≥ 0 | [`tent`] |
//! | `gaussian` | `stddev` (0.5) | 4·`stddev` | ≥ 0 | [`gaussian`] |
//! | `mitchell` | `B` (1/3), `C` (1/3) | 2 | signed | [`mitchell`] |
//! | `catmullrom` | none (`B` = 0, `C` = 1/2) | 2 | signed | [`catmullrom`] |
//! | `lanczos` | `lobes` (3) | `lobes` | signed | [`lanczos`] |
//!
//! The names, parameters and defaults are Mitsuba 3's.
//!
//! Each filter is a type implementing [`FilterModel`], in a file of its
//! own; the enums [`Filter`] (by name) and [`Profile`] (with its
//! parameters) and their dispatch are made by the `filters!` list in this
//! file, one line per filter.

pub mod r#box;
pub mod catmullrom;
pub mod gaussian;
pub mod lanczos;
pub mod mitchell;
mod model;
mod table;
pub mod tent;

use std::sync::Arc;

pub use catmullrom::CatmullRom;
pub use gaussian::Gaussian;
pub use lanczos::Lanczos;
pub use mitchell::Mitchell;
pub use model::{FilterError, FilterModel, FilterParams};
pub use r#box::BoxFilter;
pub use tent::Tent;

use table::InverseCdf;

/// Makes [`Filter`] (each filter listed by name) and [`Profile`] (each
/// with its parameters), `Variant => Model` with the model implementing
/// [`FilterModel`], and their dispatch.
macro_rules! filters {
    ($($variant:ident => $model:ty,)*) => {
        /// A pixel filter by name, with its default parameters: what the
        /// `filter` option chooses. [`PixelFilter`] is the filter with its
        /// parameters.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
        #[serde(rename_all = "lowercase")]
        pub enum Filter {
            $($variant,)*
        }

        /// A filter's profile, with its parameters.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum Profile {
            $($variant($model),)*
        }

        impl Filter {
            /// Every filter, in the list's order.
            pub const ALL: [Filter; [$(Filter::$variant,)*].len()] = [$(Filter::$variant,)*];

            /// The name users write (the serde name too).
            pub fn name(self) -> &'static str {
                match self {
                    $(Filter::$variant => <$model as FilterModel>::NAME,)*
                }
            }

            /// The names of the parameters it takes.
            pub fn params(self) -> &'static [&'static str] {
                match self {
                    $(Filter::$variant => <$model as FilterModel>::PARAMS,)*
                }
            }

            /// Its profile with `params`, or why not.
            fn build(self, params: &FilterParams) -> Result<Profile, FilterError> {
                Ok(match self {
                    $(Filter::$variant => Profile::$variant(<$model as FilterModel>::build(params)?),)*
                })
            }
        }

        impl Profile {
            /// How far from the pixel's centre a sample may land, in pixels.
            pub fn radius(self) -> f32 {
                match self {
                    $(Profile::$variant(f) => <$model as FilterModel>::radius(f),)*
                }
            }

            /// The profile along one axis (not normalised; 0 beyond the radius).
            pub fn eval(self, x: f64) -> f64 {
                match self {
                    $(Profile::$variant(f) => <$model as FilterModel>::eval(f, x),)*
                }
            }

            /// Whether it is sampled by the analytic inverse of its
            /// distribution (else through a table).
            fn is_analytic(self) -> bool {
                match self {
                    $(Profile::$variant(_) => <$model as FilterModel>::ANALYTIC,)*
                }
            }

            /// The offset of film coordinate `p` by the analytic inverse of
            /// the distribution; `None` for a tabulated filter.
            #[inline]
            fn warp(self, p: f32) -> Option<f32> {
                match self {
                    $(Profile::$variant(f) => <$model as FilterModel>::warp(f, p),)*
                }
            }

            /// The cells of its table.
            fn cells(self) -> usize {
                match self {
                    $(Profile::$variant(f) => <$model as FilterModel>::cells(f),)*
                }
            }
        }
    };
}

filters! {
    Box => BoxFilter,
    Tent => Tent,
    Gaussian => Gaussian,
    Mitchell => Mitchell,
    CatmullRom => CatmullRom,
    Lanczos => Lanczos,
}

impl Default for Filter {
    /// The box: the thesis's supersampling over the pixel.
    fn default() -> Self {
        Filter::Box
    }
}

impl Filter {
    pub fn from_name(s: &str) -> Option<Filter> {
        Filter::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// The scene file's keys (`[render]`, the film's) of the filters'
/// parameters, by the parameters' names ([`Filter::params`]).
pub const FILTER_KEYS: [(&str, &str); 5] = [
    ("radius", "filter_radius"),
    ("stddev", "filter_stddev"),
    ("B", "filter_b"),
    ("C", "filter_c"),
    ("lobes", "filter_lobes"),
];

/// A pixel filter with its parameters, ready to sample; see the
/// [module docs](self). Two filters are equal when their names and
/// parameters are.
#[derive(Clone, Debug)]
pub struct PixelFilter {
    filter: Filter,
    profile: Profile,
    /// The tabulated inverse distribution, for the filters without an
    /// analytic one.
    table: Option<Arc<InverseCdf>>,
    /// The weight of a sample where both axes' profiles are positive:
    /// the square of the normaliser `∫|f| / ∫f`.
    weight: f32,
}

impl PartialEq for PixelFilter {
    fn eq(&self, other: &Self) -> bool {
        self.filter == other.filter && self.profile == other.profile
    }
}

impl Default for PixelFilter {
    fn default() -> Self {
        PixelFilter::of(Filter::Box)
    }
}

impl PixelFilter {
    /// `filter` with `params` (the missing ones at their defaults), or why
    /// not: a parameter the filter does not take, or a bad value.
    pub fn new(filter: Filter, params: &FilterParams) -> Result<PixelFilter, FilterError> {
        if let Some(p) = params
            .given()
            .into_iter()
            .find(|p| !filter.params().contains(p))
        {
            let takes = match filter.params() {
                [] => "none".to_string(),
                names => names.join(", "),
            };
            return Err(FilterError {
                param: p,
                message: format!(
                    "the {} filter has no parameter `{p}` (it takes: {takes})",
                    filter.name()
                ),
            });
        }
        let profile = filter.build(params)?;
        let table = if profile.is_analytic() {
            None
        } else {
            let r = profile.radius();
            let t = InverseCdf::new(r, profile.cells(), |x| profile.eval(x)).ok_or_else(|| {
                FilterError {
                    param: filter.params().first().copied().unwrap_or(""),
                    message: format!("the {} filter integrates to nothing", filter.name()),
                }
            })?;
            Some(Arc::new(t))
        };
        let weight = table.as_ref().map_or(1.0, |t| t.norm * t.norm);
        Ok(PixelFilter {
            filter,
            profile,
            table,
            weight,
        })
    }

    /// `filter` with its default parameters.
    pub fn of(filter: Filter) -> PixelFilter {
        PixelFilter::new(filter, &FilterParams::default()).expect("the defaults are valid")
    }

    pub fn filter(&self) -> Filter {
        self.filter
    }

    pub fn profile(&self) -> Profile {
        self.profile
    }

    pub fn radius(&self) -> f32 {
        self.profile.radius()
    }

    /// The profile along one axis (not normalised); 0 beyond the radius.
    pub fn eval(&self, x: f32) -> f32 {
        self.profile.eval(f64::from(x)) as f32
    }

    /// Whether some samples weigh less than 0.
    pub fn is_signed(&self) -> bool {
        self.weight != 1.0
    }

    /// The offset from the pixel's centre, along one axis, of the film
    /// point coordinate `p` in `[-1/2, 1/2]`: distributed in `[-r, r]` with
    /// a density proportional to `|f|` when `p` is uniform, and increasing
    /// in `p`. The box filter returns `p` itself.
    #[inline]
    pub fn warp(&self, p: f32) -> f32 {
        match (self.profile.warp(p), &self.table) {
            (Some(x), _) => x,
            (None, Some(table)) => table.sample(p + 0.5),
            // Every filter without an analytic inverse has a table.
            (None, None) => p,
        }
    }

    /// The offset of film point `(px, py)` (both in `[-1/2, 1/2]`) and the
    /// sample's weight `f / pdf`: 1 for a filter that is never negative,
    /// else the sign of `f` on each axis times the normaliser.
    #[inline]
    pub fn sample(&self, px: f32, py: f32) -> ([f32; 2], f32) {
        let (x, y) = (self.warp(px), self.warp(py));
        if self.weight == 1.0 {
            return ([x, y], 1.0);
        }
        let sign = |x: f32| {
            let f = self.profile.eval(f64::from(x));
            if f > 0.0 {
                1.0
            } else if f < 0.0 {
                -1.0
            } else {
                0.0
            }
        };
        ([x, y], sign(x) * sign(y) * self.weight)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn all() -> Vec<PixelFilter> {
        let mut out: Vec<PixelFilter> = Filter::ALL.into_iter().map(PixelFilter::of).collect();
        let with = |f, p: FilterParams| PixelFilter::new(f, &p).unwrap();
        out.push(with(
            Filter::Tent,
            FilterParams {
                radius: Some(1.7),
                ..Default::default()
            },
        ));
        out.push(with(
            Filter::Gaussian,
            FilterParams {
                stddev: Some(0.3),
                ..Default::default()
            },
        ));
        out.push(with(
            Filter::Mitchell,
            FilterParams {
                b: Some(0.0),
                c: Some(1.0),
                ..Default::default()
            },
        ));
        out.push(with(
            Filter::Lanczos,
            FilterParams {
                lobes: Some(2),
                ..Default::default()
            },
        ));
        out
    }

    /// `∫ f` over `[a, b]` by Simpson's rule in many small cells (a second
    /// way to the integrals the tables make).
    fn integral(f: &PixelFilter, a: f64, b: f64) -> f64 {
        let n = 20_000;
        let h = (b - a) / n as f64;
        let p = f.profile();
        (0..n)
            .map(|i| {
                let x = a + i as f64 * h;
                h / 6.0 * (p.eval(x) + 4.0 * p.eval(x + 0.5 * h) + p.eval(x + h))
            })
            .sum()
    }

    /// Each warp is increasing, stays within the radius, maps the ends of
    /// the film square to the ends of the filter and its centre to 0.
    #[test]
    fn warps_are_monotone_within_the_radius() {
        for f in all() {
            let r = f.radius();
            let mut last = f32::NEG_INFINITY;
            for k in 0..=10_000 {
                let x = f.warp(k as f32 / 10_000.0 - 0.5);
                assert!(x >= last && x.abs() <= r + 1e-6, "{f:?} at {k}: {x}");
                last = x;
            }
            let ends = (f.warp(-0.5) + r).abs().max((f.warp(0.5) - r).abs());
            assert!(ends < 1e-3 * r, "{f:?}");
            assert!(f.warp(0.0).abs() < 1e-3, "{f:?}");
        }
        // The box leaves film points as they are, bit for bit, with weight 1.
        let b = PixelFilter::default();
        for p in [-0.5, -0.123_456_7, 0.0, 1e-9, 0.499_999_9] {
            assert_eq!(b.warp(p).to_bits(), f32::to_bits(p));
            assert_eq!(b.sample(p, -p), ([p, -p], 1.0));
        }
    }

    /// Uniform points warped by each filter fall into 40 bins as often as
    /// the integral of `|f|` over each bin says (χ² against the expected
    /// counts, 39 degrees of freedom, below the 0.1% critical value 72.1).
    #[test]
    fn warped_points_follow_the_magnitude_of_the_filter() {
        let n = 200_000;
        for f in all() {
            let r = f.radius();
            let bins = 40;
            let width = 2.0 * r / bins as f32;
            let mut counts = vec![0u32; bins];
            let mut rng = Rng::new(7);
            for _ in 0..n {
                let x = f.warp(rng.next_f32() - 0.5);
                let b = (((x + r) / width) as usize).min(bins - 1);
                counts[b] += 1;
            }
            let mass: Vec<f64> = (0..bins)
                .map(|b| {
                    (0..200)
                        .map(|j| {
                            let x = -r + (b as f32 + (j as f32 + 0.5) / 200.0) * width;
                            f64::from(f.eval(x).abs())
                        })
                        .sum::<f64>()
                })
                .collect();
            let total: f64 = mass.iter().sum();
            let chi2: f64 = counts
                .iter()
                .zip(&mass)
                .filter(|(_, m)| **m > 0.0)
                .map(|(&c, m)| {
                    let e = m / total * n as f64;
                    (f64::from(c) - e).powi(2) / e
                })
                .sum();
            println!("{:?}: chi2 {chi2:.1}", f.profile());
            assert!(chi2 < 72.1, "{f:?}: chi2 {chi2}");
        }
    }

    /// The mean weight of uniform film points is 1 (`E[f/pdf] = ∫f` with
    /// the profile normalised), within 4 standard errors; the signed
    /// filters have weights of both signs, the others weigh 1 exactly.
    #[test]
    fn weights_average_to_one() {
        let n = 400_000;
        for f in all() {
            let mut rng = Rng::new(11);
            let (mut sum, mut sum2, mut negative) = (0.0f64, 0.0f64, 0);
            for _ in 0..n {
                let (_, w) = f.sample(rng.next_f32() - 0.5, rng.next_f32() - 0.5);
                sum += f64::from(w);
                sum2 += f64::from(w * w);
                negative += usize::from(w < 0.0);
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            println!(
                "{:?}: mean weight {mean:.5} ± {se:.5}, {:.2}% negative",
                f.profile(),
                100.0 * negative as f64 / n as f64
            );
            if f.is_signed() {
                assert!(negative > 0, "{f:?}");
                assert!((mean - 1.0).abs() < 4.0 * se + 1e-3, "{f:?}: {mean} ± {se}");
            } else {
                assert_eq!((mean, negative), (1.0, 0), "{f:?}");
            }
        }
    }

    /// A pixel of an image that is a step edge `I = 1` for `x > e` (0
    /// before), rendered with signed weights (`Σ w·I / Σ w`), reaches the
    /// filtered value `∫_{e}^{r} f / ∫ f` (each integral by a second
    /// quadrature) within 4 standard errors (delta method), and a linear
    /// ramp `I = 2 + 3x + y` reaches its value at the centre, 2.
    #[test]
    fn a_pixel_reaches_the_filtered_image() {
        let n = 400_000;
        for f in all() {
            let r = f64::from(f.radius());
            for e in [-0.7 * r, -0.3, 0.1, 0.45 * r] {
                let want = integral(&f, e, r) / integral(&f, -r, r);
                let mut rng = Rng::new(3);
                let (mut wl, mut w, mut wl2, mut w2, mut wlw) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
                let mut ramp = 0.0f64;
                for _ in 0..n {
                    let ([x, y], weight) = f.sample(rng.next_f32() - 0.5, rng.next_f32() - 0.5);
                    let (weight, x, y) = (f64::from(weight), f64::from(x), f64::from(y));
                    let l = if x > e { 1.0 } else { 0.0 };
                    wl += weight * l;
                    w += weight;
                    wl2 += (weight * l).powi(2);
                    w2 += weight * weight;
                    wlw += weight * l * weight;
                    ramp += weight * (2.0 + 3.0 * x + y);
                }
                let got = wl / w;
                let nf = n as f64;
                // Variance of the ratio of means by the delta method.
                let (ma, mb) = (wl / nf, w / nf);
                let va = wl2 / nf - ma * ma;
                let vb = w2 / nf - mb * mb;
                let cov = wlw / nf - ma * mb;
                let var = (va - 2.0 * got * cov + got * got * vb) / (mb * mb * nf);
                let se = var.max(0.0).sqrt();
                println!(
                    "{:?}, edge {e:.2}: {got:.5} against {want:.5} ± {se:.5}",
                    f.profile()
                );
                assert!(
                    (got - want).abs() < 4.0 * se + 1e-3,
                    "{f:?}, edge {e}: {got} against {want} ± {se}"
                );
                let ramp = ramp / w;
                assert!((ramp - 2.0).abs() < 0.02 * r, "{f:?}: ramp {ramp}");
            }
        }
    }

    #[test]
    fn names_round_trip() {
        for f in Filter::ALL {
            assert_eq!(Filter::from_name(f.name()), Some(f));
            assert_eq!(PixelFilter::of(f).filter(), f);
        }
        assert_eq!(Filter::from_name("sinc"), None);
    }

    /// A parameter the filter does not take, and bad values, are refused
    /// naming the parameter.
    #[test]
    fn bad_parameters_are_refused() {
        let err = |f, p| PixelFilter::new(f, &p).unwrap_err();
        let e = err(
            Filter::Box,
            FilterParams {
                stddev: Some(1.0),
                ..Default::default()
            },
        );
        assert_eq!(e.param, "stddev");
        assert_eq!(
            e.message,
            "the box filter has no parameter `stddev` (it takes: none)"
        );
        let e = err(
            Filter::Gaussian,
            FilterParams {
                stddev: Some(-0.5),
                ..Default::default()
            },
        );
        assert_eq!(e.param, "stddev");
        let e = err(
            Filter::Lanczos,
            FilterParams {
                lobes: Some(0),
                ..Default::default()
            },
        );
        assert_eq!(e.param, "lobes");
        let e = err(
            Filter::Mitchell,
            FilterParams {
                c: Some(2.0),
                ..Default::default()
            },
        );
        assert_eq!(e.param, "C");
        assert_eq!(
            err(
                Filter::CatmullRom,
                FilterParams {
                    b: Some(0.0),
                    ..Default::default()
                }
            )
            .param,
            "B"
        );
    }
}
