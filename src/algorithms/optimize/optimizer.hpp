// src/algorithms/optimize/optimizer.hpp — the search behind optimize() (mwst/algorithms/optimize.hpp),
// one object per run over one mesh. Internal (not installed). The steps, in the order run() takes
// them (docs/algorithms/optimize.md explains each move):
//   1. whole_domain_mwt      a domain that is one small polygon → its exact MWT   (optimizer.cpp)
//   2. local_search          rounds of flips, removals, relocations, slides and
//                            region re-triangulations until a round gains little  (optimizer.cpp)
//        try_remove, try_relocate, try_slide                                      (moves.cpp)
//        try_insertions → try_region → try_region_once, region_from               (region_search.cpp)
//   3. kicks_and_search      kicks (trial moves that first raise the weight), then
//                            the local search again, while kicks pay              (optimizer.cpp)
//        kick_insertions, kick_edge_splits, kick_segment_insertions,
//        kick_removals, kick_segment_removals, kick_pairs                        (kicks.cpp)
//   4. perturbation_search   the iterated local search of perturbation_trials     (optimizer.cpp)
//   5. exact_polish          the exact MWT of the vertices while it is lighter    (exact_polish.cpp)
// Every move kept lowers the total weight strictly; every trial is undone unless it does.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <tuple>
#include <vector>

#include "algorithms/optimize/region.hpp"
#include "algorithms/optimize/separation.hpp"
#include "algorithms/optimize/testing.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::opt {

class Optimizer {
 public:
  Optimizer(Mesh& m, const OptimizeOptions& o, const OptimizeTestSwitches& test, OptimizeStats& s,
            std::chrono::steady_clock::time_point deadline)
      : m_(m), opt_(o), test_(test), stats_(s),
        first_free_(static_cast<VertexId>(std::max<std::size_t>(m.input_vertex_count, o.fixed_vertices))),
        separation_(o.min_separation >= 0.0 ? o.min_separation : default_min_separation(m)),
        deadline_(deadline) {}

  // With polish_start, first replaces the mesh by the MWT of its vertices, and returns false
  // without searching if that was not kept (not solved, too large or not lighter).
  bool run(bool polish_start);

 private:
  // ---- the phases (optimizer.cpp) -------------------------------------------------------------
  void whole_domain_mwt();     // the exact MWT of a domain that is one small polygon
  void local_search();         // rounds of local moves until a round gains too little
  void focused_flips();        // EFH's flips (only near the focus in a focused search)
  double local_flips();        // flips from the edges on flip_stack_; the weight change
  void kicks_and_search();     // kick passes alternating with the local search
  void perturbation_search();  // the iterated local search (perturbation_trials)

  // ---- the exact polish (exact_polish.cpp) ----------------------------------------------------
  void exact_polish();       // exact MWTs, each followed by the search, while they pay
  bool exact_polish_step();  // one exact MWT of the vertices; true if kept

  // ---- vertex handles (optimizer.cpp) ---------------------------------------------------------
  void rebuild_vertex_handles();
  Handle handle_of(VertexId v);  // a current handle with org v, kNone if v is gone
  void refresh_handles_after(const Region& r);
  int segment_spokes(VertexId v);  // subsegments among v's spokes, −1 without a handle

  // ---- moves of one vertex (moves.cpp) --------------------------------------------------------
  bool try_remove(VertexId v);    // a free Steiner vertex whose star's MWT is lighter
  bool try_relocate(VertexId v);  // a free Steiner vertex to its neighbours' geometric median
  bool try_slide(VertexId v);     // a Steiner vertex on a segment along the segment
  bool slide_star(Handle h, VertexId ends[2], VertexId hull[4]);  // try_slide's star
  template <class Accept>
  bool move_towards(VertexId v, Point q, Accept accept);  // the first accepted point towards q
  Handle handle_near(VertexId v, Handle near) const;
  void push_star(Handle h);
  double polish_vertex(VertexId v, Handle near);  // flips and geometric medians around a new vertex
  Handle free_steiner_handle(VertexId u) const;
  double polish_neighbours(VertexId v);           // the cluster polish (kick_neighbour_sweeps)
  VertexId insert_free_point(const Point& q, double& delta);
  Handle edge_between(VertexId a, VertexId b) const;  // the edge a → b, kNone if there is none

  // ---- kicks (kicks.cpp) ----------------------------------------------------------------------
  bool kick_insert(TriangleId t, const Point& p, double weight);
  std::size_t kick_insertions();          // a free Steiner point at each centroid
  std::vector<std::tuple<double, VertexId, VertexId>> interior_edges_longest_first() const;
  std::size_t kick_edge_splits();         // a free Steiner point at each edge's midpoint
  std::size_t kick_pairs();               // two points at the thirds of each edge (opt-in)
  std::size_t kick_segment_insertions();  // a Steiner point on a subsegment, then slides
  bool segment_kick_point(VertexId ia, VertexId ib, Handle h, Point& foot);  // where it goes
  std::size_t kick_segment_removals();    // a Steiner point on a segment removed
  bool merge_segment_sides(VertexId v, const std::size_t ends[2], std::vector<std::array<VertexId, 3>>& tris,
                           std::vector<std::uint8_t>& flags, double& delta);  // its two sides' MWTs
  std::size_t kick_removals();            // a free Steiner point removed, then flips
  bool finish_kick_removal(VertexId v, double delta, double weight);  // flips; keep or undo

  // ---- regions re-triangulated whole (region_search.cpp) --------------------------------------
  void try_insertions();  // each triangle's neighbourhood: its MWT or a star from a new point
  bool add_neighbours(TriangleId t, std::vector<TriangleId>& tris);
  bool region_from(const std::vector<TriangleId>& tris, Region& r);
  bool try_region(const std::vector<TriangleId>& tris, bool allow_star = true);
  bool try_region_once(const std::vector<TriangleId>& tris, bool allow_star, bool& depends_on_room);
  // A failed try_region() changes nothing, and what it decided was a function of what it read:
  // the triangles given (slots, in order), their corners, neighbour handles and flags, their
  // corners' points and kinds, and allow_star. The local search retries every region near a
  // change, in every round and every perturbation trial, and most of them have not changed since
  // they last failed, so such failures are remembered by a 128-bit fingerprint of that input and
  // not tried again. A lossy cache (a set-associative table of FailedRegionSet's, the newest
  // kept): forgetting only costs a retry, and a match needs all 128 bits, so the results are
  // those of trying every time, whatever the table's size.
  using RegionFingerprint = std::array<std::uint64_t, 2>;
  static constexpr std::size_t kFailedRegionWays = 4;
  // One set: the newest failure first; 64 bytes, one cache line.
  struct alignas(64) FailedRegionSet {
    std::array<RegionFingerprint, kFailedRegionWays> way{};
  };
  RegionFingerprint region_fingerprint(const std::vector<TriangleId>& tris, bool allow_star) const;
  FailedRegionSet& failed_region_set(const RegionFingerprint& f);

  // ---- budgets and trials (inline: asked before every move) -----------------------------------
  // Has OptimizeOptions::time_budget_seconds passed? (Sticky: once it has, every loop stops.)
  bool out_of_time() {
    if (!stats_.out_of_time && deadline_ != std::chrono::steady_clock::time_point::max() &&
        std::chrono::steady_clock::now() >= deadline_) {
      stats_.out_of_time = true;
    }
    return stats_.out_of_time;
  }

  // A kick is a trial: begun, then kept or undone (Mesh::begin_trial(): a journal of what the
  // trial changes, undone in time proportional to it; a copy of the mesh per trial made the kicks
  // quadratic, 42 % of opt's time on a 54 000-triangle mesh). OptimizeTestSwitches::
  // undo_trials_by_copy (testing) copies instead.
  void begin_trial() {
    if (test_.undo_trials_by_copy) {
      backup_ = m_;
    } else {
      m_.begin_trial();
    }
  }
  void keep_trial() {
    if (!test_.undo_trials_by_copy) m_.commit_trial();
  }
  void undo_trial() {
    if (test_.undo_trials_by_copy) {
      m_ = backup_;
    } else {
      m_.undo_trial();
    }
  }

  // May one more kick be tried (trial budget and time budget)?
  bool may_kick() { return kick_trials_ < opt_.max_kick_trials && !out_of_time(); }

  // How many more Steiner vertices OptimizeOptions::max_steiner allows (a scan of the vertices,
  // made only when there is a budget: the moves that insert call it once per trial, which copies
  // the mesh anyway, or once per insertion about to be kept).
  std::size_t steiner_room() const {
    if (opt_.max_steiner == std::numeric_limits<std::size_t>::max()) return opt_.max_steiner;
    std::size_t count = 0;
    for (VertexId v = first_free_; v < m_.points.size(); ++v) {
      const VertexKind kind = m_.vertex_kind[v];
      count += kind == VertexKind::kSteiner || kind == VertexKind::kSteinerOnSegment;
    }
    return count >= opt_.max_steiner ? 0 : opt_.max_steiner - count;
  }

  // Does a focused search (perturbation_search) look at p?
  bool in_focus(const Point& p) const {
    return !focused_ || (focus_lo_.x <= p.x && p.x <= focus_hi_.x && focus_lo_.y <= p.y && p.y <= focus_hi_.y);
  }

  // ---- the rules every move obeys (inline) ----------------------------------------------------
  double edge_length(Handle h) const { return distance(m_.points[m_.org(h)], m_.points[m_.dest(h)]); }

  // OptimizeOptions::min_separation: may a Steiner vertex be placed at q inside the polygon whose
  // edges `beyond` sees from outside (point_is_separated)?
  bool separated(const Point& q, const std::vector<Handle>& beyond) const {
    return !(separation_ > 0.0) || point_is_separated(m_, q, beyond, separation_);
  }
  bool separated(const Point& q, std::initializer_list<Handle> inside) {
    if (!(separation_ > 0.0)) return true;
    beyond_.clear();
    for (const Handle h : inside) beyond_.push_back(m_.sym(h));
    return separated(q, beyond_);
  }
  // ... inside triangle t; inside the two triangles of edge h.
  bool separated_in_triangle(const Point& q, TriangleId t) {
    return separated(q, {make_handle(t, 0), make_handle(t, 1), make_handle(t, 2)});
  }
  bool separated_at_edge(const Point& q, Handle h) {
    const Handle g = m_.sym(h);
    return separated(q, {Mesh::lnext(h), Mesh::lprev(h), Mesh::lnext(g), Mesh::lprev(g)});
  }

  bool star_in_domain(const Region& r) const {
    for (const TriangleId t : r.triangles) {
      if (!m_.in_domain(t)) return false;
    }
    return true;
  }

  // OptimizeOptions::max_area: may a move make triangle (a, b, c) (counter-clockwise)?
  bool area_allows(const Point& a, const Point& b, const Point& c) const {
    return !(opt_.max_area > 0.0) || triangle_area(a, b, c) <= opt_.max_area;
  }

  // ... every triangle of a triangulation (local indices) of `polygon`?
  bool within_area(const std::vector<Point>& polygon, const std::vector<std::array<std::uint32_t, 3>>& tris) const {
    if (!(opt_.max_area > 0.0)) return true;
    for (const auto& t : tris) {
      if (!area_allows(polygon[t[0]], polygon[t[1]], polygon[t[2]])) return false;
    }
    return true;
  }

  // ... every triangle of the star from q to the closed polygon (q, polygon[i], polygon[i + 1])?
  bool star_within_area(const Point& q, const std::vector<Point>& polygon) const {
    if (!(opt_.max_area > 0.0)) return true;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      if (!area_allows(q, polygon[i], polygon[(i + 1) % polygon.size()])) return false;
    }
    return true;
  }

  // spans_straight_angle for a triangulation of region_'s boundary polygon.
  bool region_sliver(const std::vector<std::array<std::uint32_t, 3>>& tris) const {
    return spans_straight_angle(m_, region_.boundary, [this](std::size_t i) { return region_.segment[i] != 0; },
                                tris);
  }

  // ---- state ----------------------------------------------------------------------------------
  Mesh& m_;
  const OptimizeOptions& opt_;
  const OptimizeTestSwitches& test_;
  OptimizeStats& stats_;
  VertexId first_free_;  // the first vertex the search may move or remove (OptimizeOptions::fixed_vertices)
  double separation_;    // OptimizeOptions::min_separation, resolved
  std::vector<Handle> beyond_;  // separated(): the handles beyond a polygon's edges
  std::vector<Handle> vertex_handle_;
  Region region_;
  std::vector<Point> polygon_;
  std::vector<std::array<std::uint32_t, 3>> local_;
  std::vector<TriangleId> member_;
  std::vector<std::pair<VertexId, Handle>> boundary_from_;  // region_from(): boundary edges by origin
  std::vector<FailedRegionSet> failed_regions_;  // try_region(): fingerprints of failures
  double region_interior_weight_ = 0.0;
  Mesh backup_;
  std::vector<Handle> flip_stack_;
  std::vector<Point> slide_spokes_;
  std::vector<std::pair<VertexId, VertexId>> slide_triangles_;
  std::vector<std::pair<VertexId, VertexId>> slide_domain_triangles_;  // those in the domain
  std::vector<Handle> slide_beyond_;  // across their link edges
  std::vector<VertexId> neighbours_;
  std::vector<double> cumulative_;  // perimeter prefix sums (perturbation_search)
  bool focused_ = false;  // local_search visits only what lies in [focus_lo_, focus_hi_]
  Point focus_lo_{0.0, 0.0};
  Point focus_hi_{0.0, 0.0};
  std::size_t kick_trials_ = 0;
  std::chrono::steady_clock::time_point deadline_;  // time_point::max(): no time budget
};

}  // namespace mwst::opt
