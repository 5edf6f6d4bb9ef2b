"""mwst: light Steiner triangulations in the plane, from Python.

The C++ library mwst (Delaunay, Delaunay refinement, bundle removal, quadtree refinement and a
weight optimiser, after Boyaci, Erten, Ungor, "Triangulations Loosing Bundles and Weight") with numpy
arrays in and out::

    import numpy as np, mwst
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    mesh = mwst.triangulate(square, [[0, 1], [1, 2], [2, 3], [3, 0]], method="dr", min_angle=25)
    mesh.triangles, mesh.report["weight_total"]

``mwst.triangle`` is a drop-in for the ``triangle`` package (Shewchuk's Triangle switches).
The computation runs without the GIL: other Python threads keep running, and several
triangulations can run at once on different threads.
"""

from __future__ import annotations

import enum
import json
import warnings
from collections.abc import Mapping
from typing import Any, NamedTuple, Optional

import numpy as np

from . import _mwst
from ._mwst import InputError, ResourceError

__version__: str = _mwst.__version__
InputError.__module__ = ResourceError.__module__ = "mwst"

__all__ = [
    "InputError",
    "ResourceError",
    "MeshWarning",
    "VertexKind",
    "Pslg",
    "Triangulation",
    "BundleNumber",
    "CheckResult",
    "triangulate",
    "bundle_number",
    "check",
    "read",
    "write",
    "plot",
    "__version__",
]


class MeshWarning(UserWarning):
    """What the library warns about (report["warnings"]): hole seeds it ignored, region seeds
    outside the domain, ... mwst.triangulate issues one per warning."""


class VertexKind(enum.IntEnum):
    """What a vertex of a result is (the values of ``Triangulation.vertex_kind``)."""

    INPUT = 0  #: an input point, at its input index
    DUPLICATE = 1  #: an input point equal to an earlier one: merged, in no triangle
    STEINER = 2  #: a Steiner point in the interior of the domain
    SEGMENT_STEINER = 3  #: a Steiner point splitting an input segment
    CROSSING = 4  #: a point where input segments cross


# ---- array conversion ---------------------------------------------------------------------------

_MAX_EXACT_INTEGER = 2**53  # larger integers do not all convert to float64 exactly


def _float_rows(value: Any, name: str) -> np.ndarray:
    """`value` as a C-contiguous float64 array. One that already is one is returned as it is (its
    memory is read by the library in place); other numeric arrays are converted (a copy)."""
    array = np.asarray(value)
    if array.ndim == 1 and array.size == 0:  # an empty list: no points
        return np.zeros((0, 2))
    if array.dtype == np.float64 and array.flags.c_contiguous:
        return array
    if array.dtype.kind not in "fiu":
        raise InputError(f"{name}: expected numbers, got an array of dtype {array.dtype}")
    if array.dtype.kind in "iu" and array.size and int(np.abs(array).max()) > _MAX_EXACT_INTEGER:
        raise InputError(f"{name}: integer coordinates beyond 2**53 do not convert to float64 exactly")
    return np.ascontiguousarray(array, dtype=np.float64)


def _index_rows(value: Any, name: str, columns: int = 2) -> np.ndarray:
    """`value` as a C-contiguous int64 array of indices: integers, or floats with integral values
    (an empty list gives an empty (0, columns) array)."""
    array = np.asarray(value)
    if array.size == 0:
        return np.zeros((0, array.shape[1] if array.ndim == 2 else columns), dtype=np.int64)
    kind = array.dtype.kind
    if kind == "f":
        if not (np.all(np.isfinite(array)) and np.all(array == np.trunc(array))):
            raise InputError(f"{name}: expected integer vertex indices, got non-integral numbers")
    elif kind not in "iu":
        raise InputError(f"{name}: expected integer vertex indices, got an array of dtype {array.dtype}")
    elif kind == "u" and int(array.max()) > np.iinfo(np.int64).max:
        raise InputError(f"{name}: an index is too large")
    return np.ascontiguousarray(array, dtype=np.int64)


def _marker_rows(value: Any, name: str) -> Optional[np.ndarray]:
    if value is None:
        return None
    array = np.asarray(value)
    if array.ndim == 2 and array.shape[1] == 1:  # the `triangle` package's (n, 1) columns
        array = array[:, 0]
    if array.dtype.kind not in "iu" and not (array.dtype.kind == "f" and np.all(array == np.round(array))):
        raise InputError(f"{name}: expected integer markers, got an array of dtype {array.dtype}")
    return np.ascontiguousarray(array, dtype=np.int32)


def _region_rows(value: Any) -> Optional[np.ndarray]:
    """Regions as (r, 4) rows x, y, attribute, max_area (a row of 3 has no area bound)."""
    if value is None:
        return None
    array = _float_rows(value, "regions")
    if array.ndim == 2 and array.shape[1] == 3:
        array = np.hstack([array, np.full((array.shape[0], 1), -1.0)])
    return array


def _optional(value: Any, convert, name: str) -> Optional[np.ndarray]:
    return None if value is None else convert(value, name)


class Pslg:
    """An input graph: vertices, segments (with boundary markers), hole seeds and regions.

    ``mwst.read("file.poly")`` gives one; ``mwst.triangulate(pslg, ...)`` and ``mwst.check(mesh, pslg)``
    take one in place of their ``vertices``. Indices count from 0 (``first_index`` is the numbering
    base the file used)."""

    def __init__(
        self,
        vertices: Any,
        segments: Any = None,
        holes: Any = None,
        regions: Any = None,
        vertex_markers: Any = None,
        segment_markers: Any = None,
        source: str = "",
        first_index: int = 0,
    ) -> None:
        """Wrap the arrays (converted as mwst.triangulate converts them)."""
        self.vertices = _float_rows(vertices, "vertices")
        self.segments = _optional(segments, _index_rows, "segments")
        self.holes = _optional(holes, _float_rows, "holes")
        self.regions = _region_rows(regions)
        self.vertex_markers = _marker_rows(vertex_markers, "vertex_markers")
        self.segment_markers = _marker_rows(segment_markers, "segment_markers")
        self.source = source
        self.first_index = first_index

    def __repr__(self) -> str:
        """A one-line summary."""
        count = lambda a: 0 if a is None else len(a)  # noqa: E731
        return (
            f"mwst.Pslg({len(self.vertices)} vertices, {count(self.segments)} segments, "
            f"{count(self.holes)} holes, {count(self.regions)} regions"
            + (f", from {self.source!r})" if self.source else ")")
        )


def _as_pslg(vertices: Any, segments: Any = None, holes: Any = None, regions: Any = None) -> Pslg:
    """A Pslg from triangulate's first arguments: `vertices` may itself be a Pslg, or a mapping with
    the `triangle` package's keys; arrays given beside it replace its own."""
    if isinstance(vertices, Pslg):
        base = vertices
    elif isinstance(vertices, Mapping):
        base = Pslg(
            vertices["vertices"],
            vertices.get("segments"),
            vertices.get("holes"),
            vertices.get("regions"),
            vertices.get("vertex_markers"),
            vertices.get("segment_markers"),
        )
    else:
        return Pslg(vertices, segments, holes, regions)
    if segments is None and holes is None and regions is None:
        return base
    return Pslg(
        base.vertices,
        base.segments if segments is None else segments,
        base.holes if holes is None else holes,
        base.regions if regions is None else regions,
        base.vertex_markers,
        base.segment_markers if segments is None else None,
        base.source,
        base.first_index,
    )


# ---- results ------------------------------------------------------------------------------------


class Triangulation:
    """A mesh as numpy arrays (mwst.triangulate's result; mwst.read of a mesh gives one too).

    Attributes:
        vertices: (n, 2) float64. Input point i is vertex i (duplicates included, in no triangle);
            Steiner points follow.
        triangles: (m, 3) int32, corners counter-clockwise.
        neighbors: (m, 3) int32: neighbors[t, i] is the triangle across the edge opposite corner i,
            -1 on the boundary (Triangle's .neigh convention). None for a mesh read from files.
        segments: (s, 2) int32: the subsegments (pieces of input segments) bounding triangles.
        segment_markers: (s,) int32 boundary markers of the subsegments.
        vertex_kind: (n,) uint8, values of mwst.VertexKind. None for a mesh read from files.
        vertex_markers: (n,) int32 boundary markers (Triangle's).
        triangle_attributes: (m,) float64 regional attributes when the input has regions, else None.
        report: dict with the keys of the command line's JSON report (weights, angles, counts,
            seconds, stop_reason, warnings, ...); empty for a mesh read from files. Its "seconds"
            also has "to_arrays": the library's conversion of the mesh into these arrays (not in
            its "total", which is the triangulation's, as the command line reports it).
    """

    __slots__ = (
        "vertices",
        "triangles",
        "neighbors",
        "segments",
        "segment_markers",
        "vertex_kind",
        "vertex_markers",
        "triangle_attributes",
        "report",
    )

    def __init__(
        self,
        vertices: np.ndarray,
        triangles: np.ndarray,
        neighbors: Optional[np.ndarray] = None,
        segments: Optional[np.ndarray] = None,
        segment_markers: Optional[np.ndarray] = None,
        vertex_kind: Optional[np.ndarray] = None,
        vertex_markers: Optional[np.ndarray] = None,
        triangle_attributes: Optional[np.ndarray] = None,
        report: Optional[dict] = None,
    ) -> None:
        """Hold the arrays as given."""
        self.vertices = vertices
        self.triangles = triangles
        self.neighbors = neighbors
        self.segments = np.zeros((0, 2), dtype=np.int32) if segments is None else segments
        self.segment_markers = (
            np.ones(len(self.segments), dtype=np.int32) if segment_markers is None else segment_markers
        )
        self.vertex_kind = vertex_kind
        self.vertex_markers = np.zeros(len(vertices), dtype=np.int32) if vertex_markers is None else vertex_markers
        self.triangle_attributes = triangle_attributes
        self.report = {} if report is None else report

    @property
    def markers(self) -> np.ndarray:
        """The vertices' boundary markers (the same array as vertex_markers)."""
        return self.vertex_markers

    @property
    def weight(self) -> float:
        """Total edge length of the mesh: report["weight_total"], or computed from the arrays."""
        if "weight_total" in self.report:
            return float(self.report["weight_total"])
        t = self.triangles.astype(np.int64)
        edges = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
        edges = np.unique(np.sort(edges, axis=1), axis=0)
        d = self.vertices[edges[:, 0]] - self.vertices[edges[:, 1]]
        return float(np.hypot(d[:, 0], d[:, 1]).sum())

    def __repr__(self) -> str:
        """A one-line summary."""
        text = f"mwst.Triangulation({len(self.vertices)} vertices, {len(self.triangles)} triangles"
        if "method" in self.report:
            text += f", method {self.report['method']}, weight {self.report['weight_total']:.6g}"
        return text + ")"


def triangulate(
    vertices: Any,
    segments: Any = None,
    holes: Any = None,
    regions: Any = None,
    *,
    method: str = "dt",
    min_angle: Optional[float] = None,
    steiner: str = "offcenter",
    max_area: Optional[float] = None,
    max_steiner: Optional[int] = None,
    bundle_k: Optional[int] = None,
    flip: bool = False,
    convex_hull: bool = False,
    strict: bool = False,
    time_limit: Optional[float] = None,
    threads: int = 0,
) -> Triangulation:
    """Triangulate points, or a graph of points and segments, with one of mwst's methods.

    What ``mwst triangulate`` does on a file, on arrays.

    Args:
        vertices: (n, 2) array-like of floats. A C-contiguous float64 array is read in place (no
            copy is made of it); other arrays are converted. May also be a ``mwst.Pslg`` (from
            ``mwst.read``) or a dict with the ``triangle`` package's keys.
        segments: (m, 2) vertex indices (from 0) of segments the mesh must contain. With segments,
            the domain is what they enclose minus the holes; without, the convex hull.
        holes: (h, 2) points: each eats the region around it up to the segments.
        regions: (r, 4) rows x, y, attribute, max_area (Triangle's regions; the attribute spreads to
            the triangles of the seed's region, see triangle_attributes).
        method: "dt" (constrained Delaunay), "dr" (Delaunay refinement), "brh" (bundle removal),
            "qtr" (quadtree refinement) or "opt" (the weight optimiser).
        min_angle: angle bound in degrees for dr, brh (and opt's starting meshes); default 20.
        steiner: refinement's Steiner point rule, "offcenter" or "circumcenter".
        max_area: refine triangles larger than this (dr, brh, opt).
        max_steiner: at most this many Steiner points.
        bundle_k: brh's bundle size (default ceil(4 pi / alpha) + 3).
        flip: weight-reducing edge flips after the method.
        convex_hull: mesh the whole convex hull (holes still carve).
        strict: refuse crossing segments instead of splitting them.
        time_limit: stop dr, brh, qtr and opt after about this many seconds (the mesh stays valid;
            qtr then gives the constrained Delaunay triangulation of the input).
        threads: worker threads, 0 for all cores; results do not depend on it.

    Returns:
        A Triangulation (numpy arrays and the report dict).

    Raises:
        InputError: bad arrays (shape, dtype, NaN or out-of-range coordinates, indices that name no
            vertex) or options, or input the library refuses, with the library's message.
        ResourceError: a request that cannot fit in memory.

    The GIL is released while the mesh is computed. The library's warnings (report["warnings"])
    are issued as mwst.MeshWarning.
    """
    pslg = _as_pslg(vertices, segments, holes, regions)
    if not isinstance(method, str) or not isinstance(steiner, str):
        raise InputError("method and steiner must be strings")
    out = _mwst.triangulate(
        pslg.vertices,
        pslg.segments,
        pslg.holes,
        pslg.regions,
        pslg.vertex_markers,
        pslg.segment_markers,
        method,
        None if min_angle is None else float(min_angle),
        steiner,
        None if max_area is None else float(max_area),
        None if max_steiner is None else int(max_steiner),
        None if bundle_k is None else int(bundle_k),
        bool(flip),
        bool(convex_hull),
        bool(strict),
        None if time_limit is None else float(time_limit),
        int(threads),
        pslg.source,
    )
    report = json.loads(out.pop("report"))
    # The library's conversion of the mesh to arrays (to_arrays), after triangulate()'s "total".
    report["seconds"]["to_arrays"] = max(0.0, out.pop("library_seconds") - report["seconds"]["total"])
    for warning in report.get("warnings", []):
        warnings.warn(warning, MeshWarning, stacklevel=2)
    return Triangulation(report=report, **out)


# ---- around it ----------------------------------------------------------------------------------


class BundleNumber(NamedTuple):
    """The bundle number of a triangulation and its witness.

    ``number`` is the largest k such that some open disk containing no vertex meets the interiors
    of k triangles; the witness is that disk (``center``, ``radius``, rounded to double) and those
    triangles (indices into the triangle array). Under a candidate budget the answer may be bounds
    only: then ``exact`` is False and lower_bound <= bundle number <= upper_bound (``number`` is the
    lower bound, and the witness is its disk)."""

    number: int
    center: tuple
    radius: float
    triangles: np.ndarray
    exact: bool
    lower_bound: int
    upper_bound: int
    circumdisk_bound: int


def _mesh_arrays(mesh: Any, triangles: Any = None) -> tuple:
    """(vertices, triangles, segments) of a Triangulation, a dict with the `triangle` package's keys,
    or separate arrays."""
    if isinstance(mesh, Triangulation):
        return mesh.vertices, mesh.triangles, mesh.segments
    if isinstance(mesh, Mapping):
        return mesh["vertices"], mesh["triangles"], mesh.get("segments")
    if triangles is None:
        raise InputError("expected a Triangulation, a dict with vertices and triangles, or both arrays")
    return mesh, triangles, None


def bundle_number(
    vertices: Any, triangles: Any = None, *, candidate_budget: Optional[int] = None, threads: int = 0
) -> BundleNumber:
    """The exact bundle number of a triangulation, with a witness disk and its triangles.

    Args:
        vertices: (n, 2) points, or a Triangulation (or a dict with vertices and triangles), in
            which case ``triangles`` is left out.
        triangles: (m, 3) vertex indices, either orientation. Vertices in no triangle are ignored.
        candidate_budget: most (circumdisk, triangle) pairs kept (memory and time); default 24 per
            triangle plus 2**20, as ``mwst bundle``; 0 for the exact number whatever it costs.
        threads: worker threads, 0 for all cores.

    Raises:
        InputError: indices out of range, degenerate, repeated or overlapping triangles.
    """
    points, corners, _ = _mesh_arrays(vertices, triangles)
    out = _mwst.bundle_number(
        _float_rows(points, "vertices"),
        _index_rows(corners, "triangles", 3),
        -1 if candidate_budget is None else int(candidate_budget),
        int(threads),
    )
    return BundleNumber(
        out["bundle_number"],
        out["center"],
        out["radius"],
        out["triangles"],
        out["exact"],
        out["lower_bound"],
        out["upper_bound"],
        out["circumdisk_bound"],
    )


class CheckResult(NamedTuple):
    """What mwst.check found: ``ok`` (no violation), the number of ``violations`` and one message
    per violation (at most max_messages), whether the mesh covers the convex hull rather than the
    carved domain, and the mesh's and the domain's areas. True in a boolean context when ok."""

    ok: bool
    violations: int
    messages: list
    convex_hull: bool
    area: float
    domain_area: float

    def __bool__(self) -> bool:
        """True when the mesh is valid."""
        return self.ok


def check(
    mesh: Any,
    vertices: Any,
    segments: Any = None,
    holes: Any = None,
    *,
    delaunay: bool = False,
    min_angle: Optional[float] = None,
    max_messages: int = 1000,
) -> CheckResult:
    """Validate a mesh against its input graph with the library's independent checker (what
    ``mwst check`` runs): exact counter-clockwise orientation, a consistent edge manifold, coverage
    of the domain (input vertices and segments present, area equal), and optionally the constrained
    Delaunay property (exact incircle tests) and a minimum angle.

    Args:
        mesh: a Triangulation or a dict with vertices, triangles (and segments: the mesh's
            subsegments, checked to lie on input segments).
        vertices: the input's (n, 2) points, or a Pslg / dict holding the whole input.
        segments, holes: the input's segments and hole seeds.
        delaunay: also require the constrained Delaunay property.
        min_angle: also require every angle at least this many degrees.
        max_messages: violations past this are counted, not described.

    Returns:
        A CheckResult (true when the mesh is valid). Raises InputError if the input itself is refused.
    """
    pslg = _as_pslg(vertices, segments, holes)
    mesh_vertices, mesh_triangles, mesh_segments = _mesh_arrays(mesh)
    out = _mwst.check(
        pslg.vertices,
        pslg.segments,
        pslg.holes,
        _float_rows(mesh_vertices, "mesh vertices"),
        _index_rows(mesh_triangles, "mesh triangles", 3),
        _optional(mesh_segments, _index_rows, "mesh segments"),
        bool(delaunay),
        0.0 if min_angle is None else float(min_angle),
        int(max_messages),
    )
    return CheckResult(**out)


def read(path: str):
    """Read Triangle's files with the library's readers.

    ``read("x.node")`` and ``read("x.poly")`` give the input graph as a Pslg (indices from 0);
    ``read("x.1")`` (a prefix, or ``"x.1.ele"``) gives the mesh x.1.node + x.1.ele (+ x.1.poly for its
    subsegments) as a Triangulation without neighbors, vertex kinds or report.

    Raises:
        InputError: a missing or malformed file, with file and line.
    """
    path = str(path)
    if path.endswith(".node") or path.endswith(".poly"):
        d = _mwst.read_input(path)
        pslg = Pslg(
            d["vertices"],
            d["segments"] if d["is_poly"] else None,
            d["holes"],
            d["regions"],
            d["vertex_markers"],
            d["segment_markers"] if d["is_poly"] else None,
            d["source"],
            d["first_index"],
        )
        return pslg
    prefix = path[: -len(".ele")] if path.endswith(".ele") else path
    d = _mwst.read_mesh(prefix)
    return Triangulation(d["vertices"], d["triangles"], segments=d["segments"], segment_markers=d["segment_markers"])


def write(prefix: str, result: Any, *, first_index: int = 1, holes: Any = None, regions: Any = None) -> None:
    """Write a mesh as Triangle's PREFIX.node, PREFIX.ele and (with segments) PREFIX.poly, with the
    library's writer (shortest round-trip decimals; each file written whole or not at all).

    Args:
        prefix: path prefix of the files.
        result: a Triangulation, or a dict with vertices, triangles (and segments, segment_markers,
            vertex_markers, holes, regions), as mwst.triangle returns.
        first_index: 1 (Triangle's default) or 0 (its -z).
        holes, regions: the input's hole seeds and regions, listed in the .poly after the segments
            so that re-meshing it gives the same domain (a dict's own are used when not given).
    """
    if isinstance(result, Triangulation):
        vertices, triangles = result.vertices, result.triangles
        segments, segment_markers, vertex_markers = result.segments, result.segment_markers, result.vertex_markers
    elif isinstance(result, Mapping):
        vertices, triangles = result["vertices"], result["triangles"]
        segments, segment_markers = result.get("segments"), result.get("segment_markers")
        vertex_markers = result.get("vertex_markers")
        holes = result.get("holes") if holes is None else holes
        regions = result.get("regions") if regions is None else regions
    else:
        raise InputError("write: expected a Triangulation or a dict with vertices and triangles")
    _mwst.write_mesh(
        str(prefix),
        _float_rows(vertices, "vertices"),
        _marker_rows(vertex_markers, "vertex_markers"),
        _index_rows(triangles, "triangles", 3),
        _optional(segments, _index_rows, "segments"),
        _marker_rows(segment_markers, "segment_markers") if segments is not None else None,
        int(first_index),
        _optional(holes, _float_rows, "holes"),
        _region_rows(regions),
    )


def plot(result: Any, ax: Any = None, **kwargs: Any) -> Any:
    """Draw a mesh with matplotlib (imported only now): triangles thin, segments bold, holes left
    empty, Steiner points marked. Returns the Axes. See mwst.plot's module for the keywords."""
    from ._plot import plot as _plot

    return _plot(result, ax, **kwargs)
