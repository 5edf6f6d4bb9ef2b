// Tests of the exact minimum weight triangulation (mwst/algorithms/mwt.hpp): against an exhaustive search over
// all triangulations of small point sets (with and without segments, convex and concave domains),
// against the polygon DP for points in convex position, both candidate routes against each other,
// never heavier than the locally minimal EFH mesh on the same vertices, and every output checked by
// validate() and by the independent checker (check_triangulation) with its segments kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/mwt.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "algorithms/mwt/polygon_mwt.hpp"

#include "support/exact_checker.hpp"

namespace mwst {
namespace {

using test::check_mesh;

using EdgeSet = std::set<std::pair<VertexId, VertexId>>;

EdgeSet domain_edges(const Mesh& m) {
  EdgeSet s;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) s.insert(std::minmax(m.org(make_handle(t, e)), m.dest(make_handle(t, e))));
  }
  return s;
}

// Exhaustive search: the lightest maximal set of pairwise non-crossing edges among `edges` that
// contains `forced` (for edges that are exactly the segments lying in a domain, the maximal sets
// are its triangulations). Edges are decided in order; an edge may be left out only if a later,
// still compatible edge crosses it (else no completion could be maximal).
double exhaustive_mwt(const std::vector<Point>& P, const std::vector<std::pair<VertexId, VertexId>>& edges,
                      const EdgeSet& forced) {
  const std::size_t m = edges.size();
  auto cross = [&](std::size_t i, std::size_t j) {
    const auto [a, b] = edges[i];
    const auto [c, d] = edges[j];
    if (a == c || a == d || b == c || b == d) return false;
    const int o1 = orient2d(P[a], P[b], P[c]), o2 = orient2d(P[a], P[b], P[d]);
    const int o3 = orient2d(P[c], P[d], P[a]), o4 = orient2d(P[c], P[d], P[b]);
    return o1 * o2 < 0 && o3 * o4 < 0;
  };
  std::vector<std::vector<char>> X(m, std::vector<char>(m, 0));
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < m; ++j) X[i][j] = cross(i, j) ? 1 : 0;
  std::vector<char> in(m, 0);
  double best = std::numeric_limits<double>::infinity();
  std::function<void(std::size_t, double)> go = [&](std::size_t i, double w) {
    if (i == m) {
      for (std::size_t e = 0; e < m; ++e) {
        if (in[e]) continue;
        bool crossed = false;
        for (std::size_t f = 0; f < m && !crossed; ++f) crossed = in[f] && X[e][f];
        if (!crossed) return;  // not maximal
      }
      best = std::min(best, w);
      return;
    }
    bool compatible = true;
    for (std::size_t f = 0; f < i && compatible; ++f) compatible = !(in[f] && X[i][f]);
    if (compatible) {
      in[i] = 1;
      go(i + 1, w + distance(P[edges[i].first], P[edges[i].second]));
      in[i] = 0;
    }
    if (forced.count(edges[i])) return;
    bool coverable = !compatible;
    for (std::size_t f = i + 1; f < m && !coverable; ++f) {
      if (!X[i][f]) continue;
      bool ok = true;
      for (std::size_t g = 0; g < i && ok; ++g) ok = !(in[g] && X[f][g]);
      coverable = ok;
    }
    if (coverable) go(i + 1, w);
  };
  go(0, 0.0);
  return best;
}

bool on_open_segment(const Point& u, const Point& v, const Point& p) {
  if (orient2d(u, v, p) != 0) return false;
  return std::min(u.x, v.x) <= p.x && p.x <= std::max(u.x, v.x) && std::min(u.y, v.y) <= p.y &&
         p.y <= std::max(u.y, v.y) && !(p == u) && !(p == v);
}

// Pairs of used vertices whose open segment contains no vertex, crosses no segment and (for a
// polygon domain) has its midpoint inside the polygon `boundary` (even-odd rule; empty = hull).
std::vector<std::pair<VertexId, VertexId>> visible_pairs(const Mesh& m, const std::vector<Point>& boundary) {
  std::set<VertexId> used;
  for (TriangleId t = 0; t < m.triangles.size(); ++t)
    if (m.in_domain(t)) used.insert(m.triangles[t].v.begin(), m.triangles[t].v.end());
  const EdgeSet segs = test::domain_subsegments(m);
  std::vector<std::pair<VertexId, VertexId>> out;
  for (VertexId a : used) {
    for (VertexId b : used) {
      if (b <= a) continue;
      const Point& A = m.points[a];
      const Point& B = m.points[b];
      bool ok = true;
      for (VertexId k : used) ok = ok && !on_open_segment(A, B, m.points[k]);
      for (const auto& [c, d] : segs) {
        if (!ok) break;
        if (c == a || c == b || d == a || d == b) continue;
        const Point& C = m.points[c];
        const Point& D = m.points[d];
        if (orient2d(A, B, C) * orient2d(A, B, D) < 0 && orient2d(C, D, A) * orient2d(C, D, B) < 0) ok = false;
      }
      if (ok && !boundary.empty()) {
        const Point mid = midpoint(A, B);
        bool inside = false;
        for (std::size_t i = 0, j = boundary.size() - 1; i < boundary.size(); j = i++) {
          const Point& p = boundary[i];
          const Point& q = boundary[j];
          if ((p.y > mid.y) != (q.y > mid.y) && mid.x < (q.x - p.x) * (mid.y - p.y) / (q.y - p.y) + p.x) inside = !inside;
        }
        ok = inside || segs.count({a, b});
      }
      if (ok) out.push_back({a, b});
    }
  }
  return out;
}

void expect_solved_and_valid(const Pslg& g, const Mesh& input, const MwtResult& r) {
  ASSERT_TRUE(r.solved) << r.route << ": " << r.reason;
  const std::vector<std::string> problems = validate(r.mesh);
  EXPECT_TRUE(problems.empty()) << problems.front();
  const CheckResult check = check_mesh(g, r.mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
  EXPECT_EQ(test::domain_subsegments(r.mesh), test::domain_subsegments(input));
  EXPECT_EQ(measure(r.mesh).vertices, measure(input).vertices);
  EXPECT_EQ(measure(r.mesh).triangles, measure(input).triangles);
  EXPECT_DOUBLE_EQ(r.weight, measure(r.mesh).weight_total);
}

std::vector<Point> random_points(std::mt19937_64& rng, std::size_t n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> p(n);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

TEST(ExactMwt, MatchesExhaustiveSearchOnSmallPointSets) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const std::size_t n = 4 + static_cast<std::size_t>(trial % 6);  // 4..9 points
    Pslg g;
    g.points = random_points(rng, n);
    const Mesh dt = delaunay(g.points);
    for (bool diamond : {true, false}) {
      MwtOptions options;
      options.diamond_route = diamond;
      const MwtResult r = exact_mwt(dt, options);
      expect_solved_and_valid(g, dt, r);
      const double brute = exhaustive_mwt(dt.points, visible_pairs(dt, {}), {});
      EXPECT_NEAR(r.weight, brute, 1e-12 * brute) << "trial " << trial << " route " << r.route;
      EXPECT_EQ(r.route, diamond ? "diamond" : "visibility");
    }
  }
}

TEST(ExactMwt, MatchesExhaustiveSearchWithSegments) {
  std::mt19937_64 rng(12);
  int with_segments = 0, by_visibility = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const std::size_t n = 6 + static_cast<std::size_t>(trial % 4);  // 6..9 points
    Pslg g;
    g.points = random_points(rng, n);
    g.is_poly = true;
    // Two non-crossing segments between random points (kept only if they cross no earlier one
    // and pass through no point).
    for (int s = 0; s < 3; ++s) {
      const auto a = static_cast<std::uint32_t>(rng() % n), b = static_cast<std::uint32_t>(rng() % n);
      if (a == b) continue;
      bool ok = true;
      for (std::size_t k = 0; k < n; ++k) ok = ok && !on_open_segment(g.points[a], g.points[b], g.points[k]);
      for (const Segment& t : g.segments) {
        if (t.a == a || t.a == b || t.b == a || t.b == b) {
          ok = ok && !(std::minmax(t.a, t.b) == std::minmax(a, b));
          continue;
        }
        ok = ok && !(orient2d(g.points[a], g.points[b], g.points[t.a]) * orient2d(g.points[a], g.points[b], g.points[t.b]) < 0 &&
                     orient2d(g.points[t.a], g.points[t.b], g.points[a]) * orient2d(g.points[t.a], g.points[t.b], g.points[b]) < 0);
      }
      if (ok) g.segments.push_back({a, b, 2});
    }
    ConstrainOptions copt;
    copt.convex_hull = true;  // keep the hull: the segments are constraints inside it
    const Mesh cdt = constrained_delaunay(g, copt);
    const EdgeSet forced = test::domain_subsegments(cdt);
    const double brute = exhaustive_mwt(cdt.points, visible_pairs(cdt, {}), forced);
    const MwtResult r = exact_mwt(cdt);
    ASSERT_TRUE(r.solved) << r.reason;
    with_segments += forced.empty() ? 0 : 1;
    by_visibility += r.route == "visibility" ? 1 : 0;
    for (const auto& s : forced) EXPECT_TRUE(domain_edges(r.mesh).count(s));
    EXPECT_NEAR(r.weight, brute, 1e-12 * brute) << "trial " << trial << " route " << r.route;
    EXPECT_TRUE(validate(r.mesh).empty());
    EXPECT_EQ(test::domain_subsegments(r.mesh), forced);
  }
  EXPECT_GE(with_segments, 30);  // the trials do constrain something
  EXPECT_GT(by_visibility, 0);   // both routes are exercised: the point set's MWT misses a
  EXPECT_LT(by_visibility, 40);  // segment in some trials and contains them all in others
}

TEST(ExactMwt, MatchesExhaustiveSearchOnConcavePolygons) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    // A star-shaped polygon of 5..7 corners around (0.5, 0.5) with 1..3 points inside it.
    const std::size_t corners = 5 + static_cast<std::size_t>(trial % 3);
    Pslg g;
    g.is_poly = true;
    for (std::size_t i = 0; i < corners; ++i) {
      const double angle = 2.0 * std::numbers::pi * (static_cast<double>(i) + 0.8 * u(rng)) / static_cast<double>(corners);
      const double radius = 0.2 + 0.3 * u(rng);
      g.points.push_back({0.5 + radius * std::cos(angle), 0.5 + radius * std::sin(angle)});
    }
    for (std::size_t i = 0; i < corners; ++i) {
      g.segments.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>((i + 1) % corners), 1});
    }
    const std::vector<Point> boundary = g.points;
    for (std::size_t k = 0; k < 1 + static_cast<std::size_t>(trial % 3); ++k) {
      g.points.push_back({0.5 + 0.1 * (u(rng) - 0.5), 0.5 + 0.1 * (u(rng) - 0.5)});
    }
    const Mesh cdt = constrained_delaunay(g);
    const EdgeSet forced = test::domain_subsegments(cdt);
    const double brute = exhaustive_mwt(cdt.points, visible_pairs(cdt, boundary), forced);
    for (bool diamond : {true, false}) {
      MwtOptions options;
      options.diamond_route = diamond;
      const MwtResult r = exact_mwt(cdt, options);
      expect_solved_and_valid(g, cdt, r);
      EXPECT_NEAR(r.weight, brute, 1e-12 * brute) << "trial " << trial << " route " << r.route;
    }
  }
}

TEST(ExactMwt, ConvexPositionMatchesThePolygonDp) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int convex_trials = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const std::size_t n = 12 + 6 * static_cast<std::size_t>(trial);
    std::vector<double> angles(n);
    for (auto& a : angles) a = 2.0 * std::numbers::pi * u(rng);
    std::sort(angles.begin(), angles.end());
    std::vector<Point> P;
    for (double a : angles) P.push_back({std::cos(a) * (1.0 + 0.3 * std::cos(2.0 * a)), std::sin(a)});
    if (!is_strictly_convex(P)) continue;
    ++convex_trials;
    double perimeter = 0.0;
    for (std::size_t i = 0; i < n; ++i) perimeter += distance(P[i], P[(i + 1) % n]);
    const double dp = polygon_mwt(P, nullptr) + perimeter;
    Pslg g;
    g.points = P;
    const Mesh dt = delaunay(P);
    const MwtResult r = exact_mwt(dt);
    expect_solved_and_valid(g, dt, r);
    EXPECT_NEAR(r.weight, dp, 1e-12 * dp) << "n = " << n;
  }
  EXPECT_GE(convex_trials, 8);
}

TEST(ExactMwt, RoutesAgreeAndBeatEfhOnRandomPointSets) {
  std::mt19937_64 rng(15);
  for (int trial = 0; trial < 12; ++trial) {
    const std::size_t n = 20 + 5 * static_cast<std::size_t>(trial);  // 20..75
    Pslg g;
    g.points = random_points(rng, n);
    const Mesh dt = delaunay(g.points);
    Mesh efh = dt;
    flip_to_local_minimum(efh);
    const double efh_weight = measure(efh).weight_total;
    const MwtResult from_dt = exact_mwt(dt);
    const MwtResult from_efh = exact_mwt(efh);
    expect_solved_and_valid(g, dt, from_dt);
    expect_solved_and_valid(g, efh, from_efh);
    EXPECT_EQ(from_dt.route, "diamond");
    EXPECT_LE(from_dt.weight, efh_weight * (1.0 + 1e-12));
    EXPECT_NEAR(from_dt.weight, from_efh.weight, 1e-12 * efh_weight);
    EXPECT_GT(from_dt.fixed_fraction(), 0.0);
    EXPECT_LE(from_dt.fixed_fraction(), 1.0);
    MwtOptions visibility;
    visibility.diamond_route = false;
    const MwtResult v = exact_mwt(dt, visibility);
    expect_solved_and_valid(g, dt, v);
    EXPECT_NEAR(v.weight, from_dt.weight, 1e-12 * efh_weight) << "n = " << n;
    // The result is locally minimal: no weight-reducing flip is left.
    EXPECT_EQ(count_weight_reducing_flips(from_dt.mesh), 0u);
  }
}

TEST(ExactMwt, RefinedMeshWithSegmentsIsNoHeavierThanEfh) {
  std::mt19937_64 rng(16);
  for (int trial = 0; trial < 4; ++trial) {
    Pslg g;
    g.points = random_points(rng, 30);
    TriangulateOptions options;
    options.method = Method::kDr;
    options.min_angle_deg = 20.0;
    options.flip = true;
    Mesh efh;
    const Report report = triangulate(g, options, &efh);
    const MwtResult r = exact_mwt(efh);
    expect_solved_and_valid(g, efh, r);
    EXPECT_LE(r.weight, report.weight_total * (1.0 + 1e-12));
  }
}

TEST(ExactMwt, SmallDataSetsAfterDrAndBrhWithEfh) {
  // Polygonal domains whose segments carry Steiner points: both routes where they apply, the
  // checker, segments kept, never heavier than EFH, and no straight-angle sliver along a segment.
  for (const char* name : {"Airliner.poly", "Africa.poly"}) {
    const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    for (Method method : {Method::kDr, Method::kBrh}) {
      TriangulateOptions options;
      options.method = method;
      options.min_angle_deg = 20.0;
      options.flip = true;
      Mesh efh;
      const Report report = triangulate(g, options, &efh);
      MwtOptions visibility;
      visibility.diamond_route = false;
      const MwtResult v = exact_mwt(efh, visibility);
      expect_solved_and_valid(g, efh, v);
      EXPECT_LE(v.weight, report.weight_total * (1.0 + 1e-12)) << name;
      EXPECT_EQ(count_weight_reducing_flips(v.mesh), 0u);
      const MwtResult r = exact_mwt(efh);
      expect_solved_and_valid(g, efh, r);
      EXPECT_NEAR(r.weight, v.weight, 1e-12 * v.weight) << name << " " << r.route;
    }
  }
}

TEST(ExactMwt, ReportsNotSolvedInsteadOfGuessing) {
  // With both routes closed (no diamond route, visibility limited below the size), nothing is
  // claimed optimal.
  std::mt19937_64 rng(17);
  const Mesh dt = delaunay(random_points(rng, 20));
  MwtOptions options;
  options.diamond_route = false;
  options.max_visibility_vertices = 10;
  const MwtResult r = exact_mwt(dt, options);
  EXPECT_FALSE(r.solved);
  EXPECT_FALSE(r.reason.empty());
  // A DP limit below every face size leaves faces unsolved: reported, not approximated.
  MwtOptions tiny;
  tiny.max_region = 3;
  tiny.max_visibility_vertices = 0;
  const MwtResult s = exact_mwt(delaunay(random_points(rng, 200)), tiny);
  if (s.regions > 0) {
    EXPECT_FALSE(s.solved);
  }
}

}  // namespace
}  // namespace mwst
