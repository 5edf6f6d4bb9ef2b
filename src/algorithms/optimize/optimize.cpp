// The weight optimiser ("--method opt" / "--optimize", mwst/algorithms/optimize.hpp): a local search
// for the minimum weight Steiner triangulation past the paper's BRH+EFH. This file is its facade:
// optimize() runs one search (class opt::Optimizer, optimizer.hpp, which lists the steps in order)
// or, with the exact polish's second start, two, and keeps the lighter. The moves, the kicks, the
// regions and the exact polish live beside it; docs/algorithms/optimize.md explains them.
#include "mwst/algorithms/optimize.hpp"

#include <chrono>
#include <utility>

#include "algorithms/optimize/optimizer.hpp"
#include "algorithms/optimize/testing.hpp"
#include "support/time_budget.hpp"

namespace mwst {

OptimizeStats optimize(Mesh& mesh, const OptimizeOptions& options, const OptimizeTestSwitches& test) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto deadline = detail::deadline_after(t0, options.time_budget_seconds);
  OptimizeStats stats;
  if (options.exact_polish && options.exact_polish_start) {
    // Two searches: from the mesh as given, and from the MWT of its vertices (another basin);
    // the lighter result is kept, so the polish never makes the result heavier.
    Mesh from_mwt = mesh;
    OptimizeStats from_mwt_stats;
    opt::Optimizer(mesh, options, test, stats, deadline).run(false);
    if (opt::Optimizer(from_mwt, options, test, from_mwt_stats, deadline).run(true)) {
      from_mwt_stats.exact_polish_tries += stats.exact_polish_tries;
      if (from_mwt_stats.weight_after < stats.weight_after) {
        mesh = std::move(from_mwt);
        stats = from_mwt_stats;
      } else {
        stats.exact_polish_tries = from_mwt_stats.exact_polish_tries;
      }
    } else {
      stats.exact_polish_tries += from_mwt_stats.exact_polish_tries;
    }
  } else {
    opt::Optimizer(mesh, options, test, stats, deadline).run(false);
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

OptimizeStats optimize(Mesh& mesh, const OptimizeOptions& options) {
  return optimize(mesh, options, OptimizeTestSwitches{});
}

}  // namespace mwst
