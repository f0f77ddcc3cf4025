//! `constant`: radiance arriving from every direction at infinity — the
//! scene's background (`render.background`), what rays that hit nothing
//! see (Mitsuba 3's `constant` emitter).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `radiance` | colour ≥ 0 | **required** | the radiance of every direction |

use crate::math::Rgb;

#[derive(Clone, Copy, Debug)]
pub struct Constant {
    pub radiance: Rgb,
}
