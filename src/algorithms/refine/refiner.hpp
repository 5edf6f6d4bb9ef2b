// src/algorithms/refine/refiner.hpp — the Delaunay refinement engine behind refine() (internal).
// The engine is Triangle's: a bucketed queue of bad triangles, a criterion (the angle and area
// test, or the caller's RefineOptions::is_bad) and a Steiner-point rule (circumcenter, off-center,
// or the caller's). docs/algorithms/refine.md describes the method. The private steps, by file:
//   refine.cpp       run: prepare, split_encroached_subsegments, queue_bad_triangles,
//                    split_bad_triangles, count_left, report; hull marking, conforming Delaunay,
//                    the area reservation; the facade refine()
//   criteria.cpp     evaluate (is a triangle bad?), encroaches, check_subsegment, may_split,
//                    mpw_leaves (Miller–Pav–Walkington)
//   steiner.cpp      steiner_point (circumcenter / off-center), split_triangle, split_at_centroid
//   insertion.cpp    walk, insert_for: insert_free (grow_cavity, check_cavity_boundary,
//                    fill_star, queue_star) or insert_lawson; after_insertion
//   segments.cpp     split_all_pending, split_subsegment (concentric shells, the shell through
//                    an encroaching vertex on a segment at a small angle; too_thin_to_split,
//                    find_split_point, insert_split_vertex, fold_hull_after_split), relax,
//                    restore_hull, unfold_hull_slivers, queue_unfolded_corners
//   termination_guard.cpp   set_feature_guard and feature_guard_length
//   fan_run.cpp      the walk's shortcut across a point fan: build_fan_run, skip_fan_run
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "algorithms/refine/walk_rng.hpp"
#include "mesh/keys.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::refinement {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A priority queue of triangle slots in buckets of a positive key (smallest first). The bucket is
// the key's exponent and top mantissa bits, so each octave of the key has 2^kSubBits buckets.
// An entry is a triangle slot and the vertex at its corner 0 when queued: a popped entry whose slot
// now holds a triangle with another corner 0 is stale and dropped without touching coordinates
// (most stale entries are cavity triangles destroyed by an earlier insertion). An entry that
// passes is re-tested, so staleness never causes a wrong split. Within a bucket the last pushed
// comes first (the newest triangles are the ones in cache).
class BucketQueue {
 public:
  static constexpr unsigned kSubBits = 2;
  static constexpr std::size_t kBuckets = std::size_t{2048} << kSubBits;

  BucketQueue() : buckets_(kBuckets), nonempty_(kBuckets / 64, 0) {}

  struct Entry {
    TriangleId t;
    VertexId v0;
  };

  void push(double key, TriangleId t, VertexId v0) {
    std::size_t b = 0;
    if (key > 0.0) {
      b = static_cast<std::size_t>(std::bit_cast<std::uint64_t>(key) >> (52 - kSubBits));
      if (b >= kBuckets) b = kBuckets - 1;
    }
    buckets_[b].push_back({t, v0});
    nonempty_[b >> 6] |= std::uint64_t{1} << (b & 63);
    if (b < lowest_) lowest_ = b;
    ++size_;
  }

  bool pop(Entry& out) {
    if (size_ == 0) return false;
    std::size_t word = lowest_ >> 6;
    std::uint64_t bits = nonempty_[word] & (~std::uint64_t{0} << (lowest_ & 63));
    while (bits == 0) bits = nonempty_[++word];
    const std::size_t b = (word << 6) | static_cast<std::size_t>(std::countr_zero(bits));
    lowest_ = b;
    std::vector<Entry>& v = buckets_[b];
    out = v.back();
    v.pop_back();
    if (v.empty()) nonempty_[b >> 6] &= ~(std::uint64_t{1} << (b & 63));
    --size_;
    return true;
  }

  std::size_t size() const { return size_; }

 private:
  std::vector<std::vector<Entry>> buckets_;
  std::vector<std::uint64_t> nonempty_;
  std::size_t lowest_ = kBuckets;
  std::size_t size_ = 0;
};

// An off-center whose Bowyer–Watson cavity passes this many triangles, if that cavity is one fan of
// nearly cocircular points (Refiner::cavity_is_one_fan), is not inserted: its triangle gets its
// circumcenter instead (Refiner::split_at_circumcenter). All the triangles of such a fan (the
// Delaunay triangulation of points on a circle, and each ring of off-centers inside it) have
// nearly one circumcircle, so any point inside it near the ring takes the whole fan, and
// shortest-edge-first takes the triangle beside the newest point, whose off-center takes the fan
// again, one ring after the other: Θ(m) per point. The circumcenter of a fan triangle is the
// ring's centre; it takes the fan once and leaves a wheel, whose triangles have circles through
// the centre, and points near the ring then meet only a few of them. Refining 1M points on a
// circle at 20°: 105M cavity triangles in all and 55 s of CPU for the refinement without the
// limit, 33M and 5 s with it. The largest off-center cavity in the refinements of the 13 data sets
// has 335 triangles (dr, bundle removal and opt, Table 1, Figure 3), so their meshes are
// unchanged. docs/algorithms/refine.md, "Large cavities".
inline constexpr std::size_t kOffCenterCavityLimit = 1024;
inline constexpr std::size_t kNoCavityLimit = ~std::size_t{0};

// The walk looks for a point fan (fan_run.cpp) once it has crossed this many edges in a row at one
// vertex; ordinary walks cross a handful.
inline constexpr std::size_t kFanTurns = 16;

// What the default test learns about a triangle.
struct Eval {
  bool bad = false;
  bool angle_bad = false;  // smallest angle below the bound
  bool size_bad = false;   // area above the bound
  unsigned apex = 0;       // corner opposite the shortest edge (the smallest angle)
  double shortest2 = 0.0;  // squared length of the shortest edge
  double key = 0.0;        // priority (smaller first)
};

class Refiner {
 public:
  Refiner(Mesh& mesh, const RefineOptions& options, RefineStats& stats)
      : m_(mesh), opt_(options), stats_(stats) {
    const double alpha = std::max(0.0, options.min_angle_deg) * std::numbers::pi / 180.0;
    alpha_ = alpha;
    if (alpha > 0.0) {
      const double c = std::cos(alpha);
      good_cos2_ = c * c;
      offcenter_scale_ = options.offcenter_factor * 0.5 / std::tan(0.5 * alpha);
    }
    // Lens: apex angle ≥ 180° − 2α, i.e. cos(apex) ≤ −cos 2α. For α ≥ 45° the lens would exceed
    // the diametral circle, and for α = 0 it is empty; both fall back to the circle.
    // Conforming Delaunay asks for empty diametral circles (Triangle's -D does the same).
    conforming_ = options.conforming_delaunay;
    lens_ = options.encroachment == Encroachment::kDiametralLens && options.min_angle_deg > 0.0 &&
            options.min_angle_deg < 45.0 && !conforming_;
    if (lens_) {
      const double c2 = std::cos(2.0 * alpha);
      lens_cos2_ = c2 * c2;
    }
    max_area_ = options.max_area;
    own_bounds_ = !mesh.area_bound.empty();
    custom_test_ = static_cast<bool>(options.is_bad);
    if (options.feature_guard_length > 0.0) guard_length2_ = options.feature_guard_length * options.feature_guard_length;
    seeded_ = custom_test_ && !options.seed_triangles.empty();
    worst_first_ = options.order == RefineOrder::kWorstQualityFirst;
  }

  void run();

 private:
  // ---- tests -----------------------------------------------------------------------------------
  bool evaluate(TriangleId t, Eval& ev);
  void enqueue_if_bad(TriangleId t) {
    Eval ev;
    if (seeded_) tested_.push_back(t);
    if (evaluate(t, ev)) queue_.push(ev.key, t, m_.triangles[t].v[0]);
  }
  bool encroaches(const Point& x, const Point& a, const Point& b) const;
  void check_subsegment(Handle h);
  bool may_split(Handle h) const;
  bool mpw_leaves(TriangleId t, const Eval& ev) const;

  // ---- Steiner points --------------------------------------------------------------------------
  Point circumcenter_of(TriangleId t, const Eval& ev) const;
  Point steiner_point(TriangleId t, const Eval& ev, bool& offcenter) const;
  void split_triangle(TriangleId t, const Eval& ev);
  void split_at_circumcenter(TriangleId t, const Eval& ev, const Point& offcenter, TriangleId t0);
  void split_pending_for(TriangleId t, const Eval& ev);
  bool cavity_is_one_fan(TriangleId t, const Eval& ev) const;
  void split_at_centroid(TriangleId t, const Eval& ev);
  void insert_or_split_at_centroid(TriangleId t, const Eval& ev, const Point& p, TriangleId t0);

  // ---- walking and inserting -------------------------------------------------------------------
  enum class WalkKind { kInTriangle, kOnEdge, kOnVertex, kBlocked };
  struct WalkResult {
    WalkKind kind;
    Handle handle;
  };
  WalkResult walk(const Point& p, TriangleId start);
  // The walk's shortcut across a point fan (fan_run.cpp).
  void build_fan_run(VertexId hub, TriangleId t);
  std::size_t skip_fan_run(const Point& p, TriangleId& t, Handle& came_from);
  bool in_fan_run(TriangleId t) const {
    return fan_run_edits_ == mesh_edits_ && t < fan_position_.size() && fan_position_[t] != 0;
  }
  // kTooLarge: an off-center's cavity outgrew kOffCenterCavityLimit (insertion.cpp); nothing changed.
  enum class InsertKind { kInserted, kEncroaches, kProtected, kFailed, kTooLarge };
  InsertKind insert_for(TriangleId t, const Eval& ev, const Point& p, TriangleId t0, std::size_t cavity_limit);
  // The steps of one insertion are defined in insertion.cpp and used only there; inline, they
  // compile into insert_for as one routine (an insertion costs a few thousand instructions, so a
  // call per step would show).
  inline InsertKind insert_free(const Point& p, TriangleId t0, std::size_t cavity_limit);
  inline InsertKind grow_cavity(const Point& p, TriangleId t0, std::size_t cavity_limit);
  inline InsertKind check_cavity_boundary(const Point& p);
  inline void fill_star(const Point& p);
  inline void queue_star(std::size_t n);
  inline void insert_lawson(const Point& p, TriangleId t0);
  void count_cavity(std::size_t size) {
    ++stats_.cavities;
    stats_.cavity_triangles += size;
    stats_.largest_cavity = std::max(stats_.largest_cavity, size);
    ++stats_.cavity_histogram[static_cast<std::size_t>(std::bit_width(size)) - 1];
  }
  void after_insertion(VertexId v, Handle around);

  // ---- subsegments -----------------------------------------------------------------------------
  struct Pending {
    VertexId u, w;
    Handle hint;
  };
  void push_pending(Handle h) { pending_.push_back({m_.org(h), m_.dest(h), h}); }
  Handle find_subsegment(const Pending& p);
  bool split_all_pending();
  bool split_subsegment(Handle h);
  // split_subsegment's steps (segments.cpp only; inline for the same reason as insert_free's).
  inline bool too_thin_to_split(Handle h, double length) const;
  inline bool find_split_point(Handle h, double length, Point& p);
  inline void insert_split_vertex(Handle h, const Point& p);
  inline void fold_hull_after_split(const std::array<Handle, 4>& opposite);
  bool shares_acute_segment(Handle h) const;
  bool shell_through_encroacher(Handle h, double length, const Point& usual, Point& from, Point& to,
                                double& t) const;
  bool encroaches_subsegment_at(Handle around, const Point& q) const;
  // If v is a split vertex of an input segment from c, that segment's other endpoint, else kNone.
  VertexId split_segment_end(VertexId v, VertexId c) const {
    if (m_.vertex_kind[v] != VertexKind::kSteinerOnSegment) return kNone;
    const auto seg = original_segment(v);
    return seg.first == c ? seg.second : (seg.second == c ? seg.first : kNone);
  }
  bool split_point_valid(Handle h, const Point& p) const;
  void restore_hull(std::vector<TriangleId>& work);
  void relax();
  bool unfold_hull_slivers(Handle h);
  void queue_unfolded_corners();
  std::pair<VertexId, VertexId> original_segment(VertexId v) const {
    const auto it = segment_of_.find(v);
    return it == segment_of_.end() ? std::pair<VertexId, VertexId>{kNone, kNone} : it->second;
  }

  // ---- bookkeeping -----------------------------------------------------------------------------
  void prepare(std::vector<TriangleId>& seeds);
  void split_encroached_subsegments(const std::vector<TriangleId>& seeds);
  void queue_bad_triangles(const std::vector<TriangleId>& seeds);
  void split_bad_triangles();
  std::size_t count_left();
  void report(std::size_t left);
  void mark_hull_segments();
  void set_feature_guard();
  void prepare_conforming();
  void reserve_for_area_bound();
  void reserve_for_angle_bound();
  bool budget_reached() const {
    return stats_.steiner_inserted + stats_.segment_splits >= opt_.max_steiner;
  }
  // True, with stop_ set and the reason "time budget", once RefineOptions::time_budget_seconds has
  // passed since the refinement started, less time_reserve_per_vertex for each vertex added. Read by
  // every loop that can run long between two reads (1 in 16 splits, 1 in 256 tested triangles): a
  // stop there leaves a valid mesh.
  bool out_of_time() {
    if (!(opt_.time_budget_seconds > 0.0)) return false;
    const double added = static_cast<double>(stats_.steiner_inserted + stats_.segment_splits);
    if (seconds_since(started_) + opt_.time_reserve_per_vertex * added <= opt_.time_budget_seconds) return false;
    stop_ = true;
    stop_reason_ = StopReason{StopKind::kTimeBudget, 0, {}};
    return true;
  }
  void ensure_capacity() {
    // Grow by a quarter instead of doubling: for large refinements this bounds peak memory.
    const std::size_t tris = m_.triangles.capacity(), verts = m_.points.capacity();
    reserve_arrays(m_.triangles.size() + 2 > tris ? tris + tris / 4 + 64 : 0,
                   m_.points.size() + 1 > verts ? verts + verts / 4 + 64 : 0);
  }
  // Room for `tris` triangle slots and `verts` vertices in every per-slot and per-vertex array of
  // the mesh (none is shrunk).
  void reserve_arrays(std::size_t tris, std::size_t verts) {
    if (tris > m_.triangles.capacity()) {
      m_.triangles.reserve(tris);
      m_.flags.reserve(tris);
      if (!m_.segment_marker.empty()) m_.segment_marker.reserve(3 * tris);
      if (own_bounds_) m_.area_bound.reserve(tris);
    }
    if (verts > m_.points.capacity()) {
      m_.points.reserve(verts);
      m_.vertex_kind.reserve(verts);
      m_.vertex_marker.reserve(verts);
    }
  }

  Mesh& m_;
  const RefineOptions& opt_;
  RefineStats& stats_;
  double alpha_ = 0.0;
  double good_cos2_ = 1.0;  // cos² of the angle bound
  double offcenter_scale_ = 0.0;
  bool lens_ = false;
  double lens_cos2_ = 0.0;
  double max_area_ = -1.0;
  bool own_bounds_ = false;  // Mesh::area_bound in use
  bool conforming_ = false;  // RefineOptions::conforming_delaunay
  std::size_t protected_skips_ = 0;  // triangles left: their point lies on or beyond a protected subsegment
  // Squared length below which a subsegment is no longer split for conforming Delaunay (the
  // termination guard of those splits; 0 = none).
  double conforming_guard2_ = 0.0;
  mutable double domain_area_ = -1.0;  // the domain's area, once too_thin_to_split needs it (< 0: not yet)
  bool custom_test_ = false;
  bool seeded_ = false;  // RefineOptions::seed_triangles in use
  bool worst_first_ = false;
  bool stop_ = false;
  StopReason stop_reason_;  // set when a budget or the termination guard stops the refinement
  const Clock::time_point started_ = Clock::now();  // the time budget counts from here
  std::size_t segment_splits_timed_ = 0;            // split_all_pending's clock reads, 1 in 16
  // Squared length below which an angle-bad triangle's shortest edge stops the refinement (the
  // termination guard; 0 = none): see set_feature_guard().
  double guard_length2_ = 0.0;

  BucketQueue queue_;
  std::vector<Pending> pending_;
  std::unordered_set<std::uint64_t> unsplittable_;
  // Refinement-made vertices on segments → the endpoints of the input segment they lie on.
  std::unordered_map<VertexId, std::pair<VertexId, VertexId>> own_segment_of_;
  std::unordered_map<VertexId, std::pair<VertexId, VertexId>>& segment_of_ =
      opt_.segment_origins != nullptr ? *opt_.segment_origins : own_segment_of_;
  std::uint32_t walk_rng_ = 0x2545F491u;

  // The walk's shortcut across a point fan (fan_run.cpp): one run of triangles around a vertex
  // (the hub) whose far edges lie on one line. fan_spokes_[i] is the edge hub → w_i of the run's
  // i-th triangle (hub, w_i, w_i+1), counter-clockwise; fan_position_[t] is 1 + t's index in the
  // run (0: not in it). The run is valid while fan_run_edits_ == mesh_edits_: every change of the
  // mesh that could touch the run counts one edit (an insertion whose cavity misses the run does
  // not, fill_star).
  std::vector<Handle> fan_spokes_;
  std::vector<std::uint32_t> fan_position_;
  VertexId fan_hub_ = kNone;
  Point fan_line_a_, fan_line_b_;  // two points of the line, in the direction of the far edges
  std::uint64_t mesh_edits_ = 0;
  std::uint64_t fan_run_edits_ = ~std::uint64_t{0};
  // Walk steps taken one at a time while turning about one vertex since the last run was built,
  // and what that build cost: a new run is built only once the first is a quarter of the second,
  // so building never costs more than four times the walking it could save.
  std::size_t fan_credit_ = 0;
  std::size_t fan_build_cost_ = 0;

  // Scratch (no allocation per insertion).
  std::vector<TriangleId> cavity_;
  // cavity_stamp_[t] == cavity_round_ iff slot t is in the cavity being grown: an O(1) membership
  // test (a linear search of cavity_ made an insertion quadratic in its cavity size, and the first
  // insertions into the fan of skinny triangles a point set on a circle gives have cavities of
  // the whole mesh).
  std::vector<std::uint32_t> cavity_stamp_;
  std::uint32_t cavity_round_ = 0;
  std::vector<Handle> boundary_;
  std::vector<Handle> stack_;
  struct BoundaryEdge {
    VertexId org;
    Handle outer;
    bool segment;
    std::int32_t marker;
    double bound;  // Mesh::area_bound of the cavity triangle on this edge
  };
  std::vector<BoundaryEdge> ring_;
  std::vector<TriangleId> slots_;
  std::vector<TriangleId> hull_work_;
  std::vector<TriangleId> unfolded_;  // ghosts made by unfold_hull_slivers, to be refolded
  // unfold_hull_slivers' breadth-first search: its nodes (a triangle and the index of the node it
  // was reached from), and per triangle slot the search that last reached it.
  struct SliverNode {
    TriangleId t;
    std::size_t parent;
  };
  std::vector<SliverNode> sliver_nodes_;
  std::vector<std::uint32_t> sliver_seen_;
  std::uint32_t sliver_search_ = 0;
  std::vector<TriangleId> tested_;    // seeded: every slot tested (the final recount's range)
};

}  // namespace mwst::refinement
