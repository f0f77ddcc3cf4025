//! What a plugin accepts: its parameters, their types, defaults and docs.
//!
//! Each plugin declares a [`Schema`] in its own layer; [`check`] holds a
//! node to it when a scene is loaded, before anything is built, so that a
//! misspelt or misplaced key, a value of the wrong type and an array of the
//! wrong length are reported at their place in the user's words, whichever
//! plugin reads them later. Ranges (a positive radius, a colour in [0, 1])
//! are declared here for the reference and enforced by the builder, which
//! names the value in its message; a test holds every builder to its
//! schema's ranges.

use super::error::{Invalid, KeyPath, Origin};
use super::props;
use super::tree::{Kind, Located, Node, Prop, Value};

/// One parameter of a plugin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    pub name: &'static str,
    pub ty: Type,
    /// The default as the docs show it (`"[0, 1, 5]"`, `"distance to look_at"`).
    pub default: &'static str,
    pub doc: &'static str,
    /// The values the builder accepts (each channel of a colour).
    pub range: Range,
    /// What Mitsuba 3 calls the parameter.
    pub mitsuba: MitsubaKey,
}

impl Param {
    /// A parameter and its docs, of any value its type holds, under the
    /// same name in Mitsuba's plugin.
    pub const fn new(
        name: &'static str,
        ty: Type,
        default: &'static str,
        doc: &'static str,
    ) -> Param {
        Param {
            name,
            ty,
            default,
            doc,
            range: Range::Any,
            mitsuba: MitsubaKey::Same,
        }
    }

    /// The parameter with the values the builder accepts.
    pub const fn range(self, range: Range) -> Param {
        Param { range, ..self }
    }

    /// The parameter under another name in Mitsuba's plugin.
    pub const fn mitsuba(self, name: &'static str) -> Param {
        Param {
            mitsuba: MitsubaKey::Named(name),
            ..self
        }
    }

    /// A texture Mitsuba's plugin holds whatever its name.
    pub const fn any_mitsuba_name(self) -> Param {
        Param {
            mitsuba: MitsubaKey::Any,
            ..self
        }
    }

    /// A parameter Mitsuba's plugin does not have.
    pub const fn penumbra_only(self) -> Param {
        Param {
            mitsuba: MitsubaKey::None,
            ..self
        }
    }

    /// Mitsuba's name for the parameter; `None` for one of Penumbra's own.
    pub const fn mitsuba_name(&self) -> Option<&'static str> {
        match self.mitsuba {
            MitsubaKey::Same => Some(self.name),
            MitsubaKey::Named(n) => Some(n),
            MitsubaKey::None | MitsubaKey::Any => None,
        }
    }

    /// True if the parameter takes a texture.
    pub const fn texturable(&self) -> bool {
        matches!(self.ty, Type::ColourTexture | Type::NumberTexture)
    }
}

/// The values of a parameter its builder accepts beyond its type (each
/// channel of a colour); every builder refuses the others, which the
/// plugins' tests check against the schemas.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// Whatever the type holds (finite where it is a number).
    Any,
    /// In [0, 1].
    Unit,
    /// ≥ 0.
    NonNegative,
    /// > 0.
    Positive,
    /// From the first to the second, both included.
    Between(f64, f64),
}

impl Range {
    /// The range as the docs write it after the type (`"in [0, 1]"`);
    /// empty for [`Range::Any`].
    pub fn markdown(&self) -> String {
        match self {
            Range::Any => String::new(),
            Range::Unit => "in [0, 1]".into(),
            Range::NonNegative => "≥ 0".into(),
            Range::Positive => "> 0".into(),
            Range::Between(lo, hi) => format!("{lo}–{hi}"),
        }
    }
}

/// What Mitsuba 3 calls a parameter of a plugin it has too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MitsubaKey {
    /// The same name.
    Same,
    /// Another name.
    Named(&'static str),
    /// Mitsuba's plugin has no such parameter.
    None,
    /// A texture's parameter Mitsuba sets from the one texture its plugin
    /// holds, whatever its name (a bump map's height field).
    Any,
}

/// The type of a parameter: what [`check`] requires of its value, and the
/// [`Props`](super::Props) reader that reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Type {
    Bool,
    Int,
    /// An integer or a float.
    Number,
    /// 3 numbers, linear RGB.
    Colour,
    /// 3 numbers.
    Vector,
    /// Exactly this many numbers.
    Numbers(usize),
    /// A number or 3 numbers.
    Scale,
    /// A number or 2 numbers (a scale of `(u, v)`).
    Scale2,
    /// 4 rows of 4 numbers.
    Matrix4,
    /// 3 rows of 3 numbers.
    Matrix3,
    String,
    /// A file name (a string).
    Path,
    /// A distribution name.
    Distribution,
    /// One of a closed set of names; the first field names the set in
    /// messages (`"penumbra model"`).
    Choice(&'static str, &'static [&'static str]),
    /// A number, or one of a closed set of names standing for numbers (an
    /// index of refraction by material); the first field names the set.
    NumberOrChoice(&'static str, &'static [&'static str]),
    /// A table with these keys (a transform).
    Table(&'static [Param]),
    /// The name of a material of the scene (one a material holds).
    Material,
    /// A colour (3 numbers), a texture's table (its `type` and parameters)
    /// or the name of a texture of the scene; the texture's own keys are
    /// its builder's to check.
    ColourTexture,
    /// A number, a texture's table or a texture's name (a texture read as
    /// one value).
    NumberTexture,
    /// A number or 3 numbers (a constant volume), a volume's table or the
    /// name of a volume of the scene (what a medium reads through space).
    Volume,
    /// A phase function's table (its `type` and parameters), one a phase
    /// function holds; its own keys are its builder's to check.
    Phase,
}

impl Type {
    /// A parameter holding another plugin (a material, a phase function),
    /// which Mitsuba XML sets from a nested object rather than a property.
    pub fn is_held(&self) -> bool {
        matches!(self, Type::Material | Type::Phase)
    }

    /// The type as the docs' tables name it.
    pub fn markdown_name(&self) -> String {
        match self {
            Type::Bool => "bool".into(),
            Type::Int => "integer".into(),
            Type::Number => "number".into(),
            Type::Colour => "colour".into(),
            Type::Vector => "vector".into(),
            Type::Numbers(n) => format!("array of {n} numbers"),
            Type::Scale => "number or vector".into(),
            Type::Scale2 => "number or array of 2 numbers".into(),
            Type::Matrix4 => "4×4 array of rows".into(),
            Type::Matrix3 => "3×3 array of rows".into(),
            Type::String => "string".into(),
            Type::Path => "file".into(),
            Type::Distribution => "distribution".into(),
            Type::Choice(_, choices) => choices.join(", "),
            Type::NumberOrChoice(what, _) => format!("number or {what} name"),
            Type::Table(_) => "table".into(),
            Type::Material => "material name".into(),
            Type::ColourTexture => "colour or texture".into(),
            Type::NumberTexture => "number or texture".into(),
            Type::Volume => "number, colour or volume".into(),
            Type::Phase => "phase function table".into(),
        }
    }
}

/// The parameters of one plugin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schema {
    pub kind: Kind,
    pub plugin: &'static str,
    /// What messages call one (`"sphere"`, `"rect light"`, `"material"`).
    pub what: &'static str,
    /// One line on what the plugin is, for the reference.
    pub doc: &'static str,
    /// The names of Mitsuba 3's plugins read as this one (empty for a
    /// plugin of Penumbra's own).
    pub mitsuba: &'static [&'static str],
    pub params: &'static [Param],
}

impl Schema {
    pub fn param(&self, name: &str) -> Option<&'static Param> {
        self.params.iter().find(|p| p.name == name)
    }

    /// The parameters' names, in order.
    pub fn names(&self) -> impl Iterator<Item = &'static str> {
        self.params.iter().map(|p| p.name)
    }
}

/// Checks every property of `node` (not its children) against `schema`:
/// a key the schema does not have is an error saying that it does not
/// apply (at its value) when it is a parameter of one of `others` (the
/// other plugins of the kind) and that it is unknown (at the key) otherwise; a value of the
/// wrong type or shape is its reader's error at the value. Tables are
/// checked key by key.
pub fn check(node: &Node, schema: &Schema, others: &[&Schema]) -> Result<(), Invalid> {
    for p in &node.props {
        let Some(param) = schema.param(&p.name) else {
            if others.iter().any(|o| o.param(&p.name).is_some()) {
                let names: Vec<&str> = schema.names().collect();
                return Err(Invalid::at(
                    &p.value.origin,
                    format!(
                        "`{}` does not apply to a {what}; a {what} takes: {}",
                        p.name,
                        names.join(", "),
                        what = schema.what,
                    ),
                ));
            }
            return Err(unknown(&node.origin.path, p, schema.params));
        };
        check_value(&p.value, &param.ty)?;
    }
    Ok(())
}

/// The node of a plugin held as a table (a texture or a volume where a
/// parameter takes one): `plugin` (at `plugin_at`) one of `schemas`, the
/// plugins of `kind`, its properties `props` checked against its schema,
/// with the schema.
pub fn checked_table(
    kind: Kind,
    schemas: &[&'static Schema],
    (plugin, plugin_at): (&str, &Origin),
    props: &[Prop],
    origin: &Origin,
) -> Result<(Node, &'static Schema), Invalid> {
    let Some(schema) = schemas.iter().copied().find(|s| s.plugin == plugin) else {
        let names: Vec<&str> = schemas.iter().map(|s| s.plugin).collect();
        return Err(Invalid::at(
            plugin_at,
            format!(
                "unknown {} `{}`; valid choices are: {}",
                kind.name(),
                crate::input::quote::clip(plugin, crate::input::quote::MAX_QUOTED_CHARS),
                names.join(", ")
            ),
        ));
    };
    let mut node = Node::new(kind, plugin, origin.clone());
    node.props = props.to_vec();
    let others: Vec<&Schema> = schemas
        .iter()
        .copied()
        .filter(|s| s.plugin != plugin)
        .collect();
    check(&node, schema, &others)?;
    Ok((node, schema))
}

/// A plugin's table as a parameter's value (`{ type = "...", ... }`):
/// the plugin its `type` names, where, and its other properties.
pub fn typed_table<'a>(
    props: &'a [Prop],
    origin: &Origin,
    kind: Kind,
) -> Result<(&'a str, &'a Origin, Vec<Prop>), Invalid> {
    let Some(i) = props.iter().position(|p| p.name == "type") else {
        return Err(Invalid::at(
            origin,
            format!("missing field `type` (the {}'s plugin)", kind.name()),
        ));
    };
    let ty = &props[i].value;
    let plugin = props::string(ty)?;
    let rest = props
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != i)
        .map(|(_, p)| p.clone())
        .collect();
    Ok((plugin, &ty.origin, rest))
}

/// The error of a parameter naming a `kind` the scene does not declare
/// (`declared` names those it does), at `at`.
pub fn no_such_name<'a>(
    kind: Kind,
    name: &str,
    declared: impl Iterator<Item = &'a String>,
    at: &Origin,
) -> Invalid {
    let mut names: Vec<&str> = declared.map(String::as_str).collect();
    names.sort_unstable();
    let known = if names.is_empty() {
        "the scene declares none".to_string()
    } else {
        format!("the scene's {}s are: {}", kind.name(), names.join(", "))
    };
    Invalid::at(
        at,
        format!(
            "no {} named `{}`; {known}",
            kind.name(),
            crate::input::quote::clip(name, crate::input::quote::MAX_QUOTED_CHARS)
        ),
    )
}

/// serde's message for an unknown key, at the key, naming its table.
fn unknown(table: &KeyPath, p: &Prop, params: &[Param]) -> Invalid {
    let at = Origin::new(table.clone(), p.key.at.clone());
    Invalid::unknown_field(&at, &p.name, params.iter().map(|p| p.name))
}

fn check_value(v: &Located<Value>, ty: &Type) -> Result<(), Invalid> {
    match ty {
        Type::Bool => props::boolean(v).map(drop),
        Type::Int => props::integer(v).map(drop),
        Type::Number => props::number(v).map(drop),
        Type::Colour | Type::Vector => props::numbers(v, 3).map(drop),
        Type::Numbers(n) => props::numbers(v, *n).map(drop),
        Type::Scale => props::scale(v).map(drop),
        Type::Scale2 => match v.value {
            Value::Array(_) => props::numbers(v, 2).map(drop),
            _ => props::number(v)
                .map(drop)
                .map_err(|_| v.type_error("a number or an array of 2 numbers")),
        },
        Type::Matrix4 => props::matrix4(v).map(drop),
        Type::Matrix3 => props::matrix3(v).map(drop),
        Type::ColourTexture => match v.value {
            Value::Table(_) | Value::String(_) => Ok(()),
            Value::Array(_) => props::numbers(v, 3).map(drop),
            _ => Err(v.type_error("3 numbers, a texture table or a texture's name")),
        },
        Type::NumberTexture => match v.value {
            Value::Table(_) | Value::String(_) => Ok(()),
            _ => props::number(v)
                .map(drop)
                .map_err(|_| v.type_error("a number, a texture table or a texture's name")),
        },
        Type::Volume => match v.value {
            Value::Table(_) | Value::String(_) => Ok(()),
            Value::Array(_) => props::numbers(v, 3).map(drop),
            _ => props::number(v).map(drop).map_err(|_| {
                v.type_error("a number, 3 numbers, a volume table or a volume's name")
            }),
        },
        Type::String | Type::Path | Type::Material => props::string(v).map(drop),
        Type::Phase => props::table(v).map(drop),
        Type::Distribution => props::distribution(v).map(drop),
        Type::Choice(what, choices) => props::choice(v, what, choices).map(drop),
        Type::NumberOrChoice(what, choices) => props::number_or_choice(v, what, choices).map(drop),
        Type::Table(params) => {
            for p in props::table(v)? {
                match params.iter().find(|param| param.name == p.name) {
                    Some(param) => check_value(&p.value, &param.ty)?,
                    None => return Err(unknown(&v.origin.path, p, params)),
                }
            }
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::description::{from_json, from_toml, SceneError};

    // Schemas after today's scene format (docs/scene-format.md).

    const TRANSFORM: &[Param] = &[
        param("scale", Type::Scale),
        param("rotate_axis", Type::Vector),
        param("rotate_degrees", Type::Number),
        param("translate", Type::Vector),
        param("matrix", Type::Matrix4),
    ];

    const fn param(name: &'static str, ty: Type) -> Param {
        Param::new(name, ty, "", "")
    }

    const SPHERE: Schema = Schema {
        kind: Kind::Shape,
        plugin: "sphere",
        what: "sphere",
        doc: "",
        mitsuba: &[],
        params: &[
            param("center", Type::Vector),
            param("radius", Type::Number),
            param("material", Type::String),
            param("transform", Type::Table(TRANSFORM)),
            param("transform_end", Type::Table(TRANSFORM)),
        ],
    };

    const QUAD: Schema = Schema {
        kind: Kind::Shape,
        plugin: "quad",
        what: "quad",
        doc: "",
        mitsuba: &[],
        params: &[
            param("origin", Type::Vector),
            param("edge_u", Type::Vector),
            param("edge_v", Type::Vector),
            param("material", Type::String),
            param("transform", Type::Table(TRANSFORM)),
            param("transform_end", Type::Table(TRANSFORM)),
        ],
    };

    const MESH: Schema = Schema {
        kind: Kind::Shape,
        plugin: "mesh",
        what: "mesh",
        doc: "",
        mitsuba: &[],
        params: &[
            param("path", Type::Path),
            param("smooth", Type::Bool),
            param("material", Type::String),
            param("transform", Type::Table(TRANSFORM)),
            param("transform_end", Type::Table(TRANSFORM)),
        ],
    };

    const SHAPES: [&Schema; 3] = [&SPHERE, &QUAD, &MESH];

    const MODEL: Type = Type::Choice("penumbra model", &["surface", "thesis"]);

    const POINT: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "point",
        what: "point light",
        doc: "",
        mitsuba: &[],
        params: &[
            param("position", Type::Vector),
            param("intensity", Type::Colour),
        ],
    };

    const RECT: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "rect",
        what: "rect light",
        doc: "",
        mitsuba: &[],
        params: &[
            param("origin", Type::Vector),
            param("edge_u", Type::Vector),
            param("edge_v", Type::Vector),
            param("radiance", Type::Colour),
            param("model", MODEL),
            param("shadow_rays", Type::Int),
            param("shadow_distribution", Type::Distribution),
        ],
    };

    const LIGHTS: [&Schema; 2] = [&POINT, &RECT];

    const CAMERA: Schema = Schema {
        kind: Kind::Sensor,
        plugin: "perspective",
        what: "camera",
        doc: "",
        mitsuba: &[],
        params: &[
            param("position", Type::Vector),
            param("look_at", Type::Vector),
            param("up", Type::Vector),
            param("fov", Type::Number),
            param("aperture", Type::Number),
            param("focal_distance", Type::Number),
            param("shutter", Type::Numbers(2)),
            param("position_end", Type::Vector),
            param("look_at_end", Type::Vector),
        ],
    };

    const MATERIAL: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "thesis",
        what: "material",
        doc: "",
        mitsuba: &[],
        params: &[
            param("albedo", Type::Colour),
            param("ior", Type::Number),
            param("reflection_rays", Type::Int),
            param("reflection_distribution", Type::Distribution),
        ],
    };

    fn schema_of(node: &Node) -> (&'static Schema, Vec<&'static Schema>) {
        let family: &[&'static Schema] = match node.kind {
            Kind::Shape => &SHAPES,
            Kind::Emitter => &LIGHTS,
            Kind::Sensor => &[&CAMERA],
            Kind::Bsdf => &[&MATERIAL],
            _ => &[],
        };
        let own = family
            .iter()
            .find(|s| s.plugin == node.plugin)
            .expect("a schema");
        let others = family.iter().filter(|s| s.plugin != node.plugin).copied();
        (own, others.collect())
    }

    /// The first error of checking every node of a scene.
    fn check_scene(root: &Node) -> Result<(), SceneError> {
        let mut nodes: Vec<&Node> = root.children.iter().collect();
        while let Some(node) = nodes.pop() {
            nodes.extend(&node.children);
            if matches!(
                node.kind,
                Kind::Shape | Kind::Emitter | Kind::Sensor | Kind::Bsdf
            ) {
                let (own, others) = schema_of(node);
                check(node, own, &others)?;
            }
        }
        Ok(())
    }

    fn err(text: &str) -> String {
        let root = from_toml(text, Path::new("test.toml")).unwrap();
        check_scene(&root).unwrap_err().to_string()
    }

    #[test]
    fn valid_scenes_pass() {
        let text = "[camera]\nposition = [0, 1, 5]\nfov = 40\nshutter = [0, 0.5]\n\
                    [materials.m]\nalbedo = [0.5, 0.5, 0.5]\nreflection_distribution = \"sobol\"\n\
                    [[objects]]\ntype = \"sphere\"\nradius = 2\nmaterial = \"m\"\n\
                    transform = { scale = [1, 2, 1], rotate_axis = [0, 1, 0], rotate_degrees = 30 }\n\
                    [[objects]]\ntype = \"mesh\"\npath = \"a.ply\"\nsmooth = true\n\
                    transform_end.matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n\
                    [[lights]]\ntype = \"rect\"\nradiance = [1, 1, 1]\nmodel = \"thesis\"\nshadow_rays = 4\n";
        let root = from_toml(text, Path::new("test.toml")).unwrap();
        assert_eq!(check_scene(&root), Ok(()));
    }

    #[test]
    fn a_key_of_another_plugin_does_not_apply_and_any_other_is_unknown() {
        let quad = "[[objects]]\ntype = \"quad\"\norigin = [0, 0, 0]\n";
        assert_eq!(
            err(&format!("{quad}radius = 1.0\n")),
            "test.toml:4:10: objects[0].radius: `radius` does not apply to a quad; \
             a quad takes: origin, edge_u, edge_v, material, transform, transform_end"
        );
        assert_eq!(
            err(&format!("{quad}radios = 1.0\n")),
            "test.toml:4:1: objects[0]: unknown field `radios`, expected one of `origin`, \
             `edge_u`, `edge_v`, `material`, `transform`, `transform_end`"
        );
        assert_eq!(
            err("[camera]\nfov = 30\nzoom = 2\n"),
            "test.toml:3:1: camera: unknown field `zoom`, expected one of `position`, `look_at`, \
             `up`, `fov`, `aperture`, `focal_distance`, `shutter`, `position_end`, `look_at_end`"
        );
        let e = err("[[lights]]\ntype = \"point\"\nmodel = \"surface\"\n");
        assert!(e.starts_with("test.toml:3:9: lights[0].model: `model` does not apply to a point light; a point light takes: position, intensity"), "{e}");
    }

    #[test]
    fn tables_are_checked_key_by_key() {
        let e = err(
            "[[objects]]\ntype = \"sphere\"\ntransform = { scale = 2, rotate_axsi = [0, 1, 0] }\n",
        );
        assert_eq!(
            e,
            "test.toml:3:26: objects[0].transform: unknown field `rotate_axsi`, expected one of \
             `scale`, `rotate_axis`, `rotate_degrees`, `translate`, `matrix`"
        );
        let e = err("[[objects]]\ntype = \"mesh\"\n[objects.transform_end]\nscale = [1, 2]\n");
        assert_eq!(
            e,
            "test.toml:4:9: objects[0].transform_end.scale: expected 3 numbers, got 2"
        );
        let e = err("[[objects]]\ntype = \"mesh\"\ntransform = 3\n");
        assert_eq!(
            e,
            "test.toml:3:13: objects[0].transform: invalid type: integer `3`, expected a table"
        );
        let e = err("[[objects]]\ntype = \"mesh\"\ntransform.matrix = [[1, 0, 0, 0], [1, 0, 0, 0], [1, 0, 0, 0], [1, 0, 0]]\n");
        assert!(
            e.contains("objects[0].transform.matrix[3]: expected 4 numbers, got 3"),
            "{e}"
        );
    }

    #[test]
    fn values_are_checked_by_type_and_shape() {
        for (text, expected) in [
            ("[camera]\nfov = \"wide\"\n", "test.toml:2:7: camera.fov: invalid type: string \"wide\", expected a number"),
            ("[camera]\nshutter = [0, 0.5, 1]\n", "test.toml:2:11: camera.shutter: expected 2 numbers, got 3"),
            ("[camera]\nposition = [0, 1, 5, 1]\n", "test.toml:2:12: camera.position: expected 3 numbers, got 4"),
            ("[materials.m]\nreflection_rays = 2.5\n", "test.toml:2:19: materials.m.reflection_rays: invalid type: floating point `2.5`, expected an integer"),
            ("[materials.m]\nreflection_distribution = \"sobel\"\n", "test.toml:2:27: materials.m.reflection_distribution: unknown distribution `sobel`; valid choices are: "),
            ("[[objects]]\ntype = \"mesh\"\nsmooth = 1\n", "test.toml:3:10: objects[0].smooth: invalid type: integer `1`, expected a boolean"),
            ("[[objects]]\ntype = \"mesh\"\npath = 1\n", "test.toml:3:8: objects[0].path: invalid type: integer `1`, expected a string"),
            ("[[lights]]\ntype = \"rect\"\nmodel = \"exact\"\n", "test.toml:3:9: lights[0].model: unknown penumbra model `exact`; valid choices are: surface, thesis"),
        ] {
            let e = err(text);
            assert!(e.starts_with(expected), "{e}\n{expected}");
        }
    }

    #[test]
    fn non_finite_numbers_are_the_builders_to_refuse() {
        let root = from_toml(
            "[camera]\nfov = inf\nposition = [nan, 0, 0]\n[[objects]]\ntype = \"sphere\"\nradius = 1e300\n",
            Path::new("test.toml"),
        )
        .unwrap();
        assert_eq!(check_scene(&root), Ok(()));
    }

    #[test]
    fn dict_errors_name_the_key_path() {
        let json: serde_json::Value =
            serde_json::from_str(r#"{"objects": [{"type": "sphere", "radius": "big"}]}"#).unwrap();
        let e = check_scene(&from_json(&json).unwrap()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "objects[0].radius: invalid type: string \"big\", expected a number"
        );
    }

    #[test]
    fn types_have_names_for_the_docs() {
        assert_eq!(Type::Numbers(2).markdown_name(), "array of 2 numbers");
        assert_eq!(MODEL.markdown_name(), "surface, thesis");
        assert_eq!(Type::Matrix4.markdown_name(), "4×4 array of rows");
        assert_eq!(Type::Table(TRANSFORM).markdown_name(), "table");
        assert_eq!(SPHERE.param("radius").map(|p| p.ty), Some(Type::Number));
    }
}
