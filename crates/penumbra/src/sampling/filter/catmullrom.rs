//! The Catmull–Rom filter (Mitsuba's `catmullrom`): the
//! [Mitchell–Netravali](super::mitchell) cubic with `B = 0`, `C = 1/2`.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | (none) | | | the radius is 2 pixels |
//!
//! Its profile is [`Mitchell::CATMULL_ROM`]'s: negative between 1 and 2
//! pixels, so samples are drawn from a table of the inverse distribution of
//! `|f|` and each weighs the sign of `f` times `∫|f|/∫f` per axis.

use super::mitchell::Mitchell;
use super::model::{FilterError, FilterModel, FilterParams};

/// The Catmull–Rom filter; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CatmullRom;

impl FilterModel for CatmullRom {
    const NAME: &'static str = "catmullrom";

    fn build(_: &FilterParams) -> Result<CatmullRom, FilterError> {
        Ok(CatmullRom)
    }

    fn radius(self) -> f32 {
        Mitchell::RADIUS
    }

    fn eval(self, x: f64) -> f64 {
        Mitchell::CATMULL_ROM.profile(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_the_mitchell_cubic_of_b_0_c_one_half() {
        let m = Mitchell::new(0.0, 0.5).unwrap();
        for k in -25..=25 {
            let x = 0.1 * f64::from(k);
            assert_eq!(CatmullRom.eval(x).to_bits(), m.profile(x).to_bits(), "{x}");
        }
        assert_eq!(CatmullRom.radius(), 2.0);
    }
}
