//! Lowering: a scene file's parts (`[render]`, `[camera]`,
//! `[textures.NAME]`, `[materials.NAME]`, `[media.NAME]`, `[[objects]]`, `[[lights]]`) into the tree of
//! plugins, the same way for a TOML file and a dict. The tree's shape is
//! described in the [module docs](super).

use std::path::Path;
use std::sync::Arc;

use super::document::{self, Entry};
use super::error::{Invalid, KeyPath, Location, Origin, SceneError};
use super::source::Source;
use super::tree::{Kind, Located, Node, Prop, Value};

/// Every key of `[render]` and the node it goes to. `integrator` names the
/// integrator's plugin and `background` becomes a constant emitter; every
/// other key is a property of its node under its own name. The order is
/// the one the message for an unknown key lists them in.
pub const RENDER_KEYS: &[(&str, Kind)] = &[
    ("width", Kind::Film),
    ("height", Kind::Film),
    ("max_depth", Kind::Integrator),
    ("rr_depth", Kind::Integrator),
    ("hide_emitters", Kind::Integrator),
    ("emitter_samples", Kind::Integrator),
    ("bsdf_samples", Kind::Integrator),
    ("sets_depth", Kind::Integrator),
    ("path_sampler", Kind::Integrator),
    ("light_sampler", Kind::Integrator),
    ("seed", Kind::Sampler),
    ("background", Kind::Emitter),
    ("spp", Kind::Sampler),
    ("shadow_rays", Kind::Sampler),
    ("reflection_rays", Kind::Sampler),
    ("refraction_rays", Kind::Sampler),
    ("distribution", Kind::Sampler),
    ("pixel_distribution", Kind::Sampler),
    ("lens_distribution", Kind::Sampler),
    ("time_distribution", Kind::Sampler),
    ("shadow_distribution", Kind::Sampler),
    ("reflection_distribution", Kind::Sampler),
    ("refraction_distribution", Kind::Sampler),
    ("points", Kind::Sampler),
    ("filter", Kind::Film),
    ("filter_radius", Kind::Film),
    ("filter_stddev", Kind::Film),
    ("filter_b", Kind::Film),
    ("filter_c", Kind::Film),
    ("filter_lobes", Kind::Film),
    ("splat", Kind::Film),
    ("filter_steps", Kind::Film),
    ("sample_border", Kind::Film),
    ("alpha", Kind::Film),
    ("crop_offset_x", Kind::Film),
    ("crop_offset_y", Kind::Film),
    ("crop_width", Kind::Film),
    ("crop_height", Kind::Film),
    ("metric", Kind::Integrator),
    ("reflection_metric", Kind::Integrator),
    ("shadow_metric", Kind::Integrator),
    ("metric_threshold", Kind::Integrator),
    ("metric_min_rays", Kind::Integrator),
    ("shadow_metric_rays", Kind::Integrator),
    ("pixel_metric", Kind::Integrator),
    ("noise_threshold", Kind::Integrator),
    ("stop_rule", Kind::Integrator),
    ("confidence", Kind::Integrator),
    ("replicas", Kind::Integrator),
    ("noise_floor", Kind::Integrator),
    ("min_spp", Kind::Integrator),
    ("integrator", Kind::Integrator),
    ("passes", Kind::Integrator),
    ("samples_per_pass", Kind::Integrator),
    ("aovs", Kind::Integrator),
    ("use_spectral_mis", Kind::Integrator),
    ("nested", Kind::Integrator),
];

/// The keys of a scene's root table.
pub const ROOT_KEYS: &[&str] = &[
    "render",
    "camera",
    "materials",
    "objects",
    "lights",
    "groups",
    "textures",
    "volumes",
    "media",
];

/// The plugins a scene gets when its input names none.
pub const DEFAULT_INTEGRATOR: &str = "whitted";
pub const DEFAULT_SENSOR: &str = "perspective";
pub const DEFAULT_FILM: &str = "hdrfilm";
pub const DEFAULT_SAMPLER: &str = "sets";
pub const DEFAULT_BSDF: &str = "thesis";
/// The keys of `[render]` that are not render options: the `aov`,
/// `moment` and `volpathmis` integrators' own, documented with them.
pub const INTEGRATOR_KEYS: &[&str] = &["aovs", "use_spectral_mis", NESTED_INTEGRATOR];

/// The key of `[render]` whose table is the integrator `aov` or `moment`
/// holds (its `type`, its parameters, and its `name`, the node's id).
pub const NESTED_INTEGRATOR: &str = "nested";
/// The emitter `render.background` becomes; its one property is `radiance`.
pub const BACKGROUND_EMITTER: &str = "constant";
/// The plugin of a `[groups.NAME]` table's node.
pub const GROUP_SHAPE: &str = "shapegroup";
/// The emitter an object's `emitter` table is when it names no `type`.
pub const CARRIED_EMITTER: &str = "area";
/// The phase function of a medium whose `phase` table names no `type`.
pub const DEFAULT_PHASE: &str = "isotropic";

/// Reads a TOML scene: `file` names it in errors. Syntax errors and keys
/// nested too deeply are located as the parser reports them; everything
/// else at the key or value it is about.
pub fn from_toml(text: &str, file: &Path) -> Result<Node, SceneError> {
    let source = Source::new(text, Arc::new(file.to_path_buf()));
    let (at, table) = document::parse_toml(&source)?;
    let entries = document::toml_entries(table, &source);
    lower(Some(at), entries, |value, path| {
        document::toml_located(value, path, &source)
    })
    .map_err(SceneError::from)
}

/// A TOML scene as the JSON of the dict that says the same (`file` names
/// it in syntax errors): what Python's `Scene.to_dict` gives.
pub fn toml_to_json(text: &str, file: &Path) -> Result<serde_json::Value, SceneError> {
    let source = Source::new(text, Arc::new(file.to_path_buf()));
    let (_, table) = document::parse_toml(&source)?;
    Ok(document::toml_json(table, &source))
}

/// Reads a scene given as JSON (a Python dict's): errors name key paths.
pub fn from_json(value: &serde_json::Value) -> Result<Node, SceneError> {
    let serde_json::Value::Object(object) = value else {
        let root = document::json_located(value, KeyPath::root(), 0)?;
        return Err(root.type_error("a table").into());
    };
    lower(None, document::json_entries(object), |value, path| {
        document::json_located(value, path, 1)
    })
    .map_err(SceneError::from)
}

/// The one lowering of a document into the scene's tree: the root table
/// at `at`, its entries in the order of the input, each value read into
/// the tree by `read` at its key path as the lowering reaches it.
fn lower<V>(
    at: Option<Location>,
    entries: Vec<Entry<V>>,
    read: impl Fn(V, KeyPath) -> Result<Located<Value>, Invalid>,
) -> Result<Node, Invalid> {
    let root = Origin::new(KeyPath::root(), at);
    let mut parts: [Option<Located<Value>>; 9] = Default::default();
    for entry in entries {
        let Some(i) = ROOT_KEYS.iter().position(|k| *k == entry.key) else {
            let at = Origin::new(KeyPath::root(), entry.key_at);
            return Err(Invalid::unknown_field(
                &at,
                &entry.key,
                ROOT_KEYS.iter().copied(),
            ));
        };
        parts[i] = Some(read(entry.value, root.path.key(&entry.key))?);
    }
    let [render, camera, materials, objects, lights, groups, textures, volumes, media] = parts;

    let mut scene = Node::new(Kind::Scene, "scene", root.clone());
    let render = route_render(render, &root)?;
    let (sensor_origin, sensor_props) = table_or(camera, &root)?;
    let mut sensor = Node::new(Kind::Sensor, DEFAULT_SENSOR, sensor_origin);
    sensor.props = sensor_props;
    sensor.children = vec![render.film, render.sampler];
    scene.children.push(render.integrator);
    scene.children.push(sensor);
    scene.children.extend(render.background);

    if let Some(textures) = textures {
        // In name order, as materials; each names its plugin by `type`.
        let mut nodes = Vec::new();
        for t in table(textures)?.1 {
            let (origin, props) = table(t.value)?;
            let mut node = plugin_node(Kind::Texture, origin, props, None)?;
            node.id = Some(t.name);
            nodes.push(node);
        }
        nodes.sort_by(|a, b| a.id.cmp(&b.id));
        scene.children.extend(nodes);
    }
    if let Some(volumes) = volumes {
        // `[volumes.NAME]`, in name order; each names its plugin by `type`.
        let mut nodes = Vec::new();
        for v in table(volumes)?.1 {
            let (origin, props) = table(v.value)?;
            let mut node = plugin_node(Kind::Volume, origin, props, None)?;
            node.id = Some(v.name);
            nodes.push(node);
        }
        nodes.sort_by(|a, b| a.id.cmp(&b.id));
        scene.children.extend(nodes);
    }
    if let Some(materials) = materials {
        // In name order, whatever order the input keeps its keys in.
        let mut bsdfs = Vec::new();
        for m in table(materials)?.1 {
            let (origin, props) = table(m.value)?;
            let mut bsdf = plugin_node(Kind::Bsdf, origin, props, Some(DEFAULT_BSDF))?;
            bsdf.id = Some(m.name);
            bsdfs.push(bsdf);
        }
        bsdfs.sort_by(|a, b| a.id.cmp(&b.id));
        scene.children.extend(bsdfs);
    }
    if let Some(media) = media {
        // `[media.NAME]`, in name order; its `phase` table is the phase
        // function it holds.
        let mut nodes = Vec::new();
        for m in table(media)?.1 {
            let (origin, mut props) = table(m.value)?;
            let phase = match props.iter().position(|p| p.name == "phase") {
                Some(i) => {
                    let (at, inner) = table(props.remove(i).value)?;
                    Some(plugin_node(Kind::Phase, at, inner, Some(DEFAULT_PHASE))?)
                }
                None => None,
            };
            let mut node = plugin_node(Kind::Medium, origin, props, None)?;
            node.id = Some(m.name);
            node.children.extend(phase);
            nodes.push(node);
        }
        nodes.sort_by(|a, b| a.id.cmp(&b.id));
        scene.children.extend(nodes);
    }
    if let Some(groups) = groups {
        // `[groups.NAME]` with its `[[groups.NAME.objects]]`: a shape
        // group named NAME holding its shapes, in name order.
        let mut nodes = Vec::new();
        for g in table(groups)?.1 {
            let (origin, props) = table(g.value)?;
            let mut node = Node::new(Kind::Shape, GROUP_SHAPE, origin.clone());
            node.id = Some(g.name);
            for p in props {
                if p.name != "objects" {
                    return Err(Invalid::unknown_field(&p.key, &p.name, ["objects"]));
                }
                for (origin, props) in array_of_tables(Some(p.value))? {
                    node.children
                        .push(plugin_node(Kind::Shape, origin, props, None)?);
                }
            }
            nodes.push(node);
        }
        nodes.sort_by(|a, b| a.id.cmp(&b.id));
        scene.children.extend(nodes);
    }
    for (part, kind) in [(objects, Kind::Shape), (lights, Kind::Emitter)] {
        for (origin, mut props) in array_of_tables(part)? {
            // An object's `emitter` table: the area emitter it carries.
            let carried = match props.iter().position(|p| p.name == "emitter") {
                Some(i) if kind == Kind::Shape => {
                    let (at, inner) = table(props.remove(i).value)?;
                    Some(plugin_node(
                        Kind::Emitter,
                        at,
                        inner,
                        Some(CARRIED_EMITTER),
                    )?)
                }
                _ => None,
            };
            let mut node = plugin_node(kind, origin, props, None)?;
            node.children.extend(carried);
            scene.children.push(node);
        }
    }
    Ok(scene)
}

/// The nodes `[render]`'s keys go to.
struct RenderNodes {
    integrator: Node,
    film: Node,
    sampler: Node,
    background: Option<Node>,
}

/// Routes `[render]`'s keys by [`RENDER_KEYS`]; the nodes take the table's
/// origin (the root's without one).
fn route_render(render: Option<Located<Value>>, root: &Origin) -> Result<RenderNodes, Invalid> {
    let (origin, props) = table_or(render, root)?;
    let mut nodes = RenderNodes {
        integrator: Node::new(Kind::Integrator, DEFAULT_INTEGRATOR, origin.clone()),
        film: Node::new(Kind::Film, DEFAULT_FILM, origin.clone()),
        sampler: Node::new(Kind::Sampler, DEFAULT_SAMPLER, origin.clone()),
        background: None,
    };
    for p in props {
        let Some(&(_, kind)) = RENDER_KEYS.iter().find(|(k, _)| *k == p.name) else {
            let at = Origin::new(origin.path.clone(), p.key.at);
            let names = RENDER_KEYS.iter().map(|(k, _)| *k);
            return Err(Invalid::unknown_field(&at, &p.name, names));
        };
        match (p.name.as_str(), kind) {
            ("integrator", _) => {
                nodes.integrator.plugin_origin = p.value.origin.clone();
                nodes.integrator.plugin = string(p.value)?;
            }
            (NESTED_INTEGRATOR, _) => {
                let (origin, mut props) = table(p.value)?;
                let name = match props.iter().position(|p| p.name == "name") {
                    Some(i) => Some(string(props.remove(i).value)?),
                    None => None,
                };
                let mut held = plugin_node(Kind::Integrator, origin, props, None)?;
                held.id = name;
                nodes.integrator.children.push(held);
            }
            ("background", _) => {
                let mut emitter = Node::new(Kind::Emitter, BACKGROUND_EMITTER, p.key.clone());
                emitter.props.push(Prop::new("radiance", p.key, p.value));
                nodes.background = Some(emitter);
            }
            (_, Kind::Film) => nodes.film.props.push(p),
            (_, Kind::Sampler) => nodes.sampler.props.push(p),
            _ => nodes.integrator.props.push(p),
        }
    }
    Ok(nodes)
}

/// A node whose plugin is its table's `type`: required when there is no
/// default, and not kept as a property.
fn plugin_node(
    kind: Kind,
    origin: Origin,
    mut props: Vec<Prop>,
    default: Option<&str>,
) -> Result<Node, Invalid> {
    let (plugin, at) = match props.iter().position(|p| p.name == "type") {
        Some(i) => {
            let value = props.remove(i).value;
            let at = value.origin.clone();
            (string(value)?, at)
        }
        None => match default {
            Some(d) => (d.to_string(), origin.clone()),
            None => return Err(Invalid::at(&origin, "missing field `type`")),
        },
    };
    let mut node = Node::new(kind, plugin, origin);
    node.plugin_origin = at;
    node.props = props;
    Ok(node)
}

/// The origin and properties of a table value.
fn table(value: Located<Value>) -> Result<(Origin, Vec<Prop>), Invalid> {
    match value.value {
        Value::Table(props) => Ok((value.origin, props)),
        _ => Err(value.type_error("a table")),
    }
}

/// [`table`] of a part that may be missing: then the root's origin and no
/// properties.
fn table_or(value: Option<Located<Value>>, root: &Origin) -> Result<(Origin, Vec<Prop>), Invalid> {
    match value {
        Some(v) => table(v),
        None => Ok((root.clone(), Vec::new())),
    }
}

/// The tables of `[[objects]]` or `[[lights]]` (none if the part is missing).
fn array_of_tables(value: Option<Located<Value>>) -> Result<Vec<(Origin, Vec<Prop>)>, Invalid> {
    match value {
        None => Ok(Vec::new()),
        Some(Located {
            value: Value::Array(items),
            ..
        }) => items.into_iter().map(table).collect(),
        Some(other) => Err(other.type_error("an array of tables")),
    }
}

fn string(value: Located<Value>) -> Result<String, Invalid> {
    match value.value {
        Value::String(s) => Ok(s),
        _ => Err(value.type_error("a string")),
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use super::*;

    fn scene(text: &str) -> Node {
        from_toml(text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    fn err(text: &str) -> String {
        match from_toml(text, Path::new("test.toml")) {
            Ok(_) => panic!("should be refused:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    fn json(text: &str) -> Node {
        from_json(&serde_json::from_str(text).unwrap()).unwrap()
    }

    fn json_err(text: &str) -> String {
        from_json(&serde_json::from_str(text).unwrap())
            .unwrap_err()
            .to_string()
    }

    fn place(origin: &Origin) -> (String, u32, u32) {
        let at = origin.at.as_ref().expect("a place");
        (origin.path.to_string(), at.line, at.column)
    }

    fn sensor(root: &Node) -> &Node {
        root.child(Kind::Sensor).unwrap()
    }

    #[test]
    fn an_empty_scene_has_the_default_plugins() {
        let root = scene("");
        let kinds: Vec<_> = root
            .children
            .iter()
            .map(|c| (c.kind, c.plugin.as_str()))
            .collect();
        assert_eq!(
            kinds,
            [(Kind::Integrator, "whitted"), (Kind::Sensor, "perspective")]
        );
        let s = sensor(&root);
        let kinds: Vec<_> = s
            .children
            .iter()
            .map(|c| (c.kind, c.plugin.as_str()))
            .collect();
        assert_eq!(kinds, [(Kind::Film, "hdrfilm"), (Kind::Sampler, "sets")]);
        assert_eq!(place(&root.origin), (String::new(), 1, 1));
        assert_eq!(place(&s.origin), (String::new(), 1, 1));
        assert_eq!((root.kind, root.plugin.as_str()), (Kind::Scene, "scene"));
    }

    #[test]
    fn unknown_root_keys_are_refused_at_the_key() {
        assert_eq!(
            err("[render]\nwidth = 3\n\n[renders]\nwidth = 3\n"),
            "test.toml:4:2: unknown field `renders`, expected one of `render`, `camera`, \
             `materials`, `objects`, `lights`, `groups`, `textures`, `volumes`, `media`"
        );
        assert_eq!(
            json_err(r#"{"foo": 1}"#),
            "foo: unknown field `foo`, expected one of `render`, `camera`, `materials`, `objects`, `lights`, `groups`, `textures`, `volumes`, `media`"
        );
        // A dict has no lines: the path names the key.
        assert!(
            json_err(r#"{"render": {"zoom": 2}}"#).starts_with("render.zoom: unknown field `zoom`")
        );
    }

    #[test]
    fn unknown_render_keys_list_every_routed_key() {
        let e = err("[render]\nwidth = 10\nheigth = 5\n");
        let names: Vec<String> = RENDER_KEYS.iter().map(|(k, _)| format!("`{k}`")).collect();
        assert_eq!(
            e,
            format!(
                "test.toml:3:1: render: unknown field `heigth`, expected one of {}",
                names.join(", ")
            )
        );
        assert!(e.contains("`min_spp`, `integrator`, `passes`"), "{e}");
    }

    #[test]
    fn render_keys_go_to_their_nodes_with_their_own_places() {
        let root = scene(
            "[camera]\nfov = 30\n\n[render]\nwidth = 64\nspp = 4\nmax_depth = 2\n\
             integrator = \"path\"\npasses = 3\nfilter = \"tent\"\n",
        );
        let integrator = root.child(Kind::Integrator).unwrap();
        assert_eq!(integrator.plugin, "path");
        assert!(integrator.prop("integrator").is_none());
        assert_eq!(
            integrator.prop("passes").unwrap().value.value,
            Value::Int(3)
        );
        assert_eq!(
            integrator.prop("max_depth").unwrap().value.value,
            Value::Int(2)
        );
        let film = sensor(&root).child(Kind::Film).unwrap();
        let width = film.prop("width").unwrap();
        assert_eq!(place(&width.key), ("render.width".into(), 5, 1));
        assert_eq!(place(&width.value.origin), ("render.width".into(), 5, 9));
        assert!(film.prop("filter").is_some());
        let sampler = sensor(&root).child(Kind::Sampler).unwrap();
        assert_eq!(sampler.prop("spp").unwrap().value.value, Value::Int(4));
        // Nodes take their table's place: [render] for the film, sampler
        // and integrator, [camera] for the sensor.
        for node in [integrator, film, sampler] {
            assert_eq!(place(&node.origin), ("render".into(), 4, 1));
        }
        assert_eq!(place(&sensor(&root).origin), ("camera".into(), 1, 1));
        assert_eq!(
            sensor(&root).prop("fov").unwrap().value.value,
            Value::Int(30)
        );
        assert_eq!(
            err("[render]\nintegrator = 3\n"),
            "test.toml:2:14: render.integrator: invalid type: integer `3`, expected a string"
        );
    }

    #[test]
    fn every_render_key_is_routed_by_the_table() {
        for &(key, kind) in RENDER_KEYS {
            let value = match key {
                "integrator" => "\"whitted\"",
                "background" => "[0, 0, 0]",
                NESTED_INTEGRATOR => "{ type = \"path\", name = \"img\" }",
                _ => "1",
            };
            let root = scene(&format!("[render]\n{key} = {value}\n"));
            let holders: Vec<&Node> = std::iter::once(&root)
                .chain(&root.children)
                .chain(&sensor(&root).children)
                .filter(|n| {
                    n.props
                        .iter()
                        .any(|p| p.key.path.to_string() == format!("render.{key}"))
                })
                .collect();
            match key {
                "integrator" => assert!(holders.is_empty()),
                // The integrator a holder holds: a child of the integrator.
                NESTED_INTEGRATOR => {
                    assert!(holders.is_empty());
                    let held = root
                        .child(Kind::Integrator)
                        .unwrap()
                        .child(Kind::Integrator);
                    let held = held.expect("a held integrator");
                    assert_eq!(
                        (held.plugin.as_str(), held.id.as_deref()),
                        ("path", Some("img"))
                    );
                    assert_eq!(held.origin.path.to_string(), "render.nested");
                }
                _ => {
                    assert_eq!(holders.len(), 1, "{key}");
                    assert_eq!(holders[0].kind, kind, "{key}");
                }
            }
        }
    }

    #[test]
    fn the_background_is_a_constant_emitter() {
        let root =
            scene("[render]\nbackground = [0.1, 0.2, 0.3]\n\n[[lights]]\ntype = \"point\"\n");
        let kinds: Vec<_> = root
            .children
            .iter()
            .map(|c| (c.kind, c.plugin.as_str()))
            .collect();
        assert_eq!(
            kinds,
            [
                (Kind::Integrator, "whitted"),
                (Kind::Sensor, "perspective"),
                (Kind::Emitter, "constant"),
                (Kind::Emitter, "point"),
            ]
        );
        let constant = &root.children[2];
        assert_eq!(constant.props.len(), 1);
        let radiance = constant.prop("radiance").unwrap();
        assert_eq!(
            place(&radiance.value.origin),
            ("render.background".into(), 2, 14)
        );
        assert_eq!(place(&radiance.key), ("render.background".into(), 2, 1));
        assert!(matches!(&radiance.value.value, Value::Array(a) if a.len() == 3));
        assert_eq!(scene("").children_of(Kind::Emitter).count(), 0);
    }

    #[test]
    fn materials_come_in_name_order_and_default_to_thesis() {
        let root = scene(
            "[materials.zinc]\nalbedo = [0.5, 0.5, 0.5]\n\n[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n",
        );
        let bsdfs: Vec<_> = root.children_of(Kind::Bsdf).collect();
        assert_eq!(bsdfs.len(), 2);
        assert_eq!(
            (bsdfs[1].id.as_deref(), bsdfs[1].plugin.as_str()),
            (Some("zinc"), "thesis")
        );
        assert_eq!(
            (bsdfs[0].id.as_deref(), bsdfs[0].plugin.as_str()),
            (Some("glass"), "dielectric")
        );
        assert!(bsdfs[0].prop("type").is_none());
        assert_eq!(place(&bsdfs[0].origin), ("materials.glass".into(), 4, 1));
        assert_eq!(
            place(&bsdfs[0].plugin_origin),
            ("materials.glass.type".into(), 5, 8)
        );
        assert_eq!(
            place(&bsdfs[0].prop("ior").unwrap().value.origin),
            ("materials.glass.ior".into(), 6, 7)
        );
        assert_eq!(
            err("[materials.m]\ntype = 2\n"),
            "test.toml:2:8: materials.m.type: invalid type: integer `2`, expected a string"
        );
    }

    #[test]
    fn objects_and_lights_need_a_type() {
        let three = "[[objects]]\ntype = \"sphere\"\n\n[[objects]]\ntype = \"quad\"\n\n";
        assert_eq!(
            err(&format!("{three}[[objects]]\nradius = 1\n")),
            "test.toml:7:1: objects[2]: missing field `type`"
        );
        assert_eq!(
            err("[[lights]]\nradiance = [1, 1, 1]\n"),
            "test.toml:1:1: lights[0]: missing field `type`"
        );
        assert_eq!(
            err("[[objects]]\ntype = true\n"),
            "test.toml:2:8: objects[0].type: invalid type: boolean `true`, expected a string"
        );
        assert_eq!(
            json_err(r#"{"objects": [{"type": "sphere"}, {"radius": 1}]}"#),
            "objects[1]: missing field `type`"
        );
        let root = scene(&format!(
            "{three}[[lights]]\ntype = \"rect\"\nmodel = \"thesis\"\n"
        ));
        let shapes: Vec<_> = root
            .children_of(Kind::Shape)
            .map(|s| s.plugin.as_str())
            .collect();
        assert_eq!(shapes, ["sphere", "quad"]);
        let light = root.children.last().unwrap();
        assert_eq!((light.kind, light.plugin.as_str()), (Kind::Emitter, "rect"));
        assert_eq!(place(&light.origin), ("lights[0]".into(), 7, 1));
        assert_eq!(light.props.len(), 1);
    }

    #[test]
    fn parts_of_the_wrong_type_say_what_was_expected() {
        for (text, expected) in [
            (
                "render = 3\n",
                "test.toml:1:10: render: invalid type: integer `3`, expected a table",
            ),
            (
                "camera = \"x\"\n",
                "test.toml:1:10: camera: invalid type: string \"x\", expected a table",
            ),
            (
                "objects = {}\n",
                "test.toml:1:11: objects: invalid type: table, expected an array of tables",
            ),
            (
                "lights = 3\n",
                "test.toml:1:10: lights: invalid type: integer `3`, expected an array of tables",
            ),
            (
                "objects = [1]\n",
                "test.toml:1:12: objects[0]: invalid type: integer `1`, expected a table",
            ),
            (
                "materials = []\n",
                "test.toml:1:13: materials: invalid type: array, expected a table",
            ),
            (
                "materials.m = 3\n",
                "test.toml:1:15: materials.m: invalid type: integer `3`, expected a table",
            ),
        ] {
            assert_eq!(err(text), expected);
        }
        assert_eq!(json_err("[1, 2]"), "invalid type: array, expected a table");
    }

    #[test]
    fn values_keep_their_kind_and_paths() {
        let root = scene(
            "[[objects]]\ntype = \"mesh\"\nsmooth = true\nwhen = 1979-05-27\n\
             transform = { scale = 2.5, translate = [1, 2, 3] }\n",
        );
        let mesh = root.child(Kind::Shape).unwrap();
        assert_eq!(mesh.prop("smooth").unwrap().value.value, Value::Bool(true));
        assert_eq!(
            mesh.prop("when").unwrap().value.value,
            Value::Datetime("1979-05-27".into())
        );
        let Value::Table(t) = &mesh.prop("transform").unwrap().value.value else {
            panic!("a table")
        };
        assert_eq!(t[0].name, "scale");
        let Value::Array(xs) = &t[1].value.value else {
            panic!("an array")
        };
        assert_eq!(
            place(&xs[2].origin),
            ("objects[0].transform.translate[2]".into(), 5, 47)
        );
    }

    #[test]
    fn values_the_tree_cannot_hold_are_refused_at_their_path() {
        assert_eq!(
            err("[render]\nwidth = 99999999999999999999\n"),
            "test.toml:2:9: render.width: integer `99999999999999999999` is out of range of a 64-bit integer"
        );
        assert_eq!(
            err("[[objects]]\ntype = \"sphere\"\nradius = 1e400\n"),
            "test.toml:3:10: objects[0].radius: number `1e400` is out of range of a 64-bit float"
        );
        assert_eq!(
            json_err(r#"{"camera": {"fov": null}}"#),
            "camera.fov: invalid type: null, expected a value (leave the key out for its default)"
        );
        assert_eq!(
            json_err(r#"{"render": {"seed": 18446744073709551615}}"#),
            "render.seed: integer `18446744073709551615` is out of range of a 64-bit integer"
        );
        let mut deep = serde_json::json!(1);
        for _ in 0..200 {
            deep = serde_json::json!([deep]);
        }
        let e = from_json(&serde_json::json!({ "camera": { "up": deep } })).unwrap_err();
        assert!(e.message.starts_with("camera.up[0][0]"), "{e}");
        assert!(
            e.message
                .ends_with("arrays and tables nest more than 128 deep"),
            "{e}"
        );
    }

    /// Syntax errors and keys nested too deeply read as the TOML parser's
    /// errors always have, at the same places.
    #[test]
    fn parser_errors_keep_their_messages_and_places() {
        let key = vec!["a"; 200].join(".");
        let deep = "a key of 200 dotted parts; keys and table headers nest at most 80 deep";
        for (text, expected) in [
            (
                format!("[render]\nwidth = 8\n{key} = 1\n"),
                format!("test.toml:3:1: {deep}"),
            ),
            (
                format!("[render]\n\n[{key}]\n"),
                format!("test.toml:3:2: {deep}"),
            ),
            (
                format!("[[objects]]\ntype = \"sphere\"\n[[{key}]]\n"),
                format!("test.toml:3:3: {deep}"),
            ),
            (
                format!("x = 1\ny = {{ {key} = 1 }}\n"),
                format!("test.toml:2:7: {deep}"),
            ),
            (
                format!(
                    "[render]\nbackground = {}{}\n",
                    "[".repeat(500),
                    "]".repeat(500)
                ),
                "test.toml:2:94: cannot recurse further; max recursion depth met".into(),
            ),
            (
                format!(
                    "[render]\nwidth = 3\nx = {}1{}\n",
                    "{a = ".repeat(300),
                    "}".repeat(300)
                ),
                "test.toml:3:405: cannot recurse further; max recursion depth met".into(),
            ),
            (
                "[render]\nwidth = = 3\n".into(),
                "test.toml:2:9: extra `=`, expected nothing".into(),
            ),
            (
                "[render\n".into(),
                "test.toml:1:8: unclosed table, expected `]`".into(),
            ),
            (
                "= 1\n".into(),
                "test.toml:1:1: unquoted keys cannot be empty, expected letters, numbers, `-`, `_`"
                    .into(),
            ),
            (
                "[render]\nwidth = 3\nwidth = 4\n".into(),
                "test.toml:3:1: duplicate key".into(),
            ),
            (
                "[render]\n[render]\n".into(),
                "test.toml:2:2: duplicate key".into(),
            ),
            (
                "[render]\nfilter = \"box\n".into(),
                "test.toml:2:14: invalid basic string, expected `\"`".into(),
            ),
            (
                "é = 1\nü = = 2\n".into(),
                "test.toml:2:5: extra `=`, expected nothing".into(),
            ),
        ] {
            assert_eq!(err(&text), expected);
        }
    }

    /// A TOML file and the dict that says the same lower to the same tree.
    #[test]
    fn a_file_and_its_dict_lower_to_the_same_tree() {
        let toml = r#"
[render]
width = 64
height = 48
filter = "gaussian"
spp = 4
distribution = "sobol"
shadow_rays = 16
max_depth = 3
metric = true
noise_threshold = 0.05
integrator = "whitted"
passes = 2
background = [0.05, 0.05, 0.08]

[camera]
position = [0.0, 1.5, 6.0]
look_at = [0.0, 0.7, 0.0]
fov = 40
aperture = 0.05

[materials.brushed]
albedo = [0.1, 0.1, 0.1]
reflectivity = 0.8
reflection_distribution = "poisson"

[materials.glass]
type = "thesis"
transparency = 1.0
ior = 1.5

[[objects]]
type = "quad"
material = "brushed"
origin = [-10.0, 0.0, -10.0]
edge_u = [0.0, 0.0, 20.0]
edge_v = [20.0, 0.0, 0.0]

[[objects]]
type = "sphere"
material = "glass"
center = [1.0, 0.7, 0.5]
radius = 0.7
transform_end = { translate = [0.3, 0.0, 0.0] }

[[objects]]
type = "mesh"
path = "meshes/teapot.obj"
smooth = true
transform = { scale = 0.5, rotate_axis = [0.0, 1.0, 0.0], rotate_degrees = 45.0, translate = [0.0, 0.0, -2.0] }

[[objects]]
type = "mesh"
path = "@bunny"
transform.matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]

[[lights]]
type = "rect"
origin = [-1.0, 4.0, -1.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 2.0]
radiance = [10.0, 10.0, 10.0]
model = "thesis"

[[lights]]
type = "point"
position = [3.0, 3.0, 3.0]
intensity = [5, 5, 5]

[[lights]]
type = "sphere"
center = [0.0, 3.0, 0.0]
radius = 0.25
radiance = [4.0, 4.0, 4.0]

[[lights]]
type = "disk"
center = [0.0, 3.0, 0.0]
normal = [0.0, -1.0, 0.0]
radius = 0.5
radiance = [4.0, 4.0, 4.0]
shadow_rays = 8
shadow_distribution = "jitter"
"#;
        let dict = r#"{
  "render": {"width": 64, "height": 48, "filter": "gaussian", "spp": 4, "distribution": "sobol",
             "shadow_rays": 16, "max_depth": 3, "metric": true, "noise_threshold": 0.05,
             "integrator": "whitted", "passes": 2, "background": [0.05, 0.05, 0.08]},
  "camera": {"position": [0.0, 1.5, 6.0], "look_at": [0.0, 0.7, 0.0], "fov": 40, "aperture": 0.05},
  "materials": {
    "brushed": {"albedo": [0.1, 0.1, 0.1], "reflectivity": 0.8, "reflection_distribution": "poisson"},
    "glass": {"type": "thesis", "transparency": 1.0, "ior": 1.5}
  },
  "objects": [
    {"type": "quad", "material": "brushed", "origin": [-10.0, 0.0, -10.0], "edge_u": [0.0, 0.0, 20.0],
     "edge_v": [20.0, 0.0, 0.0]},
    {"type": "sphere", "material": "glass", "center": [1.0, 0.7, 0.5], "radius": 0.7,
     "transform_end": {"translate": [0.3, 0.0, 0.0]}},
    {"type": "mesh", "path": "meshes/teapot.obj", "smooth": true,
     "transform": {"scale": 0.5, "rotate_axis": [0.0, 1.0, 0.0], "rotate_degrees": 45.0,
                   "translate": [0.0, 0.0, -2.0]}},
    {"type": "mesh", "path": "@bunny",
     "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}}
  ],
  "lights": [
    {"type": "rect", "origin": [-1.0, 4.0, -1.0], "edge_u": [2.0, 0.0, 0.0], "edge_v": [0.0, 0.0, 2.0],
     "radiance": [10.0, 10.0, 10.0], "model": "thesis"},
    {"type": "point", "position": [3.0, 3.0, 3.0], "intensity": [5, 5, 5]},
    {"type": "sphere", "center": [0.0, 3.0, 0.0], "radius": 0.25, "radiance": [4.0, 4.0, 4.0]},
    {"type": "disk", "center": [0.0, 3.0, 0.0], "normal": [0.0, -1.0, 0.0], "radius": 0.5,
     "radiance": [4.0, 4.0, 4.0], "shadow_rays": 8, "shadow_distribution": "jitter"}
  ]
}"#;
        let (a, b) = (scene(toml), json(dict));
        assert!(a.same_as(&b), "{}\n{}", a.fingerprint(), b.fingerprint());
        assert_eq!(a.fingerprint(), b.fingerprint());
        assert_eq!(a.children.len(), 2 + 1 + 2 + 4 + 4);
        assert!(b.children.iter().all(|c| c.origin.at.is_none()));

        // A float changed in its last bit is another tree.
        let mut c = json(dict);
        let sphere = &mut c.children[6];
        let Value::Float(r) = &mut sphere
            .props
            .iter_mut()
            .find(|p| p.name == "radius")
            .unwrap()
            .value
            .value
        else {
            panic!("a float radius")
        };
        *r = f64::from_bits(r.to_bits() + 1);
        assert!(!a.same_as(&c));
        assert_ne!(a.fingerprint(), c.fingerprint());
        // So is an integer written as a float.
        let d = scene(&toml.replace("intensity = [5, 5, 5]", "intensity = [5.0, 5, 5]"));
        assert!(!a.same_as(&d));
    }

    /// A scene file at the size limit lowers in linear time (its places
    /// are found by binary search, not by counting lines from the start).
    #[test]
    fn a_large_file_lowers_whole() {
        let text = large_scene(4 << 20);
        let start = Instant::now();
        let root = scene(&text);
        let took = start.elapsed();
        let shapes = root.children_of(Kind::Shape).count();
        let last = root.children.last().unwrap();
        let at = last.origin.at.as_ref().unwrap();
        assert_eq!(at.line as usize, text.lines().count() - 4);
        eprintln!("{} bytes, {shapes} objects lowered in {took:?}", text.len());
    }

    /// Objects of 5 values (7 counting the centre's numbers) up to `bytes`.
    fn large_scene(bytes: usize) -> String {
        let mut text = String::with_capacity(bytes + 256);
        let mut i = 0;
        while text.len() < bytes {
            text.push_str(&format!(
                "[[objects]]\ntype = \"sphere\"\nmaterial = \"material-number-{i:0>60}\"\n\
                 center = [{i}.25, -{i}.5, 0.125]\nradius = 0.{i}\n"
            ));
            i += 1;
        }
        text
    }
}
