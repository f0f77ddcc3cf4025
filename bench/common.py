"""Shared pieces of the benchmark harness: the bunny, the rays, files.

Everything is float32 and written as headerless little-endian arrays (see
crates/penumbra-bench/src/lib.rs), so Embree and Penumbra trace the very same
numbers.
"""

import math
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
WORK = HERE / ".work"

# The bunny scene (crates/penumbra/scenes/bunny.toml).
WIDTH, HEIGHT = 800, 600
EYE = np.array([0.0, 1.3, 4.2])
TARGET = np.array([-0.15, 0.65, 0.0])
FOV_Y = 40.0
BUNNY_SCALE = 10.0
BUNNY_TRANSLATE = np.array([0.0, -0.33, 0.0])


def bunny_path(arg=None):
    """The bunny: the argument, else $PENUMBRA_BUNNY; None when neither is given."""
    p = arg or os.environ.get("PENUMBRA_BUNNY")
    return Path(p).resolve() if p else None


def target_dir():
    """This checkout's cargo target directory."""
    return Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")).resolve()


def build_current(packages, features=(), run=subprocess.run):
    """Release binaries of this checkout: {name: path}. `packages` maps a
    package to the binaries wanted from it."""
    cmd = ["cargo", "build", "--release", "--bins"]
    for p in packages:
        cmd += ["-p", p]
    for f in features:
        cmd += ["--features", f]
    run(cmd, cwd=ROOT, check=True)
    return {b: target_dir() / "release" / b for bins in packages.values() for b in bins}


def revision(rev):
    """The full commit id of a git revision of this repository."""
    p = subprocess.run(["git", "rev-parse", "--verify", f"{rev}^{{commit}}"], cwd=ROOT,
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"not a commit of this repository: {rev}")
    return p.stdout.strip()


def build_revision(rev, packages, features=(), run=subprocess.run):
    """Release binaries of git revision `rev`, built from its own sources:
    {name: path}. `packages` maps a package to the binaries wanted from it.

    The revision is checked out into a temporary `git worktree` (removed
    afterwards) and built with a target directory of its own,
    bench/.work/rev-target, which starts as a copy of this checkout's so
    that the third-party crates compile only if the revision changed them.
    The binaries are kept in bench/.work/rev/COMMIT-KEY and reused while
    the compiler stays the same."""
    sha = revision(rev)
    rustc = subprocess.run(["rustc", "-V"], capture_output=True, text=True).stdout.strip()
    key = "-".join([sha[:12], *sorted(packages), *sorted(f.replace("/", "_") for f in features)])
    keep = WORK / "rev" / key
    names = [b for bins in packages.values() for b in bins]
    stamp = keep / "rustc"
    if stamp.exists() and stamp.read_text() == rustc and all((keep / b).exists() for b in names):
        return {b: keep / b for b in names}
    target = WORK / "rev-target"
    if not target.exists() and (target_dir() / "release").is_dir():
        print(f"copying {target_dir()} to {target} (once)", file=sys.stderr, flush=True)
        target.mkdir(parents=True)
        shutil.copytree(target_dir() / "release", target / "release", symlinks=True)
    with tempfile.TemporaryDirectory(prefix="penumbra-rev-") as tmp:
        src = Path(tmp) / "src"
        run(["git", "worktree", "add", "--detach", "--quiet", str(src), sha], cwd=ROOT, check=True)
        try:
            cmd = ["cargo", "build", "--release", "--bins"]
            for p in packages:
                cmd += ["-p", p]
            for f in features:
                cmd += ["--features", f]
            run(cmd, cwd=src, env=dict(os.environ, CARGO_TARGET_DIR=str(target)), check=True)
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(src)], cwd=ROOT)
            subprocess.run(["git", "worktree", "prune"], cwd=ROOT)
    shutil.rmtree(keep, ignore_errors=True)
    keep.mkdir(parents=True)
    for b in names:
        shutil.copy2(target / "release" / b, keep / b)
    stamp.write_text(rustc)
    return {b: keep / b for b in names}


def read_ply(path):
    """Vertices (n, 3) float32 and triangles (m, 3) int64 of a binary
    little-endian or ASCII PLY with x y z vertices and triangle faces."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = next(l.split()[1] for l in header if l.startswith("format"))
    elements, cur = [], None
    for l in header:
        w = l.split()
        if w[:1] == ["element"]:
            cur = [w[1], int(w[2]), []]
            elements.append(cur)
        elif w[:1] == ["property"] and cur is not None:
            cur[2].append(w[1:])
    body = data[end:]
    if fmt == "ascii":
        tokens = body.split()
        pos, verts, faces = 0, None, []
        for name, count, props in elements:
            if name == "vertex":
                k = len(props)
                arr = np.array(tokens[pos:pos + count * k], dtype=np.float64).reshape(count, k)
                pos += count * k
                names = [p[-1] for p in props]
                verts = arr[:, [names.index("x"), names.index("y"), names.index("z")]].astype(np.float32)
            elif name == "face":
                for _ in range(count):
                    n = int(tokens[pos])
                    idx = [int(t) for t in tokens[pos + 1:pos + 1 + n]]
                    pos += 1 + n
                    faces.extend([idx[0], idx[i], idx[i + 1]] for i in range(1, n - 1))
        return verts, np.array(faces, dtype=np.int64)
    assert fmt == "binary_little_endian", f"unsupported PLY format {fmt}"
    types = {"float": "<f4", "float32": "<f4", "double": "<f8", "uchar": "u1", "uint8": "u1",
             "char": "i1", "int": "<i4", "int32": "<i4", "uint": "<u4", "short": "<i2", "ushort": "<u2"}
    off, verts, faces = 0, None, None
    for name, count, props in elements:
        if name == "vertex":
            dt = np.dtype([(p[-1], types[p[0]]) for p in props])
            arr = np.frombuffer(body, dtype=dt, count=count, offset=off)
            off += dt.itemsize * count
            verts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float32)
        elif name == "face":
            (_, ctype, itype, _) = props[0]
            # Fast path: all triangles (checked).
            dt = np.dtype([("n", types[ctype]), ("i", types[itype], 3)])
            arr = np.frombuffer(body, dtype=dt, count=count, offset=off)
            assert (arr["n"] == 3).all(), "only triangle faces are supported here"
            off += dt.itemsize * count
            faces = arr["i"].astype(np.int64)
    return verts, faces


def bunny_triangles(path):
    """The bunny's triangles in scene space (x10, moved down by 0.33): (m, 3, 3) float32."""
    v, f = read_ply(path)
    v = (v * np.float32(BUNNY_SCALE) + BUNNY_TRANSLATE.astype(np.float32)).astype(np.float32)
    return v[f]


def camera_rays(width=WIDTH, height=HEIGHT):
    """One ray through each pixel centre of the bunny scene's pinhole camera,
    as Penumbra's camera computes it: (width*height, 6) float32."""
    fwd = TARGET - EYE
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    tan = math.tan(math.radians(FOV_Y) / 2)
    aspect = width / height
    ys, xs = np.mgrid[0:height, 0:width]
    nx = 2.0 * (xs + 0.5) / width - 1.0
    ny = 1.0 - 2.0 * (ys + 0.5) / height
    d = fwd + (nx * tan * aspect)[..., None] * right + (ny * tan)[..., None] * up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.broadcast_to(EYE, d.shape)
    return np.concatenate([o, d], axis=-1).reshape(-1, 6).astype(np.float32)


def incoherent_rays(tris, n=1_000_000, seed=7):
    """Rays from points on the mesh (uniform by area) in cosine-distributed
    directions about the facet's outward normal, origins moved off the surface by 1e-4 of the mesh's size:
    (n, 6) float32. Diffuse bounce rays, as a path tracer would trace."""
    rng = np.random.default_rng(seed)
    a, b, c = (tris[:, i].astype(np.float64) for i in range(3))
    cr = np.cross(b - a, c - a)
    area = np.linalg.norm(cr, axis=1)
    keep = area > 0
    a, b, c, cr, area = a[keep], b[keep], c[keep], cr[keep], area[keep]
    # Orient the facets outward as a whole (the sign of the volume they enclose).
    if np.einsum("ij,ij->", a, cr) < 0:
        cr = -cr
    idx = rng.choice(len(area), size=n, p=area / area.sum())
    u, v = rng.random(n), rng.random(n)
    su = np.sqrt(u)
    p = (1 - su)[:, None] * a[idx] + (su * (1 - v))[:, None] * b[idx] + (su * v)[:, None] * c[idx]
    nrm = cr[idx] / area[idx][:, None]
    # Cosine-weighted hemisphere about nrm.
    r1, r2 = rng.random(n), rng.random(n)
    phi = 2 * np.pi * r1
    sr = np.sqrt(r2)
    local = np.stack([sr * np.cos(phi), sr * np.sin(phi), np.sqrt(1 - r2)], axis=1)
    helper = np.where(np.abs(nrm[:, :1]) > 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]])
    t = np.cross(helper, nrm)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    s = np.cross(nrm, t)
    d = local[:, :1] * t + local[:, 1:2] * s + local[:, 2:] * nrm
    size = float(np.max(tris.max(axis=(0, 1)) - tris.min(axis=(0, 1))))
    o = p + nrm * (1e-4 * size)
    return np.concatenate([o, d], axis=1).astype(np.float32)


def bumpy_sphere(nu=1000, nv=501):
    """Vertices and triangles of a closed UV sphere with bumps:
    2*nu*(nv-1) triangles (a million for the defaults)."""
    j = np.arange(nv + 1)[:, None]
    i = np.arange(nu)[None, :]
    theta = np.pi * j / nv
    phi = 2 * np.pi * i / nu
    r = 1.0 + 0.08 * np.sin(7 * theta) * np.sin(9 * phi) + 0.02 * np.cos(31 * phi)
    pts = np.stack([r * np.sin(theta) * np.cos(phi), r * np.cos(theta), r * np.sin(theta) * np.sin(phi)], axis=-1)
    # Poles are single vertices.
    verts = [pts[0, 0][None]] + [pts[1:nv].reshape(-1, 3)] + [pts[nv, 0][None]]
    verts = np.concatenate(verts).astype(np.float32)
    ring = lambda jj, ii: 1 + (jj - 1) * nu + (ii % nu)
    south = len(verts) - 1
    faces = []
    ii = np.arange(nu)
    faces.append(np.stack([np.zeros(nu, int), ring(1, ii + 1), ring(1, ii)], axis=1))
    faces.append(np.stack([np.full(nu, south), ring(nv - 1, ii), ring(nv - 1, ii + 1)], axis=1))
    jj, ii2 = np.meshgrid(np.arange(1, nv - 1), ii, indexing="ij")
    a_, b_, c_, d_ = ring(jj, ii2), ring(jj, ii2 + 1), ring(jj + 1, ii2), ring(jj + 1, ii2 + 1)
    faces.append(np.stack([a_, b_, d_], axis=-1).reshape(-1, 3))
    faces.append(np.stack([a_, d_, c_], axis=-1).reshape(-1, 3))
    return verts, np.concatenate(faces).astype(np.int32)


def write_ply(path, verts, faces):
    """A binary little-endian PLY of triangles."""
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode("ascii")
    dt = np.dtype([("n", "u1"), ("i", "<i4", 3)])
    f = np.empty(len(faces), dtype=dt)
    f["n"] = 3
    f["i"] = faces
    with open(path, "wb") as out:
        out.write(header)
        out.write(np.ascontiguousarray(verts, dtype="<f4").tobytes())
        out.write(f.tobytes())
