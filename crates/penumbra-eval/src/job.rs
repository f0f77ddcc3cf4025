//! One render of the evaluation: a built-in scene, the settings changed for
//! this experiment, and the part of the frame to render.
//!
//! Jobs are plain values with a [`key`](Job::key) so that the runner can
//! count them before starting (for the progress bar) and render a setting
//! shared by a table and a figure only once.

use std::path::Path;

use penumbra::description::{from_json, Kind, Node, Props};
use penumbra::scene::{LoadOptions, Overrides, Scene, SceneSource, WorldCache};

use crate::error::EvalError;

/// A change to a built-in scene that [`Overrides`] cannot express.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// The scene as it is.
    AsIs,
    /// Every area light replaced by a point light at its centre with the
    /// same power straight down (thesis Figure 4.9, top left: no penumbra).
    PointLight,
    /// The showcase with a single quad of its `frosted` material standing
    /// in front of the glossy sphere, the gold ball and the glass sphere:
    /// one blurry interface, so a ray's refraction set does not branch
    /// again at a second face (a frosted sphere's sets of N rays at entry
    /// and at exit cost N² rays a pixel).
    FrostedPane,
}

/// A rectangle of the frame in fractions of its width and height, so that
/// the same crop works at every resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crop {
    pub x0: f32,
    pub y0: f32,
    pub x1: f32,
    pub y1: f32,
}

impl Crop {
    pub const fn new(x0: f32, y0: f32, x1: f32, y1: f32) -> Crop {
        Crop { x0, y0, x1, y1 }
    }

    /// The pixel region of this crop in a `width × height` frame, at least
    /// one pixel in each direction.
    pub fn region(&self, width: u32, height: u32) -> penumbra::render::Region {
        let px = |f: f32, n: u32| ((f.clamp(0.0, 1.0) * n as f32).round() as u32).min(n);
        let (x0, y0) = (
            px(self.x0, width).min(width.saturating_sub(1)),
            px(self.y0, height).min(height.saturating_sub(1)),
        );
        penumbra::render::Region {
            x0,
            y0,
            x1: px(self.x1, width).max(x0 + 1),
            y1: px(self.y1, height).max(y0 + 1),
        }
    }
}

/// What to render.
#[derive(Clone, Debug)]
pub struct Job {
    /// Shown in the progress report.
    pub label: String,
    /// A built-in scene name.
    pub scene: &'static str,
    /// Settings for this experiment; always includes width and height.
    pub overrides: Overrides,
    pub variant: Variant,
    /// Render only this part of the frame.
    pub crop: Option<Crop>,
}

impl Job {
    pub fn new(label: impl Into<String>, scene: &'static str, overrides: Overrides) -> Job {
        Job {
            label: label.into(),
            scene,
            overrides,
            variant: Variant::AsIs,
            crop: None,
        }
    }

    pub fn with_crop(mut self, crop: Crop) -> Job {
        self.crop = Some(crop);
        self
    }

    pub fn with_variant(mut self, variant: Variant) -> Job {
        self.variant = variant;
        self
    }

    /// Identifies the rendered pixels: two jobs with the same key give the
    /// same image and counts (the label is not part of it).
    pub fn key(&self) -> String {
        format!(
            "{}|{:?}|{:?}|{:?}",
            self.scene, self.overrides, self.variant, self.crop
        )
    }

    /// Loads the built-in scene, applies the settings and builds it, with
    /// the world from `worlds` if one was built there from the same geometry.
    pub fn build(&self, bunny: &Path, worlds: &mut WorldCache) -> Result<Scene, EvalError> {
        let opts = LoadOptions {
            bunny: Some(bunny.to_path_buf()),
            ..Default::default()
        };
        let err = |source| EvalError::Scene {
            job: self.label.clone(),
            source,
        };
        let mut source = SceneSource::open(self.scene, &opts).map_err(err)?;
        self.overrides.apply(&mut source);
        let children = &mut source.root.children;
        match self.variant {
            Variant::AsIs => {}
            Variant::PointLight => {
                for light in children.iter_mut().filter(|c| c.kind == Kind::Shape) {
                    if let Some(point) = point_light(light) {
                        *light = point;
                    }
                }
            }
            Variant::FrostedPane => children.extend(frosted_pane()),
        }
        source.build_reusing(worlds).map_err(err)
    }
}

/// The one node of kind `kind` of a scene given as JSON (a piece of a
/// scene written in code).
fn node(kind: Kind, scene: serde_json::Value) -> Option<Node> {
    let root = from_json(&scene).ok()?;
    root.children.into_iter().find(|c| c.kind == kind)
}

/// A 2 × 1.6 quad of the showcase's `frosted` material, upright at
/// z = 3.2 between the camera and the right half of the scene.
fn frosted_pane() -> Option<Node> {
    let quad = serde_json::json!({
        "type": "quad",
        "material": "frosted",
        "origin": [-0.2, 0.0, 3.2],
        "edge_u": [2.0, 0.0, 0.0],
        "edge_v": [0.0, 1.6, 0.0],
    });
    node(Kind::Shape, serde_json::json!({ "objects": [quad] }))
}

/// For a rectangle light (a quad carrying an area emitter, as a `rect`
/// light is read), a point light with the power it sends straight down
/// (radiance × area, W/sr), at the rectangle's centre; `None` for other
/// shapes, which are kept.
fn point_light(l: &Node) -> Option<Node> {
    let emitter = l.child(Kind::Emitter).filter(|_| l.plugin == "quad")?;
    let (p, e) = (Props::new(l), Props::new(emitter));
    let [o, u, v] = ["origin", "edge_u", "edge_v"].map(|k| p.numbers::<3>(k).ok().flatten());
    let (o, u, v, radiance) = (o?, u?, v?, e.numbers::<3>("radiance").ok().flatten()?);
    let centre = [0, 1, 2].map(|i| o[i] + 0.5 * (u[i] + v[i]));
    let cross = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let area = cross.iter().map(|c| c * c).sum::<f32>().sqrt();
    let light = serde_json::json!({
        "type": "point",
        "position": centre,
        "intensity": radiance.map(|r| r * area),
    });
    node(Kind::Emitter, serde_json::json!({ "lights": [light] }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crops_scale_with_the_frame_and_never_vanish() {
        let c = Crop::new(0.25, 0.5, 0.75, 1.0);
        let r = c.region(800, 600);
        assert_eq!((r.x0, r.y0, r.x1, r.y1), (200, 300, 600, 600));
        let r = c.region(160, 120);
        assert_eq!((r.x0, r.y0, r.x1, r.y1), (40, 60, 120, 120));
        let tiny = Crop::new(0.5, 0.5, 0.5, 0.5).region(3, 3);
        assert!(tiny.x1 > tiny.x0 && tiny.y1 > tiny.y0 && tiny.x1 <= 3 && tiny.y1 <= 3);
        let edge = Crop::new(1.0, 1.0, 1.0, 1.0).region(10, 10);
        assert_eq!((edge.x0, edge.x1), (9, 10));
    }

    #[test]
    fn keys_ignore_labels_but_not_settings() {
        let o = Overrides {
            spp: Some(4),
            ..Default::default()
        };
        let a = Job::new("a", "bunny", o.clone());
        let b = Job::new("b", "bunny", o);
        assert_eq!(a.key(), b.key());
        let c = b.clone().with_variant(Variant::PointLight);
        assert_ne!(a.key(), c.key());
        assert_ne!(
            a.key(),
            a.clone().with_crop(Crop::new(0.0, 0.0, 0.5, 0.5)).key()
        );
    }

    #[test]
    fn point_light_keeps_the_power_and_position() {
        let rect = serde_json::json!({
            "type": "rect",
            "origin": [-0.5, 4.0, -0.5],
            "edge_u": [1.0, 0.0, 0.0],
            "edge_v": [0.0, 0.0, 2.0],
            "radiance": [40.0, 40.0, 40.0],
        });
        let rect = serde_json::json!({ "lights": [rect] });
        let rect = SceneSource::from_json(&rect, Path::new("."), &LoadOptions::default()).unwrap();
        let rect = rect.root.child(Kind::Shape).unwrap();
        let p = point_light(rect).unwrap();
        assert_eq!(p.plugin, "point");
        let props = Props::new(&p);
        assert_eq!(
            props.numbers::<3>("position").unwrap(),
            Some([0.0, 4.0, 0.5])
        );
        assert_eq!(
            props.numbers::<3>("intensity").unwrap(),
            Some([80.0, 80.0, 80.0])
        );
        assert!(point_light(&p).is_none(), "other lights are kept");
        assert!(frosted_pane().is_some());
    }
}
