//! `uniform`: every emitter with probability `1 / n`, wherever the
//! shading point is (pbrt-v4's `UniformLightSampler`, Mitsuba 3's choice
//! among emitters of equal `sampling_weight`).

/// The uniform choice among `n` emitters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformSampler {
    n: usize,
}

impl UniformSampler {
    pub fn new(n: usize) -> UniformSampler {
        UniformSampler { n }
    }

    /// Emitter `⌊u · n⌋` with probability `1 / n`; `None` without emitters.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(u32, f32)> {
        if self.n == 0 {
            return None;
        }
        let k = ((u * self.n as f32) as usize).min(self.n - 1);
        Some((k as u32, 1.0 / self.n as f32))
    }

    #[inline]
    pub fn pmf(&self, emitter: u32) -> f32 {
        if (emitter as usize) < self.n {
            1.0 / self.n as f32
        } else {
            0.0
        }
    }
}
