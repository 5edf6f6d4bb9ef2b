// src/algorithms/bundle/worker_sweep.cpp — a Worker's sweep over the pencil of disks of one
// Delaunay edge (worker.hpp; the geometry is in docs/algorithms/bundle-number.md, "One pencil").
#include "algorithms/bundle/worker.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/bundle/circle_predicates.hpp"

namespace mwst::bundle {

// ---- the sweep begins here ------------------------------------------------------------------------

void Worker::sweep(std::size_t index) {
  ensure_per_triangle();
  if (given_[0] == nullptr && one_sided != nullptr && (*one_sided->mode)[index] != 0) {
    if ((*one_sided->mode)[index] != 3) sweep_one_sided(index);  // (3: both ends large, not swept)
    return;
  }
  const Mesh& dt = sh_.dt;
  const Handle h = sh_.pencils[index];
  const Handle hs = dt.sym(h);
  const VertexId lv = dt.apex(h), rv = dt.apex(hs);  // rv = kInfinite on a hull edge
  // Fewer candidates than asked for (in_k_bundle's k) even in the two lists together: the pencil
  // cannot matter, and its candidates are not gathered.
  if (min_candidates > 0 && given_[0] == nullptr &&
      sh_.list_size(triangle_of(h)) + (rv == kInfinite ? 0 : sh_.list_size(triangle_of(hs))) < min_candidates) {
    return;
  }
  if (!start_pencil(h, rv)) return;
  ++pencils;
  // The two lists hold at least as many triangles as their union: a pencil that cannot beat the
  // best count is pruned before its candidates are gathered (points on a circle: a million hull
  // pencils share one list of all the triangles).
  const bool prune = prune_ && given_[0] == nullptr;
  if (prune && sh_.list_size(triangle_of(h)) + (rv == kInfinite ? 0 : sh_.list_size(triangle_of(hs))) <= best_count) {
    count_pencil_ends(h, hs);
    return;
  }
  gather_candidates(h, hs, rv);
  candidate_pairs += candidates_.size();
  // No disk of this pencil meets more triangles than it has candidates: below the count asked
  // for (in_k_bundle), the pencil cannot matter.
  if (candidates_.size() < min_candidates) return;
  // A result of an earlier call with the same key (see CachedSweep).
  const bool cacheable = reuse != nullptr && per_triangle_enabled_ && candidates_.size() >= kCachedCandidates;
  if (cacheable && reuse_cached_sweep(lv, rv)) return;
  // No disk of this pencil meets more triangles than it has candidates. Its two circumdisks
  // are still counted (directly, when their lists could beat the best circumdisk so far).
  if (prune && candidates_.size() <= best_count) {
    count_pencil_ends(h, hs);
    return;
  }
  std::uint32_t always_count = 0, b_total = 0;
  collect_events(lv, rv, always_count, b_total);
  order_events();
  std::uint32_t lo_group = kNone, hi_group = kNone;
  group_events(lo_group, hi_group);
  // The circumdisks (the ends of the pencil).
  circumdisk_best = std::max(circumdisk_best, count_at_end(hi_group, always_count));
  if (lo_group != kNone) circumdisk_best = std::max(circumdisk_best, count_at_end(lo_group, always_count));
  // Valid intervals: above the class of s_lo (if any), not above the class of s_hi.
  const std::uint32_t j_min = lo_group == kNone ? 0 : lo_group + 1;
  const std::uint32_t j_max = hi_group;
  if (j_min > j_max) return;  // cannot happen: s_lo < s_hi strictly here
  best_interval(index, j_min, j_max, always_count, b_total);
  if (per_triangle_enabled_) spread_per_triangle(j_min, j_max, cacheable);
}

// Sets the pencil of Delaunay edge h (p → q); false if it is not swept: s_lo = s_hi (the four
// vertices are cocircular; the only disk is a circumdisk, which the neighbouring pencils reach as a
// limit, see docs/algorithms/bundle-number.md), or a list cut at the budget's cap (the sweep would
// not be exact; bundle_number bounds it).
bool Worker::start_pencil(Handle h, VertexId rv) {
  const Mesh& dt = sh_.dt;
  const Handle hs = dt.sym(h);
  pc_.pv = dt.org(h);
  pc_.qv = dt.dest(h);
  pc_.p = sh_.pts[pc_.pv];
  pc_.q = sh_.pts[pc_.qv];
  pc_.points = sh_.pts.data();
  if (rv != kInfinite && sh_.cocircular_edge(h)) return false;
  if (given_[0] == nullptr && (sh_.list_cut(triangle_of(h)) || (rv != kInfinite && sh_.list_cut(triangle_of(hs))))) {
    return false;
  }
  return true;
}

// The candidates: the union of the lists of the two Delaunay triangles on the edge (every disk of
// the pencil lies in their circumdisks), each triangle once.
void Worker::gather_candidates(Handle h, Handle hs, VertexId rv) {
  candidates_.clear();
  auto gather = [&](TriangleId dtt, const std::vector<TriangleId>* given) {
    gather_list(given ? given->data() : sh_.list_data(dtt), given ? given->size() : sh_.list_size(dtt));
  };
  gather(triangle_of(h), given_[0]);
  if (rv != kInfinite) gather(triangle_of(hs), given_[1]);
}

// Appends the triangles of a list that are not candidates yet.
void Worker::gather_list(const TriangleId* list, std::size_t size) {
  if (candidate_index_.empty()) {
    candidate_index_.assign(sh_.slots.size(), kNone);
    pencil_side_.assign(sh_.pts.size(), kUnsetSide);
    pencil_local_.assign(sh_.pts.size(), Point{});
  }
  for (std::size_t i = 0; i < size; ++i) {
    const TriangleId t = list[i];
    if (is_candidate(t)) continue;
    candidate_index_[t] = static_cast<std::uint32_t>(candidates_.size());
    Candidate c;
    c.triangle = t;
    candidates_.push_back(c);
  }
}

// Looks the pencil up in the cache of an earlier call (KBundleCache); true if its result was
// reused (per_triangle updated). Otherwise starts the entry this call makes (`made`).
bool Worker::reuse_cached_sweep(VertexId lv, VertexId rv) {
  const SweepKey key = SweepKey{sh_.mesh_id[pc_.pv]} << 32 | sh_.mesh_id[pc_.qv];
  key_order_.resize(candidates_.size());
  key_triangles_.resize(candidates_.size());
  for (std::uint32_t i = 0; i < candidates_.size(); ++i) {
    key_order_[i] = i;
    const auto& tv = sh_.slots[candidates_[i].triangle].v;
    std::array<VertexId, 3> m{sh_.mesh_id[tv[0]], sh_.mesh_id[tv[1]], sh_.mesh_id[tv[2]]};
    while (m[0] > m[1] || m[0] > m[2]) m = {m[1], m[2], m[0]};
    key_triangles_[i] = m;
  }
  std::sort(key_order_.begin(), key_order_.end(),
            [this](std::uint32_t x, std::uint32_t y) { return key_triangles_[x] < key_triangles_[y]; });
  const VertexId lm = sh_.mesh_id[lv], rm = rv == kInfinite ? kInfinite : sh_.mesh_id[rv];
  const auto it = reuse->sweeps.find(key);
  if (it != reuse->sweeps.end() && it->second.lv == lm && it->second.rv == rm &&
      it->second.triangles.size() == candidates_.size()) {
    const CachedSweep& c = it->second;
    bool same = true;
    for (std::size_t j = 0; j < key_order_.size() && same; ++j) same = c.triangles[j] == key_triangles_[key_order_[j]];
    if (same) {
      for (std::size_t j = 0; j < key_order_.size(); ++j) {
        std::uint32_t& slot = per_triangle_[candidates_[key_order_[j]].triangle];
        slot = std::max(slot, c.best[j]);
      }
      ++pencils_reused;
      reused_keys.push_back(key);
      return true;
    }
  }
  made.emplace_back(key, CachedSweep{lm, rm, {}, {}});
  CachedSweep& c = made.back().second;
  c.triangles.reserve(candidates_.size());
  for (const std::uint32_t i : key_order_) c.triangles.push_back(key_triangles_[i]);
  c.best.assign(candidates_.size(), 0);
  return false;
}

// A pencil pruned: only its two circumdisks are counted, when their lists could beat the best
// circumdisk so far.
void Worker::count_pencil_ends(Handle h, Handle hs) {
  const Mesh& dt = sh_.dt;
  for (const TriangleId dtt : {triangle_of(h), triangle_of(hs)}) {
    if (dt.is_ghost(dtt)) continue;
    const std::uint32_t size = sh_.list_size(dtt);
    if (size <= circumdisk_best) continue;
    circumdisk_best = std::max(circumdisk_best, circumdisk_count(dtt, sh_.list_data(dtt), size, nullptr));
  }
}

// The thresholds of every candidate (classify) and of the pencil's ends s_hi (apex lv) and s_lo
// (apex rv, none on a hull edge); counts the candidates that meet every disk and the b_t events.
void Worker::collect_events(VertexId lv, VertexId rv, std::uint32_t& always_count, std::uint32_t& b_total) {
  begin_events();
  classify_from(0, always_count, b_total);
  end_events(lv, rv);
}

// The pencil's local frame, and no events yet.
void Worker::begin_events() {
  pc_.bx = pc_.q.x - pc_.p.x;
  pc_.by = pc_.q.y - pc_.p.y;
  pc_.local_scale = 2.0 / (pc_.bx * pc_.bx + pc_.by * pc_.by);
  for (const VertexId v : pencil_touched_) pencil_side_[v] = kUnsetSide;  // (the last pencil's)
  pencil_touched_.clear();
  edge_info_.clear();
  events_.clear();
}

// The events of the candidates from index `first` on.
void Worker::classify_from(std::uint32_t first, std::uint32_t& always_count, std::uint32_t& b_total) {
  const auto n_cand = static_cast<std::uint32_t>(candidates_.size());
  if (edge_ref_.size() < 3 * static_cast<std::size_t>(n_cand)) edge_ref_.resize(3 * static_cast<std::size_t>(n_cand));
  for (std::uint32_t i = first; i < n_cand; ++i) {
    bool has_a = false, has_b = false;
    Threshold a, b;
    classify(i, has_a, a, has_b, b);
    if (candidates_[i].always) {
      ++always_count;
      continue;
    }
    if (has_a) events_.push_back({a, i, kRoleA});
    if (has_b) {
      events_.push_back({b, i, kRoleB});
      ++b_total;
    }
  }
}

// The events of the pencil's ends: s_hi (apex lv) and s_lo (apex rv, none on a hull edge).
void Worker::end_events(VertexId lv, VertexId rv) {
  events_.push_back({rational_threshold(pc_, Kind::kThroughVertex, lv, sh_.pts[lv]), kNone, kRoleHi});
  if (rv != kInfinite) {
    events_.push_back({rational_threshold(pc_, Kind::kThroughVertex, rv, sh_.pts[rv]), kNone, kRoleLo});
  }
}

// Sorts the events by rounded value, then repairs runs whose error windows overlap with exact
// comparisons (an insertion sort per run: runs are short).
void Worker::order_events() {
  std::sort(events_.begin(), events_.end(), [](const Event& x, const Event& y) {
    if (x.th.value != y.th.value) return x.th.value < y.th.value;
    if (x.role != y.role) return x.role < y.role;
    return x.candidate < y.candidate;
  });
  const std::size_t n = events_.size();
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && events_[j].th.value - events_[j - 1].th.value <=
                        events_[j].th.error + events_[j - 1].th.error) {
      ++j;
    }
    for (std::size_t k = i + 1; k < j; ++k) {
      const Event moving = events_[k];
      std::size_t l = k;
      while (l > i && compare_thresholds(pc_, events_[l - 1].th, moving.th, exact_comparisons) > 0) {
        events_[l] = events_[l - 1];
        --l;
      }
      events_[l] = moving;
    }
    i = j;
  }
}

// Classes of equal thresholds: group_start_, and per class how many a_t and b_t it holds; each
// candidate learns the classes of its thresholds. Interval j lies below class j (j = 0: below
// everything).
void Worker::group_events(std::uint32_t& lo_group, std::uint32_t& hi_group) {
  group_start_.clear();
  group_a_.clear();
  group_b_.clear();
  const std::size_t n = events_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i == 0 || compare_thresholds(pc_, events_[i - 1].th, events_[i].th, exact_comparisons) != 0) {
      group_start_.push_back(static_cast<std::uint32_t>(i));
      group_a_.push_back(0);
      group_b_.push_back(0);
    }
    const auto g = static_cast<std::uint32_t>(group_start_.size() - 1);
    const Event& ev = events_[i];
    if (ev.role == kRoleLo) {
      lo_group = g;
    } else if (ev.role == kRoleHi) {
      hi_group = g;
    } else if (ev.role == kRoleA) {
      candidates_[ev.candidate].a_group = g;
      ++group_a_[g];
    } else {
      candidates_[ev.candidate].b_group = g;
      ++group_b_[g];
    }
  }
}

// The count of the end circumdisk in class g: thresholds strictly below / above the end count.
std::uint32_t Worker::count_at_end(std::uint32_t g, std::uint32_t always_count) const {
  const auto groups = static_cast<std::uint32_t>(group_start_.size());
  std::uint32_t a_lt = 0, b_gt = 0;
  for (std::uint32_t k = 0; k < g; ++k) a_lt += group_a_[k];
  for (std::uint32_t k = g + 1; k < groups; ++k) b_gt += group_b_[k];
  return always_count + a_lt + b_gt;
}

// The count on every open interval up to j_max (counts_), and the witness of the best one in
// [j_min, j_max] if it beats best_count (the first such interval: ties go to the lowest).
void Worker::best_interval(std::size_t index, std::uint32_t j_min, std::uint32_t j_max, std::uint32_t always_count,
                           std::uint32_t b_total) {
  counts_.resize(static_cast<std::size_t>(j_max) + 1);
  std::uint32_t a_below = 0, b_below = 0, best_j = j_min;
  for (std::uint32_t j = 0; j <= j_max; ++j) {
    counts_[j] = always_count + a_below + (b_total - b_below);
    if (j >= j_min && counts_[j] > counts_[best_j]) best_j = j;
    a_below += group_a_[j];
    b_below += group_b_[j];
  }
  if (counts_[best_j] > best_count) record_witness(index, best_j, counts_[best_j]);
}

// Per candidate, the largest count of an interval whose disks meet it (prefix and suffix maxima
// of counts_), into per_triangle_ and, if cacheable, into the entry this call makes.
void Worker::spread_per_triangle(std::uint32_t j_min, std::uint32_t j_max, bool cacheable) {
  if (cacheable) key_best_.assign(candidates_.size(), 0);
  prefix_max_.resize(counts_.size());
  suffix_max_.resize(counts_.size() + 1);
  std::uint32_t run = 0;
  for (std::uint32_t j = j_min; j <= j_max; ++j) prefix_max_[j] = run = std::max(run, counts_[j]);
  run = 0;
  suffix_max_[j_max + 1] = 0;
  for (std::uint32_t j = j_max + 1; j-- > j_min;) suffix_max_[j] = run = std::max(run, counts_[j]);
  for (const Candidate& c : candidates_) {
    std::uint32_t best = 0;
    if (c.always) {
      best = prefix_max_[j_max];
    } else {
      if (c.a_group != kNone) {
        const std::uint32_t j = std::max(c.a_group + 1, j_min);
        if (j <= j_max) best = std::max(best, suffix_max_[j]);
      }
      if (c.b_group != kNone) {
        const std::uint32_t j = std::min(c.b_group, j_max);
        if (j >= j_min) best = std::max(best, prefix_max_[j]);
      }
    }
    std::uint32_t& slot = per_triangle_[c.triangle];
    slot = std::max(slot, best);
    if (cacheable) key_best_[candidate_index_[c.triangle]] = best;
  }
  if (cacheable) {
    std::vector<std::uint32_t>& out = made.back().second.best;
    for (std::size_t j = 0; j < key_order_.size(); ++j) out[j] = key_best_[key_order_[j]];
  }
}

// ---- one-sided pencils (in_k_bundle) begin here ---------------------------------------------------

// The pencil of Delaunay edge p→q, whose left end D_hi (s_hi) or right end D_lo (s_lo) is listed
// and whose other end meets at least k triangles and none of the queries (OneSided). Say the left
// end is listed: a query t not met by D_hi is met by no disk of the pencil (one_sided_query); one
// met has a_t < s_hi, and as D_lo misses it, a_t ≥ s_lo and b_t ≤ s_lo: the disks D_s meeting t
// are those with s > a_t. A triangle meets such a disk above
// the line pq only if it meets D_hi (the part of D_s above the line grows with s), so it is in the
// listed end's list; below the line only if b_c > s > a_t: it meets the lens Λ(a_t), the part of
// D_{a_t} below the line, which shrinks as s grows. Λ(x) holds no vertex (x ≥ s_lo) and is convex
// with the open chord on its boundary, so the triangles meeting it are reached from those meeting
// the chord across edges meeting Λ(x) (edges with b_e > x, or crossing the chord): a flood of the
// lens, not of D_lo. The counts of the disks with s > x are then exact with the listed end's list
// and the lens's triangles as candidates. With queries met at several thresholds, x is the lowest
// (the largest lens) whose query is not already answered: a lens holding enough triangles answers
// its queries at once (the interval just above x already counts k) and the flood stops there, so
// a pencil costs about k + the listed end's list, not what the large end meets (the fan of
// `mwst generate fan`: the spike bases' pencils, one end a sliver's disk meeting ~10 triangles, the
// other reaching across the apex's thousands). The right end listed is the mirror image (a ↔ b,
// lens above the line). Whatever the classification of a query contradicts (the exact circumdisk
// test said D_hi meets it and D_lo does not) falls back to the large end's list.
void Worker::sweep_one_sided(std::size_t index) {
  const Mesh& dt = sh_.dt;
  const Handle h = sh_.pencils[index];
  const Handle hs = dt.sym(h);
  const VertexId lv = dt.apex(h), rv = dt.apex(hs);
  if (!start_pencil(h, rv)) return;  // four cocircular vertices: a single disk, a circumdisk
  ++pencils;
  const bool left_listed = (*one_sided->mode)[index] == 1;
  const TriangleId listed = triangle_of(left_listed ? h : hs);
  candidates_.clear();
  gather_list(sh_.list_data(listed), sh_.list_size(listed));
  std::uint32_t always_count = 0, b_total = 0;
  begin_events();
  classify_from(0, always_count, b_total);
  const Threshold s_hi = rational_threshold(pc_, Kind::kThroughVertex, lv, sh_.pts[lv]);
  const Threshold s_lo = rational_threshold(pc_, Kind::kThroughVertex, rv, sh_.pts[rv]);
  // Each query with its bound x_t: a_t (left listed: met for s > a_t) or b_t (right: s < b_t).
  one_sided_queries_.clear();
  for (std::uint32_t i = (*one_sided->begin)[index]; i < (*one_sided->begin)[index + 1]; ++i) {
    const TriangleId t = (*one_sided->slots)[(*one_sided->queries)[i]];
    Threshold bound;
    const int met = one_sided_query(t, left_listed, s_lo, s_hi, bound);
    if (met < 0) {
      one_sided_fallback(index, left_listed);
      return;
    }
    if (met > 0) one_sided_queries_.emplace_back(t, bound);
  }
  // The largest lens first (left listed: the lowest a_t), equal bounds together.
  const int order = left_listed ? 1 : -1;
  std::sort(one_sided_queries_.begin(), one_sided_queries_.end(), [&](const auto& x, const auto& y) {
    return compare_thresholds(pc_, x.second, y.second, exact_comparisons) * order < 0;
  });
  std::size_t next = 0;
  while (next < one_sided_queries_.size()) {
    const Threshold x = one_sided_queries_[next].second;
    if (lens_flood(x, left_listed, always_count, b_total)) break;
    // The interval next to x meets k triangles: every query bounded by x is in a k-bundle.
    for (; next < one_sided_queries_.size() && compare_thresholds(pc_, one_sided_queries_[next].second, x, exact_comparisons) == 0; ++next) {
      std::uint32_t& slot = per_triangle_[one_sided_queries_[next].first];
      slot = std::max(slot, one_sided->k);
    }
  }
  candidate_pairs += candidates_.size();
  if (next == one_sided_queries_.size()) return;
  if (one_sided->boxes) (*one_sided->boxes)[(*one_sided->box_index)[index]] = lens_box_;
  end_events(lv, rv);
  order_events();
  std::uint32_t lo_group = kNone, hi_group = kNone;
  group_events(lo_group, hi_group);
  const std::uint32_t j_min = lo_group + 1, j_max = hi_group;
  if (lo_group == kNone || j_min > j_max) return;  // cannot happen: s_lo < s_hi strictly here
  // The counts of the open intervals (exact above the class of x, left listed; below it, right).
  counts_.resize(static_cast<std::size_t>(j_max) + 1);
  std::uint32_t a_below = 0, b_below = 0;
  for (std::uint32_t j = 0; j <= j_max; ++j) {
    counts_[j] = always_count + a_below + (b_total - b_below);
    a_below += group_a_[j];
    b_below += group_b_[j];
  }
  for (std::size_t q = next; q < one_sided_queries_.size(); ++q) {
    const Candidate& c = candidates_[candidate_index_[one_sided_queries_[q].first]];
    const std::uint32_t from = left_listed ? std::max(c.a_group + 1, j_min) : j_min;
    const std::uint32_t to = left_listed ? j_max : std::min(c.b_group, j_max);
    std::uint32_t best = 0;
    for (std::uint32_t j = from; j <= to; ++j) best = std::max(best, counts_[j]);
    std::uint32_t& slot = per_triangle_[one_sided_queries_[q].first];
    slot = std::max(slot, best);
  }
}

// Query t of a one-sided pencil, classified with the listed end's candidates: 1 and its bound (a_t,
// left listed; b_t, right) if the pencil's disks meet it on the listed end's side only; 0 if they
// meet it nowhere (not in the listed end's list, whose disk it then misses, nor met by the large
// end's, which stage 1 showed); -1 if the classification puts it on the large end's side, which
// contradicts the exact circumdisk tests of stage 1 (then the pencil falls back to both lists).
int Worker::one_sided_query(TriangleId t, bool left_listed, const Threshold& s_lo, const Threshold& s_hi,
                            Threshold& bound) {
  if (!is_candidate(t)) return 0;
  const std::uint32_t i = candidate_index_[t];
  if (candidates_[i].always) return -1;
  bool has_a = false, has_b = false;
  Threshold a, b;
  for (const Event& ev : events_) {
    if (ev.candidate != i) continue;
    if (ev.role == kRoleA) {
      has_a = true;
      a = ev.th;
    } else if (ev.role == kRoleB) {
      has_b = true;
      b = ev.th;
    }
  }
  auto cmp = [&](const Threshold& x, const Threshold& y) { return compare_thresholds(pc_, x, y, exact_comparisons); };
  if (left_listed) {
    if ((has_b && cmp(b, s_lo) > 0) || (has_a && cmp(a, s_lo) < 0)) return -1;
    if (!has_a || cmp(a, s_hi) >= 0) return 0;
    bound = a;
  } else {
    if ((has_a && cmp(a, s_hi) < 0) || (has_b && cmp(b, s_hi) > 0)) return -1;
    if (!has_b || cmp(b, s_lo) <= 0) return 0;
    bound = b;
  }
  return 1;
}

// Adds to the candidates the in-domain triangles meeting the lens Λ(x) (left listed: the part of
// D_x below the line; right: above), by a flood from the triangles meeting the open chord across
// the edges that may meet it (permissive: the candidates are classified exactly, and a superset
// changes no count above x). Counts as it goes the candidates meeting the disks of the open
// interval next to x; true if the flood ends below k, false once it reaches k (then that
// interval's disks are vertex-empty, meet every query bounded by x and k triangles).
bool Worker::lens_flood(const Threshold& x, bool left_listed, std::uint32_t& always_count, std::uint32_t& b_total) {
  auto cmp = [&](const Threshold& y) { return compare_thresholds(pc_, y, x, exact_comparisons); };
  // Does the interval next to x count this event's candidate? (Left: s just above x, the
  // candidate's a below s or its b above; right: s just below x.)
  auto counted = [&](const Event& ev) {
    if (ev.role == kRoleA) return left_listed ? cmp(ev.th) <= 0 : cmp(ev.th) < 0;
    if (ev.role == kRoleB) return left_listed ? cmp(ev.th) > 0 : cmp(ev.th) >= 0;
    return false;
  };
  std::uint32_t count = always_count;
  for (const Event& ev : events_) count += counted(ev) ? 1 : 0;
  if (count >= one_sided->k) return false;
  if (lens_stamp_.empty()) lens_stamp_.assign(sh_.slots.size(), 0);
  bump(lens_mark_, [this] { std::fill(lens_stamp_.begin(), lens_stamp_.end(), 0); });
  lens_box_ = {kInf, kInf, -kInf, -kInf};
  lens_stack_.clear();
  auto push = [&](TriangleId t) {
    if (t == sh_.outside || sh_.is_ghost(t) || lens_stamp_[t] == lens_mark_) return;
    lens_stamp_[t] = lens_mark_;
    lens_stack_.push_back(t);
  };
  // The seeds: the mesh triangle around p (or q) whose corner holds the chord, and across pq
  // when pq is a mesh edge (then the two triangles on it meet the open chord).
  const TriangleId first = flood_start(pc_.pv, pc_.qv);
  push(first);
  for (unsigned e = 0; e < 3; ++e) {
    const Handle eh = make_handle(first, e);
    const VertexId u = sh_.org(eh), w = sh_.dest(eh);
    if ((u == pc_.pv && w == pc_.qv) || (u == pc_.qv && w == pc_.pv)) push(triangle_of(sh_.sym(eh)));
  }
  // Permissive: an edge whose threshold is within its and x's error windows of x, or within
  // 1e-9 relatively (tangencies are rounded), is crossed too.
  auto near_side = [&](const Threshold& y) {
    const double slack = y.error + x.error + 1e-9 * (1.0 + std::fabs(x.value) + std::fabs(y.value));
    return left_listed ? y.value + slack > x.value : y.value - slack < x.value;
  };
  while (!lens_stack_.empty()) {
    const TriangleId t = lens_stack_.back();
    lens_stack_.pop_back();
    ++lens_visits;
    for (const VertexId v : sh_.slots[t].v) {
      const Point& pt = sh_.pts[v];
      lens_box_ = {std::min(lens_box_[0], pt.x), std::min(lens_box_[1], pt.y), std::max(lens_box_[2], pt.x),
                   std::max(lens_box_[3], pt.y)};
    }
    if (sh_.in_domain(t) && !is_candidate(t)) {
      const auto i = static_cast<std::uint32_t>(candidates_.size());
      candidate_index_[t] = i;
      Candidate c;
      c.triangle = t;
      candidates_.push_back(c);
      const std::size_t first_event = events_.size();
      const std::uint32_t always_before = always_count;
      classify_from(i, always_count, b_total);
      count += always_count - always_before;
      for (std::size_t k = first_event; k < events_.size(); ++k) count += counted(events_[k]) ? 1 : 0;
      if (count >= one_sided->k) return false;
    }
    for (unsigned e = 0; e < 3; ++e) {
      const Handle eh = make_handle(t, e);
      const TriangleId n = triangle_of(sh_.sym(eh));
      if (n == sh_.outside || sh_.is_ghost(n) || lens_stamp_[n] == lens_mark_) continue;
      EdgeInfo info;
      classify_edge(sh_.org(eh), sh_.dest(eh), info);
      if (info.crosses || (left_listed ? info.has_b && near_side(info.b) : info.has_a && near_side(info.a))) push(n);
    }
  }
  return true;
}

// The pencil swept from both ends' lists: the large end flooded now (its flood's box is the
// pencil's).
void Worker::one_sided_fallback(std::size_t index, bool left_listed) {
  ++one_sided_fallbacks;
  const Mesh& dt = sh_.dt;
  const Handle h = sh_.pencils[index];
  const TriangleId listed = triangle_of(left_listed ? h : dt.sym(h));
  const TriangleId large = triangle_of(left_listed ? dt.sym(h) : h);
  std::vector<TriangleId> lists[2];
  std::vector<TriangleId>& listed_list = lists[left_listed ? 0 : 1];
  listed_list.assign(sh_.list_data(listed), sh_.list_data(listed) + sh_.list_size(listed));
  flood(large, lists[left_listed ? 1 : 0]);
  if (one_sided->boxes) (*one_sided->boxes)[(*one_sided->box_index)[index]] = flood_box;
  --pencils;  // (counted again by the sweep)
  sweep_with_lists(index, lists[0], lists[1]);
}

// ---- classifying the candidates begins here -------------------------------------------------------

// Side of vertex v relative to the directed line p→q, cached per pencil with its local
// coordinates.
Worker::PencilVertex Worker::vertex(VertexId v) {
  std::int8_t& side = pencil_side_[v];
  if (side == kUnsetSide) {
    pencil_touched_.push_back(v);
    if (v == pc_.pv) {
      side = kSideP;
    } else if (v == pc_.qv) {
      side = kSideQ;
    } else {
      const Point& pt = sh_.pts[v];
      side = static_cast<std::int8_t>(orient2d(pc_.p, pc_.q, pt));
      const double dx = pt.x - pc_.p.x, dy = pt.y - pc_.p.y;
      pencil_local_[v] = {(dx * pc_.bx + dy * pc_.by) * pc_.local_scale - 1.0,
                          (pc_.bx * dy - pc_.by * dx) * pc_.local_scale};
    }
  }
  return {side, pencil_local_[v]};
}

// Keeps the smaller (sigma = +1) or larger (sigma = −1) threshold in `best`.
void Worker::keep_extreme(int sigma, bool& has, Threshold& best, const Threshold& t) {
  if (!has) {
    has = true;
    best = t;
  } else if (compare_thresholds(pc_, t, best, exact_comparisons) * sigma < 0) {
    best = t;
  }
}

// The contribution of edge uw (see EdgeInfo); `info` starts empty.
void Worker::classify_edge(VertexId u, VertexId w, EdgeInfo& info) {
  const PencilVertex& xu = vertex(u);
  const PencilVertex& xw = vertex(w);
  const std::int8_t su = xu.side, sw = xw.side;
  const Point& pu = sh_.pts[u];
  const Point& pw = sh_.pts[w];
  if ((su == 1 && sw == -1) || (su == -1 && sw == 1)) {
    // No vertex lies on the open chord of a Delaunay edge: crossing is proper or absent.
    if (orient2d(pu, pw, pc_.p) * orient2d(pu, pw, pc_.q) < 0) {
      info.crosses = true;
      return;
    }
  }
  const bool u_end = su == kSideP || su == kSideQ;
  const bool w_end = sw == kSideP || sw == kSideQ;
  if (u_end || w_end) {
    if (u_end && w_end) return;  // the edge pq itself: its triangles meet the chord
    // An edge from p or q: f is linear along it, its infimum is the tangent at that end.
    const std::int8_t end_side = u_end ? su : sw;
    const std::int8_t far_side = u_end ? sw : su;
    const VertexId far = u_end ? w : u;
    if (far_side != 1 && far_side != -1) return;
    const Threshold th = rational_threshold(pc_, end_side == kSideP ? Kind::kTangentAtP : Kind::kTangentAtQ,
                                            far, sh_.pts[far]);
    if (far_side == 1) {
      info.has_a = true;
      info.a = th;
    } else {
      info.has_b = true;
      info.b = th;
    }
    return;
  }
  for (const int sigma : {1, -1}) {
    const bool in_u = su == sigma, in_w = sw == sigma;
    if (!in_u && !in_w) continue;
    bool interior = false;
    if (in_u && in_w) {
      interior = detail::enters_circle(pc_.p, pc_.q, pu, pw, su) > 0 && detail::enters_circle(pc_.p, pc_.q, pw, pu, sw) > 0;
    } else if (in_u) {
      interior = detail::enters_circle(pc_.p, pc_.q, pu, pw, su) > 0;
    } else {
      interior = detail::enters_circle(pc_.p, pc_.q, pw, pu, sw) > 0;
    }
    if (!interior) continue;
    // Local coordinates, mirrored for the lower side (f(x₁, −x₂) = −f(x₁, x₂)).
    Point lu = in_u ? xu.local : xw.local;
    Point lw = in_u ? xw.local : xu.local;
    if (sigma < 0) {
      lu.y = -lu.y;
      lw.y = -lw.y;
    }
    Threshold th;
    th.kind = Kind::kTangentToEdge;
    th.value = sigma * tangency_minimum(lu, lw);
    if (sigma > 0) {
      info.has_a = true;
      info.a = th;
    } else {
      info.has_b = true;
      info.b = th;
    }
  }
}

// Classifies candidate i for the current pencil: "always", and/or the thresholds a_t (above:
// counts for s > a_t) and b_t (below: counts for s < b_t). Edge contributions are shared with
// the neighbouring candidate across each edge.
void Worker::classify(std::uint32_t i, bool& has_a, Threshold& a, bool& has_b, Threshold& b) {
  Candidate& cand = candidates_[i];
  const TriangleId t = cand.triangle;
  const auto& tv = sh_.slots[t].v;
  bool always = false;
  int ip = -1, iq = -1;
  for (int k = 0; k < 3; ++k) {
    const std::int8_t s = vertex(tv[k]).side;
    if (s == kSideP) ip = k;
    if (s == kSideQ) iq = k;
  }
  if (ip >= 0 && iq >= 0) always = true;  // pq is an edge of t
  // The open chord pq enters t at its corner p (or q): q strictly inside the corner's angle.
  if (!always && ip >= 0) {
    const Point& x = sh_.pts[tv[next3(static_cast<unsigned>(ip))]];
    const Point& y = sh_.pts[tv[prev3(static_cast<unsigned>(ip))]];
    always = orient2d(pc_.p, x, pc_.q) > 0 && orient2d(pc_.p, pc_.q, y) > 0;
  }
  if (!always && iq >= 0) {
    const Point& x = sh_.pts[tv[next3(static_cast<unsigned>(iq))]];
    const Point& y = sh_.pts[tv[prev3(static_cast<unsigned>(iq))]];
    always = orient2d(pc_.q, x, pc_.p) > 0 && orient2d(pc_.q, pc_.p, y) > 0;
  }
  has_a = has_b = false;
  const auto& neighbours = sh_.neighbours(t);
  for (unsigned k = 0; k < 3; ++k) {
    const Handle across = neighbours[k];
    const TriangleId n = triangle_of(across);
    std::uint32_t& ref = edge_ref_[3 * static_cast<std::size_t>(i) + k];
    if (is_candidate(n) && candidate_index_[n] < i) {
      ref = edge_ref_[3 * static_cast<std::size_t>(candidate_index_[n]) + edge_of(across)];
    } else {
      ref = static_cast<std::uint32_t>(edge_info_.size());
      edge_info_.emplace_back();
      classify_edge(tv[next3(k)], tv[prev3(k)], edge_info_.back());
    }
    const EdgeInfo& info = edge_info_[ref];
    always = always || info.crosses;
    if (info.has_a) keep_extreme(1, has_a, a, info.a);
    if (info.has_b) keep_extreme(-1, has_b, b, info.b);
  }
  cand.always = always;
  // A triangle that misses the chord cannot meet one disk of the pencil both above and below
  // the line (the segment joining the two meeting points would cross the open chord), so
  // b_t ≤ a_t; keep rounded tangencies from contradicting that.
  if (!always && has_a && has_b && compare_thresholds(pc_, b, a, exact_comparisons) > 0) b = a;
}

// ---- the witness begins here ----------------------------------------------------------------------

// A disk of the current pencil inside interval j, and the triangles it meets.
void Worker::record_witness(std::size_t index, std::uint32_t j, std::uint32_t count) {
  best_count = count;
  best_pencil = index;
  const double upper = events_[group_start_[j]].th.value;
  double s = 0.0;
  if (j == 0) {
    s = upper - std::max(1.0, std::fabs(upper));
  } else {
    const double lower = events_[group_start_[j - 1]].th.value;
    s = 0.5 * lower + 0.5 * upper;
  }
  // Centre m + s·h with h = (q − p)⊥ / 2.
  const double mx = 0.5 * pc_.p.x + 0.5 * pc_.q.x, my = 0.5 * pc_.p.y + 0.5 * pc_.q.y;
  best_center = {mx - s * 0.5 * pc_.by, my + s * 0.5 * pc_.bx};
  best_radius = distance(best_center, pc_.p);
  best_triangles.clear();
  for (const Candidate& c : candidates_) {
    if (c.always || (c.a_group != kNone && c.a_group < j) || (c.b_group != kNone && c.b_group >= j)) {
      best_triangles.push_back(c.triangle);
    }
  }
}

}  // namespace mwst::bundle
