// Tests of BRH's local bundle test (LocalBundleTest, brh_criteria.hpp): it asks
// only "is this triangle in a K-bundle?", so on a Delaunay mesh its flood stops
// on counting K triangles (O(K) visits, however many triangles the disk meets),
// and on a constrained mesh it gives up past its cap. Whatever it answers yes
// must be a K-bundle by the exact test (in_k_bundle).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/refine/brh_criteria.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "support/regression_files.hpp"

namespace mwst {
namespace {

std::vector<TriangleId> domain_triangles(const Mesh &m) {
  std::vector<TriangleId> out;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t))
      out.push_back(t);
  }
  return out;
}

// Points on an ellipse: every Delaunay triangle is a sliver whose circumdisk
// meets a large share of the mesh (hundreds of triangles), the input class
// where BRH's floods used to run to their cap.
std::vector<Point> ellipse_points(std::size_t n) {
  std::vector<Point> p;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) /
                     static_cast<double>(n);
    p.push_back({std::cos(a), 0.5 * std::sin(a)});
  }
  return p;
}

// Every local yes is an exact yes, and returns the number of local yeses.
std::size_t expect_local_yes_is_exact(const Mesh &m,
                                      brh::LocalBundleTest &local,
                                      std::uint32_t k) {
  const std::vector<TriangleId> all = domain_triangles(m);
  const std::vector<std::uint8_t> exact = in_k_bundle(m, k, all);
  std::size_t yes = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!local.in_bundle(m, all[i]))
      continue;
    ++yes;
    EXPECT_TRUE(exact[i]) << "triangle " << all[i]
                          << ": local witness but in no " << k << "-bundle";
  }
  return yes;
}

// A test kept across insertions answers every domain triangle as a fresh one;
// returns the number of yeses.
std::size_t expect_kept_answers_as_fresh(const Mesh &m,
                                         brh::LocalBundleTest &kept,
                                         brh::LocalBundleTest &fresh) {
  std::size_t yes = 0;
  for (const TriangleId t : domain_triangles(m)) {
    const bool answer = fresh.in_bundle(m, t);
    yes += answer ? 1 : 0;
    EXPECT_EQ(kept.in_bundle(m, t), answer) << "triangle " << t;
  }
  return yes;
}

// The CDT of a generated polygon, every domain triangle asked at K (every yes
// checked exact); returns the number of yeses.
std::size_t ask_every_triangle(Distribution d, std::size_t n,
                               brh::LocalBundleTest &local, std::uint32_t k) {
  const Mesh m = constrained_delaunay(generate_input(d, n, 1));
  return expect_local_yes_is_exact(m, local, k);
}

TEST(BrhLocalTest, DelaunayFloodStopsOnCountingK) {
  // 2,000 points on an ellipse: the Delaunay triangulation of a point set, so
  // every circumdisk is vertex-empty, and the circumdisks of the slivers meet
  // far more than K = 12 triangles. Each flood must stop after exactly K visits
  // when it finds K (every finite triangle is in the domain here) and never
  // visit more than K.
  const Mesh m = delaunay(ellipse_points(2000));
  constexpr std::uint32_t kK = 12;
  brh::LocalBundleTest local(kK);
  const std::size_t yes = expect_local_yes_is_exact(m, local, kK);
  const auto &s = local.stats();
  EXPECT_GT(yes, 100u);
  EXPECT_GT(s.stopped_at_k, 100u);
  EXPECT_EQ(s.capped, 0u);
  EXPECT_LE(s.max_visits, kK);
  EXPECT_LE(s.visits, s.floods * kK);
}

TEST(BrhLocalTest, VisitsPerQueryDoNotGrowWithTheMesh) {
  // The same class at 1,000 and 8,000 points, default K at 20°: the visits per
  // flood are bounded by K on both (O(K) per query), though the largest
  // circumdisks meet ~8× more triangles.
  const std::uint32_t k = static_cast<std::uint32_t>(default_bundle_k(20.0));
  for (const std::size_t n : {1000u, 8000u}) {
    const Mesh m = delaunay(ellipse_points(n));
    brh::LocalBundleTest local(k);
    for (const TriangleId t : domain_triangles(m))
      local.in_bundle(m, t);
    const auto &s = local.stats();
    EXPECT_GT(s.stopped_at_k, 0u) << n;
    EXPECT_LE(s.max_visits, k) << n;
  }
}

TEST(BrhLocalTest, ConstrainedMeshFloodStopsAtKWhereTheIndexShowsTheDiskEmpty) {
  // A polygon (Plate: a circular hole, so vertices behind segments can lie in a
  // circumdisk): a disk the vertex index shows empty is flooded only up to K
  // in-domain triangles, one it finds a vertex in is not flooded; no flood pops
  // more than cap + 1 triangles, and every yes is exact.
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
  const Mesh m = constrained_delaunay(g);
  constexpr std::uint32_t kK = 6;
  brh::LocalBundleTest local(kK);
  expect_local_yes_is_exact(m, local, kK);
  const auto &s = local.stats();
  EXPECT_GT(s.floods, 0u);
  EXPECT_GT(s.index_empty, 0u);
  EXPECT_GT(s.stopped_at_k, 0u);
  EXPECT_LE(s.stopped_at_k, s.index_empty);
  EXPECT_LE(s.max_visits, local.cap() + 1);
}

TEST(BrhLocalTest, ConstrainedMeshAsksTheIndexOnlyWhenTheFloodCountsK) {
  // A polygon with circular holes: a flood that ends below K has seen every
  // triangle meeting its disk, hence every vertex in it, so the vertex index is
  // asked only by the floods that counted K (it used to be asked before every
  // flood). On a mesh that does not change no disk is asked twice.
  const std::uint32_t k = static_cast<std::uint32_t>(default_bundle_k(20.0));
  brh::LocalBundleTest local(k);
  EXPECT_GT(ask_every_triangle(Distribution::kHoles, 2000, local, k), 0u);
  const auto &s = local.stats();
  EXPECT_GT(s.reached_k, 0u);
  EXPECT_EQ(s.index_queries, s.reached_k);
  EXPECT_EQ(s.index_newer, 0u);
  EXPECT_LT(4 * s.index_queries, 3 * (s.floods - s.recent_inside));
}

TEST(BrhLocalTest, HoleDiskIsAskedFirstBesideAHole) {
  // A triangle beside a circular hole (a segment edge with the hole's inside
  // across it): the hole triangle's disk, the hole's circle, meets the ring of
  // triangles around the hole and is the likely witness, so it is flooded
  // first; when it is one, the query floods nothing else (the triangle's own
  // disk came first and meets fewer than K triangles).
  const Mesh m = constrained_delaunay(generate_input(Distribution::kHoles, 2000, 1));
  const std::uint32_t k = static_cast<std::uint32_t>(default_bundle_k(20.0));
  std::size_t beside = 0, yes = 0, one_flood = 0;
  for (const TriangleId t : domain_triangles(m)) {
    bool hole = false;
    for (unsigned e = 0; e < 3; ++e) {
      const TriangleId n = triangle_of(m.sym(make_handle(t, e)));
      hole = hole || (m.is_segment(make_handle(t, e)) && !m.is_ghost(n) && !m.in_domain(n));
    }
    if (!hole)
      continue;
    ++beside;
    brh::LocalBundleTest local(k);
    if (!local.in_bundle(m, t))
      continue;
    ++yes;
    one_flood += local.stats().floods == 1 ? 1 : 0;
  }
  EXPECT_GT(beside, 1000u);
  EXPECT_GT(yes, beside / 2);
  EXPECT_EQ(one_flood, yes);
}

TEST(BrhLocalTest, FanQueriesStopAtKInsteadOfTheCap) {
  // A fan of 2,000 narrow wedges (0.01°): the slivers' circumdisks reach
  // across hundreds of wedges and the gaps between them, so a flood that must
  // see the whole disk passes its cap (8K + 64 visits) and answers "unknown".
  // With the vertex index the empty ones stop on counting K: most floods stop
  // at K, few are capped, and every yes is an exact yes.
  const std::uint32_t k = static_cast<std::uint32_t>(default_bundle_k(20.0));
  brh::LocalBundleTest local(k);
  EXPECT_GT(ask_every_triangle(Distribution::kFan, 2000, local, k), 0u);
  const auto &s = local.stats();
  EXPECT_GT(s.stopped_at_k, 10 * s.capped);
  EXPECT_LE(s.max_visits, local.cap() + 1);
}

TEST(BrhLocalTest, VertexIndexAgreesWithAllVertices) {
  // The index's answer for the circumdisks of random vertex triples of a fan
  // and of Plate, against the exact incircle sign of every vertex: "empty"
  // means no vertex strictly inside, "holds a vertex" that one is. A third of
  // the vertices is indexed first, then the rest (the blocks merge).
  for (const bool fan : {true, false}) {
    const Mesh m = constrained_delaunay(
        fan ? generate_input(Distribution::kFan, 600, 1)
            : io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly"));
    std::vector<Point> points(m.points.begin(),
                              m.points.begin() + static_cast<std::ptrdiff_t>(
                                                     m.points.size() / 3));
    brh::VertexIndex index;
    std::mt19937_64 rng(7);
    for (int batch = 0; batch < 2; ++batch) {
      if (batch == 1)
        points = m.points;
      index.sync(points);
      std::size_t empty = 0, holds = 0, newer_empty = 0, newer_holds = 0;
      for (int q = 0; q < 3000; ++q) {
        // Small disks (three nearby ids: the generators emit vertices in
        // order along the boundary) and arbitrary ones.
        const VertexId base = static_cast<VertexId>(rng() % points.size());
        std::array<VertexId, 3> cv{};
        for (VertexId &v : cv)
          v = q % 2 == 0
                  ? static_cast<VertexId>((base + rng() % 5) % points.size())
                  : static_cast<VertexId>(rng() % points.size());
        if (cv[0] == cv[1] || cv[1] == cv[2] || cv[0] == cv[2])
          continue;
        const int o = orient2d(points[cv[0]], points[cv[1]], points[cv[2]]);
        if (o == 0)
          continue;
        if (o < 0)
          std::swap(cv[1], cv[2]);
        auto inside = [&](VertexId x) {
          return incircle(points[cv[0]], points[cv[1]], points[cv[2]],
                          points[x]) > 0;
        };
        bool any = false;
        for (VertexId x = 0; x < points.size() && !any; ++x)
          any = x != cv[0] && x != cv[1] && x != cv[2] && inside(x);
        const auto disk = index.strictly_inside(points, cv, inside);
        if (disk == brh::VertexIndex::Disk::kUnknown)
          continue;
        EXPECT_EQ(disk == brh::VertexIndex::Disk::kHoldsVertex, any)
            << (fan ? "fan" : "Plate") << " query " << q;
        ++(any ? holds : empty);
        // Asked about the vertices from the second third on only: the
        // answer is that of those vertices alone.
        const VertexId from = static_cast<VertexId>(points.size() / 3 + 1);
        bool any_newer = false;
        for (VertexId x = from; x < points.size() && !any_newer; ++x)
          any_newer = x != cv[0] && x != cv[1] && x != cv[2] && inside(x);
        const auto newer = index.strictly_inside(points, cv, inside, from);
        if (newer != brh::VertexIndex::Disk::kUnknown) {
          EXPECT_EQ(newer == brh::VertexIndex::Disk::kHoldsVertex, any_newer)
              << (fan ? "fan" : "Plate") << " query " << q << " from " << from;
          newer_holds += any_newer && !any ? 1 : 0;  // (impossible: a subset)
          newer_empty += !any_newer && any ? 1 : 0;
        }
      }
      EXPECT_GT(empty, 0u) << (fan ? "fan" : "Plate") << " batch " << batch;
      EXPECT_GT(holds, 0u) << (fan ? "fan" : "Plate") << " batch " << batch;
      EXPECT_EQ(newer_holds, 0u);
      if (batch == 1) {  // disks holding only older vertices, shown empty of the newer ones
        EXPECT_GT(newer_empty, 0u) << (fan ? "fan" : "Plate");
      }
    }
  }
}

TEST(BrhLocalTest, VertexIndexGivesUpOnManyVerticesNearTheCircle) {
  // 20,000 points just outside the unit circle (radius 1 + 1e-7) but for the
  // three corners of each query, on it: their circumdisk holds no point, yet
  // every point is within the search's reach, so the search would visit them
  // all. It stops after its visit limit and answers "unknown" (the caller then
  // floods the disk under its cap), or answers as the exact test of every
  // point does.
  const std::vector<VertexId> corners{0, 3000, 6000, 5000, 8000, 11000, 12345, 15345, 18345};
  std::vector<Point> points;
  const std::size_t n = 20000;
  for (std::size_t i = 0; i < n; ++i) {
    const double angle = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    const bool corner = std::find(corners.begin(), corners.end(), static_cast<VertexId>(i)) != corners.end();
    const double radius = corner ? 1.0 : 1.0 + 1e-7;
    points.push_back({radius * std::cos(angle), radius * std::sin(angle)});
  }
  brh::VertexIndex index;
  index.sync(points);
  std::size_t unknown = 0;
  for (const VertexId first : {VertexId{0}, VertexId{5000}, VertexId{12345}}) {
    const std::array<VertexId, 3> cv{first, first + 3000, first + 6000};
    ASSERT_GT(orient2d(points[cv[0]], points[cv[1]], points[cv[2]]), 0);
    auto inside = [&](VertexId x) { return incircle(points[cv[0]], points[cv[1]], points[cv[2]], points[x]) > 0; };
    bool any = false;
    for (VertexId x = 0; x < points.size() && !any; ++x) {
      any = x != cv[0] && x != cv[1] && x != cv[2] && inside(x);
    }
    const auto disk = index.strictly_inside(points, cv, inside);
    EXPECT_LE(index.last_visits(), 4096u + 64u);
    if (disk == brh::VertexIndex::Disk::kUnknown) {
      ++unknown;
      continue;
    }
    EXPECT_EQ(disk == brh::VertexIndex::Disk::kHoldsVertex, any) << "query at " << first;
  }
  EXPECT_GT(unknown, 0u);
}

TEST(BrhLocalTest, VertexIndexAsksTheExactSignOnlyNearTheCircle) {
  // 3,000 points 1e-7 outside the unit circle and the three corners of the
  // query on it: all lie within the search's pruning reach (1e-4 r), but the
  // disk's own error bound (~1e-13 here) places them outside without an
  // incircle sign. Points 1e-14 outside or 1e-12 inside are asked, and the
  // answer is the exact one.
  const std::size_t n = 3000;
  auto ring = [&](double near_radius, std::size_t near_every) {
    std::vector<Point> points;
    for (std::size_t i = 0; i < n; ++i) {
      const double angle = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
      double radius = i % 1000 == 0 ? 1.0 : 1.0 + 1e-7;
      if (near_every != 0 && i % near_every == 7) radius = near_radius;
      points.push_back({radius * std::cos(angle), radius * std::sin(angle)});
    }
    return points;
  };
  const std::array<VertexId, 3> cv{0, 1000, 2000};
  struct Case {
    double near_radius;
    std::size_t near_every;
    brh::VertexIndex::Disk expected;
  };
  for (const Case c : {Case{1.0, 0, brh::VertexIndex::Disk::kEmpty},
                       Case{1.0 + 1e-14, 100, brh::VertexIndex::Disk::kEmpty},
                       Case{1.0 - 1e-12, 1000, brh::VertexIndex::Disk::kHoldsVertex}}) {
    const std::vector<Point> points = ring(c.near_radius, c.near_every);
    ASSERT_GT(orient2d(points[cv[0]], points[cv[1]], points[cv[2]]), 0);
    std::size_t asked = 0;
    auto inside = [&](VertexId x) {
      ++asked;
      return incircle(points[cv[0]], points[cv[1]], points[cv[2]], points[x]) > 0;
    };
    std::size_t near = 0;
    bool any = false;
    for (VertexId x = 0; x < points.size(); ++x) {
      if (x == cv[0] || x == cv[1] || x == cv[2]) continue;
      near += c.near_every != 0 && x % c.near_every == 7 ? 1 : 0;
      any = any || incircle(points[cv[0]], points[cv[1]], points[cv[2]], points[x]) > 0;
    }
    ASSERT_EQ(any, c.expected == brh::VertexIndex::Disk::kHoldsVertex);
    brh::VertexIndex index;
    index.sync(points);
    EXPECT_EQ(index.strictly_inside(points, cv, inside), c.expected) << "near radius " << c.near_radius;
    // Every point lies within the pruning's reach: the search visits them all,
    // but asks the exact sign of the near ones only.
    if (c.expected == brh::VertexIndex::Disk::kEmpty) {
      EXPECT_GE(index.last_visits(), n - 3);
      EXPECT_EQ(asked, near) << "near radius " << c.near_radius;
    } else {
      EXPECT_GE(asked, 1u);
      EXPECT_LE(asked, near);
      EXPECT_EQ(index.last_found() % c.near_every, 7u);  // one of the points inside
    }
  }
}

TEST(BrhLocalTest, RememberedDisksAnswerAsAFreshTestAfterInsertions) {
  // Plate (a circular hole: near-cocircular vertices, whose exact incircle
  // signs the test remembers) and a fan of narrow wedges (disks behind its
  // segments hold vertices) at K = 6: one test asks every triangle, the mesh is
  // refined a little (vertices only added), then the same test, cleared, and a
  // fresh one must answer alike. On the fan, disks the first round found
  // holding a vertex are not flooded again (a vertex inside stays inside).
  for (const bool fan : {false, true}) {
    const Pslg g =
        fan ? generate_input(Distribution::kFan, 101, 1)
            : io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
    Mesh m = constrained_delaunay(g);
    constexpr std::uint32_t kK = 6;
    brh::LocalBundleTest kept(kK);
    for (const TriangleId t : domain_triangles(m))
      kept.in_bundle(m, t);
    RefineOptions ro;
    ro.max_steiner = 60;
    refine(m, ro);
    kept.clear();
    brh::LocalBundleTest fresh(kK);
    EXPECT_GT(expect_kept_answers_as_fresh(m, kept, fresh), 0u);
    if (fan) {
      EXPECT_GT(kept.stats().known_not_empty, 0u);
      EXPECT_GT(fresh.stats().recent_inside, 0u);  // disks found holding a vertex another one held
    }
  }
}

TEST(BrhLocalTest, DisksShownEmptyAreAskedAboutNewVerticesOnly) {
  // A polygon with circular holes at the default K: the disks of the triangles
  // inside a hole meet the ring of triangles around it and are witnesses for
  // the skinny triangles beside the hole; the hole's vertices lie on their
  // circles, where only the exact incircle sign decides. After insertions a
  // disk the index showed empty is asked about the new vertices alone, and the
  // test answers as a fresh one, with fewer index visits.
  Mesh m = constrained_delaunay(generate_input(Distribution::kHoles, 2000, 1));
  const std::uint32_t k = static_cast<std::uint32_t>(default_bundle_k(20.0));
  brh::LocalBundleTest kept(k);
  for (const TriangleId t : domain_triangles(m))
    kept.in_bundle(m, t);
  RefineOptions ro;
  ro.min_angle_deg = 20.0;
  ro.max_steiner = 200;
  refine(m, ro);
  kept.clear();
  const std::uint64_t visits_before = kept.stats().index_visits;
  brh::LocalBundleTest fresh(k);
  EXPECT_GT(expect_kept_answers_as_fresh(m, kept, fresh), 0u);
  EXPECT_GT(kept.stats().index_newer, 0u);
  EXPECT_EQ(fresh.stats().index_newer, 0u);
  // (A merge of the index's blocks mixes old and new vertices: the search skips
  // the subtrees holding only old ones.)
  EXPECT_LT(2 * (kept.stats().index_visits - visits_before), fresh.stats().index_visits);
}

TEST(BrhLocalTest, UniformPointsSound) {
  // Random points at a small K, where many disks reach K and many do not: every
  // yes is exact.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> p;
  for (int i = 0; i < 3000; ++i)
    p.push_back({u(rng), u(rng)});
  const Mesh m = delaunay(p);
  brh::LocalBundleTest local(5);
  EXPECT_GT(expect_local_yes_is_exact(m, local, 5), 0u);
  EXPECT_LE(local.stats().max_visits, 5u);
}

} // namespace
} // namespace mwst
