//! The calibrated rule's promises, checked pixel by pixel against a
//! reference: its interval holds the pixel's true value about as often as
//! its confidence says (coverage), and a pixel it stops is not far off
//! (false stops).

use penumbra::integrator::stopping::calibrated::allowed;
use penumbra::integrator::stopping::PixelSamples;
use penumbra::math::Rgb;
use serde::Serialize;

/// What a calibrated render's pixels show against the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Coverage {
    /// Pixels with an interval.
    pub pixels: usize,
    /// Of those, pixels whose largest channel error is within the interval's
    /// half-width (the largest channel's, the one the rule compares).
    pub covered: usize,
    /// Pixel channels with an interval, and those within their own
    /// channel's half-width.
    pub channels: usize,
    pub channels_covered: usize,
    /// Pixels the rule stopped before the budget.
    pub stopped: usize,
    /// Stopped pixels whose largest channel error exceeds `3 T`, `T` the
    /// threshold times the largest channel of the pixel's value, or times
    /// the floor (`noise_floor`) below it: the rule's own measure.
    pub false_stops: usize,
    /// Pixels in all.
    pub total: usize,
}

impl Coverage {
    /// Coverage of the pixels' intervals.
    pub fn rate(&self) -> f64 {
        self.covered as f64 / self.pixels.max(1) as f64
    }

    /// Coverage of the channels' intervals.
    pub fn channel_rate(&self) -> f64 {
        self.channels_covered as f64 / self.channels.max(1) as f64
    }

    /// False stops as a share of all pixels.
    pub fn false_stop_rate(&self) -> f64 {
        self.false_stops as f64 / self.total.max(1) as f64
    }

    /// The counts of two renders together.
    pub fn add(&mut self, o: &Coverage) {
        self.pixels += o.pixels;
        self.covered += o.covered;
        self.channels += o.channels;
        self.channels_covered += o.channels_covered;
        self.stopped += o.stopped;
        self.false_stops += o.false_stops;
        self.total += o.total;
    }
}

/// Checks `values` (a render by the calibrated rule at `threshold` and
/// `floor` with `spp` rays at most, its pixels' `samples`) against
/// `reference`, pixel by pixel.
pub fn check(
    values: &[Rgb],
    reference: &[Rgb],
    samples: &[PixelSamples],
    spp: u32,
    (threshold, floor): (f32, f32),
) -> Coverage {
    let mut c = Coverage::default();
    for ((v, r), s) in values.iter().zip(reference).zip(samples) {
        c.total += 1;
        let err = (*v - *r).abs();
        let worst = err.max_element();
        if let Some(h) = s.half_width {
            c.pixels += 1;
            c.covered += usize::from(worst <= h.max_element());
            for (e, h) in err.to_array().into_iter().zip(h.to_array()) {
                c.channels += 1;
                c.channels_covered += usize::from(e <= h);
            }
        }
        if s.count < spp {
            c.stopped += 1;
            let t = allowed(threshold, floor, *v);
            c.false_stops += usize::from(worst > 3.0 * t);
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(count: u32, h: Option<f32>) -> PixelSamples {
        PixelSamples {
            count,
            half_width: h.map(Rgb::splat),
        }
    }

    /// Ten pixels with known errors: the counts follow by hand.
    #[test]
    fn coverage_and_false_stops_on_a_known_case() {
        let reference = vec![Rgb::splat(0.5); 10];
        // Errors 0.00, 0.01, …, 0.09 on the red channel.
        let values: Vec<Rgb> = (0..10)
            .map(|k| Rgb::new(0.5 + 0.01 * k as f32, 0.5, 0.5))
            .collect();
        // Half-width 0.045: pixels 0–4 covered, 5–9 not. Pixel 9 never
        // stopped (took the budget of 64).
        let mut s: Vec<PixelSamples> = (0..9).map(|_| samples(32, Some(0.045))).collect();
        s.push(samples(64, Some(0.045)));
        // T = 0.02 of a value of about 0.55: 3T ≈ 0.033; stopped pixels with
        // errors 0.04 … 0.08 (4 to 8) are false stops.
        let c = check(&values, &reference, &s, 64, (0.02, 0.001));
        assert_eq!(c.total, 10);
        assert_eq!(c.pixels, 10);
        assert_eq!(c.covered, 5);
        assert!((c.rate() - 0.5).abs() < 1e-12);
        // Green and blue are exact: 20 of 30 channels covered + red 5.
        assert_eq!((c.channels, c.channels_covered), (30, 25));
        assert_eq!(c.stopped, 9);
        assert_eq!(c.false_stops, 5);
        assert!((c.false_stop_rate() - 0.5).abs() < 1e-12);
    }

    /// A black pixel is judged against the floor; a pixel without an
    /// interval (another rule) counts only in the totals.
    #[test]
    fn the_floor_and_pixels_without_intervals() {
        let reference = [Rgb::ZERO, Rgb::ZERO];
        let values = [Rgb::splat(2e-4), Rgb::splat(4e-4)];
        let s = [samples(8, Some(1e-4)), samples(8, None)];
        let c = check(&values, &reference, &s, 64, (0.1, 0.001));
        assert_eq!((c.pixels, c.covered, c.stopped), (1, 0, 2));
        // 3T = 3 · 0.1 · 0.001 = 3e-4: only the second pixel is off by more.
        assert_eq!(c.false_stops, 1);
        let mut both = c;
        both.add(&c);
        assert_eq!((both.total, both.false_stops), (4, 2));
    }
}
