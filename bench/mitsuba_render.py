"""Renders a Mitsuba 3 XML scene in Mitsuba 3 and prints JSON with the render
times. Run by run.py (section path):

    python mitsuba_render.py VARIANT SCENE.xml [--repeat 1] [-D name=value ...] [--exr OUT] [--seed 1]

The scene's `<default>` parameters are set with -D. Timing: wall clock and
process CPU time around mi.render() followed by a conversion to a numpy
array (which forces the LLVM variant to evaluate), after one untimed
warm-up render at the same settings (the LLVM variant compiles its kernel
then; that render's time is reported separately). --exr writes the last
render.
"""

import argparse
import json
import resource
import statistics
import time


def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("variant")
    ap.add_argument("scene")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("-D", dest="defines", action="append", default=[])
    ap.add_argument("--exr")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    import mitsuba as mi
    import numpy as np

    mi.set_variant(a.variant)
    params = dict(d.split("=", 1) for d in a.defines)
    scene = mi.load_file(a.scene, **params)
    t = time.perf_counter()
    img = np.array(mi.render(scene, seed=a.seed + 1000))
    first = time.perf_counter() - t
    walls, cpus = [], []
    for k in range(a.repeat):
        t, c = time.perf_counter(), cpu()
        img = np.array(mi.render(scene, seed=a.seed + k))
        walls.append(time.perf_counter() - t)
        cpus.append(cpu() - c)
    if a.exr:
        mi.Bitmap(img[..., :3]).write(a.exr)
    print(json.dumps({
        "variant": a.variant, "version": mi.__version__, "first_render_s": first,
        "render_s": statistics.median(walls), "render_cpu_s": statistics.median(cpus),
        "mean_rgb": [float(x) for x in img[..., :3].reshape(-1, 3).mean(axis=0)],
    }))


if __name__ == "__main__":
    main()
