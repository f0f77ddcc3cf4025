//! Files out: image writers (PNG, EXR, written atomically); a client for
//! the tev image viewer.

pub mod output;
pub mod tev;
