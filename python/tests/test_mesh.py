"""TriangleMesh: batches of rays against Penumbra's BVH, checked against a
brute-force ray-triangle test written here in numpy (float64)."""

from __future__ import annotations

import numpy as np
import pytest

import penumbra


def soup(rng: np.random.Generator, n: int) -> np.ndarray:
    """n random triangles of size about 0.3 in the unit cube, (n, 3, 3) float32."""
    a = rng.uniform(0, 1, (n, 1, 3))
    return (a + rng.uniform(-0.15, 0.15, (n, 3, 3))).astype(np.float32)


def brute(tris: np.ndarray, o: np.ndarray, d: np.ndarray):
    """Closest hits by Möller–Trumbore over all triangles, in float64:
    (t, prim, u, v, margin), where margin is how far the hit is from the
    triangle's edges (in barycentrics) and from the next-nearest hit (in t)."""
    v0, v1, v2 = (tris[:, k].astype(np.float64) for k in range(3))
    e1, e2 = v1 - v0, v2 - v0
    n = len(o)
    best_t = np.full(n, np.inf)
    prim = np.full(n, -1)
    bu, bv = np.zeros(n), np.zeros(n)
    edge = np.full(n, np.inf)
    second = np.full(n, np.inf)
    for i in range(n):
        p = np.cross(d[i], e2)
        det = np.einsum("ij,ij->i", e1, p)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            s = o[i] - v0
            u = np.einsum("ij,ij->i", s, p) * inv
            q = np.cross(s, e1)
            v = (q @ d[i]) * inv
            t = np.einsum("ij,ij->i", e2, q) * inv
        ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        if ok.any():
            ts = np.where(ok, t, np.inf)
            j = int(np.argmin(ts))
            best_t[i], prim[i], bu[i], bv[i] = ts[j], j, u[j], v[j]
            edge[i] = min(u[j], v[j], 1 - u[j] - v[j])
            second[i] = np.partition(ts, 1)[1] - ts[j] if len(ts) > 1 else np.inf
        # Misses near an edge may go either way.
        near = (det != 0) & (t > 0) & (np.minimum(np.minimum(u, v), 1 - u - v) > -1e-4)
        if not ok.any() and near.any():
            edge[i] = 0.0
    return best_t, prim, bu, bv, np.minimum(edge, second)


def rays_at(rng: np.random.Generator, tris: np.ndarray, n: int):
    """Half aimed at triangle centroids from outside the cube, half random."""
    o = rng.uniform(-1, 2, (n, 3))
    target = tris[rng.integers(0, len(tris), n)].mean(axis=1)
    d = np.where(np.arange(n)[:, None] % 2 == 0, target - o, rng.normal(size=(n, 3)))
    return o.astype(np.float32), d.astype(np.float32)


def test_closest_hits_match_brute_force():
    rng = np.random.default_rng(7)
    tris = soup(rng, 300)
    o, d = rays_at(rng, tris, 400)
    h = penumbra.TriangleMesh(tris).intersect(o, d)
    t, prim, u, v, margin = brute(tris, o.astype(np.float64), d.astype(np.float64))
    clear = margin > 1e-4
    assert clear.sum() > 300
    assert (prim[clear] >= 0).sum() > 150, "enough hits"
    np.testing.assert_array_equal(h["prim"][clear], prim[clear])
    hit = clear & (prim >= 0)
    np.testing.assert_allclose(h["t"][hit], t[hit], rtol=1e-4)
    np.testing.assert_allclose(h["u"][hit], u[hit], atol=1e-4)
    np.testing.assert_allclose(h["v"][hit], v[hit], atol=1e-4)
    assert np.all(np.isinf(h["t"][h["prim"] == -1]))
    assert h["t"].dtype == np.float32 and h["prim"].dtype == np.int64


def test_occlusion_limits_and_forms_agree():
    rng = np.random.default_rng(8)
    tris = soup(rng, 200)
    o, d = rays_at(rng, tris, 500)
    mesh = penumbra.TriangleMesh(tris)
    # The same triangles as vertices and faces (shared vertices, reversed order).
    verts = tris.reshape(-1, 3)[::-1].copy()
    faces = (len(verts) - 1 - np.arange(len(verts))).reshape(-1, 3)
    indexed = penumbra.TriangleMesh(verts, faces)
    assert len(mesh) == len(indexed) == 200
    h = mesh.intersect(o, d)
    for k in ("t", "prim", "u", "v"):
        np.testing.assert_array_equal(indexed.intersect(o, d)[k], h[k])
    np.testing.assert_array_equal(mesh.occluded(o, d), h["prim"] != -1)
    # Per-ray limits: a hit counts only within (tmin, tmax).
    tmax = rng.uniform(0, 3, len(o)).astype(np.float32)
    within = (h["prim"] != -1) & (h["t"] < tmax)
    limited = mesh.intersect(o, d, tmax=tmax)
    np.testing.assert_array_equal(limited["prim"] != -1, mesh.occluded(o, d, tmax=tmax))
    np.testing.assert_array_equal(limited["prim"][within], h["prim"][within])
    # Beyond tmin only: what is hit is at least as far as tmin.
    far = mesh.intersect(o, d, tmin=1.0)
    assert np.all(far["t"][far["prim"] != -1] > 1.0)


def test_results_do_not_depend_on_the_batch():
    rng = np.random.default_rng(9)
    tris = soup(rng, 500)
    o, d = rays_at(rng, tris, 300)
    mesh = penumbra.TriangleMesh(tris)
    h = mesh.intersect(o, d)
    perm = rng.permutation(len(o))
    shuffled = mesh.intersect(o[perm], d[perm])
    for k in ("t", "prim", "u", "v"):
        np.testing.assert_array_equal(shuffled[k], h[k][perm])
    for i in (0, 5, 299):
        one = mesh.intersect(o[i : i + 1], d[i : i + 1])
        assert one["prim"][0] == h["prim"][i] and one["t"][0] == h["t"][i]


def grid_mesh(n: int) -> np.ndarray:
    """The unit square at z = 0.5 as 2 n² triangles sharing edges, (N, 3, 3)."""
    xs = np.linspace(0, 1, n + 1)
    x0, y0 = np.meshgrid(xs[:-1], xs[:-1])
    x1, y1 = x0 + 1 / n, y0 + 1 / n
    a, b = np.stack([x0, y0], -1), np.stack([x1, y0], -1)
    c, e = np.stack([x1, y1], -1), np.stack([x0, y1], -1)
    tris = np.concatenate([np.stack([a, b, c], -2), np.stack([a, c, e], -2)]).reshape(-1, 3, 2)
    return np.concatenate([tris, np.full(tris.shape[:-1] + (1,), 0.5)], -1).astype(np.float32)


def test_rays_from_one_point_match_single_rays():
    """Consecutive rays from one point (a camera's, in rows) are traced as
    packets: each gets what it gets alone or in a shuffled batch, also when
    aimed at edges and vertices shared by several triangles. The grid is in
    the mesh twice, so every hit on it is a tie between two triangles at
    exactly the same distance: the lower index is reported."""
    rng = np.random.default_rng(11)
    grid = grid_mesh(8)
    tris = np.concatenate([grid, soup(rng, 300), grid])
    mesh = penumbra.TriangleMesh(tris)
    origin = np.array([0.43, 0.37, -1.5], dtype=np.float32)
    # A 64 x 64 image of the square, and rays at the grid's vertices and edges.
    px = (np.arange(64) + 0.5) / 64
    gx, gy = np.meshgrid(px, px)
    aim = [np.stack([gx, gy], -1).reshape(-1, 2)]
    vx, vy = np.meshgrid(np.linspace(0, 1, 17), np.linspace(0, 1, 17))
    aim.append(np.stack([vx, vy], -1).reshape(-1, 2))
    aim = np.concatenate(aim)
    target = np.concatenate([aim, np.full((len(aim), 1), 0.5)], -1)
    o = np.broadcast_to(origin, target.shape).astype(np.float32)
    d = (target - origin).astype(np.float32)
    h = mesh.intersect(o, d)
    assert (h["prim"] != -1).sum() > 4000
    assert np.all(h["prim"] < len(grid) + 300)
    perm = rng.permutation(len(o))
    shuffled = mesh.intersect(o[perm], d[perm])
    for k in ("t", "prim", "u", "v"):
        np.testing.assert_array_equal(shuffled[k], h[k][perm])
    np.testing.assert_array_equal(mesh.occluded(o, d), h["prim"] != -1)
    np.testing.assert_array_equal(mesh.occluded(o[perm], d[perm]), h["prim"][perm] != -1)
    for i in rng.choice(len(o), 200, replace=False):
        one = mesh.intersect(o[i : i + 1], d[i : i + 1])
        assert (one["prim"][0], one["t"][0]) == (h["prim"][i], h["t"][i])


def test_batches_longer_than_a_chunk_match_short_ones():
    """A batch is traced in pieces of 4,096 rays: a long one with per-ray
    limits gives each ray what a short batch of the same rays gives it."""
    rng = np.random.default_rng(10)
    tris = soup(rng, 300)
    o, d = rays_at(rng, tris, 10_000)
    tmax = rng.uniform(0, 3, len(o)).astype(np.float32)
    mesh = penumbra.TriangleMesh(tris)
    whole, blocked = mesh.intersect(o, d, tmax=tmax), mesh.occluded(o, d, tmax=tmax)
    assert (whole["prim"] != -1).sum() > 2000
    for s in range(0, len(o), 700):
        part = slice(s, s + 700)
        short = mesh.intersect(o[part], d[part], tmax=tmax[part])
        for k in ("t", "prim", "u", "v"):
            np.testing.assert_array_equal(whole[k][part], short[k])
        np.testing.assert_array_equal(blocked[part], mesh.occluded(o[part], d[part], tmax=tmax[part]))


def test_empty_mesh_and_odd_rays():
    mesh = penumbra.TriangleMesh(np.zeros((0, 3, 3), np.float32))
    assert len(mesh) == 0 and "0 triangles" in repr(mesh)
    h = mesh.intersect(np.zeros((2, 3)), np.ones((2, 3)))
    assert list(h["prim"]) == [-1, -1]
    tri = penumbra.TriangleMesh([[[-1, -1, 0], [1, -1, 0], [0, 1, 0]]])
    o = [[0, 0, -5], [np.nan, 0, -5], [0, 0, -5], [0, 0, -5]]
    d = [[0, 0, 1], [0, 0, 1], [np.inf, 0, 1], [0, 0, 0]]
    h = tri.intersect(o, d)
    assert list(h["prim"]) == [0, -1, -1, -1] and h["t"][0] == 5.0
    assert list(tri.occluded(o, d)) == [True, False, False, False]
    assert list(tri.intersect(np.zeros((0, 3)), np.zeros((0, 3)))["prim"]) == []


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: penumbra.TriangleMesh(np.zeros((4, 3))), "triangles of shape"),
        (lambda: penumbra.TriangleMesh(np.zeros((4, 2))), "shape (..., 3)"),
        (lambda: penumbra.TriangleMesh(np.zeros((4, 3)), [[0, 1, 4]]), "faces[0, 2] = 4"),
        (lambda: penumbra.TriangleMesh(np.zeros((4, 3)), [[0, -1, 2]]), "faces[0, 1] = -1"),
        (lambda: penumbra.TriangleMesh([[[0, 0, np.inf], [1, 0, 0], [0, 1, 0]]]), "finite"),
        (lambda: penumbra.TriangleMesh("abc"), "vertices"),
    ],
)
def test_bad_meshes_are_value_errors(make, message):
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("(", r"\(").replace(")", r"\)")):
        make()


def test_bad_queries_are_value_errors():
    mesh = penumbra.TriangleMesh([[[-1, -1, 0], [1, -1, 0], [0, 1, 0]]])
    o, d = np.zeros((3, 3)), np.ones((3, 3))
    with pytest.raises(ValueError, match="both have shape"):
        mesh.intersect(o, d[:2])
    with pytest.raises(ValueError, match="tmax"):
        mesh.occluded(o, d, tmax=[1.0, 2.0])
    with pytest.raises(ValueError, match="tmax must not be NaN"):
        mesh.intersect(o, d, tmax=np.nan)
    with pytest.raises(ValueError, match="tmin"):
        mesh.intersect(o, d, tmin=-1.0)
