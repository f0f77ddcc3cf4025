//! `moment`: the integrator it holds, its films also adding up each
//! sample's CIE XYZ and its square (Mitsuba 3's `moment`).

use crate::integrator::film::Channels;
use crate::integrator::interface::Integrator;
use crate::scene::Scene;

/// The held integrator `inner` (named `name` in the channels), the first
/// and second moments of its samples beside its image.
pub struct Moment<'a, I> {
    pub inner: &'a I,
    pub names: Vec<String>,
}

impl<'a, I: Integrator> Moment<'a, I> {
    /// The moments of `inner`'s samples, in channels `name.X`, `name.Y`,
    /// `name.Z`, `m2_name.X`, `m2_name.Y`, `m2_name.Z`, Mitsuba's names.
    pub fn new(inner: &'a I, name: &str) -> Self {
        Moment {
            inner,
            names: channel_names(name),
        }
    }
}

/// The channels of `moment` holding an integrator named `name`.
pub fn channel_names(name: &str) -> Vec<String> {
    let first: Vec<String> = ["X", "Y", "Z"]
        .iter()
        .map(|c| format!("{name}.{c}"))
        .collect();
    let second = first.iter().map(|n| format!("m2_{n}"));
    first.iter().cloned().chain(second).collect()
}

impl<'a, I: Integrator> Integrator for Moment<'a, I> {
    type Worker<'s>
        = I::Worker<'s>
    where
        Self: 's;
    type TileState = I::TileState;

    fn worker<'s>(&'s self, scene: &'s Scene) -> Self::Worker<'s> {
        self.inner.worker(scene)
    }

    fn samples(&self) -> u32 {
        self.inner.samples()
    }

    fn passes(&self) -> u32 {
        self.inner.passes()
    }

    fn whole_tiles(&self) -> bool {
        self.inner.whole_tiles()
    }

    fn tile(&self) -> u32 {
        self.inner.tile()
    }

    fn state_fits(&self, state: &Self::TileState, size: (u32, u32)) -> bool {
        self.inner.state_fits(state, size)
    }

    fn channels(&self) -> Channels {
        Channels {
            names: self.names.clone(),
            moments: true,
            image: None,
        }
    }
}
