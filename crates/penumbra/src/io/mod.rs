//! Files out: image writers (PNG, EXR), atomic.

pub mod output;
