// tests/algorithms/refine/test_fan_walk.cpp — tests of the walk's point-fan shortcut
// (src/algorithms/refine/fan_run.cpp, walk_rng.hpp): the generator's jump-ahead equals stepping,
// and refinement with the shortcut gives the mesh and stats it gives without, to the bit, on point
// fans (n points on a line and one above: n − 1 slivers sharing the apex) and on mixtures of fans
// and other points, for DR with and without an area bound and for BRH, while the walks step
// through O(n) triangles one at a time instead of Θ(n²).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "algorithms/refine/walk_rng.hpp"
#include "mwst/algorithms/brh.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/mesh/delaunay.hpp"

namespace {

using namespace mwst;

TEST(WalkRng, JumpEqualsStepping) {
  std::uint32_t x = 0x2545F491u;
  std::uint64_t stepped = 0;
  for (const std::uint64_t k : {0ull, 1ull, 2ull, 3ull, 31ull, 32ull, 1000ull, 65537ull, 123457ull}) {
    std::uint32_t y = x;
    for (std::uint64_t i = 0; i < k; ++i) y = refinement::xorshift_step(y);
    EXPECT_EQ(refinement::xorshift_jump(x, k), y) << "k = " << k;
    x = y;
    stepped += k;
  }
  EXPECT_EQ(refinement::xorshift_jump(0x2545F491u, stepped), x);
}

// n points 1 apart on the line y = 0 and the apex (n/2, 1): the hull's corners at the line's ends
// are about 2/n radians, and every sliver's off-center lies beyond a hull edge there.
Pslg point_fan(int n) {
  Pslg g;
  for (int i = 0; i < n; ++i) g.points.push_back({static_cast<double>(i), 0.0});
  g.points.push_back({0.5 * n, 1.0});
  return g;
}

// Point fans along the exact line (x, y) = (2k + 1, k − 3), one apex on each side, and scattered
// points around them (so fans meet ordinary triangles, and refinement inserts points among them).
Pslg two_fans_and_scatter(int n, unsigned seed) {
  Pslg g;
  for (int k = 0; k < n; ++k) g.points.push_back({2.0 * k + 1.0, k - 3.0});
  g.points.push_back({1.0 * n - 3.0, 0.5 * n});
  g.points.push_back({1.0 * n + 5.0, 0.5 * n - 7.0});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < n / 20; ++k) g.points.push_back({2.0 * n * u(rng), (n - 3.0) * u(rng) - 3.0});
  return g;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    ASSERT_TRUE(a.points[i] == b.points[i]) << "vertex " << i;
  }
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t t = 0; t < a.triangles.size(); ++t) {
    ASSERT_EQ(a.triangles[t].v, b.triangles[t].v) << "triangle " << t;
    ASSERT_EQ(a.triangles[t].n, b.triangles[t].n) << "triangle " << t;
    ASSERT_EQ(a.flags[t], b.flags[t]) << "triangle " << t;
  }
}

struct Refined {
  Mesh mesh;
  RefineStats stats;
};

Refined refine_with(const Pslg& g, RefineOptions o, bool shortcut) {
  Refined r{constrained_delaunay(g), {}};
  o.fan_shortcut = shortcut;
  r.stats = refine(r.mesh, o);
  return r;
}

// Everything but the walk counters, and the walks cross as many triangles in all.
void expect_same_run(const Refined& with, const Refined& without) {
  expect_same_mesh(with.mesh, without.mesh);
  EXPECT_EQ(with.stats.steiner_inserted, without.stats.steiner_inserted);
  EXPECT_EQ(with.stats.segment_splits, without.stats.segment_splits);
  EXPECT_EQ(with.stats.rejected, without.stats.rejected);
  EXPECT_EQ(with.stats.left_protected, without.stats.left_protected);
  EXPECT_EQ(with.stats.left_small_angle, without.stats.left_small_angle);
  EXPECT_EQ(with.stats.cavity_triangles, without.stats.cavity_triangles);
  EXPECT_EQ(without.stats.walk_steps_skipped, 0u);
  EXPECT_EQ(with.stats.walk_steps + with.stats.walk_steps_skipped, without.stats.walk_steps);
}

// n = 10k: from about this size the hull edges at the tiny corners are too thin to split, and
// refinement leaves every sliver (as `mwst triangulate --method dr` on lineplus10k.node).
TEST(FanWalk, PointFanSameResultLinearWalk) {
  const int n = 10000;
  const Refined with = refine_with(point_fan(n), {}, true);
  const Refined without = refine_with(point_fan(n), {}, false);
  expect_same_run(with, without);
  EXPECT_EQ(with.stats.steiner_inserted, 0u);
  // Without the shortcut the walk to the i-th sliver's off-center crosses the slivers between it
  // and the fan's end: about n²/4 in all. With it, a few dozen steps a sliver.
  EXPECT_GE(without.stats.walk_steps, static_cast<std::size_t>(n) * n / 8);
  EXPECT_LE(with.stats.walk_steps, static_cast<std::size_t>(n) * 40);
}

// Fans among scattered points: points are inserted among the walks, some cavities take fan
// triangles (the run is rebuilt), others do not (it is kept).
TEST(FanWalk, TwoFansAndScatteredPointsSameResult) {
  std::size_t skipped = 0;
  for (const unsigned seed : {1u, 2u}) {
    for (const double angle : {20.0, 30.0}) {
      for (const double max_area : {-1.0, 40.0}) {
        RefineOptions o;
        o.min_angle_deg = angle;
        o.max_area = max_area;
        const Pslg g = two_fans_and_scatter(1500, seed);
        const Refined with = refine_with(g, o, true);
        const Refined without = refine_with(g, o, false);
        SCOPED_TRACE(testing::Message() << "seed " << seed << ", " << angle << " degrees, area " << max_area);
        expect_same_run(with, without);
        EXPECT_GT(with.stats.steiner_inserted, 0u);
        skipped += with.stats.walk_steps_skipped;
      }
    }
  }
  EXPECT_GT(skipped, 0u);
}

TEST(FanWalk, BrhSameResult) {
  for (const int n : {3000, 10000}) {
    BrhOptions with_o, without_o;
    without_o.refine.fan_shortcut = false;
    Mesh with = constrained_delaunay(point_fan(n));
    Mesh without = constrained_delaunay(point_fan(n));
    const BrhStats a = bundle_removal(with, with_o);
    const BrhStats b = bundle_removal(without, without_o);
    expect_same_mesh(with, without);
    EXPECT_EQ(a.rounds, b.rounds);
    EXPECT_EQ(a.skinny_left, b.skinny_left);
  }
}

}  // namespace
