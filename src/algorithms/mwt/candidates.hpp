// src/algorithms/mwt/candidates.hpp — the candidate edges of the exact MWT's two routes
// (docs/algorithms/mwt.md, step 1). Internal (not installed).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "algorithms/mwt/domain.hpp"

namespace mwst::mwt {

// Route "diamond": the pairs of points of P that pass the diamond test of Drysdale, McElfresh and
// Snoeyink with base angle `angle` (an edge of the MWT of the point set has an empty isosceles
// triangle on one side). Sets too_many (and stops) past max_edges.
std::vector<std::array<Index, 2>> diamond_candidates(const std::vector<Point>& P, double angle,
                                                     std::size_t max_edges, bool& too_many);

// Route "visibility": every pair whose open segment lies in the domain, contains no vertex and
// crosses no constraint, without straight-angle slivers at a segment's Steiner point.
std::vector<std::array<Index, 2>> visibility_candidates(const Domain& d);

}  // namespace mwst::mwt
