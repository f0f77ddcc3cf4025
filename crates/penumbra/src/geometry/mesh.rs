use crate::math::{Aabb, Mat4, Vec2, Vec3};

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (smooth shading), if any.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (u, v), if any.
    pub uvs: Option<Vec<Vec2>>,
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Vertices of triangle `i`.
    #[inline]
    pub fn vertices(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.triangles[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    pub fn triangle_bounds(&self, i: usize) -> Aabb {
        Aabb::from_points(self.vertices(i))
    }

    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }

    /// Area-weighted vertex normals: the cross product of two edges is twice
    /// the area times the normal, so summing raw cross products weights each
    /// face by its area without computing it.
    pub fn compute_vertex_normals(&mut self) {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for (i, tri) in self.triangles.iter().enumerate() {
            let [a, b, c] = self.vertices(i);
            let n = (b - a).cross(c - a);
            for &v in tri {
                normals[v as usize] += n;
            }
        }
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        self.normals = Some(normals);
    }

    /// The mesh with every vertex transformed by `m` (normals by its inverse
    /// transpose; texture coordinates are kept as they are).
    pub fn transformed(&self, m: &Mat4) -> Mesh {
        let nm = m.inverse().transpose();
        Mesh {
            positions: self
                .positions
                .iter()
                .map(|&p| m.transform_point3(p))
                .collect(),
            normals: self.normals.as_ref().map(|ns| {
                ns.iter()
                    .map(|&n| nm.transform_vector3(n).normalize_or_zero())
                    .collect()
            }),
            uvs: self.uvs.clone(),
            triangles: self.triangles.clone(),
        }
    }

    /// Shading normal at barycentrics (b1, b2) of triangle `i`, if the mesh has normals.
    pub fn shading_normal(&self, i: usize, b1: f32, b2: f32) -> Option<Vec3> {
        let ns = self.normals.as_ref()?;
        let [a, b, c] = self.triangles[i];
        let n = (1.0 - b1 - b2) * ns[a as usize] + b1 * ns[b as usize] + b2 * ns[c as usize];
        let n = n.normalize_or_zero();
        (n != Vec3::ZERO).then_some(n)
    }

    /// Texture coordinates of the corners of triangle `tri`, if the mesh has them.
    pub fn triangle_uvs(&self, tri: usize) -> Option<[Vec2; 3]> {
        let uvs = self.uvs.as_ref()?;
        let [a, b, c] = self.triangles[tri];
        Some([uvs[a as usize], uvs[b as usize], uvs[c as usize]])
    }

    /// Texture coordinates at barycentrics (b1, b2) of triangle `tri`, if the
    /// mesh has them: weight `1 - b1 - b2` on the first corner, `b1` on the
    /// second, `b2` on the third, as for [`Mesh::shading_normal`].
    pub fn uv(&self, tri: usize, b1: f32, b2: f32) -> Option<Vec2> {
        let [t0, t1, t2] = self.triangle_uvs(tri)?;
        Some((1.0 - b1 - b2) * t0 + b1 * t1 + b2 * t2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles sharing an edge, with texture coordinates.
    fn textured() -> Mesh {
        Mesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
                Vec3::new(2.0, 2.0, 0.0),
            ],
            normals: None,
            uvs: Some(vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.0, 1.0),
                Vec2::new(0.75, 0.5),
            ]),
            triangles: vec![[0, 1, 2], [2, 1, 3]],
        }
    }

    #[test]
    fn uv_interpolates_the_corners_barycentrically() {
        let mesh = textured();
        let corners = mesh.triangle_uvs(1).unwrap();
        assert_eq!(
            corners,
            [
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.75, 0.5)
            ]
        );
        // (b1, b2) = (0, 0), (1, 0), (0, 1) are the first, second and third corner.
        assert_eq!(mesh.uv(1, 0.0, 0.0), Some(corners[0]));
        assert_eq!(mesh.uv(1, 1.0, 0.0), Some(corners[1]));
        assert_eq!(mesh.uv(1, 0.0, 1.0), Some(corners[2]));
        let third = 1.0 / 3.0;
        let centroid = mesh.uv(1, third, third).unwrap();
        let mean = (corners[0] + corners[1] + corners[2]) / 3.0;
        assert!((centroid - mean).abs().max_element() < 1e-6, "{centroid}");
        assert_eq!(mesh.uv(0, 0.5, 0.25), Some(Vec2::new(0.5, 0.25)));
    }

    #[test]
    fn a_mesh_without_texture_coordinates_has_none() {
        let mesh = Mesh {
            uvs: None,
            ..textured()
        };
        assert_eq!(mesh.triangle_uvs(0), None);
        assert_eq!(mesh.uv(0, 0.25, 0.25), None);
    }

    #[test]
    fn transforms_keep_texture_coordinates() {
        let mesh = textured();
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 3.0, 0.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(1.0, -2.0, 3.0),
        );
        let moved = mesh.transformed(&m);
        assert_eq!(moved.uvs, mesh.uvs);
        assert_eq!(moved.triangles, mesh.triangles);
        assert_eq!(moved.uv(1, 0.2, 0.3), mesh.uv(1, 0.2, 0.3));
        assert_ne!(moved.positions, mesh.positions);
        let plain = Mesh { uvs: None, ..mesh };
        assert_eq!(plain.transformed(&m).uvs, None);
    }
}
