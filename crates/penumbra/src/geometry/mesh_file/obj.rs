//! Wavefront OBJ reader for triangle meshes.
//!
//! Only geometry is read: positions (`v`), texture coordinates (`vt`), normals
//! (`vn`) and faces (`f`). Materials, groups, parameter-space vertices and
//! free-form statements are skipped, because the renderer assigns materials in
//! the scene description, not from the mesh file.
//!
//! - `v x y z` may carry more numbers (`w`, or the common per-vertex colour
//!   extension), which are checked as numbers and ignored.
//! - `vt u [v [w]]`: a missing `v` is 0, as common readers take it; `w` is
//!   checked as a number and ignored.
//! - `vn x y z`.
//! - A face corner is `i`, `i/t`, `i//n` or `i/t/n`; indices start at 1, and a
//!   negative one counts back from the latest element of its kind. Every index
//!   must be in range, whether or not its attribute ends up in the mesh.
//! - Faces with more than 3 corners are fan-triangulated.
//!
//! OBJ indexes positions, texture coordinates and normals separately, while a
//! mesh has one index per vertex. Texture coordinates are kept only if every
//! face corner names one, and normals likewise, each decided on its own: a
//! corner without `/t` drops the texture coordinates of the whole mesh, not its
//! normals. When either is kept, each distinct
//! (position, texture coordinate, normal) triple of the kept attributes becomes
//! a vertex, numbered in order of first use: a position that faces use with
//! different `vt` or `vn` indices is split into several vertices, and positions
//! no face uses are left out. When neither is kept, the file's positions are the
//! mesh's vertices, untouched.

use std::collections::HashMap;
use std::path::Path;

use super::error::{Location, MeshData, MeshError};
use super::text::{parse_i64, quote, Lines, Tokens};

pub fn read_obj(path: &Path) -> Result<MeshData, MeshError> {
    let mut file = super::open::open_mesh(path)?;
    let head = file
        .read_head(super::open::HEAD)
        .map_err(MeshError::input)?;
    // Binary data from the first bytes: refused without reading the rest.
    binary_data(&head, path)?;
    let bytes = file.read_rest(head).map_err(MeshError::input)?;
    parse_obj(&bytes, path)
}

/// Parses OBJ text; `path` is used only in error messages. Bytes need not be UTF-8,
/// since names and comments in the wild use all sorts of encodings, but a NUL
/// byte is refused: it is never in text, and marks binary data.
pub fn parse_obj(text: &[u8], path: &Path) -> Result<MeshData, MeshError> {
    binary_data(text, path)?;
    let mut statements = Statements::new(text);
    let mut builder = Builder::new(path);
    while let Some(keyword) = statements.start() {
        builder.statement(keyword, &mut statements)?;
    }
    builder.finish()
}

/// An error at the first NUL byte of `text`, if it has one.
fn binary_data(text: &[u8], path: &Path) -> Result<(), MeshError> {
    let Some(at) = text.iter().position(|&b| b == 0) else {
        return Ok(());
    };
    let before = &text[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = at
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1)
        + 1;
    Err(MeshError::parse(
        path,
        Location::LineColumn { line, column },
        "a NUL byte: this is binary data, not OBJ text",
    ))
}

/// A token with its physical place, kept separately because `\` continuations join
/// several lines into one statement.
#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    text: &'a [u8],
    at: Location,
}

/// Streams the tokens of logical statements: comments removed, continuation lines
/// joined. Tokens are handed out one at a time rather than collected, so a single
/// enormous line costs no memory beyond what its contents produce.
struct Statements<'a> {
    lines: Lines<'a>,
    tokens: Tokens<'a>,
    continues: bool,
    /// Just past the last token handed out, where a missing value would belong.
    end: Location,
}

impl<'a> Statements<'a> {
    fn new(text: &'a [u8]) -> Self {
        Statements {
            lines: Lines::new(text, 0, 0),
            tokens: Tokens::new(b""),
            continues: false,
            end: Location::Unknown,
        }
    }

    /// Skips what is left of the current statement and returns the first token
    /// (the keyword) of the next non-empty one.
    fn start(&mut self) -> Option<Token<'a>> {
        while self.token().is_some() {}
        loop {
            self.load_line()?;
            if let Some(keyword) = self.token() {
                return Some(keyword);
            }
        }
    }

    /// The next token of the current statement, if any.
    fn token(&mut self) -> Option<Token<'a>> {
        loop {
            if let Some((column, text)) = self.tokens.next() {
                let line = self.lines.number;
                self.end = Location::LineColumn {
                    line,
                    column: column + text.len(),
                };
                let at = Location::LineColumn { line, column };
                return Some(Token { text, at });
            }
            if !self.continues || self.load_line().is_none() {
                return None;
            }
        }
    }

    fn load_line(&mut self) -> Option<()> {
        let raw = self.lines.next();
        self.continues = false;
        let content = raw?.split(|&b| b == b'#').next().unwrap_or_default();
        let content = match content.trim_ascii_end().split_last() {
            Some((b'\\', rest)) => {
                self.continues = true;
                rest
            }
            _ => content,
        };
        self.tokens = Tokens::new(content);
        Some(())
    }
}

/// Marks a corner without a texture coordinate or a normal.
const NO_INDEX: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Corner {
    position: u32,
    texture: u32,
    normal: u32,
}

/// Which array an index refers to, for messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Position,
    Texture,
    Normal,
}

impl Kind {
    fn noun(self) -> &'static str {
        match self {
            Kind::Position => "vertex",
            Kind::Texture => "texture coordinate",
            Kind::Normal => "normal",
        }
    }

    fn plural(self) -> &'static str {
        match self {
            Kind::Position => "vertices",
            Kind::Texture => "texture coordinates",
            Kind::Normal => "normals",
        }
    }
}

/// An index beyond the vertices seen so far. OBJ allows referring to later vertices,
/// so these are checked once the whole file is read.
#[derive(Clone, Copy, Debug)]
struct ForwardRef {
    kind: Kind,
    index: u32,
    at: Location,
}

struct Builder<'p> {
    path: &'p Path,
    positions: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    normals: Vec<[f32; 3]>,
    corners: Vec<Corner>,
    face_starts: Vec<usize>,
    forward: Vec<ForwardRef>,
    corners_with_texture: usize,
    corners_with_normal: usize,
}

impl<'p> Builder<'p> {
    fn new(path: &'p Path) -> Self {
        Builder {
            path,
            positions: Vec::new(),
            uvs: Vec::new(),
            normals: Vec::new(),
            corners: Vec::new(),
            face_starts: Vec::new(),
            forward: Vec::new(),
            corners_with_texture: 0,
            corners_with_normal: 0,
        }
    }

    fn error(&self, at: Location, message: String) -> MeshError {
        MeshError::parse(self.path, at, message)
    }

    fn statement(&mut self, keyword: Token, args: &mut Statements) -> Result<(), MeshError> {
        match keyword.text {
            b"v" => {
                let position = self.vector(args, "coordinates", true)?;
                self.positions.push(position);
            }
            b"vt" => {
                let uv = self.texture_coordinates(args)?;
                self.uvs.push(uv);
            }
            b"vn" => {
                let normal = self.vector(args, "normal components", false)?;
                self.normals.push(normal);
            }
            b"f" => self.face(keyword, args)?,
            _ => {}
        }
        Ok(())
    }

    /// Reads three finite numbers. Vertices may carry more (`w`, or the common
    /// per-vertex colour extension), which are checked as numbers and ignored.
    fn vector(
        &self,
        args: &mut Statements,
        what: &str,
        extra_ok: bool,
    ) -> Result<[f32; 3], MeshError> {
        let mut vector = [0.0; 3];
        for (found, slot) in vector.iter_mut().enumerate() {
            let Some(token) = args.token() else {
                return Err(self.error(args.end, format!("expected 3 {what}, found {found}")));
            };
            *slot = self.number(&token)?;
        }
        while let Some(token) = args.token() {
            if !extra_ok {
                let message = format!("unexpected {} after 3 {what}", quote(token.text));
                return Err(self.error(token.at, message));
            }
            self.number(&token)?;
        }
        Ok(vector)
    }

    /// Reads `u [v [w]]`: a missing `v` is 0, and `w` (of 3D textures) is
    /// checked as a number and ignored.
    fn texture_coordinates(&self, args: &mut Statements) -> Result<[f32; 2], MeshError> {
        let Some(u) = args.token() else {
            let message = "expected 1 to 3 texture coordinates, found 0".to_string();
            return Err(self.error(args.end, message));
        };
        let mut uv = [self.number(&u)?, 0.0];
        let mut found = 1;
        while let Some(token) = args.token() {
            if found == 3 {
                let message = format!(
                    "unexpected {} after 3 texture coordinates",
                    quote(token.text)
                );
                return Err(self.error(token.at, message));
            }
            let value = self.number(&token)?;
            if found == 1 {
                uv[1] = value;
            }
            found += 1;
        }
        Ok(uv)
    }

    /// Parses a finite `f32`; NaN and infinities would poison bounds and the BVH.
    fn number(&self, token: &Token) -> Result<f32, MeshError> {
        let value = std::str::from_utf8(token.text)
            .ok()
            .and_then(|s| s.parse::<f32>().ok());
        match value {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(self.error(
                token.at,
                format!("{} is not a finite number", quote(token.text)),
            )),
            None => Err(self.error(token.at, format!("malformed number {}", quote(token.text)))),
        }
    }

    fn face(&mut self, keyword: Token, args: &mut Statements) -> Result<(), MeshError> {
        let start = self.corners.len();
        while let Some(token) = args.token() {
            let corner = self.corner(&token)?;
            self.corners_with_texture += usize::from(corner.texture != NO_INDEX);
            self.corners_with_normal += usize::from(corner.normal != NO_INDEX);
            self.corners.push(corner);
        }
        let count = self.corners.len() - start;
        if count < 3 {
            let message = format!("face has {count} vertices; at least 3 are needed");
            return Err(self.error(keyword.at, message));
        }
        self.face_starts.push(start);
        Ok(())
    }

    /// Parses `i`, `i/t`, `i//n` or `i/t/n`.
    fn corner(&mut self, token: &Token) -> Result<Corner, MeshError> {
        let mut parts = token.text.split(|&b| b == b'/');
        let position = parts.next().unwrap_or_default();
        let texture = parts.next();
        let normal = parts.next();
        if parts.next().is_some() || position.is_empty() || normal.is_some_and(<[u8]>::is_empty) {
            let message = format!(
                "malformed face vertex {}; expected i, i/t, i//n or i/t/n",
                quote(token.text)
            );
            return Err(self.error(token.at, message));
        }
        // `i/` and `i//n` name no texture coordinate.
        let texture = match texture {
            Some(texture) if !texture.is_empty() => self.index(texture, token, Kind::Texture)?,
            _ => NO_INDEX,
        };
        let position = self.index(position, token, Kind::Position)?;
        let normal = match normal {
            Some(normal) => self.index(normal, token, Kind::Normal)?,
            None => NO_INDEX,
        };
        Ok(Corner {
            position,
            texture,
            normal,
        })
    }

    fn raw_index(&self, text: &[u8], token: &Token) -> Result<i64, MeshError> {
        let value = parse_i64(text);
        match value {
            Some(0) => Err(self.error(
                token.at,
                "index 0 is invalid; OBJ indices start at 1".into(),
            )),
            Some(v) => Ok(v),
            None => Err(self.error(token.at, format!("malformed index {}", quote(text)))),
        }
    }

    /// Resolves a 1-based or negative (relative) index to a 0-based one.
    fn index(&mut self, text: &[u8], token: &Token, kind: Kind) -> Result<u32, MeshError> {
        let raw = self.raw_index(text, token)?;
        let defined = self.defined(kind) as i64;
        let noun = kind.noun();
        let resolved = if raw < 0 { defined + raw } else { raw - 1 };
        if raw < 0 && resolved < 0 {
            let message =
                format!("relative {noun} index {raw} reaches before the first {noun} ({defined} defined so far)");
            return Err(self.error(token.at, message));
        }
        // The largest u32 is reserved as the "no index" marker.
        let index = match u32::try_from(resolved) {
            Ok(index) if index != NO_INDEX => index,
            _ => return Err(self.error(token.at, format!("{noun} index {raw} is too large"))),
        };
        if resolved >= defined {
            self.forward.push(ForwardRef {
                kind,
                index,
                at: token.at,
            });
        }
        Ok(index)
    }

    /// How many elements of a kind the file has defined so far.
    fn defined(&self, kind: Kind) -> usize {
        match kind {
            Kind::Position => self.positions.len(),
            Kind::Texture => self.uvs.len(),
            Kind::Normal => self.normals.len(),
        }
    }

    fn finish(self) -> Result<MeshData, MeshError> {
        for forward in &self.forward {
            let defined = self.defined(forward.kind);
            if forward.index as usize >= defined {
                let (noun, plural) = (forward.kind.noun(), forward.kind.plural());
                let index = u64::from(forward.index) + 1;
                let message = format!(
                    "{noun} index {index} is out of range (the file has {defined} {plural})"
                );
                return Err(self.error(forward.at, message));
            }
        }
        let every_corner = |count| !self.corners.is_empty() && count == self.corners.len();
        let kept = Kept {
            uvs: every_corner(self.corners_with_texture),
            normals: every_corner(self.corners_with_normal),
        };
        if kept.uvs || kept.normals {
            self.split(kept)
        } else {
            Ok(self.positions_only())
        }
    }

    /// Without texture coordinates or normals the file's vertex array is the
    /// mesh's, untouched.
    fn positions_only(self) -> MeshData {
        let triangles = fan(&self.face_starts, &self.corners, |c| c.position);
        MeshData {
            positions: self.positions,
            normals: None,
            uvs: None,
            triangles,
            attributes: Vec::new(),
        }
    }

    /// OBJ indexes positions, texture coordinates and normals separately, but the
    /// renderer wants one index per vertex, so each distinct (position, texture
    /// coordinate, normal) triple of the kept attributes becomes a vertex.
    fn split(self, kept: Kept) -> Result<MeshData, MeshError> {
        let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
        let mut positions = Vec::new();
        let mut uvs = Vec::new();
        let mut normals = Vec::new();
        let mut remapped = Vec::with_capacity(self.corners.len());
        for corner in &self.corners {
            let texture = if kept.uvs { corner.texture } else { NO_INDEX };
            let normal = if kept.normals {
                corner.normal
            } else {
                NO_INDEX
            };
            let key = [corner.position, texture, normal];
            let id = match ids.get(&key) {
                Some(&id) => id,
                None => {
                    let Some(vertex) = self.vertex(key, kept) else {
                        return Err(self.error(Location::Unknown, "face index out of range".into()));
                    };
                    let Ok(id) = u32::try_from(positions.len()) else {
                        return Err(
                            self.error(Location::Unknown, "too many distinct vertices".into())
                        );
                    };
                    positions.push(vertex.position);
                    uvs.extend(vertex.uv);
                    normals.extend(vertex.normal);
                    ids.insert(key, id);
                    id
                }
            };
            remapped.push(id);
        }
        let triangles = fan(&self.face_starts, &remapped, |&id| id);
        Ok(MeshData {
            positions,
            normals: kept.normals.then_some(normals),
            uvs: kept.uvs.then_some(uvs),
            triangles,
            attributes: Vec::new(),
        })
    }

    /// The vertex that `[position, texture, normal]` indices name; None if one
    /// of the kept ones is out of range, which [`Builder::finish`] has ruled out.
    fn vertex(&self, [position, texture, normal]: [u32; 3], kept: Kept) -> Option<Vertex> {
        let p = *self.positions.get(position as usize)?;
        let t = if kept.uvs {
            Some(*self.uvs.get(texture as usize)?)
        } else {
            None
        };
        let n = if kept.normals {
            Some(*self.normals.get(normal as usize)?)
        } else {
            None
        };
        Some(Vertex {
            position: p,
            uv: t,
            normal: n,
        })
    }
}

/// Which per-corner attributes the mesh keeps: those every face corner names.
#[derive(Clone, Copy, Debug)]
struct Kept {
    uvs: bool,
    normals: bool,
}

/// A vertex of the mesh: a position with the kept attributes of its corners.
struct Vertex {
    position: [f32; 3],
    uv: Option<[f32; 2]>,
    normal: Option<[f32; 3]>,
}

/// Fan-triangulates each face, exact for the convex polygons modellers export.
fn fan<C>(face_starts: &[usize], corners: &[C], vertex: impl Fn(&C) -> u32) -> Vec<[u32; 3]> {
    let mut triangles = Vec::with_capacity(corners.len().saturating_sub(2 * face_starts.len()));
    let ends = face_starts.iter().skip(1).copied().chain([corners.len()]);
    for (&start, end) in face_starts.iter().zip(ends) {
        let Some(face) = corners.get(start..end) else {
            continue;
        };
        let Some((first, rest)) = face.split_first() else {
            continue;
        };
        for pair in rest.windows(2) {
            if let [b, c] = pair {
                triangles.push([vertex(first), vertex(b), vertex(c)]);
            }
        }
    }
    triangles
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<MeshData, MeshError> {
        parse_obj(text.as_bytes(), Path::new("test.obj"))
    }

    /// Asserts a parse error at `line:column` whose message contains every needle.
    fn assert_error(text: &str, line: usize, column: usize, needles: &[&str]) {
        match parse(text) {
            Err(MeshError::Parse {
                location, message, ..
            }) => {
                assert_eq!(location, Location::LineColumn { line, column }, "{message}");
                for needle in needles {
                    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
                }
            }
            other => panic!("expected a parse error for {text:?}, got {other:?}"),
        }
    }

    const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn reads_positions_and_fans_polygons_ignoring_other_statements() {
        let text = "# a comment\r\nmtllib a.mtl\r\no thing\r\ng group\r\ns 1\r\nusemtl red\r\n\
                    v 0 0 0 1\r\nv 1 0 0 0.5 0.2 0.3\r\nv 1 1 0\r\nv 0 1 0 # trailing comment\r\n\
                    v 2 2 2\r\nvt 0.5 0.5\r\nvp 1 2\r\nl 1 2\r\np 3\r\ncurv 0 1 1 2\r\n\
                    f 1 2 3 4 5\r\nf 1 2 3\r\n";
        let mesh = parse(text).unwrap();
        assert_eq!(mesh.positions.len(), 5);
        assert_eq!(mesh.positions[1], [1.0, 0.0, 0.0]);
        let fans = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 1, 2]];
        assert_eq!((mesh.triangles, mesh.normals), (fans, None));
    }

    #[test]
    fn negative_indices_count_back_from_the_latest_vertex() {
        let text = format!("{SQUARE}f -4 -3 -2 -1\nv 5 5 5\nf -5 -1 -2\n");
        let mesh = parse(&text).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 4, 3]]);
    }

    #[test]
    fn all_corner_forms_are_accepted() {
        let faces = "f 1/1 2/2 3/3\nf 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\n";
        let text = format!("{SQUARE}vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n{faces}");
        let mesh = parse(&text).unwrap();
        // One face lacks normals and another texture coordinates, so neither is
        // kept and the positions are used as they are.
        assert_eq!((mesh.normals, mesh.uvs), (None, None));
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn normals_become_per_vertex_via_unique_pairs() {
        // Two faces meet at the edge 2-3 with different normals (a crease), so the
        // shared positions are split, while 1//1 is used twice and stays one vertex.
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 1 1\nvn 0 0 1\nvn 1 0 0\n\
                    f 1//1 2//1 3//1\nf 2//2 4//2 3//2\nf 1//1 3//1 2//1\n";
        let mesh = parse(text).unwrap();
        let normals = mesh.normals.as_ref().unwrap();
        assert_eq!((mesh.positions.len(), normals.len()), (6, 6));
        assert_eq!(mesh.uvs, None);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [3, 4, 5], [0, 2, 1]]);
        let z = [0.0, 0.0, 1.0];
        let x = [1.0, 0.0, 0.0];
        assert_eq!(normals, &vec![z, z, z, x, x, x]);
        let expected = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
        assert_eq!(&mesh.positions[..3], &expected);
        assert_eq!(
            &mesh.positions[3..],
            &[[1.0, 0.0, 0.0], [1.0, 1.0, 1.0], [1.0, 1.0, 0.0]]
        );
    }

    #[test]
    fn texture_coordinates_follow_their_corners() {
        let text = format!("{SQUARE}vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
        let mesh = parse(&text).unwrap();
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(mesh.positions, square);
        let uvs = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(mesh.uvs, Some(uvs));
        assert_eq!(mesh.normals, None);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn each_corner_keeps_its_position_texture_coordinate_and_normal() {
        // Position 2 is used with two normals, position 3 with two texture
        // coordinates: each distinct triple is a vertex, in order of first use.
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 0.5\n\
                    vn 0 0 1\nvn 0 1 0\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 2/2/2 3/4/1\n";
        let mesh = parse(text).unwrap();
        let (z, y) = ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]);
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert_eq!(mesh.positions, positions);
        let uvs = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.5, 0.5]];
        assert_eq!(mesh.uvs, Some(uvs));
        assert_eq!(mesh.normals, Some(vec![z, z, z, y, z]));
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 3, 4]]);
    }

    #[test]
    fn a_position_with_two_texture_coordinates_is_split() {
        // The faces share the edge 2-3 but map it to different places of the
        // texture (a seam): both copies keep their own coordinates. Corners
        // repeated with the same `vt` stay one vertex.
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\n\
                    vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0.5 0.25\nvt 0.5 0.75\nvt 1 0\n\
                    f 1/1 2/2 3/3\nf 2/4 4/6 3/5\nf 3/3 1/1 2/2\n";
        let mesh = parse(text).unwrap();
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert_eq!(mesh.positions, positions);
        let uvs = vec![
            [0.0, 0.0],
            [0.5, 0.0],
            [0.5, 1.0],
            [0.5, 0.25],
            [1.0, 0.0],
            [0.5, 0.75],
        ];
        assert_eq!(mesh.uvs, Some(uvs));
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [3, 4, 5], [2, 0, 1]]);
    }

    #[test]
    fn negative_texture_indices_count_back_from_the_latest() {
        let text = format!(
            "{SQUARE}vt 0 0\nvt 1 0\nvt 1 1\nf -4/-3 -3/-2 -2/-1\nvt 0.5 0.5\nf -4/-1 -2/-3 -1/-4\n"
        );
        let mesh = parse(&text).unwrap();
        let uvs = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.5, 0.5],
            [1.0, 0.0],
            [0.0, 0.0],
        ];
        assert_eq!(mesh.uvs, Some(uvs));
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(mesh.positions, [0, 1, 2, 0, 2, 3].map(|i| square[i]));
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [3, 4, 5]]);
    }

    #[test]
    fn short_and_long_texture_coordinates() {
        // `vt u` means (u, 0); a third number (w) is ignored.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25\nvt 0.5 0.75 0.9\nvt 1 1\nf 1/1 2/2 3/3\n";
        let mesh = parse(text).unwrap();
        assert_eq!(mesh.uvs, Some(vec![[0.25, 0.0], [0.5, 0.75], [1.0, 1.0]]));
    }

    #[test]
    fn attributes_some_corners_lack_are_dropped_each_on_its_own() {
        // Every corner has a normal, one face has no texture coordinates.
        let text = format!("{SQUARE}vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\n");
        let mesh = parse(&text).unwrap();
        assert_eq!(mesh.uvs, None);
        assert_eq!(mesh.normals, Some(vec![[0.0, 0.0, 1.0]; 4]));
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        // Every corner has a texture coordinate, one face has no normals.
        let text =
            format!("{SQUARE}vt 0 0\nvt 1 1\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf 1/2 3/1 4/1\n");
        let mesh = parse(&text).unwrap();
        assert_eq!(mesh.normals, None);
        assert_eq!(
            mesh.uvs,
            Some(vec![
                [0.0, 0.0],
                [0.0, 0.0],
                [0.0, 0.0],
                [1.0, 1.0],
                [0.0, 0.0]
            ])
        );
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [3, 2, 4]]);
    }

    #[test]
    fn texture_coordinate_errors_give_line_and_column() {
        assert_error(
            "vt\n",
            1,
            3,
            &["expected 1 to 3 texture coordinates, found 0"],
        );
        assert_error("v 0 0 0\n vt 0.5 x\n", 2, 9, &["malformed number `x`"]);
        assert_error(
            "vt 1 2 3 4\n",
            1,
            10,
            &["unexpected `4` after 3 texture coordinates"],
        );
        assert_error("vt nan 0\n", 1, 4, &["`nan` is not a finite number"]);
        let one = format!("{SQUARE}vt 0 0\n");
        assert_error(
            &format!("{one}f 1/1 2/1 3/2\n"),
            6,
            11,
            &[
                "texture coordinate index 2 is out of range",
                "1 texture coordinates",
            ],
        );
        // Indices are checked even where the mesh keeps no texture coordinates.
        assert_error(
            &format!("{one}f 1 2/7 3\n"),
            6,
            5,
            &["texture coordinate index 7 is out of range"],
        );
        assert_error(
            &format!("{one}f 1/1 2/0 3/1\n"),
            6,
            7,
            &["index 0 is invalid"],
        );
        assert_error(
            &format!("{one}f 1/1 2/1 3/-2\n"),
            6,
            11,
            &["relative texture coordinate index -2", "1 defined so far"],
        );
        assert_error(
            &format!("{one}f 1/1 2/1099511627776 3/1\n"),
            6,
            7,
            &["texture coordinate index 1099511627776 is too large"],
        );
        let error = parse(&format!("{one}f 1/1 2/1 3/2\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "test.obj:6:11: texture coordinate index 2 is out of range (the file has 1 texture coordinates)"
        );
    }

    #[test]
    fn backslash_joins_lines() {
        let text = format!("v 0 0 \\\r\n  0\n{}f 1 2 \\\n3 \\\n4 \\", &SQUARE[8..]);
        let mesh = parse(&text).unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        // An empty line ends a continued statement.
        let ended = format!("{SQUARE}f 1 2 \\\n\n3\n");
        assert_error(&ended, 5, 1, &["face has 2 vertices"]);
        // Errors point at the physical line holding the bad token.
        assert_error("v 0 \\\n0 \\\n zero\n", 3, 2, &["malformed number `zero`"]);
    }

    #[test]
    fn faces_may_refer_to_later_vertices() {
        let mesh = parse(&format!("f 1 2 3\n{SQUARE}")).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn a_file_without_faces_is_not_an_error() {
        let mesh = parse(SQUARE).unwrap();
        assert_eq!((mesh.positions.len(), mesh.triangles.len()), (4, 0));
        assert_eq!(parse("").unwrap(), MeshData::default());
    }

    #[test]
    fn errors_give_line_and_column_of_the_token() {
        assert_error("v 0 0 0\nv 1 x 0\n", 2, 5, &["malformed number `x`"]);
        assert_error("v 1 2\n", 1, 6, &["expected 3 coordinates, found 2"]);
        assert_error(
            "v 0 0 0\n  vn 1 0\n",
            2,
            9,
            &["expected 3 normal components, found 2"],
        );
        assert_error("vn 1 0 0 1\n", 1, 10, &["unexpected `1`"]);
        assert_error("v 0 nan 0\n", 1, 5, &["`nan` is not a finite number"]);
        assert_error("v 0 0 -inf\n", 1, 7, &["not a finite"]);
        assert_error("v 0 0 1e39\n", 1, 7, &["not a finite"]);
        assert_error("v 1 2 3 oops\n", 1, 9, &["malformed number `oops`"]);
        assert_error(&format!("{SQUARE}f 1 0 2\n"), 5, 5, &["index 0 is invalid"]);
        assert_error(
            &format!("{SQUARE}f 1 2 x\n"),
            5,
            7,
            &["malformed index `x`"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2\n"),
            5,
            1,
            &["face has 2 vertices", "at least 3"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2 -5\n"),
            5,
            7,
            &["relative vertex index -5", "4 defined so far"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2 1/2/3/4\n"),
            5,
            7,
            &["malformed face vertex `1/2/3/4`"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2 3//\n"),
            5,
            7,
            &["malformed face vertex"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2 /3\n"),
            5,
            7,
            &["malformed face vertex"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2 3/x\n"),
            5,
            7,
            &["malformed index `x`"],
        );
        assert_error(
            &format!("{SQUARE}f 1 2 99999999999\n"),
            5,
            7,
            &["too large"],
        );
        assert_error(
            &format!("{SQUARE}vn 0 0 1\nf 1//1 2//1 3//-2\n"),
            6,
            13,
            &["relative normal index -2"],
        );
    }

    #[test]
    fn out_of_range_indices_are_reported_where_they_are_used() {
        let text = format!("{SQUARE}f 1 2 3\n\nf 1 2  5\nv 9 9 9\nf 1 2 6\n");
        assert_error(
            &text,
            9,
            7,
            &["vertex index 6 is out of range", "5 vertices"],
        );
        let normals = format!("{SQUARE}vn 0 0 1\nf 1//1 2//1 3//2\n");
        assert_error(
            &normals,
            6,
            13,
            &["normal index 2 is out of range", "1 normals"],
        );
        let error = parse(&text).unwrap_err().to_string();
        assert_eq!(
            error,
            "test.obj:9:7: vertex index 6 is out of range (the file has 5 vertices)"
        );
    }

    #[test]
    fn mutated_files_never_panic() {
        let seed =
            format!("{SQUARE}vn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1 \\\n 4/1/1\nf -1 -2 -3\n")
                .into_bytes();
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let alphabet = b"0123456789-/\\ #\nvfn.e";
        for _ in 0..4000 {
            let mut bytes = seed.clone();
            for _ in 0..1 + next() % 4 {
                let i = (next() % bytes.len().max(1) as u64) as usize;
                match next() % 3 {
                    0 if i < bytes.len() => {
                        bytes[i] = alphabet[(next() % alphabet.len() as u64) as usize]
                    }
                    1 if i < bytes.len() => bytes[i] = next() as u8,
                    _ => bytes.truncate(i),
                }
            }
            let _ = parse_obj(&bytes, Path::new("fuzz.obj"));
        }
    }
}
