// algorithms/pipeline/phases.hpp — what the phases of triangulate() share (internal): the clock,
// a phase's timer, the time budget as it runs down, progress announcements, counted words for
// warnings, and the start mesh of Triangle's -r (start_mesh.cpp).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::phases {

using Clock = std::chrono::steady_clock;


// Times one phase: the seconds from construction to finish() are appended to the report.
class Phase {
 public:
  Phase(Report& report, std::string name) : report_(report), name_(std::move(name)), start_(Clock::now()) {}
  void finish() {
    report_.seconds.emplace_back(std::move(name_),
                                 std::chrono::duration<double>(Clock::now() - start_).count());
  }

 private:
  Report& report_;
  std::string name_;
  Clock::time_point start_;
};

// What is left of TriangulateOptions::time_budget_seconds, counted from `start`, in seconds — never
// 0, which would mean no budget — or -1 (none) without a budget.
inline double budget_left(const TriangulateOptions& options, Clock::time_point start) {
  if (!(options.time_budget_seconds > 0.0)) return -1.0;
  const double used = std::chrono::duration<double>(Clock::now() - start).count();
  return std::max(options.time_budget_seconds - used, 1e-9);
}

inline bool budget_spent(const TriangulateOptions& options, Clock::time_point start) {
  return options.time_budget_seconds > 0.0 &&
         std::chrono::duration<double>(Clock::now() - start).count() >= options.time_budget_seconds;
}

// Tells TriangulateOptions::progress that `phase`, step `done` of `total`, begins.
inline void announce(const TriangulateOptions& options, Clock::time_point start, std::string_view phase, std::size_t done,
              std::size_t total) {
  if (!options.progress) return;
  Progress p;
  p.method = method_name(options.method);
  p.phase = phase;
  p.done = done;
  p.total = total;
  p.elapsed_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (options.time_budget_seconds > 0.0) p.seconds_left = std::max(0.0, options.time_budget_seconds - p.elapsed_seconds);
  options.progress(p);
}

// "1 triangle", "3 triangles".
inline std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The carved constrained Delaunay triangulation every method except QTR starts from. Phases
// "delaunay", "segments", "carve"; its warnings (duplicates, crossings, ...) go to the report.
Mesh constrained_delaunay_phase(const Pslg& pslg, const TriangulateOptions& options, Report& report);

// Refuses (ResourceError) an area bound whose mesh cannot fit in options.memory_budget_bytes.
void check_memory_for_area_bound(const Mesh& cdt, const TriangulateOptions& options);

// The refinement options of a run: its bounds where the method reads them, its budgets (what is
// left of the time budget), the segment rules. A phase changes what it needs.
RefineOptions refine_options_for(const TriangulateOptions& options, Clock::time_point start);

// Bundle removal (BRH) on the mesh, with the run's options: phase "brh".
void brh_phase(Mesh& mesh, const TriangulateOptions& options, Clock::time_point start, Report& report);

// Our optimiser (method opt): opt's multistart over the CDT of the input, phase "optimize"
// (optimize/multistart.cpp).
Mesh optimize_phase(const Pslg& pslg, const TriangulateOptions& options, Clock::time_point start, Report& report);

// The start mesh of Triangle's -r: the triangulation Pslg::triangles gives, validated (an InputError
// names the first problem); start_mesh.cpp says what it checks and how it is built. Fills
// report.start and its warnings.
Mesh mesh_from_triangles(const Pslg& pslg, bool make_delaunay, unsigned threads, Report& report);

}  // namespace mwst::phases
