// tests/io/test_generate.cpp — the synthetic inputs of src/io/generate.cpp (mwst/io/generate.hpp):
// each distribution's defining property (range, exact symmetry, grid shape, cluster scales, the
// polygons' shapes), reproducibility from the seed, the .node / .poly text round trips, and that
// every polygon class is a valid planar straight-line graph: its strict constrained Delaunay
// triangulation builds without merging, splitting or crossing anything and has the triangle count
// and area of a polygon with holes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"

namespace {

using mwst::Distribution;
using mwst::Point;

std::set<std::pair<double, double>> as_set(const std::vector<Point>& p) {
  std::set<std::pair<double, double>> s;
  for (const Point& q : p) s.insert({q.x, q.y});
  return s;
}

TEST(Generate, NamesRoundTrip) {
  const auto all = mwst::all_distributions();
  EXPECT_EQ(all.size(), 11u);
  std::set<std::string_view> names;
  for (const Distribution d : all) {
    EXPECT_EQ(mwst::parse_distribution(mwst::distribution_name(d)), d);
    names.insert(mwst::distribution_name(d));
  }
  EXPECT_EQ(names.size(), all.size());
  EXPECT_FALSE(mwst::parse_distribution("gaussian").has_value());
  EXPECT_TRUE(mwst::has_segments(Distribution::kFan));
  EXPECT_FALSE(mwst::has_segments(Distribution::kSpiral));
}

// Every class gives exactly N points, the same bytes for the same seed, and depends on the seed
// exactly when uses_seed says so.
TEST(Generate, EveryClassCountsAndIsDeterministic) {
  for (const Distribution d : mwst::all_distributions()) {
    SCOPED_TRACE(std::string(mwst::distribution_name(d)));
    for (const std::size_t n : {std::size_t{1001}, std::size_t{2002}, mwst::minimum_count(d)}) {
      const mwst::Pslg a = mwst::generate_input(d, n, 5);
      const mwst::Pslg b = mwst::generate_input(d, n, 5);
      const mwst::Pslg c = mwst::generate_input(d, n, 6);
      ASSERT_EQ(a.points.size(), n);
      EXPECT_TRUE(a.points == b.points);
      EXPECT_EQ(a.points != c.points, mwst::uses_seed(d));
      EXPECT_EQ(a.segments.size(), mwst::has_segments(d) ? n : 0u);
      EXPECT_EQ(a.is_poly, mwst::has_segments(d));
      EXPECT_TRUE(mwst::generate_points(d, n, 5) == a.points);
      EXPECT_EQ(as_set(a.points).size(), n) << "distinct points";
      for (const Point& p : a.points) EXPECT_TRUE(mwst::in_supported_range(p));
    }
    if (mwst::minimum_count(d) > 1) {
      EXPECT_THROW((void)mwst::generate_input(d, mwst::minimum_count(d) - 1, 1), mwst::InputError);
    }
  }
}

TEST(Generate, SpiralPointsLieOnTheArchimedeanSpiral) {
  const std::size_t n = 5000;
  const auto p = mwst::generate_points(Distribution::kSpiral, n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const double r = std::hypot(p[k].x, p[k].y);
    ASSERT_NEAR(r, std::sqrt((double(k) + 0.5) / double(n)), 1e-15);
    // r = θ / (2π·turns): the angle, taken mod 2π, matches.
    const double theta = 2.0 * M_PI * mwst::kSpiralTurns * r;
    EXPECT_NEAR(std::remainder(std::atan2(p[k].y, p[k].x) - theta, 2.0 * M_PI), 0.0, 1e-9) << k;
  }
}

// Clusters: nearly Gaussian blobs whose sizes span 1 to 2⁻²⁰ of the box.
TEST(Generate, ClustersSpanSixOrdersOfMagnitude) {
  const std::size_t n = 10000, clusters = 100;
  const auto p = mwst::generate_points(Distribution::kClusters, n, 3);
  double smallest = 1e300, largest = 0.0;
  for (std::size_t c = 0; c < clusters; ++c) {
    double extent = 0.0;  // half the larger side of the cluster's bounding box
    double lx = 1e300, hx = -1e300, ly = 1e300, hy = -1e300;
    for (std::size_t i = c; i < n; i += clusters) {
      lx = std::min(lx, p[i].x), hx = std::max(hx, p[i].x);
      ly = std::min(ly, p[i].y), hy = std::max(hy, p[i].y);
    }
    extent = std::max(hx - lx, hy - ly) / 2.0;
    EXPECT_LT(extent, 2.0) << "a cluster reaches at most 2 r_c <= 2 from its centre";
    EXPECT_GT(extent, 0.0);
    smallest = std::min(smallest, extent);
    largest = std::max(largest, extent);
  }
  EXPECT_LT(smallest, 4e-6);  // a cluster of radius 2^-19 or 2^-20
  EXPECT_GT(largest, 0.1);    // and one of radius 1/2 or 1
  for (const Point& q : p) EXPECT_TRUE(q.x > -2.0 && q.x < 3.0 && q.y > -2.0 && q.y < 3.0);
}

// The area enclosed by a ring of the graph (shoelace; positive when counter-clockwise).
double ring_area(const std::vector<Point>& p, const std::vector<mwst::Segment>& ring) {
  double twice = 0.0;
  for (const auto& e : ring) twice += p[e.a].x * p[e.b].y - p[e.b].x * p[e.a].y;
  return twice / 2.0;
}

// The polygon classes are valid inputs: every vertex on exactly two segments, the strict CDT
// (which refuses crossings) builds with nothing merged, split or snapped, it is Delaunay, it holds
// the n + 2h - 2 triangles of a polygon with n vertices and h holes triangulated without Steiner
// points, and its area is the polygon's.
TEST(Generate, PolygonsAreValidAndTheirCdtBuilds) {
  for (const Distribution d : mwst::all_distributions()) {
    if (!mwst::has_segments(d)) continue;
    for (const std::size_t n : {mwst::minimum_count(d), std::size_t{2002}, std::size_t{3001}}) {
      SCOPED_TRACE(std::string(mwst::distribution_name(d)) + " " + std::to_string(n));
      const mwst::Pslg g = mwst::generate_input(d, n, 9);
      std::vector<int> degree(n, 0);
      for (const auto& e : g.segments) {
        ASSERT_LT(e.a, n);
        ASSERT_LT(e.b, n);
        ++degree[e.a], ++degree[e.b];
      }
      for (std::size_t v = 0; v < n; ++v) ASSERT_EQ(degree[v], 2) << "vertex " << v;
      mwst::ConstrainStats stats;
      const mwst::Mesh m = mwst::constrained_delaunay(g, {.strict = true}, &stats);
      EXPECT_EQ(stats.duplicates + stats.zero_length + stats.split_by_vertex + stats.crossings +
                    stats.overlaps + stats.snapped,
                0u);
      EXPECT_TRUE(stats.warnings.empty());
      EXPECT_TRUE(mwst::validate(m, {.delaunay = true}).empty());
      EXPECT_EQ(m.points.size(), n);
      EXPECT_EQ(m.domain_triangle_count(), n + 2 * g.holes.size() - 2);
      // Rings are consecutive runs of segments; the holes' rings subtract.
      double area = 0.0;
      std::size_t first = 0;
      for (std::size_t i = 0; i < g.segments.size(); ++i) {
        if (g.segments[i].b == g.segments[first].a) {
          const std::vector<mwst::Segment> ring(g.segments.begin() + long(first), g.segments.begin() + long(i) + 1);
          area += first == 0 ? std::fabs(ring_area(g.points, ring)) : -std::fabs(ring_area(g.points, ring));
          first = i + 1;
        }
      }
      EXPECT_EQ(first, g.segments.size()) << "segments form closed rings";
      EXPECT_NEAR(m.domain_area(), area, 1e-9 * std::fabs(area));
      EXPECT_GT(area, 0.0);
    }
  }
}

TEST(Generate, HolesAreAGridOfRegularPolygons) {
  const std::size_t m = mwst::kHolePolygonPoints;
  const mwst::Pslg g = mwst::generate_input(Distribution::kHoles, 10000, 0);
  const std::size_t side = 12;  // floor(sqrt(9996 / 64))
  ASSERT_EQ(g.holes.size(), side * side);
  const std::size_t boundary = 10000 - side * side * m;
  for (std::size_t i = 0; i < boundary; ++i) {
    const Point& q = g.points[i];
    EXPECT_TRUE(q.x == 0.0 || q.y == 0.0 || q.x == double(side) || q.y == double(side)) << i;
  }
  for (std::size_t h = 0; h < g.holes.size(); ++h) {
    const Point c = g.holes[h];
    EXPECT_EQ(c.x - std::floor(c.x), 0.5);
    for (std::size_t k = 0; k < m; ++k) {
      const Point& q = g.points[boundary + h * m + k];
      EXPECT_NEAR(std::hypot(q.x - c.x, q.y - c.y), 0.25, 1e-15);
    }
  }
}

TEST(Generate, FanWedgesAreNarrow) {
  // 2002 vertices: the apex and 1,000 wedges of 0.01° (2,001 rim vertices).
  const auto p = mwst::generate_points(Distribution::kFan, 2002, 0);
  EXPECT_EQ(p[0], (Point{0.0, 0.0}));
  for (std::size_t k = 0; k <= 2000; ++k) {
    const Point& q = p[1 + k];
    EXPECT_NEAR(std::hypot(q.x, q.y), k % 2 == 0 ? 1.0 : mwst::kFanInnerRadius, 1e-15);
    EXPECT_NEAR(std::atan2(q.y, q.x) * 180.0 / M_PI, 0.01 * double(k), 1e-9) << k;
  }
  // Larger fans keep within 90°: the step shrinks to 45° / wedges.
  const auto big = mwst::generate_points(Distribution::kFan, 40001, 0);
  EXPECT_NEAR(std::atan2(big[40000 - 1].y, big[40000 - 1].x) * 180.0 / M_PI, 90.0, 1e-9);
  EXPECT_NEAR(big[40000].x, 0.5 * big[40000 - 1].x, 0.0) << "odd n: the closing edge's midpoint";
}

TEST(Generate, StripIsLongAndThin) {
  const auto p = mwst::generate_points(Distribution::kStrip, 1001, 0);
  std::size_t bottom = 0;
  for (const Point& q : p) {
    EXPECT_TRUE(q.y == 0.0 || q.y == 1e-3);
    EXPECT_TRUE(q.x >= 0.0 && q.x <= 1.0);
    bottom += q.y == 0.0 ? 1 : 0;
  }
  EXPECT_EQ(bottom, 501u);  // 2 corners and 499 of the 997 side points
}

TEST(Generate, CoastlineRadiiFillTheAnnulus) {
  const std::size_t n = 4096;
  const auto p = mwst::generate_points(Distribution::kCoastline, n, 2);
  double lo = 1e300, hi = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = std::hypot(p[k].x, p[k].y);
    lo = std::min(lo, r), hi = std::max(hi, r);
    if (k > 0) {  // strictly increasing angles: star-shaped about the origin
      const double turn = p[k - 1].x * p[k].y - p[k - 1].y * p[k].x;
      EXPECT_GT(turn, 0.0) << k;
    }
  }
  EXPECT_NEAR(lo, 0.5, 1e-15);
  EXPECT_NEAR(hi, 1.5, 1e-15);
}

// .poly text reads back to the same graph.
TEST(Generate, PolyTextReadsBackExactly) {
  for (const Distribution d : {Distribution::kHoles, Distribution::kFan, Distribution::kCoastline}) {
    const mwst::Pslg g = mwst::generate_input(d, 500, 4);
    const std::string text = mwst::io::poly_text(g, "a comment");
    EXPECT_EQ(text.rfind("# a comment\n500 2 0 0\n", 0), 0u);
    const mwst::Pslg back = mwst::io::parse_poly(text, "generated");
    ASSERT_TRUE(back.points == g.points);
    ASSERT_EQ(back.segments.size(), g.segments.size());
    for (std::size_t i = 0; i < g.segments.size(); ++i) {
      EXPECT_EQ(back.segments[i].a, g.segments[i].a);
      EXPECT_EQ(back.segments[i].b, g.segments[i].b);
      EXPECT_EQ(back.segments[i].marker, g.segments[i].marker);
    }
    EXPECT_TRUE(back.holes == g.holes);
  }
}

TEST(Generate, UnitDoubleCoversTheHalfOpenInterval) {
  EXPECT_EQ(mwst::unit_double(0), 0.0);
  EXPECT_EQ(mwst::unit_double(~0ull), 1.0 - 0x1p-53);
  EXPECT_EQ(mwst::unit_double(1ull << 63), 0.5);
}

TEST(Generate, UniformIsInTheUnitSquareAndSeeded) {
  const auto a = mwst::generate_points(Distribution::kUniform, 2000, 3);
  const auto b = mwst::generate_points(Distribution::kUniform, 2000, 3);
  const auto c = mwst::generate_points(Distribution::kUniform, 2000, 4);
  ASSERT_EQ(a.size(), 2000u);
  EXPECT_TRUE(a == b);
  EXPECT_FALSE(a == c);
  double sx = 0.0;
  for (const Point& p : a) {
    EXPECT_TRUE(p.x >= 0.0 && p.x < 1.0 && p.y >= 0.0 && p.y < 1.0);
    sx += p.x;
  }
  EXPECT_NEAR(sx / 2000.0, 0.5, 0.05);  // 7 standard deviations of the mean
}

TEST(Generate, KuzminRadiiFollowTheDistribution) {
  const auto p = mwst::generate_points(Distribution::kKuzmin, 4000, 11);
  // Mass within radius r is 1 - 1/sqrt(1 + r²): half the points within r = sqrt(3).
  std::size_t inside = 0, right = 0;
  for (const Point& q : p) {
    EXPECT_TRUE(mwst::in_supported_range(q));
    inside += std::hypot(q.x, q.y) < std::sqrt(3.0) ? 1 : 0;
    right += q.x > 0.0 ? 1 : 0;
  }
  EXPECT_NEAR(static_cast<double>(inside) / 4000.0, 0.5, 0.04);
  EXPECT_NEAR(static_cast<double>(right) / 4000.0, 0.5, 0.04);  // uniform angle
}

TEST(Generate, CircleAndEllipseAreExactlySymmetric) {
  for (const std::size_t n : {7u, 8u, 12u, 100u, 1000u, 1001u}) {
    SCOPED_TRACE(n);
    const auto circle = mwst::generate_points(Distribution::kCircle, n, 0);
    const auto ellipse = mwst::generate_points(Distribution::kEllipse, n, 0);
    ASSERT_EQ(circle.size(), n);
    const auto cs = as_set(circle);
    EXPECT_EQ(cs.size(), n);
    EXPECT_EQ(circle[0], (Point{1.0, 0.0}));
    for (std::size_t k = 0; k < n; ++k) {
      const Point& q = circle[k];
      EXPECT_NEAR(q.x * q.x + q.y * q.y, 1.0, 1e-15);
      EXPECT_NEAR(std::atan2(q.y, q.x), std::remainder(2.0 * M_PI * double(k) / double(n), 2.0 * M_PI), 1e-12);
      EXPECT_TRUE(cs.count({q.x, -q.y})) << "mirror in the x axis";
      if (n % 2 == 0) {
        EXPECT_TRUE(cs.count({-q.x, q.y})) << "mirror in the y axis";
      }
      if (n % 4 == 0) {
        EXPECT_TRUE(cs.count({q.y, q.x})) << "mirror in the diagonal";
      }
      EXPECT_EQ(ellipse[k].x, q.x);
      EXPECT_EQ(ellipse[k].y, 0.5 * q.y);
    }
  }
}

TEST(Generate, GridIsRowMajorWithCeilSqrtColumns) {
  for (const std::size_t n : {1u, 2u, 4u, 5u, 9u, 10u, 99u, 100u, 101u}) {
    const auto g = mwst::generate_points(Distribution::kGrid, n, 0);
    std::size_t columns = 0;
    while (columns * columns < n) ++columns;
    ASSERT_EQ(g.size(), n);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(g[i].x, static_cast<double>(i % columns)) << n << " " << i;
      EXPECT_EQ(g[i].y, static_cast<double>(i / columns)) << n << " " << i;
    }
  }
}

TEST(Generate, NodeTextReadsBackExactly) {
  for (const Distribution d : {Distribution::kUniform, Distribution::kKuzmin, Distribution::kEllipse}) {
    const auto p = mwst::generate_points(d, 300, 5);
    const std::string text = mwst::io::node_text(p, "first line\nsecond line");
    EXPECT_EQ(text.rfind("# first line\n# second line\n300 2 0 0\n", 0), 0u);
    const mwst::Pslg back = mwst::io::parse_node(text, "generated");
    ASSERT_EQ(back.points.size(), p.size());
    EXPECT_TRUE(back.points == p);
  }
}

}  // namespace
