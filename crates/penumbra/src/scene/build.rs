//! The one builder: a scene's tree of plugins (see [`description`]) becomes
//! an immutable [`Scene`]. Every value is read through the plugin's typed
//! readers, checked for range, defaulted, and every property read
//! ([`Props::finish`](crate::description::Props::finish)); problems name
//! the value's place in the input.
//!
//! [`description`]: crate::description

use std::collections::HashMap;
use std::sync::Arc;

use super::context::BuildContext;
use super::points::read_points;
use super::ray_sets::{custom_sets, each_set, lobe_sets, Budgets};
use super::reuse::{self, WorldCache};
use super::schemas;
use super::settings::{self, Sets, Settings};
use super::shapes::{self, MeshAttributes, MeshFiles};
use super::transform;
use super::{camera, Scene};
use crate::accel::world::{mesh_bvh, Object, World};
use crate::bsdf::thesis::Thesis;
use crate::bsdf::{self, Bsdf, BsdfModel, MAX_LOBES};
use crate::description::check::{nonneg3, required};
use crate::description::Value;
use crate::description::{Invalid, Kind, Node, Origin, Props};
use crate::emitter::{self, area, Area, Emitter, PenumbraModel};
use crate::geometry::instance::Placement;
use crate::geometry::{Mesh, Place, Surface, SurfaceError};
use crate::math::{Mat4, Rgb, Vec3};
use crate::medium::{Medium, Phase};
use crate::sampling::{EffectSpec, PointTable};
use crate::texture::mesh_attribute::Bound;
use crate::texture::{AttributeUse, Texture, Textures};
use crate::volume::Volumes;

pub use super::error::BuildError;
pub use super::settings::MAX_PIXELS;
pub use super::shapes::{INSTANCED_TRIANGLES, INSTANCING_FACTOR};

/// An empty node of `kind`, for a tree made in code without one.
fn empty(kind: Kind, plugin: &str) -> Node {
    Node::new(kind, plugin, Origin::unlocated(Default::default()))
}

/// Builds the scene of the tree `root` (checked against the schemas),
/// taking the world (meshes and BVH) from `worlds` when one was built there
/// from the same geometry, and keeping a new one there.
pub fn build(
    root: &Node,
    ctx: &BuildContext,
    mut worlds: Option<&mut WorldCache>,
) -> Result<Scene, BuildError> {
    let start = std::time::Instant::now();
    schemas::check(root)?;
    let sensor = root.child(Kind::Sensor).cloned();
    let sensor = sensor.unwrap_or_else(|| empty(Kind::Sensor, "perspective"));
    let film = sensor.child(Kind::Film).cloned();
    let film = film.unwrap_or_else(|| empty(Kind::Film, "hdrfilm"));
    let sampler = sensor.child(Kind::Sampler).cloned();
    let sampler = sampler.unwrap_or_else(|| empty(Kind::Sampler, "sets"));
    let integrator = root.child(Kind::Integrator).cloned();
    let integrator = integrator.unwrap_or_else(|| empty(Kind::Integrator, "whitted"));

    let (fp, sp) = (Props::new(&film), Props::new(&sampler));
    let mut settings = settings::read(&fp, &sp)?;
    let sets = Sets {
        shadow: settings.shadow,
        reflection: settings.reflection,
        refraction: settings.refraction,
    };
    // Read when the scene is loaded, so that a broken volume file is
    // reported whether a medium reads it or not.
    let volumes = Volumes::of_scene(root, &ctx.base_dir)?;
    let (media, media_names) = media(root, &volumes)?;
    let cp = Props::new(&sensor);
    let camera = camera::build(&cp, &settings)?;
    let camera_medium = medium_index(&cp, "medium", &media_names)?;
    cp.finish("camera")?;
    fp.finish("film")?;

    let textures = Textures::of_scene(root, &ctx.base_dir)?;
    let (bsdfs, emission, names, lobes) = materials(root, &sets, &textures)?;
    // A world whose meshes' attributes are read is built anew (its
    // attributes are bound to its objects).
    let attribute_uses = textures.attribute_uses();
    let key = worlds
        .as_ref()
        .filter(|_| attribute_uses.is_empty())
        .and_then(|_| reuse::key(root, ctx));
    // A world built under the same key came from these very objects, which
    // were valid then and are now: they need neither checking nor loading.
    let reused = key
        .as_deref()
        .zip(worlds.as_deref_mut())
        .and_then(|(k, w)| w.get(k));
    // The files the objects read, kept with the world for a build that
    // reuses it (and recorded for this build's recording too).
    let (mut objects, meshes, attributes, reads) = match reused {
        Some(_) => (Vec::new(), Vec::new(), HashMap::new(), Vec::new()),
        // Hashing the files costs a millisecond a megabyte: only a
        // recording or a cache needs it.
        None if worlds.is_none() && !crate::input::is_recording() => {
            let (objects, meshes, attributes) = objects(root, ctx, &names)?;
            (objects, meshes, attributes, Vec::new())
        }
        None => {
            let (built, reads) = crate::input::recording_reads(|| objects(root, ctx, &names));
            crate::input::note_reads(&reads);
            let (objects, meshes, attributes) = built?;
            (objects, meshes, attributes, reads)
        }
    };
    let meshes: Arc<[Mesh]> = meshes.into();
    // The emitters in the tree's order: a light of its own where the tree
    // names it, an emitting shape's where the shape is, then those of the
    // instances' shapes; those at infinity come last.
    let carried = shape_emitters(root, &names, &emission, &sets, &textures)?;
    let object_media = object_media(root, &media_names)?;
    // A reused world's objects are copied to give the emitting ones their
    // emitters again (in the order they were given them when it was built).
    let mut copied;
    let (emitting, meshes_of): (&mut Vec<Object>, &Arc<[Mesh]>) = match &reused {
        Some(world) => {
            copied = copies(world);
            (&mut copied, &world.meshes)
        }
        None => (&mut objects, &meshes),
    };
    let mut emitters = Vec::new();
    // The shadow set each emitter's description asks for, by emitter.
    let mut shadow = Vec::new();
    let mut far = Vec::new();
    let mut emit = |i: usize, emitters: &mut Vec<Emitter>, shadow: &mut Vec<_>| {
        if let Some(c) = &carried[i] {
            let o = &mut emitting[i];
            emitters.push(Emitter::Area(emitter(o, meshes_of, c)?));
            shadow.push(Some(c.shadow));
            o.emitter = Some(emitters.len() as u32 - 1);
        }
        Ok::<_, Invalid>(())
    };
    // The plain shapes come first among the objects, in the tree's order.
    let mut next = 0;
    for node in &root.children {
        match node.kind {
            Kind::Emitter => {
                let p = Props::new(node);
                let Some(emitter) = emitter::build(&node.plugin, &p, &textures) else {
                    let what = format!("`{}` is not a light a scene names by itself", node.plugin);
                    return Err(p.node_error(what).into());
                };
                let emitter = emitter?;
                p.finish(schemas::schema(node)?.what)?;
                if emitter.is_infinite() {
                    far.push(emitter);
                } else {
                    emitters.push(emitter);
                    shadow.push(None);
                }
            }
            Kind::Shape if !matches!(node.plugin.as_str(), "shapegroup" | "instance") => {
                emit(next, &mut emitters, &mut shadow)?;
                next += 1;
            }
            _ => {}
        }
    }
    for i in next..carried.len() {
        emit(i, &mut emitters, &mut shadow)?;
    }
    emitters.extend(far);
    shadow.resize(emitters.len(), None);
    let budgets = Budgets { shadow, lobes };
    debug_assert_eq!(budgets.lobes.len(), bsdfs.len());
    let sets_drawn = custom_sets(&settings, &bsdfs, &budgets);
    if let Some(&(what, _)) = sets_drawn.first() {
        settings.points = points(&sampler, ctx, what)?;
    }
    // Read only when some set draws from `custom`.
    sp.get("points");
    sp.finish("sampler")?;
    let warnings = square_warnings(&settings, &bsdfs, &budgets);
    // NaN: read at each point a shadow ray crosses (a textured opacity).
    let transparency = bsdfs
        .iter()
        .map(|b| b.uniform_shadow_transmittance().unwrap_or(f32::NAN))
        .collect();
    let world = reused.unwrap_or_else(|| {
        let world = Arc::new(World::new(objects, meshes));
        if let (Some(k), Some(w)) = (key, worlds) {
            w.insert(k, Arc::clone(&world), reads);
        }
        world
    });
    bind_attributes(&attribute_uses, &world, &attributes)?;
    // A directional light's shadow rays leave the world's bounding sphere.
    let b = world.bounds();
    let (center, radius) = (0.5 * (b.min + b.max), 0.5 * (b.max - b.min).length());
    if center.is_finite() && radius.is_finite() {
        for e in &mut emitters {
            e.fit(center, radius);
        }
    }
    let far = (0..emitters.len() as u32)
        .filter(|&e| emitters[e as usize].is_infinite())
        .collect();
    Ok(Scene {
        camera,
        bsdfs,
        emitters,
        far,
        budgets,
        world,
        settings,
        integrator,
        transparency,
        media,
        object_media,
        camera_medium,
        warnings,
        build_time: start.elapsed(),
    })
}

/// The objects, the meshes and the attributes of the meshes read from
/// files (by mesh).
type Objects = (Vec<Object>, Vec<Mesh>, HashMap<usize, MeshAttributes>);

/// Binds the mesh attributes the materials read (`uses`) to the world's
/// objects, from the attributes of the meshes read from files; an object
/// whose material reads an attribute its mesh does not have is refused at
/// the texture, naming the file.
fn bind_attributes(
    uses: &[AttributeUse],
    world: &World,
    attributes: &HashMap<usize, MeshAttributes>,
) -> Result<(), Invalid> {
    let file_of = |o: &Object| {
        let m = o.shape.as_mesh()?;
        attributes.get(&(m.mesh as usize)).map(|a| (m.mesh, a))
    };
    for u in uses {
        let t = &u.texture;
        if t.bound.get().is_some() {
            continue;
        }
        let objects = world
            .objects
            .iter()
            .map(|o| {
                let (mesh, (values, file)) = file_of(o)?;
                let a = values.iter().find(|a| a.name == t.name)?;
                Some((mesh, Arc::clone(a), file))
            })
            .collect::<Vec<_>>();
        if let Some((_, _, file)) = objects
            .iter()
            .flatten()
            .find(|(_, a, _)| a.values.iter().any(|v| !v.is_finite()))
        {
            let message = format!(
                "the attribute `{}` of the mesh file {} holds values that are not finite",
                t.name,
                file.display()
            );
            return Err(Invalid::at(&u.origin, message));
        }
        let objects = objects
            .into_iter()
            .map(|o| o.map(|(mesh, a, _)| (mesh, a)))
            .collect();
        // Bound once: a texture of the scene read by several materials is
        // one texture.
        let _ = t.bound.set(Bound {
            meshes: Arc::clone(&world.meshes),
            objects,
        });
    }
    for (i, o) in world.objects.iter().enumerate() {
        for u in uses
            .iter()
            .filter(|u| u.material != 0 && u.material == o.material)
        {
            let has = u
                .texture
                .bound
                .get()
                .is_some_and(|b| b.objects.get(i).is_some_and(Option::is_some));
            if has {
                continue;
            }
            let name = &u.texture.name;
            let message = match file_of(o) {
                Some((_, (values, file))) => {
                    let names: Vec<&str> = values.iter().map(|a| a.name.as_str()).collect();
                    let list = if names.is_empty() {
                        "it has none".to_string()
                    } else {
                        format!("it has: {}", names.join(", "))
                    };
                    format!(
                        "the mesh file {} has no attribute `{name}` ({list})",
                        file.display()
                    )
                }
                None => format!(
                    "an object of this material is not a mesh read from a file: it has no attribute `{name}`"
                ),
            };
            return Err(Invalid::at(&u.origin, message));
        }
    }
    Ok(())
}

/// The materials in the tree's order (index 0 is the default, the
/// `thesis` material's defaults, for objects without one), what each
/// emits, their indices by name, and the sets their lobes ask for (see
/// [`lobe_sets`]).
type Materials = (
    Vec<Bsdf>,
    Vec<(Rgb, Origin)>,
    HashMap<String, u32>,
    Vec<[Option<EffectSpec>; MAX_LOBES]>,
);

fn materials(root: &Node, sets: &Sets, textures: &Textures) -> Result<Materials, Invalid> {
    let none = Origin::unlocated(Default::default());
    let default = empty(Kind::Bsdf, "thesis");
    let nodes: Vec<&Node> = root.children_of(Kind::Bsdf).collect();
    // Materials held by others (by name) are built before them.
    let order = holding_order(&nodes)?;
    let mut named: HashMap<String, Arc<Bsdf>> = HashMap::new();
    // The held materials' lobe slots and sets, by name.
    let mut held = HashMap::new();
    let mut built: Vec<Option<(Bsdf, (Rgb, Origin))>> = vec![None; nodes.len()];
    let mut lobes = vec![[None; MAX_LOBES]; nodes.len() + 1];
    for i in order {
        let node = nodes[i];
        textures.building_material(i as u32 + 1);
        let defaults = bsdf::Defaults {
            reflection: sets.reflection,
            refraction: sets.refraction,
            textures,
            materials: &named,
        };
        let p = Props::new(node);
        let model = match Bsdf::build(&node.plugin, &p, &defaults) {
            Some(model) => model?,
            None => {
                return Err(schemas::schema(node)
                    .err()
                    .unwrap_or_else(|| p.node_error("unknown material type")))
            }
        };
        let emits = if p.has("emission") {
            nonneg3(&p, "emission", [0.0; 3])?
        } else {
            Rgb::ZERO
        };
        let at = p
            .origin("emission")
            .cloned()
            .unwrap_or_else(|| node.origin.clone());
        p.finish(schemas::schema(node)?.what)?;
        lobes[i + 1] = lobe_sets(&model, node, &held);
        if let Some(id) = &node.id {
            named.insert(id.clone(), Arc::new(model.clone()));
            held.insert(id.clone(), (model.lobes().slots(), lobes[i + 1]));
        }
        built[i] = Some((model, (emits, at)));
    }
    textures.building_material(0);
    let defaults = bsdf::Defaults {
        reflection: sets.reflection,
        refraction: sets.refraction,
        textures,
        materials: &named,
    };
    let first = <Thesis as BsdfModel>::build(&Props::new(&default), &defaults)?;
    lobes[0] = first.sets();
    let mut bsdfs = vec![Bsdf::from(first)];
    let mut emission = vec![(Rgb::ZERO, none)];
    let mut names = HashMap::new();
    for (node, b) in nodes.iter().zip(built) {
        let (model, emits) = b.expect("every material built");
        if let Some(id) = &node.id {
            names.insert(id.clone(), bsdfs.len() as u32);
        }
        bsdfs.push(model);
        emission.push(emits);
    }
    Ok((bsdfs, emission, names, lobes))
}

/// The deepest chain of materials holding materials (a material holding
/// none is 1 deep): shading recurses through it.
pub const MAX_HOLDING_DEPTH: usize = 16;

/// The order to build the materials `nodes` in: each after the materials
/// it holds by name ([`bsdf::nested`]). A material holding itself,
/// directly or through others, is an error at the name that closes the
/// loop, and a chain deeper than [`MAX_HOLDING_DEPTH`] at the material
/// that passes it; a name no material has is left to the model to
/// report.
fn holding_order(nodes: &[&Node]) -> Result<Vec<usize>, Invalid> {
    let by_name: HashMap<&str, usize> = nodes
        .iter()
        .enumerate()
        .filter_map(|(i, n)| n.id.as_deref().map(|id| (id, i)))
        .collect();
    let held = |i: usize| -> Vec<(usize, &Origin, &str)> {
        let node = nodes[i];
        let schema = Bsdf::SCHEMAS.iter().find(|s| s.plugin == node.plugin);
        schema
            .into_iter()
            .flat_map(|s| s.params)
            .filter(|param| param.ty == crate::description::Type::Material)
            .filter_map(|param| node.prop(param.name))
            .filter_map(|p| match &p.value.value {
                Value::String(s) => by_name
                    .get(s.as_str())
                    .map(|&j| (j, &p.value.origin, s.as_str())),
                _ => None,
            })
            .collect()
    };
    // 0: not visited, 1: being visited, 2: done.
    let mut state = vec![0u8; nodes.len()];
    let mut depth = vec![0usize; nodes.len()];
    let mut order = Vec::with_capacity(nodes.len());
    for start in 0..nodes.len() {
        if state[start] != 0 {
            continue;
        }
        // A depth-first walk with an explicit stack: (node, next held index).
        let mut stack = vec![(start, 0usize)];
        state[start] = 1;
        while let Some(&mut (i, ref mut next)) = stack.last_mut() {
            let children = held(i);
            if let Some(&(j, at, name)) = children.get(*next) {
                *next += 1;
                match state[j] {
                    0 => {
                        state[j] = 1;
                        stack.push((j, 0));
                    }
                    1 => {
                        return Err(Invalid::at(
                            at,
                            format!(
                                "material `{name}` holds itself (through the materials it holds)"
                            ),
                        ))
                    }
                    _ => {}
                }
            } else {
                depth[i] = 1 + children.iter().map(|c| depth[c.0]).max().unwrap_or(0);
                if depth[i] > MAX_HOLDING_DEPTH {
                    return Err(Invalid::at(
                        &nodes[i].origin,
                        format!("materials hold each other more than {MAX_HOLDING_DEPTH} deep"),
                    ));
                }
                state[i] = 2;
                order.push(i);
                stack.pop();
            }
        }
    }
    Ok(order)
}

/// The objects of the tree's shapes (meshes loaded and baked) and their
/// meshes: the plain shapes' in their order, then those of the instances
/// (see [`instance`](crate::geometry::instance)), each group built once.
fn objects(
    root: &Node,
    ctx: &BuildContext,
    names: &HashMap<String, u32>,
) -> Result<Objects, BuildError> {
    let (mut objects, mut meshes) = (Vec::new(), Vec::new());
    let mut files = MeshFiles::default();
    let mut groups: HashMap<&str, Vec<Object>> = HashMap::new();
    let mut instances = Vec::new();
    for node in root.children_of(Kind::Shape) {
        match node.plugin.as_str() {
            "shapegroup" => {
                let Some(name) = node.id.as_deref() else {
                    return Err(Invalid::at(
                        &node.plugin_origin,
                        "a group is a `[groups.NAME]` table, not an object",
                    )
                    .into());
                };
                let group = group(node, ctx, names, &mut meshes, &mut files)?;
                groups.insert(name, group);
                continue;
            }
            "instance" => {
                instances.push(node);
                continue;
            }
            _ => {}
        }
        let p = Props::new(node);
        let material = material_index(&p, names)?;
        // Read (and checked) by `object_media`.
        p.get("interior");
        p.get("exterior");
        objects.push(shapes::object(
            &node.plugin,
            &p,
            material,
            ctx,
            &mut meshes,
            &mut files,
        )?);
        p.finish(schemas::schema(node)?.what)?;
    }
    for node in instances {
        let p = Props::new(node);
        let name = required(&p, p.string("group")?, "group", "instance")?;
        let Some(shapes) = groups.get(name) else {
            let mut known: Vec<&str> = groups.keys().copied().collect();
            known.sort_unstable();
            let list = if known.is_empty() {
                "none are defined".to_string()
            } else {
                known.join(", ")
            };
            return Err(p
                .error(
                    "group",
                    format!("no group named `{name}`; defined groups: {list}"),
                )
                .into());
        };
        let m = transform::read(&p, "transform")?.unwrap_or(Mat4::IDENTITY);
        let placement = Placement::new(m)
            .ok_or_else(|| p.error("transform", "the transform must be invertible"))?;
        let placement = Arc::new(placement);
        objects.extend(shapes.iter().map(|o| Object {
            placement: Some(Arc::clone(&placement)),
            flip_normals: o.flip_normals,
            casts_shadows: o.casts_shadows,
            mesh_bvh: o.mesh_bvh.clone(),
            ..Object::new(o.shape.clone(), o.material)
        }));
        p.finish("instance")?;
    }
    Ok((objects, meshes, files.attributes))
}

/// The shapes of a group (a `shapegroup` node's children) in the group's
/// own space, each mesh with its tree, built once for all the group's
/// instances. A group holds neither groups nor instances, and
/// nothing in it moves.
fn group(
    node: &Node,
    ctx: &BuildContext,
    names: &HashMap<String, u32>,
    meshes: &mut Vec<Mesh>,
    files: &mut MeshFiles,
) -> Result<Vec<Object>, BuildError> {
    let gp = Props::new(node);
    gp.finish("group")?;
    let mut out = Vec::new();
    for child in node.children_of(Kind::Shape) {
        if matches!(child.plugin.as_str(), "shapegroup" | "instance") {
            return Err(Invalid::at(
                &child.plugin_origin,
                format!(
                    "a group cannot hold a `{}`: groups do not nest, they hold shapes",
                    child.plugin
                ),
            )
            .into());
        }
        let p = Props::new(child);
        let material = material_index(&p, names)?;
        p.get("interior");
        p.get("exterior");
        if p.has("transform_end") {
            return Err(p
                .error(
                    "transform_end",
                    "a shape inside a group cannot move; instances place the group",
                )
                .into());
        }
        let mut o = shapes::object(&child.plugin, &p, material, ctx, meshes, files)?;
        if let Some(mesh) = o.shape.as_mesh() {
            o.mesh_bvh = Some(mesh_bvh(&meshes[mesh.mesh as usize]));
        }
        p.finish(schemas::schema(child)?.what)?;
        out.push(o);
    }
    Ok(out)
}

fn material_index(p: &Props, names: &HashMap<String, u32>) -> Result<u32, Invalid> {
    let Some(name) = p.string("material")? else {
        return Ok(0);
    };
    names.get(name).copied().ok_or_else(|| {
        let mut known: Vec<&str> = names.keys().map(String::as_str).collect();
        known.sort_unstable();
        let list = if known.is_empty() {
            "none are defined".to_string()
        } else {
            known.join(", ")
        };
        p.error(
            "material",
            format!("no material named `{name}`; defined materials: {list}"),
        )
    })
}

/// What a shape's emitter is made of: its radiance, model and shadow
/// set, and where it is described.
#[derive(Clone)]
struct Carried {
    radiance: Texture,
    model: PenumbraModel,
    shadow: EffectSpec,
    at: Origin,
}

/// The emitter each object carries, in the order of the objects: the
/// plain shapes' in their order, then each instance's shapes' (its group's,
/// in their order: each instance of an emitting shape is an emitter of its
/// own). A shape carries its `area` child's emitter, else its material's
/// emission's (the surface model with the render's shadow set), else none.
fn shape_emitters(
    root: &Node,
    names: &HashMap<String, u32>,
    emission: &[(Rgb, Origin)],
    sets: &Sets,
    textures: &Textures,
) -> Result<Vec<Option<Carried>>, Invalid> {
    let shapes = || root.children_of(Kind::Shape);
    let mut out = Vec::new();
    for shape in shapes().filter(|s| !matches!(s.plugin.as_str(), "shapegroup" | "instance")) {
        out.push(carried(shape, names, emission, sets, textures)?);
    }
    let mut groups: HashMap<&str, Vec<Option<Carried>>> = HashMap::new();
    for group in shapes().filter(|s| s.plugin == "shapegroup") {
        let carried = group
            .children_of(Kind::Shape)
            .map(|s| carried(s, names, emission, sets, textures))
            .collect::<Result<_, _>>()?;
        groups.insert(group.id.as_deref().unwrap_or_default(), carried);
    }
    for instance in shapes().filter(|s| s.plugin == "instance") {
        let name = match instance.prop("group").map(|p| &p.value.value) {
            Some(Value::String(name)) => name.as_str(),
            _ => "",
        };
        out.extend(groups.get(name).into_iter().flatten().cloned());
    }
    Ok(out)
}

/// The scene's media in the tree's order, and their indices by name.
fn media(root: &Node, volumes: &Volumes) -> Result<(Vec<Medium>, HashMap<String, u32>), Invalid> {
    let (mut media, mut names) = (Vec::new(), HashMap::new());
    for node in root.children_of(Kind::Medium) {
        let phase = match node.child(Kind::Phase) {
            Some(ph) => {
                let pp = Props::new(ph);
                let phase = Phase::build(&ph.plugin, &pp, volumes).unwrap_or_else(|| {
                    Err(pp.node_error(format!("unknown phase function `{}`", ph.plugin)))
                })?;
                pp.finish("phase function")?;
                phase
            }
            None => Phase::default(),
        };
        let p = Props::new(node);
        let Some(medium) = Medium::build(&node.plugin, &p, phase, volumes) else {
            return Err(schemas::schema(node)
                .err()
                .unwrap_or_else(|| p.node_error("unknown medium type")));
        };
        let medium = medium?;
        p.finish(schemas::schema(node)?.what)?;
        if let Some(id) = &node.id {
            names.insert(id.clone(), media.len() as u32);
        }
        media.push(medium);
    }
    Ok((media, names))
}

/// The index of the medium the string `key` of `p` names, if any; an
/// unknown name is refused at the value, naming the media there are.
fn medium_index(
    p: &Props,
    key: &str,
    names: &HashMap<String, u32>,
) -> Result<Option<u32>, Invalid> {
    let Some(name) = p.string(key)? else {
        return Ok(None);
    };
    match names.get(name) {
        Some(&i) => Ok(Some(i)),
        None => {
            let mut known: Vec<&str> = names.keys().map(String::as_str).collect();
            known.sort_unstable();
            let list = if known.is_empty() {
                "the scene has none".to_string()
            } else {
                format!("defined media: {}", known.join(", "))
            };
            Err(p.error(key, format!("no medium named `{name}`; {list}")))
        }
    }
}

/// The media on either side of each object of the world, `[interior,
/// exterior]` ([`NO_MEDIUM`](crate::scene::NO_MEDIUM) where none), in the
/// order of [`shape_emitters`]: the plain shapes, then the shapes of the
/// instances' groups.
fn object_media(root: &Node, names: &HashMap<String, u32>) -> Result<Vec<[u32; 2]>, Invalid> {
    let of = |shape: &Node| -> Result<[u32; 2], Invalid> {
        let p = Props::new(shape);
        let side =
            |key| Ok::<_, Invalid>(medium_index(&p, key, names)?.unwrap_or(super::NO_MEDIUM));
        Ok([side("interior")?, side("exterior")?])
    };
    let shapes = || root.children_of(Kind::Shape);
    let mut out = Vec::new();
    for shape in shapes().filter(|s| !matches!(s.plugin.as_str(), "shapegroup" | "instance")) {
        out.push(of(shape)?);
    }
    let mut groups: HashMap<&str, Vec<[u32; 2]>> = HashMap::new();
    for group in shapes().filter(|s| s.plugin == "shapegroup") {
        let media = group
            .children_of(Kind::Shape)
            .map(of)
            .collect::<Result<_, _>>()?;
        groups.insert(group.id.as_deref().unwrap_or_default(), media);
    }
    for instance in shapes().filter(|s| s.plugin == "instance") {
        let name = match instance.prop("group").map(|p| &p.value.value) {
            Some(Value::String(name)) => name.as_str(),
            _ => "",
        };
        out.extend(groups.get(name).into_iter().flatten().copied());
    }
    Ok(out)
}

/// The emitter the shape `shape` carries (see [`shape_emitters`]).
fn carried(
    shape: &Node,
    names: &HashMap<String, u32>,
    emission: &[(Rgb, Origin)],
    sets: &Sets,
    textures: &Textures,
) -> Result<Option<Carried>, Invalid> {
    if let Some(child) = shape.child(Kind::Emitter) {
        let p = Props::new(child);
        let (radiance, model, shadow) = area::read(&p, "area emitter", sets.shadow, textures)?;
        p.finish("area emitter")?;
        let at = child.origin.clone();
        return Ok(Some(Carried {
            radiance,
            model,
            shadow,
            at,
        }));
    }
    let material = match shape.prop("material").map(|p| &p.value.value) {
        Some(Value::String(name)) => names.get(name).copied().unwrap_or(0),
        _ => 0,
    };
    let (radiance, at) = &emission[material as usize];
    Ok((*radiance != Rgb::ZERO).then(|| Carried {
        radiance: Texture::Constant(*radiance),
        model: PenumbraModel::Surface,
        shadow: sets.shadow,
        at: at.clone(),
    }))
}

/// The area emitter `c` of the object `o`.
fn emitter(o: &Object, meshes: &Arc<[Mesh]>, c: &Carried) -> Result<Area, Invalid> {
    let what = o.shape.name();
    let thesis = c.model == PenumbraModel::Thesis;
    if o.shape.as_sphere().is_some() && o.flip_normals {
        return Err(Invalid::at(
            &c.at,
            "a sphere light emits outward: an emitting sphere cannot flip its normals",
        ));
    }
    // The thesis collapses a light to a point of its projected area.
    if thesis && o.shape.projected_area(Vec3::Z).is_none() {
        return Err(Invalid::at(
            &c.at,
            "the thesis penumbra model needs a rectangle, sphere or disk, not a mesh or cylinder",
        ));
    }
    let place = match (&o.motion, &o.placement) {
        (Some(m), _) => Place::Moving(Box::new(*m)),
        (None, Some(p)) => Place::Placed(Arc::clone(p)),
        (None, None) => Place::World,
    };
    let surface = Surface::new(o.shape.clone(), Arc::clone(meshes), place, o.flip_normals);
    let surface = surface.map_err(|e| match e {
        SurfaceError::NoArea => Invalid::at(
            &c.at,
            format!("an emitting {what} must have a surface: it has no area"),
        ),
        SurfaceError::Proportions => Invalid::at(
            &c.at,
            format!("an emitting {what} that moves or is placed by an instance {e}"),
        ),
    })?;
    if thesis && !surface.keeps_proportions() {
        return Err(Invalid::at(
            &c.at,
            "the thesis penumbra model needs a light that keeps its proportions: its \
             instance may rotate, translate and scale it uniformly",
        ));
    }
    Ok(Area::new(surface, c.radiance.clone(), c.model))
}

/// The objects of a reused world, to give the emitting ones their
/// emitters again (in the order they were given them when it was built).
fn copies(world: &World) -> Vec<Object> {
    world
        .objects
        .iter()
        .map(|o| Object {
            shape: o.shape.clone(),
            material: o.material,
            emitter: None,
            casts_shadows: o.casts_shadows,
            motion: o.motion,
            placement: o.placement.clone(),
            flip_normals: o.flip_normals,
            mesh_bvh: None,
        })
        .collect()
}

/// The `custom` distribution's points, which `what` draws from: the table
/// given in code, else the `points` file (relative to the scene file).
fn points(sampler: &Node, ctx: &BuildContext, what: &str) -> Result<Arc<PointTable>, Invalid> {
    if let Some(t) = &ctx.points {
        return Ok(Arc::clone(t));
    }
    let p = Props::new(sampler);
    let Some(file) = p.string("points")? else {
        return Err(p.error(
            "points",
            format!(
                "the custom distribution is selected for the {what}, but no points are given: \
                 set `points = \"FILE\"` in [render] (--points FILE on the command line, \
                 points= in Python) to a JSON or .npy file of point sets"
            ),
        ));
    };
    let path = ctx.base_dir.join(file);
    let table = read_points(&path)
        .map_err(|e| p.error("points", format!("cannot read the points: {e}")))?;
    Ok(Arc::new(table))
}

/// One message per effect whose ray count is not a square for a
/// distribution that needs one. The pixel's message stands for its lens
/// positions too (the same count; a pinhole camera draws none), and
/// shutter times are one-dimensional.
fn square_warnings(s: &Settings, bsdfs: &[Bsdf], budgets: &Budgets) -> Vec<String> {
    let mut seen = Vec::new();
    each_set(s, bsdfs, budgets, |what, rays, d| {
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
