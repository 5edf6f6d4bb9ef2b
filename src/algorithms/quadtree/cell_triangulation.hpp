// algorithms/quadtree/cell_triangulation.hpp — triangulating the cells of QTR (quadtree_cells.cpp):
// the case table of unwarped leaves, and the max–min-angle triangulation of warped or cut pieces.
// Internal (not installed); exported for the tests.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mwst/export.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst {

namespace detail {

// Max–min-angle triangulation of a simple polygon given counter-clockwise (collinear and slightly
// reflex vertices allowed), by dynamic programming over its diagonals (O(k³), k ≤ 64). Every
// triangle is strictly counter-clockwise (exact orient2d) and every diagonal lies inside the
// polygon (exact tests). Ties are broken by the smaller total diagonal length. Returns false if the
// polygon has no such triangulation (degenerate); otherwise appends k − 2 triangles of local
// indices to `out`.
MWST_API bool triangulate_polygon(const std::vector<Point>& polygon,
                         std::vector<std::array<std::uint8_t, 3>>& out);

// Testing only: triangulate_polygon() giving the program's smallest-angle sine too (the value
// triangulate_piece() compares with the fan), with its shortcut for weakly convex quadrilaterals
// (general = false) or the general program for every k (general = true). The two must agree
// exactly: the same triangles in the same order and the same quality.
MWST_API bool triangulate_polygon_quality(const std::vector<Point>& polygon,
                                 std::vector<std::array<std::uint8_t, 3>>& out, double& quality, bool general);

// Sine of the smallest angle over the given triangles of a polygon (+inf if there are none).
MWST_API double triangulation_quality(const std::vector<Point>& polygon,
                             const std::vector<std::array<std::uint8_t, 3>>& triangles);

// The fan from the polygon's vertex average: false unless every triangle (centre, v_i, v_i+1) is
// strictly counter-clockwise (exact); `quality` receives its smallest-angle sine.
MWST_API bool centroid_fan(const std::vector<Point>& polygon, Point& centre, double& quality);

// Triangulates a warped or cut piece of a cell: the max–min-angle triangulation of its boundary,
// unless that has an angle below 20° and the fan from the polygon's vertex average is better; then
// that fan (its triangles use index polygon.size() for `centre`, and used_centre is set). Returns
// false if neither is valid.
MWST_API bool triangulate_piece(const std::vector<Point>& polygon, std::vector<std::array<std::uint8_t, 3>>& out,
                       Point& centre, bool& used_centre);

// The case table: for each mask of present side midpoints (bit 0 bottom, 1 right, 2 top, 3 left),
// triangles over the slots 0 BL, 1 bottom-mid, 2 BR, 3 right-mid, 4 TR, 5 top-mid, 6 TL, 7 left-mid.
MWST_API const std::array<std::vector<std::array<std::uint8_t, 3>>, 16>& quadtree_case_table();

}  // namespace detail

}  // namespace mwst
