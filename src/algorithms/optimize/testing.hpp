// src/algorithms/optimize/testing.hpp — switches that only tests set: each runs the search a slower
// way that must give the same result (tests/algorithms/optimize/test_optimize.cpp compares the two). Internal.
#pragma once

#include "mwst/algorithms/optimize.hpp"
#include "mwst/export.hpp"

namespace mwst {

struct OptimizeTestSwitches {
  // With false, every region the local search looks at is tried afresh, even one whose
  // triangles, corners and neighbours are exactly as when it last failed (the search remembers
  // those by fingerprint and skips them; OptimizeStats::region_tries_skipped). The result is the
  // same either way; only the time differs.
  bool remember_failed_regions = true;
  // With true, a kick that is not kept is undone by restoring a copy of the mesh made before it,
  // instead of by the mesh's trial journal (Mesh::begin_trial). Same result, slower.
  bool undo_trials_by_copy = false;
};

// optimize() with test switches.
MWST_API OptimizeStats optimize(Mesh& mesh, const OptimizeOptions& options, const OptimizeTestSwitches& test);

}  // namespace mwst
