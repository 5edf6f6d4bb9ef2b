// mwst/algorithms/pipeline.hpp — one call that runs a method on an input and measures the result.
//
// triangulate() is what `mwst triangulate` and the experiments run: the constrained Delaunay
// triangulation of the input (carved to its domain), then the chosen method — DT, Delaunay
// refinement (DR), bundle removal (BRH), quadtree refinement (QTR) or our optimiser (OPT), the
// methods compared in Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" — then the
// optional weight-reducing flips (EFH) and the exact bundle number, and finally the metrics of
// include/mwst/algorithms/metrics.hpp. The Report holds what the JSON report prints.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/algorithms/stop_reason.hpp"

namespace mwst {

enum class Method {
  kDt,   // (constrained) Delaunay triangulation, no Steiner points
  kDr,   // Delaunay refinement to the minimum angle
  kBrh,  // bundle removal heuristic (the paper's BRH)
  kQtr,  // quadtree refinement (Bern–Eppstein–Gilbert)
  kOpt,  // our weight optimiser (past the paper)
};

// "dt", "dr", "brh", "qtr", "opt".
MWST_API std::string_view method_name(Method method);
// The inverse of method_name; std::nullopt for an unknown name.
MWST_API std::optional<Method> parse_method(std::string_view name);

// "offcenter" / "circumcenter" and back.
MWST_API std::string_view steiner_rule_name(SteinerRule rule);
MWST_API std::optional<SteinerRule> parse_steiner_rule(std::string_view name);

// Where a run is, for a progress line: the method, its phase, `done` of `total` steps of the method
// (phases; opt: its starts and searches), the seconds since the run began, and the seconds left
// at most (the time limit's rest) or -1 when no estimate exists.
struct Progress {
  std::string_view method;
  std::string_view phase;
  std::size_t done = 0;
  std::size_t total = 0;
  double elapsed_seconds = 0.0;
  double seconds_left = -1.0;
};
// Called by triangulate() when a phase begins (a few times per run, never inside a loop).
using ProgressCallback = std::function<void(const Progress&)>;
// The progress line: "mwst: dr: refine (2/3), 12.4 s, at most 37.6 s left" — the estimate only
// when one exists (seconds_left ≥ 0), the steps only when total > 0.
std::string format_progress(const Progress& progress);

// A resource ran out, or a request cannot fit in it: the memory budget
// (TriangulateOptions::memory_budget_bytes; a max_area whose mesh would not fit). The message
// says what ran out and what to try. The command line exits with its own code (4).
class ResourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The memory a mesh of `triangles` domain triangles needs at the peak of a refinement by `method`
// that makes it (measured peak resident bytes per output triangle of `mwst triangulate`, writing
// its files included, rounded down: see the comment in pipeline.cpp).
double estimated_bytes(Method method, double triangles);

inline constexpr std::size_t kDefaultOptTrials = std::numeric_limits<std::size_t>::max();

struct TriangulateOptions {
  Method method = Method::kDt;
  double min_angle_deg = 20.0;                 // DR / BRH angle bound α; 0 = none. opt: the bound of its
                                               // dr and brh starting meshes only, not of its result (the
                                               // report's parameters say so: "min_angle_bounds")
  SteinerRule steiner = SteinerRule::kOffCenter;
  std::size_t bundle_k = 0;                    // BRH: 0 = default_bundle_k(min_angle_deg)
  bool flip = false;                           // weight-reducing flips (EFH) after the method
  double max_area = -1.0;                      // ≤ 0: no area bound
  std::size_t max_steiner = std::numeric_limits<std::size_t>::max();
  bool convex_hull = false;                    // keep the whole convex hull (Triangle's -c)
  bool strict = false;                         // refuse crossing segments instead of splitting
  bool bundle = false;                         // compute the exact bundle number of the result
  double time_budget_seconds = -1.0;           // ≤ 0: none
  // Under time_budget_seconds, the seconds the methods set aside within it for each vertex they add
  // (RefineOptions::time_reserve_per_vertex): time for the caller to write the larger mesh out. 0: none.
  double time_reserve_per_vertex = 0.0;
  bool exact_polish = false;                   // opt: exact MWT polish (OptimizeOptions::exact_polish)
  // opt: iterated-local-search trials per start (OptimizeOptions::perturbation_trials). The default
  // (kDefaultOptTrials) is min(600, 300000 / triangles of the start); fewer trials are faster and
  // at most as thorough, 0 stops after the kicks.
  std::size_t opt_trials = kDefaultOptTrials;
  // qtr: the most leaves its quadtree may have before the method falls back
  // (QuadtreeOptions::max_leaves; 0 = automatic). The fuzz harness keeps its meshes small with it.
  std::size_t quadtree_max_leaves = 0;
  // The memory the run may use, in bytes (0: no budget). A max_area whose mesh cannot fit (at
  // least domain area / max_area triangles, estimated_bytes of them; refinement makes about twice
  // that) is refused with a ResourceError before any refinement.
  double memory_budget_bytes = 0.0;
  // Triangle's -D: the result is Delaunay across segments too (conforming Delaunay), input segments
  // being split where needed (RefineOptions::conforming_delaunay). Methods dt (segment splits
  // only) and dr; not with flip. A warning says if it was not reached (a budget, the guard).
  bool conforming_delaunay = false;
  // Triangle's -Y / -YY (RefineOptions::segment_splitting): methods dt, dr and brh. Triangles that
  // cannot be improved without splitting a protected subsegment are left, and the stop reason
  // counts them ("N triangles left beside subsegments that may not be split"); triangles above
  // an area bound get interior points instead, so area bounds are still met.
  SegmentSplitting segment_splitting = SegmentSplitting::kAllowed;
  // Triangle's -a without a number: each Region's max_area bounds the triangles of its region
  // (found as arrays.hpp's region_of_triangles finds them; kept in Mesh::area_bound and inherited
  // by the triangles refinement makes). Methods dr and brh.
  bool regional_area_limits = false;
  // Worker threads (0: all hardware threads; 1: everything on the calling thread) of the parallel
  // parts: the Delaunay triangulation, the quadtree, the exact bundle tests. Results do not depend
  // on it.
  unsigned threads = 0;
  // Called at every phase (may be empty).
  ProgressCallback progress;
};

// The true stop reason of `method`'s result `mesh` under `options`, given the reason its engine
// gave (`engine`) and whether the flips ran after it. The bounds are checked on the mesh (check_bounds
// of metrics.hpp: angle for dr, area for dr, brh, opt): a mesh that meets them (exemptions: the
// triangles next to input angles under 60°) is "bound reached" or "N triangles left near small
// input angles" (dr; brh's K-bundle test stands for its angle bound, checked again after flips
// with in_k_bundle), opt's "local minimum" unless it ran out of time; a mesh that does not is a
// budget stop (steiner or time) when the engine ran out of one, "below the angle bound after the
// flips" when the flips broke it, "N triangles left beside subsegments that may not be split" when
// segment_splitting protects subsegments, and otherwise "N triangles left outside the bounds".
// The area bound includes the mesh's own per-triangle bounds (Mesh::area_bound: regional limits,
// .area files). Never a reason the mesh contradicts.
// brh with flip: its exact test stops at `deadline` (the time budget's), and the reason is then "time budget".
StopReason settle_stop_reason(const Mesh& mesh, const TriangulateOptions& options, const StopReason& engine,
                              bool flipped,
                              std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

// The paper's lemma: a triangulation with minimum angle α is (4π/α + 3)-bundle-free, so the default
// bundle size for BRH is ⌈4π/α⌉ + 3 (α = 30° gives 27). Computed as ⌈720/deg⌉ + 3 so that whole
// divisors of 720 are exact. Throws std::invalid_argument if min_angle_deg ≤ 0.
MWST_API std::size_t default_bundle_k(double min_angle_deg);

// Checks the options for values no method can use (negative angles, an angle of 60° or more,
// NaN, ...). Throws std::invalid_argument naming the TriangulateOptions field ("min_angle_deg
// must be in [0, 60) degrees"); the library's messages and warnings all name fields, never
// command-line flags (a command line maps them to its own spellings).
MWST_API void check_options(const TriangulateOptions& options);

// Does `method` read the TriangulateOptions field named `option` ("min_angle_deg", "steiner",
// "bundle_k", "max_area", "max_steiner", "time_budget_seconds", "exact_polish", "opt_trials")?
// dt reads none of them, qtr only time_budget_seconds; dr the angle, rule and budgets; brh also
// bundle_k; opt all of them (its BRH and DR starts, its search). Fields every method reads (flip,
// convex_hull, strict, bundle, ...) and names not listed: true.
MWST_API bool method_reads_option(Method method, std::string_view option);

// What the phases of a run did beyond the common measures: the method-specific part of the report.
// A phase that did not run leaves its member of Report empty; the JSON report (mwst/io/report.hpp)
// prints each present one as an object under the key in brackets.
struct StartSummary {  // ["start"] Triangle's -r: the triangulation the run started from
  std::size_t triangles = 0;
  std::size_t reoriented = 0;  // triangles given clockwise, turned counter-clockwise
};
struct RefineSummary {  // ["refine"] dr (RefineStats)
  std::size_t steiner_inserted = 0;
  std::size_t segment_splits = 0;
  std::size_t left_small_angle = 0;
  std::optional<std::size_t> left_protected;  // only when segment splitting is restricted (-Y)
};
struct ConformSummary {  // ["conform"] dt with conforming Delaunay (-D)
  std::size_t segment_splits = 0;
};
struct BrhSummary {  // ["brh"] (BrhStats)
  std::size_t bundle_k = 0;
  std::size_t rounds = 0;
  std::size_t exact_evaluations = 0;
  std::size_t steiner_inserted = 0;
  std::size_t segment_splits = 0;
  std::size_t skinny_left = 0;
};
struct FlipSummary {  // ["flip"] EFH (FlipStats)
  std::size_t flips = 0;
  double weight_before = 0.0;
  double weight_after = 0.0;
};
struct QuadtreeSummary {  // ["qtr"] (QuadtreeStats)
  std::size_t leaves = 0;
  unsigned depth = 0;
  std::size_t warped = 0;
  std::size_t snapped = 0;
  std::size_t crossing_points = 0;
  std::size_t centres = 0;
  bool fallback = false;
};
struct OptimizeSummary {  // ["optimize"] opt (OptimizeStats of the winning search)
  // > 0: the domain was optimised as this many pieces; then only weight_after is set.
  std::size_t pieces = 0;
  std::string start;                                   // the start whose search won
  std::vector<std::pair<std::string, double>> starts;  // every start tried: its weight after search
  std::size_t rounds = 0;
  std::size_t relocations = 0;
  std::size_t removals = 0;
  std::size_t insertions = 0;
  std::size_t region_retriangulations = 0;
  std::size_t region_tries_skipped = 0;
  std::size_t kick_insertions = 0;
  std::size_t kick_removals = 0;
  std::size_t perturbations = 0;
  std::size_t whole_polygon_mwt = 0;
  std::size_t flips = 0;
  std::size_t crossover_pieces = 0;  // pieces the partition crossover took from other starts
  double crossover_gain = 0.0;
  double weight_before = 0.0;
  double weight_after = 0.0;
  std::optional<std::size_t> exact_polishes;      // only with exact_polish
  std::optional<std::size_t> exact_polish_tries;  // only with exact_polish
};
struct BundleSummary {  // the keys bundle_number, bundle_disk {x, y, r}, bundle_circumdisk_bound
  std::uint32_t bundle_number = 0;
  Point disk_center;
  double disk_radius = 0.0;
  std::uint32_t circumdisk_bound = 0;
};

struct MWST_API Report {
  std::string input;   // Pslg::source
  std::string method;  // method_name()
  TriangulateOptions options;

  std::size_t vertices = 0;   // vertices used by domain triangles
  std::size_t triangles = 0;  // domain triangles
  std::size_t steiner = 0;    // used vertices that are not input points
  double weight_total = 0.0;
  double weight_boundary = 0.0;  // input segments, or the convex hull of a point set
  double weight_interior = 0.0;
  double min_angle = 0.0;        // degrees, over domain triangles
  double max_angle = 0.0;
  double max_triangle_area = 0.0;  // the largest domain triangle's area (what max_area bounds)
  // Wall-clock seconds of each phase, in the order the phases ran.
  std::vector<std::pair<std::string, double>> seconds;
  StopReason stop;               // refinement methods (settle_stop_reason); qtr: "time budget" or none
  std::string stop_reason;       // to_string(stop)
  std::size_t duplicates = 0;    // duplicate input points merged
  std::size_t crossings = 0;     // crossing points inserted where segments cross
  std::vector<std::string> warnings;  // printed as "mwst: warning: ..." by the command line
  // Method-specific results, present when their phase ran.
  std::optional<StartSummary> start;
  std::optional<RefineSummary> refine;
  std::optional<ConformSummary> conform;
  std::optional<BrhSummary> brh;
  std::optional<FlipSummary> flip;
  std::optional<QuadtreeSummary> qtr;
  std::optional<OptimizeSummary> optimize;
  std::optional<BundleSummary> bundle;  // TriangulateOptions::bundle, unless the time budget ran out

  double total_seconds() const;
};

// Runs options.method on the input. If `out` is not null the final mesh is moved there. With
// Pslg::triangles (Triangle's -r) dt, dr and brh start from that triangulation instead of the CDT
// (validated: an InputError names the first problem; see pipeline.cpp), dt keeping it as it is;
// Pslg::triangle_max_area bounds its triangles and those refinement makes from them.
// Throws InputError for input the mesher refuses (naming pslg.source and, where known, the line),
// ResourceError for a request that cannot fit in options.memory_budget_bytes, std::invalid_argument for unusable options (a bundle size below 3, an angle outside [0, 60), ...),
// and InternalError for broken invariants.
MWST_API Report triangulate(const Pslg& pslg, const TriangulateOptions& options, Mesh* out = nullptr);

}  // namespace mwst
