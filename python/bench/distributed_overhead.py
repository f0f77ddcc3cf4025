"""What distributing a render over Dask costs on one machine.

Compares one process with N threads (``penumbra.render``) against N Dask
worker processes with one thread each (``penumbra.distributed.render``) at
several tile sizes, on the same cores, and prints a Markdown table of median
wall-clock times. Not a test: run it by hand, e.g.

    python python/bench/distributed_overhead.py --width 320 --height 240 --spp 4 --runs 5

The numbers in docs/distributed.md come from this script.
"""

from __future__ import annotations

import argparse
import logging
import os
import statistics
import time

import numpy as np
from distributed import Client, LocalCluster

import penumbra
from penumbra import distributed as pd


def cpu_idle_fraction(seconds: float = 0.5) -> float | None:
    """Fraction of CPU time idle over a short interval (Linux /proc/stat), or None."""

    def sample() -> tuple[int, int]:
        with open("/proc/stat") as f:
            fields = [int(x) for x in f.readline().split()[1:]]
        return sum(fields), fields[3] + fields[4]  # total, idle + iowait

    try:
        total0, idle0 = sample()
        time.sleep(seconds)
        total1, idle1 = sample()
    except (OSError, ValueError, IndexError):
        return None
    return (idle1 - idle0) / max(total1 - total0, 1)


def wait_until_idle(timeout: float, threshold: float = 0.9) -> bool:
    """Waits (up to ``timeout`` s) for other programs to leave the CPUs idle, so
    that the timings measure this benchmark and not a compiler running beside it."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        idle = cpu_idle_fraction()
        if idle is None or idle >= threshold:
            return True
    return False


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default="showcase")
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=240)
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--workers", type=int, default=os.cpu_count() or 2)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--tiles", type=int, nargs="+", default=[16, 32, 64, 128])
    p.add_argument(
        "--wait-idle",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="before each round, wait up to this long for the CPUs to be idle",
    )
    args = p.parse_args()

    scene = penumbra.load_scene(args.scene)
    options = {"width": args.width, "height": args.height, "spp": args.spp}
    reference, stats = penumbra.render(scene, **options)  # builds and caches the scene
    rays = stats["rays"]["total"]
    local = f"1 process × {args.workers} threads"
    single = "1 process × 1 thread"
    busy_rounds = 0
    times: dict[tuple[str, str], list[float]] = {}

    def timed(setup: str, tile: str, fn) -> None:
        start = time.perf_counter()
        image, _ = fn()
        times.setdefault((setup, tile), []).append(time.perf_counter() - start)
        assert np.array_equal(image, reference), f"{setup}, tile {tile}: the image differs"

    with LocalCluster(
        n_workers=args.workers,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    ) as cluster, Client(cluster) as client:
        pd.render(scene, client, tile=64, **options)  # workers import penumbra, build the scene
        # Round-robin over the set-ups, so that a burst of load from other
        # programs on the machine hits them all alike; the medians do the rest.
        for _ in range(args.runs):
            if args.wait_idle > 0 and not wait_until_idle(args.wait_idle):
                busy_rounds += 1
            timed(single, "—", lambda: penumbra.render(scene, threads=1, **options))
            timed(local, "—", lambda: penumbra.render(scene, threads=args.workers, **options))
            for tile in args.tiles:
                n = len(pd.tiles(args.width, args.height, tile))
                timed(
                    f"{args.workers} workers × 1 thread",
                    f"{tile} ({n} tiles)",
                    lambda tile=tile: pd.render(scene, client, tile=tile, **options),
                )

    local_s = statistics.median(times[(local, "—")])
    rows = []
    for (setup, tile), ts in times.items():
        m = statistics.median(ts)
        delta = "—" if setup == local else f"{(m / local_s - 1) * 100:+.0f}%"
        rows.append((setup, tile, m, delta))

    print(
        f"{args.scene} {args.width}x{args.height}, spp {args.spp}, {rays} rays, "
        f"{os.cpu_count()} cores, median of {args.runs} runs"
        + (f" ({busy_rounds} started while the CPUs were busy)" if busy_rounds else "")
        + "\n"
    )
    print("| setup | tile | wall s | vs local |")
    print("|---|---|---|---|")
    for setup, tile, seconds, delta in rows:
        print(f"| {setup} | {tile} | {seconds:.3f} | {delta} |")


if __name__ == "__main__":
    main()
