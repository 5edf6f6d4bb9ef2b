// Stop reasons (mwst/algorithms/pipeline.hpp): their words in the report, the engines' words read
// back, and the reason the final mesh bears out (settle_stop_reason).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>
#include <chrono>
#include <string_view>

#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/brh.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/error.hpp"

namespace mwst {

namespace {

// The termination guard's words (DR's and BRH's): refinement made an edge far shorter than the
// input's smallest feature allows when it terminates (angle bounds above about 34°; see
// docs/algorithms/refine.md).
constexpr const char* kStopBeyondFeatureSize = "no progress: size beyond the local-feature-size bound";
// The end of "N triangles left beside subsegments that may not be split": bad triangles remain
// whose Steiner points lie on or beyond protected subsegments (segment_splitting).
constexpr const char* kStopProtectedSuffix = " triangles left beside subsegments that may not be split";

}  // namespace

std::string to_string(const StopReason& r) {
  switch (r.kind) {
    case StopKind::kUnset: return "";
    case StopKind::kBoundReached: return "bound reached";
    case StopKind::kSmallInputAngles: return std::to_string(r.count) + " triangles left near small input angles";
    case StopKind::kSteinerBudget: return "steiner budget";
    case StopKind::kTimeBudget: return "time budget";
    case StopKind::kLocalMinimum: return "local minimum";
    case StopKind::kRoundLimit: return "round limit";
    case StopKind::kBeyondFeatureSize: return kStopBeyondFeatureSize;
    case StopKind::kBelowBoundAfterFlips:
      return std::to_string(r.count) + " triangles below the angle bound after the flips";
    case StopKind::kSkinnyInBundles: return std::to_string(r.count) + " skinny triangles in K-bundles after the flips";
    case StopKind::kLeftBelowBound: return std::to_string(r.count) + " triangles left outside the bounds";
    case StopKind::kProtectedSegments: return std::to_string(r.count) + kStopProtectedSuffix;
    case StopKind::kOther: return r.text;
  }
  throw InternalError("to_string: unknown stop reason");
}

StopReason parse_stop_reason(std::string_view text) {
  StopReason r;
  if (text.empty()) return r;
  for (const StopKind kind : {StopKind::kBoundReached, StopKind::kSteinerBudget, StopKind::kTimeBudget,
                              StopKind::kLocalMinimum, StopKind::kRoundLimit, StopKind::kBeyondFeatureSize}) {
    if (to_string(StopReason{kind, 0, {}}) == text) return StopReason{kind, 0, {}};
  }
  // "N triangles left beside subsegments that may not be split"
  const std::string_view protected_suffix = kStopProtectedSuffix;
  if (text.size() > protected_suffix.size() && text.ends_with(protected_suffix)) {
    const std::string_view digits = text.substr(0, text.size() - protected_suffix.size());
    if (std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }) && digits.size() < 19) {
      return StopReason{StopKind::kProtectedSegments, std::stoull(std::string(digits)), {}};
    }
  }
  // "N triangles left near small input angles"
  constexpr std::string_view kSmall = " triangles left near small input angles";
  if (text.size() > kSmall.size() && text.ends_with(kSmall)) {
    const std::string_view digits = text.substr(0, text.size() - kSmall.size());
    if (std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }) && digits.size() < 19) {
      return StopReason{StopKind::kSmallInputAngles, std::stoull(std::string(digits)), {}};
    }
  }
  return StopReason{StopKind::kOther, 0, std::string(text)};
}

StopReason settle_stop_reason(const Mesh& mesh, const TriangulateOptions& options, const StopReason& engine,
                              bool flipped, std::chrono::steady_clock::time_point deadline) {
  // Out of time the engine's reason stands whatever the mesh meets (every branch below returns it),
  // so the mesh is not swept again: 0.8 s on 3M triangles, past the budget.
  if (engine.kind == StopKind::kTimeBudget) return engine;
  // Reasons that say the run was cut short, or that the engine explains in its own words.
  const bool cut_short = engine.kind == StopKind::kSteinerBudget || engine.kind == StopKind::kTimeBudget ||
                         engine.kind == StopKind::kRoundLimit || engine.kind == StopKind::kBeyondFeatureSize ||
                         engine.kind == StopKind::kOther;
  // dr's bound is the angle and the area; brh's the area (its angle bound is the K-bundle test, as
  // the paper states it: a skinny triangle is left if it is in no K-bundle); opt's the area.
  const double angle = options.method == Method::kDr ? options.min_angle_deg : 0.0;
  BoundCheck check = check_bounds(mesh, angle, options.max_area);
  if (!mesh.area_bound.empty()) {
    // The mesh's own per-triangle bounds (regional limits, .area files). A triangle check_bounds
    // already counted as a violation (above the global bound, or below the angle bound and not
    // next to a small input angle) is not counted again; one it exempted is a violation now.
    const double c = std::cos(std::max(0.0, angle) * std::numbers::pi / 180.0);
    std::vector<std::uint8_t> near;
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      const double bound = mesh.area_bound[t];
      if (!(bound > 0.0) || !mesh.in_domain(t)) continue;
      const auto& v = mesh.triangles[t].v;
      const Point &a = mesh.points[v[0]], &b = mesh.points[v[1]], &p = mesh.points[v[2]];
      const double area = triangle_area(a, b, p);
      if (!(area > bound) || (options.max_area > 0.0 && area > options.max_area)) continue;
      if (angle > 0.0 && below_angle_bound(a, b, p, c * c)) {
        if (near.empty()) near = near_small_input_angles(mesh);
        if (!near[t]) continue;
        --check.exempt;
      }
      ++check.above_area;
      ++check.violations;
    }
  }
  if (check.violations > 0) {
    if (cut_short) return engine;
    if (options.segment_splitting != SegmentSplitting::kAllowed) {
      return StopReason{StopKind::kProtectedSegments, check.violations, {}};
    }
    // The refinement reached its bound and the flips broke it (flips keep the area bound).
    if (flipped && check.above_area == 0) return StopReason{StopKind::kBelowBoundAfterFlips, check.violations, {}};
    return StopReason{StopKind::kLeftBelowBound, check.violations, {}};
  }
  // The mesh meets the bound checked here.
  if (options.method == Method::kOpt) {
    // A start cut by --max-steiner does not matter once the result meets the area bound.
    return engine.kind == StopKind::kTimeBudget ? engine : StopReason{StopKind::kLocalMinimum, 0, {}};
  }
  if (cut_short) return engine;
  if (options.method == Method::kBrh) {
    if (!flipped) return engine;  // BRH's own exact test confirmed its skinny triangles
    // The flips may have put skinny triangles into K-bundles: the exact test on every skinny one
    // not next to a small input angle.
    const double c = std::cos(std::max(0.0, options.min_angle_deg) * std::numbers::pi / 180.0);
    const std::vector<std::uint8_t> near = near_small_input_angles(mesh);
    std::vector<TriangleId> skinny;
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      if (!mesh.in_domain(t) || near[t]) continue;
      const auto& v = mesh.triangles[t].v;
      if (below_angle_bound(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], c * c)) skinny.push_back(t);
    }
    if (skinny.empty()) return engine;
    const std::size_t k = options.bundle_k != 0 ? options.bundle_k : default_bundle_k(options.min_angle_deg);
    std::vector<std::uint8_t> in_bundle;
    try {
      in_bundle = in_k_bundle(mesh, static_cast<std::uint32_t>(k), skinny, nullptr, options.threads, nullptr, deadline);
    } catch (const KBundleTimeout&) {
      return StopReason{StopKind::kTimeBudget, 0, {}};
    }
    const auto count = static_cast<std::size_t>(std::count(in_bundle.begin(), in_bundle.end(), std::uint8_t{1}));
    return count > 0 ? StopReason{StopKind::kSkinnyInBundles, count, {}} : engine;
  }
  if (check.exempt > 0) return StopReason{StopKind::kSmallInputAngles, check.exempt, {}};
  return StopReason{StopKind::kBoundReached, 0, {}};
}

}  // namespace mwst
