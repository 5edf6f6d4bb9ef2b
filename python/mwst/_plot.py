"""mwst.plot: draws a mesh with matplotlib. Imported by mwst.plot() when first called, so that
`import mwst` never imports matplotlib."""

from __future__ import annotations

from typing import Any

import numpy as np


def plot(
    result: Any,
    ax: Any = None,
    *,
    face_color: str = "#dbe9f6",
    edge_color: str = "#4a6f8f",
    segment_color: str = "black",
    steiner_color: str = "#d62728",
    show_steiner: bool = True,
) -> Any:
    """Draw a mesh: triangles filled light with thin edges, segments bold, Steiner points marked.

    Holes and the outside of the domain stay empty (only the mesh's triangles are filled).

    Args:
        result: a mwst.Triangulation, or a dict with vertices and triangles (and segments,
            vertex_kind), as mwst.triangle returns.
        ax: the matplotlib Axes to draw into; a new figure's when None.
        face_color, edge_color: fill and edges of the triangles.
        segment_color: the segments (subsegments of the input's segments), drawn bold.
        steiner_color: the marks of Steiner points (vertices that are not input points).
        show_steiner: mark the Steiner points.

    Returns:
        The Axes drawn into (aspect ratio equal).
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    if isinstance(result, dict):
        vertices = np.asarray(result["vertices"], dtype=float)
        triangles = np.asarray(result["triangles"], dtype=np.int64)
        segments = result.get("segments")
        kind = result.get("vertex_kind")
    else:
        vertices = np.asarray(result.vertices, dtype=float)
        triangles = np.asarray(result.triangles, dtype=np.int64)
        segments = result.segments
        kind = result.vertex_kind
    if ax is None:
        _, ax = plt.subplots()
    if len(triangles):
        ax.add_collection(
            PolyCollection(vertices[triangles], facecolors=face_color, edgecolors=edge_color, linewidths=0.4)
        )
    if segments is not None and len(segments):
        segments = np.asarray(segments, dtype=np.int64)
        ax.add_collection(LineCollection(vertices[segments], colors=segment_color, linewidths=1.8))
    if show_steiner and kind is not None:
        steiner = np.asarray(kind) >= 2  # VertexKind.STEINER, SEGMENT_STEINER, CROSSING
        if steiner.any():
            ax.plot(vertices[steiner, 0], vertices[steiner, 1], "o", color=steiner_color, markersize=2.5,
                    label="Steiner points")
    if len(vertices):
        used = vertices[np.unique(triangles)] if len(triangles) else vertices
        lo, hi = used.min(axis=0), used.max(axis=0)
        pad = 0.02 * max(hi[0] - lo[0], hi[1] - lo[1], 1e-300)
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    return ax
