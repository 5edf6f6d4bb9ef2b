// Tests of the crowded-disk shortcut of BRH's local test (VertexIndex::crowded, brh_criteria.hpp):
// a circumdisk with more vertices within the index's pruning radius than its search may visit
// cannot be shown empty by that search, so the flood goes on without it and the search runs only
// if the flood ends under its cap. The shortcut must not change any answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "algorithms/refine/brh_criteria.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/mesh/delaunay.hpp"

namespace mwst {
namespace {

// The unit circle's corners 0, 1, 2 (angles 0, 2π/3, 4π/3), `near` points 1e-7 outside it (within
// the index's pruning radius, 1 + 1e-4, but outside the disk), `beyond` points just outside that
// radius (1 + 1e-3) and `far` points at radius 5. The near and beyond points lie on the arc of
// angles [0.5, 0.5 + span), the far ones all around.
std::vector<Point> rim_points(std::size_t near, std::size_t beyond, std::size_t far, double span) {
  std::vector<Point> p;
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 3.0;
    p.push_back({std::cos(a), std::sin(a)});
  }
  auto ring = [&](std::size_t n, double radius, double from, double width) {
    for (std::size_t i = 0; i < n; ++i) {
      const double a = from + width * static_cast<double>(i) / static_cast<double>(n);
      p.push_back({radius * std::cos(a), radius * std::sin(a)});
    }
  };
  ring(near, 1.0 + 1e-7, 0.5, span);
  ring(beyond, 1.0 + 1e-3, 0.5 + 0.3 * span, span);
  ring(far, 5.0, 0.0, 2.0 * std::numbers::pi);
  return p;
}

TEST(BrhCrowdedTest, CrowdedCountsTheVerticesWithinTheSearchsReach) {
  // crowded() says yes only when more than 4,096 vertices lie within the pruning radius (the three
  // corners count): 4,093 near points make 4,096 (never crowded), 4,094 make 4,097. On a short arc
  // (0.01 rad: its boxes lie within the radius, so a subtree is counted whole) it says so in a few
  // hundred box reads, however many points lie just beyond the radius on the same arc or far away
  // (a subtree counted whole when only partly within the radius, or a pending vertex missed, would
  // change the answer on one side). Spread around the whole circle, no box lies within the radius
  // and it gives up (no) after its read budget: the search runs then, as without it.
  for (const double span : {0.01, 2.0 * std::numbers::pi}) {
    for (const std::size_t beyond : {0u, 3000u}) {
      for (const std::size_t far : {0u, 20000u}) {
        for (const std::size_t near : {4093u, 4094u, 9000u}) {
          const std::vector<Point> points = rim_points(near, beyond, far, span);
          brh::VertexIndex index;
          index.sync(points);
          const std::array<VertexId, 3> cv{0, 1, 2};
          const bool within_budget = span < 1.0;
          const bool crowded = index.crowded(points, cv);
          EXPECT_EQ(crowded, within_budget && near + 3 > 4096)
              << span << " span, " << near << " near, " << beyond << " beyond, " << far << " far";
          if (within_budget) {
            EXPECT_LT(index.last_crowd_reads(), 1000u) << near << " near";
          }
          // A crowded disk is never shown empty by the search (here it holds no vertex: the
          // search gives up).
          auto inside = [&](VertexId x) { return incircle(points[0], points[1], points[2], points[x]) > 0; };
          const auto disk = index.strictly_inside(points, cv, inside);
          EXPECT_NE(disk, brh::VertexIndex::Disk::kHoldsVertex);
          if (crowded) {
            EXPECT_EQ(disk, brh::VertexIndex::Disk::kUnknown) << near;
          }
        }
      }
    }
  }
}

TEST(BrhCrowdedTest, CrowdedDisksAreNeverShownEmpty) {
  // Random disks through the near ring's points and the corners, a vertex placed strictly inside
  // some: whenever crowded() says yes, the search answers "unknown" or finds a vertex.
  std::vector<Point> points = rim_points(6000, 500, 2000, 0.01);
  points.push_back({0.3, 0.2});  // inside the unit disk
  brh::VertexIndex index;
  index.sync(points);
  std::size_t crowded = 0;
  for (VertexId q = 0; q < 400; ++q) {
    std::array<VertexId, 3> cv{q % 3, 3 + (q * 37) % 6000, 3 + (q * 101 + 2000) % 6000};
    if (cv[1] == cv[2]) continue;
    const int o = orient2d(points[cv[0]], points[cv[1]], points[cv[2]]);
    if (o == 0) continue;
    if (o < 0) std::swap(cv[1], cv[2]);
    auto inside = [&](VertexId x) { return incircle(points[cv[0]], points[cv[1]], points[cv[2]], points[x]) > 0; };
    if (!index.crowded(points, cv)) continue;
    ++crowded;
    EXPECT_NE(index.strictly_inside(points, cv, inside), brh::VertexIndex::Disk::kEmpty) << "query " << q;
  }
  EXPECT_GT(crowded, 100u);
}

TEST(BrhCrowdedTest, DeferringTheSearchOfCrowdedDisksChangesNoAnswer) {
  // BRH's first pass on a fan of narrow wedges (the refinement with "skinny and a local witness"
  // as its criterion), once with the crowded disks' searches deferred and once without: the
  // answers, hence the meshes, are the same, and disks were deferred.
  const Pslg input = generate_input(Distribution::kFan, 6000, 1);
  const std::uint32_t k = static_cast<std::uint32_t>(default_bundle_k(20.0));
  const brh::SkinnyTest skinny(20.0);
  std::vector<Mesh> meshes;
  std::uint64_t crowded = 0;
  for (const bool defer : {true, false}) {
    Mesh m = constrained_delaunay(input);
    brh::LocalBundleTest local(k);
    local.set_defer_crowded(defer);
    RefineOptions ro;
    ro.min_angle_deg = 20.0;
    ro.is_bad = [&](const Mesh& mesh, TriangleId t) { return skinny(mesh, t) && local.in_bundle(mesh, t); };
    refine(m, ro);
    if (defer) crowded = local.stats().index_crowded;
    meshes.push_back(std::move(m));
  }
  EXPECT_GT(crowded, 0u);
  ASSERT_EQ(meshes[0].points.size(), meshes[1].points.size());
  for (std::size_t i = 0; i < meshes[0].points.size(); ++i) {
    ASSERT_EQ(meshes[0].points[i].x, meshes[1].points[i].x) << i;
    ASSERT_EQ(meshes[0].points[i].y, meshes[1].points[i].y) << i;
  }
}

TEST(BrhCrowdedTest, ACrowdedDiskWhoseFloodEndsUnderTheCapIsStillAWitness) {
  // The unit circle through corners 0, 1, 2 and 4,200 points 5e-5 outside it on a 0.01 rad arc:
  // the disk holds no vertex, and more than 4,096 lie within the index's pruning radius (it is
  // crowded: the search gives up). The disk meets the ~4,200 triangles from the corners to the arc,
  // fewer than the flood's cap at K = 600 (8 K + 64), so the flood sees it whole. An interior
  // segment far away makes the mesh constrained (the index is used). The triangle of the three
  // corners is in a K-bundle by its own disk, with the search deferred or not: the shortcut must
  // not take "crowded" for "holds a vertex".
  Pslg g;
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 3.0;
    g.points.push_back({std::cos(a), std::sin(a)});
  }
  for (std::size_t i = 0; i < 4200; ++i) {
    const double a = 0.5 + 0.01 * static_cast<double>(i) / 4200.0;
    g.points.push_back({(1.0 + 5e-5) * std::cos(a), (1.0 + 5e-5) * std::sin(a)});
  }
  const std::uint32_t far = static_cast<std::uint32_t>(g.points.size());
  g.points.insert(g.points.end(), {{9.0, 0.5}, {11.0, 0.5}, {10.0, 0.0}, {10.0, 1.0}});
  g.segments.push_back({far, far + 1});
  g.point_markers.assign(g.points.size(), 0);
  ConstrainOptions whole_hull;
  whole_hull.convex_hull = true;
  const Mesh m = constrained_delaunay(g, whole_hull);
  constexpr std::uint32_t kK = 600;
  std::vector<bool> answers[2];
  std::uint64_t crowded = 0;
  TriangleId corners = kNone;
  for (const bool defer : {true, false}) {
    brh::LocalBundleTest local(kK);
    local.set_defer_crowded(defer);
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (!m.in_domain(t)) continue;
      std::array<VertexId, 3> v = m.triangles[t].v;
      std::sort(v.begin(), v.end());
      if (v == std::array<VertexId, 3>{0, 1, 2}) corners = t;
      answers[defer ? 0 : 1].push_back(local.in_bundle(m, t));
    }
    if (defer) crowded = local.stats().index_crowded;
  }
  ASSERT_NE(corners, kNone);
  EXPECT_GT(crowded, 0u);
  EXPECT_EQ(answers[0], answers[1]);
  brh::LocalBundleTest local(kK);
  EXPECT_TRUE(local.in_bundle(m, corners));
  EXPECT_GT(local.stats().index_crowded, 0u);
  EXPECT_LE(local.stats().max_visits, local.cap());
  EXPECT_TRUE(in_k_bundle(m, kK, {corners})[0]);
}

}  // namespace
}  // namespace mwst
