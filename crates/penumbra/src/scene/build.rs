//! Validation and build: the plain description becomes an immutable [`Scene`].

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::check::*;
use super::context::resolve_mesh_path;
pub use super::context::BuildContext;
use super::desc::*;
use super::error::{Invalid, KeyPath};
use super::points::read_points;
use super::ray_sets::{custom_sets, each_set};
use super::reuse::{self, WorldCache};
use super::{Metric, Scene, Settings, Stopping};
use crate::accel::world::{mesh_bvh, Object, World};
use crate::bsdf::thesis::{Thesis, ThesisParams};
use crate::bsdf::Bsdf;
use crate::camera::{Camera, CameraSpec};
use crate::emitter::{Area, AreaShape, Constant, Emitter, MeshLight, PenumbraModel, Point};
use crate::geometry::mesh_file::{read_mesh, MeshError};
use crate::geometry::motion::{Motion, Similarity};
use crate::geometry::quad::Quad;
use crate::geometry::Mesh;
use crate::geometry::Shape;
use crate::math::{Frame, Mat4, Quat, Rgb, Vec2, Vec3};
use crate::sampling::{Distribution, EffectSpec, PointTable};

/// Why a description could not be built.
#[derive(Debug)]
pub enum BuildError {
    Invalid(Invalid),
    Mesh { path: KeyPath, error: MeshError },
}

impl From<Invalid> for BuildError {
    fn from(i: Invalid) -> Self {
        BuildError::Invalid(i)
    }
}

const MAX_SIDE: i64 = super::options::MAX_SIDE as i64;
const MAX_RAYS: i64 = super::options::MAX_RAYS as i64;
const MAX_REPLICAS: i64 = super::options::MAX_REPLICAS as i64;

/// Most pixels an image may have (16384 × 16384): the frame is held in
/// memory as 32-bit floats, 12 bytes a pixel, 3 GiB at this size.
pub const MAX_PIXELS: u64 = 1 << 28;

/// Triangles a scene may always hold, counting a mesh once for every
/// object that uses it (each is a copy in world space, or a BVH of its own).
pub const INSTANCED_TRIANGLES: u64 = 1 << 22;

/// How many times the triangles of its mesh files a scene may hold, when
/// that is more than [`INSTANCED_TRIANGLES`]: objects sharing a mesh
/// multiply it, and a few hundred bytes of scene naming one small mesh
/// thousands of times would otherwise fill memory (as entities do in the
/// "billion laughs" of XML, whose parsers bound the same ratio).
pub const INSTANCING_FACTOR: u64 = 16;

/// Validates `desc` and builds the scene, taking the world (meshes and BVH)
/// from `worlds` when one was built there from the same geometry, and
/// keeping a new one there.
pub fn build(
    desc: &SceneDesc,
    ctx: &BuildContext,
    mut worlds: Option<&mut WorldCache>,
) -> Result<Scene, BuildError> {
    let start = std::time::Instant::now();
    let defaults = Defaults::of(&desc.render)?;
    let mut settings = settings(&desc.render, &defaults)?;
    let camera = camera(&desc.camera, &settings)?;
    let (mut materials, emission, names) = materials(desc, &defaults)?;
    let key = worlds.as_ref().and_then(|_| reuse::key(desc, ctx));
    // A world built under the same key came from these very objects, which
    // were valid then and are now: they need neither checking nor loading.
    let reused = key
        .as_deref()
        .zip(worlds.as_deref_mut())
        .and_then(|(k, w)| w.get(k));
    let (mut objects, meshes) = match reused {
        Some(_) => (Vec::new(), Vec::new()),
        None => objects(desc, ctx, &names)?,
    };
    let light_material = materials.len() as u32;
    materials.push(black_material(&defaults));
    let mut emission = emission;
    emission.push((Rgb::ZERO, KeyPath::root()));
    let mut emitters = Vec::new();
    let root = KeyPath::root().key("lights");
    for (i, l) in desc.lights.iter().enumerate() {
        let (emitter, shape) = light(&root.index(i), l, &defaults)?;
        if let Some(shape) = shape.filter(|_| reused.is_none()) {
            objects.push(Object {
                shape,
                material: light_material,
                emitter: Some(i as u32),
                casts_shadows: false,
                motion: None,
                mesh_bvh: None,
            });
        }
        emitters.push(emitter);
    }
    match &reused {
        Some(world) => emitting_objects_of(world, &emission, &defaults, &mut emitters)?,
        None => emitting_objects(&mut objects, &meshes, &emission, &defaults, &mut emitters)?,
    }
    if desc.render.background != [0.0; 3] {
        let radiance = nonneg3(
            &KeyPath::root().key("render").key("background"),
            desc.render.background,
        )?;
        emitters.push(Emitter::Constant(Constant { radiance }));
    }
    let bsdfs: Vec<Bsdf> = materials.iter().map(|m| Thesis::new(m).into()).collect();
    let sets = custom_sets(&settings, &bsdfs, &emitters);
    if let Some(&(what, _)) = sets.first() {
        settings.points = points(&desc.render, ctx, what)?;
    }
    let warnings = square_warnings(&settings, &bsdfs, &emitters);
    let transparency = bsdfs.iter().map(Bsdf::shadow_transmittance).collect();
    let world = reused.unwrap_or_else(|| {
        let world = Arc::new(World::new(objects, meshes));
        if let (Some(k), Some(w)) = (key, worlds) {
            w.insert(k, Arc::clone(&world));
        }
        world
    });
    Ok(Scene {
        camera,
        bsdfs,
        emitters,
        world,
        settings,
        transparency,
        warnings,
        build_time: start.elapsed(),
    })
}

/// Gives every object whose material emits an area emitter, appended to
/// `emitters`.
fn emitting_objects(
    objects: &mut [Object],
    meshes: &[Mesh],
    emission: &[(Rgb, KeyPath)],
    d: &Defaults,
    emitters: &mut Vec<Emitter>,
) -> Result<(), Invalid> {
    for (i, o) in objects.iter_mut().enumerate() {
        let (radiance, at) = &emission[o.material as usize];
        if *radiance == Rgb::ZERO || !o.casts_shadows {
            continue;
        }
        if o.motion.is_some() {
            return Err(Invalid::new(
                KeyPath::root().key("objects").index(i).key("transform_end"),
                format!("an emitting object cannot move (its material emits: {at})"),
            ));
        }
        let shape = match &o.shape {
            Shape::Quad(q) => AreaShape::Rect(*q),
            Shape::Sphere { center, radius } => AreaShape::Sphere {
                center: *center,
                radius: *radius,
            },
            Shape::Disk {
                center,
                frame,
                radius,
            } => AreaShape::Disk {
                center: *center,
                frame: *frame,
                radius: *radius,
            },
            Shape::Mesh { mesh } => {
                let m = &meshes[*mesh as usize];
                let tris = (0..m.triangles.len()).map(|t| m.vertices(t)).collect();
                AreaShape::Mesh(MeshLight::new(tris).ok_or_else(|| {
                    Invalid::new(
                        KeyPath::root().key("objects").index(i),
                        format!("an emitting mesh must have a surface (its material emits: {at})"),
                    )
                })?)
            }
        };
        o.emitter = Some(emitters.len() as u32);
        emitters.push(Emitter::Area(Area {
            shape,
            radiance: *radiance,
            model: PenumbraModel::Surface,
            shadow: d.shadow,
        }));
    }
    Ok(())
}

/// The emitters of the emitting objects of a reused world (whose objects
/// were numbered the same way when it was built).
fn emitting_objects_of(
    world: &World,
    emission: &[(Rgb, KeyPath)],
    d: &Defaults,
    emitters: &mut Vec<Emitter>,
) -> Result<(), Invalid> {
    let mut objects: Vec<Object> = world
        .objects
        .iter()
        .map(|o| Object {
            shape: o.shape.clone(),
            material: o.material,
            emitter: None,
            casts_shadows: o.casts_shadows,
            motion: o.motion,
            mesh_bvh: None,
        })
        .collect();
    emitting_objects(&mut objects, &world.meshes, emission, d, emitters)
}

/// The objects of `desc` (meshes loaded and baked) and their meshes.
fn objects(
    desc: &SceneDesc,
    ctx: &BuildContext,
    names: &HashMap<String, u32>,
) -> Result<(Vec<Object>, Vec<Mesh>), BuildError> {
    let (mut objects, mut meshes) = (Vec::new(), Vec::new());
    let mut files = MeshFiles::default();
    let root = KeyPath::root().key("objects");
    for (i, o) in desc.objects.iter().enumerate() {
        let path = root.index(i);
        let material = material_index(&path, o.material.as_deref(), names)?;
        objects.push(object(&path, o, material, ctx, &mut meshes, &mut files)?);
    }
    Ok((objects, meshes))
}

/// The mesh files read so far (each once) and the triangles the objects
/// using them add up to.
#[derive(Default)]
struct MeshFiles {
    /// Meshes by file: a file named by several paths (`m.ply`, `./m.ply`, a
    /// link to it) is read once, and counted once in `read`.
    cache: HashMap<FileKey, usize>,
    /// Triangles in the files read.
    read: u64,
    /// Triangles of the objects, a mesh counted once for each object using it.
    used: u64,
}

/// Which file a path names: on Unix its device and inode, elsewhere its
/// canonical path (the path as given if it cannot be resolved; reading it
/// then fails with the error to report).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum FileKey {
    Inode(u64, u64),
    Path(PathBuf),
}

impl FileKey {
    fn of(path: &Path) -> FileKey {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            // stat only: it follows links and never blocks, whatever the file is.
            if let Ok(m) = std::fs::metadata(path) {
                return FileKey::Inode(m.dev(), m.ino());
            }
        }
        FileKey::Path(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()))
    }
}

impl MeshFiles {
    /// Counts an object's use of a mesh of `triangles`, refusing it past the
    /// instancing bound.
    fn use_mesh(&mut self, p: &KeyPath, triangles: usize) -> Result<(), Invalid> {
        let used = self.used + triangles as u64;
        let limit = INSTANCED_TRIANGLES.max(INSTANCING_FACTOR * self.read);
        if used > limit {
            return Err(Invalid::new(
                p.clone(),
                format!(
                    "the objects so far use meshes of {used} triangles in all (a mesh counted \
                     once for each object using it), more than a scene may: {INSTANCED_TRIANGLES} \
                     or {INSTANCING_FACTOR} times the {} triangles of its mesh files",
                    self.read
                ),
            ));
        }
        self.used = used;
        Ok(())
    }
}

/// Global ray budgets and distributions, overridable per light and material.
struct Defaults {
    shadow: EffectSpec,
    reflection: EffectSpec,
    refraction: EffectSpec,
}

impl Defaults {
    fn of(r: &RenderDesc) -> Result<Defaults, Invalid> {
        let p = KeyPath::root().key("render");
        let spec = |key: &str, rays: i64, d: Option<Distribution>| -> Result<EffectSpec, Invalid> {
            Ok(EffectSpec {
                rays: int(&p.key(key), rays, 1, MAX_RAYS)?,
                distribution: d.unwrap_or(r.distribution),
            })
        };
        Ok(Defaults {
            shadow: spec("shadow_rays", r.shadow_rays, r.shadow_distribution)?,
            reflection: spec(
                "reflection_rays",
                r.reflection_rays,
                r.reflection_distribution,
            )?,
            refraction: spec(
                "refraction_rays",
                r.refraction_rays,
                r.refraction_distribution,
            )?,
        })
    }
}

fn settings(r: &RenderDesc, d: &Defaults) -> Result<Settings, Invalid> {
    let p = KeyPath::root().key("render");
    let width = int(&p.key("width"), r.width, 1, MAX_SIDE)?;
    let height = int(&p.key("height"), r.height, 1, MAX_SIDE)?;
    let pixels = u64::from(width) * u64::from(height);
    if pixels > MAX_PIXELS {
        return Err(Invalid::new(
            p.key("height"),
            format!(
                "a {width} x {height} image has {pixels} pixels, more than the {MAX_PIXELS} \
                 (16384 x 16384) an image may have"
            ),
        ));
    }
    Ok(Settings {
        width,
        height,
        max_depth: int(&p.key("max_depth"), r.max_depth, 0, 64)?,
        seed: u64::from(int(&p.key("seed"), r.seed, 0, i64::from(u32::MAX))?),
        background: nonneg3(&p.key("background"), r.background)?,
        spp: int(&p.key("spp"), r.spp, 1, MAX_RAYS)?,
        passes: int(&p.key("passes"), r.passes, 1, MAX_RAYS)?,
        pixel: r.pixel_distribution.unwrap_or(r.distribution),
        lens: r.lens_distribution.unwrap_or(r.distribution),
        time: r.time_distribution.unwrap_or(r.distribution),
        shadow: d.shadow,
        reflection: d.reflection,
        refraction: d.refraction,
        points: Arc::new(PointTable::NONE),
        filter: r.filter,
        metric: metric(r, &p)?,
        stopping: stopping(r, &p)?,
    })
}

/// Adaptive sampling's settings; `None` when `noise_threshold` is 0.
fn stopping(r: &RenderDesc, p: &KeyPath) -> Result<Option<Stopping>, Invalid> {
    let threshold = range(&p.key("noise_threshold"), r.noise_threshold, 0.0, 1e6)?;
    let s = Stopping {
        rule: r.stop_rule,
        threshold,
        confidence: range(&p.key("confidence"), r.confidence, 0.5, 0.999)?,
        replicas: int(&p.key("replicas"), r.replicas, 2, MAX_REPLICAS)?,
        floor: range(&p.key("noise_floor"), r.noise_floor, 1e-6, 1e6)?,
        min_spp: int(&p.key("min_spp"), r.min_spp, 0, MAX_RAYS)?,
    };
    if threshold > 0.0 && r.metric && r.pixel_metric {
        return Err(Invalid::new(
            p.key("noise_threshold"),
            "adaptive sampling and `pixel_metric` both stop a pixel's camera rays: \
             turn one of them off",
        ));
    }
    Ok((threshold > 0.0).then_some(s))
}

fn metric(r: &RenderDesc, p: &KeyPath) -> Result<Option<Metric>, Invalid> {
    let m = Metric {
        reflections: r.reflection_metric,
        shadows: r.shadow_metric,
        threshold: range(&p.key("metric_threshold"), r.metric_threshold, 0.0, 1e6)?,
        min_rays: int(&p.key("metric_min_rays"), r.metric_min_rays, 1, MAX_RAYS)?,
        shadow_rays: int(
            &p.key("shadow_metric_rays"),
            r.shadow_metric_rays,
            1,
            MAX_RAYS,
        )?,
        pixels: r.pixel_metric,
    };
    let any = m.reflections || m.shadows || m.pixels;
    Ok((r.metric && any).then_some(m))
}

fn camera(c: &CameraDesc, s: &Settings) -> Result<Camera, Invalid> {
    let p = KeyPath::root().key("camera");
    let position = finite3(&p.key("position"), c.position)?;
    let look_at = finite3(&p.key("look_at"), c.look_at)?;
    let up = nonzero3(&p.key("up"), c.up)?;
    let position_end = c
        .position_end
        .map_or(Ok(position), |v| finite3(&p.key("position_end"), v))?;
    let look_at_end = c
        .look_at_end
        .map_or(Ok(look_at), |v| finite3(&p.key("look_at_end"), v))?;
    for (eye, target, key) in [
        (position, look_at, "look_at"),
        (position_end, look_at_end, "look_at_end"),
    ] {
        let view = target - eye;
        if view.length_squared() <= 0.0 {
            return Err(Invalid::new(
                p.key(key),
                "the camera must look at a point other than its position",
            ));
        }
        if view.normalize().cross(up.normalize()).length() < 1e-4 {
            return Err(Invalid::new(
                p.key("up"),
                "`up` must not be parallel to the viewing direction",
            ));
        }
    }
    let fov = range(&p.key("fov"), c.fov, 0.01, 179.0)?;
    let aperture = range(&p.key("aperture"), c.aperture, 0.0, f32::MAX)?;
    let focal_distance = match c.focal_distance {
        Some(f) => positive(&p.key("focal_distance"), f)?,
        None => (look_at - position).length(),
    };
    let [open, close] = c.shutter;
    if !(open.is_finite() && close.is_finite() && 0.0 <= open && open <= close && close <= 1.0) {
        return Err(Invalid::new(
            p.key("shutter"),
            format!(
                "must be [open, close] with 0 <= open <= close <= 1, got {:?}",
                c.shutter
            ),
        ));
    }
    Ok(Camera::new(CameraSpec {
        position: [position, position_end],
        look_at: [look_at, look_at_end],
        up,
        fov: fov.to_radians(),
        aperture,
        focal_distance,
        shutter: [open, close],
        width: s.width,
        height: s.height,
    }))
}

/// The materials and what each emits, in name order (index 0 is the
/// default grey for objects without one).
type Materials = (Vec<ThesisParams>, Vec<(Rgb, KeyPath)>, HashMap<String, u32>);

fn materials(desc: &SceneDesc, defaults: &Defaults) -> Result<Materials, Invalid> {
    let root = KeyPath::root();
    let (first, _) = material(&root, &MaterialDesc::default(), defaults)?;
    let (mut out, mut emission) = (vec![first], vec![(Rgb::ZERO, root)]);
    let mut names = HashMap::new();
    for (name, m) in &desc.materials {
        let path = KeyPath::root().key("materials").key(name);
        names.insert(name.clone(), out.len() as u32);
        let (params, emits) = material(&path, m, defaults)?;
        out.push(params);
        emission.push((emits, path.key("emission")));
    }
    Ok((out, emission, names))
}

fn material(p: &KeyPath, m: &MaterialDesc, d: &Defaults) -> Result<(ThesisParams, Rgb), Invalid> {
    let albedo = nonneg3(&p.key("albedo"), m.albedo)?;
    let specular = range(&p.key("specular"), m.specular, 0.0, 1.0)?;
    if (albedo + Rgb::splat(specular)).max_element() > 1.0 {
        return Err(Invalid::new(
            p.key("albedo"),
            "albedo + specular must not exceed 1 in any channel (the surface would create light)",
        ));
    }
    let reflectivity = range(&p.key("reflectivity"), m.reflectivity, 0.0, 1.0)?;
    let transparency = range(&p.key("transparency"), m.transparency, 0.0, 1.0)?;
    if reflectivity + transparency > 1.0 + 1e-6 {
        return Err(Invalid::new(
            p.key("transparency"),
            "reflectivity + transparency must not exceed 1 (the surface would create light)",
        ));
    }
    let effect = |key: &str,
                  rays: Option<i64>,
                  dist: Option<Distribution>,
                  def: EffectSpec|
     -> Result<EffectSpec, Invalid> {
        Ok(EffectSpec {
            rays: rays.map_or(Ok(def.rays), |r| int(&p.key(key), r, 1, MAX_RAYS))?,
            distribution: dist.unwrap_or(def.distribution),
        })
    };
    let emission = nonneg3(&p.key("emission"), m.emission)?;
    let params = ThesisParams {
        albedo,
        specular,
        shininess: range(&p.key("shininess"), m.shininess, 0.0, 1e6)?,
        reflectivity,
        transparency,
        ior: range(&p.key("ior"), m.ior, 1.0, 10.0)?,
        glossiness: m.glossiness.map_or(Ok((1.0 - reflectivity) * 0.2), |g| {
            range(&p.key("glossiness"), g, 0.0, 1e3)
        })?,
        translucency: m.translucency.map_or(Ok((1.0 - transparency) * 0.2), |g| {
            range(&p.key("translucency"), g, 0.0, 1e3)
        })?,
        reflection: effect(
            "reflection_rays",
            m.reflection_rays,
            m.reflection_distribution,
            d.reflection,
        )?,
        refraction: effect(
            "refraction_rays",
            m.refraction_rays,
            m.refraction_distribution,
            d.refraction,
        )?,
    };
    Ok((params, emission))
}

/// The surface material of light shapes: black, since their emission is the light's.
fn black_material(d: &Defaults) -> ThesisParams {
    ThesisParams {
        albedo: Rgb::ZERO,
        specular: 0.0,
        shininess: 0.0,
        reflectivity: 0.0,
        transparency: 0.0,
        ior: 1.0,
        glossiness: 0.0,
        translucency: 0.0,
        reflection: d.reflection,
        refraction: d.refraction,
    }
}

fn material_index(
    p: &KeyPath,
    name: Option<&str>,
    names: &HashMap<String, u32>,
) -> Result<u32, Invalid> {
    let Some(name) = name else { return Ok(0) };
    names.get(name).copied().ok_or_else(|| {
        let mut known: Vec<&str> = names.keys().map(String::as_str).collect();
        known.sort_unstable();
        let list = if known.is_empty() {
            "none are defined".to_string()
        } else {
            known.join(", ")
        };
        Invalid::new(
            p.key("material"),
            format!("no material named `{name}`; defined materials: {list}"),
        )
    })
}

const OBJECT_TYPES: [&str; 3] = ["sphere", "quad", "mesh"];

fn object(
    p: &KeyPath,
    o: &ObjectDesc,
    material: u32,
    ctx: &BuildContext,
    meshes: &mut Vec<Mesh>,
    files: &mut MeshFiles,
) -> Result<Object, BuildError> {
    let kind = one_of(&p.key("type"), &o.kind, "object type", &OBJECT_TYPES)?;
    let set = [
        ("center", o.center.is_some()),
        ("radius", o.radius.is_some()),
        ("origin", o.origin.is_some()),
        ("edge_u", o.edge_u.is_some()),
        ("edge_v", o.edge_v.is_some()),
        ("path", o.path.is_some()),
        ("smooth", o.smooth.is_some()),
    ];
    let start = transform(&p.key("transform"), o.transform.as_ref())?;
    let end = o
        .transform_end
        .as_ref()
        .map(|t| transform(&p.key("transform_end"), Some(t)))
        .transpose()?;
    let motion = match end {
        Some(end) => Some(Motion {
            start: similarity(&p.key("transform"), &start)?,
            end: similarity(&p.key("transform_end"), &end)?,
        }),
        None => None,
    };
    let shape = match kind {
        "sphere" => {
            only_keys(p, kind, &set, &["center", "radius"])?;
            let center = finite3(&p.key("center"), o.center.unwrap_or([0.0; 3]))?;
            let radius = positive(&p.key("radius"), o.radius.unwrap_or(1.0))?;
            sphere_shape(p, center, radius, &start, motion.is_some())?
        }
        "quad" => {
            only_keys(p, kind, &set, &["origin", "edge_u", "edge_v"])?;
            let q = quad(p, o.origin, o.edge_u, o.edge_v, "quad")?;
            Shape::Quad(if motion.is_some() {
                q
            } else {
                transform_quad(&q, &start)
            })
        }
        _ => {
            only_keys(p, kind, &set, &["path", "smooth"])?;
            let file = required(&p.key("path"), o.path.as_ref(), "path", kind)?;
            let m = load_mesh(
                &p.key("path"),
                file,
                ctx,
                files,
                meshes,
                o.smooth.unwrap_or(false),
            )?;
            files.use_mesh(&p.key("path"), meshes[m].triangles.len())?;
            let mesh = if motion.is_some() {
                m
            } else {
                bake(meshes, m, &start)
            };
            Shape::Mesh { mesh: mesh as u32 }
        }
    };
    let mesh_bvh = match (&shape, motion) {
        (Shape::Mesh { mesh }, Some(_)) => Some(mesh_bvh(&meshes[*mesh as usize])),
        _ => None,
    };
    Ok(Object {
        shape,
        material,
        emitter: None,
        casts_shadows: true,
        motion,
        mesh_bvh,
    })
}

/// A static sphere stays analytic under translation, rotation and uniform
/// scale; anything else would make an ellipsoid, which we do not support.
fn sphere_shape(
    p: &KeyPath,
    center: Vec3,
    radius: f32,
    m: &Mat4,
    moving: bool,
) -> Result<Shape, Invalid> {
    if moving {
        return Ok(Shape::Sphere { center, radius });
    }
    let (scale, _, _) = m.to_scale_rotation_translation();
    let s = scale.abs();
    if (s.max_element() - s.min_element()) > 1e-4 * s.max_element() {
        return Err(Invalid::new(
            p.key("transform"),
            "a sphere can only be scaled uniformly",
        ));
    }
    Ok(Shape::Sphere {
        center: m.transform_point3(center),
        radius: radius * s.x,
    })
}

fn quad(
    p: &KeyPath,
    o: Option<[f32; 3]>,
    u: Option<[f32; 3]>,
    v: Option<[f32; 3]>,
    kind: &str,
) -> Result<Quad, Invalid> {
    let origin = finite3(&p.key("origin"), required(p, o, "origin", kind)?)?;
    let eu = nonzero3(&p.key("edge_u"), required(p, u, "edge_u", kind)?)?;
    let ev = nonzero3(&p.key("edge_v"), required(p, v, "edge_v", kind)?)?;
    if eu.cross(ev).length() <= 1e-6 * eu.length() * ev.length() {
        return Err(Invalid::new(
            p.key("edge_v"),
            "edge_u and edge_v must not be parallel",
        ));
    }
    Ok(Quad::new(origin, eu, ev))
}

fn transform_quad(q: &Quad, m: &Mat4) -> Quad {
    let o = m.transform_point3(q.origin);
    Quad::new(
        o,
        m.transform_point3(q.origin + q.edge_u) - o,
        m.transform_point3(q.origin + q.edge_v) - o,
    )
}

fn load_mesh(
    p: &KeyPath,
    file: &str,
    ctx: &BuildContext,
    files: &mut MeshFiles,
    meshes: &mut Vec<Mesh>,
    smooth: bool,
) -> Result<usize, BuildError> {
    let path = resolve_mesh_path(p, file, ctx)?;
    let key = FileKey::of(&path);
    if let Some(&i) = files.cache.get(&key) {
        if smooth && meshes[i].normals.is_none() {
            meshes[i].compute_vertex_normals();
        }
        return Ok(i);
    }
    let data = read_mesh(&path).map_err(|error| BuildError::Mesh {
        path: p.clone(),
        error,
    })?;
    if data.triangles.is_empty() {
        return Err(Invalid::new(p.clone(), format!("{} has no faces", path.display())).into());
    }
    let mut mesh = Mesh {
        positions: data
            .positions
            .iter()
            .map(|&v| Vec3::from_array(v))
            .collect(),
        normals: data.normals.map(|ns| {
            ns.iter()
                .map(|&n| Vec3::from_array(n).normalize_or_zero())
                .collect()
        }),
        uvs: data
            .uvs
            .map(|ts| ts.iter().map(|&t| Vec2::from_array(t)).collect()),
        triangles: data.triangles,
    };
    if !smooth {
        mesh.normals = None;
    } else if mesh.normals.is_none() {
        mesh.compute_vertex_normals();
    }
    files.read += mesh.triangles.len() as u64;
    meshes.push(mesh);
    files.cache.insert(key, meshes.len() - 1);
    Ok(meshes.len() - 1)
}

/// A static mesh baked into world space (cached meshes are copied first).
fn bake(meshes: &mut Vec<Mesh>, index: usize, m: &Mat4) -> usize {
    let baked = meshes[index].transformed(m);
    meshes.push(baked);
    meshes.len() - 1
}

fn transform(p: &KeyPath, t: Option<&TransformDesc>) -> Result<Mat4, Invalid> {
    let Some(t) = t else {
        return Ok(Mat4::IDENTITY);
    };
    if let Some(rows) = t.matrix {
        if t.scale.is_some()
            || t.rotate_axis.is_some()
            || t.rotate_degrees.is_some()
            || t.translate.is_some()
        {
            return Err(Invalid::new(
                p.key("matrix"),
                "`matrix` excludes scale, rotate_axis, rotate_degrees and translate",
            ));
        }
        return matrix(&p.key("matrix"), rows);
    }
    let scale = match t.scale {
        None => Vec3::ONE,
        Some(Scale::Uniform(s)) => Vec3::splat(s),
        Some(Scale::PerAxis(v)) => finite3(&p.key("scale"), v)?,
    };
    if !scale.is_finite() || scale.abs().min_element() < 1e-12 {
        return Err(Invalid::new(
            p.key("scale"),
            "scale factors must be finite and non-zero",
        ));
    }
    let rotation = match (t.rotate_axis, t.rotate_degrees) {
        (None, None) => Quat::IDENTITY,
        (axis, Some(deg)) => {
            let axis = nonzero3(&p.key("rotate_axis"), axis.unwrap_or([0.0, 1.0, 0.0]))?;
            let deg = range(&p.key("rotate_degrees"), deg, -1e6, 1e6)?;
            Quat::from_axis_angle(axis.normalize(), deg.to_radians())
        }
        (Some(_), None) => {
            return Err(Invalid::new(
                p.key("rotate_axis"),
                "`rotate_axis` needs `rotate_degrees`",
            ))
        }
    };
    let translate = finite3(&p.key("translate"), t.translate.unwrap_or([0.0; 3]))?;
    Ok(Mat4::from_scale_rotation_translation(
        scale, rotation, translate,
    ))
}

fn matrix(p: &KeyPath, rows: [[f32; 4]; 4]) -> Result<Mat4, Invalid> {
    if rows.iter().flatten().any(|x| !x.is_finite()) {
        return Err(Invalid::new(p.clone(), "matrix entries must be finite"));
    }
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(Invalid::new(
            p.clone(),
            "the last row of the matrix must be [0, 0, 0, 1] (affine)",
        ));
    }
    let m = Mat4::from_cols_array_2d(&rows).transpose();
    if m.determinant().abs() < 1e-12 {
        return Err(Invalid::new(p.clone(), "the matrix is singular"));
    }
    Ok(m)
}

/// Decomposes a placement for motion interpolation; shear cannot be interpolated.
fn similarity(p: &KeyPath, m: &Mat4) -> Result<Similarity, Invalid> {
    let (scale, rotation, translation) = m.to_scale_rotation_translation();
    let s = Similarity {
        scale,
        rotation,
        translation,
    };
    if !s.matrix().abs_diff_eq(
        *m,
        1e-4 * m
            .abs()
            .to_cols_array()
            .iter()
            .fold(1.0f32, |a, b| a.max(*b)),
    ) {
        return Err(Invalid::new(
            p.clone(),
            "a moving object's transform must not shear",
        ));
    }
    Ok(s)
}

const LIGHT_TYPES: [&str; 4] = ["point", "rect", "sphere", "disk"];

/// A light: its emitter and, for an area light, the shape that carries it.
fn light(p: &KeyPath, l: &LightDesc, d: &Defaults) -> Result<(Emitter, Option<Shape>), Invalid> {
    let kind = one_of(&p.key("type"), &l.kind, "light type", &LIGHT_TYPES)?;
    let set = [
        ("position", l.position.is_some()),
        ("intensity", l.intensity.is_some()),
        ("radiance", l.radiance.is_some()),
        ("origin", l.origin.is_some()),
        ("edge_u", l.edge_u.is_some()),
        ("edge_v", l.edge_v.is_some()),
        ("center", l.center.is_some()),
        ("radius", l.radius.is_some()),
        ("normal", l.normal.is_some()),
        ("model", l.model.is_some()),
        ("shadow_rays", l.shadow_rays.is_some()),
        ("shadow_distribution", l.shadow_distribution.is_some()),
    ];
    let area_common = ["radiance", "model", "shadow_rays", "shadow_distribution"];
    let with = |own: &[&'static str]| -> Vec<&'static str> {
        own.iter().chain(area_common.iter()).copied().collect()
    };
    let radiance = || {
        nonneg3(
            &p.key("radiance"),
            required(p, l.radiance, "radiance", kind)?,
        )
    };
    let (shape, power): (Option<AreaShape>, Rgb) = match kind {
        "point" => {
            only_keys(p, kind, &set, &["position", "intensity"])?;
            let position = finite3(
                &p.key("position"),
                required(p, l.position, "position", kind)?,
            )?;
            let intensity = nonneg3(
                &p.key("intensity"),
                required(p, l.intensity, "intensity", kind)?,
            )?;
            return Ok((
                Emitter::Point(Point {
                    position,
                    intensity,
                }),
                None,
            ));
        }
        "rect" => {
            only_keys(p, kind, &set, &with(&["origin", "edge_u", "edge_v"]))?;
            (
                Some(AreaShape::Rect(quad(
                    p,
                    l.origin,
                    l.edge_u,
                    l.edge_v,
                    "rect light",
                )?)),
                radiance()?,
            )
        }
        "sphere" => {
            only_keys(p, kind, &set, &with(&["center", "radius"]))?;
            let center = finite3(&p.key("center"), required(p, l.center, "center", kind)?)?;
            let radius = positive(&p.key("radius"), required(p, l.radius, "radius", kind)?)?;
            (Some(AreaShape::Sphere { center, radius }), radiance()?)
        }
        _ => {
            only_keys(p, kind, &set, &with(&["center", "normal", "radius"]))?;
            let center = finite3(&p.key("center"), required(p, l.center, "center", kind)?)?;
            let normal = nonzero3(&p.key("normal"), required(p, l.normal, "normal", kind)?)?;
            let radius = positive(&p.key("radius"), required(p, l.radius, "radius", kind)?)?;
            let frame = Frame::from_normal(normal.normalize());
            (
                Some(AreaShape::Disk {
                    center,
                    frame,
                    radius,
                }),
                radiance()?,
            )
        }
    };
    let model = match l.model.as_deref() {
        None => PenumbraModel::Surface,
        Some(m) => match one_of(&p.key("model"), m, "penumbra model", &["surface", "thesis"])? {
            "thesis" => PenumbraModel::Thesis,
            _ => PenumbraModel::Surface,
        },
    };
    let shadow = EffectSpec {
        rays: l.shadow_rays.map_or(Ok(d.shadow.rays), |r| {
            int(&p.key("shadow_rays"), r, 1, MAX_RAYS)
        })?,
        distribution: l.shadow_distribution.unwrap_or(d.shadow.distribution),
    };
    let shape = shape.expect("an area light has a shape");
    let surface = match &shape {
        AreaShape::Rect(q) => Shape::Quad(*q),
        AreaShape::Sphere { center, radius } => Shape::Sphere {
            center: *center,
            radius: *radius,
        },
        AreaShape::Disk {
            center,
            frame,
            radius,
        } => Shape::Disk {
            center: *center,
            frame: *frame,
            radius: *radius,
        },
        AreaShape::Mesh(_) => unreachable!("lights are not meshes"),
    };
    let emitter = Emitter::Area(Area {
        shape,
        radiance: power,
        model,
        shadow,
    });
    Ok((emitter, Some(surface)))
}

/// The `custom` distribution's points, which `what` draws from: the table
/// given in code, else the `points` file (relative to the scene file).
fn points(r: &RenderDesc, ctx: &BuildContext, what: &str) -> Result<Arc<PointTable>, Invalid> {
    let key = KeyPath::root().key("render").key("points");
    if let Some(t) = &r.points_table {
        return Ok(Arc::clone(t));
    }
    let Some(file) = &r.points else {
        return Err(Invalid::new(
            key,
            format!(
                "the custom distribution is selected for the {what}, but no points are given: \
                 set `points = \"FILE\"` in [render] (--points FILE on the command line, \
                 points= in Python) to a JSON or .npy file of point sets"
            ),
        ));
    };
    let path = ctx.base_dir.join(file);
    let table = read_points(&path)
        .map_err(|e| Invalid::new(key, format!("cannot read the points: {e}")))?;
    Ok(Arc::new(table))
}

/// One message per effect whose ray count is not a square for a
/// distribution that needs one. The pixel's message stands for its lens
/// positions too (the same count; a pinhole camera draws none), and
/// shutter times are one-dimensional.
fn square_warnings(s: &Settings, bsdfs: &[Bsdf], emitters: &[Emitter]) -> Vec<String> {
    let mut seen = Vec::new();
    each_set(s, bsdfs, emitters, |what, rays, d| {
        let message = d.non_square_warning(rays as usize);
        let camera = matches!(what, "lens positions" | "shutter times");
        if let (Some(msg), false) = (message, camera) {
            let line = format!("{what}: {msg}");
            if !seen.contains(&line) {
                seen.push(line);
            }
        }
    });
    seen
}

#[cfg(test)]
mod tests {
    use crate::math::Vec2;
    use crate::scene::{LoadOptions, SceneSource};

    /// Texture coordinates travel from the file to the scene's meshes,
    /// smooth or flat, baked into world space or not.
    #[test]
    fn meshes_keep_the_texture_coordinates_of_their_files() {
        let dir = tempfile::tempdir().unwrap();
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
        std::fs::write(dir.path().join("t.obj"), obj).unwrap();
        let scene = "[[objects]]\ntype = \"mesh\"\npath = \"t.obj\"\n\n\
                     [[objects]]\ntype = \"mesh\"\npath = \"t.obj\"\nsmooth = true\n\
                     transform = { scale = 2.0, translate = [0.0, 1.0, 0.0] }\n";
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, scene).unwrap();
        let source = SceneSource::open(path.to_str().unwrap(), &LoadOptions::default()).unwrap();
        let built = source.build().unwrap();
        let meshes = &built.world.meshes;
        assert!(meshes.len() >= 2, "{} meshes", meshes.len());
        let expected = vec![Vec2::ZERO, Vec2::X, Vec2::Y];
        for mesh in meshes.iter() {
            assert_eq!(mesh.uvs.as_ref(), Some(&expected));
        }
        assert!(meshes.iter().any(|m| m.positions[2].y == 3.0));
    }
}
