"""Progressive renders from Python: time limits, checkpoints resumed bit for
bit, the image after each pass, and Dask tiles kept on disk across restarts."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import penumbra
from penumbra import distributed as pd

#: Long enough (some tenths of a second on one thread) that a render can be
#: stopped in the middle, in several passes over several tiles.
LONG = {"width": 96, "height": 64, "spp": 16, "passes": 4, "seed": 7, "threads": 1}


@pytest.fixture(scope="module")
def scene() -> penumbra.Scene:
    return penumbra.load_scene("showcase")


@pytest.fixture(scope="module")
def whole(scene) -> np.ndarray:
    """The uninterrupted render."""
    image, stats = penumbra.render(scene, **LONG)
    assert stats["ended"] == "complete"
    return image


class Stop(Exception):
    pass


@pytest.mark.parametrize("after_tiles", [1, 3, 7])
def test_ctrl_c_saves_the_checkpoint_and_resuming_gives_the_same_bits(
    scene, whole, tmp_path, after_tiles
):
    ckpt = tmp_path / "render.ckpt"

    def progress(done: int, total: int) -> None:
        if done >= after_tiles:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        penumbra.render(scene, checkpoint=ckpt, progress=progress, **LONG)
    assert ckpt.is_file()
    done = []
    image, stats = penumbra.render(
        scene, checkpoint=ckpt, resume=ckpt, progress=lambda d, t: done.append((d, t)), **LONG
    )
    assert stats["ended"] == "complete"
    assert np.array_equal(image, whole)
    # The resumed render had work left, and started where the first stopped.
    assert done, "the render was not stopped before its end"
    assert done[0][0] > after_tiles


def test_an_exception_in_a_callback_stops_cleanly_too(scene, whole, tmp_path):
    ckpt = tmp_path / "render.ckpt"

    def on_pass(image, info):
        raise Stop("enough")

    with pytest.raises(Stop):
        penumbra.render(scene, checkpoint=ckpt, on_pass=on_pass, **LONG)
    image, _ = penumbra.render(scene, resume=ckpt, **LONG)
    assert np.array_equal(image, whole)


def test_time_limits_end_early_and_resumes_finish_the_same_image(scene, whole, tmp_path):
    ckpt = tmp_path / "render.ckpt"
    limit, ended = 0.02, []
    while not ended or ended[-1] != "complete":
        assert len(ended) < 40, ended
        image, stats = penumbra.render(
            scene,
            time_limit=limit,
            checkpoint=ckpt,
            resume=ckpt if ended else None,
            checkpoint_interval=0.01,
            **LONG,
        )
        ended.append(stats["ended"])
        limit *= 1.5
    assert ended[0] == "time-limit"
    assert set(ended[:-1]) == {"time-limit"}
    assert np.array_equal(image, whole)


def test_a_time_limit_without_checkpoint_returns_the_samples_so_far(scene, whole):
    image, stats = penumbra.render(scene, time_limit=0.02, **LONG)
    assert stats["ended"] == "time-limit"
    assert image.shape == whole.shape
    assert stats["rays"]["primary"] < LONG["width"] * LONG["height"] * LONG["spp"]


def test_on_pass_gets_each_pass_but_the_last_on_this_thread(scene, whole):
    seen = []

    def on_pass(image, info):
        seen.append((image.copy(), dict(info), threading.current_thread()))

    image, stats = penumbra.render(scene, on_pass=on_pass, **LONG)
    assert np.array_equal(image, whole)
    assert [info["pass"] for _, info, _ in seen] == [1, 2, 3]
    assert all(info["passes"] == 4 for _, info, _ in seen)
    assert all(t is threading.main_thread() for *_, t in seen)
    for img, _, _ in seen:
        assert img.dtype == np.float32 and img.shape == whole.shape
        assert np.isfinite(img).all()
    rays = [info["rays"] for _, info, _ in seen]
    assert rays == sorted(rays) and rays[0] > 0 and rays[-1] < stats["rays"]["total"]
    assert [info["elapsed"] for _, info, _ in seen] == sorted(info["elapsed"] for _, info, _ in seen)
    # Each pass adds samples: the images differ, and converge to the last.
    errors = [np.abs(img - whole).mean() for img, _, _ in seen]
    assert errors[0] > 0 and errors[-1] < errors[0]


def test_a_checkpoint_of_another_render_is_refused_and_left_as_it_is(scene, tmp_path):
    ckpt = tmp_path / "other.ckpt"
    small = {**LONG, "spp": 4}
    penumbra.render(scene, checkpoint=ckpt, **small)
    saved = ckpt.read_bytes()
    for changed in ({"seed": 8}, {"spp": 9}):
        with pytest.raises(ValueError, match="another render") as info:
            penumbra.render(scene, checkpoint=ckpt, resume=ckpt, **{**small, **changed})
        assert str(ckpt) in str(info.value)
        assert ckpt.read_bytes() == saved
    with pytest.raises(ValueError, match="another render"):
        penumbra.render(penumbra.load_scene("cornell-box"), resume=ckpt, **small)
    # Another thread count is the same render.
    penumbra.render(scene, resume=ckpt, **{**small, "threads": 2})


def test_a_damaged_checkpoint_is_refused_and_left_as_it_is(scene, tmp_path):
    ckpt = tmp_path / "damaged.ckpt"
    small = {**LONG, "spp": 4}
    penumbra.render(scene, checkpoint=ckpt, **small)
    data = bytearray(ckpt.read_bytes())
    data[len(data) // 2] ^= 0x40
    ckpt.write_bytes(bytes(data))
    with pytest.raises(ValueError, match="damaged") as info:
        penumbra.render(scene, checkpoint=ckpt, resume=ckpt, **small)
    assert str(ckpt) in str(info.value)
    assert ckpt.read_bytes() == bytes(data)
    (tmp_path / "text.ckpt").write_text("not a checkpoint")
    with pytest.raises(ValueError, match="not a Penumbra checkpoint"):
        penumbra.render(scene, resume=tmp_path / "text.ckpt", **small)


def test_checkpoint_files_that_cannot_be_read_or_saved_raise_oserror(scene, tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.ckpt"):
        penumbra.render(scene, resume=tmp_path / "missing.ckpt", **LONG)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        penumbra.render(scene, checkpoint=tmp_path / "no" / "such.ckpt", **LONG)
    with pytest.raises(ValueError, match="time_limit"):
        penumbra.render(scene, time_limit=0, **LONG)
    with pytest.raises(ValueError, match="checkpoint_interval"):
        penumbra.render(scene, checkpoint_interval=-1.0, **LONG)
    with pytest.raises(TypeError, match="on_pass"):
        penumbra.render(scene, on_pass=3, **LONG)


TENT = "v -1 0 -1\nv 1 0 -1\nv 0 1 0\nv -1 0 1\nv 1 0 1\nf 1 2 3\nf 4 3 5\n"


def test_the_digest_covers_the_files_read_even_when_the_meshes_are_cached(tmp_path):
    (tmp_path / "tent.obj").write_text(TENT)
    d = penumbra.load_scene("showcase").to_dict()
    d["objects"].append({"type": "mesh", "path": "tent.obj", "material": d["objects"][0]["material"]})
    scene = penumbra.scene_from_dict(d, base_dir=tmp_path)
    first = scene.digest(spp=2)
    # Built again from the cache (no file read): the same digest as a fresh scene's.
    assert scene.digest(spp=2) == first
    assert penumbra.scene_from_dict(d, base_dir=tmp_path).digest(spp=2) == first
    assert scene.digest(spp=3) != first
    assert scene.digest((0, 0, 8, 8), spp=2) != first
    # The mesh rewritten: another render, although the description is the same.
    (tmp_path / "tent.obj").write_text(TENT + "f 1 2 5\n")
    assert scene.digest(spp=2) != first
    # And so a checkpoint of the old mesh is refused.
    (tmp_path / "tent.obj").write_text(TENT)
    ckpt = tmp_path / "mesh.ckpt"
    penumbra.render(scene, checkpoint=ckpt, width=24, height=16, spp=1)
    (tmp_path / "tent.obj").write_text(TENT.replace("v 0 1 0", "v 0 2.5 0"))
    with pytest.raises(ValueError, match="another render"):
        penumbra.render(scene, resume=ckpt, width=24, height=16, spp=1)


def test_python_m_penumbra_resumes_a_checkpoint(tmp_path, whole):
    ckpt = tmp_path / "r.ckpt"
    flags = [f"--{k.replace('_', '-')}={v}" for k, v in LONG.items()]
    base = [sys.executable, "-m", "penumbra", "render", "showcase", "--quiet", *flags,
            "--checkpoint", str(ckpt)]
    first = subprocess.run([*base, "--time-limit", "0.02", "-o", str(tmp_path / "a.exr")],
                           capture_output=True, text=True)
    assert first.returncode == 0, first.stderr
    assert "--resume" in first.stderr and ckpt.is_file()
    second = subprocess.run([*base, "--resume", str(ckpt), "-o", str(tmp_path / "b.exr")],
                            capture_output=True, text=True)
    assert second.returncode == 0, second.stderr
    assert np.array_equal(penumbra.load_image(tmp_path / "b.exr"), whole)
    wrong = subprocess.run([*base, "--tiles-dir", str(tmp_path), "-o", str(tmp_path / "c.exr")],
                           capture_output=True, text=True)
    assert wrong.returncode == 2 and "--tiles-dir" in wrong.stderr


def test_sigint_to_python_m_penumbra_saves_the_checkpoint(scene, tmp_path):
    slow = {**LONG, "spp": 64, "width": 128}
    ckpt = tmp_path / "r.ckpt"
    flags = [f"--{k.replace('_', '-')}={v}" for k, v in slow.items()]
    proc = subprocess.Popen(
        [sys.executable, "-m", "penumbra", "render", "showcase", "--quiet", *flags,
         "--checkpoint", str(ckpt), "--checkpoint-interval", "0.05", "-o", str(tmp_path / "a.exr")],
        stderr=subprocess.PIPE, text=True,
    )
    # Once the first checkpoint is saved the render is under way.
    deadline = time.monotonic() + 60
    while not ckpt.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "--resume" in stderr
    assert not (tmp_path / "a.exr").exists()
    done = []
    image, _ = penumbra.render(scene, resume=ckpt, progress=lambda d, t: done.append(d), **slow)
    assert done, "the render ended before the signal"
    whole, _ = penumbra.render(scene, **slow)
    assert np.array_equal(image, whole)


@pytest.mark.parametrize("name", ["showcase", "file"])
def test_checkpoints_pass_between_the_binary_and_python(cli, tmp_path, whole, name):
    if name == "file":
        (tmp_path / "scenes").mkdir()
        name = str(tmp_path / "scenes" / "s.toml")
        Path(name).write_text(penumbra.load_scene("showcase").text)
    scene = penumbra.load_scene(name)
    flags = [f"--{k.replace('_', '-')}={v}" for k, v in LONG.items()]
    ckpt = tmp_path / "cli.ckpt"
    subprocess.run([str(cli), "render", name, "--quiet", *flags, "--time-limit", "0.02",
                    "--checkpoint", str(ckpt), "-o", str(tmp_path / "a.exr")], check=True,
                   capture_output=True)
    image, stats = penumbra.render(scene, resume=ckpt, **LONG)
    assert stats["ended"] == "complete" and np.array_equal(image, whole)
    ckpt = tmp_path / "py.ckpt"
    _, stats = penumbra.render(scene, time_limit=0.02, checkpoint=ckpt, **LONG)
    assert stats["ended"] == "time-limit"
    subprocess.run([str(cli), "render", name, "--quiet", *flags, "--resume", str(ckpt),
                    "-o", str(tmp_path / "b.exr")], check=True, capture_output=True)
    assert np.array_equal(penumbra.load_image(tmp_path / "b.exr"), whole)


# ---------------------------------------------------------------------------
# Dask: finished tiles kept in a directory


class Counting:
    """Counts the tasks a render submits."""

    def __init__(self, monkeypatch, client) -> None:
        self.submitted = 0
        submit = client.submit

        def counted(*args, **kwargs):
            self.submitted += 1
            return submit(*args, **kwargs)

        monkeypatch.setattr(client, "submit", counted)


def test_a_restarted_dask_render_renders_only_the_missing_tiles(client, small, tmp_path, monkeypatch):
    scene = penumbra.load_scene("showcase")
    opts = {**small, "seed": 3}
    local, local_stats = penumbra.render(scene, **opts)
    tiles_dir = tmp_path / "tiles"
    count = Counting(monkeypatch, client)
    image, stats = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, **opts)
    n = len(pd.tiles(48, 32, 16))
    assert count.submitted == n and stats["tiles_loaded"] == 0
    assert np.array_equal(image, local)
    files = sorted(tiles_dir.glob("tile-*.bin"))
    assert len(files) == n
    assert not list(tiles_dir.glob(".tile-*"))

    # Restarted with two tiles lost: only those are rendered.
    files[0].unlink()
    files[3].unlink()
    count.submitted = 0
    image, stats = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, **opts)
    assert count.submitted == 2 and stats["tiles_loaded"] == n - 2
    assert np.array_equal(image, local)
    assert stats["rays"] == local_stats["rays"]

    # Nothing missing: nothing submitted, the same image.
    count.submitted = 0
    image, stats = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, **opts)
    assert count.submitted == 0 and np.array_equal(image, local)

    # A damaged tile is rendered again (and replaced), with a warning.
    data = bytearray(files[1].read_bytes())
    data[-5] ^= 0x01
    files[1].write_bytes(bytes(data))
    count.submitted = 0
    with pytest.warns(UserWarning, match="damaged"):
        image, _ = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, **opts)
    assert count.submitted == 1 and np.array_equal(image, local)
    count.submitted = 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pd.render(scene, client, tile=16, tiles_dir=tiles_dir, **opts)
    assert count.submitted == 0

    # Truncated, or not a tile file at all: the same.
    files[2].write_bytes(files[2].read_bytes()[:100])
    files[4].write_text("hello")
    count.submitted = 0
    with pytest.warns(UserWarning, match=r"damaged|not a Penumbra tile"):
        image, _ = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, **opts)
    assert count.submitted == 2 and np.array_equal(image, local)


def test_tiles_of_another_render_are_never_trusted(client, small, tmp_path, monkeypatch):
    scene = penumbra.load_scene("showcase")
    tiles_dir = tmp_path / "tiles"
    pd.render(scene, client, tile=16, tiles_dir=tiles_dir, seed=3, **small)
    local, _ = penumbra.render(scene, seed=4, **small)
    count = Counting(monkeypatch, client)
    with pytest.warns(UserWarning, match="another render"):
        image, stats = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, seed=4, **small)
    assert count.submitted == len(pd.tiles(48, 32, 16)) and stats["tiles_loaded"] == 0
    assert np.array_equal(image, local)
    # The directory now holds the new render's tiles.
    count.submitted = 0
    image, _ = pd.render(scene, client, tile=16, tiles_dir=tiles_dir, seed=4, **small)
    assert count.submitted == 0 and np.array_equal(image, local)


def test_the_tile_digest_is_the_render_digest(scene):
    assert scene.digest(seed=3) == scene.digest(seed=3, threads=1)
    assert len(scene.digest()) == 64 and scene.digest(seed=3) != scene.digest(seed=4)
