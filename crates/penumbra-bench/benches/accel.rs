//! BVH build, closest hit and any hit of the triangle BVH (the structure
//! meshes live in), on the Stanford bunny when `$PENUMBRA_BUNNY` names it
//! and on a procedural mesh of the same size otherwise.
//!
//! `cargo bench -p penumbra-bench --bench accel`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use penumbra::accel::TriangleBvh;
use penumbra::geometry::mesh_file::read_mesh;
use penumbra::geometry::tessellate::uv_sphere;
use penumbra::math::Vec3;
use penumbra_bench::{bumpy_radius, random_rays};
use std::hint::black_box;

/// The bunny's triangles scaled by 10 (as in the bunny scenes), or a bumpy
/// sphere of 69,696 triangles.
fn mesh() -> (String, Vec<[Vec3; 3]>) {
    let bunny = std::env::var_os("PENUMBRA_BUNNY").and_then(|p| read_mesh(p.as_ref()).ok());
    match bunny {
        Some(m) => {
            let p = |i: u32| Vec3::from_array(m.positions[i as usize]) * 10.0;
            let tris = m.triangles.iter().map(|t| t.map(p)).collect();
            ("bunny".into(), tris)
        }
        None => ("sphere70k".into(), uv_sphere(264, 133, bumpy_radius)),
    }
}

fn accel(c: &mut Criterion) {
    let (name, tris) = mesh();
    let mut g = c.benchmark_group(format!("build/{name}"));
    g.sample_size(20);
    g.throughput(Throughput::Elements(tris.len() as u64));
    g.bench_function("triangle_bvh", |b| {
        b.iter(|| black_box(TriangleBvh::build(tris.len(), |i| tris[i])))
    });
    g.finish();

    let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
    let rays = random_rays(100_000, &bvh.bounds(), 42);
    let mut g = c.benchmark_group(format!("trace/{name}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("triangle_bvh/closest", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| bvh.closest_hit(r, 0.0, f32::INFINITY).is_some())
                .count()
        })
    });
    g.bench_function("triangle_bvh/any", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| bvh.occluded(r, 0.0, f32::INFINITY))
                .count()
        })
    });
    g.finish();
}

criterion_group!(benches, accel);
criterion_main!(benches);
