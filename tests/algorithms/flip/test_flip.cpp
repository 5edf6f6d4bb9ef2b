// Tests of the weight-reducing edge flips (EFH): locally minimal result, validity, monotone weight,
// segments and vertices unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/refine.hpp"
#include "support/mesh_queries.hpp"

namespace mwst {
namespace {

void check_flipped(Mesh& m) {
  const Metrics before = measure(m);
  const auto segments_before = test::domain_subsegments(m);
  const FlipStats stats = flip_to_local_minimum(m);
  const Metrics after = measure(m);
  EXPECT_TRUE(validate(m).empty());
  EXPECT_EQ(count_weight_reducing_flips(m), 0u);
  EXPECT_LE(after.weight_total, before.weight_total);
  if (stats.flips > 0) {
    EXPECT_LT(after.weight_total, before.weight_total);
  }
  EXPECT_DOUBLE_EQ(stats.weight_before, before.weight_total);
  EXPECT_DOUBLE_EQ(stats.weight_after, after.weight_total);
  EXPECT_EQ(after.vertices, before.vertices);
  EXPECT_EQ(after.triangles, before.triangles);
  EXPECT_NEAR(after.area, before.area, 1e-9 * before.area);
  // The boundary edges are the same (checked exactly just below); their lengths are summed in
  // triangle-slot order, which flips permute, so the sums may differ by rounding (n·ε relative).
  EXPECT_NEAR(after.weight_boundary, before.weight_boundary, 1e-13 * before.weight_boundary);
  EXPECT_EQ(test::domain_subsegments(m), segments_before);
}

TEST(Flip, ConvexQuadrilateralTakesTheShorterDiagonal) {
  // A kite whose Delaunay diagonal is the long one: (0,0), (10,0) and (5,±1).
  Mesh m = delaunay({{0, 0}, {10, 0}, {5, 1}, {5, -1}});
  const double w0 = measure(m).weight_total;
  const FlipStats stats = flip_to_local_minimum(m);
  EXPECT_EQ(stats.flips, 0u);  // DT already uses the short diagonal (5,-1)-(5,1)
  EXPECT_DOUBLE_EQ(measure(m).weight_total, w0);
  // A quadrilateral whose Delaunay diagonal is the longer one.
  Mesh q = delaunay({{0, 0}, {4, -1}, {5, 3}, {1, 4}});
  check_flipped(q);
}

TEST(Flip, RandomPointSetsReachALocalMinimum) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Point> pts(50 + 40 * trial);
    for (auto& p : pts) p = {u(rng), u(rng) * (1 + trial % 3)};
    Mesh m = delaunay(pts);
    check_flipped(m);
  }
}

TEST(Flip, NeverFlipsNonConvexOrDegenerateQuads) {
  // Points on a parabola-like cup plus a grid: plenty of collinear and cocircular quadrilaterals.
  std::vector<Point> pts;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) pts.push_back({static_cast<double>(i), static_cast<double>(j)});
  }
  Mesh m = delaunay(pts);
  check_flipped(m);
}

class FlipOnDataSet : public ::testing::TestWithParam<std::string> {};

TEST_P(FlipOnDataSet, LocallyMinimalValidAndLighter) {
  Pslg g = io::read_input(GetParam());
  Mesh m = constrained_delaunay(g);
  check_flipped(m);
}

std::vector<std::string> data_sets() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(MWST_DATA_DIR)) {
    if (e.path().extension() == ".poly") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

INSTANTIATE_TEST_SUITE_P(DataSets, FlipOnDataSet, ::testing::ValuesIn(data_sets()),
                         [](const auto& param_info) {
                           return std::filesystem::path(param_info.param).stem().string();
                         });

}  // namespace
// With an area bound (--max-area after dr, brh or opt), EFH takes only the flips that make no
// triangle larger than it. A flip keeps its quadrilateral but not its halves' areas: on a mesh
// refined to the bound, unbounded flips leave triangles over it (checked below, so the test can
// fail), bounded flips none; the result is locally minimal among the allowed flips and lighter.
TEST(Flip, AreaBoundHolds) {
  for (const char* name : {"Superior.poly", "Africa.poly"}) {
    SCOPED_TRACE(name);
    Mesh cdt = constrained_delaunay(io::read_input(std::string(MWST_DATA_DIR) + "/" + name));
    const double max_area = measure(cdt).max_triangle_area / 50.0;
    test::refine_to_area(cdt, max_area);
    ASSERT_LE(measure(cdt).max_triangle_area, max_area);
    Mesh free = cdt, bounded = cdt;
    flip_to_local_minimum(free);
    EXPECT_GT(measure(free).max_triangle_area, max_area * 1.01);
    const FlipStats stats = flip_to_local_minimum(bounded, max_area);
    EXPECT_GT(stats.flips, 0u);
    EXPECT_TRUE(validate(bounded).empty());
    EXPECT_LE(measure(bounded).max_triangle_area, max_area);
    for (TriangleId t = 0; t < bounded.triangles.size(); ++t) {
      if (!bounded.in_domain(t)) continue;
      const auto& v = bounded.triangles[t].v;
      EXPECT_LE(triangle_area(bounded.points[v[0]], bounded.points[v[1]], bounded.points[v[2]]), max_area);
    }
    EXPECT_EQ(count_weight_reducing_flips(bounded, max_area), 0u);
    EXPECT_GT(count_weight_reducing_flips(bounded), 0u);
    EXPECT_LT(measure(bounded).weight_total, measure(cdt).weight_total);
    EXPECT_EQ(test::domain_subsegments(bounded), test::domain_subsegments(cdt));
  }
}

// Points on an ellipse: their Delaunay triangulation is a fan of long chords, far from a local
// minimum (thousands of flips), as BRH's mesh is when opt's time budget cuts it short.
Mesh ellipse_delaunay(std::size_t n) {
  std::vector<Point> pts(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 2.0 * 3.141592653589793 * static_cast<double>(i) / static_cast<double>(n);
    pts[i] = {std::cos(t), 0.5 * std::sin(t)};
  }
  return delaunay(pts);
}

TEST(Flip, DeadlinePassedFlipsNothing) {
  const Mesh dt = ellipse_delaunay(4000);
  Mesh full = dt;
  const FlipStats all = flip_to_local_minimum(full);
  ASSERT_GT(all.flips, 4096u);
  EXPECT_FALSE(all.out_of_time);

  // A deadline already passed: not even the first scan of the edges (a second on a million
  // triangles), the mesh as it was.
  Mesh cut = dt;
  const FlipStats stopped =
      flip_to_local_minimum(cut, -1.0, std::chrono::steady_clock::now() - std::chrono::seconds(1));
  EXPECT_TRUE(stopped.out_of_time);
  EXPECT_EQ(stopped.flips, 0u);
  EXPECT_TRUE(validate(cut).empty());
  ASSERT_EQ(cut.triangles.size(), dt.triangles.size());
  for (TriangleId t = 0; t < cut.triangles.size(); ++t) EXPECT_EQ(cut.triangles[t].v, dt.triangles[t].v);
  EXPECT_GT(count_weight_reducing_flips(cut), 0u);
}

TEST(Flip, DeadlineNotReachedGivesTheSameFlips) {
  const Mesh dt = ellipse_delaunay(3000);
  Mesh plain = dt, timed = dt;
  const FlipStats a = flip_to_local_minimum(plain);
  const FlipStats b = flip_to_local_minimum(timed, -1.0, std::chrono::steady_clock::now() + std::chrono::hours(1));
  EXPECT_FALSE(b.out_of_time);
  EXPECT_EQ(a.flips, b.flips);
  ASSERT_EQ(plain.triangles.size(), timed.triangles.size());
  for (TriangleId t = 0; t < plain.triangles.size(); ++t) {
    EXPECT_EQ(plain.triangles[t].v, timed.triangles[t].v);
  }
}

}  // namespace mwst
