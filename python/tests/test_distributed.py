"""Dask rendering: identical to a local render whatever the workers do."""

from __future__ import annotations

import logging
import os
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest
from distributed import Client, LocalCluster

import penumbra
from penumbra import distributed as pd

FRAMES = [
    {"seed": 1},
    {"camera": {"position": [0.5, 1.4, 5.5], "look_at": [0.0, 0.6, 0.0]}},
    {
        "objects": {
            1: {
                "transform": {"translate": [0.3, 0.0, 0.0]},
                "transform_end": {"translate": [0.6, 0.1, 0.0]},
            }
        },
        "seed": 2,
    },
    {},
]


@pytest.mark.parametrize("tile", [8, 13, 64])
def test_tiles_on_two_worker_processes_give_exactly_the_local_image(client, small, tile):
    scene = penumbra.load_scene("showcase")
    local, local_stats = penumbra.render(scene, seed=3, **small)
    image, stats = pd.render(scene, client, tile=tile, seed=3, **small)
    assert image.dtype == np.float32
    assert np.array_equal(image, local)
    assert stats["rays"] == local_stats["rays"]
    assert stats["tiles"] == len(pd.tiles(48, 32, tile))
    assert stats["time"]["wall_s"] > 0 and stats["time"]["render_s"] > 0
    for key in ("scene", "width", "height", "seed", "spp", "max_depth", "primitives"):
        assert stats[key] == local_stats[key], key


def test_a_crop_window_renders_on_the_workers_as_here(client):
    """The film's crop window is the image, tiled over the workers, each
    pixel the full frame's."""
    d = tomllib.loads(penumbra.load_scene("showcase").text)
    d["render"].update({"width": 48, "height": 32, "spp": 2, "seed": 4})
    full, _ = penumbra.render(penumbra.scene_from_dict(d))
    crop = {"crop_offset_x": 5, "crop_offset_y": 9, "crop_width": 30, "crop_height": 17}
    d["render"].update(crop)
    scene = penumbra.scene_from_dict(d)
    assert scene.settings()["crop"] == [5, 9, 35, 26]
    local, _ = penumbra.render(scene)
    image, stats = pd.render(scene, client, tile=8)
    assert image.shape == local.shape == (17, 30, 3)
    assert np.array_equal(image, local)
    assert np.array_equal(local, full[9:26, 5:35])
    assert stats["tiles"] == len(pd.tiles(30, 17, 8))


@pytest.mark.parametrize("integrator", ["path", "distributed"])
def test_path_traced_tiles_on_two_workers_give_exactly_the_local_image(client, integrator):
    scene = penumbra.load_scene("cornell-box")
    opts = {"width": 40, "height": 40, "spp": 4, "integrator": integrator, "max_depth": 6, "seed": 5}
    local, local_stats = penumbra.render(scene, **opts)
    image, stats = pd.render(scene, client, tile=13, **opts)
    assert local.mean() > 0.01
    assert np.array_equal(image, local)
    assert stats["rays"] == local_stats["rays"]
    # The stages take the same rays in more, smaller calls.
    for stage in ("closest_hit", "occlusion", "shading"):
        merged, alone = stats["batches"][stage], local_stats["batches"][stage]
        assert merged["items"] == alone["items"] > 0, stage
        assert merged["calls"] > alone["calls"], stage
        assert merged["mean"] == pytest.approx(merged["items"] / merged["calls"])


def test_light_traced_tiles_on_two_workers_give_exactly_the_local_image(client):
    # A particle tracer's tile traces every light path of the frame and
    # keeps its own pixels: the tiles assemble into the local image's bits.
    scene = penumbra.load_scene("cornell-box")
    opts = {"width": 40, "height": 40, "spp": 4, "integrator": "ptracer", "max_depth": 6, "seed": 5}
    local, local_stats = penumbra.render(scene, **opts)
    image, stats = pd.render(scene, client, tile=13, **opts)
    assert local.mean() > 0.01
    assert np.array_equal(image, local)
    tiles = len(pd.tiles(40, 40, 13))
    assert stats["rays"]["primary"] == tiles * local_stats["rays"]["primary"] > 0


def test_channels_of_tiles_on_two_workers_are_the_local_ones(client):
    """A `moment` render's channels (splatted by Mitsuba's default Gaussian)
    stitch from tiles into exactly the local render's."""
    d = tomllib.loads(penumbra.load_scene("cornell-box").text)
    d["render"] = {
        "width": 40,
        "height": 40,
        "spp": 4,
        "seed": 5,
        "filter": "gaussian",
        "splat": True,
        "integrator": "moment",
        "nested": {"type": "path", "max_depth": 4},
    }
    scene = penumbra.scene_from_dict(d)
    local, local_stats = penumbra.render(scene)
    image, stats = pd.render(scene, client, tile=13)
    assert local.shape == (40, 40, 9)
    assert stats["channels"] == local_stats["channels"]
    assert stats["channels"][3:] == [
        "_arg_0.X", "_arg_0.Y", "_arg_0.Z", "m2__arg_0.X", "m2__arg_0.Y", "m2__arg_0.Z"
    ]
    assert np.array_equal(image, local)


def test_alpha_of_tiles_on_two_workers_is_the_local_one(client):
    """The film's alpha (splatted by a Gaussian, in two passes) stitches
    from tiles into exactly the local render's."""
    d = tomllib.loads(penumbra.load_scene("cornell-box").text)
    d["render"] = {
        "width": 40,
        "height": 40,
        "spp": 4,
        "seed": 5,
        "filter": "gaussian",
        "splat": True,
        "alpha": True,
        "integrator": "path",
        "passes": 2,
    }
    scene = penumbra.scene_from_dict(d)
    local, local_stats = penumbra.render(scene)
    image, stats = pd.render(scene, client, tile=13)
    assert local.shape == (40, 40, 4)
    assert stats["channels"] == local_stats["channels"] == ["R", "G", "B", "A"]
    assert np.array_equal(image, local)


def test_progress_counts_tiles(client, small):
    calls = []
    pd.render(penumbra.load_scene("showcase"), client, tile=16,
              progress=lambda d, t: calls.append((d, t)), **small)
    assert calls == [(i, 6) for i in range(1, 7)]


def test_frames_render_like_their_local_equivalents(client, small):
    scene = penumbra.load_scene("showcase")
    results = pd.render_frames(scene, client, FRAMES, **small)
    assert len(results) == len(FRAMES)
    images = []
    for i, (frame, (image, stats)) in enumerate(zip(FRAMES, results)):
        changed, options = pd.apply_frame(scene, frame, small)
        local, local_stats = penumbra.render(changed, **options)
        assert np.array_equal(image, local), i
        assert stats["rays"] == local_stats["rays"] and stats["frame"] == i
        images.append(image)
    plain, _ = penumbra.render(scene, **small)
    assert np.array_equal(images[3], plain), "an empty frame is the scene itself"
    for i in range(3):
        assert not np.array_equal(images[i], plain), f"frame {i} changed nothing"
    assert results[0][1]["seed"] == 1


def test_apply_frame_changes_only_what_it_names():
    scene = penumbra.load_scene("showcase")
    same, opts = pd.apply_frame(scene, {"seed": 4}, {"spp": 2})
    assert same is scene and opts == {"spp": 2, "seed": 4}
    moved, _ = pd.apply_frame(scene, FRAMES[2])
    d, before = moved.to_dict(), scene.to_dict()
    assert d["objects"][1]["transform"] == {"translate": [0.3, 0.0, 0.0]}
    assert d["objects"][0] == before["objects"][0]
    assert d["camera"] == before["camera"]
    with pytest.raises(ValueError, match="unknown frame key 'zoom'"):
        pd.apply_frame(scene, {"zoom": 2})
    with pytest.raises(ValueError, match="has 6 objects|objects"):
        pd.apply_frame(scene, {"objects": {99: {"material": "x"}}})
    with pytest.raises(penumbra.SceneError, match=r"camera\.zoom"):
        pd.apply_frame(scene, {"camera": {"zoom": 2}})


def test_bad_input_fails_on_the_client_before_submitting(client, tmp_path: Path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[objects]]\ntype = "sphere"\nradius = -1.0\n')
    with pytest.raises(penumbra.SceneError, match=r"bad\.toml:3:10"):
        pd.render(penumbra.load_scene(bad), client, width=8, height=8)
    with pytest.raises(ValueError, match="spp"):
        pd.render(penumbra.load_scene("showcase"), client, spp=0)
    with pytest.raises(TypeError, match="progress"):
        pd.render_frames(penumbra.load_scene("showcase"), client, [{}], progress=None,
                         **{"progress": print})
    with pytest.raises(ValueError, match="unknown frame key"):
        pd.render_frames(penumbra.load_scene("showcase"), client, [{"sed": 1}])


def test_errors_inside_tasks_are_raised_here_not_retried(client, tmp_path: Path):
    """A frame that breaks the scene fails once, with the scene's message."""
    scene = penumbra.load_scene("showcase")
    with pytest.raises(penumbra.SceneError, match=r"objects\[1\]\.transform"):
        pd.render_frames(scene, client, [{"objects": {1: {"transform": {"scale": 0.0}}}}],
                         width=8, height=8)


def test_command_line_with_a_scheduler_matches_the_local_render(client, small, tmp_path: Path):
    out, stats = tmp_path / "d.exr", tmp_path / "d.json"
    address = client.scheduler.address
    result = subprocess.run(
        [sys.executable, "-m", "penumbra", "render", "showcase", "-o", str(out),
         "--scheduler", address, "--tile", "16", "--stats", str(stats),
         "--width", "48", "--height", "32", "--spp", "4"],
        capture_output=True, text=True,
    )
    assert result.returncode == 0, result.stderr
    assert "wrote" in result.stdout and "workers" in result.stdout
    local, _ = penumbra.render(penumbra.load_scene("showcase"), **small)
    assert np.array_equal(penumbra.load_image(out), local)


def test_command_line_exit_status_for_bad_input(tmp_path: Path):
    result = subprocess.run(
        [sys.executable, "-m", "penumbra", "render", "no-such-scene", "-o", str(tmp_path / "x.png")],
        capture_output=True, text=True,
    )
    assert result.returncode == 2
    assert result.stderr.startswith("error: no-such-scene")
    result = subprocess.run(
        [sys.executable, "-m", "penumbra", "render", "showcase", "-o", str(tmp_path / "x.jpg")],
        capture_output=True, text=True,
    )
    assert result.returncode == 2 and "unsupported output format" in result.stderr


def test_a_worker_killed_mid_render_changes_nothing():
    """SIGKILL one of two workers while it renders a tile: Dask reruns its
    tasks (the nanny restarts it) and the image is still exactly the local one."""
    scene = penumbra.load_scene("showcase")
    options = {"width": 64, "height": 48, "spp": 16, "seed": 8}
    local, local_stats = penumbra.render(scene, **options)
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.CRITICAL,
    ) as cluster, Client(cluster) as client:
        killed: list[int] = []

        def kill_a_busy_worker(done: int, total: int) -> None:
            if killed or done < 3:
                return
            busy = [w for w, keys in client.processing().items() if keys]
            pids = client.run(os.getpid)
            victim = busy[0] if busy else next(iter(pids))
            os.kill(pids[victim], signal.SIGKILL)
            killed.append(pids[victim])

        image, stats = pd.render(scene, client, tile=8, progress=kill_a_busy_worker, **options)
        assert killed, "no worker was killed"
        assert np.array_equal(image, local)
        assert stats["rays"] == local_stats["rays"]
        # The nanny brings the worker back as a new process.
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            pids = client.run(os.getpid)
            if len(pids) == 2 and killed[0] not in pids.values():
                break
            time.sleep(0.2)
        assert len(pids) == 2 and killed[0] not in pids.values()
