// src/cli/commands.hpp — how the `mwst` subcommands plug into the command line, and the helpers
// they share (exit codes, warnings, output files that vanish on failure, the default prefix).
//
// Adding a subcommand `mwst NAME`: write src/cli/cmd_NAME.cpp defining
//     void register_NAME(CLI::App& app, Action& action);
// which adds the subcommand and its options to `app` and, in the subcommand's parse callback,
// stores in `action` what to run once parsing is done (so that errors in the run are not mistaken
// for usage errors). Declare it below and add it to kCommands in main.cpp. The action returns the
// exit code; errors are thrown and turned into exit codes in one place (main.cpp):
//   InputError → 1, printed as "mwst: FILE:LINE: what is wrong" (exactly one line);
//   UsageError, std::invalid_argument, CLI11 parse errors → 2;
//   ResourceError, std::bad_alloc (memory ran out: the --max-memory budget) → 4;
//   InternalError and anything else → 3.
// Nothing may be written to an output file before all computation succeeded: collect outputs in
// an OutputFiles and commit() at the end.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/arrays.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/io/triangle_files.hpp"

namespace mwst::cli {

// Exit codes of the command-line contract (docs/DESIGN.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 1;  // also: `mwst check` found violations
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInternal = 3;
inline constexpr int kExitResource = 4;  // out of memory, or a request that cannot fit (--max-memory)

// What a subcommand runs after a successful parse; returns the exit code.
using Action = std::function<int()>;

// A subcommand's registration function (see above).
using Registrar = void (*)(CLI::App& app, Action& action);

void register_triangulate(CLI::App& app, Action& action);  // cmd_triangulate.cpp
void register_check(CLI::App& app, Action& action);        // cmd_check.cpp
void register_generate(CLI::App& app, Action& action);     // cmd_generate.cpp
void register_bundle(CLI::App& app, Action& action);       // cmd_bundle.cpp
void register_draw(CLI::App& app, Action& action);          // cmd_draw.cpp
void register_experiment(CLI::App& app, Action& action);    // cmd_experiment.cpp
void register_triangle(CLI::App& app, Action& action);      // cmd_triangle.cpp

// Bad usage found after parsing (an option value no method can use, an output that would
// overwrite the input, a feature not implemented yet): exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Checks of numeric option values whose failure is one short line naming the value found, e.g.
// "mwst: --max-steiner: must be a whole number >= 0, found '-1'" (CLI11's NonNegativeNumber and
// PositiveNumber print their upper bound, DBL_MAX, in all its 309 digits).
CLI::Validator whole_number();                      // decimal digits only, at most 2^64 - 1
CLI::Validator number_above(double low);            // a finite number > low
CLI::Validator number_in(double low, double high);  // a finite number in [low, high)

// The library's messages name the fields of TriangulateOptions ("min_angle_deg must be in [0, 60)
// degrees"); each command names its own flags. The one table of how each spells each field:
enum class Spelling { kTriangulate, kTriangle };
struct FieldFlags {
  std::string_view field;        // TriangulateOptions' member
  std::string_view triangulate;  // `mwst triangulate`'s flag ("" if none)
  std::string_view triangle;     // `mwst triangle`'s switch ("" if none)
};
inline constexpr FieldFlags kFieldFlags[] = {
    {"min_angle_deg", "--min-angle", "-q"},
    {"max_area", "--max-area", "-a"},
    {"max_steiner", "--max-steiner", "-S"},
    {"time_budget_seconds", "--time-limit", ""},
    {"bundle_k", "--bundle-k", ""},
    {"steiner", "--steiner", ""},
    {"convex_hull", "--convex-hull", "-c"},
    {"strict", "--strict", ""},
    {"opt_trials", "--opt-trials", ""},
    {"exact_polish", "--exact-polish", ""},
    {"memory_budget_bytes", "--max-memory", ""},
    {"threads", "--threads", ""},
    {"conforming_delaunay", "", "-D"},
    {"segment_splitting", "", "-Y"},
    {"regional_area_limits", "", "-a"},
};
// `message` with every field name of kFieldFlags (as a whole word) replaced by the flag that
// `spelling`'s command has for it (fields it has no flag for stay as they are).
std::string with_flag_names(std::string_view message, Spelling spelling);
// The field of kFieldFlags that `mwst triangulate` spells `flag` ("--min-angle" → "min_angle_deg"),
// or "" if it spells none.
std::string_view field_of_triangulate_flag(std::string_view flag);

// "mwst: warning: MESSAGE" on stderr.
void warn(std::string_view message);

// Triangle's default output prefix: the input path without its extension, with its iteration
// number incremented if the name ends in one ("foo.1.poly" → "foo.2"), else plus ".1"
// ("data/Africa.poly" → "data/Africa.1").
std::string default_prefix(const std::string& input);
// The same for a name without its extension: "foo.1" → "foo.2", "foo" → "foo.1".
std::string next_iteration(const std::string& stem);

// Throws UsageError if writing `output` would replace the file `input`.
void refuse_overwrite(const std::string& input, const std::string& output);

// Files written by one command: each is written atomically (temporary name, rename); if the
// command fails before commit(), the destructor removes every file written so far, so a failure
// leaves no output behind.
class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();

  void write(const std::string& path, std::string_view content);
  // PREFIX + extension of each of `files` (io::write_triangle_files: two at a time, none left
  // behind if one fails).
  void write_files(const std::string& prefix, const std::vector<io::TriangleFile>& files);
  // PREFIX.node, PREFIX.ele and, if the mesh has subsegments, PREFIX.poly (io::mesh_files,
  // formatted by io::format_triangle_files). A stale PREFIX.poly from an earlier run is removed at
  // commit() when the mesh has none. The .poly lists the input's `holes` and `regions` too.
  void write_mesh(const MeshArrays& mesh, const std::string& prefix, int first_index,
                  const std::vector<Point>& holes = {}, const std::vector<Region>& regions = {});
  // `path` "-" means standard output, printed at commit() (after every file is in place).
  void write_json(const std::string& path, const nlohmann::json& json);
  void commit();
  const std::vector<std::string>& written() const { return written_; }

 private:
  std::vector<std::string> written_;
  std::vector<std::string> remove_at_commit_;
  std::string stdout_text_;
  bool committed_ = false;
};

// ---- limits (limits.cpp) -------------------------------------------------------------------------

// A byte count as --max-memory takes it: a positive number with an optional suffix K, M, G or T
// (powers of 1024): "512M", "1.5G", "100000". std::nullopt if it is none.
std::optional<double> parse_bytes(std::string_view text);
CLI::Validator byte_count();
// 75% of the machine's memory (MemTotal), or the process's address-space limit or its control
// group's memory limit if lower; 0 if none is known.
double default_memory_budget();
// Makes `bytes` the process's address-space limit (RLIMIT_AS; not in sanitizer builds), so that
// allocating past it throws std::bad_alloc, and remembers it for memory_budget() and the message.
void set_memory_budget(double bytes);
double memory_budget();

// ---- allocation policies (large_allocations.cpp) ------------------------------------------------

// From now on every operator new of 4 MiB or more starts on a 2 MiB boundary and its first half is
// advised transparent huge pages (one fault per 2 MiB of a fresh mapping instead of one per 4 KiB; values
// unchanged). Call before any thread starts. Sanitizer builds: no effect.
void advise_huge_pages_for_large_allocations();

// Whether it was asked for (and is in effect).
bool huge_pages_for_large_allocations();

// The meshing commands' heap (`mwst triangulate`, `mwst triangle`), set up for one run of a
// process: every thread allocates from glibc's one main heap (not an arena of its own each), which
// keeps the blocks below 1 MiB (glibc's adaptive threshold moves up to 32 MiB as mapped blocks are
// freed) and is never trimmed: what one phase frees, the next writes again without faulting in
// fresh pages. Each first write to a fresh 4 KiB page traps into the kernel, about 9 µs on a
// virtual machine; DR on 20,000 points on an ellipse faulted in ~3,300 pages, a fifth of its CPU
// (now ~2,900). Growing the heap by 64 MiB at a time, or advising it transparent huge pages,
// saved more but put 4-9 MB more at the peak of 40k-point runs (bench/README.md). Call once,
// before any thread starts. Sanitizer builds and other C libraries: no effect.
void use_one_heap();

// When the process started (its static initialisation, before main): --time-limit counts from here.
std::chrono::steady_clock::time_point process_start();

// The progress line (format_progress of mwst/algorithms/pipeline.hpp) of a run longer than
// kProgressAfterSeconds, on stderr, redrawn in place every 0.2 s by a thread of its own, and only
// when stderr is a terminal and `enabled` (not --quiet). callback() is what
// TriangulateOptions::progress takes (empty when there is no line); finish() clears the line.
inline constexpr double kProgressAfterSeconds = 2.0;
class ProgressLine {
 public:
  explicit ProgressLine(bool enabled);
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ~ProgressLine();
  ProgressCallback callback();
  void finish();

 private:
  struct State;
  std::shared_ptr<State> state_;
  std::thread ticker_;
};

}  // namespace mwst::cli
