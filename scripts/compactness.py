#!/usr/bin/env python3
"""Side-by-side compactness benchmark (issue 17): trigbody against QEM
decimation and Draco, in parameters and bytes against symmetric RMS.

    python3 scripts/compactness.py                       # built-in + shared bodies
    python3 scripts/compactness.py --corpus 40           # ... and 40 corpus meshes
    python3 scripts/compactness.py --corpus 0,5,10 --no-bodies --rate-only   # only the --target-rms checks
    python3 scripts/compactness.py --out out/compactness --plot docs/img/compactness.png

A documented tool, not part of CI. It makes its own venv (target/compactness-venv)
with fast_simplification (QEM, Garland-Heckbert quadrics), DracoPy (Draco),
numpy and matplotlib from PyPI, and builds `trigbody` and the
`mesh_distance` example (cargo, release).

Every contender is measured the same way: its surface against the input mesh
by `mesh_distance` (60 000 samples each way, RMS of each direction, symmetric
RMS = sqrt((a^2 + b^2)/2), the reconstruction report's definition), in mm.
trigbody is measured on the written outer skin (`trigbody mesh MODEL --skin
outer --edge 0.004*height`, the edge `reconstruct --mesh` uses) of the file
read back (JSON, and the compact .tbm when the build writes it).

Counted numbers: trigbody, the model's design parameters (the report's,
docs/model-format.md: 9 numbers per section frame) and the numbers its
compact .tbm file stores (3 per frame after a part's first); a mesh, 3 x its vertices (the issue's count,
connectivity not counted). Bytes: the model file (.json, .json.gz, .tbm); a
mesh, its Draco encoding at quantization 8-14 bits (of the full mesh and of
every QEM level). Output: results.json and table.md in --out, a plot PNG.
"""

import argparse
import gzip
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VENV = os.path.join(ROOT, "target", "compactness-venv")
PYPI = ["numpy", "matplotlib", "fast_simplification", "DracoPy"]

# trigbody settings: the coarseness c of `reconstruct --target-rms` (E_a =
# 0.01 c, E_M = 0.05 c, pruning tolerance 0.0003 c and the fingers'
# section spacing 0.008 c of the height, at least 0.004; spacing 0.012),
# c = 1 the defaults.
TRIG_COARSENESS = [0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0]


def trig_flags(c):
    return ["--spacing", "0.012", "--ea", f"{0.01 * c:g}", "--em", f"{0.05 * c:g}",
            "--prune", f"{0.0003 * c:g}", "--digit-spacing", f"{max(0.004, 0.008 * c):g}"]


# QEM: the share of the input's triangles kept.
QEM_KEEP = [0.5, 0.35, 0.25, 0.18, 0.12, 0.08, 0.05, 0.035, 0.025]
DRACO_BITS = [8, 9, 10, 11, 12, 14]
# .tbm quantization steps in mm (None: the default, 0.00002 x the height).
TBM_QUANTA_MM = [None, 0.1, 0.2, 0.4]


def in_venv():
    return os.path.realpath(sys.prefix) == os.path.realpath(VENV)


def ensure_venv():
    """Re-runs this script inside its own venv, making it first."""
    if in_venv():
        return
    py = os.path.join(VENV, "bin", "python")
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
        subprocess.check_call([py, "-m", "pip", "install", "-q", "--upgrade", "pip"])
    subprocess.check_call([py, "-m", "pip", "install", "-q"] + PYPI)
    os.execv(py, [py] + sys.argv)


# ---------------------------------------------------------------- mesh files


def read_obj(path):
    import numpy as np

    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) for t in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(v) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    f.append([idx[0], idx[k], idx[k + 1]])
    return np.array(v, dtype=np.float64), np.array(f, dtype=np.int64)


PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
    "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


def read_ply(path):
    """Binary little-endian or ASCII PLY: vertex x, y, z and face lists."""
    import numpy as np

    with open(path, "rb") as fh:
        data = fh.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = [l.split()[1] for l in header if l.startswith("format")][0]
    elements = []
    for line in header:
        w = line.split()
        if w and w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w and w[0] == "property":
            elements[-1][2].append(w[1:])
    verts, faces = None, []
    if fmt == "ascii":
        tokens = data[end:].split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = []
                for p in props:
                    if p[0] == "list":
                        n = int(tokens[pos]); pos += 1
                        row.append([int(t) for t in tokens[pos:pos + n]]); pos += n
                    else:
                        row.append(float(tokens[pos])); pos += 1
                rows.append(row)
            if name == "vertex":
                names = [p[-1] for p in props]
                ix = [names.index(c) for c in "xyz"]
                verts = np.array([[r[i] for i in ix] for r in rows])
            elif name == "face":
                faces = [r[0] for r in rows]
    else:
        assert fmt == "binary_little_endian", f"{path}: PLY format {fmt}"
        pos = end
        for name, count, props in elements:
            if all(p[0] != "list" for p in props):
                dt = np.dtype([(p[-1], "<" + PLY_TYPES[p[0]]) for p in props])
                arr = np.frombuffer(data, dtype=dt, count=count, offset=pos)
                pos += dt.itemsize * count
                if name == "vertex":
                    verts = np.stack([arr[c].astype(np.float64) for c in "xyz"], axis=1)
                continue
            assert len(props) == 1, f"{path}: face element with extra properties"
            ct, it = PLY_TYPES[props[0][1]], PLY_TYPES[props[0][2]]
            cs, isz = struct.calcsize(ct), struct.calcsize(it)
            rows = []
            for _ in range(count):
                (n,) = struct.unpack_from("<" + ct, data, pos); pos += cs
                rows.append(struct.unpack_from("<%d%s" % (n, it), data, pos)); pos += n * isz
            if name == "face":
                faces = rows
    tris = [[r[0], r[k], r[k + 1]] for r in faces for k in range(1, len(r) - 1)]
    return verts, np.array(tris, dtype=np.int64)


def read_mesh(path):
    return read_obj(path) if path.lower().endswith(".obj") else read_ply(path)


def write_ply(path, v, f):
    import numpy as np

    v = np.ascontiguousarray(v, dtype="<f4")
    f = np.asarray(f, dtype="<i4")
    head = (
        "ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
        "property float x\nproperty float y\nproperty float z\n"
        "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
        % (len(v), len(f))
    )
    rows = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", 3)])
    rows["n"] = 3
    rows["i"] = f
    with open(path, "wb") as fh:
        fh.write(head.encode("ascii"))
        fh.write(v.tobytes())
        fh.write(rows.tobytes())


# --------------------------------------------------------------------- tools


def cargo_build():
    subprocess.check_call(["cargo", "build", "--release", "-q", "-p", "trigbody"], cwd=ROOT)
    subprocess.check_call(
        ["cargo", "build", "--release", "-q", "-p", "trigbody-io", "--example", "mesh_distance"],
        cwd=ROOT,
    )
    rel = os.path.join(ROOT, "target", "release")
    return os.path.join(rel, "trigbody"), os.path.join(rel, "examples", "mesh_distance")


class Tools:
    def __init__(self, trigbody, distance):
        self.trigbody, self.distance_bin = trigbody, distance

    def distance(self, input_path, surface_path, mm_per_unit):
        out = subprocess.run(
            [self.distance_bin, input_path, surface_path, "--mm-per-unit", str(mm_per_unit)],
            check=True, capture_output=True, text=True,
        ).stdout
        return json.loads(out)

    def run(self, args):
        return subprocess.run([self.trigbody] + args, capture_output=True, text=True)


MM_PER_UNIT = {"m": 1000.0, "cm": 10.0, "mm": 1.0}


def inputs(corpus_count):
    """(name, path, units, up axis or None) of every input measured."""
    out = [("mh_male (built-in)", os.path.join(ROOT, "data", "bodies", "mh_male.obj"), "m", None)]
    shared = os.path.join(ROOT, "..", "shared", "data")
    if not os.path.isdir(shared):
        shared = "/work/shared/data"
    if not os.path.isdir(shared):
        print("WARNING: no shared data found: only the built-in body is measured", file=sys.stderr)
        return out
    for f in ("mh_base.obj", "mh_female.ply"):
        out.append((f.split(".")[0], os.path.join(shared, "bodies", f), "m", None))
    manifest = os.path.join(shared, "corpus", "manifest.json")
    if corpus_count and os.path.exists(manifest):
        with open(manifest) as fh:
            bodies = json.load(fh)["bodies"]
        if "," in corpus_count:
            bodies = [bodies[int(i)] for i in corpus_count.split(",")]
        else:
            bodies = bodies[:int(corpus_count)]
        for b in bodies:
            up = ",".join(str(x) for x in b["up"])
            out.append((b["name"], os.path.join(shared, "corpus", b["file"]), b["units"], up))
    return out


# ----------------------------------------------------------------- contenders


def is_tbm(path):
    """Whether the build wrote a compact model (an older build writes JSON
    whatever the extension)."""
    with open(path, "rb") as fh:
        return fh.read(3) == b"TBM"


def trig_points(tools, name, path, units, up, work):
    """One point per setting: parameters, file bytes and RMS of the model."""
    pts = []
    for c in TRIG_COARSENESS:
        tag = f"c{c:g}"
        model = os.path.join(work, f"trig_{tag}.json")
        report = os.path.join(work, f"trig_{tag}_report.json")
        args = ["reconstruct", path, "-o", model, "--report", report, "--force",
                "--units", units] + trig_flags(c)
        if up:
            args += ["--up-axis", up]
        r = tools.run(args)
        if r.returncode != 0:
            print(f"  trigbody {tag}: failed: {r.stderr.strip()[-300:]}", file=sys.stderr)
            continue
        with open(report) as fh:
            rep = json.load(fh)
        params = rep["design_parameters"]
        with open(model) as fh:
            height = json.load(fh)["body"]["height"]
        with open(model, "rb") as fh:
            gz = len(gzip.compress(fh.read(), 9))
        point = {"setting": tag, "coarseness": c, "parameters": params,
                 "compact_numbers": rep["compact_numbers"],
                 "json_bytes": os.path.getsize(model), "json_gz_bytes": gz}
        files = [("json", None, model)]
        for quantum in TBM_QUANTA_MM:
            tbm = os.path.join(work, f"trig_{tag}_{quantum}.tbm")
            r = tools.run(["reconstruct", path, "-o", tbm, "--force", "--units", units]
                          + trig_flags(c)
                          + (["--up-axis", up] if up else [])
                          + (["--quantum", str(quantum)] if quantum else []))
            if r.returncode == 0 and is_tbm(tbm):
                files.append(("tbm", quantum, tbm))
        for kind, quantum, f in files:
            skin = os.path.join(work, f"trig_{tag}_{kind}_skin.ply")
            r = tools.run(["mesh", f, "-o", skin, "--skin", "outer", "--force",
                           "--edge", str(0.004 * height)])
            if r.returncode != 0:
                print(f"  trigbody mesh {f}: {r.stderr.strip()}", file=sys.stderr)
                continue
            d = tools.distance(path, skin, MM_PER_UNIT[units])
            os.remove(skin)
            if kind == "json":
                point["json_rms_mm"] = d["rms_mm"]
                point["json_in_to_model_mm"] = d["a_to_b_mm"]
                point["json_model_to_in_mm"] = d["b_to_a_mm"]
            else:
                point.setdefault("tbm", []).append(
                    {"quantum_mm": quantum or "default", "bytes": os.path.getsize(f),
                     "rms_mm": d["rms_mm"]})
        if "json_rms_mm" in point:
            point["rms_mm"] = point["json_rms_mm"]
            pts.append(point)
            print(f"  trigbody {tag}: {params} parameters, {point['rms_mm']:.3f} mm; .tbm "
                  + ", ".join(f"{t['bytes']} B at {t['rms_mm']:.3f} mm" for t in point.get("tbm", [])))
    return pts


def draco_point(tools, path, units, v, f, bits, work, label):
    import DracoPy
    import numpy as np

    blob = DracoPy.encode(v.astype(np.float32), f.astype(np.uint32),
                          quantization_bits=bits, compression_level=10)
    dec = DracoPy.decode(blob)
    out = os.path.join(work, f"draco_{label}_{bits}.ply")
    write_ply(out, np.asarray(dec.points).reshape(-1, 3), np.asarray(dec.faces).reshape(-1, 3))
    d = tools.distance(path, out, MM_PER_UNIT[units])
    os.remove(out)
    return {"mesh": label, "bits": bits, "bytes": len(blob), "rms_mm": d["rms_mm"],
            "vertices": len(v)}


def mesh_points(tools, path, units, work):
    """QEM levels (parameters = 3 x vertices) and Draco of the full and
    every decimated mesh."""
    import fast_simplification
    import numpy as np

    v, f = read_mesh(path)
    qem, draco = [], []
    for bits in DRACO_BITS:
        draco.append(draco_point(tools, path, units, v, f, bits, work, "full"))
    for keep in QEM_KEEP:
        dv, df = fast_simplification.simplify(v.astype(np.float32), f.astype(np.int32),
                                              target_reduction=1.0 - keep)
        used = np.unique(df)
        remap = np.full(len(dv), -1, dtype=np.int64)
        remap[used] = np.arange(len(used))
        dv, df = dv[used], remap[df]
        out = os.path.join(work, f"qem_{keep}.ply")
        write_ply(out, dv, df)
        d = tools.distance(path, out, MM_PER_UNIT[units])
        os.remove(out)
        qem.append({"keep": keep, "vertices": len(dv), "parameters": 3 * len(dv),
                    "rms_mm": d["rms_mm"]})
        for bits in DRACO_BITS:
            draco.append(draco_point(tools, path, units, dv, df, bits, work, f"qem{keep}"))
    print(f"  QEM: " + ", ".join(f"{q['parameters']}@{q['rms_mm']:.2f}" for q in qem))
    return {"input_vertices": len(v), "qem": qem, "draco": draco}


def rate_points(tools, path, units, up, work, targets, budgets):
    """`reconstruct --target-rms` and `--max-parameters`: what each gave
    (the report's symmetric RMS and parameters) and how long it took."""
    import time

    out = []
    for flag, value in [("--target-rms", t) for t in targets] + \
            [("--max-parameters", n) for n in budgets]:
        report = os.path.join(work, "rate_report.json")
        args = ["reconstruct", path, flag, str(value), "--report", report, "--force",
                "--units", units] + (["--up-axis", up] if up else [])
        start = time.time()
        r = tools.run(args)
        row = {"flag": flag, "value": value, "seconds": time.time() - start,
               "exit": r.returncode}
        if r.returncode == 0:
            with open(report) as fh:
                rep = json.load(fh)
            row["parameters"] = rep["design_parameters"]
            row["rms_mm"] = rep["distance_mm"]["rms"]
            row["met"] = "NOT met" not in r.stdout
        else:
            row["error"] = r.stderr.strip()[-200:]
        print(f"  {flag} {value}: " + (f"{row['parameters']} parameters, {row['rms_mm']:.3f} mm, "
              f"{row['seconds']:.1f} s" if "rms_mm" in row else row["error"]))
        out.append(row)
    return out


def rate_table(results):
    out = ["\n| input | goal | parameters | symmetric RMS (report) | within | time |",
           "| --- | --- | ---: | ---: | --- | ---: |"]
    for res in results:
        for r in res.get("rate", []):
            if "rms_mm" not in r:
                out.append(f"| {res['name']} | {r['flag']} {r['value']} | — | — | error: "
                           f"{r['error'][:60]} | |")
                continue
            if r["flag"] == "--target-rms":
                ok = abs(r["rms_mm"] - r["value"]) <= 0.1 * r["value"]
                within = f"{100 * (r['rms_mm'] / r['value'] - 1):+.1f} % " + ("yes" if ok else "NO")
            else:
                within = "yes" if r["parameters"] <= r["value"] else "NO (over budget)"
            out.append(f"| {res['name']} | {r['flag']} {r['value']} | {r['parameters']} "
                       f"| {r['rms_mm']:.3f} mm | {within} | {r['seconds']:.1f} s |")
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------- the table


def cost_at(points, key, rms, rms_key="rms_mm"):
    """The least `key` reaching `rms`: on the lower convex-free frontier of
    (rms, cost), interpolated in log-log between the neighbouring points;
    None when no point is that accurate."""
    import math

    pts = sorted((p[rms_key], p[key]) for p in points if rms_key in p and key in p)
    front = []
    for r, c in pts:  # Pareto frontier: cost falls as rms rises
        if not front or c < front[-1][1]:
            front.append((r, c))
    if not front or front[0][0] > rms:
        return None
    for (r0, c0), (r1, c1) in zip(front, front[1:]):
        if r0 <= rms <= r1:
            t = (math.log(rms) - math.log(r0)) / (math.log(r1) - math.log(r0))
            return math.exp(math.log(c0) + t * (math.log(c1) - math.log(c0)))
    return front[-1][1]


def summary(results, levels=(1.0, 1.5, 2.0)):
    rows = []
    for res in results:
        row = {"input": res["name"]}
        for lv in levels:
            tp = cost_at(res["trig"], "parameters", lv)
            tc = cost_at(res["trig"], "compact_numbers", lv)
            qp = cost_at(res["qem"], "parameters", lv)
            tb = cost_at([t for p in res["trig"] for t in p.get("tbm", [])], "bytes", lv)
            tj = cost_at(res["trig"], "json_gz_bytes", lv)
            db = cost_at(res["draco"], "bytes", lv)
            row[lv] = (tp, tc, qp, tb, tj, db)
        rows.append(row)
    return rows


def fmt(x, digits=0):
    return "—" if x is None else f"{x:,.{digits}f}".replace(",", " ")


def ratio(a, b):
    return "—" if a is None or b is None else f"{a / b:.2f}"


def table_md(rows, levels=(1.0, 1.5, 2.0)):
    out = []
    for lv in levels:
        out.append(f"\nAt symmetric RMS {lv:g} mm (— : no setting that accurate)\n")
        out.append("| input | trigbody params | .tbm numbers | QEM params (3V) | ratio params "
                   "| ratio .tbm numbers | .tbm bytes | .json.gz bytes "
                   "| Draco bytes (best of full/QEM) | .tbm / Draco |")
        out.append("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for row in rows:
            tp, tc, qp, tb, tj, db = row[lv]
            out.append(f"| {row['input']} | {fmt(tp)} | {fmt(tc)} | {fmt(qp)} | {ratio(tp, qp)} "
                       f"| {ratio(tc, qp)} | {fmt(tb)} | {fmt(tj)} | {fmt(db)} | {ratio(tb, db)} |")
    return "\n".join(out) + "\n"


def plot(results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = results[:4]
    fig, axes = plt.subplots(2, len(shown), figsize=(4.2 * len(shown), 7.5), squeeze=False)
    for k, res in enumerate(shown):
        ax = axes[0][k]
        t = sorted(res["trig"], key=lambda p: p["rms_mm"])
        q = sorted(res["qem"], key=lambda p: p["rms_mm"])
        ax.plot([p["rms_mm"] for p in t], [p["parameters"] for p in t], "o-",
                label="trigbody (design parameters)")
        tc = [p for p in t if "compact_numbers" in p]
        ax.plot([p["rms_mm"] for p in tc], [p["compact_numbers"] for p in tc], "^--",
                label="trigbody (.tbm numbers)")
        ax.plot([p["rms_mm"] for p in q], [p["parameters"] for p in q], "s-", label="QEM (3 x V)")
        ax.set_title(res["name"], fontsize=10)
        ax.set_xlim(0.2, 10)
        ax.set_xlabel("symmetric RMS (mm)")
        ax.set_ylabel("numbers")
        ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        ax = axes[1][k]
        tb = [t for p in res["trig"] for t in p.get("tbm", [])]
        if tb:
            ax.scatter([t["rms_mm"] for t in tb], [t["bytes"] for t in tb], s=14, c="C0",
                       label="trigbody .tbm (settings x quanta)")
        ax.plot([p["rms_mm"] for p in t], [p["json_gz_bytes"] for p in t], "o:",
                label="trigbody .json.gz")
        full = sorted((p for p in res["draco"] if p["mesh"] == "full"), key=lambda p: p["rms_mm"])
        ax.plot([p["rms_mm"] for p in full], [p["bytes"] for p in full], "^-",
                label="Draco, full mesh (8-14 bits)")
        dec = [p for p in res["draco"] if p["mesh"] != "full"]
        ax.scatter([p["rms_mm"] for p in dec], [p["bytes"] for p in dec], s=6, c="grey",
                   label="Draco on QEM meshes")
        ax.set_xlabel("symmetric RMS (mm)")
        ax.set_ylabel("bytes")
        ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
        ax.set_xlim(0.3, 10)
        ax.legend(fontsize=7)
    from matplotlib.ticker import NullFormatter

    for ax in axes.flat:
        ax.xaxis.set_minor_formatter(NullFormatter())
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--corpus", default="0",
                    help="how many corpus meshes (0-40), or their indices (0,5,10)")
    ap.add_argument("--no-bodies", action="store_true", help="leave out the three bodies")
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "compactness"))
    ap.add_argument("--plot", default=os.path.join(ROOT, "docs", "img", "compactness.png"))
    ap.add_argument("--only", help="measure only inputs whose name contains this")
    ap.add_argument("--rate", default="1.0,2.0",
                    help="target RMS values (mm) to check reconstruct --target-rms at ('' for none)")
    ap.add_argument("--budgets", default="5000",
                    help="parameter budgets to check reconstruct --max-parameters at")
    ap.add_argument("--rate-only", action="store_true", help="only the rate-distortion checks")
    ap.add_argument("--bin-dir", help="use trigbody and mesh_distance from here (no cargo build)")
    args = ap.parse_args()
    ensure_venv()
    if args.bin_dir:
        tools = Tools(os.path.join(args.bin_dir, "trigbody"), os.path.join(args.bin_dir, "mesh_distance"))
    else:
        tools = Tools(*cargo_build())
    os.makedirs(args.out, exist_ok=True)
    results = []
    for name, path, units, up in inputs(args.corpus if args.corpus != "0" else None):
        if args.only and args.only not in name:
            continue
        if args.no_bodies and name.startswith("mh_"):
            continue
        print(f"{name} ({path})", flush=True)
        work = tempfile.mkdtemp(prefix="compactness-")
        try:
            res = {"name": name, "path": path, "units": units}
            if not args.rate_only:
                res["trig"] = trig_points(tools, name, path, units, up, work)
                res.update(mesh_points(tools, path, units, work))
            targets = [float(x) for x in args.rate.split(",") if x]
            budgets = [int(x) for x in args.budgets.split(",") if x]
            res["rate"] = rate_points(tools, path, units, up, work, targets, budgets)
            results.append(res)
        finally:
            shutil.rmtree(work)
        with open(os.path.join(args.out, "results.json"), "w") as fh:
            json.dump(results, fh, indent=1)
    table = "" if args.rate_only else table_md(summary(results))
    table += rate_table(results)
    with open(os.path.join(args.out, "table.md"), "w") as fh:
        fh.write(table)
    print(table)
    if not args.rate_only:
        plot(results, args.plot)
    print(f"wrote {args.out}/results.json, {args.out}/table.md, {args.plot}")


if __name__ == "__main__":
    main()
