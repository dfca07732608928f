#!/usr/bin/env python3
"""Cut the example cross-section loops in this folder from the shared bodies.

Provenance script (standard library only): reads a body mesh (OBJ), cuts it
with a plane, chains the crossing segments into closed loops, keeps the loop
that encloses (or is nearest to) a chosen point, and writes it as `x y z`
lines in metres, counter-clockwise about the plane normal.

Usage: python3 cut_loops.py ../../../shared/data/bodies/mh_male.obj
The levels below are given as fractions of the body's height and the chosen
point relative to the body's bounding box, so they are readable, but they were
picked for these A-pose bodies: this is data preparation, not library code.
"""
import math
import sys


def read_obj(path):
    verts, faces = [], []
    for line in open(path, encoding="utf-8"):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            verts.append(tuple(float(x) for x in parts[1:4]))
        elif parts[0] == "f":
            idx = [int(p.split("/")[0]) for p in parts[1:]]
            idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
            for k in range(1, len(idx) - 1):
                faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def section(verts, faces, origin, normal):
    """Closed loops of the mesh ∩ plane, each a list of points."""
    h = [dot(sub(v, origin), normal) for v in verts]
    sign = [1 if x >= 0 else -1 for x in h]
    point_of = {}

    def crossing(i, j):
        key = (min(i, j), max(i, j))
        if key not in point_of:
            t = h[i] / (h[i] - h[j])
            vi, vj = verts[i], verts[j]
            point_of[key] = tuple(vi[k] + t * (vj[k] - vi[k]) for k in range(3))
        return key

    nxt = {}
    for f in faces:
        s = [sign[i] for i in f]
        if s[0] == s[1] == s[2]:
            continue
        keys = []
        for a in range(3):
            i, j = f[a], f[(a + 1) % 3]
            if sign[i] != sign[j]:
                keys.append(crossing(i, j))
        if len(keys) == 2:
            nxt.setdefault(keys[0], []).append(keys[1])
            nxt.setdefault(keys[1], []).append(keys[0])
    loops, seen = [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, prev, cur = [start], None, start
        seen.add(start)
        while True:
            cands = [k for k in nxt[cur] if k != prev and k not in seen]
            if not cands:
                break
            prev, cur = cur, cands[0]
            seen.add(cur)
            loop.append(cur)
        loops.append([point_of[k] for k in loop])
    return loops


def plane_coords(p, origin, normal):
    helper = (1.0, 0.0, 0.0) if abs(normal[0]) < 0.9 else (0.0, 1.0, 0.0)
    e1 = sub(helper, tuple(normal[k] * dot(helper, normal) for k in range(3)))
    n1 = math.sqrt(dot(e1, e1))
    e1 = tuple(x / n1 for x in e1)
    e2 = (normal[1] * e1[2] - normal[2] * e1[1], normal[2] * e1[0] - normal[0] * e1[2], normal[0] * e1[1] - normal[1] * e1[0])
    d = sub(p, origin)
    return dot(d, e1), dot(d, e2)


def signed_area(pts2):
    return 0.5 * sum(pts2[i][0] * pts2[(i + 1) % len(pts2)][1] - pts2[(i + 1) % len(pts2)][0] * pts2[i][1] for i in range(len(pts2)))


def encloses(pts2, q):
    inside = False
    n = len(pts2)
    for i in range(n):
        (x1, y1), (x2, y2) = pts2[i], pts2[(i + 1) % n]
        if (y1 > q[1]) != (y2 > q[1]):
            x = x1 + (q[1] - y1) * (x2 - x1) / (y2 - y1)
            if x > q[0]:
                inside = not inside
    return inside


def pick(loops, origin, normal, target):
    q = plane_coords(target, origin, normal)
    best, best_d = None, float("inf")
    for loop in loops:
        p2 = [plane_coords(p, origin, normal) for p in loop]
        if encloses(p2, q):
            best = loop
            break
        d = min(math.hypot(a - q[0], b - q[1]) for a, b in p2)
        if d < best_d:
            best, best_d = loop, d
    p2 = [plane_coords(p, origin, normal) for p in best]
    if signed_area(p2) < 0:
        best = best[::-1]
    return best


def centroid(pts):
    n = len(pts)
    return tuple(sum(p[k] for p in pts) / n for k in range(3))


def main():
    path = sys.argv[1]
    verts, faces = read_obj(path)
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    height = hi[1] - lo[1]
    up = (0.0, 1.0, 0.0)
    mid_x = 0.5 * (lo[0] + hi[0])
    mid_z = 0.5 * (lo[2] + hi[2])

    def level(frac):
        return (mid_x, lo[1] + frac * height, mid_z)

    out = {}
    # Torso at chest level, waist, and the neck: horizontal, the loop around the body axis.
    for name, frac in [("torso_chest", 0.72), ("torso_waist", 0.62), ("neck", 0.855)]:
        o = level(frac)
        out[name] = pick(section(verts, faces, o, up), o, up, o)
    # A thigh and a calf: horizontal, the loop on the body's left (+x) side.
    for name, frac in [("thigh", 0.40), ("calf", 0.18)]:
        o = level(frac)
        target = (mid_x + 0.25 * (hi[0] - lo[0]) * 0.4, o[1], mid_z)
        out[name] = pick(section(verts, faces, o, up), o, up, target)
    # Upper arm: perpendicular to the arm's own axis (centroids of its
    # horizontal loops at two heights), through their midpoint.
    cs = []
    for frac in (0.66, 0.74):
        o = level(frac)
        target = (lo[0] + 0.22 * (hi[0] - lo[0]), o[1], mid_z)
        cs.append(centroid(pick(section(verts, faces, o, up), o, up, target)))
    axis = sub(cs[0], cs[1])
    n = math.sqrt(dot(axis, axis))
    axis = tuple(x / n for x in axis)
    o = tuple(0.5 * (cs[0][k] + cs[1][k]) for k in range(3))
    out["upper_arm"] = pick(section(verts, faces, o, axis), o, axis, o)
    for name, loop in out.items():
        with open(f"{name}.xyz", "w", encoding="utf-8") as f:
            f.write(f"# {name}: cross-section loop cut from {path.split('/')[-1]} (MakeHuman, CC0)\n")
            f.write(f"# {len(loop)} points, metres, ordered counter-clockwise; made by cut_loops.py\n")
            for p in loop:
                f.write(f"{p[0]:.7f} {p[1]:.7f} {p[2]:.7f}\n")
        print(name, len(loop))


if __name__ == "__main__":
    main()
