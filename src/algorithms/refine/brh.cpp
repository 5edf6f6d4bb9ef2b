// The bundle removal heuristic (BRH), Boyacı, Erten and Üngör, "Triangulations Loosing Bundles and
// Weight": Delaunay refinement relaxed so that a skinny triangle may stay as long as it is in no
// k-bundle. Their lemma: a mesh with minimum angle α is (4π/α + 3)-bundle-free; so with
// K ≥ ⌈4π/A⌉ + 3 every K-bundle must contain a triangle with an angle below A (otherwise the
// triangles of the bundle alone would violate the lemma's count), and splitting only the skinny
// triangles of K-bundles leaves a K-bundle-free mesh with fewer Steiner points — and less weight —
// than DR at the same A.
//
// Which triangles are in a K-bundle changes with every insertion. The DR engine (its pluggable
// bad-triangle test) refines with a local test decided when a triangle is made: a skinny triangle
// is bad if the circumdisk of it or of a neighbour is vertex-empty (checked by the same flood that
// counts) and meets at least K triangles — a witness that it is in a K-bundle, found in time
// proportional to the disk's triangles, so the refinement runs like DR, in one pass. When no
// skinny triangle passes the local test, the exact test (in_k_bundle, bundle.cpp: circumdisks,
// then pencil sweeps, only near the skinny triangles) decides; the triangles it finds are
// refined in another pass, seeded with them (RefineOptions::seed_triangles: only they and the
// triangles the splits make are tested, no sweep over the mesh); BRH stops when it finds none.
// So the guarantee rests on the exact test alone; the local one (whose edge crossings are decided
// in floating point) only makes the refinement fast, and a triangle it wrongly called bad would
// only cost a Steiner point.
//
// Between passes the exact test is asked only about skinny triangles not known clean: one the last
// test found in no K-bundle stays so while every triangle made since lies away from its reach box
// (CleanQueries below), and pencil sweeps are reused across tests (KBundleCache, bundle.hpp). Both
// give the answers a fresh test would, so the output does not depend on them.
#include "mwst/algorithms/brh.hpp"


#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "support/time_budget.hpp"
#include "algorithms/triangle_key.hpp"

namespace mwst {

namespace {

using detail::TripleHash;

std::array<VertexId, 3> sorted_triple(const Mesh& m, TriangleId t) {
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
class LocalBundleTest {
 public:
  // A flood pops at most cap_ + 1 triangles, so it adds at most 3 (cap_ + 1) + 1 triangles and
  // as many vertices plus the three corners to its sets.
  explicit LocalBundleTest(std::uint32_t k)
      : k_(k), cap_(8 * static_cast<std::size_t>(k) + 64), seen_triangles_(3 * cap_ + 8), seen_vertices_(3 * cap_ + 8) {}

  // Forgets every cached result (a new epoch: no sweep over the cache).
  void clear() {
    if (++epoch_ == 0) {
      std::fill(cache_.begin(), cache_.end(), Cached{});
      epoch_ = 1;
    }
  }

  bool in_bundle(const Mesh& m, TriangleId t) {
    if (cache_.size() < m.triangle_slots()) cache_.resize(m.triangle_slots() + m.triangle_slots() / 4 + 64);
    Cached& c = cache_[t];
    if (c.epoch == epoch_ && c.v == m.triangles[t].v) return c.value == 2;
    bool found = disk_count(m, t) >= k_;
    for (unsigned e = 0; e < 3 && !found; ++e) {
      const TriangleId n = triangle_of(m.triangles[t].n[e]);
      if (!m.is_ghost(n) && !m.is_dead(n)) found = disk_count(m, n) >= k_;
    }
    c.v = m.triangles[t].v;
    c.value = found ? 2 : 1;
    c.epoch = epoch_;
    return found;
  }

 private:
  // circumdisk_count(m, c), remembered while the mesh is unchanged: the refinement only inserts
  // vertices, so the mesh is the same while its vertex and slot counts are (the triangles made by
  // one insertion are tested one after another, each with its neighbours, many of them made by the
  // same insertion: without this, one disk would be flooded up to four times).
  std::uint32_t disk_count(const Mesh& m, TriangleId c) {
    const std::uint64_t version = std::uint64_t{m.points.size()} << 32 | m.triangles.size();
    if (disk_cache_.size() < m.triangle_slots()) disk_cache_.resize(m.triangle_slots() + m.triangle_slots() / 4 + 64);
    DiskCount& d = disk_cache_[c];
    if (d.version == version && d.v == m.triangles[c].v) return d.count;
    d = {m.triangles[c].v, version, circumdisk_count(m, c)};
    return d.count;
  }

  struct Cached {
    std::array<VertexId, 3> v{kNone, kNone, kNone};
    std::uint8_t value = 0;   // 1 no, 2 yes
    std::uint16_t epoch = 0;  // valid if equal to epoch_
  };

  // The number of in-domain triangles meeting the open circumdisk of c, by a flood across the
  // edges meeting it; 0 if a vertex lies strictly inside the disk (exact incircle), or if the
  // flood grows past cap_ (unknown: the exact test will decide).
  std::uint32_t circumdisk_count(const Mesh& m, TriangleId c) {
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
    std::size_t visited = 0;
    while (!stack_.empty()) {
      const TriangleId t = stack_.back();
      stack_.pop_back();
      if (++visited > cap_) return 0;
      if (m.in_domain(t)) ++count;
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
          // stage only when the filter cannot vouch); its rounded value serves the edge tests.
          const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, d, m.points[x]);
          if (det.value > det.bound) return 0;  // the disk is not vertex-empty
          if (!(-det.value > det.bound) && detail::incircle_exact(a, b, d, m.points[x]) > 0) return 0;
          value_[x % kValueCache] = {x, stamp_, det.value};
        }
        stack_.push_back(n);
      }
    }
    return count;
  }

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
  std::vector<Cached> cache_;
  struct DiskCount {
    std::array<VertexId, 3> v{kNone, kNone, kNone};
    std::uint64_t version = 0;
    std::uint32_t count = 0;
  };
  std::vector<DiskCount> disk_cache_;
  std::uint16_t epoch_ = 1;
};

// Skinny triangles the exact test found in no K-bundle, kept across passes while nothing near them
// changes. Sound because vertices are only added: if a disk D (vertex-empty after a pass, hence
// before it) puts such a triangle t in a K-bundle after the pass, D met fewer than K triangles
// before it, so it meets a triangle the pass made; while the hull is unchanged that triangle lies
// in the convex hull, where D meets only triangles inside t's reach box (KBundleCache::reach), so
// the box of the made triangle meets t's box. A pass that changes the hull forgets every entry.
class CleanQueries {
 public:
  bool empty() const { return boxes_.empty(); }
  bool contains(const std::array<VertexId, 3>& triple) const { return boxes_.count(triple) != 0; }
  void add(const std::array<VertexId, 3>& triple, const std::array<double, 4>& box) {
    if (box[0] <= box[2] && box[1] <= box[3]) boxes_[triple] = box;  // an empty box: not kept
  }
  void clear() { boxes_.clear(); }

  // Before a pass: the triangles as they are.
  void snapshot(const Mesh& m) {
    before_v_.resize(m.triangles.size());
    for (TriangleId t = 0; t < m.triangles.size(); ++t) before_v_[t] = m.triangles[t].v;
    before_flags_ = m.flags;
  }

  // After the pass: forgets the entries whose box meets the box of a triangle the pass made (a
  // slot whose corners or flags changed; conservative when a triangle merely moved slot).
  void update(const Mesh& m) {
    made_.clear();
    std::array<double, 4> all{kInf, kInf, -kInf, -kInf};
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
      if (t < before_v_.size() && before_v_[t] == m.triangles[t].v && before_flags_[t] == m.flags[t]) continue;
      if (m.is_dead(t)) continue;
      if (m.is_ghost(t)) {  // the hull changed
        boxes_.clear();
        return;
      }
      std::array<double, 4> b{kInf, kInf, -kInf, -kInf};
      for (const VertexId v : m.triangles[t].v) {
        const Point& p = m.points[v];
        b = {std::min(b[0], p.x), std::min(b[1], p.y), std::max(b[2], p.x), std::max(b[3], p.y)};
      }
      all = {std::min(all[0], b[0]), std::min(all[1], b[1]), std::max(all[2], b[2]), std::max(all[3], b[3])};
      made_.push_back(b);
    }
    if (made_.empty()) return;
    // A grid over the made boxes: the cells each covers are marked; an entry is forgotten if its box
    // covers a marked cell. Cell indices are monotone in the coordinate, so two closed boxes that
    // meet share a cell.
    const double sx = all[2] > all[0] ? kGrid / (all[2] - all[0]) : 0.0;
    const double sy = all[3] > all[1] ? kGrid / (all[3] - all[1]) : 0.0;
    auto cell = [](double v, double v0, double scale) {
      return static_cast<std::size_t>(std::clamp(std::floor((v - v0) * scale), 0.0, kGrid - 1.0));
    };
    marks_.assign(static_cast<std::size_t>(kGrid * kGrid), 0);
    for (const auto& b : made_) {
      for (std::size_t y = cell(b[1], all[1], sy); y <= cell(b[3], all[1], sy); ++y) {
        for (std::size_t x = cell(b[0], all[0], sx); x <= cell(b[2], all[0], sx); ++x) {
          marks_[y * static_cast<std::size_t>(kGrid) + x] = 1;
        }
      }
    }
    std::erase_if(boxes_, [&](const auto& entry) {
      const auto& b = entry.second;
      if (b[2] < all[0] || b[0] > all[2] || b[3] < all[1] || b[1] > all[3]) return false;
      for (std::size_t y = cell(b[1], all[1], sy); y <= cell(b[3], all[1], sy); ++y) {
        for (std::size_t x = cell(b[0], all[0], sx); x <= cell(b[2], all[0], sx); ++x) {
          if (marks_[y * static_cast<std::size_t>(kGrid) + x]) return true;
        }
      }
      return false;
    });
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kGrid = 256.0;
  std::unordered_map<std::array<VertexId, 3>, std::array<double, 4>, TripleHash> boxes_;
  std::vector<std::array<VertexId, 3>> before_v_;
  std::vector<std::uint8_t> before_flags_;
  std::vector<std::array<double, 4>> made_;
  std::vector<std::uint8_t> marks_;
};

// Below this many skinny triangles the exact test is local and cheap: no clean-list bookkeeping.
constexpr std::size_t kCleanQueriesFrom = 1024;

}  // namespace

BrhStats bundle_removal(Mesh& mesh, const BrhOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  // The time budget also bounds each exact test (in_k_bundle), which alone can take many seconds.
  const auto deadline = detail::deadline_after(start, options.refine.time_budget_seconds);
  BrhStats stats;
  const double A = options.min_angle_deg;
  const std::uint32_t K = static_cast<std::uint32_t>(options.bundle_k);
  std::unordered_set<std::array<VertexId, 3>, TripleHash> marked;  // found by the exact test
  LocalBundleTest local(K);
  // Pencil sweeps of one exact test reused by the next where nothing they read changed.
  KBundleCache sweep_cache;
  CleanQueries clean;
  const SkinnyTest is_skinny(A);
  RefineOptions ro = options.refine;
  ro.min_angle_deg = A;
  // DR's termination guard (refine.hpp), measured once on the input: BRH splits only skinny
  // triangles, as DR does, so above the angles where DR provably stops it may crowd vertices
  // without end as well; its passes stop once a skinny triangle to split is far below the input's
  // smallest feature.
  if (ro.feature_guard_length < 0.0) ro.feature_guard_length = A > 0.0 ? feature_guard_length(mesh, options.refine.max_area) : 0.0;
  // Skinny triangles a pass tested: every triangle a pass makes passes through is_bad, and an
  // unseeded pass (a custom is_bad) ends by testing every triangle of the domain again (refine.cpp).
  std::vector<TriangleId> made_skinny;
  bool record_skinny = false;
  ro.is_bad = [&](const Mesh& m, TriangleId t) {
    if (!is_skinny(m, t)) return false;
    if (record_skinny) made_skinny.push_back(t);
    return (!marked.empty() && marked.count(sorted_triple(m, t)) != 0) || local.in_bundle(m, t);
  };
  std::size_t steiner_budget = options.refine.max_steiner;
  // Set when a pass driven by the local test alone inserted nothing (its triangles sit at small
  // input angles): the next pass asks the exact test, so that no triangle it would find is missed.
  bool force_exact = false;
  // The skinny triangles of the domain. After a pass they are updated, not recounted: a triangle
  // the pass did not make is unchanged, so they are the old ones still alive and skinny plus the
  // skinny ones the pass tested (`made_skinny`; after an unseeded pass that is all of them). Before
  // BRH stops on such a list, a sweep over the whole mesh confirms it (the guarantee must not rest
  // on the bookkeeping).
  std::vector<TriangleId> skinny;
  bool skinny_updated = false;      // skinny comes from an update, not a sweep
  std::size_t confirmed_skinny = 0;  // the sweep's count when it confirmed the list
  bool confirmed = false;
  bool swept_again = false;          // confirm_skinny failed: skinny holds its sweep
  auto sweep_skinny = [&] {
    skinny.clear();
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.in_domain(t) && is_skinny(mesh, t)) skinny.push_back(t);
    }
    skinny_updated = false;
  };
  // True if the updated list holds every skinny triangle (else it is replaced by the sweep's).
  auto confirm_skinny = [&] {
    const std::size_t updated = skinny.size();
    sweep_skinny();
    if (skinny.size() != updated) return false;  // the update is a subset of the sweep
    confirmed = true;
    confirmed_skinny = updated;
    return true;
  };
  // Stopping on a list this round's sweep made (the mesh unchanged since): it is the count.
  auto stop_on_sweep = [&] {
    confirmed = true;
    confirmed_skinny = skinny.size();
  };
  stats.stop_reason = "bound reached";
  // An area bound (--max-area) splits every triangle larger than it, skinny or not, in a bundle or
  // not: first one pass of the DR engine with the area bound alone over the whole mesh, then in
  // every pass below (refine tests the area of each triangle a pass makes, whatever its is_bad).
  bool stopped = false;
  if (options.refine.max_area > 0.0) {
    RefineOptions area = options.refine;
    area.min_angle_deg = 0.0;
    area.is_bad = {};
    area.seed_triangles.clear();
    const RefineStats rs = refine(mesh, area);
    const std::size_t added = rs.steiner_inserted + rs.segment_splits;
    stats.steiner_inserted += rs.steiner_inserted;
    stats.segment_splits += rs.segment_splits;
    if (steiner_budget != static_cast<std::size_t>(-1)) steiner_budget -= std::min(steiner_budget, added);
    if (rs.stop_reason == "steiner budget" || rs.stop_reason == "time budget") {
      stats.stop_reason = rs.stop_reason;
      stopped = true;
    }
  }
  for (stats.rounds = 0; !stopped && stats.rounds < options.max_rounds;) {
    if (options.refine.time_budget_seconds > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
            options.refine.time_budget_seconds) {
      stats.stop_reason = "time budget";
      break;
    }
    if (swept_again) {
      swept_again = false;  // skinny holds confirm_skinny's sweep
    } else if (skinny_updated) {
      skinny.insert(skinny.end(), made_skinny.begin(), made_skinny.end());
      std::sort(skinny.begin(), skinny.end());
      skinny.erase(std::unique(skinny.begin(), skinny.end()), skinny.end());
      std::erase_if(skinny, [&](TriangleId t) {
        return t >= mesh.triangles.size() || !mesh.in_domain(t) || !is_skinny(mesh, t);
      });
    } else {
      sweep_skinny();
    }
    made_skinny.clear();
    if (skinny.empty()) {
      if (!skinny_updated) {
        stop_on_sweep();
        break;
      }
      if (confirm_skinny()) break;
      swept_again = true;  // the sweep found skinny triangles the update missed
      continue;
    }
    marked.clear();
    local.clear();
    // First pass: any skinny triangle the local test finds starts the refinement. With many
    // skinny triangles only a sample is tried: when none of it is found, the exact test (whose
    // first, circumdisk stage finds what the local test would) is cheaper than testing them all.
    // Later passes go to the exact test directly: after a refinement few skinny triangles are
    // left, the exact test on few triangles is local (in_k_bundle), and the pass it starts is
    // seeded with the triangles it marks (no sweep over the whole mesh).
    bool any_local = false;
    const std::size_t sample = stats.rounds > 0 ? 0 : std::min<std::size_t>(skinny.size(), 256);
    for (std::size_t i = 0; i < sample && !any_local && !force_exact; ++i) {
      any_local = local.in_bundle(mesh, skinny[i * (skinny.size() / sample)]);
    }
    if (!any_local || force_exact) {
      // Ask only the skinny triangles not known clean (see CleanQueries).
      std::vector<std::uint8_t> exact(skinny.size(), 0);
      // From the second exact test on (the first pass changes most of the mesh; with the default K
      // one test is often all there is).
      const bool use_cache = stats.exact_evaluations >= 1;
      const bool use_clean = use_cache && skinny.size() >= kCleanQueriesFrom;
      if (!use_clean) clean.clear();
      std::vector<TriangleId> asked;
      std::vector<std::size_t> asked_at;
      for (std::size_t i = 0; i < skinny.size(); ++i) {
        if (use_clean && clean.contains(sorted_triple(mesh, skinny[i]))) {
          ++stats.known_clean;
          continue;
        }
        asked.push_back(skinny[i]);
        asked_at.push_back(i);
      }
      if (!asked.empty()) {
        // Before the second test only DT(V) is kept (the next test inserts the new vertices into it).
        sweep_cache.reuse_sweeps = use_cache;
        std::vector<std::uint8_t> answers;
        try {
          answers = in_k_bundle(mesh, K, asked, nullptr, options.threads, &sweep_cache, deadline);
        } catch (const KBundleTimeout&) {  // (the mesh is as the last pass left it)
          stats.stop_reason = "time budget";
          break;
        }
        for (std::size_t j = 0; j < asked.size(); ++j) {
          exact[asked_at[j]] = answers[j];
          if (use_clean && !answers[j]) clean.add(sorted_triple(mesh, asked[j]), sweep_cache.reach[j]);
        }
      }
      ++stats.exact_evaluations;
      ro.seed_triangles.clear();
      for (std::size_t i = 0; i < skinny.size(); ++i) {
        if (!exact[i]) continue;
        marked.insert(sorted_triple(mesh, skinny[i]));
        ro.seed_triangles.push_back(skinny[i]);
      }
      if (marked.empty()) {  // no skinny triangle is in a K-bundle
        if (!skinny_updated) {
          stop_on_sweep();
          break;
        }
        if (confirm_skinny()) break;
        swept_again = true;  // the sweep found skinny triangles the update missed: test them all
        continue;
      }
    }
    // After the first pass the mesh is refined (hull marked, nothing encroached) and only the
    // marked triangles need a look: a seeded pass starts from them alone, at a cost proportional
    // to what it splits instead of a sweep over the whole mesh. The first pass, and any pass the
    // local test started, sweeps the whole mesh.
    if (stats.rounds == 0 || any_local) ro.seed_triangles.clear();
    ++stats.rounds;
    ro.max_steiner = steiner_budget;
    record_skinny = true;
    if (!clean.empty()) clean.snapshot(mesh);
    // Each pass gets what is left of the budget, not all of it again.
    if (options.refine.time_budget_seconds > 0.0) {
      ro.time_budget_seconds = std::max(1e-9, options.refine.time_budget_seconds -
                                                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    const RefineStats rs = refine(mesh, ro);
    if (!clean.empty()) clean.update(mesh);
    skinny_updated = record_skinny;
    record_skinny = false;
    const std::size_t added = rs.steiner_inserted + rs.segment_splits;
    stats.steiner_inserted += rs.steiner_inserted;
    stats.segment_splits += rs.segment_splits;
    stats.left_small_angle = rs.left_small_angle;
    if (rs.stop_reason == "steiner budget" || rs.stop_reason == "time budget" || rs.stop_reason == kStopBeyondFeatureSize) {
      stats.stop_reason = rs.stop_reason;
      break;
    }
    if (steiner_budget != static_cast<std::size_t>(-1)) steiner_budget -= std::min(steiner_budget, added);
    if (added == 0 && marked.empty()) {
      force_exact = true;
      continue;
    }
    force_exact = false;
    if (added == 0) {
      // Nothing could be split (the marked triangles sit at small input angles): stop honestly.
      stats.stop_reason = std::to_string(rs.left_small_angle) + " triangles left near small input angles";
      break;
    }
  }
  if (stats.rounds >= options.max_rounds) stats.stop_reason = "round limit";
  if (confirmed) {
    stats.skinny_left = confirmed_skinny;  // the mesh has not changed since the sweep
  } else {
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.in_domain(t) && is_skinny(mesh, t)) ++stats.skinny_left;
    }
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace mwst
