//! Files out: image writers (PNG, EXR, written atomically), and pictures of
//! ray distributions with the bitmap font their titles use.

pub mod font;
pub mod output;
pub mod plot;
