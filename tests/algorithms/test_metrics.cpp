// tests/algorithms/test_metrics.cpp — measure() (src/algorithms/metrics.cpp) against a direct recomputation:
// every domain edge's length once (boundary = not shared by two domain triangles, or a segment),
// the angle extremes from all three angles of every domain triangle (triangle_angles_deg, atan2
// per corner), and the area by the shoelace formula in long double. measure() finds the extremes
// from one corner per triangle (the smallest angle is opposite the shortest edge, the largest
// opposite the longest) without trigonometry, so this checks that shortcut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>
#include <random>
#include <string>
#include <utility>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/refine.hpp"
#include "support/generators.hpp"

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

// ---- bounds and stop reasons (check_bounds, near_small_input_angles, settle_stop_reason) ---------

// A polygon from its corners, one closed ring of segments.
Pslg ring(const std::vector<Point>& corners) {
  Pslg g;
  g.points = corners;
  g.is_poly = true;
  for (std::uint32_t i = 0; i < corners.size(); ++i) {
    g.segments.push_back({i, static_cast<std::uint32_t>((i + 1) % corners.size()), 1});
  }
  return g;
}

// The smallest angle of triangle t by atan2 at all three corners (not the cos² test under check).
double smallest_angle_deg(const Mesh& m, TriangleId t) {
  double a[3];
  triangle_angles_deg(m, t, a);
  return std::min({a[0], a[1], a[2]});
}

// Does the triangle have a vertex at `apex`, or one vertex on each of the rays from `apex` through
// `a` and through `b` (within rounding)? The geometric meaning of "next to the input angle at
// apex", computed from coordinates alone.
bool next_to_angle(const Mesh& m, TriangleId t, const Point& apex, const Point& a, const Point& b) {
  const auto on_ray = [&](const Point& p, const Point& far) {
    const double ux = far.x - apex.x, uy = far.y - apex.y, vx = p.x - apex.x, vy = p.y - apex.y;
    const double cross = ux * vy - uy * vx, dot = ux * vx + uy * vy;
    return dot > 0.0 && std::fabs(cross) <= 1e-9 * std::hypot(ux, uy) * std::hypot(vx, vy);
  };
  const auto& v = m.triangles[t].v;
  bool on_a = false, on_b = false;
  for (const VertexId w : v) {
    const Point& p = m.points[w];
    if (p.x == apex.x && p.y == apex.y) return true;
    on_a = on_a || on_ray(p, a);
    on_b = on_b || on_ray(p, b);
  }
  return on_a && on_b;
}

// A thin wedge (a 10° input angle at the origin, closed by an arc-like cap) refined at 25°: the
// triangles left below the bound all sit at the 10° angle, and near_small_input_angles flags
// exactly triangles next to it (geometrically), among them every one left below the bound.
TEST(StopReason, TrianglesLeftBelowTheBoundAreNextToTheSmallInputAngle) {
  const double t = 10.0 * std::numbers::pi / 180.0;
  const Point apex{0.0, 0.0}, a{1.0, 0.0}, b{std::cos(t), std::sin(t)};
  Mesh m = constrained_delaunay(ring({apex, a, {1.02, 0.09}, b}), {}, nullptr);
  RefineOptions o;
  o.min_angle_deg = 25.0;
  const RefineStats stats = refine(m, o);
  const std::vector<std::uint8_t> near = near_small_input_angles(m);
  std::size_t below = 0, flagged = 0;
  for (TriangleId tr = 0; tr < m.triangles.size(); ++tr) {
    if (!m.in_domain(tr)) continue;
    if (near[tr]) {
      ++flagged;
      EXPECT_TRUE(next_to_angle(m, tr, apex, a, b)) << "triangle " << tr << " flagged but not at the 10 degree angle";
    }
    if (smallest_angle_deg(m, tr) < 25.0 - 1e-9) {
      ++below;
      EXPECT_TRUE(near[tr]) << "triangle " << tr << " below the bound, not flagged";
    }
  }
  EXPECT_GT(below, 0u);  // a 10° input angle leaves some
  EXPECT_LT(flagged, m.domain_triangle_count());  // not the whole mesh
  const BoundCheck check = check_bounds(m, 25.0, -1.0);
  EXPECT_EQ(check.violations, 0u);
  EXPECT_EQ(check.exempt, check.below_angle);
  EXPECT_EQ(check.below_angle, below);
  EXPECT_EQ(to_string(stats.stop), std::to_string(below) + " triangles left near small input angles");
  // settle_stop_reason agrees with the refinement on its own result.
  TriangulateOptions options;
  options.method = Method::kDr;
  options.min_angle_deg = 25.0;
  const StopReason settled = settle_stop_reason(m, options, stats.stop, false);
  EXPECT_EQ(to_string(settled), to_string(stats.stop));
}

// An input angle of 60° or more, or one on the far side of the domain, exempts nothing: a square's
// corners are 90°, and the reflex side of a thin notch is no angle of the domain.
TEST(StopReason, WideAndReflexAnglesExemptNothing) {
  const Mesh square = constrained_delaunay(ring({{0, 0}, {1, 0}, {1, 1}, {0, 1}}), {}, nullptr);
  for (const std::uint8_t n : near_small_input_angles(square)) EXPECT_EQ(n, 0);
  // A notch of 5° cut into the square at (1, 0.5): the domain's angle there is 355°.
  const double h = 0.5 * std::tan(2.5 * std::numbers::pi / 180.0);
  const Mesh notch =
      constrained_delaunay(ring({{0, 0}, {1, 0}, {1, 0.5 - h}, {0.5, 0.5}, {1, 0.5 + h}, {1, 1}, {0, 1}}), {}, nullptr);
  const std::vector<std::uint8_t> near = near_small_input_angles(notch);
  // The corners at (1, 0.5 ± h) are 92.5°; the segments meeting at (0.5, 0.5) make 5°, but the
  // domain lies on the other side of them (355°).
  for (TriangleId t = 0; t < notch.triangles.size(); ++t) {
    if (!notch.in_domain(t)) continue;
    EXPECT_EQ(near[t], 0) << "triangle " << t;
  }
}

// A planted false stop reason: a mesh with a skinny triangle far from any small input angle (the
// Delaunay triangulation of a square with a point near one side) claimed as "bound reached" or as
// "1 triangles left near small input angles" by the engine; settle_stop_reason does not repeat the
// claim but says what the mesh shows.
TEST(StopReason, PlantedFalseReasonIsCaught) {
  Pslg g = ring({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  g.points.push_back({0.5, 0.02});  // a sliver against the bottom side
  const Mesh m = constrained_delaunay(g, {}, nullptr);
  ASSERT_LT(measure(m).min_angle_deg, 20.0);
  TriangulateOptions options;
  options.method = Method::kDr;
  options.min_angle_deg = 20.0;
  const BoundCheck check = check_bounds(m, 20.0, -1.0);
  ASSERT_GT(check.violations, 0u);
  EXPECT_EQ(check.exempt, 0u);
  for (const StopReason& claim : {StopReason{StopKind::kBoundReached, 0, {}}, StopReason{StopKind::kSmallInputAngles, 1, {}}}) {
    const StopReason settled = settle_stop_reason(m, options, claim, false);
    EXPECT_EQ(settled.kind, StopKind::kLeftBelowBound) << to_string(settled);
    EXPECT_EQ(settled.count, check.violations);
    // After flips the same mesh is the flips' doing.
    EXPECT_EQ(settle_stop_reason(m, options, claim, true).kind, StopKind::kBelowBoundAfterFlips);
  }
  // A budget stop stays one: the mesh misses the bound because the budget ran out.
  EXPECT_EQ(settle_stop_reason(m, options, {StopKind::kSteinerBudget, 0, {}}, false).kind, StopKind::kSteinerBudget);
  EXPECT_EQ(settle_stop_reason(m, options, {StopKind::kTimeBudget, 0, {}}, false).kind, StopKind::kTimeBudget);
  // An area bound: opt's "local minimum" with a triangle larger than it is not a local minimum of
  // the bounded problem; with a steiner budget it is that budget.
  options.method = Method::kOpt;
  options.max_area = 0.01;
  EXPECT_EQ(settle_stop_reason(m, options, {StopKind::kLocalMinimum, 0, {}}, false).kind, StopKind::kLeftBelowBound);
  EXPECT_EQ(settle_stop_reason(m, options, {StopKind::kSteinerBudget, 0, {}}, false).kind, StopKind::kSteinerBudget);
  options.max_area = 1.0;
  EXPECT_EQ(settle_stop_reason(m, options, {StopKind::kSteinerBudget, 0, {}}, false).kind, StopKind::kLocalMinimum);
}

// Every reason reads back as itself.
TEST(StopReason, WordsRoundTrip) {
  for (const StopReason& r : {StopReason{StopKind::kBoundReached, 0, {}}, StopReason{StopKind::kSteinerBudget, 0, {}},
                              StopReason{StopKind::kTimeBudget, 0, {}}, StopReason{StopKind::kLocalMinimum, 0, {}},
                              StopReason{StopKind::kRoundLimit, 0, {}}, StopReason{StopKind::kSmallInputAngles, 7, {}},
                              StopReason{StopKind::kOther, 0, "no progress: something"}}) {
    EXPECT_EQ(parse_stop_reason(to_string(r)), r) << to_string(r);
  }
  EXPECT_EQ(to_string(StopReason{StopKind::kBelowBoundAfterFlips, 3, {}}), "3 triangles below the angle bound after the flips");
  EXPECT_EQ(to_string(StopReason{}), "");
}

// dr then --flip on a data set: the flips lower the weight and leave triangles below the angle
// bound, and the pipeline's stop reason says so with their number (it said "bound reached").
TEST(StopReason, FlipsBelowTheBoundAreReported) {
  TriangulateOptions options;
  options.method = Method::kDr;
  options.min_angle_deg = 20.0;
  options.flip = true;
  Mesh m;
  const Report r = triangulate(io::read_input(std::string(MWST_DATA_DIR) + "/Africa.poly"), options, &m);
  const BoundCheck check = check_bounds(m, 20.0, -1.0);
  ASSERT_GT(check.violations, 0u);
  EXPECT_EQ(r.stop.kind, StopKind::kBelowBoundAfterFlips) << to_string(r.stop);
  EXPECT_EQ(r.stop.count, check.violations);
  EXPECT_EQ(r.stop_reason, to_string(r.stop));
}

// The progress line's words.
TEST(Progress, Format) {
  Progress p;
  p.method = "opt";
  p.phase = "local search";
  p.done = 2;
  p.total = 8;
  p.elapsed_seconds = 12.345;
  EXPECT_EQ(format_progress(p), "mwst: opt: local search (3/8), 12.3 s");
  p.seconds_left = 37.66;
  EXPECT_EQ(format_progress(p), "mwst: opt: local search (3/8), 12.3 s, at most 37.7 s left");
  p.total = 0;
  EXPECT_EQ(format_progress(p), "mwst: opt: local search, 12.3 s, at most 37.7 s left");
  p.done = 9;  // never past the total
  p.total = 8;
  EXPECT_EQ(format_progress(p), "mwst: opt: local search (8/8), 12.3 s, at most 37.7 s left");
}

// The phases triangulate() announces, in order, with what is left of the budget.
TEST(Progress, PhasesAreAnnounced) {
  TriangulateOptions options;
  options.method = Method::kDr;
  options.flip = true;
  options.time_budget_seconds = 1000.0;
  std::vector<std::string> phases;
  options.progress = [&](const Progress& p) {
    phases.push_back(std::string(p.method) + ":" + std::string(p.phase) + ":" + std::to_string(p.done) + "/" +
                     std::to_string(p.total));
    EXPECT_GE(p.seconds_left, 0.0);
    EXPECT_LE(p.seconds_left, 1000.0);
  };
  triangulate(io::read_input(std::string(MWST_DATA_DIR) + "/Africa.poly"), options);
  EXPECT_EQ(phases, (std::vector<std::string>{"dr:delaunay:0/3", "dr:refine:1/3", "dr:flip:2/3"}));
}

}  // namespace
