// Cocircular Delaunay triangles share one circumdisk: bundle_number floods and lists each distinct
// disk once (BundleResult::disks), so points on a circle cost one list, not one per triangle.
#include <gtest/gtest.h>
#include <gmpxx.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "algorithms/bundle/shared.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {
namespace {

// The lattice points on the circle x² + y² = R² with R = 5²·13·17·29·37 (1,620 of them: R² has the
// primes 5, 13, 17, 29, 37, each ≡ 1 mod 4), `count` of them spread evenly by angle. Exactly
// cocircular in double.
std::vector<Point> lattice_circle(std::size_t count) {
  const std::int64_t r = 25 * 13 * 17 * 29 * 37;
  const std::int64_t r2 = r * r;
  std::vector<Point> all;
  for (std::int64_t x = -r; x <= r; ++x) {
    const std::int64_t y2 = r2 - x * x;
    auto y = static_cast<std::int64_t>(std::llround(std::sqrt(static_cast<double>(y2))));
    while (y * y > y2) --y;
    while ((y + 1) * (y + 1) <= y2) ++y;
    if (y * y != y2) continue;
    all.push_back({static_cast<double>(x), static_cast<double>(y)});
    if (y != 0) all.push_back({static_cast<double>(x), static_cast<double>(-y)});
  }
  EXPECT_EQ(all.size(), 1620u);
  std::sort(all.begin(), all.end(), [](const Point& a, const Point& b) {
    return std::atan2(a.y, a.x) < std::atan2(b.y, b.x);
  });
  std::vector<Point> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(all[i * all.size() / count]);
  return out;
}

std::size_t finite_triangle_count(const Mesh& m) {
  std::size_t n = 0;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) n += m.is_dead(t) || m.is_ghost(t) ? 0 : 1;
  return n;
}

// The witness disk, shrunk by a relative 1e-9 (it is rounded, and every vertex lies on the circle),
// holds no vertex: exact rationals.
void expect_empty_witness(const std::vector<Point>& pts, const BundleResult& r) {
  const mpq_class cx(r.disk_center.x), cy(r.disk_center.y);
  const mpq_class radius(r.disk_radius * (1.0 - 1e-9));
  for (const Point& p : pts) {
    const mpq_class dx = mpq_class(p.x) - cx, dy = mpq_class(p.y) - cy;
    EXPECT_GE(dx * dx + dy * dy, radius * radius);
  }
}

// 1,000 points on a circle: 998 Delaunay triangles, one circumdisk. It is flooded once, it meets
// every triangle, and a budget of a few pairs per triangle (which 998 separate lists would
// exhaust, each list being every triangle) leaves the answer exact.
TEST(BundleCocircular, PointsOnACircleHaveOneDisk) {
  const std::vector<Point> pts = lattice_circle(1000);
  const Mesh m = delaunay(pts);
  const std::size_t triangles = finite_triangle_count(m);
  ASSERT_EQ(triangles, 998u);
  for (const std::size_t budget : {std::size_t{0}, std::size_t{4000}}) {
    SCOPED_TRACE("budget " + std::to_string(budget));
    const BundleResult r = bundle_number(m, {.candidate_budget = budget});
    EXPECT_EQ(r.disks, 1u);
    EXPECT_TRUE(r.exact);
    EXPECT_EQ(r.truncated_disks, 0u);
    EXPECT_EQ(r.bundle_number, triangles);
    EXPECT_EQ(r.upper_bound, triangles);
    EXPECT_EQ(r.triangles.size(), triangles);
    expect_empty_witness(pts, r);
  }
}

// One more point just outside the circle: the few triangles joining it to the hull get circumdisks
// of their own; the rest keep sharing the circle's.
TEST(BundleCocircular, APointOutsideAddsItsOwnDisks) {
  std::vector<Point> pts = lattice_circle(1000);
  const Point& a = pts[0];
  const Point& b = pts[1];
  pts.push_back({(a.x + b.x) * 0.5005, (a.y + b.y) * 0.5005});
  const Mesh m = delaunay(pts);
  const BundleResult r = bundle_number(m);
  EXPECT_GE(r.disks, 2u);
  EXPECT_LE(r.disks, 50u);  // a dozen or so hull edges see the point; 999 triangles without sharing
  EXPECT_TRUE(r.exact);
  expect_empty_witness(pts, r);
}

// A k × k grid: the two Delaunay triangles of each unit square share its circumdisk, and
// neighbouring squares' disks differ, so there are (k − 1)² disks for 2 (k − 1)² triangles.
TEST(BundleCocircular, GridSquaresShareTheirDisk) {
  for (const int k : {2, 5, 12}) {
    std::vector<Point> pts;
    for (int i = 0; i < k; ++i) {
      for (int j = 0; j < k; ++j) pts.push_back({static_cast<double>(i), static_cast<double>(j)});
    }
    const Mesh m = delaunay(pts);
    ASSERT_EQ(finite_triangle_count(m), static_cast<std::size_t>(2 * (k - 1) * (k - 1)));
    const BundleResult r = bundle_number(m);
    EXPECT_EQ(r.disks, static_cast<std::size_t>((k - 1) * (k - 1))) << k << " x " << k;
    EXPECT_TRUE(r.exact);
  }
}

// Shared::share_cocircular_disks tests each Delaunay edge once and keeps the answers for the
// pencils (Shared::cocircular_edge): on a grid and on points on a circle with one outside, they
// are the exact incircle signs, the same from both triangles on the edge.
TEST(BundleCocircular, EdgeAnswersAreTheExactIncircleSigns) {
  std::vector<Point> grid;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 7; ++j) grid.push_back({static_cast<double>(i), static_cast<double>(j)});
  }
  std::vector<Point> circle = lattice_circle(300);
  circle.push_back({(circle[0].x + circle[1].x) * 0.5005, (circle[0].y + circle[1].y) * 0.5005});
  for (const std::vector<Point>* pts : {&grid, &circle}) {
    const Mesh m = delaunay(*pts);
    bundle::Shared sh(m);
    ASSERT_TRUE(sh.build());
    sh.share_cocircular_disks(2);
    ASSERT_EQ(sh.cocircular.size(), sh.dt.triangle_slots());
    std::size_t cocircular = 0;
    for (TriangleId t = 0; t < sh.dt.triangle_slots(); ++t) {
      if (sh.dt.is_dead(t) || sh.dt.is_ghost(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e), hs = sh.dt.sym(h);
        if (sh.dt.is_ghost(triangle_of(hs))) {
          EXPECT_EQ(sh.cocircular[t] >> e & 1u, 0u);
          continue;
        }
        const bool exact = incircle(sh.pts[sh.dt.org(h)], sh.pts[sh.dt.dest(h)], sh.pts[sh.dt.apex(h)],
                                    sh.pts[sh.dt.apex(hs)]) == 0;
        EXPECT_EQ(sh.cocircular_edge(h), exact);
        EXPECT_EQ(sh.cocircular_edge(hs), exact);
        cocircular += exact ? 1 : 0;
      }
    }
    EXPECT_GT(cocircular, 0u);
  }
}

}  // namespace
}  // namespace mwst
