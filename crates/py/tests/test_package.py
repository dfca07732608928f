"""The Python package against the CLI on the same input: the same model
bytes, the same report numbers, dtypes and shapes, and bad input raising
ValueError with the library's message."""

import json
import pickle
import re
import time
from pathlib import Path

import numpy as np
import pytest

import trigbody
from conftest import BODY, LOOPS, REPO, run_cli, run_module


def loop(name):
    return np.loadtxt(LOOPS / f"{name}.xyz")


# --- fit_curve -------------------------------------------------------------


@pytest.mark.parametrize("name", ["neck", "thigh", "torso_waist"])
def test_fit_curve_is_the_cli_fit(name):
    points = loop(name)
    curve = trigbody.fit_curve(points)
    cli = run_cli("fit", LOOPS / f"{name}.xyz", "--json").stdout
    assert curve.fit_json == cli
    expected = json.loads(cli)
    assert curve.order == expected["order"]
    assert curve.a.dtype == np.float64 and curve.a.shape == (2 * curve.order + 1,)
    assert curve.a.tolist() == expected["a"] and curve.b.tolist() == expected["b"]
    assert curve.frame["origin"].tolist() == expected["frame"]["origin"]
    assert curve.errors["ea"] == expected["ea"] and curve.errors["em"] == expected["em"]
    assert curve.met is expected["met"]


def test_fit_curve_options_and_evaluate():
    points = loop("calf")
    curve = trigbody.fit_curve(points, order=3, ea=0.02, em=0.1)
    cli = run_cli("fit", LOOPS / "calf.xyz", "--json", "--order", "3", "--ea", "0.02", "--em", "0.1")
    assert curve.fit_json == cli.stdout
    assert curve.order == 3
    v = np.linspace(0, 2 * np.pi, 7)
    p = curve.evaluate(v)
    assert p.dtype == np.float64 and p.shape == (7, 3)
    assert np.allclose(p[0], p[-1])  # closed
    # The fitted curve passes near the loop: within its largest error.
    dist = np.min(np.linalg.norm(points[:, None, :] - curve.evaluate(np.linspace(0, 2 * np.pi, 2000))[None], axis=2), axis=1)
    assert dist.max() < 2 * curve.errors["max"] + 1e-9


def test_fit_curve_noise_and_smoothing_are_the_cli_flags():
    points = loop("calf")
    curve = trigbody.fit_curve(points, smoothing=1e-5, noise=0.002)
    cli = run_cli("fit", LOOPS / "calf.xyz", "--json", "--smoothing", "1e-5", "--noise", "0.002")
    assert curve.fit_json == cli.stdout
    # 2 mm of scatter on a calf allows a lower order than none.
    assert curve.order < trigbody.fit_curve(points, smoothing=1e-5).order
    with pytest.raises(ValueError, match="noise"):
        trigbody.fit_curve(points, noise=-1)


def test_fit_curve_2d_circle_is_order_1():
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    curve = trigbody.fit_curve(np.c_[0.2 * np.cos(t), 0.2 * np.sin(t)])
    assert curve.order == 1
    assert curve.perimeter == pytest.approx(2 * np.pi * 0.2, rel=1e-9)


@pytest.mark.parametrize(
    "points, message",
    [
        (np.zeros((0, 2)), "no points"),
        (np.array([[0.0, 0.0], [1.0, np.nan], [1.0, 1.0], [0.0, 1.0]]), "point 1 is not finite"),
        (np.zeros((5, 4)), r"must be an \(N, 2 or 3\) array; got shape \(5, 4\)"),
        (np.zeros(6), r"got shape \(6,\)"),
        (np.array([["a", "b"]]), "must hold numbers"),
    ],
)
def test_fit_curve_bad_input(points, message):
    with pytest.raises(ValueError, match=message):
        trigbody.fit_curve(points)


def test_fit_curve_bad_options_match_the_cli():
    with pytest.raises(ValueError) as e:
        trigbody.fit_curve(loop("calf"), ea=-1)
    cli = run_cli("fit", LOOPS / "calf.xyz", "--ea=-1", check=False)
    assert cli.returncode == 2
    assert str(e.value) in cli.stderr
    with pytest.raises(ValueError, match="order"):
        trigbody.fit_curve(loop("calf"), order=0)


# --- reconstruct, Model, Report --------------------------------------------


def test_reconstruct_writes_the_cli_model_and_report(cli_model, py_result, tmp_path):
    model_path, report_path = cli_model
    model, report = py_result
    model.save(tmp_path / "m.json")
    assert (tmp_path / "m.json").read_bytes() == model_path.read_bytes()
    assert model.to_bytes() == model_path.read_bytes()
    report.save(tmp_path / "r.json")
    assert (tmp_path / "r.json").read_bytes() == report_path.read_bytes()
    expected = json.loads(report_path.read_text())
    assert dict(report) == expected
    assert report["distance_mm"]["rms"] == expected["distance_mm"]["rms"]
    assert set(report) >= {"design_parameters", "coverage", "parts", "warnings"}
    with pytest.raises(FileExistsError, match="overwrite=True"):
        model.save(tmp_path / "m.json")


def test_reconstruct_takes_other_dtypes_and_options(py_result):
    v, f, _ = trigbody.read_geometry(BODY)
    # Fortran order and int64 faces: converted, the same model.
    model, report = trigbody.reconstruct(np.asfortranarray(v), f.astype(np.int64))
    assert model.to_bytes() == py_result[0].to_bytes()
    # The same body in millimetres, up given: the same body, scaled.
    mm, rep_mm = trigbody.reconstruct(v * 1000.0, f, units="mm", up="y")
    assert mm.units == "mm"
    assert mm.height == pytest.approx(1000.0 * py_result[0].height, rel=1e-3)
    assert rep_mm["distance_mm"]["rms"] == pytest.approx(py_result[1]["distance_mm"]["rms"], rel=0.1)


def test_read_geometry_dtypes_and_shapes():
    v, f, n = trigbody.read_geometry(BODY)
    assert v.dtype == np.float64 and v.ndim == 2 and v.shape[1] == 3
    assert f.dtype == np.uint32 and f.shape[1] == 3 and f.max() < len(v)
    assert n is None or n.shape == v.shape
    with pytest.raises(ValueError, match="nothing.obj"):
        trigbody.read_geometry("nothing.obj")


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        (np.full((4, 3), np.nan), np.array([[0, 1, 2]]), r"vertex 0 has a non-finite coordinate"),
        (np.zeros((0, 3)), np.zeros((0, 3), dtype=np.uint32), "the mesh has no vertices"),
        (np.eye(3), np.zeros((0, 3), dtype=np.uint32), "the mesh has no triangles"),
        (np.zeros((0, 3)), None, "no"),
        (np.zeros((4, 2)), None, r"vertices must be an \(N, 3\) array; got shape \(4, 2\)"),
        (np.zeros((12,)), None, r"got shape \(12,\)"),
        (np.eye(3), np.array([[0, 1, 5]]), "refers to vertex 5, but there are only 3 vertices"),
        (np.eye(3), np.array([[0, 1, -1]]), "indices start at 0"),
        (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "whole numbers"),
        (np.eye(3), np.array([0, 1, 2]), r"faces must be an \(M, 3\)"),
    ],
)
def test_reconstruct_bad_input(vertices, faces, message):
    with pytest.raises(ValueError, match=message):
        trigbody.reconstruct(vertices, faces)


def test_reconstruct_bad_options():
    v, f, _ = trigbody.read_geometry(BODY)
    with pytest.raises(ValueError, match="units 'inch'"):
        trigbody.reconstruct(v, f, units="inch")
    with pytest.raises(ValueError, match="up 'w'"):
        trigbody.reconstruct(v, f, up="w")
    with pytest.raises(ValueError, match="not a direction"):
        trigbody.reconstruct(v, f, up=(0, 0, 0))
    with pytest.raises(ValueError, match="scan_frames"):
        trigbody.reconstruct(v, f, scan_frames=0)
    with pytest.raises(ValueError, match="fit 'bogus' is not auto, global or none"):
        trigbody.reconstruct(v, f, fit="bogus")
    with pytest.raises(ValueError, match="prune_tolerance"):
        trigbody.reconstruct(v, f, prune=-1.0)


def test_reconstruct_without_pruning_keeps_every_section(py_result):
    v, f, _ = trigbody.read_geometry(BODY)
    model, report = trigbody.reconstruct(v, f, prune=0.0)
    pruned = py_result[1]
    assert report["design_parameters"] > 1.2 * pruned["design_parameters"]
    assert report["compact_numbers"] < report["design_parameters"]
    assert pruned["distance_mm"]["rms"] < 1.1 * report["distance_mm"]["rms"]


def test_no_body_is_the_cli_message(tmp_path):
    # A small flat sheet of points: no body to find.
    g = np.stack(np.meshgrid(np.linspace(0, 1, 30), np.linspace(0, 1, 30)), -1).reshape(-1, 2)
    pts = np.c_[g, np.zeros(len(g))]
    np.savetxt(tmp_path / "sheet.xyz", pts, fmt="%.17g")
    with pytest.raises(ValueError) as e:
        trigbody.reconstruct(pts)
    cli = run_cli("reconstruct", tmp_path / "sheet.xyz", check=False)
    assert cli.returncode == 2
    assert str(e.value) in cli.stderr


def test_load_model_and_parts(cli_model, tmp_path):
    model_path, _ = cli_model
    model = trigbody.load_model(model_path)
    model.save(tmp_path / "again.json")
    assert (tmp_path / "again.json").read_bytes() == model_path.read_bytes()
    doc = json.loads(model_path.read_text())
    assert [p.name for p in model.parts] == [p["name"] for p in doc["parts"]]
    torso = model.parts[0]
    assert torso.cavity_of is None
    assert any(p.cavity_of == "head" for p in model.parts)
    k = len(torso.sections)
    assert k > 5 and torso.knots.shape == (k,) and torso.knots.dtype == np.float64
    pts = torso.section_points(16)
    assert pts.shape == (k, 16, 3) and pts.dtype == np.float64
    s0 = torso.sections[0]
    assert s0.errors is None and s0.a.shape == (2 * s0.order + 1,)
    assert np.allclose(s0.evaluate(np.linspace(0, 2 * np.pi, 16, endpoint=False)), pts[0])
    with pytest.raises(ValueError, match="nothing.json"):
        trigbody.load_model(tmp_path / "nothing.json")
    (tmp_path / "bad.json").write_text('{"format": "trigbody-model", "version": 5')
    with pytest.raises(ValueError, match="bad.json"):
        trigbody.load_model(tmp_path / "bad.json")


def read_obj(path):
    v, f = [], []
    for line in Path(path).read_text().splitlines():
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            f.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.array(v), np.array(f)


def test_tessellate_is_the_cli_mesh(cli_model, tmp_path):
    model_path, _ = cli_model
    model = trigbody.load_model(model_path)
    run_cli("mesh", model_path, "-o", tmp_path / "m.obj", "--edge", "0.02", "--skin", "whole")
    v, f = model.tessellate(edge=0.02)
    assert v.dtype == np.float64 and f.dtype == np.uint32
    assert v.shape[1] == 3 and f.shape[1] == 3
    ov, of = read_obj(tmp_path / "m.obj")
    assert v.shape == ov.shape and f.shape == of.shape
    assert np.array_equal(f, of)
    assert np.allclose(v, ov, atol=1e-6)
    outer_v, outer_f = model.tessellate(edge=0.02, skin="outer")
    assert len(outer_f) < len(f)
    with pytest.raises(ValueError, match="edge"):
        model.tessellate(edge=-1.0)


def test_to_trimesh(cli_model):
    model = trigbody.load_model(cli_model[0])
    try:
        import trimesh  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="pip install trimesh"):
            model.to_trimesh(edge=0.03)
        return
    mesh = model.to_trimesh(edge=0.03)
    v, f = model.tessellate(edge=0.03)
    assert np.array_equal(mesh.vertices, v) and np.array_equal(mesh.faces, f)


def test_measure_is_the_cli_measure(cli_model):
    model_path, _ = cli_model
    m = trigbody.load_model(model_path).measure()
    cli = json.loads(run_cli("measure", model_path, "--json").stdout)
    assert {x["name"]: x["value"] for x in cli["measurements"]} == {
        k: v for k, v in m.items() if k not in ("volume", "surface_area")
    }
    assert m["volume"] == cli["volume"]["value"]
    assert m["surface_area"] == cli["surface_area"]["value"]
    assert 1.6 < m["stature"] < 1.9


def test_measure_refuses_a_loft(tmp_path):
    # A model of parts without a body (a loft) has no frame to measure.
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    curves = []
    for z in (0.0, 0.1, 0.2):
        c = trigbody.fit_curve(np.c_[0.1 * np.cos(t), 0.1 * np.sin(t), np.full(40, z)])
        doc = json.loads(c.fit_json)
        curves.append({"frame": doc["frame"], "a": doc["a"], "b": doc["b"]})
    (tmp_path / "curves.json").write_text(json.dumps({"curves": curves}))
    run_cli("loft", tmp_path / "curves.json", "-o", tmp_path / "loft.json")
    with pytest.raises(ValueError, match="body frame"):
        trigbody.load_model(tmp_path / "loft.json").measure()


def test_pickle_round_trip(py_result):
    model, report = py_result
    again = pickle.loads(pickle.dumps(model))
    assert again.to_bytes() == model.to_bytes()


def test_python_m_trigbody_is_the_cli(tmp_path):
    args = ["fit", LOOPS / "neck.xyz", "--json"]
    p = run_module(*args)
    assert p.returncode == 0, p.stderr
    assert p.stdout == run_cli(*args).stdout
    bad = run_module("fit", tmp_path / "missing.xyz")
    assert bad.returncode == 2 and "missing.xyz" in bad.stderr
    assert run_module("no-such-command").returncode == 2
    assert "batch" in run_module("--help").stdout


def test_readme_python_example_runs(tmp_path, monkeypatch):
    readme = (REPO / "README.md").read_text()
    section = readme.split("## Python", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert len(code.strip().splitlines()) == 5, code
    monkeypatch.chdir(REPO)
    exec(compile(code, "README.md", "exec"), {})


def test_reconstruct_releases_the_gil():
    # While one thread reconstructs, another keeps running Python: with the
    # GIL held it could not come back from its sleeps until the call ended.
    import threading

    v, f, _ = trigbody.read_geometry(BODY)
    entered, results = threading.Event(), []

    def work():
        entered.set()
        results.append(trigbody.reconstruct(v, f))

    worker = threading.Thread(target=work)
    worker.start()
    entered.wait()
    ticks = 0
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert results and results[0][1].seconds > 0
    assert ticks >= 20, f"the main thread ran only {ticks} times during the call"
