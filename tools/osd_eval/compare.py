#!/usr/bin/env python3
"""Point-by-point comparison of two `f u v x y z nx ny nz` files (e.g. `tessera limit --grid N` and
osd_eval at the same grid): distance at equal (face, u, v) as a fraction of the bbox diagonal given,
and the angle between the normals; RMS and max over the keys both files have.

    compare.py EXACT.txt OTHER.txt DIAGONAL [--quads-only] [--only TYPE TYPED.txt]

`--only TYPE TYPED.txt` keeps the keys whose line in TYPED.txt (a file with the patch type appended
as the tenth column, as `examples/adaptive_grid.rs` and `tessera sample --scheme adaptive` write)
names TYPE, e.g. `end-cap`: OpenSubdiv's figure over the points where tessera draws an end cap.
"""
import math
import sys


def read(path, quads_only):
    out = {}
    for line in open(path):
        t = line.split()
        if len(t) < 9 or line.startswith("#") or (quads_only and ":" in t[0]):
            continue
        key = (t[0], round(float(t[1]), 9), round(float(t[2]), 9))
        out[key] = ([float(x) for x in t[3:6]], [float(x) for x in t[6:9]])
    return out


def main():
    exact_path, other_path, diag = sys.argv[1], sys.argv[2], float(sys.argv[3])
    quads_only = "--quads-only" in sys.argv
    exact, other = read(exact_path, quads_only), read(other_path, quads_only)
    keys = set(exact) & set(other)
    if "--only" in sys.argv:
        i = sys.argv.index("--only")
        kind, typed = sys.argv[i + 1], sys.argv[i + 2]
        keep = set()
        for line in open(typed):
            t = line.split()
            if len(t) >= 10 and t[9] == kind and not (quads_only and ":" in t[0]):
                keep.add((t[0], round(float(t[1]), 9), round(float(t[2]), 9)))
        keys &= keep
    keys = sorted(keys)
    d2 = dmax = a2 = amax = 0.0
    for k in keys:
        (p, n), (q, m) = exact[k], other[k]
        d = math.dist(p, q) / diag
        c = sum(x * y for x, y in zip(n, m))
        a = math.acos(max(-1.0, min(1.0, c))) if any(m) else math.pi
        d2, dmax, a2, amax = d2 + d * d, max(dmax, d), a2 + a * a, max(amax, a)
    n = max(len(keys), 1)
    print(f"points {len(keys)} (exact {len(exact)}, other {len(other)}) "
          f"distance/diag rms {math.sqrt(d2 / n):.3e} max {dmax:.3e} "
          f"normal rad rms {math.sqrt(a2 / n):.3e} max {amax:.3e}")


main()
