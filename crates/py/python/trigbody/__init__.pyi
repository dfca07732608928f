"""Type stubs of the trigbody package."""

from collections.abc import Mapping
from os import PathLike
from typing import Any, Iterator, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._trigbody import Curve as Curve, Model as Model, Part as Part, load_model as load_model

_Path = Union[str, PathLike]
_Direction = Union[str, Sequence[float], npt.ArrayLike, None]

class Report(Mapping[str, Any]):
    seconds: Optional[float]
    def __init__(self, text: str, seconds: Optional[float] = None) -> None: ...
    def __getitem__(self, key: str) -> Any: ...
    def __iter__(self) -> Iterator[str]: ...
    def __len__(self) -> int: ...
    def to_json(self) -> str: ...
    def save(self, path: _Path, overwrite: bool = False) -> None: ...

def fit_curve(
    points: npt.ArrayLike,
    order: Union[str, int] = "auto",
    ea: float = 0.01,
    em: float = 0.05,
    *,
    smoothing: float = 0.0,
    noise: float = 0.0,
) -> Curve: ...
def read_geometry(
    path: _Path,
) -> Tuple[npt.NDArray[np.float64], Optional[npt.NDArray[np.uint32]], Optional[npt.NDArray[np.float64]]]: ...
def reconstruct(
    vertices: npt.ArrayLike,
    faces: Optional[npt.ArrayLike] = None,
    *,
    normals: Optional[npt.ArrayLike] = None,
    units: str = "m",
    up: _Direction = None,
    front: _Direction = None,
    spacing: Optional[float] = None,
    ea: Optional[float] = None,
    em: Optional[float] = None,
    prune: Optional[float] = None,
    scan_frames: Optional[int] = None,
    fit: Optional[str] = None,
) -> Tuple[Model, Report]: ...
def reconstruct_file(path: _Path, **options: Any) -> Tuple[Model, Report]: ...
def cli(args: Sequence[str]) -> int: ...
