// src/algorithms/bundle/k_bundle.cpp — in_k_bundle: is each query triangle in a k-bundle?
// (mwst/algorithms/bundle.hpp). The steps, in order:
//   local_region                     the mesh region and the vertices W around few queries
//   KBundleAttempt::run              one attempt, over DT(V) or over DT(W):
//     first_stage                    per query, S(t) walked until a circumdisk meeting ≥ k decides
//     merge_parts, mark_needed       S(t) of the queries left, and the DT triangles to flood
//     reach_boxes                    (with a cache) how far a disk meeting each query reaches
//     lists_show_empty_disks         (over DT(W)) every DT(W) triangle used is one of DT(V)
//     pencils_to_sweep, sweep_pencils, keep_sweeps   the second stage: exact pencil sweeps
//   in_k_bundle                      local attempts first (12, then 32 rings), then DT(V)
#include "mwst/algorithms/bundle.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>
#ifdef __GLIBC__
#include <malloc.h>  // malloc_trim
#endif

#include "algorithms/bundle/circle_predicates.hpp"
#include "algorithms/bundle/lists.hpp"
#include "algorithms/bundle/part_lists.hpp"
#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/worker.hpp"

namespace mwst {

namespace {

using bundle::CachedSweep;
using bundle::DenseIds;
using bundle::kInf;
using bundle::release;
using bundle::Shared;
using bundle::SweepKey;
using bundle::Worker;

// in_k_bundle with DT(V) (subset null), or with the Delaunay triangulation of a subset W of the
// vertices around the queries. A triangle of DT(W) whose open circumdisk holds no vertex of V is a
// triangle of DT(V) (a Delaunay triangulation of V; with cocircular vertices any one serves: the
// empty disks are the same). The local attempt checks that of every DT(W) triangle it uses — the
// fan around the flood's starting corner, S(t) and the neighbours across its edges — and that none
// of those lies on the hull of DT(W) except along hull edges of the mesh; then the floods over
// DT(W) are the floods over DT(V) and the answer is exact. Otherwise it gives up (kGaveUp). The
// local attempt sees only a region of the mesh (Shared::build_region); a flood that would leave it
// makes it give up too (kEscaped: a larger region may do).
enum class Attempt : std::uint8_t { kAnswered, kGaveUp, kEscaped };

// ---- one attempt begins here ----------------------------------------------------------------------

// S(t): the Delaunay triangles whose open circumdisk meets query t. Every pencil disk meeting t
// lies in the union of the circumdisks of the two Delaunay triangles on its edge, so one of them
// is in S(t). S(t) is connected across Delaunay edges (for a point x the triangles whose
// circumdisks hold x form the connected Bowyer–Watson cavity of x, and the cavities of nearby
// points share triangles), and it holds a triangle around each corner of t (the one overlapping
// t's corner): a flood with the permissive test from the triangles around one corner finds it.
//
// Stage 1, per query, stopping at the first answer: each Delaunay triangle d of S(t) the flood
// reaches is asked whether its circumdisk (vertex-empty) meets at least k triangles — counted
// by a flood over the mesh that stops at k (Worker::count_meeting), once per d for all queries
// — and if so whether it meets t (exactly). So a query in a large circumdisk costs O(k), not
// what the disk meets (points on a circle: every circumdisk is the whole circle and meets every
// triangle). Only the queries left undecided keep their S(t), for the pencils of stage 2: S(t)
// and its neighbours across edges are flooded in full (the candidate lists of the pencils), and
// the pencils of the edges of S(t) whose two lists together reach k are swept exactly.
class KBundleAttempt {
 public:
  // `sh` is built (DT(V): Shared::build(false); DT(W): Shared::build_region, `subset` true);
  // `queries` are slots of sh (kNone for a query outside the domain).
  // `memo` (may be null): the caller's KBundleCache for the witnesses (hints and witnesses), used
  // even when `cache` is null.
  KBundleAttempt(Shared& sh, std::uint32_t k, const std::vector<TriangleId>& queries, KBundleStats& st, bool subset,
                 std::vector<std::uint8_t>& answer, KBundleCache* cache, KBundleCache* memo)
      : sh_(sh), k_(k), queries_(queries), st_(st), subset_(subset), answer_(answer), cache_(cache), memo_(memo),
        dt_(sh.dt), dt_slots_(sh.dt.triangle_slots()) {}

  Attempt run(unsigned threads_requested) {
    answer_.assign(queries_.size(), 0);
    st_ = {};
    index_dt_vertices();
    resolve_hints();
    const unsigned threads = bundle::worker_threads(threads_requested, 64 * queries_.size());
    workers_ = bundle::make_workers(sh_, threads, true, false);
    // Stage 1's floods decide the edges the filters leave open exactly (see Worker::exact_edges):
    // they count up to k, and a flat disk along a hull edge would otherwise run along the edge.
    for (auto& w : workers_) w->exact_edges = true;
    disk_state_.reset(new std::atomic<std::uint8_t>[dt_slots_]());
    std::vector<Part> parts(workers_.size());
    first_stage(parts);
    if (!merge_parts(parts)) return Attempt::kGaveUp;
    record_witnesses();
    if (!subset_) {
      second_stage_one_sided();
      for (const auto& w : workers_) st_.flood_visits += w->flood_visits;
      return Attempt::kAnswered;
    }
    std::vector<std::uint8_t> needed;  // 1: in some S(t); 2: a partner across an edge
    if (!mark_needed(needed)) return Attempt::kGaveUp;
    for (auto& w : workers_) {
      w->escaped = false;  // (stage 1's floods that left a region were cut short)
      w->exact_edges = false;  // the candidate lists: permissive floods, as `mwst bundle` builds them
      w->release_disk_scratch();  // (the floods use none; a sweep allocates it again)
    }
    bundle::FloodBoxes boxes;
    bundle::build_lists(sh_, workers_, &needed, cache_ ? &boxes : nullptr);
    if (cache_) reach_boxes(boxes);
    if (subset_ && !lists_show_empty_disks(needed)) return Attempt::kGaveUp;
    // A flood that left the region (checked after the test above: a list cut short that already
    // shows a vertex inside its disk gives up for good).
    for (const auto& w : workers_) {
      if (w->escaped) return Attempt::kEscaped;
    }
    std::vector<Handle> pencils = pencils_to_sweep();
    st_.pencils_swept = pencils.size();
    if (!pencils.empty()) sweep_pencils(std::move(pencils));
    for (const auto& w : workers_) {
      st_.flood_visits += w->flood_visits;
      st_.candidate_pairs += w->candidate_pairs;
    }
    return Attempt::kAnswered;
  }

 private:
  // One worker's share of stage 1.
  struct Part {
    std::vector<TriangleId> s_list, fan;
    // Per DT slot: the stamp of the last query whose walk considered it (16 bits, cleared when the
    // stamps wrap: 2 bytes a DT slot per worker at in_k_bundle's peak instead of 4).
    std::vector<std::uint16_t> dt_stamp;
    std::size_t decided = 0, disks_counted = 0, fan_steps = 0, hinted = 0;
    bool gave_up = false;
  };

  bool in_domain(TriangleId t) const { return t < sh_.slots.size() && sh_.in_domain(t); }

  // A Delaunay edge leaving every vertex of V (DT ids are the renumbered ids below `used`).
  // Also the degree of every vertex in DT(V) (its finite triangles), for seed_corner.
  void index_dt_vertices() {
    dt_vertex_edge_.assign(sh_.used, kNone);
    dt_degree_.assign(sh_.used, 0);
    for (TriangleId t = 0; t < dt_slots_; ++t) {
      if (dt_.is_dead(t) || dt_.is_ghost(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const VertexId o = dt_.org(make_handle(t, e));
        if (dt_vertex_edge_[o] == kNone) dt_vertex_edge_[o] = make_handle(t, e);
        ++dt_degree_[o];
      }
    }
  }

  // ---- witnesses from an earlier call ----

  // hint_dt_: per query, the Delaunay triangle the caller's hint names, if it is one of DT(V)
  // now (kNone otherwise). Only over DT(V): a subset attempt's DT(W) would need each hint shown
  // to be a DT(V) triangle, and few queries are cheap to walk anyway.
  void resolve_hints() {
    decided_by_.assign(queries_.size(), kNone);
    if (memo_ != nullptr) memo_->witnesses.clear();
    if (subset_ || memo_ == nullptr || memo_->hints.size() != queries_.size()) return;
    // The renumbered id of each mesh vertex of DT(V).
    std::vector<VertexId> dt_id(sh_.pts.size(), kNone);
    for (VertexId i = 0; i < sh_.used; ++i) {
      if (sh_.mesh_id[i] < dt_id.size()) dt_id[sh_.mesh_id[i]] = i;
    }
    hint_dt_.assign(queries_.size(), kNone);
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      const auto& hint = memo_->hints[qi];
      std::array<VertexId, 3> v{};
      bool known = true;
      for (unsigned c = 0; c < 3; ++c) {
        known = known && hint[c] < dt_id.size() && dt_id[hint[c]] != kNone;
        if (known) v[c] = dt_id[hint[c]];
      }
      if (known) hint_dt_[qi] = dt_triangle(v);
    }
  }

  // The finite Delaunay triangle with corners v (any order), or kNone: a walk around the corner
  // of fewest Delaunay triangles (a vertex that lost its triangle to an insertion may have
  // thousands around it on a fan's rim; past kHintFan the hint is not looked up).
  static constexpr std::uint32_t kHintFan = 256;
  TriangleId dt_triangle(const std::array<VertexId, 3>& v) const {
    unsigned c = 0;
    for (unsigned i = 1; i < 3; ++i) {
      if (dt_degree_[v[i]] < dt_degree_[v[c]]) c = i;
    }
    if (dt_vertex_edge_[v[c]] == kNone || dt_degree_[v[c]] > kHintFan) return kNone;
    const Handle first = dt_vertex_edge_[v[c]];
    Handle g = first;
    for (std::uint32_t turn = 0; turn <= kHintFan + 1; ++turn) {
      const TriangleId d = triangle_of(g);
      if (!dt_.is_ghost(d)) {
        const auto& dv = dt_.triangles[d].v;
        auto has = [&](VertexId x) { return dv[0] == x || dv[1] == x || dv[2] == x; };
        if (has(v[0]) && has(v[1]) && has(v[2])) return d;
      }
      g = dt_.onext(g);
      if (g == first) break;
    }
    return kNone;
  }

  // The caller's witnesses: the corners (mesh ids) of the Delaunay triangle that decided each
  // query in the first stage.
  void record_witnesses() {
    if (memo_ == nullptr) return;
    constexpr std::array<VertexId, 3> kNoWitness{kNone, kNone, kNone};
    memo_->witnesses.assign(queries_.size(), kNoWitness);
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      const TriangleId d = decided_by_[qi];
      if (d == kNone) continue;
      const auto& dv = dt_.triangles[d].v;
      memo_->witnesses[qi] = {sh_.mesh_id[dv[0]], sh_.mesh_id[dv[1]], sh_.mesh_id[dv[2]]};
    }
  }

  // ---- stage 1 ----

  // Does the circumdisk of Delaunay triangle d meet at least k triangles (and, over DT(W), hold no
  // vertex of V)? Decided once per d for all queries: disk_state_ is 0 not yet counted; 1 fewer
  // than k; 2 at least k; 3 at least k, but not shown vertex-empty in V (stage 2 then gives up).
  bool large_disk(Worker& w, Part& part, TriangleId d) {
    std::uint8_t state = disk_state_[d].load(std::memory_order_relaxed);
    if (state != 0) return state == 2;
    ++part.disks_counted;
    state = w.count_meeting(d, k_) >= k_ ? 2 : 1;
    if (state == 2 && subset_ && !empty_in_v(w, d)) state = 3;
    disk_state_[d].store(state, std::memory_order_relaxed);
    return state == 2;
  }

  // DT(W) is Delaunay for W only: the disk of d must hold no other vertex of V, which would be a
  // corner of an in-domain triangle meeting it (a full flood, which must stay in the region).
  bool empty_in_v(Worker& w, TriangleId d) {
    std::vector<TriangleId> list;
    const bool escaped_before = w.escaped;
    w.escaped = false;
    w.flood(d, list);
    const auto& dv = dt_.triangles[d].v;
    bool empty = !w.escaped;
    for (std::size_t i = 0; i < list.size() && empty; ++i) {
      for (const VertexId v : sh_.slots[list[i]].v) {
        if (v >= sh_.used && incircle(sh_.pts[dv[0]], sh_.pts[dv[1]], sh_.pts[dv[2]], sh_.pts[v]) > 0) empty = false;
      }
    }
    w.escaped = escaped_before;
    return empty;
  }

  void first_stage(std::vector<Part>& parts) {
    bundle::for_ranges(workers_, queries_.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t k_part) {
      Part& part = parts[k_part];
      part.dt_stamp.assign(dt_slots_, 0);
      std::vector<TriangleId> stack;
      std::uint16_t stamp = 0;
      for (std::size_t qi = begin; qi < end; ++qi) {
        if (!in_domain(queries_[qi])) continue;
        sh_.check_deadline();
        if (++stamp == 0) {  // wrapped: no slot may keep a stamp the next queries reuse
          std::fill(part.dt_stamp.begin(), part.dt_stamp.end(), std::uint16_t{0});
          stamp = 1;
        }
        if (!first_stage_query(w, part, qi, stamp, stack)) return;
      }
    });
  }

  // The seed corner of a query's flood. S(t) holds a triangle around each corner, so any corner
  // serves, but the walk goes once around the seed's whole fan when no disk decides: on
  // `mwst generate fan` (160k) a corner had tens of thousands of Delaunay triangles, and each of
  // the 80,000 triangles left at small input angles walked them in BRH's last exact test (~40 s).
  // So the first corner of at most kSmallFan Delaunay triangles, else the one of fewest (the first
  // corner unless it has more than kSmallFan, as before: the walk's order decides how many disks
  // it counts before one decides, and always taking the fewest cost ~2 s more on the fan 40k).
  // With a subset, only a corner whose fan in DT(W) has no ghost (a corner on the hull of V has
  // ghosts around it in any Delaunay triangulation; another corner serves as well); 3 if none.
  static constexpr std::uint32_t kSmallFan = 64;
  unsigned seed_corner(const std::array<VertexId, 3>& tv) const {
    unsigned corner = 3;
    for (unsigned c = 0; c < 3; ++c) {
      if (subset_ && tv[c] >= sh_.used) break;  // a corner outside W
      if (dt_vertex_edge_[tv[c]] == kNone) continue;
      if (corner != 3 && dt_degree_[tv[c]] >= dt_degree_[tv[corner]]) continue;
      if (subset_ && ghost_around(tv[c])) continue;
      corner = c;
      if (dt_degree_[tv[c]] <= kSmallFan) break;
    }
    return corner == 3 && !subset_ ? 0 : corner;
  }

  bool ghost_around(VertexId v) const {
    const Handle first_edge = dt_vertex_edge_[v];
    Handle g = first_edge;
    do {
      if (dt_.is_ghost(triangle_of(g))) return true;
      g = dt_.onext(g);
    } while (g != first_edge);
    return false;
  }

  // Stage 1 for query qi: walks S(t) from the fan around the seed corner, one fan triangle at a
  // time, each followed by the flood it starts (a vertex of DT(V) may have thousands of
  // neighbours, e.g. on a circle: a query decided near its first fan triangle does not walk the
  // whole fan). False if the attempt gives up (no seed corner).
  bool first_stage_query(Worker& w, Part& part, std::size_t qi, std::uint16_t stamp, std::vector<TriangleId>& stack) {
    const TriangleId t = queries_[qi];
    const auto& tv = sh_.slots[t].v;
    // The earlier call's witness first: its disk, if still vertex-empty (the Delaunay triangle
    // still exists), meeting k triangles and t, decides t as the walk would (on the fan 160k,
    // 80,000 triangles left at small input angles are asked again before BRH stops; their walks
    // took ~22 s of CPU).
    if (!hint_dt_.empty() && hint_dt_[qi] != kNone) {
      const TriangleId d = hint_dt_[qi];
      if (large_disk(w, part, d) && w.disk_meets(d, t)) {
        answer_[qi] = 1;
        decided_by_[qi] = d;
        ++part.decided;
        ++part.hinted;
        return true;
      }
    }
    const Point* const corners[3] = {&sh_.pts[tv[0]], &sh_.pts[tv[1]], &sh_.pts[tv[2]]};
    const std::size_t first = part.s_list.size(), first_fan = part.fan.size();
    stack.clear();
    auto consider = [&](TriangleId d) {
      if (part.dt_stamp[d] == stamp || dt_.is_ghost(d)) return;
      part.dt_stamp[d] = stamp;
      const auto& dv = dt_.triangles[d].v;
      if (!bundle::circumdisk_may_meet(sh_.pts[dv[0]], sh_.pts[dv[1]], sh_.pts[dv[2]], corners)) return;
      stack.push_back(d);
      part.s_list.push_back(d);
    };
    const unsigned corner = seed_corner(tv);
    if (corner == 3) {
      part.gave_up = true;
      return false;
    }
    const Handle start = dt_vertex_edge_[tv[corner]];
    Handle h = start;
    bool decided = false;
    TriangleId decider = kNone;
    std::size_t popped = 0;
    do {
      ++part.fan_steps;
      if (subset_) part.fan.push_back(triangle_of(h));
      consider(triangle_of(h));
      while (!stack.empty()) {
        // One query may walk and flood for long (a fan's apex triangle: its S(t) reaches across
        // the wedges), so the clock is read within it too.
        if ((++popped & 15) == 0) sh_.check_deadline();
        const TriangleId d = stack.back();
        stack.pop_back();
        decided = large_disk(w, part, d) && w.disk_meets(d, t);
        if (decided) {
          decider = d;
          break;
        }
        for (unsigned e = 0; e < 3; ++e) consider(triangle_of(dt_.sym(make_handle(d, e))));
      }
      h = dt_.onext(h);
    } while (h != start && !decided);
    if (decided) {
      answer_[qi] = 1;
      decided_by_[qi] = decider;
      ++part.decided;
      part.s_list.resize(first);
      part.fan.resize(first_fan);
    } else {
      s_count_[qi] = static_cast<std::uint32_t>(part.s_list.size() - first);
    }
    return true;
  }

  // The workers' S(t) lists in query order (s_begin_, s_lists_: each worker's part as it wrote it,
  // not copied; fan_); false if one gave up.
  bool merge_parts(std::vector<Part>& parts) {
    s_begin_.assign(queries_.size() + 1, 0);
    std::size_t fan_total = 0;  // (reserved exactly: the lists are held through stage 2)
    for (const Part& part : parts) fan_total += part.fan.size();
    fan_.reserve(fan_total);
    for (Part& part : parts) {
      if (part.gave_up) return false;
      st_.decided_by_circumdisks += part.decided;
      st_.decided_by_hints += part.hinted;
      st_.disks_counted += part.disks_counted;
      st_.seed_fan_steps += part.fan_steps;
      s_lists_.append(std::move(part.s_list));
      fan_.insert(fan_.end(), part.fan.begin(), part.fan.end());
      part = Part{};
    }
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) s_begin_[qi + 1] = s_begin_[qi] + s_count_[qi];
    return true;
  }

  // ---- stage 2 ----

  // The Delaunay triangles to flood in full: S(t) of the queries left (1) and their neighbours
  // across edges and the fans walked (2). Over DT(W), false (give up) if S(t) reaches a hull edge
  // of DT(W) that is not one of the mesh.
  bool mark_needed(std::vector<std::uint8_t>& needed) {
    needed.assign(dt_slots_, 0);
    for (const auto& part : s_lists_.parts()) {
      if (!mark_s_part(part, needed)) return false;
    }
    for (const TriangleId d : fan_) {
      if (needed[d] == 0) needed[d] = 2;
    }
    for (TriangleId d = 0; d < dt_slots_; ++d) {
      if (needed[d] != 0) ++st_.flooded;
    }
    return true;
  }

  // mark_needed over one worker's part of the S(t) lists: its triangles and their neighbours.
  bool mark_s_part(const std::vector<TriangleId>& s_part, std::vector<std::uint8_t>& needed) const {
    for (const TriangleId d : s_part) {
      needed[d] = 1;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(d, e);
        const TriangleId n = triangle_of(dt_.sym(h));
        if (!dt_.is_ghost(n) && needed[n] == 0) needed[n] = 2;
        if (subset_ && dt_.is_ghost(n) && !mesh_hull_edge(dt_.org(h), dt_.dest(h))) return false;
      }
    }
    return true;
  }

  // Is a → b a hull edge of the mesh? (A hull edge of DT(W) is one of DT(V) if it is one of the
  // mesh, whose hull holds V.)
  bool mesh_hull_edge(VertexId a, VertexId b) const {
    const Handle first = sh_.vertex_edge[a];
    Handle g = first;
    for (std::size_t turn = 0; turn < sh_.slots.size(); ++turn) {
      if (sh_.dest(g) == b) return sh_.is_ghost(triangle_of(sh_.sym(g))) && !sh_.is_ghost(triangle_of(g));
      g = sh_.onext(g);
      if (g == first) break;
    }
    return false;
  }

  // Per query, the box of every mesh triangle meeting a circumdisk of S(t) or of a neighbour of
  // S(t): every vertex-empty disk meeting t lies in two such circumdisks (or, on the hull side of
  // a pencil, meets the mesh only inside one), so every triangle it meets is in the box. A query
  // answered 1 gets its own box (bundle removal keeps the boxes of queries answered 0 only).
  void reach_boxes(const bundle::FloodBoxes& boxes) {
    own_boxes();
    auto widen = [&](std::array<double, 4>& r, TriangleId d) {
      const auto b = boxes.box(d);
      r = {std::min(r[0], b[0]), std::min(r[1], b[1]), std::max(r[2], b[2]), std::max(r[3], b[3])};
    };
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      auto& r = cache_->reach[qi];
      for (const TriangleId d : s_lists_.range(s_begin_[qi], s_begin_[qi + 1])) {
        widen(r, d);
        for (unsigned e = 0; e < 3; ++e) {
          const TriangleId n = triangle_of(dt_.sym(make_handle(d, e)));
          if (!dt_.is_ghost(n)) widen(r, n);
        }
      }
    }
  }

  // Over DT(W): each DT(W) triangle used must have a vertex-empty circumdisk: a vertex of V
  // strictly inside would be a corner of an in-domain triangle meeting the disk, hence of its
  // candidate list. Only vertices outside W need the test (ids from sh.used on): DT(W) is
  // Delaunay, exactly, so no vertex of W lies strictly inside one of its circumdisks. Each is
  // tested once per disk (it is a corner of several candidates; on meshes of slivers the disks are
  // nearly flat and most of these tests need the exact stage).
  bool lists_show_empty_disks(const std::vector<std::uint8_t>& needed) const {
    std::vector<TriangleId> tested_for(sh_.pts.size(), kNone);
    for (TriangleId d = 0; d < dt_slots_; ++d) {
      if (needed[d] == 0) continue;
      const auto& dv = dt_.triangles[d].v;
      const Point& a = sh_.pts[dv[0]];
      const Point& b = sh_.pts[dv[1]];
      const Point& c = sh_.pts[dv[2]];
      const TriangleId* list = sh_.list_data(d);
      for (std::uint32_t i = 0; i < sh_.list_size(d); ++i) {
        for (const VertexId v : sh_.slots[list[i]].v) {
          if (v < sh_.used || tested_for[v] == d) continue;
          tested_for[v] = d;
          if (incircle(a, b, c, sh_.pts[v]) > 0) return false;
        }
      }
    }
    return true;
  }

  // The pencils of the edges of S(t) whose two candidate lists together reach k (the only ones
  // whose disks can meet t and k triangles), each once; counts the queries none can decide.
  std::vector<Handle> pencils_to_sweep() {
    auto list_size = [&](TriangleId d) { return dt_.is_ghost(d) ? 0u : sh_.list_begin[d + 1] - sh_.list_begin[d]; };
    std::vector<Handle> pencils;
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      const TriangleId t = queries_[qi];
      if (!in_domain(t) || answer_[qi]) continue;
      bool any = false;
      for (const TriangleId d : s_lists_.range(s_begin_[qi], s_begin_[qi + 1])) {
        for (unsigned e = 0; e < 3; ++e) {
          const Handle h = make_handle(d, e);
          const TriangleId n = triangle_of(dt_.sym(h));
          if (list_size(d) + list_size(n) < k_) continue;
          any = true;
          // Each edge once, directed from its smaller mesh vertex id (so that a KBundleCache key
          // does not depend on the slots of this call's Delaunay triangulation); a hull edge with
          // its finite side on the left.
          const Handle hs = dt_.sym(h);
          pencils.push_back(dt_.is_ghost(n) || sh_.mesh_id[dt_.org(h)] < sh_.mesh_id[dt_.dest(h)] ? h : hs);
        }
      }
      if (!any) ++st_.decided_by_bound;
    }
    std::sort(pencils.begin(), pencils.end());
    pencils.erase(std::unique(pencils.begin(), pencils.end()), pencils.end());
    return pencils;
  }

  // ---- stage 2 over DT(V): one-sided pencils ----

  // Stage 2 over DT(V). A disk of the pencil of a Delaunay edge meeting t lies in the union of the
  // two end circumdisks, and the part of it on either side of the edge lies in that side's end
  // disk, so one of the two ends meets t (bundle-number.md, "One-sided pencils"); a query left
  // undecided meets only end disks counted below k (one meeting k or more would have decided it).
  // So an end meeting k triangles or more is never listed: a pencil of an edge of S(t) with one
  // such end is swept from the other end's list and a lens (Worker::sweep_one_sided), one with
  // two is not swept. On the fan of `mwst generate fan` (40k) the
  // neighbours of S(t) listed in full held 75M of the 81M candidates of the first exact test.
  void second_stage_one_sided() {
    std::vector<std::uint8_t> in_s(dt_slots_, 0);  // the Delaunay triangles of some S(t)
    for (const auto& part : s_lists_.parts()) {
      for (const TriangleId d : part) in_s[d] = 1;
    }
    count_ends(in_s);
    // The ends to list and the pencils to sweep: one-sided, or both ends listed (with k candidates
    // together, once listed), each once, directed as pencils_to_sweep directs them.
    std::vector<std::uint8_t> needed(dt_slots_, 0);
    std::vector<Handle> pencils;
    for (int pass = 0; pass < 2; ++pass) {
      for (TriangleId d = 0; d < dt_slots_; ++d) {
        if (!in_s[d]) continue;
        for (unsigned e = 0; e < 3; ++e) {
          const Handle h = normalized(make_handle(d, e));
          const std::uint8_t m = mode_of(h);
          if (pass == 0) {
            const TriangleId left = triangle_of(h), right = triangle_of(dt_.sym(h));
            if (m == 0 || m == 1) needed[left] = 1;
            if ((m == 0 || m == 2) && !dt_.is_ghost(right)) needed[right] = 1;
          } else if (may_reach(h, m)) {
            pencils.push_back(h);
          }
        }
      }
      if (pass > 0) break;
      for (TriangleId d = 0; d < dt_slots_; ++d) st_.flooded += needed[d] != 0 ? 1 : 0;
      for (auto& w : workers_) {
        w->exact_edges = false;  // the lists: permissive floods, as `mwst bundle`'s
        w->release_disk_scratch();  // (the floods use none; a sweep allocates it again)
      }
      bundle::build_lists(sh_, workers_, &needed, cache_ ? &boxes_ : nullptr);
      release(needed);
    }
    release(in_s);
    std::sort(pencils.begin(), pencils.end());
    pencils.erase(std::unique(pencils.begin(), pencils.end()), pencils.end());
    std::vector<std::uint8_t> mode(pencils.size());
    for (std::size_t p = 0; p < pencils.size(); ++p) mode[p] = mode_of(pencils[p]);
    // The queries of the one-sided pencils, per pencil (Worker::sweep_one_sided reads them), and
    // the queries none of whose pencils is swept.
    std::vector<std::uint32_t> query_begin(pencils.size() + 1, 0), pencil_queries;
    {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (pencil, query index)
      std::vector<std::uint8_t> reached(queries_.size(), 0);
      for_each_s_edge([&](std::size_t qi, Handle h) {
        const std::uint8_t m = mode_of(h);
        if (!may_reach(h, m)) return;
        reached[qi] = 1;
        if (m != 0) pairs.emplace_back(index_of(pencils, h), static_cast<std::uint32_t>(qi));
      });
      for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
        if (in_domain(queries_[qi]) && !answer_[qi] && !reached[qi]) ++st_.decided_by_bound;
      }
      std::sort(pairs.begin(), pairs.end());
      pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
      for (const auto& [p, qi] : pairs) ++query_begin[p + 1];
      for (std::size_t p = 0; p < pencils.size(); ++p) query_begin[p + 1] += query_begin[p];
      pencil_queries.reserve(pairs.size());
      for (const auto& pair : pairs) pencil_queries.push_back(pair.second);
    }
    std::vector<std::uint32_t> box_index(cache_ ? pencils.size() : 0, kNone);  // one-sided: its lens box
    std::size_t one_sided_count = 0;
    for (std::size_t p = 0; p < pencils.size(); ++p) {
      if (mode[p] == 0) continue;
      if (cache_) box_index[p] = static_cast<std::uint32_t>(one_sided_count);
      ++one_sided_count;
    }
    st_.pencils_swept = pencils.size();
    st_.pencils_one_sided = one_sided_count;
    std::vector<std::array<double, 4>> lens_boxes(cache_ ? one_sided_count : 0, {kInf, kInf, -kInf, -kInf});
    const bundle::OneSided one_sided{&mode,          &query_begin, &pencil_queries, &queries_,
                                     cache_ ? &box_index : nullptr, cache_ ? &lens_boxes : nullptr, k_};
    for (auto& w : workers_) w->one_sided = &one_sided;
    if (!pencils.empty()) sweep_pencils(std::move(pencils));
    for (const auto& w : workers_) {
      st_.lens_visits += w->lens_visits;
      st_.candidate_pairs += w->candidate_pairs;
      w->one_sided = nullptr;
    }
    if (cache_) reach_boxes_one_sided(box_index, boxes_, lens_boxes);
  }

  // Edge h of a Delaunay triangle directed as pencils_to_sweep directs it: from its smaller mesh
  // vertex id, or with its finite side on the left on the hull.
  Handle normalized(Handle h) const {
    const Handle hs = dt_.sym(h);
    return dt_.is_ghost(triangle_of(hs)) || sh_.mesh_id[dt_.org(h)] < sh_.mesh_id[dt_.dest(h)] ? h : hs;
  }

  // Can a pencil of mode m (mode_of) put a query left in a k-bundle? One-sided: yes; both ends
  // large: no; both listed: if their lists hold k triangles together.
  bool may_reach(Handle h, std::uint8_t m) const {
    if (m == 3) return false;
    if (m != 0) return true;
    auto list_size = [&](TriangleId d) { return dt_.is_ghost(d) ? 0u : sh_.list_size(d); };
    return list_size(triangle_of(h)) + list_size(triangle_of(dt_.sym(h))) >= k_;
  }

  // Calls f(query index, pencil) for each edge of each Delaunay triangle in S(t) of the queries
  // left, the pencil directed as pencils_to_sweep directs it.
  template <class F>
  void for_each_s_edge(F f) const {
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      for (const TriangleId d : s_lists_.range(s_begin_[qi], s_begin_[qi + 1])) {
        for (unsigned e = 0; e < 3; ++e) f(qi, normalized(make_handle(d, e)));
      }
    }
  }

  static std::uint32_t index_of(const std::vector<Handle>& sorted, Handle h) {
    return static_cast<std::uint32_t>(std::lower_bound(sorted.begin(), sorted.end(), h) - sorted.begin());
  }

  // The ends of the pencils of S(t) not counted in stage 1 (its neighbours), counted now up to k
  // (each once, by the flood that stops at k): mode_of reads the counts.
  void count_ends(const std::vector<std::uint8_t>& in_s) {
    std::vector<TriangleId> uncounted;
    for (TriangleId d = 0; d < dt_slots_; ++d) {
      if (!in_s[d]) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const TriangleId n = triangle_of(dt_.sym(make_handle(d, e)));
        if (!dt_.is_ghost(n) && disk_state_[n].load(std::memory_order_relaxed) == 0) uncounted.push_back(n);
      }
    }
    std::sort(uncounted.begin(), uncounted.end());
    uncounted.erase(std::unique(uncounted.begin(), uncounted.end()), uncounted.end());
    st_.disks_counted += uncounted.size();
    bundle::for_ranges(workers_, uncounted.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
      for (std::size_t i = begin; i < end; ++i) {
        if ((i & 15) == 0) sh_.check_deadline();
        const TriangleId d = uncounted[i];
        disk_state_[d].store(w.count_meeting(d, k_) >= k_ ? 2 : 1, std::memory_order_relaxed);
      }
    });
  }

  // The mode of a pencil: 0 both ends listed (or a hull edge), 1 only the left end (the right
  // one's disk meets k triangles or more), 2 only the right end, 3 neither (both ends meet k
  // triangles or more, or a hull edge's one end does: then no disk of the pencil meets a query
  // left).
  std::uint8_t mode_of(Handle h) const {
    const TriangleId left = triangle_of(h), right = triangle_of(dt_.sym(h));
    const bool left_large = disk_state_[left].load(std::memory_order_relaxed) != 1;
    const bool right_large = !dt_.is_ghost(right) && disk_state_[right].load(std::memory_order_relaxed) != 1;
    // (A hull edge's disks meet triangles only on the left, so only where its left end does.)
    if (left_large && (right_large || dt_.is_ghost(right))) return 3;
    if (right_large) return 1;
    return left_large ? 2 : 0;
  }

  // The reach boxes (see reach_boxes) over one-sided pencils: a disk of a pencil meeting t meets
  // only triangles meeting the listed end or the lens flooded for the lowest bound of the queries
  // it meets (a pencil with both ends listed: either end; with neither, no disk of it meets t).
  void reach_boxes_one_sided(const std::vector<std::uint32_t>& box_index, const bundle::FloodBoxes& boxes,
                             const std::vector<std::array<double, 4>>& lens_boxes) {
    if (!reach_wanted()) return;
    own_boxes();
    auto widen = [](std::array<double, 4>& r, const std::array<double, 4>& b) {
      r = {std::min(r[0], b[0]), std::min(r[1], b[1]), std::max(r[2], b[2]), std::max(r[3], b[3])};
    };
    for_each_s_edge([&](std::size_t qi, Handle h) {
      if (answer_[qi]) return;
      auto& r = cache_->reach[qi];
      const std::uint8_t m = mode_of(h);
      const TriangleId left = triangle_of(h), right = triangle_of(dt_.sym(h));
      if (m == 3) return;
      if (m != 2) widen(r, boxes.box(left));
      if (m != 1 && !dt_.is_ghost(right)) widen(r, boxes.box(right));
      if (m != 0) widen(r, lens_boxes[box_index[index_of(sh_.pencils, h)]]);
    });
  }

  // Are the reach boxes to be computed (once every query is answered: over DT(V), after the
  // sweeps)? Not when the caller wants none for a call answering no query 1
  // (KBundleCache::reach_when_all_no): every box is then left empty, "nothing known". (The local
  // attempts, over DT(W), compute theirs before the sweeps and always do: they are cheap.)
  bool reach_wanted() {
    if (cache_->reach_when_all_no || std::find(answer_.begin(), answer_.end(), 1) != answer_.end()) return true;
    cache_->reach.assign(queries_.size(), {kInf, kInf, -kInf, -kInf});
    return false;
  }

  // A query answered 1 gets the box of its own corners; the others start empty.
  void own_boxes() {
    cache_->reach.assign(queries_.size(), {kInf, kInf, -kInf, -kInf});
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      if (!answer_[qi]) continue;
      auto& r = cache_->reach[qi];
      for (const VertexId v : sh_.slots[queries_[qi]].v) {
        const Point& p = sh_.pts[v];
        r = {std::min(r[0], p.x), std::min(r[1], p.y), std::max(r[2], p.x), std::max(r[3], p.y)};
      }
    }
  }

  // Sweeps the pencils (reusing the cache's sweeps), keeps what the cache should, and answers the
  // queries left from the per-triangle counts.
  void sweep_pencils(std::vector<Handle> pencils) {
    sh_.pencils = std::move(pencils);
    for (auto& w : workers_) {
      w->release_flood_scratch();  // (the sweeps' own scratch takes its place)
      w->min_candidates = k_;
      if (cache_ && cache_->keep_sweeps) w->reuse = cache_->impl.get();
    }
#ifdef __GLIBC__
    // The arrays freed since stage 1 (the floods' per-vertex and per-slot scratch, the marks of
    // the lists' Delaunay triangles) are under the 4 MB that gets its own mapping, so they stay
    // resident in the heap (`mwst triangulate` never trims it), and the sweeps' per-slot scratch
    // does not fit in their holes: in_k_bundle's peak was here, at the end of the sweeps. Returning
    // the free pages now (~12 MB at 160k points) lowers it by 2–3 MB; the sweeps fault in what
    // they use afresh. (No value depends on it.)
    malloc_trim(0);
#endif
    bundle::for_ranges(workers_, sh_.pencils.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
      for (std::size_t i = begin; i < end; ++i) {
        sh_.check_deadline();
        w.sweep(i);
      }
    });
    if (cache_ && cache_->keep_sweeps) keep_sweeps();
    for (std::size_t qi = 0; qi < queries_.size(); ++qi) {
      const TriangleId t = queries_[qi];
      if (!in_domain(t) || answer_[qi]) continue;
      for (const auto& w : workers_) {
        if (w->per_triangle()[t] >= k_) answer_[qi] = 1;
      }
      if (answer_[qi]) ++st_.decided_by_pencils;
    }
  }

  // Keeps in the cache what this call used or made; drops the rest (stale keys of the mesh before).
  void keep_sweeps() {
    std::unordered_map<SweepKey, CachedSweep> next;
    auto& old = cache_->impl->sweeps;
    for (auto& w : workers_) {
      st_.pencils_reused += w->pencils_reused;
      for (const SweepKey key : w->reused_keys) {
        const auto it = old.find(key);
        if (it != old.end()) next.insert_or_assign(key, std::move(it->second));
      }
      for (auto& [key, sweep] : w->made) next.insert_or_assign(key, std::move(sweep));
    }
    old = std::move(next);
  }

  Shared& sh_;
  const std::uint32_t k_;
  const std::vector<TriangleId>& queries_;
  KBundleStats& st_;
  const bool subset_;
  std::vector<std::uint8_t>& answer_;
  KBundleCache* const cache_;
  KBundleCache* const memo_;
  const Mesh& dt_;
  const std::size_t dt_slots_;
  std::vector<Handle> dt_vertex_edge_;
  std::vector<std::uint32_t> dt_degree_;  // finite Delaunay triangles around each vertex
  std::vector<std::unique_ptr<Worker>> workers_;
  std::unique_ptr<std::atomic<std::uint8_t>[]> disk_state_;  // per Delaunay triangle (large_disk)
  std::vector<std::uint32_t> s_count_ = std::vector<std::uint32_t>(queries_.size(), 0);  // |S(t)| per query
  std::vector<std::uint32_t> s_begin_;
  std::vector<TriangleId> hint_dt_;     // per query: the Delaunay triangle its hint names (resolve_hints)
  std::vector<TriangleId> decided_by_;  // per query: the Delaunay triangle whose disk answered it 1
  bundle::PartLists s_lists_;  // S(t) of the queries left, from s_begin_[qi] (merge_parts)
  std::vector<TriangleId> fan_;
  bundle::FloodBoxes boxes_;  // per Delaunay triangle listed: its flood's box
};

Attempt in_k_bundle_attempt(Shared& sh, std::uint32_t k, const std::vector<TriangleId>& queries, KBundleStats& st,
                            unsigned threads_requested, bool subset, std::vector<std::uint8_t>& answer,
                            KBundleCache* cache, KBundleCache* memo) {
  return KBundleAttempt(sh, k, queries, st, subset, answer, cache, memo).run(threads_requested);
}

// ---- the region of a local attempt begins here ----------------------------------------------------

// The local attempt: W holds the vertices of the mesh triangles fewer than kSubsetRings steps
// (across edges, ghosts skipped) from the queries; the region holds the triangles at most
// `region_rings` steps away, every triangle around a vertex of W, and the ghosts next to them.
constexpr std::uint32_t kSubsetRings = 12;
constexpr std::uint32_t kRegionRings[] = {12, 32};

// Fills `region` / `region_ids` and `w` (ascending) for the queries.
void local_region(const Mesh& mesh, const std::vector<TriangleId>& queries, std::uint32_t region_rings,
                  std::vector<TriangleId>& region, DenseIds& region_ids, std::vector<VertexId>& w) {
  region.clear();
  region_ids = DenseIds(queries.size() * 256);
  std::vector<std::pair<VertexId, Handle>> corners;  // the corners of W, with an edge leaving each
  std::vector<TriangleId> frontier, next;
  for (const TriangleId t : queries) {
    if (t < mesh.triangle_slots() && !mesh.is_dead(t) && !mesh.is_ghost(t) && region_ids.insert(t).second) {
      region.push_back(t);
      frontier.push_back(t);
    }
  }
  for (std::uint32_t ring = 0; ring < region_rings && !frontier.empty(); ++ring) {
    next.clear();
    for (const TriangleId t : frontier) {
      const Triangle& tri = mesh.triangles[t];
      if (ring < kSubsetRings) {
        // Corner c is the origin of edge prev3(c).
        for (unsigned c = 0; c < 3; ++c) corners.emplace_back(tri.v[c], make_handle(t, prev3(c)));
      }
      for (unsigned e = 0; e < 3; ++e) {
        const TriangleId n = triangle_of(tri.n[e]);
        if (mesh.is_ghost(n) || mesh.is_dead(n) || !region_ids.insert(n).second) continue;
        region.push_back(n);
        next.push_back(n);
      }
    }
    frontier.swap(next);
  }
  std::sort(corners.begin(), corners.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  w.clear();
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (i > 0 && corners[i].first == corners[i - 1].first) continue;
    w.push_back(corners[i].first);
    const Handle start = corners[i].second;
    Handle h = start;
    do {
      if (region_ids.insert(triangle_of(h)).second) region.push_back(triangle_of(h));
      h = mesh.onext(h);
    } while (h != start);
  }
  const std::size_t finite = region.size();
  for (std::size_t i = 0; i < finite; ++i) {
    if (mesh.is_ghost(region[i])) continue;
    for (const Handle nh : mesh.triangles[region[i]].n) {
      const TriangleId n = triangle_of(nh);
      if (mesh.is_ghost(n) && region_ids.insert(n).second) region.push_back(n);
    }
  }
}

}  // namespace

// ---- in_k_bundle begins here ----------------------------------------------------------------------

std::vector<std::uint8_t> in_k_bundle(const Mesh& mesh, std::uint32_t k, const std::vector<TriangleId>& queries,
                                      KBundleStats* stats, unsigned threads, KBundleCache* cache_given,
                                      std::chrono::steady_clock::time_point deadline) {
  std::vector<std::uint8_t> answer(queries.size(), 0);
  // `cache`: sweeps and reach boxes; `cache_given`: also DT(V) (see KBundleCache::reuse_sweeps).
  KBundleCache* const cache = cache_given && cache_given->reuse_sweeps ? cache_given : nullptr;
  KBundleStats local_stats;
  KBundleStats& st = stats ? *stats : local_stats;
  st = {};
  if (cache) cache->reach.assign(queries.size(), {kInf, kInf, -kInf, -kInf});  // empty: nothing known
  if (cache_given) cache_given->witnesses.clear();  // (each attempt sets them)
  if (queries.empty()) return answer;
  // Few queries in a large mesh: try the Delaunay triangulation of the vertices within a few
  // rings of mesh triangles around them (verified, see in_k_bundle_attempt) before DT(V), over a
  // region of the mesh around them (its cost is what the region holds); if a flood leaves the
  // region, over a larger one.
  if (queries.size() * 256 < mesh.triangle_slots()) {
    std::vector<TriangleId> region;
    DenseIds region_ids;
    std::vector<VertexId> w;
    Attempt a = Attempt::kGaveUp;
    for (const std::uint32_t rings : kRegionRings) {
      local_region(mesh, queries, rings, region, region_ids, w);
      Shared sh(mesh, deadline);
      if (!sh.build_region(region, region_ids, w)) break;
      std::vector<TriangleId> local_queries(queries.size());
      for (std::size_t qi = 0; qi < queries.size(); ++qi) local_queries[qi] = region_ids.find(queries[qi]);
      a = in_k_bundle_attempt(sh, k, local_queries, st, threads, true, answer, cache, cache_given);
      if (a == Attempt::kAnswered) {
        st.local = true;
        return answer;
      }
      if (a == Attempt::kGaveUp) break;
    }
    if (a == Attempt::kEscaped) {
      // Floods reach far (long Delaunay disks, e.g. along the hull of a point set): the same
      // attempt over the whole mesh, still cheaper than DT(V).
      Shared sh(mesh, deadline);
      if (sh.build(false, &w) && in_k_bundle_attempt(sh, k, queries, st, threads, true, answer, cache, cache_given) == Attempt::kAnswered) {
        st.local = true;
        return answer;
      }
    }
  }
  Shared sh(mesh, deadline);
  KBundleCache::Impl* const keep = cache_given ? cache_given->impl.get() : nullptr;
  if (!sh.build(false, nullptr, keep ? &keep->dt : nullptr, keep ? &keep->dt_mesh_id : nullptr)) {
    st = {};
    answer.assign(queries.size(), 0);
    if (cache) cache->reach.assign(queries.size(), {kInf, kInf, -kInf, -kInf});  // nothing known
    return answer;
  }
  // DT(V)'s coordinates are sh.pts[0, used): the attempt reads only its topology, and the cache
  // gets them back.
  const bool points_dropped = sh.dt.points.size() == sh.used;
  if (points_dropped) bundle::release(sh.dt.points);
  in_k_bundle_attempt(sh, k, queries, st, threads, false, answer, cache, cache_given);
  st.kept_dt = sh.kept_dt;
  if (keep) {
    if (points_dropped) sh.dt.points.assign(sh.pts.begin(), sh.pts.begin() + sh.used);
    keep->dt = std::move(sh.dt);
    keep->dt_mesh_id.assign(sh.mesh_id.begin(), sh.mesh_id.begin() + sh.used);
  }
  return answer;
}

}  // namespace mwst
