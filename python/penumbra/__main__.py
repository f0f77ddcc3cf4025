"""``python -m penumbra``: render a scene here or on a Dask cluster.

    python -m penumbra render SCENE -o OUT.exr [--scheduler tcp://HOST:PORT | --local-workers N]
                              [--tile N] [--tiles-dir DIR]
                              [--time-limit S] [--checkpoint FILE] [--resume FILE]
                              [render options of `penumbra render`]
    python -m penumbra scenes

Without ``--scheduler`` or ``--local-workers`` the render runs in this
process, like the ``penumbra`` binary. With them it goes through
:func:`penumbra.distributed.render`, the same code path as the tests, and
gives the same pixels. A local render takes ``--time-limit``,
``--checkpoint``, ``--checkpoint-interval`` and ``--resume`` as the binary
does (Ctrl-C saves the checkpoint); a distributed one keeps its finished
tiles in ``--tiles-dir``. Exit status as the binary's: 0 on success, 2 for
invalid input (arguments, scene, mesh, output path), 1 otherwise (130 on
Ctrl-C).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import shlex
import sys
import tempfile
from pathlib import Path
from typing import Any

from . import DISTRIBUTIONS, RENDER_OPTIONS, SceneError, load_scene, render, save_image, scenes
from ._penumbra import _OPTION_FLAGS

INPUT_ERROR = 2
OTHER_ERROR = 1


class InputError(Exception):
    """Bad arguments or output paths: exit status 2."""


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command == "scenes":
            for name, description in scenes().items():
                print(f"{name:16} {description}")
            return 0
        return _render(args)
    except (InputError, SceneError, ValueError, TypeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return INPUT_ERROR
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - the command line reports every failure
        print(f"error: {e}", file=sys.stderr)
        return OTHER_ERROR


def _render(args: argparse.Namespace) -> int:
    output = Path(args.output)
    _check_output(output, (".png", ".exr"))
    if args.stats:
        _check_output(Path(args.stats), None)
    scene = load_scene(args.scene, bunny=args.bunny)
    # Every render option has a flag of the same name ("progress" is the bar).
    options = {
        name: getattr(args, name)
        for name in RENDER_OPTIONS
        if getattr(args, name, None) is not None
    }
    distributed = bool(args.scheduler or args.local_workers)
    progressive = {
        "time_limit": args.time_limit,
        "checkpoint": args.checkpoint,
        "resume": args.resume,
    }
    if distributed:
        given = [f"--{k.replace('_', '-')}" for k, v in progressive.items() if v is not None]
        if given:
            raise InputError(
                f"{', '.join(given)}: a distributed render keeps its finished tiles with "
                "--tiles-dir instead"
            )
    elif args.tiles_dir is not None:
        raise InputError(
            "--tiles-dir keeps the tiles of a distributed render (--scheduler or --local-workers)"
        )
    if args.checkpoint:
        _check_output(Path(args.checkpoint), None)
    bar = _Bar(args.quiet)
    try:
        if distributed:
            image, stats = _render_distributed(scene, args, options, bar.update)
        else:
            image, stats = render(
                scene,
                progress=bar.update,
                checkpoint_interval=args.checkpoint_interval,
                **progressive,
                **options,
            )
    except KeyboardInterrupt:
        bar.close()
        print(f"error: interrupted{_resumable(args)}", file=sys.stderr)
        return 130
    finally:
        bar.close()
    save_image(output, image)
    if args.stats:
        _write_atomic(Path(args.stats), json.dumps(stats, indent=2) + "\n")
    if not args.quiet:
        _summary(output, stats)
    if stats.get("ended") == "time-limit":
        print(
            "the render reached its time limit: the image holds the samples rendered so far"
            + _resumable(args),
            file=sys.stderr,
        )
    return 0


def _resumable(args: argparse.Namespace) -> str:
    """How to go on with a render ended early."""
    if args.checkpoint:
        return f"; continue it with --resume {shlex.quote(args.checkpoint)}"
    return ""


def _render_distributed(scene, args, options, progress):
    # Imported here: a local render needs neither Dask nor its start-up time.
    from distributed import Client, LocalCluster

    from . import distributed

    if args.scheduler:
        with Client(args.scheduler) as client:
            return distributed.render(
                scene, client, tile=args.tile, retries=args.retries, progress=progress,
                tiles_dir=args.tiles_dir, **options,
            )
    with LocalCluster(
        n_workers=args.local_workers,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    ) as cluster, Client(cluster) as client:
        return distributed.render(
            scene, client, tile=args.tile, retries=args.retries, progress=progress,
            tiles_dir=args.tiles_dir, **options,
        )


class _Bar:
    """A tqdm progress bar fed by (done, total) callbacks; hidden when quiet,
    when stderr is not a terminal, or when tqdm is not installed."""

    def __init__(self, quiet: bool) -> None:
        self._bar = None
        self._enabled = not quiet and sys.stderr.isatty()

    def update(self, done: int, total: int) -> None:
        if not self._enabled:
            return
        if self._bar is None:
            try:
                from tqdm import tqdm
            except ImportError:
                self._enabled = False
                return
            self._bar = tqdm(total=total, unit="tile", desc="rendering", leave=False)
        self._bar.n = done
        self._bar.refresh()

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()


def _check_output(path: Path, extensions: tuple[str, ...] | None) -> None:
    if extensions and path.suffix.lower() not in extensions:
        raise InputError(
            f"{path}: unsupported output format; use .png (8-bit sRGB) or .exr (32-bit float linear)"
        )
    parent = path.parent
    if str(parent) not in ("", ".") and not parent.is_dir():
        raise InputError(f"{path}: directory {parent} does not exist")


def _write_atomic(path: Path, text: str) -> None:
    directory = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=".penumbra-", suffix=".partial", dir=directory)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _summary(output: Path, stats: dict[str, Any]) -> None:
    r, t = stats["rays"], stats["time"]
    print(f"wrote {output} ({stats['width']}x{stats['height']})")
    print(
        f"rays: {r['primary']} primary, {r['shadow']} shadow, {r['reflection']} reflection, "
        f"{r['refraction']} refraction, {r['total']} total"
    )
    line = f"time: build {t['build_s']:.3f} s, render {t['render_s']:.3f} s on {stats['threads']} threads"
    if "wall_s" in t:
        line += f" ({stats['workers']} workers, {stats['tiles']} tiles, wall {t['wall_s']:.3f} s)"
    print(f"{line}, {stats['mrays_per_s']:.2f} Mrays/s")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not an integer") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"`{text}` must be at least 1")
    return value


def _positive_seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < 1e12:
        raise argparse.ArgumentTypeError(f"`{text}` is not a positive number of seconds")
    return value


def _add_render_options(r: argparse.ArgumentParser) -> None:
    """The flags of `penumbra render`'s render options, from the library's
    options table: the same names, switches and --no- flags, each stored
    under its keyword argument."""
    for o in _OPTION_FLAGS:
        name, help = o["name"], o["help"].replace("%", "%%")
        if o["kind"] == "bool":
            # As in `penumbra render`, the last of --x and --no-x wins.
            r.add_argument(o["flag"], dest=name, action="store_true", default=None, help=help)
            if o["off_flag"]:
                r.add_argument(o["off_flag"], dest=name, action="store_false", help=o["off_help"])
        elif o["kind"] == "distribution":
            r.add_argument(o["flag"], dest=name, choices=DISTRIBUTIONS, metavar=o["metavar"], help=help)
        elif o["kind"] == "filter":
            r.add_argument(o["flag"], dest=name, choices=("box", "tent", "gaussian", "mitchell", "catmullrom", "lanczos"), metavar=o["metavar"], help=help)
        elif o["kind"] == "stop_rule":
            choices = ("calibrated", "cycles", "povray", "dammertz")
            r.add_argument(o["flag"], dest=name, choices=choices, metavar=o["metavar"], help=help)
        elif o["kind"] == "integrator":
            r.add_argument(o["flag"], dest=name, choices=("whitted", "path", "direct", "distributed", "volpath", "volpathmis", "ptracer", "depth", "aov", "moment"), metavar=o["metavar"], help=help)
        elif o["kind"] == "path_sampler":
            choices = ("independent", "sobol", "zsobol", "pmj02", "pmj02bn", "halton", "r2")
            r.add_argument(o["flag"], dest=name, choices=choices, metavar=o["metavar"], help=help)
        elif o["kind"] == "light_sampler":
            choices = ("uniform", "power", "bvh")
            r.add_argument(o["flag"], dest=name, choices=choices, metavar=o["metavar"], help=help)
        elif o["kind"] == "path":
            r.add_argument(o["flag"], dest=name, metavar=o["metavar"], help=help)
        else:
            kind = int if o["kind"] == "int" else float
            r.add_argument(o["flag"], dest=name, type=kind, metavar=o["metavar"], help=help)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m penumbra",
        description="Render Penumbra scenes here or on a Dask cluster.",
    )
    sub = p.add_subparsers(dest="command", required=True)
    sub.add_parser("scenes", help="list the built-in scenes")
    r = sub.add_parser(
        "render",
        help="render a scene file or built-in scene to PNG or EXR",
        description="Render a scene. Options override the scene file, as for `penumbra render`. "
        "When distributed, --threads is per task and defaults to 1.",
    )
    r.add_argument("scene", nargs="?", default="showcase", help="scene file (TOML) or built-in name")
    r.add_argument("-o", "--output", default="render.png", help="output image: .png or .exr")
    where = r.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler, e.g. tcp://host:8786")
    where.add_argument(
        "--local-workers",
        type=_positive_int,
        metavar="N",
        help="start a local Dask cluster of N single-threaded worker processes",
    )
    r.add_argument("--tile", type=_positive_int, default=64, metavar="N", help="tile side in pixels (distributed)")
    r.add_argument("--retries", type=int, default=3, metavar="N", help="retries per task (distributed)")
    r.add_argument("--stats", metavar="PATH", help="write render statistics as JSON")
    r.add_argument("--bunny", metavar="PATH",
                   help="the Stanford bunny PLY for scenes that need it (else $PENUMBRA_BUNNY)")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress bar, no summary")
    r.add_argument("--time-limit", type=_positive_seconds, metavar="SECONDS",
                   help="end the render after this many seconds: no tile starts after it, the "
                   "image holds the samples so far (and the checkpoint, with --checkpoint, the "
                   "state to resume from)")
    r.add_argument("--checkpoint", metavar="FILE",
                   help="save the render's state to this file every --checkpoint-interval "
                   "seconds, at the end, and on Ctrl-C: --resume continues it to the image an "
                   "uninterrupted render makes, bit for bit")
    r.add_argument("--checkpoint-interval", type=_positive_seconds, default=60.0,
                   metavar="SECONDS",
                   help="seconds between checkpoints (saved as tiles finish) (default: 60)")
    r.add_argument("--resume", metavar="FILE",
                   help="continue the render saved in this checkpoint: the same scene, files and "
                   "pixel-changing options (threads, time limit and interval may differ); another "
                   "render's checkpoint is refused")
    r.add_argument("--tiles-dir", metavar="DIR",
                   help="keep each finished tile in this directory (distributed): a restarted "
                   "render loads the tiles of the same render there and renders only the others")
    _add_render_options(r)
    return p


if __name__ == "__main__":
    sys.exit(main())
