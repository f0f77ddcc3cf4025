//! The XML language: files read through [`crate::input`], parsed by
//! roxmltree (no DTD, nothing external), `$name` substituted in every
//! attribute, `<default>` recorded, `<include>` read in place and `<path>`
//! recorded, into a tree of [`Element`]s that carry their file, line and
//! column.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::description::error::{Location, SceneError};
use crate::description::Source;
use crate::input::{self, quote, InputError};

/// Parameters given by the caller (`-D name=value`), which win over the
/// file's `<default>`s.
pub type Defines = [(String, String)];

/// How deep elements nest, counting those of included files from the
/// `<include>` down.
pub const MAX_DEPTH: usize = 64;
/// How deep includes nest.
pub const MAX_INCLUDES: usize = 32;

/// An attribute with the place of its value.
#[derive(Clone, Debug)]
pub struct Attr {
    pub name: String,
    pub value: String,
    pub at: Location,
}

/// An XML element, its attributes substituted.
#[derive(Clone, Debug)]
pub struct Element {
    pub tag: String,
    pub attrs: Vec<Attr>,
    pub children: Vec<Element>,
    pub at: Location,
    /// The folder of its file, as a path relative to the scene's folder (or
    /// absolute), shared by the elements of the file.
    pub dir: Arc<Path>,
    /// Whether its file is older than version 2.0.
    pub old: bool,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&Attr> {
        self.attrs.iter().find(|a| a.name == name)
    }

    pub fn get(&self, name: &str) -> Option<&str> {
        self.attr(name).map(|a| a.value.as_str())
    }
}

/// A problem at a place in a file.
pub fn error_at(at: &Location, message: impl Into<String>) -> SceneError {
    SceneError {
        file: Some(at.file.as_ref().clone()),
        position: Some((at.line as usize, at.column as usize)),
        message: message.into(),
    }
}

/// Most attributes an element may have. Mitsuba's elements take a few;
/// the XML parser compares each attribute of an element with the ones
/// before it, so one element of very many would take time quadratic in its
/// size.
pub const MAX_ATTRIBUTES: usize = 64;

/// The first element of `text` with more than [`MAX_ATTRIBUTES`]
/// attributes: its offset and name. One pass of a tokenizer, in time
/// linear in the text; a text that does not tokenize is left to the
/// parser to report.
fn crowded_element(text: &str) -> Option<(usize, &str)> {
    let (mut count, mut start) = (0, None);
    for token in xmlparser::Tokenizer::from(text) {
        match token.ok()? {
            xmlparser::Token::ElementStart { local, span, .. } => {
                count = 0;
                start = Some((span.start(), local.as_str()));
            }
            xmlparser::Token::Attribute { .. } => {
                count += 1;
                if count > MAX_ATTRIBUTES {
                    return start;
                }
            }
            _ => {}
        }
    }
    None
}

/// What the whole read shares: the scene's folder, the parameters, the
/// files open above the current one, the bytes read so far, the search
/// folders of `<path>`, the files older than version 2.0. Paths are as the
/// command line gave the scene: relative to the working folder or absolute.
pub struct Reader<'a> {
    pub scene_dir: &'a Path,
    pub params: HashMap<String, String>,
    /// Parameters given by the caller (`-D`): a `<default>` never replaces them.
    fixed: Vec<String>,
    stack: Vec<PathBuf>,
    bytes_left: u64,
    limit: u64,
    pub search: Vec<PathBuf>,
    pub old_files: Vec<(PathBuf, String)>,
}

impl<'a> Reader<'a> {
    pub fn new(scene_dir: &'a Path, defines: &Defines, limit: u64) -> Self {
        Reader {
            scene_dir,
            params: defines.iter().cloned().collect(),
            fixed: defines.iter().map(|(k, _)| k.clone()).collect(),
            stack: Vec::new(),
            bytes_left: limit,
            limit,
            search: Vec::new(),
            old_files: Vec::new(),
        }
    }

    /// Reads a file (named in errors as `rel`) whose root element is at
    /// nesting `depth`: its root element.
    pub fn file(&mut self, rel: &Path, depth: usize) -> Result<Element, SceneError> {
        let full = rel.to_path_buf();
        let key = std::fs::canonicalize(&full).unwrap_or_else(|_| full.clone());
        if self.stack.contains(&key) {
            return Err(SceneError {
                file: Some(rel.to_path_buf()),
                position: None,
                message: "the file includes itself (an include loop)".into(),
            });
        }
        if self.stack.len() > MAX_INCLUDES {
            return Err(SceneError {
                file: Some(rel.to_path_buf()),
                position: None,
                message: format!("includes nest more than {MAX_INCLUDES} deep"),
            });
        }
        let text = self.read(&full, rel)?;
        self.stack.push(key);
        let root = self.document(&text, rel, depth);
        self.stack.pop();
        root
    }

    /// The bytes of a file, within the limit left for the scene's files.
    fn read(&mut self, full: &Path, rel: &Path) -> Result<String, SceneError> {
        let whole = |message: String| SceneError {
            file: Some(rel.to_path_buf()),
            position: None,
            message,
        };
        let bytes = input::read_file_within(full, self.bytes_left).map_err(|e| match e {
            InputError::Io { source, .. } => whole(source.to_string()),
            InputError::NotRegular { kind, .. } => whole(format!(
                "is {kind}, not a regular file; only regular files are read"
            )),
            InputError::TooLarge { size, .. } => whole(format!(
                "the file is {size} bytes, more than the {} bytes left of the limit of {} \
                 bytes for a scene and its includes (raise it with --max-file-size or {})",
                self.bytes_left,
                self.limit,
                input::MAX_FILE_SIZE_VAR
            )),
            e => whole(e.to_string()),
        })?;
        self.bytes_left -= bytes.len() as u64;
        String::from_utf8(bytes).map_err(|e| {
            let offset = e.utf8_error().valid_up_to();
            let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
            let at = Source::new(&text, Arc::new(rel.to_path_buf())).location(offset);
            error_at(&at, "the file is not valid UTF-8")
        })
    }

    fn document(&mut self, text: &str, rel: &Path, depth: usize) -> Result<Element, SceneError> {
        let file = Arc::new(rel.to_path_buf());
        if let Some((offset, name)) = crowded_element(text) {
            let at = Source::new(text, Arc::clone(&file)).location(offset);
            return Err(error_at(
                &at,
                format!(
                    "<{}> has more than {MAX_ATTRIBUTES} attributes (a Mitsuba element takes a few)",
                    quote::clip(name, quote::MAX_QUOTED_CHARS)
                ),
            ));
        }
        let options = roxmltree::ParsingOptions {
            allow_dtd: false,
            // Elements, attributes and text: at most one node per byte.
            nodes_limit: u32::try_from(text.len() + 16).unwrap_or(u32::MAX),
            entity_resolver: None,
        };
        let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| {
            let pos = e.pos();
            let message = e.to_string();
            let suffix = format!(" at {pos}");
            let message = message.strip_suffix(&suffix).unwrap_or(&message);
            SceneError {
                file: Some(rel.to_path_buf()),
                position: Some((pos.row as usize, pos.col as usize)),
                message: format!("malformed XML: {message}"),
            }
        })?;
        let src = Source::new(text, file);
        let root = doc.root_element();
        let at = src.location(root.range().start);
        let version = root.attribute("version").ok_or_else(|| {
            error_at(
                &at,
                format!("<{}>: missing attribute `version`", root.tag_name().name()),
            )
        })?;
        let old = parse_version(version)
            .ok_or_else(|| {
                let value_at = root
                    .attributes()
                    .find(|a| a.name() == "version")
                    .map_or(at.clone(), |a| src.location(a.range_value().start));
                error_at(
                    &value_at,
                    format!("`{}` is not a version (such as 3.0.0)", clip(version)),
                )
            })?
            .0
            < 2;
        if old {
            self.old_files
                .push((rel.to_path_buf(), version.to_string()));
        }
        let dir: Arc<Path> = Arc::from(rel.parent().unwrap_or(Path::new("")));
        let file = FileCtx {
            src: &src,
            dir,
            old,
        };
        let mut out = Vec::new();
        self.element(&file, root, depth, None, &mut out)?;
        let mut root = out.pop().expect("the root element");
        root.attrs.retain(|a| a.name != "version");
        Ok(root)
    }

    /// Reads `node` into `out` (an `<include>` of a scene adds the scene's
    /// children; `<default>` and `<path>` add nothing).
    fn element(
        &mut self,
        file: &FileCtx,
        node: roxmltree::Node,
        depth: usize,
        parent: Option<&str>,
        out: &mut Vec<Element>,
    ) -> Result<(), SceneError> {
        let at = file.src.location(node.range().start);
        if depth > MAX_DEPTH {
            return Err(error_at(
                &at,
                format!("elements nest more than {MAX_DEPTH} deep"),
            ));
        }
        let tag = node.tag_name();
        if tag.namespace().is_some() {
            return Err(error_at(
                &at,
                format!("<{}>: XML namespaces are not used by scenes", tag.name()),
            ));
        }
        let mut attrs = Vec::with_capacity(node.attributes().len());
        for a in node.attributes() {
            let value_at = file.src.location(a.range_value().start);
            let value = self.substitute(a.value(), &value_at)?;
            attrs.push(Attr {
                name: a.name().to_string(),
                value,
                at: value_at,
            });
        }
        let mut element = Element {
            tag: tag.name().to_string(),
            attrs,
            children: Vec::new(),
            at,
            dir: file.dir.clone(),
            old: file.old,
        };
        for child in node.children() {
            if child.is_text() && !child.text().unwrap_or("").trim().is_empty() {
                let at = file.src.location(child.range().start);
                return Err(error_at(&at, "text is not allowed between elements"));
            }
        }
        match element.tag.as_str() {
            "default" => return self.default(&element),
            "include" => return self.include(&element, depth, out),
            "path" => return self.path(&element, parent),
            _ => {}
        }
        let mut children = Vec::new();
        for child in node.children().filter(roxmltree::Node::is_element) {
            self.element(file, child, depth + 1, Some(&element.tag), &mut children)?;
        }
        children.shrink_to_fit();
        element.children = children;
        out.push(element);
        Ok(())
    }

    /// `$name` replaced by the parameter's value; an unknown one is an error.
    fn substitute(&self, text: &str, at: &Location) -> Result<String, SceneError> {
        if !text.contains('$') {
            return Ok(text.to_string());
        }
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let n = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..n];
            match self.params.get(name) {
                Some(v) if !name.is_empty() => out.push_str(v),
                _ => {
                    return Err(error_at(
                        at,
                        format!(
                            "undefined parameter `${}` (give it with <default> or -D {}=VALUE)",
                            clip(name),
                            clip(name)
                        ),
                    ))
                }
            }
            rest = &after[n..];
        }
        out.push_str(rest);
        Ok(out)
    }

    fn default(&mut self, e: &Element) -> Result<(), SceneError> {
        check_attrs(e, &["name", "value"], &["name", "value"])?;
        let name = e.get("name").unwrap_or_default();
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(error_at(
                &e.attr("name").expect("checked").at,
                format!(
                    "`{}` is not a parameter name (letters, digits and _)",
                    clip(name)
                ),
            ));
        }
        if !self.fixed.iter().any(|k| k == name) && !self.params.contains_key(name) {
            let value = e.get("value").unwrap_or_default().to_string();
            self.params.insert(name.to_string(), value);
        }
        Ok(())
    }

    fn include(
        &mut self,
        e: &Element,
        depth: usize,
        out: &mut Vec<Element>,
    ) -> Result<(), SceneError> {
        check_attrs(e, &["filename", "name"], &["filename"])?;
        let attr = e.attr("filename").expect("checked");
        let rel = self.resolve(&e.dir, &attr.value);
        if !rel.exists() {
            return Err(error_at(
                &attr.at,
                format!("<include>: no file `{}`", rel.display()),
            ));
        }
        let key = std::fs::canonicalize(&rel).unwrap_or_else(|_| rel.clone());
        if self.stack.contains(&key) {
            return Err(error_at(
                &attr.at,
                format!(
                    "<include>: an include loop: `{}` is being read already (it includes this \
                     file, directly or through others)",
                    clip(&attr.value)
                ),
            ));
        }
        // Errors inside name the included file and their place in it.
        let mut root = self.file(&rel, depth)?;
        if root.tag == "scene" {
            out.append(&mut root.children);
        } else {
            if let Some(name) = e.attr("name") {
                root.attrs.retain(|a| a.name != "name");
                root.attrs.push(name.clone());
            }
            out.push(root);
        }
        Ok(())
    }

    fn path(&mut self, e: &Element, parent: Option<&str>) -> Result<(), SceneError> {
        check_attrs(e, &["value"], &["value"])?;
        let attr = e.attr("value").expect("checked");
        if parent != Some("scene") {
            return Err(error_at(&e.at, "<path> must be a child of <scene>"));
        }
        let dir = e.dir.join(&attr.value);
        if !dir.is_dir() {
            return Err(error_at(
                &attr.at,
                format!("<path>: no folder `{}`", clip(&attr.value)),
            ));
        }
        self.search.insert(0, dir);
        Ok(())
    }

    /// A file named in `dir`'s file, found as Mitsuba's parser finds an
    /// include: in that folder if it exists there, else in the folders of
    /// the files being read that include it (the nearest first), else in
    /// the `<path>` folders (the last given first), else in the scene's
    /// folder; one found nowhere is `dir`'s, for the error to name.
    pub fn resolve(&self, dir: &Path, name: &str) -> PathBuf {
        let own = dir.join(name);
        if Path::new(name).is_absolute() || own.exists() {
            return own;
        }
        let includers = self.stack.iter().rev().filter_map(|f| f.parent());
        includers
            .chain(self.search.iter().map(PathBuf::as_path))
            .chain([self.scene_dir])
            .map(|d| d.join(name))
            .find(|p| p.exists())
            .unwrap_or(own)
    }

    /// A file a plugin names (a mesh, an image), found where Mitsuba finds
    /// it when the plugin is built: in the `<path>` folders (the last given
    /// first), then in the scene's folder, whichever file names it; then,
    /// beyond Mitsuba, in the folder `dir` of the file that names it. One
    /// found nowhere is the scene folder's, for the error to name.
    pub fn resolve_file(&self, dir: &Path, name: &str) -> PathBuf {
        if Path::new(name).is_absolute() {
            return PathBuf::from(name);
        }
        let scene = self.scene_dir.join(name);
        let search = self.search.iter().map(|d| d.join(name));
        search
            .chain([scene.clone(), dir.join(name)])
            .find(|p| p.exists())
            .unwrap_or(scene)
    }

    /// A path of [`resolve`](Self::resolve) as the scene's own files name
    /// theirs: relative to the scene's folder where it lies below it,
    /// otherwise absolute.
    pub fn scene_relative(&self, path: &Path) -> PathBuf {
        if !self.scene_dir.as_os_str().is_empty() {
            if let Ok(rest) = path.strip_prefix(self.scene_dir) {
                return rest.to_path_buf();
            }
        }
        if path.is_absolute() || self.scene_dir.as_os_str().is_empty() {
            return path.to_path_buf();
        }
        std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
    }
}

struct FileCtx<'s, 't> {
    src: &'s Source<'t>,
    dir: Arc<Path>,
    old: bool,
}

/// `major.minor.patch` (the last two may be left out).
fn parse_version(text: &str) -> Option<(u32, u32, u32)> {
    let parts: Vec<&str> = text.trim().split('.').collect();
    if parts.is_empty() || parts.len() > 3 {
        return None;
    }
    let mut v = [0u32; 3];
    for (i, p) in parts.iter().enumerate() {
        if p.is_empty() || !p.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        v[i] = p.parse().ok()?;
    }
    Some((v[0], v[1], v[2]))
}

/// Refuses an attribute not in `allowed` and a missing one of `required`.
pub fn check_attrs(e: &Element, allowed: &[&str], required: &[&str]) -> Result<(), SceneError> {
    for a in &e.attrs {
        if !allowed.contains(&a.name.as_str()) {
            let names: Vec<String> = allowed.iter().map(|n| format!("`{n}`")).collect();
            return Err(error_at(
                &a.at,
                format!(
                    "<{}>: unexpected attribute `{}` (it takes {})",
                    e.tag,
                    clip(&a.name),
                    names.join(", ")
                ),
            ));
        }
    }
    for r in required {
        if e.attr(r).is_none() {
            return Err(error_at(
                &e.at,
                format!("<{}>: missing attribute `{r}`", e.tag),
            ));
        }
    }
    Ok(())
}

/// Text from a file, cut for a message.
pub fn clip(s: &str) -> String {
    quote::clip(s, quote::MAX_QUOTED_CHARS).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_are_read() {
        assert_eq!(parse_version("3.0.0"), Some((3, 0, 0)));
        assert_eq!(parse_version("0.6"), Some((0, 6, 0)));
        assert_eq!(parse_version("2"), Some((2, 0, 0)));
        for bad in ["", "3.x", "1.2.3.4", "-1", "3..0"] {
            assert_eq!(parse_version(bad), None, "{bad}");
        }
    }
}
