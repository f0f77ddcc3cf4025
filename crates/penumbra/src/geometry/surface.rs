//! Points drawn on a shape's surface, as an `area` emitter draws the
//! targets of its shadow rays (pbrt-v4's `Shape::Sample(ctx, u)`, Mitsuba
//! 3's `Shape::sample_direction`).
//!
//! [`Shape::sample`] draws a point of a shape in its own space for a
//! distribution point, uniformly in area, or for a sphere seen from
//! outside uniformly in the solid angle it subtends (every point drawn is
//! on the visible cap); [`Shape::density`] gives the density in solid
//! angle. A [`Surface`] is a shape where it is in the world: still, placed
//! by an instance's affine map, or moving over the shutter, where it is at
//! the ray's time. It keeps what sampling needs beyond the shape (a mesh's
//! triangles by area, the area in world space) and shares the scene's
//! meshes rather than copying their triangles.
//!
//! A moving surface keeps its proportions (a uniform scale at both ends of
//! its motion), and so does a placed sphere or cylinder; a placed flat
//! shape or mesh may be sheared or scaled along any axis, since an affine
//! map keeps a uniform density on a plane uniform.

use std::sync::Arc;

use super::instance::Placement;
use super::mesh::Mesh;
pub use super::model::{area_pdf, Density, ShapeSample};
use super::motion::{Motion, Similarity};
use super::shape::Shape;
use crate::math::{Aabb, Vec2, Vec3};
use crate::sampling::{Discrete, Distribution};

/// Where a surface is.
#[derive(Clone, Debug)]
pub enum Place {
    /// In world space.
    World,
    /// Placed by a fixed affine map (an instance's).
    Placed(Arc<Placement>),
    /// Moving over the shutter, with a uniform scale.
    Moving(Box<Motion>),
}

/// Why a shape cannot be a [`Surface`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceError {
    /// It has no area.
    NoArea,
    /// It moves or is placed with a scale that is not uniform (or a
    /// shear), which would not keep its samples uniform.
    Proportions,
}

impl std::fmt::Display for SurfaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SurfaceError::NoArea => "it has no area",
            SurfaceError::Proportions => {
                "must keep its proportions: rotate, translate and scale it uniformly"
            }
        })
    }
}

/// A shape where it is in the world, ready to be sampled (see the [module
/// docs](self)). Its normals point to the side it faces: against the
/// shape's own when `flip`.
#[derive(Clone, Debug)]
pub struct Surface {
    shape: Shape,
    place: Place,
    flip: bool,
    meshes: Arc<[Mesh]>,
    /// A mesh's triangles by area (in world space when placed).
    triangles: Option<Discrete>,
    /// The area in the shape's own space and, still or placed, in the
    /// world's (moving, at frame time 0).
    local_area: f32,
    area: f32,
    similar: bool,
}

impl Surface {
    /// The surface of `shape` (a mesh's index into `meshes`) at `place`,
    /// facing against its normals when `flip`.
    pub fn new(
        shape: Shape,
        meshes: Arc<[Mesh]>,
        place: Place,
        flip: bool,
    ) -> Result<Surface, SurfaceError> {
        let uniform = |s: Vec3| {
            let s = s.abs();
            s.max_element() - s.min_element() <= 1e-4 * s.max_element()
        };
        let similar = match &place {
            Place::World => true,
            Place::Placed(p) => uniform(p.to_world.to_scale_rotation_translation().0),
            Place::Moving(m) => uniform(m.start.scale) && uniform(m.end.scale),
        };
        let flat = shape.is_flat();
        let placed = matches!(place, Place::Placed(_));
        if !(similar || placed && flat) {
            return Err(SurfaceError::Proportions);
        }
        let to_world = match &place {
            Place::Placed(p) => Some(p.to_world),
            _ => None,
        };
        let triangles = match shape.as_mesh() {
            Some(mesh) => {
                let m = &meshes[mesh.mesh as usize];
                let area = |i| {
                    let [a, b, c] = m.vertices(i);
                    let [a, b, c] = match &to_world {
                        Some(t) => [a, b, c].map(|v| t.transform_point3(v)),
                        None => [a, b, c],
                    };
                    0.5 * (b - a).cross(c - a).length()
                };
                let table = Discrete::new((0..m.triangles.len()).map(area));
                Some(table.ok_or(SurfaceError::NoArea)?)
            }
            None => None,
        };
        let local_area = match &triangles {
            Some(t) if to_world.is_none() => t.total() as f32,
            _ => shape.area(&meshes),
        };
        let area = match &place {
            Place::World => local_area,
            // A placed mesh's table is in world space.
            Place::Placed(_) if triangles.is_some() => {
                triangles.as_ref().map_or(0.0, |t| t.total() as f32)
            }
            Place::Placed(p) => local_area * shape.area_scale(&p.to_world),
            Place::Moving(m) => local_area * m.start.scale.x.abs().powi(2),
        };
        if !(area > 0.0 && area.is_finite()) {
            return Err(SurfaceError::NoArea);
        }
        Ok(Surface {
            shape,
            place,
            flip,
            meshes,
            triangles,
            local_area,
            area,
            similar,
        })
    }

    /// The shape, in its own space.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// True for a shape in world space that keeps its normals: what a
    /// kernel of the shape may take as it is.
    #[inline]
    pub fn is_plain(&self) -> bool {
        matches!(self.place, Place::World) && !self.flip
    }

    /// The area in world space (moving, at frame time 0).
    pub fn area(&self) -> f32 {
        self.area
    }

    /// True if it faces against its shape's normals.
    pub fn is_flipped(&self) -> bool {
        self.flip
    }

    /// True if it keeps the proportions of its shape: in world space,
    /// moving, or placed by a similarity (rotation, translation, uniform
    /// scale).
    pub fn keeps_proportions(&self) -> bool {
        self.similar
    }

    /// The similarity that carries the shape into the world at `time`, if
    /// it moves or is placed (`None` in world space; placed by a map that
    /// is not a similarity, its nearest one).
    #[inline]
    pub fn similarity(&self, time: f32) -> Option<Similarity> {
        match &self.place {
            Place::World => None,
            Place::Moving(m) => Some(m.at(time)),
            Place::Placed(p) => {
                let (scale, rotation, translation) = p.to_world.to_scale_rotation_translation();
                Some(Similarity {
                    scale,
                    rotation,
                    translation,
                })
            }
        }
    }

    /// A point of the surface for the distribution point `point` of `d`,
    /// seen from `from` at `time` (see [`Shape::sample`]), in world space.
    #[inline(always)]
    pub fn sample(
        &self,
        from: Vec3,
        time: f32,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample> {
        if !matches!(self.place, Place::World) {
            return self.sample_placed(from, time, point, d);
        }
        let mesh = (self.triangles.as_ref(), self.local_area);
        let s = self.shape.sample(&self.meshes, mesh, from, point, d)?;
        Some(if self.flip {
            ShapeSample { n: -s.n, ..s }
        } else {
            s
        })
    }

    /// [`sample`](Self::sample) of a surface placed or moving.
    #[inline(never)]
    fn sample_placed(
        &self,
        from: Vec3,
        time: f32,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample> {
        let mesh = (self.triangles.as_ref(), self.local_area);
        let face = |n: Vec3| if self.flip { -n } else { n };
        if let Place::Placed(pl) = &self.place {
            if self.shape.is_flat() {
                // Flat pieces under any affine map: uniform stays uniform.
                let local = pl.to_object.transform_point3(from);
                let s = self.shape.sample(&self.meshes, mesh, local, point, d)?;
                return Some(ShapeSample {
                    p: pl.point_to_world(s.p),
                    n: face(pl.normal_to_world(s.n)),
                    density: Density::Area {
                        area: self.area,
                        two_sided: false,
                    },
                    ..s
                });
            }
        }
        let sim = self.similarity(time)?;
        let s = self
            .shape
            .sample(&self.meshes, mesh, sim.point_to_local(from), point, d)?;
        let density = match s.density {
            Density::Area { area, two_sided } => Density::Area {
                area: area * sim.scale.x * sim.scale.x,
                two_sided,
            },
            // Solid angles are the same in both spaces.
            cone => cone,
        };
        Some(ShapeSample {
            p: sim.point_to_world(s.p),
            n: face(sim.normal_to_world(s.n)),
            density,
            ..s
        })
    }

    /// The surface coordinates `(u, v)` of a point `s` drawn by
    /// [`sample`](Self::sample): those a ray hitting the surface there
    /// would find.
    pub fn uv(&self, s: &ShapeSample) -> Vec2 {
        self.shape.geometry(&self.meshes, &s.hit, s.local).uv
    }

    /// The solid-angle density with which [`sample`](Self::sample) draws
    /// `target` (a point of the surface with normal `n`, facing the side
    /// the surface faces) from `from` at `time`.
    #[inline]
    pub fn density(&self, from: Vec3, time: f32, target: Vec3, n: Vec3) -> f32 {
        match &self.place {
            Place::World => self.shape.density(self.local_area, from, target, n),
            _ if !self.shape.uniform_in_area() => {
                // In the shape's space (a sphere's cone): solid angles
                // are the same.
                let Some(sim) = self.similarity(time) else {
                    return 0.0;
                };
                let local = |p| sim.point_to_local(p);
                // The inverse of `normal_to_world`: `S R⁻¹ n`, made unit.
                let n = (sim.rotation.conjugate() * n * sim.scale).normalize_or_zero();
                let area = self.local_area;
                self.shape.density(area, local(from), local(target), n)
            }
            place => {
                let area = match place {
                    Place::Moving(m) => self.local_area * m.at(time).scale.x.powi(2),
                    _ => self.area,
                };
                let to = target - from;
                let r2 = to.length_squared();
                area_pdf(n.dot(-to) / r2.sqrt(), r2, area)
            }
        }
    }

    /// The centre of the shape in its own space (see
    /// [`ShapeModel::center`](super::ShapeModel::center)).
    pub fn shape_center(&self) -> Vec3 {
        self.shape.center(&self.meshes)
    }

    /// The box around the shape in its own space.
    pub fn shape_bounds(&self) -> Aabb {
        self.shape.bounds(&self.meshes)
    }

    /// The box around the surface over the whole shutter.
    pub fn bounds(&self) -> Aabb {
        let b = self.shape.bounds(&self.meshes);
        match &self.place {
            Place::World => b,
            Place::Placed(p) => p.bounds(b),
            Place::Moving(m) => m.bounds(b),
        }
    }

    /// A cone holding the normals of the side the surface faces: its axis
    /// and the cosine of its half-angle (−1: every direction). A rectangle
    /// or disk has one normal; a sphere every one; a tube those across its
    /// axis; a mesh a cone around its triangles' (the area-weighted mean
    /// normal, widened to the farthest). Placed or moving, every
    /// direction.
    pub fn normal_cone(&self) -> (Vec3, f32) {
        if !matches!(self.place, Place::World) {
            return (Vec3::Z, -1.0);
        }
        self.shape
            .normal_cone(&self.meshes, self.triangles.as_ref(), self.flip)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::shape::{MeshShape, Sphere};
    use crate::math::Mat4;
    use std::f32::consts::PI;

    /// The surface of `shape` in world space, facing its normals.
    pub(crate) fn still(shape: Shape) -> Surface {
        Surface::new(shape, Arc::from(Vec::new()), Place::World, false).expect("an area")
    }

    /// The surface of a mesh of `triangles`, in world space.
    pub(crate) fn triangles(triangles: &[[Vec3; 3]]) -> Surface {
        let mesh = Mesh {
            positions: triangles.iter().flatten().copied().collect(),
            triangles: (0..triangles.len() as u32)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect(),
            ..Mesh::default()
        };
        let meshes = Arc::from(vec![mesh]);
        Surface::new(
            Shape::MeshShape(MeshShape::new(0)),
            meshes,
            Place::World,
            false,
        )
        .expect("an area")
    }

    use crate::geometry::quad::Quad;
    use crate::geometry::Cylinder;
    use crate::math::Quat;
    use crate::sampling::Rng;

    /// Irradiance at the origin (normal +y) from a polygon of radiance 1
    /// facing it (the contour integral).
    fn polygon_irradiance(vertices: &[Vec3]) -> f32 {
        let mut sum = 0.0;
        for k in 0..vertices.len() {
            let a = vertices[k].normalize();
            let b = vertices[(k + 1) % vertices.len()].normalize();
            let theta = a.dot(b).clamp(-1.0, 1.0).acos();
            sum += theta * Vec3::Y.dot(a.cross(b).normalize());
        }
        0.5 * sum.abs()
    }

    /// The irradiance at the origin (normal +y) from a surface of radiance
    /// 1, estimated from `n` of its samples at `time` (Jittered points of
    /// the unit square), each checked against [`Surface::density`].
    fn irradiance(s: &Surface, time: f32, n: usize) -> f32 {
        let mut rng = Rng::new(9);
        let mut sum = 0.0f64;
        for _ in 0..n {
            let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
            let Some(x) = s.sample(Vec3::ZERO, time, point, Distribution::Jitter) else {
                continue;
            };
            let r2 = x.p.length_squared();
            let dir = x.p / r2.sqrt();
            let pdf = match x.density {
                Density::Area { area, two_sided } => {
                    let cos = x.n.dot(-dir);
                    let cos = if two_sided { cos.abs() } else { cos };
                    if cos <= 0.0 {
                        continue;
                    }
                    r2 / (cos * area)
                }
                Density::Cone(solid_angle) => 1.0 / solid_angle,
            };
            let density = s.density(Vec3::ZERO, time, x.p, x.n);
            assert!(
                (density - pdf).abs() <= 1e-3 * pdf,
                "{density} vs {pdf} of {s:?}"
            );
            sum += f64::from(dir.y.max(0.0) / pdf);
        }
        (sum / n as f64) as f32
    }

    /// A unit square at height 0 facing down, in its own space.
    fn square() -> Quad {
        Quad::new(Vec3::new(-0.5, 0.0, -0.5), Vec3::X, Vec3::Z)
    }

    /// Surfaces placed by an affine map (a sheared, stretched square, and
    /// the same square as a mesh of two triangles) and moving ones (a
    /// square, and a sphere growing as it moves) give the exact irradiance
    /// of the shape where it is: their samples are uniform in world area
    /// (or in the sphere's cone), with the density they report.
    #[test]
    fn placed_and_moving_surfaces_give_the_exact_irradiance() {
        let m = Mat4::from_cols_array_2d(&[
            [1.5, 0.3, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.5, 0.0, 1.0, 0.0],
            [0.2, 1.5, -0.1, 1.0],
        ]);
        let placement = Arc::new(Placement::new(m).unwrap());
        let q = square();
        let corners = [
            q.point(0.0, 0.0),
            q.point(1.0, 0.0),
            q.point(1.0, 1.0),
            q.point(0.0, 1.0),
        ];
        let placed = corners.map(|c| m.transform_point3(c));
        let want = polygon_irradiance(&placed);
        let none: Arc<[Mesh]> = Arc::from(Vec::new());
        let quad = Surface::new(
            Shape::Quad(q),
            Arc::clone(&none),
            Place::Placed(Arc::clone(&placement)),
            false,
        )
        .unwrap();
        assert!(!quad.keeps_proportions());
        let got = irradiance(&quad, 0.0, 200_000);
        assert!((got - want).abs() < 5e-3 * want, "quad: {got} vs {want}");
        let [a, b, c, d] = corners;
        let mesh = Mesh {
            positions: vec![a, b, c, d],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            ..Mesh::default()
        };
        let meshes: Arc<[Mesh]> = Arc::from(vec![mesh]);
        let mesh = Surface::new(
            Shape::MeshShape(MeshShape::new(0)),
            meshes,
            Place::Placed(placement),
            false,
        )
        .unwrap();
        let got = irradiance(&mesh, 0.0, 200_000);
        assert!((got - want).abs() < 5e-3 * want, "mesh: {got} vs {want}");

        // Moving: rising and turning, seen half-way through the shutter.
        let start = Similarity {
            scale: Vec3::splat(0.8),
            rotation: Quat::IDENTITY,
            translation: Vec3::new(-0.4, 1.0, 0.0),
        };
        let end = Similarity {
            scale: Vec3::splat(1.2),
            rotation: Quat::from_rotation_z(0.4),
            translation: Vec3::new(0.6, 2.0, 0.3),
        };
        let motion = Motion { start, end };
        let mid = motion.at(0.5);
        let want = polygon_irradiance(&corners.map(|c| mid.point_to_world(c)));
        let moving = Surface::new(
            Shape::Quad(q),
            Arc::clone(&none),
            Place::Moving(Box::new(motion)),
            false,
        )
        .unwrap();
        let got = irradiance(&moving, 0.5, 200_000);
        assert!(
            (got - want).abs() < 5e-3 * want,
            "moving quad: {got} vs {want}"
        );
        // A sphere seen from outside: E = π r² h / d³ for its centre at
        // height h and distance d.
        let ball = Shape::Sphere(Sphere::new(Vec3::ZERO, 0.25));
        let moving = Surface::new(ball, none, Place::Moving(Box::new(motion)), false).unwrap();
        let (c, r) = (mid.translation, 0.25 * mid.scale.x);
        let want = PI * r * r * c.y / c.length().powi(3);
        let got = irradiance(&moving, 0.5, 100_000);
        assert!(
            (got - want).abs() < 5e-3 * want,
            "moving sphere: {got} vs {want}"
        );
        // A sphere placed by a mirroring similarity around the point: seen
        // from inside, E = π.
        let mirror = Mat4::from_cols_array_2d(&[
            [-1.5, 0.0, 0.0, 0.0],
            [0.0, 1.5, 0.0, 0.0],
            [0.0, 0.0, 1.5, 0.0],
            [0.0, 0.5, 0.0, 1.0],
        ]);
        let placement = Arc::new(Placement::new(mirror).unwrap());
        let unit = Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0));
        let around =
            Surface::new(unit, Arc::from(Vec::new()), Place::Placed(placement), false).unwrap();
        assert!(around.keeps_proportions());
        let got = irradiance(&around, 0.0, 100_000);
        assert!((got - PI).abs() < 5e-3 * PI, "sphere around: {got} vs π");
        // Stretching as it moves, a light would not stay uniform.
        let stretch = Motion {
            end: Similarity {
                scale: Vec3::new(2.0, 1.0, 1.0),
                ..end
            },
            start,
        };
        let err = Surface::new(
            Shape::Quad(q),
            Arc::from(Vec::new()),
            Place::Moving(Box::new(stretch)),
            false,
        );
        assert_eq!(err.err(), Some(SurfaceError::Proportions));
    }

    /// A mesh's samples are uniform in area: over a large and a small
    /// triangle (areas 8 and 0.5) the share landing on each is its share
    /// of the area (binomial, 5σ), and within the large one the points'
    /// mean is its centroid; a mesh of no area is refused.
    #[test]
    fn mesh_samples_are_uniform_in_area() {
        let big = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
        ];
        let small = [
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(6.0, 0.0, 0.0),
            Vec3::new(5.0, 0.0, 1.0),
        ];
        let light = triangles(&[big, small]);
        assert!((light.area() - 8.5).abs() < 1e-5);
        let mut rng = Rng::new(13);
        let (n, mut on_small, mut sum) = (40_000, 0, Vec3::ZERO);
        let from = Vec3::new(2.0, -3.0, 1.0);
        for _ in 0..n {
            let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
            let s = light
                .sample(from, 0.0, point, Distribution::Jitter)
                .unwrap();
            assert_eq!(s.n, -Vec3::Y);
            if s.p.x > 4.5 {
                on_small += 1;
            } else {
                sum += s.p;
            }
        }
        let share = 0.5 / 8.5;
        let sigma = (n as f32 * share * (1.0 - share)).sqrt();
        assert!(
            (on_small as f32 - n as f32 * share).abs() < 5.0 * sigma,
            "{on_small}"
        );
        let mean = sum / (n - on_small) as f32;
        assert!(
            (mean - Vec3::new(4.0 / 3.0, 0.0, 4.0 / 3.0)).length() < 0.03,
            "{mean:?}"
        );
        let flat = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X],
            triangles: vec![[0, 1, 2]],
            ..Mesh::default()
        };
        let none = Surface::new(
            Shape::MeshShape(MeshShape::new(0)),
            Arc::from(vec![flat]),
            Place::World,
            false,
        );
        assert_eq!(none.err(), Some(SurfaceError::NoArea));
    }

    /// A tube's samples fall uniformly in its (φ, z) parameters: a χ² test
    /// over a 16 × 8 grid of 64,000 samples drawn from the axis, facing
    /// inward (flipped), where every sample is seen. 127 degrees of
    /// freedom, bound at the 0.999 quantile (181.9). Against counts
    /// expected 10% denser toward one end the same samples fail: the test
    /// can tell.
    #[test]
    fn tube_samples_are_uniform_in_area() {
        let c = Cylinder::new(Vec3::new(0.2, -0.3, 0.1), Vec3::new(1.0, 1.5, -0.4), 0.7).unwrap();
        let tube = Surface::new(
            Shape::Cylinder(c),
            Arc::from(Vec::new()),
            Place::World,
            true,
        )
        .unwrap();
        let (nphi, nz, n) = (16, 8, 64_000);
        let mid = c.base + 0.5 * c.length * c.frame.n;
        let mut counts = vec![0u32; nphi * nz];
        let mut rng = Rng::new(7);
        let mut drawn = 0;
        while drawn < n {
            let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
            if point.length_squared() >= 1.0 {
                continue;
            }
            let s = tube.sample(mid, 0.0, point, Distribution::Random).unwrap();
            // Flipped: facing the axis.
            assert!(s.n.dot(mid - s.p) > 0.0);
            let g = c.geometry(s.p - c.base);
            let i = ((g.uv.x * nphi as f32) as usize).min(nphi - 1);
            let j = ((g.uv.y * nz as f32) as usize).min(nz - 1);
            counts[j * nphi + i] += 1;
            drawn += 1;
        }
        let chi2 = |expected: &dyn Fn(usize) -> f64| {
            (0..nphi * nz)
                .map(|k| (counts[k] as f64 - expected(k)).powi(2) / expected(k))
                .sum::<f64>()
        };
        let cell = n as f64 / (nphi * nz) as f64;
        let uniform = chi2(&|_| cell);
        assert!(uniform < 181.9, "χ² = {uniform}");
        let tilted = chi2(&|k| {
            let z = ((k / nphi) as f64 + 0.5) / nz as f64;
            cell * (1.0 + 0.2 * (z - 0.5))
        });
        assert!(tilted > 181.9, "a wrong density passes: χ² = {tilted}");
    }
}
