//! Cancelling a render: it stops within a row of pixels of every tile in
//! flight, not after the whole frame, and reports that it was cancelled.

mod common;

use common::*;
use penumbra::render::{render, RenderError, RenderOptions};
use penumbra::scene::Scene;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

fn showcase(width: u32, height: u32) -> Scene {
    let mut src = builtin("showcase", None);
    set(
        &mut src,
        penumbra::scene::Overrides {
            width: Some(width),
            height: Some(height),
            ..Default::default()
        },
    );
    src.build().expect("showcase builds")
}

#[test]
fn a_cancel_set_before_the_render_stops_it_at_once() {
    let scene = showcase(64, 48);
    let cancel = AtomicBool::new(true);
    let calls = AtomicUsize::new(0);
    let opts = RenderOptions::default();
    let progress = |_: usize, _: usize| {
        calls.fetch_add(1, Ordering::Relaxed);
    };
    let result = render(&scene, &opts, &progress, Some(&cancel));
    assert!(matches!(result, Err(RenderError::Cancelled)));
    assert_eq!(calls.load(Ordering::Relaxed), 0, "no tile finished");
}

/// Cancelled when the first tile is done: of the 300 tiles, only those
/// that had passed their last row check can still finish.
#[test]
fn a_cancel_during_the_render_stops_the_tiles_in_flight() {
    let scene = showcase(640, 480);
    let cancel = AtomicBool::new(false);
    let calls = AtomicUsize::new(0);
    let threads = 2;
    let opts = RenderOptions {
        threads: Some(threads),
        region: None,
    };
    let progress = |_: usize, _: usize| {
        calls.fetch_add(1, Ordering::Relaxed);
        cancel.store(true, Ordering::Relaxed);
    };
    let result = render(&scene, &opts, &progress, Some(&cancel));
    assert!(matches!(result, Err(RenderError::Cancelled)));
    let finished = calls.load(Ordering::Relaxed);
    assert!(
        (1..=threads).contains(&finished),
        "{finished} tiles finished"
    );
}
