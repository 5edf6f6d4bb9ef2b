// mwst/algorithms/brh.hpp — the bundle removal heuristic (BRH) of Boyacı, Erten and Üngör.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/refine.hpp"

namespace mwst {

struct BrhOptions {
  double min_angle_deg = 20.0;  // A: a triangle with an angle below A is skinny
  std::size_t bundle_k = 0;     // K (≥ 3): a skinny triangle is split only inside a K-bundle
  RefineOptions refine;         // Steiner rule, budgets, ... (its angle / is_bad are set by BRH)
  std::size_t max_rounds = 1000;
  unsigned threads = 0;         // threads of the exact bundle tests (0: all hardware threads)
};

struct BrhStats {
  std::size_t rounds = 0;             // refinement passes
  std::size_t exact_evaluations = 0;  // exact tests (in_k_bundle) between passes
  std::size_t known_clean = 0;        // skinny triangles those tests did not ask again (see brh.cpp)
  std::size_t steiner_inserted = 0;
  std::size_t segment_splits = 0;
  std::size_t skinny_left = 0;        // skinny triangles left: each in no K-bundle
  std::size_t left_small_angle = 0;   // bad triangles the engine could not improve (MPW rule)
  std::string stop_reason;
  double seconds = 0.0;
};

// Refines the carved CDT like Delaunay refinement, but splits a skinny triangle only if it belongs
// to a K-bundle: some vertex-empty open disk meeting its interior meets the interiors of at least K
// triangles. Passes of the DR engine: inside a pass a skinny triangle is split when a local test
// finds it in a K-bundle (the circumdisk of it or of a neighbour is vertex-empty and meets ≥ K
// triangles) or when the last exact test marked it; between passes the exact test (in_k_bundle,
// bundle.hpp: circumdisks, then pencil sweeps, only around the skinny triangles) marks the skinny
// triangles in K-bundles; BRH stops when it marks none. Guarantees on a normal stop ("bound
// reached"): every triangle left with an angle below A is in no K-bundle; when K ≥ ⌈4π/A⌉ + 3 the
// mesh is K-bundle-free. With refine.max_area > 0 every triangle larger than it is split as well
// (a pass with the area bound alone comes first, and every pass tests the area of the triangles it
// makes), so on a normal stop none is left. Above the angles where DR provably terminates BRH can
// crowd vertices without end as DR can: it shares DR's termination guard (measured once on its
// input, refine.hpp feature_guard_length) and stops with kStopBeyondFeatureSize. Passes after the first are seeded (RefineOptions::seed_triangles) with
// the triangles the exact test marked, and the skinny list is updated, not recounted, between
// them. From the second exact test on, a skinny triangle the last test found in no K-bundle is not
// asked again while no triangle made since lies near it (its "reach", KBundleCache::reach: a
// disk putting it in a K-bundle would have to meet such a triangle), and pencil sweeps whose
// inputs did not change are reused (KBundleCache). Cost on a 1M-triangle input
// (bench/bench_brh.cpp): about 2.5–3× DR's CPU time at the default K (one exact test over all
// ~150k skinny triangles of the CDT, which builds DT(V)), 2.2–2.7× at K = 6 and 2.5–2.8× at
// K = 8, where seven exact tests are needed, each local (its cost is that of the mesh region
// around the skinny triangles, not of the mesh); DR's own time swings ±15% between runs. On point
// sets (hull edges split into nearly collinear pieces) the exact tests near the hull rebuild
// DT(V): 200k uniform points take about 7× DR at K = 8 and 9–10× at K = 12.
MWST_API BrhStats bundle_removal(Mesh& mesh, const BrhOptions& options);

}  // namespace mwst
