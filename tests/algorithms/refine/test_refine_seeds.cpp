// tests/algorithms/refine/test_refine_seeds.cpp — tests of seeded refinement (RefineOptions::seed_triangles,
// src/algorithms/refine/refine.cpp), the incremental pass bundle removal (src/algorithms/refine/brh.cpp) runs
// after its first pass.
//
// 1. Seeds without a custom bad-triangle test are ignored: the output equals the unseeded one
//    vertex for vertex and triangle for triangle.
// 2. A mesh refined with a custom test that spares half of the domain, then refined again seeded
//    with every skinny triangle (and stale / invalid slots, which are ignored) under the plain angle
//    test, meets the angle bound everywhere: every triangle a seeded pass makes is tested, so
//    starting from all the bad ones suffices. validate() with the Delaunay check; no triangle below
//    the bound.
// 3. Seeds that are not bad insert nothing and leave the mesh as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/refine.hpp"
#include "support/mesh_queries.hpp"

namespace {

using namespace mwst;

Mesh square_cdt(std::size_t n, unsigned seed) {
  Pslg g;
  g.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) g.points.push_back({u(rng), u(rng)});
  for (std::uint32_t i = 0; i < 4; ++i) g.segments.push_back({i, (i + 1) % 4, 1});
  g.is_poly = true;
  return constrained_delaunay(g);
}

bool same_mesh(const Mesh& a, const Mesh& b) {
  if (a.points.size() != b.points.size() || a.triangles.size() != b.triangles.size()) return false;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    if (a.points[i].x != b.points[i].x || a.points[i].y != b.points[i].y) return false;
  }
  for (TriangleId t = 0; t < a.triangles.size(); ++t) {
    if (a.triangles[t].v != b.triangles[t].v || a.triangles[t].n != b.triangles[t].n) return false;
    if (a.flags[t] != b.flags[t]) return false;
  }
  return true;
}

TEST(RefineSeeds, IgnoredWithoutCustomTest) {
  const Mesh cdt = square_cdt(3000, 11);
  Mesh plain = cdt, seeded = cdt;
  RefineOptions o;
  o.min_angle_deg = 25.0;
  const RefineStats a = refine(plain, o);
  o.seed_triangles = {0, 1, 2, 3};
  const RefineStats b = refine(seeded, o);
  EXPECT_GT(a.steiner_inserted, 0u);
  EXPECT_EQ(a.steiner_inserted, b.steiner_inserted);
  EXPECT_EQ(a.segment_splits, b.segment_splits);
  EXPECT_TRUE(same_mesh(plain, seeded));
}

TEST(RefineSeeds, SeededPassFromAllBadTrianglesMeetsTheBound) {
  const double bound = 25.0;
  Mesh m = square_cdt(4000, 12);
  // First pass: only triangles whose centroid lies left of x = 0.5 are refined.
  RefineOptions first;
  first.min_angle_deg = bound;
  first.is_bad = [&](const Mesh& mesh, TriangleId t) {
    const auto& v = mesh.triangles[t].v;
    const double cx = (mesh.points[v[0]].x + mesh.points[v[1]].x + mesh.points[v[2]].x) / 3.0;
    return cx < 0.5 && test::min_angle_of(mesh, t) < bound;
  };
  refine(m, first);
  ASSERT_TRUE(validate(m, {true, 0.0}).empty());
  std::vector<TriangleId> skinny;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t) && test::min_angle_of(m, t) < bound) skinny.push_back(t);
  }
  ASSERT_GT(skinny.size(), 100u);  // the right half is untouched
  const std::size_t slots_before = m.triangles.size();
  // Second pass, seeded: every skinny triangle, plus slots that are out of range or not in the
  // domain (ghosts), which must be ignored.
  RefineOptions second;
  second.min_angle_deg = bound;
  second.is_bad = [&](const Mesh& mesh, TriangleId t) { return test::min_angle_of(mesh, t) < bound; };
  second.seed_triangles = skinny;
  second.seed_triangles.push_back(static_cast<TriangleId>(slots_before + 1000));
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.is_ghost(t) && !m.is_dead(t)) {
      second.seed_triangles.push_back(t);
      break;
    }
  }
  const RefineStats s = refine(m, second);
  EXPECT_GT(s.steiner_inserted, 0u);
  EXPECT_EQ(s.left_small_angle, 0u);
  EXPECT_EQ(to_string(s.stop), "bound reached");
  ValidateOptions vo;
  vo.delaunay = true;
  const auto problems = validate(m, vo);
  EXPECT_TRUE(problems.empty()) << (problems.empty() ? "" : problems.front());
  std::size_t below = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t) && test::min_angle_of(m, t) < bound) ++below;
  }
  EXPECT_EQ(below, 0u);
}

TEST(RefineSeeds, GoodSeedsChangeNothing) {
  Mesh m = square_cdt(2000, 13);
  RefineOptions o;
  o.min_angle_deg = 20.0;
  refine(m, o);
  const Mesh before = m;
  RefineOptions again;
  again.min_angle_deg = 20.0;
  again.is_bad = [](const Mesh& mesh, TriangleId t) { return test::min_angle_of(mesh, t) < 20.0; };
  for (TriangleId t = 0; t < m.triangles.size() && again.seed_triangles.size() < 50; ++t) {
    if (m.in_domain(t)) again.seed_triangles.push_back(t);
  }
  const RefineStats s = refine(m, again);
  EXPECT_EQ(s.steiner_inserted + s.segment_splits, 0u);
  EXPECT_EQ(s.left_small_angle, 0u);
  EXPECT_TRUE(same_mesh(before, m));
}

}  // namespace
