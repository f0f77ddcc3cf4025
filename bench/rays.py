"""Embree (through embreex) or Penumbra (through its Python module) on the
harness's triangle and ray files: build time, and closest-hit and any-hit
throughput on the calling thread. Prints JSON. Run by run.py with the
venv's Python:

    python rays.py --system embree|penumbra --tris F --rays NAME=F ... [--repeat 5] [--one-cpu]

Both are timed the same way: the on-CPU time of the calling thread
(time.thread_time) around one Python call that traces a numpy array of
rays and returns arrays of results. Embree: embreex's run(), which loops in
C (Cython) calling rtcIntersect1 / rtcOccluded1 per ray. Penumbra:
TriangleMesh.intersect / occluded, which trace runs of consecutive rays
from one point (the camera rays) as packets and the other rays eight at a
time with their traversals interleaved.

--one-cpu pins the process to one CPU before the system starts its threads,
so the build runs on one thread.
"""

import argparse
import json
import os
import statistics
import time

import numpy as np


class Embree:
    """embreex: the build is the commit, which embreex runs on the first
    run() call."""

    def __init__(self, tris):
        from embreex import rtcore

        self.verts = np.ascontiguousarray(tris.reshape(-1, 3))
        self.faces = np.arange(len(self.verts), dtype=np.int32).reshape(-1, 3)
        self.device = rtcore.EmbreeDevice()
        self.scene = None

    def build(self):
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        # Scene creation and the copy of the buffers into Embree (slow in
        # embreex) are not counted: only the commit, here with one ray.
        self.scene = rtcore_scene.EmbreeScene(self.device)
        TriangleMesh(self.scene, self.verts, self.faces)
        t0 = time.perf_counter()
        self.scene.run(np.zeros((1, 3), np.float32), np.array([[0.0, 0.0, 1.0]], np.float32), query="OCCLUDED")
        return time.perf_counter() - t0

    def hits(self, kind, o, d):
        # Hit primitive ids for INTERSECT, geometry ids (0) of the occluded
        # rays for OCCLUDED; -1 for a miss either way.
        ids = self.scene.run(o, d, query="INTERSECT" if kind == "closest" else "OCCLUDED")
        return int((np.asarray(ids) != -1).sum())


class Penumbra:
    """penumbra.TriangleMesh: build in the constructor (its copy included)."""

    def __init__(self, tris):
        import penumbra

        self.tris, self.cls, self.mesh = tris, penumbra.TriangleMesh, None

    def build(self):
        t0 = time.perf_counter()
        self.mesh = self.cls(self.tris)
        return time.perf_counter() - t0

    def hits(self, kind, o, d):
        if kind == "closest":
            return int((self.mesh.intersect(o, d)["prim"] != -1).sum())
        return int(self.mesh.occluded(o, d).sum())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--system", choices=["embree", "penumbra"], default="embree")
    ap.add_argument("--tris", required=True)
    ap.add_argument("--rays", action="append", default=[])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--one-cpu", action="store_true")
    a = ap.parse_args()
    if a.one_cpu:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    tris = np.fromfile(a.tris, dtype="<f4").reshape(-1, 3, 3)
    system = (Embree if a.system == "embree" else Penumbra)(tris)
    builds = [system.build() for _ in range(a.repeat)]
    out = {
        "system": a.system,
        "triangles": len(tris),
        "threads": len(os.sched_getaffinity(0)),
        "build_ms": 1e3 * statistics.median(builds),
        "rays": {},
    }
    for spec in a.rays:
        name, path = spec.split("=", 1)
        r = np.fromfile(path, dtype="<f4").reshape(-1, 6)
        o = np.ascontiguousarray(r[:, :3])
        d = np.ascontiguousarray(r[:, 3:])
        res = {"rays": len(r)}
        for kind in ("closest", "any"):
            times, hits = [], None
            for _ in range(a.repeat):
                t0 = time.thread_time()
                hits = system.hits(kind, o, d)
                times.append(time.thread_time() - t0)
            sec = statistics.median(times)
            res[kind] = {"hits": hits, "seconds": sec, "mrays_per_s": len(r) / sec / 1e6}
        out["rays"][name] = res
    print(json.dumps(out))


if __name__ == "__main__":
    main()
