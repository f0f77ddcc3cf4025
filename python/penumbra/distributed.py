"""Rendering on a Dask cluster (``dask.distributed``), bit for bit like a local render.

Every pixel of a Penumbra render is a pure function of the scene, the render
options and the pixel's coordinates. So a frame can be cut into tiles,
rendered anywhere, in any order, any number of times, and stitched into
exactly the image a single machine makes with the same seed. This module
does that on Dask, with no scheduler of its own:

* :func:`render` splits one frame into tiles, one Dask task each;
* :func:`render_frames` renders an animation, one task per frame, each frame
  a dict of changes (seed, camera, object placement) applied to the scene.

The scene is scattered to every worker once (``client.scatter(...,
broadcast=True)``), not shipped with each task; a worker builds it (meshes,
BVH) on its first task and reuses it for the others. Tasks are pure and
submitted with ``retries``: when a worker dies, Dask reruns its tasks
elsewhere and the image is unchanged.

Errors in the scene or options are raised on the client before anything is
submitted; an error a task still meets (e.g. a mesh missing on one worker)
is returned, not raised, so that Dask does not retry what cannot succeed,
and is re-raised here.
"""

from __future__ import annotations

import copy
import hashlib
import json
import os
import tempfile
import time
import uuid
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from . import _penumbra
from ._penumbra import RENDER_OPTIONS, Scene, SceneError

try:
    from distributed import Client, as_completed, get_worker
except ImportError as e:  # pragma: no cover - depends on the environment
    raise ImportError(
        "penumbra.distributed needs Dask: pip install dask distributed "
        "(see python/requirements.txt)"
    ) from e

__all__ = ["apply_frame", "merge_stats", "render", "render_frames", "tiles"]

#: Default tile side in pixels: big enough that scheduling costs little
#: next to tracing (see docs/distributed.md for measurements).
DEFAULT_TILE = 64

#: Default retries per task. Dask reschedules the tasks of a dead worker by
#: itself; ``retries`` also reruns a task that raised an unexpected error
#: (e.g. out of memory), which a pure task makes safe.
DEFAULT_RETRIES = 3

#: Per-task rayon threads unless ``threads=`` is given: Dask already runs one
#: task per worker thread, so more would oversubscribe the cores.
TASK_THREADS = 1

#: Keys of a frame dict that change the scene description (everything else
#: must be a render option).
FRAME_TABLES = ("render", "camera")
FRAME_LISTS = ("objects", "lights")

Progress = Callable[[int, int], Any]


def tiles(width: int, height: int, tile: int) -> list[tuple[int, int, int, int]]:
    """The frame cut into ``tile``×``tile`` regions ``(x0, y0, x1, y1)``, row by row
    (the last row and column may be smaller)."""
    if not isinstance(tile, int) or isinstance(tile, bool) or tile < 1:
        raise ValueError(f"tile must be a positive int, got {tile!r}")
    return [
        (x0, y0, min(x0 + tile, width), min(y0 + tile, height))
        for y0 in range(0, height, tile)
        for x0 in range(0, width, tile)
    ]


def render(
    scene: Scene,
    client: Client,
    *,
    tile: int = DEFAULT_TILE,
    retries: int = DEFAULT_RETRIES,
    progress: Progress | None = None,
    tiles_dir: str | os.PathLike[str] | None = None,
    **options: Any,
) -> tuple[np.ndarray, dict[str, Any]]:
    """Renders one frame on a Dask cluster, tile by tile. Returns ``(image, stats)``.

    ``options`` are :func:`penumbra.render`'s (``width``, ``spp``, ``seed``,
    ...); ``threads`` is per task and defaults to 1. The image is identical
    bit for bit to ``penumbra.render(scene, **options)``, whatever the
    number of workers, the tile size or the order tasks finish in. The
    stats are merged (see :func:`merge_stats`): ray counts add up exactly to
    the local render's. ``progress(done_tiles, total_tiles)`` is called on
    this thread as tiles arrive.

    ``tiles_dir`` names a directory (made if missing) where each finished
    tile is kept, written atomically with the render's digest
    (:meth:`penumbra.Scene.digest`) and its region: a render restarted with
    the same directory, scene, files and options loads the tiles there and
    submits only the others, and makes the same image. A tile file of
    another render (another digest or tile) or a damaged one is never
    trusted: it is rendered again and replaced, with a warning. A tile
    that cannot be written raises OSError (the tasks left are cancelled;
    the tiles written are kept). The stats then count the rays of every
    tile, loaded or rendered, and ``tiles_loaded`` says how many were
    loaded.

    The scene is validated here first (which loads its meshes on the client
    once) so that a bad scene raises :class:`penumbra.SceneError` before any
    work is sent.
    """
    _check_retries(retries)
    options = _task_options(options)
    settings = scene.settings(**options)
    for w in settings["warnings"]:
        warnings.warn(w, stacklevel=2)
    # The film's crop window (the whole frame when it has none) is the image.
    cx0, cy0, cx1, cy1 = settings["crop"]
    regions = [
        (x0 + cx0, y0 + cy0, x1 + cx0, y1 + cy0)
        for x0, y0, x1, y1 in tiles(cx1 - cx0, cy1 - cy0, tile)
    ]
    started = time.perf_counter()
    kept: _TileStore | None = None
    loaded: dict[tuple[int, int, int, int], tuple[np.ndarray, dict[str, Any], tuple[str, int]]] = {}
    if tiles_dir is not None:
        kept = _TileStore(Path(tiles_dir), scene.digest(**options))
        for region in regions:
            found = kept.load(region)
            if found is not None:
                loaded[region] = found
    missing = [region for region in regions if region not in loaded]
    futures = []
    if missing:
        scattered, run = _scatter(client, scene)
        futures = [
            client.submit(
                _tile_task,
                scattered,
                region,
                options,
                key=f"penumbra-tile-{run}-{i}",
                retries=retries,
                pure=True,
            )
            for i, region in enumerate(missing)
        ]
    image: np.ndarray | None = None
    parts: list[tuple[dict[str, Any], tuple[str, int]]] = []

    def place(region: tuple[int, int, int, int], tile_image: np.ndarray) -> None:
        nonlocal image
        x0, y0, x1, y1 = region
        if image is None:
            # RGB, and the channels an `aov` or `moment` integrator writes.
            channels = tile_image.shape[2]
            image = np.zeros((cy1 - cy0, cx1 - cx0, channels), dtype=np.float32)
        image[y0 - cy0 : y1 - cy0, x0 - cx0 : x1 - cx0] = tile_image

    for region, (tile_image, stats, worker) in loaded.items():
        place(region, tile_image)
        parts.append((stats, worker))
    done = (len(loaded), len(regions))
    if loaded and progress is not None:
        progress(*done)
    for region, tile_image, stats, worker in _collect(client, futures, progress, done):
        if kept is not None:
            kept.save(tuple(region), tile_image, stats, worker)
        place(tuple(region), tile_image)
        parts.append((stats, worker))
    wall = time.perf_counter() - started
    merged = merge_stats(parts, wall_s=wall)
    merged["tile"] = tile
    if kept is not None:
        merged["tiles_loaded"] = len(loaded)
    assert image is not None
    return image, merged


def render_frames(
    scene: Scene,
    client: Client,
    frames: Iterable[Mapping[str, Any]],
    *,
    retries: int = DEFAULT_RETRIES,
    progress: Progress | None = None,
    **options: Any,
) -> list[tuple[np.ndarray, dict[str, Any]]]:
    """Renders an animation on a Dask cluster, one task per frame.

    Each frame is a dict of changes applied by :func:`apply_frame`: render
    options (``seed``, ``spp``, ...), ``camera`` keys (``position``,
    ``look_at``, ...), ``render`` keys (``background``, ...), and
    ``objects``/``lights`` as ``{index: {key: value}}`` (e.g. an object's
    ``transform`` and ``transform_end``). ``options`` apply to every frame;
    a frame's own values win. Returns ``[(image, stats), ...]`` in frame
    order, each identical to ``penumbra.render(*apply_frame(scene, frame,
    options))`` run locally. ``progress(done_frames, total_frames)`` is
    called as frames arrive.
    """
    _check_retries(retries)
    frames = list(frames)
    options = _task_options(options)
    for frame in frames:
        # Parses every frame's changes here, so a typo fails before submitting.
        _, frame_options = apply_frame(scene, frame, options)
        _penumbra._check_options(**frame_options)
    if not frames:
        return []
    scattered, run = _scatter(client, scene)
    futures = [
        client.submit(
            _frame_task,
            scattered,
            i,
            frame,
            options,
            key=f"penumbra-frame-{run}-{i}",
            retries=retries,
            pure=True,
        )
        for i, frame in enumerate(frames)
    ]
    out: list[Any] = [None] * len(frames)
    for index, image, stats, _worker in _collect(client, futures, progress):
        stats["frame"] = index
        out[index] = (image, stats)
    return out


def apply_frame(
    scene: Scene,
    frame: Mapping[str, Any],
    options: Mapping[str, Any] | None = None,
) -> tuple[Scene, dict[str, Any]]:
    """Applies one animation frame's changes. Returns ``(scene, options)``.

    ``frame`` keys:

    * any render option (``seed``, ``spp``, ``width``, ...): replaces ``options[key]``;
    * ``camera``, ``render``: dicts whose keys replace those of the scene's
      table (``{"camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0]}}``);
    * ``objects``, ``lights``: ``{index: {key: value}}`` replacing keys of the
      object or light at that index (``{"objects": {2: {"transform":
      {"translate": [0.1, 0, 0]}}}}``); a value of None removes the key.

    The scene is returned unchanged when the frame changes only render
    options; otherwise it is ``scene.derive`` of the changed description: the
    same name, base directory and bunny, and the scene's built meshes and BVH
    shared (a frame that moves only the camera does not rebuild them).
    """
    if not isinstance(frame, Mapping):
        raise TypeError(f"a frame must be a dict, got {type(frame).__name__}")
    opts = dict(options or {})
    desc_changes: dict[str, Any] = {}
    for key, value in frame.items():
        if key in RENDER_OPTIONS and key != "progress":
            opts[key] = value
        elif key in FRAME_TABLES or key in FRAME_LISTS:
            if not isinstance(value, Mapping):
                raise TypeError(f"frame[{key!r}] must be a dict, got {type(value).__name__}")
            desc_changes[key] = value
        else:
            options = [name for name in RENDER_OPTIONS if name != "progress"]
            valid = ", ".join([*FRAME_TABLES, *FRAME_LISTS, *options])
            raise ValueError(f"unknown frame key {key!r}; valid keys are: {valid}")
    if not desc_changes:
        return scene, opts
    d = scene.to_dict()
    for key, changes in desc_changes.items():
        if key in FRAME_TABLES:
            _update(d.setdefault(key, {}), changes)
            continue
        items = d.setdefault(key, [])
        for index, item_changes in changes.items():
            i = _index(key, index, len(items))
            if not isinstance(item_changes, Mapping):
                raise TypeError(
                    f"frame[{key!r}][{index!r}] must be a dict, got {type(item_changes).__name__}"
                )
            _update(items[i], item_changes)
    # Derived, so that frames with the scene's geometry share its built world.
    return scene.derive(d), opts


def merge_stats(
    parts: Sequence[tuple[Mapping[str, Any], tuple[str, int]]], *, wall_s: float
) -> dict[str, Any]:
    """Merges the stats documents of the tiles of one frame.

    ``parts`` holds ``(tile_stats, (worker_address, worker_threads))``.
    Ray counts (``rays``, ``saved``) and ``bad_samples`` are summed, so they
    equal a local render's exactly; the stages' ``batches`` add their calls
    and items, and their means follow. ``time.render_s`` is the sum of the
    tiles' render times (CPU-ish time: compare it with a local render's
    render_s times its threads), ``time.wall_s`` the client's wall clock from
    scatter to the last tile, ``time.build_s`` the longest build of any task
    (each worker builds the scene once). ``mrays_per_s`` keeps its meaning,
    rays over ``render_s``. Added: ``workers`` (distinct worker processes
    that rendered tiles), ``tiles``; ``threads`` is the threads of those
    workers times the threads per task.
    """
    if not parts:
        raise ValueError("no tiles to merge")
    out = copy.deepcopy(dict(parts[0][0]))
    out.pop("region", None)
    for section in ("rays", "saved"):
        if isinstance(out.get(section), dict):
            out[section] = {
                k: sum(int(p[section][k]) for p, _ in parts) for k in out[section]
            }
    if isinstance(out.get("batches"), dict):
        for stage in out["batches"]:
            calls = sum(int(p["batches"][stage]["calls"]) for p, _ in parts)
            items = sum(int(p["batches"][stage]["items"]) for p, _ in parts)
            out["batches"][stage] = {
                "calls": calls,
                "items": items,
                "mean": items / calls if calls else 0.0,
            }
    out["bad_samples"] = sum(int(p.get("bad_samples", 0)) for p, _ in parts)
    render_s = sum(float(p["time"]["render_s"]) for p, _ in parts)
    out["time"] = {
        "build_s": max(float(p["time"]["build_s"]) for p, _ in parts),
        "render_s": render_s,
        "wall_s": wall_s,
    }
    total = out["rays"]["total"]
    out["mrays_per_s"] = total / render_s / 1e6 if render_s > 0 else 0.0
    workers: dict[str, int] = {}
    for p, (address, nthreads) in parts:
        workers[address] = max(workers.get(address, 0), nthreads * int(p["threads"]))
    out["workers"] = len(workers)
    out["threads"] = sum(workers.values())
    out["tiles"] = len(parts)
    return out


# ---------------------------------------------------------------------------
# Tasks (module-level functions: workers import them from the installed package)


class TaskFailure:
    """An input error met inside a task, returned instead of raised so that
    Dask does not retry it; :func:`_collect` re-raises it on the client."""

    def __init__(self, error: BaseException) -> None:
        self.error = error


def _tile_task(scene: Scene, region: tuple[int, int, int, int], options: dict[str, Any]):
    try:
        image, stats = _penumbra.render_region(scene, *region, **options)
    except (SceneError, ValueError, TypeError) as e:
        return TaskFailure(e)
    return region, image, stats, _worker()


def _frame_task(scene: Scene, index: int, frame: Mapping[str, Any], options: dict[str, Any]):
    try:
        changed, opts = apply_frame(scene, frame, options)
        image, stats = _penumbra.render(changed, **opts)
    except (SceneError, ValueError, TypeError) as e:
        return TaskFailure(e)
    return index, image, stats, _worker()


def _worker() -> tuple[str, int]:
    """This worker's address and task threads, for the merged stats."""
    try:
        w = get_worker()
    except ValueError:  # run outside a worker (e.g. a synchronous client)
        return ("local", 1)
    return (str(w.address), int(getattr(w, "nthreads", 1) or 1))


# ---------------------------------------------------------------------------
# Tiles kept on disk

#: The first bytes of a tile file.
TILE_MAGIC = b"PENUMBRA-TILE\r\n"

#: The version of a tile file's layout.
TILE_FORMAT = 1


class _TileStore:
    """The finished tiles of one render in a directory, one file each.

    A file is: :data:`TILE_MAGIC`; the length of the header (8 bytes,
    little-endian); the header, JSON: ``format``, ``digest`` (the render's,
    :meth:`penumbra.Scene.digest`), ``region`` ``[x0, y0, x1, y1]``,
    ``shape`` of the pixels, ``sha256`` of the pixels, the tile's ``stats``
    and ``worker``; then the pixels, float32 little-endian, row by row. It
    is written whole to a temporary file in the directory, flushed to the
    disk and renamed over the tile's name, so a file of that name is
    always whole: a crash while writing leaves at most a stray temporary.
    """

    def __init__(self, directory: Path, digest: str) -> None:
        directory.mkdir(parents=True, exist_ok=True)
        self.directory = directory
        self.digest = digest

    def path(self, region: tuple[int, int, int, int]) -> Path:
        return self.directory / ("tile-{}-{}-{}-{}.bin".format(*region))

    def load(
        self, region: tuple[int, int, int, int]
    ) -> tuple[np.ndarray, dict[str, Any], tuple[str, int]] | None:
        """The tile of ``region`` kept in the directory, or None when there
        is none or it is not this render's or damaged (with a warning)."""
        path = self.path(region)
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            return None
        except OSError as e:
            warnings.warn(f"{path}: cannot read the tile ({e}); rendering it again", stacklevel=3)
            return None
        try:
            return self._decode(data, region)
        except _NotThisTile as e:
            warnings.warn(f"{path}: {e}; rendering it again", stacklevel=3)
            return None

    def _decode(
        self, data: bytes, region: tuple[int, int, int, int]
    ) -> tuple[np.ndarray, dict[str, Any], tuple[str, int]]:
        if not data.startswith(TILE_MAGIC):
            raise _NotThisTile("not a Penumbra tile file")
        at = len(TILE_MAGIC)
        length = int.from_bytes(data[at : at + 8], "little")
        at += 8
        if length > len(data) - at:
            raise _NotThisTile("the tile file is damaged (truncated header)")
        try:
            header = json.loads(data[at : at + length])
            fmt, digest = header["format"], header["digest"]
            stored_region = tuple(int(v) for v in header["region"])
            shape = tuple(int(v) for v in header["shape"])
            checksum, stats = header["sha256"], header["stats"]
            worker = (str(header["worker"][0]), int(header["worker"][1]))
        except (ValueError, KeyError, TypeError, IndexError) as e:
            raise _NotThisTile(f"the tile file is damaged (header: {e})") from None
        if fmt != TILE_FORMAT:
            raise _NotThisTile(f"the tile file is of format {fmt!r}, not {TILE_FORMAT}")
        if digest != self.digest:
            raise _NotThisTile(
                "the tile is of another render: the scene, a file it reads or an option "
                f"that changes the pixels differs (its digest {digest}, this render's {self.digest})"
            )
        x0, y0, x1, y1 = region
        if stored_region != region or len(shape) != 3 or shape[:2] != (y1 - y0, x1 - x0):
            raise _NotThisTile(f"the tile is of region {list(stored_region)}, not {list(region)}")
        pixels = data[at + length :]
        if len(pixels) != 4 * shape[0] * shape[1] * shape[2]:
            raise _NotThisTile("the tile file is damaged (its pixels are truncated)")
        if hashlib.sha256(pixels).hexdigest() != checksum:
            raise _NotThisTile("the tile file is damaged (its pixels do not match their checksum)")
        image = np.frombuffer(pixels, dtype="<f4").reshape(shape).astype(np.float32)
        return image, stats, worker

    def save(
        self,
        region: tuple[int, int, int, int],
        image: np.ndarray,
        stats: Mapping[str, Any],
        worker: tuple[str, int],
    ) -> None:
        pixels = np.ascontiguousarray(image, dtype="<f4").tobytes()
        header = json.dumps(
            {
                "format": TILE_FORMAT,
                "digest": self.digest,
                "region": list(region),
                "shape": list(image.shape),
                "sha256": hashlib.sha256(pixels).hexdigest(),
                "stats": stats,
                "worker": list(worker),
            }
        ).encode()
        data = TILE_MAGIC + len(header).to_bytes(8, "little") + header + pixels
        path = self.path(region)
        fd, tmp = tempfile.mkstemp(prefix=".tile-", suffix=".partial", dir=self.directory)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        _sync_directory(self.directory)


class _NotThisTile(Exception):
    """Why a tile file is not used."""


def _sync_directory(directory: Path) -> None:
    """Flushes a rename in ``directory`` to the disk, where the system can."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


# ---------------------------------------------------------------------------
# Helpers


def _collect(
    client: Client,
    futures: list,
    progress: Progress | None,
    before: tuple[int, int] | None = None,
):
    """Yields task results as they complete. On any exception (including
    KeyboardInterrupt) the remaining tasks are cancelled. ``before`` is
    ``(done, total)`` of work done without tasks (tiles loaded), which
    ``progress`` counts too."""
    start, total = before if before is not None else (0, len(futures))
    finished = False
    try:
        for done, future in enumerate(as_completed(futures), start + 1):
            result = future.result()
            future.release()
            if isinstance(result, TaskFailure):
                raise result.error
            yield result
            if progress is not None:
                progress(done, total)
        finished = True
    finally:
        if not finished:
            client.cancel(futures)


def _scatter(client: Client, scene: Scene) -> tuple[Any, str]:
    """Sends the scene to every worker once. Returns its future and a name
    for this run's task keys.

    Keys are unique per call rather than content hashes: a hashed key that
    an earlier render is still releasing can be forgotten by the scheduler
    just after it is scattered again (lost dependencies). Purity, which is
    what makes retries safe, does not need equal keys.
    """
    run = uuid.uuid4().hex[:16]
    future = client.scatter(scene, broadcast=True, hash=False)
    return future, run


def _task_options(options: Mapping[str, Any]) -> dict[str, Any]:
    if "progress" in options:
        raise TypeError(
            "progress is an argument of penumbra.distributed.render itself "
            "(called on the client per tile), not a per-task render option"
        )
    opts = {k: v for k, v in options.items() if v is not None}
    opts.setdefault("threads", TASK_THREADS)
    _penumbra._check_options(**opts)
    return opts


def _check_retries(retries: int) -> None:
    if not isinstance(retries, int) or isinstance(retries, bool) or retries < 0:
        raise ValueError(f"retries must be an int >= 0, got {retries!r}")


def _update(target: dict[str, Any], changes: Mapping[str, Any]) -> None:
    for k, v in changes.items():
        if v is None:
            target.pop(k, None)
        else:
            target[k] = v


def _index(key: str, index: Any, length: int) -> int:
    try:
        i = int(index)
    except (TypeError, ValueError):
        raise TypeError(f"frame[{key!r}] keys must be indices, got {index!r}") from None
    if not 0 <= i < length:
        raise ValueError(f"frame[{key!r}][{index!r}]: the scene has {length} {key}")
    return i
