#!/usr/bin/env python3
"""Holds Penumbra's renders of Mitsuba 3 XML scenes against Mitsuba 3's own.

    python bench/mitsuba_compare.py [SCENE ...] [--check] [--spp-scale F]
                                    [--penumbra BIN] [--threads N] [--speed]

SCENE is a name in bench/scenes/mitsuba/compare.json (default: all of
them). That file gives, per scene, the sample count, the integrators to
compare, the path depth, and the regions: rectangles `[x0, y0, x1, y1]` in
pixels (x1, y1 excluded), one per BSDF sphere, per light's footprint, per
instance; `generated`, the images the scene reads (`envmap`, `texture`:
passed as `-D NAME=FILE`), and `defines`, other parameters; a media scene
gives `reference_spp` instead of integrators and depth, and may give
`speed_spp` and `null_collisions_spp` (see below). Each scene must take
its sample count from a `<default name="spp">` parameter.

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

Scenes with participating media (`media_*.xml`, integrator `volpath`) are
judged against a reference instead: Mitsuba 3 renders the scene once at
`reference_spp` through its `moment` integrator, which gives each pixel's
mean and the variance of one sample (kept in bench/.work/mitsuba-compare
and reused while the scene file and sample count are unchanged).
Penumbra renders it at `spp`; as Mitsuba's own render tests do
(bench/mitsuba_tests.py), each pixel and channel in CIE XYZ gets the z
statistic of its difference from the reference, here with both images'
noise, |x − ref| / sqrt(var · (1/spp + 1/reference_spp)), and its
two-sided p-value; the scene passes when at least 99.75% of them exceed
the Šidák level 1 − 0.99^(1/pixels). Each region's mean (and the whole
image's) is held against the reference's by the same z statistic over
the region (each pixel's variance floored as above), at the Šidák level
of all regions and channels; its ratio is printed. Mitsuba's own render
at `spp` (seed 2) is judged by the same z-test, to show how far its noise
alone goes. With `--speed`, Penumbra and Mitsuba then render each such scene
at `speed_spp`, side by side (at the same time), on one thread each, and
the relative MSE against the reference times the render time is compared;
and the smoke scene's null collisions per camera ray are counted with
Penumbra's default majorant grid and with one majorant
(`majorant_resolution = 1`, Mitsuba's). Mitsuba is given one thread only
after the scene is loaded (Mitsuba 3.9.1 hangs loading a `gridvolume`
on one thread).

`--check` exits 1 when a row fails. Mitsuba's first render of each is kept
as NAME-INTEGRATOR-mitsuba.exr beside Penumbra's NAME-INTEGRATOR.exr. The
generated images (the environment
map of envmap.xml and the bitmap of textured.xml, made here with numpy,
deterministically) and the renders go to bench/.work/mitsuba-compare. No
download happens here: run bench/setup.sh first for Mitsuba.
"""

import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENES = HERE / "scenes" / "mitsuba"
WORK = HERE / ".work" / "mitsuba-compare"
RAY_KINDS = ("primary", "shadow", "reflection", "refraction")
# Linear sRGB to CIE XYZ (D65), as in bench/mitsuba_tests.py.
RGB_TO_XYZ = ((0.412453, 0.357580, 0.180423), (0.212671, 0.715160, 0.072169), (0.019334, 0.119193, 0.950227))
ALPHA = 0.01


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


def reference(mi, np, name, path, spp, params):
    """Mitsuba's render of `path` at `spp` through `moment`: the RGB image,
    and each pixel's mean and one sample's variance in XYZ. Cached in WORK
    under the hash of the scene file, its parameters and `spp`."""
    key = hashlib.sha256(path.read_bytes() + json.dumps([spp, params], sort_keys=True).encode()).hexdigest()[:12]
    cache = WORK / f"{name}-reference-{key}.exr"
    if not cache.exists():
        scene = mi.load_file(str(path), spp=spp, **params)
        moment = mi.load_dict({"type": "moment", "nested": scene.integrator()})
        start = time.perf_counter()
        img = np.array(mi.render(scene, integrator=moment, seed=101), dtype=np.float32)
        print(f"  reference of {name}: {spp} spp in {time.perf_counter() - start:.0f} s", flush=True)
        mi.Bitmap(img).write(str(cache))
    img = np.array(mi.Bitmap(str(cache)), dtype=np.float64)
    rgb, m1, m2 = img[..., 0:3], img[..., 3:6], img[..., 6:9]
    return rgb, np.maximum(m2 - m1**2, 0.0)


def z_scores(np, x, ref, var, spp, ref_spp):
    """|x − ref| over the standard error of the difference of a pixel mean
    of `spp` samples and the reference's of `ref_spp`, per pixel-channel in
    XYZ; the variance floored at 1e-4 as Mitsuba's render tests floor it."""
    m = np.array(RGB_TO_XYZ)
    return np.abs((x - ref) @ m.T) / np.sqrt(np.maximum(var, 1e-4) * (1 / spp + 1 / ref_spp))


def p_value(z):
    return math.erfc(z / math.sqrt(2.0))


def media_scene(mi, dr, np, a, name, c, path, params):
    """The per-pixel and per-region tests of a media scene; then, with
    `--speed`, the relMSE × time comparison. Returns (rows, speed row or
    None, failures)."""
    spp = max(1, round(c["spp"] * a.spp_scale))
    ref_spp = max(1, round(c["reference_spp"] * a.spp_scale))
    ref, var = reference(mi, np, name, path, ref_spp, params)
    out = WORK / f"{name}.exr"
    penumbra(a.penumbra, path, out, spp, params, a.threads)
    ours = np.array(mi.Bitmap(str(out)), dtype=np.float64)[..., :3]
    pixels = ref.shape[0] * ref.shape[1]
    level = 1.0 - (1.0 - ALPHA) ** (1.0 / pixels)

    def judge(img):
        p = np.vectorize(p_value)(z_scores(np, img, ref, var, spp, ref_spp))
        return np.count_nonzero(p > level) / p.size, float(p.min())

    fraction, p_min = judge(ours)
    ok = fraction >= 0.9975
    # Mitsuba's own render at the same sample count, judged alike: how
    # often its noise alone falls outside the test.
    scene = mi.load_file(str(path), spp=spp, **params)
    own, own_min = judge(np.array(mi.render(scene, seed=2), dtype=np.float64)[..., :3])
    rows, failed = [], 0
    regions = {"whole image": [0, 0, None, None], **c["regions"]}
    region_level = 1.0 - (1.0 - ALPHA) ** (1.0 / (3 * len(regions)))
    region_ok = True
    means = []
    for region, (x0, y0, x1, y1) in regions.items():
        o, r, v = (img[y0:y1, x0:x1].reshape(-1, 3) for img in (ours, ref, var))
        m = np.array(RGB_TO_XYZ)
        diff = (o.mean(axis=0) - r.mean(axis=0)) @ m.T
        se = np.sqrt(np.maximum(v, 1e-4).sum(axis=0) / len(v) ** 2 * (1 / spp + 1 / ref_spp))
        zr = np.abs(diff) / se
        pr = min(p_value(float(t)) for t in zr)
        ratio = o.mean(axis=0) / np.maximum(r.mean(axis=0), 1e-12)
        good = pr > region_level
        region_ok &= good
        means.append(f"{region}: {' '.join(f'{q:.4f}' for q in ratio)} (p {pr:.2g}){'' if good else ' **differs**'}")
    failed += (not ok) + (not region_ok)
    rel = rel_mse(ours, ref)
    rows.append(f"| {name} | {spp} | {ref_spp} | {'pass' if ok and region_ok else '**FAIL**'} | "
                f"{100 * fraction:.3f}% | {p_min:.1e} | {100 * own:.3f}%, {own_min:.1e} | {rel:.2e} | "
                f"{'; '.join(means)} |")
    print(rows[-1], flush=True)
    speed = None
    if a.speed and "speed_spp" in c:
        speed = speed_row(mi, dr, np, a, name, c, path, params, ref)
        print(speed, flush=True)
    return rows, speed, failed


def speed_row(mi, dr, np, a, name, c, path, params, ref):
    """Penumbra and Mitsuba at `speed_spp` on one thread each, at the same
    time: relMSE against the reference × render time, and their ratio."""
    spp = max(1, round(c["speed_spp"] * a.spp_scale))
    scene = mi.load_file(str(path), spp=spp, **params)
    dr.set_thread_count(1)
    out = WORK / f"{name}-speed.exr"
    stats = out.with_suffix(".json")
    cmd = [str(a.penumbra), "render", str(path), "-D", f"spp={spp}", "-o", str(out), "--quiet",
           "--threads", "1", "--stats", str(stats), "--seed", "5", "--light-sampler", "uniform"]
    for k, v in params.items():
        cmd += ["-D", f"{k}={v}"]
    proc = subprocess.Popen(cmd)
    start = time.perf_counter()
    theirs = np.array(mi.render(scene, seed=5), dtype=np.float64)[..., :3]
    t_mitsuba = time.perf_counter() - start
    if proc.wait() != 0:
        raise RuntimeError(f"penumbra failed on {path}")
    dr.set_thread_count(max(a.threads, 2))
    t_ours = json.loads(stats.read_text())["time"]["render_s"]
    ours = np.array(mi.Bitmap(str(out)), dtype=np.float64)[..., :3]
    e_ours, e_theirs = rel_mse(ours, ref), rel_mse(theirs, ref)
    ratio = (e_ours * t_ours) / (e_theirs * t_mitsuba)
    return (f"| {name} | {spp} | {e_ours:.2e} | {t_ours:.2f} | {e_theirs:.2e} | {t_mitsuba:.2f} | "
            f"{e_ours / e_theirs:.2f} | {t_ours / t_mitsuba:.2f} | **{ratio:.2f}** |")


def null_collisions(a, name, path, params, spp):
    """Null collisions per camera ray of Penumbra's render of `path` with its
    default majorant grid and with one majorant for the whole medium."""
    toml = WORK / f"{name}-one-majorant.toml"
    cmd = [str(a.penumbra), "convert", str(path), "-o", str(toml)]
    for k, v in params.items():
        cmd += ["-D", f"{k}={v}"]
    subprocess.run(cmd, check=True, capture_output=True)
    text = toml.read_text()
    lines = []
    for line in text.splitlines():
        lines.append(line)
        if line.startswith("[media.") and "heterogeneous" in text:
            lines.append("majorant_resolution = 1")
    toml.write_text("\n".join(lines) + "\n")
    counts = []
    for scene in (path, toml):
        out = WORK / f"{name}-majorant.exr"
        stats = out.with_suffix(".json")
        cmd = [str(a.penumbra), "render", str(scene), "--spp", str(spp), "-o", str(out), "--quiet",
               "--threads", str(a.threads), "--stats", str(stats), "--light-sampler", "uniform"]
        if scene == path:
            for k, v in params.items():
                cmd += ["-D", f"{k}={v}"]
        subprocess.run(cmd, check=True)
        s = json.loads(stats.read_text())
        counts.append(s["media"]["null_collisions"] / s["rays"]["primary"])
    return counts


def table(header, rows):
    """Prints a Markdown table of `rows` under `header`, after a blank line;
    nothing without rows."""
    if not rows:
        return
    print()
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    print("\n".join(rows))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--check", action="store_true", help="exit 1 when a row fails the limits")
    ap.add_argument("--spp-scale", type=float, default=1.0,
                    help="multiply every scene's sample count (a quick look: 1/16)")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--speed", action="store_true",
                    help="media scenes: relMSE x time against Mitsuba on one thread each, and null collisions")
    ap.add_argument("--penumbra", type=Path, default=HERE.parent / "target" / "release" / "penumbra")
    a = ap.parse_args()
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant("scalar_rgb")
    config = json.loads((SCENES / "compare.json").read_text())
    names = a.scenes or list(config)
    unknown = [n for n in names if n not in config]
    if unknown:
        sys.exit(f"unknown scene(s) {', '.join(unknown)}; known: {', '.join(config)}")
    print(f"Mitsuba {mi.__version__} (scalar_rgb), {a.threads} threads", flush=True)
    WORK.mkdir(parents=True, exist_ok=True)
    generated = {"envmap": WORK / "sky.exr", "texture": WORK / "texture.exr"}
    # Loading a `gridvolume` with one thread hangs Mitsuba 3.9.1: scenes are
    # loaded with two or more, and the speed runs set one after loading.
    dr.set_thread_count(max(a.threads, 2))
    mi.Bitmap(sky(np)).write(str(generated["envmap"]))
    mi.Bitmap(texture(np)).write(str(generated["texture"]))
    defines = {k: str(v) for k, v in generated.items()}

    fmt = lambda v: ", ".join(f"{x:+.2%}" for x in v)
    rows, dist_rows, media_rows, speed_rows, nulls, failed = [], [], [], [], [], 0
    for name in names:
        c = config[name]
        path = SCENES / f"{name}.xml"
        spp = max(1, round(c["spp"] * a.spp_scale))
        params = {**{k: defines[k] for k in c.get("generated", [])}, **c.get("defines", {})}
        if "reference_spp" in c:
            r, speed, f = media_scene(mi, dr, np, a, name, c, path, params)
            media_rows += r
            speed_rows += [speed] if speed else []
            failed += f
            if a.speed and "null_collisions_spp" in c:
                default, one = null_collisions(a, name, path, params, c["null_collisions_spp"])
                nulls.append(f"| {name} | {default:.2f} | {one:.2f} | {one / default:.1f} |")
                print(nulls[-1], flush=True)
            continue
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

    table(["scene", "spp", "reference spp", "result", "pixel-channels passing", "smallest p",
           "Mitsuba's own render: passing, smallest p", "relMSE",
           "mean / reference (R G B) by region"], media_rows)
    table(["scene", "spp", "Penumbra relMSE", "Penumbra s", "Mitsuba relMSE", "Mitsuba s",
           "relMSE ratio", "time ratio", "relMSE × time ratio"], speed_rows)
    table(["scene", "null collisions per camera ray, majorant grid 16³", "one majorant", "ratio"],
          nulls)
    if not rows:
        print(f"\n{failed} row(s) outside the limits")
        sys.exit(1 if failed and a.check else 0)
    table(["scene", "integrator", "region", "spp", "Mitsuba's run-to-run relMSE",
           "Penumbra against Mitsuba", "mean Δ (R, G, B)", "Mitsuba's own mean Δ", "result"], rows)
    table(["scene", "`path` spp", "`distributed` spp", "Mitsuba's run-to-run relMSE",
           "`distributed` against `path`", "mean Δ (R, G, B)",
           "`path` rays, M (primary / shadow / reflection / refraction)", "`distributed` rays, M",
           "result"], dist_rows)
    print(f"\n{failed} row(s) outside the limits")
    sys.exit(1 if failed and a.check else 0)


if __name__ == "__main__":
    main()
