"""Mitsuba 3 scenes from Python: XML files with parameters, and dicts in
Mitsuba's ``load_dict`` form, lowered as the command line lowers XML."""

from __future__ import annotations

import pickle
import subprocess
from pathlib import Path

import numpy as np
import pytest

import penumbra
from penumbra import distributed as pd

# A scene whose radius, material, sample count and emitter strength are
# parameters, with its lights in an included file.
XML = """<scene version="3.0.0">
    <default name="radius" value="0.8"/>
    <default name="spp" value="2"/>
    <default name="colour" value="0.7, 0.2, 0.2"/>
    <default name="two" value="false"/>
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="0, 1, 5" target="0, 1, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="40"/>
            <integer name="height" value="30"/>
            <rfilter type="box"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    </sensor>
    <bsdf type="diffuse" id="red"><rgb name="reflectance" value="$colour"/></bsdf>
    <shape type="sphere">
        <point name="center" value="0, 1, 0"/>
        <float name="radius" value="$radius"/>
        <ref id="red"/>
    </shape>
    <shape type="obj">
        <string name="filename" value="meshes/floor.obj"/>
        <transform name="to_world">
            <matrix value="5 0 0 0  0 0 5 0  0 -5 0 0  0 0 0 1"/>
        </transform>
        <bsdf type="twosided"><bsdf type="diffuse"/></bsdf>
    </shape>
    <include filename="lights.xml"/>
</scene>
"""

LIGHTS = """<scene version="3.0.0">
    <default name="power" value="20"/>
    <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
    <emitter type="point">
        <point name="position" value="2, 4, 2"/>
        <rgb name="intensity" value="$power"/>
    </emitter>
</scene>
"""

FLOOR = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n"

PARAMS = {"radius": 0.6, "spp": 3, "colour": "0.2, 0.25, 0.7", "power": 35}


def lookat() -> np.ndarray:
    """The camera's `<lookat>` as its matrix (x to the left, y up, z along the view)."""
    return np.array(
        [[-1.0, 0, 0, 0], [0, 1, 0, 1], [0, 0, -1, 5], [0, 0, 0, 1]], dtype=np.float64
    )


def as_dict(radius=0.6, spp=3, colour=(0.2, 0.25, 0.7), power=35) -> dict:
    """The XML scene with PARAMS, in Mitsuba's dict form."""
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 4},
        "sensor": {
            "type": "perspective",
            "fov": 40,
            "fov_axis": "y",
            "to_world": lookat(),
            "film": {"type": "hdrfilm", "width": 40, "height": 30, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "red": {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(colour)}},
        "ball": {
            "type": "sphere",
            "center": [0, 1, 0],
            "radius": radius,
            "bsdf": {"type": "ref", "id": "red"},
        },
        "floor": {
            "type": "obj",
            "filename": "meshes/floor.obj",
            "to_world": [[5, 0, 0, 0], [0, 0, 5, 0], [0, -5, 0, 0], [0, 0, 0, 1]],
            "bsdf": {"type": "twosided", "material": {"type": "diffuse"}},
        },
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.1}},
        "lamp": {
            "type": "point",
            "position": (2, 4, 2),
            "intensity": {"type": "rgb", "value": power},
        },
    }


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "scene.xml").write_text(XML)
    (tmp_path / "lights.xml").write_text(LIGHTS)
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "floor.obj").write_text(FLOOR)
    return tmp_path


def test_xml_parameters_render_the_pixels_of_the_command_line_with_defines(
    cli: Path, folder: Path
):
    out = folder / "cli.exr"
    defines = [arg for k, v in PARAMS.items() for arg in ("-D", f"{k}={v}")]
    subprocess.run(
        [str(cli), "render", str(folder / "scene.xml"), "-o", str(out), "--quiet", *defines],
        check=True,
    )
    scene = penumbra.load_scene(folder / "scene.xml", params=PARAMS)
    assert scene.format == "xml"
    image, stats = penumbra.render(scene)
    assert image.shape == (30, 40, 3) and stats["spp"] == 3
    assert np.array_equal(penumbra.load_image(out), image)
    # The parameters change the picture: the defaults render another one.
    default, _ = penumbra.render(penumbra.load_scene(folder / "scene.xml"))
    assert not np.array_equal(default, image)


def test_parameter_values_convert_like_defines(folder: Path):
    text = XML.replace('value="false"/>', 'value="false"/>\n    <default name="flip" value="x"/>')
    text = text.replace(
        '<float name="radius" value="$radius"/>',
        '<float name="radius" value="$radius"/><boolean name="flip_normals" value="$flip"/>',
    )
    (folder / "scene.xml").write_text(text)
    scene = penumbra.load_scene(folder / "scene.xml", params={"flip": False, "radius": 1e-3})
    assert "flip_normals = false" in scene.text and "radius = 0.001" in scene.text
    with pytest.raises(penumbra.SceneError, match="`x` is not `true` or `false`"):
        penumbra.load_scene(folder / "scene.xml")
    with pytest.raises(TypeError, match=r'params\["radius"\]: must be a str, int, float or bool'):
        penumbra.load_scene(folder / "scene.xml", params={"radius": [1]})
    with pytest.raises(penumbra.SceneError, match=r'params\["radius"\]: must be a finite number'):
        penumbra.load_scene(folder / "scene.xml", params={"radius": float("nan")})


def test_params_on_a_toml_scene_are_refused_naming_the_argument(tmp_path: Path):
    toml = tmp_path / "s.toml"
    toml.write_text(penumbra.load_scene("showcase").text)
    for name in (toml, "showcase"):
        with pytest.raises(penumbra.SceneError, match="`params` sets the parameters of Mitsuba XML"):
            penumbra.load_scene(name, params={"spp": 2})
    # No parameters is no error.
    penumbra.load_scene(toml, params={})


def test_xml_errors_name_the_file_line_and_column_also_inside_includes(folder: Path):
    (folder / "lights.xml").write_text(LIGHTS.replace('value="0.1"', 'value="0.1, x"'))
    with pytest.raises(penumbra.SceneError) as e:
        penumbra.load_scene(folder / "scene.xml")
    assert str(e.value).startswith(f"{folder / 'lights.xml'}:3:58: `x` is not a finite number")
    (folder / "lights.xml").write_text(LIGHTS)
    # A parameter's value is placed where the parameter is used.
    with pytest.raises(penumbra.SceneError) as e:
        penumbra.load_scene(folder / "scene.xml", params={"spp": "many"})
    assert str(e.value) == f"{folder / 'scene.xml'}:18:73: `many` is not an integer (64-bit)"


def test_a_dict_in_mitsubas_form_is_the_xml_scene_that_says_the_same(folder: Path):
    xml = penumbra.load_scene(folder / "scene.xml", params=PARAMS)
    d = penumbra.load_dict(as_dict(), base_dir=folder)
    assert d.format == "mitsuba_dict"
    # The same tree: the same scene file written from both.
    assert d.to_dict() == xml.to_dict()
    a, _ = penumbra.render(xml, seed=4)
    b, _ = penumbra.render(d, seed=4)
    assert a.mean() > 0.01
    assert np.array_equal(a, b)
    # Mitsuba's own types are taken as the arrays they are.
    class Transform:  # shaped like mi.ScalarTransform4f: its `matrix` converts
        matrix = lookat()

    alt = as_dict()
    alt["sensor"]["to_world"] = Transform()
    alt["ball"]["center"] = np.array([0.0, 1.0, 0.0])
    assert penumbra.load_dict(alt, base_dir=folder).to_dict() == xml.to_dict()


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda d: d["ball"].update(type="hairy"), "ball.type: `hairy` is not a plugin Penumbra reads; it reads integrator: path, volpath, volpathmis, direct, ptracer, depth, aov, moment; sensor:"),
        (lambda d: d["red"].update(type="pplastic"), "red.type: `pplastic` is not a plugin"),
        (lambda d: d["ball"].update(radius="big"), "ball.radius: `radius` must be a float, got a string"),
        (lambda d: d["ball"].update(center=[0, 1]), "ball.center: expected 3 numbers (a point or vector)"),
        (lambda d: d["red"]["reflectance"].update(value=[1, 2]), "red.reflectance.value: expected 3 numbers"),
        (lambda d: d["sensor"].update(to_world=np.eye(3)), "sensor.to_world: expected 3 numbers (a point or vector) or a 4×4 matrix"),
        (lambda d: d["floor"].update(to_world=[[1, 0, 0, 0]] * 3 + [[0, 0, 0, 1]]), "floor.to_world: the transform's matrix is singular"),
        (lambda d: d["ball"].update(bsdf={"type": "ref", "id": "blue"}), "ball.bsdf: <ref>: no object has the id `blue`"),
        (lambda d: d["ball"].update(bsdf={"type": "diffuse", "reflectance": {"type": "rgb"}}), "ball.bsdf.reflectance: missing key `value`"),
        (lambda d: d["ball"].update(bsdf={"reflectance": 0.5}), "ball.bsdf: missing key `type`"),
        (lambda d: d["ball"].update(radius=None), "ball.radius: None is not a value of a scene"),
        (lambda d: d["ball"].update(radius={1, 2}), "ball.radius: cannot use a set in a scene"),
        (lambda d: d["ball"].update(radius=float("inf")), "ball.radius: must be a finite number"),
        (lambda d: d.update(type="shape"), "type: the root's type is `shape`"),
    ],
)
def test_dict_errors_raise_scene_error_naming_the_key_path(folder: Path, change, message):
    d = as_dict()
    change(d)
    with pytest.raises(penumbra.SceneError) as e:
        penumbra.load_dict(d, base_dir=folder)
    assert str(e.value).startswith(message), str(e.value)


def test_load_dict_takes_only_a_dict():
    with pytest.raises(TypeError, match="load_dict expects a dict in Mitsuba's form"):
        penumbra.load_dict([("type", "scene")])


def test_mitsuba_scenes_pickle_to_the_same_pixels(folder: Path):
    for scene in (
        penumbra.load_scene(folder / "scene.xml", params=PARAMS),
        penumbra.load_dict(as_dict(), base_dir=folder),
    ):
        again = pickle.loads(pickle.dumps(scene))
        assert again.format == scene.format
        a, _ = penumbra.render(scene, seed=2)
        b, _ = penumbra.render(again, seed=2)
        assert np.array_equal(a, b)


def test_dask_renders_of_mitsuba_scenes_equal_the_local_render(client, folder: Path):
    for scene in (
        penumbra.load_scene(folder / "scene.xml", params=PARAMS),
        penumbra.load_dict(as_dict(), base_dir=folder),
    ):
        local, local_stats = penumbra.render(scene, seed=9)
        image, stats = pd.render(scene, client, tile=16, seed=9)
        assert local.mean() > 0.01
        assert np.array_equal(image, local)
        assert stats["rays"] == local_stats["rays"]
    # Animation frames change the converted description.
    scene = penumbra.load_scene(folder / "scene.xml", params=PARAMS)
    frames = [{"seed": 1}, {"camera": {"position": [0.5, 1.2, 5.0]}}]
    results = pd.render_frames(scene, client, frames)
    plain, _ = penumbra.render(scene)
    for frame, (image, _) in zip(frames, results):
        changed, opts = pd.apply_frame(scene, frame, {})
        expected, _ = penumbra.render(changed, **opts)
        assert np.array_equal(image, expected)
        assert not np.array_equal(image, plain)


MEDIA_XML = """<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="6"/></integrator>
    <medium type="homogeneous" id="fog">
        <rgb name="sigma_t" value="0.5, 1, 1.5"/>
        <float name="albedo" value="0.8"/>
        <phase type="hg"><float name="g" value="0.5"/></phase>
    </medium>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, 0, 6" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <medium type="homogeneous">
            <float name="sigma_t" value="0.02"/>
            <float name="albedo" value="0.5"/>
        </medium>
        <film type="hdrfilm">
            <integer name="width" value="24"/>
            <integer name="height" value="18"/>
            <rfilter type="box"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere">
        <point name="center" value="-1, 0, 0"/>
        <float name="radius" value="0.9"/>
        <bsdf type="null"/>
        <ref name="interior" id="fog"/>
    </shape>
    <shape type="cube">
        <transform name="to_world">
            <scale value="0.7"/>
            <translate value="1.2, 0, 0"/>
        </transform>
        <bsdf type="null"/>
        <medium type="heterogeneous" name="interior">
            <volume type="gridvolume" name="sigma_t">
                <string name="filename" value="smoke.vol"/>
            </volume>
            <float name="scale" value="2"/>
            <rgb name="albedo" value="0.9, 0.6, 0.3"/>
            <phase type="isotropic"/>
        </medium>
    </shape>
</scene>
"""


def media_dict() -> dict:
    """MEDIA_XML in Mitsuba's dict form."""
    return {
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": 6},
        "fog": {
            "type": "homogeneous",
            "sigma_t": {"type": "rgb", "value": [0.5, 1, 1.5]},
            "albedo": 0.8,
            "phase": {"type": "hg", "g": 0.5},
        },
        "sensor": {
            "type": "perspective",
            "fov": 40,
            "to_world": np.array([[-1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 6], [0, 0, 0, 1]]),
            "medium": {"type": "homogeneous", "sigma_t": 0.02, "albedo": 0.5},
            "film": {"type": "hdrfilm", "width": 24, "height": 18, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": 4},
        },
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 1}},
        "ball": {
            "type": "sphere",
            "center": [-1, 0, 0],
            "radius": 0.9,
            "bsdf": {"type": "null"},
            "interior": {"type": "ref", "id": "fog"},
        },
        "box": {
            "type": "cube",
            "to_world": [[0.7, 0, 0, 1.2], [0, 0.7, 0, 0], [0, 0, 0.7, 0], [0, 0, 0, 1]],
            "bsdf": {"type": "null"},
            "interior": {
                "type": "heterogeneous",
                "sigma_t": {"type": "gridvolume", "filename": "smoke.vol"},
                "scale": 2,
                "albedo": {"type": "rgb", "value": [0.9, 0.6, 0.3]},
                "phase": {"type": "isotropic"},
            },
        },
    }


def write_vol(path: Path) -> None:
    """A 4³ grid of one channel rising along x over the unit cube, in
    Mitsuba's `.vol` format."""
    import struct

    values = [0.25 * (i % 4) + 0.1 for i in range(64)]
    head = b"VOL" + bytes([3]) + struct.pack("<iiiii", 1, 4, 4, 4, 1)
    bbox = struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    path.write_bytes(head + bbox + struct.pack(f"<{len(values)}f", *values))


def test_media_phases_and_volumes_in_a_dict_render_as_the_xml(tmp_path: Path):
    """A dict's media (one at the scene's level referred to by id as a
    shape's `interior`, one nested, the sensor's `medium`), their phase
    functions and a `gridvolume` of a file read as Mitsuba's `load_dict`
    reads them: the same pixels as the XML saying the same."""
    (tmp_path / "media.xml").write_text(MEDIA_XML)
    write_vol(tmp_path / "smoke.vol")
    xml = penumbra.load_scene(tmp_path / "media.xml")
    d = penumbra.load_dict(media_dict(), base_dir=tmp_path)
    a, _ = penumbra.render(xml, seed=5)
    b, _ = penumbra.render(d, seed=5)
    assert a.mean() > 0.05
    assert np.array_equal(a, b)
    # The fog thins red least: the ball is redder than it is blue.
    ball = a[9, 8]
    assert ball[0] > ball[2]
    bad = media_dict()
    bad["fog"]["phase"] = {"type": "hgx"}
    with pytest.raises(penumbra.SceneError, match=r"^fog\.phase\.type: `hgx` is not a plugin"):
        penumbra.load_dict(bad, base_dir=tmp_path)
