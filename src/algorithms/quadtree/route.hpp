// algorithms/quadtree/route.hpp — the vocabulary of quadtree refinement (QTR), shared by the files
// of this folder, and the route's stages in order, by file (docs/algorithms/quadtree.md explains
// the method's steps, 1 to 5, and where each one lives):
//
//   quadtree.cpp           quadtree_refinement(): runs the stages below, or the fallback
//   1. clean_input.cpp     clean_graph(), clean_point_set(): the features (vertices, segments)
//      size_bound.cpp      segment_leaf_lower_bound(): how many leaves the tree needs at least
//   2. tree.hpp            Tree: nodes, feature lists, neighbour look-ups (inline)
//      tree_build.cpp      Tree(): the root and the vertices' Morton ranks; build(): split by
//                          the feature rule, level by level
//      tree_balance.cpp    Tree::finish(): balance and the warp rule, in two lanes then one
//   3. builder.hpp         Builder: from the leaves to the mesh
//      builder_grid.cpp    number_vertices(), build_loops(), warp(): grid vertices, each leaf's
//                          loop, corners onto input vertices
//      builder_segments.cpp segments_pass(): corners onto segments, crossing points, chains
//      cells.hpp           the case table with its adjacency (PlainCell)
//      builder_cells.cpp   prepare_cells(), emit_cells(): each leaf's triangles
//      quadtree_cells.cpp  the max–min-angle dynamic program and the case table (detail::)
//      builder_link.cpp    triangulate_cells() over chunks, link_cell(), the border, the segments
//      builder_run.cpp     Builder::run(): the steps in order, the mesh's arrays, carving
//   4. fallback.cpp        fallback_mesh(); drop_unused_vertices(): corners outside the domain
//   testing.hpp            the test switches (refine_with_switches()), for tests/algorithms/quadtree/test_quadtree.cpp
// Memory and thread helpers live in src/support/ (parallel.hpp, spare_room.hpp, page_faulter.hpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mwst/algorithms/quadtree.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"
#include "support/parallel.hpp"

namespace mwst::qtr {

// ---- timing and threads ---------------------------------------------------------------------------

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The workers for a pass over `count` items (support::parallel_ranges(): contiguous halves that
// write disjoint ranges; the first half's exception wins, as it would in one pass): two from
// `threshold` on (and at least two items), else one, in the calling thread.
inline std::size_t workers_for(std::size_t count, std::size_t threshold) {
  return count < threshold || count < 2 ? 1 : 2;
}

// The size from which a pass splits over two threads: `large` by default, never with
// QuadtreeOptions::threads = 1, always with 2.
inline std::size_t threads_from(const QuadtreeOptions& options, std::size_t large) {
  if (options.threads == 1) return std::numeric_limits<std::size_t>::max();
  return options.threads == 2 ? 0 : large;
}

// ---- failure --------------------------------------------------------------------------------------

// The quadtree route could not finish (see quadtree.cpp); the caller builds the fallback.
struct RouteFailure {
  std::string reason;
  bool corners_usable = true;  // the fallback may add the quadtree's free corners
  bool out_of_time = false;    // QuadtreeOptions::deadline passed (check_deadline())
};

// ---- the time budget ------------------------------------------------------------------------------

// QuadtreeOptions::deadline, checked by the route's long loops between their steps and every
// kClockStride items (a clock read costs about 20 ns; a stride of items at least a few hundred
// microseconds): past it, RouteFailure with out_of_time, and the caller falls back to the CDT
// alone (no corners: the tree is half built).
inline constexpr std::size_t kClockStride = 4096;
inline void check_deadline(Clock::time_point deadline) {
  if (deadline == Clock::time_point::max() || Clock::now() < deadline) return;
  throw RouteFailure{"the time budget ran out", /*corners_usable=*/false,
                     /*out_of_time=*/true};
}
// The check on item i of a loop: every kClockStride-th item only.
inline void check_deadline_at(std::size_t i, Clock::time_point deadline) {
  if (i % kClockStride == 0) check_deadline(deadline);
}

// Points the route puts on segments (crossings, snapped corners) are rounded, up to half an ulp off
// the segment's line; the domain's boundary moves with them, by at most the sum of each subsegment's
// length times the larger offset of its ends. That must stay below this fraction of the domain's
// area — it does by far unless the domain is a sliver thinner than a few ulps, where the rounding
// would decide the area and, for an independent check, which side of a segment a point is on.
constexpr double kBoundaryRoundingShare = 1e-10;

// ---- the clean input (clean_input.cpp) ------------------------------------------------------

struct FeatureSegment {
  VertexId a = 0, b = 0;
  std::int32_t marker = 0;
  bool hull_only = false;  // a convex hull edge that is not an input segment (domain boundary only)
};

struct CleanInput {
  Mesh vertices_only;                    // points, kinds, markers, duplicates; no triangles
  std::vector<VertexId> vertices;        // feature vertices (every vertex that is not a duplicate)
  std::vector<FeatureSegment> segments;  // subsegments of the clean graph, then hull edges
  double domain_area = 0.0;              // of the input's domain (in floating point)
  std::vector<Point> hole_seeds;         // where to carve the holes (see clean_graph())
  double leaf_lower_bound = 0.0;         // leaves the tree will have at least (size_bound.cpp)
  // Under a time budget (QuadtreeOptions::deadline): fallback_mesh() without extra points, kept
  // for the fallback (a graph's cleaning CDT; a point set's Delaunay triangulation, made first).
  std::optional<Mesh> cdt_for_fallback;
};

// A PSLG with segments: its CDT resolves duplicates, vertices on segments and crossings; the
// subsegments of the CDT are the clean segments.
CleanInput clean_graph(const Pslg& pslg, const QuadtreeOptions& options, QuadtreeStats& stats);
// A lower bound on the leaves of the finished quadtree that meet the segments of `cdt` (the input's
// CDT; its subsegments are the clean segments), for cells no larger than `clip` at the deepest
// level (size_bound.cpp). O(segments · log of their distance ratios); it stops (with a bound above
// stop_above) once the bound exceeds stop_above.
double segment_leaf_lower_bound(const Mesh& cdt, double clip, double stop_above);
// A point set: duplicates by sorting, the convex hull by Andrew's monotone chain (exact), the
// points on hull edges inserted into them. O(n log n).
CleanInput clean_point_set(const Pslg& pslg, const QuadtreeOptions& options);
// The centroid of finite triangle t of m, if it lies strictly inside t (exact): a hole seed.
std::optional<Point> inner_centroid(const Mesh& m, TriangleId t);

// ---- after the route (fallback.cpp) ---------------------------------------------------------------

// The carved CDT of the input plus `extra` Steiner points inserted strictly inside its domain;
// past options.deadline the rest of `extra` is left out and *out_of_time is set.
Mesh fallback_mesh(const Pslg& pslg, const QuadtreeOptions& options, std::vector<Point> extra, bool* out_of_time);
// The vertices the output keeps: the input points and the corners of the domain's triangles.
std::vector<char> kept_vertices(const Mesh& m);
// The first kept vertex outside the supported coordinate range, or kNone.
VertexId out_of_range_vertex(const Mesh& m, const std::vector<char>& kept);
// Drops the vertices kept_vertices() does not keep; the rest of the hull is triangulated anew.
void drop_unused_vertices(Mesh& m, const std::vector<char>& kept);

}  // namespace mwst::qtr
