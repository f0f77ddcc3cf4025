//! BVH build, closest hit and any hit of the triangle BVH (the structure
//! static meshes live in) and of the generic BVH, on the Stanford bunny when
//! it is there (`$PENUMBRA_BUNNY`, else `shared/data/bunny.ply` in the folder
//! beside the checkout) and on a procedural mesh of the same size otherwise.
//!
//! `cargo bench -p penumbra-bench --bench accel`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use penumbra::accel::{Bvh, TriangleBvh};
use penumbra::geometry::mesh_file::read_mesh;
use penumbra::geometry::tessellate::uv_sphere;
use penumbra::geometry::triangle::{intersect_triangle, RayShear};
use penumbra::math::{Aabb, Ray, Vec3};
use penumbra_bench::{bumpy_radius, random_rays};
use std::hint::black_box;
use std::path::PathBuf;

/// The bunny's triangles scaled by 10 (as in the bunny scenes), or a bumpy
/// sphere of 69,696 triangles.
fn mesh() -> (String, Vec<[Vec3; 3]>) {
    let path = std::env::var_os("PENUMBRA_BUNNY")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../../shared/data/bunny.ply"
            ))
        });
    match read_mesh(&path) {
        Ok(m) => {
            let p = |i: u32| Vec3::from_array(m.positions[i as usize]) * 10.0;
            let tris = m.triangles.iter().map(|t| t.map(p)).collect();
            ("bunny".into(), tris)
        }
        Err(_) => ("sphere70k".into(), uv_sphere(264, 133, bumpy_radius)),
    }
}

fn accel(c: &mut Criterion) {
    let (name, tris) = mesh();
    let bounds: Vec<Aabb> = tris.iter().map(|t| Aabb::from_points(*t)).collect();
    let mut g = c.benchmark_group(format!("build/{name}"));
    g.sample_size(20);
    g.throughput(Throughput::Elements(tris.len() as u64));
    g.bench_function("triangle_bvh", |b| {
        b.iter(|| black_box(TriangleBvh::build(tris.len(), |i| tris[i])))
    });
    g.bench_function("generic_bvh", |b| b.iter(|| black_box(Bvh::build(&bounds))));
    g.finish();

    let tbvh = TriangleBvh::build(tris.len(), |i| tris[i]);
    let gbvh = Bvh::build(&bounds);
    let rays = random_rays(100_000, &tbvh.bounds(), 42);
    let mut g = c.benchmark_group(format!("trace/{name}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("triangle_bvh/closest", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| tbvh.closest_hit(r, 0.0, f32::INFINITY).is_some())
                .count()
        })
    });
    g.bench_function("triangle_bvh/any", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| tbvh.occluded(r, 0.0, f32::INFINITY))
                .count()
        })
    });
    let test = |ray: &Ray, shear: &RayShear, p: u32, tmax: f32| {
        let [a, b, c] = tris[p as usize];
        intersect_triangle(ray, shear, a, b, c, 0.0, tmax)
    };
    g.bench_function("generic_bvh/closest", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| {
                    let s = RayShear::new(r);
                    gbvh.closest_hit(r, 0.0, f32::INFINITY, |p, t| test(r, &s, p, t).map(|h| h.0))
                        .is_some()
                })
                .count()
        })
    });
    g.bench_function("generic_bvh/any", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| {
                    let s = RayShear::new(r);
                    gbvh.any_hit(r, 0.0, f32::INFINITY, |p, t| test(r, &s, p, t).is_some())
                })
                .count()
        })
    });
    g.finish();
}

criterion_group!(benches, accel);
criterion_main!(benches);
