#!/usr/bin/env python3
"""Screened Poisson beside trigbody on the corpus scans, on the same measure.

    python3 scripts/poisson.py ../shared/data/corpus --results RESULTS.csv [--only body_005_scan]

For each scan of the corpus manifest: screened Poisson surface
reconstruction of its points (open3d: normals from 30 neighbours,
oriented consistently, depth 8, the 2 % lowest-density vertices trimmed),
judged against the truth mesh as `trigbody corpus` judges a scan's model:
model -> truth everywhere, truth -> model over the truth within 5 mm of a
scan point (100 000 area-uniform samples each way; symmetric RMS, the
larger p95). With --results (the corpus runner's results.csv) trigbody's
numbers stand beside Poisson's. Prints a markdown table.

Needs open3d and numpy from PyPI (on Debian, open3d's import needs the
package libusb-1.0-0). Not part of the tests: a measurement to rerun.
"""
import argparse
import csv
import json
import sys
from pathlib import Path

import numpy as np
import open3d as o3d

MM = {"m": 1000.0, "cm": 10.0, "mm": 1.0}
SAMPLES = 100_000
SEEN_MM = 5.0


def poisson(points: o3d.geometry.PointCloud, spacing: float) -> o3d.geometry.TriangleMesh:
    points.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=6 * spacing, max_nn=30))
    points.orient_normals_consistent_tangent_plane(15)
    mesh, density = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(points, depth=8)
    density = np.asarray(density)
    mesh.remove_vertices_by_mask(density < np.quantile(density, 0.02))
    # Poisson's normals may face in: the distances do not care.
    return mesh


def distances(mesh: o3d.geometry.TriangleMesh, points: np.ndarray) -> np.ndarray:
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))
    return scene.compute_distance(o3d.core.Tensor(points.astype(np.float32))).numpy()


def judge(truth, model, scan, mm):
    t = np.asarray(truth.sample_points_uniformly(SAMPLES).points)
    m = np.asarray(model.sample_points_uniformly(SAMPLES).points)
    samples = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(t))
    seen = np.asarray(samples.compute_point_cloud_distance(scan)) * mm <= SEEN_MM
    a = distances(model, t[seen]) * mm
    b = distances(truth, m) * mm
    rms = np.sqrt((np.mean(a * a) + np.mean(b * b)) / 2)
    return rms, max(np.quantile(a, 0.95), np.quantile(b, 0.95))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("corpus", type=Path)
    ap.add_argument("--results", type=Path, help="trigbody corpus results.csv")
    ap.add_argument("--only", default="", help="comma-separated scan names")
    args = ap.parse_args()
    manifest = json.loads((args.corpus / "manifest.json").read_text())
    ours = {}
    if args.results:
        with open(args.results) as f:
            ours = {r["input"]: r for r in csv.DictReader(f)}
    only = {s for s in args.only.split(",") if s}
    print("| scan | floor / strays | Poisson RMS / p95 mm | trigbody RMS / p95 mm | ratio RMS / p95 |")
    print("| --- | --- | --- | --- | --- |")
    for body in manifest["bodies"]:
        scan_info = body.get("scan")
        name = body["name"] + "_scan"
        if not scan_info or (only and name not in only):
            continue
        mm = MM[body["units"]]
        truth = o3d.io.read_triangle_mesh(str(args.corpus / body["file"]))
        scan = o3d.io.read_point_cloud(str(args.corpus / scan_info["file"]))
        spacing = np.mean(scan.compute_nearest_neighbor_distance())
        model = poisson(o3d.geometry.PointCloud(scan), spacing)
        rms, p95 = judge(truth, model, scan, mm)
        clutter = f"{scan_info.get('floor_points', 0)} / {scan_info.get('stray_points', 0)}"
        clean = scan_info.get("floor_points", 0) == 0 and scan_info.get("stray_points", 0) == 0
        row = ours.get(name)
        if row and row.get("rms_mm"):
            r, p = float(row["rms_mm"]), float(row["p95_mm"])
            # Raw Poisson closes a floor and strays into the surface: a
            # ratio only where the scan has neither.
            ratio = f"{r / rms:.1f} / {p / p95:.1f}" if clean else "(clutter)"
            print(f"| {name} | {clutter} | {rms:.2f} / {p95:.2f} | {r:.2f} / {p:.2f} | {ratio} |")
        else:
            print(f"| {name} | {clutter} | {rms:.2f} / {p95:.2f} | - | - |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
