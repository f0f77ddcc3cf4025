"""The Python API on its own: scenes, renders, regions, samples, images, errors."""

from __future__ import annotations

import json
import os
import pickle
import signal
import subprocess
import sys
import textwrap
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

import penumbra

TETRA_OBJ = """\
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
"""

MESH_SCENE = """\
[render]
width = 40
height = 30
shadow_rays = 4
distribution = "jitter"

[camera]
position = [1.5, 1.5, 3.0]
look_at = [0.3, 0.3, 0.3]

[[objects]]
type = "mesh"
path = "meshes/tetra.obj"
transform = { rotate_axis = [0.0, 1.0, 0.0], rotate_degrees = 20.0 }

[[objects]]
type = "quad"
origin = [-3.0, 0.0, -3.0]
edge_u = [0.0, 0.0, 6.0]
edge_v = [6.0, 0.0, 0.0]

[[lights]]
type = "rect"
origin = [-0.5, 3.0, -0.5]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 1.0]
radiance = [8.0, 8.0, 8.0]
"""


@pytest.fixture()
def mesh_scene(tmp_path: Path) -> Path:
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "tetra.obj").write_text(TETRA_OBJ)
    path = tmp_path / "tetra.toml"
    path.write_text(MESH_SCENE)
    return path


def test_render_returns_a_float_image_and_the_stats_document(small):
    image, stats = penumbra.render(penumbra.load_scene("showcase"), **small)
    assert image.shape == (32, 48, 3) and image.dtype == np.float32
    assert np.isfinite(image).all() and image.mean() > 0
    assert stats["scene"] == "showcase"
    assert (stats["width"], stats["height"], stats["spp"]) == (48, 32, 4)
    assert stats["rays"]["primary"] == 48 * 32 * 4
    r = stats["rays"]
    assert r["total"] == r["primary"] + r["shadow"] + r["reflection"] + r["refraction"]
    assert {"build_s", "render_s"} <= stats["time"].keys()


def test_same_seed_same_pixels_on_any_thread_count(small):
    scene = penumbra.load_scene("showcase")
    a, sa = penumbra.render(scene, seed=3, threads=1, **small)
    b, sb = penumbra.render(scene, seed=3, threads=2, **small)
    c, _ = penumbra.render(scene, seed=4, threads=2, **small)
    assert np.array_equal(a, b)
    assert sa["rays"] == sb["rays"]
    assert not np.array_equal(a, c)


def test_every_kernel_set_gives_the_same_pixels(small):
    default = penumbra.kernels()
    assert default == penumbra.SIMD_SETS[0] and "portable" in penumbra.SIMD_SETS
    try:
        runs = {}
        for name in penumbra.SIMD_SETS:
            assert penumbra.kernels(name) == name
            image, stats = penumbra.render(penumbra.load_scene("cornell-box"), **small)
            assert stats["kernels"] == name
            runs[name] = (image, stats["rays"])
        want = runs["portable"]
        for name, (image, rays) in runs.items():
            assert np.array_equal(image, want[0]), name
            assert rays == want[1], name
        with pytest.raises(ValueError, match="kernel set"):
            penumbra.kernels("sse9")
    finally:
        penumbra.kernels(default)


def test_a_kernel_set_from_the_environment_is_used_or_warned_about():
    code = "import penumbra; print(penumbra.kernels())"
    for value, want in (("portable", "portable"), ("sse9", penumbra.SIMD_SETS[0])):
        env = {**os.environ, "PENUMBRA_SIMD": value}
        p = subprocess.run([sys.executable, "-W", "always", "-c", code], env=env, capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        assert p.stdout.strip() == want
        assert ("unknown kernel set 'sse9'" in p.stderr) == (value == "sse9"), p.stderr


def test_dict_and_toml_front_ends_give_the_same_scene(small):
    toml_scene = penumbra.load_scene("showcase")
    dict_scene = penumbra.scene_from_dict(tomllib.loads(toml_scene.text))
    assert dict_scene.format == "json" and toml_scene.format == "toml"
    a, sa = penumbra.render(toml_scene, **small)
    b, sb = penumbra.render(dict_scene, **small)
    assert np.array_equal(a, b)
    assert sa["rays"] == sb["rays"]


def test_to_dict_round_trips_exactly(small):
    scene = penumbra.load_scene("showcase")
    d = scene.to_dict()
    assert d["render"]["distribution"] == "jitter"
    assert "pixel_distribution" not in d["render"], "absent values stay absent"
    again = penumbra.scene_from_dict(d, name="copy")
    assert again.to_dict() == d
    a, _ = penumbra.render(scene, **small)
    b, stats = penumbra.render(again, **small)
    assert np.array_equal(a, b)
    assert stats["scene"] == "copy"


def test_relative_mesh_paths_follow_the_scene_file(mesh_scene: Path):
    scene = penumbra.load_scene(mesh_scene)
    image, stats = penumbra.render(scene, spp=1)
    assert image.shape == (30, 40, 3)
    assert stats["primitives"] >= 5
    d = scene.to_dict()
    with pytest.raises(penumbra.SceneError, match="tetra.obj"):
        penumbra.render(penumbra.scene_from_dict(d))  # base_dir "." has no meshes/
    b, _ = penumbra.render(penumbra.scene_from_dict(d, base_dir=mesh_scene.parent), spp=1)
    assert np.array_equal(image, b)


def test_a_settings_sweep_renders_what_fresh_scenes_render(mesh_scene: Path):
    scene = penumbra.load_scene(mesh_scene)
    sweep = [
        {"spp": 1},
        {"spp": 4, "distribution": "poisson"},
        {"shadow_rays": 9, "width": 20, "height": 15},
        {"spp": 1},
    ]
    for options in sweep:
        a, sa = penumbra.render(scene, **options)
        b, sb = penumbra.render(penumbra.load_scene(mesh_scene), **options)
        assert np.array_equal(a, b), options
        assert sa["rays"] == sb["rays"]
    # A mesh file rewritten on disk is read again by the same object.
    mesh = mesh_scene.parent / "meshes" / "tetra.obj"
    mesh.write_text(TETRA_OBJ.replace("f 2 3 4\n", ""))
    _, stats = penumbra.render(scene, spp=1)
    assert stats["primitives"] == sa["primitives"] - 1


def test_derived_scenes_share_built_worlds(mesh_scene: Path):
    scene = penumbra.load_scene(mesh_scene)
    a, _ = penumbra.render(scene, spp=1)
    assert scene._worlds_kept() == 1
    d = scene.to_dict()
    d["camera"]["position"] = [1.0, 2.0, 3.0]
    moved = scene.derive(d)
    assert (moved.name, moved.base_dir, moved.bunny) == (scene.name, scene.base_dir, scene.bunny)
    assert moved._worlds_kept() == 1, "shared before its first render"
    b, _ = penumbra.render(moved, spp=1)
    assert scene._worlds_kept() == 1, "the camera is not geometry"
    fresh = penumbra.scene_from_dict(d, base_dir=scene.base_dir)
    assert np.array_equal(b, penumbra.render(fresh, spp=1)[0])
    assert not np.array_equal(a, b)
    d["objects"][0]["transform"]["rotate_degrees"] = 40.0
    turned = moved.derive(d, name="turned")
    c, stats = penumbra.render(turned, spp=1)
    assert stats["scene"] == "turned"
    assert scene._worlds_kept() == 2, "a turned mesh is other geometry"
    fresh = penumbra.scene_from_dict(d, base_dir=scene.base_dir)
    assert np.array_equal(c, penumbra.render(fresh, spp=1)[0])
    with pytest.raises(TypeError, match="Scene.derive expects a dict"):
        scene.derive([1])
    with pytest.raises(penumbra.SceneError, match="radius"):
        scene.derive({"objects": [{"type": "sphere", "radius": "big"}]})


def test_scene_pickles_as_text_and_renders_the_same(mesh_scene: Path):
    scene = penumbra.load_scene(mesh_scene)
    data = pickle.dumps(scene)
    assert len(data) < 4096, "the text travels, not a built scene"
    copy = pickle.loads(data)
    assert Path(copy.base_dir).is_absolute()
    assert copy.name == scene.name and copy.text == scene.text
    a, _ = penumbra.render(scene, spp=1)
    b, _ = penumbra.render(copy, spp=1)
    assert np.array_equal(a, b)
    d = penumbra.scene_from_dict({"objects": [{"type": "sphere"}]}, name="ball")
    d2 = pickle.loads(pickle.dumps(d))
    assert d2.to_dict() == d.to_dict() and d2.name == "ball"


def test_tiles_stitch_into_exactly_the_full_frame(small):
    scene = penumbra.load_scene("showcase")
    full, stats = penumbra.render(scene, seed=5, **small)
    stitched = np.zeros_like(full)
    total = 0
    # Uneven tiles that do not line up with the renderer's own 32-pixel tiles.
    xs, ys = [0, 7, 30, 48], [0, 13, 32]
    for y0, y1 in zip(ys, ys[1:]):
        for x0, x1 in zip(xs, xs[1:]):
            tile, ts = penumbra.render_region(scene, x0, y0, x1, y1, seed=5, **small)
            assert tile.shape == (y1 - y0, x1 - x0, 3)
            assert ts["region"] == [x0, y0, x1, y1]
            stitched[y0:y1, x0:x1] = tile
            total += ts["rays"]["total"]
    assert np.array_equal(stitched, full)
    assert total == stats["rays"]["total"]


@pytest.mark.parametrize("region", [(0, 0, 0, 5), (10, 0, 5, 5), (0, 0, 49, 32), (-1, 0, 5, 5)])
def test_bad_regions_are_value_errors(small, region):
    with pytest.raises(ValueError, match="x0|region"):
        penumbra.render_region(penumbra.load_scene("showcase"), *region, **small)


def test_progress_is_called_on_the_caller_thread_up_to_the_total(small):
    import threading

    calls = []
    caller = threading.get_ident()

    def progress(done, total):
        assert threading.get_ident() == caller
        calls.append((done, total))

    penumbra.render(penumbra.load_scene("showcase"), progress=progress, **small)
    assert calls and calls[-1] == (2, 2)  # 48x32 is two 32-pixel tiles
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_an_exception_in_progress_stops_the_render(small):
    def progress(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        penumbra.render(penumbra.load_scene("showcase"), progress=progress, width=200, height=150)


def test_ctrl_c_interrupts_a_render_cleanly():
    """SIGINT during a long render raises KeyboardInterrupt within a moment."""
    code = textwrap.dedent(
        """
        import signal, sys, time, penumbra
        # A test runner started in the background may hand its children
        # SIGINT ignored, and Python then keeps it ignored: restore Python's
        # own handler, the one an interactive user has.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        scene = penumbra.load_scene("showcase")
        print("ready", flush=True)
        t = time.perf_counter()
        try:
            penumbra.render(scene, width=800, height=600, spp=64)
        except KeyboardInterrupt:
            print(f"interrupted {time.perf_counter() - t:.3f}", flush=True)
            sys.exit(0)
        print("finished", flush=True)
        sys.exit(1)
        """
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == "ready"
    import time

    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    assert proc.returncode == 0, (out, err)
    assert out.startswith("interrupted"), (out, err)


def test_bad_scene_file_errors_name_file_line_and_column(tmp_path: Path, small):
    bad = tmp_path / "bad.toml"
    bad.write_text('[render]\nwidth = 64\n\n[[objects]]\ntype = "sphere"\nradius = -1.0\n')
    scene = penumbra.load_scene(bad)  # parses; values are checked with the options applied
    with pytest.raises(penumbra.SceneError) as info:
        penumbra.render(scene, **small)
    assert f"{bad}:6:10: objects[0].radius" in str(info.value)
    assert isinstance(info.value, ValueError)
    with pytest.raises(penumbra.SceneError, match=r"bad\.toml:6:10"):
        scene.settings()

    syntax = tmp_path / "syntax.toml"
    syntax.write_text("[render]\nwidth = = 3\n")
    with pytest.raises(penumbra.SceneError, match=r"syntax\.toml:2:\d+"):
        penumbra.load_scene(syntax)

    unknown = tmp_path / "unknown.toml"
    unknown.write_text("[camera]\nfov = 30\nzoom = 2\n")
    with pytest.raises(penumbra.SceneError, match=r"unknown\.toml:3:1: .*zoom"):
        penumbra.load_scene(unknown)


def test_missing_scene_lists_the_built_ins():
    with pytest.raises(penumbra.SceneError, match="showcase"):
        penumbra.load_scene("no-such-scene")
    assert "showcase" in penumbra.scenes()


def test_dict_errors_name_the_key_path():
    with pytest.raises(penumbra.SceneError, match=r"camera\.zoom|unknown field `zoom`"):
        penumbra.scene_from_dict({"camera": {"zoom": 2}})
    with pytest.raises(penumbra.SceneError, match=r"objects\[0\]\.radius"):
        penumbra.scene_from_dict({"objects": [{"type": "sphere", "radius": "big"}]})
    with pytest.raises(penumbra.SceneError, match=r"objects\[0\]\.radius: must be a positive"):
        penumbra.render(penumbra.scene_from_dict({"objects": [{"type": "sphere", "radius": -1.0}]}))
    with pytest.raises(penumbra.SceneError, match="finite"):
        penumbra.scene_from_dict({"render": {"background": [float("nan"), 0.0, 0.0]}})
    with pytest.raises(TypeError, match="keys must be strings"):
        penumbra.scene_from_dict({"materials": {1: {}}})
    with pytest.raises(TypeError):
        penumbra.scene_from_dict([1, 2])


@pytest.mark.parametrize(
    ("key", "value", "expected", "got"),
    [
        (("camera", "position"), np.zeros(4), 3, 4),
        (("camera", "position"), np.zeros(2), 3, 2),
        (("camera", "up"), np.zeros((2, 3)), 3, 2),
        (("camera", "shutter"), np.array([0.0, 0.5, 1.0]), 2, 3),
        (("render", "background"), np.zeros(100_000), 3, 100_000),
    ],
)
def test_arrays_of_the_wrong_shape_are_value_errors_naming_the_key(key, value, expected, got):
    table, name = key
    with pytest.raises(ValueError) as info:
        penumbra.scene_from_dict({table: {name: value}})
    assert isinstance(info.value, penumbra.SceneError)
    message = str(info.value)
    assert message.startswith(f"{table}.{name}"), message
    assert f"expected {expected} numbers, got {got}" in message or "invalid type" in message, message
    assert len(message) < 300, message
    matrix = {"type": "sphere", "transform": {"matrix": np.eye(4)[:3]}}
    with pytest.raises(penumbra.SceneError, match=r"objects\[0\]\.transform\.matrix: expected 4 rows, got 3"):
        penumbra.scene_from_dict({"objects": [matrix]})


def test_special_files_and_huge_values_are_refused_quickly(tmp_path: Path):
    import os
    import time

    start = time.monotonic()
    for path in [Path("/dev/zero"), tmp_path]:
        if path.exists():
            with pytest.raises(penumbra.SceneError, match="not a regular file"):
                penumbra.load_scene(path)
    if hasattr(os, "mkfifo"):
        fifo = tmp_path / "pipe.toml"
        os.mkfifo(fifo)
        with pytest.raises(penumbra.SceneError, match=r"pipe\.toml: is a named pipe"):
            penumbra.load_scene(fifo)
    else:
        print("skipped the FIFO: this platform has none")
    assert time.monotonic() - start < 1.0
    huge = tmp_path / "huge.toml"
    huge.write_text('[[objects]]\ntype = "' + "y" * 1_000_000 + '"\n')
    with pytest.raises(penumbra.SceneError) as info:
        penumbra.render(penumbra.load_scene(huge), width=8, height=6)
    assert len(str(info.value)) < 300 and "yyy…" in str(info.value), str(info.value)[:300]
    with pytest.raises(penumbra.SceneError) as info:
        penumbra.scene_from_dict({"objects": [{"type": "z" * 1_000_000}]}).settings()
    assert len(str(info.value)) < 300, str(info.value)[:300]


def test_numpy_values_are_accepted_in_dicts(small):
    d = {
        "camera": {"position": np.array([0.0, 1.0, 5.0]), "fov": np.float64(40.0)},
        "objects": [{"type": "sphere", "radius": 1.0}],
        "lights": [{"type": "point", "position": [2.0, 3.0, 2.0], "intensity": [5.0, 5.0, 5.0]}],
    }
    image, _ = penumbra.render(penumbra.scene_from_dict(d), **small)
    assert image.mean() > 0


@pytest.mark.parametrize(
    ("options", "error", "match"),
    [
        ({"width": 0}, ValueError, r"width must be an integer in 1\.\.=32768"),
        ({"spp": "4"}, TypeError, "spp must be an int"),
        ({"spp": True}, TypeError, "spp must be an int"),
        ({"seed": -1}, ValueError, "seed"),
        ({"threads": 0}, ValueError, "threads"),
        ({"distribution": "sobel"}, ValueError, "unknown distribution `sobel`; valid choices are: grid"),
        ({"aperture": -0.1}, ValueError, "aperture must be a finite number >= 0"),
        ({"focal_distance": 0}, ValueError, "focal_distance must be a finite number > 0"),
        ({"progress": 3}, TypeError, "progress must be a callable"),
        ({"metric": 1}, TypeError, "metric must be a bool"),
        ({"metric_min_rays": 0}, ValueError, "metric_min_rays"),
        ({"colour": 3}, TypeError, "unexpected keyword argument 'colour'"),
    ],
)
def test_bad_options_are_refused_before_rendering(options, error, match):
    with pytest.raises(error, match=match):
        penumbra.render(penumbra.load_scene("showcase"), **options)


def test_options_override_the_scene_like_the_cli(small):
    scene = penumbra.load_scene("showcase")
    s = scene.settings(width=10, height=20, seed=9, spp=9, max_depth=1)
    assert (s["width"], s["height"], s["seed"], s["spp"], s["max_depth"]) == (10, 20, 9, 9, 1)
    assert scene.settings()["width"] == 800
    _, stats = penumbra.render(scene, max_depth=0, **small)
    assert stats["rays"]["reflection"] == stats["rays"]["refraction"] == 0


def test_non_square_counts_warn(small):
    scene = penumbra.scene_from_dict({"objects": [{"type": "sphere"}]})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        penumbra.render(scene, spp=2, distribution="grid", width=8, height=8)
        penumbra.samples("jitter", 5)
    assert len(caught) >= 2
    assert all(issubclass(w.category, UserWarning) for w in caught)


NET16 = np.array([[(i + 0.5) / 16, int(f"{i:04b}"[::-1], 2) / 16 + 1 / 32] for i in range(16)])


def test_samples_shapes_and_determinism():
    for name in penumbra.DISTRIBUTIONS:
        points = NET16 if name == "custom" else None
        pts = penumbra.samples(name, 16, radius=0.5, seed=2, points=points)
        assert pts.dtype == np.float32
        assert pts.shape == ((16, 3) if name == "fast-random" else (16, 2))
        assert np.array_equal(pts, penumbra.samples(name, 16, radius=0.5, seed=2, points=points))
        assert np.abs(pts).max() <= 0.5 + 1e-6
    with pytest.raises(ValueError, match="count"):
        penumbra.samples("grid", 0)
    with pytest.raises(ValueError, match="radius"):
        penumbra.samples("grid", 4, radius=0)


def test_images_save_and_load(tmp_path: Path, small):
    image, _ = penumbra.render(penumbra.load_scene("showcase"), **small)
    penumbra.save_image(tmp_path / "a.exr", image)
    assert np.array_equal(penumbra.load_image(tmp_path / "a.exr"), image)
    penumbra.save_image(str(tmp_path / "a.png"), image.astype(np.float64))
    assert (tmp_path / "a.png").stat().st_size > 100
    with pytest.raises(ValueError, match="unsupported output format"):
        penumbra.save_image(tmp_path / "a.jpg", image)
    with pytest.raises(ValueError, match="shape"):
        penumbra.save_image(tmp_path / "b.exr", image[:, :, :2])
    with pytest.raises(OSError):
        penumbra.save_image(tmp_path / "missing" / "c.exr", image)
    with pytest.raises(ValueError, match="exr"):
        penumbra.load_image(tmp_path / "a.png")


def test_custom_points_from_arrays_files_and_functions(tmp_path: Path, small):
    """The same sets give the same image whether they come as an array, a
    JSON file or a function; a function is asked for each set size."""
    scene = penumbra.load_scene("showcase")
    opts = dict(small, distribution="custom", shadow_rays=16, spp=4)
    sets = np.stack([NET16, (NET16 + 0.25) % 1.0])
    (tmp_path / "p.json").write_text(json.dumps(sets.tolist()))
    from_array, _ = penumbra.render(scene, points=sets, **opts)
    from_file, _ = penumbra.render(scene, points=tmp_path / "p.json", **opts)
    asked = []

    def made(n):
        asked.append(n)
        return sets if n == 16 else np.full((n, 2), 0.5)

    from_function, _ = penumbra.render(scene, points=made, **opts)
    assert np.array_equal(from_array, from_file)
    assert sorted(set(asked)) == asked and 16 in asked and 4 in asked
    with_jitter, _ = penumbra.render(scene, **dict(opts, distribution="jitter"))
    assert not np.array_equal(from_array, with_jitter)
    assert np.isfinite(from_function).all()


@pytest.mark.parametrize(
    ("points", "error", "match"),
    [
        (None, penumbra.SceneError, "no points are given"),
        ([[0.5, 1.5]], ValueError, r"set 0, point 0: \(0.5, 1.5\) is not in the unit square"),
        ([[0.5, float("nan")]], ValueError, "not in the unit square"),
        ([[0.5, 0.5, 0.5]], ValueError, "set 0, point 0: expected \\[x, y\\]"),
        ([], ValueError, "set 0: a set needs at least one point"),
        ("missing.json", penumbra.SceneError, "missing.json"),
        (object(), TypeError, "points must be"),
        (lambda n: np.zeros((n + 1, 2)), ValueError, "asked for sets of"),
    ],
)
def test_bad_custom_points_are_refused(points, error, match, small):
    scene = penumbra.load_scene("showcase")
    with pytest.raises(error, match=match):
        penumbra.render(scene, distribution="custom", points=points, **small)


def test_aov_channels_follow_the_image_with_their_names(mesh_scene: Path):
    """An `aov` integrator's channels come after RGB, named as Mitsuba names
    them; the RGB is the held integrator's image, and a region holds the
    whole frame's channels."""
    d = tomllib.loads(mesh_scene.read_text())
    d["render"].update(
        integrator="aov",
        aovs="dd:depth,nn:geo_normal",
        nested={"type": "path", "name": "img", "max_depth": 3},
        spp=4,
    )
    scene = penumbra.scene_from_dict(d, base_dir=str(mesh_scene.parent))
    image, stats = penumbra.render(scene, threads=2)
    names = ["R", "G", "B", "img.R", "img.G", "img.B", "img.A", "dd.T", "nn.X", "nn.Y", "nn.Z"]
    assert stats["channels"] == names
    assert image.shape == (30, 40, len(names)) and image.dtype == np.float32
    plain = dict(d)
    plain["render"] = {k: v for k, v in d["render"].items() if k not in ("aovs", "nested")}
    plain["render"].update(integrator="path", max_depth=3)
    plain_scene = penumbra.scene_from_dict(plain, base_dir=str(mesh_scene.parent))
    rgb, plain_stats = penumbra.render(plain_scene, threads=2)
    assert "channels" not in plain_stats and rgb.shape == (30, 40, 3)
    assert np.array_equal(image[..., :3], rgb)
    assert np.array_equal(image[..., 3:6], rgb)
    depth = image[..., names.index("dd.T")]
    assert depth.max() > 1.0 and depth.min() >= 0.0
    normal = image[..., 8:11]
    lengths = np.linalg.norm(normal, axis=-1)
    assert (np.abs(lengths[depth > 0] - 1.0) < 0.05).mean() > 0.9
    part, part_stats = penumbra.render_region(scene, 10, 5, 30, 25, threads=1)
    assert part_stats["channels"] == names
    assert np.array_equal(part, image[5:25, 10:30])


def test_alpha_is_a_fourth_channel_of_the_covered_share(mesh_scene: Path):
    """`alpha=True` adds the film's alpha `A` after RGB: 1 where the camera
    sees the mesh, 0 where it sees nothing, the same in a region and on any
    number of threads."""
    scene = penumbra.load_scene(mesh_scene)
    image, stats = penumbra.render(scene, alpha=True, spp=4, threads=2)
    assert stats["channels"] == ["R", "G", "B", "A"]
    assert image.shape == (30, 40, 4)
    a = image[..., 3]
    assert a.min() >= 0.0 and a.max() <= 1.0
    assert (a == 1.0).any()
    rgb, _ = penumbra.render(scene, spp=4, threads=2)
    assert np.array_equal(image[..., :3], rgb)
    again, _ = penumbra.render(scene, alpha=True, spp=4, threads=1)
    assert np.array_equal(again, image)
    part, _ = penumbra.render_region(scene, 10, 5, 30, 25, alpha=True, spp=4, threads=1)
    assert np.array_equal(part, image[5:25, 10:30])
