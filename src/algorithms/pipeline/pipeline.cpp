// triangulate() (mwst/algorithms/pipeline.hpp): runs one of the methods compared in Boyacı,
// Erten, Üngör, "Triangulations Loosing Bundles and Weight" (DT, QTR, DR, BRH, BRH+EFH) or our own
// optimiser on an input graph, times each phase and measures the result (weight split into
// boundary and interior as the paper's Table 1 reports it, angle range).
//
// Adding a method: write its entry point in its own file, then add one case to the switch in
// triangulate() that runs it between the `Phase` markers and fills the Report (stop_reason,
// warnings, and its method-specific summary; mwst/io/report.hpp prints it).
#include "mwst/algorithms/pipeline.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <numeric>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>

#include "mwst/algorithms/arrays.hpp"
#include "mwst/algorithms/brh.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/quadtree.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/version.hpp"
#include "algorithms/pipeline/phases.hpp"
#include "support/parallel.hpp"
#include "support/time_budget.hpp"
#include "algorithms/triangle_key.hpp"

namespace mwst {

namespace {

using namespace phases;

// "1.5 GiB", "300 MiB".
std::string bytes_text(double bytes) {
  constexpr double kMiB = 1024.0 * 1024.0, kGiB = 1024.0 * kMiB;
  char buf[64];
  if (bytes >= kGiB) {
    std::snprintf(buf, sizeof buf, "%.3g GiB", bytes / kGiB);
  } else {
    std::snprintf(buf, sizeof buf, "%.3g MiB", bytes / kMiB);
  }
  return buf;
}

}  // namespace

// Refuses an area bound whose mesh cannot fit in the memory budget, before any refinement: every
// domain triangle has area at most max_area, so there are at least area / max_area of them, and
// refinement makes about twice that (its triangles are not all as large as the bound).
void phases::check_memory_for_area_bound(const Mesh& cdt, const TriangulateOptions& options) {
  if (!(options.max_area > 0.0) || !(options.memory_budget_bytes > 0.0)) return;
  const double area = cdt.domain_area();
  const double least = area / options.max_area;  // a lower bound on the triangles
  const double expected = 2.0 * least;
  if (!(estimated_bytes(options.method, least) > options.memory_budget_bytes)) return;
  char text[256];
  std::snprintf(text, sizeof text, "max_area %g on a domain of area %g would make about %.3g triangles (at least %.3g), ",
                options.max_area, area, expected, least);
  throw ResourceError(std::string(text) + "needing about " + bytes_text(estimated_bytes(options.method, expected)) +
                      ", more than the memory budget of " + bytes_text(options.memory_budget_bytes) +
                      " (memory_budget_bytes): give a larger max_area, or a larger memory_budget_bytes if the machine has it");
}


// The carved constrained Delaunay triangulation every method except QTR starts from. Phases
// "delaunay", "segments", "carve" (as constrained_delaunay measures them).
Mesh phases::constrained_delaunay_phase(const Pslg& pslg, const TriangulateOptions& options, Report& report) {
  ConstrainOptions constrain;
  constrain.strict = options.strict;
  constrain.convex_hull = options.convex_hull;
  constrain.threads = options.threads;
  ConstrainStats stats;
  Mesh mesh = constrained_delaunay(pslg, constrain, &stats);
  report.seconds.emplace_back("delaunay", stats.seconds_delaunay);
  if (!pslg.segments.empty()) {
    report.seconds.emplace_back("segments", stats.seconds_segments);
    report.seconds.emplace_back("carve", stats.seconds_carve);
  }
  report.duplicates = stats.duplicates;
  report.crossings = stats.crossings;
  if (stats.duplicates > 0) {
    report.warnings.push_back(plural(stats.duplicates, "duplicate point", "duplicate points") + " merged");
  }
  if (stats.zero_length > 0) {
    report.warnings.push_back(plural(stats.zero_length, "segment", "segments") +
                              " of zero length (both ends at the same point) dropped");
  }
  if (stats.crossings > 0) {
    report.warnings.push_back("crossing segments split at " +
                              plural(stats.crossings, "intersection point", "intersection points") +
                              " (the option strict refuses them)");
  }
  if (stats.overlaps > 0) {
    report.warnings.push_back(plural(stats.overlaps, "overlapping collinear segment piece",
                                     "overlapping collinear segment pieces") + " merged");
  }
  for (std::string& w : stats.warnings) report.warnings.push_back(std::move(w));
  return mesh;
}


// The refinement options of a run, made here only: the angle and area bounds and the Steiner rule
// where the method reads them (method_reads_option; otherwise no bound), the Steiner budget, what
// is left of the time budget, and the segment rules (-Y, -D). A phase then changes what it needs.
RefineOptions phases::refine_options_for(const TriangulateOptions& options, Clock::time_point start) {
  RefineOptions r;
  r.min_angle_deg = method_reads_option(options.method, "min_angle_deg") ? options.min_angle_deg : 0.0;
  if (method_reads_option(options.method, "max_area")) r.max_area = options.max_area;
  if (method_reads_option(options.method, "steiner")) r.rule = options.steiner;
  r.max_steiner = options.max_steiner;
  r.time_budget_seconds = budget_left(options, start);
  r.time_reserve_per_vertex = options.time_reserve_per_vertex;
  r.segment_splitting = options.segment_splitting;
  r.conforming_delaunay = options.conforming_delaunay;
  return r;
}

namespace {

// Delaunay refinement (Ruppert / Chew / Shewchuk with Üngör's off-centers): phase "refine".
void refine_phase(Mesh& mesh, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  const RefineOptions refine_options = refine_options_for(options, start);
  Phase phase(report, "refine");
  const RefineStats stats = refine(mesh, refine_options);
  phase.finish();
  report.stop = stats.stop;
  report.refine = RefineSummary{stats.steiner_inserted, stats.segment_splits, stats.left_small_angle, std::nullopt};
  if (options.segment_splitting != SegmentSplitting::kAllowed) report.refine->left_protected = stats.left_protected;
}

// Conforming Delaunay without refinement (dt with Triangle's -D): only the subsegments that are not
// locally Delaunay are split (refine with no bound and RefineOptions::conforming_delaunay). Phase
// "conform".
void conform_phase(Mesh& mesh, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  RefineOptions refine_options = refine_options_for(options, start);
  refine_options.conforming_delaunay = true;
  Phase phase(report, "conform");
  const RefineStats stats = refine(mesh, refine_options);
  phase.finish();
  report.conform = ConformSummary{stats.segment_splits};
  if (stats.stop.kind != StopKind::kBoundReached) {
    report.warnings.push_back("conforming Delaunay stopped: " + to_string(stats.stop));
  }
}

// The edges of the final mesh that are not locally Delaunay (exact incircle across every edge with
// finite triangles on both sides, subsegments included): 0 for a conforming Delaunay mesh.
std::size_t non_delaunay_edges(const Mesh& mesh) {
  std::size_t count = 0;
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.is_dead(t) || mesh.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const TriangleId u = mesh.sym(h) >> 2;
      if (u < t || mesh.is_ghost(u) || (!mesh.in_domain(t) && !mesh.in_domain(u))) continue;
      if (mesh.is_locally_non_delaunay(h) || mesh.is_locally_non_delaunay(mesh.sym(h))) ++count;
    }
  }
  return count;
}

// Triangle's -a without a number: each region's max_area bounds the domain triangles its seed
// reaches (region_of_triangles: a later region wins); kept in Mesh::area_bound, which refinement
// hands down to the triangles it makes. A seed outside the domain is an InputError.
void apply_regional_area_limits(Mesh& mesh, const Pslg& pslg) {
  const std::vector<std::int32_t> region = region_of_triangles(mesh, pslg.regions, pslg.source);
  if (mesh.area_bound.empty()) mesh.area_bound.assign(mesh.triangle_slots(), -1.0);
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (region[t] >= 0) mesh.area_bound[t] = pslg.regions[static_cast<std::size_t>(region[t])].max_area;
  }
}

}  // namespace

// Bundle removal (BRH): phase "brh".
void phases::brh_phase(Mesh& mesh, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  BrhOptions brh;
  brh.min_angle_deg = options.min_angle_deg;
  brh.bundle_k = options.bundle_k != 0 ? options.bundle_k : default_bundle_k(options.min_angle_deg);
  brh.refine = refine_options_for(options, start);  // (its angle bound is brh.min_angle_deg)
  brh.threads = options.threads;
  Phase phase(report, "brh");
  if (!mesh.area_bound.empty()) {
    // The mesh's own area bounds first (bundle_removal's own area pass reads max_area only); its
    // passes then test the bounds of every triangle they make.
    RefineOptions area = brh.refine;
    area.min_angle_deg = 0.0;
    const RefineStats rs = refine(mesh, area);
    if (brh.refine.max_steiner != static_cast<std::size_t>(-1)) {
      brh.refine.max_steiner -= std::min(brh.refine.max_steiner, rs.steiner_inserted + rs.segment_splits);
    }
    brh.refine.time_budget_seconds = budget_left(options, start);
    if (brh.refine.time_budget_seconds > 0.0) {  // (the time set aside for this pass's vertices)
      brh.refine.time_budget_seconds = std::max(
          brh.refine.time_budget_seconds - options.time_reserve_per_vertex * static_cast<double>(rs.steiner_inserted + rs.segment_splits),
          1e-9);
    }
  }
  const BrhStats stats = bundle_removal(mesh, brh);
  phase.finish();
  report.stop = stats.stop;
  report.brh = BrhSummary{brh.bundle_k,           stats.rounds,         stats.exact_evaluations,
                          stats.steiner_inserted, stats.segment_splits, stats.skinny_left};
}

namespace {

// Weight-reducing flips (EFH) after any method: phase "flip". The area bound of a method that
// reads it (dr, brh, opt) holds after the flips too: no flip makes a triangle larger than it.
// Under the time budget of a method that reads it the flips stop at it (flip.hpp: the mesh valid, the flips of largest gain
// done), and the stop reason is then "time budget".
void flip_phase(Mesh& mesh, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  Phase phase(report, "flip");
  const double max_area = method_reads_option(options.method, "max_area") ? options.max_area : -1.0;
  const bool timed = options.time_budget_seconds > 0.0 && method_reads_option(options.method, "time_budget_seconds");
  const FlipStats stats = timed
                              ? flip_to_local_minimum(mesh, max_area, detail::deadline_after(start, options.time_budget_seconds))
                              : flip_to_local_minimum(mesh, max_area);
  if (stats.out_of_time) report.stop = StopReason{StopKind::kTimeBudget, 0, {}};
  phase.finish();
  report.flip = FlipSummary{stats.flips, stats.weight_before, stats.weight_after};
}

}  // namespace

std::string_view method_name(Method method) {
  switch (method) {
    case Method::kDt: return "dt";
    case Method::kDr: return "dr";
    case Method::kBrh: return "brh";
    case Method::kQtr: return "qtr";
    case Method::kOpt: return "opt";
  }
  throw InternalError("method_name: unknown method");
}

std::optional<Method> parse_method(std::string_view name) {
  for (const Method m : {Method::kDt, Method::kDr, Method::kBrh, Method::kQtr, Method::kOpt}) {
    if (method_name(m) == name) return m;
  }
  return std::nullopt;
}

std::string_view steiner_rule_name(SteinerRule rule) {
  switch (rule) {
    case SteinerRule::kOffCenter: return "offcenter";
    case SteinerRule::kCircumcenter: return "circumcenter";
  }
  throw InternalError("steiner_rule_name: unknown rule");
}

std::optional<SteinerRule> parse_steiner_rule(std::string_view name) {
  if (name == "offcenter") return SteinerRule::kOffCenter;
  if (name == "circumcenter") return SteinerRule::kCircumcenter;
  return std::nullopt;
}

std::string format_progress(const Progress& p) {
  std::string line = "mwst: ";
  line += p.method;
  line += ": ";
  line += p.phase;
  if (p.total > 0) line += " (" + std::to_string(std::min(p.done + 1, p.total)) + "/" + std::to_string(p.total) + ")";
  char buf[96];
  std::snprintf(buf, sizeof buf, ", %.1f s", p.elapsed_seconds);
  line += buf;
  if (p.seconds_left >= 0.0) {
    std::snprintf(buf, sizeof buf, ", at most %.1f s left", p.seconds_left);
    line += buf;
  }
  return line;
}

// Peak resident bytes per output triangle of `mwst triangulate --max-area` (the whole process: the
// mesh, the refinement's queues, the output text), measured on the unit square: dr and brh at
// 1e-6 (1.55M triangles, 159 and 161 MB: 102 and 104 bytes each), opt at 1e-5 (140k triangles,
// 49 MB, 290 bytes each beyond the process's 8 MB: it keeps the CDT, its starts and their copies).
// Rounded down, so that with the lower bound area / max_area on the triangles a request refused
// by check_memory_for_area_bound cannot fit.
double estimated_bytes(Method method, double triangles) {
  const double per_triangle = method == Method::kOpt ? 250.0 : 100.0;
  return per_triangle * triangles;
}

std::size_t default_bundle_k(double min_angle_deg) {
  if (!(min_angle_deg > 0.0)) {
    throw std::invalid_argument("the default bundle size ceil(4*pi/alpha)+3 needs min_angle_deg > 0; "
                                "give bundle_k");
  }
  // 4π/α with α in radians is 720/deg with deg in degrees.
  return static_cast<std::size_t>(std::ceil(720.0 / min_angle_deg)) + 3;
}

void check_options(const TriangulateOptions& o) {
  if (!(o.min_angle_deg >= 0.0 && o.min_angle_deg < 60.0)) {
    throw std::invalid_argument("min_angle_deg must be in [0, 60) degrees");
  }
  if (std::isnan(o.max_area) || std::isinf(o.max_area)) {
    throw std::invalid_argument("max_area must be a finite number");
  }
  if (std::isnan(o.time_budget_seconds)) throw std::invalid_argument("time_budget_seconds must be a number");
  if (o.bundle_k == 1 || o.bundle_k == 2) {
    // Every triangle with a vertex-empty disk inside it is a 1-bundle; two neighbours a 2-bundle.
    throw std::invalid_argument("bundle_k must be at least 3 (0 = the default from the angle)");
  }
  if (o.conforming_delaunay && o.flip) {
    // The weight-reducing flips would undo the Delaunay property.
    throw std::invalid_argument("conforming_delaunay and flip exclude each other");
  }
}

bool method_reads_option(Method method, std::string_view option) {
  const bool refinement = option == "min_angle_deg" || option == "steiner" || option == "max_area" ||
                          option == "max_steiner" || option == "time_budget_seconds";
  const bool bundle_size = option == "bundle_k";
  const bool optimiser = option == "exact_polish" || option == "opt_trials";
  if (!refinement && !bundle_size && !optimiser) return true;
  switch (method) {
    case Method::kDt: return false;
    case Method::kQtr: return option == "time_budget_seconds";
    case Method::kDr: return refinement;
    case Method::kBrh: return refinement || bundle_size;
    case Method::kOpt: return true;
  }
  throw InternalError("method_reads_option: unknown method");
}

double Report::total_seconds() const {
  double total = 0.0;
  for (const auto& phase : seconds) total += phase.second;
  return total;
}

namespace {

// The combinations of the Triangle switches and methods that triangulate() refuses: an existing
// triangulation is refined by dt, dr and brh only; regional area limits need refinement (dr, brh);
// conforming Delaunay is made by dt and dr; protected segments hold for every method that only adds
// points through Delaunay refinement (dt, dr, brh).
void check_method_supports_options(const Pslg& pslg, const TriangulateOptions& options) {
  if (!pslg.triangles.empty() && (options.method == Method::kQtr || options.method == Method::kOpt)) {
    throw std::invalid_argument("an existing triangulation (Pslg::triangles) is refined by the methods dt, dr and "
                                "brh only, not " + std::string(method_name(options.method)));
  }
  const bool refining = options.method == Method::kDr || options.method == Method::kBrh;
  if (options.regional_area_limits && !refining) {
    throw std::invalid_argument("regional_area_limits is supported by the methods dr and brh only, not " +
                                std::string(method_name(options.method)));
  }
  if (options.conforming_delaunay && options.method != Method::kDt && options.method != Method::kDr) {
    throw std::invalid_argument("conforming_delaunay is supported by the methods dt and dr only, not " +
                                std::string(method_name(options.method)));
  }
  if (options.segment_splitting != SegmentSplitting::kAllowed && !refining && options.method != Method::kDt) {
    throw std::invalid_argument("segment_splitting other than kAllowed is supported by the methods dt, dr and brh only, "
                                "not " + std::string(method_name(options.method)));
  }
}

// Quadtree refinement (include/mwst/algorithms/quadtree.hpp): phases "input", "quadtree", "mesh",
// "carve". It cleans the input with the CDT itself. Out of time it returns the carved CDT of the
// input, and the stop reason is "time budget".
Mesh quadtree_phase(const Pslg& pslg, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  QuadtreeOptions quadtree_options;
  quadtree_options.convex_hull = options.convex_hull;
  quadtree_options.strict = options.strict;
  quadtree_options.max_leaves = options.quadtree_max_leaves;
  // QuadtreeOptions::threads: 1 is one thread, 0 two on large inputs (its most).
  quadtree_options.threads = options.threads == 1 ? 1u : 0u;
  quadtree_options.deadline = detail::deadline_after(start, options.time_budget_seconds);
  quadtree_options.time_reserve_per_vertex = options.time_reserve_per_vertex;
  QuadtreeStats qs;
  Mesh mesh = quadtree_refinement(pslg, quadtree_options, &qs);
  report.seconds.emplace_back("input", qs.seconds_input);
  report.seconds.emplace_back("quadtree", qs.seconds_tree);
  report.seconds.emplace_back("mesh", qs.seconds_mesh);
  report.seconds.emplace_back("carve", qs.seconds_carve);
  report.duplicates = qs.input.duplicates;
  report.crossings = qs.input.crossings;
  if (qs.input.duplicates > 0) {
    report.warnings.push_back(plural(qs.input.duplicates, "duplicate point", "duplicate points") + " merged");
  }
  if (qs.input.crossings > 0) {
    report.warnings.push_back("crossing segments split at " +
                              plural(qs.input.crossings, "intersection point", "intersection points"));
  }
  for (std::string& w : qs.input.warnings) report.warnings.push_back(std::move(w));
  for (std::string& w : qs.warnings) report.warnings.push_back(std::move(w));
  report.qtr = QuadtreeSummary{qs.leaves, qs.depth, qs.warped, qs.snapped, qs.crossings, qs.centres, qs.fallback};
  if (qs.out_of_time) report.stop.kind = StopKind::kTimeBudget;
  return mesh;
}

// The exact bundle number of the result (mwst/algorithms/bundle.hpp), with a witness disk, within
// what is left of the time budget (past it the report has no bundle number, and a warning says
// why): phase "bundle".
void bundle_phase(const Mesh& mesh, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  Phase phase(report, "bundle");
  BundleOptions bundle_options;
  bundle_options.deadline = detail::deadline_after(start, options.time_budget_seconds);
  bundle_options.threads = options.threads;
  try {
    const BundleResult bundle = bundle_number(mesh, bundle_options);
    report.bundle = BundleSummary{bundle.bundle_number, bundle.disk_center, bundle.disk_radius, bundle.circumdisk_bound};
  } catch (const KBundleTimeout&) {
    report.warnings.push_back("the bundle number was not computed: the time budget (time_budget_seconds) ran out");
  }
  phase.finish();
}

// The metrics of the final mesh (weights, angles, largest area): phase "measure".
void measure_phase(const Mesh& mesh, Report& report) {
  Phase phase(report, "measure");
  const Metrics metrics = measure(mesh);
  phase.finish();
  report.vertices = metrics.vertices;
  report.triangles = metrics.triangles;
  report.steiner = metrics.steiner;
  report.weight_total = metrics.weight_total;
  report.weight_boundary = metrics.weight_boundary;
  report.weight_interior = metrics.weight_interior;
  report.min_angle = metrics.min_angle_deg;
  report.max_angle = metrics.max_angle_deg;
  report.max_triangle_area = metrics.max_triangle_area;
  if (metrics.triangles == 0) {
    report.warnings.push_back("the domain is empty: the segments enclose no region outside the holes "
                              "(convex_hull keeps the whole hull)");
  }
}

}  // namespace

Report triangulate(const Pslg& pslg, const TriangulateOptions& options, Mesh* out) {
  check_options(options);
  check_method_supports_options(pslg, options);
  const Clock::time_point start = Clock::now();
  Report report;
  report.input = pslg.source;
  report.method = std::string(method_name(options.method));
  report.options = options;

  // Phases of the progress line: the input's triangulation, the method, the flips, the bundle number.
  const std::size_t phases = 2 + (options.flip ? 1 : 0) + (options.bundle ? 1 : 0);
  std::size_t phase_number = 0;
  announce(options, start, "delaunay", phase_number++, phases);
  // The start of dt, dr and brh: the given triangulation (Triangle's -r), else the carved CDT.
  const auto start_mesh = [&] {
    if (pslg.triangles.empty()) return constrained_delaunay_phase(pslg, options, report);
    Phase phase(report, "start");
    Mesh m = mesh_from_triangles(pslg, options.method != Method::kDt || options.conforming_delaunay, options.threads, report);
    phase.finish();
    return m;
  };
  Mesh mesh;
  switch (options.method) {
    case Method::kDt:
      mesh = start_mesh();
      if (options.conforming_delaunay) conform_phase(mesh, options, start, report);
      break;
    case Method::kDr:
      mesh = start_mesh();
      if (options.regional_area_limits) apply_regional_area_limits(mesh, pslg);
      check_memory_for_area_bound(mesh, options);
      announce(options, start, "refine", phase_number++, phases);
      refine_phase(mesh, options, start, report);
      break;
    case Method::kBrh:
      mesh = start_mesh();
      if (options.regional_area_limits) apply_regional_area_limits(mesh, pslg);
      check_memory_for_area_bound(mesh, options);
      announce(options, start, "brh", phase_number++, phases);
      brh_phase(mesh, options, start, report);
      break;
    case Method::kQtr:
      announce(options, start, "quadtree", phase_number++, phases);
      mesh = quadtree_phase(pslg, options, start, report);
      break;
    case Method::kOpt:
      announce(options, start, "optimize", phase_number++, phases);
      mesh = phases::optimize_phase(pslg, options, start, report);
      break;
  }
  if (options.flip) {
    announce(options, start, "flip", phase_number++, phases);
    flip_phase(mesh, options, start, report);
  }
  // The stop reason the final mesh bears out (the flips, opt's moves and the budgets included).
  if (options.method == Method::kDr || options.method == Method::kBrh || options.method == Method::kOpt) {
    report.stop = settle_stop_reason(mesh, options, report.stop, options.flip,
                                     detail::deadline_after(start, options.time_budget_seconds));
  }
  if (options.bundle) {
    announce(options, start, "bundle", phase_number++, phases);
    bundle_phase(mesh, options, start, report);
  }
  if (options.conforming_delaunay) {
    const std::size_t bad = non_delaunay_edges(mesh);
    if (bad > 0) {
      report.warnings.push_back(plural(bad, "edge is", "edges are") +
                                " not Delaunay: conforming Delaunay was not reached (see the stop reason)");
    }
  }
  if (report.stop.kind == StopKind::kLeftBelowBound) {
    report.warnings.push_back(plural(report.stop.count, "triangle does", "triangles do") +
                              " not meet the bounds: refinement could not place their Steiner points (double "
                              "precision, or the supported coordinate range of magnitudes 1e-50 to 1e50)");
  }
  report.stop_reason = to_string(report.stop);

  measure_phase(mesh, report);
  if (out) *out = std::move(mesh);
  return report;
}

}  // namespace mwst
