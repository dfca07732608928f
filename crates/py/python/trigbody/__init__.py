"""trigbody: compact, smooth human body models from trigonometric
cross-section curves, numpy in and numpy out.

>>> import numpy as np, trigbody
>>> t = np.linspace(0, 2 * np.pi, 50, endpoint=False)
>>> curve = trigbody.fit_curve(np.c_[0.1 * np.cos(t), 0.1 * np.sin(t)])
>>> curve.order
1

Every long call releases the GIL. Bad input (NaN, wrong shapes, empty
arrays, a file that cannot be read, no body) raises ``ValueError`` with the
message the ``trigbody`` command line prints.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from typing import Any, Iterator, Optional, Sequence, Tuple, Union

import numpy as np

from . import _trigbody
from ._trigbody import Curve, Model, Part, load_model

__all__ = [
    "Curve",
    "Model",
    "Part",
    "Report",
    "fit_curve",
    "load_model",
    "read_geometry",
    "reconstruct",
    "reconstruct_file",
    "cli",
]

_AXES = {
    "x": (1.0, 0.0, 0.0),
    "y": (0.0, 1.0, 0.0),
    "z": (0.0, 0.0, 1.0),
    "-x": (-1.0, 0.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "-z": (0.0, 0.0, -1.0),
}


class Report(Mapping):
    """The report of a reconstruction: a read-only mapping with the keys of
    ``trigbody reconstruct --report`` (``design_parameters``,
    ``distance_mm``, ``coverage``, ``parts``, ``warnings``, ...)."""

    def __init__(self, text: str, seconds: Optional[float] = None) -> None:
        self._text = text
        self._data = json.loads(text)
        #: The seconds the library's reconstruction took (None for a report
        #: read from a file); the rest of ``reconstruct``'s time is the
        #: package's own (numpy in, model and report out).
        self.seconds = seconds

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def to_json(self) -> str:
        """The report as the JSON text ``trigbody reconstruct --report`` writes."""
        return self._text

    def save(self, path: Union[str, os.PathLike], overwrite: bool = False) -> None:
        """Writes the report file (the bytes the CLI writes); an existing file
        is kept unless ``overwrite``."""
        mode = "w" if overwrite else "x"
        try:
            with open(path, mode, encoding="utf-8", newline="\n") as f:
                f.write(self._text)
        except FileExistsError:
            raise FileExistsError(
                f"{os.fspath(path)}: already exists; pass overwrite=True to replace it"
            ) from None

    def __repr__(self) -> str:
        d = self._data["distance_mm"]
        return (
            f"Report(design_parameters={self._data['design_parameters']}, "
            f"rms_mm={d['rms']:.3f}, coverage={self._data['coverage']:.4f})"
        )


def _float_array(name: str, a: Any, columns: Sequence[int]) -> np.ndarray:
    """``a`` as a C-contiguous float64 array of shape (N, c), c in
    ``columns`` (no copy when it already is one)."""
    arr = np.asarray(a)
    if arr.dtype.kind not in "fiu":
        raise ValueError(f"{name} must hold numbers; got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] not in columns:
        cols = " or ".join(str(c) for c in columns)
        raise ValueError(f"{name} must be an (N, {cols}) array; got shape {arr.shape}")
    return np.ascontiguousarray(arr, dtype=np.float64)


def _faces(faces: Any, vertices: int) -> np.ndarray:
    arr = np.asarray(faces)
    if arr.dtype.kind not in "iu":
        raise ValueError(f"faces must hold whole numbers; got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"faces must be an (M, 3) array of vertex indices; got shape {arr.shape}")
    if arr.size and arr.min() < 0:
        raise ValueError(f"faces refer to vertex {int(arr.min())}: indices start at 0")
    if arr.size and arr.max() > np.iinfo(np.uint32).max:
        raise ValueError(f"faces refer to vertex {int(arr.max())}, beyond 2^32 - 1")
    return np.ascontiguousarray(arr, dtype=np.uint32)


def _direction(name: str, d: Any) -> Optional[Tuple[float, float, float]]:
    if d is None:
        return None
    if isinstance(d, str):
        try:
            return _AXES[d.strip().lower().lstrip("+")]
        except KeyError:
            raise ValueError(f"{name} '{d}' is not x, y, z, -x, -y, -z or three numbers") from None
    v = np.asarray(d, dtype=np.float64)
    if v.shape != (3,):
        raise ValueError(f"{name} must be an axis name or three numbers; got shape {v.shape}")
    return (float(v[0]), float(v[1]), float(v[2]))


def fit_curve(
    points: Any,
    order: Union[str, int] = "auto",
    ea: float = 0.01,
    em: float = 0.05,
    *,
    smoothing: float = 0.0,
    noise: float = 0.0,
) -> Curve:
    """Fits a trigonometric curve to one closed loop of points.

    ``points`` is an (N, 2) or (N, 3) array ordered along the loop; ``order``
    is ``"auto"`` (the smallest order meeting both tolerances) or a whole
    number; ``ea`` and ``em`` are the average and maximum relative error
    tolerances (paper Eq. 12); ``smoothing`` a penalty on high harmonics
    (bridges gaps); ``noise`` the points' scatter (standard deviation, in
    their units), under which ``"auto"`` does not fit. The same fit as
    ``trigbody fit --order ORDER --ea EA --em EM --smoothing S --noise N``
    (``Curve.fit_json`` is its ``--json`` output)."""
    return _trigbody.fit_curve(
        _float_array("points", points, (2, 3)), order, float(ea), float(em), float(smoothing), float(noise)
    )


def read_geometry(path: Union[str, os.PathLike]):
    """Reads a mesh (.obj, .ply, .stl) or a scan (.ply points, .xyz):
    ``(vertices, faces, normals)`` with vertices float64 (N, 3), faces
    uint32 (M, 3) or None for a scan, normals float64 (N, 3) or None."""
    return _trigbody.read_geometry(os.fspath(path))


def reconstruct(
    vertices: Any,
    faces: Any = None,
    *,
    normals: Any = None,
    units: str = "m",
    up: Any = None,
    front: Any = None,
    spacing: Optional[float] = None,
    ea: Optional[float] = None,
    em: Optional[float] = None,
    prune: Optional[float] = None,
    scan_frames: Optional[int] = None,
    fit: Optional[str] = None,
) -> Tuple[Model, Report]:
    """Reconstructs a body model from a mesh (``faces`` given) or a scan.

    ``vertices`` (N, 3) in ``units`` ("m", "cm", "mm", or "auto": the one
    that makes the body a human height, 0.4-2.6 m; the report's ``units``
    says which, and a body no unit or several fit raises); ``faces`` (M, 3)
    vertex indices, or None for a point cloud; ``normals`` (N, 3) or None;
    ``up`` and ``front`` an axis name ("y", "-z", ...) or three numbers
    (default: found from the data); ``spacing`` (fraction of the height),
    ``ea``, ``em``, ``prune`` (a section goes where the others' skinning
    passes its loop within this fraction of the height; 0 keeps every
    section) and ``scan_frames`` (a scan is reconstructed in that
    many frames turned about its up axis, 1-6, and the model nearest it
    kept) and ``fit`` ("auto": scans are fitted to their points by least
    squares after the parts are built, "global": meshes too, "none") as
    ``trigbody reconstruct`` (None: its defaults).
    Returns the model and its report, the same as ``trigbody reconstruct
    -o MODEL --report REPORT`` on a file holding the same geometry."""
    v = _float_array("vertices", vertices, (3,))
    f = None if faces is None else _faces(faces, len(v))
    n = None if normals is None else _float_array("normals", normals, (3,))
    options = {
        "units": units,
        "up": _direction("up", up),
        "front": _direction("front", front),
        "spacing": spacing,
        "ea": ea,
        "em": em,
        "prune": prune,
        "scan_frames": scan_frames,
        "fit": fit,
    }
    model, report, seconds = _trigbody.reconstruct(v, f, n, options)
    return model, Report(report, seconds)


def reconstruct_file(path: Union[str, os.PathLike], **options: Any) -> Tuple[Model, Report]:
    """``reconstruct`` on the geometry of a mesh or scan file (what
    ``trigbody reconstruct FILE`` and ``trigbody batch`` do per file); an
    error names the file, as theirs do."""
    v, f, n = read_geometry(path)
    try:
        return reconstruct(v, f, normals=n, **options)
    except ValueError as e:
        raise ValueError(f"{os.fspath(path)}: {e}") from e


def cli(args: Sequence[str]) -> int:
    """Runs the ``trigbody`` command line on ``args`` (without the program
    name) and returns its exit code; ``python -m trigbody`` calls it."""
    return _trigbody.cli([str(a) for a in args])
