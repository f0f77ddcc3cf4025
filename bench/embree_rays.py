"""Embree (through embreex) on the harness's triangle and ray files: build
time, and closest-hit (rtcIntersect1) and any-hit (rtcOccluded1) throughput
on the calling thread. Prints JSON. Run by run.py with the venv's Python:

    python embree_rays.py --tris F --rays NAME=F ... [--repeat 5] [--one-cpu]

--one-cpu pins the process to one CPU before Embree starts its TBB threads,
so the build runs on one thread. Timing is on-CPU time of the calling thread
(time.thread_time), as raybench does; embreex's run() loops over the rays in
C (Cython) calling rtcIntersect1/rtcOccluded1 per ray.
"""

import argparse
import json
import os
import statistics
import time

import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tris", required=True)
    ap.add_argument("--rays", action="append", default=[])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--one-cpu", action="store_true")
    a = ap.parse_args()
    if a.one_cpu:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    tris = np.fromfile(a.tris, dtype="<f4").reshape(-1, 3, 3)
    verts = np.ascontiguousarray(tris.reshape(-1, 3))
    faces = np.arange(len(verts), dtype=np.int32).reshape(-1, 3)
    # Build: the commit (Embree's BVH build), which embreex runs on the
    # first run() call, here with one ray. Scene creation and the copy of the
    # buffers into Embree (slow in embreex) are not counted.
    from embreex import rtcore
    device = rtcore.EmbreeDevice()
    o1 = np.zeros((1, 3), np.float32)
    d1 = np.array([[0.0, 0.0, 1.0]], np.float32)
    builds = []
    scene = None
    for _ in range(a.repeat):
        s = rtcore_scene.EmbreeScene(device)
        TriangleMesh(s, verts, faces)
        t0 = time.perf_counter()
        s.run(o1, d1, query="OCCLUDED")
        builds.append(time.perf_counter() - t0)
        scene = s
    out = {
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
        for kind, query in (("closest", "INTERSECT"), ("any", "OCCLUDED")):
            times, hits = [], None
            for _ in range(a.repeat):
                t0 = time.thread_time()
                ids = scene.run(o, d, query=query)
                times.append(time.thread_time() - t0)
                # Hit primitive ids for INTERSECT, geometry ids (0) of the
                # occluded rays for OCCLUDED; -1 for a miss either way.
                hits = int((np.asarray(ids) != -1).sum())
            sec = statistics.median(times)
            res[kind] = {"hits": hits, "seconds": sec, "mrays_per_s": len(r) / sec / 1e6}
        out["rays"][name] = res
    print(json.dumps(out))


if __name__ == "__main__":
    main()
