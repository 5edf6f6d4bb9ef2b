// mwst/algorithms/quadtree.hpp — quadtree refinement (QTR): a Steiner triangulation of a point set
// or of a polygonal domain with holes from a balanced quadtree, after Bern, Eppstein and Gilbert,
// "Provably good mesh generation" (FOCS 1990; JCSS 48, 1994); the QTR column of Boyacı, Erten,
// Üngör, "Triangulations Loosing Bundles and Weight". Eppstein (1994): such a triangulation weighs
// O(1) times the minimum weight Steiner triangulation.
// Contract: input vertices keep their ids and positions; every input segment is a chain of
// subsegments; the domain is the CDT's (same area); every Steiner point is a corner of a triangle
// of the domain and lies in the supported coordinate range. A leaf of size s that meets a feature
// has s ≤ 2·lfs; untouched cells have all angles in [26.57°, 90°]; cut cells have no proven angle
// bound. The output is byte-identical whatever the number of threads. If the quadtree route cannot
// finish (QuadtreeStats::fallback), the output is the CDT of the input plus the quadtree's free
// corners: valid, without the guarantees. A route stopped by QuadtreeOptions::deadline falls back
// to the CDT of the input alone (QuadtreeStats::out_of_time).
// The route, the case table, the guarantees with their measurements, and the data layout:
// docs/algorithms/quadtree.md.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

struct QuadtreeOptions {
  bool convex_hull = false;    // keep the whole convex hull (Triangle's -c); holes still carve
  bool strict = false;         // refuse crossing segments (InputError) instead of splitting them
  // BEG's warp towards segments (docs/algorithms/quadtree.md, step 4): a corner moves onto a
  // segment crossing one of its edges within this fraction of the leaf size, or lying this
  // fraction of its largest leaf from it (and 0.4 of its smallest). In (0, 0.5); larger values
  // move more corners and leave fewer, fatter pieces in cut cells.
  double snap_fraction = 0.4;
  // Deepest level of the quadtree (cells of size root / 2^max_depth); at most 52 (cell corners
  // are then still distinct doubles for inputs near the origin).
  unsigned max_depth = 50;
  // Most leaves the quadtree may have; beyond it the route falls back (QuadtreeStats::fallback)
  // instead of running out of memory or time. 0: automatic, 1024 per input feature (vertex or
  // segment) but at least 2^20 and at most 2^26.
  std::size_t max_leaves = 0;
  // 0: two threads on large inputs (about 10^4 points and up); 1: one thread; 2: two threads
  // whatever the size (testing). The output is byte-identical in all three.
  unsigned threads = 0;
  // The time budget: past it the route stops at its next clock check (every few thousand cells,
  // features or work items of the tree, the mesh's chunks) and the output is the carved CDT of the
  // input (QuadtreeStats::out_of_time). The cleaning CDT and that fallback CDT are not
  // interrupted: a run takes at least their time. time_point::max(): no budget.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  // Under a deadline, the seconds set aside before it for each vertex the mesh will have beyond the
  // input's (about one per leaf: 2.2M vertices for 1.9M leaves on 160k uniform points), for the
  // caller's writing: once the tree is done, the mesh is built against the deadline less that much.
  double time_reserve_per_vertex = 0.0;
};

struct QuadtreeStats {
  ConstrainStats input;              // the cleaning CDT (duplicates, crossings, warnings)
  std::size_t features_vertices = 0;
  std::size_t features_segments = 0; // subsegments of the clean input (plus hull edges if any)
  std::size_t leaves = 0;
  unsigned depth = 0;                // deepest leaf level
  std::size_t splits_feature = 0;    // splits by the "meets the input simply" rule
  std::size_t splits_balance = 0;    // splits to balance neighbours
  std::size_t splits_warp = 0;       // splits by the warp rule
  std::size_t unresolved = 0;        // leaves at max_depth that still see the input non-simply
  std::size_t warped = 0;            // corners moved onto input vertices
  std::size_t snapped = 0;           // corners moved onto segments
  std::size_t on_segment = 0;        // corners lying exactly on a segment (not moved)
  std::size_t crossings = 0;         // Steiner points where segments cross cell edges
  std::size_t centres = 0;           // Steiner points at the centre of a distorted cell or piece
  std::size_t table_cells = 0;       // leaves triangulated by the case table
  std::size_t program_cells = 0;     // warped or cut leaves triangulated by the dynamic program
  bool fallback = false;             // the quadtree route failed; the output is the CDT of the
  std::string fallback_reason;       //   input plus the quadtree's corners (valid, no guarantees)
  bool out_of_time = false;          // QuadtreeOptions::deadline passed: the fallback, no corners
  std::vector<std::string> warnings;
  double seconds_input = 0.0;        // cleaning (CDT or, for a point set, sort + hull)
  double seconds_tree = 0.0;         // splitting, balancing
  double seconds_mesh = 0.0;         // warping, cutting, triangulating, assembling
  double seconds_carve = 0.0;
};

// Quadtree refinement of a point set (.node: the domain is the convex hull) or a PSLG (.poly: the
// domain the segments enclose minus the holes). Input points keep their ids (duplicates are
// VertexKind::kDuplicate); Steiner points come after them, VertexKind::kSteinerOnSegment on input
// segments and kSteiner elsewhere, only those the domain's triangles use (quadtree corners outside
// the domain are dropped; carved kOutside triangles of the kept vertices fill the rest of the
// hull). Throws InputError for input the CDT refuses.
MWST_API Mesh quadtree_refinement(const Pslg& pslg, const QuadtreeOptions& options = {},
                         QuadtreeStats* stats = nullptr);

}  // namespace mwst
