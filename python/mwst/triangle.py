"""mwst.triangle: a drop-in for the `triangle` package (the Python wrapper of Shewchuk's Triangle).

Code written as ``import triangle as tr`` works as ``import mwst.triangle as tr``::

    import mwst.triangle as tr
    A = dict(vertices=[[0, 0], [1, 0], [1, 1], [0, 1]], segments=[[0, 1], [1, 2], [2, 3], [3, 0]])
    B = tr.triangulate(A, "pq30a0.01")

The switch string is read by the library's parser (mwst::parse_triangle_switches), with Triangle's
meanings: p (use segments, holes and regions), q[angle] (Delaunay refinement, 20 degrees by default),
a[area] (area bound), c (convex hull), S[n] (Steiner budget), A (regional attributes), e (edges),
n (neighbors), j (drop unused vertices), B, P, N, E, O, z, Q, V and the no-op i, F, l, s, C, X.
A switch mwst does not do raises mwst.InputError naming it (u, g, o2, unknown letters; and D, Y,
r and a without a number while the library refuses them). Like the `triangle` package, numbering
is from 0 ('z' is implied), and dict keys are present only when they have content.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import InputError, _float_rows, _index_rows, _marker_rows, _mwst, _region_rows

__all__ = ["triangulate", "delaunay", "voronoi", "convex_hull", "parse_switches"]


def parse_switches(opts: str) -> dict:
    """What the library's parser makes of a Triangle switch string: a dict of its settings (method,
    min_angle, max_area, max_steiner, convex_hull, poly, refine, edges, neighbours, ...). Raises
    mwst.InputError naming a switch that is malformed, unknown or not supported."""
    return _mwst.parse_triangle_switches(str(opts))


def _input(tri: dict, key: str, convert, *args):
    value = tri.get(key)
    if value is None:
        return None
    return convert(value, key, *args)


def _call(tri: dict, opts: str) -> dict:
    """The library's run of `opts` on the input dict: Triangle's outputs as the library writes
    them (mwst::io::format_triangle_files), as arrays named as the `triangle` package names them
    (markers as (n, 1) columns), plus "switches" and "report"."""
    if "vertices" not in tri:
        raise InputError("triangulate: the input dict has no 'vertices'")
    area = tri.get("triangle_max_area")
    attributes = tri.get("vertex_attributes")
    if attributes is not None:
        attributes = np.ascontiguousarray(np.asarray(attributes, dtype=np.float64).reshape(len(tri["vertices"]), -1))
    return _mwst.triangulate_switches(
        _float_rows(tri["vertices"], "vertices"),
        _input(tri, "segments", _index_rows),
        _input(tri, "holes", _float_rows),
        _region_rows(tri.get("regions")),
        _marker_rows(tri.get("vertex_markers"), "vertex_markers"),
        _marker_rows(tri.get("segment_markers"), "segment_markers"),
        _input(tri, "triangles", _index_rows, 3),
        None if area is None else np.ascontiguousarray(np.asarray(area, dtype=np.float64).reshape(-1)),
        attributes,
        str(opts),
    )


def triangulate(tri: dict, opts: str = "") -> dict:
    """Triangulate the input dict `tri` as Triangle does with the switches `opts`.

    `tri` holds ``vertices`` (n, 2) and optionally ``segments``, ``holes``, ``regions`` (x, y,
    attribute, max area), ``vertex_markers``, ``segment_markers``, ``vertex_attributes``, and for
    refinement (r) ``triangles`` and ``triangle_max_area``. Returns a dict with ``vertices``,
    ``vertex_markers``, ``triangles``, and as the switches ask ``segments``, ``segment_markers``
    (p or c), ``holes``, ``regions`` (p), ``neighbors`` (n), ``edges``, ``edge_markers`` (e),
    ``triangle_attributes`` (A), ``vertex_attributes`` (an input vertex keeps its own; a Steiner
    point gets them interpolated linearly over the input's constrained Delaunay triangulation).
    Numbering is from 0; markers are (n, 1)
    columns, carried as Triangle carries them; keys with nothing in them are left out.

    Raises mwst.InputError for a switch mwst does not do, and for input it refuses.
    """
    out = _call(tri, opts)
    switches = out.pop("switches")
    for key in ("report", "voronoi_vertices", "voronoi_edges", "voronoi_directions"):
        out.pop(key, None)  # (the `triangle` package's triangulate drops the Voronoi diagram too)
    out.pop("kept_vertices", None)
    # vertex_attributes: the input vertices keep theirs; Steiner points get them interpolated
    # linearly over the input's constrained Delaunay triangulation (the library's
    # interpolate_vertex_attributes).
    if switches["poly"]:  # Triangle hands the input's holes and regions back
        for key in ("holes", "regions"):
            if tri.get(key) is not None and len(tri[key]) and not (key == "holes" and switches["ignore_holes"]):
                out[key] = np.asarray(tri[key], dtype=np.float64)

    dropped = set()
    if switches["no_node_output"]:  # N
        dropped |= {"vertices", "vertex_markers", "vertex_attributes"}
    if switches["no_ele_output"]:  # E
        dropped |= {"triangles", "triangle_attributes"}
    if switches["no_poly_output"]:  # P
        dropped |= {"segments", "segment_markers"}
    if switches["no_boundary_markers"]:  # B
        dropped |= {"vertex_markers", "segment_markers", "edge_markers"}
    return {key: value for key, value in out.items() if key not in dropped and len(value)}


def delaunay(pts: Any) -> np.ndarray:
    """The Delaunay triangulation of the points `pts`: an (m, 3) int32 array of vertex indices
    (from 0), counter-clockwise. Duplicate points are in no triangle."""
    return _call({"vertices": pts}, "Qz")["triangles"]


def convex_hull(pts: Any) -> np.ndarray:
    """The convex hull of the points `pts`: its edges as an (h, 2) int32 array of vertex index
    pairs (from 0), each directed counter-clockwise around the hull (Triangle's "Qzc" segments)."""
    return _call({"vertices": pts}, "Qzc")["segments"]


def voronoi(pts: Any):
    """The Voronoi diagram of the points `pts`, as Triangle's -v gives it (the library's .v.node
    and .v.edge).

    Returns ``(points, edges, ray_origins, ray_directions)``: the Voronoi vertices (the
    circumcentres of the Delaunay triangles, vertex i for triangle i), the finite edges as pairs of
    Voronoi vertices (one per interior Delaunay edge), and for each convex hull edge a ray: the
    Voronoi vertex it starts at and its direction (the hull edge turned outward, of its length)."""
    out = _call({"vertices": pts}, "Qzv")
    edges, directions = out["voronoi_edges"], out["voronoi_directions"]
    finite = edges[:, 1] != -1
    return out["voronoi_vertices"], edges[finite], edges[~finite, 0], directions[~finite]
