//! The plain-data scene description: exactly what a scene file (or, later, a
//! Python dict) says, with defaults filled in and nothing checked yet.
//!
//! Every table rejects unknown keys. Objects and lights are flat records with a
//! `type` key rather than serde enums, so that serde reports wrong types at the
//! exact key and validation can say which keys a given type accepts.
//! `docs/scene-format.md` is the user reference for every key here.

use std::path::PathBuf;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::arity;
use super::settings::StopRule;
use crate::sampling::{Distribution, Filter, PointTable};

/// A whole scene file.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    #[serde(default)]
    pub render: RenderDesc,
    #[serde(default)]
    pub camera: CameraDesc,
    #[serde(default)]
    pub materials: std::collections::BTreeMap<String, MaterialDesc>,
    #[serde(default)]
    pub objects: Vec<ObjectDesc>,
    #[serde(default)]
    pub lights: Vec<LightDesc>,
}

/// `[render]`: image size, recursion, seed and the global ray budgets.
///
/// Every key is a [render option](super::options::OPTIONS); a test checks
/// the names, defaults and accepted ranges here against that table.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderDesc {
    pub width: i64,
    pub height: i64,
    pub max_depth: i64,
    pub seed: i64,
    #[serde(deserialize_with = "arity::array")]
    pub background: [f32; 3],
    /// Primary rays per pixel (supersampling, depth of field, motion blur).
    pub spp: i64,
    /// Passes the samples are added to the film in.
    pub passes: i64,
    pub shadow_rays: i64,
    pub reflection_rays: i64,
    pub refraction_rays: i64,
    /// Distribution for every effect unless a more specific key overrides it.
    pub distribution: Distribution,
    pub pixel_distribution: Option<Distribution>,
    pub lens_distribution: Option<Distribution>,
    pub time_distribution: Option<Distribution>,
    pub shadow_distribution: Option<Distribution>,
    pub reflection_distribution: Option<Distribution>,
    pub refraction_distribution: Option<Distribution>,
    /// The `custom` distribution's points file, relative to the scene file.
    pub points: Option<PathBuf>,
    /// A `custom` table given in code (Python), which wins over `points`.
    #[serde(skip)]
    pub points_table: Option<Arc<PointTable>>,
    /// The pixel filter.
    pub filter: Filter,
    /// The acceleration metrics of thesis §3.4 (off: the plain algorithm).
    pub metric: bool,
    /// With `metric`: stop reflection and refraction sets by the α/threshold rule.
    pub reflection_metric: bool,
    /// With `metric`: stop shadow sets by the k rule.
    pub shadow_metric: bool,
    /// Relative change of a set's running average below which it stops.
    pub metric_threshold: f32,
    /// α: rays traced before the reflection/refraction metric applies.
    pub metric_min_rays: i64,
    /// k: shadow rays after which an all-lit or all-blocked set stops.
    pub shadow_metric_rays: i64,
    /// With `metric`: apply the α/threshold rule to a pixel's primary rays as well.
    pub pixel_metric: bool,
    /// Adaptive sampling: the noise a pixel may keep (0: off).
    pub noise_threshold: f32,
    /// The adaptive sampling rule.
    pub stop_rule: StopRule,
    /// Confidence of the interval the `calibrated` and `povray` rules bound.
    pub confidence: f32,
    /// Independently scrambled replicas of a pixel's sets (`calibrated`).
    pub replicas: i64,
    /// The value below which the `calibrated` threshold is absolute.
    pub noise_floor: f32,
    /// Camera rays before a pixel may stop (0: the rule's own).
    pub min_spp: i64,
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            width: 800,
            height: 600,
            max_depth: 3,
            seed: 0,
            background: [0.0; 3],
            spp: 1,
            passes: 1,
            shadow_rays: 1,
            reflection_rays: 1,
            refraction_rays: 1,
            distribution: Distribution::Grid,
            pixel_distribution: None,
            lens_distribution: None,
            time_distribution: None,
            shadow_distribution: None,
            reflection_distribution: None,
            refraction_distribution: None,
            points: None,
            points_table: None,
            filter: Filter::Box,
            metric: false,
            reflection_metric: true,
            shadow_metric: true,
            metric_threshold: 0.01,
            metric_min_rays: 4,
            shadow_metric_rays: 4,
            pixel_metric: false,
            noise_threshold: 0.0,
            stop_rule: StopRule::Calibrated,
            confidence: 0.9,
            replicas: 8,
            noise_floor: 1.0,
            min_spp: 0,
        }
    }
}

/// `[camera]`: a pinhole camera, a thin lens when `aperture > 0`, and a shutter.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraDesc {
    #[serde(deserialize_with = "arity::array")]
    pub position: [f32; 3],
    #[serde(deserialize_with = "arity::array")]
    pub look_at: [f32; 3],
    #[serde(deserialize_with = "arity::array")]
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov: f32,
    /// Lens radius in scene units; 0 is a pinhole.
    pub aperture: f32,
    /// Distance to the plane in focus; defaults to the distance to `look_at`.
    pub focal_distance: Option<f32>,
    /// Shutter open and close times; motion is defined over this interval.
    #[serde(deserialize_with = "arity::array")]
    pub shutter: [f32; 2],
    /// Camera position and target at shutter close (camera motion blur).
    #[serde(default, deserialize_with = "arity::option")]
    pub position_end: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub look_at_end: Option<[f32; 3]>,
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            position: [0.0, 1.0, 5.0],
            look_at: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov: 40.0,
            aperture: 0.0,
            focal_distance: None,
            shutter: [0.0, 1.0],
            position_end: None,
            look_at_end: None,
        }
    }
}

/// `[materials.NAME]`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct MaterialDesc {
    /// Diffuse reflectance (Lambertian, BRDF = albedo / π).
    #[serde(deserialize_with = "arity::array")]
    pub albedo: [f32; 3],
    /// Weight of the energy-normalised Phong highlight.
    pub specular: f32,
    /// Phong exponent.
    pub shininess: f32,
    /// Fraction of light mirrored (blurred by `glossiness`).
    pub reflectivity: f32,
    /// Fraction of light transmitted (dielectric with Fresnel, blurred by `translucency`).
    pub transparency: f32,
    pub ior: f32,
    /// Emitted radiance (front side).
    #[serde(deserialize_with = "arity::array")]
    pub emission: [f32; 3],
    /// Radius of the blurry-reflection distribution; default `(1 - reflectivity) * 0.2`.
    pub glossiness: Option<f32>,
    /// Radius of the blurry-refraction distribution; default `(1 - transparency) * 0.2`.
    pub translucency: Option<f32>,
    pub reflection_rays: Option<i64>,
    pub refraction_rays: Option<i64>,
    pub reflection_distribution: Option<Distribution>,
    pub refraction_distribution: Option<Distribution>,
}

impl Default for MaterialDesc {
    fn default() -> Self {
        MaterialDesc {
            albedo: [0.8; 3],
            specular: 0.0,
            shininess: 32.0,
            reflectivity: 0.0,
            transparency: 0.0,
            ior: 1.5,
            emission: [0.0; 3],
            glossiness: None,
            translucency: None,
            reflection_rays: None,
            refraction_rays: None,
            reflection_distribution: None,
            refraction_distribution: None,
        }
    }
}

/// `[[objects]]`: one record for every shape; `type` selects which keys apply.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    #[serde(rename = "type")]
    pub kind: String,
    pub material: Option<String>,
    // sphere
    #[serde(default, deserialize_with = "arity::option")]
    pub center: Option<[f32; 3]>,
    pub radius: Option<f32>,
    // quad
    #[serde(default, deserialize_with = "arity::option")]
    pub origin: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub edge_u: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub edge_v: Option<[f32; 3]>,
    // mesh
    pub path: Option<String>,
    pub smooth: Option<bool>,
    /// Placement at shutter open (and for the whole shutter if `transform_end` is absent).
    pub transform: Option<TransformDesc>,
    /// Placement at shutter close: the object moves during the exposure.
    pub transform_end: Option<TransformDesc>,
}

/// Scale, then rotate about an axis, then translate; or a full 4×4 matrix.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    pub scale: Option<Scale>,
    #[serde(default, deserialize_with = "arity::option")]
    pub rotate_axis: Option<[f32; 3]>,
    pub rotate_degrees: Option<f32>,
    #[serde(default, deserialize_with = "arity::option")]
    pub translate: Option<[f32; 3]>,
    /// Row-major 4×4 matrix acting on column vectors; excludes the other keys.
    #[serde(default, deserialize_with = "arity::matrix")]
    pub matrix: Option<[[f32; 4]; 4]>,
}

/// A uniform (`scale = 2.0`) or per-axis (`scale = [1, 2, 1]`) scale; read
/// by hand so that a per-axis scale must have exactly 3 numbers.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
#[serde(untagged)]
pub enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ScaleVisitor)
    }
}

struct ScaleVisitor;

impl<'de> serde::de::Visitor<'de> for ScaleVisitor {
    type Value = Scale;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a number or an array of 3 numbers")
    }

    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Scale, E> {
        Ok(Scale::Uniform(v as f32))
    }

    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Scale, E> {
        Ok(Scale::Uniform(v as f32))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Scale, E> {
        Ok(Scale::Uniform(v as f32))
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Scale, A::Error> {
        arity::numbers::<A, 3>(seq).map(Scale::PerAxis)
    }
}

/// `[[lights]]`: one record for every light; `type` selects which keys apply.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LightDesc {
    #[serde(rename = "type")]
    pub kind: String,
    // point
    #[serde(default, deserialize_with = "arity::option")]
    pub position: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub intensity: Option<[f32; 3]>,
    // area lights
    #[serde(default, deserialize_with = "arity::option")]
    pub radiance: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub origin: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub edge_u: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub edge_v: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "arity::option")]
    pub center: Option<[f32; 3]>,
    pub radius: Option<f32>,
    #[serde(default, deserialize_with = "arity::option")]
    pub normal: Option<[f32; 3]>,
    /// `thesis` (disk facing the point, §3.3) or `surface` (the real shape).
    pub model: Option<String>,
    pub shadow_rays: Option<i64>,
    pub shadow_distribution: Option<Distribution>,
}
