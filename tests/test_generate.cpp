// tests/test_generate.cpp — the synthetic point sets of src/io/generate.cpp (mwst/generate.hpp):
// each distribution's defining property (range, exact symmetry, grid shape), reproducibility from
// the seed, and the .node text round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "mwst/generate.hpp"
#include "mwst/io.hpp"

namespace {

using mwst::Distribution;
using mwst::Point;

std::set<std::pair<double, double>> as_set(const std::vector<Point>& p) {
  std::set<std::pair<double, double>> s;
  for (const Point& q : p) s.insert({q.x, q.y});
  return s;
}

TEST(Generate, NamesRoundTrip) {
  for (const Distribution d : {Distribution::kUniform, Distribution::kKuzmin, Distribution::kEllipse,
                               Distribution::kGrid, Distribution::kCircle}) {
    EXPECT_EQ(mwst::parse_distribution(mwst::distribution_name(d)), d);
  }
  EXPECT_FALSE(mwst::parse_distribution("gaussian").has_value());
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
