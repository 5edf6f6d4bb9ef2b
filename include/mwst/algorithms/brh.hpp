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
  std::size_t known_clean = 0;        // skinny triangles those tests did not ask again (brh.md)
  std::size_t steiner_inserted = 0;
  std::size_t segment_splits = 0;
  std::size_t skinny_left = 0;        // skinny triangles left: each in no K-bundle
  std::size_t left_small_angle = 0;   // bad triangles the engine could not improve (MPW rule)
  StopReason stop;  // kBoundReached, kTimeBudget, kSteinerBudget, kRoundLimit, kBeyondFeatureSize, kSmallInputAngles
  double seconds = 0.0;
};

// Refines the carved CDT like Delaunay refinement, but splits a skinny triangle (an angle below A)
// only if it belongs to a K-bundle: some vertex-empty open disk meeting its interior meets the
// interiors of at least K triangles. Passes of the DR engine (refine.hpp) with BRH's criterion;
// between passes the exact test (in_k_bundle, bundle.hpp) marks the skinny triangles in K-bundles,
// and BRH stops when it marks none. On a normal stop ("bound reached") every triangle left with an
// angle below A is in no K-bundle; when K ≥ ⌈4π/A⌉ + 3 the mesh is K-bundle-free. With
// refine.max_area > 0 every triangle larger than it is split as well, so on a normal stop none is
// left. BRH shares DR's termination guard (measured once on its input, feature_guard_length) and
// stops with StopKind::kBeyondFeatureSize where DR would. docs/algorithms/brh.md describes the passes,
// the local and exact tests, what is reused between tests, and the cost.
MWST_API BrhStats bundle_removal(Mesh& mesh, const BrhOptions& options);

}  // namespace mwst
