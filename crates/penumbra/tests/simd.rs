//! Kernel sets: every set this processor supports gives the portable set's
//! results bit for bit, query by query on random and adversarial rays
//! (axis-parallel, grazing, through edges and vertices, degenerate
//! triangles, instances) and image by image for every integrator. Each
//! test prints the sets it ran.

mod common;

use std::sync::Arc;

use common::*;
use penumbra::accel::world::mesh_bvh;
use penumbra::accel::{Hits, Object, PacketScratch, ShaftSet, World};
use penumbra::geometry::instance::Placement;
use penumbra::geometry::quad::Quad;
use penumbra::geometry::{Mesh, MeshShape, Shape, Sphere};
use penumbra::math::{Aabb, Mat4, Ray, Vec3};
use penumbra::sampling::Rng;
use penumbra::scene::{IntegratorChoice, Overrides};
use penumbra::simd::{self, KernelSet};

/// The sets other than `portable` this processor supports, printed.
fn wide_sets(what: &str) -> Vec<KernelSet> {
    let sets = KernelSet::supported();
    let names: Vec<&str> = sets.iter().map(|k| k.name()).collect();
    println!("{what}: kernel sets run: {}", names.join(", "));
    sets.into_iter()
        .filter(|&k| k != KernelSet::Portable)
        .collect()
}

/// A regular grid of `n`×`n` quads (two triangles each) in the plane
/// y = `y`: shared edges and vertices everywhere.
fn grid(n: u32, y: f32) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(Vec3::new(
                i as f32 - n as f32 / 2.0,
                y,
                j as f32 - n as f32 / 2.0,
            ));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Mesh {
        positions,
        normals: None,
        uvs: None,
        triangles,
    }
}

/// Small random triangles in a box, and degenerate ones: collinear
/// vertices, a repeated vertex, a point.
fn soup(rng: &mut Rng, n: u32) -> Mesh {
    let mut v = || {
        Vec3::new(
            rng.range(-3.0, 3.0),
            rng.range(0.0, 3.0),
            rng.range(-3.0, 3.0),
        )
    };
    let mut positions = Vec::new();
    for _ in 0..n {
        let c = v();
        positions.extend([c, c + v() * 0.15, c + v() * 0.15]);
    }
    let c = Vec3::new(0.25, 1.5, 0.25);
    let d = Vec3::new(0.5, 0.25, -0.5);
    positions.extend([c, c + d, c + 2.0 * d]); // collinear
    positions.extend([c, c, c + d]); // a repeated vertex
    positions.extend([c, c, c]); // a point
    let count = positions.len() as u32 / 3;
    Mesh {
        positions,
        normals: None,
        uvs: None,
        triangles: (0..count).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect(),
    }
}

/// A world of a grid floor, a triangle soup, two instances of a small
/// grid, a sphere and a quad.
fn world() -> World {
    let mut rng = Rng::new(17);
    let floor = grid(12, 0.0);
    let small = grid(3, 0.0);
    let meshes = vec![floor, soup(&mut rng, 900), small.clone()];
    let tree = mesh_bvh(&small);
    let instance = |m: Mat4| Object {
        placement: Some(Arc::new(Placement::new(m).expect("invertible"))),
        mesh_bvh: Some(tree.clone()),
        ..Object::new(Shape::MeshShape(MeshShape::new(2)), 3)
    };
    let objects = vec![
        Object::new(Shape::MeshShape(MeshShape::new(0)), 0),
        Object::new(Shape::MeshShape(MeshShape::new(1)), 1),
        Object::new(
            Shape::Sphere(Sphere::new(Vec3::new(1.0, 1.0, -1.0), 0.75)),
            2,
        ),
        Object::new(
            Shape::Quad(Quad::new(
                Vec3::new(-2.0, 0.0, 2.0),
                Vec3::Y * 2.0,
                Vec3::X * 2.0,
            )),
            2,
        ),
        instance(Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0))),
        instance(Mat4::from_rotation_z(1.0) * Mat4::from_translation(Vec3::new(2.0, 1.0, 0.0))),
    ];
    World::new(objects, meshes)
}

/// Random rays and adversarial ones: axis-parallel from grid vertices
/// and box planes, aimed at vertices and edge midpoints, grazing the
/// floor's plane, and with zero direction components.
fn rays(w: &World) -> Vec<Ray> {
    let mut rng = Rng::new(5);
    let mut out = Vec::new();
    for _ in 0..3000 {
        let o = Vec3::new(
            rng.range(-7.0, 7.0),
            rng.range(-1.0, 5.0),
            rng.range(-7.0, 7.0),
        );
        let t = Vec3::new(
            rng.range(-4.0, 4.0),
            rng.range(0.0, 3.0),
            rng.range(-4.0, 4.0),
        );
        out.push(Ray::new(o, t - o, rng.next_f32()));
    }
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    for i in -6..=6 {
        for j in -6..=6 {
            let (x, z) = (i as f32, j as f32);
            // Down onto a vertex, onto an edge midpoint, onto a diagonal.
            for (dx, dz) in [(0.0, 0.0), (0.5, 0.0), (0.5, 0.5)] {
                out.push(Ray::new(Vec3::new(x + dx, 4.0, z + dz), -Vec3::Y, 0.5));
            }
            // Along the floor's plane and along grid lines.
            out.push(Ray::new(Vec3::new(x, 0.0, -8.0), Vec3::Z, 0.5));
            out.push(Ray::new(Vec3::new(-8.0, 0.0, z), Vec3::X, 0.5));
            for a in axes {
                out.push(Ray::new(Vec3::new(x * 0.5, 1.5, z * 0.5), a, 0.5));
            }
        }
    }
    // From the bounds' corners and face centres, axis-parallel.
    let b: Aabb = w.bounds();
    for c in 0..8 {
        let p = Vec3::new(
            if c & 1 == 0 { b.min.x } else { b.max.x },
            if c & 2 == 0 { b.min.y } else { b.max.y },
            if c & 4 == 0 { b.min.z } else { b.max.z },
        );
        for a in axes {
            out.push(Ray::new(p, a, 0.0));
            out.push(Ray::new((p + b.centroid()) * 0.5, a, 0.0));
        }
    }
    // Through the degenerate triangles and grazing the floor.
    let c = Vec3::new(0.25, 1.5, 0.25);
    for a in axes {
        out.push(Ray::new(c - a * 3.0, a, 0.0));
    }
    for k in 0..64 {
        let a = k as f32 / 64.0 * std::f32::consts::TAU;
        out.push(Ray::new(
            Vec3::new(0.0, 1e-7, 0.0),
            Vec3::new(a.cos(), 0.0, a.sin()),
            0.0,
        ));
        out.push(Ray::new(
            Vec3::new(0.1, 3.0, 0.1),
            Vec3::new(a.cos(), -1e-4, a.sin()),
            0.0,
        ));
    }
    out
}

/// Everything the world's queries answer for the rays, as text that
/// holds every bit (`{:?}` of an `f32` round-trips).
fn answers(w: &World, rays: &[Ray]) -> Vec<String> {
    let mut out = Vec::new();
    for r in rays {
        out.push(format!("{:?}", w.intersect(r, 1e-4, f32::INFINITY)));
        let mut crossed = Vec::new();
        let stopped = w.crossings(r, (1e-4, 6.0), None, |c| {
            crossed.push((c.material(), c.count()));
            crossed.len() > 40
        });
        out.push(format!(
            "{stopped} {crossed:?} {}",
            w.occluded(r, (1e-4, 6.0))
        ));
    }
    // Batches: a packet of rays from one point and an incoherent batch.
    let mut scratch = PacketScratch::default();
    let (mut hits, mut records) = (Hits::default(), Vec::new());
    let o = Vec3::new(0.3, 4.0, 0.2);
    let packet: Vec<Ray> = (0..64)
        .map(|i| {
            let (u, v) = ((i % 8) as f32 / 8.0 - 0.5, (i / 8) as f32 / 8.0 - 0.5);
            Ray::new(o, Vec3::new(u, -1.0, v), 0.0)
        })
        .collect();
    for batch in [&packet[..], &rays[..200]] {
        w.intersect_all(batch, 1e-4, &mut scratch, &mut hits);
        w.surfaces(batch, &hits, &mut records);
        let mut made = Vec::new();
        w.intersect_all_records(batch, 1e-4, &mut scratch, &mut made);
        assert_eq!(format!("{records:?}"), format!("{made:?}"));
        out.push(format!("{hits:?} {records:?}"));
    }
    // A batch of shadow rays, each as alone.
    let mut blocked = Vec::new();
    w.occluded_all(rays, (1e-4, 6.0), &mut blocked);
    let alone: Vec<bool> = rays.iter().map(|r| w.occluded(r, (1e-4, 6.0))).collect();
    assert_eq!(blocked, alone);
    out.push(format!("{blocked:?}"));
    // Shadow sets through a shaft: from a patch of the floor to a light.
    let mut set = ShaftSet::default();
    let origins = Aabb::from_points([Vec3::new(-1.0, 0.01, -1.0), Vec3::new(-0.5, 0.01, -0.5)]);
    let targets = Aabb::from_points([Vec3::new(0.0, 4.5, 0.0), Vec3::new(1.0, 4.5, 1.0)]);
    let gathered = w.gather_shaft(origins, targets, 1 << 20, &mut set);
    out.push(format!("{gathered} {}", w.shaft_is_clear(&set)));
    let mut rng = Rng::new(9);
    for _ in 0..500 {
        let lerp = |b: &Aabb, rng: &mut Rng| {
            b.min + (b.max - b.min) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
        };
        let (a, b) = (lerp(&origins, &mut rng), lerp(&targets, &mut rng));
        let r = Ray::new(a, b - a, 0.0);
        let mut crossed = Vec::new();
        w.crossings(&r, (1e-4, 1.0), gathered.then_some(&set), |c| {
            crossed.push((c.material(), c.count()));
            false
        });
        out.push(format!("{crossed:?}"));
    }
    out
}

#[test]
fn every_kernel_set_answers_every_query_with_the_portable_bits() {
    let sets = wide_sets("world queries");
    let mut w = world();
    let rays = rays(&w);
    w.set_kernels(KernelSet::Portable).unwrap();
    let want = answers(&w, &rays);
    // The rays do hit: a test of nothing would pass too.
    let hits = want
        .iter()
        .step_by(2)
        .filter(|a| a.starts_with("Some"))
        .count();
    assert!(hits > 1000, "only {hits} hits");
    for k in sets {
        w.set_kernels(k).unwrap();
        assert_eq!(w.kernels(), k);
        let got = answers(&w, &rays);
        assert_eq!(got.len(), want.len());
        for (i, (g, e)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g, e, "{k}: answer {i} differs from the portable one");
        }
    }
}

#[test]
fn the_batch_calls_of_a_mesh_give_the_portable_bits_on_every_set() {
    let sets = wide_sets("mesh batches");
    let mut rng = Rng::new(3);
    let mesh = soup(&mut rng, 3000);
    let tree = mesh_bvh(&mesh);
    let w = world();
    let rays = rays(&w);
    let tmax = vec![f32::INFINITY; rays.len()];
    let run = |k: KernelSet| {
        simd::set_active(k).unwrap();
        let (mut hits, mut blocked) = (Vec::new(), Vec::new());
        tree.closest_hit_each(&rays, 1e-4, &tmax, &mut hits);
        tree.occluded_each(&rays, 1e-4, &tmax, &mut blocked);
        format!("{hits:?} {blocked:?}")
    };
    let want = run(KernelSet::Portable);
    assert!(want.matches("Some").count() > 300);
    for k in sets {
        assert_eq!(run(k), want, "{k}");
    }
    simd::set_active(KernelSet::best()).unwrap();
}

/// The scene's world, which a scene just built holds alone.
fn world_of(scene: &mut penumbra::scene::Scene) -> &mut World {
    Arc::get_mut(&mut scene.world).expect("a world of its own")
}

#[test]
fn images_and_ray_counts_are_the_same_on_every_set_for_every_integrator() {
    let sets = wide_sets("images");
    let bunny = bunny();
    for integrator in IntegratorChoice::ALL {
        // A mesh where the bunny is at hand, else the triangles of the
        // Cornell box and the showcase's shapes.
        let name = match (integrator, &bunny) {
            (IntegratorChoice::Whitted, Some(_)) => "bunny-mirror",
            (IntegratorChoice::Path | IntegratorChoice::Direct, _) => "cornell-box",
            _ => "showcase",
        };
        let mut src = builtin(name, bunny.clone());
        set(
            &mut src,
            Overrides {
                integrator: Some(integrator),
                width: Some(48),
                height: Some(36),
                spp: Some(4),
                ..Default::default()
            },
        );
        let mut scene = src.build().expect("scene builds");
        world_of(&mut scene)
            .set_kernels(KernelSet::Portable)
            .unwrap();
        let (want, want_rays) = render_scene(&scene, 2);
        for &k in &sets {
            world_of(&mut scene).set_kernels(k).unwrap();
            let (got, rays) = render_scene(&scene, 2);
            let what = format!("{} on {name} with {k}", integrator.name());
            assert_eq!(rays, want_rays, "{what}: ray counts");
            assert!(
                got.pixels
                    .iter()
                    .zip(&want.pixels)
                    .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)),
                "{what}: pixels differ"
            );
            let extra = |i: &penumbra::render::Image| {
                i.extra
                    .as_ref()
                    .map(|e| e.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
            };
            assert_eq!(extra(&got), extra(&want), "{what}: extra channels differ");
        }
    }
}
