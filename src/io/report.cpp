// The JSON report of a run (mwst/io/report.hpp).
#include "mwst/io/report.hpp"

#include <limits>
#include <string>

#include "mwst/version.hpp"

namespace mwst {

namespace {

// opt's summary: the pieces and their weight when the domain was cut, else the winning search.
nlohmann::json optimize_json(const OptimizeSummary& o) {
  if (o.pieces > 0) return {{"pieces", o.pieces}, {"weight_after", o.weight_after}};
  nlohmann::json starts = nlohmann::json::object();
  for (const auto& [name, weight] : o.starts) starts[name] = weight;
  nlohmann::json j = {{"start", o.start},
                      {"starts", std::move(starts)},
                      {"rounds", o.rounds},
                      {"relocations", o.relocations},
                      {"removals", o.removals},
                      {"insertions", o.insertions},
                      {"region_retriangulations", o.region_retriangulations},
                      {"region_tries_skipped", o.region_tries_skipped},
                      {"kick_insertions", o.kick_insertions},
                      {"kick_removals", o.kick_removals},
                      {"perturbations", o.perturbations},
                      {"whole_polygon_mwt", o.whole_polygon_mwt},
                      {"flips", o.flips},
                      {"crossover_pieces", o.crossover_pieces},
                      {"crossover_gain", o.crossover_gain},
                      {"weight_before", o.weight_before},
                      {"weight_after", o.weight_after}};
  if (o.exact_polishes) j["exact_polishes"] = *o.exact_polishes;
  if (o.exact_polish_tries) j["exact_polish_tries"] = *o.exact_polish_tries;
  return j;
}

}  // namespace

nlohmann::json to_json(const Report& r) {
  const TriangulateOptions& o = r.options;
  nlohmann::json parameters = {
      {"min_angle", o.min_angle_deg},
      {"steiner", std::string(steiner_rule_name(o.steiner))},
      {"flip", o.flip},
      {"convex_hull", o.convex_hull},
      {"strict", o.strict},
      {"bundle", o.bundle},
  };
  if (o.method == Method::kOpt) {
    // opt's moves lower the weight whatever the angles: the bound holds for its starts only.
    parameters["min_angle_bounds"] = "the dr and brh starting meshes only, not the result";
  }
  if (o.method == Method::kBrh) {
    parameters["bundle_k"] = o.bundle_k != 0 ? o.bundle_k : default_bundle_k(o.min_angle_deg);
  }
  if (o.max_area > 0.0) parameters["max_area"] = o.max_area;
  if (o.max_steiner != std::numeric_limits<std::size_t>::max()) parameters["max_steiner"] = o.max_steiner;
  if (o.time_budget_seconds > 0.0) parameters["time_budget"] = o.time_budget_seconds;
  if (o.method == Method::kOpt && o.opt_trials != kDefaultOptTrials) parameters["opt_trials"] = o.opt_trials;

  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& [phase, s] : r.seconds) {
    // A phase that ran twice (e.g. flips after two methods) adds up.
    seconds[phase] = seconds.value(phase, 0.0) + s;
  }
  seconds["total"] = r.total_seconds();

  nlohmann::json j = {
      {"version", kVersionString},
      {"input", r.input},
      {"method", r.method},
      {"parameters", std::move(parameters)},
      {"vertices", r.vertices},
      {"triangles", r.triangles},
      {"steiner", r.steiner},
      {"weight_total", r.weight_total},
      {"weight_boundary", r.weight_boundary},
      {"weight_interior", r.weight_interior},
      {"min_angle", r.min_angle},
      {"max_angle", r.max_angle},
      {"max_triangle_area", r.max_triangle_area},
      {"seconds", std::move(seconds)},
      {"duplicates", r.duplicates},
      {"crossings", r.crossings},
      {"warnings", r.warnings},
  };
  if (!r.stop_reason.empty()) j["stop_reason"] = r.stop_reason;
  if (r.start) j["start"] = {{"triangles", r.start->triangles}, {"reoriented", r.start->reoriented}};
  if (r.refine) {
    j["refine"] = {{"steiner_inserted", r.refine->steiner_inserted},
                   {"segment_splits", r.refine->segment_splits},
                   {"left_small_angle", r.refine->left_small_angle}};
    if (r.refine->left_protected) j["refine"]["left_protected"] = *r.refine->left_protected;
  }
  if (r.conform) j["conform"] = {{"segment_splits", r.conform->segment_splits}};
  if (r.brh) {
    j["brh"] = {{"bundle_k", r.brh->bundle_k},
                {"rounds", r.brh->rounds},
                {"exact_evaluations", r.brh->exact_evaluations},
                {"steiner_inserted", r.brh->steiner_inserted},
                {"segment_splits", r.brh->segment_splits},
                {"skinny_left", r.brh->skinny_left}};
  }
  if (r.flip) {
    j["flip"] = {{"flips", r.flip->flips}, {"weight_before", r.flip->weight_before}, {"weight_after", r.flip->weight_after}};
  }
  if (r.qtr) {
    j["qtr"] = {{"leaves", r.qtr->leaves},   {"depth", r.qtr->depth},
                {"warped", r.qtr->warped},   {"snapped", r.qtr->snapped},
                {"crossing_points", r.qtr->crossing_points}, {"centres", r.qtr->centres},
                {"fallback", r.qtr->fallback}};
  }
  if (r.optimize) j["optimize"] = optimize_json(*r.optimize);
  if (r.bundle) {
    j["bundle_number"] = r.bundle->bundle_number;
    j["bundle_disk"] = {{"x", r.bundle->disk_center.x}, {"y", r.bundle->disk_center.y}, {"r", r.bundle->disk_radius}};
    j["bundle_circumdisk_bound"] = r.bundle->circumdisk_bound;
  }
  return j;
}

}  // namespace mwst
