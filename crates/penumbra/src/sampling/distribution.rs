//! TEMPORARY stand-in; replaced by the full module.
use super::Rng;
use crate::math::Vec3;
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Distribution {
    Grid,
    Jitter,
    SemiJitter,
    Poisson,
    Random,
    FastRandom,
}
impl Distribution {
    pub const ALL: [Distribution; 6] = [
        Self::Grid,
        Self::Jitter,
        Self::SemiJitter,
        Self::Poisson,
        Self::Random,
        Self::FastRandom,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Self::Grid => "grid",
            Self::Jitter => "jitter",
            Self::SemiJitter => "semi-jitter",
            Self::Poisson => "poisson",
            Self::Random => "random",
            Self::FastRandom => "fast-random",
        }
    }
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|d| d.name() == s)
    }
    pub fn is_3d(self) -> bool {
        self == Self::FastRandom
    }
    pub fn needs_square_count(self) -> bool {
        matches!(self, Self::Grid | Self::Jitter | Self::SemiJitter)
    }
    pub fn non_square_warning(self, count: usize) -> Option<String> {
        let s = (count as f64).sqrt().ceil() as usize;
        (self.needs_square_count() && s * s != count).then(|| format!("{count} not square"))
    }
    pub fn generate(self, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        out.clear();
        let s = (count as f64).sqrt().ceil() as usize;
        for i in 0..count {
            let (a, b) = (i / s, i % s);
            let _ = rng.next_f32();
            out.push(Vec3::new(
                radius * (-1.0 + (2 * a + 1) as f32 / s as f32),
                radius * (-1.0 + (2 * b + 1) as f32 / s as f32),
                0.0,
            ));
        }
    }
    pub fn generate_1d(self, count: usize, _rng: &mut Rng, out: &mut Vec<f32>) {
        out.clear();
        for i in 0..count {
            out.push((i as f32 + 0.5) / count as f32);
        }
    }
}
