// src/algorithms/optimize/crossover.hpp — partition crossover of two triangulations of one input
// (crossover.cpp; docs/algorithms/optimize.md). Internal (not installed); method opt's last step.
#pragma once

#include <cstddef>

#include "mwst/export.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {

// Cuts the domain along the edges two triangulations of the same input share, and replaces each
// piece of `a` by `b`'s triangles there when those are lighter and meet the rest along the same
// edges, marked as the same subsegments. `a` is never made heavier; it is compacted.
struct CrossoverStats {
  std::size_t pieces = 0;      // pieces of the domain between shared edges
  std::size_t taken = 0;       // pieces taken from b
  std::size_t mismatched = 0;  // pieces whose boundary differs in b (a segment split differently,
                               // or an edge a subsegment in one parent only)
  double gain = 0.0;           // weight removed from a
};
MWST_API CrossoverStats partition_crossover(Mesh& a, const Mesh& b);

}  // namespace mwst
