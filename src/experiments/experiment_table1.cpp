// Table 1 of Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight", reproduced by
// `mwst experiment table1`: for every data set the interior weight (without the boundary: the input
// segments, or the convex hull of a point set) of DT, QTR, DR, BRH, BRH+EFH and our optimiser,
// normalised so that DT = 100, with Steiner counts, exact bundle numbers and the settings the sweep
// chose. Writes table1.csv (one row per data set), table1.md (ours beside the paper's figures) and
// runs.csv (every run of the sweep and the final runs).
#include <cmath>
#include <limits>
#include <sstream>

#include "experiments/experiment.hpp"

namespace mwst::experiments {

namespace {

constexpr double kNa = std::numeric_limits<double>::quiet_NaN();

// The paper's Table 1 (weights without boundary, DT = 100; NaN = NA in the paper).
struct PaperRow {
  const char* stem;  // our file name
  const char* name;  // the paper's name
  int points;
  int edges;
  double boundary;
  double qtr, dr, brh, brh_efh;
};
constexpr PaperRow kPaper[] = {
    {"Africa", "Africa", 54, 54, 30.7, 454.9, 96.4, 98.1, 88.5},
    {"Airliner", "Boeing", 30, 30, 26.6, 256.3, 61.6, 53.9, 50.1},
    {"California", "California", 291, 3603, 1.2, 305.1, 88.9, 83.4, 76.6},
    {"Ellipse", "Ellipse", 1000, 0, 1.0, 42.9, 11.8, 10.7, 9.9},
    {"Florida", "Florida", 304, 304, 17.0, 319.5, 90.8, 85.7, 78.5},
    {"Kuzmin2K", "Kuzmin2K", 2000, 0, 82.6, kNa, 91.6, 64.0, 63.2},
    {"NewYork", "New York", 282, 282, 18.3, 328.6, 89.5, 84.9, 77.3},
    {"Plate", "Plate", 65, 65, 14.2, kNa, 58.6, 54.6, 52.7},
    {"PuertoRico", "PuertoRico", 77, 77, 22.2, 345.5, 93.3, 86.5, 80.4},
    {"Random", "Random", 1004, 4, 3.5, kNa, 97.3, 95.9, 93.8},
    {"Superior", "Superior", 522, 522, 13.9, 271.8, 88.0, 78.8, 74.2},
    {"Texas", "Texas", 641, 641, 11.0, 284.4, 78.1, 73.0, 69.0},
    {"Turkey", "Turkey", 216, 216, 24.4, 391.5, 92.0, 92.6, 85.8},
};

const PaperRow* paper_row(const std::string& stem) {
  for (const PaperRow& row : kPaper) {
    if (stem == row.stem) return &row;
  }
  return nullptr;
}

// The paper's figure for a column, if it has one.
std::optional<double> paper_value(const PaperRow& row, Column c) {
  double v = kNa;
  switch (c) {
    case Column::kDt: v = 100.0; break;
    case Column::kQtr: v = row.qtr; break;
    case Column::kDr: v = row.dr; break;
    case Column::kBrh: v = row.brh; break;
    case Column::kBrhEfh: v = row.brh_efh; break;
    case Column::kOpt: break;
  }
  if (std::isnan(v)) return std::nullopt;
  return v;
}

std::string or_na(const std::optional<double>& v, int digits) { return v ? fixed(*v, digits) : "NA"; }

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

std::string md_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

// The final run of a column, if it succeeded.
const RunResult* final_run(const Study& s, std::size_t d, Column c) {
  const std::optional<std::size_t> f = s.final_index[d][static_cast<std::size_t>(c)];
  if (!f || !s.finals[*f].ok) return nullptr;
  return &s.finals[*f];
}

const TriangulateOptions* final_options(const Study& s, std::size_t d, Column c) {
  const std::optional<std::size_t> f = s.final_index[d][static_cast<std::size_t>(c)];
  return f ? &s.final_specs[*f].options : nullptr;
}

std::optional<double> column_value(const Study& s, std::size_t d, Column c) {
  const RunResult* r = final_run(s, d, c);
  if (!r) return std::nullopt;
  return normalised(s, d, *r);
}

std::optional<long long> bundle_of(const RunResult* r) {
  if (!r || !r->report.bundle) return std::nullopt;
  return static_cast<long long>(r->report.bundle->bundle_number);
}

std::string why_na(const Study& s, std::size_t d, Column c) {
  const std::optional<std::size_t> f = s.final_index[d][static_cast<std::size_t>(c)];
  if (f && !s.finals[*f].ok) return s.finals[*f].reason;
  const ColumnChoice& choice = s.choices[d][static_cast<std::size_t>(c)];
  if (!f) return choice.reason.empty() ? "not run" : choice.reason;
  if (!s.dt_interior[d] || !(*s.dt_interior[d] > 0.0)) return "no DT interior weight to normalise by";
  return "unknown";
}

std::optional<double> boundary_value(const Study& s, std::size_t d) {
  const RunResult* dt = final_run(s, d, Column::kDt);
  if (!dt || !s.dt_interior[d] || !(*s.dt_interior[d] > 0.0)) return std::nullopt;
  return dt->report.weight_boundary / *s.dt_interior[d] * 100.0;
}

std::string settings_text(const TriangulateOptions* o) {
  if (!o) return "—";
  if (o->method == Method::kDr) {
    return angle_text(o->min_angle_deg) + "°, " +
           (o->steiner == SteinerRule::kOffCenter ? "off-centers" : "circumcenters");
  }
  if (o->method == Method::kBrh) {
    const std::size_t k = o->bundle_k != 0 ? o->bundle_k : default_bundle_k(o->min_angle_deg);
    return "A = " + angle_text(o->min_angle_deg) + "°, K = " + std::to_string(k) + (o->bundle_k == 0 ? " (default)" : "");
  }
  return "—";
}

std::string grid_text(const std::vector<double>& v) {
  if (v.empty()) return "none";
  bool unit_steps = v.size() > 2;
  for (std::size_t i = 1; i < v.size() && unit_steps; ++i) unit_steps = v[i] - v[i - 1] == 1.0;
  if (unit_steps) return angle_text(v.front()) + "°, " + angle_text(v[1]) + "°, …, " + angle_text(v.back()) + "°";
  std::string s;
  for (const double a : v) s += (s.empty() ? "" : ", ") + angle_text(a) + "°";
  return s;
}

// table1.csv: one row per data set, every column's weight, Steiner points and bundle number, and
// the settings chosen.
std::string table1_csv(const Study& s) {
  const std::size_t n = s.data_sets.size();
  std::ostringstream csv;
  csv << "name,points,segments,boundary";
  for (const Column c : kColumns) csv << ',' << column_name(c);
  for (const Column c : kColumns) csv << ",steiner_" << column_name(c);
  for (const Column c : kColumns) csv << ",bundle_" << column_name(c);
  csv << ",dr_angle,dr_steiner,brh_angle,brh_k,brh_efh_angle,brh_efh_k,dt_interior_weight,dt_boundary_weight\n";
  for (std::size_t d = 0; d < n; ++d) {
    const DataSet& ds = s.data_sets[d];
    csv << csv_quote(ds.name) << ',' << ds.pslg.points.size() << ',' << ds.pslg.segments.size() << ','
        << or_na(boundary_value(s, d), 3);
    for (const Column c : kColumns) csv << ',' << or_na(column_value(s, d, c), 3);
    for (const Column c : kColumns) {
      const RunResult* r = final_run(s, d, c);
      csv << ',' << (r ? std::to_string(r->report.steiner) : "NA");
    }
    for (const Column c : kColumns) {
      const std::optional<long long> b = bundle_of(final_run(s, d, c));
      csv << ',' << (b ? std::to_string(*b) : "NA");
    }
    const TriangulateOptions* dr = final_options(s, d, Column::kDr);
    const TriangulateOptions* brh = final_options(s, d, Column::kBrh);
    const TriangulateOptions* efh = final_options(s, d, Column::kBrhEfh);
    const auto k_of = [](const TriangulateOptions* o) {
      return o ? std::to_string(o->bundle_k != 0 ? o->bundle_k : default_bundle_k(o->min_angle_deg)) : "NA";
    };
    csv << ',' << (dr ? angle_text(dr->min_angle_deg) : "NA") << ','
        << (dr ? std::string(steiner_rule_name(dr->steiner)) : "NA") << ','
        << (brh ? angle_text(brh->min_angle_deg) : "NA") << ',' << k_of(brh) << ','
        << (efh ? angle_text(efh->min_angle_deg) : "NA") << ',' << k_of(efh) << ','
        << (s.dt_interior[d] ? fixed(*s.dt_interior[d], 9) : "NA") << ',';
    const RunResult* dt = final_run(s, d, Column::kDt);
    csv << (dt ? fixed(dt->report.weight_boundary, 9) : "NA") << '\n';
  }

  return csv.str();
}

// table1.md, "Ours beside the paper": each weight as ours / the paper's.
void write_ours_beside_paper(const Study& s, std::ostringstream& md) {
  const std::size_t n = s.data_sets.size();
  md << "## Ours beside the paper (ours / paper)\n\n"
     << "| name | points | segments | boundary |";
  for (const Column c : kColumns) md << ' ' << column_name(c) << " |";
  md << "\n|---|---:|---:|---:|";
  for (std::size_t c = 0; c < kColumnCount; ++c) md << "---:|";
  md << '\n';
  for (std::size_t d = 0; d < n; ++d) {
    const DataSet& ds = s.data_sets[d];
    const PaperRow* p = paper_row(ds.name);
    const auto pair = [&](const std::string& ours, const std::string& theirs) {
      return p ? ours + " / " + theirs : ours;
    };
    md << "| " << md_escape(ds.name) << (p && std::string(p->name) != ds.name ? " (" + std::string(p->name) + ")" : "")
       << " | " << pair(std::to_string(ds.pslg.points.size()), p ? std::to_string(p->points) : "")
       << " | " << pair(std::to_string(ds.pslg.segments.size()), p ? std::to_string(p->edges) : "")
       << " | " << pair(or_na(boundary_value(s, d), 1), p ? fixed(p->boundary, 1) : "") << " |";
    for (const Column c : kColumns) {
      const std::string ours = or_na(column_value(s, d, c), 1);
      if (p && c != Column::kOpt) {
        md << ' ' << ours << " / " << or_na(paper_value(*p, c), 1) << " |";
      } else {
        md << ' ' << ours << " |";
      }
    }
    md << '\n';
  }

}

// table1.md: Steiner points and exact bundle numbers of every cell.
void write_steiner_and_bundles(const Study& s, std::ostringstream& md) {
  const std::size_t n = s.data_sets.size();
  md << "\n## Steiner points and bundle numbers (Steiner points, exact bundle number)\n\n| name |";
  for (const Column c : kColumns) md << ' ' << column_name(c) << " |";
  md << "\n|---|";
  for (std::size_t c = 0; c < kColumnCount; ++c) md << "---:|";
  md << '\n';
  for (std::size_t d = 0; d < n; ++d) {
    md << "| " << md_escape(s.data_sets[d].name) << " |";
    for (const Column c : kColumns) {
      const RunResult* r = final_run(s, d, c);
      const std::optional<long long> b = bundle_of(r);
      md << ' ' << (r ? std::to_string(r->report.steiner) : "NA") << ", " << (b ? std::to_string(*b) : "NA") << " |";
    }
    md << '\n';
  }

}

// table1.md: the settings the sweep chose, and opt's winning start.
void write_chosen_settings(const Study& s, std::ostringstream& md) {
  const std::size_t n = s.data_sets.size();
  md << "\n## Settings chosen by the sweep\n\n"
     << "The paper reports each method at its minimum-weight setting but does not say which setting "
     << "that was, so we choose by a sweep: the lightest interior weight among the runs that finished "
     << "(a run stopped by its time or Steiner budget is never chosen; ties go to the smaller setting). "
     << "DR: angle bounds " << grid_text(s.grids.dr_angles) << ", circumcenters and off-centers. "
     << "BRH and BRH+EFH: angle A in " << grid_text(s.grids.brh_angles) << " and bundle size K in {";
  for (std::size_t i = 0; i < s.grids.brh_ks.size(); ++i) {
    const std::size_t k = s.grids.brh_ks[i];
    md << (i ? ", " : "") << (k == 0 ? std::string("⌈4π/A⌉+3") : std::to_string(k));
  }
  md << "}, off-centers; BRH+EFH is chosen over the same grid with the flips run after BRH. OPT is not "
     << "swept: it searches from BRH+EFH at the (A, K) chosen for BRH+EFH, from DR at 5°, 10°, 15°, "
     << "20°, from DT and, for inputs with segments, from DT seeded with Steiner points "
     << "(dt+junctions: at the circumcenters of its triangles with no boundary edge; dt+centroids: at "
     << "every triangle's centroid), keeps the lightest and crosses it with the others; the last column "
     << "names the start that won"
     << (s.opt_trials == kDefaultOptTrials
             ? std::string()
             : " (each start searched with --opt-trials " + std::to_string(s.opt_trials) +
                   " trials, not the default min(600, 300000 / triangles))")
     << ". Every run is listed in runs.csv.\n\n"
     << "| name | DR | BRH | BRH+EFH | OPT start |\n|---|---|---|---|---|\n";
  for (std::size_t d = 0; d < n; ++d) {
    std::string opt_start = "—";
    if (const RunResult* r = final_run(s, d, Column::kOpt)) {
      if (r->report.optimize && r->report.optimize->pieces == 0) opt_start = r->report.optimize->start;
    }
    md << "| " << md_escape(s.data_sets[d].name) << " | " << settings_text(final_options(s, d, Column::kDr))
       << " | " << settings_text(final_options(s, d, Column::kBrh)) << " | "
       << settings_text(final_options(s, d, Column::kBrhEfh)) << " | " << opt_start << " |\n";
  }

}

// table1.md: why cells are NA, and the study's warnings.
void write_na_and_warnings(const Study& s, std::ostringstream& md) {
  const std::size_t n = s.data_sets.size();
  // Why cells are NA.
  std::ostringstream na;
  for (std::size_t d = 0; d < n; ++d) {
    for (const Column c : kColumns) {
      if (column_value(s, d, c)) continue;
      na << "- " << md_escape(s.data_sets[d].name) << ", " << column_name(c) << ": " << md_escape(why_na(s, d, c)) << '\n';
    }
  }
  if (!na.str().empty()) md << "\n## NA cells\n\n" << na.str();
  if (!s.warnings.empty()) {
    md << "\n## Warnings\n\n";
    for (const std::string& w : s.warnings) md << "- " << md_escape(w) << '\n';
  }
}

}  // namespace

std::vector<OutputFile> table1_files(const Study& s) {
  const std::size_t n = s.data_sets.size();
  std::ostringstream md;
  md << "# Table 1: weights without boundary, DT = 100\n\n"
     << "Written by `mwst experiment` from " << n << " data sets. Weight = sum of edge lengths; the "
     << "boundary (input segments, or the convex hull of a point set) is left out and the rest "
     << "normalised so that DT = 100, as in the paper. *boundary* is the boundary weight on the same "
     << "scale. OPT is our optimiser (not in the paper).\n\n";

  write_ours_beside_paper(s, md);
  write_steiner_and_bundles(s, md);
  write_chosen_settings(s, md);
  write_na_and_warnings(s, md);
  return {{"table1.csv", table1_csv(s)}, {"table1.md", md.str()}};
}

OutputFile runs_file(const Study& s) {
  std::ostringstream csv;
  csv << "phase,name,method,min_angle,steiner_rule,bundle_k,flip,status,weight_interior,normalised,"
         "steiner,min_angle_result,max_angle_result,stop_reason,bundle_number,seconds,reason\n";
  const auto rows = [&](const char* phase, const std::vector<RunSpec>& specs, const std::vector<RunResult>& results) {
    for (std::size_t i = 0; i < specs.size() && i < results.size(); ++i) {
      const RunSpec& spec = specs[i];
      const RunResult& r = results[i];
      const TriangulateOptions& o = spec.options;
      const bool uses_angle = o.method == Method::kDr || o.method == Method::kBrh || o.method == Method::kOpt;
      const bool uses_k = o.method == Method::kBrh || o.method == Method::kOpt;
      csv << phase << ',' << csv_quote(s.data_sets[spec.data_set].name) << ',' << method_name(o.method) << ','
          << (uses_angle ? angle_text(o.min_angle_deg) : "") << ','
          << (uses_angle ? std::string(steiner_rule_name(o.steiner)) : "") << ','
          << (uses_k && (o.bundle_k != 0 || o.min_angle_deg > 0.0)
                  ? std::to_string(o.bundle_k != 0 ? o.bundle_k : default_bundle_k(o.min_angle_deg))
                  : "")
          << ',' << (o.flip ? "yes" : "no") << ',' << (r.ok ? "ok" : "NA") << ',';
      if (r.ok) {
        const std::optional<long long> b = bundle_of(&r);
        csv << fixed(r.report.weight_interior, 9) << ',' << or_na(normalised(s, spec.data_set, r), 3) << ','
            << r.report.steiner << ',' << fixed(r.report.min_angle, 3) << ',' << fixed(r.report.max_angle, 3) << ','
            << csv_quote(r.report.stop_reason) << ',' << (b ? std::to_string(*b) : "") << ',';
      } else {
        csv << ",,,,,,,";
      }
      csv << fixed(r.seconds, 4) << ',' << csv_quote(r.reason) << '\n';
    }
  };
  rows("sweep", s.sweep_specs, s.sweep);
  rows("final", s.final_specs, s.finals);
  return {"runs.csv", csv.str()};
}

}  // namespace mwst::experiments
