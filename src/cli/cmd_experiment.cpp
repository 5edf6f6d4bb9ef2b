// `mwst experiment table1|figure3|figure4|all [--data DIR] [--out DIR] [--jobs N] [--opt-trials N]`:
// the experiments of Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" in one command.
//
//   table1   Table 1: interior weights of DT, QTR, DR, BRH, BRH+EFH and our optimiser (DT = 100),
//            Steiner counts, exact bundle numbers, the settings chosen by the sweep
//            (table1.csv, table1.md beside the paper's figures, runs.csv with every run)
//   figure3  DR's weight against the angle bound 0°–20°, circumcenters vs off-centers
//            (figure3.csv, figure3.gp, and the plots figure3*.png/.pdf drawn by gnuplot)
//   figure4  per data set the six meshes side by side (figure4_NAME.png/.pdf)
//   all      all three, sharing the runs
//
// The plan (src/experiments/experiment_study.cpp): every data set in --data (default data/) is run with
// DT, QTR, DR at every angle bound of the grid below with both Steiner rules, BRH over an (A, K)
// grid with and without the flips, and our optimiser (--opt-trials trials per start, default as for
// triangulate); each Table 1 column takes its lightest setting, which is then run again with the
// exact bundle number (and drawn for Figure 4). Runs go to a pool of --jobs worker threads
// (default: the hardware threads); every result lands in its spec's slot, so the outputs do not
// depend on scheduling. Progress goes to stderr. Files are written to --out (default results/) only
// once everything is computed.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <thread>

#include "cli/commands.hpp"
#include "experiments/experiment.hpp"
#include "mwst/error.hpp"

namespace mwst::cli {

namespace {

using namespace mwst::experiments;

struct ExperimentArgs {
  std::string target;
  std::string data = "data";
  std::string out = "results";
  std::size_t jobs = 0;
  std::size_t opt_trials = kDefaultOptTrials;
};

// The sweep grids. DR: every whole degree (DR is fast: all 34 angles × 2 rules on the 13 data
// sets take seconds). Figure 3: 0°–20° in 1° steps as in the paper. BRH: the paper's bound α
// (as A) from 10° to 30°, and K from small (close to DR) to the paper's default ⌈4π/A⌉ + 3.
Grids default_grids() {
  Grids g;
  for (int a = 1; a <= 34; ++a) g.dr_angles.push_back(a);
  for (int a = 0; a <= 20; ++a) g.figure3_angles.push_back(a);
  g.brh_angles = {5.0, 10.0, 15.0, 20.0, 25.0, 30.0};
  g.brh_ks = {6, 8, 10, 12, 14, 16, 18, 20, 24, 0};
  return g;
}

// Says on the progress line which data sets were found in `data_dir`.
void announce_data_sets(experiments::Progress& progress, const Study& study, const std::string& data_dir) {
  std::string names;
  for (const DataSet& d : study.data_sets) names += (names.empty() ? "" : " ") + d.name;
  progress.line(std::to_string(study.data_sets.size()) + " data sets from " + data_dir + ": " + names);
}

// Creates the output directory `out` (and its parents), or fails naming it.
void create_output_directory(const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) {
    throw InputError(out, 0, "cannot create the output directory" + (ec ? ": " + ec.message() : std::string()));
  }
}

// Plans and runs the sweep; records each data set's DT interior weight (the 100 of Table 1).
void run_sweep(Study& study, bool for_finals, bool figure3, std::size_t workers, experiments::Progress& progress) {
  plan_sweep(study, for_finals, figure3);
  study.sweep = run_all(study.data_sets, study.sweep_specs, workers, progress, "sweep");
  study.dt_interior.assign(study.data_sets.size(), std::nullopt);
  for (std::size_t i = 0; i < study.sweep_specs.size(); ++i) {
    const RunSpec& s = study.sweep_specs[i];
    if (s.options.method == Method::kDt && study.sweep[i].ok) {
      study.dt_interior[s.data_set] = study.sweep[i].report.weight_interior;
    }
  }
}

// Prints the section "Ours beside the paper" of table1.md (among `files`) on stdout.
void print_paper_comparison(const std::vector<OutputFile>& files) {
  const std::string& md = files.front().name == "table1.csv" ? files[1].content : files.front().content;
  const std::size_t begin = md.find("## Ours beside the paper");
  const std::size_t end = md.find("\n## ", begin + 1);
  if (begin != std::string::npos) std::cout << md.substr(begin, end == std::string::npos ? end : end - begin) << '\n';
}

// Prints the study's warnings; fails if any run ended in an internal error.
void report_problems(const Study& study, const std::string& out) {
  bool internal = false;
  for (const RunResult& r : study.sweep) internal = internal || r.internal_error;
  for (const RunResult& r : study.finals) internal = internal || r.internal_error;
  for (const std::string& w : study.warnings) warn(w);
  if (internal) {
    throw InternalError("some runs failed with an internal error (see the warnings above and " + out + "/runs.csv)");
  }
}

// The steps: the sweep (run_sweep), the final runs of the chosen settings, the files of each
// target written at once, figure 3's plots by gnuplot, the comparison with the paper.
int run_experiment(const ExperimentArgs& a) {
  const bool table1 = a.target == "table1" || a.target == "all";
  const bool figure3 = a.target == "figure3" || a.target == "all";
  const bool figure4 = a.target == "figure4" || a.target == "all";
  const std::size_t workers =
      a.jobs != 0 ? a.jobs : std::max<std::size_t>(1, static_cast<std::size_t>(std::thread::hardware_concurrency()));

  experiments::Progress progress;
  Study study;
  study.grids = default_grids();
  study.opt_trials = a.opt_trials;
  study.data_sets = find_data_sets(a.data);
  announce_data_sets(progress, study, a.data);
  create_output_directory(a.out);

  run_sweep(study, table1 || figure4, figure3, workers, progress);
  if (table1 || figure4) {
    choose_and_plan_finals(study, figure4);
    study.finals = run_all(study.data_sets, study.final_specs, workers, progress, "final runs (with bundle numbers)");
    check_finals(study);
  }

  std::vector<OutputFile> files;
  if (table1) {
    for (OutputFile& f : table1_files(study)) files.push_back(std::move(f));
  }
  files.push_back(runs_file(study));
  if (figure3) {
    for (OutputFile& f : figure3_files(study)) files.push_back(std::move(f));
  }
  if (figure4) {
    for (OutputFile& f : figure4_files(study, workers, progress)) files.push_back(std::move(f));
  }

  OutputFiles out;
  for (const OutputFile& f : files) out.write((std::filesystem::path(a.out) / f.name).string(), f.content);
  out.commit();
  std::size_t written = files.size();
  if (figure3) {
    progress.line("figure 3: plotting with gnuplot");
    const std::string problem = run_gnuplot(a.out, "figure3.gp");
    if (problem.empty()) {
      written += 2 * (study.data_sets.size() + 1 + (study.data_sets.size() > 1 ? 1 : 0));
    } else {
      study.warnings.push_back(problem);
    }
  }
  progress.line("wrote " + std::to_string(written) + " files to " + a.out + "/");

  if (table1) print_paper_comparison(files);  // on stdout
  report_problems(study, a.out);
  return kExitOk;
}

}  // namespace

void register_experiment(CLI::App& app, Action& action) {
  auto args = std::make_shared<ExperimentArgs>();
  CLI::App* sub = app.add_subcommand(
      "experiment", "The paper's experiments: Table 1, Figure 3 (weight vs angle bound), Figure 4 (pictures)");
  sub->add_option("TARGET", args->target,
                  "table1 = Table 1 (CSV + Markdown beside the paper), figure3 = DR weight against the angle "
                  "bound (CSV + plots), figure4 = pictures of every method per data set, all = everything")
      ->check(CLI::IsMember({"table1", "figure3", "figure4", "all"}))
      ->required();
  sub->add_option("--data", args->data, "Directory of the data sets (*.poly, *.node; a .poly wins over a .node)")
      ->type_name("DIR")
      ->capture_default_str();
  sub->add_option("--out", args->out, "Directory for the results (created if missing)")
      ->type_name("DIR")
      ->capture_default_str();
  sub->add_option("--jobs", args->jobs, "Worker threads (default: the hardware threads)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{256}));
  sub->add_option("--opt-trials", args->opt_trials,
                  "OPT's iterated local search trials per start, as for triangulate (default min(600, "
                  "300000 / triangles)); fewer is faster, and table1.md says how many were used")
      ->type_name("N")
      ->check(whole_number());
  sub->callback([args, &action] { action = [args] { return run_experiment(*args); }; });
}

}  // namespace mwst::cli
