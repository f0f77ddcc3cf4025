use crate::math::{Aabb, Mat4, Vec3};

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (smooth shading), if any.
    pub normals: Option<Vec<Vec3>>,
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

    /// The mesh with every vertex transformed by `m` (normals by its inverse transpose).
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
            triangles: self.triangles.clone(),
        }
    }

    /// The texture coordinates of triangle `i`'s corners, if the mesh has them.
    pub fn triangle_uvs(&self, _i: usize) -> Option<[crate::math::Vec2; 3]> {
        None
    }

    /// Shading normal at barycentrics (b1, b2) of triangle `i`, if the mesh has normals.
    pub fn shading_normal(&self, i: usize, b1: f32, b2: f32) -> Option<Vec3> {
        let ns = self.normals.as_ref()?;
        let [a, b, c] = self.triangles[i];
        let n = (1.0 - b1 - b2) * ns[a as usize] + b1 * ns[b as usize] + b2 * ns[c as usize];
        let n = n.normalize_or_zero();
        (n != Vec3::ZERO).then_some(n)
    }
}
