// mwst/algorithms/optimize.hpp — our weight optimiser, past the paper: a local search for the minimum weight
// Steiner triangulation that moves, removes and inserts Steiner points and flips edges until no
// move lowers the weight.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "mwst/mesh/mesh.hpp"

namespace mwst {

struct OptimizeOptions {
  std::size_t max_rounds = 100;    // a round visits every Steiner vertex once, then flips
  // Vertices below this id are never moved or removed, like the input points: the pipeline fixes
  // the crossing points its constrained Delaunay triangulation added (vertices of the domain,
  // which every method keeps; one whose crossing segments merged looks like any Steiner point on
  // a straight chain of subsegments).
  std::size_t fixed_vertices = 0;
  // Most Steiner vertices (kSteiner or kSteinerOnSegment, ids from fixed_vertices on) the mesh may
  // hold: no move that inserts a vertex is tried beyond it (removals and the rest still are). A
  // mesh given with more is never made to hold fewer by force.
  std::size_t max_steiner = std::numeric_limits<std::size_t>::max();
  // Area bound (--max-area; ≤ 0: none): no move makes a domain triangle larger than this
  // (triangle_area) — flips, relocations, slides, removals and re-triangulated regions are
  // refused when one of their new triangles would be; insertions only split triangles. A mesh
  // given with larger triangles keeps them until a move replaces them by smaller ones.
  double max_area = -1.0;
  // Separation (no degenerate geometry): no move of the search places a Steiner vertex — a
  // relocation (Weiszfeld step), a slide along a segment, an insertion, a kick, a perturbation —
  // nearer than this distance to any other vertex, or to any segment or domain boundary edge it
  // is not on (point_is_separated). So every edge the search makes to a vertex it placed is at
  // least this long, and no such vertex lies within rounding of a segment. (Interior edges may
  // pass nearer: light triangulations have flat triangles.) Flips, removals and
  // re-triangulations only join vertices already there; vertices of the mesh given keep their
  // places. < 0 (the default): default_min_separation(mesh given), kSeparationFraction × its
  // shortest domain edge; method opt passes default_min_separation of the input's constrained
  // Delaunay triangulation (pipeline.cpp), the input's smallest feature, for every start alike.
  // 0: no separation (the strict orientation tests and in_kernel's rounding margin only).
  static constexpr double kSeparationFraction = 0.25;
  double min_separation = -1.0;
  bool relocate = true;            // move Steiner vertices to the geometric median of neighbours
  bool remove = true;              // remove Steiner vertices whose star re-triangulates lighter
  bool insert = true;              // try Steiner points at the Fermat points of heavy triangles
  double min_relative_gain = 1e-9; // stop when a round gains less than this fraction of weight
  std::size_t kick_passes = 2;         // rounds of kicks (trial insertions/removals), 0 = none
  std::size_t max_kick_trials = 200000;  // total trial budget (deterministic, not a time limit)
  double kick_min_relative_gain = 1e-12; // a kick is kept if it lowers the weight by this fraction
  // Cluster polish: a kick insertion that does not pay on its own is re-polished together with
  // its free Steiner neighbours (flips and geometric medians) this many sweeps; 0 = off.
  std::size_t kick_neighbour_sweeps = 0;
  bool kick_pairs = false;  // pair kicks: two Steiner points at the thirds of each interior edge
  // Iterated local search after the kicks: trials that scatter 1–3 Steiner points near a random
  // triangle (seeded, deterministic) and run the local search, each kept only if lighter; 0 = off.
  std::size_t perturbation_trials = 0;
  std::uint64_t perturbation_seed = 0x5eed;
  bool perturbation_focus = true;  // each trial's search visits only the perturbed neighbourhood
  std::size_t max_exact_polygon = 400;   // whole-domain MWT by dynamic programming up to this size
  std::size_t max_exact_convex_polygon = 2000;  // ... and up to this size if the domain is convex
  // Exact polish (off by default): after the search, replace the mesh by the exact MWT of its own
  // vertices (exact_mwt, mwt.hpp) when that is solved and lighter, search again, and repeat while
  // the weight drops by more than min_relative_gain. Budgets are sizes, not seconds (deterministic):
  bool exact_polish = false;
  bool exact_polish_start = true;   // ... and a second search from the MWT of the start (lighter kept)
  std::size_t exact_polish_rounds = 8;              // exact MWTs tried after the search, at most
  std::size_t exact_polish_max_vertices = 4000;     // skip meshes with more vertices
  std::size_t exact_polish_visibility_vertices = 400;  // visibility-route fallback up to this many
  // MwtOptions limits (give up beyond): diamond candidates per vertex (well-spaced meshes have
  // about 11; far more means a slow skeleton that rarely solves), crossing pairs of candidates.
  std::size_t exact_polish_candidates_per_vertex = 16;
  std::size_t exact_polish_max_crossing_pairs = 2000000;
  // Wall-clock budget in seconds (≤ 0: none, the default). The search looks at the clock before
  // each round of the local search and every 1024 vertices or triangles within one (and every
  // 1024 heap entries of its whole-mesh flips), before each kick, perturbation trial and exact
  // polish round; once the budget has passed it stops there
  // (OptimizeStats::out_of_time). Every move kept before that lowered the weight, so the mesh is
  // valid and no heavier than given, but where it stopped depends on the machine's speed: only
  // the size budgets above give the same result on every run.
  double time_budget_seconds = -1.0;
};

struct OptimizeStats {
  std::size_t rounds = 0;
  std::size_t relocations = 0;  // accepted moves
  std::size_t removals = 0;
  std::size_t insertions = 0;
  std::size_t region_retriangulations = 0;  // small regions re-triangulated by their MWT
  std::size_t region_tries_skipped = 0;     // regions not retried: unchanged since they failed
  std::size_t flips = 0;
  std::size_t kick_insertions = 0;  // trial insertions kept after their local re-optimisation
  std::size_t kick_removals = 0;    // trial removals kept
  std::size_t kick_pairs = 0;       // pair kicks kept (each also counts 2 kick_insertions)
  std::size_t perturbations = 0;    // perturbation trials kept (iterated local search)
  std::size_t whole_polygon_mwt = 0;  // 1 if the domain was replaced by its exact MWT
  std::size_t exact_polishes = 0;     // exact MWTs of the vertex set kept by the exact polish
  std::size_t exact_polish_tries = 0; // exact MWTs computed (solved or not)
  double weight_before = 0.0;
  double weight_after = 0.0;
  double seconds = 0.0;
  bool out_of_time = false;  // stopped by OptimizeOptions::time_budget_seconds
};

// Improves the weight of a carved mesh in place: the exact MWT of the domain when it is one small
// polygon without interior vertices, the local search above, then kicks (trial insertions of free
// and on-segment Steiner points and trial removals, each kept only if flips and relocations around
// it bring the weight below where it was) alternating with the local search while they pay, and
// with perturbation_trials > 0 an iterated local search (seeded random perturbations of 1–3
// Steiner points, each kept only if the search after it ends lighter).
// Input vertices and segments never change (a Steiner point on a segment only slides along its
// subsegment line or is removed, merging its two subsegments); every kept move keeps the mesh
// valid and strictly lowers the total weight, so the search terminates; results are deterministic
// (the kick budget counts trials, not seconds) unless time_budget_seconds cuts the search short.
// Removed vertices are dropped (mwst::compact).
// With exact_polish (off by default) the exact MWT of the mesh's vertices (exact_mwt, mwt.hpp)
// replaces the converged mesh whenever it is solved and lighter, followed by the search again; with
// exact_polish_start a second search runs from the MWT of the starting mesh, and the lighter of
// the two results is kept. Either way the result is never heavier than without the polish.
MWST_API OptimizeStats optimize(Mesh& mesh, const OptimizeOptions& options = {});

}  // namespace mwst
