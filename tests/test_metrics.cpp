// tests/test_metrics.cpp — measure() (src/algorithms/metrics.cpp) against a direct recomputation:
// every domain edge's length once (boundary = not shared by two domain triangles, or a segment),
// the angle extremes from all three angles of every domain triangle (triangle_angles_deg, atan2
// per corner), and the area by the shoelace formula in long double. measure() finds the extremes
// from one corner per triangle (the smallest angle is opposite the shortest edge, the largest
// opposite the longest) without trigonometry, so this checks that shortcut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>

#include "mwst/delaunay.hpp"
#include "mwst/io.hpp"
#include "mwst/metrics.hpp"
#include "mwst/refine.hpp"
#include "test_helpers.hpp"

namespace {

using namespace mwst;

void expect_measure_matches_direct(const Mesh& m) {
  const Metrics r = measure(m);
  std::map<std::pair<VertexId, VertexId>, int> edge_count;
  std::map<std::pair<VertexId, VertexId>, bool> edge_segment;
  double min_angle = 180.0, max_angle = 0.0;
  long double area = 0.0L;
  std::size_t triangles = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    ++triangles;
    const Triangle& T = m.triangles[t];
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId u = m.org(h), w = m.dest(h);
      const std::pair<VertexId, VertexId> key{std::min(u, w), std::max(u, w)};
      ++edge_count[key];
      if (m.is_segment(h)) edge_segment[key] = true;
    }
    double ang[3];
    triangle_angles_deg(m, t, ang);
    for (double a : ang) {
      min_angle = std::min(min_angle, a);
      max_angle = std::max(max_angle, a);
    }
    const Point &a = m.points[T.v[0]], &b = m.points[T.v[1]], &c = m.points[T.v[2]];
    area += 0.5L * ((static_cast<long double>(b.x) - a.x) * (static_cast<long double>(c.y) - a.y) -
                    (static_cast<long double>(b.y) - a.y) * (static_cast<long double>(c.x) - a.x));
  }
  long double total = 0.0L, boundary = 0.0L;
  for (const auto& [key, count] : edge_count) {
    const long double len = std::hypot(static_cast<long double>(m.points[key.first].x) - m.points[key.second].x,
                                       static_cast<long double>(m.points[key.first].y) - m.points[key.second].y);
    total += len;
    if (count == 1 || edge_segment.count(key)) boundary += len;
  }
  EXPECT_EQ(r.triangles, triangles);
  EXPECT_NEAR(r.weight_total, static_cast<double>(total), 1e-12 * static_cast<double>(total));
  EXPECT_NEAR(r.weight_boundary, static_cast<double>(boundary), 1e-12 * static_cast<double>(total));
  EXPECT_NEAR(r.min_angle_deg, min_angle, 1e-9);
  EXPECT_NEAR(r.max_angle_deg, max_angle, 1e-9);
  EXPECT_NEAR(r.area, static_cast<double>(area), 1e-12 * std::fabs(static_cast<double>(area)));
}

TEST(Metrics, MatchesDirectRecomputationOnDelaunayOfPointSets) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    expect_measure_matches_direct(delaunay(test::uniform_points(2000, seed)));
    expect_measure_matches_direct(delaunay(test::kuzmin_points(2000, seed)));
  }
  expect_measure_matches_direct(delaunay(test::grid_points(30, 20, 3)));
}

TEST(Metrics, MatchesDirectRecomputationOnRefinedPolygonsWithHoles) {
  for (const char* name : {"Superior.poly", "Texas.poly", "Plate.poly"}) {
    const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    Mesh m = constrained_delaunay(g, {}, nullptr);
    expect_measure_matches_direct(m);  // the CDT: slivers, angles near 0° and 180°
    RefineOptions o;
    o.min_angle_deg = 20.0;
    refine(m, o);
    expect_measure_matches_direct(m);
  }
}

// triangle_area, the area --max-area is tested and reported with, is the same double whichever
// corner a caller names first: a move of the optimiser checks a new triangle as (q, u, w), and
// measure() later reads it in its stored rotation. (When it depended on the rotation, opt with
// --max-area 10 on Superior reported a largest triangle of 10.000000000000002.) On random
// triangles whose rotations round differently; measure().max_triangle_area is the largest.
TEST(Metrics, TriangleAreaDoesNotDependOnTheRotation) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1000.0, 1000.0);
  std::size_t rotations_differ = 0;
  for (int i = 0; i < 20000; ++i) {
    const Point a{u(rng), u(rng)}, b{u(rng), u(rng)}, c{u(rng), u(rng)};
    const double area = triangle_area(a, b, c);
    EXPECT_EQ(area, triangle_area(b, c, a));
    EXPECT_EQ(area, triangle_area(c, a, b));
    EXPECT_EQ(-area, triangle_area(a, c, b));
    const auto plain = [](const Point& p, const Point& q, const Point& r) {
      return 0.5 * ((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x));
    };
    rotations_differ += plain(a, b, c) != plain(b, c, a);
  }
  EXPECT_GT(rotations_differ, 100u);  // the naive formula does depend on it
  Mesh cdt = constrained_delaunay(io::read_input(std::string(MWST_DATA_DIR) + "/Superior.poly"));
  double largest = 0.0;
  for (TriangleId t = 0; t < cdt.triangles.size(); ++t) {
    if (!cdt.in_domain(t)) continue;
    const auto& v = cdt.triangles[t].v;
    largest = std::max(largest, triangle_area(cdt.points[v[0]], cdt.points[v[1]], cdt.points[v[2]]));
  }
  EXPECT_EQ(measure(cdt).max_triangle_area, largest);
  EXPECT_GT(largest, 0.0);
}

}  // namespace
