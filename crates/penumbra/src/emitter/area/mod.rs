//! `area`: a surface emitting uniform radiance, carried by a shape (Mitsuba
//! 3's `area` emitter): a rectangle, sphere, disk, cylinder or triangle
//! mesh (cubes included). What a
//! ray that hits the shape sees, and what a shading point is lit by.
//!
//! One-sided (emitting along the shape's geometric normal), but for
//! spheres, which emit outward from their whole surface. A shading point
//! samples it by one of two penumbra models:
//!
//! * `surface`: the shadow ray's target lies on the light's real surface
//!   (uniform in area, or in the solid angle a sphere subtends from
//!   outside) and its weight carries the geometry term and the pdf, so the
//!   average converges to the exact direct illumination (what pbrt or
//!   Mitsuba compute).
//! * `thesis` (§3.3): the target is the light's centre moved on the plane
//!   facing the shading point by the distribution point (radius: the
//!   light's size), and each ray is shaded as if the light's whole power
//!   came from that point. With one grid ray this is the classic Whitted
//!   shadow ray to the centre. Rectangles, spheres and disks only.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `radiance` | colour ≥ 0 | **required** | emitted radiance |
//! | `model` | `"surface"` or `"thesis"` | `"surface"` | the penumbra model |
//! | `shadow_rays` | integer 1–65536 | the render's | shadow rays per shading point |
//! | `shadow_distribution` | distribution | the render's | |

mod cylinder;
mod disk;
mod mesh;
mod rect;
mod sphere;

pub use mesh::MeshLight;

use crate::description::check::{int, nonneg3, required};
use crate::description::mitsuba::adapt;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::emitter::bounds::{mean, LightBounds};
use crate::emitter::model::EmitterModel;
use crate::emitter::sample::{area_pdf, LightSample};
use crate::geometry::quad::Quad;
use crate::geometry::Cylinder;
use crate::math::{Aabb, Frame, Rgb, Vec3};
use crate::sampling::points::end_point;
use crate::sampling::{Distribution, EffectSpec, MAX_RAYS};

/// How shadow rays toward an area light are aimed and weighted (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PenumbraModel {
    Thesis,
    Surface,
}

impl PenumbraModel {
    pub const NAMES: [&'static str; 2] = ["surface", "thesis"];

    pub fn from_name(s: &str) -> Option<PenumbraModel> {
        match s {
            "surface" => Some(PenumbraModel::Surface),
            "thesis" => Some(PenumbraModel::Thesis),
            _ => None,
        }
    }
}

/// The parameters of an area emitter (and of the lights that are shapes
/// carrying one).
pub const PARAMS: [Param; 4] = [
    Param::new("radiance", Type::Colour, "required", "emitted radiance, ≥ 0").range(Range::NonNegative),
    Param::new("model", Type::Choice("penumbra model", &PenumbraModel::NAMES), "\"surface\"", "penumbra model: `surface` samples the light's real surface with the geometry term and converges to the exact direct illumination; `thesis` distributes shadow-ray end points over a disk/square of the light's size facing the shading point (§3.3) and shades each as if the light's power came from there").penumbra_only(),
    Param::new("shadow_rays", Type::Int, "render.shadow_rays", "shadow rays per shading point, 1–65536").penumbra_only().range(Range::Between(1.0, 65536.0)),
    Param::new("shadow_distribution", Type::Distribution, "render.shadow_distribution", "").penumbra_only(),
];

/// An `area` emitter, the child of the shape that carries it.
pub const SCHEMA: Schema = Schema {
    kind: Kind::Emitter,
    plugin: "area",
    what: "area emitter",
    doc: "uniform radiance from the surface of the shape that carries it, sampled by one of two penumbra models",
    mitsuba: &["area"],
    params: &PARAMS,
};

/// How Mitsuba's `area` maps onto it.
pub const MITSUBA: Mitsuba = Mitsuba {
    differences: "`radiance` is 1 when not given, as in Mitsuba",
    reads: &[],
    adapt: Some(Adapt::Node(adapt::area)),
};

/// What an area emitter's parameters say, read and checked; `what` names
/// the light in messages, `shadow` is the render's shadow set.
pub fn read(
    p: &Props,
    what: &str,
    shadow: EffectSpec,
) -> Result<(Rgb, PenumbraModel, EffectSpec), Invalid> {
    required(p, p.numbers::<3>("radiance")?, "radiance", what)?;
    let radiance = nonneg3(p, "radiance", [0.0; 3])?;
    let model = match p.choice("model", "penumbra model", &PenumbraModel::NAMES)? {
        Some("thesis") => PenumbraModel::Thesis,
        _ => PenumbraModel::Surface,
    };
    let shadow = EffectSpec {
        rays: int(
            p,
            "shadow_rays",
            i64::from(shadow.rays),
            1,
            i64::from(MAX_RAYS),
        )?,
        distribution: p
            .distribution("shadow_distribution")?
            .unwrap_or(shadow.distribution),
    };
    Ok((radiance, model, shadow))
}

/// The shape an area light samples, in world space.
#[derive(Clone, Debug)]
pub enum AreaShape {
    /// A parallelogram emitting along `edge_u × edge_v`.
    Rect(Quad),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// A disk emitting along `frame.n`.
    Disk {
        center: Vec3,
        frame: Frame,
        radius: f32,
    },
    /// An open cylinder emitting away from its axis, or toward it when
    /// `inward` (`flip_normals`).
    Cylinder {
        cylinder: Cylinder,
        inward: bool,
    },
    Mesh(MeshLight),
}

/// An area light (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Area {
    pub shape: AreaShape,
    pub radiance: Rgb,
    pub model: PenumbraModel,
}

impl Area {
    /// The light's centre, which the thesis model aims around.
    pub fn center(&self) -> Vec3 {
        match &self.shape {
            AreaShape::Rect(q) => q.center(),
            AreaShape::Sphere { center, .. } | AreaShape::Disk { center, .. } => *center,
            AreaShape::Cylinder { cylinder: c, .. } => c.base + 0.5 * c.length * c.frame.n,
            AreaShape::Mesh(m) => m.centroid(),
        }
    }

    /// The thesis's light size: the radius of the distribution around the
    /// centre. A rectangle (or mesh) uses half the side of the square of
    /// equal area.
    pub fn size(&self) -> f32 {
        match &self.shape {
            AreaShape::Rect(q) => rect::size(q),
            AreaShape::Sphere { radius, .. } | AreaShape::Disk { radius, .. } => *radius,
            AreaShape::Cylinder { cylinder: c, .. } => 0.5 * c.area().sqrt(),
            AreaShape::Mesh(m) => 0.5 * m.area().sqrt(),
        }
    }

    /// The area of the emitting surface.
    pub fn area(&self) -> f32 {
        match &self.shape {
            AreaShape::Rect(q) => q.area(),
            AreaShape::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
            AreaShape::Disk { radius, .. } => disk::area(*radius),
            AreaShape::Cylinder { cylinder: c, .. } => c.area(),
            AreaShape::Mesh(m) => m.area(),
        }
    }

    /// The power it emits, `π · A · L` (one-sided: a sphere outward), the
    /// mean over the colour channels: the same under either penumbra model.
    pub fn power(&self) -> f32 {
        std::f32::consts::PI * self.area() * mean(self.radiance)
    }

    /// What a light BVH knows of it: the box around the shape, the cone
    /// of its normals (one normal for a rectangle or disk; every direction
    /// for a sphere; the directions across the axis for a tube; a cone
    /// around a mesh's triangles' normals), emitting into the hemisphere
    /// of each normal, and its [`power`](Self::power).
    pub fn bounds(&self) -> LightBounds {
        let (bounds, axis, cos_theta_o) = match &self.shape {
            AreaShape::Rect(q) => {
                let corners = [
                    q.origin,
                    q.origin + q.edge_u,
                    q.origin + q.edge_v,
                    q.origin + q.edge_u + q.edge_v,
                ];
                (Aabb::from_points(corners), q.normal, 1.0)
            }
            AreaShape::Disk {
                center,
                frame,
                radius,
            } => {
                let n = frame.n;
                let e = (Vec3::ONE - n * n).max(Vec3::ZERO);
                let r = *radius * Vec3::new(e.x.sqrt(), e.y.sqrt(), e.z.sqrt());
                (Aabb::new(*center - r, *center + r), n, 1.0)
            }
            AreaShape::Sphere { center, radius } => {
                let r = Vec3::splat(*radius);
                (Aabb::new(*center - r, *center + r), Vec3::Z, -1.0)
            }
            AreaShape::Cylinder { cylinder: c, .. } => (c.bounds(), c.frame.n, 0.0),
            AreaShape::Mesh(m) => {
                let (axis, cos) = m.normal_cone();
                (m.bounds(), axis, cos)
            }
        };
        LightBounds::new(bounds, axis, self.power(), cos_theta_o, 0.0)
    }

    /// Radiance leaving the light's surface toward `-dir` at a point with
    /// geometric normal `n` (one-sided but for spheres).
    #[inline]
    pub fn emitted(&self, n: Vec3, dir: Vec3) -> Rgb {
        match self.shape {
            AreaShape::Sphere { .. } => self.radiance,
            _ if n.dot(dir) < 0.0 => self.radiance,
            _ => Rgb::ZERO,
        }
    }

    /// True if [`sample`](Self::sample) takes points of `d` four at a time
    /// through a kernel: a rectangle sampled on its surface by a square
    /// distribution.
    #[inline]
    pub(super) fn four_wide(&self, d: Distribution) -> bool {
        let rect = matches!(self.shape, AreaShape::Rect(_));
        rect && self.model == PenumbraModel::Surface && d != Distribution::Random
    }

    /// Samples for a batch of distribution points (see
    /// [`Emitter::sample`](super::Emitter::sample)).
    pub(super) fn sample(
        &self,
        at: impl Fn(usize) -> Vec3,
        points: &[Vec3],
        d: Distribution,
        out: &mut Vec<Option<LightSample>>,
    ) {
        let wide = match &self.shape {
            AreaShape::Rect(q) if self.four_wide(d) => {
                let fours = points.chunks_exact(4);
                for (g, four) in fours.enumerate() {
                    let p = std::array::from_fn(|l| at(4 * g + l));
                    let four = four.try_into().expect("chunks of four");
                    out.extend(rect::sample4(self.radiance, q, &p, four).lanes());
                }
                points.len() / 4 * 4
            }
            _ => 0,
        };
        let rest = points.iter().enumerate().skip(wide);
        out.extend(rest.map(|(k, &point)| self.sample_one(at(k), point, d)));
    }

    /// One sample: the portable form, which the rectangle's kernel is
    /// tested against.
    pub(super) fn sample_one(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        match self.model {
            PenumbraModel::Thesis => self.sample_thesis(p, point, d),
            PenumbraModel::Surface => self.sample_surface(p, point, d),
        }
    }

    /// The solid-angle density with which the surface model draws `target`
    /// (a point of the light with outward normal `n`) from `p`; 0 under the
    /// thesis model, whose rays are not drawn from the light's surface.
    pub fn pdf(&self, p: Vec3, target: Vec3, n: Vec3) -> f32 {
        if self.model == PenumbraModel::Thesis {
            return 0.0;
        }
        let to = target - p;
        let r2 = to.length_squared();
        let cos_l = n.dot(-to) / r2.sqrt();
        match &self.shape {
            AreaShape::Sphere { center, radius } => sphere::pdf(p, *center, *radius, cos_l, r2),
            AreaShape::Rect(q) => area_pdf(cos_l, r2, q.area()),
            AreaShape::Disk { radius, .. } => area_pdf(cos_l, r2, disk::area(*radius)),
            AreaShape::Cylinder { cylinder: c, .. } => area_pdf(cos_l, r2, c.area()),
            AreaShape::Mesh(m) => m.pdf(cos_l, r2),
        }
    }

    fn sample_thesis(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        let c = self.center();
        let axis = (c - p).normalize_or_zero();
        let target = end_point(c, axis, point, self.size(), d);
        let to = target - p;
        let r2 = to.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        let weight = self.point_intensity(-to / r2.sqrt()) / r2;
        Some(LightSample {
            target,
            dir: to.normalize_or_zero(),
            weight,
            pdf: 0.0,
        })
    }

    /// Intensity toward direction `w` (unit, from the light) of the light
    /// collapsed to a point, as the thesis shades every shadow ray.
    fn point_intensity(&self, w: Vec3) -> Rgb {
        let power = self.radiance;
        match &self.shape {
            AreaShape::Rect(q) => rect::intensity(power, q, w),
            AreaShape::Sphere { radius, .. } => sphere::intensity(power, *radius),
            AreaShape::Disk { frame, radius, .. } => disk::intensity(power, frame.n, *radius, w),
            // Not reached: the thesis model is refused on meshes and
            // cylinders when the scene is built; a flat light of the
            // shape's area facing `w`.
            AreaShape::Cylinder { cylinder: c, .. } => power * c.area(),
            AreaShape::Mesh(m) => power * m.area(),
        }
    }

    fn sample_surface(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        let power = self.radiance;
        match &self.shape {
            AreaShape::Rect(q) => rect::sample(power, q, p, point, d),
            AreaShape::Disk {
                center,
                frame,
                radius,
            } => disk::sample(power, *center, frame, *radius, p, point, d),
            AreaShape::Sphere { center, radius } => {
                sphere::sample(power, *center, *radius, p, point, d)
            }
            AreaShape::Cylinder { cylinder, inward } => {
                cylinder::sample(power, cylinder, *inward, p, point, d)
            }
            AreaShape::Mesh(m) => m.sample(power, p, point, d),
        }
    }
}

impl EmitterModel for Area {
    fn power(&self, _radius: f32) -> f32 {
        Area::power(self)
    }

    fn bounds(&self) -> Option<LightBounds> {
        Some(Area::bounds(self))
    }

    #[inline]
    fn eval(&self, n: Vec3, dir: Vec3) -> Rgb {
        self.emitted(n, dir)
    }

    #[inline]
    fn sample(
        &self,
        at: impl Fn(usize) -> Vec3,
        points: &[Vec3],
        d: Distribution,
        out: &mut Vec<Option<LightSample>>,
    ) {
        Area::sample(self, at, points, d, out);
    }

    #[inline]
    fn sample_one(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        Area::sample_one(self, p, point, d)
    }

    fn pdf(&self, p: Vec3, target: Vec3, n: Vec3) -> f32 {
        Area::pdf(self, p, target, n)
    }
}
