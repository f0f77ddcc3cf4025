//! Files out: image writers (PNG, EXR, written atomically).

pub mod output;
