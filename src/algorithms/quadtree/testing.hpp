// algorithms/quadtree/testing.hpp — test switches of quadtree refinement, kept out of the public
// QuadtreeOptions: the final quadtree's leaves, a forced fallback, the size bound turned off. For tests/algorithms/quadtree/test_quadtree.cpp.
#pragma once

#include <vector>

#include "mwst/algorithms/quadtree.hpp"

namespace mwst::qtr {

// A leaf of the final quadtree: lower-left corner, side, and whether its closed square meets a
// feature (a vertex or a segment).
struct QuadtreeLeaf {
  double x = 0.0, y = 0.0, size = 0.0;
  bool meets_feature = false;
};

struct TestSwitches {
  bool keep_leaves = false;     // fill *leaves with the final quadtree's leaves, in node order
  bool force_fallback = false;  // skip the quadtree route and build the fallback
  bool skip_size_bound = false; // build the tree even where the lower bound on its leaves
                                // (size_bound.cpp) already exceeds QuadtreeOptions::max_leaves
};

// quadtree_refinement() with the test switches; `leaves` may be null (then keep_leaves is ignored).
Mesh refine_with_switches(const Pslg& pslg, const QuadtreeOptions& options, const TestSwitches& switches,
                          QuadtreeStats* stats, std::vector<QuadtreeLeaf>* leaves);

}  // namespace mwst::qtr
