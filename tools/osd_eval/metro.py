#!/usr/bin/env python3
"""Metro-style distance of a surface's sample points to the exact limit surface (dev only).

    metro.py EXACT.txt OTHER.txt DIAGONAL [--faces-from FILE] [--one-sided MESH.obj]

EXACT.txt is `tessera limit MESH --grid N` (a lattice of (N+1)^2 points per face or sub-face,
`f u v x y z nx ny nz`); it is triangulated per lattice cell into a dense piecewise-linear copy
of the exact surface (its own error is O(h^2 curvature), h = 1/N of a face). OTHER.txt is any
file of the same format whose parameters are ignored: `tessera sample` (captured TES points) or
osd_eval. For each point of OTHER: the distance to the closest point of the triangulated exact
surface (16 candidate triangles nearest by centroid, exact point-triangle distance), and the
angle between its normal and the exact normal interpolated there. Prints RMS and max of both,
distances as fractions of DIAGONAL. `--faces-from FILE` keeps only the points of OTHER whose base
face (the id before any `:k`) has a point in FILE (e.g. compare OpenSubdiv on the faces a
tessera capture draws, leaving out faces tessera keeps on its exact CPU path). `--one-sided MESH.obj` pairs each point only with exact
triangles on its own side of the mesh's infinitely sharp creases (tags `t crease 2/1/0 a b s`,
s >= 10): the faces reachable from its base face across smooth and semi-sharp edges. Near such a
crease the plain closest point may lie on the other side, whose normal differs by the dihedral
angle; a point with no own-side triangle among its 64 nearest is left out and counted. Independent of tessera's own closest-point search
(`gregory::accuracy::closest_exact`) and of any parameterisation. Needs numpy and scipy.
"""
import sys
from collections import defaultdict

import numpy as np
from scipy.spatial import cKDTree


def read(path):
    rows = []
    keys = []
    for line in open(path):
        t = line.split()
        if len(t) < 9 or line.startswith("#"):
            continue
        keys.append(t[0])
        rows.append([float(x) for x in t[1:9]])
    return keys, np.array(rows)


def triangulate(keys, rows):
    by_face = defaultdict(list)
    for i, k in enumerate(keys):
        by_face[k].append(i)
    tris = []
    for idx in by_face.values():
        uv = rows[idx, 0:2]
        us = np.unique(np.round(uv[:, 0], 9))
        n = len(us) - 1
        if n < 1 or len(idx) != (n + 1) ** 2:
            raise SystemExit(f"not a lattice: {len(idx)} points")
        at = {}
        for j, i in enumerate(idx):
            at[(int(round(uv[j, 0] * n)), int(round(uv[j, 1] * n)))] = i
        for a in range(n):
            for b in range(n):
                p00, p10, p11, p01 = at[(a, b)], at[(a + 1, b)], at[(a + 1, b + 1)], at[(a, b + 1)]
                tris.append((p00, p10, p11))
                tris.append((p00, p11, p01))
    return np.array(tris)


def smooth_regions(obj_path):
    """Per base face of the OBJ, the id of its region: faces joined across edges that are not
    infinitely sharp (union-find over shared edges)."""
    faces, sharp = [], set()
    for line in open(obj_path):
        t = line.split()
        if not t:
            continue
        if t[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in t[1:]])
        elif t[0] == "t" and t[1] == "crease" and t[2] == "2/1/0" and float(t[5]) >= 10:
            a, b = int(t[3]), int(t[4])
            sharp.add((min(a, b), max(a, b)))
    parent = list(range(len(faces)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    by_edge = defaultdict(list)
    for f, vs in enumerate(faces):
        for i, a in enumerate(vs):
            b = vs[(i + 1) % len(vs)]
            by_edge[(min(a, b), max(a, b))].append(f)
    for e, fs in by_edge.items():
        if e not in sharp:
            for g in fs[1:]:
                parent[find(g)] = find(fs[0])
    return [find(f) for f in range(len(faces))]


def closest_on_triangles(p, a, b, c):
    """Closest points on triangles (a, b, c) to points p (all (m, 3)); returns points and
    barycentric weights (Ericson, Real-Time Collision Detection 5.1.5, vectorised)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    m = len(p)
    w = np.zeros((m, 3))
    done = np.zeros(m, bool)

    def take(mask, wa, wb, wc):
        nonlocal done
        mask = mask & ~done
        w[mask, 0], w[mask, 1], w[mask, 2] = wa[mask], wb[mask], wc[mask]
        done |= mask

    one, zero = np.ones(m), np.zeros(m)
    with np.errstate(divide="ignore", invalid="ignore"):
        take((d1 <= 0) & (d2 <= 0), one, zero, zero)
        take((d3 >= 0) & (d4 <= d3), zero, one, zero)
        v = d1 / (d1 - d3)
        take((vc <= 0) & (d1 >= 0) & (d3 <= 0), 1 - v, v, zero)
        take((d6 >= 0) & (d5 <= d6), zero, zero, one)
        v = d2 / (d2 - d6)
        take((vb <= 0) & (d2 >= 0) & (d6 <= 0), 1 - v, zero, v)
        v = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        take((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), zero, 1 - v, v)
        den = 1.0 / (va + vb + vc)
        v, u = vb * den, vc * den
        take(np.ones(m, bool), 1 - v - u, v, u)
    q = w[:, 0:1] * a + w[:, 1:2] * b + w[:, 2:3] * c
    return q, w


def main():
    exact_path, other_path, diag = sys.argv[1], sys.argv[2], float(sys.argv[3])
    ekeys, exact = read(exact_path)
    okeys, other = read(other_path)
    if "--faces-from" in sys.argv:
        keep_keys, _ = read(sys.argv[sys.argv.index("--faces-from") + 1])
        keep = {k.split(":")[0] for k in keep_keys}
        other = other[[k.split(":")[0] in keep for k in okeys]]
        okeys = [k for k in okeys if k.split(":")[0] in keep]
    tris = triangulate(ekeys, exact)
    pos, nrm = exact[:, 2:5], exact[:, 5:8]
    cen = pos[tris].mean(axis=1)
    tree = cKDTree(cen)
    q = other[:, 2:5]
    qn = other[:, 5:8]
    one_sided = "--one-sided" in sys.argv
    k = 64 if one_sided else 16
    if one_sided:
        region = smooth_regions(sys.argv[sys.argv.index("--one-sided") + 1])
        tri_region = np.array([region[int(ekeys[t[0]].split(":")[0])] for t in tris])
        q_region = np.array([region[int(key.split(":")[0])] for key in okeys])
    _, cand = tree.query(q, k=k)
    best = np.full(len(q), np.inf)
    bestn = np.zeros((len(q), 3))
    for j in range(k):
        t = tris[cand[:, j]]
        cp, w = closest_on_triangles(q, pos[t[:, 0]], pos[t[:, 1]], pos[t[:, 2]])
        d = np.linalg.norm(q - cp, axis=1)
        n = w[:, 0:1] * nrm[t[:, 0]] + w[:, 1:2] * nrm[t[:, 1]] + w[:, 2:3] * nrm[t[:, 2]]
        better = d < best
        if one_sided:
            better &= tri_region[cand[:, j]] == q_region
        best[better] = d[better]
        bestn[better] = n[better]
    unmatched = 0
    if one_sided:
        found = np.isfinite(best)
        unmatched = int((~found).sum())
        best, bestn, qn = best[found], bestn[found], qn[found]
    bestn /= np.linalg.norm(bestn, axis=1, keepdims=True)
    qn = qn / np.maximum(np.linalg.norm(qn, axis=1, keepdims=True), 1e-300)
    ang = np.arccos(np.clip(np.einsum("ij,ij->i", bestn, qn), -1, 1))
    d = best / diag
    extra = f" (one-sided; {unmatched} points without an own-side triangle left out)" if one_sided else ""
    print(f"points {len(best)}{extra} exact-triangles {len(tris)} distance/diag rms {np.sqrt(np.mean(d*d)):.3e} "
          f"max {d.max():.3e} normal rad rms {np.sqrt(np.mean(ang*ang)):.3e} max {ang.max():.3e}")


main()
