//! Procedural triangle meshes: a closed UV sphere whose radius may vary with
//! direction. The BVH tests use it as a closed mesh with known vertices and
//! edges, the benchmarks as a mesh of any size (a bumpy sphere of a million
//! triangles stands in for a large scan) that needs no file.

use crate::math::Vec3;

/// A closed UV sphere about the origin: `nu` segments around the y axis and
/// `nv` rings from pole to pole, `2 * nu * (nv - 1)` triangles (none if
/// `nu < 3` or `nv < 2`), each wound counter-clockwise seen from outside.
/// The surface point at polar angle θ (from +y) and azimuth φ lies at
/// distance `radius(θ, φ)` from the origin.
///
/// Neighbouring triangles share their vertices bit for bit (each vertex is
/// computed once per grid position, the seam reuses φ = 0 and each pole is
/// one point), so the mesh is watertight for a watertight triangle test.
pub fn uv_sphere(nu: usize, nv: usize, radius: impl Fn(f32, f32) -> f32) -> Vec<[Vec3; 3]> {
    use std::f32::consts::{PI, TAU};
    if nu < 3 || nv < 2 {
        return Vec::new();
    }
    let pos = |j: usize, i: usize| {
        let theta = PI * j as f32 / nv as f32;
        let phi = TAU * (i % nu) as f32 / nu as f32;
        radius(theta, phi)
            * Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            )
    };
    let mut tris = Vec::with_capacity(2 * nu * (nv - 1));
    for i in 0..nu {
        tris.push([pos(0, 0), pos(1, i + 1), pos(1, i)]);
        tris.push([pos(nv, 0), pos(nv - 1, i), pos(nv - 1, i + 1)]);
    }
    for j in 1..nv - 1 {
        for i in 0..nu {
            let (a, b, c, d) = (pos(j, i), pos(j, i + 1), pos(j + 1, i), pos(j + 1, i + 1));
            tris.push([a, b, d]);
            tris.push([a, d, c]);
        }
    }
    tris
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn key(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    #[test]
    fn closed_consistently_wound_and_outward() {
        for (nu, nv) in [(3, 2), (4, 3), (17, 9)] {
            let bump = |t: f32, p: f32| 1.0 + 0.1 * (3.0 * t).sin() * (2.0 * p).cos();
            let tris = uv_sphere(nu, nv, bump);
            assert_eq!(tris.len(), 2 * nu * (nv - 1));
            // Every directed edge once, and its reverse once: closed, and
            // neighbours agree on the winding.
            let mut edges: HashMap<([u32; 3], [u32; 3]), usize> = HashMap::new();
            for t in &tris {
                for k in 0..3 {
                    *edges.entry((key(t[k]), key(t[(k + 1) % 3]))).or_default() += 1;
                }
                let n = (t[1] - t[0]).cross(t[2] - t[0]);
                let centre = (t[0] + t[1] + t[2]) / 3.0;
                assert!(n.dot(centre) > 0.0, "{nu}x{nv}: a triangle faces inwards");
            }
            for (&(a, b), &count) in &edges {
                assert_eq!(count, 1, "{nu}x{nv}: a directed edge twice");
                assert_eq!(edges.get(&(b, a)), Some(&1), "{nu}x{nv}: an open edge");
            }
        }
    }

    #[test]
    fn vertices_lie_at_the_given_radius() {
        for t in uv_sphere(8, 5, |_, _| 2.5) {
            for v in t {
                assert!((v.length() - 2.5).abs() < 1e-5, "{v}");
            }
        }
    }

    #[test]
    fn too_few_segments_or_rings_give_no_triangles() {
        assert!(uv_sphere(2, 5, |_, _| 1.0).is_empty());
        assert!(uv_sphere(8, 1, |_, _| 1.0).is_empty());
        assert!(uv_sphere(0, 0, |_, _| 1.0).is_empty());
    }
}
