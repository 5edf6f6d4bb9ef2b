// src/algorithms/refine/refine.cpp — Delaunay refinement (DR, and the engine bundle removal
// reuses): the facade refine(), the engine's main loop and its bookkeeping (refiner.hpp lists the
// private steps by file; docs/algorithms/refine.md describes the method and its choices).
//
// Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh generation" (1995), with
// the practical rules of Shewchuk, "Delaunay refinement algorithms for triangular mesh generation"
// (2002) as Triangle 1.6 applies them, and Üngör's off-centers ("Off-centers: a new type of Steiner
// points for computing size-optimal quality-guaranteed Delaunay triangulations", LATIN 2004):
// encroached subsegments are split first (criteria.cpp, segments.cpp); then bad triangles, shortest
// edge first, at their off-centers or circumcenters (steiner.cpp), inserted Bowyer–Watson style
// (insertion.cpp); the Miller–Pav–Walkington rule leaves the triangles at small input angles, and
// the termination guard (termination_guard.cpp) stops runaways above the proven angle bounds.
#include "mwst/algorithms/refine.hpp"

#include "algorithms/refine/refiner.hpp"
#include "mwst/error.hpp"

namespace mwst {

namespace refinement {

// ---- the main loop begins here --------------------------------------------------------------------

void Refiner::run() {
  const auto t0 = Clock::now();
  std::vector<TriangleId> seeds;
  prepare(seeds);
  split_encroached_subsegments(seeds);
  const auto t1 = Clock::now();
  stats_.seconds_segments = std::chrono::duration<double>(t1 - t0).count();
  queue_bad_triangles(seeds);
  split_bad_triangles();
  stats_.seconds_triangles = seconds_since(t1);
  report(count_left());
  stats_.seconds = seconds_since(t0);
}

// Seeded: the mesh was refined before (hull marked, no encroached subsegment); only the seeds
// and what the splits make are looked at. A seed slot that is dead, a ghost or outside is
// ignored (the caller's list may be stale). Unseeded: the hull marked, the arrays reserved, the
// termination guard set, and conforming Delaunay prepared.
void Refiner::prepare(std::vector<TriangleId>& seeds) {
  if (seeded_) {
    for (const TriangleId t : opt_.seed_triangles) {
      if (t < m_.triangles.size() && m_.in_domain(t)) seeds.push_back(t);
    }
  } else {
    mark_hull_segments();
    reserve_for_area_bound();
    reserve_for_angle_bound();
    set_feature_guard();
    if (conforming_) prepare_conforming();
  }
}

// Phase 1: every encroached subsegment, before any triangle (Ruppert's order).
void Refiner::split_encroached_subsegments(const std::vector<TriangleId>& seeds) {
  const std::size_t slots = seeded_ ? seeds.size() : m_.triangles.size();
  for (std::size_t i = 0; i < slots; ++i) {
    if ((i & 4095) == 0 && out_of_time()) return;  // (a sweep of 2M slots on 1M points on an ellipse)
    const TriangleId t = seeded_ ? seeds[i] : static_cast<TriangleId>(i);
    if (!m_.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!m_.is_segment(h)) continue;
      const TriangleId other = m_.sym(h) >> 2;
      if (!seeded_ && m_.in_domain(other) && other < t) continue;  // checked from the other side
      check_subsegment(h);
    }
  }
  split_all_pending();
}

// Phase 2 starts: the bad triangles (of the seeds, or of the whole mesh) queued.
void Refiner::queue_bad_triangles(const std::vector<TriangleId>& seeds) {
  if (seeded_) {
    for (const TriangleId t : seeds) {
      if (m_.in_domain(t)) enqueue_if_bad(t);  // a segment split may have replaced it
    }
  } else {
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      // Every triangle is tested here: with a costly test (BRH's bundle test floods each skinny
      // triangle's disk) that is half of a first pass, so the clock is read here too.
      if ((t & 255) == 0 && out_of_time()) return;
      if (m_.in_domain(t)) enqueue_if_bad(t);
    }
  }
}

// Phase 2: bad triangles split, worst bucket first, until the queue is empty or a budget, the
// Miller–Pav–Walkington rule or the termination guard says otherwise.
void Refiner::split_bad_triangles() {
  std::size_t iterations = 0;
  while (!stop_) {
    // One clock read in 16 turns of the loop, whatever the turn does: a split costs far more than
    // the read, and on inputs where each split flips thousands of edges (points on a circle) 256
    // splits could take seconds. Every turn counts, not only the splits: a turn that pops an entry
    // no longer bad still runs the criterion (BRH's floods the triangle's circumdisk).
    if ((++iterations & 15) == 0 && out_of_time()) break;
    if (!pending_.empty()) {
      split_all_pending();
      continue;
    }
    BucketQueue::Entry entry;
    if (!queue_.pop(entry)) break;
    const TriangleId t = entry.t;
    if (m_.triangles[t].v[0] != entry.v0 || !m_.in_domain(t)) continue;
    Eval ev;
    if (!evaluate(t, ev)) continue;
    if (ev.angle_bad && !ev.size_bad && mpw_leaves(t, ev)) {
      ++stats_.skipped_mpw;
      continue;
    }
    if (ev.angle_bad && !ev.size_bad && ev.shortest2 < guard_length2_) {
      stop_ = true;
      stop_reason_ = StopReason{StopKind::kBeyondFeatureSize, 0, {}};
      break;
    }
    if (budget_reached()) {
      stop_ = true;
      stop_reason_ = StopReason{StopKind::kSteinerBudget, 0, {}};
      break;
    }
    split_triangle(t, ev);
  }
}

// What is left: triangles the test still calls bad (MPW, or precision limits). Every triangle
// made was tested when it was made, so after a clean run with the local default test there is
// nothing to count; a custom test may depend on more than the triangle, so it is rerun. Nothing is
// counted after the time budget ran out.
std::size_t Refiner::count_left() {
  // Out of time, a custom test (BRH's bundle test) is not asked again about every triangle: that
  // would cost as much as the first pass's queue. The caller counts what it reports (BRH: its
  // skinny triangles left).
  // Out of time nothing is counted at all: the stop reason already says the bounds were not all
  // reached, and the sweep (0.3 s on 2M triangles) would run past the budget.
  if (stop_reason_.kind == StopKind::kTimeBudget) return 0;
  std::size_t left = 0;
  if (seeded_) {
    // Only the seeds and the triangles made were tested; a slot tested twice is counted once.
    std::sort(tested_.begin(), tested_.end());
    tested_.erase(std::unique(tested_.begin(), tested_.end()), tested_.end());
    for (const TriangleId t : tested_) {
      if (!m_.in_domain(t)) continue;
      Eval ev;
      if (evaluate(t, ev)) ++left;
    }
  } else if (stop_ || custom_test_ || stats_.skipped_mpw > 0 || stats_.precision_skips > 0 || protected_skips_ > 0) {
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (!m_.in_domain(t)) continue;
      Eval ev;
      if (evaluate(t, ev)) ++left;
    }
  }
  return left;
}

// The stop reason and the counts of what is left.
void Refiner::report(std::size_t left) {
  stats_.left_small_angle = left;
  if (protected_skips_ > 0) stats_.left_protected = left;
  if (stop_reason_.kind != StopKind::kUnset) {
    stats_.stop = stop_reason_;
  } else if (left > 0 && protected_skips_ > 0) {
    stats_.stop = StopReason{StopKind::kProtectedSegments, left, {}};
  } else if (left > 0) {
    stats_.stop = StopReason{StopKind::kSmallInputAngles, left, {}};
  } else {
    stats_.stop = StopReason{StopKind::kBoundReached, 0, {}};
  }
}

// ---- bookkeeping begins here ----------------------------------------------------------------------

// A point set's domain (or Triangle's -c) is its convex hull: hull edges of the domain that are not
// subsegments are marked as subsegments (marker 1), so they are protected like input segments.
void Refiner::mark_hull_segments() {
  ++mesh_edits_;  // (the fan run, fan_run.cpp)
  const std::size_t slots = m_.triangles.size();
  for (TriangleId g = 0; g < slots; ++g) {
    if (m_.is_dead(g) || !m_.is_ghost(g)) continue;
    const Triangle& G = m_.triangles[g];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    const Handle hull_edge = make_handle(g, k);
    if (!m_.is_segment(hull_edge) && m_.in_domain(m_.sym(hull_edge) >> 2)) {
      m_.set_segment(hull_edge, 1);
      ++stats_.hull_edges_marked;
    }
  }
}

// Conforming Delaunay: subsegments with no domain triangle beside them (dangling segments in a
// hole, segments outside the domain) are unmarked, and the outside region is made Delaunay across
// them, so that only subsegments of the domain remain to be made locally Delaunay. The guard of
// the conforming splits is set at kFeatureGuardFraction of the smallest feature.
void Refiner::prepare_conforming() {
  const std::size_t slots = m_.triangles.size();
  stack_.clear();
  for (TriangleId t = 0; t < slots; ++t) {
    if (m_.is_dead(t) || m_.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (m_.is_segment(h) && !m_.in_domain(t) && !m_.in_domain(m_.sym(h) >> 2)) m_.clear_segment(h);
      stack_.push_back(h);
    }
  }
  relax();
  const double length = feature_guard_length(m_, -1.0);
  if (length > 0.0) conforming_guard2_ = length * length;
}

// With an area bound the final size is known in advance to within a few per cent (about 1.6
// triangles per max_area of domain for uniform refinement, measured): reserving once avoids the
// transient doubling of the triangle arrays, which dominates peak memory on large runs. With
// regional bounds (Mesh::area_bound, Triangle's -a of each region) the domain counts triangle by
// triangle, at the smaller of its own bound and max_area: 40,000 regions of 170 triangles each
// grew the arrays by quarters from the start, 15% of that run in copies.
void Refiner::reserve_for_area_bound() {
  if (max_area_ <= 0.0 && !own_bounds_) return;
  double area = 0.0;  // the domain's area in units of its bounds
  for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
    if (!m_.in_domain(t)) continue;
    double bound = own_bounds_ && m_.area_bound[t] > 0.0 ? m_.area_bound[t] : max_area_;
    if (max_area_ > 0.0) bound = std::min(bound, max_area_);
    if (!(bound > 0.0)) continue;  // no bound here
    const auto& v = m_.triangles[t].v;
    area += signed_area(m_.points[v[0]], m_.points[v[1]], m_.points[v[2]]) / bound;
  }
  if (area == 0.0) return;
  // No more than the Steiner budget allows (each point adds two triangles; a budget of 32 on a
  // domain of area 5.6e14 with --max-area 2 reserved 9.8 GB), and no reservation beyond 1e8
  // triangles (2.4 GB): past that the arrays grow as they are used.
  const double expected = std::min(1.7 * area, 2.0 * static_cast<double>(opt_.max_steiner) + 16.0);
  if (!(expected < 1e8)) return;
  reserve_arrays(m_.triangles.size() + static_cast<std::size_t>(expected),
                 m_.points.size() + static_cast<std::size_t>(expected * 0.5));
}

// Without an area bound, refinement to an angle bound ends with 1.6 (uniform points) to 3.7 (a fan
// of narrow wedges) times the triangles it starts with (`mwst generate`, 40k points, 20°). The
// arrays would otherwise grow from their initial size by quarters, five or more copies of the
// whole mesh into fresh pages: on 40k uniform points ~12% of DR's time went to those copies and
// as much again to the page faults. Twice the start is reserved once, untouched (so not resident:
// only address space) until used; past it the arrays grow as before.
void Refiner::reserve_for_angle_bound() {
  if (max_area_ > 0.0 || own_bounds_ || !(alpha_ > 0.0) || custom_test_) return;  // (BRH often adds nothing)
  reserve_arrays(2 * m_.triangles.size(), 2 * m_.points.size());
}

}  // namespace refinement

RefineStats refine(Mesh& mesh, const RefineOptions& options) {
  RefineStats stats;
  const auto t0 = refinement::Clock::now();
  if (options.min_angle_deg > 60.0) {
    throw InputError("", 0, "minimum angle bound above 60 degrees cannot be met");
  }
  if (options.min_angle_deg <= 0.0 && options.max_area <= 0.0 && !options.is_bad && mesh.area_bound.empty() &&
      !options.conforming_delaunay) {
    // Nothing asked: the constrained Delaunay triangulation is returned unchanged.
    stats.stop = StopReason{StopKind::kBoundReached, 0, {}};
    stats.seconds = refinement::seconds_since(t0);
    return stats;
  }
  refinement::Refiner refiner(mesh, options, stats);
  refiner.run();
  return stats;
}

}  // namespace mwst
