//! The tree: plugins ([`Node`]s) with named, typed properties ([`Prop`]s),
//! every key and value carrying its [`Origin`].

use std::fmt::Write as _;

use super::error::{Invalid, KeyPath, KeySeg, Origin};
use crate::input::quote;

/// What a node is: the plugin interface it implements.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Scene,
    Integrator,
    Sensor,
    Film,
    /// A film's pixel filter (Mitsuba's `<rfilter>`), whose parameters
    /// are the film's keys: no node of a tree is one.
    Filter,
    Sampler,
    Shape,
    Bsdf,
    Emitter,
    Texture,
    /// Values through space that a participating medium reads.
    Volume,
    /// A participating medium (Mitsuba's `<medium>`).
    Medium,
    /// A medium's phase function (Mitsuba's `<phase>`), which only a
    /// medium holds.
    Phase,
}

impl Kind {
    /// Every kind, in the order of the enum.
    pub const ALL: [Kind; 13] = [
        Kind::Scene,
        Kind::Integrator,
        Kind::Sensor,
        Kind::Film,
        Kind::Filter,
        Kind::Sampler,
        Kind::Shape,
        Kind::Bsdf,
        Kind::Emitter,
        Kind::Texture,
        Kind::Volume,
        Kind::Medium,
        Kind::Phase,
    ];

    /// The kind's name in lower case, as messages and XML tags write it.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Scene => "scene",
            Kind::Integrator => "integrator",
            Kind::Sensor => "sensor",
            Kind::Film => "film",
            Kind::Filter => "rfilter",
            Kind::Sampler => "sampler",
            Kind::Shape => "shape",
            Kind::Bsdf => "bsdf",
            Kind::Emitter => "emitter",
            Kind::Texture => "texture",
            Kind::Volume => "volume",
            Kind::Medium => "medium",
            Kind::Phase => "phase",
        }
    }
}

/// A value together with where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Located<T> {
    pub value: T,
    pub origin: Origin,
}

impl<T> Located<T> {
    pub fn new(value: T, origin: Origin) -> Self {
        Located { value, origin }
    }
}

impl Located<Value> {
    /// serde's type error, at the value:
    /// ``invalid type: integer `3`, expected a table``.
    pub fn type_error(&self, expected: &str) -> Invalid {
        Invalid::at(
            &self.origin,
            format!(
                "invalid type: {}, expected {expected}",
                self.value.type_name()
            ),
        )
    }
}

/// A property value, as the input wrote it: nothing is converted or checked
/// here (a typed reader does that, see [`Props`](super::Props)).
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    String(String),
    /// Each element with its own origin (`key[i]`).
    Array(Vec<Located<Value>>),
    /// An inline or dotted table, such as a transform.
    Table(Vec<Prop>),
    /// A TOML date or time, as the file wrote it; no property takes one.
    Datetime(String),
}

impl Value {
    /// What the value is, in serde's words, with the value itself quoted
    /// and cut to a few dozen characters: `string "wide"`, ``integer `3` ``,
    /// ``floating point `1.5` ``, ``boolean `true` ``, `array`, `table`,
    /// `datetime`. The unexpected half of a type error.
    pub fn type_name(&self) -> String {
        match self {
            Value::Bool(b) => format!("boolean `{b}`"),
            Value::Int(i) => format!("integer `{i}`"),
            Value::Float(f) => format!("floating point {}", quote::quote(&float_text(*f))),
            Value::String(s) => format!("string {:?}", quote::clip(s, quote::MAX_QUOTED_CHARS)),
            Value::Array(_) => "array".to_string(),
            Value::Table(_) => "table".to_string(),
            Value::Datetime(_) => "datetime".to_string(),
        }
    }
}

/// A float as serde shows it: with a decimal point when it is a whole number.
fn float_text(f: f64) -> String {
    let s = f.to_string();
    if f.is_finite() && !s.contains(['.', 'e']) {
        s + ".0"
    } else {
        s
    }
}

/// A named property of a node (or of a table value).
#[derive(Clone, Debug, PartialEq)]
pub struct Prop {
    pub name: String,
    /// Where the key is written (its path is the property's).
    pub key: Origin,
    /// The value and where it is written.
    pub value: Located<Value>,
}

impl Prop {
    pub fn new(name: impl Into<String>, key: Origin, value: Located<Value>) -> Self {
        Prop {
            name: name.into(),
            key,
            value,
        }
    }
}

/// One plugin of the scene: its kind, which plugin of that kind, an id
/// (a material's name), its properties in the order of the input, and the
/// nodes it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub kind: Kind,
    pub plugin: String,
    pub id: Option<String>,
    pub props: Vec<Prop>,
    pub children: Vec<Node>,
    /// Where the node's table is written (the root of the input when it
    /// has none).
    pub origin: Origin,
    /// Where the plugin's name is written (its table's `type`, say); the
    /// node's origin when the name is a default.
    pub plugin_origin: Origin,
}

impl Node {
    /// A node without id, properties or children.
    pub fn new(kind: Kind, plugin: impl Into<String>, origin: Origin) -> Self {
        Node {
            kind,
            plugin: plugin.into(),
            id: None,
            props: Vec::new(),
            children: Vec::new(),
            plugin_origin: origin.clone(),
            origin,
        }
    }

    pub fn prop(&self, name: &str) -> Option<&Prop> {
        self.props.iter().find(|p| p.name == name)
    }

    /// Sets a property (a command-line override, say): replaces the value
    /// of `name` or appends it. The key takes the value's origin: the
    /// property now comes from wherever the value did.
    pub fn set_prop(&mut self, name: &str, value: Located<Value>) {
        let key = value.origin.clone();
        match self.props.iter_mut().find(|p| p.name == name) {
            Some(p) => {
                p.key = key;
                p.value = value;
            }
            None => self.props.push(Prop::new(name, key, value)),
        }
    }

    /// Removes a property, returning it if it was there.
    pub fn remove_prop(&mut self, name: &str) -> Option<Prop> {
        let i = self.props.iter().position(|p| p.name == name)?;
        Some(self.props.remove(i))
    }

    /// The children of one kind, in order.
    pub fn children_of(&self, kind: Kind) -> impl Iterator<Item = &Node> {
        self.children.iter().filter(move |c| c.kind == kind)
    }

    /// The first child of a kind.
    pub fn child(&self, kind: Kind) -> Option<&Node> {
        self.children.iter().find(|c| c.kind == kind)
    }

    pub fn child_mut(&mut self, kind: Kind) -> Option<&mut Node> {
        self.children.iter_mut().find(|c| c.kind == kind)
    }

    /// Whether two trees say the same thing from the same key paths,
    /// wherever they were read from: files, lines and columns are ignored,
    /// properties compare as sets (a TOML file keeps its keys' order, a
    /// dict its map's), children in order, floats bit for bit.
    pub fn same_as(&self, other: &Node) -> bool {
        self.kind == other.kind
            && self.plugin == other.plugin
            && self.id == other.id
            && self.origin.path == other.origin.path
            && same_props(&self.props, &other.props)
            && self.children.len() == other.children.len()
            && self
                .children
                .iter()
                .zip(&other.children)
                .all(|(a, b)| a.same_as(b))
    }

    /// A canonical text of the tree: equal for trees that are
    /// [`same_as`](Self::same_as) each other (but for NaNs of different
    /// bits), different otherwise. Floats are written exactly, so that a
    /// change in the last bit shows; a key for caches of what was built
    /// from a node.
    pub fn fingerprint(&self) -> String {
        let mut out = String::new();
        write_node(&mut out, self);
        out
    }
}

fn sorted(props: &[Prop]) -> Vec<&Prop> {
    let mut v: Vec<&Prop> = props.iter().collect();
    v.sort_by(|a, b| a.name.cmp(&b.name));
    v
}

fn same_props(a: &[Prop], b: &[Prop]) -> bool {
    a.len() == b.len()
        && sorted(a).iter().zip(sorted(b)).all(|(x, y)| {
            x.name == y.name && x.key.path == y.key.path && same_located(&x.value, &y.value)
        })
}

fn same_located(a: &Located<Value>, b: &Located<Value>) -> bool {
    a.origin.path == b.origin.path && same_value(&a.value, &b.value)
}

fn same_value(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Bool(x), Value::Bool(y)) => x == y,
        (Value::Int(x), Value::Int(y)) => x == y,
        (Value::Float(x), Value::Float(y)) => x.to_bits() == y.to_bits(),
        (Value::String(x), Value::String(y)) | (Value::Datetime(x), Value::Datetime(y)) => x == y,
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(a, b)| same_located(a, b))
        }
        (Value::Table(x), Value::Table(y)) => same_props(x, y),
        _ => false,
    }
}

// The fingerprint's grammar: every string and key in `{:?}` (quoted and
// escaped), every list bracketed, so that no two trees write the same text.

fn write_node(out: &mut String, node: &Node) {
    let _ = write!(out, "{}{:?}", node.kind.name(), node.plugin);
    if let Some(id) = &node.id {
        let _ = write!(out, "#{id:?}");
    }
    write_path(out, &node.origin.path);
    write_props(out, &node.props);
    out.push('[');
    for child in &node.children {
        write_node(out, child);
        out.push(',');
    }
    out.push(']');
}

fn write_props(out: &mut String, props: &[Prop]) {
    out.push('{');
    for p in sorted(props) {
        let _ = write!(out, "{:?}", p.name);
        write_path(out, &p.key.path);
        out.push('=');
        write_located(out, &p.value);
        out.push(';');
    }
    out.push('}');
}

fn write_located(out: &mut String, v: &Located<Value>) {
    match &v.value {
        Value::Bool(b) => {
            let _ = write!(out, "{b}");
        }
        Value::Int(i) => {
            let _ = write!(out, "i{i}");
        }
        Value::Float(f) => {
            let _ = write!(out, "f{f:?}");
        }
        Value::String(s) => {
            let _ = write!(out, "{s:?}");
        }
        Value::Datetime(d) => {
            let _ = write!(out, "d{d:?}");
        }
        Value::Array(items) => {
            out.push('[');
            for item in items {
                write_located(out, item);
                out.push(',');
            }
            out.push(']');
        }
        Value::Table(props) => write_props(out, props),
    }
    write_path(out, &v.origin.path);
}

fn write_path(out: &mut String, path: &KeyPath) {
    out.push('@');
    for seg in path.segments() {
        let _ = match seg {
            KeySeg::Key(k) => write!(out, ".{k:?}"),
            KeySeg::Index(i) => write!(out, "[{i}]"),
        };
    }
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;
    use std::sync::Arc;

    use super::*;
    use crate::description::error::Location;

    fn at(line: u32) -> Option<Location> {
        Some(Location {
            file: Arc::new(PathBuf::from("a.toml")),
            line,
            column: 1,
        })
    }

    fn num(path: &KeyPath, x: f64, line: u32) -> Located<Value> {
        Located::new(Value::Float(x), Origin::new(path.clone(), at(line)))
    }

    /// A sphere at `objects[0]` with a radius and a centre, the keys in
    /// the given order, every place on the given line.
    fn sphere(radius: f64, reversed: bool, line: u32) -> Node {
        let base = KeyPath::root().key("objects").index(0);
        let mut n = Node::new(Kind::Shape, "sphere", Origin::new(base.clone(), at(line)));
        let r = base.key("radius");
        let c = base.key("center");
        let centre: Vec<_> = (0..3).map(|i| num(&c.index(i), i as f64, line)).collect();
        let mut props = vec![
            Prop::new(
                "radius",
                Origin::new(r.clone(), at(line)),
                num(&r, radius, line),
            ),
            Prop::new(
                "center",
                Origin::new(c.clone(), at(line)),
                Located::new(Value::Array(centre), Origin::new(c, at(line))),
            ),
        ];
        if reversed {
            props.reverse();
        }
        n.props = props;
        n
    }

    #[test]
    fn trees_compare_without_places_and_key_order() {
        let a = sphere(0.5, false, 3);
        let b = sphere(0.5, true, 9);
        assert!(a.same_as(&b));
        assert_eq!(a.fingerprint(), b.fingerprint());
        let mut c = sphere(0.5, false, 3);
        c.props[0].value.origin.path = KeyPath::root().key("elsewhere");
        assert!(!a.same_as(&c));
        assert_ne!(a.fingerprint(), c.fingerprint());
    }

    #[test]
    fn a_float_changed_in_its_last_bit_changes_the_fingerprint() {
        let x = 0.7f64;
        let y = f64::from_bits(x.to_bits() + 1);
        let (a, b) = (sphere(x, false, 1), sphere(y, false, 1));
        assert!(!a.same_as(&b));
        assert_ne!(a.fingerprint(), b.fingerprint());
        let int = {
            let mut n = sphere(1.0, false, 1);
            n.props[0].value.value = Value::Int(1);
            n
        };
        assert_ne!(sphere(1.0, false, 1).fingerprint(), int.fingerprint());
    }

    #[test]
    fn props_are_set_replaced_and_removed() {
        let mut n = sphere(0.5, false, 1);
        let cli = Origin::unlocated(KeyPath::root().key("--radius"));
        n.set_prop("radius", Located::new(Value::Float(2.0), cli.clone()));
        assert_eq!(n.props.len(), 2);
        assert_eq!(n.prop("radius").unwrap().value.value, Value::Float(2.0));
        assert_eq!(n.prop("radius").unwrap().key, cli);
        n.set_prop("smooth", Located::new(Value::Bool(true), cli));
        assert_eq!(n.props.last().unwrap().name, "smooth");
        assert!(n.remove_prop("center").is_some());
        assert!(n.remove_prop("center").is_none());
        assert_eq!(n.props.len(), 2);
    }

    #[test]
    fn children_are_found_by_kind() {
        let mut root = Node::new(Kind::Scene, "scene", Origin::default());
        root.children.push(sphere(1.0, false, 1));
        root.children
            .push(Node::new(Kind::Emitter, "point", Origin::default()));
        root.children.push(sphere(2.0, false, 1));
        assert_eq!(root.children_of(Kind::Shape).count(), 2);
        assert_eq!(root.child(Kind::Emitter).unwrap().plugin, "point");
        root.child_mut(Kind::Shape).unwrap().plugin = "quad".into();
        assert_eq!(root.children[0].plugin, "quad");
        assert!(root.child(Kind::Texture).is_none());
    }

    #[test]
    fn type_names_say_what_a_value_is_in_few_characters() {
        assert_eq!(Value::String("wide".into()).type_name(), "string \"wide\"");
        assert_eq!(Value::Int(3).type_name(), "integer `3`");
        assert_eq!(Value::Float(1.5).type_name(), "floating point `1.5`");
        assert_eq!(Value::Float(2.0).type_name(), "floating point `2.0`");
        assert_eq!(Value::Bool(true).type_name(), "boolean `true`");
        assert_eq!(Value::Array(vec![]).type_name(), "array");
        assert_eq!(Value::Table(vec![]).type_name(), "table");
        assert_eq!(Value::Datetime("1979-05-27".into()).type_name(), "datetime");
        let long = Value::String("x".repeat(10_000)).type_name();
        assert!(long.len() < 60 && long.ends_with("x…\""), "{long}");
        assert!(Value::Float(1e300).type_name().chars().count() < 60);
        assert_eq!(Kind::Bsdf.name(), "bsdf");
    }
}
