//! `penumbra.Scene`: a scene description and where it came from.
//!
//! A `Scene` holds the description's *text* (the TOML file, the JSON of a
//! dict, of either shape) or a Mitsuba XML file's path and parameters, its
//! base directory and the bunny path, never a built scene: that is
//! what travels to Dask workers (pickled) and what `render` rebuilds from,
//! with the same error positions every time. Each render validates the
//! description after overrides; the expensive part of a build, loading the
//! meshes and building the BVH, happens on the first render and is kept in
//! the object for later renders with the same geometry (other tiles, sample
//! counts, distributions, image sizes), until a mesh file changes.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString, PyTuple, PyType};
use serde_json::Value;

use penumbra::description::mitsuba::dict::DictValue;
use penumbra::description::toml_to_json;
use penumbra::input::{note_read, recording_reads};
use penumbra::render::{render_digest, Digest, DigestInput, Region};
use penumbra::scene::{
    default_bunny_path, LoadOptions, Points, Scene as Built, SceneError as LibSceneError,
    SceneSource, WorldCache,
};

use crate::convert::{json_to_py, json_to_py_with, py_to_dict_value, py_to_json, ToPy};
use crate::error::SceneError;
use crate::options::{parse_options, Options};
use crate::points::function_table;

/// How the library labels the text of a built-in scene (`SceneSource::open`).
const BUILTIN_LABEL: &str = "<built-in scene ";

/// The text a scene was read from.
#[derive(Clone, Debug)]
enum Text {
    /// A TOML file or built-in scene; `file` labels error positions.
    Toml { text: String, file: PathBuf },
    /// The JSON of a dict given to `scene_from_dict`.
    Json { text: String },
    /// A Mitsuba 3 XML file and its parameters (`<default>` overrides),
    /// read again with its includes for every build, so that every error
    /// names the file, line and column that hold it.
    Xml {
        file: PathBuf,
        params: Vec<(String, String)>,
    },
    /// The JSON of a dict in Mitsuba's form given to `load_dict`, its
    /// entries in the dict's order.
    MitsubaDict { text: String },
}

/// A scene description (from a TOML file, a built-in scene or a dict),
/// ready to render with `penumbra.render`. Picklable: it pickles as its
/// source text plus base directory and bunny path (made absolute), so it
/// means the same on a Dask worker; its meshes and BVH are built there once
/// per process.
#[pyclass(module = "penumbra._penumbra", frozen)]
pub struct Scene {
    name: String,
    text: Text,
    base_dir: PathBuf,
    bunny: Option<PathBuf>,
    /// The worlds (meshes and BVH) of the last few builds, shared by builds
    /// that differ in settings only, and with the scenes [`derive`]d from
    /// this one.
    ///
    /// [`derive`]: Scene::derive
    worlds: Arc<Mutex<WorldCache>>,
}

/// A library scene error as `penumbra.SceneError`, with the CLI's message.
pub fn scene_error(e: LibSceneError) -> PyErr {
    SceneError::new_err(e.to_string())
}

impl Scene {
    fn new(name: String, text: Text, base_dir: PathBuf, bunny: Option<PathBuf>) -> Scene {
        Scene {
            name,
            text,
            base_dir,
            bunny,
            worlds: Arc::new(Mutex::new(WorldCache::default())),
        }
    }

    /// The name the stats document reports (`scene`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parsed source, as the CLI has it before applying overrides.
    fn source(&self) -> Result<SceneSource, LibSceneError> {
        let mut opts = LoadOptions {
            bunny: self.bunny.clone(),
            ..Default::default()
        };
        match &self.text {
            Text::Toml { text, file } => SceneSource::from_toml(text, file, &self.base_dir, &opts),
            Text::Json { text } => {
                let value: Value = serde_json::from_str(text)
                    .map_err(|e| LibSceneError::new(format!("corrupt scene JSON: {e}")))?;
                SceneSource::from_json(&value, &self.base_dir, &opts)
            }
            Text::Xml { file, params } => {
                opts.defines = params.clone();
                SceneSource::from_xml(file, &self.base_dir, &opts)
            }
            Text::MitsubaDict { text } => {
                let d = DictValue::from_json(text)
                    .map_err(|e| LibSceneError::new(format!("corrupt scene JSON: {e}")))?;
                SceneSource::from_mitsuba_dict(&d, &self.base_dir, &opts)
            }
        }
    }

    /// The scene built with these options, its world (meshes and BVH)
    /// taken from an earlier build with the same geometry and mesh files;
    /// a `points=` function is called for the set sizes of the built scene.
    pub fn build(&self, py: Python<'_>, opts: &Options) -> PyResult<Built> {
        Ok(self.build_recorded(py, opts)?.0)
    }

    /// [`build`](Self::build), and the digest a checkpoint of a render of
    /// `region` of it is tied to: the description as the options left it,
    /// every file the build read (those of a reused world too: the cache
    /// records them as read again), and the points given as an array or
    /// made by a function.
    pub fn build_with_digest(
        &self,
        py: Python<'_>,
        opts: &Options,
        region: Option<Region>,
    ) -> PyResult<(Built, Digest)> {
        let (built, source, mut reads) = self.build_recorded(py, opts)?;
        if let Some(Points::Table(_)) = &opts.overrides.points {
            let table = format!("{:?}", built.settings.points);
            reads.push(DigestInput::new().add(table.as_bytes()).finish().0);
        }
        Ok((built, render_digest(&source, &reads, region)))
    }

    /// The scene built, its source after the options, and the digests of
    /// the files read to build it (the XML file and its includes, meshes,
    /// textures, volumes, point files).
    fn build_recorded(
        &self,
        py: Python<'_>,
        opts: &Options,
    ) -> PyResult<(Built, SceneSource, Vec<[u8; 32]>)> {
        let (built, reads) = recording_reads(|| -> PyResult<_> {
            // Read from a file: as `penumbra render` reads it first, so
            // that the two tie their checkpoints to the same digest.
            if let Text::Toml { text, file } = &self.text {
                if !file.to_string_lossy().starts_with(BUILTIN_LABEL) {
                    note_read(text.as_bytes());
                }
            }
            let mut source = self.source().map_err(scene_error)?;
            opts.overrides.apply(&mut source);
            let built = py.detach(|| {
                let mut worlds = self.worlds.lock().unwrap_or_else(|e| e.into_inner());
                source.build_reusing(&mut worlds)
            });
            Ok((built.map_err(scene_error)?, source))
        });
        let (mut built, source) = built?;
        if let Some(f) = &opts.points_fn {
            let sizes = built.custom_set_sizes();
            if !sizes.is_empty() {
                built.settings.points = Arc::new(function_table(f.bind(py), &sizes)?);
            }
        }
        Ok((built, source, reads))
    }

    /// The TOML scene file the description converts to (`penumbra
    /// convert`'s text, file names relative to the base directory).
    fn converted(&self) -> PyResult<String> {
        let source = self.source().map_err(scene_error)?;
        penumbra::scene::convert::to_toml(&source, &self.base_dir).map_err(scene_error)
    }

    fn format(&self) -> &'static str {
        match self.text {
            Text::Toml { .. } => "toml",
            Text::Json { .. } => "json",
            Text::Xml { .. } => "xml",
            Text::MitsubaDict { .. } => "mitsuba_dict",
        }
    }

    /// What pickling keeps: paths made absolute so that a worker with another
    /// working directory finds the same files.
    fn state(
        &self,
    ) -> (
        String,
        &'static str,
        String,
        Option<String>,
        String,
        Option<String>,
    ) {
        let abs = |p: &Path| {
            std::path::absolute(p)
                .unwrap_or_else(|_| p.to_path_buf())
                .to_string_lossy()
                .into_owned()
        };
        let (text, file) = match &self.text {
            Text::Toml { text, file } => (text.clone(), Some(file.to_string_lossy().into_owned())),
            Text::Json { text } | Text::MitsubaDict { text } => (text.clone(), None),
            // The parameters as a JSON list of [name, value] pairs.
            Text::Xml { file, params } => (serde_json::json!(params).to_string(), Some(abs(file))),
        };
        (
            self.name.clone(),
            self.format(),
            text,
            file,
            abs(&self.base_dir),
            self.bunny.as_deref().map(abs),
        )
    }
}

#[pymethods]
impl Scene {
    /// What the stats call the scene: the path or built-in name given to
    /// `load_scene`, or the `name` given to `scene_from_dict`.
    #[getter(name)]
    fn py_name(&self) -> &str {
        &self.name
    }

    /// `"toml"` (a file or built-in scene), `"json"` (made from a dict
    /// shaped like a scene file), `"xml"` (a Mitsuba XML file) or
    /// `"mitsuba_dict"` (made by `load_dict`).
    #[getter(format)]
    fn py_format(&self) -> &'static str {
        self.format()
    }

    /// The source text: the TOML file, the JSON of the dict (either
    /// shape), or for a Mitsuba XML file the TOML it converts to
    /// (`penumbra convert`'s), with its parameters.
    #[getter]
    fn text(&self) -> PyResult<String> {
        match &self.text {
            Text::Toml { text, .. } | Text::Json { text } | Text::MitsubaDict { text } => {
                Ok(text.clone())
            }
            Text::Xml { .. } => self.converted(),
        }
    }

    /// The directory relative mesh paths are resolved against.
    #[getter]
    fn base_dir(&self) -> String {
        self.base_dir.to_string_lossy().into_owned()
    }

    /// The Stanford bunny used for `path = "@bunny"`, if one was given or found.
    #[getter]
    fn bunny(&self) -> Option<String> {
        self.bunny
            .as_deref()
            .map(|p| p.to_string_lossy().into_owned())
    }

    /// The description as a dict, shaped like the scene file: the keys the
    /// file (or dict) gives, defaults left out; for a Mitsuba scene (XML or
    /// `load_dict`), the keys of the TOML it converts to.
    /// `scene_from_dict(scene.to_dict(), base_dir=scene.base_dir)` renders
    /// exactly like `scene`: this is how animation frames change a camera
    /// or an object.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let value = match &self.text {
            Text::Toml { text, file } => toml_to_json(text, file).map_err(scene_error)?,
            Text::Json { text } => serde_json::from_str(text)
                .map_err(|e| PyValueError::new_err(format!("cannot convert the scene: {e}")))?,
            Text::Xml { .. } | Text::MitsubaDict { .. } => {
                toml_to_json(&self.converted()?, Path::new("<converted scene>"))
                    .map_err(scene_error)?
            }
        };
        json_to_py_with(
            py,
            &value,
            ToPy {
                drop_nulls: true,
                f32_values: true,
            },
        )
    }

    /// A scene from the dict `d` (shaped like a scene file: typically this
    /// scene's `to_dict()`, changed), with this scene's base directory and
    /// bunny, and its name unless `name` is given. It shares this scene's
    /// built meshes and BVHs: a render whose geometry (objects, light
    /// shapes, material names, mesh files) matches one built for either
    /// scene reuses it, so animation frames that move only the camera build
    /// them once. Renders exactly like `scene_from_dict(d, base_dir=...,
    /// bunny=..., name=...)`.
    #[pyo3(signature = (d, *, name = None))]
    fn derive(&self, d: &Bound<'_, PyAny>, name: Option<String>) -> PyResult<Scene> {
        Ok(Scene {
            name: name.unwrap_or_else(|| self.name.clone()),
            text: dict_text("Scene.derive", d)?,
            base_dir: self.base_dir.clone(),
            bunny: self.bunny.clone(),
            worlds: Arc::clone(&self.worlds),
        })
    }

    /// Built worlds this scene holds (with the scenes it shares them with);
    /// for tests.
    fn _worlds_kept(&self) -> usize {
        self.worlds.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    /// Validates the scene with these render options, exactly as `render`
    /// would (loading meshes and building the BVH, which is then cached), and
    /// returns the settings in force: width, height (of the frame sampled:
    /// the film and, with `sample_border`, the filter's reach beyond it),
    /// crop (the part of that frame rendered and returned, `[x0, y0, x1,
    /// y1]`), seed, spp, max_depth,
    /// primitives, build_s and warnings. Raises SceneError for an invalid
    /// scene. Use it to fail early, before sending work to a cluster.
    #[pyo3(signature = (**options))]
    fn settings<'py>(
        &self,
        py: Python<'py>,
        options: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let opts = parse_options("settings", options)?;
        let built = self.build(py, &opts)?;
        let s = &built.settings;
        let config = penumbra::integrator::Config::of(&built)
            .map_err(|e| scene_error(LibSceneError::from(e)))?;
        let crop = penumbra::render::frame(s);
        let doc = serde_json::json!({
            "width": s.width,
            "height": s.height,
            "crop": [crop.x0, crop.y0, crop.x1, crop.y1],
            "seed": s.seed,
            "spp": s.spp,
            "max_depth": config.depth(),
            "integrator": config.choice().name(),
            "passes": config.passes(),
            "primitives": built.world.primitive_count(),
            "build_s": built.build_time.as_secs_f64(),
            "warnings": built.warnings,
        });
        json_to_py(py, &doc)
    }

    /// The digest (64 hex digits) a render of this scene with these render
    /// options is tied to: of its description after the options, the
    /// bytes of every file it reads (meshes, textures, an XML file and its
    /// includes) and `region` (`(x0, y0, x1, y1)`; None: the whole frame).
    /// A checkpoint, or a tile `penumbra.distributed.render` keeps in its
    /// `tiles_dir`, of another digest is refused. Builds the scene as
    /// `settings` does (raising SceneError for an invalid one).
    #[pyo3(signature = (region = None, **options))]
    fn digest(
        &self,
        py: Python<'_>,
        region: Option<(u32, u32, u32, u32)>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<String> {
        let opts = parse_options("digest", options)?;
        let region = region.map(|(x0, y0, x1, y1)| Region { x0, y0, x1, y1 });
        let (_, digest) = self.build_with_digest(py, &opts, region)?;
        Ok(digest.hex())
    }

    /// Rebuilds a scene from `__reduce__`'s state (used by pickle).
    #[classmethod]
    fn _restore(
        _cls: &Bound<'_, PyType>,
        state: (
            String,
            String,
            String,
            Option<String>,
            String,
            Option<String>,
        ),
    ) -> PyResult<Scene> {
        let (name, format, text, file, base_dir, bunny) = state;
        let corrupt = || PyValueError::new_err("corrupt pickled penumbra.Scene");
        let text = match (format.as_str(), file) {
            ("toml", Some(file)) => Text::Toml {
                text,
                file: PathBuf::from(file),
            },
            ("json", None) => Text::Json { text },
            ("xml", Some(file)) => Text::Xml {
                file: PathBuf::from(file),
                params: serde_json::from_str(&text).map_err(|_| corrupt())?,
            },
            ("mitsuba_dict", None) => Text::MitsubaDict { text },
            _ => return Err(corrupt()),
        };
        let scene = Scene::new(
            name,
            text,
            PathBuf::from(base_dir),
            bunny.map(PathBuf::from),
        );
        // Fail at unpickling, not at the first render, if the text is unusable.
        scene.source().map_err(scene_error)?;
        Ok(scene)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let restore = py.get_type::<Scene>().getattr("_restore")?;
        let state = slf.get().state().into_pyobject(py)?;
        PyTuple::new(
            py,
            [restore.into_any(), PyTuple::new(py, [state])?.into_any()],
        )
    }

    /// Dask's deterministic token: equal descriptions give equal task keys.
    fn __dask_tokenize__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(("penumbra.Scene", self.state())
            .into_pyobject(py)?
            .into_any())
    }

    fn __repr__(&self) -> String {
        format!("<penumbra.Scene {:?} ({})>", self.name, self.format())
    }
}

/// Reads a scene file (TOML or Mitsuba 3 XML), or a built-in scene by name
/// (`penumbra.scenes()`).
///
/// Parses the file (syntax, types and unknown keys are checked here, with
/// `file:line:column` in the SceneError); values are validated when the
/// scene is rendered, after the render options are applied, as the command
/// line does (`Scene.settings()` validates early). `params` sets a Mitsuba
/// XML scene's parameters (`$name`), over its `<default>`s, as `-D
/// name=value` does: each value a str, int, float or bool. `bunny` is the
/// Stanford bunny PLY for `path = "@bunny"` (default: `$PENUMBRA_BUNNY`).
#[pyfunction]
#[pyo3(signature = (path_or_builtin_name, *, params = None, bunny = None))]
pub fn load_scene(
    path_or_builtin_name: PathBuf,
    params: Option<&Bound<'_, PyDict>>,
    bunny: Option<PathBuf>,
) -> PyResult<Scene> {
    let name = path_or_builtin_name
        .to_str()
        .ok_or_else(|| PyValueError::new_err("the scene path is not valid UTF-8"))?
        .to_owned();
    let bunny = bunny.or_else(default_bunny_path);
    let path = Path::new(&name);
    let is_xml = path.exists()
        && path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("xml"));
    let params = match params {
        Some(p) if !p.is_empty() => {
            if !is_xml {
                return Err(SceneError::new_err(format!(
                    "{name}: `params` sets the parameters of Mitsuba XML scenes (.xml); this is \
                     not one"
                )));
            }
            define_values(p)?
        }
        _ => Vec::new(),
    };
    // As the library resolves it: a file if one exists, else a built-in scene.
    let base = if path.exists() {
        path.parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
    } else {
        PathBuf::from(".")
    };
    if is_xml {
        let scene = Scene::new(
            name.clone(),
            Text::Xml {
                file: path.to_path_buf(),
                params,
            },
            base,
            bunny,
        );
        // Read now, so that a bad file fails here, not at the first render.
        scene.source().map_err(scene_error)?;
        return Ok(scene);
    }
    let opts = LoadOptions {
        bunny: bunny.clone(),
        ..Default::default()
    };
    // The library's own reading (bounded, regular files only), so every
    // error is the CLI's; the text kept is the text it parsed.
    let source = SceneSource::open(&name, &opts).map_err(scene_error)?;
    let (file, text) = source
        .text()
        .ok_or_else(|| SceneError::new_err(format!("{name}: the scene has no text")))?;
    let scene = Scene::new(
        name.clone(),
        Text::Toml {
            text: text.to_string(),
            file: file.to_path_buf(),
        },
        base,
        bunny,
    );
    Ok(scene)
}

/// `params` as `-D name=value` pairs: a bool as `true`/`false`, a number
/// as its shortest decimal, a str as it is.
fn define_values(params: &Bound<'_, PyDict>) -> PyResult<Vec<(String, String)>> {
    let mut out = Vec::with_capacity(params.len());
    for (k, v) in params.iter() {
        let key: String = k.extract().map_err(|_| {
            PyTypeError::new_err(format!("params: keys must be str, got {}", type_name(&k)))
        })?;
        let value = if let Ok(b) = v.cast::<PyBool>() {
            (if b.is_true() { "true" } else { "false" }).to_string()
        } else if v.is_instance_of::<PyInt>() {
            v.extract::<i64>()
                .map_err(|_| {
                    SceneError::new_err(format!("params[{key:?}]: the integer is out of range"))
                })?
                .to_string()
        } else if v.is_instance_of::<PyFloat>() {
            let x: f64 = v.extract()?;
            if !x.is_finite() {
                return Err(SceneError::new_err(format!(
                    "params[{key:?}]: must be a finite number, got {x}"
                )));
            }
            format!("{x}")
        } else if let Ok(s) = v.cast::<PyString>() {
            s.to_str()?.to_owned()
        } else {
            return Err(PyTypeError::new_err(format!(
                "params[{key:?}]: must be a str, int, float or bool, got {}",
                type_name(&v)
            )));
        };
        out.push((key, value));
    }
    Ok(out)
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string())
}

/// A scene from a dict in Mitsuba 3's form (`mi.load_dict`'s): `{"type":
/// "scene", "sensor": {"type": "perspective", ...}, "ball": {"type":
/// "sphere", ...}, ...}`, lowered by the same mapping as a Mitsuba XML
/// file. Nested dicts are objects (their `type` the plugin), `{"type":
/// "rgb", "value": ...}` and `{"type": "spectrum", "value": ...}` colours,
/// `{"type": "ref", "id": ...}` references; a list of 3 numbers is a point
/// or vector and a 4×4 array-like (nested lists, a numpy array) a
/// transform such as `to_world`. Errors raise SceneError naming the key
/// path (`ball.bsdf.reflectance`). Relative file names are resolved
/// against `base_dir`.
#[pyfunction]
#[pyo3(signature = (d, *, base_dir = PathBuf::from("."), bunny = None, name = None))]
pub fn load_dict(
    d: &Bound<'_, PyAny>,
    base_dir: PathBuf,
    bunny: Option<PathBuf>,
    name: Option<String>,
) -> PyResult<Scene> {
    if !d.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "load_dict expects a dict in Mitsuba's form ({{\"type\": \"scene\", ...}}), got {}",
            type_name(d)
        )));
    }
    let value = py_to_dict_value(d, "", 0).map_err(|e| {
        let py = d.py();
        if e.is_instance_of::<PyValueError>(py) {
            SceneError::new_err(e.value(py).to_string())
        } else {
            e
        }
    })?;
    let base_dir = std::path::absolute(&base_dir).unwrap_or(base_dir);
    let scene = Scene::new(
        name.unwrap_or_else(|| "<dict>".to_string()),
        Text::MitsubaDict {
            text: value.to_json(),
        },
        base_dir,
        bunny.or_else(default_bunny_path),
    );
    scene.source().map_err(scene_error)?;
    Ok(scene)
}

/// A scene from a dict with the same structure as a scene file
/// (`{"render": {...}, "camera": {...}, "materials": {...}, "objects": [...],
/// "lights": [...]}`), deserialized into the same description type the TOML
/// parser produces: same keys, defaults and validation. Unknown keys and
/// wrong types raise SceneError naming the key path. Vectors may be lists,
/// tuples or numpy arrays. Relative mesh paths are resolved against `base_dir`.
#[pyfunction]
#[pyo3(signature = (d, *, base_dir = PathBuf::from("."), bunny = None, name = None))]
pub fn scene_from_dict(
    d: &Bound<'_, PyAny>,
    base_dir: PathBuf,
    bunny: Option<PathBuf>,
    name: Option<String>,
) -> PyResult<Scene> {
    Ok(Scene::new(
        name.unwrap_or_else(|| "<dict>".to_string()),
        dict_text("scene_from_dict", d)?,
        base_dir,
        bunny.or_else(default_bunny_path),
    ))
}

/// The JSON text of a dict shaped like a scene file, checked to deserialize.
fn dict_text(func: &str, d: &Bound<'_, PyAny>) -> PyResult<Text> {
    if !d.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "{func} expects a dict shaped like a scene file"
        )));
    }
    let value = py_to_json(d, "", 0).map_err(|e| {
        // Bad values are a bad scene; keep the type of a wrong Python type.
        let py = d.py();
        if e.is_instance_of::<PyValueError>(py) {
            SceneError::new_err(e.value(py).to_string())
        } else {
            e
        }
    })?;
    let text = value.to_string();
    // Types, shapes and keys are checked now, values when the scene is built.
    SceneSource::from_json(&value, Path::new("."), &LoadOptions::default()).map_err(scene_error)?;
    Ok(Text::Json { text })
}
