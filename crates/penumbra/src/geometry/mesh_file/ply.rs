//! Stanford PLY reader (ASCII and both binary byte orders).
//!
//! The `vertex` element gives the positions (`x`, `y`, `z`, required), normals
//! (`nx`, `ny`, `nz`, when all three are present) and texture coordinates: the
//! first pair present, in this order, of `u`/`v`, `s`/`t`, `texture_u`/`texture_v`
//! and `texture_s`/`texture_t` (names as written, lower case; numbers of any
//! type, not lists). A vertex with only one property of a pair has no texture
//! coordinates from it. The `face` element's `vertex_indices` (or `vertex_index`)
//! list gives polygons, fan-triangulated. Other elements are skipped.
//!
//! Other number properties of `vertex` and `face` are read as Mitsuba reads
//! them, as mesh attributes ([`MeshAttribute`]): `r, g, b` (or `red, green,
//! blue`), with `a` (or `alpha`) if there, as `vertex_color` / `face_color`;
//! consecutive properties `P_x, P_y, P_z` (or `P_r, P_g, P_b`, `P_0, P_1,
//! P_2`, `P_1, P_2, P_3`) as `vertex_P` (`vertex_P_color` for `r, g, b`),
//! one such property alone as a 1-value attribute; other properties are
//! skipped. Integer values are taken as Mitsuba takes them: over their
//! type's largest value (255 for `uchar`), then decoded from sRGB.
//!
//! Files come from scanners, converters and the internet, so every count and index in
//! them is treated as untrusted: allocations are bounded by the bytes actually present
//! and all reads are checked, so a corrupt file yields an error naming the spot rather
//! than a panic or an out-of-memory abort.

mod header;
mod source;

use std::path::Path;

use self::header::{parse_header, Element, Format, Header, PropKind, Scalar};
use self::source::{AsciiSource, BinarySource, Fallible, Source};
use super::error::{Location, MeshAttribute, MeshData, MeshError};

/// Polygons with more corners than this are taken as a corrupt list count. Real files
/// stay far below it, while a garbage count of billions would otherwise be read as one
/// enormous face.
const MAX_FACE_CORNERS: i64 = 1 << 16;

pub fn read_ply(path: &Path) -> Result<MeshData, MeshError> {
    let mut file = super::open::open_mesh(path)?;
    let head = file
        .read_head(super::open::HEAD)
        .map_err(MeshError::input)?;
    // Not a PLY file from its first line: refused without reading the rest.
    let first = head.split(|&b| b == b'\n').next().unwrap_or_default();
    if first.trim_ascii() != b"ply" {
        return parse_ply(&head, path);
    }
    let bytes = file.read_rest(head).map_err(MeshError::input)?;
    parse_ply(&bytes, path)
}

/// Parses PLY bytes; `path` is used only in error messages.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<MeshData, MeshError> {
    let header = parse_header(bytes, path)?;
    let plans = plan_elements(&header, path)?;
    match header.format {
        Format::Ascii => {
            let mut source = AsciiSource::new(bytes, &header, path);
            read_body(&mut source, &header, &plans).map_err(|e| *e)
        }
        Format::BinaryLittleEndian | Format::BinaryBigEndian => {
            let big_endian = header.format == Format::BinaryBigEndian;
            let mut source = BinarySource::new(bytes, header.body_start, big_endian, path);
            read_body(&mut source, &header, &plans).map_err(|e| *e)
        }
    }
}

/// What to do with one property of one element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Action {
    Position(usize, Scalar),
    Normal(usize, Scalar),
    Uv(usize, Scalar),
    Corners {
        count: Scalar,
        item: Scalar,
    },
    /// A value of an attribute: its place among the record's attribute
    /// values.
    Attribute(usize, Scalar),
    Skip(PropKind),
}

/// The attributes an element's properties make: each its name and its
/// number of values, in the order of [`Action::Attribute`]'s places.
type Groups = Vec<(String, usize)>;

#[derive(Clone, Debug, PartialEq, Eq)]
enum Plan {
    Vertices {
        actions: Vec<Action>,
        normals: bool,
        uvs: bool,
        groups: Groups,
    },
    Faces {
        actions: Vec<Action>,
        vertex_count: u64,
        groups: Groups,
    },
    Skip,
}

/// Decides, before touching the body, how each element is used, so header mistakes
/// (a vertex without `z`, a face without indices) are reported at their header line.
fn plan_elements(header: &Header, path: &Path) -> Result<Vec<Plan>, MeshError> {
    let vertex = single_element(header, "vertex", path)?;
    let Some(vertex) = vertex else {
        let message = "the file has no `vertex` element";
        let line = header.end_line;
        return Err(MeshError::parse(path, line_start(line), message));
    };
    if vertex.count > u64::from(u32::MAX) {
        let message = format!(
            "{} vertices are more than 32-bit indices can address",
            vertex.count
        );
        return Err(MeshError::parse(path, vertex.location(), message));
    }
    single_element(header, "face", path)?;
    let mut plans = Vec::with_capacity(header.elements.len());
    for element in &header.elements {
        plans.push(match element.name.as_str() {
            "vertex" => vertex_plan(element, path)?,
            "face" => face_plan(element, vertex.count, path)?,
            _ => Plan::Skip,
        });
    }
    Ok(plans)
}

fn line_start(line: usize) -> Location {
    Location::LineColumn { line, column: 1 }
}

/// Finds the element called `name`, rejecting duplicates, whose meaning would be ambiguous.
fn single_element<'h>(
    header: &'h Header,
    name: &str,
    path: &Path,
) -> Result<Option<&'h Element>, MeshError> {
    let mut found = header.elements.iter().filter(|e| e.name == name);
    let first = found.next();
    match found.next() {
        Some(second) => {
            let message = format!("a second `{name}` element");
            Err(MeshError::parse(path, second.location(), message))
        }
        None => Ok(first),
    }
}

fn scalar_named(element: &Element, name: &str, path: &Path) -> Result<Option<Scalar>, MeshError> {
    match element
        .props
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.kind)
    {
        None => Ok(None),
        Some(PropKind::Scalar(t)) => Ok(Some(t)),
        Some(PropKind::List { .. }) => {
            let message = format!("vertex property `{name}` is a list; expected a number");
            Err(MeshError::parse(path, element.location(), message))
        }
    }
}

fn vertex_plan(element: &Element, path: &Path) -> Result<Plan, MeshError> {
    for axis in ["x", "y", "z"] {
        if scalar_named(element, axis, path)?.is_none() {
            let message = format!("the `vertex` element has no `{axis}` property");
            return Err(MeshError::parse(path, element.location(), message));
        }
    }
    let mut normals = true;
    for axis in ["nx", "ny", "nz"] {
        normals &= scalar_named(element, axis, path)?.is_some();
    }
    let uv = uv_names(element);
    let reserved = |name: &str| {
        ["x", "y", "z", "nx", "ny", "nz", "u", "v"].contains(&name)
            || uv.is_some_and(|(u, v)| name == u || name == v)
    };
    let (groups, places) = attribute_groups(element, reserved);
    let actions = element
        .props
        .iter()
        .zip(&places)
        .map(|(p, place)| match (p.name.as_str(), p.kind) {
            ("x", PropKind::Scalar(t)) => Action::Position(0, t),
            ("y", PropKind::Scalar(t)) => Action::Position(1, t),
            ("z", PropKind::Scalar(t)) => Action::Position(2, t),
            ("nx", PropKind::Scalar(t)) if normals => Action::Normal(0, t),
            ("ny", PropKind::Scalar(t)) if normals => Action::Normal(1, t),
            ("nz", PropKind::Scalar(t)) if normals => Action::Normal(2, t),
            (name, PropKind::Scalar(t)) if uv.is_some_and(|(u, _)| u == name) => Action::Uv(0, t),
            (name, PropKind::Scalar(t)) if uv.is_some_and(|(_, v)| v == name) => Action::Uv(1, t),
            (_, PropKind::Scalar(t)) if place.is_some() => Action::Attribute(place.unwrap_or(0), t),
            (_, kind) => Action::Skip(kind),
        })
        .collect();
    Ok(Plan::Vertices {
        actions,
        normals,
        uvs: uv.is_some(),
        groups: named("vertex_", groups),
    })
}

/// Mitsuba's names: `vertex_NAME`, `face_NAME`.
fn named(prefix: &str, groups: Groups) -> Groups {
    groups
        .into_iter()
        .map(|(name, dim)| (format!("{prefix}{name}"), dim))
        .collect()
}

/// Groups the number properties of `element` (but the `reserved` ones) into
/// attributes as Mitsuba's PLY reader does (see the [module docs](self)):
/// the attributes (name without `vertex_`/`face_`, values) and, for each
/// property, its place among a record's attribute values, if it has one.
fn attribute_groups(
    element: &Element,
    reserved: impl Fn(&str) -> bool,
) -> (Groups, Vec<Option<usize>>) {
    let props = &element.props;
    let number = |i: usize| matches!(props[i].kind, PropKind::Scalar(_));
    let find = |name: &str| (0..props.len()).find(|&i| number(i) && props[i].name == name);
    let mut members: Vec<(String, Vec<usize>)> = Vec::new();
    for names in [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]] {
        if let (Some(r), Some(g), Some(b)) = (find(names[0]), find(names[1]), find(names[2])) {
            let mut of = vec![r, g, b];
            of.extend(find(names[3]));
            members.push(("color".to_string(), of));
            break;
        }
    }
    // The colour's properties, and the names kept for it.
    let colour: Vec<usize> = members.iter().flat_map(|(_, of)| of.clone()).collect();
    let taken = |i: usize| {
        !number(i)
            || reserved(&props[i].name)
            || ["r", "g", "b", "a"].contains(&props[i].name.as_str())
            || colour.contains(&i)
    };
    // The postfixes of the components, by kind (x y z w, r g b a, 0 1 2 3,
    // 1 2 3 4): component k of kind j is `POSTFIXES[k][j]`.
    const POSTFIXES: [&[u8; 4]; 4] = [b"xr01", b"yg12", b"zb23", b"wa34"];
    let mut seen: Vec<String> = Vec::new();
    let mut current: Option<(String, usize, Vec<usize>)> = None;
    let flush = |current: &mut Option<(String, usize, Vec<usize>)>,
                 members: &mut Vec<(String, Vec<usize>)>,
                 seen: &mut Vec<String>| {
        if let Some((prefix, kind, of)) = current.take() {
            if matches!(of.len(), 1 | 3) && !seen.contains(&prefix) {
                let name = if kind == 1 {
                    format!("{prefix}_color")
                } else {
                    prefix.clone()
                };
                seen.push(prefix);
                members.push((name, of));
            }
        }
    };
    for (i, prop) in props.iter().enumerate() {
        if taken(i) {
            continue;
        }
        let name = prop.name.as_str();
        let split = name.rfind('_').map(|at| (&name[..at], &name[at + 1..]));
        let Some((prefix, postfix)) = split.filter(|(_, post)| post.len() == 1) else {
            flush(&mut current, &mut members, &mut seen);
            continue;
        };
        let c = postfix.as_bytes()[0];
        if current.as_ref().is_some_and(|(p, _, _)| p != prefix) {
            flush(&mut current, &mut members, &mut seen);
        }
        match &mut current {
            None => {
                if seen.iter().any(|p| p == prefix) {
                    continue;
                }
                if let Some(kind) = POSTFIXES[0].iter().position(|&p| p == c) {
                    current = Some((prefix.to_string(), kind, vec![i]));
                }
            }
            Some((_, kind, of)) => {
                if of.len() < POSTFIXES.len() && POSTFIXES[of.len()][*kind] == c {
                    of.push(i);
                } else {
                    current = None;
                }
            }
        }
    }
    flush(&mut current, &mut members, &mut seen);
    let mut places = vec![None; props.len()];
    let mut next = 0;
    let mut groups = Vec::with_capacity(members.len());
    for (name, of) in members {
        for &i in &of {
            places[i] = Some(next);
            next += 1;
        }
        groups.push((name, of.len()));
    }
    (groups, places)
}

/// Names of texture coordinate pairs, the first present one used.
const UV_NAMES: [(&str, &str); 4] = [
    ("u", "v"),
    ("s", "t"),
    ("texture_u", "texture_v"),
    ("texture_s", "texture_t"),
];

/// The texture coordinate pair a vertex element has, if any: the first of
/// [`UV_NAMES`] whose two properties are both numbers.
fn uv_names(element: &Element) -> Option<(&'static str, &'static str)> {
    let number = |name: &str| {
        element
            .props
            .iter()
            .any(|p| p.name == name && matches!(p.kind, PropKind::Scalar(_)))
    };
    UV_NAMES.into_iter().find(|&(u, v)| number(u) && number(v))
}

fn face_plan(element: &Element, vertex_count: u64, path: &Path) -> Result<Plan, MeshError> {
    let is_indices = |name: &str| name == "vertex_indices" || name == "vertex_index";
    let mut found = false;
    let mut actions = Vec::with_capacity(element.props.len());
    let (groups, places) = attribute_groups(element, |_| false);
    for (prop, place) in element.props.iter().zip(places) {
        let action = match prop.kind {
            PropKind::List { count, item } if !found && is_indices(&prop.name) => {
                if !item.is_integer() {
                    let message = format!(
                        "face indices must have an integer type, not {}",
                        item.name()
                    );
                    return Err(MeshError::parse(path, element.location(), message));
                }
                found = true;
                Action::Corners { count, item }
            }
            PropKind::Scalar(t) if place.is_some() => Action::Attribute(place.unwrap_or(0), t),
            kind => Action::Skip(kind),
        };
        actions.push(action);
    }
    if !found {
        let message = "the `face` element has no `vertex_indices` list property";
        return Err(MeshError::parse(path, element.location(), message));
    }
    Ok(Plan::Faces {
        actions,
        vertex_count,
        groups: named("face_", groups),
    })
}

fn read_body<S: Source>(source: &mut S, header: &Header, plans: &[Plan]) -> Fallible<MeshData> {
    let mut mesh = MeshData::default();
    for (element, plan) in header.elements.iter().zip(plans) {
        // A property-less element stores nothing, and looping over its (untrusted) count
        // would only burn time.
        if element.props.is_empty() {
            continue;
        }
        source.start_element(element);
        match plan {
            Plan::Vertices {
                actions,
                normals,
                uvs,
                groups,
            } => {
                let with = Attributes {
                    normals: *normals,
                    uvs: *uvs,
                };
                let mut values = Values::new(groups, false);
                read_vertices(source, element, actions, with, &mut mesh, &mut values)?;
                mesh.attributes.extend(values.attributes);
            }
            Plan::Faces {
                actions,
                vertex_count,
                groups,
            } => {
                let faces = FaceReader {
                    actions,
                    vertex_count: *vertex_count,
                };
                let mut values = Values::new(groups, true);
                faces.read(source, element, &mut mesh.triangles, &mut values)?;
                mesh.attributes.extend(values.attributes);
            }
            Plan::Skip => skip_element(source, element)?,
        }
    }
    source.finish()?;
    Ok(mesh)
}

fn skip_element<S: Source>(source: &mut S, element: &Element) -> Fallible<()> {
    for index in 0..element.count {
        source.begin_record(index)?;
        for prop in &element.props {
            source.skip(prop.kind, &prop.name)?;
        }
        source.end_record()?;
    }
    Ok(())
}

/// Which vertex attributes besides positions the file has.
#[derive(Clone, Copy, Debug)]
struct Attributes {
    normals: bool,
    uvs: bool,
}

/// The attributes of an element as they are read: one record's values,
/// then each attribute's.
struct Values {
    record: Vec<f32>,
    attributes: Vec<MeshAttribute>,
}

impl Values {
    fn new(groups: &Groups, per_face: bool) -> Values {
        Values {
            record: vec![0.0; groups.iter().map(|g| g.1).sum()],
            attributes: groups
                .iter()
                .map(|(name, dim)| MeshAttribute {
                    name: name.clone(),
                    per_face,
                    dim: *dim,
                    values: Vec::new(),
                })
                .collect(),
        }
    }

    /// Reads value `place` of the record, of type `t`, as Mitsuba does:
    /// an integer over its type's largest value, then decoded from sRGB.
    /// Values are kept as they are, finite or not, as Mitsuba keeps them (a
    /// scene is refused for them only where a texture reads them).
    fn read<S: Source>(
        &mut self,
        source: &mut S,
        place: usize,
        t: Scalar,
        name: &str,
    ) -> Fallible<()> {
        let raw = source.number(t, name)?;
        let value = match t {
            Scalar::F32 | Scalar::F64 => raw as f32,
            _ => {
                let max = match t {
                    Scalar::I8 => f64::from(i8::MAX),
                    Scalar::U8 => f64::from(u8::MAX),
                    Scalar::I16 => f64::from(i16::MAX),
                    Scalar::U16 => f64::from(u16::MAX),
                    Scalar::I32 => f64::from(i32::MAX),
                    _ => f64::from(u32::MAX),
                };
                srgb_decode((raw / max) as f32)
            }
        };
        if let Some(slot) = self.record.get_mut(place) {
            *slot = value;
        }
        Ok(())
    }

    /// Keeps the record's values `times` times (a face's for each triangle
    /// of its fan).
    fn keep(&mut self, times: usize) {
        let mut at = 0;
        for a in &mut self.attributes {
            let values = &self.record[at..at + a.dim];
            for _ in 0..times {
                a.values.extend_from_slice(values);
            }
            at += a.dim;
        }
    }
}

/// An sRGB-encoded value in [0, 1] decoded to linear (negative values, from
/// signed integers, keep their sign).
fn srgb_decode(v: f32) -> f32 {
    let a = v.abs();
    let linear = if a <= 0.04045 {
        a / 12.92
    } else {
        ((a + 0.055) / 1.055).powf(2.4)
    };
    linear.copysign(v)
}

fn read_vertices<S: Source>(
    source: &mut S,
    element: &Element,
    actions: &[Action],
    with: Attributes,
    mesh: &mut MeshData,
    values: &mut Values,
) -> Fallible<()> {
    let capacity = source.capacity(element);
    mesh.positions.reserve_exact(capacity);
    let mut normals = with.normals.then(|| Vec::with_capacity(capacity));
    let mut uvs = with.uvs.then(|| Vec::with_capacity(capacity));
    for index in 0..element.count {
        source.begin_record(index)?;
        let mut position = [0.0; 3];
        let mut normal = [0.0; 3];
        let mut uv = [0.0; 2];
        for (action, prop) in actions.iter().zip(&element.props) {
            let (slot, t) = match *action {
                Action::Position(axis, t) => (position.get_mut(axis), t),
                Action::Normal(axis, t) => (normal.get_mut(axis), t),
                Action::Uv(axis, t) => (uv.get_mut(axis), t),
                Action::Attribute(place, t) => {
                    values.read(source, place, t, &prop.name)?;
                    continue;
                }
                Action::Corners { .. } | Action::Skip(_) => {
                    source.skip(prop.kind, &prop.name)?;
                    continue;
                }
            };
            let value = finite_value(source, t, &prop.name, index)?;
            if let Some(slot) = slot {
                *slot = value;
            }
        }
        source.end_record()?;
        values.keep(1);
        mesh.positions.push(position);
        if let Some(normals) = &mut normals {
            normals.push(normal);
        }
        if let Some(uvs) = &mut uvs {
            uvs.push(uv);
        }
    }
    mesh.normals = normals;
    mesh.uvs = uvs;
    Ok(())
}

/// Reads a vertex value as `f32`, rejecting NaN and infinities (including doubles too
/// large for `f32`), which would otherwise poison bounding boxes and the BVH.
fn finite_value<S: Source>(source: &mut S, t: Scalar, name: &str, vertex: u64) -> Fallible<f32> {
    let value = source.number(t, name)? as f32;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(source.error(format!(
            "vertex {vertex}: `{name}` is {value}; vertex data must be finite"
        )))
    }
}

/// The face element's index list, as declared.
struct List<'a> {
    count: Scalar,
    item: Scalar,
    name: &'a str,
}

struct FaceReader<'a> {
    actions: &'a [Action],
    vertex_count: u64,
}

impl FaceReader<'_> {
    fn read<S: Source>(
        &self,
        source: &mut S,
        element: &Element,
        out: &mut Vec<[u32; 3]>,
        values: &mut Values,
    ) -> Fallible<()> {
        // Most faces are triangles; polygons only make the vector grow past this.
        out.reserve_exact(source.capacity(element));
        for index in 0..element.count {
            source.begin_record(index)?;
            let before = out.len();
            for (action, prop) in self.actions.iter().zip(&element.props) {
                match *action {
                    Action::Corners { count, item } => {
                        let list = List {
                            count,
                            item,
                            name: &prop.name,
                        };
                        self.polygon(source, index, list, out)?
                    }
                    Action::Attribute(place, t) => values.read(source, place, t, &prop.name)?,
                    _ => source.skip(prop.kind, &prop.name)?,
                }
            }
            source.end_record()?;
            values.keep(out.len() - before);
        }
        Ok(())
    }

    /// Reads one polygon and fan-triangulates it on the fly, which is exact for the
    /// convex polygons scanners and modellers write and needs no per-face buffer.
    fn polygon<S: Source>(
        &self,
        source: &mut S,
        face: u64,
        list: List,
        out: &mut Vec<[u32; 3]>,
    ) -> Fallible<()> {
        let corners = source.integer(list.count, list.name)?;
        if corners < 3 {
            return Err(source.error(format!(
                "face {face} has {corners} vertices; at least 3 are needed"
            )));
        }
        if corners > MAX_FACE_CORNERS {
            let message = format!(
                "face {face} claims {corners} vertices, more than the {MAX_FACE_CORNERS} accepted"
            );
            return Err(source.error(message));
        }
        let first = self.index(source, face, 0, &list)?;
        let mut previous = self.index(source, face, 1, &list)?;
        for corner in 2..corners {
            let current = self.index(source, face, corner, &list)?;
            out.push([first, previous, current]);
            previous = current;
        }
        Ok(())
    }

    #[inline(always)]
    fn index<S: Source>(
        &self,
        source: &mut S,
        face: u64,
        corner: i64,
        list: &List,
    ) -> Fallible<u32> {
        let value = source.integer(list.item, list.name)?;
        match u32::try_from(value) {
            Ok(index) if u64::from(index) < self.vertex_count => Ok(index),
            _ => Err(self.bad_index(source, face, corner, value)),
        }
    }

    #[cold]
    fn bad_index<S: Source>(
        &self,
        source: &S,
        face: u64,
        corner: i64,
        value: i64,
    ) -> Box<MeshError> {
        let problem = if value < 0 {
            format!("negative vertex index {value}")
        } else {
            let count = self.vertex_count;
            format!("vertex index {value} is out of range (the file has {count} vertices)")
        };
        source.error(format!("face {face}, corner {corner}: {problem}"))
    }
}

#[cfg(test)]
mod tests {
    use std::fmt::Write as _;
    use std::time::{Duration, Instant};

    use super::*;

    const POSITIONS: [[f32; 3]; 9] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.0, 0.5],
        [3.0, 0.0, 0.5],
        [3.0, 1.0, 0.5],
        [2.5, 2.0, 0.5],
        [2.0, 1.0, -0.25],
    ];
    /// A triangle, a quad and a pentagon.
    const FACES: [&[i32]; 3] = [&[0, 1, 3], &[0, 1, 2, 3], &[4, 5, 6, 7, 8]];
    const FANS: [[u32; 3]; 6] = [
        [0, 1, 3],
        [0, 1, 2],
        [0, 2, 3],
        [4, 5, 6],
        [4, 6, 7],
        [4, 7, 8],
    ];
    /// An unknown element whose list must be skipped (named like the face list, to be sure
    /// only the `face` element's list is taken as indices).
    const EDGES: [(&[i32], i32); 2] = [(&[0, 1], 7), (&[4, 5, 6], -2)];

    fn normal(i: usize) -> [f32; 3] {
        [0.0, i as f32 / 16.0, 1.0]
    }

    fn expected() -> MeshData {
        MeshData {
            positions: POSITIONS.to_vec(),
            normals: Some((0..POSITIONS.len()).map(normal).collect()),
            uvs: None,
            triangles: FANS.to_vec(),
            attributes: Vec::new(),
        }
    }

    fn header(format: &str) -> String {
        format!(
            "ply\r\nformat {format} 1.0\r\ncomment test mesh\nelement vertex 9\nproperty float x\n\
             property float y\nproperty float z\nproperty float nx\nproperty float ny\n\
             property float nz\nproperty uchar red\nelement edge 2\n\
             property list uchar int vertex_indices\nproperty int crease\nelement face 3\n\
             property uchar flags\nproperty list uchar int vertex_indices\nend_header\n"
        )
    }

    fn ascii_mesh() -> Vec<u8> {
        let mut text = header("ascii");
        for (i, [x, y, z]) in POSITIONS.iter().enumerate() {
            let [nx, ny, nz] = normal(i);
            writeln!(text, "{x} {y} {z} {nx} {ny} {nz} 200").unwrap();
        }
        for (list, crease) in EDGES {
            let items: Vec<String> = list.iter().map(i32::to_string).collect();
            writeln!(text, "{} {} {crease}", list.len(), items.join(" ")).unwrap();
        }
        for (flags, face) in FACES.iter().enumerate() {
            let items: Vec<String> = face.iter().map(i32::to_string).collect();
            writeln!(text, " {flags}\t{} {}\r", face.len(), items.join("  ")).unwrap();
        }
        text.into_bytes()
    }

    /// Writes binary PLY values in either byte order.
    struct Writer {
        big: bool,
        out: Vec<u8>,
    }

    impl Writer {
        fn new(header: &str, big: bool) -> Self {
            Writer {
                big,
                out: header.as_bytes().to_vec(),
            }
        }

        fn put<const N: usize>(&mut self, le: [u8; N], be: [u8; N]) -> &mut Self {
            self.out.extend_from_slice(if self.big { &be } else { &le });
            self
        }

        fn f32(&mut self, v: f32) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }

        fn f64(&mut self, v: f64) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }

        fn i32(&mut self, v: i32) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }

        fn u32(&mut self, v: u32) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }

        fn i16(&mut self, v: i16) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }

        fn u16(&mut self, v: u16) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }

        fn u8(&mut self, v: u8) -> &mut Self {
            self.put([v], [v])
        }

        fn i8(&mut self, v: i8) -> &mut Self {
            self.put(v.to_le_bytes(), v.to_be_bytes())
        }
    }

    fn binary_mesh(big: bool) -> Vec<u8> {
        let format = if big {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut w = Writer::new(&header(format), big);
        for (i, position) in POSITIONS.iter().enumerate() {
            for v in position.iter().chain(&normal(i)) {
                w.f32(*v);
            }
            w.u8(200);
        }
        for (list, crease) in EDGES {
            w.u8(list.len() as u8);
            for &i in list {
                w.i32(i);
            }
            w.i32(crease);
        }
        for (flags, face) in FACES.iter().enumerate() {
            w.u8(flags as u8).u8(face.len() as u8);
            for &i in face.iter() {
                w.i32(i);
            }
        }
        w.out
    }

    /// Byte offsets in [`binary_mesh`]: vertices take 25 bytes, the edges 13 and 17.
    fn face_offset(face: usize) -> usize {
        let body = header("binary_little_endian").len();
        body + 9 * 25 + 30 + [0, 14, 32, 54][face]
    }

    fn parse(bytes: &[u8]) -> Result<MeshData, MeshError> {
        parse_ply(bytes, Path::new("test.ply"))
    }

    /// Asserts a parse error at `location` whose message contains every needle.
    fn assert_error(bytes: &[u8], location: Location, needles: &[&str]) {
        match parse(bytes) {
            Err(MeshError::Parse {
                location: got,
                message,
                ..
            }) => {
                assert_eq!(got, location, "{message}");
                for needle in needles {
                    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
                }
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    fn at(line: usize, column: usize) -> Location {
        Location::LineColumn { line, column }
    }

    fn byte(offset: usize) -> Location {
        Location::ByteOffset(offset as u64)
    }

    /// A one-triangle ASCII file: header lines 1-9, vertices from line 10.
    fn small_ascii(vertex_count: u64, vertices: &str, face_count: u64, faces: &str) -> Vec<u8> {
        format!(
            "ply\nformat ascii 1.0\nelement vertex {vertex_count}\nproperty float x\nproperty float y\n\
             property float z\nelement face {face_count}\nproperty list uchar int vertex_indices\n\
             end_header\n{vertices}{faces}"
        )
        .into_bytes()
    }

    const TRIANGLE: &str = "0 0 0\n1 0 0\n0 1 0\n";

    /// A binary little-endian file holding [`TRIANGLE`]'s vertices, with a chosen face
    /// list type; the body starts at the returned offset.
    fn small_binary(vertex_count: u64, face_list: &str, face_count: u64) -> (Writer, usize) {
        let header = format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex {vertex_count}\nproperty float x\n\
             property float y\nproperty float z\nelement face {face_count}\n\
             property list {face_list} vertex_indices\nend_header\n"
        );
        let mut w = Writer::new(&header, false);
        for v in TRIANGLE.split_whitespace() {
            w.f32(v.parse().unwrap());
        }
        (w, header.len())
    }

    #[test]
    fn ascii_and_both_binary_orders_give_identical_meshes() {
        let ascii = parse(&ascii_mesh()).unwrap();
        assert_eq!(ascii, expected());
        assert_eq!(parse(&binary_mesh(false)).unwrap(), expected());
        assert_eq!(parse(&binary_mesh(true)).unwrap(), expected());
    }

    #[test]
    fn quads_and_pentagons_are_fan_triangulated() {
        let faces = "4 0 1 2 3\n5 4 0 1 2 3\n";
        let vertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 2 0\n";
        let mesh = parse(&small_ascii(5, vertices, 2, faces)).unwrap();
        let fans = vec![[0, 1, 2], [0, 2, 3], [4, 0, 1], [4, 1, 2], [4, 2, 3]];
        assert_eq!(mesh.triangles, fans);
        assert_eq!(mesh.normals, None);
    }

    #[test]
    fn binary_skips_unknown_elements_with_lists_in_any_order() {
        let header = "ply\nformat binary_big_endian 1.0\nelement face 1\n\
                      property list uchar uint vertex_index\nelement material 2\n\
                      property list ushort double weights\nproperty list uchar char tag\n\
                      element vertex 3\nproperty double x\nproperty double y\nproperty double z\n\
                      end_header\n";
        let mut w = Writer::new(header, true);
        w.u8(3).u32(2).u32(1).u32(0);
        for len in [300u16, 0] {
            w.u16(len);
            for i in 0..len {
                w.f64(f64::from(i));
            }
            w.u8(2).i8(-1).i8(1);
        }
        for v in TRIANGLE.split_whitespace() {
            w.f64(v.parse().unwrap());
        }
        let mesh = parse(&w.out).unwrap();
        assert_eq!(mesh.triangles, vec![[2, 1, 0]]);
        assert_eq!(
            mesh.positions,
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        );
    }

    #[test]
    fn every_scalar_type_reads_as_a_coordinate() {
        let header = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty int8 x\n\
                      property uint16 y\nproperty float64 z\nproperty short a\nproperty uint b\n\
                      property int32 c\nproperty uchar d\nproperty float32 e\nelement face 1\n\
                      property list uint16 int16 vertex_indices\nend_header\n";
        let mut w = Writer::new(header, false);
        w.i8(-5)
            .u16(60000)
            .f64(0.25)
            .i16(1)
            .u32(2)
            .i32(3)
            .u8(4)
            .f32(5.0);
        w.i8(7).u16(1).f64(-1.5).i16(1).u32(2).i32(3).u8(4).f32(5.0);
        w.u16(3).i16(0).i16(1).i16(1);
        let mesh = parse(&w.out).unwrap();
        assert_eq!(
            mesh.positions,
            vec![[-5.0, 60000.0, 0.25], [7.0, 1.0, -1.5]]
        );
        assert_eq!(mesh.triangles, vec![[0, 1, 1]]);
    }

    #[test]
    fn a_file_without_faces_is_a_point_set() {
        let text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                    property float z\nend_header\n1 2 3\n\n";
        let mesh = parse(text.as_bytes()).unwrap();
        assert_eq!(
            (mesh.positions, mesh.triangles.len()),
            (vec![[1.0, 2.0, 3.0]], 0)
        );
    }

    #[test]
    fn ascii_errors_give_line_and_column() {
        let bad_index = small_ascii(3, TRIANGLE, 1, "3 0 1 9\n");
        assert_error(
            &bad_index,
            at(13, 7),
            &["face 0", "corner 2", "index 9", "3 vertices"],
        );
        let negative = small_ascii(3, TRIANGLE, 1, "3 0 -1 2\n");
        assert_error(
            &negative,
            at(13, 5),
            &["face 0", "negative vertex index -1"],
        );
        let nan = small_ascii(3, "0 0 0\n1 nan 0\n0 1 0\n", 1, "3 0 1 2\n");
        assert_error(&nan, at(11, 3), &["vertex 1", "`y`", "finite"]);
        let too_big_for_f32 = small_ascii(3, "0 0 0\n1 0 0\n0 1 1e39\n", 1, "3 0 1 2\n");
        assert_error(&too_big_for_f32, at(12, 5), &["vertex 2", "finite"]);
        let two_corners = small_ascii(3, TRIANGLE, 1, "2 0 1\n");
        assert_error(
            &two_corners,
            at(13, 1),
            &["face 0 has 2 vertices", "at least 3"],
        );
        let trailing = small_ascii(3, "0 0 0 7\n1 0 0\n0 1 0\n", 1, "3 0 1 2\n");
        assert_error(&trailing, at(10, 7), &["vertex 0", "extra value `7`"]);
        let garbled = small_ascii(3, "0 0 abc\n1 0 0\n0 1 0\n", 1, "3 0 1 2\n");
        assert_error(&garbled, at(10, 5), &["expected a number for `z`", "`abc`"]);
        let short = small_ascii(3, "0 0\n1 0 0\n0 1 0\n", 1, "3 0 1 2\n");
        assert_error(&short, at(10, 4), &["vertex 0", "ends before property `z`"]);
        let overflow = small_ascii(3, TRIANGLE, 1, "300 0 1 2\n");
        assert_error(&overflow, at(13, 1), &["300 does not fit", "uchar"]);
        let leftover = small_ascii(3, TRIANGLE, 1, "3 0 1 2\n\n0 0 0\n");
        assert_error(&leftover, at(15, 1), &["after the last element"]);
        let truncated = small_ascii(3, "0 0 0\n", 1, "");
        assert_error(
            &truncated,
            at(11, 1),
            &["file ends before vertex 1 of 3", "truncated"],
        );
    }

    #[test]
    fn binary_errors_give_the_byte_offset() {
        let (mut w, body) = small_binary(3, "uchar int", 1);
        w.u8(3).i32(0).i32(1).i32(3);
        assert_error(
            &w.out,
            byte(body + 36 + 9),
            &["face 0, corner 2", "index 3", "3 vertices"],
        );
        let (mut w, body) = small_binary(3, "uchar int", 1);
        w.u8(3).i32(0).i32(-7).i32(2);
        assert_error(
            &w.out,
            byte(body + 36 + 5),
            &["corner 1", "negative vertex index -7"],
        );
        let (mut w, body) = small_binary(3, "int uint", 1);
        w.i32(2_000_000_000).u32(0).u32(1).u32(2);
        assert_error(
            &w.out,
            byte(body + 36),
            &["face 0 claims 2000000000 vertices"],
        );
        let (mut w, body) = small_binary(3, "int uint", 1);
        w.i32(-3);
        assert_error(&w.out, byte(body + 36), &["face 0 has -3 vertices"]);
        let (mut w, body) = small_binary(4, "uchar int", 0);
        w.f32(1.0).f32(f32::NAN);
        assert_error(
            &w.out,
            byte(body + 40),
            &["vertex 3", "`y`", "NaN", "finite"],
        );
    }

    #[test]
    fn truncation_anywhere_is_an_error_naming_the_record() {
        for big in [false, true] {
            let bytes = binary_mesh(big);
            for cut in 0..bytes.len() {
                let result = parse(&bytes[..cut]);
                assert!(
                    matches!(result, Err(MeshError::Parse { .. })),
                    "cut at {cut}: {result:?}"
                );
            }
        }
        let bytes = binary_mesh(false);
        let inside = &bytes[..face_offset(1) + 5];
        assert_error(
            inside,
            byte(face_offset(1)),
            &["file ends inside face 1 of 3 (truncated?)"],
        );
        let between = &bytes[..face_offset(2)];
        assert_error(
            between,
            byte(face_offset(2)),
            &["file ends before face 2 of 3 (truncated?)"],
        );
        let error = parse(inside).unwrap_err().to_string();
        let expected = format!(
            "test.ply: byte {}: file ends inside face 1 of 3 (truncated?)",
            face_offset(1)
        );
        assert_eq!(error, expected);
    }

    #[test]
    fn absurd_counts_fail_fast_without_allocating() {
        let start = Instant::now();
        let (w, body) = small_binary(4_000_000_000, "uchar int", 0);
        assert_error(
            &w.out,
            byte(body + 36),
            &["file ends before vertex 3 of 4000000000"],
        );
        let (mut w, body) = small_binary(3, "uchar int", u64::MAX);
        w.u8(3).i32(0).i32(1).i32(2);
        let end = body + 36 + 13;
        assert_error(
            &w.out,
            byte(end),
            &["face 1 of 18446744073709551615", "truncated"],
        );
        let ascii = small_ascii(4_000_000_000, TRIANGLE, 0, "");
        assert_error(&ascii, at(13, 1), &["vertex 3 of 4000000000"]);
        assert!(
            start.elapsed() < Duration::from_secs(1),
            "took {:?}",
            start.elapsed()
        );
        let (w, _) = small_binary(5_000_000_000, "uchar int", 0);
        assert_error(&w.out, at(3, 1), &["5000000000 vertices"]);
    }

    #[test]
    fn header_semantics_are_checked_before_the_body() {
        let no_vertex = "ply\nformat ascii 1.0\nelement face 0\n\
                         property list uchar int vertex_indices\nend_header\n";
        assert_error(no_vertex.as_bytes(), at(5, 1), &["no `vertex` element"]);
        let no_y = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n\
                    property float z\nend_header\n";
        assert_error(no_y.as_bytes(), at(3, 1), &["no `y` property"]);
        let list_x =
            "ply\nformat ascii 1.0\nelement vertex 0\nproperty list uchar float x\nend_header\n";
        assert_error(list_x.as_bytes(), at(3, 1), &["`x` is a list"]);
        let (w, _) = small_binary(3, "uchar float", 0);
        assert_error(&w.out, at(7, 1), &["integer type"]);
        let no_list =
            "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                       property float z\nelement face 0\nproperty int vertex_indices\nend_header\n";
        assert_error(no_list.as_bytes(), at(7, 1), &["no `vertex_indices` list"]);
        let twice = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                     property float z\nelement vertex 0\nend_header\n";
        assert_error(twice.as_bytes(), at(7, 1), &["second `vertex`"]);
    }

    const SQUARE: [[f32; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];

    /// The value of vertex property `k` (after x, y, z) of vertex `i` in
    /// [`textured`]: whole numbers for integer types.
    fn extra_value(i: usize, k: usize, ty: &str) -> f64 {
        let whole = (i + 4 * k) as f64;
        match ty {
            "float" | "double" => whole / 4.0,
            _ => whole,
        }
    }

    /// Texture coordinates [`textured`] holds when `u` and `v` are its
    /// properties number `ku` and `kv` after x, y, z.
    fn textured_uvs(ku: usize, kv: usize, ty: &str) -> Vec<[f32; 2]> {
        (0..SQUARE.len())
            .map(|i| [extra_value(i, ku, ty) as f32, extra_value(i, kv, ty) as f32])
            .collect()
    }

    /// A square of two triangles in `format` (`ascii`, `binary_little_endian`
    /// or `binary_big_endian`) whose vertices carry, after x, y, z, one
    /// property of type `ty` (`float`, `double` or `uchar`) for each of `names`.
    fn textured(format: &str, names: &[&str], ty: &str) -> Vec<u8> {
        let mut header = format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\n"
        );
        for name in names {
            writeln!(header, "property {ty} {name}").unwrap();
        }
        header.push_str("element face 2\nproperty list uchar int vertex_indices\nend_header\n");
        let faces = [[0, 1, 2], [0, 2, 3]];
        if format == "ascii" {
            for (i, [x, y, z]) in SQUARE.iter().enumerate() {
                write!(header, "{x} {y} {z}").unwrap();
                for k in 0..names.len() {
                    write!(header, " {}", extra_value(i, k, ty)).unwrap();
                }
                header.push('\n');
            }
            for [a, b, c] in faces {
                writeln!(header, "3 {a} {b} {c}").unwrap();
            }
            return header.into_bytes();
        }
        let mut w = Writer::new(&header, format == "binary_big_endian");
        for (i, position) in SQUARE.iter().enumerate() {
            for &x in position {
                w.f32(x);
            }
            for k in 0..names.len() {
                let value = extra_value(i, k, ty);
                match ty {
                    "float" => w.f32(value as f32),
                    "double" => w.f64(value),
                    _ => w.u8(value as u8),
                };
            }
        }
        for face in faces {
            w.u8(3);
            for i in face {
                w.i32(i);
            }
        }
        w.out
    }

    /// Offset of the first byte after `end_header`.
    fn body_start(bytes: &[u8]) -> usize {
        let end = b"end_header\n";
        bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len()
    }

    const FORMATS: [&str; 3] = ["ascii", "binary_little_endian", "binary_big_endian"];

    #[test]
    fn texture_coordinates_in_every_encoding_and_spelling() {
        for format in FORMATS {
            for (u, v) in UV_NAMES {
                let mesh = parse(&textured(format, &[v, "w", u], "float")).unwrap();
                assert_eq!(mesh.uvs, Some(textured_uvs(2, 0, "float")), "{format} {u}");
                assert_eq!(mesh.positions, SQUARE, "{format} {u}");
                assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
                assert_eq!(mesh.normals, None);
            }
            for ty in ["double", "uchar"] {
                let mesh = parse(&textured(format, &["s", "t"], ty)).unwrap();
                assert_eq!(mesh.uvs, Some(textured_uvs(0, 1, ty)), "{format} {ty}");
            }
        }
    }

    #[test]
    fn the_first_pair_present_wins() {
        let all = [
            "texture_s",
            "texture_t",
            "s",
            "t",
            "texture_u",
            "texture_v",
            "u",
            "v",
        ];
        let some = ["texture_v", "t", "texture_u", "s"];
        // `u` without `v` is no pair.
        let lone_u = ["texture_t", "texture_s", "u"];
        for format in FORMATS {
            let mesh = parse(&textured(format, &all, "float")).unwrap();
            assert_eq!(mesh.uvs, Some(textured_uvs(6, 7, "float")), "{format}");
            let mesh = parse(&textured(format, &some, "float")).unwrap();
            assert_eq!(mesh.uvs, Some(textured_uvs(3, 1, "float")), "{format}");
            let mesh = parse(&textured(format, &lone_u, "float")).unwrap();
            assert_eq!(mesh.uvs, Some(textured_uvs(1, 0, "float")), "{format}");
        }
    }

    #[test]
    fn half_a_pair_gives_no_texture_coordinates() {
        for format in FORMATS {
            for names in [&["u"][..], &["u", "t"], &["texture_u", "v"], &["U", "V"]] {
                let mesh = parse(&textured(format, names, "float")).unwrap();
                assert_eq!(mesh.uvs, None, "{format} {names:?}");
                assert_eq!(mesh.positions, SQUARE);
                assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
            }
        }
        // A list is not a texture coordinate: skipped like any other property.
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                    property float z\nproperty list uchar float u\nproperty float v\n\
                    element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                    0 0 0 2 0.5 0.5 1\n1 0 0 0 1\n0 1 0 1 7 1\n3 0 1 2\n";
        let mesh = parse(text.as_bytes()).unwrap();
        assert_eq!((mesh.uvs, mesh.triangles.len()), (None, 1));
    }

    #[test]
    fn texture_coordinates_must_be_finite() {
        let text = String::from_utf8(textured("ascii", &["u", "v"], "float")).unwrap();
        let text = text.replace("0 1 0 0.75 1.75", "0 1 0 0.75 nan");
        assert_error(text.as_bytes(), at(15, 12), &["vertex 3", "`v`", "finite"]);
        let mut bytes = textured("binary_big_endian", &["u", "v"], "float");
        let header = b"end_header\n";
        let body = bytes
            .windows(header.len())
            .position(|w| w == header)
            .unwrap()
            + header.len();
        // Vertices take 20 bytes: x, y, z, u, v.
        let v = body + 2 * 20 + 16;
        bytes[v..v + 4].copy_from_slice(&f32::INFINITY.to_be_bytes());
        assert_error(&bytes, byte(v), &["vertex 2", "`v` is inf", "finite"]);
    }

    #[test]
    fn textured_files_cut_anywhere_fail() {
        for format in &FORMATS[1..] {
            let bytes = textured(format, &["u", "v"], "double");
            for cut in 0..bytes.len() {
                let result = parse(&bytes[..cut]);
                assert!(
                    matches!(result, Err(MeshError::Parse { .. })),
                    "{format}, cut at {cut}: {result:?}"
                );
            }
        }
    }

    #[test]
    fn textured_files_claiming_absurd_counts_fail_fast() {
        let start = Instant::now();
        for format in FORMATS {
            let bytes = textured(format, &["u", "v"], "float");
            let (header, body) = bytes.split_at(body_start(&bytes));
            let header = std::str::from_utf8(header).unwrap();
            let mut lying = header
                .replace("element vertex 4", "element vertex 4000000000")
                .into_bytes();
            lying.extend_from_slice(body);
            let message = parse(&lying).unwrap_err().to_string();
            assert!(message.contains("of 4000000000"), "{format}: {message}");
        }
        assert!(
            start.elapsed() < Duration::from_secs(1),
            "{:?}",
            start.elapsed()
        );
    }

    /// xorshift64: deterministic, dependency-free randomness for the fuzz loop.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }

        fn below(&mut self, n: usize) -> usize {
            (self.next() % n.max(1) as u64) as usize
        }
    }

    /// Damages a file in ways real corruption does: flipped bytes, digits changed
    /// (which inflates counts and indices), truncation and duplicated chunks.
    fn mutate(rng: &mut Rng, bytes: &mut Vec<u8>) {
        for _ in 0..1 + rng.below(4) {
            let i = rng.below(bytes.len());
            match rng.below(5) {
                0 => bytes[i] = rng.next() as u8,
                1 => bytes[i] = b"0123456789-"[rng.below(11)],
                2 => bytes[i] ^= 1 << rng.below(8),
                3 => bytes.truncate(i),
                _ => {
                    let end = (i + rng.below(64)).min(bytes.len());
                    let chunk = bytes[i..end].to_vec();
                    bytes.splice(i..i, chunk);
                }
            }
            if bytes.is_empty() {
                return;
            }
        }
    }

    #[test]
    fn mutated_files_never_panic() {
        let seeds = [ascii_mesh(), binary_mesh(false), binary_mesh(true)];
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let mut parsed = 0;
        for round in 0..4000 {
            let mut bytes = seeds[round % seeds.len()].clone();
            mutate(&mut rng, &mut bytes);
            parsed += usize::from(parse(&bytes).is_ok());
        }
        // Some mutations are harmless (a changed coordinate), most are not.
        assert!(parsed > 0 && parsed < 4000, "{parsed} of 4000 parsed");
    }

    #[test]
    fn mutated_textured_files_never_panic() {
        let seeds = FORMATS.map(|format| textured(format, &["s", "t", "u", "v"], "float"));
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        let mut kept = 0;
        for round in 0..3000 {
            let mut bytes = seeds[round % seeds.len()].clone();
            mutate(&mut rng, &mut bytes);
            if let Ok(mesh) = parse(&bytes) {
                let uvs = mesh.uvs.as_ref().map_or(0, Vec::len);
                assert!(uvs == 0 || uvs == mesh.positions.len(), "{mesh:?}");
                kept += usize::from(uvs > 0);
            }
        }
        assert!(kept > 0, "no mutated file kept its texture coordinates");
    }

    #[test]
    fn reads_the_stanford_bunny_quickly() {
        // The test command passes the bunny's path; nothing looks for it.
        let path = std::path::PathBuf::from(std::env::var_os("PENUMBRA_BUNNY").unwrap_or_default());
        let Ok(bytes) = std::fs::read(&path) else {
            eprintln!(
                "skipping: no bunny at {} (set PENUMBRA_BUNNY)",
                path.display()
            );
            return;
        };
        let mut times = Vec::new();
        let mut mesh = MeshData::default();
        for _ in 0..7 {
            let start = Instant::now();
            mesh = parse_ply(&bytes, &path).unwrap();
            times.push(start.elapsed());
        }
        times.sort();
        eprintln!(
            "bunny parse: median {:?} of {times:?}",
            times[times.len() / 2]
        );
        assert_eq!(
            (mesh.positions.len(), mesh.triangles.len()),
            (34_834, 69_451)
        );
        assert_eq!((mesh.normals, mesh.uvs), (None, None));
        let ranges = [(-0.0947, 0.0610), (0.0330, 0.1873), (-0.0619, 0.0588)];
        for (axis, (low, high)) in ranges.into_iter().enumerate() {
            let values = mesh.positions.iter().map(|p| p[axis]);
            let min = values.clone().fold(f32::INFINITY, f32::min);
            let max = values.fold(f32::NEG_INFINITY, f32::max);
            assert!(
                (min - low).abs() < 1e-4 && (max - high).abs() < 1e-4,
                "axis {axis}: {min}..{max}"
            );
        }
    }

    /// Attributes are named and grouped as Mitsuba's: `red, green, blue,
    /// alpha` as `vertex_color` (4 values), `P_x, P_y, P_z` as `vertex_P`,
    /// `P_r, P_g, P_b` as `vertex_P_color`, one `P_0` alone as a 1-value
    /// attribute; 2 components, a broken sequence, no postfix or a reserved
    /// name make none. Integers are over their largest value then decoded
    /// from sRGB; a face's values go to each triangle of its fan.
    #[test]
    fn attributes_are_grouped_and_named_as_mitsubas() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\n\
            property float x\nproperty float y\nproperty float z\n\
            property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n\
            property float dir_x\nproperty float dir_y\nproperty float dir_z\n\
            property ushort tint_r\nproperty ushort tint_g\nproperty ushort tint_b\n\
            property double heat_0\n\
            property float two_x\nproperty float two_y\n\
            property float odd_x\nproperty float odd_z\nproperty float odd_y\n\
            property float confidence\n\
            element face 2\nproperty float grade_x\nproperty list uchar int vertex_indices\n\
            end_header\n\
            0 0 0 255 0 128 255 1 2 3 0 65535 32768 0.5 7 8 1 2 3 9\n\
            1 0 0 0 0 0 0 1 2 3 0 0 0 1.5 7 8 1 2 3 9\n\
            1 1 0 0 0 0 0 1 2 3 0 0 0 2.5 7 8 1 2 3 9\n\
            0 1 0 0 0 0 0 1 2 3 0 0 0 3.5 7 8 1 2 3 9\n\
            0.25 3 0 1 2\n0.75 4 0 1 2 3\n";
        let mesh = parse(text.as_bytes()).unwrap();
        let names: Vec<(&str, bool, usize)> = mesh
            .attributes
            .iter()
            .map(|a| (a.name.as_str(), a.per_face, a.dim))
            .collect();
        assert_eq!(
            names,
            [
                ("vertex_color", false, 4),
                ("vertex_dir", false, 3),
                ("vertex_tint_color", false, 3),
                ("vertex_heat", false, 1),
                ("face_grade", true, 1),
            ]
        );
        let decode = |v: f32| ((v + 0.055) / 1.055).powf(2.4);
        let colour = &mesh.attributes[0].values;
        assert_eq!(colour[..2], [1.0, 0.0]);
        assert!((colour[2] - decode(128.0 / 255.0)).abs() < 1e-6);
        assert_eq!(colour[3], 1.0);
        assert_eq!(colour.len(), 16);
        assert_eq!(mesh.attributes[1].values[..3], [1.0, 2.0, 3.0]);
        let tint = &mesh.attributes[2].values;
        assert_eq!(tint[..2], [0.0, 1.0]);
        assert!((tint[2] - decode(32768.0 / 65535.0)).abs() < 1e-6);
        assert_eq!(mesh.attributes[3].values, [0.5, 1.5, 2.5, 3.5]);
        // The quad's two triangles each carry its grade.
        assert_eq!(mesh.attributes[4].values, [0.25, 0.75, 0.75]);
        assert_eq!(mesh.triangles.len(), 3);
    }

    /// Hostile attribute headers: many properties, odd names (no postfix,
    /// an empty prefix, a multi-byte postfix, a postfix of several letters,
    /// a name that is all underscores), a property list among them, and a
    /// value that is not finite, read without a panic.
    #[test]
    fn odd_attribute_headers_do_not_panic() {
        let mut header = String::from(
            "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n",
        );
        let odd = [
            "_", "__", "_x", "a_é", "a_xy", "é_x", "é_y", "é_z", "r", "g",
        ];
        for name in odd {
            writeln!(header, "property float {name}").unwrap();
        }
        writeln!(header, "property list uchar float l_x").unwrap();
        for i in 0..3000 {
            writeln!(
                header,
                "property uchar p{}_{}",
                i / 3,
                ["x", "y", "z"][i % 3]
            )
            .unwrap();
        }
        header.push_str("element face 1\nproperty list uchar int vertex_indices\nend_header\n");
        let record = |x: f32| {
            let mut r = format!("{x} 0 0");
            for _ in odd {
                r.push_str(" 0.5");
            }
            r.push_str(" 2 1 2");
            for i in 0..3000 {
                write!(r, " {}", i % 256).unwrap();
            }
            r + "\n"
        };
        let text = header.clone() + &record(0.0) + &record(1.0) + "3 0 1 1\n";
        let mesh = parse(text.as_bytes()).unwrap();
        // `_x` alone is `vertex_` (an empty prefix, as Mitsuba names it);
        // `é_x, é_y, é_z` is a 3-value attribute; the 1000 `p*_` ones too.
        assert_eq!(mesh.attributes[0].name, "vertex_");
        assert!(mesh.attributes.iter().any(|a| a.name == "vertex_é"));
        assert_eq!(mesh.attributes.len(), 2 + 1000);
        assert!(mesh.attributes.iter().all(|a| a.values.len() == 2 * a.dim));
        let bad = header.replace("property float _\n", "property double _\n")
            + &record(0.0).replacen(" 0.5", " 1e300", 1)
            + &record(1.0)
            + "3 0 1 1\n";
        // `_` makes no attribute: its huge value is skipped, not refused.
        parse(bad.as_bytes()).unwrap();
        // A value that is not finite is kept (refused only where read).
        let bad = header.clone()
            + &record(0.0).replacen("0.5 0.5 0.5 0.5 0.5 0.5", "0.5 0.5 0.5 0.5 0.5 1e300", 1)
            + &record(1.0)
            + "3 0 1 1\n";
        let mesh = parse(bad.as_bytes()).unwrap();
        let a = mesh
            .attributes
            .iter()
            .find(|a| a.name == "vertex_é")
            .unwrap();
        assert_eq!(a.values[0], f32::INFINITY);
    }
}
