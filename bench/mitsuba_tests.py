#!/usr/bin/env python3
"""Renders Mitsuba 3's own render-test scenes with Penumbra and judges each
pixel as Mitsuba's test suite judges Mitsuba.

    python bench/mitsuba_tests.py DATA [SCENE ...] [--penumbra BIN]
                                  [--threads N] [--check] [--out DIR]

DATA is a checkout of the `mitsuba-data` repository (Mitsuba's scenes and
references; nothing is downloaded here): its `tests/scenes/*/*.xml` are the
scenes, named `NAME_INTEGRATOR.xml`, each with a reference image rendered
by Mitsuba at a high sample count and the per-sample variance of its pixels
(`refs/NAME_ref_rgb.exr` and `refs/NAME_ref_rgb_var.exr`). SCENE filters the
scenes by a substring of their path.

Each scene is rendered as Mitsuba's `src/render/tests/test_renders.py`
renders it: `spp` = 2·10⁶ / pixels, the integrator of its file name, both
passed as the `spp` and `integrator` parameters (`-D`). Then, as that
test does, the image and the reference are taken to CIE XYZ (linear sRGB
primaries), each channel of each pixel gets the z statistic
|image − reference| · sqrt(spp / max(variance, 10⁻⁴)) and its two-sided
p-value, and the pixel-channel passes when the p-value exceeds the Šidák
level 1 − (1 − 0.01)^(1/pixels). A scene passes when at least 99.75% of
its pixels' channels pass.

Printed per scene: pass or fail, the fraction of channels that pass, the
smallest p-value, Penumbra's mean radiance relative to the reference's,
and the render time; or why Penumbra refused the scene. With `--noise`,
Mitsuba 3 (`scalar_rgb`, from bench/requirements.txt) renders the scene
too at the same sample count, and the relative MSE of each image against
the reference (mean of (x − ref)² / (ref² + 0.01)) is printed, Penumbra's
over Mitsuba's: the noise at equal samples, each averaged over `--seeds N`
renders (default 1; the relative MSE of one render swings by a factor of
two from seed to seed where a few pixels dominate it). `--check` exits 1 when any
scene fails or is refused. Renders go to DIR (default
bench/.work/mitsuba-tests).
"""

import argparse
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ALPHA = 0.01
SAMPLE_BUDGET = 2_000_000
# Linear sRGB to CIE XYZ (D65), as Mitsuba's bitmap conversion.
RGB_TO_XYZ = np.array(
    [
        [0.412453, 0.357580, 0.180423],
        [0.212671, 0.715160, 0.072169],
        [0.019334, 0.119193, 0.950227],
    ]
)


def read_exr(path):
    """An EXR's RGB channels as a float array (height, width, 3)."""
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        parts = f.channels()
        if "RGB" in parts:
            img = np.asarray(parts["RGB"].pixels, dtype=np.float64)
        elif "RGBA" in parts:
            img = np.asarray(parts["RGBA"].pixels, dtype=np.float64)[..., :3]
        else:
            img = np.stack([np.asarray(parts[c].pixels, dtype=np.float64) for c in "RGB"], -1)
    return img


def to_xyz(img):
    return img @ RGB_TO_XYZ.T


def p_values(img, spp, ref, ref_var):
    """Two-sided p-values of the z statistic of each pixel-channel."""
    z = np.abs(img - ref) * np.sqrt(spp / np.maximum(ref_var, 1e-4))
    erfc = np.vectorize(math.erfc)
    return erfc(z / math.sqrt(2.0))


def judge(img, ref, ref_var, spp):
    pixels = ref.shape[0] * ref.shape[1]
    p = p_values(to_xyz(img), spp, to_xyz(ref), to_xyz(ref_var))
    level = 1.0 - (1.0 - ALPHA) ** (1.0 / pixels)
    passed = np.count_nonzero(p > level) / 3.0
    return passed >= 0.9975 * pixels, passed / pixels, float(p.min()), level


def rel_mse(img, ref):
    return float(((img - ref) ** 2 / (ref**2 + 0.01)).mean())


def mitsuba_image(scene, spp, integrator, seed=1):
    """Mitsuba 3's render of `scene` at `spp` (scalar_rgb), RGB."""
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    loaded = mi.load_file(str(scene), spp=spp, integrator=integrator)
    img = np.asarray(mi.render(loaded, spp=spp, seed=seed), dtype=np.float64)
    return img[..., :3]


def scenes(data, filters):
    root = Path(data) / "tests" / "scenes"
    found = sorted(root.glob("*/*.xml"))
    return [s for s in found if not filters or any(f in str(s) for f in filters)]


def references(scene):
    name = scene.stem.rsplit("_", 1)[0]
    refs = scene.parent / "refs"
    return refs / f"{name}_ref_rgb.exr", refs / f"{name}_ref_rgb_var.exr"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data", help="a checkout of mitsuba-data")
    ap.add_argument("scenes", nargs="*", help="substrings of the scenes' paths")
    ap.add_argument("--penumbra", default=str(HERE.parent / "target" / "release" / "penumbra"))
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--noise", action="store_true", help="relative MSE against Mitsuba's at equal samples")
    ap.add_argument("--seeds", type=int, default=1,
                    help="with --noise: seeds each renderer's relative MSE is averaged over")
    ap.add_argument("--out", default=str(HERE / ".work" / "mitsuba-tests"))
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    failed = 0
    rows = []
    for scene in scenes(a.data, a.scenes):
        ref_path, var_path = references(scene)
        label = f"{scene.parent.name}/{scene.name}"
        if not ref_path.exists():
            continue
        ref, ref_var = read_exr(ref_path), read_exr(var_path)
        pixels = ref.shape[0] * ref.shape[1]
        spp = SAMPLE_BUDGET // pixels
        integrator = scene.stem.rsplit("_", 1)[1]
        image = out / f"{scene.parent.name}-{scene.stem}.exr"
        cmd = [a.penumbra, "render", str(scene), "-o", str(image), "--quiet",
               "--threads", str(a.threads), "-D", f"spp={spp}", "-D", f"integrator={integrator}"]
        start = time.perf_counter()
        r = subprocess.run(cmd, capture_output=True, text=True)
        seconds = time.perf_counter() - start
        if r.returncode != 0:
            failed += 1
            why = (r.stderr.strip().splitlines() or ["no message"])[-1]
            rows.append(f"{label:60} refused   {why}")
            print(rows[-1], flush=True)
            continue
        img = read_exr(image)
        if img.shape != ref.shape:
            failed += 1
            rows.append(f"{label:60} size      {img.shape[:2]} against {ref.shape[:2]}")
            print(rows[-1], flush=True)
            continue
        ok, fraction, p_min, level = judge(img, ref, ref_var, spp)
        failed += not ok
        mean = img.mean(axis=(0, 1)) / np.maximum(ref.mean(axis=(0, 1)), 1e-12)
        noise = ""
        if a.noise:
            ours, theirs = [rel_mse(img, ref)], []
            for seed in range(1, a.seeds):
                again = out / f"{scene.parent.name}-{scene.stem}-seed{seed}.exr"
                more = [a.penumbra, "render", str(scene), "-o", str(again), "--quiet",
                        "--threads", str(a.threads), "-D", f"spp={spp}",
                        "-D", f"integrator={integrator}", "--seed", str(seed)]
                subprocess.run(more, capture_output=True, check=True)
                ours.append(rel_mse(read_exr(again), ref))
            for seed in range(1, a.seeds + 1):
                theirs.append(rel_mse(mitsuba_image(scene, spp, integrator, seed), ref))
            ours, theirs = float(np.mean(ours)), float(np.mean(theirs))
            noise = f", relMSE {ours:.2e} / Mitsuba's {theirs:.2e} = {ours / theirs:.2f}"
        rows.append(
            f"{label:60} {'pass' if ok else 'FAIL':9} {100 * fraction:7.3f}% channels, "
            f"min p {p_min:.2e} (level {level:.1e}), mean/ref "
            f"{' '.join(f'{m:.4f}' for m in mean)}, {spp} spp, {seconds:.1f} s{noise}"
        )
        print(rows[-1], flush=True)
    total = len(rows)
    print(f"\n{total - failed} of {total} scenes pass")
    if a.check and failed:
        sys.exit(1)


if __name__ == "__main__":
    main()
