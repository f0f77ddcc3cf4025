//! Traces ray files through Penumbra's triangle BVH and prints what it
//! measured as JSON: the batch counterpart of what the harness in `bench/`
//! asks of Embree, on the very same triangles and rays (see the crate docs
//! for the file formats).
//!
//! ```text
//! raybench --tris bunny.tris --rays camera=camera.rays --rays incoherent=inc.rays
//!          [--repeat 5] [--obvhs]
//! ```
//!
//! For each ray file: closest hit and any hit over `(0, inf)`, one thread,
//! the number of hits and the median over `--repeat` runs of the on-CPU time
//! of the tracing thread, through the batch calls (`closest_hit_each`,
//! `occluded_each`, which trace runs of rays from one point as packets and
//! interleave the traversals of eight other rays: `rays` in the output) and
//! one ray per call (`closest_hit`, `occluded`: `single`). Build: median
//! time on one thread (on-CPU) and on all threads (wall clock). `--obvhs`
//! (with the `obvhs` feature) also measures the `obvhs` crate's CWBVH, with
//! its own triangle test.

use clap::Parser;
use penumbra::accel::TriangleBvh;
use penumbra::math::{Ray, Vec3};
use penumbra_bench::{median, read_rays, read_triangles, thread_time};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Times Penumbra's BVH (and optionally obvhs's) on ray files and prints
/// JSON: build time, and closest-hit and any-hit rates per ray file.
#[derive(Parser)]
#[command(name = "raybench")]
struct Args {
    /// The triangles, as the harness in bench/ writes them.
    #[arg(long)]
    tris: PathBuf,
    /// A named ray file, NAME=FILE (repeatable).
    #[arg(long = "rays", value_name = "NAME=FILE", value_parser = named_file)]
    rays: Vec<(String, PathBuf)>,
    /// Runs whose median is reported.
    #[arg(long, default_value_t = 5, value_parser = positive)]
    repeat: usize,
    /// Also time the obvhs crate's CWBVH (with the `obvhs` feature).
    #[arg(long)]
    obvhs: bool,
}

/// A count of at least 1.
fn positive(v: &str) -> Result<usize, String> {
    match v.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("`{v}` is not a count of at least 1")),
    }
}

/// `NAME=FILE`.
fn named_file(v: &str) -> Result<(String, PathBuf), String> {
    let (name, path) = v.split_once('=').ok_or("--rays takes NAME=FILE")?;
    Ok((name.to_string(), PathBuf::from(path)))
}

/// Median seconds over `repeat` runs of `f` timed on one thread (on-CPU time).
fn time_cpu(repeat: usize, mut f: impl FnMut() -> usize) -> (f64, usize) {
    let mut times = Vec::new();
    let mut out = 0;
    for _ in 0..repeat {
        let start = thread_time();
        out = f();
        times.push(thread_time() - start);
    }
    (median(times), out)
}

/// Median build times: one thread (on-CPU) and all threads (wall clock).
fn time_build<T: Send>(repeat: usize, build: impl Fn() -> T + Sync) -> Value {
    let threads = rayon::current_num_threads();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build();
    let serial = one.map(|pool| {
        pool.install(|| {
            time_cpu(repeat, || {
                std::hint::black_box(build());
                0
            })
            .0
        })
    });
    let parallel = median(
        (0..repeat)
            .map(|_| {
                let start = Instant::now();
                std::hint::black_box(build());
                start.elapsed().as_secs_f64()
            })
            .collect(),
    );
    json!({
        "ms_1_thread": serial.ok().map(|s| s * 1e3),
        "ms_all_threads": parallel * 1e3,
        "threads": threads,
    })
}

fn rate(n: usize, seconds: f64, hits: usize) -> Value {
    json!({
        "hits": hits,
        "seconds": seconds,
        "mrays_per_s": n as f64 / seconds / 1e6,
    })
}

/// Times `closest` and `any` (each traces a whole set and counts its hits)
/// over every ray set, after `prepare` turned the set into what they take.
fn set_rates<S>(
    args: &Args,
    rays: &[(String, Vec<Ray>)],
    prepare: impl Fn(&[Ray]) -> S,
    mut closest: impl FnMut(&S) -> usize,
    mut any: impl FnMut(&S) -> usize,
) -> Value {
    let mut out = serde_json::Map::new();
    for (name, set) in rays {
        let prepared = prepare(set);
        let (tc, hits_closest) = time_cpu(args.repeat, || closest(&prepared));
        let (ta, hits_any) = time_cpu(args.repeat, || any(&prepared));
        out.insert(
            name.clone(),
            json!({
                "rays": set.len(),
                "closest": rate(set.len(), tc, hits_closest),
                "any": rate(set.len(), ta, hits_any),
            }),
        );
    }
    Value::Object(out)
}

/// [`set_rates`] one ray per call: `closest` and `any` say whether a ray hit.
fn rates<R>(
    args: &Args,
    rays: &[(String, Vec<Ray>)],
    prepare: impl Fn(&[Ray]) -> Vec<R>,
    closest: impl Fn(&R) -> bool,
    any: impl Fn(&R) -> bool,
) -> Value {
    let count = |f: &dyn Fn(&R) -> bool, set: &Vec<R>| set.iter().filter(|r| f(r)).count();
    set_rates(
        args,
        rays,
        prepare,
        |set| count(&closest, set),
        |set| count(&any, set),
    )
}

/// [`set_rates`] through the batch calls (`closest_hit_each`,
/// `occluded_each`: runs as packets, the other rays interleaved), each ray
/// over `(0, inf)`.
fn batch_rates(args: &Args, rays: &[(String, Vec<Ray>)], bvh: &TriangleBvh) -> Value {
    let (mut hits, mut blocked) = (Vec::new(), Vec::new());
    set_rates(
        args,
        rays,
        |set| (set.to_vec(), vec![f32::INFINITY; set.len()]),
        |(set, tmax)| {
            bvh.closest_hit_each(set, 0.0, tmax, &mut hits);
            hits.iter().filter(|h| h.is_some()).count()
        },
        |(set, tmax)| {
            bvh.occluded_each(set, 0.0, tmax, &mut blocked);
            blocked.iter().filter(|&&b| b).count()
        },
    )
}

fn penumbra(args: &Args, tris: &[[Vec3; 3]], rays: &[(String, Vec<Ray>)]) -> Value {
    let build = time_build(args.repeat, || TriangleBvh::build(tris.len(), |i| tris[i]));
    let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
    let s = bvh.stats();
    let single = rates(
        args,
        rays,
        <[Ray]>::to_vec,
        |r| bvh.closest_hit(r, 0.0, f32::INFINITY).is_some(),
        |r| bvh.occluded(r, 0.0, f32::INFINITY),
    );
    let batch = batch_rates(args, rays, &bvh);
    json!({
        "build": build,
        "tree": {
            "nodes": s.nodes,
            "leaves": s.leaves,
            "packs": s.packs,
            "lane_fill": s.triangles as f64 / (4 * s.packs.max(1)) as f64,
            "bytes": s.bytes,
        },
        "rays": batch,
        "single": single,
    })
}

#[cfg(feature = "obvhs")]
fn obvhs(args: &Args, tris: &[[Vec3; 3]], rays: &[(String, Vec<Ray>)]) -> Value {
    use obvhs::cwbvh::builder::build_cwbvh_from_tris;
    use obvhs::ray::{Ray as ORay, RayHit};
    use obvhs::rt_triangle::RtTriangle;
    use obvhs::triangle::Triangle;
    use obvhs::BvhBuildParams;
    use std::time::Duration;
    let v = |p: Vec3| glam::Vec3A::new(p.x, p.y, p.z);
    let otris: Vec<Triangle> = tris
        .iter()
        .map(|t| Triangle {
            v0: v(t[0]),
            v1: v(t[1]),
            v2: v(t[2]),
        })
        .collect();
    let make = || {
        build_cwbvh_from_tris(
            &otris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        )
    };
    let build = time_build(args.repeat, make);
    let bvh = make();
    // Triangles in the tree's primitive order, as obvhs's examples do.
    let rt: Vec<RtTriangle> = bvh
        .primitive_indices
        .iter()
        .map(|&i| RtTriangle::from(&otris[i as usize]))
        .collect();
    let out = rates(
        args,
        rays,
        |set| {
            set.iter()
                .map(|r| ORay::new_inf(v(r.origin), v(r.dir)))
                .collect::<Vec<ORay>>()
        },
        |&r| {
            let mut hit = RayHit::none();
            bvh.ray_traverse(r, &mut hit, |r, id| rt[id].intersect(r))
        },
        |&r| !bvh.ray_traverse_miss(r, |r, id| rt[id].intersect(r)),
    );
    json!({ "build": build, "rays": out })
}

#[cfg(not(feature = "obvhs"))]
fn obvhs(_: &Args, _: &[[Vec3; 3]], _: &[(String, Vec<Ray>)]) -> Value {
    json!({ "error": "built without the obvhs feature" })
}

fn main() -> ExitCode {
    let args = Args::parse();
    let loaded = read_triangles(&args.tris).and_then(|t| {
        let rays = args
            .rays
            .iter()
            .map(|(n, p)| Ok((n.clone(), read_rays(p)?)))
            .collect::<Result<Vec<_>, String>>()?;
        Ok((t, rays))
    });
    let (tris, rays) = match loaded {
        Ok(x) => x,
        Err(e) => {
            eprintln!("raybench: {e}");
            return ExitCode::from(2);
        }
    };
    let mut doc = json!({
        "triangles": tris.len(),
        "penumbra": penumbra(&args, &tris, &rays),
    });
    if args.obvhs {
        doc["obvhs"] = obvhs(&args, &tris, &rays);
    }
    println!("{doc:#}");
    ExitCode::SUCCESS
}
