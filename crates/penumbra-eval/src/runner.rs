//! Runs jobs: builds each scene, renders it once, remembers the result, and
//! reports progress in whole jobs. Jobs that differ only in settings share
//! one built world (meshes and BVH) through a [`WorldCache`].
//!
//! The progress callback of the public API is not `Sync`, so it cannot be
//! called from the render's worker threads. Each render runs on a helper
//! thread instead while the calling thread polls its tile counter and calls
//! the callback with the job's label, its percentage, and the number of
//! distinct jobs done and planned — so a render of several minutes still
//! shows movement.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

/// How often a running render's progress is looked at.
const POLL: Duration = Duration::from_millis(250);

use penumbra::render::{render, Image, RenderOptions, RenderStats};
use penumbra::scene::{Scene, WorldCache};

use crate::error::EvalError;
use crate::job::Job;

/// The frame size the thesis used: all its ray counts are for 800×600.
pub const THESIS_PIXELS: f64 = 800.0 * 600.0;

/// A finished render.
#[derive(Debug)]
pub struct Rendered {
    /// Linear radiance of the rendered region.
    pub image: Image,
    pub stats: RenderStats,
    /// Width and height of the whole frame (the region may be smaller).
    pub frame: (u32, u32),
    /// The library's warnings (e.g. a non-square count rounded up for grid).
    pub warnings: Vec<String>,
}

impl Rendered {
    pub fn time(&self) -> Duration {
        self.stats.render_time
    }

    /// Pixels actually rendered.
    pub fn pixels(&self) -> u64 {
        u64::from(self.image.width) * u64::from(self.image.height)
    }

    /// Factor that turns this render's counts into counts at 800×600.
    pub fn scale_to_thesis(&self) -> f64 {
        THESIS_PIXELS / (f64::from(self.frame.0) * f64::from(self.frame.1))
    }
}

/// Renders jobs with a cache and progress reporting.
pub struct Runner<'a> {
    bunny: PathBuf,
    threads: Option<usize>,
    progress: &'a dyn Fn(&str, usize, usize),
    cache: HashMap<String, Rc<Rendered>>,
    worlds: WorldCache,
    planned: HashSet<String>,
    done: usize,
    warnings: Vec<String>,
}

impl<'a> Runner<'a> {
    pub fn new(
        bunny: PathBuf,
        threads: Option<usize>,
        progress: &'a dyn Fn(&str, usize, usize),
    ) -> Runner<'a> {
        Runner {
            bunny,
            threads,
            progress,
            cache: HashMap::new(),
            worlds: WorldCache::default(),
            planned: HashSet::new(),
            done: 0,
            warnings: Vec::new(),
        }
    }

    /// Announces jobs that will run, so the progress total is known early.
    pub fn plan<'j>(&mut self, jobs: impl IntoIterator<Item = &'j Job>) {
        for j in jobs {
            self.planned.insert(j.key());
        }
    }

    /// Distinct jobs planned (or run without being planned).
    pub fn total(&self) -> usize {
        self.planned.len()
    }

    /// Tells the caller what is happening without finishing a job.
    pub fn report(&self, stage: &str) {
        (self.progress)(stage, self.done, self.total());
    }

    /// The library's warnings so far, each once.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Renders a job, or returns the earlier render of the same key.
    pub fn run(&mut self, job: &Job) -> Result<Rc<Rendered>, EvalError> {
        let key = job.key();
        if let Some(r) = self.cache.get(&key) {
            return Ok(Rc::clone(r));
        }
        self.planned.insert(key.clone());
        (self.progress)(&job.label, self.done, self.total());
        let rendered = Rc::new(self.render(job)?);
        self.done += 1;
        (self.progress)(&job.label, self.done, self.total());
        self.cache.insert(key, Rc::clone(&rendered));
        Ok(rendered)
    }

    fn render(&mut self, job: &Job) -> Result<Rendered, EvalError> {
        let scene = job.build(&self.bunny, &mut self.worlds)?;
        for w in &scene.warnings {
            if !self.warnings.contains(w) {
                self.warnings.push(w.clone());
            }
        }
        let (w, h) = (scene.settings.width, scene.settings.height);
        let opts = RenderOptions {
            threads: self.threads,
            region: job.crop.map(|c| c.region(w, h)),
        };
        let (image, stats) = self.watch(&scene, &opts, &job.label)?;
        Ok(Rendered {
            image,
            stats,
            frame: (w, h),
            warnings: scene.warnings.clone(),
        })
    }

    /// Renders on a helper thread and reports the share of tiles done while
    /// waiting for it.
    fn watch(
        &self,
        scene: &Scene,
        opts: &RenderOptions,
        label: &str,
    ) -> Result<(Image, RenderStats), EvalError> {
        let tiles = (AtomicUsize::new(0), AtomicUsize::new(0));
        let record = |done: usize, total: usize| {
            tiles.0.store(done, Ordering::Relaxed);
            tiles.1.store(total, Ordering::Relaxed);
        };
        let (tx, rx) = mpsc::channel();
        let result = std::thread::scope(|s| {
            let worker = s.spawn(move || {
                // A send fails only if the receiver is gone, which it is not.
                let _ = tx.send(render(scene, opts, &record, None));
            });
            let mut shown = 0;
            loop {
                match rx.recv_timeout(POLL) {
                    Ok(r) => break Some(r),
                    Err(RecvTimeoutError::Disconnected) => break None,
                    Err(RecvTimeoutError::Timeout) => {}
                }
                let done = tiles.0.load(Ordering::Relaxed);
                let percent = (100 * done)
                    .checked_div(tiles.1.load(Ordering::Relaxed))
                    .unwrap_or(0);
                if percent > shown {
                    shown = percent;
                    (self.progress)(&format!("{label} ({percent}%)"), self.done, self.total());
                }
            }
            .filter(|_| worker.join().is_ok())
        });
        let job = label.to_string();
        match result {
            Some(r) => r.map_err(|source| EvalError::Render { job, source }),
            None => Err(EvalError::Panicked { job }),
        }
    }
}
