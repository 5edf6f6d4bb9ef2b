# Type stub of the package mwst (python/mwst/__init__.py and the compiled _mwst).
import enum
from collections.abc import Mapping
from typing import Any, NamedTuple, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

class InputError(ValueError): ...
class ResourceError(MemoryError): ...
class MeshWarning(UserWarning): ...

class VertexKind(enum.IntEnum):
    INPUT = 0
    DUPLICATE = 1
    STEINER = 2
    SEGMENT_STEINER = 3
    CROSSING = 4

class Pslg:
    vertices: npt.NDArray[np.float64]
    segments: Optional[npt.NDArray[np.int64]]
    holes: Optional[npt.NDArray[np.float64]]
    regions: Optional[npt.NDArray[np.float64]]
    vertex_markers: Optional[npt.NDArray[np.int32]]
    segment_markers: Optional[npt.NDArray[np.int32]]
    source: str
    first_index: int
    def __init__(
        self,
        vertices: npt.ArrayLike,
        segments: Optional[npt.ArrayLike] = ...,
        holes: Optional[npt.ArrayLike] = ...,
        regions: Optional[npt.ArrayLike] = ...,
        vertex_markers: Optional[npt.ArrayLike] = ...,
        segment_markers: Optional[npt.ArrayLike] = ...,
        source: str = ...,
        first_index: int = ...,
    ) -> None: ...

class Triangulation:
    vertices: npt.NDArray[np.float64]
    triangles: npt.NDArray[np.int32]
    neighbors: Optional[npt.NDArray[np.int32]]
    segments: npt.NDArray[np.int32]
    segment_markers: npt.NDArray[np.int32]
    vertex_kind: Optional[npt.NDArray[np.uint8]]
    vertex_markers: npt.NDArray[np.int32]
    triangle_attributes: Optional[npt.NDArray[np.float64]]
    report: dict[str, Any]
    def __init__(
        self,
        vertices: npt.NDArray[np.float64],
        triangles: npt.NDArray[np.int32],
        neighbors: Optional[npt.NDArray[np.int32]] = ...,
        segments: Optional[npt.NDArray[np.int32]] = ...,
        segment_markers: Optional[npt.NDArray[np.int32]] = ...,
        vertex_kind: Optional[npt.NDArray[np.uint8]] = ...,
        vertex_markers: Optional[npt.NDArray[np.int32]] = ...,
        triangle_attributes: Optional[npt.NDArray[np.float64]] = ...,
        report: Optional[dict[str, Any]] = ...,
    ) -> None: ...
    @property
    def markers(self) -> npt.NDArray[np.int32]: ...
    @property
    def weight(self) -> float: ...

_Input = Union[npt.ArrayLike, Pslg, Mapping[str, Any]]
_Mesh = Union[Triangulation, Mapping[str, Any]]

def triangulate(
    vertices: _Input,
    segments: Optional[npt.ArrayLike] = ...,
    holes: Optional[npt.ArrayLike] = ...,
    regions: Optional[npt.ArrayLike] = ...,
    *,
    method: str = ...,
    min_angle: Optional[float] = ...,
    steiner: str = ...,
    max_area: Optional[float] = ...,
    max_steiner: Optional[int] = ...,
    bundle_k: Optional[int] = ...,
    flip: bool = ...,
    convex_hull: bool = ...,
    strict: bool = ...,
    time_limit: Optional[float] = ...,
    threads: int = ...,
) -> Triangulation: ...

class BundleNumber(NamedTuple):
    number: int
    center: tuple[float, float]
    radius: float
    triangles: npt.NDArray[np.int64]
    exact: bool
    lower_bound: int
    upper_bound: int
    circumdisk_bound: int

def bundle_number(
    vertices: Union[npt.ArrayLike, _Mesh],
    triangles: Optional[npt.ArrayLike] = ...,
    *,
    candidate_budget: Optional[int] = ...,
    threads: int = ...,
) -> BundleNumber: ...

class CheckResult(NamedTuple):
    ok: bool
    violations: int
    messages: list[str]
    convex_hull: bool
    area: float
    domain_area: float

def check(
    mesh: _Mesh,
    vertices: _Input,
    segments: Optional[npt.ArrayLike] = ...,
    holes: Optional[npt.ArrayLike] = ...,
    *,
    delaunay: bool = ...,
    min_angle: Optional[float] = ...,
    max_messages: int = ...,
) -> CheckResult: ...
def read(path: str) -> Union[Pslg, Triangulation]: ...
def write(
    prefix: str,
    result: _Mesh,
    *,
    first_index: int = ...,
    holes: Optional[npt.ArrayLike] = ...,
    regions: Optional[npt.ArrayLike] = ...,
) -> None: ...
def plot(result: _Mesh, ax: Any = ..., **kwargs: Any) -> Any: ...
