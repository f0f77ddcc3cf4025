//! Instancing: a scene of N instances of the Stanford bunny (one group,
//! one mesh, one triangle tree, N placements, each a random rotation,
//! scale and position on a square grid) against the same scene with one
//! instance. Prints, as JSON, the time to read and build each scene, the
//! memory each holds once built (live heap bytes, counted by this
//! program's allocator) and its peak while building, the difference
//! between the two (what the extra instances cost beyond one bunny), and
//! the closest-hit rate of random rays into the field (one thread, by its
//! CPU time). The scene is read from TOML text, so the times include
//! parsing one `[[objects]]` table per instance.
//!
//! ```text
//! instancebench [--bunny PATH] [--instances N] [--rays N]
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::Instant;

use clap::Parser;
use penumbra::math::{Ray, Vec3};
use penumbra::sampling::Rng;
use penumbra::scene::{default_bunny_path, LoadOptions, Scene, SceneSource};
use penumbra_bench::thread_time;
use serde_json::json;

/// The system allocator, counting the bytes it holds and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is the system allocator's.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = LIVE.fetch_add(layout.size(), Relaxed) + layout.size();
            PEAK.fetch_max(now, Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            let now = if new_size >= layout.size() {
                LIVE.fetch_add(new_size - layout.size(), Relaxed) + new_size - layout.size()
            } else {
                LIVE.fetch_sub(layout.size() - new_size, Relaxed) - (layout.size() - new_size)
            };
            PEAK.fetch_max(now, Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

#[derive(Parser)]
#[command(name = "instancebench")]
struct Args {
    /// The Stanford bunny PLY (else $PENUMBRA_BUNNY).
    #[arg(long)]
    bunny: Option<PathBuf>,
    /// Instances of the bunny.
    #[arg(long, default_value_t = 10_000)]
    instances: u32,
    /// Random rays traced into the field of instances.
    #[arg(long, default_value_t = 200_000)]
    rays: u32,
}

/// The TOML scene of `n` bunnies on a square grid of spacing 0.25 (the
/// bunny is about 0.15 across), each turned, scaled and lifted at random.
fn scene_text(n: u32) -> String {
    let side = (n as f64).sqrt().ceil() as u32;
    let mut r = Rng::new(1);
    let mut text = String::from(
        "[render]\nwidth = 32\nheight = 32\n\n[[groups.bunny.objects]]\ntype = \"mesh\"\npath = \"@bunny\"\n\n",
    );
    for i in 0..n {
        let (x, z) = ((i % side) as f32 * 0.25, (i / side) as f32 * 0.25);
        text += &format!(
            "[[objects]]\ntype = \"instance\"\ngroup = \"bunny\"\ntransform = {{ scale = {}, \
             rotate_axis = [0, 1, 0], rotate_degrees = {}, translate = [{x}, {}, {z}] }}\n",
            r.range(0.6, 1.2),
            r.range(0.0, 360.0),
            r.range(0.0, 0.1),
        );
    }
    text
}

/// Reads and builds the scene of `n` instances: the scene, seconds taken
/// (wall clock and the thread's CPU time), live bytes once built and peak bytes while building, both counted from
/// before the text was made.
type Built = (Scene, (f64, f64), usize, usize);

fn build(n: u32, load: &LoadOptions) -> Result<Built, String> {
    let base = LIVE.load(Relaxed);
    PEAK.store(base, Relaxed);
    let text = scene_text(n);
    let (start, cpu) = (Instant::now(), thread_time());
    let src = SceneSource::from_toml(&text, Path::new("instances.toml"), Path::new("."), load)
        .map_err(|e| e.to_string())?;
    let scene = src.build().map_err(|e| e.to_string())?;
    let took = (start.elapsed().as_secs_f64(), thread_time() - cpu);
    drop((src, text));
    let live = LIVE.load(Relaxed) - base;
    let peak = PEAK.load(Relaxed) - base;
    Ok((scene, took, live, peak))
}

fn run(args: Args) -> Result<serde_json::Value, String> {
    let load = LoadOptions {
        bunny: args.bunny.or_else(default_bunny_path),
        ..Default::default()
    };
    if load.bunny.is_none() {
        return Err("no bunny: give --bunny PATH or set PENUMBRA_BUNNY".into());
    }
    let (one, one_s, one_live, one_peak) = build(1, &load)?;
    drop(one);
    let (many, many_s, many_live, many_peak) = build(args.instances, &load)?;
    // Rays from above the field toward random points of it.
    let b = many.world.bounds();
    let mut r = Rng::new(2);
    let rays: Vec<Ray> = (0..args.rays)
        .map(|_| {
            let o = Vec3::new(
                r.range(b.min.x, b.max.x),
                b.max.y + 1.0,
                r.range(b.min.z, b.max.z),
            );
            let to = Vec3::new(
                r.range(b.min.x, b.max.x),
                b.min.y,
                r.range(b.min.z, b.max.z),
            );
            Ray::new(o, (to - o).normalize(), 0.0)
        })
        .collect();
    let start = thread_time();
    let hits = rays
        .iter()
        .filter(|ray| many.world.intersect(ray, 0.0, f32::INFINITY).is_some())
        .count();
    let trace_s = thread_time() - start;
    let mb = |b: usize| b as f64 / (1 << 20) as f64;
    Ok(json!({
        "instances": args.instances,
        "objects": many.world.objects.len(),
        "one_instance": {
            "load_and_build_s": one_s.0,
            "load_and_build_cpu_s": one_s.1,
            "live_mb": mb(one_live),
            "peak_mb": mb(one_peak),
        },
        "all_instances": {
            "load_and_build_s": many_s.0,
            "load_and_build_cpu_s": many_s.1,
            "build_s": many.build_time.as_secs_f64(),
            "live_mb": mb(many_live),
            "peak_mb": mb(many_peak),
        },
        "extra_live_mb": mb(many_live.saturating_sub(one_live)),
        "extra_peak_mb": mb(many_peak.saturating_sub(one_peak)),
        "rays": args.rays,
        "hit_fraction": hits as f64 / args.rays as f64,
        "closest_hit_mrays_per_s_1_thread": args.rays as f64 / trace_s / 1e6,
    }))
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(doc) => {
            println!("{doc}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("instancebench: {e}");
            ExitCode::from(2)
        }
    }
}
