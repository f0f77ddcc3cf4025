#!/usr/bin/env python3
"""Penumbra's benchmark harness: sets up the reference systems, runs them and
Penumbra on the same scenes in one run, and prints a table of medians and
ratios (docs/performance.md explains every figure).

    python3 bench/run.py [--bunny PATH] [--rounds N] [--quick] [--only a,b,c,...]
                         [--skip a,b,...] [--obvhs] [--baseline REV] [--update-doc]
                         [--no-setup]

Sections (--only and --skip take their names):
  rays     Embree (embreex) vs Penumbra: build, closest and any hit, per thread
  a        scene (a): 16 primary rays per pixel + 1 shadow ray, vs Mitsuba 3;
           Penumbra on 1 vs 2 threads (parallel efficiency on a long frame)
  b        scene (b): 1 primary ray + 64 shadow rays per pixel, vs POV-Ray
  whitted  the Whitted bunny at 800x600: frames per second, 1 vs 2 threads
  mirror   the thesis's hardest case (Fig. 4.8 right): bunny-mirror at
           800x600, 4 spp, 32 reflection and 32 shadow rays, metrics on;
           2 threads then 1, about 4 minutes a round (--skip mirror)
  scaling  parallel efficiency from many short one- and two-thread pairs of
           scene (a) at 400x300 and of the Whitted frame (--pairs, default
           25), order alternating
  linear   render time against pixels, primary rays and shadow rays
  memory   maximum resident memory of `penumbra render bunny`; peak memory
           of reading and building 10,000 instances of the bunny from
           Mitsuba XML, beyond one bunny's; peak memory of the largest
           hostile TOML (a 4 MB array of 2 million numbers, refused)
  million  a procedural 1,000,000-triangle mesh: build, render, memory
  points   the cost of a point of each low-discrepancy distribution (sets of
           256) and of a set of one
  path     the path tracer on the Cornell box (bench/scenes/mitsuba/
           cornell.xml, read by both renderers) at 256x256, 64 spp,
           max_depth 8, 2 threads, vs Mitsuba 3 scalar_rgb and llvm_ad_rgb
           at equal spp; then relative MSE x time against a 2048-spp
           reference (Mitsuba llvm_ad_rgb, rendered once into bench/.work)
  instances 10,000 instances of the bunny (one group, one tree): read and
           build time, memory beyond one instance, closest-hit rate
  xmlread  the million-triangle scene read and built from Mitsuba XML and
           from TOML (scenebench's read_and_build_s, from opening the file
           to the built scene), pairs in alternating order, at least 5
  before   with --baseline REV: git revision REV against the working tree
           on three bunny scenes (one thread, CPU time)

--baseline REV builds git revision REV (penumbra, raybench, scenebench) in a
temporary git worktree with a target directory of its own (bench/common.py)
and runs every Penumbra figure of the sections chosen for REV's binaries and
this tree's side by side: in each round both builds, the one going first
alternating from round to round; --rounds defaults to 5 then (the linear and
million sections, which otherwise run once, run --rounds times too). A table
gives both medians, the median of the per-round ratios (this tree / REV) and
whether this tree is worse (slower, more memory) by more than 3%. Rows of Embree, Mitsuba and
POV-Ray, and Penumbra's figures timed through its Python module, have no
baseline column. REV's binaries are kept in bench/.work/rev and reused.

Setup (bench/setup.sh) installs Mitsuba 3, embreex and maturin into
bench/.venv (bench/requirements.txt) and POV-Ray and LLVM's shared library
from Debian's packages; the script then re-runs itself with the venv's
Python and builds Penumbra's Python module into the venv with maturin. Work files go to bench/.work.
Rounds alternate the systems compared, so that load from other processes on
a shared machine hits both alike; each figure is the median over rounds, and
each ratio the median of the per-round ratios.
"""

import argparse
import json
import os
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
VENV_PY = HERE / ".venv" / "bin" / "python"
BEGIN, END = "<!-- results:begin -->", "<!-- results:end -->"
# A row of the baseline table is flagged when this tree is worse (slower, or
# more memory) than the baseline by more than this fraction.
SLOWER = 0.03
SECTIONS = ["rays", "a", "b", "whitted", "mirror", "scaling", "linear", "memory", "million", "points", "path", "instances",
            "xmlread", "lights", "progressive", "kernels", "before"]
# bench/common.py needs numpy: it is imported where used, once the venv runs the script.
sys.path.insert(0, str(HERE))


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def run(cmd, env=None, cwd=None, check=True):
    log("$", " ".join(str(c) for c in cmd))
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=env, cwd=cwd)
    if check and p.returncode != 0:
        sys.stderr.write(p.stdout + p.stderr)
        raise SystemExit(f"command failed ({p.returncode}): {cmd[0]}")
    return p


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def llvm_library():
    """A libLLVM that Dr.Jit accepts (it needs LLVM 15 or later)."""
    # Debian names them libLLVM-15.so.1 up to 18 and libLLVM.so.19.1 from 19
    # on (libLLVM-19.so beside it).
    cands = sorted(Path("/usr/lib/x86_64-linux-gnu").glob("libLLVM*.so*")) + sorted(
        Path("/usr/lib").glob("llvm-*/lib/libLLVM*.so*"))
    def major(p):
        m = re.search(r"LLVM(?:-|\.so\.)(\d+)", p.name)
        return int(m.group(1)) if m else 0
    good = [p for p in cands if major(p) >= 15]
    return str(max(good, key=major)) if good else None


# ---------------------------------------------------------------------------
# Setup and build
# ---------------------------------------------------------------------------

def ensure_venv(args):
    if Path(sys.prefix).resolve() == (HERE / ".venv").resolve():
        return
    if not args.no_setup:
        subprocess.run(["bash", str(HERE / "setup.sh")], check=True)
    os.execv(str(VENV_PY), [str(VENV_PY), str(Path(__file__).resolve())] + sys.argv[1:])


# The binaries the harness runs, by package.
BINARIES = {"penumbra-cli": ["penumbra"], "penumbra-bench": ["raybench", "scenebench"]}


def features(args):
    return ["penumbra-bench/obvhs"] if args.obvhs else []


def build(args):
    import common

    # lightsbench is this tree's only: a baseline is built from BINARIES.
    current = BINARIES | {"penumbra-bench": BINARIES["penumbra-bench"] + ["lightsbench"]}
    bins = common.build_current(current, features(args), run=run)
    # The Python module, into the harness's venv: the ray section times
    # Penumbra's batch call through Python, as it times embreex's.
    env = dict(os.environ, VIRTUAL_ENV=str(HERE / ".venv"))
    run([VENV_PY, "-m", "maturin", "develop", "--release", "--quiet", "-m", ROOT / "python" / "Cargo.toml"],
        cwd=ROOT, env=env)
    return bins


def build_baseline(args):
    """The same binaries of git revision --baseline, built from its own
    sources in a temporary git worktree (bench/common.py): what `base` is
    in the sections. Its Python module is not built: the rows timed through
    Python (and those of Embree, Mitsuba and POV-Ray) have no baseline
    column."""
    import common

    sha = common.revision(args.baseline)
    log(f"== building the baseline {args.baseline} ({sha[:12]})")
    return {"rev": sha[:12], "bins": common.build_revision(sha, BINARIES, features(args), run=run)}


def both(bins, base, k, fn):
    """fn(binaries) for this tree's binaries and, when `base` is given, for
    the baseline's, which goes first alternating with k (the round), so
    that load from other processes hits both alike: (this tree's result,
    the baseline's or None)."""
    if base is None:
        return fn(bins), None
    order = [("cur", bins), ("base", base["bins"])]
    if k % 2 == 0:
        order.reverse()
    out = {who: fn(b) for who, b in order}
    return out["cur"], out["base"]


def versus(what, cur, base, higher=False):
    """A row of the baseline table from per-round figures of this tree and
    of the baseline: medians, and the median of the per-round ratios
    (this tree / baseline). `higher`: a larger figure is faster."""
    ratio = med([c / b for c, b in zip(cur, base) if c is not None and b])
    slower = ratio is not None and (ratio < 1 / (1 + SLOWER) if higher else ratio > 1 + SLOWER)
    return {"what": what, "cur": med(cur), "base": med(base), "ratio": ratio, "higher": higher,
            "runs": len(cur), "slower": slower}


def prepare(args):
    import common
    import povray_bunny

    common.WORK.mkdir(exist_ok=True)
    w = common.WORK
    bunny = common.bunny_path(args.bunny)
    if bunny is None:
        raise SystemExit("the harness needs the Stanford bunny: pass --bunny PATH or set PENUMBRA_BUNNY to it")
    if not bunny.exists():
        raise SystemExit(f"the Stanford bunny is not at {bunny}: pass --bunny PATH or set PENUMBRA_BUNNY to it")
    tris = common.bunny_triangles(bunny)
    tris.astype("<f4").tofile(w / "bunny.tris")
    if not (w / "camera.rays").exists():
        common.camera_rays().astype("<f4").tofile(w / "camera.rays")
    if not (w / "incoherent.rays").exists():
        common.incoherent_rays(tris).astype("<f4").tofile(w / "incoherent.rays")
    povray_bunny.write_pov(bunny, w / "bunny.pov", "area")
    if not (w / "sphere1m.ply").exists():
        v, f = common.bumpy_sphere(1000, 501)
        common.write_ply(w / "sphere1m.ply", v, f)
    (w / "sphere1m.toml").write_text(
        "# A procedural bumpy sphere of 1,000,000 triangles on the bunny scene's ground.\n"
        "[camera]\nposition = [0.0, 1.3, 4.2]\nlook_at = [0.0, 0.8, 0.0]\nfov = 40\n\n"
        "[[objects]]\ntype = \"quad\"\norigin = [-5.0, 0.0, -5.0]\nedge_u = [0.0, 0.0, 10.0]\nedge_v = [10.0, 0.0, 0.0]\n\n"
        "[[objects]]\ntype = \"mesh\"\npath = \"sphere1m.ply\"\n"
        "transform = { scale = 0.8, translate = [0.0, 0.8, 0.0] }\n\n"
        "[[lights]]\ntype = \"rect\"\norigin = [-0.5, 4.0, -0.5]\nedge_u = [1.0, 0.0, 0.0]\n"
        "edge_v = [0.0, 0.0, 1.0]\nradiance = [40.0, 40.0, 40.0]\n")
    return {"bunny": bunny, "triangles": len(tris)}


# ---------------------------------------------------------------------------
# Measurements
# ---------------------------------------------------------------------------

def scenebench(bins, bunny, scene, *extra, repeat=3):
    p = run([bins["scenebench"], scene, "--bunny", bunny, "--repeat", repeat, *extra], cwd=ROOT)
    return json.loads(p.stdout)


def section_before(args, bins, data):
    base = data["base"]
    if base is None:
        return {"skipped": "no --baseline REV"}
    cases = [
        ("Whitted bunny (1 ray/pixel, point light)", [HERE / "scenes" / "bunny-whitted.toml"], 5),
        ("bunny, 4 primary + 1 shadow ray/pixel", ["bunny", "--spp", "4", "--distribution", "jitter"], 1),
        ("scene (b): bunny, 64 shadow rays/pixel", ["bunny", "--shadow-rays", "64", "--distribution", "grid"], 1),
    ]
    rows = []
    for name, argv, rep in cases:
        old, new = [], []
        for k in range(args.rounds):
            n, o = both(bins, base, k, lambda b: scenebench(b, data["bunny"], argv[0], *argv[1:], "--threads", "1",
                                                             repeat=rep))
            new.append(n)
            old.append(o)
        rows.append({
            "what": name, "rays": new[0]["rays"],
            "before_cpu": med([x["render_cpu_s"] for x in old]), "after_cpu": med([x["render_cpu_s"] for x in new]),
            "before_s": med([x["render_s"] for x in old]), "after_s": med([x["render_s"] for x in new]),
            "ratio_cpu": med([n["render_cpu_s"] / o["render_cpu_s"] for o, n in zip(old, new)]),
        })
    return {"rev": base["rev"], "rows": rows}


def section_rays(args, bins, data):
    w = HERE / ".work"
    rays = ["--rays", f"camera={w / 'camera.rays'}", "--rays", f"incoherent={w / 'incoherent.rays'}"]
    rounds = []
    for k in range(args.rounds):
        def python_rays(system):
            return json.loads(run([VENV_PY, HERE / "rays.py", "--system", system, "--tris", w / "bunny.tris",
                                   *rays, "--repeat", 3]).stdout)
        # Alternate which system goes first.
        systems = ["embree", "penumbra"] if k % 2 == 0 else ["penumbra", "embree"]
        py = {s: python_rays(s) for s in systems}
        def raybench(b):
            cmd = [b["raybench"], "--tris", w / "bunny.tris", *rays, "--repeat", 3]
            if args.obvhs:
                cmd.append("--obvhs")
            return json.loads(run(cmd).stdout)
        p, pb = both(bins, data["base"], k, raybench)
        rounds.append((py["embree"], p, py["penumbra"], pb))
    e1 = json.loads(run([VENV_PY, HERE / "rays.py", "--system", "embree", "--tris", w / "bunny.tris", "--one-cpu",
                         "--repeat", 5]).stdout)
    out = {"rows": [], "build": {}, "tree": rounds[-1][1]["penumbra"]["tree"]}
    for set_name in ("camera", "incoherent"):
        for kind in ("closest", "any"):
            def rates(get):
                return [get(r)["rays"][set_name][kind]["mrays_per_s"] for r in rounds]
            er = rates(lambda r: r[0])
            pr = rates(lambda r: r[2])
            nb = rates(lambda r: r[1]["penumbra"])
            ns = [r[1]["penumbra"]["single"][set_name][kind]["mrays_per_s"] for r in rounds]
            row = {
                "set": set_name, "kind": kind,
                "rays": rounds[0][0]["rays"][set_name]["rays"],
                "embree": med(er), "penumbra": med(pr),
                "ratio": med([p / e for p, e in zip(pr, er)]),
                "native_batch": med(nb),
                "single": med(ns), "ratio_single": med([p / e for p, e in zip(ns, er)]),
                "hits_embree": rounds[0][0]["rays"][set_name][kind]["hits"],
                "hits_penumbra": rounds[0][2]["rays"][set_name][kind]["hits"],
                "hits_single": rounds[0][1]["penumbra"]["single"][set_name][kind]["hits"],
            }
            if args.obvhs:
                orr = [r[1]["obvhs"]["rays"][set_name][kind]["mrays_per_s"] for r in rounds]
                row["obvhs"] = med(orr)
            out["rows"].append(row)
    out["build"] = {
        "embree_ms_all": med([r[0]["build_ms"] for r in rounds]),
        "embree_ms_1": e1["build_ms"],
        "penumbra_ms_all": med([r[1]["penumbra"]["build"]["ms_all_threads"] for r in rounds]),
        "penumbra_ms_1": med([r[1]["penumbra"]["build"]["ms_1_thread"] for r in rounds]),
        "python_ms_all": med([r[2]["build_ms"] for r in rounds]),
    }
    if args.obvhs:
        out["build"]["obvhs_ms_all"] = med([r[1]["obvhs"]["build"]["ms_all_threads"] for r in rounds])
        out["build"]["obvhs_ms_1"] = med([r[1]["obvhs"]["build"]["ms_1_thread"] for r in rounds])
    if data["base"] is not None:
        def pick(get, r):
            try:
                return get(r)
            except (KeyError, TypeError):
                return None
        def vs(what, get, higher):
            return versus(what, [pick(get, r[1]) for r in rounds], [pick(get, r[3]) for r in rounds], higher)
        rows = []
        for set_name in ("camera", "incoherent"):
            for kind in ("closest", "any"):
                rows.append(vs(f"raybench {set_name} rays, {kind} hit, batch, Mrays/s",
                               lambda r: r["penumbra"]["rays"][set_name][kind]["mrays_per_s"], True))
                rows.append(vs(f"raybench {set_name} rays, {kind} hit, one ray per call, Mrays/s",
                               lambda r: r["penumbra"]["single"][set_name][kind]["mrays_per_s"], True))
        rows.append(vs("BVH build, bunny, ms, all threads", lambda r: r["penumbra"]["build"]["ms_all_threads"], False))
        rows.append(vs("BVH build, bunny, ms, 1 thread", lambda r: r["penumbra"]["build"]["ms_1_thread"], False))
        out["vs"] = rows
    return out


def section_a(args, bins, data):
    bunny = data["bunny"]
    llvm = llvm_library()
    env = dict(os.environ)
    if llvm:
        env["DRJIT_LIBLLVM_PATH"] = llvm
    rounds, base = [], []
    for k in range(args.rounds):
        def penumbra(b):
            two = scenebench(b, bunny, "bunny", "--spp", "16", "--distribution", "jitter", repeat=2)
            # One thread right after: a frame of seconds, so that the parallel
            # efficiency does not rest on the Whitted frame's 0.1 s alone.
            one = scenebench(b, bunny, "bunny", "--spp", "16", "--distribution", "jitter", "--threads", "1",
                             repeat=2)
            return two, one
        (p, p1), pb = both(bins, data["base"], k, penumbra)
        base.append(pb)
        s = json.loads(run([VENV_PY, HERE / "mitsuba_bunny.py", "scalar_rgb", bunny, "--repeat", 1]).stdout)
        lp = run([VENV_PY, HERE / "mitsuba_bunny.py", "llvm_ad_rgb", bunny, "--repeat", 2], env=env, check=False)
        l = json.loads(lp.stdout) if lp.returncode == 0 else {"error": (lp.stderr.strip().splitlines() or ["?"])[-1]}
        rounds.append((p, s, l, p1))
    # Same scene, same estimator: the image means agree (see docs).
    exr = HERE / ".work" / "a_penumbra.exr"
    run([bins["penumbra"], "render", "bunny", "--bunny", bunny, "--spp", "16", "--distribution", "jitter",
         "-o", exr, "--quiet"], cwd=ROOT)
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")
    pen_mean = [float(x) for x in np.array(mi.Bitmap(str(exr))).reshape(-1, 3).mean(axis=0)]
    r = {
        "penumbra_s": med([x[0]["render_s"] for x in rounds]),
        "penumbra_cpu_s": med([x[0]["render_cpu_s"] for x in rounds]),
        "penumbra_1_thread_s": med([x[3]["render_s"] for x in rounds]),
        "efficiency": med([x[3]["render_s"] / (2 * x[0]["render_s"]) for x in rounds]),
        "penumbra_rays": rounds[0][0]["rays"],
        "penumbra_shadow_rays": rounds[0][0]["shadow_rays"],
        "scalar_s": med([x[1]["render_s"] for x in rounds]),
        "scalar_cpu_s": med([x[1]["render_cpu_s"] for x in rounds]),
        "ratio_scalar": med([x[0]["render_s"] / x[1]["render_s"] for x in rounds]),
        "ratio_scalar_cpu": med([x[0]["render_cpu_s"] / x[1]["render_cpu_s"] for x in rounds]),
        "mean_penumbra": pen_mean,
        "mean_mitsuba": rounds[0][1]["mean_rgb"],
        "llvm_library": llvm,
        "mitsuba_version": rounds[0][1]["version"],
    }
    if all("render_s" in x[2] for x in rounds):
        r.update({
            "llvm_s": med([x[2]["render_s"] for x in rounds]),
            "llvm_cpu_s": med([x[2]["render_cpu_s"] for x in rounds]),
            "llvm_first_s": med([x[2]["first_render_s"] for x in rounds]),
            "ratio_llvm": med([x[0]["render_s"] / x[2]["render_s"] for x in rounds]),
            "ratio_llvm_cpu": med([x[0]["render_cpu_s"] / x[2]["render_cpu_s"] for x in rounds]),
        })
    else:
        r["llvm_error"] = next(x[2]["error"] for x in rounds if "error" in x[2])
    if data["base"] is not None:
        r["vs"] = [
            versus("scene (a), 2 threads, s (wall)", [x[0]["render_s"] for x in rounds],
                   [x[0]["render_s"] for x in base]),
            versus("scene (a), 2 threads, s (CPU)", [x[0]["render_cpu_s"] for x in rounds],
                   [x[0]["render_cpu_s"] for x in base]),
            versus("scene (a), 1 thread, s (wall)", [x[3]["render_s"] for x in rounds],
                   [x[1]["render_s"] for x in base]),
        ]
    return r


POV_TIME = re.compile(r"Trace Time:.*\(([\d.]+) seconds\)\s*\n\s*using (\d+) thread\(s\) with ([\d.]+) CPU-seconds")


def povray(pov):
    p = run(["povray", f"-I{pov.name}", "+W800", "+H600", "-A", "-D", "+WT2", "+FN", "-O/dev/null"],
            cwd=pov.parent, check=False)
    text = p.stderr + p.stdout
    m = POV_TIME.search(text)
    rays = int(re.search(r"^Rays:\s+(\d+)", text, re.M).group(1))
    shadow = int(re.search(r"Shadow Ray Tests:\s+(\d+)", text).group(1))
    if not m:
        raise SystemExit("cannot read POV-Ray's statistics:\n" + text[-2000:])
    return {"trace_s": float(m.group(1)), "threads": int(m.group(2)), "cpu_s": float(m.group(3)),
            "rays": rays, "shadow_rays": shadow, "total_rays": rays + shadow}


def section_b(args, bins, data):
    pov = HERE / ".work" / "bunny.pov"
    rounds = []
    for k in range(args.rounds):
        pv = povray(pov)
        pn, pb = both(bins, data["base"], k, lambda b: scenebench(b, data["bunny"], "bunny", "--shadow-rays", "64",
                                                                  "--distribution", "grid", repeat=2))
        rounds.append((pv, pn, pb))
    rate = lambda rays, s: rays / s / 1e6
    pv_rate = [rate(x[0]["total_rays"], x[0]["trace_s"]) for x in rounds]
    pn_rate = [rate(x[1]["rays"], x[1]["render_s"]) for x in rounds]
    pv_cpu = [rate(x[0]["total_rays"], x[0]["cpu_s"]) for x in rounds]
    pn_cpu = [rate(x[1]["rays"], x[1]["render_cpu_s"]) for x in rounds]
    v = run(["povray", "--version"], check=False)
    vs = {}
    if data["base"] is not None:
        vs["vs"] = [
            versus("scene (b), Mrays/s (wall)", pn_rate, [rate(x[2]["rays"], x[2]["render_s"]) for x in rounds], True),
            versus("scene (b), Mrays per CPU-second", pn_cpu,
                   [rate(x[2]["rays"], x[2]["render_cpu_s"]) for x in rounds], True),
        ]
    return vs | {
        "povray_version": (v.stdout + v.stderr).strip().splitlines()[0] if (v.stdout + v.stderr).strip() else "?",
        "povray_s": med([x[0]["trace_s"] for x in rounds]),
        "povray_rays": rounds[0][0]["total_rays"], "povray_shadow": rounds[0][0]["shadow_rays"],
        "penumbra_s": med([x[1]["render_s"] for x in rounds]),
        "penumbra_rays": rounds[0][1]["rays"], "penumbra_shadow": rounds[0][1]["shadow_rays"],
        "povray_mrays": med(pv_rate), "penumbra_mrays": med(pn_rate),
        "ratio": med([a / b for a, b in zip(pn_rate, pv_rate)]),
        "povray_mrays_cpu": med(pv_cpu), "penumbra_mrays_cpu": med(pn_cpu),
        "ratio_cpu": med([a / b for a, b in zip(pn_cpu, pv_cpu)]),
    }


def render_cli(bins, bunny, scene, *extra):
    """One `penumbra render` with --stats: the render call's wall time (from
    the stats, as scenebench times it), the process's CPU time (children's
    rusage: loading the bunny, the build and writing the image included,
    about 0.2 s of CPU), and the rays traced and saved by the metrics."""
    w = HERE / ".work"
    stats = w / "frame.json"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run([bins["penumbra"], "render", scene, "--bunny", bunny, *extra, "-o", w / "frame.png", "--quiet",
         "--stats", stats], cwd=ROOT)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    s = json.loads(stats.read_text())
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"render_s": s["time"]["render_s"], "render_cpu_s": cpu, "rays": s["rays"]["total"],
            "saved": s["saved"]["total"]}


# The scene rows timed on two threads and on one, side by side with the
# baseline: name -> (the row's label in the tables, whether its wall figure
# is in frames per second, how one frame is timed on T threads). The Whitted
# frame (about 0.1 s) is the median of 9 renders in one scenebench process;
# the thesis's hardest case (Fig. 4.8 right: the mirror bunny on the mirror
# floor, 4 camera rays, 32 reflection and 32 shadow rays, the acceleration
# metrics on; about 145 s of CPU, 75-80 s on two free cores) is one
# `penumbra render`, since scenebench has no options for reflection rays or
# the metrics.
WHITTED = HERE / "scenes" / "bunny-whitted.toml"
MIRROR = ["--width", "800", "--height", "600", "--spp", "4", "--reflection-rays", "32", "--shadow-rays", "32",
          "--metric"]
FRAMES = {
    "whitted": ("Whitted bunny", True,
                lambda b, bunny, t: scenebench(b, bunny, WHITTED, "--threads", t, repeat=9)),
    "mirror": ("bunny-mirror, 4 spp, 32 reflection + 32 shadow rays, metrics on", False,
               lambda b, bunny, t: render_cli(b, bunny, "bunny-mirror", *MIRROR, "--threads", t)),
}


def section_frames(name, args, bins, data):
    """A scene row of FRAMES: in each round, one frame on 2 threads then one
    on 1 thread, for this tree and the baseline (order alternating)."""
    label, per_second, frame = FRAMES[name]
    rounds, base = [], []
    for k in range(args.rounds):
        def frames(b):
            two = frame(b, data["bunny"], 2)
            one = frame(b, data["bunny"], 1)
            return one, two
        cur, old = both(bins, data["base"], k, frames)
        rounds.append(cur)
        base.append(old)
    vs = {}
    if data["base"] is not None:
        wall = versus(f"{label}, 2 threads, frames/s (wall)", [1 / x[1]["render_s"] for x in rounds],
                      [1 / x[1]["render_s"] for x in base], True) if per_second else \
            versus(f"{label}, 2 threads, s (wall)", [x[1]["render_s"] for x in rounds],
                   [x[1]["render_s"] for x in base])
        vs["vs"] = [
            wall,
            versus(f"{label}, 2 threads, s (CPU)", [x[1]["render_cpu_s"] for x in rounds],
                   [x[1]["render_cpu_s"] for x in base]),
            versus(f"{label}, 1 thread, s (wall)", [x[0]["render_s"] for x in rounds],
                   [x[0]["render_s"] for x in base]),
        ]
    return vs | {
        "rays": rounds[0][1]["rays"],
        "saved": rounds[0][1].get("saved"),
        "s_2": med([x[1]["render_s"] for x in rounds]),
        "s_1": med([x[0]["render_s"] for x in rounds]),
        "cpu_2": med([x[1]["render_cpu_s"] for x in rounds]),
        "cpu_1": med([x[0]["render_cpu_s"] for x in rounds]),
        "fps_2": med([1 / x[1]["render_s"] for x in rounds]),
        "efficiency": med([x[0]["render_s"] / (2 * x[1]["render_s"]) for x in rounds]),
        # What two dedicated cores would do: the frame's CPU time split over 2.
        "fps_cpu_2": med([2 / x[1]["render_cpu_s"] for x in rounds]),
    }


# The canonical scene (section a's: the bunny, 16 jittered camera rays, one
# shadow ray) rendered progressively: what passes, checkpoints and the
# preview cost against one plain pass, in alternating order.
CANONICAL = ["bunny", "--spp", "16", "--distribution", "jitter", "--threads", "2"]


def section_progressive(args, bins, data):
    """The cost of rendering progressively: 64 passes against one; a
    checkpoint after every pass (16 passes, the interval a sixteenth of the
    plain render) against 16 passes without; the preview (16 passes, no
    viewer) against 16 passes without. CPU seconds of the whole process,
    medians of the rounds, each round running the variants in turn (the
    order rotating)."""
    w = HERE / ".work"
    plain = render_cli(bins, data["bunny"], *CANONICAL)["render_s"]
    variants = {
        "1 pass": [],
        "64 passes": ["--passes", "64"],
        "16 passes": ["--passes", "16"],
        "16 passes, a checkpoint per pass": ["--passes", "16", "--checkpoint", w / "p.ckpt",
                                             "--checkpoint-interval", f"{plain / 16:.4f}"],
        "16 passes, preview": ["--passes", "16", "--preview"],
    }
    names = list(variants)
    got = {n: [] for n in names}
    for k in range(args.rounds):
        for n in names[k % len(names):] + names[:k % len(names)]:
            got[n].append(render_cli(bins, data["bunny"], *CANONICAL, *variants[n])["render_cpu_s"])
    cpu = {n: med(v) for n, v in got.items()}
    return {
        "cpu_s": cpu,
        "passes_64_over_1": cpu["64 passes"] / cpu["1 pass"],
        "checkpoint_per_pass_over_none": cpu["16 passes, a checkpoint per pass"] / cpu["16 passes"],
        "preview_over_none": cpu["16 passes, preview"] / cpu["16 passes"],
    }


# What each kernel set (`--simd`) costs on the canonical scene, the Whitted
# frame and a small hardest case (the mirror bunny at 400×300, 16
# reflection and 16 shadow rays, the metrics on), 2 threads.
KERNEL_SCENES = {
    "scene (a)": CANONICAL,
    "Whitted frame": [str(ROOT / "bench" / "scenes" / "bunny-whitted.toml"), "--threads", "2"],
    "hardest case, 400×300": ["bunny-mirror", "--width", "400", "--height", "300", "--spp", "4",
                              "--shadow-rays", "16", "--reflection-rays", "16", "--metric", "--threads", "2"],
}


def section_kernels(args, bins, data):
    """CPU seconds of the whole process for each kernel set this machine
    supports (the sets `penumbra --version` lists), medians of the rounds,
    the sets in turn (the order rotating), and each set against portable;
    the images must be the same file."""
    v = run([bins["penumbra"], "--version"]).stdout
    sets = v.split("supported: ")[1].strip().rstrip(")").split(", ")
    out = {"sets": sets, "cpu_s": {}, "over_portable": {}}
    for label, scene in KERNEL_SCENES.items():
        got = {k: [] for k in sets}
        files = {}
        for r in range(args.rounds):
            for k in sets[r % len(sets):] + sets[:r % len(sets)]:
                got[k].append(render_cli(bins, data["bunny"], *scene, "--simd", k)["render_cpu_s"])
                files[k] = (HERE / ".work" / "frame.png").read_bytes()
        if len(set(files.values())) != 1:
            raise SystemExit(f"kernel sets wrote different images for {label}")
        cpu = {k: med(x) for k, x in got.items()}
        out["cpu_s"][label] = cpu
        out["over_portable"][label] = {k: cpu[k] / cpu["portable"] for k in sets}
    return out


def section_whitted(args, bins, data):
    return section_frames("whitted", args, bins, data)


def section_mirror(args, bins, data):
    return section_frames("mirror", args, bins, data)


def section_points(args, bins, data):
    """The CPU cost of one point of each low-discrepancy distribution (sets
    of 256) and of a set of one, medians of pointbench's rounds (built with
    the other binaries of penumbra-bench; no baseline column: the tool is
    newer than most revisions)."""
    import common

    tool = common.target_dir() / "release" / "pointbench"
    p = run([tool, "--rounds", max(args.rounds, 3)], cwd=ROOT)
    return json.loads(p.stdout)


def section_instances(args, bins, data):
    """10,000 instances of the bunny against one (instancebench, built with
    the other binaries of penumbra-bench): medians over the rounds."""
    import common

    tool = common.target_dir() / "release" / "instancebench"
    runs = [json.loads(run([tool, "--bunny", data["bunny"]], cwd=ROOT).stdout) for _ in range(max(args.rounds, 1))]
    pick = {"load_build_s": lambda r: r["all_instances"]["load_and_build_s"],
            "build_s": lambda r: r["all_instances"]["build_s"],
            "extra_live_mb": lambda r: r["extra_live_mb"],
            "extra_peak_mb": lambda r: r["extra_peak_mb"],
            "mrays": lambda r: r["closest_hit_mrays_per_s_1_thread"]}
    return {k: med([get(r) for r in runs]) for k, get in pick.items()} | {"instances": runs[0]["instances"]}


def section_scaling(args, bins, data):
    """Parallel efficiency as the median of many adjacent pairs: on a shared
    machine one pair swings by a quarter either way, and a pair of frames
    seconds apart shares the machine's state better than rounds minutes
    apart. The order within a pair alternates. Scene (a) at 400x300 (a
    third of a second or so on one thread) and the Whitted frame (about
    0.1 s, so each side is the median of three renders)."""
    scenes = {
        "a": (("bunny", "--spp", "16", "--distribution", "jitter", "--width", "400", "--height", "300"), 1),
        "whitted": ((HERE / "scenes" / "bunny-whitted.toml",), 3),
    }
    out, vs = {}, []
    for name, (extra, repeat) in scenes.items():
        ratios, base = [], []
        for k in range(args.pairs):
            order = (1, 2) if k % 2 == 0 else (2, 1)
            def pair(b):
                t = {n: scenebench(b, data["bunny"], *extra, "--threads", str(n), repeat=repeat)["render_s"]
                     for n in order}
                return t[1] / (2 * t[2])
            cur, old = both(bins, data["base"], k // 2, pair)
            ratios.append(cur)
            base.append(old)
        q = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else [ratios[0]] * 3
        out[name] = {"pairs": len(ratios), "efficiency": med(ratios), "q1": q[0], "q3": q[2],
                     "min": min(ratios), "max": max(ratios)}
        if data["base"] is not None:
            what = {"a": "scene (a) at 400×300", "whitted": "Whitted frame"}[name]
            vs.append(versus(f"parallel efficiency, 2 threads, {what}, pairs", ratios, base, True))
    if vs:
        out["vs"] = vs
    return out


def section_linear(args, bins, data):
    """One run of each row; with --baseline, --rounds runs of each row for
    both builds, alternating, and the medians."""
    scene = HERE / "scenes" / "bunny-whitted.toml"
    cases = [(f"Whitted {w}x{h}", w * h, [scene, "--width", w, "--height", h])
             for w, h in ((400, 300), (800, 600), (1600, 1200))]
    cases += [(f"bunny, {spp} primary rays/pixel", 480000, ["bunny", "--spp", spp, "--distribution", "jitter"])
              for spp in (1, 4, 16)]
    cases += [(f"bunny, {n} shadow rays", 480000, ["bunny", "--shadow-rays", n, "--distribution", "grid"])
              for n in (1, 4, 16, 64)]
    rows, vs = [], []
    for what, pixels, argv in cases:
        runs = [both(bins, data["base"], k, lambda b: scenebench(b, data["bunny"], *argv, "--threads", "1", repeat=3))
                for k in range(args.rounds if data["base"] is not None else 1)]
        cur = [c for c, _ in runs]
        rows.append({"what": what, "pixels": pixels, "rays": cur[0]["rays"],
                     "s": med([x["render_s"] for x in cur]), "cpu_s": med([x["render_cpu_s"] for x in cur])})
        if data["base"] is not None:
            vs.append(versus(f"linearity: {what}, 1 thread, s (CPU)", [x["render_cpu_s"] for x in cur],
                             [b["render_cpu_s"] for _, b in runs]))
    return {"rows": rows} | ({"vs": vs} if vs else {})


def max_rss(cmd, cwd, codes=(0,)):
    """The maximum resident set size of a command, MB (MiB), and its run;
    an exit status outside `codes` stops the harness."""
    p = run(["/usr/bin/time", "-v", *cmd], cwd=cwd, check=False)
    if p.returncode not in codes:
        sys.stderr.write(p.stdout + p.stderr)
        raise SystemExit(f"command failed ({p.returncode}): {cmd[0]}")
    kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1))
    return kb / 1024, p


# Instances of the bunny in the memory section's Mitsuba XML scene.
MEMORY_INSTANCES = 10_000


def instances_xml(bunny, n):
    """A Mitsuba 3 scene of one shapegroup holding the bunny's PLY and `n`
    instances of it on a square grid of spacing 0.25 (the bunny is about
    0.15 across), each turned, scaled and lifted at random, each with its
    own `to_world`: the scene of instancebench, as XML."""
    import math
    import random

    side = max(1, math.ceil(math.sqrt(n)))
    r = random.Random(1)
    lines = ['<scene version="3.0.0">',
             '    <sensor type="perspective">',
             '        <transform name="to_world"><lookat origin="12, 8, 30" target="12, 0, 12" up="0, 1, 0"/></transform>',
             '    </sensor>',
             '    <shape type="shapegroup" id="bunny">',
             f'        <shape type="ply"><string name="filename" value="{bunny}"/></shape>',
             '    </shape>']
    for i in range(n):
        x, z = (i % side) * 0.25, (i // side) * 0.25
        lines.append(f'    <shape type="instance"><ref id="bunny"/><transform name="to_world">'
                     f'<scale value="{r.uniform(0.6, 1.2):.4f}"/><rotate y="1" angle="{r.uniform(0, 360):.3f}"/>'
                     f'<translate x="{x:g}" y="{r.uniform(0, 0.1):.4f}" z="{z:g}"/></transform></shape>')
    lines += ['    <emitter type="constant"/>', '</scene>']
    return "\n".join(lines) + "\n"


# The largest scene of the hostile corpus (crates/penumbra-cli/tests/hostile.rs,
# "array of 2 million numbers"): 4 MB, refused with status 2 at its line.
HOSTILE_TOML = "[render]\nbackground = [" + "1," * 2_000_000 + "]\n"


def section_memory(args, bins, data):
    """Maximum resident memory of whole `penumbra render` processes: the
    bunny scene at 800x600; reading and building (a 1x1 render at 1 spp)
    10,000 instances of the bunny from Mitsuba XML and the same scene with
    one, and their difference; the largest hostile TOML, which the reader
    refuses. The scenes are written to a temporary folder."""
    import tempfile

    out, vs = {}, []
    stats = HERE / ".work" / "memory.json"
    for name, extra in (("bunny", []), ("bunny, 64 shadow rays", ["--shadow-rays", "64"])):
        def rss(b):
            mb, _ = max_rss([b["penumbra"], "render", "bunny", "--bunny", data["bunny"], *extra,
                             "-o", HERE / ".work" / "memory.png", "--quiet", "--stats", stats], ROOT)
            return mb
        out[name], base = both(bins, data["base"], 0, rss)
        if base is not None:
            vs.append(versus(f"max resident memory, `penumbra render` {name}, MB", [out[name]], [base]))
    tiny = ["--width", "1", "--height", "1", "--spp", "1", "--quiet"]
    with tempfile.TemporaryDirectory(prefix="penumbra-memory-") as tmp:
        tmp = Path(tmp)
        bunny = Path(data["bunny"]).resolve()
        scenes = {"one": tmp / "one.xml", "many": tmp / "many.xml"}
        scenes["one"].write_text(instances_xml(bunny, 1))
        scenes["many"].write_text(instances_xml(bunny, MEMORY_INSTANCES))
        hostile = tmp / "hostile.toml"
        hostile.write_text(HOSTILE_TOML)

        def instances(b):
            mb = {k: max_rss([b["penumbra"], "render", path, "-o", tmp / "out.png", *tiny], tmp)[0]
                  for k, path in scenes.items()}
            return mb | {"beyond": mb["many"] - mb["one"]}

        def refused(b):
            mb, p = max_rss([b["penumbra"], "render", hostile, "-o", tmp / "out.png", *tiny], tmp, codes=(2,))
            if f"{hostile.name}:2:" not in p.stderr:
                raise SystemExit(f"the hostile TOML was not refused at its line: {p.stderr.strip()[:300]}")
            return mb

        inst, inst_base = both(bins, data["base"], 0, instances)
        big, big_base = both(bins, data["base"], 0, refused)
    result = {"rss_mb": out,
              "instances": {"instances": MEMORY_INSTANCES, "one_mb": inst["one"], "many_mb": inst["many"],
                            "beyond_mb": inst["beyond"]},
              "hostile_toml_mb": big}
    if data["base"] is not None:
        vs.append(versus(f"{MEMORY_INSTANCES:,} bunny instances from XML: peak memory beyond one bunny, MB",
                         [inst["beyond"]], [inst_base["beyond"]]))
        vs.append(versus("largest hostile TOML (4 MB): peak memory, MB", [big], [big_base]))
    return result | ({"vs": vs} if vs else {})


def section_million(args, bins, data):
    """One render for the build time and the memory, scenebench for the
    render time; with --baseline, --rounds of both for both builds."""
    w = HERE / ".work"
    stats = w / "million.json"
    def million(b):
        mb, _ = max_rss([b["penumbra"], "render", w / "sphere1m.toml", "-o", w / "million.png",
                         "--quiet", "--stats", stats], ROOT)
        s = json.loads(stats.read_text())
        r = scenebench(b, data["bunny"], w / "sphere1m.toml", repeat=3)
        return {"triangles": s["primitives"], "build_s": s["time"]["build_s"], "render_s": r["render_s"],
                "render_cpu_s": r["render_cpu_s"], "rays": r["rays"], "rss_mb": mb}
    runs = [both(bins, data["base"], k, million) for k in range(args.rounds if data["base"] is not None else 1)]
    cur = [c for c, _ in runs]
    out = {k: med([x[k] for x in cur]) for k in ("build_s", "render_s", "render_cpu_s", "rss_mb")}
    out |= {"triangles": cur[0]["triangles"], "rays": cur[0]["rays"]}
    if data["base"] is not None:
        base = [b for _, b in runs]
        out["vs"] = [versus(f"1,000,000-triangle mesh: {what}", [x[key] for x in cur], [x[key] for x in base])
                     for what, key in (("load + build, s", "build_s"), ("render, s (wall)", "render_s"),
                                       ("render, s (CPU)", "render_cpu_s"), ("memory, MB", "rss_mb"))]
    return out


# sphere1m.toml as a Mitsuba 3 scene: the same camera, ground, mesh file,
# placement and flat facets; its light an emitting rectangle.
SPHERE1M_XML = """<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world"><lookat origin="0, 1.3, 4.2" target="0, 0.8, 0" up="0, 1, 0"/></transform>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><matrix value="0 5 0 0  0 0 1 0  5 0 0 0  0 0 0 1"/></transform>
    </shape>
    <shape type="ply">
        <string name="filename" value="sphere1m.ply"/>
        <boolean name="face_normals" value="true"/>
        <transform name="to_world"><scale value="0.8"/><translate y="0.8"/></transform>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><matrix value="0.5 0 0 0  0 0 -0.5 4  0 0.5 0 0  0 0 0 1"/></transform>
        <emitter type="area"><rgb name="radiance" value="40"/></emitter>
    </shape>
</scene>
"""


def section_xmlread(args, bins, data):
    """Reading and building the million-triangle scene from XML against
    from TOML, each round both in one process each, the one going first
    alternating: the medians and the median of the per-round ratios."""
    w = HERE / ".work"
    (w / "sphere1m.xml").write_text(SPHERE1M_XML)
    scenes = {"toml": w / "sphere1m.toml", "xml": w / "sphere1m.xml"}
    times = {"toml": [], "xml": []}
    for k in range(max(args.rounds, 5)):
        order = ["toml", "xml"] if k % 2 == 0 else ["xml", "toml"]
        for name in order:
            r = scenebench(bins, data["bunny"], scenes[name], "--width", 8, "--height", 8, "--spp", 1,
                           "--threads", 1, repeat=1)
            times[name].append(r["read_and_build_s"])
    ratios = [x / t for x, t in zip(times["xml"], times["toml"])]
    return {"toml_s": med(times["toml"]), "xml_s": med(times["xml"]), "ratio": med(ratios),
            "pairs": len(ratios)}


CORNELL = HERE / "scenes" / "mitsuba" / "cornell.xml"
CORNELL_SET = ["spp=64", "res=256", "max_depth=8"]
CORNELL_REF_SPP = 2048


def defines(pairs):
    return [x for d in pairs for x in ("-D", d)]


def penumbra_xml(b, scene, sets, exr, *extra):
    """One `penumbra render` of a Mitsuba XML scene: the render call's wall
    time (from --stats) and the process's CPU time (loading and writing
    included)."""
    stats = HERE / ".work" / "xml.json"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run([b["penumbra"], "render", scene, *defines(sets), *extra, "-o", exr, "--quiet", "--stats", stats], cwd=ROOT)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    s = json.loads(stats.read_text())
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"render_s": s["time"]["render_s"], "render_cpu_s": cpu, "rays": s["rays"]["total"]}


def mitsuba_xml(variant, scene, sets, exr, repeat, env=None):
    p = run([VENV_PY, HERE / "mitsuba_render.py", variant, scene, *defines(sets), "--repeat", repeat,
             "--exr", exr], env=env, check=False)
    if p.returncode != 0:
        return {"error": (p.stderr.strip().splitlines() or ["?"])[-1]}
    return json.loads(p.stdout)


def section_path(args, bins, data):
    """Penumbra's `path` against Mitsuba 3's on the Cornell box: time at
    equal samples, then relative MSE x time (lower is better) against a
    high-sample reference, each renderer's 64-spp image measured."""
    import mitsuba as mi
    import numpy as np

    w = HERE / ".work"
    llvm = llvm_library()
    env = dict(os.environ)
    if llvm:
        env["DRJIT_LIBLLVM_PATH"] = llvm
    rounds, base = [], []
    exr = {k: w / f"cornell_{k}.exr" for k in ("penumbra", "scalar", "llvm")}
    for k in range(args.rounds):
        p, pb = both(bins, data["base"], k,
                     lambda b: penumbra_xml(b, CORNELL, CORNELL_SET, exr["penumbra"], "--threads", "2"))
        base.append(pb)
        s = mitsuba_xml("scalar_rgb", CORNELL, CORNELL_SET, exr["scalar"], 1)
        l = mitsuba_xml("llvm_ad_rgb", CORNELL, CORNELL_SET, exr["llvm"], 2, env)
        rounds.append((p, s, l))
    ref = w / f"cornell_ref_{CORNELL_REF_SPP}.exr"
    if not ref.exists():
        variant = "llvm_ad_rgb" if "render_s" in rounds[0][2] else "scalar_rgb"
        sets = [f"spp={CORNELL_REF_SPP}"] + CORNELL_SET[1:]
        r = mitsuba_xml(variant, CORNELL, sets, w / "cornell_ref.tmp.exr", 1, env)
        if "error" in r:
            raise SystemExit(f"the Cornell reference: {r['error']}")
        (w / "cornell_ref.tmp.exr").rename(ref)
    mi.set_variant("scalar_rgb")
    read = lambda path: np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3]
    reference = read(ref)
    rel_mse = lambda x: float(((x - reference) ** 2 / (reference ** 2 + 0.01)).mean())
    out = {
        "penumbra_s": med([x[0]["render_s"] for x in rounds]),
        "penumbra_cpu_s": med([x[0]["render_cpu_s"] for x in rounds]),
        "penumbra_rays": rounds[0][0]["rays"],
        "scalar_s": med([x[1]["render_s"] for x in rounds]),
        "ratio_scalar": med([x[0]["render_s"] / x[1]["render_s"] for x in rounds]),
        "mean_penumbra": [float(v) for v in read(exr["penumbra"]).reshape(-1, 3).mean(axis=0)],
        "mean_mitsuba": rounds[0][1]["mean_rgb"],
        "relmse_penumbra": rel_mse(read(exr["penumbra"])),
        "relmse_scalar": rel_mse(read(exr["scalar"])),
        "reference_spp": CORNELL_REF_SPP,
    }
    out["work_ratio_scalar"] = (out["relmse_penumbra"] * out["penumbra_s"]) / (out["relmse_scalar"] * out["scalar_s"])
    if all("render_s" in x[2] for x in rounds):
        out |= {
            "llvm_s": med([x[2]["render_s"] for x in rounds]),
            "llvm_first_s": med([x[2]["first_render_s"] for x in rounds]),
            "ratio_llvm": med([x[0]["render_s"] / x[2]["render_s"] for x in rounds]),
            "relmse_llvm": rel_mse(read(exr["llvm"])),
        }
        out["work_ratio_llvm"] = (out["relmse_penumbra"] * out["penumbra_s"]) / (out["relmse_llvm"] * out["llvm_s"])
    else:
        out["llvm_error"] = next(x[2]["error"] for x in rounds if "error" in x[2])
    if data["base"] is not None:
        out["vs"] = [versus("Cornell box, path, 256×256, 64 spp, 2 threads, s (wall)",
                            [x[0]["render_s"] for x in rounds], [x["render_s"] for x in base])]
    return out


def section_lights(args, bins, data):
    """Many lights: `path` on a floor under 1,000 small area lights
    (lightsbench), with each light sampler at 16 spp on two threads: the
    render time, the relative MSE against a 2048-spp reference and their
    product (lower is better). Timed in one process, samplers in turn, each
    the median of three renders of its frame."""
    p = run([bins["lightsbench"], "--width", "160", "--height", "100", "--spp", "16", "--reference-spp", "2048",
             "--threads", "2", "--repeat", "3", "--write-scene", HERE / ".work" / "lights.toml"], cwd=ROOT)
    return json.loads(p.stdout)


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

def machine():
    cpu = "?"
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    rustc = run(["rustc", "--version"], check=False).stdout.strip()
    osr = {}
    if Path("/etc/os-release").exists():
        for l in Path("/etc/os-release").read_text().splitlines():
            if "=" in l:
                k, v = l.split("=", 1)
                osr[k] = v.strip('"')
    return {"cpu": cpu, "cores": os.cpu_count(), "load": os.getloadavg(), "rustc": rustc,
            "os": osr.get("PRETTY_NAME", platform.platform()), "kernel": platform.release(),
            "python": platform.python_version()}


def f(x, d=2):
    return "—" if x is None else f"{x:.{d}f}"


def report(res):
    m = res["machine"]
    L = []
    L.append(f"Measured {res['date']} on: {m['cpu']}, {m['cores']} cores, {m['os']} (kernel {m['kernel']}); "
             f"load average {m['load_start'][0]:.1f} at the start, {m['load'][0]:.1f} at the end. "
             f"{m['rustc']}; Python {m['python']}; " + ", ".join(f"{k} {v}" for k, v in res["versions"].items())
             + f". {res['rounds']} rounds.")
    L.append("")
    L.append("| comparison | reference | Penumbra | ratio (Penumbra / reference) | target | met |")
    L.append("|---|---|---|---|---|---|")
    def row(name, ref, pen, ratio, target, met):
        L.append(f"| {name} | {ref} | {pen} | {ratio} | {target} | {'yes' if met else '**no**'} |")
    if "rays" in res:
        r = res["rays"]
        for x in r["rows"]:
            tgt = x["set"] == "incoherent"
            row(f"{x['set']} rays ({x['rays']:,}), {x['kind']} hit, 1 thread, Mrays/s (batch call from Python)",
                f"Embree {f(x['embree'])}", f(x["penumbra"]), f"{f(x['ratio'])}×",
                "≥ 1×" if tgt else "—", (x["ratio"] >= 1) if tgt else True)
        for x in r["rows"]:
            if x["set"] == "incoherent":
                row(f"incoherent rays, {x['kind']} hit, Penumbra one ray per call (raybench), Mrays/s",
                    f"Embree {f(x['embree'])}", f(x["single"]), f"{f(x['ratio_single'])}×", "—", True)
        b = r["build"]
        row("BVH build, bunny (69,451 triangles), ms, all threads", f"Embree {f(b['embree_ms_all'], 1)}",
            f(b["penumbra_ms_all"], 1), f"{f(b['penumbra_ms_all'] / b['embree_ms_all'])}×", "≤ 2×",
            b["penumbra_ms_all"] <= 2 * b["embree_ms_all"])
        row("BVH build, bunny, ms, 1 thread", f"Embree {f(b['embree_ms_1'], 1)}", f(b["penumbra_ms_1"], 1),
            f"{f(b['penumbra_ms_1'] / b['embree_ms_1'])}×", "≤ 2×", b["penumbra_ms_1"] <= 2 * b["embree_ms_1"])
    if "a" in res:
        a = res["a"]
        row("scene (a): 800×600, 16 primary + 1 shadow ray, s (wall)", f"Mitsuba scalar_rgb {f(a['scalar_s'])}",
            f(a["penumbra_s"]), f"{f(a['ratio_scalar'])}×", "≤ 0.5×", a["ratio_scalar"] <= 0.5)
        row("scene (a), s (CPU time, all threads)", f"Mitsuba scalar_rgb {f(a['scalar_cpu_s'])}",
            f(a["penumbra_cpu_s"]), f"{f(a['ratio_scalar_cpu'])}×", "≤ 0.5×", a["ratio_scalar_cpu"] <= 0.5)
        if "llvm_s" in a:
            row("scene (a), s (wall)", f"Mitsuba llvm_ad_rgb {f(a['llvm_s'])}", f(a["penumbra_s"]),
                f"{f(a['ratio_llvm'])}×", "≤ 1×", a["ratio_llvm"] <= 1)
            row("scene (a), s (CPU time)", f"Mitsuba llvm_ad_rgb {f(a['llvm_cpu_s'])}", f(a["penumbra_cpu_s"]),
                f"{f(a['ratio_llvm_cpu'])}×", "≤ 1×", a["ratio_llvm_cpu"] <= 1)
        else:
            row("scene (a)", f"Mitsuba llvm_ad_rgb: {a['llvm_error']}", "—", "—", "≤ 1×", False)
    if "b" in res:
        b = res["b"]
        row("scene (b): 800×600, 1 primary + 64 shadow rays, Mrays/s (wall)", f"POV-Ray {f(b['povray_mrays'])}",
            f(b["penumbra_mrays"]), f"{f(b['ratio'])}×", "≥ 5×", b["ratio"] >= 5)
        row("scene (b), Mrays per CPU-second", f"POV-Ray {f(b['povray_mrays_cpu'])}", f(b["penumbra_mrays_cpu"]),
            f"{f(b['ratio_cpu'])}×", "≥ 5×", b["ratio_cpu"] >= 5)
    if "whitted" in res:
        w = res["whitted"]
        row("Whitted bunny 800×600, frames/s, 2 threads (wall)", "—", f(w["fps_2"]), "—", "≥ 10", w["fps_2"] >= 10)
        row("Whitted bunny, frames/s from CPU time / 2 cores", "—", f(w["fps_cpu_2"]), "—", "≥ 10",
            w["fps_cpu_2"] >= 10)
        row("parallel efficiency, 2 threads, Whitted frame (wall: t1 / 2 t2)", "—", f"{100 * w['efficiency']:.0f}%",
            "—", "≥ 90%", w["efficiency"] >= 0.9)
    if "mirror" in res:
        w = res["mirror"]
        row("bunny-mirror 800×600, 4 spp, 32 reflection + 32 shadow rays, metrics on (thesis Fig. 4.8 right), "
            "s, 2 threads (wall)", "—", f(w["s_2"]), "—", "—", True)
        row("bunny-mirror, s (CPU time, 2 threads)", "—", f(w["cpu_2"]), "—", "—", True)
        row("parallel efficiency, 2 threads, bunny-mirror (wall: t1 / 2 t2)", "—", f"{100 * w['efficiency']:.0f}%",
            "—", "≥ 90%", w["efficiency"] >= 0.9)
    if "points" in res:
        for name, x in res["points"]["distributions"].items():
            row(f"drawing a point of `{name}` (sets of {res['points']['set']}), ns (CPU)", "—", f(x["point_ns"], 1),
                "—", "≤ 20", x["point_ns"] <= 20)
            row(f"a set of one point of `{name}`, stream derivation included, ns (CPU)", "—", f(x["one_ns"], 1),
                "—", "—", True)
    if "path" in res:
        c = res["path"]
        row("Cornell box, `path`, 256×256, 64 spp, max_depth 8, 2 threads, s (wall)",
            f"Mitsuba scalar_rgb {f(c['scalar_s'])}", f(c["penumbra_s"]), f"{f(c['ratio_scalar'])}×", "≤ 0.5×",
            c["ratio_scalar"] <= 0.5)
        if "llvm_s" in c:
            row("Cornell box, `path`, s (wall)", f"Mitsuba llvm_ad_rgb {f(c['llvm_s'])}", f(c["penumbra_s"]),
                f"{f(c['ratio_llvm'])}×", "as measured", True)
        row("Cornell box, relative MSE × s at 64 spp (lower is better)",
            f"Mitsuba scalar_rgb {c['relmse_scalar'] * c['scalar_s']:.3g}",
            f"{c['relmse_penumbra'] * c['penumbra_s']:.3g}", f"{f(c['work_ratio_scalar'])}×", "≤ 1×",
            c["work_ratio_scalar"] <= 1)
        if "llvm_s" in c:
            row("Cornell box, relative MSE × s at 64 spp", f"Mitsuba llvm_ad_rgb {c['relmse_llvm'] * c['llvm_s']:.3g}",
                f"{c['relmse_penumbra'] * c['penumbra_s']:.3g}", f"{f(c['work_ratio_llvm'])}×", "as measured", True)
    if "a" in res and "efficiency" in res["a"]:
        e = res["a"]["efficiency"]
        row("parallel efficiency, 2 threads, scene (a) (wall: t1 / 2 t2)", "—", f"{100 * e:.0f}%", "—", "≥ 90%",
            e >= 0.9)
    if "scaling" in res:
        for key, what in (("a", "scene (a) at 400×300"), ("whitted", "Whitted frame")):
            sc = res["scaling"][key]
            row(f"parallel efficiency, 2 threads, {what}, median of {sc['pairs']} adjacent pairs "
                f"(quartiles {100 * sc['q1']:.0f}–{100 * sc['q3']:.0f}%)", "—", f"{100 * sc['efficiency']:.0f}%",
                "—", "≥ 90%", sc["efficiency"] >= 0.9)
    if "memory" in res:
        m = res["memory"]
        for k, v in m["rss_mb"].items():
            row(f"max resident memory, `penumbra render` {k}, MB", "—", f(v, 0), "—", "< 100", v < 100)
        x = m["instances"]
        row(f"{x['instances']:,} bunny instances from Mitsuba XML, read and built: peak memory beyond one bunny "
            f"({f(x['many_mb'], 0)} against {f(x['one_mb'], 0)}), MB", "—", f(x["beyond_mb"], 1), "—", "< 50",
            x["beyond_mb"] < 50)
        row("largest hostile TOML (a 4 MB array of 2 million numbers, refused): peak memory, MB", "—",
            f(m["hostile_toml_mb"], 0), "—", "< 400", m["hostile_toml_mb"] < 400)
    if "instances" in res:
        x = res["instances"]
        row(f"{x['instances']:,} bunny instances: read + build, s (wall)", "—", f(x["load_build_s"]), "—", "< 2",
            x["load_build_s"] < 2)
        row(f"{x['instances']:,} bunny instances: memory held beyond one instance, MB", "—", f(x["extra_live_mb"], 1),
            "—", "< 50", x["extra_live_mb"] < 50)
        row(f"{x['instances']:,} bunny instances: peak memory while reading and building, beyond one instance's, MB",
            "—", f(x["extra_peak_mb"], 1), "—", "< 50", x["extra_peak_mb"] < 50)
        row(f"{x['instances']:,} bunny instances: closest hits into the field, Mrays/s, 1 thread (CPU)", "—",
            f(x["mrays"]), "—", "—", True)
    if "xmlread" in res:
        x = res["xmlread"]
        row(f"1,000,000-triangle scene read + built from Mitsuba XML against from TOML, s ({x['pairs']} pairs)",
            f"TOML {f(x['toml_s'])}", f(x["xml_s"]), f"{f(x['ratio'], 3)}×", "≤ 1.10×", x["ratio"] <= 1.10)
    if "lights" in res:
        g = res["lights"]
        L.append("")
        L.append(f"| many lights: path, {g['lights']:,} area lights, {g['width']}×{g['height']}, {g['spp']} spp, "
                 f"2 threads | s (wall) | relative MSE (against {g['reference_spp']} spp) | relMSE × s | "
                 "relMSE × s / uniform's |")
        L.append("|---|---|---|---|---|")
        for x in g["samplers"]:
            L.append(f"| `{x['sampler']}` | {f(x['render_s'], 3)} | {x['relmse']:.3g} | {x['relmse_x_s']:.3g} | "
                     f"{f(x['work_vs_uniform'], 3)} |")
    if "kernels" in res:
        kr = res["kernels"]
        L.append("")
        L.append("| kernel set (CPU s, whole process, 2 threads) | " + " | ".join(kr["sets"]) + " |")
        L.append("|---|" + "---|" * len(kr["sets"]))
        for label, cpu in kr["cpu_s"].items():
            ratio = kr["over_portable"][label]
            L.append(f"| {label} | " + " | ".join(f"{f(cpu[k], 3)} ({f(ratio[k], 3)}×)" for k in kr["sets"]) + " |")
    if "million" in res:
        mm = res["million"]
        row(f"1,000,000-triangle mesh: load + build s / render s / memory MB", "—",
            f"{f(mm['build_s'])} / {f(mm['render_s'])} / {f(mm['rss_mb'], 0)}", "—", "no surprises", True)
    L.append("")
    if "rays" in res:
        r = res["rays"]
        L.append(f"Hits (Embree / Penumbra batch / Penumbra one per call): " + "; ".join(
            f"{x['set']} {x['kind']} {x['hits_embree']:,} / {x['hits_penumbra']:,} / {x['hits_single']:,}"
            for x in r["rows"]) + ".")
        L.append("Penumbra's batch call without Python (raybench: `closest_hit_each` / `occluded_each` on the same "
                 "arrays), Mrays/s: " + "; ".join(f"{x['set']} {x['kind']} {f(x['native_batch'])}" for x in r["rows"])
                 + f". `TriangleMesh` from Python builds in {f(r['build']['python_ms_all'], 1)} ms (all threads, "
                 "the copy of the array included).")
        t = r["tree"]
        L.append(f"Penumbra's tree: {t['nodes']:,} four-wide nodes, {t['leaves']:,} leaves, {t['packs']:,} packets "
                 f"({100 * t['lane_fill']:.0f}% of lanes used), {t['bytes'] / 2**20:.1f} MiB.")
        if "obvhs" in r["rows"][0]:
            L.append("obvhs 0.4 CWBVH (medium build, its own triangle test), Mrays/s: " + "; ".join(
                f"{x['set']} {x['kind']} {f(x['obvhs'])}" for x in r["rows"]) +
                f"; build {f(r['build']['obvhs_ms_all'], 1)} ms all threads, {f(r['build']['obvhs_ms_1'], 1)} ms 1 thread.")
    if "a" in res:
        a = res["a"]
        L.append(f"Scene (a) image means (linear RGB): Penumbra {', '.join(f(x, 4) for x in a['mean_penumbra'])}; "
                 f"Mitsuba {', '.join(f(x, 4) for x in a['mean_mitsuba'])}. Penumbra traced {a['penumbra_rays']:,} rays "
                 f"({a['penumbra_shadow_rays']:,} shadow rays)"
                 + (f"; 1 thread {f(a['penumbra_1_thread_s'])} s wall, 2 threads {f(a['penumbra_s'])} s."
                    if "penumbra_1_thread_s" in a else "."))
        if "llvm_s" in a:
            L.append(f"Mitsuba llvm_ad_rgb with {a['llvm_library']}; its first render (kernel compilation) took "
                     f"{f(a['llvm_first_s'])} s.")
    if "b" in res:
        b = res["b"]
        L.append(f"Scene (b) rays: POV-Ray {b['povray_rays']:,} ({b['povray_shadow']:,} shadow ray tests) in "
                 f"{f(b['povray_s'])} s; Penumbra {b['penumbra_rays']:,} ({b['penumbra_shadow']:,} shadow) in "
                 f"{f(b['penumbra_s'])} s.")
    if "whitted" in res:
        w = res["whitted"]
        L.append(f"Whitted frame: {w['rays']:,} rays; 2 threads {f(w['s_2'], 3)} s wall ({f(w['cpu_2'], 3)} s CPU), "
                 f"1 thread {f(w['s_1'], 3)} s wall ({f(w['cpu_1'], 3)} s CPU).")
    if "mirror" in res:
        w = res["mirror"]
        L.append(f"bunny-mirror frame: {w['rays']:,} rays traced, {w['saved']:,} saved by the metrics; 2 threads "
                 f"{f(w['s_2'], 1)} s wall ({f(w['cpu_2'], 1)} s CPU), 1 thread {f(w['s_1'], 1)} s wall "
                 f"({f(w['cpu_1'], 1)} s CPU; CPU times of the whole `penumbra render` process).")
    if "linear" in res:
        L.append("")
        L.append("| linearity (1 thread) | pixels | rays | s (wall) | s (CPU) | ns per ray (CPU) |")
        L.append("|---|---|---|---|---|---|")
        for x in res["linear"]["rows"]:
            L.append(f"| {x['what']} | {x['pixels']:,} | {x['rays']:,} | {f(x['s'], 3)} | {f(x['cpu_s'], 2)} | "
                     f"{f(1e9 * x['cpu_s'] / x['rays'], 0)} |")
    if "before" in res and "rows" in res["before"]:
        L.append("")
        L.append(f"| before → after (library of `{res['before']['rev']}` → this tree; 1 thread) | rays | "
                 "before s (CPU) | after s (CPU) | after / before (CPU) | before s (wall) | after s (wall) |")
        L.append("|---|---|---|---|---|---|---|")
        for x in res["before"]["rows"]:
            L.append(f"| {x['what']} | {x['rays']:,} | {f(x['before_cpu'])} | {f(x['after_cpu'])} | "
                     f"{f(x['ratio_cpu'])}× | {f(x['before_s'])} | {f(x['after_s'])} |")
    if "path" in res:
        c = res["path"]
        L.append(f"Cornell box image means (linear RGB): Penumbra {', '.join(f(x, 4) for x in c['mean_penumbra'])}; "
                 f"Mitsuba {', '.join(f(x, 4) for x in c['mean_mitsuba'])}. Relative MSE at 64 spp against Mitsuba's "
                 f"{c['reference_spp']}-spp reference: Penumbra {c['relmse_penumbra']:.3g}, Mitsuba scalar_rgb "
                 f"{c['relmse_scalar']:.3g}" + (f", llvm_ad_rgb {c['relmse_llvm']:.3g}" if "relmse_llvm" in c else "")
                 + f". Penumbra traced {c['penumbra_rays']:,} rays."
                 + (f" Mitsuba llvm_ad_rgb's first render (kernel compilation): {f(c['llvm_first_s'])} s."
                    if "llvm_first_s" in c else ""))
    if "progressive" in res:
        pr = res["progressive"]
        L.append("")
        L.append("Progressive rendering of the canonical scene (CPU s, medians): "
                 + "; ".join(f"{n} {f(v)}" for n, v in pr["cpu_s"].items())
                 + f". 64 passes / 1 pass {f(pr['passes_64_over_1'], 3)}×; a checkpoint per pass "
                 f"{f(pr['checkpoint_per_pass_over_none'], 3)}×; the preview {f(pr['preview_over_none'], 3)}×.")
    if "million" in res:
        mm = res["million"]
        L.append("")
        L.append(f"1M mesh: {mm['triangles']:,} primitives; load (PLY) and build {f(mm['build_s'])} s; "
                 f"render (800×600, 1 primary + 1 shadow ray) {f(mm['render_s'])} s wall, "
                 f"{f(mm['render_cpu_s'])} s CPU; max resident memory {f(mm['rss_mb'], 0)} MB.")
    vs = [(s, x) for s in SECTIONS if isinstance(res.get(s), dict) for x in res[s].get("vs", [])]
    if vs:
        L.append("")
        L.append(f"| this tree against `{res['baseline']}` (side by side, order alternating) | runs | baseline | "
                 f"this tree | this tree / baseline | worse by more than {100 * SLOWER:.0f}% |")
        L.append("|---|---|---|---|---|---|")
        for s, x in vs:
            L.append(f"| {x['what']} | {x['runs']} | {f(x['base'], 3)} | {f(x['cur'], 3)} | {f(x['ratio'], 3)}× | "
                     f"{'**yes**' if x['slower'] else 'no'} |")
        slower = [x["what"] for _, x in vs if x["slower"]]
        L.append("")
        L.append(f"{len(slower)} of {len(vs)} rows worse than `{res['baseline']}` by more than "
                 f"{100 * SLOWER:.0f}%" + (": " + "; ".join(slower) + "." if slower else "."))
    return "\n".join(L) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bunny", help="the Stanford bunny PLY (default: $PENUMBRA_BUNNY)")
    ap.add_argument("--rounds", type=int, help="rounds of each section (default 3; 5 with --baseline)")
    ap.add_argument("--quick", action="store_true", help="one round")
    ap.add_argument("--only", help="comma-separated sections: " + ",".join(SECTIONS))
    ap.add_argument("--skip", help="comma-separated sections not to run (e.g. mirror: about 4 minutes a round, "
                                   "twice that with --baseline)")
    ap.add_argument("--obvhs", action="store_true", help="also measure the obvhs crate in the rays section")
    ap.add_argument("--baseline", metavar="REV",
                    help="also build git revision REV in a temporary worktree and run every Penumbra row for it "
                         "and this tree side by side, alternating; adds a table of both columns and their ratio, "
                         "and the 'before' section")
    ap.add_argument("--update-doc", action="store_true", help="write the results into docs/performance.md")
    ap.add_argument("--no-setup", action="store_true", help="do not run bench/setup.sh")
    ap.add_argument("--pairs", type=int, default=25, help="one- and two-thread pairs of the scaling section")
    args = ap.parse_args()
    ensure_venv(args)
    if args.quick:
        args.rounds = 1
    elif args.rounds is None:
        args.rounds = 5 if args.baseline else 3
    sections = SECTIONS[:-1]
    if args.baseline:
        sections.append("before")
    if args.only:
        sections = [s for s in args.only.split(",") if s]
    skip = [s for s in (args.skip or "").split(",") if s]
    unknown = [s for s in sections + skip if s not in SECTIONS]
    if unknown:
        raise SystemExit(f"unknown sections: {', '.join(unknown)} (sections: {', '.join(SECTIONS)})")
    sections = [s for s in sections if s not in skip]
    load_start = os.getloadavg()
    bins = build(args)
    data = prepare(args)
    data["base"] = build_baseline(args) if args.baseline else None
    import importlib.metadata as md
    versions = {}
    for pkg in ("mitsuba", "drjit", "embreex", "numpy"):
        try:
            versions[pkg] = md.version(pkg)
        except md.PackageNotFoundError:
            pass
    if shutil.which("povray"):
        v = run(["povray", "--version"], check=False)
        m = re.search(r"POV-Ray ([\w.]+)", v.stdout + v.stderr)
        versions["POV-Ray"] = m.group(1) if m else "?"
    res = {"date": time.strftime("%Y-%m-%d"), "rounds": args.rounds, "versions": versions}
    if data["base"] is not None:
        res["baseline"] = data["base"]["rev"]
    fns = {"rays": section_rays, "a": section_a, "b": section_b, "whitted": section_whitted,
           "mirror": section_mirror, "scaling": section_scaling, "linear": section_linear,
           "memory": section_memory, "million": section_million, "points": section_points,
           "path": section_path, "instances": section_instances, "lights": section_lights,
           "xmlread": section_xmlread, "progressive": section_progressive, "kernels": section_kernels,
           "before": section_before}
    for s in sections:
        log(f"== {s}")
        res[s] = fns[s](args, bins, data)
        log(json.dumps(res[s], default=str))
    res["machine"] = machine()
    res["machine"]["load_start"] = load_start
    (HERE / ".work" / "results.json").write_text(json.dumps(res, indent=1, default=str))
    text = report(res)
    print(text)
    if args.update_doc:
        doc = ROOT / "docs" / "performance.md"
        d = doc.read_text()
        i, j = d.index(BEGIN) + len(BEGIN), d.index(END)
        doc.write_text(d[:i] + "\n" + text + d[j:])
        log(f"updated {doc.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
