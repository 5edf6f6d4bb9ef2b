// tests/algorithms/refine/test_clean_queries.cpp — bundle removal's clean list (clean_queries.hpp):
// after a pass it forgets exactly the entries whose box covers a grid cell that a triangle made by
// the pass covers. The cells are counted with a summed-area table; here every entry is checked
// against walking the cells of each box, on boxes from a point to the whole mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <random>
#include <utility>
#include <vector>

#include "algorithms/refine/clean_queries.hpp"
#include "mwst/mesh/delaunay.hpp"

namespace mwst {
namespace {

using Box = std::array<double, 4>;

Box box_of(const Mesh& m, TriangleId t) {
  Box b{1e300, 1e300, -1e300, -1e300};
  for (const VertexId v : m.triangles[t].v) {
    const Point& p = m.points[v];
    b = {std::min(b[0], p.x), std::min(b[1], p.y), std::max(b[2], p.x), std::max(b[3], p.y)};
  }
  return b;
}

// Does `entry` cover a cell of the 256 × 256 grid over the made boxes that one of them covers?
// (Each box's cells walked one by one.)
bool covers_a_made_cell(const Box& entry, const std::vector<Box>& made) {
  Box all{1e300, 1e300, -1e300, -1e300};
  for (const Box& b : made) all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]), std::max(all[3], b[3])};
  if (entry[2] < all[0] || entry[0] > all[2] || entry[3] < all[1] || entry[1] > all[3]) return false;
  const double sx = all[2] > all[0] ? 256.0 / (all[2] - all[0]) : 0.0;
  const double sy = all[3] > all[1] ? 256.0 / (all[3] - all[1]) : 0.0;
  auto cell = [](double v, double v0, double scale) {
    return static_cast<long>(std::clamp(std::floor((v - v0) * scale), 0.0, 255.0));
  };
  for (const Box& b : made) {
    const long x0 = std::max(cell(b[0], all[0], sx), cell(entry[0], all[0], sx));
    const long x1 = std::min(cell(b[2], all[0], sx), cell(entry[2], all[0], sx));
    const long y0 = std::max(cell(b[1], all[1], sy), cell(entry[1], all[1], sy));
    const long y1 = std::min(cell(b[3], all[1], sy), cell(entry[3], all[1], sy));
    if (x0 <= x1 && y0 <= y1) return true;
  }
  return false;
}

TEST(CleanQueries, ForgetsExactlyTheEntriesOverCellsOfMadeTriangles) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> pts(3000);
  for (Point& p : pts) p = {u(rng), u(rng)};
  for (const int made_count : {1, 40, 2000}) {
    SCOPED_TRACE(made_count);
    Mesh m = delaunay(pts);
    brh::CleanQueries clean;
    std::vector<std::pair<std::array<VertexId, 3>, Box>> entries;
    for (VertexId i = 0; i < 4000; ++i) {
      const double x = u(rng), y = u(rng);
      const double w = std::pow(10.0, -4.0 * u(rng)), h = std::pow(10.0, -4.0 * u(rng));  // 1e-4 to 1
      const Box b{x - w, y - h, x + w, y + h};
      entries.push_back({{i, i + 1, i + 2}, b});
      clean.add(entries.back().first, b);
    }
    clean.snapshot(m);
    // "Made" triangles: live finite slots whose corners are rotated (the same triangle, changed).
    std::vector<TriangleId> finite;
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (!m.is_dead(t) && !m.is_ghost(t)) finite.push_back(t);
    }
    std::shuffle(finite.begin(), finite.end(), rng);
    std::vector<Box> made;
    for (int i = 0; i < made_count; ++i) {
      auto& v = m.triangles[finite[static_cast<std::size_t>(i)]].v;
      v = {v[1], v[2], v[0]};
      made.push_back(box_of(m, finite[static_cast<std::size_t>(i)]));
    }
    clean.update(m);
    std::size_t forgotten = 0;
    for (const auto& [key, b] : entries) {
      const bool expect_forgotten = covers_a_made_cell(b, made);
      EXPECT_EQ(clean.contains(key), !expect_forgotten);
      forgotten += expect_forgotten ? 1 : 0;
    }
    EXPECT_GT(forgotten, 0u);
    EXPECT_LT(forgotten, entries.size());
  }
}

}  // namespace
}  // namespace mwst
