// tests/algorithms/test_nearest_segment.cpp — NearestSegment (algorithms/nearest_segment.hpp)
// against the scan it replaced: for every query the same segment index as a scan of all segments
// in input order keeping the first least rounded squared distance, on grids of crossing segments
// (queries at their rounded crossings, where two segments are within rounding of the point),
// on fans and stars of long segments through shared points, with repeated and zero-length segments
// (ties), for any piece budget. Then the attributes of the crossings of a grid of attributed
// segments, end to end, against the scan.
#include "algorithms/nearest_segment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mwst/algorithms/arrays.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/pslg.hpp"

namespace {

using mwst::Point;
using mwst::Pslg;
using mwst::Segment;
using mwst::detail::NearestSegment;
using mwst::detail::squared_distance_to_segment;

// The scan attributes_of_cdt_vertices ran before the tree: the first segment of least distance.
std::size_t scan_nearest(const std::vector<Point>& points, const std::vector<Segment>& segments, const Point& p) {
  std::size_t nearest = NearestSegment::kNoSegment;
  double best = 0.0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const double d = squared_distance_to_segment(points[segments[i].a], points[segments[i].b], p);
    if (nearest == NearestSegment::kNoSegment || d < best) {
      nearest = i;
      best = d;
    }
  }
  return nearest;
}

// k horizontal and k vertical segments over the unit square, unevenly spaced, scaled and moved by
// (scale, offset): k² crossings.
Pslg grid(int k, double scale, double offset) {
  Pslg g;
  const auto add = [&](Point a, Point b) {
    g.points.push_back({offset + scale * a.x, offset + scale * a.y});
    g.points.push_back({offset + scale * b.x, offset + scale * b.y});
    g.segments.push_back(Segment{static_cast<std::uint32_t>(g.points.size() - 2),
                                 static_cast<std::uint32_t>(g.points.size() - 1), 1});
  };
  for (int i = 0; i < k; ++i) {
    const double y = (i + 0.5 + 0.37 * (i % 3) / 7.0) / k;
    add({-0.1, y}, {1.1, y});
  }
  for (int j = 0; j < k; ++j) {
    const double x = (j + 0.5 + 0.29 * (j % 5) / 11.0) / k;
    add({x, -0.1}, {x, 1.1});
  }
  return g;
}

// Rounded crossings of every pair of segments that cross, plus points near them and random ones.
std::vector<Point> queries_for(const Pslg& g, std::mt19937_64& random) {
  std::vector<Point> q;
  for (std::size_t i = 0; i < g.segments.size(); ++i) {
    for (std::size_t j = i + 1; j < g.segments.size(); ++j) {
      const Point &a = g.points[g.segments[i].a], &b = g.points[g.segments[i].b];
      const Point &c = g.points[g.segments[j].a], &d = g.points[g.segments[j].b];
      if (mwst::orient2d(a, b, c) * mwst::orient2d(a, b, d) >= 0) continue;
      if (mwst::orient2d(c, d, a) * mwst::orient2d(c, d, b) >= 0) continue;
      const Point x = mwst::segment_intersection(a, b, c, d);
      q.push_back(x);
      q.push_back({std::nextafter(x.x, 1e300), x.y});
      q.push_back({x.x, std::nextafter(x.y, -1e300)});
    }
  }
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (const Point& p : g.points) {
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x), ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  std::uniform_real_distribution<double> ux(xmin - 0.2 * (xmax - xmin), xmax + 0.2 * (xmax - xmin));
  std::uniform_real_distribution<double> uy(ymin - 0.2 * (ymax - ymin), ymax + 0.2 * (ymax - ymin));
  for (int i = 0; i < 500; ++i) q.push_back({ux(random), uy(random)});
  for (const Point& p : g.points) q.push_back(p);
  return q;
}

void expect_tree_equals_scan(const Pslg& g, std::mt19937_64& random) {
  const std::vector<Point> queries = queries_for(g, random);
  for (const std::size_t pieces : {std::size_t{0}, std::size_t{1}, g.segments.size(), queries.size(), 50 * queries.size()}) {
    const NearestSegment tree(g.points, g.segments, pieces);
    std::size_t differ = 0;
    for (const Point& p : queries) {
      const std::size_t expected = scan_nearest(g.points, g.segments, p);
      const std::size_t got = tree.nearest(p);
      if (got != expected && ++differ <= 5) {
        ADD_FAILURE() << "pieces " << pieces << ", point (" << p.x << ", " << p.y << "): tree " << got
                      << ", scan " << expected;
      }
    }
    EXPECT_EQ(differ, 0u) << "pieces " << pieces;
  }
}

TEST(NearestSegment, EqualsTheScanOnGridsAtAnyScale) {
  std::mt19937_64 random(32);
  expect_tree_equals_scan(grid(12, 1.0, 0.0), random);
  expect_tree_equals_scan(grid(9, 1e-40, 3e-40), random);   // tiny coordinates
  expect_tree_equals_scan(grid(9, 1.0, 7.3e14), random);    // far from the origin: doubles 0.125 apart
  expect_tree_equals_scan(grid(9, 3e45, -1e46), random);    // huge coordinates
}

// Long segments through shared points (stars), in random directions, each crossing many others:
// their boxes overlap everywhere, and ties at the shared ends go to the first segment.
TEST(NearestSegment, EqualsTheScanOnStarsAndRandomSegments) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pslg g;
  for (int star = 0; star < 3; ++star) {
    g.points.push_back({u(random), u(random)});
    const auto centre = static_cast<std::uint32_t>(g.points.size() - 1);
    for (int ray = 0; ray < 15; ++ray) {
      g.points.push_back({3.0 * u(random), 3.0 * u(random)});
      g.segments.push_back(Segment{centre, static_cast<std::uint32_t>(g.points.size() - 1), 1});
    }
  }
  for (int i = 0; i < 30; ++i) {
    g.points.push_back({2.0 * u(random), 2.0 * u(random)});
    g.points.push_back({2.0 * u(random), 2.0 * u(random)});
    g.segments.push_back(Segment{static_cast<std::uint32_t>(g.points.size() - 2),
                                 static_cast<std::uint32_t>(g.points.size() - 1), 1});
  }
  expect_tree_equals_scan(g, random);
}

// Ties: the same segment twice, reversed, and a zero-length segment at an end of another. The scan
// keeps the first of equal distances, and so must the tree, whatever order it visits them in.
TEST(NearestSegment, TiesGoToTheFirstSegmentInInputOrder) {
  Pslg g;
  g.points = {{0, 0}, {4, 0}, {0, 2}, {4, 2}, {4, 0}};
  g.segments = {Segment{2, 3, 1}, Segment{1, 0, 1}, Segment{0, 1, 1}, Segment{4, 4, 1}, Segment{1, 1, 1}};
  std::mt19937_64 random(1);
  expect_tree_equals_scan(g, random);
  const NearestSegment tree(g.points, g.segments, 100);
  EXPECT_EQ(tree.nearest({2, 1}), 0u);    // equally far from y = 2 (first) and y = 0
  EXPECT_EQ(tree.nearest({2, -1}), 1u);   // on segments 1 and 2, the same one reversed
  EXPECT_EQ(tree.nearest({5, 0}), 1u);    // the end (4, 0) of 1 and 2, and segments 3 and 4 there
  EXPECT_EQ(NearestSegment(g.points, {}, 10).nearest({0, 0}), NearestSegment::kNoSegment);
}

// End to end: a grid of attributed segments, each end with its own attribute, so that a crossing
// takes a different value from its horizontal and its vertical segment. The crossings' attributes
// are those of the segment the scan picks, interpolated as along_segment() does.
TEST(NearestSegment, CrossingAttributesAreThoseOfTheScannedSegment) {
  Pslg g = grid(30, 1.0, 0.0);
  g.is_poly = true;
  g.attributes_per_point = 1;
  for (std::size_t i = 0; i < g.points.size(); ++i) g.point_attributes.push_back(static_cast<double>((i * 37) % 101));
  mwst::TriangulateOptions options;
  options.method = mwst::Method::kDt;
  options.convex_hull = true;
  const mwst::MeshArrays arrays = mwst::triangulate_arrays(g, options);
  ASSERT_EQ(arrays.vertex_count(), g.points.size() + 30 * 30);
  ASSERT_EQ(arrays.attributes_per_vertex, 1u);
  std::size_t differ = 0;
  for (std::size_t v = g.points.size(); v < arrays.vertex_count(); ++v) {
    const Point p{arrays.vertices[2 * v], arrays.vertices[2 * v + 1]};
    const Segment& s = g.segments[scan_nearest(g.points, g.segments, p)];
    const Point &a = g.points[s.a], &b = g.points[s.b];
    const double dx = b.x - a.x, dy = b.y - a.y, length2 = dx * dx + dy * dy;
    const double t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0);
    const double expected = (1.0 - t) * g.point_attributes[s.a] + t * g.point_attributes[s.b];
    if (arrays.vertex_attributes[v] != expected && ++differ <= 5) {
      ADD_FAILURE() << "crossing " << v << " (" << p.x << ", " << p.y << "): " << arrays.vertex_attributes[v]
                    << ", the scan's segment gives " << expected;
    }
  }
  EXPECT_EQ(differ, 0u);
}

}  // namespace
