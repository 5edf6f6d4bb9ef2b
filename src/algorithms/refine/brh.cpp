// src/algorithms/refine/brh.cpp — the bundle removal heuristic (BRH) of Boyacı, Erten and Üngör
// (mwst/algorithms/brh.hpp): a thin driver over the refinement engine, the shape of CGAL's
// Delaunay_mesher_2 over Mesh_2/Refine_faces. The engine (refiner.hpp) refines; BRH supplies the
// criterion (brh_criteria.hpp: skinny and in a K-bundle, by the local witness or the last exact
// test) and decides between passes with the exact test (in_k_bundle, bundle.hpp).
// docs/algorithms/brh.md describes the method. The steps of a round, in order:
//   update_skinny        the skinny triangles (updated from the pass, or swept)
//   local_sample         first round: does the local test find any? then one unseeded pass
//   exact_test           otherwise in_k_bundle marks the skinny triangles in K-bundles (the
//                        clean ones, CleanQueries, not asked again)
//   refine_pass          one pass of refine() with the criterion, seeded with the marked
//   stop_or_recheck      nothing left to split: confirm the skinny list by a sweep, or stop
#include "mwst/algorithms/brh.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "algorithms/refine/brh_criteria.hpp"
#include "algorithms/refine/clean_queries.hpp"
#include "algorithms/refine/tested_slots.hpp"
#include "algorithms/triangle_key.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "support/time_budget.hpp"

namespace mwst {

namespace {

using brh::CleanQueries;
using brh::kCleanQueriesFrom;
using brh::LocalBundleTest;
using brh::SkinnyTest;
using brh::TestedSlots;
using brh::sorted_triple;
using detail::TripleHash;

class BundleRemoval {
 public:
  BundleRemoval(Mesh& mesh, const BrhOptions& options);
  BundleRemoval(const BundleRemoval&) = delete;  // ro_.is_bad refers to this object
  BundleRemoval& operator=(const BundleRemoval&) = delete;

  BrhStats run();

 private:
  // What a step tells the loop of rounds.
  enum class Step { kProceed, kNextRound, kStop };

  bool area_pass();
  double reserved_seconds() const;
  double seconds_used() const;
  bool time_up() const;
  std::chrono::steady_clock::time_point exact_test_deadline() const;
  void update_skinny();
  void sweep_skinny();
  bool confirm_skinny();
  void stop_on_sweep();
  Step stop_or_recheck();
  bool local_sample();
  Step exact_test(bool ask_all);
  void remember_left(const std::vector<std::array<VertexId, 3>>& seeds_before);
  Step refine_pass(bool any_local);

  Mesh& mesh_;
  const BrhOptions& options_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  // The time budget also bounds each exact test (in_k_bundle), which alone can take many seconds.
  const std::chrono::steady_clock::time_point deadline_;
  BrhStats stats_;
  const double A_;
  const std::uint32_t K_;
  std::unordered_set<std::array<VertexId, 3>, TripleHash> marked_;  // found by the exact test
  // Triangles the exact test marked that the pass seeded with them left as they were: the engine
  // does not split them (the Miller–Pav–Walkington rule: they subtend a small input angle), so
  // asking about them again after every pass only costs (a narrow fan: all but ~900 of 18,000
  // skinny triangles, asked 20 times). The next exact tests skip them; when a test over the
  // others marks nothing, or its pass inserts nothing, every skinny triangle is asked again
  // (`ask_all_`), so BRH stops on a full test as before. Each keeps its witness (the corners of
  // the Delaunay triangle whose circumdisk put it in a K-bundle, KBundleCache::witnesses; kNone if
  // the pencils did): the full test tries that disk first (on the fan 160k it asks 80,000 of them
  // again, and each walk over S(t) cost ~0.3 ms).
  using Triple = std::array<VertexId, 3>;
  static constexpr Triple kNoWitness{kNone, kNone, kNone};
  std::unordered_map<Triple, Triple, TripleHash> left_marked_;
  // The witnesses of the seeds of the next pass (ro_.seed_triangles, in order), until the pass
  // tells which it left.
  std::vector<Triple> seed_witness_;
  std::size_t skipped_left_ = 0;  // skinny triangles the last exact test skipped as left
  bool ask_all_ = false;
  LocalBundleTest local_;
  // Pencil sweeps of one exact test reused by the next where nothing they read changed.
  KBundleCache sweep_cache_;
  CleanQueries clean_;
  const SkinnyTest is_skinny_;
  RefineOptions ro_;
  // Where the vertices the passes put on segments come from, kept across passes (see
  // RefineOptions::segment_origins).
  std::unordered_map<VertexId, std::pair<VertexId, VertexId>> segment_origins_;
  // Skinny triangles a pass tested: every triangle a pass makes passes through is_bad, and an
  // unseeded pass (a custom is_bad) ends by testing every triangle of the domain again (refine.cpp).
  TestedSlots made_skinny_;
  bool record_skinny_ = false;
  std::size_t steiner_budget_;
  // Set when a pass driven by the local test alone inserted nothing (its triangles sit at small
  // input angles): the next pass asks the exact test, so that no triangle it would find is missed.
  bool force_exact_ = false;
  // The skinny triangles of the domain. After a pass they are updated, not recounted: a triangle
  // the pass did not make is unchanged, so they are the old ones still alive and skinny plus the
  // skinny ones the pass tested (`made_skinny_`; after an unseeded pass that is all of them). Before
  // BRH stops on such a list, a sweep over the whole mesh confirms it (the guarantee must not rest
  // on the bookkeeping).
  std::vector<TriangleId> skinny_;
  bool skinny_updated_ = false;       // skinny_ comes from an update, not a sweep
  std::size_t confirmed_skinny_ = 0;  // the sweep's count when it confirmed the list
  bool confirmed_ = false;
  bool swept_again_ = false;          // confirm_skinny failed: skinny_ holds its sweep
};

BundleRemoval::BundleRemoval(Mesh& mesh, const BrhOptions& options)
    : mesh_(mesh),
      options_(options),
      deadline_(detail::deadline_after(start_, options.refine.time_budget_seconds)),
      A_(options.min_angle_deg),
      K_(static_cast<std::uint32_t>(options.bundle_k)),
      local_(K_),
      is_skinny_(A_),
      ro_(options.refine),
      steiner_budget_(options.refine.max_steiner) {
  ro_.min_angle_deg = A_;
  if (ro_.segment_origins == nullptr) ro_.segment_origins = &segment_origins_;
  // DR's termination guard (refine.hpp), measured once on the input: BRH splits only skinny
  // triangles, as DR does, so above the angles where DR provably stops it may crowd vertices
  // without end as well; its passes stop once a skinny triangle to split is far below the input's
  // smallest feature.
  if (ro_.feature_guard_length < 0.0) {
    ro_.feature_guard_length = A_ > 0.0 ? feature_guard_length(mesh_, options_.refine.max_area) : 0.0;
  }
  // The criterion: skinny, and marked by the last exact test or found by the local test.
  ro_.is_bad = [this](const Mesh& m, TriangleId t) {
    if (!is_skinny_(m, t)) return false;
    if (record_skinny_) made_skinny_.add(t);
    return (!marked_.empty() && marked_.count(sorted_triple(m, t)) != 0) || local_.in_bundle(m, t);
  };
}

BrhStats BundleRemoval::run() {
  stats_.stop = StopReason{StopKind::kBoundReached, 0, {}};
  bool stopped = area_pass();
  for (stats_.rounds = 0; !stopped && stats_.rounds < options_.max_rounds;) {
    if (time_up()) {
      stats_.stop = StopReason{StopKind::kTimeBudget, 0, {}};
      break;
    }
    update_skinny();
    if (skinny_.empty()) {
      if (stop_or_recheck() == Step::kStop) break;
      continue;
    }
    marked_.clear();
    local_.clear();
    const bool any_local = local_sample();
    if (!any_local || force_exact_) {
      const Step step = exact_test(ask_all_);
      if (step == Step::kStop) break;
      if (step == Step::kNextRound) continue;
    }
    if (refine_pass(any_local) == Step::kStop) break;
  }
  if (stats_.rounds >= options_.max_rounds) stats_.stop = StopReason{StopKind::kRoundLimit, 0, {}};
  if (confirmed_) {
    stats_.skinny_left = confirmed_skinny_;  // the mesh has not changed since the sweep
  } else {
    for (TriangleId t = 0; t < mesh_.triangles.size(); ++t) {
      if (mesh_.in_domain(t) && is_skinny_(mesh_, t)) ++stats_.skinny_left;
    }
  }
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return stats_;
}

// An area bound (--max-area) splits every triangle larger than it, skinny or not, in a bundle or
// not: first one pass of the DR engine with the area bound alone over the whole mesh, then in
// every pass below (refine tests the area of each triangle a pass makes, whatever its is_bad).
// True if a budget stopped it.
bool BundleRemoval::area_pass() {
  if (!(options_.refine.max_area > 0.0)) return false;
  RefineOptions area = options_.refine;
  area.min_angle_deg = 0.0;
  area.is_bad = {};
  area.seed_triangles.clear();
  const RefineStats rs = refine(mesh_, area);
  const std::size_t added = rs.steiner_inserted + rs.segment_splits;
  stats_.steiner_inserted += rs.steiner_inserted;
  stats_.segment_splits += rs.segment_splits;
  if (steiner_budget_ != static_cast<std::size_t>(-1)) steiner_budget_ -= std::min(steiner_budget_, added);
  if (rs.stop.kind == StopKind::kSteinerBudget || rs.stop.kind == StopKind::kTimeBudget) {
    stats_.stop = rs.stop;
    return true;
  }
  return false;
}

// RefineOptions::time_reserve_per_vertex for each vertex inserted so far: the time BRH's caller
// needs to write them out.
double BundleRemoval::reserved_seconds() const {
  return options_.refine.time_reserve_per_vertex * static_cast<double>(stats_.steiner_inserted + stats_.segment_splits);
}

// The budget counts the time since BRH started plus the reserve for the vertices inserted so far.
double BundleRemoval::seconds_used() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() + reserved_seconds();
}

bool BundleRemoval::time_up() const {
  return options_.refine.time_budget_seconds > 0.0 && seconds_used() > options_.refine.time_budget_seconds;
}

std::chrono::steady_clock::time_point BundleRemoval::exact_test_deadline() const {
  if (deadline_ == std::chrono::steady_clock::time_point::max()) return deadline_;
  return deadline_ -
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(reserved_seconds()));
}

// ---- the skinny triangles begin here --------------------------------------------------------------

// The skinny list for this round: confirm_skinny's sweep, the last list updated with what the pass
// tested, or a sweep over the mesh.
void BundleRemoval::update_skinny() {
  if (swept_again_) {
    swept_again_ = false;  // skinny_ holds confirm_skinny's sweep
  } else if (skinny_updated_) {
    made_skinny_.append_to(skinny_);
    std::sort(skinny_.begin(), skinny_.end());
    skinny_.erase(std::unique(skinny_.begin(), skinny_.end()), skinny_.end());
    std::erase_if(skinny_, [&](TriangleId t) {
      return t >= mesh_.triangles.size() || !mesh_.in_domain(t) || !is_skinny_(mesh_, t);
    });
    // (its capacity held the old list and every evaluation of the pass: strip 160k, 3.9 MB)
    skinny_.shrink_to_fit();
  } else {
    sweep_skinny();
  }
  // Freed, not cleared: a pass tests a triangle many times over (on 40k points on a circle it
  // held a million entries), and the exact test that follows is BRH's peak of memory.
  made_skinny_.release();
}

void BundleRemoval::sweep_skinny() {
  skinny_.clear();
  for (TriangleId t = 0; t < mesh_.triangles.size(); ++t) {
    if (mesh_.in_domain(t) && is_skinny_(mesh_, t)) skinny_.push_back(t);
  }
  skinny_updated_ = false;
}

// True if the updated list holds every skinny triangle (else it is replaced by the sweep's).
bool BundleRemoval::confirm_skinny() {
  const std::size_t updated = skinny_.size();
  sweep_skinny();
  if (skinny_.size() != updated) return false;  // the update is a subset of the sweep
  confirmed_ = true;
  confirmed_skinny_ = updated;
  return true;
}

// Stopping on a list this round's sweep made (the mesh unchanged since): it is the count.
void BundleRemoval::stop_on_sweep() {
  confirmed_ = true;
  confirmed_skinny_ = skinny_.size();
}

// Nothing to split: stop, unless the skinny list came from an update and a sweep finds triangles
// the update missed (then the next round tests them all).
BundleRemoval::Step BundleRemoval::stop_or_recheck() {
  if (!skinny_updated_) {
    stop_on_sweep();
    return Step::kStop;
  }
  if (confirm_skinny()) return Step::kStop;
  swept_again_ = true;  // the sweep found skinny triangles the update missed
  return Step::kNextRound;
}

// ---- the tests begin here -------------------------------------------------------------------------

// First round: any skinny triangle the local test finds starts the refinement. With many skinny
// triangles only a sample is tried: when none of it is found, the exact test (whose first,
// circumdisk stage finds what the local test would) is cheaper than testing them all. Later
// rounds go to the exact test directly: after a refinement few skinny triangles are left, the
// exact test on few triangles is local (in_k_bundle), and the pass it starts is seeded with the
// triangles it marks (no sweep over the whole mesh).
bool BundleRemoval::local_sample() {
  bool any_local = false;
  const std::size_t sample = stats_.rounds > 0 ? 0 : std::min<std::size_t>(skinny_.size(), 256);
  for (std::size_t i = 0; i < sample && !any_local && !force_exact_; ++i) {
    any_local = local_.in_bundle(mesh_, skinny_[i * (skinny_.size() / sample)]);
  }
  return any_local;
}

// The exact test over the skinny triangles not known clean (see CleanQueries): those in a
// K-bundle are marked and seed the next pass.
BundleRemoval::Step BundleRemoval::exact_test(bool ask_all) {
  ask_all_ = false;
  // Per skinny triangle: the answer, and the witness of one answered 1 (if any). Both are made
  // after in_k_bundle, whose peak of memory is BRH's (as are `asked` and the hints: 4 and 12
  // bytes a query, the hints only when a full test has witnesses to give).
  std::vector<std::uint8_t> exact;
  std::vector<Triple> witness_at;
  // Sweeps are kept from the second exact test on (the first pass changes most of the mesh; with
  // the default K one test is often all there is).
  const bool use_cache = stats_.exact_evaluations >= 1;
  // The clean list from the first test on: on 160k points on a spiral the first test marks ~140
  // triangles, their pass inserts one vertex, and the second test asked all 182k skinny
  // triangles again (as long as the first). The first test keeps no sweeps, only the reach boxes.
  const bool use_clean = skinny_.size() >= kCleanQueriesFrom;
  if (!use_clean) clean_.clear();
  std::vector<TriangleId> asked;
  std::vector<std::uint32_t> asked_at;  // (skinny_ holds triangle ids: fewer than 2^32)
  skipped_left_ = 0;
  // A full test asks the left triangles again, each with its witness as a hint.
  std::unordered_map<Triple, Triple, TripleHash> witness_of;
  if (ask_all) witness_of.swap(left_marked_);
  std::vector<Triple> hints;
  bool any_hint = false;
  std::unordered_map<Triple, Triple, TripleHash> still_left;  // (entries of gone triangles dropped)
  for (std::size_t i = 0; i < skinny_.size(); ++i) {
    const Triple triple = sorted_triple(mesh_, skinny_[i]);
    if (!left_marked_.empty()) {
      const auto it = left_marked_.find(triple);
      if (it != left_marked_.end()) {
        still_left.insert(*it);
        ++skipped_left_;
        continue;
      }
    }
    if (use_clean && clean_.contains(triple)) {
      ++stats_.known_clean;
      continue;
    }
    asked.push_back(skinny_[i]);
    asked_at.push_back(static_cast<std::uint32_t>(i));
    if (witness_of.empty()) continue;  // (no hint to give)
    const auto w = witness_of.find(triple);
    hints.push_back(w != witness_of.end() ? w->second : kNoWitness);
    any_hint = any_hint || hints.back() != kNoWitness;
  }
  left_marked_ = std::move(still_left);
  std::unordered_map<Triple, Triple, TripleHash>().swap(witness_of);
  if (any_hint) {
    sweep_cache_.hints = std::move(hints);
  } else {
    sweep_cache_.hints.clear();
    std::vector<Triple>().swap(hints);
  }
  if (!asked.empty()) {
    // Before the second test only DT(V) and the reach boxes are kept (the next test inserts the
    // new vertices into DT(V)).
    sweep_cache_.reuse_sweeps = use_cache || use_clean;
    sweep_cache_.keep_sweeps = use_cache;
    // A test that marks nothing ends BRH (stop_or_recheck) unless it skipped left triangles (the
    // full test then asks the others again, and skips the clean ones): only then are the reach
    // boxes of a test answering all no used. (Were the skinny list's confirmation to fail, the
    // next test would ask those triangles again: slower, the same answers.)
    sweep_cache_.reach_when_all_no = skipped_left_ > 0;
    std::vector<std::uint8_t> answers;
    local_.release_spare(mesh_);  // (the peak memory is reached in the exact test)
    try {
      answers = in_k_bundle(mesh_, K_, asked, nullptr, options_.threads, &sweep_cache_, exact_test_deadline());
    } catch (const KBundleTimeout&) {  // (the mesh is as the last pass left it)
      stats_.stop = StopReason{StopKind::kTimeBudget, 0, {}};
      return Step::kStop;
    }
    sweep_cache_.hints.clear();
    sweep_cache_.hints.shrink_to_fit();
    exact.assign(skinny_.size(), 0);
    witness_at.assign(skinny_.size(), kNoWitness);
    const bool witnessed = sweep_cache_.witnesses.size() == asked.size();
    for (std::size_t j = 0; j < asked.size(); ++j) {
      exact[asked_at[j]] = answers[j];
      if (answers[j] && witnessed) witness_at[asked_at[j]] = sweep_cache_.witnesses[j];
      if (use_clean && !answers[j]) clean_.add(sorted_triple(mesh_, asked[j]), sweep_cache_.reach[j]);
    }
  }
  exact.resize(skinny_.size());  // (all 0 if none was asked)
  ++stats_.exact_evaluations;
  ro_.seed_triangles.clear();
  seed_witness_.clear();
  for (std::size_t i = 0; i < skinny_.size(); ++i) {
    if (!exact[i]) continue;
    marked_.insert(sorted_triple(mesh_, skinny_[i]));
    ro_.seed_triangles.push_back(skinny_[i]);
    seed_witness_.push_back(witness_at[i]);
  }
  if (marked_.empty() && skipped_left_ > 0) return exact_test(true);  // the full test decides
  if (marked_.empty()) return stop_or_recheck();  // no skinny triangle is in a K-bundle
  return Step::kProceed;
}

// ---- one pass of the engine begins here -----------------------------------------------------------

// After the first pass the mesh is refined (hull marked, nothing encroached) and only the marked
// triangles need a look: a seeded pass starts from them alone, at a cost proportional to what it
// splits instead of a sweep over the whole mesh. The first pass, and any pass the local test
// started, sweeps the whole mesh.
BundleRemoval::Step BundleRemoval::refine_pass(bool any_local) {
  if (stats_.rounds == 0 || any_local) ro_.seed_triangles.clear();
  ++stats_.rounds;
  ro_.max_steiner = steiner_budget_;
  record_skinny_ = true;
  if (!clean_.empty()) clean_.snapshot(mesh_);
  // Each pass gets what is left of the budget, not all of it again.
  if (options_.refine.time_budget_seconds > 0.0) {
    ro_.time_budget_seconds = std::max(1e-9, options_.refine.time_budget_seconds - seconds_used());
  }
  std::vector<std::array<VertexId, 3>> seeds_before;
  for (const TriangleId t : ro_.seed_triangles) seeds_before.push_back(sorted_triple(mesh_, t));
  const RefineStats rs = refine(mesh_, ro_);
  if (!clean_.empty()) clean_.update(mesh_);
  remember_left(seeds_before);
  skinny_updated_ = record_skinny_;
  record_skinny_ = false;
  const std::size_t added = rs.steiner_inserted + rs.segment_splits;
  stats_.steiner_inserted += rs.steiner_inserted;
  stats_.segment_splits += rs.segment_splits;
  stats_.left_small_angle = rs.left_small_angle;
  if (rs.stop.kind == StopKind::kSteinerBudget || rs.stop.kind == StopKind::kTimeBudget ||
      rs.stop.kind == StopKind::kBeyondFeatureSize) {
    stats_.stop = rs.stop;
    return Step::kStop;
  }
  if (steiner_budget_ != static_cast<std::size_t>(-1)) steiner_budget_ -= std::min(steiner_budget_, added);
  if (added == 0 && marked_.empty()) {
    force_exact_ = true;
    return Step::kNextRound;
  }
  force_exact_ = false;
  if (added == 0 && skipped_left_ > 0) {
    ask_all_ = true;  // the skipped triangles are asked again before BRH stops
    return Step::kNextRound;
  }
  if (added == 0) {
    // Nothing could be split (the marked triangles sit at small input angles): stop honestly.
    stats_.stop = StopReason{StopKind::kSmallInputAngles, rs.left_small_angle, {}};
    return Step::kStop;
  }
  return Step::kProceed;
}

// The seeds a pass left as they were (same slot, same corners, still skinny) join left_marked_.
void BundleRemoval::remember_left(const std::vector<std::array<VertexId, 3>>& seeds_before) {
  for (std::size_t i = 0; i < seeds_before.size(); ++i) {
    const TriangleId t = ro_.seed_triangles[i];
    if (t < mesh_.triangles.size() && mesh_.in_domain(t) && sorted_triple(mesh_, t) == seeds_before[i] &&
        is_skinny_(mesh_, t)) {
      left_marked_.emplace(seeds_before[i], i < seed_witness_.size() ? seed_witness_[i] : kNoWitness);
    }
  }
  std::vector<Triple>().swap(seed_witness_);
}

}  // namespace

BrhStats bundle_removal(Mesh& mesh, const BrhOptions& options) {
  BundleRemoval removal(mesh, options);
  return removal.run();
}

}  // namespace mwst
