// src/algorithms/mwt/polygon_mwt.hpp — the minimum weight triangulation of a simple polygon by
// dynamic programming (Gilbert 1979; Klincsek 1980; docs/algorithms/mwt.md). Internal (not
// installed): the exact MWT (mwt.cpp) runs it on the faces of its LMT-skeleton, the optimiser
// (algorithms/optimize/) on every star and small region it re-triangulates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mwst/export.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst {

// Minimum weight triangulation of a simple polygon (vertices counter-clockwise) by dynamic
// programming over its valid diagonals, O(d³). Returns the total length of the diagonals used, or
// +inf if the polygon cannot be triangulated (not simple), and appends its triangles (indices into
// the polygon) to `triangles`. Ties go to the smallest apex (the first one found).
MWST_API double polygon_mwt(const std::vector<Point>& polygon, std::vector<std::array<std::uint32_t, 3>>* triangles);

// True if the closed polygon (counter-clockwise) is simple and strictly convex: every corner turns
// left and the fan from the first vertex turns left throughout (exact orientation tests).
MWST_API bool is_strictly_convex(const std::vector<Point>& polygon);

}  // namespace mwst
