"""Shared fixtures: the repository, the CLI binary the package is compared
with, and one reconstruction of the built-in body by the CLI."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
BIN = Path(os.environ.get("TRIGBODY_BIN", REPO / "target" / "release" / "trigbody"))
SHARED = Path(os.environ.get("TRIGBODY_DATA", REPO.parent / "shared" / "data"))
BODY = REPO / "data" / "bodies" / "mh_male.obj"
LOOPS = REPO / "data" / "loops"


def run_cli(*args, check=True):
    """Runs the trigbody binary; returns the completed process."""
    if not BIN.is_file():
        pytest.fail(f"the trigbody binary is not at {BIN}: run `cargo build --release` first")
    p = subprocess.run([str(BIN), *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        pytest.fail(f"trigbody {' '.join(map(str, args))} exited {p.returncode}:\n{p.stderr}")
    return p


def run_module(*args):
    """Runs `python -m trigbody ARGS` in a fresh interpreter."""
    return subprocess.run(
        [sys.executable, "-m", "trigbody", *map(str, args)], capture_output=True, text=True
    )


def shared(relative):
    """A file of the shared data, or None (said loudly) when it is absent."""
    p = SHARED / relative
    if not p.is_file():
        print(f"\nNOTE: shared data {p} is absent; the test uses the repository's body instead")
        return None
    return p


@pytest.fixture(scope="session")
def cli_model(tmp_path_factory):
    """The built-in body reconstructed by the CLI: (model path, report path)."""
    d = tmp_path_factory.mktemp("cli")
    model, report = d / "m.json", d / "r.json"
    run_cli("reconstruct", BODY, "-o", model, "--report", report)
    return model, report


@pytest.fixture(scope="session")
def py_result():
    """The built-in body reconstructed by the package: (Model, Report)."""
    import trigbody

    v, f, n = trigbody.read_geometry(BODY)
    return trigbody.reconstruct(v, f, normals=n)
