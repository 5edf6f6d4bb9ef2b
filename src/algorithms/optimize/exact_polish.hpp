// src/algorithms/optimize/exact_polish.hpp — one exact polish step on its own (exact_polish.cpp).
// Internal (not installed); the pipeline makes the "+mwt" starts of method opt with it.
#pragma once

#include "mwst/algorithms/optimize.hpp"
#include "mwst/export.hpp"

namespace mwst {

// Compacts `mesh` and, within the exact_polish_* size limits of `options`, replaces its
// triangulation by the exact MWT of its vertices with its segments (exact_mwt,
// mwst/algorithms/mwt.hpp) if that is solved and lighter by more than min_relative_gain. Returns
// true if it did; vertices, segments and markers are unchanged either way.
MWST_API bool exact_polish_mesh(Mesh& mesh, const OptimizeOptions& options);

}  // namespace mwst
