#!/usr/bin/env python3
"""Checks this checkout's renderer against a baseline commit: ray counts,
image means and noise, scene by scene.

    python3 bench/baseline.py --baseline REV [--bunny PATH] [--quick] [--threads N]

Builds `penumbra` of git revision REV in a temporary git worktree and of this
checkout (bench/common.py), then renders every built-in scene (`penumbra
scenes`) at 64x48 with both binaries, same arguments and same seed, in these
settings:

  D            --distribution D for every effect, D each of grid, jitter,
               semi-jitter, poisson, random, fast-random
  D +metric    the same with the acceleration metrics on (--metric, with
               --metric-min-rays 2 --shadow-metric-rays 2 so that they act
               on the small ray counts)
  mixed k      one distribution per effect through --pixel-, --lens-,
               --time-, --shadow-, --reflection- and --refraction-distribution,
               rotated by k so that every effect meets every distribution;
               odd k with --metric --pixel-metric

always with --spp 4 --shadow-rays 4 --reflection-rays 3 --refraction-rays 3.
--quick renders D with the metrics on for every other distribution and
mixed 0 and 1 only.

Checks, each a violation when it fails:

  rays     ray counts by kind, traced and saved by the metrics
           (`rays` and `saved` of --stats): identical
  mean     each channel's mean radiance: within 0.5% of the baseline's
  relMSE   the bunny scene at 160x120, 16 jittered primary rays per pixel:
           the relative MSE, mean over pixels and channels of
           (x - ref)^2 / (ref^2 + 0.01), of each binary's render against a
           1024-sample reference by the baseline binary (256 with --quick;
           another seed). The two figures agree when they differ by at most
           10% of the baseline's or by at most twice the standard error of
           their difference (per-pixel spread over sqrt(pixels), the two
           renders taken as independent), whichever allows more.

Prints a table, one row per render, and exits 1 on any violation. Bunny
scenes need --bunny PATH or $PENUMBRA_BUNNY; without it they are skipped and
the table says so. The columns `pixels` (identical, or how many differ) and
`s` (render time of baseline / current) are for information only. Work files go to bench/.work/baseline-check.
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
VENV = HERE / ".venv"
REQUIREMENTS = HERE / "requirements-baseline.txt"

DISTRIBUTIONS = ["grid", "jitter", "semi-jitter", "poisson", "random", "fast-random"]
EFFECTS = ["pixel", "lens", "time", "shadow", "reflection", "refraction"]
COUNTS = ["--spp", "4", "--shadow-rays", "4", "--reflection-rays", "3", "--refraction-rays", "3"]
METRIC = ["--metric", "--metric-min-rays", "2", "--shadow-metric-rays", "2"]
SIZE = ["--width", "64", "--height", "48"]
MEAN_TOLERANCE = 0.005
RELMSE_TOLERANCE, RELMSE_SIGMAS, RELMSE_EPS = 0.10, 2.0, 0.01


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def ensure_packages():
    """numpy and OpenEXR, from bench/.venv (created and filled from
    bench/requirements-baseline.txt when they are missing)."""
    if all(importlib.util.find_spec(m) for m in ("numpy", "OpenEXR")):
        return
    py = VENV / "bin" / "python"
    if not py.exists():
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
    subprocess.run([str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
                    "-r", str(REQUIREMENTS)], check=True)
    if Path(sys.prefix).resolve() == VENV.resolve():
        raise SystemExit(f"numpy and OpenEXR are still missing after installing {REQUIREMENTS}")
    os.execv(str(py), [str(py), str(Path(__file__).resolve())] + sys.argv[1:])


def cases(quick):
    """(label, seed, arguments) of the renders of every scene."""
    out = []
    for i, d in enumerate(DISTRIBUTIONS):
        if not quick or i % 2 == 0:
            out.append((d, ["--distribution", d]))
        if not quick or i % 2 == 1:
            out.append((f"{d} +metric", ["--distribution", d, *METRIC]))
    for k in range(2 if quick else len(DISTRIBUTIONS)):
        argv = []
        for j, effect in enumerate(EFFECTS):
            argv += [f"--{effect}-distribution", DISTRIBUTIONS[(j + k) % len(DISTRIBUTIONS)]]
        if k % 2 == 1:
            argv += [*METRIC, "--pixel-metric"]
        out.append((f"mixed {k}", argv))
    return [(label, 1 + i, COUNTS + argv) for i, (label, argv) in enumerate(out)]


def isolated(work):
    """Where the binaries run: in the work directory, without
    $PENUMBRA_BUNNY (the bunny is passed with --bunny), so that a binary
    that looks for the bunny elsewhere finds nothing."""
    return {"cwd": work, "env": {k: v for k, v in os.environ.items() if k != "PENUMBRA_BUNNY"}}


def built_ins(penumbra, work):
    """The built-in scenes, each with whether it needs the bunny."""
    text = subprocess.run([str(penumbra), "scenes"], capture_output=True, text=True, check=True,
                          **isolated(work)).stdout
    scenes = []
    for line in text.splitlines():
        if line.startswith("  ") and line.strip():
            scenes.append((line.split()[0], "[needs --bunny" in line))
    if not scenes:
        raise SystemExit(f"`{penumbra} scenes` listed no scenes:\n{text}")
    return scenes


def render(penumbra, scene, argv, out, bunny, threads):
    """Renders to OUT.exr with OUT.json; returns (stats, image)."""
    cmd = [str(penumbra), "render", scene, "-o", f"{out}.exr", "--stats", f"{out}.json", "--quiet", *argv]
    if bunny:
        cmd += ["--bunny", str(bunny)]
    if threads:
        cmd += ["--threads", str(threads)]
    p = subprocess.run(cmd, capture_output=True, text=True, **isolated(Path(out).parent))
    if p.returncode != 0:
        return {"error": (p.stderr.strip().splitlines() or [f"exit status {p.returncode}"])[-1]}, None
    return json.loads(Path(f"{out}.json").read_text()), read_exr(f"{out}.exr")


def read_exr(path):
    """The image as a (height, width, 3) float64 array."""
    import numpy as np
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        ch = f.channels()
        if "RGB" in ch:
            px = ch["RGB"].pixels
        else:
            px = np.stack([ch[c].pixels for c in "RGB"], axis=-1)
    return np.asarray(px, dtype=np.float64)


def compare(base, cur):
    """The row of one render pair: figures and violations."""
    import numpy as np

    (bs, bi), (cs, ci) = base, cur
    row = {"problems": []}
    if "error" in bs or "error" in cs:
        for who, s in (("baseline", bs), ("current", cs)):
            if "error" in s:
                row["problems"].append(f"{who} failed: {s['error']}")
        return row
    row["rays"] = cs["rays"]["total"]
    for part in ("rays", "saved"):
        if bs[part] != cs[part]:
            diff = ", ".join(f"{k} {bs[part].get(k)} -> {cs[part].get(k)}"
                             for k in sorted(set(bs[part]) | set(cs[part])) if bs[part].get(k) != cs[part].get(k))
            row["problems"].append(f"{part}: {diff}")
    if bi.shape != ci.shape:
        row["problems"].append(f"image size {bi.shape[:2]} -> {ci.shape[:2]}")
        return row
    bm, cm = bi.reshape(-1, 3).mean(axis=0), ci.reshape(-1, 3).mean(axis=0)
    rel = np.abs(cm - bm) / np.maximum(np.abs(bm), 1e-12)
    rel[np.abs(cm - bm) <= 1e-9] = 0.0
    row["mean"] = float(rel.max())
    if row["mean"] > MEAN_TOLERANCE:
        row["problems"].append("mean radiance " + ", ".join(
            f"{c} {b:.5g} -> {n:.5g}" for c, b, n in zip("RGB", bm, cm)))
    differ = int(np.any(bi != ci, axis=-1).sum())
    row["pixels"] = "identical" if differ == 0 else f"{differ} of {bi.shape[0] * bi.shape[1]} differ"
    row["s"] = (bs["time"]["render_s"], cs["time"]["render_s"])
    return row


def rel_mse(img, ref):
    """Relative MSE of an image against a reference, and its standard error
    (the spread of the per-pixel values over the square root of their count)."""
    import numpy as np

    per_pixel = ((img - ref) ** 2 / (ref ** 2 + RELMSE_EPS)).mean(axis=-1).ravel()
    return float(per_pixel.mean()), float(per_pixel.std(ddof=1) / np.sqrt(per_pixel.size))


def bunny_noise(bins, bunny, work, quick, threads):
    """The relMSE check of the bunny scene: a row like compare()'s."""
    size = ["--width", "160", "--height", "120", "--distribution", "jitter", "--shadow-rays", "1"]
    ref_spp = 256 if quick else 1024
    log(f"bunny reference: {ref_spp} samples per pixel by the baseline binary")
    rs, ref = render(bins["base"], "bunny", [*size, "--spp", str(ref_spp), "--seed", "1000"],
                     work / "bunny-ref", bunny, threads)
    if ref is None:
        return {"problems": [f"reference render failed: {rs['error']}"]}
    figures = {}
    for who in ("base", "cur"):
        s, img = render(bins[who], "bunny", [*size, "--spp", "16", "--seed", "1"], work / f"bunny-noise-{who}",
                        bunny, threads)
        if img is None:
            return {"problems": [f"{who} render failed: {s['error']}"]}
        figures[who] = rel_mse(img, ref)
    (b, bse), (c, cse) = figures["base"], figures["cur"]
    allowed = max(RELMSE_TOLERANCE * b, RELMSE_SIGMAS * (bse ** 2 + cse ** 2) ** 0.5)
    row = {"base": figures["base"], "cur": figures["cur"], "allowed": allowed, "problems": []}
    if abs(c - b) > allowed:
        row["problems"].append(f"relMSE {b:.5f} -> {c:.5f}, more than {allowed:.5f} apart")
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", required=True, metavar="REV", help="git revision to compare against")
    ap.add_argument("--bunny", metavar="PATH", help="the Stanford bunny PLY (default: $PENUMBRA_BUNNY)")
    ap.add_argument("--quick", action="store_true", help="fewer settings per scene, a cheaper bunny reference")
    ap.add_argument("--threads", type=int, help="worker threads of each render (default: all cores)")
    args = ap.parse_args()
    ensure_packages()
    sys.path.insert(0, str(HERE))
    import common

    bunny = common.bunny_path(args.bunny)
    if bunny is not None and not bunny.is_file():
        raise SystemExit(f"the Stanford bunny is not at {bunny}")
    sha = common.revision(args.baseline)
    log(f"== building {args.baseline} ({sha[:12]}) and this checkout")
    bins = {"base": common.build_revision(sha, {"penumbra-cli": ["penumbra"]})["penumbra"],
            "cur": common.build_current({"penumbra-cli": ["penumbra"]})["penumbra"]}
    work = common.WORK / "baseline-check"
    work.mkdir(parents=True, exist_ok=True)

    mine = dict(built_ins(bins["cur"], work))
    scenes = [(name, needs or mine.get(name, False)) for name, needs in built_ins(bins["base"], work)]
    todo = cases(args.quick)
    rows, skipped = [], []
    for scene, needs_bunny in scenes:
        if needs_bunny and bunny is None:
            skipped.append(scene)
            continue
        if scene not in mine:
            rows.append((scene, "(all)", {"problems": ["not a built-in scene of this checkout"]}))
        log(f"== {scene}: {len(todo)} settings")
        for label, seed, argv in todo:
            argv = [*SIZE, *argv, "--seed", str(seed)]
            stem = work / f"{scene}-{seed}"
            pair = {who: render(bins[who], scene, argv, f"{stem}-{who}", bunny, args.threads)
                    for who in ("base", "cur")}
            rows.append((scene, label, compare(pair["base"], pair["cur"])))
    noise = bunny_noise(bins, bunny, work, args.quick, args.threads) if bunny is not None else None

    print(f"baseline {args.baseline} ({sha[:12]}) against this checkout; "
          f"{len(todo)} settings per scene at 64x48, {' '.join(COUNTS)}")
    print()
    print("| scene | setting | rays | mean Δ | pixels | s (baseline / current) | result |")
    print("|---|---|---|---|---|---|---|")
    for scene, label, r in rows:
        mean = f"{100 * r['mean']:.3f}%" if "mean" in r else "—"
        s = f"{r['s'][0]:.3f} / {r['s'][1]:.3f}" if "s" in r else "—"
        result = "ok" if not r["problems"] else "**" + "; ".join(r["problems"]) + "**"
        rays = f"{r['rays']:,}" if "rays" in r else "—"
        print(f"| {scene} | {label} | {rays} | {mean} | {r.get('pixels', '—')} | {s} | {result} |")
    print()
    problems = sum(bool(r["problems"]) for _, _, r in rows)
    if noise is not None:
        if "base" in noise:
            (b, bse), (c, cse) = noise["base"], noise["cur"]
            print(f"bunny relMSE against the reference: baseline {b:.5f} ± {bse:.5f}, current {c:.5f} ± {cse:.5f} "
                  f"(difference {c - b:+.5f}, allowed ±{noise['allowed']:.5f}): "
                  + ("ok" if not noise["problems"] else "**VIOLATION**"))
        else:
            print("bunny relMSE: **" + "; ".join(noise["problems"]) + "**")
        problems += bool(noise["problems"])
    if skipped:
        print(f"SKIPPED (no bunny: pass --bunny PATH or set PENUMBRA_BUNNY): {', '.join(skipped)} and the relMSE check")
    checks = len(rows) + (noise is not None)
    print(f"{checks - problems} of {checks} checks pass" + (f"; {problems} VIOLATION(S)" if problems else ""))
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
