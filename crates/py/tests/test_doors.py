"""One behaviour behind every door: the hostile inputs of
`crates/cli/tests/doors.rs`, made again here, give the same status, the
same message and the same exit class through the command line,
`trigbody batch`, the package's `reconstruct_file` and the Dask example's
task, because the checks live in the library."""

import json
import sys

import numpy as np
import pytest

import trigbody
from conftest import BODY, REPO, run_cli

sys.path.insert(0, str(REPO / "crates" / "py" / "examples"))


def _body():
    v, f, _ = trigbody.read_geometry(BODY)
    return v, f.astype(np.int64)


def _obj(v, f):
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in f.tolist()]
    return "\n".join(lines) + "\n"


def _part(v, f, keep):
    """The triangles whose corners all pass `keep`, with only their vertices."""
    tri = f[keep[f].all(axis=1)]
    used, inverse = np.unique(tri, return_inverse=True)
    return _obj(v[used], inverse.reshape(-1, 3))


def _cases(folder):
    """The files and the exit class each must give."""
    v, f = _body()
    two = np.vstack([v, v + [2.0, 0.0, 0.0]])
    two_f = np.vstack([f, f + len(v)])
    nan = v.copy()
    nan[4, 0] = np.nan
    ten = "".join(f"{0.1 * i} {0.17 * i} 0\n" for i in range(10))
    truncated = (
        "ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n0 0 0\n0 1 0\n"
    )
    files = {
        "body.obj": (_obj(v, f), 0),
        "body_in_mm.obj": (_obj(v * 1000.0, f), 2),
        "body_1_7_mm.obj": (_obj(v * 0.001, f), 2),
        "arm.obj": (_part(v, f, (v[:, 0] > 0.25) & (v[:, 1] > 0.0)), 2),
        "nan_vertex.obj": (_obj(nan, f), 2),
        "two_bodies.obj": (_obj(two, two_f), 2),
        "empty.obj": ("", 2),
        "truncated.ply": (truncated, 2),
        "ten_points.xyz": (ten, 2),
    }
    folder.mkdir()
    for name, (text, _) in files.items():
        (folder / name).write_text(text)
    return {name: code for name, (_, code) in files.items()}


def _cli(name):
    p = run_cli("reconstruct", f"in/{name}", check=False)
    errors = [l for l in p.stderr.splitlines() if l.startswith("trigbody: error: ")]
    return p.returncode, errors[0][len("trigbody: error: "):] if errors else ""


def _package(name):
    try:
        trigbody.reconstruct_file(f"in/{name}")
        return 0, ""
    except ValueError as e:
        return 2, str(e)


def _dask_task(name, out):
    import dask_folder

    row = dask_folder.reconstruct_one(f"in/{name}", str(out), {})
    return (0, "") if row["status"] == "ok" else (2, row["error"])


def test_every_door_says_the_same_of_every_hostile_input(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cases = _cases(tmp_path / "in")
    cli = {name: _cli(name) for name in cases}
    for name, code in cases.items():
        assert cli[name][0] == code, (name, cli[name])
    assert "in mm it is 1.67 m tall" in cli["body_in_mm.obj"][1]
    assert "2 separate bodies" in cli["two_bodies.obj"][1]
    assert "non-finite" in cli["nan_vertex.obj"][1]

    batch = run_cli("batch", "in", "-o", "batch", check=False)
    assert batch.returncode == 2, batch.stderr
    rows = [json.loads(l) for l in (tmp_path / "batch" / "summary.jsonl").read_text().splitlines()]
    (tmp_path / "dask").mkdir()
    by_batch = {
        r["input"].split("/")[-1]: (0, "") if r["status"] == "ok" else (2, r["error"]) for r in rows
    }
    for name in cases:
        assert _package(name) == cli[name], name
        assert _dask_task(name, tmp_path / "dask") == cli[name], name
        assert by_batch[name] == cli[name], name


def test_units_auto_through_the_package(tmp_path):
    v, f = _body()
    path = tmp_path / "body_in_mm.obj"
    path.write_text(_obj(v * 1000.0, f))
    with pytest.raises(ValueError, match="in mm it is 1.67 m tall"):
        trigbody.reconstruct_file(path)
    with pytest.raises(ValueError, match=str(path)):
        trigbody.reconstruct_file(path)
    model, report = trigbody.reconstruct_file(path, units="auto")
    assert (report["units"], report["units_inferred"]) == ("mm", True)
    assert model.units == "mm"
    _, given = trigbody.reconstruct_file(path, units="mm")
    assert given["units_inferred"] is False
    assert abs(given["distance_mm"]["rms"] - report["distance_mm"]["rms"]) < 1e-9
    with pytest.raises(ValueError, match="are not m, cm, mm or auto"):
        trigbody.reconstruct_file(path, units="inch")
