"""The Python API against the `penumbra` binary: same pixels, numbers and messages."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import penumbra

OPTIONS = {
    "width": 48,
    "height": 32,
    "spp": 4,
    "seed": 11,
    "shadow_rays": 4,
    "reflection_distribution": "poisson",
    "max_depth": 2,
}


def cli_args(options: dict) -> list[str]:
    out = []
    for k, v in options.items():
        out += [f"--{k.replace('_', '-')}", str(v)]
    return out


def run(cli: Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run([str(cli), *args], capture_output=True, text=True, check=check)


def test_render_matches_the_cli_exr_pixel_for_pixel(cli: Path, tmp_path: Path):
    out, stats_path = tmp_path / "cli.exr", tmp_path / "cli.json"
    run(cli, "render", "showcase", "-o", str(out), "--stats", str(stats_path), "--quiet",
        *cli_args(OPTIONS))
    image, stats = penumbra.render(penumbra.load_scene("showcase"), **OPTIONS)
    assert np.array_equal(penumbra.load_image(out), image)
    expected = json.loads(stats_path.read_text())
    assert stats.keys() == expected.keys()
    for key in expected:
        if key not in ("time", "mrays_per_s", "threads"):
            assert stats[key] == expected[key], key


def test_scene_files_render_like_the_cli(cli: Path, tmp_path: Path):
    scene = tmp_path / "s.toml"
    scene.write_text(penumbra.load_scene("showcase").text.replace("spp = 4", "spp = 1"))
    out = tmp_path / "cli.exr"
    run(cli, "render", str(scene), "-o", str(out), "--quiet", "--width", "40", "--height", "24")
    image, _ = penumbra.render(penumbra.load_scene(scene), width=40, height=24)
    assert np.array_equal(penumbra.load_image(out), image)


# Metric parameters that act on the showcase at OPTIONS' budgets.
METRIC = {"metric_threshold": 0.05, "metric_min_rays": 2, "shadow_metric_rays": 2}


def test_metric_options_match_the_cli(cli: Path, tmp_path: Path):
    out, stats_path = tmp_path / "m.exr", tmp_path / "m.json"
    run(cli, "render", "showcase", "-o", str(out), "--stats", str(stats_path), "--quiet",
        "--metric", "--pixel-metric", *cli_args(OPTIONS), *cli_args(METRIC))
    image, stats = penumbra.render(
        penumbra.load_scene("showcase"), metric=True, pixel_metric=True, **OPTIONS, **METRIC
    )
    assert np.array_equal(penumbra.load_image(out), image)
    expected = json.loads(stats_path.read_text())
    assert stats["rays"] == expected["rays"]
    assert stats.get("saved") == expected.get("saved")
    plain, _ = penumbra.render(penumbra.load_scene("showcase"), metric=False, **OPTIONS)
    assert not np.array_equal(plain, image), "the metric changed nothing"


@pytest.mark.parametrize("alone", ["reflection", "shadow"])
def test_one_metric_alone_matches_the_cli(cli: Path, tmp_path: Path, alone: str):
    other = "shadow" if alone == "reflection" else "reflection"
    out, stats_path = tmp_path / "m.exr", tmp_path / "m.json"
    run(cli, "render", "showcase", "-o", str(out), "--stats", str(stats_path), "--quiet",
        "--metric", f"--no-{other}-metric", *cli_args(OPTIONS), *cli_args(METRIC))
    image, stats = penumbra.render(
        penumbra.load_scene("showcase"), metric=True, **{f"{other}_metric": False}, **OPTIONS,
        **METRIC,
    )
    assert np.array_equal(penumbra.load_image(out), image)
    expected = json.loads(stats_path.read_text())
    assert stats["rays"] == expected["rays"]
    assert stats["saved"] == expected["saved"]
    assert stats["saved"][other] == 0 and stats["saved"][alone] > 0
    assert stats["metric"][f"{alone}s"] and not stats["metric"][f"{other}s"]


@pytest.mark.parametrize("distribution", list(penumbra.DISTRIBUTIONS))
def test_samples_match_the_cli_json(cli: Path, distribution: str, tmp_path: Path):
    sets = [[[(i + 0.5) / 25, ((7 * i) % 25 + 0.5) / 25] for i in range(25)]]
    (tmp_path / "p.json").write_text(json.dumps(sets))
    custom = ["--points", str(tmp_path / "p.json")] if distribution == "custom" else []
    doc = json.loads(
        run(cli, "samples", "--distribution", distribution, "--count", "25", "--radius", "0.5",
            "--seed", "7", *custom).stdout
    )
    given = tmp_path / "p.json" if distribution == "custom" else None
    points = penumbra.samples(distribution, 25, radius=0.5, seed=7, points=given)
    assert np.array_equal(points, np.array(doc["points"], dtype=np.float32))


@pytest.mark.parametrize(
    ("text", "stage"),
    [
        ('[render]\nwidth = 64\n\n[[objects]]\ntype = "sphere"\nradius = -1.0\n', "render"),
        ("[render]\nwidth = = 3\n", "load"),
        ("[camera]\nfov = 30\nzoom = 2\n", "load"),
        ('[[objects]]\ntype = "mesh"\npath = "missing.obj"\n', "render"),
        ('[[objects]]\ntype = "sphere"\nmaterial = "gold"\n', "render"),
        ("[camera]\nposition = [0, 1, 5, 1]\n", "load"),
        ("[render]\n" + ".".join(["a"] * 200) + " = 1\n", "load"),
        ('[render]\nfilter = "' + "x" * 100_000 + '"\n', "load"),
    ],
)
def test_scene_errors_have_the_cli_message(cli: Path, tmp_path: Path, text: str, stage: str):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    result = run(cli, "render", str(path), "-o", str(tmp_path / "x.png"), "--quiet", check=False)
    assert result.returncode == 2
    message = result.stderr.strip().removeprefix("error: ")
    with pytest.raises(penumbra.SceneError) as info:
        scene = penumbra.load_scene(path)
        assert stage == "render", "should have failed to load"
        penumbra.render(scene, width=8, height=8)
    assert str(info.value) == message
    assert f"{path}:" in message


@pytest.mark.parametrize("where", [[], ["--local-workers", "2", "--tile", "16"]])
def test_python_m_penumbra_writes_the_cli_image(cli: Path, tmp_path: Path, where: list[str]):
    import sys

    args = ["render", "showcase", "--quiet", *cli_args(OPTIONS)]
    run(cli, *args, "-o", str(tmp_path / "cli.exr"))
    result = subprocess.run(
        [sys.executable, "-m", "penumbra", *args, "-o", str(tmp_path / "py.exr"),
         "--stats", str(tmp_path / "py.json"), *where],
        capture_output=True, text=True,
    )
    assert result.returncode == 0, result.stderr
    assert np.array_equal(
        penumbra.load_image(tmp_path / "py.exr"), penumbra.load_image(tmp_path / "cli.exr")
    )
    assert json.loads((tmp_path / "py.json").read_text())["rays"]["primary"] == 48 * 32 * 4
