//! The cube (Mitsuba 3's `cube`): a triangle mesh of the box [−1, 1]³
//! before its transform, two triangles per face.
//!
//! Each face has four vertices of its own (24 in all), carrying the face's
//! outward normal and the corners of the unit square as texture
//! coordinates, laid out as Mitsuba lays them out, so that every face maps
//! onto [0, 1]² the same way there and here.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `flip_normals` | boolean | `false` | normals point into the cube |

use super::Mesh;
use crate::math::{Vec2, Vec3};

/// The outward normal of each face.
const FACE_NORMALS: [[f32; 3]; 6] = [
    [0.0, -1.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0],
    [-1.0, 0.0, 0.0],
    [0.0, 0.0, -1.0],
];

/// The texture coordinates of a face's four vertices, in order.
const FACE_UVS: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];

/// The box corner of each vertex: corner `c` is at (±1, ±1, ±1), bit `k`
/// of `c` set for +1 on axis `k`.
const CORNERS: [u8; 24] = [
    1, 5, 4, 0, 3, 2, 6, 7, 1, 3, 7, 5, 5, 7, 6, 4, 4, 6, 2, 0, 3, 1, 0, 2,
];

/// The cube's mesh in its own space, with normals and texture coordinates.
pub fn cube() -> Mesh {
    let corner = |c: u8| {
        let s = |bit: u8| if c & bit != 0 { 1.0 } else { -1.0 };
        Vec3::new(s(1), s(2), s(4))
    };
    let positions = CORNERS.iter().map(|&c| corner(c)).collect();
    let normals = (0..24)
        .map(|v| Vec3::from_array(FACE_NORMALS[v / 4]))
        .collect();
    let uvs = (0..24).map(|v| Vec2::from_array(FACE_UVS[v % 4])).collect();
    let triangles = (0..6u32)
        .flat_map(|f| {
            let v = 4 * f;
            [[v, v + 1, v + 2], [v + 3, v, v + 2]]
        })
        .collect();
    Mesh {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle winds outward (its normal is its face's), lies on its
    /// face's plane, and the twelve cover the surface: area 24.
    #[test]
    fn triangles_face_outward_and_cover_the_box() {
        let m = cube();
        assert_eq!((m.positions.len(), m.triangles.len()), (24, 12));
        let mut area = 0.0;
        for t in 0..12 {
            let [a, b, c] = m.vertices(t);
            let n = Vec3::from_array(FACE_NORMALS[t / 2]);
            let cross = (b - a).cross(c - a);
            assert!((cross.normalize() - n).length() < 1e-6, "triangle {t}");
            for p in [a, b, c] {
                assert_eq!(p.dot(n), 1.0, "triangle {t} off its face");
            }
            area += 0.5 * cross.length();
        }
        assert_eq!(area, 24.0);
        // Each face's uv square covers [0, 1]²: corners (0,0) and (1,1) there.
        let uvs = m.uvs.as_ref().unwrap();
        for f in 0..6 {
            let face = &uvs[4 * f..4 * f + 4];
            assert!(face.contains(&Vec2::ZERO) && face.contains(&Vec2::ONE));
        }
    }
}
