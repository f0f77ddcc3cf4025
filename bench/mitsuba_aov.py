#!/usr/bin/env python3
"""Renders one small scene with Mitsuba 3's `aov` integrator and with
Penumbra (which reads the same XML file), and compares the channels.

    python bench/mitsuba_aov.py [--penumbra BIN] [--out DIR] [--spp N]

The scene (written to DIR, default bench/.work/mitsuba-aov): a diffuse
sphere in front of a diffuse rectangle, a perspective camera, a box pixel
filter, the `aov` integrator with `depth`, `position`, `geo_normal`,
`sh_normal`, `uv`, `albedo`, `prim_index` and `shape_index` beside a `path`
integrator named `img`. Mitsuba 3 (`scalar_rgb`, from bench/requirements.txt)
writes `mitsuba.exr`, Penumbra `penumbra.exr`.

Printed: the channel names each wrote (sorted, as OpenEXR stores them),
whether they agree, and for each channel the mean absolute difference, the
largest one, and the fraction of pixels within 1e-3 (pixels on the
outline of an object, where sub-pixel rays meet different surfaces, are
counted too: the two renderers' camera samples differ). Exits 1 if the
channel names differ.
"""

import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

SCENE = """<scene version="3.0.0">
    <integrator type="aov">
        <string name="aovs" value="dd:depth,pp:position,ng:geo_normal,nn:sh_normal,uv:uv,al:albedo,pi:prim_index,si:shape_index"/>
        <integrator type="path" name="img">
            <integer name="max_depth" value="3"/>
        </integrator>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="{spp}"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="64"/>
            <integer name="height" value="48"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <emitter type="constant">
        <rgb name="radiance" value="1.0"/>
    </emitter>
    <shape type="sphere">
        <point name="center" value="0.3, -0.2, 0.5"/>
        <float name="radius" value="0.8"/>
        <bsdf type="diffuse">
            <rgb name="reflectance" value="0.2, 0.5, 0.7"/>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <scale value="2.5"/>
            <rotate y="1" angle="20"/>
            <translate value="0, 0, -1"/>
        </transform>
        <bsdf type="diffuse">
            <rgb name="reflectance" value="0.6, 0.3, 0.1"/>
        </bsdf>
    </shape>
</scene>
"""


def channels(path):
    import mitsuba as mi

    bmp = mi.Bitmap(path)
    out = {}
    for name, b in bmp.split():
        a = np.array(b, dtype=np.float64)
        if a.ndim == 2:
            a = a[:, :, None]
        # A split bitmap of several channels holds them in its own order.
        names = [f.name for f in b.struct_()]
        for k, n in enumerate(names):
            full = n if name in ("<root>", "") else f"{name}.{n}"
            out[full] = a[:, :, k]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--penumbra", default=os.path.join(HERE, "..", "target", "release", "penumbra"))
    ap.add_argument("--out", default=os.path.join(HERE, ".work", "mitsuba-aov"))
    ap.add_argument("--spp", type=int, default=16)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    xml = os.path.join(a.out, "aov.xml")
    with open(xml, "w") as f:
        f.write(SCENE.format(spp=a.spp))

    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    scene = mi.load_file(xml)
    mi.render(scene)
    film = scene.sensors()[0].film()
    mexr = os.path.join(a.out, "mitsuba.exr")
    film.write(mexr)
    pexr = os.path.join(a.out, "penumbra.exr")
    subprocess.run([a.penumbra, "render", xml, "-o", pexr, "-q"], check=True)

    m, p = channels(mexr), channels(pexr)
    print("mitsuba: ", " ".join(sorted(m)))
    print("penumbra:", " ".join(sorted(p)))
    same = sorted(m) == sorted(p)
    print("channel names agree" if same else "channel names DIFFER")
    print(f"{'channel':10} {'mean |d|':>10} {'max |d|':>10} {'within 1e-3':>12}")
    for name in sorted(set(m) & set(p)):
        d = np.abs(m[name] - p[name])
        print(f"{name:10} {d.mean():10.2e} {d.max():10.2e} {np.mean(d < 1e-3):12.1%}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
