// tests/algorithms/quadtree/test_quadtree_size.cpp — the lower bound on the quadtree's leaves
// (src/algorithms/quadtree/size_bound.cpp) and the refusal it allows before the tree is built.
//
// BEG's tree needs about ∫ dA / lfs² leaves, unbounded in the number of features; a tree beyond
// QuadtreeOptions::max_leaves falls back to the CDT. The bound is computed from the CDT alone, so
// a narrow fan (issue 32: 5,000 spikes took 23 s of CPU and 2.2 GB to reach the limit) falls back at once.
// Tested here: the bound never exceeds the leaves that meet segments in a finished tree (brute
// force over leaves and segments), it is within a stated factor of them on fans, the refusal it
// makes gives the same mesh as the refusal at the limit, and it respects max_depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "mwst/algorithms/quadtree.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "algorithms/quadtree/route.hpp"
#include "algorithms/quadtree/testing.hpp"
#include "support/mesh_queries.hpp"

namespace mwst {
namespace {

// A narrow fan as tests/regression/make_fan_poly.py writes it: from the origin to the outer
// vertices at radius 1 (angles i·width), with a vertex at radius `inner` between each two.
Pslg fan(int wedges, double width_deg, double inner) {
  Pslg g;
  g.points.push_back({0.0, 0.0});
  const double rad = std::numbers::pi / 180.0;
  for (int i = 0; i <= wedges; ++i) {
    g.points.push_back({std::cos(i * width_deg * rad), std::sin(i * width_deg * rad)});
    if (i < wedges) {
      const double a = (i + 0.5) * width_deg * rad;
      g.points.push_back({inner * std::cos(a), inner * std::sin(a)});
    }
  }
  const auto n = static_cast<std::uint32_t>(g.points.size());
  for (std::uint32_t i = 0; i < n; ++i) g.segments.push_back({i, (i + 1) % n, 1});
  return g;
}

// Does segment p–q meet the closed square [x, x + s] × [y, y + s]? Exact (separating axes).
bool meets(const Point& p, const Point& q, double x, double y, double s) {
  if (std::max(p.x, q.x) < x || std::min(p.x, q.x) > x + s || std::max(p.y, q.y) < y ||
      std::min(p.y, q.y) > y + s) {
    return false;
  }
  const int o[4] = {orient2d(p, q, {x, y}), orient2d(p, q, {x + s, y}), orient2d(p, q, {x + s, y + s}),
                    orient2d(p, q, {x, y + s})};
  const bool left = o[0] > 0 && o[1] > 0 && o[2] > 0 && o[3] > 0;
  const bool right = o[0] < 0 && o[1] < 0 && o[2] < 0 && o[3] < 0;
  return !left && !right;
}

struct Measured {
  double bound = 0.0;
  std::size_t leaves_on_segments = 0;
  bool fallback = false;
};

// The bound (no clip: the default depth's cells are far below every distance here) and, from the
// finished tree, the leaves meeting an input segment.
Measured measure_bound(const Pslg& g) {
  Measured m;
  m.bound = qtr::segment_leaf_lower_bound(constrained_delaunay(g, ConstrainOptions{}), 0.0,
                                           std::numeric_limits<double>::infinity());
  QuadtreeStats stats;
  std::vector<qtr::QuadtreeLeaf> leaves;
  qtr::TestSwitches switches;
  switches.keep_leaves = true;
  qtr::refine_with_switches(g, QuadtreeOptions{}, switches, &stats, &leaves);
  m.fallback = stats.fallback;
  for (const qtr::QuadtreeLeaf& leaf : leaves) {
    for (const Segment& s : g.segments) {
      if (meets(g.points[s.a], g.points[s.b], leaf.x, leaf.y, leaf.size)) {
        ++m.leaves_on_segments;
        break;
      }
    }
  }
  return m;
}

// The bound is a lower bound: on fans, strips, holes, a coastline and data sets whose trees are
// built, it never exceeds the leaves that meet segments; on fans it is within a factor 8 of them
// (measured 5.6 to 6.9; 5 to 18 on the others), so it refuses the fans whose trees need more
// than about 8 times the limit (the generated fans from 2,000 vertices need over 50 times).
TEST(QuadtreeSizeBound, NeverExceedsTheLeavesMeetingSegments) {
  struct Case {
    std::string name;
    Pslg g;
    bool is_fan;
  };
  std::vector<Case> cases = {
      {"fan 16 x 1 deg", fan(16, 1.0, 0.01), true},
      {"fan 20 x 1 deg", fan(20, 1.0, 0.001), true},
      {"fan 10 x 2 deg", fan(10, 2.0, 0.05), true},
      {"strip 300", generate_input(Distribution::kStrip, 300, 1), false},
      {"holes 600", generate_input(Distribution::kHoles, 600, 1), false},
      {"coastline 800", generate_input(Distribution::kCoastline, 800, 1), false},
  };
  for (const char* name : {"Africa.poly", "Airliner.poly", "Plate.poly", "PuertoRico.poly"}) {
    cases.push_back({name, io::read_input(std::string(MWST_DATA_DIR) + "/" + name), false});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Measured m = measure_bound(c.g);
    ASSERT_FALSE(m.fallback);
    EXPECT_GT(m.bound, 0.0);
    const auto on_segments = static_cast<double>(m.leaves_on_segments);
    EXPECT_LE(m.bound, on_segments);
    if (c.is_fan) {
      EXPECT_LE(on_segments, 8.0 * m.bound);
    }
    RecordProperty(c.name, std::to_string(on_segments / m.bound));
  }
}

// Point sets: the bound from the hull polygon's CDT (clean_input.cpp, hull_leaf_bound) never
// exceeds the leaves that meet the hull edges, on uniform points, points on a circle (every point
// a hull vertex) and a thin strip of points (hull edges 0.002 apart along a length of 1).
TEST(QuadtreeSizeBound, PointSetsBoundNeverExceedsTheLeavesMeetingTheHull) {
  std::vector<std::pair<std::string, Pslg>> cases = {
      {"uniform 2000", generate_input(Distribution::kUniform, 2000, 1)},
      {"circle 2000", generate_input(Distribution::kCircle, 2000, 1)},
  };
  Pslg strip;
  for (const Point& p : generate_points(Distribution::kUniform, 400, 2)) strip.points.push_back({p.x, 0.002 * p.y});
  cases.emplace_back("strip of points", strip);
  for (const auto& [name, g] : cases) {
    SCOPED_TRACE(name);
    const qtr::CleanInput in = qtr::clean_point_set(g, QuadtreeOptions{});
    QuadtreeStats stats;
    std::vector<qtr::QuadtreeLeaf> leaves;
    qtr::TestSwitches switches;
    switches.keep_leaves = true;
    qtr::refine_with_switches(g, QuadtreeOptions{}, switches, &stats, &leaves);
    ASSERT_FALSE(stats.fallback);
    const std::vector<Point>& p = in.vertices_only.points;
    std::size_t on_hull = 0;
    for (const qtr::QuadtreeLeaf& leaf : leaves) {
      for (const qtr::FeatureSegment& s : in.segments) {
        if (meets(p[s.a], p[s.b], leaf.x, leaf.y, leaf.size)) {
          ++on_hull;
          break;
        }
      }
    }
    EXPECT_GT(in.leaf_lower_bound, 0.0);
    EXPECT_LE(in.leaf_lower_bound, static_cast<double>(on_hull));
    RecordProperty(name, std::to_string(static_cast<double>(on_hull) / in.leaf_lower_bound));
  }
}

// `mwst generate fan 2002`: 1,000 spikes of 0.01° out to radius 1 from radius 1e-3. Its tree needs
// hundreds of millions of leaves; the bound (8.4 million) exceeds the limit (2 million), so the route
// falls back to the CDT without building any of it (before the bound: 6.5 s and 220 MB to reach
// the limit). The mesh is the one the refusal at the limit gives: with a limit the build reaches
// quickly, the two refusals are compared.
TEST(QuadtreeSizeBound, AFanFarBeyondTheLimitFallsBackBeforeTheBuild) {
  const Pslg g = generate_input(Distribution::kFan, 2002, 1);
  QuadtreeStats stats;
  const Mesh mesh = quadtree_refinement(g, QuadtreeOptions{}, &stats);
  ASSERT_TRUE(stats.fallback);
  EXPECT_EQ(stats.fallback_reason.rfind("the quadtree would need more than 4100096 leaves", 0), 0u)
      << stats.fallback_reason;
  EXPECT_NE(stats.fallback_reason.find("along the segments"), std::string::npos) << stats.fallback_reason;
  EXPECT_EQ(stats.leaves, 0u);
  EXPECT_EQ(mesh.points.size(), g.points.size()) << "the CDT of the input, no corners";
  const CheckResult check = test::check_mesh(g, mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());

  QuadtreeOptions small;
  small.max_leaves = 20000;
  QuadtreeStats early_stats, late_stats;
  std::vector<qtr::QuadtreeLeaf> unused;
  qtr::TestSwitches built;
  built.skip_size_bound = true;
  const Mesh early = qtr::refine_with_switches(g, small, qtr::TestSwitches{}, &early_stats, &unused);
  const Mesh late = qtr::refine_with_switches(g, small, built, &late_stats, &unused);
  ASSERT_TRUE(early_stats.fallback && late_stats.fallback);
  EXPECT_NE(early_stats.fallback_reason.find("along the segments"), std::string::npos);
  EXPECT_EQ(late_stats.fallback_reason,
            "the quadtree would need more than 20000 leaves (features very close for their extent, as in a "
            "long thin strip)");
  EXPECT_EQ(early.points, late.points);
  ASSERT_EQ(early.triangles.size(), late.triangles.size());
  for (std::size_t t = 0; t < early.triangles.size(); ++t) {
    EXPECT_EQ(early.triangles[t].v, late.triangles[t].v) << "triangle " << t;
  }
}

// The deepest level bounds the leaves too: with max_depth 10 the fan's tree stops at cells of
// 1/256 of the input's span, far fewer than the limit; the bound (clipped at that size) stays below
// the limit, and the route fails later, on the leaves that still see the input non-simply.
TEST(QuadtreeSizeBound, RespectsTheDeepestLevel) {
  const Pslg g = generate_input(Distribution::kFan, 2002, 1);
  QuadtreeOptions shallow;
  shallow.max_depth = 10;
  QuadtreeStats stats;
  const Mesh mesh = quadtree_refinement(g, shallow, &stats);
  ASSERT_TRUE(stats.fallback);
  EXPECT_NE(stats.fallback_reason.find("still see the input non-simply"), std::string::npos) << stats.fallback_reason;
  const CheckResult check = test::check_mesh(g, mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
}

// A wheel: a centre joined to 1,000 points on the unit circle, and the circle. The centre, a grid
// corner, is in four cells cut by 250 spokes each, more boundary vertices than a cell takes (250;
// 600 spokes still go the quadtree route), so the route falls back to
// the CDT plus the quadtree's free corners. Those are inserted in Hilbert order (in x order, walks
// across the thin spoke triangles took 68 % of the run at 8,000 spokes): the mesh is still the
// input's carved CDT with corners inside its domain.
TEST(QuadtreeSizeBound, AWheelOfManySpokesFallsBackWithCorners) {
  Pslg g;
  constexpr std::uint32_t kSpokes = 1000;
  g.points.push_back({0.0, 0.0});
  for (std::uint32_t k = 0; k < kSpokes; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kSpokes;
    g.points.push_back({std::cos(a), std::sin(a)});
    g.segments.push_back({0, k + 1, 1});
    g.segments.push_back({k + 1, (k + 1) % kSpokes + 1, 1});
  }
  QuadtreeStats stats;
  const Mesh mesh = quadtree_refinement(g, QuadtreeOptions{}, &stats);
  ASSERT_TRUE(stats.fallback);
  EXPECT_EQ(stats.fallback_reason, "a cell has too many boundary vertices");
  EXPECT_GT(mesh.points.size(), g.points.size() + 1000) << "the corners are used";
  const CheckResult check = test::check_mesh(g, mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
}

}  // namespace
}  // namespace mwst
