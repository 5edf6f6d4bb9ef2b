// mwst/algorithms/stop_reason.hpp — why a refinement engine or method stopped, as a kind and a
// count; the report's words (to_string) are made from it in one place.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "mwst/export.hpp"

namespace mwst {

// Why a refinement method (dr, brh, opt) stopped, checked against the final mesh (after the flips and
// opt's moves) and the budgets: see settle_stop_reason().
enum class StopKind {
  kUnset,                 // dt, and qtr unless out of time: no stop reason
  kBoundReached,          // every triangle meets the angle and area bounds ("bound reached")
  kSmallInputAngles,      // all but `count` triangles next to input angles under 60° do
  kSteinerBudget,         // max_steiner ran out first
  kTimeBudget,            // time_budget_seconds passed first
  kLocalMinimum,          // opt: no move lowers the weight, and the area bound holds
  kRoundLimit,            // brh: its pass limit
  kBeyondFeatureSize,     // the termination guard of dr and brh (refine.hpp)
  kBelowBoundAfterFlips,  // flip: `count` triangles below the bound after the flips
  kSkinnyInBundles,       // brh with flip: `count` skinny triangles in K-bundles after the flips
  kLeftBelowBound,        // `count` triangles miss the bound, none of the reasons above holds
  kProtectedSegments,     // `count` triangles miss the bound beside subsegments that may not be
                          // split (segment_splitting, Triangle's -Y / -YY)
  kOther,                 // a reason an engine gave in its own words (`text`)
};
struct StopReason {
  StopKind kind = StopKind::kUnset;
  std::size_t count = 0;  // kSmallInputAngles, kBelowBoundAfterFlips, kSkinnyInBundles, kLeftBelowBound,
                          // kProtectedSegments
  std::string text;       // kOther
  friend bool operator==(const StopReason&, const StopReason&) = default;
};
// The words of the report: "bound reached", "N triangles left near small input angles",
// "steiner budget", "time budget", "local minimum", "round limit", "N triangles below the angle
// bound after the flips", "N skinny triangles in K-bundles after the flips", "N triangles left
// outside the bounds", "N triangles left beside subsegments that may not be split", or the
// engine's text; "" for kUnset.
MWST_API std::string to_string(const StopReason& reason);
// The inverse of to_string (kOther for words it does not know).
MWST_API StopReason parse_stop_reason(std::string_view text);
}  // namespace mwst
