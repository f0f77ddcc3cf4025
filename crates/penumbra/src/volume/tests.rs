//! The majorant grid, its walk and the tracking over it, against what they
//! must be: bounds that hold at every point, stretches that tile the ray,
//! and estimates equal to the closed-form transmittance.

use std::sync::Arc;

use super::gridvolume::{Filter, GridVolume};
use super::majorant::{clip_to_box, DEFAULT_RESOLUTION};
use super::tracking::{delta_track, ratio_track, single_segment};
use super::vol_file::VolGrid;
use super::*;
use crate::sampling::Rng;
use crate::texture::bitmap::Wrap;

/// A grid volume of `f(x, y, z)` at each voxel, one channel.
fn grid_volume(
    resolution: [u32; 3],
    f: impl Fn(usize, usize, usize) -> f32,
    filter: Filter,
    wrap: Wrap,
    to_world: Mat4,
) -> Volume {
    let [nx, ny, nz] = resolution.map(|n| n as usize);
    let mut data = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                data.push(f(x, y, z));
            }
        }
    }
    let grid = VolGrid {
        resolution,
        channels: 1,
        bbox: Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        },
        data,
    };
    Volume::GridVolume(GridVolume::new(Arc::new(grid), filter, wrap, to_world))
}

fn random3(rng: &mut Rng) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
}

/// A placement that scales, rotates and moves.
fn turned() -> Mat4 {
    Mat4::from_translation(Vec3::new(0.5, -1.0, 2.0))
        * Mat4::from_rotation_y(0.6)
        * Mat4::from_rotation_x(-0.3)
        * Mat4::from_scale(Vec3::new(2.0, 1.5, 3.0))
}

/// Every cell's majorant is at least the scaled value at random points in
/// it, for both filters, every wrap mode, and a turned placement (the cells
/// divide the world box, the volume's cube sits askew in it).
#[test]
fn the_majorant_bounds_every_lookup_in_its_cell() {
    let mut rng = Rng::new(11);
    let noise = |x: usize, y: usize, z: usize| {
        let h = (x * 73_856_093) ^ (y * 19_349_663) ^ (z * 83_492_791);
        (h % 1000) as f32 / 100.0
    };
    for to_world in [Mat4::IDENTITY, turned()] {
        for filter in [Filter::Trilinear, Filter::Nearest] {
            for wrap in [Wrap::Clamp, Wrap::Repeat, Wrap::Mirror] {
                let v = grid_volume([23, 17, 30], noise, filter, wrap, to_world);
                let scale = 2.5;
                let g = v.majorant_grid(scale, DEFAULT_RESOLUTION);
                let b = g.bounds;
                let n = Vec3::from_array(g.resolution.map(|n| n as f32));
                let mut below = 0usize;
                for z in 0..g.resolution[2] {
                    for y in 0..g.resolution[1] {
                        for x in 0..g.resolution[0] {
                            let m = g.cell(x, y, z);
                            let c = Vec3::new(x as f32, y as f32, z as f32);
                            for _ in 0..8 {
                                let u = (c + random3(&mut rng)) / n;
                                let p = b.min + (b.max - b.min) * u;
                                let value = scale * v.eval_1(p);
                                assert!(
                                    value <= m * (1.0 + 1e-5),
                                    "{filter:?} {wrap:?} cell ({x}, {y}, {z}): {value} > {m}"
                                );
                                below += usize::from(value < m);
                            }
                        }
                    }
                }
                // Not a bound that is merely loose everywhere.
                assert!(below > 0);
                assert!(g.max() <= scale * v.max() * (1.0 + 1e-6));
            }
        }
    }
}

/// Checks that the segments of a ray tile its stretch inside the box in
/// order, each with the majorant of the cell around its middle.
fn assert_tiles(g: &MajorantGrid, o: Vec3, d: Vec3, tmin: f32, tmax: f32, what: &str) {
    let segments: Vec<Segment> = g.segments(o, d, tmin, tmax).collect();
    match clip_to_box(&g.bounds, o, d, tmin, tmax) {
        None => assert!(segments.is_empty(), "{what}: {segments:?}"),
        Some((t0, t1)) => {
            assert!(!segments.is_empty(), "{what}: none for [{t0}, {t1}]");
            assert_eq!(segments[0].t0, t0, "{what}");
            assert_eq!(segments.last().unwrap().t1, t1, "{what}");
            for w in segments.windows(2) {
                assert_eq!(w[0].t1, w[1].t0, "{what}: a gap or an overlap");
            }
            let n = Vec3::from_array(g.resolution.map(|n| n as f32));
            let extent = g.bounds.max - g.bounds.min;
            for s in &segments {
                assert!(s.t1 > s.t0, "{what}: {s:?}");
                let mid = o + d * (0.5 * (s.t0 + s.t1));
                let c = ((mid - g.bounds.min) / extent * n).floor();
                let cell = [c.x, c.y, c.z];
                // Away from the cell walls, the cell of the middle is the
                // segment's.
                let frac = (mid - g.bounds.min) / extent * n - c;
                if s.t1 - s.t0 > 1e-3 * (t1 - t0)
                    && frac.min_element() > 1e-3
                    && frac.max_element() < 1.0 - 1e-3
                {
                    let [x, y, z] = cell.map(|c| c.clamp(0.0, 15.0) as u32);
                    assert_eq!(s.majorant, g.cell(x, y, z), "{what}: {s:?}");
                }
            }
        }
    }
}

/// The walk tiles `[tmin, tmax]` ∩ box without gaps or overlaps: rays along
/// the axes (both ways, some along cell walls and faces), diagonal rays,
/// grazing rays, rays starting inside, missing, and random ones.
#[test]
fn segments_tile_the_ray_inside_the_box() {
    let v = grid_volume(
        [8, 8, 8],
        |x, y, z| (x + 2 * y + 3 * z) as f32,
        Filter::Trilinear,
        Wrap::Clamp,
        Mat4::from_translation(Vec3::new(-1.0, 0.0, 2.0))
            * Mat4::from_scale(Vec3::new(2.0, 4.0, 1.0)),
    );
    let g = v.majorant_grid(1.0, DEFAULT_RESOLUTION);
    let b = g.bounds;
    let c = 0.5 * (b.min + b.max);
    let e = b.max - b.min;
    let inf = f32::INFINITY;
    let mut rays = vec![
        ("+x", Vec3::new(b.min.x - 1.0, c.y, c.z), Vec3::X, 0.0, inf),
        (
            "-x",
            Vec3::new(b.max.x + 1.0, c.y + 0.1, c.z),
            -Vec3::X,
            0.0,
            inf,
        ),
        ("+y", Vec3::new(c.x, b.min.y - 3.0, c.z), Vec3::Y, 0.0, inf),
        ("-z", Vec3::new(c.x, c.y, b.max.z + 0.5), -Vec3::Z, 0.0, inf),
        // Along a cell wall (x at a multiple of the cell's width).
        (
            "wall",
            Vec3::new(b.min.x + e.x * 0.25, b.min.y - 1.0, c.z),
            Vec3::Y,
            0.0,
            inf,
        ),
        // Along the box's face.
        (
            "face",
            Vec3::new(b.min.x, b.min.y - 1.0, b.min.z),
            Vec3::Y,
            0.0,
            inf,
        ),
        ("diagonal", b.min - e * 0.5, e.normalize(), 0.0, inf),
        (
            "anti-diagonal",
            Vec3::new(b.max.x, b.max.y, b.min.z) + Vec3::new(1.0, 1.0, -1.0) * 0.1,
            Vec3::new(-e.x, -e.y, e.z).normalize(),
            0.0,
            inf,
        ),
        // Through a corner of cells: all three walls at once.
        ("cell corners", b.min, e, 0.0, 1.0),
        (
            "grazing",
            Vec3::new(b.min.x - 1.0, c.y, b.max.z - 1e-4),
            Vec3::new(1.0, 0.0, 1e-5).normalize(),
            0.0,
            inf,
        ),
        (
            "grazing edge",
            Vec3::new(b.min.x - 1.0, b.max.y, b.max.z),
            Vec3::new(1.0, 1e-6, 0.0).normalize(),
            0.0,
            inf,
        ),
        ("inside", c, Vec3::new(0.3, -0.4, 0.5).normalize(), 0.0, inf),
        (
            "inside, short",
            c,
            Vec3::new(0.3, -0.4, 0.5).normalize(),
            0.05,
            0.2,
        ),
        ("ends before", b.min - 1.0, Vec3::ONE.normalize(), 0.0, 0.5),
        ("misses", b.max + 1.0, Vec3::X, 0.0, inf),
        ("away", b.max + 1.0, Vec3::ONE, 0.0, inf),
    ];
    let mut rng = Rng::new(5);
    for _ in 0..2000 {
        let o = c + (random3(&mut rng) - 0.5) * e * 3.0;
        let target = b.min + random3(&mut rng) * e;
        let tmin = rng.next_f32() * 0.5;
        rays.push(("random", o, (target - o).normalize(), tmin, inf));
    }
    for (what, o, d, tmin, tmax) in rays {
        assert_tiles(&g, o, d, tmin, tmax, what);
    }
    // A direction of length 0 is no ray: no segments.
    assert_eq!(g.segments(c, Vec3::ZERO, 0.0, f32::INFINITY).count(), 0);
}

/// Voxel values `a + b · z` at the centres, along z: the trilinear
/// interpolant is linear between the outermost centres and constant past
/// them (clamped), so its integral over the cube's height is
/// `(v₀ + v_{n−1}) / 2`.
fn linear_in_depth(n: u32, a: f32, b: f32) -> (impl Fn(usize, usize, usize) -> f32, f32) {
    let v = move |z: usize| a + b * (z as f32 + 0.5) / n as f32;
    (move |_, _, z| v(z), 0.5 * (v(0) + v(n as usize - 1)))
}

/// Delta tracking's escape probability and ratio tracking's mean equal the
/// closed-form transmittance `exp(−∫σ)` within 3 standard deviations, on a
/// density linear in depth, through the majorant grid and through one
/// global majorant, along the z axis and along a tilted ray.
#[test]
fn tracking_estimates_the_transmittance_of_a_density_linear_in_depth() {
    let (f, mean) = linear_in_depth(12, 0.1, 1.6);
    let scale = 0.7;
    let size = Vec3::new(2.0, 2.0, 1.5);
    let to_world = Mat4::from_translation(Vec3::new(-1.0, -1.0, 0.0)) * Mat4::from_scale(size);
    let v = grid_volume([4, 4, 12], f, Filter::Trilinear, Wrap::Clamp, to_world);
    let grid = v.majorant_grid(scale, DEFAULT_RESOLUTION);
    let global = scale * v.max();
    let n = 40_000;
    let mut rng = Rng::new(2024);
    for (what, o, d) in [
        ("along z", Vec3::new(0.1, -0.2, -1.0), Vec3::Z),
        (
            "tilted",
            Vec3::new(-0.5, 0.0, -1.0),
            Vec3::new(0.3, 0.1, 1.0).normalize(),
        ),
    ] {
        let tau = scale * mean * size.z / d.z;
        let want = (-tau).exp();
        let density = |t: f32| scale * v.eval_1(o + d * t);
        for majorants in ["grid", "global"] {
            let segments = || -> Vec<Segment> {
                match majorants {
                    "grid" => grid.segments(o, d, 0.0, f32::INFINITY).collect(),
                    _ => single_segment(&v.bbox(), o, d, 0.0, f32::INFINITY, global)
                        .into_iter()
                        .collect(),
                }
            };
            let segs = segments();
            let mut escaped = 0u32;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let flight = delta_track(segs.iter().copied(), density, || rng.next_f32());
                escaped += u32::from(flight.collision.is_none());
                let tr = ratio_track(segs.iter().copied(), density, || rng.next_f32()).value as f64;
                sum += tr;
                sum2 += tr * tr;
            }
            let p = f64::from(escaped) / f64::from(n);
            let sigma = (want as f64 * (1.0 - want as f64) / f64::from(n)).sqrt();
            assert!(
                (p - want as f64).abs() < 3.0 * sigma,
                "{what}, {majorants}: delta tracking escapes {p}, want {want} ± {sigma}"
            );
            let m = sum / f64::from(n);
            let var = (sum2 / f64::from(n) - m * m).max(0.0);
            let sigma = (var / f64::from(n)).sqrt().max(1e-9);
            assert!(
                (m - want as f64).abs() < 3.0 * sigma,
                "{what}, {majorants}: ratio tracking gives {m}, want {want} ± {sigma}"
            );
        }
    }
}

/// Smoke: a few dense blobs in an empty 64³ grid. Tracking through the
/// majorant grid takes far fewer null collisions than through one global
/// majorant; the ratio is printed (`--nocapture`).
#[test]
fn the_majorant_grid_saves_null_collisions_in_sparse_smoke() {
    let blobs = [
        (Vec3::new(0.3, 0.35, 0.4), 0.08, 30.0),
        (Vec3::new(0.65, 0.6, 0.55), 0.12, 12.0),
        (Vec3::new(0.5, 0.75, 0.3), 0.05, 40.0),
    ];
    let n = 64u32;
    let smoke = |x: usize, y: usize, z: usize| {
        let p = Vec3::new(x as f32 + 0.5, y as f32 + 0.5, z as f32 + 0.5) / n as f32;
        blobs
            .iter()
            .map(|&(c, r, d)| {
                let q = (p - c).length() / r;
                if q < 1.0 {
                    d * (1.0 - q * q)
                } else {
                    0.0
                }
            })
            .sum()
    };
    let v = grid_volume(
        [n, n, n],
        smoke,
        Filter::Trilinear,
        Wrap::Clamp,
        Mat4::IDENTITY,
    );
    let scale = 1.0;
    let grid = v.majorant_grid(scale, DEFAULT_RESOLUTION);
    let global = scale * v.max();
    let v = &v;
    let density = |o: Vec3, d: Vec3| move |t: f32| scale * v.eval_1(o + d * t);
    let mut rng = Rng::new(99);
    let (mut with_grid, mut with_global) = ([0u64; 2], [0u64; 2]);
    let (mut escaped_grid, mut escaped_global) = (0u32, 0u32);
    let rays = 4000;
    for _ in 0..rays {
        let o = Vec3::splat(0.5) + (random3(&mut rng) - 0.5).normalize() * 2.0;
        let d = (random3(&mut rng) - o).normalize();
        let mut u = || rng.next_f32();
        let f = delta_track(
            grid.segments(o, d, 0.0, f32::INFINITY),
            density(o, d),
            &mut u,
        );
        with_grid[0] += u64::from(f.nulls);
        escaped_grid += u32::from(f.collision.is_none());
        let r = ratio_track(
            grid.segments(o, d, 0.0, f32::INFINITY),
            density(o, d),
            &mut u,
        );
        with_grid[1] += u64::from(r.nulls);
        let one = single_segment(&v.bbox(), o, d, 0.0, f32::INFINITY, global);
        let f = delta_track(one, density(o, d), &mut u);
        with_global[0] += u64::from(f.nulls);
        escaped_global += u32::from(f.collision.is_none());
        let r = ratio_track(one, density(o, d), &mut u);
        with_global[1] += u64::from(r.nulls);
    }
    let delta = with_global[0] as f64 / with_grid[0].max(1) as f64;
    let ratio = with_global[1] as f64 / with_grid[1].max(1) as f64;
    eprintln!(
        "null collisions per ray, sparse smoke 64³, majorant grid 16³ vs one majorant: \
         delta tracking {:.2} vs {:.2} ({delta:.1}× fewer), ratio tracking {:.2} vs {:.2} ({ratio:.1}× fewer); \
         escapes {escaped_grid} vs {escaped_global} of {rays}",
        with_grid[0] as f64 / f64::from(rays),
        with_global[0] as f64 / f64::from(rays),
        with_grid[1] as f64 / f64::from(rays),
        with_global[1] as f64 / f64::from(rays),
    );
    assert!(
        delta >= 3.0,
        "delta tracking: only {delta:.2}× fewer null collisions"
    );
    assert!(
        ratio >= 3.0,
        "ratio tracking: only {ratio:.2}× fewer null collisions"
    );
    // The same flights either way: escape counts agree within noise.
    let p = f64::from(escaped_grid) / f64::from(rays);
    let q = f64::from(escaped_global) / f64::from(rays);
    let sigma = (p * (1.0 - p) * 2.0 / f64::from(rays)).sqrt();
    assert!((p - q).abs() < 4.0 * sigma.max(1e-3), "{p} vs {q}");
}

/// A constant volume: its value, its mean as one value, its box placed.
#[test]
fn a_constant_volume_fills_its_placed_cube() {
    let c = Volume::ConstVolume(constvolume::ConstVolume::new(
        Rgb::new(1.0, 2.0, 6.0),
        Mat4::from_translation(Vec3::ONE) * Mat4::from_scale(Vec3::splat(2.0)),
    ));
    assert_eq!(c.eval(Vec3::ZERO), Rgb::new(1.0, 2.0, 6.0));
    assert_eq!(c.eval_1(Vec3::ZERO), 3.0);
    assert_eq!(c.max(), 6.0);
    assert_eq!(c.bbox(), Aabb::new(Vec3::ONE, Vec3::splat(3.0)));
    let g = c.majorant_grid(0.5, [2, 2, 2]);
    assert!(g.cells.iter().all(|&m| m == 3.0));
}

/// Mitsuba's own `.vol` files (its participating-media tests), read when
/// `PENUMBRA_VOL_FILES` names them (colon-separated): each loads, and its
/// header is printed.
#[test]
#[ignore = "reads the files PENUMBRA_VOL_FILES names"]
fn mitsuba_vol_files_load() {
    let Ok(files) = std::env::var("PENUMBRA_VOL_FILES") else {
        return;
    };
    for f in files.split(':') {
        let g = vol_file::read_vol(Path::new(f)).unwrap();
        eprintln!(
            "{f}: {:?} voxels, {} channel(s), box {:?} to {:?}, values in [{}, {}]",
            g.resolution,
            g.channels,
            g.bbox.min.to_array(),
            g.bbox.max.to_array(),
            g.data.iter().fold(f32::INFINITY, |a, &b| a.min(b)),
            g.max()
        );
        if g.channels != 1 {
            continue;
        }
        // Null collisions as in Mitsuba's test scenes: the grid on
        // [−0.5, 1]³, scale 5.
        let to_world =
            Mat4::from_translation(Vec3::splat(-0.5)) * Mat4::from_scale(Vec3::splat(1.5));
        let v = Volume::GridVolume(GridVolume::new(
            Arc::new(g),
            Filter::Trilinear,
            Wrap::Clamp,
            to_world,
        ));
        let scale = 5.0;
        let grid = v.majorant_grid(scale, DEFAULT_RESOLUTION);
        let global = scale * v.max();
        let mut rng = Rng::new(1);
        let (mut a, mut b, rays) = (0u64, 0u64, 4000u32);
        for _ in 0..rays {
            let o = Vec3::splat(0.25) + (random3(&mut rng) - 0.5).normalize() * 3.0;
            let d = (Vec3::splat(-0.5) + 1.5 * random3(&mut rng) - o).normalize();
            let density = |t: f32| scale * v.eval_1(o + d * t);
            let mut u = || rng.next_f32();
            a += u64::from(
                delta_track(grid.segments(o, d, 0.0, f32::INFINITY), density, &mut u).nulls,
            );
            let one = single_segment(&v.bbox(), o, d, 0.0, f32::INFINITY, global);
            b += u64::from(delta_track(one, density, &mut u).nulls);
        }
        eprintln!(
            "  delta tracking, null collisions per ray: grid {:.2}, one majorant {:.2} ({:.1}× fewer)",
            a as f64 / f64::from(rays),
            b as f64 / f64::from(rays),
            b as f64 / a.max(1) as f64
        );
    }
}
