// mwst/mesh/delaunay.hpp — Delaunay and constrained Delaunay triangulation.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

struct DelaunayStats {
  std::size_t duplicates = 0;   // input points equal to an earlier point (merged)
  double seconds_sort = 0.0;    // spatial sort
  double seconds_insert = 0.0;  // incremental insertion
};

// Delaunay triangulation of a point set, exact. Vertex ids are the indices into `points`.
// Incremental insertion in Hilbert-curve order with a walking point location and Lawson flips.
// Duplicate points are merged (kept in Mesh::points as VertexKind::kDuplicate, listed in
// Mesh::duplicates). Throws InputError if a coordinate is outside the supported range, if fewer
// than three distinct points remain, or if all points are collinear (the messages say which).
// Large inputs are triangulated in two halves, on two threads unless `threads` is 1 (0: all
// hardware threads); the halves depend only on the input, so the mesh does not depend on it.
MWST_API Mesh delaunay(std::vector<Point> points, DelaunayStats* stats = nullptr, unsigned threads = 0);

struct ConstrainOptions {
  bool strict = false;       // refuse crossing segments (InputError naming both) instead of splitting
  bool convex_hull = false;  // keep the whole convex hull (Triangle's -c); holes still carve
  unsigned threads = 0;      // delaunay()'s threads (1: one; 0: all hardware threads)
};

struct ConstrainStats {
  std::size_t duplicates = 0;        // merged duplicate points
  std::size_t zero_length = 0;       // segments dropped because both ends coincide
  std::size_t split_by_vertex = 0;   // segments split at a vertex lying inside them
  std::size_t crossings = 0;         // crossing points inserted (new Steiner vertices)
  std::size_t overlaps = 0;          // collinear overlapping segments merged (and repeated segments)
  std::size_t snapped = 0;           // crossings resolved at an existing vertex: one within rounding
                                     // of the crossing point, or an end of one piece within rounding
                                     // of the other's line
  std::vector<std::string> warnings; // e.g. hole seeds outside the domain or on a segment
  double seconds_delaunay = 0.0;
  double seconds_segments = 0.0;
  double seconds_carve = 0.0;
};

// Constrained Delaunay triangulation of a planar straight-line graph, carved to its domain:
// what the segments enclose minus the holes (flood fill across non-segment edges from hole seeds
// and from hull edges that are not segments). A graph without segments keeps its convex hull.
// Input points keep their ids; crossing points are appended as Steiner vertices.
MWST_API Mesh constrained_delaunay(const Pslg& pslg, const ConstrainOptions& options = {},
                          ConstrainStats* stats = nullptr);

// Inserts the segment between existing vertices a and b (a ≠ b) into a constrained Delaunay mesh:
// the triangles it crosses are removed and the two pseudo-polygons on either side are
// retriangulated (constrained Delaunay). Vertices lying on the open segment split it; the caller
// must have resolved crossings with other segments (InternalError otherwise).
MWST_API void insert_segment(Mesh& mesh, VertexId a, VertexId b, std::int32_t marker);

// Lawson's flip algorithm from a stack of suspect edges: flips every edge that is not locally
// Delaunay (ghost triangles included) and is not a subsegment, re-examining the four edges around
// each flip, until none is left. On any triangulation it ends with the constrained Delaunay
// triangulation of its vertices and subsegments (Lawson 1977; each flip lifts the surface).
MWST_API void restore_delaunay(Mesh& mesh, std::vector<Handle>& stack);

// Marks triangles outside the domain with kOutside (see constrained_delaunay).
MWST_API void carve(Mesh& mesh, const std::vector<Point>& holes, bool convex_hull,
           std::vector<std::string>* warnings = nullptr);

}  // namespace mwst
