#!/usr/bin/env python3
"""Holds Penumbra's renders of Mitsuba 3 XML scenes against Mitsuba 3's own.

    python bench/mitsuba_compare.py [SCENE ...] [--check] [--spp-scale F]
                                    [--penumbra BIN] [--threads N]

SCENE is a name in bench/scenes/mitsuba/compare.json (default: all of
them). That file gives, per scene, the sample count, the integrators to
compare, the path depth, and the regions: rectangles `[x0, y0, x1, y1]` in
pixels (x1, y1 excluded), one per BSDF sphere, per light's footprint, per
instance; `generated`, the images the scene reads (`envmap`, `texture`:
passed as `-D NAME=FILE`), and `defines`, other parameters. Each scene must take its sample count from a `<default
name="spp">` parameter.

For each scene and integrator (`path`, `direct`), Mitsuba 3 (`scalar_rgb`)
renders it twice with two seeds, Penumbra (`penumbra render SCENE -D spp=N
[--integrator direct]`, its own reading of the same file, choosing the
emitter of next-event estimation uniformly as Mitsuba does) once. For the
whole image and each region the script prints:

  noise    relMSE of Mitsuba's second render against its first: Mitsuba's
           own run-to-run noise at this sample count
  penumbra relMSE of Penumbra's render against Mitsuba's first
  mean Δ   Penumbra's mean radiance per channel relative to Mitsuba's, and
           Mitsuba's own run-to-run difference beside it

relMSE is the mean over pixels and channels of (x - ref)² / (ref² + 0.01).
A row agrees when Penumbra's relMSE is within 1.5x Mitsuba's noise plus
5e-4 and its means within 1%. The sample counts are chosen so that
Mitsuba's whole-image noise is below 2e-4.

Then Penumbra's `distributed` integrator (a quarter of the camera samples,
4 shadow rays and 4 reflection rays at the first vertex, the scene's path
depth) is held against Penumbra's `path` render by the same limits, and
the rays each traced, by kind, are printed from `penumbra render --stats`.

`--check` exits 1 when a row fails. Mitsuba's first render of each is kept
as NAME-INTEGRATOR-mitsuba.exr beside Penumbra's NAME-INTEGRATOR.exr. The
generated images (the environment
map of envmap.xml and the bitmap of textured.xml, made here with numpy,
deterministically) and the renders go to bench/.work/mitsuba-compare. No
download happens here: run bench/setup.sh first for Mitsuba.
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENES = HERE / "scenes" / "mitsuba"
WORK = HERE / ".work" / "mitsuba-compare"
RAY_KINDS = ("primary", "shadow", "reflection", "refraction")


def rel_mse(x, ref):
    return float(((x - ref) ** 2 / (ref**2 + 0.01)).mean())


def mean_delta(x, ref):
    """Mean per channel of x relative to ref's; 0 where both are 0."""
    a, b = x.reshape(-1, 3).mean(axis=0), ref.reshape(-1, 3).mean(axis=0)
    return [0.0 if p == q == 0 else p / q - 1.0 if q else float("inf") for p, q in zip(a, b)]


def agrees(err, noise, delta):
    return err <= 1.5 * noise + 5e-4 and max(abs(d) for d in delta) <= 0.01


def sky(np):
    """An equirectangular sky, 256 × 128, brighter toward one side, with a
    small warm sun and a dark brown ground: no symmetry a mirror or a turn
    of the map would hide."""
    h, w = 128, 256
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(w) + 0.5) / w
    theta = np.pi * v[:, None]
    phi = 2 * np.pi * u[None, :]
    d = np.stack([np.sin(phi) * np.sin(theta), np.cos(theta) * np.ones_like(phi), -np.cos(phi) * np.sin(theta)], -1)
    up = np.clip(d[..., 1], 0, 1)
    side = 0.5 + 0.5 * d[..., 0]
    img = np.empty((h, w, 3))
    img[..., 0] = 0.25 + 0.5 * side * up
    img[..., 1] = 0.35 + 0.6 * side * up
    img[..., 2] = 0.6 + 0.9 * side * up
    ground = d[..., 1] < 0
    img[ground] = np.array([0.12, 0.09, 0.06])
    sun = np.array([0.55, 0.55, 0.63])
    sun /= np.linalg.norm(sun)
    cos = d @ sun
    img += np.exp((cos - 1) / 0.004)[..., None] * np.array([60.0, 45.0, 30.0])
    return img.astype(np.float32)


def texture(np):
    """A 64 × 48 picture: a red-to-green ramp left to right, blue rising
    toward the bottom, and a white letter-like block in the top-left
    quarter, so a flip or a turn shows."""
    h, w = 48, 64
    y, x = np.mgrid[0:h, 0:w]
    img = np.empty((h, w, 3))
    img[..., 0] = 0.1 + 0.8 * (1 - x / (w - 1))
    img[..., 1] = 0.1 + 0.8 * x / (w - 1)
    img[..., 2] = 0.05 + 0.7 * y / (h - 1)
    block = ((x >= 6) & (x < 12) & (y >= 4) & (y < 20)) | ((x >= 6) & (x < 22) & (y >= 4) & (y < 9))
    img[block] = 0.9
    return img.astype(np.float32)


def penumbra(binary, path, out, spp, defines, threads, extra=()):
    stats = out.with_suffix(".json")
    cmd = [str(binary), "render", str(path), "-D", f"spp={spp}", "-o", str(out), "--quiet",
           "--threads", str(threads), "--stats", str(stats), "--light-sampler", "uniform", *extra]
    for k, v in defines.items():
        cmd += ["-D", f"{k}={v}"]
    subprocess.run(cmd, check=True)
    return json.loads(stats.read_text())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--check", action="store_true", help="exit 1 when a row fails the limits")
    ap.add_argument("--spp-scale", type=float, default=1.0,
                    help="multiply every scene's sample count (a quick look: 1/16)")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--penumbra", type=Path, default=HERE.parent / "target" / "release" / "penumbra")
    a = ap.parse_args()
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant("scalar_rgb")
    dr.set_thread_count(a.threads)
    config = json.loads((SCENES / "compare.json").read_text())
    names = a.scenes or list(config)
    unknown = [n for n in names if n not in config]
    if unknown:
        sys.exit(f"unknown scene(s) {', '.join(unknown)}; known: {', '.join(config)}")
    print(f"Mitsuba {mi.__version__} (scalar_rgb), {a.threads} threads", flush=True)
    WORK.mkdir(parents=True, exist_ok=True)
    generated = {"envmap": WORK / "sky.exr", "texture": WORK / "texture.exr"}
    mi.Bitmap(sky(np)).write(str(generated["envmap"]))
    mi.Bitmap(texture(np)).write(str(generated["texture"]))
    defines = {k: str(v) for k, v in generated.items()}

    fmt = lambda v: ", ".join(f"{x:+.2%}" for x in v)
    rows, dist_rows, failed = [], [], 0
    for name in names:
        c = config[name]
        path = SCENES / f"{name}.xml"
        spp = max(1, round(c["spp"] * a.spp_scale))
        params = {**{k: defines[k] for k in c.get("generated", [])}, **c.get("defines", {})}
        full = [0, 0, None, None]
        regions = {"whole image": full, **c["regions"]}
        renders = {}
        for integrator in c["integrators"]:
            scene = mi.load_file(str(path), spp=spp, **params)
            kw = {} if integrator == "path" else {"integrator": mi.load_dict({"type": integrator})}
            first = np.array(mi.render(scene, seed=1, **kw), dtype=np.float64)[..., :3]
            second = np.array(mi.render(scene, seed=2, **kw), dtype=np.float64)[..., :3]
            mi.Bitmap(first.astype(np.float32)).write(str(WORK / f"{name}-{integrator}-mitsuba.exr"))
            out = WORK / f"{name}-{integrator}.exr"
            extra = () if integrator == "path" else ("--integrator", integrator)
            stats = penumbra(a.penumbra, path, out, spp, params, a.threads, extra)
            ours = np.array(mi.Bitmap(str(out)), dtype=np.float64)[..., :3]
            renders[integrator] = (first, second, ours, stats)
            for region, (x0, y0, x1, y1) in regions.items():
                f, s, o = (img[y0:y1, x0:x1] for img in (first, second, ours))
                noise, err = rel_mse(s, f), rel_mse(o, f)
                delta, own = mean_delta(o, f), mean_delta(s, f)
                ok = agrees(err, noise, delta)
                failed += not ok
                rows.append(f"| {name} | {integrator} | {region} | {spp} | {noise:.2e} | {err:.2e} | {fmt(delta)} | "
                            f"{fmt(own)} | {'ok' if ok else '**differs**'} |")
                print(rows[-1], flush=True)
        if "path" in renders:
            first, second, ours, path_stats = renders["path"]
            out = WORK / f"{name}-distributed.exr"
            quarter = max(1, spp // 4)
            depth = c["max_depth"]
            stats = penumbra(a.penumbra, path, out, quarter, params, a.threads,
                             ("--integrator", "distributed", "--max-depth", str(depth), "--spp", str(quarter),
                              "--shadow-rays", "4", "--reflection-rays", "4"))
            dist = np.array(mi.Bitmap(str(out)), dtype=np.float64)[..., :3]
            noise = rel_mse(second, first)
            err = rel_mse(dist, ours)
            delta = mean_delta(dist, ours)
            ok = agrees(err, noise, delta)
            failed += not ok
            rays = lambda s: " / ".join(f"{s['rays'][k] / 1e6:.1f}" for k in RAY_KINDS)
            dist_rows.append(f"| {name} | {spp} | {quarter} | {noise:.2e} | {err:.2e} | {fmt(delta)} | "
                             f"{rays(path_stats)} | {rays(stats)} | {'ok' if ok else '**differs**'} |")
            print(dist_rows[-1], flush=True)

    print()
    print("| scene | integrator | region | spp | Mitsuba's run-to-run relMSE | Penumbra against Mitsuba | "
          "mean Δ (R, G, B) | Mitsuba's own mean Δ | result |")
    print("|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    if dist_rows:
        print()
        print("| scene | `path` spp | `distributed` spp | Mitsuba's run-to-run relMSE | `distributed` against `path` | "
              "mean Δ (R, G, B) | `path` rays, M (primary / shadow / reflection / refraction) | "
              "`distributed` rays, M | result |")
        print("|---|---|---|---|---|---|---|---|---|")
        print("\n".join(dist_rows))
    print(f"\n{failed} row(s) outside the limits")
    sys.exit(1 if failed and a.check else 0)


if __name__ == "__main__":
    main()
