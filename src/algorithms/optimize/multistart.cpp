// opt's multistart (method opt of triangulate(), declared in algorithms/pipeline/phases.hpp): a thin
// facade over the parts of src/algorithms/optimize/, as CGAL's Delaunay_mesher_2 is over its
// refinement of faces. docs/algorithms/optimize.md describes the method. In order:
//   1. the domain in independent pieces, each a whole multistart of its own (optimize_in_pieces);
//   2. the starts: BRH at the given (A, K) followed by EFH, DR at 5°, 10°, 15° and 20°, the CDT, and
//      (inputs with segments) the CDT seeded with Steiner points at its junction triangles'
//      circumcenters and at its centroids (make_starts); with exact_polish, each start
//      re-triangulated by the exact MWT of its vertices is one more start;
//   3. the local search of optimize() on every start (local_search);
//   4. the kicks and the iterated local search on the starts within 5% of the lightest (kick_search);
//   5. the lightest result improved by a partition crossover with the others (crossover);
//   6. the report's summary (summarise).
// Since every search only lowers the weight of its start, and the crossover is kept only if
// lighter, opt is never heavier than BRH+EFH with the same parameters. With a time budget every
// refinement and search gets what is left of it; once it has passed, the starts not yet made are
// skipped, every search stops where it is, and the stop reason says "time budget" (the lightest
// mesh so far is returned; valid, but then no longer bounded by BRH+EFH if the BRH start itself
// was cut short).
#include <algorithm>
#include <cstddef>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/optimize/crossover.hpp"
#include "algorithms/optimize/domain_pieces.hpp"
#include "algorithms/optimize/exact_polish.hpp"
#include "algorithms/optimize/seed_points.hpp"
#include "algorithms/optimize/separation.hpp"
#include "algorithms/pipeline/phases.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/algorithms/refine.hpp"
#include "support/parallel.hpp"
#include "support/time_budget.hpp"

namespace mwst::phases {

namespace {

// ---- the multistart begins here -------------------------------------------------------------------

struct Start {
  std::string name;
  Mesh mesh;
};

// Memory. opt's peak is what the multistart keeps at once: the meshes of all its starts (each
// searched in turn, all kept for the crossover), the CDT until the starts are made, and one
// search's scratch (Optimizer: its table of failed regions, 128 bytes per triangle, and a copy of
// the mesh per perturbation trial). A mesh is about 40 bytes per triangle (Triangle, a flag byte,
// half a vertex), but a refinement or a search grows its arrays by doubling and leaves up to as much
// again unused: every mesh kept goes through release_spare_capacity, the CDT is freed once the
// starts are made, and the starts once the crossover has taken what it wants from them. Nothing
// here changes a result: only when memory is freed.
void release_spare_capacity(Mesh& m) {
  m.points.shrink_to_fit();
  m.vertex_kind.shrink_to_fit();
  m.vertex_marker.shrink_to_fit();
  m.triangles.shrink_to_fit();
  m.flags.shrink_to_fit();
  m.segment_marker.shrink_to_fit();
  m.area_bound.shrink_to_fit();
  m.duplicates.shrink_to_fit();
}

class Multistart {
 public:
  Multistart(const Pslg& pslg, const TriangulateOptions& options, Clock::time_point start, Mesh cdt)
      : pslg_(pslg), options_(options), start_(start), cdt_(std::move(cdt)), cdt_steiner_(measure(cdt_).steiner),
        cdt_vertices_(cdt_.points.size()), cdt_separation_(default_min_separation(cdt_)) {}

  Mesh run(Report& report) {
    make_starts();
    set_aside_for_growth();
    cdt_ = Mesh{};  // (only its size and separation scale are needed from here on)
    add_exact_polish_starts();
    local_search();
    kick_search();
    Mesh best = crossover();
    summarise(report);
    return best;
  }

 private:
  // Step 2: the starts. Large inputs get the BRH start only (each start costs a refinement and a
  // search); large also by the BRH start's size: an area bound makes meshes of tens of thousands
  // of triangles from a few hundred points, and the search's cost grows faster than the mesh.
  // When the CDT is already that large, so is the BRH start (BRH only inserts vertices; the flips
  // keep the count), and the BRH start is known to be the only one before it is made: it then
  // takes the CDT itself, not a copy, one mesh less at BRH's peak (2.8 of 35 MB on 40k uniform
  // points), with the same result.
  void make_starts() {
    constexpr std::size_t kLargeStartTriangles = 20000;
    const bool large_input = pslg_.points.size() > 100000;
    const bool large_cdt = cdt_.domain_triangle_count() > kLargeStartTriangles;
    make_brh_start(/*last_start=*/large_input || large_cdt);
    const bool large =
        large_input || large_cdt || starts_.front().mesh.domain_triangle_count() > kLargeStartTriangles;
    if (large || time_is_up()) return;
    make_refined_starts();
    make_seeded_starts();
  }

  // BRH at the run's (A, K) (A = 20° when the run has no angle bound), then EFH. When it is the
  // only start, it takes the CDT itself rather than a copy (one mesh less during BRH, the peak of
  // opt on large inputs).
  void make_brh_start(bool last_start) {
    announce(options_, start_, "start brh+efh", 0, 1);
    Mesh m = last_start ? std::move(cdt_) : cdt_;
    Report scratch;
    TriangulateOptions o = options_;
    if (!(o.min_angle_deg > 0.0)) o.min_angle_deg = 20.0;
    brh_phase(m, o, start_, scratch);
    out_of_time_ |= scratch.stop.kind == StopKind::kTimeBudget;
    out_of_steiner_ |= scratch.stop.kind == StopKind::kSteinerBudget;
    // The flips lower the weight most (the Delaunay triangulation of 20k points on an ellipse from
    // 12737 to 130), largest gain first, but only up to the deadline: on a mesh far from a local
    // minimum (160k points on a spiral, BRH cut short by the budget: 545k triangles) they take
    // seconds, and --time-limit bounds the whole run.
    out_of_time_ |= flip_to_local_minimum(m, options_.max_area, detail::deadline_after(start_, options_.time_budget_seconds))
                        .out_of_time;
    // (Out of time, no search follows: shrinking the arrays, a copy of each, would only delay the
    // result, by 1.3 s on a million points on the loaded machine.)
    if (!out_of_time_) release_spare_capacity(m);
    starts_.push_back({"brh+efh", std::move(m)});
  }

  // DR at 5°, 10°, 15° and 20°, and the CDT (refined to the area bound if there is one).
  void make_refined_starts() {
    for (const double angle : {5.0, 10.0, 15.0, 20.0}) {
      if (time_is_up()) break;
      announce(options_, start_, "start dr", starts_.size(), 8);
      Mesh m = cdt_;
      RefineOptions ro = refine_options_for(options_, start_);
      ro.min_angle_deg = angle;
      note_refinement(refine(m, ro).stop);
      release_spare_capacity(m);
      starts_.push_back({"dr" + std::to_string(static_cast<int>(angle)), std::move(m)});
    }
    if (!time_is_up()) {
      announce(options_, start_, "start dt", starts_.size(), 8);
      starts_.push_back({"dt", area_bounded(cdt_)});
    }
  }

  // Seeded starts (seed_steiner_points) for polygonal domains: the CDT with Steiner points where
  // its dual branches (an approximate medial axis), and with one at every triangle's centroid.
  // They pay where the domain has strips between boundary chains (the coastlines: 0.1–0.5 points)
  // and cost a third more time; on point sets (Kuzmin2K, Ellipse, uniform points) they never won
  // by more than 0.001%, so point sets skip them.
  void make_seeded_starts() {
    if (pslg_.segments.empty() || time_is_up()) return;
    for (const auto& [name, seeds] : {std::pair{"dt+junctions", SeedPoints::kJunctionCircumcenters},
                                      std::pair{"dt+centroids", SeedPoints::kCentroids}}) {
      if (time_is_up()) break;
      announce(options_, start_, "start seeded", starts_.size(), 8);
      Mesh m = cdt_;
      seed_steiner_points(m, seeds);
      m = area_bounded(std::move(m));
      if (within_steiner_budget(m)) starts_.push_back({name, std::move(m)});
    }
  }

  // Opt-in exact polish: each start re-triangulated by the exact MWT of its vertices (mwt.hpp; when
  // solved and lighter) is one more start, "<name>+mwt"; the 5% cut is taken over the original
  // starts only, so the original starts get the same treatment and the polish never makes opt
  // heavier.
  void add_exact_polish_starts() {
    original_starts_ = starts_.size();
    if (!options_.exact_polish) return;
    for (std::size_t i = 0; i < original_starts_ && !time_is_up(); ++i) {
      Mesh m = starts_[i].mesh;
      OptimizeOptions polish;
      polish.max_area = options_.max_area;
      if (exact_polish_mesh(m, polish)) {
        release_spare_capacity(m);
        starts_.push_back({starts_[i].name + "+mwt", std::move(m)});
      }
    }
  }

  // Step 3: the local search (no kicks) on every start, with one separation scale for all: the
  // input's CDT's.
  void local_search() {
    local_.kick_passes = 0;
    local_.fixed_vertices = cdt_vertices_;  // the input and the CDT's crossing points
    local_.max_steiner = options_.max_steiner;
    local_.max_area = options_.max_area;
    local_.min_separation = cdt_separation_;
    for (std::size_t i = 0; i < starts_.size(); ++i) {
      announce(options_, start_, "local search", i, starts_.size());
      if (time_is_up()) {
        // No search, so no passes over the mesh either (measures, compaction, the arrays shrunk:
        // 0.9 s on a million points on the loaded machine): the start as it is.
        local_weight_.push_back(measure(starts_[i].mesh).weight_total);
        if (i < original_starts_) lightest_ = std::min(lightest_, local_weight_.back());
        continue;
      }
      local_.time_budget_seconds = budget_left(options_, start_);
      const OptimizeStats os = optimize(starts_[i].mesh, local_);
      release_spare_capacity(starts_[i].mesh);
      out_of_time_ |= os.out_of_time;
      local_weight_.push_back(os.weight_after);
      if (i < original_starts_) lightest_ = std::min(lightest_, local_weight_.back());
    }
  }

  // Step 4: the costlier kicks (optimize.hpp) and the iterated local search on the starts within 5%
  // of the lightest local optimum (kicks have never gained more than ~4% on the data sets). The
  // whole-domain MWT was tried in the first pass.
  void kick_search() {
    OptimizeOptions kicks;
    kicks.fixed_vertices = local_.fixed_vertices;
    kicks.max_steiner = local_.max_steiner;
    kicks.max_area = local_.max_area;
    kicks.min_separation = local_.min_separation;
    kicks.max_exact_polygon = 0;
    kicks.max_exact_convex_polygon = 0;
    kicks.exact_polish = options_.exact_polish;  // and after the search (optimize.hpp)
    result_.resize(starts_.size());
    for (std::size_t i = 0; i < starts_.size(); ++i) {
      Start& s = starts_[i];
      OptimizeStats& os = result_[i];
      if (local_weight_[i] <= 1.05 * lightest_ && !time_is_up()) {
        announce(options_, start_, "kicks", i, starts_.size());
        // The iterated local search's budget counts trials, scaled by this start's own size (each
        // trial copies the mesh), so that the exact polish's extra starts leave every original
        // start's search unchanged.
        OptimizeOptions o = kicks;
        const std::size_t triangles = std::max<std::size_t>(1, s.mesh.domain_triangle_count());
        o.perturbation_trials = options_.opt_trials != kDefaultOptTrials ? options_.opt_trials
                                                                         : std::min<std::size_t>(600, 300000 / triangles);
        o.time_budget_seconds = budget_left(options_, start_);
        os = optimize(s.mesh, o);
        release_spare_capacity(s.mesh);
        out_of_time_ |= os.out_of_time;
      } else {
        os.weight_before = os.weight_after = local_weight_[i];
      }
      tried_.emplace_back(s.name, os.weight_after);
    }
  }

  // Step 5: the lightest result (ties: the earlier start) takes from each other result, in order,
  // the pieces between their shared edges that are lighter there (crossover.cpp: different starts
  // end in different local minima in different places); the local search then polishes the seams.
  // Kept only if lighter: no gain, no change.
  Mesh crossover() {
    std::vector<std::size_t> order(starts_.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return result_[x].weight_after < result_[y].weight_after; });
    const std::size_t lightest_start = order.front();
    best_weight_ = result_[lightest_start].weight_after;
    best_name_ = starts_[lightest_start].name;
    best_stats_ = result_[lightest_start];
    Mesh best = std::move(starts_[lightest_start].mesh);
    if (order.size() <= 1 || time_is_up()) return best;
    announce(options_, start_, "crossover", 0, 1);
    Mesh child = best;
    for (std::size_t k = 1; k < order.size(); ++k) {
      crossed_.taken += partition_crossover(child, starts_[order[k]].mesh).taken;
    }
    starts_.clear();  // (their meshes: the polish of the seams below needs only the child)
    starts_.shrink_to_fit();
    // (Pieces come from results that keep the area bound, but a start cut short by the budgets
    // may hold larger triangles: a child with a triangle larger than the bound and than the
    // lightest result's largest is not taken.)
    const bool within_area = !(options_.max_area > 0.0) ||
                             measure(child).max_triangle_area <= std::max(options_.max_area, measure(best).max_triangle_area);
    if (crossed_.taken > 0 && within_steiner_budget(child) && within_area && !time_is_up()) {
      local_.time_budget_seconds = budget_left(options_, start_);
      const OptimizeStats polished = optimize(child, local_);
      out_of_time_ |= polished.out_of_time;
      if (polished.weight_after < best_weight_) {
        crossed_.gain = best_weight_ - polished.weight_after;
        best_weight_ = polished.weight_after;
        best = std::move(child);
      }
    }
    return best;
  }

  // Step 6: the stop reason and opt's part of the report.
  void summarise(Report& report) {
    report.stop.kind = out_of_time_      ? StopKind::kTimeBudget
                       : out_of_steiner_ ? StopKind::kSteinerBudget
                                         : StopKind::kLocalMinimum;
    OptimizeSummary& summary = report.optimize.emplace();
    summary.start = best_name_;
    summary.starts = std::move(tried_);
    summary.rounds = best_stats_.rounds;
    summary.relocations = best_stats_.relocations;
    summary.removals = best_stats_.removals;
    summary.insertions = best_stats_.insertions;
    summary.region_retriangulations = best_stats_.region_retriangulations;
    summary.region_tries_skipped = best_stats_.region_tries_skipped;
    summary.kick_insertions = best_stats_.kick_insertions;
    summary.kick_removals = best_stats_.kick_removals;
    summary.perturbations = best_stats_.perturbations;
    summary.whole_polygon_mwt = best_stats_.whole_polygon_mwt;
    summary.flips = best_stats_.flips;
    summary.crossover_pieces = crossed_.gain > 0.0 ? crossed_.taken : 0;
    summary.crossover_gain = crossed_.gain;
    summary.weight_before = best_stats_.weight_before;
    summary.weight_after = best_weight_;
    if (options_.exact_polish) {
      summary.exact_polishes = best_stats_.exact_polishes;
      summary.exact_polish_tries = best_stats_.exact_polish_tries;
    }
  }

  // ---- budgets --------------------------------------------------------------------------------------

  // The result is one of the starts (or a crossover of them, of about their size): the time the
  // caller needs to write the vertices the starts added (TriangulateOptions::time_reserve_per_vertex
  // for each vertex beyond the CDT's, in the largest start) comes off what is left for the search.
  void set_aside_for_growth() {
    if (!(options_.time_budget_seconds > 0.0)) return;
    std::size_t most = cdt_vertices_;
    for (const Start& s : starts_) most = std::max(most, s.mesh.points.size());
    const double reserve = options_.time_reserve_per_vertex * static_cast<double>(most - cdt_vertices_);
    options_.time_budget_seconds = std::max(options_.time_budget_seconds - reserve, 1e-9);
  }

  bool time_is_up() {
    out_of_time_ = out_of_time_ || budget_spent(options_, start_);
    return out_of_time_;
  }
  void note_refinement(const StopReason& stop) {
    const StopKind kind = stop.kind;
    out_of_time_ |= kind == StopKind::kTimeBudget;
    out_of_steiner_ |= kind == StopKind::kSteinerBudget;
  }
  // max_steiner bounds the Steiner points beyond the CDT's (its crossing points) in every start and
  // every search; a mesh over it (a seeded start, a crossover) is not taken.
  bool within_steiner_budget(const Mesh& m) const {
    const std::size_t steiner = measure(m).steiner;
    return steiner <= cdt_steiner_ || steiner - cdt_steiner_ <= options_.max_steiner;
  }
  // With an area bound every start keeps it, as the search then does (OptimizeOptions::max_area):
  // the refined starts get it, and the CDT and the seeded starts are refined to it with no angle
  // bound (Delaunay refinement splitting only the triangles larger than the bound).
  Mesh area_bounded(Mesh m) {
    if (options_.max_area > 0.0) {
      RefineOptions ro = refine_options_for(options_, start_);
      ro.min_angle_deg = 0.0;
      note_refinement(refine(m, ro).stop);
    }
    release_spare_capacity(m);
    return m;
  }

  const Pslg& pslg_;
  TriangulateOptions options_;  // (a copy: set_aside_for_growth shortens its time budget)
  const Clock::time_point start_;
  Mesh cdt_;  // freed once the starts are made
  const std::size_t cdt_steiner_;
  const std::size_t cdt_vertices_;
  const double cdt_separation_;
  bool out_of_time_ = false;     // the budget has passed (a refinement or search was cut, or a step skipped)
  bool out_of_steiner_ = false;  // a start's refinement ran out of max_steiner
  std::vector<Start> starts_;
  std::size_t original_starts_ = 0;  // the starts before the exact polish's
  OptimizeOptions local_;            // the local search's options (also for the crossover's seams)
  std::vector<double> local_weight_;
  double lightest_ = std::numeric_limits<double>::infinity();
  std::vector<OptimizeStats> result_;
  std::vector<std::pair<std::string, double>> tried_;
  std::string best_name_;
  OptimizeStats best_stats_;
  double best_weight_ = 0.0;
  CrossoverStats crossed_;
};

// ---- the multistart ends here ---------------------------------------------------------------------

// Step 1: independent pieces of the domain (optimize/domain_pieces.hpp), each searched alone as if
// it were the whole input (its own starts and budgets), on all cores, and put back together. False
// when the domain does not split (or the pieces do not go back together).
bool optimize_in_pieces(const Pslg& pslg, const TriangulateOptions& options, Clock::time_point start,
                        const Mesh& cdt, Report& report, Mesh& merged) {
  DomainPieces pieces;
  if (!split_domain(pslg, cdt, pieces)) return false;
  Phase phase(report, "optimize");
  const std::size_t count = pieces.pslgs.size();
  std::vector<Mesh> results(count);
  std::vector<Report> reports(count);
  // The first piece's error is rethrown, whichever thread ran it.
  support::parallel_for(count, support::worker_count(options.threads),
                        [&](std::size_t i) { results[i] = optimize_phase(pieces.pslgs[i], options, start, reports[i]); });
  if (!merge_pieces(pslg, cdt, pieces, results, merged)) return false;
  phase.finish();
  // optimize_phase settles each piece's stop (the string form comes later, in triangulate()).
  const bool cut = std::any_of(reports.begin(), reports.end(), [](const Report& r) { return r.stop.kind == StopKind::kTimeBudget; });
  report.stop = StopReason{cut ? StopKind::kTimeBudget : StopKind::kLocalMinimum, 0, {}};
  report.optimize = OptimizeSummary{};
  report.optimize->pieces = count;
  report.optimize->weight_after = measure(merged).weight_total;
  return true;
}

}  // namespace

Mesh optimize_phase(const Pslg& pslg, const TriangulateOptions& options, Clock::time_point start, Report& report) {
  Mesh cdt = constrained_delaunay_phase(pslg, options, report);
  check_memory_for_area_bound(cdt, options);
  // (Not in pieces with max_steiner, a budget for the whole mesh, nor with convex_hull.)
  const bool whole_budget = options.max_steiner != std::numeric_limits<std::size_t>::max();
  if (!options.convex_hull && !whole_budget) {
    Mesh merged;
    if (optimize_in_pieces(pslg, options, start, cdt, report, merged)) return merged;
  }
  Phase phase(report, "optimize");
  Multistart multistart(pslg, options, start, std::move(cdt));
  Mesh best = multistart.run(report);
  phase.finish();
  return best;
}

}  // namespace mwst::phases
