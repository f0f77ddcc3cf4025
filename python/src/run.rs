//! Running a render without holding the GIL, while staying responsive to
//! Ctrl-C and reporting progress to Python.
//!
//! The render runs on a scoped thread, which hands the tiles to the
//! library's worker pool. The calling thread waits for it with the GIL
//! released, waking every [`POLL`] to re-acquire the GIL, run Python's signal
//! handlers (`PyErr_CheckSignals`: only the main thread can) and call the
//! progress callback. On an exception (KeyboardInterrupt, or one raised by
//! the callback) it sets the render's cancel flag, waits for the tiles in
//! flight to stop (each checks the flag before every row of pixels), and
//! raises. Python code is never called from a rayon worker.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError};
use pyo3::prelude::*;

use penumbra::render::{render as lib_render, Image, RenderError, RenderOptions, RenderStats};
use penumbra::scene::Scene;

/// How often the waiting thread checks for signals and progress: short
/// enough that Ctrl-C feels immediate, long enough to cost nothing.
const POLL: Duration = Duration::from_millis(50);

pub fn render(
    py: Python<'_>,
    scene: &Scene,
    opts: &RenderOptions,
    progress: Option<&Py<PyAny>>,
) -> PyResult<(Image, RenderStats)> {
    let cancel = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let total = AtomicUsize::new(0);
    let report = |d: usize, t: usize| {
        total.store(t, Ordering::Relaxed);
        done.fetch_max(d, Ordering::Relaxed);
    };
    // Set (and signalled) by the render thread when it is done.
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let result = lib_render(scene, opts, &report, Some(&cancel));
            let (flag, signal) = &finished;
            *flag.lock().unwrap_or_else(|e| e.into_inner()) = true;
            signal.notify_all();
            result
        });
        let mut shown = 0;
        let mut failure: Option<PyErr> = None;
        loop {
            let done_rendering = py.detach(|| {
                let (flag, signal) = &finished;
                let guard = flag.lock().unwrap_or_else(|e| e.into_inner());
                let (guard, _) = signal
                    .wait_timeout_while(guard, POLL, |f| !*f)
                    .unwrap_or_else(|e| e.into_inner());
                *guard
            });
            if let Err(e) = py.check_signals() {
                failure = Some(e);
                break;
            }
            if let Some(callback) = progress {
                let d = done.load(Ordering::Relaxed);
                if d > shown {
                    shown = d;
                    let t = total.load(Ordering::Relaxed);
                    if let Err(e) = callback.call1(py, (d, t)) {
                        failure = Some(e);
                        break;
                    }
                }
            }
            if done_rendering {
                break;
            }
        }
        if failure.is_some() {
            cancel.store(true, Ordering::Relaxed);
        }
        let joined = py.detach(|| worker.join());
        match (failure, joined) {
            (Some(e), _) => Err(e),
            (None, Ok(Ok(result))) => Ok(result),
            (None, Ok(Err(RenderError::Cancelled))) => {
                Err(PyKeyboardInterrupt::new_err("render cancelled"))
            }
            (None, Ok(Err(e))) => Err(PyRuntimeError::new_err(e.to_string())),
            (None, Err(_)) => Err(PyRuntimeError::new_err(
                "the renderer panicked (a bug: please report it with the scene)",
            )),
        }
    })
}
