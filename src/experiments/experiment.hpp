// src/experiments/experiment.hpp — the pieces of `mwst experiment` (the experiments of Boyacı, Erten,
// Üngör, "Triangulations Loosing Bundles and Weight": Table 1, Figure 3, Figure 4), shared by
// cmd_experiment.cpp (the command, the sweep grids), experiment_runner.cpp (data sets, the worker
// pool, progress), experiment_study.cpp (the sweep plan, the choices, the final runs),
// experiment_table1.cpp (table1.csv/.md, runs.csv) and experiment_figures.cpp (figure3.csv +
// gnuplot, figure4 pictures).
//
// Every run is a (data set, TriangulateOptions) pair executed by mwst::triangulate. Runs are
// independent; they are executed by a pool of worker threads and their results stored in the slot
// of their spec, so every output depends only on the list of specs, never on the scheduling.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mwst/io/draw.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::experiments {

// ---- data sets ---------------------------------------------------------------------------------

struct DataSet {
  std::string name;  // file stem, e.g. "Africa"
  std::string path;  // the file read (.poly preferred over .node)
  Pslg pslg;
};

// Every *.poly and *.node in `dir` (a stem with both: the .poly), sorted by name. Throws
// InputError if the directory cannot be read, holds no data set, or a file does not parse.
std::vector<DataSet> find_data_sets(const std::string& dir);

// ---- runs --------------------------------------------------------------------------------------

// The columns of Table 1 (and the panels of Figure 4), in the paper's order plus ours.
enum class Column { kDt, kQtr, kDr, kBrh, kBrhEfh, kOpt };
inline constexpr Column kColumns[] = {Column::kDt, Column::kQtr, Column::kDr,
                                      Column::kBrh, Column::kBrhEfh, Column::kOpt};
inline constexpr std::size_t kColumnCount = 6;
// "DT", "QTR", "DR", "BRH", "BRH+EFH", "OPT".
const char* column_name(Column column);

struct RunSpec {
  std::size_t data_set = 0;  // index into the data sets
  TriangulateOptions options;
  std::string group;         // what progress reports group by, e.g. "dr sweep", "final"
  bool keep_picture = false; // keep a picture of the mesh (Figure 4)
};

struct RunResult {
  bool ok = false;
  bool internal_error = false;  // failed for a reason other than input/options/not implemented
  std::string reason;           // why not ok (the error's message)
  Report report;                // when ok
  std::optional<io::Picture> picture;
  std::vector<std::string> violations;  // validate() of kept meshes (empty = valid)
  double seconds = 0.0;         // wall clock of the run
};

// "dr 12° offcenter", "brh 20° k=12 +efh", "qtr", ... (for progress lines and notes).
std::string describe(const TriangulateOptions& options);

// Progress on stderr: when stderr is a terminal, one status line rewritten after every run (data
// set, method, the run's time, elapsed time); otherwise one line per finished group (data set +
// group) and per phase.
class Progress {
 public:
  Progress();
  bool tty() const { return tty_; }
  double elapsed() const;  // seconds since construction
  // Terminal only: replaces the status line.
  void status(const std::string& text);
  // A line of its own, "mwst: experiment: TEXT" (clears the status line first).
  void line(const std::string& text);
  // Ends the status line (terminal only).
  void done();

 private:
  bool tty_ = false;
  double start_ = 0.0;
  bool status_shown_ = false;
  double last_status_ = 0.0;
};

// Runs every spec on `workers` threads (at least 1); result i belongs to spec i. Never throws for
// a failing run: a run that throws is recorded as not ok with the reason. `phase` names the batch
// in the progress output.
std::vector<RunResult> run_all(const std::vector<DataSet>& data_sets, const std::vector<RunSpec>& specs,
                               std::size_t workers, Progress& progress, const std::string& phase);

// ---- the study: what the sweep found ---------------------------------------------------------

// The sweep grids (see cmd_experiment.cpp for why these values).
struct Grids {
  std::vector<double> dr_angles;                     // Table 1's DR choice (≥ 1°)
  std::vector<double> figure3_angles;                // 0..20
  std::vector<double> brh_angles;                    // A
  std::vector<std::size_t> brh_ks;                   // K (0 = ⌈720/A⌉ + 3)
};

// All runs of one data set for one Table 1 column, and the one chosen (lightest interior weight
// among the finished runs; ties to the earliest spec), or none.
struct ColumnChoice {
  std::vector<std::size_t> runs;   // spec indices
  std::optional<std::size_t> chosen;
  std::string reason;              // why there is no choice (first failure's reason)
};

struct Study {
  std::vector<DataSet> data_sets;
  Grids grids;
  std::size_t opt_trials = kDefaultOptTrials;  // OPT's trials per start (TriangulateOptions::opt_trials)
  std::vector<RunSpec> sweep_specs;
  std::vector<RunResult> sweep;
  // [data set][column]
  std::vector<std::vector<ColumnChoice>> choices;
  // Final runs: the chosen options again with the bundle number (and a picture). [data set][column]
  std::vector<std::vector<std::optional<std::size_t>>> final_index;  // index into final_specs
  std::vector<RunSpec> final_specs;
  std::vector<RunResult> finals;
  // DT's interior weight per data set (the normaliser), if DT ran.
  std::vector<std::optional<double>> dt_interior;
  std::vector<std::string> warnings;
};

// Interior weight of a run normalised to DT = 100, or nullopt.
std::optional<double> normalised(const Study& study, std::size_t data_set, const RunResult& run);

// Builds the sweep specs for the targets (table1/figure4 need the full sweep; figure3 alone only DT
// and the DR angles 0..20).
void plan_sweep(Study& study, bool full_sweep, bool figure3);
// Chooses per column after the sweep ran, and plans the final runs.
void choose_and_plan_finals(Study& study, bool pictures);
// After the final runs: compares them to their sweep runs (determinism) and collects warnings.
void check_finals(Study& study);

// ---- outputs (text of the files) ---------------------------------------------------------------

struct OutputFile {
  std::string name;     // file name inside the output directory
  std::string content;
};

std::vector<OutputFile> table1_files(const Study& study);   // table1.csv, table1.md
OutputFile runs_file(const Study& study);                    // runs.csv (every run)
std::vector<OutputFile> figure3_files(const Study& study);  // figure3.csv, figure3.gp
// The Figure 4 pictures (figure4_NAME.png/.pdf), rendered on `workers` threads.
std::vector<OutputFile> figure4_files(const Study& study, std::size_t workers, Progress& progress);

// Runs gnuplot on figure3.gp in `out_dir`. Returns an empty string on success, else a warning.
std::string run_gnuplot(const std::string& out_dir, const std::string& script);

// ---- formatting helpers ------------------------------------------------------------------------
std::string fixed(double value, int digits);
std::string angle_text(double degrees);  // "12" or "12.5"

}  // namespace mwst::experiments
