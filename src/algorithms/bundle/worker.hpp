// src/algorithms/bundle/worker.hpp — one thread's share of the bundle number (internal): floods
// over the mesh from the circumdisks of Delaunay triangles, and sweeps over pencils of disks.
// Each Worker owns its scratch (stamped per flood, disk and pencil: nothing is cleared per item).
//
// Floods (below the class, inline: they run per flood and per triangle):
//   flood / flood_each     — the mesh triangles whose edges may meet a circumdisk (permissive)
//   count_meeting          — how many meet it exactly, stopping at `enough`
//   collect_meeting        — which meet it exactly
//   circumdisk_count       — how many of a candidate list meet it exactly
//   meets_circumdisk       — the exact test: corner inside, corner on the circle, edge crossing
// One pencil (worker_sweep.cpp; docs/algorithms/bundle-number.md, "One pencil"):
//   sweep                  — the steps below, for the pencil of one Delaunay edge
//     start_pencil, gather_candidates, reuse_cached_sweep, count_pencil_ends,
//     collect_events (classify, classify_edge), order_events, group_events,
//     best_interval (record_witness), spread_per_triangle
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "algorithms/bundle/approx.hpp"
#include "algorithms/bundle/circle_predicates.hpp"
#include "algorithms/bundle/corner_incircle.hpp"
#include "algorithms/bundle/pencil.hpp"
#include "algorithms/bundle/shared.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/error.hpp"

namespace mwst {

namespace bundle {

// Frees a vector's memory. (`v = {}` does not: it assigns an empty initializer list, which keeps
// the capacity.)
template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

enum : std::uint8_t { kRoleLo = 0, kRoleA = 1, kRoleB = 2, kRoleHi = 3 };

struct Event {
  Threshold th;
  std::uint32_t candidate = kNone;
  std::uint8_t role = kRoleA;
};

struct Candidate {
  TriangleId triangle = 0;
  bool always = false;
  std::uint32_t a_group = kNone;  // class of a_t (counts on the intervals above it)
  std::uint32_t b_group = kNone;  // class of b_t (counts on the intervals below it)
};

// What one edge of a candidate contributes for the current pencil (the same for both triangles
// on the edge, so it is computed once per pencil).
struct EdgeInfo {
  bool crosses = false;  // the edge crosses the open chord pq
  bool has_a = false, has_b = false;
  Threshold a, b;        // infimum of f above the line along the edge / supremum below
};

constexpr std::int8_t kSideP = 2;
constexpr std::int8_t kSideQ = 3;

// A pencil sweep's result kept across in_k_bundle calls (KBundleCache): the key is everything the
// sweep reads — the directed edge p→q, the apices (mesh vertex ids; kInfinite on the hull side)
// and the candidate triangles as vertex triples (mesh ids, rotated to start at the smallest,
// sorted) — and the value is, per candidate in that order, its largest count over the pencil.
// Only pencils with at least kCachedCandidates candidates are kept: the small ones are cheap.
constexpr std::size_t kCachedCandidates = 64;

struct CachedSweep {
  VertexId lv = kNone, rv = kNone;
  std::vector<std::array<VertexId, 3>> triangles;
  std::vector<std::uint32_t> best;
};

using SweepKey = std::uint64_t;  // p << 32 | q (mesh ids)

// in_k_bundle's one-sided pencils: a pencil one of whose two circumdisks meets at least k
// triangles (the "large" end) and none of the queries asked of it, while the other (the "listed"
// end, with a candidate list) meets each of them. Such a pencil's disks meet a query t only on the
// listed end's side of one threshold (docs/algorithms/bundle-number.md, "One-sided pencils"), so
// only the triangles of a lens next to the chord are needed, not the large end's list.
struct OneSided {
  const std::vector<std::uint8_t>* mode = nullptr;     // per pencil: 0 both ends listed (or a hull
                                                       // edge); 1 the left end is listed; 2 the right;
                                                       // 3 neither (not swept)
  const std::vector<std::uint32_t>* begin = nullptr;   // per pencil: its queries in `queries`
  const std::vector<std::uint32_t>* queries = nullptr; // indices into `slots`
  const std::vector<TriangleId>* slots = nullptr;      // the queries: slots of Shared
  const std::vector<std::uint32_t>* box_index = nullptr;  // per pencil: its entry in `boxes`
  std::vector<std::array<double, 4>>* boxes = nullptr; // (null: not wanted) per one-sided pencil, the
                                                       // box of every triangle its lens flood visited
  std::uint32_t k = 0;
};

}  // namespace bundle

struct KBundleCache::Impl {
  std::unordered_map<bundle::SweepKey, bundle::CachedSweep> sweeps;
  Mesh dt;                          // DT(V) of the last call over the whole mesh (empty: none)
  std::vector<VertexId> dt_mesh_id;  // its vertex i is mesh vertex dt_mesh_id[i]
};

namespace bundle {

class Worker {
 public:
  Worker(const Shared& shared, bool per_triangle, bool prune);

  // Results.
  std::uint32_t best_count = 0;
  std::size_t best_pencil = static_cast<std::size_t>(-1);
  Point best_center;
  double best_radius = 0.0;
  std::vector<TriangleId> best_triangles;
  std::uint32_t circumdisk_best = 0;
  std::size_t pencils = 0, candidate_pairs = 0, exact_comparisons = 0;
  std::size_t flood_visits = 0;      // triangles popped by floods (in the domain or not)
  std::uint32_t min_candidates = 0;  // pencils with fewer candidates are not swept
  // Floods decide an edge the filters leave open exactly (an end's incircle sign, then
  // segment_meets_open_circumdisk) instead of crossing it: in_k_bundle's, where the flat disks
  // along a fan's hull edges (nearly collinear segment points) crossed every edge along it.
  bool exact_edges = false;
  bool escaped = false;              // a flood reached Shared::outside (see Shared::build_region)
  // The bounding box (x0, y0, x1, y1) of the corners of every triangle the last flood visited
  // (in the domain or not): it holds every mesh triangle meeting the circumdisk.
  std::array<double, 4> flood_box{};
  bool want_flood_box = false;
  // Sweep results of an earlier call (read only while the workers run), the keys reused and the
  // results made now (merged into the cache afterwards).
  const KBundleCache::Impl* reuse = nullptr;
  // in_k_bundle's one-sided pencils (null: every pencil is swept from both lists), and what they
  // cost: triangles their lens floods popped, and pencils that fell back to the large end's list.
  const OneSided* one_sided = nullptr;
  std::size_t lens_visits = 0, one_sided_fallbacks = 0;
  std::size_t pencils_reused = 0;
  std::vector<SweepKey> reused_keys;
  std::vector<std::pair<SweepKey, CachedSweep>> made;
  // Per mesh slot, the largest count of a disk the sweeps found meeting it (with per-triangle
  // values): allocated at the first sweep or the first read, so that it is not held through the
  // floods that come before the sweeps (in_k_bundle's peak is its candidate lists).
  std::vector<std::uint32_t>& per_triangle() {
    ensure_per_triangle();
    return per_triangle_;
  }
  // Frees the scratch of the floods (flood_each) / of the sweeps (sweep); it is allocated again
  // if used again.
  void release_flood_scratch();
  void release_sweep_scratch();
  void release_disk_scratch();  // circumdisk_count's
  void ensure_per_triangle() {
    if (per_triangle_enabled_ && per_triangle_.empty()) per_triangle_.assign(sh_.slots.size(), 0);
  }

  // ---- floods ----

  // Collects into `out` the in-domain mesh triangles (a superset of those) meeting the open
  // circumdisk of Delaunay triangle `dtt`, by a flood across mesh edges that meet it. The mesh
  // triangles meeting the disk are connected that way: the disk's intersection with the convex
  // hull is convex, and a path inside it avoiding vertices crosses edges at points inside the disk.
  void flood(TriangleId dtt, std::vector<TriangleId>& out) {
    out.clear();
    flood_each(dtt, [&out](TriangleId t) {
      out.push_back(t);
      return true;
    });
  }

  // The flood of flood(), calling visit(t) for each in-domain triangle t it reaches (a superset of
  // those meeting the disk), in the same order; it stops when visit returns false.
  template <class Visit>
  void flood_each(TriangleId dtt, Visit visit) {
    flood_box = {kInf, kInf, -kInf, -kInf};
    const auto& v = sh_.dt.triangles[dtt].v;
    circle_[0] = sh_.pts[v[0]];
    circle_[1] = sh_.pts[v[1]];
    circle_[2] = sh_.pts[v[2]];
    circle_orient_ = orient_approx(circle_[0], circle_[1], circle_[2]);
    corner_circle_ = corner_circle(circle_[0], circle_[1], circle_[2]);
    if (triangle_stamp_.empty()) {
      flood_vertex_.assign(sh_.pts.size(), kUnset);
      triangle_stamp_.assign(sh_.slots.size(), 0);
    }
    for (const VertexId u : flood_touched_) flood_vertex_[u] = kUnset;  // (the last flood's values)
    flood_touched_.clear();
    bump(triangle_mark_, [this] { std::fill(triangle_stamp_.begin(), triangle_stamp_.end(), 0); });
    // The chord from v[0] to v[1] lies in the open disk, and so does the corner of the mesh
    // triangle it leaves v[0] by (or v[1]: see flood_start).
    const TriangleId start = flood_start(v[0], v[1]);
    stack_.clear();
    stack_.push_back(start);
    triangle_stamp_[start] = triangle_mark_;
    while (!stack_.empty()) {
      const TriangleId t = stack_.back();
      stack_.pop_back();
      ++flood_visits;
      if (sh_.in_domain(t) && !visit(t)) return;
      for (unsigned i = 0; i < 3 && want_flood_box; ++i) {
        const VertexId c = sh_.slots[t].v[i];
        const Point& pt = sh_.pts[c];
        flood_box[0] = std::min(flood_box[0], pt.x);
        flood_box[1] = std::min(flood_box[1], pt.y);
        flood_box[2] = std::max(flood_box[2], pt.x);
        flood_box[3] = std::max(flood_box[3], pt.y);
      }
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId n = triangle_of(sh_.sym(h));
        if (n == sh_.outside) {
          // The flood would leave the region (in_k_bundle's local attempt): it cannot be trusted.
          escaped = escaped || edge_may_meet(sh_.org(h), sh_.dest(h));
          continue;
        }
        if (triangle_stamp_[n] == triangle_mark_ || sh_.is_ghost(n)) continue;
        if (edge_may_meet(sh_.org(h), sh_.dest(h))) {
          triangle_stamp_[n] = triangle_mark_;
          stack_.push_back(n);
        }
      }
    }
  }

  // The number of in-domain triangles meeting the open circumdisk of Delaunay triangle `dtt`
  // (exactly: meets_circumdisk), counted along its flood, which stops as soon as `enough` are
  // found: on a disk meeting many triangles (points on a circle: every circumdisk is the whole
  // circle) the cost is that of `enough` triangles, not of all it meets.
  std::uint32_t count_meeting(TriangleId dtt, std::uint32_t enough);

  // The in-domain triangles meeting the open circumdisk of Delaunay triangle `dtt` (exactly), all
  // of them, by one flood: no list is kept but `met`.
  void collect_meeting(TriangleId dtt, std::vector<TriangleId>& met);

  // Does mesh triangle t meet the open circumdisk of Delaunay triangle `dtt`? (Exact.)
  bool disk_meets(TriangleId dtt, TriangleId t);

  // The number of triangles of `list` meeting the open circumdisk of Delaunay triangle `dtt`
  // (see meets_circumdisk); appends them to `met` if it is not null.
  std::uint32_t circumdisk_count(TriangleId dtt, const TriangleId* list, std::size_t size,
                                 std::vector<TriangleId>* met);

  // ---- one pencil ----

  // The largest count of a disk of pencil `index` (sh.pencils), its witness if it beats best_count,
  // the counts of its two end circumdisks (circumdisk_best) and, with per-triangle values, the
  // largest count of a disk meeting each candidate.
  void sweep(std::size_t index);

  // sweep() with the candidates of the pencil's two Delaunay triangles given (full floods, where
  // their lists in Shared were cut at the budget's cap; `right` empty on a hull edge), not pruned.
  void sweep_with_lists(std::size_t index, const std::vector<TriangleId>& left, const std::vector<TriangleId>& right) {
    given_[0] = &left;
    given_[1] = &right;
    sweep(index);
    given_[0] = given_[1] = nullptr;
  }

 private:
  // flood_vertex_'s entry of a vertex whose value the current flood has not computed (an error
  // bound is never negative).
  static constexpr Approx kUnset{0.0, -1.0};
  struct PencilVertex {
    std::int8_t side = 0;  // +1 left of p→q ("above"), −1 right, 0 on the line, kSideP, kSideQ
    Point local;           // local coordinates: p = (−1, 0), q = (1, 0)
  };
  static constexpr std::int8_t kUnsetSide = 127;  // pencil_side_: not computed for this pencil

  // A new disk for meets_circumdisk's caches. (Stamps below 2^15: edge_meets_ keeps the stamp
  // shifted by one bit in 16 bits, disk_side_ by two in 32. Three entries a mesh slot per worker
  // were 12 bytes at in_k_bundle's peak, its first stage; the clearing every 32767 disks costs
  // a pass over 6 bytes a slot, against a flood per disk.)
  void start_disk() {
    if (edge_meets_.empty()) {
      disk_side_.assign(sh_.pts.size(), 0u);
      edge_meets_.assign(3 * sh_.slots.size(), std::uint16_t{0});
    }
    if (++disk_stamp_ == (1u << 15)) {
      std::fill(disk_side_.begin(), disk_side_.end(), 0u);
      std::fill(edge_meets_.begin(), edge_meets_.end(), std::uint16_t{0});
      disk_stamp_ = 1;
    }
  }

  // edge_meets_'s entry for handle h: three per slot (a handle's fourth value is unused).
  static std::size_t edge_entry(Handle h) { return 3 * std::size_t{h >> 2} + (h & 3); }

  // Advances a stamp; on wrap-around clears the marks it guards.
  template <class Stamp, class Clear>
  static void bump(Stamp& stamp, Clear clear) {
    if (++stamp == 0) {
      clear();
      stamp = 1;
    }
  }

  // The finite mesh triangle around vertex a whose closed corner at a contains the direction
  // towards b, or around b towards a (a, b: vertices of the mesh, the chord ab inside the convex
  // hull). Turning around a costs its degree, n/2 at a fan's apex for each of n floods: after a
  // few turns around a alone (where almost every flood of a mesh of bounded degree starts, as it
  // always did), it turns around a and b in step, which costs the smaller degree.
  TriangleId flood_start(VertexId a, VertexId b) const;

  const Approx& circle_value(VertexId v) {
    Approx& f = flood_vertex_[v];
    if (f.error < 0.0) {
      flood_touched_.push_back(v);
      // (With the corner form when incircle's filter cannot vouch: a small disk's values at far
      // vertices, which would let the flood cross every edge with such an end.)
      f = incircle_from_either(circle_[0], circle_[1], circle_[2], sh_.pts[v], corner_circle_);
    }
    return f;
  }

  // Permissive: true whenever the closed segment uw might meet the open circumdisk (never false
  // when it does). g(λ) = incircle value at u + λ(w − u) = (1−λ) g(u) + λ g(w) + O|e|² λ(1−λ),
  // O = orient(a, b, c) > 0: a concave quadratic.
  bool edge_may_meet(VertexId u, VertexId w);

  // Does mesh triangle t meet the open circumdisk of the vertices ca, cb, cc (counter-clockwise)?
  // A corner strictly inside (exact incircle), a corner on the circle whose edge enters the disk
  // (exact), or an edge passing through between two corners outside (exact:
  // segment_meets_open_circumdisk). Only within circumdisk_count(), which starts each disk.
  bool meets_circumdisk(TriangleId t, VertexId ca, VertexId cb, VertexId cc);

  // sweep()'s steps, defined in worker_sweep.cpp and used only there (inline: they compile into
  // sweep() as one routine, and the per-candidate ones into their loops).
  inline bool start_pencil(Handle h, VertexId rv);
  inline void gather_candidates(Handle h, Handle hs, VertexId rv);
  inline bool reuse_cached_sweep(VertexId lv, VertexId rv);
  inline void count_pencil_ends(Handle h, Handle hs);
  inline void collect_events(VertexId lv, VertexId rv, std::uint32_t& always_count, std::uint32_t& b_total);
  inline void begin_events();
  inline void classify_from(std::uint32_t first, std::uint32_t& always_count, std::uint32_t& b_total);
  inline void end_events(VertexId lv, VertexId rv);
  inline void gather_list(const TriangleId* list, std::size_t size);
  // A one-sided pencil (see OneSided): its lens, the queries' counts (worker_sweep.cpp).
  void sweep_one_sided(std::size_t index);
  int one_sided_query(TriangleId t, bool left_listed, const Threshold& s_lo, const Threshold& s_hi, Threshold& bound);
  bool lens_flood(const Threshold& x, bool left_listed, std::uint32_t& always_count, std::uint32_t& b_total);
  void one_sided_fallback(std::size_t index, bool left_listed);
  inline void order_events();
  inline void group_events(std::uint32_t& lo_group, std::uint32_t& hi_group);
  inline std::uint32_t count_at_end(std::uint32_t g, std::uint32_t always_count) const;
  inline void best_interval(std::size_t index, std::uint32_t j_min, std::uint32_t j_max, std::uint32_t always_count,
                            std::uint32_t b_total);
  inline void spread_per_triangle(std::uint32_t j_min, std::uint32_t j_max, bool cacheable);
  // Is mesh slot t a candidate of the current pencil (gather_candidates)?
  bool is_candidate(TriangleId t) const {
    const std::uint32_t i = candidate_index_[t];
    return i < candidates_.size() && candidates_[i].triangle == t;
  }
  // Side of vertex v relative to the directed line p→q, cached per pencil with its local
  // coordinates.
  inline PencilVertex vertex(VertexId v);
  // Keeps the smaller (sigma = +1) or larger (sigma = −1) threshold in `best`.
  inline void keep_extreme(int sigma, bool& has, Threshold& best, const Threshold& t);
  // The contribution of edge uw (see EdgeInfo); `info` starts empty.
  inline void classify_edge(VertexId u, VertexId w, EdgeInfo& info);
  // Classifies candidate i for the current pencil: "always", and/or the thresholds a_t (above:
  // counts for s > a_t) and b_t (below: counts for s < b_t). Edge contributions are shared with
  // the neighbouring candidate across each edge.
  inline void classify(std::uint32_t i, bool& has_a, Threshold& a, bool& has_b, Threshold& b);
  // A disk of the current pencil inside interval j, and the triangles it meets.
  inline void record_witness(std::size_t index, std::uint32_t j, std::uint32_t count);

  const Shared& sh_;
  bool per_triangle_enabled_;
  bool prune_;
  const std::vector<TriangleId>* given_[2] = {nullptr, nullptr};  // sweep_with_lists's candidates
  std::vector<std::uint32_t> per_triangle_;

  // Flood scratch.
  Point circle_[3];
  Approx circle_orient_;
  CornerCircle corner_circle_;
  // 16-bit marks per slot on every thread (cleared every 65,535 floods: a sweep of 2 bytes a slot
  // per that many floods, for half the memory of 32-bit ones).
  std::uint16_t triangle_mark_ = 0;
  // Per vertex, the incircle determinant of the current circle at it (kUnset: not computed yet),
  // and the vertices the current flood computed (reset by the next flood: a stamp per vertex on
  // every thread would add half as much again).
  std::vector<Approx> flood_vertex_;
  std::vector<VertexId> flood_touched_;
  std::vector<std::uint16_t> triangle_stamp_;
  std::vector<TriangleId> stack_;

  // Pencil scratch.
  Pencil pc_;
  // Per vertex (vertex()): its side (kUnsetSide: not computed for the current pencil) and local
  // coordinates, in two arrays (17 bytes a vertex on every thread, not 24), and the vertices the
  // current pencil computed (reset by the next).
  std::vector<std::int8_t> pencil_side_;
  std::vector<Point> pencil_local_;
  std::vector<VertexId> pencil_touched_;
  // circumdisk_count(): per vertex the exact incircle sign the filter left undecided (stamp << 2 |
  // sign + 1), and per edge handle (edge_entry) whether the edge meets the disk (stamp << 1 |
  // answer), per disk.
  std::uint32_t disk_stamp_ = 0;
  std::vector<std::uint32_t> disk_side_;
  std::vector<std::uint16_t> edge_meets_;
  // Per mesh slot: its index in candidates_ if it is a candidate of the current pencil (a sparse
  // set: valid when candidates_[i].triangle is the slot, so that nothing is cleared per pencil).
  std::vector<std::uint32_t> candidate_index_;
  std::vector<Candidate> candidates_;
  std::vector<EdgeInfo> edge_info_;        // the edges classified for the current pencil
  std::vector<std::uint32_t> edge_ref_;    // per candidate edge: its index in edge_info_
  std::vector<Event> events_;
  std::vector<std::uint32_t> group_start_, group_a_, group_b_, counts_, prefix_max_, suffix_max_;
  std::vector<std::uint32_t> key_order_, key_best_;       // the cache key's order; results by candidate
  std::vector<std::array<VertexId, 3>> key_triangles_;   // by candidate
  // One-sided pencils: the lens flood's marks per mesh slot, its stack and box, the queries.
  std::uint32_t lens_mark_ = 0;
  std::vector<std::uint32_t> lens_stamp_;
  std::vector<TriangleId> lens_stack_;
  std::array<double, 4> lens_box_{};
  std::vector<std::pair<TriangleId, Threshold>> one_sided_queries_;
};

// ---- Worker: the floods and the circumdisk test (inline: called per flood and per triangle) ----

// The scratch arrays (per vertex and per slot, on every thread) are allocated when first used:
// floods, disk counts and sweeps each have their own, and bundle_number frees the floods' before
// the sweeps start, so that peak memory holds one phase's scratch, not all.
inline Worker::Worker(const Shared& shared, bool per_triangle, bool prune)
    : sh_(shared), per_triangle_enabled_(per_triangle), prune_(prune) {}

inline void Worker::release_flood_scratch() {
  release(flood_vertex_);
  release(flood_touched_);
  release(triangle_stamp_);
  release(stack_);
}

inline void Worker::release_disk_scratch() {
  release(disk_side_);
  release(edge_meets_);
}

inline void Worker::release_sweep_scratch() {
  release(pencil_side_);
  release(pencil_local_);
  release(pencil_touched_);
  release(candidate_index_);
  release(candidates_);
  release(edge_info_);
  release(edge_ref_);
  release(events_);
  release(lens_stamp_);
  release(lens_stack_);
}

// The finite mesh triangle around vertex a whose closed corner at a contains the direction
// towards `target` (a point of the convex hull other than a).
inline TriangleId Worker::flood_start(VertexId a, VertexId b) const {
  constexpr std::size_t kAloneTurns = 64;
  struct Turning {
    VertexId from;
    const Point* target;
    Handle start, h;
    bool live = true;
  };
  Turning around[2] = {{a, &sh_.pts[b], sh_.vertex_edge[a], sh_.vertex_edge[a]},
                       {b, &sh_.pts[a], sh_.vertex_edge[b], sh_.vertex_edge[b]}};
  // One turn around one end: the triangle if its corner faces the other end, else kNone.
  auto turn = [this](Turning& t) {
    if (triangle_of(t.h) == sh_.outside) {
      t.live = false;
      return kNone;
    }
    const Point& pa = sh_.pts[t.from];
    const VertexId d = sh_.dest(t.h), x = sh_.apex(t.h);
    if (d != kInfinite && x != kInfinite && orient2d(pa, sh_.pts[d], *t.target) >= 0 &&
        orient2d(pa, *t.target, sh_.pts[x]) >= 0) {
      return triangle_of(t.h);
    }
    t.h = sh_.onext(t.h);
    if (t.h == t.start) t.live = false;
    return kNone;
  };
  for (std::size_t k = 0; k < sh_.slots.size() + kAloneTurns && (around[0].live || around[1].live); ++k) {
    for (int side = 0; side < 2; ++side) {
      if (!around[side].live || (side == 1 && k < kAloneTurns)) continue;
      const TriangleId found = turn(around[side]);
      if (found != kNone) return found;
    }
  }
  throw InternalError("bundle: no mesh triangle around a vertex faces its Delaunay neighbour");
}

// Permissive: true whenever the closed segment uw might meet the open circumdisk (never false
// when it does). g(λ) = incircle value at u + λ(w − u) = (1−λ) g(u) + λ g(w) + O|e|² λ(1−λ),
// O = orient(a, b, c) > 0: a concave quadratic.
inline bool Worker::edge_may_meet(VertexId u, VertexId w) {
  const Approx& gu = circle_value(u);
  const Approx& gw = circle_value(w);
  const Point& pu = sh_.pts[u];
  const Point& pw = sh_.pts[w];
  if (gu.value > -gu.error || gw.value > -gw.error) {
    if (!exact_edges) return true;
    // An end inside or on the circle (exactly): the edge meets the closed disk.
    if ((gu.value > -gu.error && incircle(circle_[0], circle_[1], circle_[2], pu) >= 0) ||
        (gw.value > -gw.error && incircle(circle_[0], circle_[1], circle_[2], pw) >= 0)) {
      return true;
    }
    return segment_meets_open_circumdisk(circle_[0], circle_[1], circle_[2], pu, pw);
  }
  const double ex = pw.x - pu.x, ey = pw.y - pu.y;
  const double e2 = ex * ex + ey * ey;
  const double a = circle_orient_.value * e2;
  const double a_error = (circle_orient_.error + 4.0 * kEps * circle_orient_.value) * e2;
  const double slope = gw.value - gu.value + a;
  const double lambda = a > 0.0 ? std::clamp(slope / (2.0 * a), 0.0, 1.0) : 0.0;
  const double gmax = gu.value + lambda * (slope - a * lambda);
  const double slack = 2.0 * (gu.error + gw.error + a_error +
                              8.0 * kEps * (std::fabs(gu.value) + std::fabs(gw.value) + a));
  if (gmax <= -slack) return false;
  if (gmax > slack) return true;
  // Undecided: g_w − g_u cancels for the huge circles of flat Delaunay triangles (nearly
  // collinear hull vertices), which would flood along the whole hull; the centre-based filter
  // rules most such edges out (and with exact_edges, integers decide the rest).
  if (exact_edges) return segment_meets_open_circumdisk(circle_[0], circle_[1], circle_[2], pu, pw);
  return segment_meets_open_circumdisk_filtered(circle_[0], circle_[1], circle_[2], pu, pw) != 0;
}

// The number of in-domain triangles meeting the open circumdisk of Delaunay triangle `dtt`
// (exactly: meets_circumdisk), counted along its flood, which stops as soon as `enough` are
// found: on a disk meeting many triangles (points on a circle: every circumdisk is the whole
// circle) the cost is that of `enough` triangles, not of all it meets.
inline std::uint32_t Worker::count_meeting(TriangleId dtt, std::uint32_t enough) {
  const auto& v = sh_.dt.triangles[dtt].v;
  start_disk();
  std::uint32_t count = 0;
  flood_each(dtt, [&](TriangleId t) {
    if (meets_circumdisk(t, v[0], v[1], v[2])) ++count;
    return count < enough;
  });
  return count;
}

// The in-domain triangles meeting the open circumdisk of Delaunay triangle `dtt` (exactly), all
// of them, by one flood: no list is kept but `met`.
inline void Worker::collect_meeting(TriangleId dtt, std::vector<TriangleId>& met) {
  const auto& v = sh_.dt.triangles[dtt].v;
  start_disk();
  met.clear();
  flood_each(dtt, [&](TriangleId t) {
    if (meets_circumdisk(t, v[0], v[1], v[2])) met.push_back(t);
    return true;
  });
}

// ---- one circumdisk against triangles begins here -------------------------------------------------

// Does mesh triangle t meet the open circumdisk of Delaunay triangle `dtt`? (Exact.)
inline bool Worker::disk_meets(TriangleId dtt, TriangleId t) {
  const auto& v = sh_.dt.triangles[dtt].v;
  start_disk();
  return meets_circumdisk(t, v[0], v[1], v[2]);
}

// The number of triangles of `list` meeting the open circumdisk of Delaunay triangle `dtt`
// (see meets_circumdisk); appends them to `met` if it is not null.
inline std::uint32_t Worker::circumdisk_count(TriangleId dtt, const TriangleId* list, std::size_t size,
                                               std::vector<TriangleId>* met) {
  const auto& v = sh_.dt.triangles[dtt].v;
  start_disk();
  std::uint32_t count = 0;
  for (std::size_t i = 0; i < size; ++i) {
    if (meets_circumdisk(list[i], v[0], v[1], v[2])) {
      ++count;
      if (met) met->push_back(list[i]);
    }
  }
  return count;
}

// Does mesh triangle t meet the open circumdisk of the vertices ca, cb, cc (counter-clockwise)?
// A corner strictly inside (exact incircle), a corner on the circle whose edge enters the disk
// (exact), or an edge passing through between two corners outside (exact:
// segment_meets_open_circumdisk). Only within circumdisk_count(), which starts each disk.
inline bool Worker::meets_circumdisk(TriangleId t, VertexId ca, VertexId cb, VertexId cc) {
  const Point& a = sh_.pts[ca];
  const Point& b = sh_.pts[cb];
  const Point& c = sh_.pts[cc];
  const auto& tv = sh_.slots[t].v;
  int inside[3];
  for (int i = 0; i < 3; ++i) {
    const VertexId v = tv[i];
    if (v == ca || v == cb || v == cc) {
      inside[i] = 0;
      continue;
    }
    // incircle(a, b, c, v): the filter, and the exact stage at most once per vertex and disk (a
    // vertex is a corner of several candidates; on meshes of slivers the disks are nearly flat
    // and most corners need the exact stage).
    const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, c, sh_.pts[v]);
    if (det.value > det.bound) return true;
    if (-det.value > det.bound) {
      inside[i] = -1;
      continue;
    }
    std::uint32_t& side = disk_side_[v];
    if ((side >> 2) != disk_stamp_) {
      side = disk_stamp_ << 2 | static_cast<std::uint32_t>(detail::incircle_exact(a, b, c, sh_.pts[v]) + 1);
    }
    inside[i] = static_cast<int>(side & 3u) - 1;
    if (inside[i] > 0) return true;
  }
  const VertexId circle_ids[3] = {ca, cb, cc};
  for (int i = 0; i < 3; ++i) {
    if (inside[i] != 0) continue;
    const VertexId u = tv[i];
    // u is on the circle: two circle-defining vertices other than u span the same circle.
    VertexId pa = kNone, pb = kNone;
    for (const VertexId z : circle_ids) {
      if (z == u) continue;
      if (pa == kNone) {
        pa = z;
      } else if (pb == kNone) {
        pb = z;
      }
    }
    const Point& p = sh_.pts[pa];
    const Point& q = sh_.pts[pb];
    const Point& pu = sh_.pts[u];
    const int o = orient2d(p, q, pu);
    for (int k = 1; k <= 2; ++k) {
      if (detail::enters_circle(p, q, pu, sh_.pts[tv[(i + k) % 3]], o) > 0) return true;
    }
  }
  for (int i = 0; i < 3; ++i) {
    const int iu = (i + 1) % 3, iw = (i + 2) % 3;
    if (inside[iu] == 0 || inside[iw] == 0) continue;  // decided above
    // Edge i of t (from corner i + 1 to i + 2), decided once per disk for both triangles on it.
    const Handle h = make_handle(t, static_cast<unsigned>(i));
    const std::uint32_t known = edge_meets_[edge_entry(h)];
    if ((known >> 1) == disk_stamp_) {
      if ((known & 1u) != 0) return true;
      continue;
    }
    const bool meets = segment_meets_open_circumdisk(a, b, c, sh_.pts[tv[iu]], sh_.pts[tv[iw]]);
    const auto value = static_cast<std::uint16_t>(disk_stamp_ << 1 | (meets ? 1u : 0u));
    edge_meets_[edge_entry(h)] = value;
    // (Only in-domain triangles are candidates; a region's edges out of it all lead to the one
    // `outside` slot, which is not.)
    const Handle twin = sh_.sym(h);
    if (sh_.in_domain(triangle_of(twin))) edge_meets_[edge_entry(twin)] = value;
    if (meets) return true;
  }
  return false;
}


}  // namespace bundle

}  // namespace mwst
