// src/support/time_budget.hpp — the deadline of a wall-clock budget in seconds, as the
// algorithms with a time_budget_seconds option (refine's callers, bundle removal, the optimiser)
// read it: ≤ 0 is no budget, and so is anything beyond 1e9 s (31 years), where the time point
// would overflow.
#pragma once

#include <chrono>

namespace mwst::detail {

inline std::chrono::steady_clock::time_point deadline_after(std::chrono::steady_clock::time_point start,
                                                            double budget_seconds) {
  if (!(budget_seconds > 0.0 && budget_seconds < 1e9)) return std::chrono::steady_clock::time_point::max();
  return start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                     std::chrono::duration<double>(budget_seconds));
}

}  // namespace mwst::detail
