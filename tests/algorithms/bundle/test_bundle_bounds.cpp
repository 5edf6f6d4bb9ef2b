// bundle_number's bounds when a candidate budget cuts lists short (upper_bound.cpp): the box
// counts match brute force, and on inputs whose exact answer is known (solved without a budget)
// the bounds bracket it; the upper bound is far below the triangle count where disks are bounded.
// Also the fan (a polygon whose apex is a corner of every triangle), which cost the square of its
// size before the floods and the covering mesh turned around their ends of smaller degree.
#include <gtest/gtest.h>
#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "algorithms/bundle/lists.hpp"
#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/upper_bound.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {
namespace {

using Tri = std::array<std::uint32_t, 3>;

std::vector<Tri> domain_triangles(const Mesh& m) {
  std::vector<Tri> out;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t)) out.push_back({m.triangles[t].v[0], m.triangles[t].v[1], m.triangles[t].v[2]});
  }
  return out;
}

// n points on the ellipse x = cos t, y = ry sin t, and a few inside.
std::vector<Point> ellipse_points(std::size_t n, double ry) {
  std::vector<Point> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * static_cast<double>(i) / static_cast<double>(n);
    pts.push_back({std::cos(a), ry * std::sin(a)});
  }
  pts.push_back({0.1, 0.05 * ry});
  pts.push_back({-0.3, -0.1 * ry});
  return pts;
}

// A fan polygon: apex (0, 0), then `wedges` thin wedges alternating between radius 1 and radius
// 0.001, as `mwst generate fan` makes; triangulated (constrained Delaunay of the polygon).
std::vector<Tri> fan(std::size_t wedges, std::vector<Point>& pts) {
  Pslg pslg;
  pslg.points.push_back({0.0, 0.0});
  const double step = 1e-4;  // radians
  for (std::size_t i = 0; i < wedges; ++i) {
    const double a = step * static_cast<double>(i);
    const double r = i % 2 == 0 ? 1.0 : 0.001;
    pslg.points.push_back({r * std::cos(a), r * std::sin(a)});
  }
  const auto n = static_cast<std::uint32_t>(pslg.points.size());
  for (std::uint32_t i = 0; i < n; ++i) pslg.segments.push_back({i, (i + 1) % n, 1});
  const Mesh m = constrained_delaunay(pslg, {});
  pts = m.points;
  return domain_triangles(m);
}

void expect_brackets(const std::vector<Point>& pts, const std::vector<Tri>& tris, const BundleResult& exact,
                     std::size_t budget) {
  SCOPED_TRACE("budget " + std::to_string(budget));
  const BundleResult r = bundle_number(pts, tris, {.candidate_budget = budget});
  EXPECT_LE(r.lower_bound, exact.bundle_number);
  EXPECT_GE(r.upper_bound, exact.bundle_number);
  EXPECT_EQ(r.exact, r.lower_bound == r.upper_bound);
  EXPECT_EQ(r.triangles.size(), r.lower_bound);
  if (r.exact) {
    EXPECT_EQ(r.bundle_number, exact.bundle_number);
  }
}

TEST(BundleBounds, BoxCountsMatchBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> coordinate(0, 20);  // small integers: many ties
  auto random_box = [&] {
    const int x0 = coordinate(rng), x1 = coordinate(rng), y0 = coordinate(rng), y1 = coordinate(rng);
    return bundle::outward_box(std::min(x0, x1), std::min(y0, y1), std::max(x0, x1), std::max(y0, y1));
  };
  std::vector<bundle::Box> boxes(300), queries(200);
  for (auto& b : boxes) b = random_box();
  for (auto& q : queries) q = random_box();
  const bundle::BoxCounter counter(boxes);
  const std::vector<std::uint32_t> counts = counter.count(queries);
  ASSERT_EQ(counts.size(), queries.size());
  // The two sweeps on two threads (and the counter's scratch reused) give the same counts.
  EXPECT_EQ(counter.count(queries, 2), counts);
  EXPECT_EQ(bundle::BoxCounter(boxes, 2).count(queries, 2), counts);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto& q = queries[i];
    std::uint32_t brute = 0;
    for (const auto& b : boxes) brute += (b[2] >= q[0] && b[0] <= q[2] && b[3] >= q[1] && b[1] <= q[3]) ? 1 : 0;
    EXPECT_EQ(counts[i], brute) << "query " << i;
  }
}

// circumdisk_box holds the exact circumdisk (rationals) of random triangles, nearly flat ones and
// ones far from the origin included, whenever it places one: the exact centre lies at least the
// exact radius inside each side.
TEST(BundleBounds, CircumdiskBoxHoldsTheExactDisk) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::size_t placed = 0, placed_flat = 0;
  for (int i = 0; i < 3000; ++i) {
    const double offset = i % 3 == 0 ? 0.0 : (i % 3 == 1 ? 1e6 : -3e9);
    const double scale = i % 5 == 0 ? 1e-6 : 1.0;
    Point a{offset + unit(rng) * scale, offset + unit(rng) * scale};
    Point b{offset + unit(rng) * scale, offset + unit(rng) * scale};
    Point c{offset + unit(rng) * scale, offset + unit(rng) * scale};
    if (i % 4 == 0) c = {0.5 * a.x + 0.5 * b.x + unit(rng) * 1e-12 * scale, 0.5 * a.y + 0.5 * b.y};  // nearly flat
    if (orient2d(a, b, c) == 0) continue;
    if (orient2d(a, b, c) < 0) std::swap(b, c);
    std::array<double, 4> box;
    if (!bundle::circumdisk_box(a, b, c, box)) continue;
    ++placed;
    if (i % 4 == 0) ++placed_flat;
    const mpq_class ux = mpq_class(b.x) - a.x, uy = mpq_class(b.y) - a.y;
    const mpq_class vx = mpq_class(c.x) - a.x, vy = mpq_class(c.y) - a.y;
    const mpq_class u2 = ux * ux + uy * uy, v2 = vx * vx + vy * vy;
    const mpq_class d = 2 * (ux * vy - uy * vx);
    const mpq_class ox = (vy * u2 - uy * v2) / d, oy = (ux * v2 - vx * u2) / d;
    const mpq_class cx = ox + a.x, cy = oy + a.y, r2 = ox * ox + oy * oy;
    const mpq_class gaps[4] = {cx - box[0], cy - box[1], mpq_class(box[2]) - cx, mpq_class(box[3]) - cy};
    for (const mpq_class& g : gaps) {
      ASSERT_GE(sgn(g), 0) << "triangle " << i;
      ASSERT_GE(g * g, r2) << "triangle " << i;
    }
  }
  EXPECT_GT(placed, 2000u);
  EXPECT_GT(placed_flat, 100u);  // nearly flat triangles with huge disks are placed too
}

// Points on an ellipse: with a budget far too small, the lower and upper bounds bracket the exact
// number (computed without a budget), and the upper bound is not the triangle count: the disks of
// the ellipse's Delaunay triangles each meet about a third of the triangles.
TEST(BundleBounds, EllipseBoundsBracketTheExactNumber) {
  for (const std::size_t n : {60u, 400u, 2000u}) {
    SCOPED_TRACE(std::to_string(n) + " points");
    const std::vector<Point> pts = ellipse_points(n, 0.5);
    const std::vector<Tri> tris = domain_triangles(delaunay(pts));
    const BundleResult exact = bundle_number(pts, tris);
    ASSERT_TRUE(exact.exact);
    for (const std::size_t budget : {std::size_t{1}, std::size_t{50}, 4 * tris.size()}) {
      expect_brackets(pts, tris, exact, budget);
    }
    const BundleResult cut = bundle_number(pts, tris, {.candidate_budget = 4 * tris.size()});
    EXPECT_GT(cut.truncated_disks, 0u);
    EXPECT_LT(cut.upper_bound, tris.size() * 3 / 4);
  }
}

// build_lists_within_budget's lists are the floods' lists cut at their caps: the second pass's
// longer lists replace the first pass's cut ones in place (moved from the last down), and every
// other list stays as it was. Points in a square inside a ring of points on a circle: small disks
// inside, huge ones along the ring, so that some budgets cut lists twice.
TEST(BundleBounds, BudgetListsAreTheFloodsCutAtTheirCaps) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
  std::vector<Point> pts;
  for (int i = 0; i < 400; ++i) pts.push_back({coordinate(rng), coordinate(rng)});
  for (int i = 0; i < 150; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / 150.0;
    pts.push_back({2.0 * std::cos(a), 2.0 * std::sin(a)});
  }
  const Mesh mesh = delaunay(pts);
  bool second_pass = false;
  for (const std::size_t per_disk : {4u, 8u, 12u, 16u, 24u}) {
    SCOPED_TRACE("budget per disk " + std::to_string(per_disk));
    bundle::Shared sh(mesh);
    ASSERT_TRUE(sh.build());
    const std::size_t disks = sh.share_cocircular_disks();
    auto workers = bundle::make_workers(sh, 1, false, true);
    bundle::build_lists_within_budget(sh, workers, per_disk * disks);
    std::vector<TriangleId> full;
    for (TriangleId d = 0; d < sh.dt.triangle_slots(); ++d) {
      if (sh.dt.is_dead(d) || sh.dt.is_ghost(d) || sh.disk(d) != d) continue;
      workers[0]->flood(d, full);
      const std::size_t size = sh.list_size(d);
      ASSERT_LE(size, full.size());
      EXPECT_TRUE(std::equal(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(size), sh.list_data(d)));
      EXPECT_EQ(sh.list_cut(d), size < full.size());
      second_pass = second_pass || size > per_disk;
    }
  }
  EXPECT_TRUE(second_pass);
}

// The fan: exact without a budget, bracketed with one (its apex is a corner of every triangle).
TEST(BundleBounds, FanBoundsBracketTheExactNumber) {
  std::vector<Point> pts;
  const std::vector<Tri> tris = fan(301, pts);
  ASSERT_GT(tris.size(), 290u);
  const BundleResult exact = bundle_number(pts, tris);
  ASSERT_TRUE(exact.exact);
  EXPECT_GE(exact.bundle_number, tris.size() / 2);  // a disk at the apex meets about half
  for (const std::size_t budget : {std::size_t{1}, std::size_t{300}, 8 * tris.size()}) {
    expect_brackets(pts, tris, exact, budget);
  }
}

// count_cut_lists stops counting once no disk left can enter the few largest counts, and picks the
// same disks as counting every cut list: points on an ellipse (whose cut disks meet all of their
// lists: it stops early) and random points inside a circle (which it may not).
TEST(BundleBounds, CutListCountsStopOnceTheLargestAreKnown) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
  std::vector<Point> inside = ellipse_points(300, 0.5);
  for (int i = 0; i < 300; ++i) inside.push_back({coordinate(rng), coordinate(rng)});
  std::vector<Point> ellipse = ellipse_points(20000, 0.5);
  bool stopped_early = false;
  for (const std::vector<Point>* pts : {&ellipse, &inside}) {
    const Mesh mesh = delaunay(*pts);
    for (const std::size_t per_disk : {2u, 6u}) {
      SCOPED_TRACE("budget per disk " + std::to_string(per_disk));
      bundle::Shared sh(mesh);
      ASSERT_TRUE(sh.build());
      const std::size_t disks = sh.share_cocircular_disks();
      auto workers = bundle::make_workers(sh, 2, false, true);
      ASSERT_FALSE(bundle::build_lists_within_budget(sh, workers, per_disk * disks));
      std::vector<std::pair<std::uint32_t, TriangleId>> cut, all;
      for (TriangleId d = 0; d < sh.truncated.size(); ++d) {
        if (sh.truncated[d]) cut.emplace_back(0, d);
      }
      ASSERT_GT(cut.size(), 4u);
      all = cut;
      for (auto& [count, d] : all) count = workers[0]->circumdisk_count(d, sh.list_data(d), sh.list_size(d), nullptr);
      const std::size_t counted = bundle::count_cut_lists(sh, workers, cut, 4);
      ASSERT_LE(counted, cut.size());
      for (std::size_t i = 0; i < counted; ++i) EXPECT_EQ(cut[i], all[i]);
      stopped_early = stopped_early || counted < cut.size();
      const auto larger = [](const auto& x, const auto& y) {
        return x.first > y.first || (x.first == y.first && x.second < y.second);
      };
      std::partial_sort(all.begin(), all.begin() + 4, all.end(), larger);
      std::partial_sort(cut.begin(), cut.begin() + 4, cut.begin() + static_cast<std::ptrdiff_t>(counted), larger);
      for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(cut[i], all[i]);
    }
  }
  EXPECT_TRUE(stopped_early);
}

// bundle_number of a triangle list builds DT(V) from the points alone, in Shared::curve_order, on a
// second thread while the covering mesh is built, and gives it to Shared::build as its prior DT:
// the same renumbering, the same DT slot for slot, the same pencils, and (above the size where
// the list version starts that thread) the same answer as on one thread.
TEST(BundleBounds, DelaunayFromThePointsAloneIsSharedsOwn) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
  std::vector<Point> pts = ellipse_points(2000, 0.5);
  for (int i = 0; i < 12000; ++i) pts.push_back({coordinate(rng), 0.5 * coordinate(rng)});
  const Mesh mesh = delaunay(pts);
  bundle::Shared own(mesh);
  ASSERT_TRUE(own.build());
  std::vector<VertexId> ids = bundle::Shared::curve_order(mesh.points);
  std::vector<Point> in_order;
  for (const VertexId v : ids) in_order.push_back(mesh.points[v]);
  Mesh prior = delaunay(in_order, nullptr, 1);
  bundle::Shared given(mesh);
  ASSERT_TRUE(given.build(true, nullptr, &prior, &ids));
  EXPECT_TRUE(given.kept_dt);
  EXPECT_EQ(given.mesh_id, own.mesh_id);
  ASSERT_EQ(given.dt.triangle_slots(), own.dt.triangle_slots());
  for (TriangleId t = 0; t < own.dt.triangle_slots(); ++t) {
    EXPECT_EQ(given.dt.triangles[t].v, own.dt.triangles[t].v);
    EXPECT_EQ(given.dt.triangles[t].n, own.dt.triangles[t].n);
  }
  EXPECT_EQ(given.pencils, own.pencils);
  const std::vector<Tri> tris = domain_triangles(mesh);
  ASSERT_GT(tris.size(), 20000u);
  const BundleResult one = bundle_number(pts, tris, {.threads = 1});
  const BundleResult two = bundle_number(pts, tris, {.threads = 2});
  EXPECT_EQ(two.bundle_number, one.bundle_number);
  EXPECT_EQ(two.triangles, one.triangles);
  EXPECT_EQ(two.disk_center, one.disk_center);
  EXPECT_EQ(two.disk_radius, one.disk_radius);
}

}  // namespace
}  // namespace mwst
