//! Typed reading of a node's properties, remembering which were read.
//!
//! Every reader returns `Ok(None)` for a property that is not there (the
//! builder fills in its default), the value when it has the type asked
//! for, and otherwise serde's type error at the value
//! (``invalid type: string "wide", expected a number``). Arrays are read
//! exactly: a vector given 4 numbers is ``expected 3 numbers, got 4`` at
//! the array, never a value cut to size. Ranges (a positive radius, a
//! finite number) are the builder's to check: 1e300 read as an `f32` is
//! infinity, which its range check reports.

use std::cell::Cell;

use super::error::{Invalid, Origin};
use super::tree::{Located, Node, Prop, Value};
use crate::sampling::Distribution;

/// A uniform (`scale = 2.0`) or per-axis (`scale = [1, 2, 1]`) scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// A number, or a name standing for one (see [`Props::number_or_choice`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NumberOr {
    Number(f32),
    Name(&'static str),
}

/// The properties of a node (or of a table value) being read.
pub struct Props<'a> {
    props: &'a [Prop],
    origin: &'a Origin,
    read: Vec<Cell<bool>>,
}

impl<'a> Props<'a> {
    /// The properties of a node.
    pub fn new(node: &'a Node) -> Self {
        Props::of(&node.props, &node.origin)
    }

    /// The properties of a table (a transform, say) at `origin`.
    pub fn of(props: &'a [Prop], origin: &'a Origin) -> Self {
        Props {
            props,
            origin,
            read: vec![Cell::new(false); props.len()],
        }
    }

    /// Where the node (or table) is written.
    pub fn node_origin(&self) -> &'a Origin {
        self.origin
    }

    fn find(&self, name: &str) -> Option<usize> {
        self.props.iter().position(|p| p.name == name)
    }

    /// Whether the property is there; does not count as reading it.
    pub fn has(&self, name: &str) -> bool {
        self.find(name).is_some()
    }

    /// The property, marked as read.
    pub fn get(&self, name: &str) -> Option<&'a Prop> {
        let i = self.find(name)?;
        self.read[i].set(true);
        Some(&self.props[i])
    }

    /// The value's origin (not marked as read).
    pub fn origin(&self, name: &str) -> Option<&'a Origin> {
        self.find(name).map(|i| &self.props[i].value.origin)
    }

    fn read<T>(
        &self,
        name: &str,
        f: impl FnOnce(&'a Located<Value>) -> Result<T, Invalid>,
    ) -> Result<Option<T>, Invalid> {
        self.get(name).map(|p| f(&p.value)).transpose()
    }

    /// A number (an integer or a float), as `f32`.
    pub fn f32(&self, name: &str) -> Result<Option<f32>, Invalid> {
        self.read(name, number)
    }

    /// An integer (a float is a type error).
    pub fn int(&self, name: &str) -> Result<Option<i64>, Invalid> {
        self.read(name, integer)
    }

    pub fn bool(&self, name: &str) -> Result<Option<bool>, Invalid> {
        self.read(name, boolean)
    }

    pub fn string(&self, name: &str) -> Result<Option<&'a str>, Invalid> {
        self.read(name, string)
    }

    /// Exactly `N` numbers.
    pub fn numbers<const N: usize>(&self, name: &str) -> Result<Option<[f32; N]>, Invalid> {
        self.read(name, |v| {
            let xs = numbers(v, N)?;
            Ok(std::array::from_fn(|i| xs[i]))
        })
    }

    /// A number (uniform) or exactly 3 numbers (per axis).
    pub fn scale(&self, name: &str) -> Result<Option<Scale>, Invalid> {
        self.read(name, scale)
    }

    /// 4 rows of 4 numbers each.
    pub fn matrix4(&self, name: &str) -> Result<Option<[[f32; 4]; 4]>, Invalid> {
        self.read(name, matrix4)
    }

    /// 3 rows of 3 numbers each.
    pub fn matrix3(&self, name: &str) -> Result<Option<[[f32; 3]; 3]>, Invalid> {
        self.read(name, matrix3)
    }

    /// A table's properties, to be read in turn (and
    /// [`finish`](Self::finish)ed on their own).
    pub fn table(&self, name: &str) -> Result<Option<Props<'a>>, Invalid> {
        self.read(name, |v| table(v).map(|props| Props::of(props, &v.origin)))
    }

    /// A distribution by name ([`Distribution::from_name`]).
    pub fn distribution(&self, name: &str) -> Result<Option<Distribution>, Invalid> {
        self.read(name, distribution)
    }

    /// One of a closed set of names; `what` names the set in the message
    /// (``unknown penumbra model `x`; valid choices are: surface, thesis``).
    pub fn choice(
        &self,
        name: &str,
        what: &str,
        choices: &[&'static str],
    ) -> Result<Option<&'static str>, Invalid> {
        self.read(name, |v| choice(v, what, choices))
    }

    /// A number, or one of a closed set of names (`int_ior = 1.5` or
    /// `int_ior = "water"`); `what` names the set in the message.
    pub fn number_or_choice(
        &self,
        name: &str,
        what: &str,
        choices: &[&'static str],
    ) -> Result<Option<NumberOr>, Invalid> {
        self.read(name, |v| number_or_choice(v, what, choices))
    }

    /// A problem with a property: at its value if it is there, else at the
    /// node, under the property's path.
    pub fn error(&self, name: &str, message: impl Into<String>) -> Invalid {
        match self.origin(name) {
            Some(origin) => Invalid::at(origin, message),
            None => {
                let at = Origin::new(self.origin.path.key(name), self.origin.at.clone());
                Invalid::at(&at, message)
            }
        }
    }

    /// A problem with the node as a whole (a required property missing).
    pub fn node_error(&self, message: impl Into<String>) -> Invalid {
        Invalid::at(self.origin, message)
    }

    /// The properties never read, in order.
    pub fn unused(&self) -> Vec<&'a Prop> {
        self.props
            .iter()
            .zip(&self.read)
            .filter(|(_, read)| !read.get())
            .map(|(p, _)| p)
            .collect()
    }

    /// Errs at the first property never read: a property a plugin accepts
    /// (its schema says so) but does not use is a bug of the plugin.
    pub fn finish(&self, what: &str) -> Result<(), Invalid> {
        match self.unused().first() {
            Some(p) => Err(Invalid::at(
                &p.key,
                format!("unused property `{}` of a {what}", p.name),
            )),
            None => Ok(()),
        }
    }
}

// The readers of one value, shared with the schema check.

pub(crate) fn number(v: &Located<Value>) -> Result<f32, Invalid> {
    match v.value {
        Value::Int(i) => Ok(i as f32),
        Value::Float(f) => Ok(f as f32),
        _ => Err(v.type_error("a number")),
    }
}

pub(crate) fn integer(v: &Located<Value>) -> Result<i64, Invalid> {
    match v.value {
        Value::Int(i) => Ok(i),
        _ => Err(v.type_error("an integer")),
    }
}

pub(crate) fn boolean(v: &Located<Value>) -> Result<bool, Invalid> {
    match v.value {
        Value::Bool(b) => Ok(b),
        _ => Err(v.type_error("a boolean")),
    }
}

pub(crate) fn string(v: &Located<Value>) -> Result<&str, Invalid> {
    match &v.value {
        Value::String(s) => Ok(s),
        _ => Err(v.type_error("a string")),
    }
}

/// Exactly `n` numbers.
pub(crate) fn numbers(v: &Located<Value>, n: usize) -> Result<Vec<f32>, Invalid> {
    let items = array(v, &format!("an array of {n} numbers"))?;
    exact_length(v, items, n, "numbers")?;
    items.iter().map(number).collect()
}

fn array<'v>(v: &'v Located<Value>, expected: &str) -> Result<&'v [Located<Value>], Invalid> {
    match &v.value {
        Value::Array(items) => Ok(items),
        _ => Err(v.type_error(expected)),
    }
}

fn exact_length<T>(v: &Located<Value>, items: &[T], n: usize, what: &str) -> Result<(), Invalid> {
    if items.len() == n {
        Ok(())
    } else {
        Err(Invalid::at(
            &v.origin,
            format!("expected {n} {what}, got {}", items.len()),
        ))
    }
}

pub(crate) fn scale(v: &Located<Value>) -> Result<Scale, Invalid> {
    match &v.value {
        Value::Int(_) | Value::Float(_) => number(v).map(Scale::Uniform),
        Value::Array(_) => {
            let xs = numbers(v, 3)?;
            Ok(Scale::PerAxis([xs[0], xs[1], xs[2]]))
        }
        _ => Err(v.type_error("a number or an array of 3 numbers")),
    }
}

pub(crate) fn matrix4(v: &Located<Value>) -> Result<[[f32; 4]; 4], Invalid> {
    matrix(v)
}

pub(crate) fn matrix3(v: &Located<Value>) -> Result<[[f32; 3]; 3], Invalid> {
    matrix(v)
}

/// `N` rows of `N` numbers each.
fn matrix<const N: usize>(v: &Located<Value>) -> Result<[[f32; N]; N], Invalid> {
    let rows = array(v, &format!("an array of {N} rows"))?;
    exact_length(v, rows, N, "rows")?;
    let mut m = [[0.0; N]; N];
    for (row, r) in m.iter_mut().zip(rows) {
        let xs = numbers(r, N)?;
        row.copy_from_slice(&xs);
    }
    Ok(m)
}

pub(crate) fn table(v: &Located<Value>) -> Result<&[Prop], Invalid> {
    match &v.value {
        Value::Table(props) => Ok(props),
        _ => Err(v.type_error("a table")),
    }
}

pub(crate) fn distribution(v: &Located<Value>) -> Result<Distribution, Invalid> {
    let name = string(v)?;
    Distribution::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Distribution::SELECTABLE.iter().map(|d| d.name()).collect();
        unknown_choice(v, name, "distribution", &names)
    })
}

pub(crate) fn choice(
    v: &Located<Value>,
    what: &str,
    choices: &[&'static str],
) -> Result<&'static str, Invalid> {
    let name = string(v)?;
    choices
        .iter()
        .copied()
        .find(|c| *c == name)
        .ok_or_else(|| unknown_choice(v, name, what, choices))
}

pub(crate) fn number_or_choice(
    v: &Located<Value>,
    what: &str,
    choices: &[&'static str],
) -> Result<NumberOr, Invalid> {
    match v.value {
        Value::String(_) => choice(v, what, choices).map(NumberOr::Name),
        Value::Int(_) | Value::Float(_) => number(v).map(NumberOr::Number),
        _ => Err(v.type_error("a number or a name")),
    }
}

fn unknown_choice(v: &Located<Value>, name: &str, what: &str, choices: &[&str]) -> Invalid {
    Invalid::at(
        &v.origin,
        format!(
            "unknown {what} `{name}`; valid choices are: {}",
            choices.join(", ")
        ),
    )
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::description::{from_json, from_toml, Kind, SceneError};

    fn scene(text: &str) -> Node {
        from_toml(text, Path::new("test.toml")).unwrap()
    }

    fn shape(text: &str) -> Node {
        scene(text).child(Kind::Shape).unwrap().clone()
    }

    fn err(e: Invalid) -> String {
        SceneError::from(e).to_string()
    }

    #[test]
    fn a_type_error_is_at_the_value() {
        let s = scene("[camera]\nfov = \"wide\"\nup = [0, 1, 0]\n");
        let camera = Props::new(s.child(Kind::Sensor).unwrap());
        assert_eq!(
            err(camera.f32("fov").unwrap_err()),
            "test.toml:2:7: camera.fov: invalid type: string \"wide\", expected a number"
        );
        assert_eq!(camera.numbers::<3>("up"), Ok(Some([0.0, 1.0, 0.0])));
        assert_eq!(camera.f32("aperture"), Ok(None));
        for (read, expected) in [
            (camera.int("fov").map(|_| ()), "an integer"),
            (camera.bool("fov").map(|_| ()), "a boolean"),
            (camera.string("up").map(|_| ()), "a string"),
            (
                camera.numbers::<3>("fov").map(|_| ()),
                "an array of 3 numbers",
            ),
            (
                camera.scale("fov").map(|_| ()),
                "a number or an array of 3 numbers",
            ),
            (camera.matrix4("fov").map(|_| ()), "an array of 4 rows"),
            (camera.table("fov").map(|_| ()), "a table"),
        ] {
            let e = err(read.unwrap_err());
            assert!(e.ends_with(&format!(", expected {expected}")), "{e}");
        }
    }

    #[test]
    fn numbers_are_integers_or_floats_and_integers_only_integers() {
        let s = shape("[[objects]]\ntype = \"sphere\"\na = 2\nb = 2.5\nc = 1e300\nd = true\n");
        let p = Props::new(&s);
        assert_eq!(p.f32("a"), Ok(Some(2.0)));
        assert_eq!(p.f32("b"), Ok(Some(2.5)));
        assert_eq!(p.f32("c"), Ok(Some(f32::INFINITY)));
        assert_eq!(p.int("a"), Ok(Some(2)));
        assert_eq!(
            err(p.int("b").unwrap_err()),
            "test.toml:4:5: objects[0].b: invalid type: floating point `2.5`, expected an integer"
        );
        assert_eq!(p.bool("d"), Ok(Some(true)));
    }

    #[test]
    fn arrays_have_exactly_their_length() {
        let s = shape(
            "[[objects]]\ntype = \"quad\"\norigin = [1, 2, 3, 4]\nedge_u = [1, \"x\", 3]\n\
             [objects.transform]\nscale = [1, 2]\nrotate_axis = 2\n",
        );
        let p = Props::new(&s);
        assert_eq!(
            err(p.numbers::<3>("origin").unwrap_err()),
            "test.toml:3:10: objects[0].origin: expected 3 numbers, got 4"
        );
        assert_eq!(
            err(p.numbers::<3>("edge_u").unwrap_err()),
            "test.toml:4:14: objects[0].edge_u[1]: invalid type: string \"x\", expected a number"
        );
        let t = p.table("transform").unwrap().unwrap();
        assert_eq!(
            err(t.scale("scale").unwrap_err()),
            "test.toml:6:9: objects[0].transform.scale: expected 3 numbers, got 2"
        );
        assert_eq!(t.scale("rotate_axis"), Ok(Some(Scale::Uniform(2.0))));
    }

    #[test]
    fn matrices_have_4_rows_of_4_numbers() {
        let row = "[1, 0, 0, 0]";
        let scene_of = |rows: &[&str]| {
            shape(&format!(
                "[[objects]]\ntype = \"mesh\"\ntransform.matrix = [{}]\n",
                rows.join(", ")
            ))
        };
        let matrix_error = |s: &Node| {
            let p = Props::new(s);
            let t = p.table("transform").unwrap().unwrap();
            err(t.matrix4("matrix").unwrap_err())
        };
        assert_eq!(
            matrix_error(&scene_of(&[row, row, row])),
            "test.toml:3:20: objects[0].transform.matrix: expected 4 rows, got 3"
        );
        assert_eq!(
            matrix_error(&scene_of(&[row, row, row, "[0, 0, 1]"])),
            "test.toml:3:63: objects[0].transform.matrix[3]: expected 4 numbers, got 3"
        );
        let s = scene_of(&[row, "[0, 1, 0, 0]", "[0, 0, 1, 0]", "[0, 0, 0, 1]"]);
        let p = Props::new(&s);
        let m = p.table("transform").unwrap().unwrap().matrix4("matrix");
        assert_eq!(m.unwrap().unwrap()[3], [0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn distributions_and_choices_list_the_valid_names() {
        let s = scene("[render]\ndistribution = \"sobel\"\nfilter = \"tent\"\nspp = 4\n");
        let sensor = s.child(Kind::Sensor).unwrap();
        let sampler = Props::new(sensor.child(Kind::Sampler).unwrap());
        let e = err(sampler.distribution("distribution").unwrap_err());
        let names: Vec<&str> = Distribution::SELECTABLE.iter().map(|d| d.name()).collect();
        assert_eq!(
            e,
            format!(
                "test.toml:2:16: render.distribution: unknown distribution `sobel`; valid choices are: {}",
                names.join(", ")
            )
        );
        assert!(e.contains("custom"));
        let film = Props::new(sensor.child(Kind::Film).unwrap());
        assert_eq!(
            film.choice("filter", "filter", &["box", "tent", "gaussian"]),
            Ok(Some("tent"))
        );
        let e = film
            .choice("filter", "pixel filter", &["box", "gaussian"])
            .unwrap_err();
        assert_eq!(
            err(e),
            "test.toml:3:10: render.filter: unknown pixel filter `tent`; valid choices are: box, gaussian"
        );
        let json: serde_json::Value =
            serde_json::from_str(r#"{"render": {"distribution": "Semi_Jitter"}}"#).unwrap();
        let s = from_json(&json).unwrap();
        let sampler = s.child(Kind::Sensor).unwrap().child(Kind::Sampler).unwrap();
        assert_eq!(
            Props::new(sampler).distribution("distribution"),
            Ok(Some(Distribution::SemiJitter))
        );
    }

    #[test]
    fn finish_names_the_first_property_never_read() {
        let s = shape(
            "[[objects]]\ntype = \"sphere\"\nradius = 1\ncentre = [0, 0, 0]\nsmooth = true\n",
        );
        let p = Props::new(&s);
        assert!(p.has("centre") && p.has("smooth") && !p.has("center"));
        assert_eq!(p.f32("radius"), Ok(Some(1.0)));
        let unused: Vec<&str> = p.unused().iter().map(|p| p.name.as_str()).collect();
        assert_eq!(unused, ["centre", "smooth"]);
        assert_eq!(
            err(p.finish("sphere").unwrap_err()),
            "test.toml:4:1: objects[0].centre: unused property `centre` of a sphere"
        );
        assert!(p.get("centre").is_some());
        assert!(p.bool("smooth").is_ok());
        assert_eq!(p.finish("sphere"), Ok(()));
    }

    #[test]
    fn errors_are_at_the_value_or_else_at_the_node() {
        let s = shape("[[objects]]\ntype = \"quad\"\norigin = [0, 0, 0]\n");
        let p = Props::new(&s);
        assert_eq!(
            err(p.error("origin", "must differ")),
            "test.toml:3:10: objects[0].origin: must differ"
        );
        assert_eq!(
            err(p.error("edge_u", "is required")),
            "test.toml:1:1: objects[0].edge_u: is required"
        );
        assert_eq!(
            err(p.node_error("a quad needs `edge_u`")),
            "test.toml:1:1: objects[0]: a quad needs `edge_u`"
        );
        assert_eq!(
            p.origin("origin").map(|o| o.path.to_string()),
            Some("objects[0].origin".into())
        );
        assert_eq!(p.node_origin().path.to_string(), "objects[0]");
    }
}
