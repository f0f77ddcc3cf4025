#!/usr/bin/env python3
"""Holds Penumbra's renders of Mitsuba 3 XML scenes against Mitsuba 3's own.

    python bench/mitsuba_compare.py [SCENE.xml ...] [--spp 1024] [--penumbra BIN]

Each scene (default: every file in bench/scenes/mitsuba/) must take its
sample count from a `<default name="spp">` parameter. Mitsuba 3
(`scalar_rgb`, from bench/requirements.txt) renders it twice with two seeds,
Penumbra (`penumbra render SCENE -D spp=N`, its own reading of the same
file) once; the script prints, per scene:

  noise    relMSE of Mitsuba's second render against its first: Mitsuba's
           own run-to-run noise at this sample count
  penumbra relMSE of Penumbra's render against Mitsuba's first
  mean Δ   Penumbra's mean radiance per channel relative to Mitsuba's, and
           Mitsuba's own run-to-run difference beside it

relMSE is the mean over pixels and channels of (x - ref)² / (ref² + 0.01).
Penumbra agrees when its relMSE is within 1.5x Mitsuba's noise plus 5e-4
and its means within 1%; the script exits 1 otherwise. Work files go to
bench/.work/mitsuba-compare. No download happens here: run bench/setup.sh
first for Mitsuba.
"""

import argparse
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
WORK = HERE / ".work" / "mitsuba-compare"


def rel_mse(x, ref):
    return float(((x - ref) ** 2 / (ref**2 + 0.01)).mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", type=Path)
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--penumbra", type=Path, default=HERE.parent / "target" / "release" / "penumbra")
    a = ap.parse_args()
    import mitsuba as mi
    import numpy as np

    mi.set_variant("scalar_rgb")
    scenes = a.scenes or sorted((HERE / "scenes" / "mitsuba").glob("*.xml"))
    WORK.mkdir(parents=True, exist_ok=True)
    print(f"| scene | spp | noise (Mitsuba vs Mitsuba) | penumbra vs Mitsuba | mean Δ (R, G, B) | Mitsuba's own mean Δ | result |")
    print("|---|---|---|---|---|---|---|")
    failed = 0
    for path in scenes:
        scene = mi.load_file(str(path), spp=a.spp)
        first = np.array(mi.render(scene, seed=1), dtype=np.float64)[..., :3]
        second = np.array(mi.render(scene, seed=2), dtype=np.float64)[..., :3]
        out = WORK / f"{path.stem}.exr"
        subprocess.run([str(a.penumbra), "render", str(path), "-D", f"spp={a.spp}", "-o", str(out),
                        "--quiet"], check=True)
        ours = np.array(mi.Bitmap(str(out)), dtype=np.float64)[..., :3]
        noise = rel_mse(second, first)
        err = rel_mse(ours, first)
        mean = first.reshape(-1, 3).mean(axis=0)
        delta = ours.reshape(-1, 3).mean(axis=0) / mean - 1.0
        own = second.reshape(-1, 3).mean(axis=0) / mean - 1.0
        ok = err <= 1.5 * noise + 5e-4 and np.abs(delta).max() <= 0.01
        failed += not ok
        fmt = lambda v: ", ".join(f"{x:+.2%}" for x in v)
        print(f"| {path.stem} | {a.spp} | {noise:.2e} | {err:.2e} | {fmt(delta)} | {fmt(own)} | {'ok' if ok else 'differs'} |")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
