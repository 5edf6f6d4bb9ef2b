// The plan of `mwst experiment` (src/experiments/experiment.hpp): which runs the sweep makes for each data
// set, how Table 1's DR, BRH and BRH+EFH settings are chosen from it (the lightest interior weight;
// Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" report minimum-weight settings
// without saying which), and the final runs that repeat each choice with the exact bundle number.
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "experiments/experiment.hpp"

namespace mwst::experiments {

namespace {

// A safety net per run: refinement stops after this long and says so (stop_reason "time budget");
// such a run is kept in runs.csv but never chosen, since it is not the method at that setting.
constexpr double kRunBudgetSeconds = 60.0;
// The optimiser's run (Table 1's OPT column) searches for up to a minute on the largest data sets
// (Texas: 64 s on a 2-core machine), and a search cut by its budget would make the column depend
// on the machine's speed: its safety net is fifteen times longer.
constexpr double kOptRunBudgetSeconds = 900.0;

bool stopped_by_budget(const Report& r) {
  return r.stop.kind == StopKind::kTimeBudget || r.stop.kind == StopKind::kSteinerBudget;
}

// The Table 1 column a sweep run competes for, if any (DR at 0° is Figure 3's DT end point only).
std::optional<Column> table_column(const TriangulateOptions& o) {
  switch (o.method) {
    case Method::kDt: return Column::kDt;
    case Method::kQtr: return Column::kQtr;
    case Method::kDr:
      if (o.min_angle_deg > 0.0) return Column::kDr;
      return std::nullopt;
    case Method::kBrh: return o.flip ? Column::kBrhEfh : Column::kBrh;
    case Method::kOpt: return Column::kOpt;
  }
  return std::nullopt;
}

TriangulateOptions base_options(Method method) {
  TriangulateOptions o;
  o.method = method;
  o.time_budget_seconds = kRunBudgetSeconds;
  return o;
}

}  // namespace

std::optional<double> normalised(const Study& study, std::size_t data_set, const RunResult& run) {
  if (!run.ok || data_set >= study.dt_interior.size() || !study.dt_interior[data_set]) return std::nullopt;
  const double dt = *study.dt_interior[data_set];
  if (!(dt > 0.0)) return std::nullopt;
  // DT itself: x / x = 1 exactly, so the DT column is exactly 100.
  const double v = run.report.weight_interior / dt * 100.0;
  if (!std::isfinite(v)) return std::nullopt;
  return v;
}

void plan_sweep(Study& study, bool full_sweep, bool figure3) {
  study.sweep_specs.clear();
  for (std::size_t d = 0; d < study.data_sets.size(); ++d) {
    const auto add = [&](TriangulateOptions o, const char* group) {
      RunSpec s;
      s.data_set = d;
      s.options = o;
      s.group = group;
      study.sweep_specs.push_back(std::move(s));
    };
    add(base_options(Method::kDt), "dt");
    if (full_sweep) add(base_options(Method::kQtr), "qtr");

    // DR: both Steiner rules over the union of the angles needed (each setting runs once).
    std::set<double> angles;
    if (figure3) angles.insert(study.grids.figure3_angles.begin(), study.grids.figure3_angles.end());
    if (full_sweep) angles.insert(study.grids.dr_angles.begin(), study.grids.dr_angles.end());
    for (const SteinerRule rule : {SteinerRule::kCircumcenter, SteinerRule::kOffCenter}) {
      for (const double a : angles) {
        TriangulateOptions o = base_options(Method::kDr);
        o.min_angle_deg = a;
        o.steiner = rule;
        add(o, "dr sweep");
      }
    }
    if (!full_sweep) continue;

    // BRH over the (A, K) grid, without and with the flips (EFH) afterwards.
    for (const bool flip : {false, true}) {
      for (const double a : study.grids.brh_angles) {
        for (const std::size_t k : study.grids.brh_ks) {
          TriangulateOptions o = base_options(Method::kBrh);
          o.min_angle_deg = a;
          o.bundle_k = k;
          o.flip = flip;
          add(o, flip ? "brh+efh sweep" : "brh sweep");
        }
      }
    }
    // OPT is not swept: it starts from BRH+EFH at that column's chosen (A, K) (and from DR, DT and
    // seeded DT), so it runs once, among the final runs (choose_and_plan_finals).
  }
}

void choose_and_plan_finals(Study& study, bool pictures) {
  const std::size_t n = study.data_sets.size();
  study.choices.assign(n, std::vector<ColumnChoice>(kColumnCount));
  for (std::size_t i = 0; i < study.sweep_specs.size(); ++i) {
    const RunSpec& s = study.sweep_specs[i];
    const std::optional<Column> column = table_column(s.options);
    if (!column) continue;
    ColumnChoice& c = study.choices[s.data_set][static_cast<std::size_t>(*column)];
    c.runs.push_back(i);
    const RunResult& r = study.sweep[i];
    if (!r.ok) {
      if (c.reason.empty()) c.reason = r.reason;
      continue;
    }
    if (stopped_by_budget(r.report)) continue;
    // The lightest interior weight; ties keep the earlier spec (deterministic).
    if (!c.chosen || r.report.weight_interior < study.sweep[*c.chosen].report.weight_interior) c.chosen = i;
  }
  for (auto& row : study.choices) {
    for (ColumnChoice& c : row) {
      if (!c.chosen && c.reason.empty() && !c.runs.empty()) c.reason = "every run stopped at its time or Steiner budget";
    }
  }

  study.final_specs.clear();
  study.final_index.assign(n, std::vector<std::optional<std::size_t>>(kColumnCount));
  for (std::size_t d = 0; d < n; ++d) {
    for (std::size_t c = 0; c < kColumnCount; ++c) {
      const ColumnChoice& choice = study.choices[d][c];
      RunSpec s;
      if (kColumns[c] == Column::kOpt) {
        // Our optimiser searches from BRH+EFH at the given (A, K), among other starts: give it the
        // (A, K) chosen for BRH+EFH, so that OPT ≤ BRH+EFH holds in the table.
        s.data_set = d;
        s.options = base_options(Method::kOpt);
        s.options.time_budget_seconds = kOptRunBudgetSeconds;
        s.options.opt_trials = study.opt_trials;
        const ColumnChoice& efh = study.choices[d][static_cast<std::size_t>(Column::kBrhEfh)];
        if (efh.chosen) {
          s.options.min_angle_deg = study.sweep_specs[*efh.chosen].options.min_angle_deg;
          s.options.bundle_k = study.sweep_specs[*efh.chosen].options.bundle_k;
        }
      } else {
        if (!choice.chosen) continue;
        s = study.sweep_specs[*choice.chosen];
      }
      s.options.bundle = true;
      s.keep_picture = pictures;
      s.group = "final";
      study.final_index[d][c] = study.final_specs.size();
      study.final_specs.push_back(std::move(s));
    }
  }
}

void check_finals(Study& study) {
  for (std::size_t d = 0; d < study.data_sets.size(); ++d) {
    for (std::size_t c = 0; c < kColumnCount; ++c) {
      const std::optional<std::size_t> f = study.final_index[d][c];
      if (!f) continue;
      const RunResult& fin = study.finals[*f];
      const std::string where = study.data_sets[d].name + " " + column_name(kColumns[c]) + " (" +
                                describe(study.final_specs[*f].options) + ")";
      if (!fin.ok) {
        study.warnings.push_back(where + ": the final run failed: " + fin.reason);
        continue;
      }
      if (!study.choices[d][c].chosen) continue;  // OPT: no sweep run to compare with
      const RunResult& swept = study.sweep[*study.choices[d][c].chosen];
      if (fin.report.weight_interior != swept.report.weight_interior || fin.report.steiner != swept.report.steiner) {
        study.warnings.push_back(where + ": not deterministic: the sweep gave interior weight " +
                                 fixed(swept.report.weight_interior, 9) + " with " +
                                 std::to_string(swept.report.steiner) + " Steiner points, the repeat " +
                                 fixed(fin.report.weight_interior, 9) + " with " +
                                 std::to_string(fin.report.steiner) + " (the table shows the repeat)");
      }
      if (!fin.violations.empty()) {
        study.warnings.push_back(where + ": validate() found " + std::to_string(fin.violations.size()) +
                                 " violations, first: " + fin.violations.front());
      }
    }
  }
  for (std::size_t i = 0; i < study.sweep.size(); ++i) {
    if (study.sweep[i].internal_error) {
      study.warnings.push_back(study.data_sets[study.sweep_specs[i].data_set].name + " " +
                               describe(study.sweep_specs[i].options) + ": " + study.sweep[i].reason);
    }
  }
}

}  // namespace mwst::experiments
