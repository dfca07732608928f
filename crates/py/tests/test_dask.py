"""The Dask example on a local cluster of 2 workers writes the same models
and reports as `trigbody batch` on the same folder."""

import shutil
import sys
from pathlib import Path

import pytest

from conftest import BODY, REPO, run_cli, shared

sys.path.insert(0, str(REPO / "crates" / "py" / "examples"))


def test_dask_local_cluster_writes_the_batch_models(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    import dask_folder

    folder = tmp_path / "bodies"
    folder.mkdir()
    shutil.copy(BODY, folder / "mh_male.obj")
    # A second, smaller body from the shared corpus (metres, y up).
    other = shared("corpus/body_002.ply")
    shutil.copy(other or BODY, folder / ("body_002.ply" if other else "copy.obj"))
    (folder / "notes.md").write_text("not a body: ignored by both")

    run_cli("batch", folder, "-o", tmp_path / "batch", "--jobs", "2")
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        rows = dask_folder.run(client, str(folder), str(tmp_path / "dask"))
    assert [r["status"] for r in rows] == ["ok", "ok"], rows
    written = sorted(p.name for p in (tmp_path / "dask").iterdir())
    assert len(written) == 4, written
    for name in written:
        assert (tmp_path / "dask" / name).read_bytes() == (tmp_path / "batch" / name).read_bytes(), name
