"""Type stubs of the Rust extension ``penumbra._penumbra`` (re-exported by ``penumbra``)."""

import os
from collections.abc import Callable, Mapping
from typing import Any, Literal, TypedDict, final

import numpy as np
import numpy.typing as npt

__version__: str

#: The ray distributions, by name: the thesis's grid, jitter, semi-jitter, poisson, random,
#: fast-random, then the low-discrepancy sobol, zsobol, pmj02, pmj02bn, halton, r2, then custom
#: (the user's own points, given by ``points=``).
DISTRIBUTIONS: tuple[str, ...]
SIMD_SETS: tuple[str, ...]

#: The keyword arguments of ``render`` and ``render_region``.
RENDER_OPTIONS: tuple[str, ...]

#: The ``penumbra render`` flags of the render options, for ``python -m penumbra``.
_OPTION_FLAGS: tuple[dict[str, Any], ...]

DistributionName = Literal[
    "grid",
    "jitter",
    "semi-jitter",
    "poisson",
    "random",
    "fast-random",
    "sobol",
    "zsobol",
    "pmj02",
    "pmj02bn",
    "halton",
    "r2",
    "custom",
]
#: The pixel filters, by name.
FilterName = Literal["box", "tent", "gaussian", "mitchell", "catmullrom", "lanczos"]
StopRuleName = Literal["calibrated", "cycles", "povray", "dammertz"]
IntegratorName = Literal["whitted", "path", "direct", "distributed", "volpath", "volpathmis", "ptracer", "depth", "aov", "moment"]
PathSamplerName = Literal["independent", "sobol", "zsobol", "pmj02", "pmj02bn", "halton", "r2"]
LightSamplerName = Literal["uniform", "power", "bvh"]
StrPath = str | os.PathLike[str]
#: The custom distribution's point sets: a JSON or .npy file, an array of shape (N, 2) or
#: (S, N, 2) in [0, 1), or a function of the set size returning such an array.
PointSets = StrPath | npt.ArrayLike | Callable[[int], npt.ArrayLike]
Image = npt.NDArray[np.float32]

class SceneError(ValueError):
    """An invalid scene or mesh; the message names ``file:line:column`` (or the key path for a dict)."""

class Rays(TypedDict):
    primary: int
    shadow: int
    reflection: int
    refraction: int
    total: int

class Times(TypedDict, total=False):
    build_s: float
    render_s: float
    wall_s: float  # distributed renders only

class Stats(TypedDict, total=False):
    """The document of ``penumbra render --stats`` (docs/statistics.md)."""

    scene: str
    width: int
    height: int
    threads: int
    seed: int
    spp: int
    max_depth: int
    integrator: str
    passes: int
    primitives: int
    rays: Rays
    saved: Rays  # rays the acceleration metrics did not trace, where the library reports them
    metric: dict[str, Any] | None
    time: Times
    mrays_per_s: float
    bad_samples: int
    ended: Literal["complete", "time-limit", "interrupted"]
    region: list[int]  # render_region only: [x0, y0, x1, y1]

#: What ``on_pass`` is told with the image after a pass: the passes finished (``pass``) and in
#: all (``passes``), the seconds of rendering so far (``elapsed``, those before a resumed
#: checkpoint included) and the rays traced so far (``rays``). Functional form: ``pass`` is a
#: keyword.
PassInfo = TypedDict("PassInfo", {"pass": int, "passes": int, "elapsed": float, "rays": int})

class Settings(TypedDict):
    width: int
    height: int
    seed: int
    spp: int
    max_depth: int
    integrator: str
    passes: int
    primitives: int
    build_s: float
    warnings: list[str]

@final
class Scene:
    """A scene description from a TOML file, a Mitsuba 3 XML file, a built-in
    scene or a dict (shaped like a TOML file, or in Mitsuba's ``load_dict`` form).

    Holds the source text (for an XML file: its path and parameters, read
    again where it is rendered), not a built scene: it pickles small and
    rebuilds where it is rendered (meshes and BVH once per geometry, cached).
    """

    @property
    def name(self) -> str:
        """What the stats call the scene (the path or built-in name, or the dict's name)."""
    @property
    def format(self) -> Literal["toml", "json", "xml", "mitsuba_dict"]:
        """``"toml"`` for a TOML file or built-in scene, ``"json"`` for a dict shaped
        like one, ``"xml"`` for a Mitsuba XML file, ``"mitsuba_dict"`` for ``load_dict``."""
    @property
    def text(self) -> str:
        """The source text (TOML, or the JSON of the dict); for an XML file, the TOML
        it converts to (``penumbra convert``'s)."""
    @property
    def base_dir(self) -> str:
        """The directory relative mesh paths are resolved against."""
    @property
    def bunny(self) -> str | None:
        """The Stanford bunny PLY used for ``path = "@bunny"``, if any."""
    def to_dict(self) -> dict[str, Any]:
        """The description as a dict that ``scene_from_dict`` turns back into the same scene
        (for a Mitsuba scene, the dict of the TOML file it converts to)."""
    def derive(self, d: dict[str, Any], *, name: str | None = None) -> Scene:
        """A scene from a dict (e.g. a changed ``to_dict()``) with this scene's base_dir,
        bunny and name, sharing its built meshes and BVH where the geometry matches."""
    def settings(
        self,
        *,
        integrator: IntegratorName | None = None,
        width: int | None = None,
        height: int | None = None,
        spp: int | None = None,
        passes: int | None = None,
        shadow_rays: int | None = None,
        reflection_rays: int | None = None,
        refraction_rays: int | None = None,
        distribution: DistributionName | None = None,
        pixel_distribution: DistributionName | None = None,
        lens_distribution: DistributionName | None = None,
        time_distribution: DistributionName | None = None,
        shadow_distribution: DistributionName | None = None,
        reflection_distribution: DistributionName | None = None,
        refraction_distribution: DistributionName | None = None,
        points: PointSets | None = None,
        filter: FilterName | None = None,
        filter_radius: float | None = None,
        filter_stddev: float | None = None,
        filter_b: float | None = None,
        filter_c: float | None = None,
        filter_lobes: int | None = None,
        splat: bool | None = None,
        filter_steps: int | None = None,
        sample_border: bool | None = None,
        alpha: bool | None = None,
        aperture: float | None = None,
        focal_distance: float | None = None,
        max_depth: int | None = None,
        rr_depth: int | None = None,
        hide_emitters: bool | None = None,
        sets_depth: int | None = None,
        path_sampler: PathSamplerName | None = None,
        light_sampler: LightSamplerName | None = None,
        emitter_samples: int | None = None,
        bsdf_samples: int | None = None,
        seed: int | None = None,
        metric: bool | None = None,
        reflection_metric: bool | None = None,
        shadow_metric: bool | None = None,
        metric_threshold: float | None = None,
        metric_min_rays: int | None = None,
        shadow_metric_rays: int | None = None,
        pixel_metric: bool | None = None,
        noise_threshold: float | None = None,
        stop_rule: StopRuleName | None = None,
        confidence: float | None = None,
        replicas: int | None = None,
        noise_floor: float | None = None,
        min_spp: int | None = None,
        threads: int | None = None,
        progress: Callable[[int, int], object] | None = None,
    ) -> Settings:
        """Validates (builds and caches) the scene with these options; returns the settings in force."""
    def digest(
        self, region: tuple[int, int, int, int] | None = None, **options: Any
    ) -> str:
        """The SHA-256 (hex) a render of ``region`` (None: the frame) with these render options
        is tied to: the description after the options and the bytes of every file it reads.
        Checkpoints and ``penumbra.distributed`` tile files of another digest are refused."""
    def __reduce__(self) -> tuple[Any, ...]: ...
    def __dask_tokenize__(self) -> tuple[Any, ...]: ...

class Hits(TypedDict):
    """What ``TriangleMesh.intersect`` returns: one entry per ray."""

    t: npt.NDArray[np.float32]  # inf for a miss
    prim: npt.NDArray[np.int64]  # triangle index, -1 for a miss
    u: npt.NDArray[np.float32]  # barycentric weight of the second vertex
    v: npt.NDArray[np.float32]  # barycentric weight of the third vertex

@final
class TriangleMesh:
    """Triangles in Penumbra's BVH, to trace batches of rays against (docs/python.md)."""

    def __init__(self, vertices: npt.ArrayLike, faces: npt.ArrayLike | None = None) -> None: ...
    def __len__(self) -> int: ...
    def intersect(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tmin: float = 0.0,
        tmax: float | npt.ArrayLike | None = None,
    ) -> Hits: ...
    def occluded(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tmin: float = 0.0,
        tmax: float | npt.ArrayLike | None = None,
    ) -> npt.NDArray[np.bool_]: ...

def load_scene(
    path_or_builtin_name: StrPath,
    *,
    params: Mapping[str, str | int | float | bool] | None = None,
    bunny: StrPath | None = None,
) -> Scene:
    """Reads a scene file (TOML or Mitsuba 3 XML), or a built-in scene by name.

    ``params`` sets an XML scene's ``$name`` parameters over its ``<default>``s,
    as ``-D name=value`` does (bools as ``true``/``false``); on any other scene
    it is an error. Raises SceneError (file:line:col, in an included file too).
    """

def load_dict(
    d: Mapping[str, Any],
    *,
    base_dir: StrPath = ".",
    bunny: StrPath | None = None,
    name: str | None = None,
) -> Scene:
    """A scene from a dict in Mitsuba 3's ``load_dict`` form (``{"type": "scene", ...}``),
    lowered by the mapping Mitsuba XML files take. Nested dicts with a ``type`` are
    objects, ``{"type": "rgb"|"spectrum", "value": ...}`` colours, ``{"type": "ref",
    "id": ...}`` references; a sequence of 3 numbers is a point or vector, a 4×4
    array-like (nested lists, a numpy array, a Mitsuba ``ScalarTransform4f``) a
    transform. Raises SceneError naming the key path (``ball.bsdf.reflectance``).
    """

def scene_from_dict(
    d: dict[str, Any],
    *,
    base_dir: StrPath = ".",
    bunny: StrPath | None = None,
    name: str | None = None,
) -> Scene:
    """A scene from a dict shaped like a scene file. Raises SceneError naming the key path."""

def render(
    scene: Scene,
    *,
    integrator: IntegratorName | None = None,
    width: int | None = None,
    height: int | None = None,
    spp: int | None = None,
    passes: int | None = None,
    shadow_rays: int | None = None,
    reflection_rays: int | None = None,
    refraction_rays: int | None = None,
    distribution: DistributionName | None = None,
    pixel_distribution: DistributionName | None = None,
    lens_distribution: DistributionName | None = None,
    time_distribution: DistributionName | None = None,
    shadow_distribution: DistributionName | None = None,
    reflection_distribution: DistributionName | None = None,
    refraction_distribution: DistributionName | None = None,
    points: PointSets | None = None,
    filter: FilterName | None = None,
    filter_radius: float | None = None,
    filter_stddev: float | None = None,
    filter_b: float | None = None,
    filter_c: float | None = None,
    filter_lobes: int | None = None,
    splat: bool | None = None,
    filter_steps: int | None = None,
    sample_border: bool | None = None,
    alpha: bool | None = None,
    aperture: float | None = None,
    focal_distance: float | None = None,
    max_depth: int | None = None,
    rr_depth: int | None = None,
    hide_emitters: bool | None = None,
    sets_depth: int | None = None,
    path_sampler: PathSamplerName | None = None,
    light_sampler: LightSamplerName | None = None,
    emitter_samples: int | None = None,
    bsdf_samples: int | None = None,
    seed: int | None = None,
    metric: bool | None = None,
    reflection_metric: bool | None = None,
    shadow_metric: bool | None = None,
    metric_threshold: float | None = None,
    metric_min_rays: int | None = None,
    shadow_metric_rays: int | None = None,
    pixel_metric: bool | None = None,
    noise_threshold: float | None = None,
    stop_rule: StopRuleName | None = None,
    confidence: float | None = None,
    replicas: int | None = None,
    noise_floor: float | None = None,
    min_spp: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    time_limit: float | None = None,
    checkpoint: StrPath | None = None,
    checkpoint_interval: float = 60.0,
    resume: StrPath | None = None,
    on_pass: Callable[[Image, PassInfo], object] | None = None,
) -> tuple[Image, Stats]:
    """Renders the frame: a float32 (height, width, 3) linear-RGB image and the stats document.

    With an integrator that writes channels beside the image (``aov``,
    ``moment``) the image is (height, width, 3 + C): RGB, then the channels
    in Mitsuba's order, their names in ``stats["channels"]`` (``R``, ``G``,
    ``B`` first).
    """

def render_region(
    scene: Scene,
    x0: int,
    y0: int,
    x1: int,
    y1: int,
    *,
    integrator: IntegratorName | None = None,
    width: int | None = None,
    height: int | None = None,
    spp: int | None = None,
    passes: int | None = None,
    shadow_rays: int | None = None,
    reflection_rays: int | None = None,
    refraction_rays: int | None = None,
    distribution: DistributionName | None = None,
    pixel_distribution: DistributionName | None = None,
    lens_distribution: DistributionName | None = None,
    time_distribution: DistributionName | None = None,
    shadow_distribution: DistributionName | None = None,
    reflection_distribution: DistributionName | None = None,
    refraction_distribution: DistributionName | None = None,
    points: PointSets | None = None,
    filter: FilterName | None = None,
    filter_radius: float | None = None,
    filter_stddev: float | None = None,
    filter_b: float | None = None,
    filter_c: float | None = None,
    filter_lobes: int | None = None,
    splat: bool | None = None,
    filter_steps: int | None = None,
    sample_border: bool | None = None,
    alpha: bool | None = None,
    aperture: float | None = None,
    focal_distance: float | None = None,
    max_depth: int | None = None,
    rr_depth: int | None = None,
    hide_emitters: bool | None = None,
    sets_depth: int | None = None,
    path_sampler: PathSamplerName | None = None,
    light_sampler: LightSamplerName | None = None,
    emitter_samples: int | None = None,
    bsdf_samples: int | None = None,
    seed: int | None = None,
    metric: bool | None = None,
    reflection_metric: bool | None = None,
    shadow_metric: bool | None = None,
    metric_threshold: float | None = None,
    metric_min_rays: int | None = None,
    shadow_metric_rays: int | None = None,
    pixel_metric: bool | None = None,
    noise_threshold: float | None = None,
    stop_rule: StopRuleName | None = None,
    confidence: float | None = None,
    replicas: int | None = None,
    noise_floor: float | None = None,
    min_spp: int | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    time_limit: float | None = None,
    checkpoint: StrPath | None = None,
    checkpoint_interval: float = 60.0,
    resume: StrPath | None = None,
    on_pass: Callable[[Image, PassInfo], object] | None = None,
) -> tuple[Image, Stats]:
    """Renders pixels [x0, x1) × [y0, y1) with their full-frame values: tiles stitch exactly."""

def samples(
    distribution: DistributionName,
    count: int,
    radius: float = 1.0,
    seed: int = 0,
    points: PointSets | None = None,
) -> npt.NDArray[np.float32]:
    """A distribution's points in trace order: shape (count, 2), or (count, 3) for fast-random."""

def save_image(path: StrPath, image: npt.ArrayLike) -> None:
    """Writes a (height, width, 3) image atomically: .png (8-bit sRGB) or .exr (float linear)."""

def load_image(path: StrPath) -> Image:
    """Reads an OpenEXR file into a float32 (height, width, 3) array."""

def kernels(name: str | None = None) -> str:
    """The kernel set of scenes loaded from now on; with `name`, chooses it."""

def scenes() -> dict[str, str]:
    """The built-in scenes: name → description."""

def _check_options(**options: Any) -> None: ...
