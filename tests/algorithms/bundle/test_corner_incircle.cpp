// tests/algorithms/bundle/test_corner_incircle.cpp — the incircle determinant of a small circle at
// far points (corner_incircle.hpp), and the permissive floods that read it: a flood from the disk
// of a micrometre sliver (two corners 10⁻¹⁰ apart, as at the apex of `mwst generate fan`) must stay
// near the disk instead of crossing every edge with a far end.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "algorithms/bundle/corner_incircle.hpp"
#include "algorithms/bundle/lists.hpp"
#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/worker.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/delaunay.hpp"

namespace mwst {
namespace {

// A Delaunay sliver of BRH's mesh of a 10,000-vertex fan (shell points near the apex): radius
// 4.8e-7, two corners 3e-10 apart.
const Point kA{0.000547144183, 0.000838177488};
const Point kB{0.000547665107, 0.00083897632};
const Point kC{0.000547143932, 0.000838177651};

std::vector<Point> far_ring(std::size_t count) {
  std::vector<Point> ring;
  for (std::size_t i = 0; i < count; ++i) {
    const double t = 2.0 * 3.14159265358979323846 * static_cast<double>(i) / static_cast<double>(count);
    ring.push_back({kA.x + std::cos(t), kA.y + std::sin(t)});
  }
  return ring;
}

int sign_of(const bundle::Approx& g) { return g.value > g.error ? 1 : (g.value < -g.error ? -1 : 0); }

TEST(CornerIncircle, DecidesWhereIncirclesFilterCannot) {
  const bool ccw = orient2d(kA, kB, kC) > 0;
  const Point& b = ccw ? kB : kC;
  const Point& c = ccw ? kC : kB;
  const bundle::CornerCircle circle = bundle::corner_circle(kA, b, c);
  std::size_t filter_undecided = 0;
  for (const Point& d : far_ring(64)) {
    const int exact = incircle(kA, b, c, d);
    ASSERT_EQ(exact, -1);  // far outside
    if (sign_of(bundle::incircle_approx(kA, b, c, d)) == 0) ++filter_undecided;
    const bundle::Approx g = bundle::corner_incircle(circle, d);
    EXPECT_EQ(sign_of(g), exact);
    EXPECT_EQ(sign_of(bundle::incircle_from_either(kA, b, c, d, circle)), exact);
  }
  EXPECT_GT(filter_undecided, 32u);  // the premise: incircle's own filter fails at far points
}

// Wherever it gives a sign, the corner form gives the exact one (random circles and points, near
// and far, some nearly on the circle).
TEST(CornerIncircle, SignIsExactWhenDecided) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::size_t decided = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double scale = std::pow(10.0, -6.0 * (unit(rng) + 1.0) / 2.0);
    Point a{unit(rng), unit(rng)};
    Point b{a.x + scale * unit(rng), a.y + scale * unit(rng)};
    Point c{a.x + scale * unit(rng), a.y + scale * unit(rng)};
    if (orient2d(a, b, c) == 0) continue;
    if (orient2d(a, b, c) < 0) std::swap(b, c);
    Point d{unit(rng), unit(rng)};
    if (trial % 4 == 0) d = {b.x + scale * 1e-9 * unit(rng), b.y};  // near the circle
    const bundle::Approx g = bundle::corner_incircle(bundle::corner_circle(a, b, c), d);
    const int s = sign_of(g);
    if (s == 0) continue;
    ++decided;
    ASSERT_EQ(s, incircle(a, b, c, d)) << trial;
  }
  EXPECT_GT(decided, 10000u);
}

// The flood of the sliver's disk in DT(V): it meets the triangles around the sliver only, and the
// flood pops those and their neighbours across edges meeting the disk, not the whole mesh (before
// the corner form every edge to the ring had an end the filter could not place: the flood popped
// every triangle).
TEST(CornerIncircle, FloodOfASliverDiskStaysNearIt) {
  std::vector<Point> pts{kA, kB, kC};
  for (const Point& p : far_ring(128)) pts.push_back(p);
  const Mesh mesh = delaunay(pts);
  bundle::Shared sh(mesh);
  ASSERT_TRUE(sh.build(false));
  TriangleId sliver = kNone;
  std::size_t finite = 0;
  for (TriangleId d = 0; d < sh.dt.triangle_slots(); ++d) {
    if (sh.dt.is_dead(d) || sh.dt.is_ghost(d)) continue;
    ++finite;
    std::size_t near = 0;
    for (const VertexId v : sh.dt.triangles[d].v) near += std::fabs(sh.pts[v].x - kA.x) < 1e-5 ? 1 : 0;
    if (near == 3) sliver = d;
  }
  ASSERT_NE(sliver, kNone);
  ASSERT_GT(finite, 120u);
  auto workers = bundle::make_workers(sh, 1, false, false);
  bundle::Worker& w = *workers[0];
  std::uint32_t meeting = 0;  // by brute force, exactly
  for (TriangleId t = 0; t < sh.slots.size(); ++t) {
    if (!sh.is_ghost(t) && sh.in_domain(t) && w.disk_meets(sliver, t)) ++meeting;
  }
  w.flood_visits = 0;
  EXPECT_EQ(w.count_meeting(sliver, 1000), meeting);
  EXPECT_LE(w.flood_visits, 3 * meeting + 3);
}

// The flat Delaunay triangles along a hull edge of nearly collinear vertices (a fan's last wedge
// edge at 90°: x = r·cos(π/2) rounded): their disks, of radius up to 10²³, lie outside the hull and
// meet the triangles on the edge and a sliver beyond. The filters cannot place the other vertices
// of the edge, so a flood crossed every edge along it; with exact_edges (in_k_bundle's floods) the
// undecided edges are decided exactly, and the flood pops about what the disk meets.
TEST(CornerIncircle, ExactEdgesKeepFlatHullFloodsShort) {
  std::vector<Point> pts;
  const double cos_right = std::cos(3.14159265358979323846 / 2.0);
  for (int i = 1; i <= 200; ++i) {
    const double r = 0.00731 * i + 0.0001 * (i % 7);
    pts.push_back({r * cos_right, r});
  }
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) pts.push_back({0.01 + 0.02 * i, 0.02 + 0.07 * j});
  }
  const Mesh mesh = delaunay(pts);
  bundle::Shared sh(mesh);
  ASSERT_TRUE(sh.build(false));
  auto workers = bundle::make_workers(sh, 1, false, false);
  bundle::Worker& w = *workers[0];
  std::size_t flat = 0, leaked = 0;
  for (TriangleId d = 0; d < sh.dt.triangle_slots(); ++d) {
    if (sh.dt.is_dead(d) || sh.dt.is_ghost(d)) continue;
    bool on_hull_line = true;
    for (const VertexId v : sh.dt.triangles[d].v) on_hull_line = on_hull_line && std::fabs(sh.pts[v].x) < 1e-12;
    if (!on_hull_line) continue;
    ++flat;
    std::uint32_t meeting = 0;  // by brute force, exactly
    for (TriangleId t = 0; t < sh.slots.size(); ++t) {
      if (!sh.is_ghost(t) && sh.in_domain(t) && w.disk_meets(d, t)) ++meeting;
    }
    w.exact_edges = false;
    w.flood_visits = 0;
    EXPECT_EQ(w.count_meeting(d, 100000), meeting);
    if (w.flood_visits > 3 * meeting + 3) ++leaked;
    w.exact_edges = true;
    w.flood_visits = 0;
    EXPECT_EQ(w.count_meeting(d, 100000), meeting);
    EXPECT_LE(w.flood_visits, 3 * meeting + 3);
  }
  EXPECT_GT(flat, 10u);
  EXPECT_GT(leaked, 0u);  // the premise: without exact edges, some of these floods ran along the edge
}

}  // namespace
}  // namespace mwst
