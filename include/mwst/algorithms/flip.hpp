// mwst/algorithms/flip.hpp — the paper's edge flip heuristic (EFH): greedy weight-reducing flips.
#pragma once

#include <chrono>
#include <cstddef>

#include "mwst/mesh/mesh.hpp"

namespace mwst {

struct FlipStats {
  std::size_t flips = 0;
  double weight_before = 0.0;  // total weight of the domain triangles
  double weight_after = 0.0;
  double seconds = 0.0;
  bool out_of_time = false;  // stopped at the deadline before the local minimum
};

// True if a triangle corner at v whose two sides are subsegments (side1_is_segment,
// side2_is_segment) would be a straight angle in truth: v is a Steiner point splitting a segment,
// and its two subsegments are straight however convex the rounded point makes the corner look. Such
// a triangle is a sliver along the segment; neither the flips nor the optimiser may make one.
MWST_API bool is_straight_corner(const Mesh& mesh, VertexId v, bool side1_is_segment, bool side2_is_segment);

// True if edge h (between two domain triangles, not a subsegment) has a strictly convex
// quadrilateral whose other diagonal is strictly shorter (exact comparison of squared lengths).
// With max_area > 0 (an area bound), also neither new triangle may be larger than
// max_area (triangle_area): a flip keeps its quadrilateral but not the areas of its two
// halves, so without this EFH would undo what the refinement's area bound made.
MWST_API bool is_weight_reducing_flip(const Mesh& mesh, Handle h, double max_area = -1.0);

// Repeatedly flips the weight-reducing edge with the largest relative gain (|ac| / |bd|, the old
// diagonal over the new) until none is left. Segments and vertices never change; the weight
// strictly drops with every flip, so it terminates. The result is locally minimal: no single flip
// lowers the weight. Afterwards the mesh is generally no longer Delaunay. With max_area > 0 only
// flips that make no triangle larger than it are taken (is_weight_reducing_flip).
MWST_API FlipStats flip_to_local_minimum(Mesh& mesh, double max_area = -1.0);

// The same flips in the same order, stopped between two flips once `deadline` has passed (then
// out_of_time is set; a deadline already passed returns at once, weights left 0): the mesh is
// valid and no heavier, and the flips done are those of largest gain. Before the deadline the result is flip_to_local_minimum's exactly. A time budget (opt's
// --time-limit) uses it: on a large mesh far from a local minimum, e.g. BRH's cut short by the
// budget, the flips alone take seconds.
MWST_API FlipStats flip_to_local_minimum(Mesh& mesh, double max_area, std::chrono::steady_clock::time_point deadline);

// Number of weight-reducing flips available (0 after flip_to_local_minimum with the same bound).
MWST_API std::size_t count_weight_reducing_flips(const Mesh& mesh, double max_area = -1.0);

}  // namespace mwst
