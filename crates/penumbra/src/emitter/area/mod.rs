//! `area`: a surface emitting radiance, uniform or a texture, carried by a
//! shape (Mitsuba 3's `area` emitter): a rectangle, sphere, disk, cylinder or triangle
//! mesh (cubes included), still, placed by an instance or moving. What a
//! ray that hits the shape sees, and what a shading point is lit by. The
//! emitter holds the shape's [`Surface`] and samples it through
//! [`Shape::sample`](crate::geometry::Shape::sample) (a moving light where
//! it is at the ray's time); a mesh's triangles stay the scene's.
//!
//! One-sided (emitting along the shape's geometric normal), but for
//! spheres, which emit outward from their whole surface. The radiance may
//! be a texture, looked up at the surface coordinates `(u, v)` of the
//! point of the light (where a ray hits it, or the point drawn on it),
//! which a ray hitting the shape there would find. A rectangle of a
//! `bitmap` radiance draws its points by the texture ([`ByTexture`]:
//! `(u, v)` in proportion to the texels, as Mitsuba draws them, less
//! noise where the texture is uneven); any other light draws them as a
//! uniform light does (uniformly in area, or in a sphere's cone), so that
//! [`Area::pdf`] is the density of the draw for any parameterisation of
//! the shape. A shading point samples it by one of two penumbra models:
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
//!   shadow ray to the centre. Rectangles, spheres and disks only, of a
//!   constant radiance.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `radiance` | colour ≥ 0 or texture | **required** | emitted radiance |
//! | `model` | `"surface"` or `"thesis"` | `"surface"` | the penumbra model |
//! | `shadow_rays` | integer 1–65536 | the render's | shadow rays per shading point |
//! | `shadow_distribution` | distribution | the render's | |

pub mod by_texture;
mod rect;

use std::sync::Arc;

pub use by_texture::{ByTexture, TexturePoint};

use crate::description::check::{int, nonneg3, required};
use crate::description::mitsuba::adapt;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::emitter::bounds::{mean, LightBounds};
use crate::emitter::model::EmitterModel;
use crate::emitter::sample::{area_sample, EmittedRay, LightSample, Reference, SurfacePoint};
use crate::geometry::quad::Quad;
use crate::geometry::{Density, ShapeSample, Surface};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::points::{end_point, unit_square};
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::sampling::SetPoint;
use crate::sampling::{Distribution, Domain, EffectSpec, MAX_RAYS};
use crate::texture::{Texture, Textures};

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
    Param::new("radiance", Type::ColourTexture, "required", "emitted radiance, ≥ 0: a colour or a texture looked up at the surface coordinates of the point of the light").range(Range::NonNegative),
    Param::new("model", Type::Choice("penumbra model", &PenumbraModel::NAMES), "\"surface\"", "penumbra model: `surface` samples the light's real surface with the geometry term and converges to the exact direct illumination; `thesis` distributes shadow-ray end points over a disk/square of the light's size facing the shading point (§3.3) and shades each as if the light's power came from there").penumbra_only(),
    Param::new("shadow_rays", Type::Int, "render.shadow_rays", "shadow rays per shading point, 1–65536").penumbra_only().range(Range::Between(1.0, 65536.0)),
    Param::new("shadow_distribution", Type::Distribution, "render.shadow_distribution", "").penumbra_only(),
];

/// An `area` emitter, the child of the shape that carries it.
pub const SCHEMA: Schema = Schema {
    kind: Kind::Emitter,
    plugin: "area",
    what: "area emitter",
    doc: "radiance, uniform or a texture, from the surface of the shape that carries it, sampled by one of two penumbra models",
    mitsuba: &["area"],
    params: &PARAMS,
};

/// How Mitsuba's `area` maps onto it.
pub const MITSUBA: Mitsuba = Mitsuba {
    differences: "`radiance` is 1 when not given, as in Mitsuba; a textured `radiance` is looked up at the `(u, v)` of the point of the light; a rectangle's points are drawn by its `bitmap` texture (without `to_uv`) as Mitsuba draws them, in proportion to the texels (a bilinear texel weighed as the brightest of it and its neighbours); the points of other textured lights are drawn as a plain light's (uniformly in area, or in a sphere's cone) where Mitsuba draws them by the texture: the same mean, other noise",
    reads: &[],
    adapt: Some(Adapt::Node(adapt::area)),
};

/// What an area emitter's parameters say, read and checked; `what` names
/// the light in messages, `shadow` is the render's shadow set, `textures`
/// reads a textured radiance.
pub fn read(
    p: &Props,
    what: &str,
    shadow: EffectSpec,
    textures: &Textures,
) -> Result<(Texture, PenumbraModel, EffectSpec), Invalid> {
    let radiance = match p.get("radiance") {
        Some(_) => textures.colour(p, "radiance", Rgb::ZERO)?,
        None => {
            required(p, p.numbers::<3>("radiance")?, "radiance", what)?;
            Texture::Constant(nonneg3(p, "radiance", [0.0; 3])?)
        }
    };
    if matches!(radiance, Texture::MeshAttribute(_)) {
        return Err(p.error(
            "radiance",
            "an area light's radiance takes a texture looked up at surface coordinates (u, v), \
             not a mesh attribute",
        ));
    }
    let model = match p.choice("model", "penumbra model", &PenumbraModel::NAMES)? {
        Some("thesis") => PenumbraModel::Thesis,
        _ => PenumbraModel::Surface,
    };
    if model == PenumbraModel::Thesis && !matches!(radiance, Texture::Constant(_)) {
        return Err(p.error(
            "radiance",
            "the thesis penumbra model collapses the light to a point: it takes a constant \
             radiance, not a texture",
        ));
    }
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

/// An area light (see the [module docs](self)): the surface of a shape
/// where it is (still, placed by an instance, or moving), emitting from
/// the side its normals face.
#[derive(Clone, Debug)]
pub struct Area {
    pub surface: Surface,
    /// The radiance, at the surface coordinates of the point of the light.
    pub radiance: Texture,
    pub model: PenumbraModel,
    /// The draw of its points by its texture, where the texture and the
    /// shape allow one ([`ByTexture`]); `None`: drawn uniformly.
    pub by_texture: Option<Arc<ByTexture>>,
}

/// Points per side of the grid in `(u, v)` over which a texture's mean
/// radiance is taken, for the light's power.
const MEAN_GRID: usize = 64;

impl Area {
    /// The light of `surface` emitting `radiance`, its points drawn by its
    /// texture where the texture and the shape allow it ([`ByTexture`]).
    pub fn new(surface: Surface, radiance: Texture, model: PenumbraModel) -> Area {
        let by_texture = match model {
            PenumbraModel::Surface => ByTexture::new(&surface, &radiance).map(Arc::new),
            PenumbraModel::Thesis => None,
        };
        Area {
            surface,
            radiance,
            model,
            by_texture,
        }
    }

    /// The light drawn uniformly whatever its texture (the draw that
    /// [`ByTexture`] replaces, kept to compare them).
    pub fn uniform(self) -> Area {
        Area {
            by_texture: None,
            ..self
        }
    }

    /// A sample toward `r` of a point drawn by the texture for the
    /// distribution point `point` of `d`.
    fn sample_by_texture(
        &self,
        by: &ByTexture,
        r: Reference,
        point: Vec3,
        d: Distribution,
    ) -> Option<LightSample> {
        let t = by.sample(unit_square(point, d))?;
        let radiance = self.radiance.eval_uv(t.uv);
        area_sample(radiance, r.p, t.p, t.n, 1.0 / t.pdf_area, false)
    }

    /// The radiance where it is the same everywhere.
    #[inline(always)]
    fn constant(&self) -> Option<Rgb> {
        match self.radiance {
            Texture::Constant(c) => Some(c),
            _ => None,
        }
    }

    /// The radiance at the point `s` drawn on the surface.
    #[inline(always)]
    fn radiance_at(&self, s: &ShapeSample) -> Rgb {
        self.constant()
            .unwrap_or_else(|| self.radiance.eval_uv(self.surface.uv(s)))
    }

    /// The mean radiance over the unit square of `(u, v)` (of a texture,
    /// on a grid of `MEAN_GRID`² points): what the light's power counts.
    pub fn mean_radiance(&self) -> Rgb {
        if let Some(c) = self.constant() {
            return c;
        }
        let n = MEAN_GRID;
        let mut sum = [0.0f64; 3];
        for j in 0..n {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let c = self.radiance.eval_uv(uv).to_array();
                for k in 0..3 {
                    sum[k] += f64::from(c[k]);
                }
            }
        }
        let m = (n * n) as f64;
        Rgb::new(
            (sum[0] / m) as f32,
            (sum[1] / m) as f32,
            (sum[2] / m) as f32,
        )
    }

    /// The light's centre in the shape's own space, which the thesis model
    /// aims around.
    fn center(&self) -> Vec3 {
        self.surface.shape_center()
    }

    /// The thesis's light size in the shape's own space: the radius of the
    /// distribution around the centre. A rectangle (or any other shape)
    /// uses half the side of the square of equal area.
    fn size(&self) -> f32 {
        let size = self.surface.shape().size();
        size.unwrap_or_else(|| 0.5 * self.surface.area().sqrt())
    }

    /// The area of the emitting surface.
    pub fn area(&self) -> f32 {
        self.surface.area()
    }

    /// The power it emits, `π · A · L` (one-sided: a sphere outward), the
    /// mean over the colour channels: the same under either penumbra model.
    /// A texture counts its [mean](Self::mean_radiance) over `(u, v)`
    /// (the power of a shape whose `(u, v)` cover it evenly).
    pub fn power(&self) -> f32 {
        std::f32::consts::PI * self.area() * mean(self.mean_radiance())
    }

    /// What a light BVH knows of it: the box around the surface over the
    /// shutter, the cone of its normals
    /// ([`Surface::normal_cone`]), emitting into the hemisphere of each
    /// normal, and its [`power`](Self::power).
    pub fn bounds(&self) -> LightBounds {
        let (axis, cos_theta_o) = self.surface.normal_cone();
        LightBounds::new(self.surface.bounds(), axis, self.power(), cos_theta_o, 0.0)
    }

    /// Radiance leaving the light's surface toward `-dir` at a point with
    /// geometric normal `n` and surface coordinates `uv` (one-sided but for
    /// spheres).
    #[inline]
    pub fn emitted(&self, n: Vec3, uv: Vec2, dir: Vec3) -> Rgb {
        if self.surface.shape().as_sphere().is_some() || n.dot(dir) < 0.0 {
            self.radiance.eval_uv(uv)
        } else {
            Rgb::ZERO
        }
    }

    /// The rectangle in world space facing its normal that the light is, if
    /// it is one of a constant radiance.
    #[inline(always)]
    fn plain_rect(&self) -> Option<(&Quad, Rgb)> {
        let q = self.surface.shape().as_quad();
        let q = q.filter(|_| self.surface.is_plain());
        Some((q?, self.constant()?))
    }

    /// The rectangle that [`sample`](Self::sample) takes points of `d`
    /// four at a time for through a kernel: a rectangle in world space
    /// sampled on its surface by a square distribution.
    #[inline]
    pub(super) fn four_wide(&self, d: Distribution) -> Option<(&Quad, Rgb)> {
        let surface = self.model == PenumbraModel::Surface && d.domain() != Domain::Disk;
        self.plain_rect().filter(|_| surface)
    }

    /// Samples for a batch of distribution points (see
    /// [`Emitter::sample`](super::Emitter::sample)); inlined into each
    /// caller's loop.
    #[inline(always)]
    pub(super) fn sample(
        &self,
        at: impl Fn(usize) -> Reference,
        points: &[Vec3],
        d: Distribution,
        out: &mut Vec<Option<LightSample>>,
    ) {
        let wide = match self.four_wide(d) {
            Some((q, radiance)) => {
                let fours = points.chunks_exact(4);
                for (g, four) in fours.enumerate() {
                    let p = std::array::from_fn(|l| at(4 * g + l).p);
                    let four = four.try_into().expect("chunks of four");
                    out.extend(rect::sample4(radiance, q, &p, four).lanes());
                }
                points.len() / 4 * 4
            }
            None => 0,
        };
        let rest = points.iter().enumerate().skip(wide);
        out.extend(rest.map(|(k, &point)| self.sample_one(at(k), point, d)));
    }

    /// One sample: the portable form, which the rectangle's kernel is
    /// tested against.
    pub(super) fn sample_one(
        &self,
        r: Reference,
        point: Vec3,
        d: Distribution,
    ) -> Option<LightSample> {
        match self.model {
            PenumbraModel::Thesis => self.sample_thesis(r, point, d),
            PenumbraModel::Surface => {
                if let Some((q, radiance)) = self.plain_rect() {
                    // The rectangle's own path, which its kernel repeats.
                    let u = unit_square(point, d);
                    let target = q.point(u.x, u.y);
                    return area_sample(radiance, r.p, target, q.normal, q.area(), false);
                }
                if let Some(by) = &self.by_texture {
                    return self.sample_by_texture(by, r, point, d);
                }
                let s = self.surface.sample(r.p, r.time, point, d)?;
                let radiance = self.radiance_at(&s);
                match s.density {
                    Density::Area { area, two_sided } => {
                        area_sample(radiance, r.p, s.p, s.n, area, two_sided)
                    }
                    Density::Cone(solid_angle) => Some(LightSample {
                        target: s.p,
                        dir: (s.p - r.p).normalize_or_zero(),
                        weight: radiance * solid_angle,
                        pdf: 1.0 / solid_angle,
                    }),
                }
            }
        }
    }

    /// A point over the surface at `time` for the point `u` of the unit
    /// square (uniform, or drawn by the texture where [`ByTexture`] draws
    /// them), with the normal of the side it emits toward (a sphere
    /// outward), whatever the penumbra model (both emit the same light
    /// from the same surface).
    pub fn sample_position(&self, u: Vec2, time: f32) -> Option<SurfacePoint> {
        if let Some(by) = &self.by_texture {
            let t = by.sample(u)?;
            return Some(SurfacePoint {
                p: t.p,
                n: t.n,
                uv: t.uv,
                inv_pdf: 1.0 / t.pdf_area,
            });
        }
        // Seen from the shape's centre, every shape is drawn uniformly in
        // area (a sphere from outside would be drawn in its cone).
        let c = self.center();
        let from = self
            .surface
            .similarity(time)
            .map_or(c, |s| s.point_to_world(c));
        let point = SetPoint::uniform(u).native();
        let s = self
            .surface
            .sample(from, time, point, Distribution::Jitter)?;
        match s.density {
            Density::Area { area, .. } if area > 0.0 => Some(SurfacePoint {
                p: s.p,
                n: s.n,
                uv: self.surface.uv(&s),
                inv_pdf: area,
            }),
            _ => None,
        }
    }

    /// The solid-angle density with which the surface model draws `target`
    /// (a point of the light with outward normal `n`) from `r`; 0 under
    /// the thesis model, whose rays are not drawn from the light's surface.
    pub fn pdf(&self, r: Reference, target: Vec3, n: Vec3) -> f32 {
        if self.model == PenumbraModel::Thesis {
            return 0.0;
        }
        if let Some(by) = &self.by_texture {
            let to = target - r.p;
            let r2 = to.length_squared();
            let cos_l = n.dot(-to) / r2.sqrt();
            if !(cos_l > 0.0 && r2 > 0.0) {
                return 0.0;
            }
            return by.pdf_area(target) * r2 / cos_l;
        }
        self.surface.density(r.p, r.time, target, n)
    }

    /// The thesis's shadow-ray target (§3.3), in the shape's own space
    /// carried to the world where the light moves or is placed (where it
    /// keeps its proportions: directions, and the weight's ratio of the
    /// light's intensity to the squared distance, are the same in both).
    fn sample_thesis(&self, r: Reference, point: Vec3, d: Distribution) -> Option<LightSample> {
        let sim = self.surface.similarity(r.time);
        let p = sim.map_or(r.p, |s| s.point_to_local(r.p));
        let c = self.center();
        let axis = (c - p).normalize_or_zero();
        let target = end_point(c, axis, point, self.size(), d);
        let to = target - p;
        let r2 = to.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        let weight = self.point_intensity(-to / r2.sqrt()) / r2;
        let target = sim.map_or(target, |s| s.point_to_world(target));
        Some(LightSample {
            target,
            dir: (target - r.p).normalize_or_zero(),
            weight,
            pdf: 0.0,
        })
    }

    /// Intensity toward direction `w` (unit, from the light, in its own
    /// space) of the light collapsed to a point, as the thesis shades
    /// every shadow ray.
    fn point_intensity(&self, w: Vec3) -> Rgb {
        // `L · A⊥`: the area the shape shows toward `w` (a flipped shape
        // shows its other side).
        let w = if self.surface.is_flipped() { -w } else { w };
        // The thesis model takes a constant radiance (a texture is refused
        // when the scene is read): its mean is it.
        let radiance = self.mean_radiance();
        match self.surface.shape().projected_area(w) {
            Some(area) => radiance * area,
            // Not reached: the thesis model is refused on shapes without
            // one when the scene is built; a flat light of the shape's
            // area facing `w`.
            None => radiance * self.area(),
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
    fn eval(&self, n: Vec3, uv: Vec2, dir: Vec3) -> Rgb {
        self.emitted(n, uv, dir)
    }

    #[inline(always)]
    fn sample(
        &self,
        at: impl Fn(usize) -> Reference,
        points: &[Vec3],
        d: Distribution,
        out: &mut Vec<Option<LightSample>>,
    ) {
        Area::sample(self, at, points, d, out);
    }

    #[inline]
    fn sample_one(&self, r: Reference, point: Vec3, d: Distribution) -> Option<LightSample> {
        Area::sample_one(self, r, point, d)
    }

    fn pdf(&self, r: Reference, target: Vec3, n: Vec3) -> f32 {
        Area::pdf(self, r, target, n)
    }

    fn sample_position(&self, u: Vec2, time: f32) -> Option<SurfacePoint> {
        Area::sample_position(self, u, time)
    }

    /// A ray from a point uniform over the surface in a cosine-weighted
    /// direction about its normal: `L · π · A`, `L` at the point.
    fn sample_ray(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        time: f32,
        _: (Vec3, f32),
    ) -> Option<EmittedRay> {
        let s = Area::sample_position(self, u_pos, time)?;
        let dir = Frame::from_normal(s.n).to_world(square_to_cosine_hemisphere(u_dir));
        Some(EmittedRay {
            origin: s.p,
            dir,
            weight: self.radiance.eval_uv(s.uv) * (std::f32::consts::PI * s.inv_pdf),
            normal: Some(s.n),
        })
    }
}

#[cfg(test)]
mod tests;
