//! What the first camera hit is, beside the image: Mitsuba 3's `aov`
//! (arbitrary output variables of the first hit, beside the image of the
//! integrator it holds), `depth` (the distance to the first hit as the
//! image) and `moment` (the image of the integrator it holds with the
//! first and second moments of its samples).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `aovs` | string | `""` | `aov`: the variables, `name:type` pairs separated by commas (or spaces), Mitsuba's syntax |
//! | `nested` | table | none | `aov` and `moment`: the integrator held, a table with its `type`, its parameters and an optional `name` (default `_arg_0`, the name Mitsuba gives an unnamed child); without it (and, for `aov`, without `aovs`) the image is black and no channel is written, as in Mitsuba |
//!
//! # Channels
//!
//! The image keeps its RGB; the channels beside it are named and ordered
//! as Mitsuba's `hdrfilm` writes them in an EXR file:
//!
//! * `aov` holding an integrator named `N`: `N.R`, `N.G`, `N.B` (its
//!   image again) and `N.A` (1 where the camera ray meets a surface, or
//!   anywhere when the scene has an emitter at infinity the integrator
//!   does not hide with `hide_emitters`, as Mitsuba's), then each
//!   variable's channels; without one, the variables' channels alone (the
//!   image is black, as Mitsuba's).
//! * a variable `name:type` gives, by type, `name.R`/`.G`/`.B`
//!   (`albedo`), `name.T` (`depth`), `name.X`/`.Y`/`.Z` (`position`,
//!   `geo_normal`, `sh_normal`, `dp_du`, `dp_dv`), `name.U`/`.V` (`uv`,
//!   `duv_dx`, `duv_dy`), `name.I` (`prim_index`, `shape_index`).
//! * `moment` holding `N`: `N.X`, `N.Y`, `N.Z` (the mean of its samples'
//!   CIE XYZ), then `m2_N.X`, `m2_N.Y`, `m2_N.Z` (the mean of their
//!   squares): `m2_N.Y − N.Y²` is the variance of a sample's luminance in
//!   the pixel (with the box filter; with another, of the filter-weighted
//!   samples).
//!
//! Each channel is a pixel's samples' values filtered as the image is
//! (splatted by the same filter in the same fixed point with a splatting
//! film), so integer variables are fractional where a pixel sees several
//! primitives. A camera ray that meets nothing gives 0 in every variable.
//!
//! # Values
//!
//! Those of the first camera hit's
//! [`SurfaceInteraction`](crate::geometry::SurfaceInteraction): `depth`
//! is the distance from where the camera ray starts (its near clip plane,
//! as Mitsuba's rays start there) to the hit; `position` the point;
//! `geo_normal` the shape's geometric normal; `sh_normal` the normal the
//! material shades by (the interpolated shading normal, or the one a
//! `normalmap` or `bumpmap` perturbs it to, as Mitsuba's `sh_frame`); `uv`, `dp_du`,
//! `dp_dv` the shape's parameterisation; `duv_dx`, `duv_dy` the change
//! of `uv` over a pixel's step scaled by `1/√spp`, from the rays through
//! the neighbouring film points meeting the hit's tangent plane
//! (Mitsuba's ray differentials); `prim_index` the primitive (a mesh's
//! triangle, 0 for analytic shapes); `shape_index` the object hit,
//! counted from 1 in the order of the world's objects (0 for a miss);
//! `albedo` the BSDF's diffuse reflectance
//! ([`Bsdf::diffuse_reflectance`](crate::bsdf::Bsdf::diffuse_reflectance)).
//!
//! # Random numbers
//!
//! The variables are taken along the camera rays every integrator
//! traces for the same pixel and sample index (the same film point,
//! lens point and time), so a held integrator's image and the variables
//! see the same rays, and both are the same on any number of threads,
//! tiles or passes.

mod depth;
mod moment;
pub mod plugins;

pub use depth::{Depth, DepthWorker};
pub use moment::Moment;
pub use plugins::{AovPlugin, AovSettings, DepthPlugin, Held, MomentPlugin, MomentSettings};

use std::ops::Range;

use super::clip::first_hits;
use super::film::{Channels, FilmTile};
use super::interface::{BadSample, Integrator, PixelWorker, TileJob};
use super::stats::{RayStats, StageBatches};
use super::stopping::PixelSamples;
use super::whitted::{camera_samples_of, CameraRays};
use crate::accel::{Hit, Hits};
use crate::camera::CameraSample;
use crate::description::tree::{Kind, Node, Value as TreeValue};
use crate::math::{Ray, Rgb, Vec2, Vec3};
use crate::scene::Scene;

/// A kind of variable of Mitsuba's `aov` integrator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovType {
    Albedo,
    Depth,
    Position,
    Uv,
    GeoNormal,
    ShNormal,
    DpDu,
    DpDv,
    DuvDx,
    DuvDy,
    PrimIndex,
    ShapeIndex,
}

impl AovType {
    pub const ALL: [AovType; 12] = [
        AovType::Albedo,
        AovType::Depth,
        AovType::Position,
        AovType::Uv,
        AovType::GeoNormal,
        AovType::ShNormal,
        AovType::DpDu,
        AovType::DpDv,
        AovType::DuvDx,
        AovType::DuvDy,
        AovType::PrimIndex,
        AovType::ShapeIndex,
    ];

    /// The names `aovs` gives the types by, Mitsuba's.
    pub const NAMES: [&'static str; 12] = [
        "albedo",
        "depth",
        "position",
        "uv",
        "geo_normal",
        "sh_normal",
        "dp_du",
        "dp_dv",
        "duv_dx",
        "duv_dy",
        "prim_index",
        "shape_index",
    ];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    pub fn from_name(s: &str) -> Option<AovType> {
        AovType::ALL.into_iter().find(|t| t.name() == s)
    }

    /// The suffixes of its channels, in order (`name.SUFFIX`), Mitsuba's.
    pub fn suffixes(self) -> &'static [&'static str] {
        match self {
            AovType::Albedo => &["R", "G", "B"],
            AovType::Depth => &["T"],
            AovType::Position
            | AovType::GeoNormal
            | AovType::ShNormal
            | AovType::DpDu
            | AovType::DpDv => &["X", "Y", "Z"],
            AovType::Uv | AovType::DuvDx | AovType::DuvDy => &["U", "V"],
            AovType::PrimIndex | AovType::ShapeIndex => &["I"],
        }
    }
}

/// The variables of an `aov` integrator: `(name, type)` in the order
/// `aovs` lists them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AovSpec {
    pub items: Vec<(String, AovType)>,
}

impl AovSpec {
    /// Reads Mitsuba's `aovs` string: `name:type` pairs separated by
    /// commas or spaces. The error says what is wrong with which pair.
    pub fn parse(s: &str) -> Result<AovSpec, String> {
        let mut items = Vec::new();
        for token in s.split([',', ' ']).filter(|t| !t.is_empty()) {
            let (name, ty) = match token.split(':').collect::<Vec<_>>().as_slice() {
                [name, ty] if !name.is_empty() && !ty.is_empty() => (*name, *ty),
                _ => {
                    return Err(format!(
                        "`{token}` is not a `name:type` pair (as in \"dd:depth,nn:sh_normal\")"
                    ))
                }
            };
            let ty = AovType::from_name(ty).ok_or_else(|| {
                format!(
                    "unknown AOV type `{ty}` in `{token}`; valid types are: {}",
                    AovType::NAMES.join(", ")
                )
            })?;
            items.push((name.to_string(), ty));
        }
        Ok(AovSpec { items })
    }

    /// The names of the variables' channels, in order.
    pub fn channel_names(&self) -> Vec<String> {
        self.items
            .iter()
            .flat_map(|(name, ty)| ty.suffixes().iter().map(move |s| format!("{name}.{s}")))
            .collect()
    }

    /// True if a variable needs the rays through the neighbouring film
    /// points (`duv_dx`, `duv_dy`).
    fn differentials(&self) -> bool {
        self.items
            .iter()
            .any(|(_, t)| matches!(t, AovType::DuvDx | AovType::DuvDy))
    }
}

/// The channels of `aov`: the held integrator's (named `held`) image and
/// alpha, then the variables'.
pub fn channel_names(held: Option<&str>, spec: &AovSpec) -> Vec<String> {
    let mut names = Vec::new();
    if let Some(name) = held {
        names.extend(["R", "G", "B", "A"].map(|c| format!("{name}.{c}")));
    }
    names.extend(spec.channel_names());
    names
}

/// Mitsuba's `aov`: the image of the integrator it holds (black without
/// one) with the variables of the first camera hit as channels beside it.
pub struct Aov<'a, I> {
    pub inner: Option<&'a I>,
    pub spec: AovSpec,
    /// Every channel's name: the held integrator's `N.R`, `N.G`, `N.B`,
    /// `N.A` (with one), then the variables'; the film's `A` alone for
    /// [`Aov::alpha`].
    pub names: Vec<String>,
    /// Camera rays per pixel without a held integrator.
    pub spp: u32,
    /// The one channel is the film's alpha `A` ([`Aov::alpha`]).
    pub alpha_only: bool,
}

impl<'a, I: Integrator> Aov<'a, I> {
    /// The variables `spec` of the first hits of `scene`, beside the image
    /// of `inner` (named `name`) if given.
    pub fn new(scene: &Scene, inner: Option<(&'a I, &str)>, spec: AovSpec) -> Self {
        let names = channel_names(inner.map(|(_, name)| name), &spec);
        Aov {
            inner: inner.map(|(i, _)| i),
            spec,
            names,
            spp: scene.settings.spp,
            alpha_only: false,
        }
    }

    /// The image of `inner` with the film's alpha channel `A` beside it
    /// (`alpha`, Mitsuba's `pixel_format` `rgba`): per sample 1 where its
    /// camera ray meets a surface, or anywhere when the scene has an
    /// emitter at infinity the integrator does not hide; filtered as the
    /// image is.
    pub fn alpha(scene: &Scene, inner: &'a I) -> Self {
        Aov {
            inner: Some(inner),
            spec: AovSpec::default(),
            names: vec![ALPHA_CHANNEL.to_string()],
            spp: scene.settings.spp,
            alpha_only: true,
        }
    }
}

/// The name of the film's alpha channel.
pub const ALPHA_CHANNEL: &str = "A";

/// Whether the integrator `node` describes (or the one it holds) hides
/// the emitters a camera ray sees (`hide_emitters`): then a ray that
/// meets nothing has alpha 0 even with an emitter at infinity, as in
/// Mitsuba.
fn hides_emitters(node: &Node) -> bool {
    let hides = |n: &Node| {
        n.prop("hide_emitters")
            .is_some_and(|p| p.value.value == TreeValue::Bool(true))
    };
    hides(node) || node.child(Kind::Integrator).is_some_and(hides)
}

impl<'a, I: Integrator> Integrator for Aov<'a, I> {
    type Worker<'s>
        = AovWorker<'s, I::Worker<'s>>
    where
        Self: 's;
    type TileState = I::TileState;

    fn worker<'s>(&'s self, scene: &'s Scene) -> Self::Worker<'s> {
        AovWorker {
            inner: self.inner.map(|i| i.worker(scene)),
            probe: Probe::new(scene, &self.spec, self.lead()),
            stats: RayStats::default(),
        }
    }

    fn samples(&self) -> u32 {
        self.inner.map_or(self.spp, |i| i.samples())
    }

    fn passes(&self) -> u32 {
        self.inner.map_or(1, |i| i.passes())
    }

    fn whole_tiles(&self) -> bool {
        self.inner.is_some_and(|i| i.whole_tiles())
    }

    fn tile(&self) -> u32 {
        self.inner.map_or(64, |i| i.tile())
    }

    fn state_fits(&self, state: &Self::TileState, size: (u32, u32)) -> bool {
        self.inner.is_none_or(|i| i.state_fits(state, size))
    }

    fn channels(&self) -> Channels {
        Channels {
            names: self.names.clone(),
            moments: false,
            image: self.inner.filter(|_| !self.alpha_only).map(|_| 0),
        }
    }
}

impl<I> Aov<'_, I> {
    /// What the probe writes before the variables.
    fn lead(&self) -> Lead {
        match (self.inner, self.alpha_only) {
            (_, true) => Lead::Alpha,
            (Some(_), false) => Lead::Image,
            (None, false) => Lead::Black,
        }
    }
}

/// What a probe writes before the variables of a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Lead {
    /// Nothing; it adds the black image's samples itself.
    Black,
    /// The held integrator's `N.R` to `N.A`: zeros (filled from its image)
    /// and the alpha.
    Image,
    /// The film's alpha `A` alone.
    Alpha,
}

/// An [`Aov`] worker: the held integrator's, and the probe of the first
/// hits.
pub struct AovWorker<'s, W> {
    inner: Option<W>,
    probe: Probe<'s>,
    stats: RayStats,
}

impl<W: PixelWorker> PixelWorker for AovWorker<'_, W> {
    type State = W::State;

    fn render(
        &mut self,
        tile: TileJob<'_>,
        state: &mut W::State,
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        if let Some(w) = &mut self.inner {
            let job = TileJob {
                xs: tile.xs.clone(),
                ys: tile.ys.clone(),
                samples: tile.samples.clone(),
                cancelled: tile.cancelled,
            };
            if !w.render(job, state, film, bad) {
                return false;
            }
        }
        let probe = &mut self.probe;
        let done = tile.rows(1, |ys| {
            for y in ys {
                probe.row((&tile.xs, y), &tile.samples, film);
            }
        });
        self.stats = self
            .inner
            .as_ref()
            .map_or_else(RayStats::default, |w| *w.stats());
        self.stats += self.probe.stats;
        done
    }

    fn pixel_samples(&self, state: &W::State) -> Vec<PixelSamples> {
        self.inner
            .as_ref()
            .map_or_else(Vec::new, |w| w.pixel_samples(state))
    }

    fn stats(&self) -> &RayStats {
        &self.stats
    }

    fn clear_counts(&mut self) {
        if let Some(w) = &mut self.inner {
            w.clear_counts();
        }
        self.probe.stats = RayStats::default();
        self.stats = RayStats::default();
    }

    fn batches(&self) -> StageBatches {
        self.inner
            .as_ref()
            .map_or_else(StageBatches::default, |w| w.batches())
    }
}

/// The first camera hits of a tile's samples and their variables.
struct Probe<'s> {
    scene: &'s Scene,
    spec: &'s AovSpec,
    lead: Lead,
    /// Rays that meet nothing see an emitter at infinity the integrator
    /// does not hide (the alpha of a miss).
    sees_far: bool,
    cam: CameraRays,
    /// The camera rays' first hits, compact, then as records.
    found: Hits,
    hits: Vec<Option<Hit>>,
    /// The rays through the film points a pixel to the right and below,
    /// scaled toward the sample's by `1/√spp` (`duv_dx`, `duv_dy`).
    dx: Vec<Ray>,
    dy: Vec<Ray>,
    shifted: Vec<CameraSample>,
    values: Vec<f32>,
    stats: RayStats,
}

impl<'s> Probe<'s> {
    fn new(scene: &'s Scene, spec: &'s AovSpec, lead: Lead) -> Self {
        Probe {
            scene,
            spec,
            lead,
            sees_far: !scene.far.is_empty() && !hides_emitters(&scene.integrator),
            cam: CameraRays::default(),
            found: Hits::default(),
            hits: Vec::new(),
            dx: Vec::new(),
            dy: Vec::new(),
            shifted: Vec::new(),
            values: Vec::new(),
            stats: RayStats::default(),
        }
    }

    /// Adds the variables of samples `samples` of the pixels `xs` of row
    /// `y` to `film` (and, without a held integrator, their black image).
    fn row(&mut self, (xs, y): (&Range<u32>, u32), samples: &Range<u32>, film: &mut FilmTile) {
        let m = samples.len();
        if m == 0 {
            return;
        }
        let scene = self.scene;
        self.cam.clear();
        camera_samples_of(
            scene,
            (xs.clone(), y),
            samples.start as usize..samples.end as usize,
            &mut self.cam,
        );
        first_hits(scene, &self.cam.rays, &mut self.found, &mut self.hits);
        self.stats.primary += self.cam.rays.len() as u64;
        if self.spec.differentials() {
            let scale = 1.0 / (scene.settings.spp.max(1) as f32).sqrt();
            for (out, step) in [
                (&mut self.dx, Vec2::new(1.0, 0.0)),
                (&mut self.dy, Vec2::new(0.0, 1.0)),
            ] {
                self.shifted.clear();
                self.shifted
                    .extend(self.cam.samples.iter().map(|s| CameraSample {
                        film: s.film + step,
                        ..*s
                    }));
                out.clear();
                scene.camera.generate(&self.shifted, out);
                for (r, base) in out.iter_mut().zip(&self.cam.rays) {
                    r.origin = base.origin + (r.origin - base.origin) * scale;
                    r.dir = base.dir + (r.dir - base.dir) * scale;
                }
            }
        }
        let mut q = 0;
        for x in xs.clone() {
            let k = film.index(x, y);
            for _ in 0..m {
                let (w, o) = (self.cam.weights[q], self.cam.offsets[q]);
                self.values.clear();
                self.variables(q);
                if self.lead == Lead::Black {
                    film.add(k, Rgb::ZERO, w, o);
                }
                film.add_channels(k, &self.values, w, o);
                q += 1;
            }
        }
    }

    /// The channels of sample `q` into `self.values`.
    fn variables(&mut self, q: usize) {
        let ray = &self.cam.rays[q];
        let hit = self.hits[q].as_ref();
        let out = &mut self.values;
        let alpha = if hit.is_some() || self.sees_far {
            1.0
        } else {
            0.0
        };
        match self.lead {
            Lead::Black => {}
            Lead::Image => out.extend([0.0, 0.0, 0.0, alpha]),
            Lead::Alpha => out.push(alpha),
        }
        let v3 = |out: &mut Vec<f32>, v: Vec3| out.extend([v.x, v.y, v.z]);
        for (_, ty) in &self.spec.items {
            let Some(si) = hit else {
                out.extend(ty.suffixes().iter().map(|_| 0.0));
                continue;
            };
            match ty {
                AovType::Albedo => {
                    let bsdf = &self.scene.bsdfs[si.material as usize];
                    let c = bsdf.diffuse_reflectance(si, -ray.dir);
                    out.extend([c.r, c.g, c.b]);
                }
                AovType::Depth => {
                    let near = self.scene.camera.clip(ray).map_or(0.0, |(near, _)| near);
                    out.push((si.t - near) * ray.dir.length());
                }
                AovType::Position => v3(out, si.p),
                AovType::Uv => out.extend([si.uv.x, si.uv.y]),
                AovType::GeoNormal => v3(out, si.ng),
                AovType::ShNormal => {
                    let bsdf = &self.scene.bsdfs[si.material as usize];
                    v3(out, bsdf.shading_normal(si, -ray.dir.normalize()));
                }
                AovType::DpDu => v3(out, si.dpdu),
                AovType::DpDv => v3(out, si.dpdv),
                AovType::DuvDx | AovType::DuvDy => {
                    let (dx, dy) = uv_partials(si, &self.dx[q], &self.dy[q]);
                    let d = if *ty == AovType::DuvDx { dx } else { dy };
                    out.extend([d.x, d.y]);
                }
                AovType::PrimIndex => out.push(si.prim as f32),
                AovType::ShapeIndex => out.push((si.object + 1) as f32),
            }
        }
    }
}

/// The change of `uv` at the hit `si` toward the rays `rx` and `ry`
/// (through the neighbouring film points), which meet the tangent plane
/// of the shading normal: for each, the least-squares solution of
/// `dp = dp/du · du + dp/dv · dv`, as Mitsuba's `compute_uv_partials`.
/// Zero where the tangents are degenerate.
fn uv_partials(si: &Hit, rx: &Ray, ry: &Ray) -> (Vec2, Vec2) {
    let n = si.n;
    let d = n.dot(si.p);
    let toward = |r: &Ray| {
        let t = (d - n.dot(r.origin)) / n.dot(r.dir);
        r.origin + r.dir * t - si.p
    };
    let (dpdx, dpdy) = (toward(rx), toward(ry));
    let (a00, a01, a11) = (
        si.dpdu.dot(si.dpdu),
        si.dpdu.dot(si.dpdv),
        si.dpdv.dot(si.dpdv),
    );
    let inv = 1.0 / (a00 * a11 - a01 * a01);
    if !inv.is_finite() {
        return (Vec2::ZERO, Vec2::ZERO);
    }
    let solve = |dp: Vec3| {
        let (b0, b1) = (si.dpdu.dot(dp), si.dpdv.dot(dp));
        let v = Vec2::new(a11 * b0 - a01 * b1, a00 * b1 - a01 * b0) * inv;
        if v.is_finite() {
            v
        } else {
            Vec2::ZERO
        }
    };
    (solve(dpdx), solve(dpdy))
}

#[cfg(test)]
mod tests;
