"""Scene (a) in Mitsuba 3: the bunny scene at 800x600 rendered with the
`direct` integrator, 16 samples per pixel (independent sampler, box filter),
one emitter sample (a shadow ray to a point of the area light) and no BSDF
sample per hit. Prints JSON with the render times. Run by run.py:

    python mitsuba_bunny.py VARIANT BUNNY.ply [--repeat 5] [--spp 16] [--exr OUT]

Timing: wall clock and process CPU time around mi.render() followed by a
conversion to a numpy array (which forces the LLVM variant to evaluate),
after one untimed warm-up render (the LLVM variant compiles its kernel then;
that first render is reported separately).
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
    ap.add_argument("bunny")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--exr")
    a = ap.parse_args()
    import mitsuba as mi
    import numpy as np

    mi.set_variant(a.variant)
    T = mi.ScalarTransform4f
    # Two-sided, as Penumbra shades (the bunny's facets face inward).
    diffuse = lambda rgb: {"type": "twosided", "bsdf": {
        "type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}}
    t0 = time.perf_counter()
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "fov_axis": "y",
            "to_world": T().look_at(origin=[0.0, 1.3, 4.2], target=[-0.15, 0.65, 0.0], up=[0.0, 1.0, 0.0]),
            "film": {"type": "hdrfilm", "width": 800, "height": 600, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": a.spp},
        },
        # A 10x10 quad at y = 0 facing up (the rectangle is [-1, 1]^2 in z = 0, facing +z).
        "ground": {"type": "rectangle", "to_world": T().rotate([1, 0, 0], -90).scale([5, 5, 1]),
                   "bsdf": diffuse([0.7, 0.7, 0.7])},
        "bunny": {"type": "ply", "filename": a.bunny, "face_normals": True,
                  "to_world": T().translate([0.0, -0.33, 0.0]).scale(10.0),
                  "bsdf": diffuse([0.75, 0.72, 0.65])},
        # The 1x1 light at height 4, facing down.
        "light": {"type": "rectangle", "to_world": T().translate([0, 4, 0]).rotate([1, 0, 0], 90).scale([0.5, 0.5, 1]),
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [40.0, 40.0, 40.0]}}},
    })
    load_s = time.perf_counter() - t0
    w0, c0 = time.perf_counter(), cpu()
    img = np.array(mi.render(scene, spp=a.spp))
    first = (time.perf_counter() - w0, cpu() - c0)
    walls, cpus = [], []
    for i in range(a.repeat):
        w0, c0 = time.perf_counter(), cpu()
        img = np.array(mi.render(scene, spp=a.spp, seed=i + 1))
        walls.append(time.perf_counter() - w0)
        cpus.append(cpu() - c0)
    if a.exr:
        mi.Bitmap(img).write(a.exr)
    print(json.dumps({
        "variant": a.variant,
        "version": mi.__version__,
        "load_s": load_s,
        "first_render_s": first[0],
        "render_s": statistics.median(walls),
        "render_s_all": walls,
        "render_cpu_s": statistics.median(cpus),
        "mean_rgb": [float(x) for x in img.reshape(-1, img.shape[-1])[:, :3].mean(axis=0)],
    }))


if __name__ == "__main__":
    main()
