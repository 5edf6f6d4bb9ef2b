// tests/mesh/test_check.cpp — the independent checker behind `mwst check` (src/mesh/check.cpp) refuses
// planted faults that its reference domain (the constrained Delaunay triangulation of the input,
// built by the same code as the meshes) cannot see: a crossing vertex or a Steiner point moved off
// its input segment by more than rounding, and vertices outside the supported coordinate range.
// Each fault is planted into an otherwise valid mesh that the checker first accepts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "support/exact_checker.hpp"
#include "support/regression_files.hpp"

namespace mwst {
namespace {

using test::joined;

bool mentions(const CheckResult& r, const std::string& text) {
  return std::any_of(r.messages.begin(), r.messages.end(),
                     [&](const std::string& m) { return m.find(text) != std::string::npos; });
}

// A 4 × 4 square with its two diagonals from (1, 1) to (3, 3) and from (1, 3) to (3, 1): they cross
// at (2, 2), the one Steiner point.
Pslg crossing_square() {
  return io::parse_poly(
      "8 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 3 3\n7 1 3\n8 3 1\n"
      "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 7 8\n0\n",
      "crossing_square.poly");
}

TEST(Check, PlantedCrossingMovedOffBothSegmentsIsRefused) {
  const Pslg g = crossing_square();
  Mesh m = constrained_delaunay(g, {});
  ASSERT_EQ(m.points.size(), 9u);
  ASSERT_EQ(m.points[8], (Point{2, 2}));
  const CheckResult valid = test::check_mesh(g, m);
  ASSERT_TRUE(valid.ok()) << joined(valid.messages);
  // 3e-12 is 3400 ulps of 4: far beyond rounding, yet inside the 1e-12 relative tolerance by which
  // the reference chains accept rounded points (which alone let item 4 of issue 36 through).
  m.points[8] = {2.0 + 3e-12, 2.0};
  const CheckResult moved = test::check_mesh(g, m);
  EXPECT_FALSE(moved.ok());
  EXPECT_TRUE(mentions(moved, "is not a chain of mesh edges within rounding of it")) << joined(moved.messages);
  // Moved by one ulp it is still the rounded crossing.
  m.points[8] = {std::nextafter(2.0, 3.0), 2.0};
  const CheckResult ulp = test::check_mesh(g, m);
  EXPECT_FALSE(mentions(ulp, "within rounding")) << joined(ulp.messages);
}

// A Steiner point on the bottom side of a square, moved 3e-12 (3400 ulps of 4) below it: the
// reference's chain test (within 1e-12 of the coordinates' magnitude) and the area (a sliver of
// 6e-12) accept it; the independent segment check does not.
TEST(Check, PlantedSteinerPointOffItsSegmentIsRefused) {
  const Pslg g = io::parse_poly("4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n",
                                "square.poly");
  std::vector<Point> points = g.points;
  points.push_back({2, 0});
  const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 4, 3}, {4, 1, 2}, {4, 2, 3}};
  const std::vector<Segment> subsegments = {{0, 4, 1}, {4, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  const CheckResult valid = check_triangulation(g, points, triangles, subsegments);
  ASSERT_TRUE(valid.ok()) << joined(valid.messages);
  points[4] = {2, -3e-12};
  const CheckResult moved = check_triangulation(g, points, triangles, subsegments);
  EXPECT_FALSE(moved.ok());
  EXPECT_TRUE(mentions(moved, "input segment 1 (line")) << joined(moved.messages);
  EXPECT_TRUE(mentions(moved, "within rounding")) << joined(moved.messages);
}

// The mesh issue 36 item 4 reported, as it was written: the crossing of
// tests/regression/crossing_snapped_far_off_segment.poly at (9.63e-51, -1.04e-50) put at x = 0.
// The checker refuses it: the input itself is refused now (its crossing has no representable
// rounding), and the segments are no chains within rounding.
TEST(Check, SnappedCrossingOfTheRegressionInputIsRefused) {
  const std::string path = test::regression_path("crossing_snapped_far_off_segment.poly");
  const Pslg g = io::read_input(path);
  std::vector<Point> points = g.points;
  points.push_back({0, -1.0365853658536586e-50});
  // The .ele it was written with (counted from 0 here).
  const std::vector<std::array<std::uint32_t, 3>> triangles = {
      {6, 7, 2}, {4, 0, 7}, {3, 4, 5}, {6, 2, 1}, {7, 0, 2}, {0, 3, 8},
      {0, 4, 3}, {3, 5, 1}, {5, 6, 1}, {1, 8, 3}, {1, 2, 8}, {2, 0, 8}};
  EXPECT_THROW(check_triangulation(g, points, triangles, {}), InputError);
  // Without the second segment the input has no crossing (the reference accepts it), and the
  // first segment's chain through the moved vertex is refused.
  Pslg one = g;
  one.segments.erase(one.segments.begin() + 1);
  const CheckResult r = check_triangulation(one, points, triangles, {});
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r, "input segment 1 (line")) << joined(r.messages);
}

// Vertices outside the supported range (what qtr once wrote: an unused corner at -3.74e50, a
// corner at x = 1.34e-51) are violations, used or not.
TEST(Check, PlantedOutOfRangeVerticesAreRefused) {
  const Pslg g = crossing_square();
  const Mesh m = constrained_delaunay(g, {});
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t)) triangles.push_back(m.triangles[t].v);
  }
  std::vector<Point> points = m.points;
  ASSERT_TRUE(check_triangulation(g, points, triangles, {}).ok());
  for (const Point bad : {Point{-3.74e50, 1.0}, Point{1.34e-51, 2.0}}) {
    std::vector<Point> with = points;
    with.push_back(bad);
    const CheckResult r = check_triangulation(g, with, triangles, {});
    EXPECT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r, "outside the supported coordinate range")) << joined(r.messages);
  }
}

}  // namespace
}  // namespace mwst
