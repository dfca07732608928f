#!/usr/bin/env python3
"""A depth-camera-like cloud from a corpus body: the input issue 37 asks
the reconstruction to accept.

    python3 scripts/depth_cloud.py ../shared/data/corpus body_002 -o body_002_depth.xyz

The body's truth mesh (its unit from the manifest, written in metres) is
sampled area-uniformly and thinned to one point per cube of --spacing
(3 mm: a depth camera's density at 1-2 m); the surface facing away from
one camera in front of the body is dropped (points whose face normal
points backwards, dot(normal, front) < -FACING, FACING 0.3: about the
back third of the skin); 1 mm of Gaussian noise is added, and --clumps
clumps of 150 stray points (2 cm wide) float 0.3-1.2 m from the body.
No normals are written. Deterministic for a given --seed.

Needs numpy and the trigbody package (its reader). The test
`a_depth_camera_s_cloud_without_a_back_is_reconstructed` makes the same
kind of cloud in Rust; docs/global-fit.md has the numbers.
"""
import argparse
import json
from pathlib import Path

import numpy as np
import trigbody

MM = {"m": 1000.0, "cm": 10.0, "mm": 1.0}


def sample(v, f, n, rng):
    """`n` points area-uniform on the triangles, and each point's face."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    face = rng.choice(len(f), size=n, p=area / area.sum())
    r1, r2 = rng.random(n), rng.random(n)
    s = np.sqrt(r1)
    p = a[face] * (1 - s)[:, None] + b[face] * (s * (1 - r2))[:, None] + c[face] * (s * r2)[:, None]
    return p, face


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("corpus", type=Path)
    ap.add_argument("body", help="a body's name in the manifest, e.g. body_002")
    ap.add_argument("-o", "--output", type=Path, required=True)
    ap.add_argument("--spacing", type=float, default=0.003, help="metres (default 0.003)")
    ap.add_argument("--facing", type=float, default=0.3)
    ap.add_argument("--noise", type=float, default=0.001, help="metres (default 0.001)")
    ap.add_argument("--clumps", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    manifest = json.loads((args.corpus / "manifest.json").read_text())
    body = next(b for b in manifest["bodies"] if b["name"] == args.body)
    v, f, _ = trigbody.read_geometry(args.corpus / body["file"])
    v = v * MM[body["units"]] / 1000.0
    f = f.astype(np.int64)
    up, front = np.array(body["up"]), np.array(body["front"])
    rng = np.random.default_rng(args.seed)
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1).sum()
    p, face = sample(v, f, int(8 * area / args.spacing**2), rng)
    _, first = np.unique(np.floor(p / args.spacing).astype(np.int64), axis=0, return_index=True)
    first = np.sort(first)
    p, face = p[first], face[first]
    n = np.cross(v[f[face, 1]] - v[f[face, 0]], v[f[face, 2]] - v[f[face, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
    p = p[n @ front > -args.facing]
    p = p + rng.normal(scale=args.noise, size=p.shape)
    centre = p.mean(axis=0)
    side = np.cross(up, front)
    places = [centre + 0.6 * front + 0.3 * up, centre - 0.2 * up + 0.7 * side, centre + 1.2 * up]
    for c in places[: args.clumps]:
        p = np.vstack([p, c + rng.normal(scale=0.02, size=(150, 3))])
    np.savetxt(args.output, p, fmt="%.5f")
    print(f"{args.output}: {len(p)} points, metres, up {up.tolist()}, front {front.tolist()}")


if __name__ == "__main__":
    main()
