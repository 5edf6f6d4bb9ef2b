// tests/algorithms/bundle/test_witness_hints.cpp — in_k_bundle's witnesses (KBundleCache::hints
// and witnesses, k_bundle.cpp): a query answered 1 by a circumdisk of the first stage reports that
// Delaunay triangle; given back as a hint in a later call (after the mesh has changed), the hint's
// disk is tried first and answers the query only if it is still a Delaunay triangle, still meets k
// triangles and meets the query. Bundle removal gives each triangle left at a small input angle
// its witness when it asks them all again before stopping. The answers must be the exact
// per-triangle bundle values whatever the hints: stale (the mesh refined since) or wrong (another
// query's witness).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "support/mesh_queries.hpp"

namespace mwst {
namespace {

using Triple = std::array<VertexId, 3>;
constexpr Triple kNoWitness{kNone, kNone, kNone};

Triple corners_of(const Mesh& m, TriangleId t) {
  Triple v = m.triangles[t].v;
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<TriangleId> skinny_of(const Mesh& m, double angle) {
  std::vector<TriangleId> skinny;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.in_domain(t) && test::min_angle_of(m, t) < angle) skinny.push_back(t);
  }
  return skinny;
}

// The fan of 800 vertices refined at 20°, its skinny triangles asked with witnesses; then 400
// vertices more inserted refining at 24° (they kill some of the witnesses' Delaunay triangles and change the counts
// of others), and the skinny triangles that survived asked again with their old witnesses as
// hints and with none; and every skinny triangle given a wrong hint (another query's witness).
TEST(WitnessHints, StaleAndWrongHintsGiveTheExactAnswers) {
  Mesh mesh = constrained_delaunay(generate_input(Distribution::kFan, 800, 1));
  RefineOptions ro;
  ro.min_angle_deg = 20.0;
  refine(mesh, ro);
  constexpr std::uint32_t k = 39;
  const std::vector<TriangleId> first = skinny_of(mesh, 20.0);
  ASSERT_GT(first.size(), 1000u);
  KBundleCache cache;
  KBundleStats st;
  const std::vector<std::uint8_t> first_in = in_k_bundle(mesh, k, first, &st, 1, &cache);
  ASSERT_EQ(cache.witnesses.size(), first.size());
  std::map<Triple, Triple> witness_of;
  std::size_t witnessed = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    // A witness only for a query answered 1 (by a circumdisk, not by the pencils).
    if (cache.witnesses[i] != kNoWitness) {
      EXPECT_TRUE(first_in[i]) << "triangle " << first[i];
      ++witnessed;
    }
    witness_of[corners_of(mesh, first[i])] = cache.witnesses[i];
  }
  EXPECT_EQ(witnessed, st.decided_by_circumdisks);
  ASSERT_GT(witnessed, 100u);

  ro.min_angle_deg = 24.0;
  ro.max_steiner = 400;  // (the fan at 24° is a refinement cliff: a few hundred vertices serve)
  refine(mesh, ro);
  std::vector<TriangleId> again;
  std::vector<Triple> hints;
  for (const TriangleId t : skinny_of(mesh, 20.0)) {
    const auto it = witness_of.find(corners_of(mesh, t));
    if (it == witness_of.end() || it->second == kNoWitness) continue;
    again.push_back(t);
    hints.push_back(it->second);
  }
  ASSERT_GT(again.size(), 100u);
  const BundleResult per = bundle_number(mesh, {.per_triangle = true});
  std::size_t in_bundle = 0;
  for (const TriangleId t : again) in_bundle += per.per_triangle[t] >= k;
  // Both answers occur: some triangles witnessed before are in no k-bundle now.
  ASSERT_GT(in_bundle, 0u);

  std::size_t decided_by_stale = 0;
  for (const bool with_hints : {true, false}) {
    KBundleCache again_cache;
    if (with_hints) again_cache.hints = hints;
    KBundleStats again_st;
    const std::vector<std::uint8_t> in = in_k_bundle(mesh, k, again, &again_st, 1, &again_cache);
    for (std::size_t i = 0; i < again.size(); ++i) {
      EXPECT_EQ(in[i] != 0, per.per_triangle[again[i]] >= k) << "triangle " << again[i];
    }
    if (with_hints) decided_by_stale = again_st.decided_by_hints;
    if (!with_hints) {
      EXPECT_EQ(again_st.decided_by_hints, 0u);
    }
  }
  // Wrong hints: every skinny triangle, in a k-bundle or not, given the witness of another
  // (large disks that meet k triangles, most of them not meeting the query).
  const std::vector<TriangleId> all = skinny_of(mesh, 20.0);
  std::vector<Triple> wrong(all.size());
  std::size_t not_in_bundle = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    wrong[i] = hints[(i * 7919) % hints.size()];
    not_in_bundle += per.per_triangle[all[i]] < k;
  }
  ASSERT_GT(not_in_bundle, 100u);
  KBundleCache wrong_cache;
  wrong_cache.hints = wrong;
  const std::vector<std::uint8_t> in = in_k_bundle(mesh, k, all, nullptr, 1, &wrong_cache);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(in[i] != 0, per.per_triangle[all[i]] >= k) << "triangle " << all[i];
  }
  // The old witnesses decide many of the queries again, but not all (the refinement at 24°
  // killed or changed some of them; those queries walk S(t) as without hints).
  EXPECT_GT(decided_by_stale, 0u);
  EXPECT_LT(decided_by_stale, again.size());
}

}  // namespace
}  // namespace mwst
