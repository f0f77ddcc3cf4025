//! Volumes: values that vary through space, looked up at a world point
//! (Mitsuba 3's volumes): what a heterogeneous participating medium reads
//! its extinction and albedo from. With them, the majorant grid that bounds
//! a volume's values cell by cell ([`majorant`]) and the free-flight
//! sampling and transmittance estimation over it ([`tracking`]).
//!
//! A parameter that takes a volume is written as
//!
//! * a plain value, a number or 3 numbers: a [`constvolume`](constvolume::ConstVolume)
//!   filling the unit cube;
//! * a volume's table, its `type` and parameters:
//!   `sigma_t = { type = "gridvolume", filename = "smoke.vol" }`;
//! * the name of a volume declared once under `[volumes.NAME]`:
//!   `sigma_t = "smoke"`.
//!
//! A volume declared under `[volumes.NAME]` is read when the scene is
//! loaded, used or not, so a broken file is reported at once.
//!
//! | volume | what |
//! |---|---|
//! | [`gridvolume`](gridvolume::GridVolume) | values on a grid read from a `.vol` file, trilinear or nearest, clamped, repeated or mirrored (Mitsuba 3's `gridvolume`) |
//! | [`constvolume`](constvolume::ConstVolume) | one number or 3 numbers everywhere (Mitsuba 3's `constvolume`) |
//!
//! Every volume fills the unit cube of its own coordinates, placed in the
//! world by its `transform` (Mitsuba's `to_world`); its world box
//! ([`Volume::bbox`]) is the box around the placed cube, which bounds the
//! medium that reads its extinction from it (as Mitsuba's heterogeneous
//! medium).

pub mod majorant;
pub mod tracking;
pub mod vol_file;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{
    checked_table, no_such_name, typed_table, Invalid, Kind, Node, Origin, Prop, Props, Schema,
    Value,
};
use crate::math::{Aabb, Mat4, Rgb, Vec3};

pub use majorant::{MajorantGrid, Segment, Segments};

/// What every volume answers: its names and schema, its builder, and its
/// values at world points.
pub trait VolumeModel: Sized {
    /// The name scenes select the volume by.
    const NAME: &'static str;

    /// Its parameters.
    const SCHEMA: Schema;

    /// How Mitsuba's plugin of its name maps onto it.
    const MITSUBA: Mitsuba = Mitsuba::SAME;

    /// The volume of a scene's parameters, its files relative to
    /// `volumes.base_dir`.
    fn build(p: &Props, volumes: &Volumes) -> Result<Self, Invalid>;

    /// The value at the world point `p`, 3 channels (one channel repeated).
    fn eval(&self, p: Vec3) -> Rgb;

    /// One value at `p` (Mitsuba's `eval_1`).
    fn eval_1(&self, p: Vec3) -> f32;

    /// The largest value of any channel anywhere (Mitsuba's `max`; what a
    /// medium's single majorant is made of).
    fn max(&self) -> f32;

    /// The world box around the placed unit cube.
    fn bbox(&self) -> Aabb;

    /// The map from world points to the unit cube's coordinates.
    fn to_local(&self) -> Mat4;

    /// A bound on every channel's value at the points whose unit-cube
    /// coordinates lie in the box `[lo, hi]` (which may reach outside the
    /// cube).
    fn max_in(&self, lo: Vec3, hi: Vec3) -> f32;
}

/// The world box around the unit cube placed by `to_world`.
pub fn world_box(to_world: &Mat4) -> Aabb {
    Aabb::from_points((0..8).map(|c| {
        to_world.transform_point3(Vec3::new(
            (c & 1) as f32,
            ((c >> 1) & 1) as f32,
            ((c >> 2) & 1) as f32,
        ))
    }))
}

/// Declares the volumes' modules, and makes [`Volume`], one of the volumes
/// listed (each `module::Model`, its variant named as the model), and its
/// dispatch.
macro_rules! volumes {
    ($($module:ident::$variant:ident,)*) => {
        $(pub mod $module;)*

        /// A volume: one of the volume models.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Volume {
            $($variant($module::$variant),)*
        }

        impl Volume {
            /// The names of the volumes, as scenes select them.
            pub const NAMES: &'static [&'static str] =
                &[$(<$module::$variant as VolumeModel>::NAME,)*];

            /// The volumes' parameters.
            pub const SCHEMAS: &'static [&'static Schema] =
                &[$(&<$module::$variant as VolumeModel>::SCHEMA,)*];

            /// The volumes as the readers see them.
            pub const PLUGINS: &'static [Plugin] = &[$(Plugin::new(&<$module::$variant as VolumeModel>::SCHEMA, <$module::$variant as VolumeModel>::MITSUBA),)*];

            /// The volume `plugin` of the parameters `p`; `None` for a name
            /// that is not a volume's.
            fn build_model(plugin: &str, p: &Props, volumes: &Volumes) -> Option<Result<Volume, Invalid>> {
                match plugin {
                    $(<$module::$variant as VolumeModel>::NAME => {
                        Some(<$module::$variant>::build(p, volumes).map(Volume::$variant))
                    })*
                    _ => None,
                }
            }

            /// The value at the world point `p`.
            #[inline]
            pub fn eval(&self, p: Vec3) -> Rgb {
                match self {
                    $(Volume::$variant(v) => v.eval(p),)*
                }
            }

            /// One value at the world point `p` (Mitsuba's `eval_1`).
            #[inline]
            pub fn eval_1(&self, p: Vec3) -> f32 {
                match self {
                    $(Volume::$variant(v) => v.eval_1(p),)*
                }
            }

            /// The largest value of any channel anywhere.
            pub fn max(&self) -> f32 {
                match self {
                    $(Volume::$variant(v) => v.max(),)*
                }
            }

            /// The world box around the placed unit cube.
            pub fn bbox(&self) -> Aabb {
                match self {
                    $(Volume::$variant(v) => v.bbox(),)*
                }
            }

            /// The map from world points to the unit cube's coordinates.
            pub fn to_local(&self) -> Mat4 {
                match self {
                    $(Volume::$variant(v) => v.to_local(),)*
                }
            }

            /// A bound on every value at unit-cube coordinates in `[lo, hi]`.
            pub fn max_in(&self, lo: Vec3, hi: Vec3) -> f32 {
                match self {
                    $(Volume::$variant(v) => v.max_in(lo, hi),)*
                }
            }
        }
    };
}

// The volumes: one line each.
volumes! {
    gridvolume::GridVolume,
    constvolume::ConstVolume,
}

impl Volume {
    /// The same value in the unit cube (a plain value where a volume is
    /// expected).
    pub fn constant(value: Rgb) -> Volume {
        Volume::ConstVolume(constvolume::ConstVolume::new(value, Mat4::IDENTITY))
    }

    /// The majorant grid of `scale` times this volume's values over its
    /// world box, `resolution` cells along each axis.
    pub fn majorant_grid(&self, scale: f32, resolution: [u32; 3]) -> MajorantGrid {
        MajorantGrid::new(
            self.bbox(),
            &self.to_local(),
            |lo, hi| self.max_in(lo, hi),
            scale,
            resolution,
        )
    }
}

/// The volumes of a scene by name, and where its files are: what a medium
/// reads its volume parameters with ([`Volumes::volume`]).
#[derive(Clone, Debug, Default)]
pub struct Volumes {
    /// The folder relative file names start from.
    pub base_dir: PathBuf,
    named: HashMap<String, Volume>,
}

impl Volumes {
    /// No named volumes; files relative to `base_dir`.
    pub fn new(base_dir: &Path) -> Volumes {
        Volumes {
            base_dir: base_dir.to_path_buf(),
            named: HashMap::new(),
        }
    }

    /// Builds the scene's named volumes: the children of `root` of kind
    /// volume, each by its id.
    pub fn of_scene(root: &Node, base_dir: &Path) -> Result<Volumes, Invalid> {
        let mut v = Volumes::new(base_dir);
        for node in root.children_of(Kind::Volume) {
            let volume = v.build(&node.plugin, &node.plugin_origin, &node.props, &node.origin)?;
            if let Some(id) = &node.id {
                v.named.insert(id.clone(), volume);
            }
        }
        Ok(v)
    }

    /// The volume named `name`, if the scene declares one.
    pub fn get(&self, name: &str) -> Option<&Volume> {
        self.named.get(name)
    }

    /// Builds the volume `plugin` of the properties `props`, checked
    /// against its schema.
    pub fn build(
        &self,
        plugin: &str,
        plugin_at: &Origin,
        props: &[Prop],
        origin: &Origin,
    ) -> Result<Volume, Invalid> {
        let (node, schema) = checked_table(
            Kind::Volume,
            Volume::SCHEMAS,
            (plugin, plugin_at),
            props,
            origin,
        )?;
        let p = Props::new(&node);
        let volume = Volume::build_model(plugin, &p, self).expect("every schema has a builder")?;
        p.finish(schema.what)?;
        Ok(volume)
    }

    /// A volume parameter `name` of `p`: a number or 3 numbers (finite,
    /// ≥ 0; a [`Volume::constant`]), a volume's table or a volume's name;
    /// the constant `default` when it is not there.
    pub fn volume(&self, p: &Props, name: &str, default: Rgb) -> Result<Volume, Invalid> {
        let Some(prop) = p.get(name) else {
            return Ok(Volume::constant(default));
        };
        let v = &prop.value;
        match &v.value {
            Value::String(id) => self
                .named
                .get(id)
                .cloned()
                .ok_or_else(|| no_such_name(Kind::Volume, id, self.named.keys(), &v.origin)),
            Value::Table(props) => {
                let (plugin, at, rest) = typed_table(props, &v.origin, Kind::Volume)?;
                self.build(plugin, at, &rest, &v.origin)
            }
            Value::Array(_) => {
                let xs = crate::description::props::numbers(v, 3)?;
                let c = Rgb::new(xs[0], xs[1], xs[2]);
                if !c.is_finite() || c.min_element() < 0.0 {
                    return Err(p.error(name, format!("must be finite and ≥ 0, got {xs:?}")));
                }
                Ok(Volume::constant(c))
            }
            _ => {
                let x = crate::description::props::number(v)?;
                if !(x.is_finite() && x >= 0.0) {
                    return Err(p.error(name, format!("must be finite and ≥ 0, got {x}")));
                }
                Ok(Volume::constant(Rgb::splat(x)))
            }
        }
    }
}

#[cfg(test)]
mod tests;
