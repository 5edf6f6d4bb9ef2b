// tests/algorithms/test_triangle_switches_mesher.cpp — the mesher side of Triangle's switches
// (TriangulateOptions::regional_area_limits = -a without a number, Pslg::triangles = -r with
// Pslg::triangle_max_area = .area, segment_splitting = -Y / -YY, conforming_delaunay = -D,
// threads). Every mesh goes through the independent checker (check_triangulation via
// test::check_mesh); the bounds are checked on the result's triangles by area and by region,
// found here from the geometry (which side of a segment a centroid lies on), not from the mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "mwst/io/report.hpp"
#include "mwst/algorithms/arrays.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "support/exact_checker.hpp"
#include "support/generators.hpp"
#include "support/regression_files.hpp"

namespace {

using namespace mwst;

using mwst::test::joined;

Point centroid(const Mesh& m, TriangleId t) {
  const auto& v = m.triangles[t].v;
  return {(m.points[v[0]].x + m.points[v[1]].x + m.points[v[2]].x) / 3.0,
          (m.points[v[0]].y + m.points[v[1]].y + m.points[v[2]].y) / 3.0};
}

double area_of(const Mesh& m, TriangleId t) {
  const auto& v = m.triangles[t].v;
  return triangle_area(m.points[v[0]], m.points[v[1]], m.points[v[2]]);
}

// The square [0, 10]² cut by the segment x = 4 into a left region (area 40) and a right one (60),
// each with a region seed and an area limit.
Pslg two_regions(double left_limit, double right_limit) {
  Pslg g;
  g.points = {{0, 0}, {4, 0}, {10, 0}, {10, 10}, {4, 10}, {0, 10}};
  g.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 4, 1}, {4, 5, 1}, {5, 0, 1}, {1, 4, 2}};
  g.regions = {{{2, 5}, 1.0, left_limit}, {{7, 5}, 2.0, right_limit}};
  g.is_poly = true;
  g.source = "two_regions.poly";
  return g;
}

// ---- 1. regional area limits ----------------------------------------------------------------

TEST(RegionalAreaLimits, EachRegionsTrianglesObeyItsLimit) {
  const Pslg g = two_regions(0.5, 3.0);
  for (const Method method : {Method::kDr, Method::kBrh}) {
    for (const double angle : {0.0, 20.0}) {
      if (method == Method::kBrh && angle == 0.0) continue;  // brh needs an angle
      SCOPED_TRACE(std::string(method_name(method)) + " at " + std::to_string(angle));
      TriangulateOptions o;
      o.method = method;
      o.min_angle_deg = angle;
      o.regional_area_limits = true;
      Mesh m;
      const Report r = triangulate(g, o, &m);
      const CheckResult check = test::check_mesh(g, m);
      EXPECT_TRUE(check.ok()) << joined(check.messages);
      std::size_t left = 0, right = 0;
      for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        if (!m.in_domain(t)) continue;
        const bool is_left = centroid(m, t).x < 4.0;
        EXPECT_LE(area_of(m, t), is_left ? 0.5 : 3.0) << "triangle " << t << (is_left ? " (left)" : " (right)");
        (is_left ? left : right) += 1;
      }
      // At least area / limit triangles per region: 80 on the left, 20 on the right.
      EXPECT_GE(left, 80u);
      EXPECT_GE(right, 20u);
      EXPECT_EQ(r.stop.kind, StopKind::kBoundReached) << r.stop_reason;
    }
  }
}

// The limits are what the triangle count follows: without the switch the regions' limits are not
// applied (the CDT of the square has 4 triangles, the symptom), and a tighter left limit
// gives more triangles on the left only.
TEST(RegionalAreaLimits, LimitsDriveTheMesh) {
  TriangulateOptions o;
  o.method = Method::kDr;
  o.min_angle_deg = 0.0;
  const Report plain = triangulate(two_regions(0.5, 3.0), o);
  EXPECT_EQ(plain.triangles, 4u);
  o.regional_area_limits = true;
  const Report loose = triangulate(two_regions(0.5, 3.0), o);
  const Report tight = triangulate(two_regions(0.1, 3.0), o);
  EXPECT_GT(tight.triangles, loose.triangles + 200);
  // A later region wins: a second seed on the left with no limit lifts the left limit.
  Pslg g = two_regions(0.5, 3.0);
  g.regions.push_back({{1, 1}, 3.0, -1.0});
  Mesh m;
  triangulate(g, o, &m);
  std::size_t left = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) left += m.in_domain(t) && centroid(m, t).x < 4.0;
  EXPECT_LT(left, 10u);
}

TEST(RegionalAreaLimits, SeedOutsideTheDomainIsAnInputErrorAndOtherMethodsRefuse) {
  Pslg g = two_regions(0.5, 3.0);
  g.source = "rooms.poly";
  g.regions.push_back({{20, 20}, 0.0, 0.01, 17});
  TriangulateOptions o;
  o.method = Method::kDr;
  o.regional_area_limits = true;
  try {
    triangulate(g, o);
    ADD_FAILURE() << "a region seed outside the domain was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "rooms.poly");
    EXPECT_EQ(e.line(), 17u);
    EXPECT_NE(std::string(e.what()).find("region 3: its seed (20, 20) lies outside the domain"), std::string::npos)
        << e.what();
  }
  for (const Method method : {Method::kDt, Method::kQtr, Method::kOpt}) {
    o.method = method;
    EXPECT_THROW(triangulate(g, o), std::invalid_argument) << method_name(method);
  }
}

// ---- 2. refining a given triangulation (-r) ---------------------------------------------------

// The square [0, 4]² as two triangles.
Pslg coarse_square() {
  Pslg g;
  g.points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  g.triangles = {0, 1, 2, 0, 2, 3};
  g.first_index = 0;
  g.source = "square.ele";
  return g;
}

TEST(RefineGivenTriangles, DtKeepsItDrRefinesItToTheAreaBound) {
  const Pslg g = coarse_square();
  Pslg input = g;
  input.triangles.clear();
  TriangulateOptions o;
  Mesh m;
  EXPECT_EQ(triangulate(g, o, &m).triangles, 2u);
  EXPECT_TRUE(test::check_mesh(input, m).ok());
  o.method = Method::kDr;
  o.max_area = 0.05;
  o.min_angle_deg = 25.0;
  const Report r = triangulate(g, o, &m);
  CheckOptions c;
  c.delaunay = true;
  c.min_angle_deg = 25.0;
  const CheckResult check = test::check_mesh(input, m, c);
  EXPECT_TRUE(check.ok()) << joined(check.messages);
  EXPECT_LE(r.max_triangle_area, 0.05);
  EXPECT_GE(r.triangles, 320u);
  EXPECT_EQ(r.stop.kind, StopKind::kBoundReached) << r.stop_reason;
}

// A non-convex start (an L of three triangles) keeps its domain; a clockwise triangle is turned.
TEST(RefineGivenTriangles, NonConvexAndClockwise) {
  Pslg g;
  g.points = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  g.triangles = {0, 1, 2, 0, 3, 2 /* clockwise */, 0, 3, 4, 0, 4, 5};
  g.first_index = 0;
  g.source = "ell.ele";
  // The checker's reference: the L as a .poly.
  Pslg ell = g;
  ell.triangles.clear();
  for (std::uint32_t i = 0; i < 6; ++i) ell.segments.push_back({i, (i + 1) % 6, 1});
  ell.is_poly = true;
  TriangulateOptions o;
  o.method = Method::kDr;
  o.max_area = 0.01;
  Mesh m;
  const Report r = triangulate(g, o, &m);
  EXPECT_TRUE(std::any_of(r.warnings.begin(), r.warnings.end(),
                          [](const std::string& w) { return w.find("1 triangle was clockwise") != std::string::npos; }))
      << joined(r.warnings);
  const CheckResult check = test::check_mesh(ell, m);
  EXPECT_TRUE(check.ok()) << joined(check.messages);
  EXPECT_NEAR(m.domain_area(), 3.0, 1e-12);
  EXPECT_LE(r.max_triangle_area, 0.01);
}

// The bounds are inherited: a triangle's bound is that of the triangle it replaced on its side
// (Bowyer–Watson cavities: the old triangle on each boundary edge; flips: the mean, or none). So
// every triangle meets its own bound, and the bounded half is refined while the other is not; near
// the diagonal (not a segment) bounds mix, as Triangle's own do ("constraints tend to diffuse").
TEST(RefineGivenTriangles, PerTriangleAreaBoundsAreInherited) {
  Pslg g = coarse_square();
  g.triangle_max_area = {0.02, -1.0};  // the lower-right triangle (below the diagonal y = x) only
  TriangulateOptions o;
  o.method = Method::kDr;
  o.min_angle_deg = 0.0;
  Mesh m;
  const Report r = triangulate(g, o, &m);
  Pslg input = g;
  input.triangles.clear();
  const CheckResult check = test::check_mesh(input, m);
  EXPECT_TRUE(check.ok()) << joined(check.messages);
  ASSERT_EQ(m.area_bound.size(), m.triangles.size());
  std::size_t below = 0, above = 0, below_small = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    if (m.area_bound[t] > 0.0) {
      EXPECT_LE(area_of(m, t), m.area_bound[t]) << "triangle " << t;
    }
    const Point c = centroid(m, t);
    if (c.y < c.x) {
      ++below;
      below_small += area_of(m, t) <= 0.02;
    } else {
      ++above;
    }
  }
  EXPECT_GE(below_small, 400u);  // the half's area 8, at most 0.02 each, but for the mixing
  EXPECT_GE(below_small, below * 9 / 10) << below;
  EXPECT_LT(above, below / 2) << below;  // the other half is not bound by it
  EXPECT_EQ(r.stop.kind, StopKind::kBoundReached) << r.stop_reason;
}

// mwst's own output, read back as a triangulation with its subsegments, refined again.
TEST(RefineGivenTriangles, RefinesItsOwnOutputAgain) {
  const Pslg plate = io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
  TriangulateOptions o;
  o.method = Method::kDr;
  o.min_angle_deg = 20.0;
  Mesh first;
  const Report r1 = triangulate(plate, o, &first);
  const MeshArrays a = to_arrays(first);
  Pslg again;
  for (std::size_t v = 0; v < a.vertex_count(); ++v) again.points.push_back({a.vertices[2 * v], a.vertices[2 * v + 1]});
  again.triangles = a.triangles;
  for (std::size_t s = 0; s < a.segment_count(); ++s) {
    again.segments.push_back({a.segments[2 * s], a.segments[2 * s + 1], a.segment_markers[s]});
  }
  again.first_index = 0;
  again.is_poly = true;
  again.source = "Plate.1";
  // dt keeps it as it is.
  TriangulateOptions keep;
  Mesh same;
  EXPECT_EQ(triangulate(again, keep, &same).triangles, r1.triangles);
  EXPECT_TRUE(test::check_mesh(plate, same).ok());
  // dr refines it to a tighter bound.
  o.min_angle_deg = 30.0;
  o.max_area = 40.0;
  Mesh second;
  const Report r2 = triangulate(again, o, &second);
  EXPECT_GT(r2.triangles, r1.triangles);
  EXPECT_LE(r2.max_triangle_area, 40.0);
  CheckOptions c;
  c.delaunay = true;
  const CheckResult check = test::check_mesh(plate, second, c);
  EXPECT_TRUE(check.ok()) << joined(check.messages);
  EXPECT_NE(r2.stop.kind, StopKind::kLeftBelowBound) << r2.stop_reason;
}

TEST(RefineGivenTriangles, BadTrianglesAreRefusedNamingTheProblem) {
  TriangulateOptions o;
  o.method = Method::kDr;
  const auto refused = [&](Pslg g, const std::string& words) {
    try {
      triangulate(g, o);
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what() << " (expected: " << words << ")";
    }
  };
  Pslg g = coarse_square();
  g.triangles[4] = 7;
  refused(g, "triangle 1 names vertex 7");
  g = coarse_square();
  g.triangles = {0, 1, 2, 0, 1, 2};
  refused(g, "overlap");
  g = coarse_square();
  g.points.push_back({3, 1});  // inside triangle 0, in no triangle
  refused(g, "do not form a triangulation");
  g = coarse_square();
  g.points.push_back({2, 2});  // on the diagonal: a triangle on the same side of edge (0, 1) as triangle 0
  g.triangles = {0, 1, 2, 0, 2, 3, 0, 1, 4};
  refused(g, "triangles 0 and 2 overlap");
  g = coarse_square();
  g.points.push_back({2, -1});
  g.triangles = {0, 1, 2, 0, 2, 3, 1, 0, 4, 0, 1, 4};
  refused(g, "overlap");
  g = coarse_square();
  g.points.push_back({8, 0});
  g.triangles = {0, 1, 2, 0, 2, 3, 0, 1, 4};  // collinear corners
  refused(g, "degenerate");
  g = coarse_square();
  g.segments = {{1, 3, 1}};
  refused(g, "segment 0 (1, 3) is not an edge");
  g = coarse_square();
  g.triangle_max_area = {1.0};
  refused(g, "area bounds");
  o.method = Method::kQtr;
  EXPECT_THROW(triangulate(coarse_square(), o), std::invalid_argument);
}

// ---- 3. segments refinement may not split (-Y, -YY) -------------------------------------------

// True if `p` lies on the closed segment a–b (exactly).
bool on_segment(const Point& p, const Point& a, const Point& b) {
  if (orient2d(a, b, p) != 0) return false;
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

void expect_no_point_on(const Mesh& m, const Pslg& g, const std::vector<std::size_t>& protected_segments) {
  for (VertexId v = static_cast<VertexId>(g.points.size()); v < m.points.size(); ++v) {
    if (m.vertex_kind[v] == VertexKind::kRemoved) continue;
    for (const std::size_t s : protected_segments) {
      const Segment& seg = g.segments[s];
      EXPECT_FALSE(on_segment(m.points[v], g.points[seg.a], g.points[seg.b]))
          << "Steiner point " << v << " lies on protected segment " << s;
    }
  }
}

TEST(SegmentSplitting, NoSteinerPointOnProtectedSegments) {
  for (const char* name : {"Plate.poly", "Airliner.poly"}) {
    const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    for (const SegmentSplitting mode : {SegmentSplitting::kNotBoundary, SegmentSplitting::kNever}) {
      for (const Method method : {Method::kDr, Method::kBrh}) {
        SCOPED_TRACE(std::string(name) + " " + std::string(method_name(method)) +
                     (mode == SegmentSplitting::kNever ? " -YY" : " -Y"));
        TriangulateOptions o;
        o.method = method;
        o.min_angle_deg = 25.0;
        o.segment_splitting = mode;
        // An area bound too, so that interior Steiner points must be made (most triangles of
        // these inputs' CDT touch the boundary, and their Steiner points lie beyond it).
        o.max_area = constrained_delaunay(g).domain_area() / 200.0;
        Mesh m;
        const Report r = triangulate(g, o, &m);
        const CheckResult check = test::check_mesh(g, m);
        EXPECT_TRUE(check.ok()) << joined(check.messages);
        // Every segment of these inputs bounds the domain (the -Y set is the -YY set).
        std::vector<std::size_t> all(g.segments.size());
        for (std::size_t s = 0; s < all.size(); ++s) all[s] = s;
        expect_no_point_on(m, g, all);
        EXPECT_GT(r.steiner, 100u);  // interior Steiner points are still made
        EXPECT_LE(r.max_triangle_area, o.max_area);
        // The stop reason is what the mesh bears out: the triangles outside the bound are counted.
        if (method == Method::kDr) {
          const BoundCheck b = check_bounds(m, 25.0, o.max_area);
          if (b.violations == 0) {
            EXPECT_TRUE(r.stop.kind == StopKind::kBoundReached || r.stop.kind == StopKind::kSmallInputAngles)
                << r.stop_reason;
          } else {
            EXPECT_EQ(r.stop.kind, StopKind::kProtectedSegments) << r.stop_reason;
            EXPECT_EQ(r.stop.count, b.violations);
          }
        }
      }
    }
  }
}

// -Y keeps the boundary but splits an interior segment; -YY splits neither.
TEST(SegmentSplitting, InteriorSegmentsOnlyUnderSingleY) {
  const Pslg g = two_regions(-1.0, -1.0);
  TriangulateOptions o;
  o.method = Method::kDr;
  o.min_angle_deg = 20.0;
  o.max_area = 0.5;
  std::vector<std::size_t> boundary = {0, 1, 2, 3, 4, 5};
  std::vector<std::size_t> all = {0, 1, 2, 3, 4, 5, 6};
  for (const SegmentSplitting mode : {SegmentSplitting::kNotBoundary, SegmentSplitting::kNever}) {
    o.segment_splitting = mode;
    Mesh m;
    const Report r = triangulate(g, o, &m);
    const CheckResult check = test::check_mesh(g, m);
    EXPECT_TRUE(check.ok()) << joined(check.messages);
    expect_no_point_on(m, g, mode == SegmentSplitting::kNever ? all : boundary);
    std::size_t on_interior = 0;
    for (VertexId v = 6; v < m.points.size(); ++v) on_interior += on_segment(m.points[v], g.points[1], g.points[4]);
    if (mode == SegmentSplitting::kNotBoundary) {
      EXPECT_GT(on_interior, 0u);
    }
    EXPECT_LE(r.max_triangle_area, 0.5);  // an area bound is always reachable by interior points
  }
}

// ---- 4. conforming Delaunay (-D) ---------------------------------------------------------------

// Every domain triangle's circumcircle holds no vertex of the mesh strictly inside (exact
// incircle, brute force): Delaunay, not only constrained Delaunay.
std::size_t vertices_in_circumcircles(const Mesh& m) {
  std::vector<VertexId> used;
  std::vector<char> seen(m.points.size(), 0);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    for (const VertexId v : m.triangles[t].v) {
      if (!seen[v]) used.push_back(v);
      seen[v] = 1;
    }
  }
  std::size_t bad = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    const auto& v = m.triangles[t].v;
    for (const VertexId x : used) {
      if (incircle(m.points[v[0]], m.points[v[1]], m.points[v[2]], m.points[x]) > 0) ++bad;
    }
  }
  return bad;
}

void expect_empty_circumcircles(const Mesh& m) {
  EXPECT_EQ(vertices_in_circumcircles(m), 0u) << "vertices inside circumcircles of domain triangles";
}

// dt or dr with conforming_delaunay on `g`: no warning, the checker's conforming Delaunay test
// (exact incircle across every interior edge, segments included), every circumcircle empty, and
// for dt only Steiner points on segments.
void expect_conforming(const Pslg& g, Method method) {
  SCOPED_TRACE(g.source + " " + std::string(method_name(method)));
  TriangulateOptions o;
  o.method = method;
  o.min_angle_deg = 20.0;
  o.conforming_delaunay = true;
  Mesh m;
  const Report r = triangulate(g, o, &m);
  EXPECT_TRUE(r.warnings.empty()) << joined(r.warnings);
  CheckOptions c;
  c.conforming_delaunay = true;
  const CheckResult check = test::check_mesh(g, m, c);
  EXPECT_TRUE(check.ok()) << joined(check.messages);
  expect_empty_circumcircles(m);
  if (method == Method::kDt) {
    for (VertexId v = static_cast<VertexId>(g.points.size()); v < m.points.size(); ++v) {
      EXPECT_EQ(m.vertex_kind[v], VertexKind::kSteinerOnSegment) << v;
    }
  } else {
    EXPECT_NE(r.stop.kind, StopKind::kLeftBelowBound) << r.stop_reason;
  }
}

TEST(ConformingDelaunay, DataSetsDtAndDr) {
  for (const char* name : {"Plate.poly", "Airliner.poly", "Africa.poly", "PuertoRico.poly", "Texas.poly",
                           "Superior.poly", "NewYork.poly", "Turkey.poly", "Florida.poly", "California.poly"}) {
    const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    for (const Method method : {Method::kDt, Method::kDr}) expect_conforming(g, method);
  }
}

// Small input angles: a fan of thin wedges (1° and 5°) and the 1° spike; concentric shells end
// the splitting.
TEST(ConformingDelaunay, SmallInputAngles) {
  std::vector<Pslg> inputs;
  inputs.push_back(test::read_regression("spike_1deg.poly"));
  for (const double degrees : {1.0, 5.0}) {
    Pslg fan;
    fan.points.push_back({0, 0});
    const int spokes = 6;
    for (int i = 0; i < spokes; ++i) {
      const double a = i * degrees * std::numbers::pi / 180.0;
      fan.points.push_back({10.0 * std::cos(a), 10.0 * std::sin(a)});
    }
    fan.points.push_back({-5, 5});
    for (std::uint32_t i = 1; i <= static_cast<std::uint32_t>(spokes); ++i) fan.segments.push_back({0, i, 1});
    for (std::uint32_t i = 1; i < static_cast<std::uint32_t>(spokes); ++i) fan.segments.push_back({i, i + 1, 1});
    fan.segments.push_back({static_cast<std::uint32_t>(spokes), static_cast<std::uint32_t>(spokes) + 1, 1});
    fan.segments.push_back({static_cast<std::uint32_t>(spokes) + 1, 0, 1});
    fan.is_poly = true;
    fan.source = "fan" + std::to_string(static_cast<int>(degrees)) + ".poly";
    inputs.push_back(fan);
  }
  for (const Pslg& g : inputs) {
    for (const Method method : {Method::kDt, Method::kDr}) expect_conforming(g, method);
  }
}

TEST(ConformingDelaunay, TheCheckerCanFail) {
  // The constrained Delaunay triangulation of a thin rectangle with a vertex near its long side is
  // not Delaunay across that side: the conforming check says so.
  Pslg g;
  g.points = {{0, 0}, {10, 0}, {10, 1}, {0, 1}, {5, 0.2}, {5, -0.2}};
  g.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  g.is_poly = true;
  TriangulateOptions o;
  o.convex_hull = true;
  Mesh m;
  triangulate(g, o, &m);
  CheckOptions c;
  c.conforming_delaunay = true;
  EXPECT_FALSE(test::check_mesh(g, m, c).ok());
  EXPECT_GT(vertices_in_circumcircles(m), 0u);
  o.conforming_delaunay = true;
  const Report r = triangulate(g, o, &m);
  EXPECT_TRUE(test::check_mesh(g, m, c).ok());
  EXPECT_EQ(vertices_in_circumcircles(m), 0u);
  EXPECT_GT(r.steiner, 0u);
  o.flip = true;
  EXPECT_THROW(triangulate(g, o), std::invalid_argument);
}

}  // namespace

// ---- 5. threads ----------------------------------------------------------------------------------

namespace threads_test {

struct Outcome {
  MeshArrays arrays;
  double weight = 0.0;
  nlohmann::json bundle;
};

Outcome run(const Pslg& g, TriangulateOptions o, unsigned threads) {
  o.threads = threads;
  Outcome out;
  out.arrays = triangulate_arrays(g, o);
  out.weight = out.arrays.report.weight_total;
  out.bundle = to_json(out.arrays.report).value("bundle_number", nlohmann::json());
  return out;
}

void expect_same(const Outcome& a, const Outcome& b) {
  EXPECT_EQ(a.arrays.vertices, b.arrays.vertices);
  EXPECT_EQ(a.arrays.triangles, b.arrays.triangles);
  EXPECT_EQ(a.arrays.neighbours, b.arrays.neighbours);
  EXPECT_EQ(a.arrays.segments, b.arrays.segments);
  EXPECT_EQ(a.weight, b.weight);
  EXPECT_EQ(a.bundle, b.bundle);
}

}  // namespace threads_test

// The meshes are the same, array for array, with 1, 2 and all threads: on inputs large enough for
// the two-thread paths of the Delaunay triangulation (2^15 points and up) and of the quadtree, and
// with the exact bundle tests of brh and --bundle.
TEST(Threads, ResultsDoNotDependOnTheThreadCount) {
  Pslg points;
  points.points = test::uniform_points(40000, 7);
  points.source = "uniform40k";
  std::vector<std::pair<Pslg, TriangulateOptions>> runs;
  TriangulateOptions dt;
  runs.push_back({points, dt});
  TriangulateOptions qtr;
  qtr.method = Method::kQtr;
  Pslg smaller = points;
  smaller.points.resize(12000);
  runs.push_back({smaller, qtr});
  const Pslg plate = io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
  TriangulateOptions brh;
  brh.method = Method::kBrh;
  brh.min_angle_deg = 30.0;
  brh.bundle = true;
  runs.push_back({plate, brh});
  TriangulateOptions dr;
  dr.method = Method::kDr;
  dr.regional_area_limits = true;
  dr.conforming_delaunay = true;
  dr.bundle = true;
  runs.push_back({two_regions(0.5, 3.0), dr});
  for (const auto& [g, o] : runs) {
    SCOPED_TRACE(g.source + " " + std::string(method_name(o.method)));
    const threads_test::Outcome one = threads_test::run(g, o, 1);
    EXPECT_GT(one.arrays.triangle_count(), 0u);
    for (const unsigned threads : {2u, 0u}) threads_test::expect_same(one, threads_test::run(g, o, threads));
  }
}
