// tests/algorithms/bundle/test_one_sided.cpp — in_k_bundle's one-sided pencils (k_bundle.cpp,
// Worker::sweep_one_sided): over DT(V) a pencil one of whose ends meets k triangles or more is
// swept from the other end's list and a lens next to the chord, not from the large end's list.
// On the Delaunay-refined narrow fan (`mwst generate fan`) the spike bases' pencils have one end
// a sliver's disk meeting ~10 triangles and the other reaching across thousands: the answers
// must stay those of the exact per-triangle bundle values, and the work must stay near k per
// query, not the large disks' sizes. And the first stage's walk starts at a corner of few Delaunay
// triangles (a wheel's rim, not its centre).
#include <gtest/gtest.h>

#include <cstddef>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "support/mesh_queries.hpp"

namespace mwst {
namespace {

struct FanCase {
  Mesh mesh;
  std::vector<TriangleId> skinny;  // below 20°: what bundle removal asks
};

FanCase refined_fan(std::size_t vertices) {
  FanCase c;
  c.mesh = constrained_delaunay(generate_input(Distribution::kFan, vertices, 1));
  RefineOptions ro;
  ro.min_angle_deg = 20.0;
  refine(c.mesh, ro);
  for (TriangleId t = 0; t < c.mesh.triangle_slots(); ++t) {
    if (c.mesh.in_domain(t) && test::min_angle_of(c.mesh, t) < 20.0) c.skinny.push_back(t);
  }
  return c;
}

// The Delaunay-refined fan of 800 vertices (34k triangles, 15k skinny). Each candidate of a
// one-sided pencil is a triangle of the listed end's list (a disk meeting fewer than k) or of a lens
// flood that stops at k, so the sweeps classify fewer than k candidates per pencil on average
// (k = 39: 20; with both ends listed, as before one-sided pencils: 53, and on BRH's fan of 40,000
// vertices about 5,000).
TEST(OneSidedPencils, FanAnswersAreExactAndCostAboutKPerPencil) {
  const FanCase fan = refined_fan(800);
  ASSERT_GT(fan.skinny.size(), 1000u);
  const BundleResult per = bundle_number(fan.mesh, {.per_triangle = true});
  for (const std::uint32_t k : {20u, 39u}) {
    SCOPED_TRACE(k);
    KBundleStats st;
    const std::vector<std::uint8_t> in = in_k_bundle(fan.mesh, k, fan.skinny, &st, 1);
    for (std::size_t i = 0; i < fan.skinny.size(); ++i) {
      EXPECT_EQ(in[i] != 0, per.per_triangle[fan.skinny[i]] >= k) << "triangle " << fan.skinny[i];
    }
    EXPECT_GT(st.pencils_one_sided, 100u);
    EXPECT_LE(st.lens_visits, 4 * std::size_t{k} * st.pencils_one_sided);
    EXPECT_LE(st.candidate_pairs, std::size_t{k} * st.pencils_swept);
  }
}

// Stage 1 walks S(t) from the Delaunay triangles around one corner of the query, one at a time,
// going once around that corner's whole fan when no disk decides. At 160,000 vertices of
// `mwst generate fan` BRH's last exact test, over the 80,000 triangles left at small input angles,
// walked a fan of tens of thousands per query (~40 s): the walk now starts at a corner of at most
// 64 Delaunay triangles (or of fewest). A wheel (a centre and 2,000 points on a circle) has the centre as a corner
// of every triangle and 2,000 triangles around it; with k above what any disk meets, no query is
// decided in stage 1, so starting at the centre would walk 2,000 steps per query where a rim
// corner has 4. The answers are the exact per-triangle bundle values whichever corner it starts at.
TEST(OneSidedPencils, WalksStartAtTheCornerOfFewestDelaunayTriangles) {
  std::vector<Point> pts{{0.0, 0.0}};
  constexpr std::size_t kRim = 2000;
  for (std::size_t i = 0; i < kRim; ++i) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / kRim;
    pts.push_back({std::cos(a), std::sin(a)});
  }
  const Mesh m = delaunay(pts);
  std::vector<TriangleId> queries;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t)) queries.push_back(t);
  }
  ASSERT_EQ(queries.size(), kRim);
  const BundleResult per = bundle_number(m, {.per_triangle = true});
  for (const std::uint32_t k : {5u, 100000u}) {
    SCOPED_TRACE(k);
    KBundleStats st;
    const std::vector<std::uint8_t> in = in_k_bundle(m, k, queries, &st, 1);
    for (std::size_t i = 0; i < queries.size(); ++i) {
      EXPECT_EQ(in[i] != 0, per.per_triangle[queries[i]] >= k) << "triangle " << queries[i];
    }
    EXPECT_LE(st.seed_fan_steps, 8 * queries.size());
  }
}

}  // namespace
}  // namespace mwst
