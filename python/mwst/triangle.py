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


def _column(array: np.ndarray) -> np.ndarray:
    """An (n,) array as the `triangle` package's (n, 1) column."""
    return array.reshape(-1, 1)


def _edges(triangles: np.ndarray, neighbors: np.ndarray, segments: np.ndarray, segment_markers: np.ndarray):
    """Every edge of the mesh once (Triangle's .edge) with its marker: the segment's marker on a
    subsegment, 1 on the rest of the boundary, 0 inside."""
    t = triangles.astype(np.int64)
    m = len(t)
    # Edge i of triangle k is opposite corner i; it is listed from the triangle with the lower index
    # (or the only one, on the boundary).
    ends = np.stack([t[:, [1, 2]], t[:, [2, 0]], t[:, [0, 1]]], axis=1).reshape(-1, 2)
    across = neighbors.reshape(-1).astype(np.int64)
    own = np.repeat(np.arange(m), 3)
    keep = (across < 0) | (own < across)
    ends, boundary = ends[keep], across[keep] < 0
    markers = boundary.astype(np.int32)
    if len(segments):
        n = int(max(ends.max(initial=0), segments.max(initial=0))) + 1
        key = np.minimum(ends[:, 0], ends[:, 1]) * n + np.maximum(ends[:, 0], ends[:, 1])
        s = segments.astype(np.int64)
        segment_key = np.minimum(s[:, 0], s[:, 1]) * n + np.maximum(s[:, 0], s[:, 1])
        order = np.argsort(segment_key)
        position = np.searchsorted(segment_key[order], key)
        position = np.minimum(position, len(order) - 1)
        on_segment = segment_key[order][position] == key
        markers[on_segment] = segment_markers[order][position[on_segment]]
    return ends.astype(np.int32), markers


def triangulate(tri: dict, opts: str = "") -> dict:
    """Triangulate the input dict `tri` as Triangle does with the switches `opts`.

    `tri` holds ``vertices`` (n, 2) and optionally ``segments``, ``holes``, ``regions`` (x, y,
    attribute, max area), ``vertex_markers``, ``segment_markers``, ``vertex_attributes``, and for
    refinement (r) ``triangles`` and ``triangle_max_area``. Returns a dict with ``vertices``,
    ``vertex_markers``, ``triangles``, and as the switches ask ``segments``, ``segment_markers``,
    ``holes``, ``regions`` (p), ``neighbors`` (n), ``edges``, ``edge_markers`` (e),
    ``triangle_attributes`` (A), ``vertex_attributes``. Numbering is from 0.

    Raises mwst.InputError for a switch mwst does not do, and for input it refuses.
    """
    if "vertices" not in tri:
        raise InputError("triangulate: the input dict has no 'vertices'")
    vertices = _float_rows(tri["vertices"], "vertices")
    out = _mwst.triangulate_switches(
        vertices,
        _input(tri, "segments", _index_rows),
        _input(tri, "holes", _float_rows),
        _region_rows(tri.get("regions")),
        _marker_rows(tri.get("vertex_markers"), "vertex_markers"),
        _marker_rows(tri.get("segment_markers"), "segment_markers"),
        _input(tri, "triangles", _index_rows, 3),
        None if tri.get("triangle_max_area") is None
        else np.ascontiguousarray(np.asarray(tri["triangle_max_area"], dtype=np.float64).reshape(-1)),
        str(opts),
    )
    switches = out["switches"]
    points, triangles, neighbors = out["vertices"], out["triangles"], out["neighbors"]
    segments, segment_markers = out["segments"], out["segment_markers"]
    vertex_markers = out["vertex_markers"]

    # Triangle outputs segments with p or c: the subsegments, and with c the hull edges too.
    if switches["convex_hull"]:
        hull = _hull_edges(triangles, neighbors)
        if len(segments):
            known = {tuple(sorted(e)) for e in segments.tolist()}
            hull = np.array([e for e in hull.tolist() if tuple(sorted(e)) not in known], dtype=np.int32).reshape(-1, 2)
        segments = np.concatenate([segments, hull]).astype(np.int32)
        segment_markers = np.concatenate([segment_markers, np.ones(len(hull), dtype=np.int32)])
    edges = edge_markers = None
    if switches["edges"]:
        edges, edge_markers = _edges(triangles, neighbors, segments, segment_markers)

    vertex_attributes = None
    if tri.get("vertex_attributes") is not None:
        vertex_attributes = np.asarray(tri["vertex_attributes"], dtype=np.float64).reshape(len(vertices), -1)
        if len(points) > len(vertices):
            raise InputError("vertex_attributes: mwst does not interpolate vertex attributes to Steiner points; "
                             "leave them out, or use no switch that adds points (q, a, S)")

    if switches["jettison"]:  # j: vertices in no triangle left out, the rest renumbered
        used = np.zeros(len(points), dtype=bool)
        used[triangles.reshape(-1)] = True
        keep = np.flatnonzero(used)
        renumber = np.full(len(points), -1, dtype=np.int64)
        renumber[keep] = np.arange(len(keep))
        points, vertex_markers = points[keep], vertex_markers[keep]
        triangles = renumber[triangles].astype(np.int32)
        segments = renumber[segments].astype(np.int32)
        if edges is not None:
            edges = renumber[edges].astype(np.int32)
        if vertex_attributes is not None:
            vertex_attributes = vertex_attributes[keep]

    markers = not switches["no_boundary_markers"]  # B
    result: dict[str, Any] = {}
    if not switches["no_node_output"]:  # N
        result["vertices"] = points
        if markers:
            result["vertex_markers"] = _column(vertex_markers)
        if vertex_attributes is not None and vertex_attributes.size:
            result["vertex_attributes"] = vertex_attributes
    if not switches["no_ele_output"] and len(triangles):  # E
        result["triangles"] = triangles
        if switches["region_attributes"] and out["triangle_attributes"] is not None:  # A
            result["triangle_attributes"] = _column(out["triangle_attributes"])
    if (switches["poly"] or switches["convex_hull"]) and not switches["no_poly_output"] and len(segments):  # P
        result["segments"] = segments
        if markers:
            result["segment_markers"] = _column(segment_markers)
    if switches["poly"]:  # Triangle hands the input's holes and regions back
        for key in ("holes", "regions"):
            if tri.get(key) is not None and len(tri[key]) and not (key == "holes" and switches["ignore_holes"]):
                result[key] = np.asarray(tri[key], dtype=np.float64)
    if switches["neighbours"] and len(triangles):  # n
        result["neighbors"] = neighbors
    if edges is not None and len(edges):  # e
        result["edges"] = edges
        if markers:
            result["edge_markers"] = _column(edge_markers)
    return result


def _hull_edges(triangles: np.ndarray, neighbors: np.ndarray) -> np.ndarray:
    """The boundary edges of a mesh (those with no triangle across), each from its triangle's side,
    so counter-clockwise around the domain."""
    t = triangles.astype(np.int64)
    ends = np.stack([t[:, [1, 2]], t[:, [2, 0]], t[:, [0, 1]]], axis=1)  # edge i opposite corner i
    return ends[neighbors < 0].astype(np.int32).reshape(-1, 2)


def delaunay(pts: Any) -> np.ndarray:
    """The Delaunay triangulation of the points `pts`: an (m, 3) int32 array of vertex indices
    (from 0), counter-clockwise. Duplicate points are in no triangle."""
    return triangulate({"vertices": pts}, "Qz")["triangles"]


def convex_hull(pts: Any) -> np.ndarray:
    """The convex hull of the points `pts`: its edges as an (h, 2) int32 array of vertex index
    pairs (from 0), each directed counter-clockwise around the hull."""
    out = _mwst.triangulate_switches(_float_rows(pts, "pts"), None, None, None, None, None, None, None, "Qzc")
    return _hull_edges(out["triangles"], out["neighbors"])


def voronoi(pts: Any):
    """The Voronoi diagram of the points `pts`, as Triangle's -v gives it.

    Returns ``(points, edges, ray_origins, ray_directions)``: the Voronoi vertices (the
    circumcentres of the Delaunay triangles, vertex i for triangle i), the finite edges as pairs of
    Voronoi vertices (one per interior Delaunay edge), and for each convex hull edge a ray: the
    Voronoi vertex it starts at and its direction (the hull edge turned outward, of its length)."""
    out = _mwst.triangulate_switches(_float_rows(pts, "pts"), None, None, None, None, None, None, None, "Qz")
    vertices, triangles, neighbors = out["vertices"], out["triangles"].astype(np.int64), out["neighbors"]
    a, b, c = (vertices[triangles[:, i]] for i in range(3))
    # Circumcentres relative to a: the solution of 2 [b-a; c-a] x = [|b-a|^2; |c-a|^2].
    ba, ca = b - a, c - a
    d = 2.0 * (ba[:, 0] * ca[:, 1] - ba[:, 1] * ca[:, 0])
    nb, nc = (ba ** 2).sum(axis=1), (ca ** 2).sum(axis=1)
    centres = a + np.stack([(ca[:, 1] * nb - ba[:, 1] * nc) / d, (ba[:, 0] * nc - ca[:, 0] * nb) / d], axis=1)
    m = len(triangles)
    own = np.repeat(np.arange(m), 3)
    across = neighbors.reshape(-1).astype(np.int64)
    interior = (across >= 0) & (own < across)
    edges = np.stack([own[interior], across[interior]], axis=1).astype(np.int32)
    hull = across < 0
    ends = np.stack([triangles[:, [1, 2]], triangles[:, [2, 0]], triangles[:, [0, 1]]], axis=1).reshape(-1, 2)[hull]
    p, q = vertices[ends[:, 0]], vertices[ends[:, 1]]
    # The domain lies left of p -> q (counter-clockwise), so outward is the right-hand normal.
    directions = np.stack([q[:, 1] - p[:, 1], p[:, 0] - q[:, 0]], axis=1)
    return centres, edges, own[hull].astype(np.int32), directions

