//! Running a render without holding the GIL, while staying responsive to
//! Ctrl-C and reporting progress to Python.
//!
//! The render runs on a scoped thread, which hands the tiles to the
//! library's worker pool. The calling thread waits for it with the GIL
//! released, waking every [`POLL`] to re-acquire the GIL, run Python's signal
//! handlers (`PyErr_CheckSignals`: only the main thread can), call the
//! progress callback and hand the images of the passes finished to the
//! `on_pass` callback (the driver only queues them). On an exception
//! (KeyboardInterrupt, or one raised by a callback) it stops the render and
//! raises: a render with checkpoints is *interrupted* (the tiles in flight
//! abandoned within a row, the checkpoint saved, so that it resumes), one
//! without is cancelled (each tile checks the flag before every row of
//! pixels). Python code is never called from a rayon worker.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use penumbra::render::{
    render_progressive, CheckpointError, Checkpointing, Image, PassView, Progressive, RenderError,
    RenderOptions, RenderStats,
};
use penumbra::scene::Scene;

use crate::convert::image_to_numpy;

/// How often the waiting thread checks for signals and progress: short
/// enough that Ctrl-C feels immediate, long enough to cost nothing.
const POLL: Duration = Duration::from_millis(50);

/// What a render does besides rendering, as the Python arguments say.
#[derive(Default)]
pub struct Run<'a> {
    /// `progress(done_tiles, total_tiles)`.
    pub progress: Option<&'a Py<PyAny>>,
    /// `on_pass(image, info)`.
    pub on_pass: Option<&'a Py<PyAny>>,
    pub time_limit: Option<Duration>,
    pub checkpoint: Option<Checkpointing>,
}

/// A pass finished, queued by the render for the Python thread.
struct Pass {
    pass: u32,
    passes: u32,
    image: Image,
    elapsed: f64,
    rays: u64,
}

pub fn render(
    py: Python<'_>,
    scene: &Scene,
    opts: &RenderOptions,
    run: Run<'_>,
) -> PyResult<(Image, RenderStats)> {
    let cancel = AtomicBool::new(false);
    let interrupt = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let total = AtomicUsize::new(0);
    let report = |d: usize, t: usize| {
        total.store(t, Ordering::Relaxed);
        done.fetch_max(d, Ordering::Relaxed);
    };
    // Every pass's image, in order, until the Python thread takes it.
    let queued: Mutex<VecDeque<Pass>> = Mutex::new(VecDeque::new());
    let queue = |view: &PassView<'_>| {
        let pass = Pass {
            pass: view.pass,
            passes: view.passes,
            image: view.image.clone(),
            elapsed: view.stats.render_time.as_secs_f64(),
            rays: view.stats.rays.total(),
        };
        queued
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push_back(pass);
    };
    let interrupted = || interrupt.load(Ordering::Relaxed);
    let clean_stop = run.checkpoint.as_ref().is_some_and(|k| k.save.is_some());
    let progressive = Progressive {
        time_limit: run.time_limit,
        interrupt: Some(&interrupted),
        on_pass: run.on_pass.is_some().then_some(&queue as _),
        checkpoint: run.checkpoint.clone(),
    };
    // Set (and signalled) by the render thread when it is done.
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let result = render_progressive(scene, opts, &report, Some(&cancel), &progressive);
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
            if let Err(e) = poll(py, &run, &queued, (&done, &total), &mut shown) {
                failure = Some(e);
                break;
            }
            if done_rendering {
                break;
            }
        }
        if failure.is_some() {
            match clean_stop {
                true => interrupt.store(true, Ordering::Relaxed),
                false => cancel.store(true, Ordering::Relaxed),
            }
        }
        let joined = py.detach(|| worker.join());
        match (failure, joined) {
            (Some(e), Ok(Ok((_, stats)))) => match stats.checkpoint_error {
                // The render stopped, but its state is not saved: say so.
                Some(saving) => {
                    let error = PyOSError::new_err(saving);
                    error.set_cause(py, Some(e));
                    Err(error)
                }
                None => Err(e),
            },
            (Some(e), _) => Err(e),
            (None, Ok(Ok((_, stats)))) if stats.checkpoint_error.is_some() => Err(
                PyOSError::new_err(stats.checkpoint_error.unwrap_or_default()),
            ),
            (None, Ok(Ok(result))) => Ok(result),
            (None, Ok(Err(RenderError::Cancelled))) => {
                Err(PyKeyboardInterrupt::new_err("render cancelled"))
            }
            (None, Ok(Err(e))) => Err(render_error(e)),
            (None, Err(_)) => Err(PyRuntimeError::new_err(
                "the renderer panicked (a bug: please report it with the scene)",
            )),
        }
    })
}

/// Runs Python's signal handlers, then the callbacks with what the render
/// did since the last poll: `progress` with the tiles done, `on_pass` with
/// each pass finished.
fn poll(
    py: Python<'_>,
    run: &Run<'_>,
    queued: &Mutex<VecDeque<Pass>>,
    (done, total): (&AtomicUsize, &AtomicUsize),
    shown: &mut usize,
) -> PyResult<()> {
    py.check_signals()?;
    if let Some(callback) = run.progress {
        let d = done.load(Ordering::Relaxed);
        if d > *shown {
            *shown = d;
            callback.call1(py, (d, total.load(Ordering::Relaxed)))?;
        }
    }
    if let Some(callback) = run.on_pass {
        loop {
            let next = queued.lock().unwrap_or_else(|e| e.into_inner()).pop_front();
            let Some(pass) = next else { break };
            let info = PyDict::new(py);
            info.set_item("pass", pass.pass)?;
            info.set_item("passes", pass.passes)?;
            info.set_item("elapsed", pass.elapsed)?;
            info.set_item("rays", pass.rays)?;
            callback.call1(py, (image_to_numpy(py, &pass.image)?, info))?;
            py.check_signals()?;
        }
    }
    Ok(())
}

/// A render error as a Python exception: a checkpoint that cannot be
/// resumed is bad input (ValueError naming the file), one that cannot be
/// read or saved an OSError.
fn render_error(e: RenderError) -> PyErr {
    match &e {
        RenderError::Checkpoint(CheckpointError::Read { .. } | CheckpointError::Write { .. }) => {
            PyOSError::new_err(e.to_string())
        }
        RenderError::Checkpoint(_) => PyValueError::new_err(e.to_string()),
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}
