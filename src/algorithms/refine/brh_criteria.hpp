// src/algorithms/refine/brh_criteria.hpp — bundle removal's criterion for the refinement engine
// (internal): the shape of CGAL's Delaunay_mesh_criteria_2 beside Delaunay_mesher_2. BRH plugs
// "skinny and in a K-bundle" into RefineOptions::is_bad; the engine (refiner.hpp) does the rest.
//   sorted_triple    — a triangle by its corners, whatever its slot
//   SkinnyTest       — an angle below A, decided without atan2 when it can be
//   FloodSet         — a set emptied in O(1), what one flood has seen
//   LocalBundleTest  — the fast local witness: the circumdisk of t or of a neighbour is
//                      vertex-empty and meets at least K triangles (exact test: in_k_bundle)
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "algorithms/refine/vertex_index.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::brh {

inline std::array<VertexId, 3> sorted_triple(const Mesh& m, TriangleId t) {
  std::array<VertexId, 3> v = m.triangles[t].v;
  std::sort(v.begin(), v.end());
  return v;
}

// Has t an angle below A (in degrees, as triangle_angles_deg measures it)? The angle at a corner
// is atan2(|cross|, dot) of the two edges leaving it; below A < 90° iff dot > 0 and
// |cross| < tan(A)·dot. That comparison decides unless the two sides agree to 1e-9 relatively;
// then (and for A ≥ 90°) the angle itself is computed, so the answer is always the one
// triangle_angles_deg gives. Called for every triangle the refinement makes: no atan2 on the way.
class SkinnyTest {
 public:
  explicit SkinnyTest(double min_angle_deg)
      : a_(min_angle_deg), tan_a_(std::tan(min_angle_deg * std::numbers::pi / 180.0)), fast_(min_angle_deg < 89.0) {}

  bool operator()(const Mesh& m, TriangleId t) const {
    const auto& v = m.triangles[t].v;
    const Point* p[3] = {&m.points[v[0]], &m.points[v[1]], &m.points[v[2]]};
    for (int i = 0; i < 3; ++i) {
      const Point& o = *p[i];
      const Point& q = *p[(i + 1) % 3];
      const Point& r = *p[(i + 2) % 3];
      const double ux = q.x - o.x, uy = q.y - o.y, vx = r.x - o.x, vy = r.y - o.y;
      const double cross = std::fabs(ux * vy - uy * vx), dot = ux * vx + uy * vy;
      if (fast_) {
        if (dot <= 0.0) continue;  // a right or obtuse angle
        const double bound = tan_a_ * dot;
        if (cross < bound * (1.0 - 1e-9)) return true;
        if (cross > bound * (1.0 + 1e-9)) continue;
      }
      if (std::atan2(cross, dot) * 180.0 / std::numbers::pi < a_) return true;
    }
    return false;
  }

 private:
  double a_, tan_a_;
  bool fast_;
};

// A set of 32-bit keys (triangle slots, vertex ids) emptied in O(1) by a new stamp: what one flood
// of the local test has seen. Its table is sized for every key a flood can add (the flood is capped)
// and stays in cache, where per-slot or per-vertex stamp arrays over the whole mesh would not.
class FloodSet {
 public:
  explicit FloodSet(std::size_t max_keys) : cells_(std::bit_ceil(2 * max_keys + 16)), mask_(cells_.size() - 1) {}

  void clear() {
    if (++stamp_ == 0) {
      std::fill(cells_.begin(), cells_.end(), Cell{});
      stamp_ = 1;
    }
  }
  bool contains(std::uint32_t key) const {
    for (std::size_t i = hash(key);; i = (i + 1) & mask_) {
      if (cells_[i].stamp != stamp_) return false;
      if (cells_[i].key == key) return true;
    }
  }
  // Adds key; false if it was there.
  bool insert(std::uint32_t key) {
    std::size_t i = hash(key);
    for (; cells_[i].stamp == stamp_; i = (i + 1) & mask_) {
      if (cells_[i].key == key) return false;
    }
    cells_[i] = {key, stamp_};
    return true;
  }

 private:
  struct Cell {
    std::uint32_t key = 0;
    std::uint32_t stamp = 0;
  };
  std::size_t hash(std::uint32_t key) const {
    return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> 40) & mask_;
  }
  std::vector<Cell> cells_;
  std::size_t mask_;
  std::uint32_t stamp_ = 1;
};

// The local test: is the open circumdisk of t, or of a (live, finite) neighbour of t, free of
// vertices and meeting at least K in-domain triangles? Such a disk meets t (t's own circumdisk
// holds t; a neighbour's holds the shared edge's interior, hence points of t), so t is then in a
// K-bundle (up to the floating-point edge crossings of the flood). Results are cached per slot
// and corner triple until clear().
//
// When every segment of the mesh is a convex hull edge (point sets), the mesh is the Delaunay
// triangulation of its vertices and every circumdisk is vertex-empty (the empty circle property),
// so a flood stops as soon as it has counted K in-domain triangles: the answer is yes, at a cost
// of O(K) visits, however many triangles the disk meets. Otherwise (interior segments, holes) a
// vertex hidden behind a segment may lie in the disk: an index over the vertices (VertexIndex)
// decides whether one does, exactly, without flooding the disk; a disk it shows empty is flooded
// up to K in-domain triangles as on a Delaunay mesh, one holding a vertex not at all. Disks too
// flat for the index are flooded whole, giving up past cap_ visits (unknown: the exact test
// decides). So a query costs O(K) visits plus the index's search.
class LocalBundleTest {
 public:
  // What the floods cost: the visits (triangles popped) of each, and how they ended. An internal
  // hook for the tests (a flood's visits are bounded by O(K)), not a timing.
  struct Stats {
    std::uint64_t floods = 0;          // circumdisk floods run (cache misses)
    std::uint64_t visits = 0;          // triangles popped, over all floods
    std::uint64_t max_visits = 0;      // the most one flood popped
    std::uint64_t stopped_at_k = 0;    // Delaunay floods that stopped on reaching K
    std::uint64_t capped = 0;          // floods that gave up past cap_ visits
    std::uint64_t known_not_empty = 0; // disks not flooded: an earlier flood found a vertex inside
    std::uint64_t recent_inside = 0;   // disks not flooded: a vertex found inside another disk is in
    std::uint64_t index_empty = 0;     // constrained mesh: disks the vertex index showed empty
    std::uint64_t index_holds = 0;     // constrained mesh: disks not flooded, the index found a vertex in
    std::uint64_t index_visits = 0;    // kd nodes and pending vertices the index looked at
    std::uint64_t reached_k = 0;       // floods that counted K in-domain triangles
    std::uint64_t index_queries = 0;   // constrained mesh: questions to the vertex index
    std::uint64_t index_newer = 0;     // of them, about the vertices newer than the disk's last query only
    std::uint64_t index_crowded = 0;   // disks not searched: more vertices near the rim than the search visits
    std::uint64_t crowd_reads = 0;     // kd boxes the crowding counts read
  };

  // A flood pops at most cap_ + 1 triangles, so it adds at most 3 (cap_ + 1) + 1 triangles and
  // as many vertices plus the three corners to its sets.
  explicit LocalBundleTest(std::uint32_t k)
      : k_(k), cap_(8 * static_cast<std::size_t>(k) + 64), seen_triangles_(3 * cap_ + 8), seen_vertices_(3 * cap_ + 8) {}

  // Forgets every cached result (a new epoch: no sweep over the cache), and whether the mesh is
  // Delaunay (looked up again by the first query of the epoch: a pass only splits segments, so
  // it cannot make a segment that is not a hull edge).
  void clear() {
    if (++epoch_ == 0) {
      for (SlotCache& c : cache_) c.epoch = 0;
      epoch_ = 1;
    }
    delaunay_known_ = false;
  }

  // Frees the cache's spare room (a quarter of the slots, kept for the refinement's growth) while
  // the mesh does not grow: BRH calls it before the exact test, whose peak memory it lowers. Every
  // entry is kept (the slots past triangle_slots() hold none), so no answer changes.
  void release_spare(const Mesh& m) {
    if (cache_.size() > m.triangle_slots()) cache_.resize(m.triangle_slots());
    cache_.shrink_to_fit();
  }

  const Stats& stats() const { return stats_; }
  std::size_t cap() const { return cap_; }
  // Whether a crowded disk's index search waits for its flood (on by default; off only for the
  // tests, which compare the answers of both).
  void set_defer_crowded(bool on) { defer_crowded_ = on; }

  bool in_bundle(const Mesh& m, TriangleId t) {
    if (!delaunay_known_) {
      delaunay_ = only_hull_segments(m);
      delaunay_known_ = true;
    }
    SlotCache& c = slot_cache(m, t);
    if (c.epoch == epoch_) return c.value == 2;
    // The disks of t and of its live finite neighbours. A disk's count is its cached one if it has
    // one, else a flood's, whichever disk is asked first, so asking the cached ones first (a star's
    // triangles share neighbours) changes no answer, only saves floods.
    std::array<TriangleId, 4> disks{t, kNone, kNone, kNone};
    for (unsigned e = 0; e < 3; ++e) {
      const TriangleId n = triangle_of(m.triangles[t].n[e]);
      if (!m.is_ghost(n) && !m.is_dead(n)) disks[e + 1] = n;
    }
    bool found = false;
    for (const TriangleId d : disks) {
      if (d != kNone && !found) found = cached_count(m, d) >= k_;
    }
    // A neighbour outside the domain first (across a segment: a hole's triangles, whose disk, the
    // hole's circle, is a witness for the skinny triangles beside it); the answer is the same in
    // any order, each disk's count being its own.
    for (std::size_t i = 2; i < 4; ++i) {
      if (disks[i] != kNone && !m.in_domain(disks[i]) && (disks[1] == kNone || m.in_domain(disks[1]))) {
        std::swap(disks[1], disks[i]);
      }
    }
    if (disks[1] != kNone && !m.in_domain(disks[1])) std::swap(disks[0], disks[1]);
    for (const TriangleId d : disks) {
      if (d != kNone && !found) found = disk_count(m, d) >= k_;
    }
    SlotCache& done = slot_cache(m, t);  // (the floods may have grown cache_)
    done.value = found ? 2 : 1;
    done.epoch = epoch_;
    return found;
  }

 private:
  // Per slot, for the triangle its corners `v` make: in_bundle's answer in this epoch, and whether
  // the count of its circumdisk reaches K at a mesh version (disk_count; the count is only ever
  // compared with K, so that is all that is kept).
  struct SlotCache {
    std::array<VertexId, 3> v{kNone, kNone, kNone};
    std::uint32_t version = 0;  // the count's mesh version (0: none; a mesh has 3 vertices or more)
    // The index showed that none of the vertices below this id lies strictly inside the disk (0:
    // not known): a later flood asks it about the newer ones only.
    std::uint32_t empty_below = 0;
    std::uint16_t epoch = 0;            // in_bundle's answer is valid if equal to epoch_
    std::uint8_t value : 2 = 0;         // in_bundle's answer: 1 no, 2 yes
    std::uint8_t holds_vertex : 1 = 0;  // a vertex lies strictly inside the disk: count 0 whatever the version
    std::uint8_t reaches_k : 1 = 0;     // the count at `version` is K or more
  };
  static_assert(sizeof(SlotCache) == 24);

  // circumdisk_count(m, c), remembered while the mesh is unchanged: the refinement only inserts
  // vertices, so the mesh is the same while its vertex and slot counts are (the triangles made by
  // one insertion are tested one after another, each with its neighbours, many of them made by the
  // same insertion: without this, one disk would be flooded up to four times).
  // True if every segment of m is a convex hull edge (a ghost triangle across it): the CDT is then
  // the Delaunay triangulation of the vertices.
  static bool only_hull_segments(const Mesh& m) {
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (m.is_dead(t) || m.is_ghost(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (m.is_segment(h) && !m.is_ghost(triangle_of(m.sym(h)))) return false;
      }
    }
    return true;
  }

  // The refinement changes the mesh only by inserting vertices, so the vertex count is its version.
  static std::uint32_t mesh_version(const Mesh& m) { return static_cast<std::uint32_t>(m.points.size()); }

  // What is remembered of slot t, for its corners now: an entry made for other corners (the slot
  // held another triangle) is reset.
  SlotCache& slot_cache(const Mesh& m, TriangleId t) {
    if (cache_.size() < m.triangle_slots()) cache_.resize(m.triangle_slots() + m.triangle_slots() / 4 + 64);
    SlotCache& c = cache_[t];
    if (c.v != m.triangles[t].v) c = SlotCache{m.triangles[t].v};
    return c;
  }

  // disk_count's remembered value (K if it reached K), or 0 if it has none.
  std::uint32_t cached_count(const Mesh& m, TriangleId c) const {
    if (c >= cache_.size()) return 0;
    const SlotCache& d = cache_[c];
    return d.version == mesh_version(m) && d.v == m.triangles[c].v && d.reaches_k ? k_ : 0;
  }

  // A disk found to hold a vertex strictly inside holds it for good: the refinement only adds
  // vertices, and the disk is the circumdisk of the slot's corners. Such a slot is not flooded
  // again while it keeps its corners, whatever the mesh version (on polygons with circular holes,
  // the disks of the triangles inside a hole, or across its boundary, were flooded after every
  // insertion nearby, each time with exact incircle tests on the hole's near-cocircular vertices).
  std::uint32_t disk_count(const Mesh& m, TriangleId c) {
    const std::uint32_t version = mesh_version(m);
    {
      const SlotCache& d = slot_cache(m, c);
      if (d.holds_vertex) {
        ++stats_.known_not_empty;
        return 0;
      }
      if (d.version == version) return d.reaches_k ? k_ : 0;
    }
    holds_vertex_ = false;
    shown_empty_ = false;
    const std::uint32_t count = circumdisk_count(m, c);
    SlotCache& d = slot_cache(m, c);  // (a reference taken before the flood would do as well)
    d.version = version;
    d.reaches_k = count >= k_;
    d.holds_vertex = holds_vertex_;
    if (shown_empty_) d.empty_below = version;
    return count;
  }

  // The number of in-domain triangles meeting the open circumdisk of c, by a flood across the
  // edges meeting it; 0 if a vertex lies strictly inside the disk (exact incircle), or if the
  // flood grows past cap_ (unknown: the exact test will decide). On a Delaunay mesh the count
  // stops at K (the disk is vertex-empty: K is the answer the caller needs).
  std::uint32_t circumdisk_count(const Mesh& m, TriangleId c) {
    ++stats_.floods;
    std::size_t visited = 0;
    const std::uint32_t count = flood(m, c, visited);
    stats_.visits += visited;
    stats_.max_visits = std::max<std::uint64_t>(stats_.max_visits, visited);
    return count;
  }

  std::uint32_t flood(const Mesh& m, TriangleId c, std::size_t& visited) {
    if (++stamp_ == 0) {
      value_.fill(ValueSlot{});
      stamp_ = 1;
    }
    seen_triangles_.clear();
    seen_vertices_.clear();
    const auto& cv = m.triangles[c].v;
    const Point& a = m.points[cv[0]];
    const Point& b = m.points[cv[1]];
    const Point& d = m.points[cv[2]];
    const double orient = (a.x - d.x) * (b.y - d.y) - (a.y - d.y) * (b.x - d.x);
    if (!delaunay_ && recent_holds_vertex(m, cv)) return 0;
    // Is the disk known to hold no vertex (then the flood stops at K and tests no vertex)? On a
    // Delaunay mesh always. On a constrained mesh, if an earlier flood of this slot showed it empty
    // of the vertices then present, the index is asked about the newer ones only (the refinement
    // only appends vertices, and the disk is the circumdisk of the slot's corners); otherwise the
    // index is asked only when the flood has counted K: a flood that ends below K has seen every
    // triangle meeting the disk, hence every vertex in it.
    bool known_empty = delaunay_;
    bool index_asked = delaunay_;
    bool index_deferred = false;  // the search was not run: the disk is crowded (see below)
    if (!delaunay_ && cache_[c].empty_below != 0) {
      index_asked = true;
      ++stats_.index_newer;
      known_empty = indexed_empty(m, cv, cache_[c].empty_below);
      if (holds_vertex_) return 0;
    }
    for (const VertexId v : cv) {
      seen_vertices_.insert(v);
      value_[v % kValueCache] = {v, stamp_, 0.0};
    }
    auto value_at = [&](VertexId v) {
      ValueSlot& s = value_[v % kValueCache];
      if (s.v != v || s.stamp != stamp_) return detail::incircle_determinant(a, b, d, m.points[v]).value;
      return s.value;
    };
    stack_.clear();
    stack_.push_back(c);
    seen_triangles_.insert(c);
    std::uint32_t count = 0;
    while (!stack_.empty()) {
      const TriangleId t = stack_.back();
      stack_.pop_back();
      if (++visited > cap_) {
        ++stats_.capped;
        return 0;
      }
      if (m.in_domain(t) && ++count >= k_) {
        if (count == k_) ++stats_.reached_k;
        if (!index_asked) {
          index_asked = true;
          // A disk crowded by more vertices near its rim than the search may visit cannot be shown
          // empty by it: the search would find a vertex inside (answer 0) or give up (the flood
          // goes on, whole). The flood goes on at once; the search is run only if the flood ends
          // below its cap, when its answer decides (see index_deferred below).
          index_deferred = defer_crowded_ && crowded(m, cv);
          if (!index_deferred) {
            known_empty = indexed_empty(m, cv, 0);
            if (holds_vertex_) return 0;
          }
        }
        if (known_empty) {
          ++stats_.stopped_at_k;
          return count;
        }
      }
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const VertexId u = m.org(h), w = m.dest(h);
        // The incircle value along the edge is a concave quadratic: its maximum on [0, 1]. (Tested
        // first: it needs only t's corners, so the triangle across is loaded only for edges that
        // meet the disk.)
        const double gu = value_at(u), gw = value_at(w);
        const Point& pu = m.points[u];
        const Point& pw = m.points[w];
        const double ex = pw.x - pu.x, ey = pw.y - pu.y;
        const double quad = orient * (ex * ex + ey * ey);
        const double slope = gw - gu + quad;
        const double lambda = quad > 0.0 ? std::clamp(slope / (2.0 * quad), 0.0, 1.0) : 0.0;
        if (!(gu + lambda * (slope - quad * lambda) > 0.0)) continue;
        const Handle across = m.sym(h);
        const TriangleId n = triangle_of(across);
        if (seen_triangles_.contains(n)) continue;
        // u and w are finite (t is), so the triangle across is a ghost iff its apex is infinite.
        const VertexId x = m.apex(across);
        if (x == kInfinite) continue;
        seen_triangles_.insert(n);
        if (seen_vertices_.insert(x)) {
          // The sign of the incircle determinant decides (exactly: incircle's filter, then its exact
          // stage only when the filter cannot vouch); its rounded value serves the edge tests. (In
          // a disk known empty the sign is not needed.)
          const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, d, m.points[x]);
          if (!known_empty && (det.value > det.bound || (!(-det.value > det.bound) && exact_sign(m, cv, x) > 0))) {
            holds_vertex_ = true;  // the disk is not vertex-empty, for good
            remember_inside(x);
            return 0;
          }
          value_[x % kValueCache] = {x, stamp_, det.value};
        }
        stack_.push_back(n);
      }
    }
    // The flood saw the whole disk without passing its cap. The search skipped for a crowded disk
    // answers now as it would have then: a vertex inside it found ends in 0, as before; it cannot
    // show the disk empty (then the count at K, as a flood stopped there, would be the answer).
    if (index_deferred) {
      known_empty = indexed_empty(m, cv, 0);
      if (holds_vertex_) return 0;
      if (known_empty) return k_;
    }
    return count;
  }

  // Does one of the vertices recently found inside a disk lie strictly inside the circumdisk of
  // corners cv? Then the flood's answer is 0 whatever it would visit first (a vertex strictly
  // inside is a corner of a triangle meeting the disk; the flood answers 0 when it finds one or
  // when it passes its cap), so it is not run. On a fan of narrow wedges the slivers near the apex
  // have disks reaching across hundreds of wedges, holding the apex's neighbours: their floods
  // passed the cap before finding one (10,000 vertices: 250k floods of 376 visits).
  bool recent_holds_vertex(const Mesh& m, const std::array<VertexId, 3>& cv) {
    for (const VertexId x : recent_inside_) {
      if (x == kNone || x == cv[0] || x == cv[1] || x == cv[2]) continue;
      const detail::FilteredDeterminant det =
          detail::incircle_determinant(m.points[cv[0]], m.points[cv[1]], m.points[cv[2]], m.points[x]);
      if (det.value > det.bound || (!(-det.value > det.bound) && exact_sign(m, cv, x) > 0)) {
        holds_vertex_ = true;
        ++stats_.recent_inside;
        return true;
      }
    }
    return false;
  }
  // On a constrained mesh: is the circumdisk of corners cv shown vertex-empty by the index (then
  // the flood may stop at K, as on a Delaunay mesh)? Only the vertices from `from` on are asked
  // (the caller knows the older ones are not inside). If the index finds a vertex strictly inside,
  // holds_vertex_ is set (the flood's answer is 0: it would find that vertex, a corner of a
  // triangle meeting the disk, or pass its cap); if it shows the disk empty, shown_empty_.
  bool indexed_empty(const Mesh& m, const std::array<VertexId, 3>& cv, VertexId from) {
    index_.sync(m.points);
    ++stats_.index_queries;
    const Point& a = m.points[cv[0]];
    const Point& b = m.points[cv[1]];
    const Point& d = m.points[cv[2]];
    const VertexIndex::Disk disk = index_.strictly_inside(m.points, cv, [&](VertexId x) {
      const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, d, m.points[x]);
      return det.value > det.bound || (!(-det.value > det.bound) && exact_sign(m, cv, x) > 0);
    }, from);
    stats_.index_visits += index_.last_visits();
    if (disk == VertexIndex::Disk::kHoldsVertex) {
      holds_vertex_ = true;
      remember_inside(index_.last_found());
      ++stats_.index_holds;
      return false;
    }
    if (disk != VertexIndex::Disk::kEmpty) return false;
    ++stats_.index_empty;
    shown_empty_ = true;
    return true;
  }
  VertexIndex index_;

  // Is the circumdisk of corners cv crowded (VertexIndex::crowded: its search over every vertex
  // would pass its visit cap or find a vertex inside, never show it empty)?
  bool crowded(const Mesh& m, const std::array<VertexId, 3>& cv) {
    index_.sync(m.points);
    const bool crowded = index_.crowded(m.points, cv);
    stats_.crowd_reads += index_.last_crowd_reads();
    if (!crowded) return false;
    ++stats_.index_crowded;
    return true;
  }

  void remember_inside(VertexId x) {
    if (std::find(recent_inside_.begin(), recent_inside_.end(), x) == recent_inside_.end()) {
      recent_inside_[recent_next_++ % kRecentInside] = x;
    }
  }
  static constexpr std::size_t kRecentInside = 8;
  std::array<VertexId, kRecentInside> recent_inside_{kNone, kNone, kNone, kNone, kNone, kNone, kNone, kNone};
  std::size_t recent_next_ = 0;

  // The exact incircle sign of x against the circle through corners cv, remembered in a small
  // direct-mapped table: the filter fails on near-cocircular vertices (a circular hole's), and the
  // disks through them (a hole's triangles) are flooded again after every insertion nearby, each
  // time asking the same vertices.
  int exact_sign(const Mesh& m, const std::array<VertexId, 3>& cv, VertexId x) {
    std::uint64_t h = (std::uint64_t{cv[0]} * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t{cv[1]} * 0xC2B2AE3D27D4EB4Full) ^
                      (std::uint64_t{cv[2]} * 0x165667B19E3779F9ull) ^ (std::uint64_t{x} * 0xD6E8FEB86659FD93ull);
    ExactSlot& e = exact_[(h >> 40) & (kExactCache - 1)];
    if (e.filled && e.v == cv && e.x == x) return e.sign;
    e = {cv, x, static_cast<std::int8_t>(detail::incircle_exact(m.points[cv[0]], m.points[cv[1]], m.points[cv[2]], m.points[x])), true};
    return e.sign;
  }
  struct ExactSlot {
    std::array<VertexId, 3> v{};
    VertexId x = 0;
    std::int8_t sign = 0;
    bool filled = false;
  };
  static constexpr std::size_t kExactCache = 4096;
  std::vector<ExactSlot> exact_ = std::vector<ExactSlot>(kExactCache);

  struct ValueSlot {
    VertexId v = kNone;
    std::uint32_t stamp = 0;  // the flood that wrote it
    double value = 0.0;
  };
  static constexpr std::size_t kValueCache = 256;

  std::uint32_t k_;
  std::size_t cap_;
  std::uint32_t stamp_ = 0;  // the current flood
  FloodSet seen_triangles_, seen_vertices_;
  std::vector<TriangleId> stack_;
  std::array<ValueSlot, kValueCache> value_{};
  std::vector<SlotCache> cache_;
  bool holds_vertex_ = false;  // the last flood found a vertex strictly inside its disk
  bool shown_empty_ = false;   // the index showed the last flood's disk vertex-empty
  bool defer_crowded_ = true;
  std::uint16_t epoch_ = 1;
  bool delaunay_known_ = false;
  bool delaunay_ = false;  // every segment is a hull edge: circumdisks are vertex-empty
  Stats stats_;
};

}  // namespace mwst::brh
