//! BVH build and single-thread traversal throughput on procedurally tessellated
//! bumpy spheres of about 70k and 1M triangles (the size of the Stanford bunny
//! and of a large scan), for the generic [`Bvh`] (triangles through a closure)
//! and the [`TriangleBvh`] that static meshes use.
//!
//! Run with `cargo run --release -p penumbra-bench --example bvh_bench [70k|1M]`. The comparison
//! with Embree, Mitsuba and POV-Ray is `bench/run.py` (docs/performance.md). Every figure is
//! the median of five runs, timed in on-CPU time of the measuring thread where
//! the OS reports it (Linux), so that other load on the machine does not
//! count; wall-clock time otherwise (and always for the multi-threaded build).
//! Incoherent rays start uniformly in the mesh's box and go in uniform random
//! directions; coherent rays are the 800 x 600 primary rays of a pinhole camera
//! framing the mesh.

use penumbra::accel::{Bvh, TriangleBvh};
use penumbra::geometry::tessellate::uv_sphere;
use penumbra::geometry::triangle::{intersect_triangle, RayShear};
use penumbra::math::{Aabb, Ray, Vec3};
use penumbra_bench::{bumpy_radius, median, random_rays, thread_time as now};
use std::time::Instant;

type Tri = [Vec3; 3];

static WALL: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();

fn camera_rays(w: usize, h: usize) -> Vec<Ray> {
    let eye = Vec3::new(0.4, 0.6, 3.2);
    let fwd = (-eye).normalize();
    let right = fwd.cross(Vec3::Y).normalize();
    let up = right.cross(fwd);
    let half = (20.0f32).to_radians().tan();
    let aspect = w as f32 / h as f32;
    let mut rays = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let u = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * half * aspect;
            let v = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * half;
            rays.push(Ray::new(eye, (fwd + u * right + v * up).normalize(), 0.0));
        }
    }
    rays
}

/// Median Mrays/s over five runs and the number of hits.
fn trace(bvh: &Bvh, tris: &[Tri], rays: &[Ray], any: bool) -> (f64, usize) {
    let mut rates = Vec::new();
    let mut hits = 0;
    for _ in 0..5 {
        let start = now();
        hits = 0;
        for ray in rays {
            let shear = RayShear::new(ray);
            let f = |p: u32, tmax: f32| {
                let [a, b, c] = tris[p as usize];
                intersect_triangle(ray, &shear, a, b, c, 0.0, tmax)
            };
            let hit = if any {
                bvh.any_hit(ray, 0.0, f32::INFINITY, |p, t| f(p, t).is_some())
            } else {
                bvh.closest_hit(ray, 0.0, f32::INFINITY, |p, t| f(p, t).map(|h| h.0))
                    .is_some()
            };
            hits += usize::from(hit);
        }
        rates.push(rays.len() as f64 / (now() - start) / 1e6);
    }
    (median(rates), hits)
}

/// Median Mrays/s over five runs and the number of hits, triangle BVH.
fn trace_tri(bvh: &TriangleBvh, rays: &[Ray], any: bool) -> (f64, usize) {
    let mut rates = Vec::new();
    let mut hits = 0;
    for _ in 0..5 {
        let start = now();
        hits = rays
            .iter()
            .filter(|ray| {
                if any {
                    bvh.occluded(ray, 0.0, f32::INFINITY)
                } else {
                    bvh.closest_hit(ray, 0.0, f32::INFINITY).is_some()
                }
            })
            .count();
        rates.push(rays.len() as f64 / (now() - start) / 1e6);
    }
    (median(rates), hits)
}

fn build_ms(bounds: &[Aabb], threads: usize) -> f64 {
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("thread pool: {e}");
            return f64::NAN;
        }
    };
    // One thread: on-CPU time of the worker; several: wall-clock time.
    let clock = move || {
        if threads == 1 {
            now()
        } else {
            WALL.get_or_init(Instant::now).elapsed().as_secs_f64()
        }
    };
    let times = (0..5)
        .map(|_| {
            pool.install(|| {
                let start = clock();
                let bvh = Bvh::build(bounds);
                let ms = (clock() - start) * 1e3;
                std::hint::black_box(bvh);
                ms
            })
        })
        .collect();
    median(times)
}

fn main() {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let only = std::env::args().nth(1);
    let incoherent = 1_000_000;
    let camera = camera_rays(800, 600);
    for (name, nu, nv) in [("70k", 264, 133), ("1M", 1000, 501)] {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let tris = uv_sphere(nu, nv, bumpy_radius);
        let bounds: Vec<Aabb> = tris.iter().map(|t| Aabb::from_points(*t)).collect();
        let serial = build_ms(&bounds, 1);
        let parallel = build_ms(&bounds, threads);
        let bvh = Bvh::build(&bounds);
        let s = bvh.stats();
        println!(
            "{name}: {} tris, build {serial:.1} ms (1 thread), {parallel:.1} ms ({threads} threads); \
             {} nodes, {} leaves, depth {}, SAH {:.2}",
            tris.len(),
            s.nodes,
            s.leaves,
            s.max_depth,
            s.sah_cost
        );
        let start = Instant::now();
        let tbvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        let tri_ms = start.elapsed().as_secs_f64() * 1e3;
        let ts = tbvh.stats();
        println!(
            "  triangle BVH: build {tri_ms:.1} ms ({threads} threads, one run); {} nodes, {} packets, {:.1} MiB",
            ts.nodes,
            ts.packs,
            ts.bytes as f64 / (1 << 20) as f64
        );
        let inc = random_rays(incoherent, &bvh.bounds(), 42);
        for (kind, rays) in [("incoherent", &inc), ("coherent", &camera)] {
            let (closest, ch) = trace(&bvh, &tris, rays, false);
            let (any, ah) = trace(&bvh, &tris, rays, true);
            let (tclosest, tch) = trace_tri(&tbvh, rays, false);
            let (tany, tah) = trace_tri(&tbvh, rays, true);
            println!(
                "  {kind:>10} {} rays, 1 thread ({:.0}% hit), Mrays/s: generic closest {closest:.2}, \
                 any {any:.2}; triangle closest {tclosest:.2}, any {tany:.2}",
                rays.len(),
                100.0 * ch as f64 / rays.len() as f64
            );
            assert_eq!(ch, ah, "closest and any hit disagree on hit counts");
            assert_eq!((tch, tah), (ch, ch), "the two BVHs disagree on hit counts");
        }
    }
}
