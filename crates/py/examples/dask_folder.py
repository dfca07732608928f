"""Reconstruct every body in a folder on a Dask cluster.

Each task reads one mesh or scan, reconstructs it with the trigbody package
and writes ``OUTDIR/NAME.json`` (the model) and ``OUTDIR/NAME.report.json``
(the report): the same files, byte for byte, as ``trigbody batch FOLDER -o
OUTDIR``. A task holds one body at a time (its input, the model and the
report's samples: tens of MB for a 200 000-point scan) and releases the GIL
while it works, so a worker runs as many bodies at once as it has threads.

    python dask_folder.py FOLDER OUTDIR                  # a local cluster of 2 workers
    python dask_folder.py FOLDER OUTDIR --scheduler tcp://host:8786

The folder must be readable at the same path on every worker (a shared
file system or object store mount).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any, Dict, List

import trigbody

# The file types `trigbody batch` reads from a folder.
SUFFIXES = {".obj", ".ply", ".stl", ".xyz", ".csv", ".txt"}


def reconstruct_one(path: str, outdir: str, options: Dict[str, Any]) -> Dict[str, Any]:
    """One task: one body in, its model and report out, a summary row back."""
    started = time.perf_counter()
    stem = Path(path).stem
    row: Dict[str, Any] = {"input": path, "status": "ok", "error": None}
    try:
        model, report = trigbody.reconstruct_file(path, **options)
        model.save(Path(outdir) / f"{stem}.json", overwrite=True)
        report.save(Path(outdir) / f"{stem}.report.json", overwrite=True)
        row["rms_mm"] = report["distance_mm"]["rms"]
        row["design_parameters"] = report["design_parameters"]
    except (ValueError, OSError) as e:
        row.update(status="failed", error=str(e))
    row["seconds"] = time.perf_counter() - started
    return row


def inputs(folder: str) -> List[str]:
    """The mesh and scan files of a folder, sorted (not recursive)."""
    return sorted(
        str(p)
        for p in Path(folder).iterdir()
        if p.is_file() and p.suffix.lower() in SUFFIXES and not p.name.startswith(".")
    )


def run(client: Any, folder: str, outdir: str, **options: Any) -> List[Dict[str, Any]]:
    """Reconstructs every body of ``folder`` on ``client``'s cluster; the
    rows come back in input order."""
    Path(outdir).mkdir(parents=True, exist_ok=True)
    files = inputs(folder)
    futures = client.map(reconstruct_one, files, outdir=str(outdir), options=options, pure=False)
    return client.gather(futures)


def main() -> int:
    from dask.distributed import Client, LocalCluster

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("folder")
    p.add_argument("outdir")
    p.add_argument("--scheduler", help="address of a running scheduler (default: a local cluster)")
    p.add_argument("--workers", type=int, default=2, help="local cluster size (default 2)")
    p.add_argument("--units", default="m", choices=["m", "cm", "mm", "auto"])
    args = p.parse_args()
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        client = Client(LocalCluster(n_workers=args.workers, threads_per_worker=1))
    with client:
        rows = run(client, args.folder, args.outdir, units=args.units)
    for r in rows:
        print(r["status"], r["input"], r["error"] or f"rms {r['rms_mm']:.2f} mm")
    return 1 if any(r["status"] != "ok" for r in rows) else 0


if __name__ == "__main__":
    raise SystemExit(main())
