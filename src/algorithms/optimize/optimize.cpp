// The weight optimiser ("--method opt" / "--optimize"): a local search for the minimum weight
// Steiner triangulation (MWST), past the paper's BRH+EFH. Moves, each applied only when it strictly
// lowers the total edge length:
//   flip      the greedy weight-reducing flips of EFH (flip.cpp);
//   remove    a Steiner vertex whose star polygon has a lighter minimum weight triangulation
//             (dynamic programming over the polygon's valid diagonals, Gilbert 1979 / Klincsek
//             1980) than its spokes;
//   relocate  a Steiner vertex to the geometric median of its neighbours (Weiszfeld's iteration),
//             which minimises the length of its spokes — the only edges that change — as far as
//             its star stays valid; a Steiner vertex on a segment slides along its subsegment line;
//   insert    a Steiner vertex at the geometric median of a small region (a triangle with its
//             neighbours, or the triangles around a triangle's corners) when the star from it is
//             lighter than the region's interior edges. Such regions are where long edges stack up
//             over a small area — the k-bundles of Boyacı, Erten and Üngör — and a point there
//             replaces k long edges by short spokes (their lemma: bundle-free meshes are light).
// Rounds repeat until a round gains less than a relative threshold. Before the rounds, a domain
// that is one polygon without interior vertices (a simple polygon's CDT) is replaced by its exact
// minimum weight triangulation. After them come kicks, moves that first raise the weight and are
// kept only if a local re-optimisation brings it below where it was (an iterated local search):
//   kick insert    a free Steiner vertex at the centroid of each triangle (heaviest first), then
//                  weight-reducing flips around it alternating with moving it to the geometric
//                  median of its neighbours;
//   segment insert a Steiner vertex on a subsegment at the foot of the perpendicular from the
//                  opposite corner, then flips and slides along the segment;
//   kick remove    a free Steiner vertex whose star's MWT is heavier than its spokes, followed by
//                  flips around the hole.
//   pair kick      (opt-in) two free Steiner vertices at the thirds of an interior edge, polished
//                  together; cluster polish (opt-in): a kick that does not pay alone is polished
//                  again with its free Steiner neighbours (a joint relocation of the cluster).
// Kicks and rounds alternate while kicks pay, within a deterministic budget of trials. Then, when
// perturbation_trials > 0, an iterated local search: 1–3 Steiner points scattered near a triangle
// drawn with probability proportional to its perimeter (seeded mt19937_64), the local search
// around them, kept only if the total weight drops. Everything is sequential and ordered by ids,
// by weight or by the seeded generator, so results are deterministic.
// Exact polish (opt-in, OptimizeOptions::exact_polish): flips only reach a local minimum, and the
// exact minimum weight triangulation of the same vertices (exact_mwt, mwt.hpp: diamond test of
// Drysdale–McElfresh–Snoeyink, LMT-skeleton, polygon DP) is often lighter; when it is solved and
// lighter it replaces the triangulation, the search runs again from it, and this repeats while the
// weight drops; a second search from the MWT of the starting mesh competes with the first.
// Its limits are sizes (vertices, candidate edges, crossing pairs), never seconds.
#include "mwst/algorithms/optimize.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numeric>
#include <random>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/mwt.hpp"
#include "support/time_budget.hpp"

namespace mwst {

namespace {

// ---- minimum weight triangulation of a simple polygon --------------------------------------------

// Do the closed segments pq and rs intersect (exactly)?
bool segments_intersect(const Point& p, const Point& q, const Point& r, const Point& s) {
  const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s);
  const int o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  auto on_segment = [](const Point& a, const Point& b, const Point& x) {
    return std::min(a.x, b.x) <= x.x && x.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= x.y &&
           x.y <= std::max(a.y, b.y);
  };
  if (o1 == 0 && on_segment(p, q, r)) return true;
  if (o2 == 0 && on_segment(p, q, s)) return true;
  if (o3 == 0 && on_segment(r, s, p)) return true;
  if (o4 == 0 && on_segment(r, s, q)) return true;
  return false;
}

// Is the segment from polygon vertex i to vertex j inside the polygon near i (O'Rourke's InCone,
// strict)?
bool in_cone(const std::vector<Point>& P, std::size_t i, std::size_t j) {
  const std::size_t d = P.size();
  const Point& prev = P[(i + d - 1) % d];
  const Point& cur = P[i];
  const Point& next = P[(i + 1) % d];
  const Point& target = P[j];
  if (orient2d(prev, cur, next) >= 0) {  // convex (or straight) corner
    return orient2d(cur, target, prev) > 0 && orient2d(target, cur, next) > 0;
  }
  return !(orient2d(cur, target, next) >= 0 && orient2d(target, cur, prev) >= 0);
}

}  // namespace

bool is_strictly_convex(const std::vector<Point>& P) {
  const std::size_t d = P.size();
  if (d < 3) return false;
  // Every corner turns left, and the fan from P[0] turns left throughout (so the boundary winds
  // once: a simple convex polygon).
  for (std::size_t i = 0; i < d; ++i) {
    if (orient2d(P[(i + d - 1) % d], P[i], P[(i + 1) % d]) <= 0) return false;
  }
  for (std::size_t i = 1; i + 1 < d; ++i) {
    if (orient2d(P[0], P[i], P[i + 1]) <= 0) return false;
  }
  return true;
}

double polygon_mwt(const std::vector<Point>& P, std::vector<std::array<std::uint32_t, 3>>* triangles) {
  const std::size_t d = P.size();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (d < 3) return kInf;
  // Scratch kept between calls (the optimiser calls this for every small region it tries, and
  // three allocations per call were a sizeable part of its time).
  thread_local std::vector<char> valid;
  thread_local std::vector<double> W, length;
  thread_local std::vector<std::uint32_t> choice;
  // valid[i][j]: the chord ij is a polygon edge or a diagonal lying inside the polygon. In a
  // strictly convex polygon every chord is (O(d) test instead of O(d³)).
  valid.assign(d * d, 0);
  for (std::size_t i = 0; i < d; ++i) {
    valid[i * d + (i + 1) % d] = valid[((i + 1) % d) * d + i] = 1;
  }
  const bool convex = is_strictly_convex(P);
  if (convex) std::fill(valid.begin(), valid.end(), 1);
  for (std::size_t i = 0; i < d && !convex; ++i) {
    for (std::size_t j = i + 2; j < d; ++j) {
      if (i == 0 && j == d - 1) continue;
      bool ok = in_cone(P, i, j) && in_cone(P, j, i);
      for (std::size_t k = 0; ok && k < d; ++k) {
        const std::size_t k1 = (k + 1) % d;
        if (k == i || k == j || k1 == i || k1 == j) continue;
        if (segments_intersect(P[i], P[j], P[k], P[k1])) ok = false;
      }
      // A diagonal through another vertex touches it: caught above only if that vertex's edges
      // are tested, which they are (every edge not incident to i or j).
      valid[i * d + j] = valid[j * d + i] = ok ? 1 : 0;
    }
  }
  // W[i][j]: lightest triangulation of the sub-polygon i..j (diagonal weights only, chord ij
  // excluded); choice[i][j] the apex k of the triangle on chord ij.
  W.assign(d * d, kInf);
  choice.assign(d * d, 0);
  for (std::size_t i = 0; i + 1 < d; ++i) W[i * d + i + 1] = 0.0;
  // length[i][j] (i < j): the weight chord ij adds, 0 for a polygon edge; computed once per chord
  // rather than once per triangle of the recurrence that uses it.
  length.resize(d * d);
  for (std::size_t i = 0; i < d; ++i) {
    for (std::size_t j = i + 1; j < d; ++j) {
      length[i * d + j] = (j == i + 1 || (i == 0 && j == d - 1) || !valid[i * d + j]) ? 0.0 : distance(P[i], P[j]);
    }
  }
  auto chord = [&](std::size_t i, std::size_t j) { return length[i * d + j]; };
  for (std::size_t gap = 2; gap < d; ++gap) {
    for (std::size_t i = 0; i + gap < d; ++i) {
      const std::size_t j = i + gap;
      if (!valid[i * d + j]) continue;
      double best = kInf;
      std::uint32_t best_k = 0;
      for (std::size_t k = i + 1; k < j; ++k) {
        if (!valid[i * d + k] || !valid[k * d + j]) continue;
        if (W[i * d + k] == kInf || W[k * d + j] == kInf) continue;
        if (!convex && orient2d(P[i], P[k], P[j]) <= 0) continue;
        const double w = W[i * d + k] + W[k * d + j] + chord(i, k) + chord(k, j);
        if (w < best) {
          best = w;
          best_k = static_cast<std::uint32_t>(k);
        }
      }
      W[i * d + j] = best;
      choice[i * d + j] = best_k;
    }
  }
  const double total = W[0 * d + d - 1];
  if (total == kInf || !triangles) return total;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, d - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    const std::uint32_t k = choice[i * d + j];
    triangles->push_back({static_cast<std::uint32_t>(i), k, static_cast<std::uint32_t>(j)});
    stack.emplace_back(i, k);
    stack.emplace_back(k, j);
  }
  return total;
}

namespace {

// A closed polygonal region of the mesh (a topological disk of live triangles) about to be
// re-triangulated: its boundary cycle counter-clockwise and the handles outside each boundary edge.
// True if a triangulation `tris` (corner indices into a polygon of `ids.size()` corners whose edge
// i → i+1 is a subsegment iff edge_is_segment(i)) has a triangle cornered at a Steiner point on a
// segment with both of its sides there being the polygon's subsegments. The two subsegments are
// straight in truth (the rounded point only looks convex or reflex), so that triangle would be a
// sliver lying along the segment, with its third side on the segment too: refused everywhere the
// optimiser retriangulates a polygon (the same rule as flip.cpp's flippable).
template <class EdgeIsSegment>
bool spans_straight_angle(const Mesh& m, const std::vector<VertexId>& ids, EdgeIsSegment edge_is_segment,
                          const std::vector<std::array<std::uint32_t, 3>>& tris) {
  const std::size_t d = ids.size();
  for (const auto& tri : tris) {
    for (unsigned k = 0; k < 3; ++k) {
      const std::size_t j = tri[k], a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
      const std::size_t before = (j + d - 1) % d, after = (j + 1) % d;
      const bool both_sides_on_boundary = (a == before && b == after) || (a == after && b == before);
      if (both_sides_on_boundary && is_straight_corner(m, ids[j], edge_is_segment(before), edge_is_segment(j))) {
        return true;
      }
    }
  }
  return false;
}

struct Region {
  std::vector<TriangleId> triangles;
  std::vector<VertexId> boundary;  // counter-clockwise
  std::vector<Handle> outer;       // outer[i]: the handle across boundary edge i→i+1, outside
  std::vector<char> segment;       // boundary edge i is a subsegment
  std::vector<std::int32_t> marker;
  std::uint8_t outside_flag = 0;   // kOutside if the region is outside the domain
};

// Replaces the region's triangles by `tris` (vertex triples, counter-clockwise, covering the same
// polygon, using only boundary vertices and possibly one new vertex), reusing slots.
// `flags`, when given, holds each new triangle's flag (kOutside or 0) instead of r.outside_flag.
void replace_region(Mesh& m, const Region& r, const std::vector<std::array<VertexId, 3>>& tris,
                    const std::vector<std::uint8_t>* flags = nullptr) {
  // (In a trial the slots and their outer neighbours are saved first: written directly below.)
  for (const TriangleId t : r.triangles) m.save_triangle(t);
  for (const Handle o : r.outer) m.save_triangle(o >> 2);
  std::vector<TriangleId> slots = r.triangles;
  while (slots.size() < tris.size()) slots.push_back(m.new_triangle());
  for (std::size_t i = tris.size(); i < slots.size(); ++i) m.kill_triangle(slots[i]);
  slots.resize(tris.size());
  auto key = [](VertexId u, VertexId v) { return (static_cast<std::uint64_t>(u) << 32) | v; };
  std::unordered_map<std::uint64_t, std::size_t> boundary_index;
  for (std::size_t i = 0; i < r.boundary.size(); ++i) {
    boundary_index.emplace(key(r.boundary[i], r.boundary[(i + 1) % r.boundary.size()]), i);
  }
  for (std::size_t i = 0; i < tris.size(); ++i) {
    m.triangles[slots[i]].v = tris[i];
    m.flags[slots[i]] = flags ? (*flags)[i] : r.outside_flag;
  }
  std::unordered_map<std::uint64_t, Handle> open;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = slots[i];
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId u = m.org(h), v = m.dest(h);
      const auto b = boundary_index.find(key(u, v));
      if (b != boundary_index.end()) {
        const Handle o = r.outer[b->second];
        m.triangles[t].n[e] = o;
        m.triangles[o >> 2].n[o & 3] = h;
        if (r.segment[b->second]) m.set_segment(h, r.marker[b->second]);
        continue;
      }
      const auto twin = open.find(key(v, u));
      if (twin != open.end()) {
        m.triangles[t].n[e] = twin->second;
        m.triangles[twin->second >> 2].n[twin->second & 3] = h;
        open.erase(twin);
      } else {
        open.emplace(key(u, v), h);
      }
    }
  }
  if (!open.empty()) throw InternalError("optimize: re-triangulated region does not close");
}

// The star of vertex v (h has org v): its neighbours counter-clockwise and its triangles.
bool star_of(const Mesh& m, Handle h, Region& r) {
  r.triangles.clear();
  r.boundary.clear();
  r.outer.clear();
  r.segment.clear();
  r.marker.clear();
  const Handle start = h;
  for (std::size_t guard = 0; guard < 4096; ++guard) {
    const TriangleId t = h >> 2;
    if (m.is_ghost(t) || m.is_dead(t)) return false;
    r.triangles.push_back(t);
    r.boundary.push_back(m.dest(h));
    const Handle opposite = Mesh::lnext(h);  // dest → apex, the star polygon's edge
    r.outer.push_back(m.sym(opposite));
    r.segment.push_back(m.is_segment(opposite) ? 1 : 0);
    r.marker.push_back(m.marker(opposite));
    h = m.onext(h);
    if (h == start) return true;
  }
  return false;
}

double spoke_sum(const Point& p, const std::vector<Point>& nb) {
  double s = 0.0;
  for (const Point& q : nb) s += distance(p, q);
  return s;
}

// Weiszfeld's iteration for the geometric median of `nb`, from `start`.
Point geometric_median(Point p, const std::vector<Point>& nb) {
  for (int it = 0; it < 64; ++it) {
    double wx = 0.0, wy = 0.0, w = 0.0;
    for (const Point& q : nb) {
      const double dd = distance(p, q);
      if (dd == 0.0) return p;  // at a neighbour: stop (the caller rejects it)
      wx += q.x / dd;
      wy += q.y / dd;
      w += 1.0 / dd;
    }
    const Point next{wx / w, wy / w};
    const double step = distance(next, p);
    p = next;
    if (!(step > 1e-15 * (std::fabs(p.x) + std::fabs(p.y) + 1e-300))) break;
  }
  return p;
}

// Is p strictly inside the kernel of the closed polygon (all fan triangles counter-clockwise), and
// clear of every polygon edge's line by a margin far above the rounding of constructed points?
// (A free Steiner point a few ulps from a segment would be taken for a point on it by any
// tolerant checker, and makes needle triangles.)
bool in_kernel(const Point& p, const std::vector<Point>& polygon) {
  const std::size_t d = polygon.size();
  constexpr double kMargin = 1e-9;  // times the coordinate magnitude
  for (std::size_t i = 0; i < d; ++i) {
    const Point& a = polygon[i];
    const Point& b = polygon[(i + 1) % d];
    if (orient2d(p, a, b) <= 0) return false;
    const double scale = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(b.x), std::fabs(b.y), std::fabs(p.x),
                                   std::fabs(p.y)});
    const double dx = b.x - a.x, dy = b.y - a.y;
    if (dx * (p.y - a.y) - dy * (p.x - a.x) <= kMargin * scale * std::hypot(dx, dy)) return false;
  }
  return true;
}

// The shortest edge of the domain (OptimizeOptions::min_separation's default scale).
double shortest_domain_edge(const Mesh& m) {
  double shortest = std::numeric_limits<double>::infinity();
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    const auto& v = m.triangles[t].v;
    for (unsigned k = 0; k < 3; ++k) shortest = std::min(shortest, distance(m.points[v[k]], m.points[v[(k + 1) % 3]]));
  }
  return std::isfinite(shortest) ? shortest : 0.0;
}

class Optimizer {
 public:
  Optimizer(Mesh& m, const OptimizeOptions& o, OptimizeStats& s, std::chrono::steady_clock::time_point deadline)
      : m_(m), opt_(o), stats_(s),
        first_free_(static_cast<VertexId>(std::max<std::size_t>(m.input_vertex_count, o.fixed_vertices))),
        separation_(o.min_separation >= 0.0 ? o.min_separation : default_min_separation(m)),
        deadline_(deadline) {}

  // With polish_start, first replaces the mesh by the MWT of its vertices, and returns false
  // without searching if that was not kept (not solved, too large or not lighter).
  bool run(bool polish_start) {
    const double start_weight = measure(m_).weight_total;
    stats_.weight_before = start_weight;
    if (polish_start && !exact_polish_step()) return false;
    if (!out_of_time()) whole_domain_mwt();
    local_search();
    // Kicks: trial insertions and removals, each followed by a local re-optimisation and kept only
    // if the total weight drops; then the local search again, while the kicks pay.
    kicks_and_search();
    perturbation_search();
    if (opt_.exact_polish) exact_polish();
    compact(m_);
    stats_.weight_after = measure(m_).weight_total;
    return true;
  }

 private:
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
  // quadratic, 42 % of opt's time on a 54 000-triangle mesh). OptimizeOptions::undo_trials_by_copy
  // (testing) copies instead.
  void begin_trial() {
    if (opt_.undo_trials_by_copy) {
      backup_ = m_;
    } else {
      m_.begin_trial();
    }
  }
  void keep_trial() {
    if (!opt_.undo_trials_by_copy) m_.commit_trial();
  }
  void undo_trial() {
    if (opt_.undo_trials_by_copy) {
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

  void kicks_and_search() {
    for (std::size_t pass = 0; pass < opt_.kick_passes && !out_of_time(); ++pass) {
      const std::size_t accepted =
          kick_insertions() + kick_edge_splits() + kick_segment_insertions() + kick_removals() +
          kick_segment_removals() + kick_pairs();
      if (accepted == 0) break;
      local_search();
    }
  }

  // Iterated local search: each trial scatters one to three free Steiner points over a domain
  // triangle drawn at random and its surroundings (the triangle scaled 2.5 times about its
  // centroid), runs the local search (flips, removals, relocations, region insertions) around
  // them, and keeps the result only if the total weight is lower than before the trial;
  // otherwise the mesh is restored. A final unfocused search follows the trials. A perturbation of several points reaches basins that single kicks (one point, one
  // local polish) do not. The random numbers come from a seeded std::mt19937_64 mapped to
  // doubles by bit arithmetic (no std distribution, whose output is library-defined), so
  // results are the same on every platform and run; the budget counts trials, not seconds.
  void perturbation_search() {
    if (opt_.perturbation_trials == 0) return;
    std::mt19937_64 rng(opt_.perturbation_seed);
    const auto unit = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    double weight = measure(m_).weight_total;
    std::vector<TriangleId> domain;
    Mesh saved;
    for (std::size_t trial = 0; trial < opt_.perturbation_trials && !out_of_time(); ++trial) {
      // A triangle drawn with probability proportional to its perimeter (long edges are where
      // weight can be saved).
      domain.clear();
      cumulative_.clear();
      double total = 0.0;
      for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
        if (!m_.in_domain(t)) continue;
        const Triangle& T = m_.triangles[t];
        total += distance(m_.points[T.v[0]], m_.points[T.v[1]]) + distance(m_.points[T.v[1]], m_.points[T.v[2]]) +
                 distance(m_.points[T.v[2]], m_.points[T.v[0]]);
        domain.push_back(t);
        cumulative_.push_back(total);
      }
      if (domain.empty()) return;
      const auto pick = std::upper_bound(cumulative_.begin(), cumulative_.end(), unit() * total);
      const TriangleId t =
          domain[std::min<std::size_t>(static_cast<std::size_t>(pick - cumulative_.begin()), domain.size() - 1)];
      const Triangle& T = m_.triangles[t];
      const Point a = m_.points[T.v[0]], b = m_.points[T.v[1]], c = m_.points[T.v[2]];
      const Point centroid{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
      const std::size_t count = std::min<std::size_t>(1 + static_cast<std::size_t>(rng() % 3), steiner_room());
      if (count == 0) continue;
      saved = m_;
      double ignored = 0.0;
      std::size_t inserted = 0;
      for (std::size_t i = 0; i < count; ++i) {
        double r1 = unit(), r2 = unit();
        if (r1 + r2 > 1.0) {
          r1 = 1.0 - r1;
          r2 = 1.0 - r2;
        }
        const Point in_t{a.x + r1 * (b.x - a.x) + r2 * (c.x - a.x), a.y + r1 * (b.y - a.y) + r2 * (c.y - a.y)};
        const Point q{snap_to_range(centroid.x + 2.5 * (in_t.x - centroid.x)),
                      snap_to_range(centroid.y + 2.5 * (in_t.y - centroid.y))};
        if (insert_free_point(q, ignored) != kInfinite) ++inserted;
      }
      if (inserted == 0) {
        m_ = std::move(saved);
        continue;
      }
      // The search visits only vertices, triangles and edges near the perturbation (a box three
      // times the size of the scattered region).
      const double reach = 3.0 * 2.5 *
                           std::max({std::fabs(a.x - centroid.x), std::fabs(b.x - centroid.x), std::fabs(c.x - centroid.x),
                                     std::fabs(a.y - centroid.y), std::fabs(b.y - centroid.y), std::fabs(c.y - centroid.y)});
      focus_lo_ = {centroid.x - reach, centroid.y - reach};
      focus_hi_ = {centroid.x + reach, centroid.y + reach};
      focused_ = opt_.perturbation_focus;
      local_search();
      focused_ = false;
      const double now = measure(m_).weight_total;
      if (now < weight * (1.0 - opt_.kick_min_relative_gain)) {
        weight = now;
        ++stats_.perturbations;
        compact(m_);
      } else {
        m_ = std::move(saved);
      }
    }
    local_search();  // unfocused: what the focused searches left elsewhere
  }

  bool in_focus(const Point& p) const {
    return !focused_ || (focus_lo_.x <= p.x && p.x <= focus_hi_.x && focus_lo_.y <= p.y && p.y <= focus_hi_.y);
  }

  // The exact polish: replace the triangulation by the MWT of its own vertices with its segments
  // (same vertices, segments and markers, so the domain and the input vertices are unchanged; it
  // excludes straight-angle slivers along segments, as EFH does) when it is solved and lighter by
  // more than min_relative_gain, then the search and kicks again — relocations, removals and
  // insertions now start from the lighter triangulation, and their local minimum is no heavier.
  // Every step lowers the weight strictly, so the polished mesh is never heavier than before.
  void exact_polish() {
    for (std::size_t round = 0; round < opt_.exact_polish_rounds && !out_of_time(); ++round) {
      if (!exact_polish_step()) return;
      local_search();
      kicks_and_search();
    }
  }

  // One exact MWT of the mesh's vertices within the size limits; true if it was kept (lighter).
  bool exact_polish_step() {
    compact(m_);
    if (m_.points.size() > opt_.exact_polish_max_vertices) return false;
    ++stats_.exact_polish_tries;
    if (!exact_polish_mesh(m_, opt_)) return false;
    ++stats_.exact_polishes;
    return true;
  }

  void local_search() {
    double weight = measure(m_).weight_total;
    for (std::size_t round = 0; round < opt_.max_rounds && !out_of_time(); ++round) {
      ++stats_.rounds;
      focused_flips();
      rebuild_vertex_handles();
      const std::size_t n = m_.points.size();
      for (VertexId v = first_free_; v < n; ++v) {
        if ((v & 1023u) == 0 && out_of_time()) break;
        const VertexKind kind = m_.vertex_kind[v];
        if (kind != VertexKind::kSteiner && kind != VertexKind::kSteinerOnSegment) continue;
        if (!in_focus(m_.points[v])) continue;
        // Decide by the mesh, not the label: a vertex with subsegment spokes lies on a segment
        // (a free Steiner point can land exactly on one).
        const int on_segment = segment_spokes(v);
        if (on_segment < 0) continue;
        if (on_segment == 0) {
          if (!(opt_.remove && try_remove(v)) && opt_.relocate) try_relocate(v);
        } else if (opt_.relocate) {
          try_slide(v);
        }
      }
      try_insertions();
      const double now = measure(m_).weight_total;
      const double gain = weight - now;
      weight = now;
      if (!(gain > opt_.min_relative_gain * now)) break;
    }
    if (!out_of_time()) focused_flips();
  }

  // EFH's flips to a local minimum; in a focused search (perturbation_search) only from the edges
  // of the triangles in focus (and the edges those flips expose), which is what a local
  // perturbation can change.
  void focused_flips() {
    if (!focused_) {
      stats_.flips += flip_to_local_minimum(m_, opt_.max_area).flips;
      return;
    }
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (!m_.in_domain(t) || !in_focus(m_.points[m_.triangles[t].v[0]])) continue;
      for (unsigned e = 0; e < 3; ++e) flip_stack_.push_back(make_handle(t, e));
    }
    local_flips();
  }

  // ---- kicks: moves that first raise the weight, then re-optimise locally ---------------------

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

  // Weight-reducing flips from the edges on `flip_stack_` (and the edges they expose); returns the
  // change in weight (≤ 0). Each flip lowers the weight strictly (exact test), so it terminates.
  double local_flips() {
    double delta = 0.0;
    while (!flip_stack_.empty()) {
      const Handle h = flip_stack_.back();
      flip_stack_.pop_back();
      if (m_.is_dead(h >> 2) || !is_weight_reducing_flip(m_, h, opt_.max_area)) continue;
      const double before = edge_length(h);
      const Handle diag = m_.flip(h);
      delta += edge_length(diag) - before;
      const Handle other = m_.sym(diag);
      for (const Handle g : {Mesh::lnext(diag), Mesh::lprev(diag), Mesh::lnext(other), Mesh::lprev(other)}) {
        flip_stack_.push_back(g);
      }
    }
    return delta;
  }

  // A handle with org v, found by walking from `near`.
  Handle handle_near(VertexId v, Handle near) const {
    const Location loc = m_.locate(m_.points[v], near);
    if (loc.kind != Location::Kind::kOnVertex || m_.org(loc.handle) != v) return kNone;
    return loc.handle;
  }

  // Pushes v's spokes and the edges of its star polygon onto flip_stack_.
  void push_star(Handle h) {
    const Handle start = h;
    std::size_t guard = 0;
    do {
      flip_stack_.push_back(h);
      flip_stack_.push_back(Mesh::lnext(h));
      h = m_.onext(h);
    } while (h != start && ++guard < 4096);
  }

  // Polishes a new free Steiner vertex v: flips around it and moves it to the geometric median of
  // its neighbours, alternately. Returns the weight change.
  double polish_vertex(VertexId v, Handle near) {
    double delta = 0.0;
    for (int it = 0; it < 4; ++it) {
      Handle h = handle_near(v, near);
      if (h == kNone) return delta;
      push_star(h);
      delta += local_flips();
      h = handle_near(v, h);
      if (h == kNone || !star_of(m_, h, region_) || !star_in_domain(region_)) return delta;
      polygon_.clear();
      for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
      const Point p = m_.points[v];
      const double before = spoke_sum(p, polygon_);
      Point q = geometric_median(p, polygon_);
      bool moved = false;
      for (int halving = 0; halving < 30 && !moved; ++halving) {
        q = {snap_to_range(q.x), snap_to_range(q.y)};
        if (in_supported_range(q)) {
          const double after = spoke_sum(q, polygon_);
          if (after < before && in_kernel(q, polygon_) && separated(q, region_.outer) && star_within_area(q, polygon_)) {
            m_.save_vertex(v);
            m_.points[v] = q;
            delta += after - before;
            moved = true;
            break;
          }
        }
        q = {0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
        if (q == p) break;
      }
      near = h;
      if (!moved) {
        push_star(h);
        delta += local_flips();
        break;
      }
    }
    return delta;
  }

  // Tries a free Steiner vertex at p inside domain triangle t: split t, polish, keep if lighter.
  bool kick_insert(TriangleId t, const Point& p, double weight) {
    const Triangle& T = m_.triangles[t];
    // Copies: add_vertex below may reallocate m_.points.
    const Point a = m_.points[T.v[0]];
    const Point b = m_.points[T.v[1]];
    const Point c = m_.points[T.v[2]];
    if (!in_supported_range(p) || orient2d(a, b, p) <= 0 || orient2d(b, c, p) <= 0 || orient2d(c, a, p) <= 0 ||
        !separated_in_triangle(p, t)) {
      return false;
    }
    if (steiner_room() == 0) return false;
    begin_trial();
    const VertexId v = m_.add_vertex(p, VertexKind::kSteiner, 0);
    double delta = distance(p, a) + distance(p, b) + distance(p, c);
    const auto opposite = m_.split_triangle(t, v);
    delta += polish_vertex(v, opposite[0]);
    if (!(delta < -opt_.kick_min_relative_gain * weight)) delta += polish_neighbours(v);
    if (delta < -opt_.kick_min_relative_gain * weight) {
      keep_trial();
      ++stats_.kick_insertions;
      return true;
    }
    undo_trial();
    return false;
  }

  std::size_t kick_insertions() {
    const double weight = measure(m_).weight_total;
    // Candidates: the centroids of the domain triangles, heaviest (longest perimeter) first.
    std::vector<std::pair<double, TriangleId>> order;
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (!m_.in_domain(t)) continue;
      const Triangle& T = m_.triangles[t];
      const double perimeter = distance(m_.points[T.v[0]], m_.points[T.v[1]]) +
                               distance(m_.points[T.v[1]], m_.points[T.v[2]]) +
                               distance(m_.points[T.v[2]], m_.points[T.v[0]]);
      order.emplace_back(-perimeter, t);
    }
    std::sort(order.begin(), order.end());
    std::vector<Point> candidates;
    for (const auto& [key, t] : order) {
      (void)key;
      const Triangle& T = m_.triangles[t];
      const Point& a = m_.points[T.v[0]];
      const Point& b = m_.points[T.v[1]];
      const Point& c = m_.points[T.v[2]];
      candidates.push_back({(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0});
    }
    std::size_t accepted = 0;
    Handle near = m_.any_live_handle();
    for (const Point& p : candidates) {
      if (!may_kick()) break;
      const Location loc = m_.locate(p, near);
      if (loc.kind != Location::Kind::kInTriangle) continue;
      const TriangleId t = loc.handle >> 2;
      near = loc.handle;
      if (!m_.in_domain(t)) continue;
      ++kick_trials_;
      if (kick_insert(t, p, weight)) ++accepted;
      near = m_.any_live_handle();
    }
    return accepted;
  }

  // The interior non-segment edges of the domain, longest first (ties by ids): (−length, org, dest).
  std::vector<std::tuple<double, VertexId, VertexId>> interior_edges_longest_first() const {
    std::vector<std::tuple<double, VertexId, VertexId>> edges;
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (!m_.in_domain(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId u = m_.sym(h) >> 2;
        if (m_.is_segment(h) || !m_.in_domain(u) || u < t) continue;
        edges.emplace_back(-edge_length(h), m_.org(h), m_.dest(h));
      }
    }
    std::sort(edges.begin(), edges.end());
    return edges;
  }

  // Tries a free Steiner vertex at the midpoint of each interior edge (longest first): the edge
  // and its two triangles split in four (or, when the rounded midpoint misses the edge, the
  // triangle holding it in three), then polished; kept only if the weight drops.
  std::size_t kick_edge_splits() {
    const double weight = measure(m_).weight_total;
    const std::vector<std::tuple<double, VertexId, VertexId>> edges = interior_edges_longest_first();
    std::size_t accepted = 0;
    for (const auto& [key, ia, ib] : edges) {
      (void)key;
      if (!may_kick()) break;
      Handle h = handle_near(ia, m_.any_live_handle());
      if (h == kNone) continue;
      {
        const Handle first = h;
        std::size_t guard = 0;
        while (m_.dest(h) != ib && ++guard < 4096) {
          h = m_.onext(h);
          if (h == first) break;
        }
      }
      if (m_.dest(h) != ib || m_.is_segment(h) || !m_.in_domain(h >> 2) || !m_.in_domain(m_.sym(h) >> 2)) continue;
      const Point a = m_.points[ia], b = m_.points[ib];
      const Point c = m_.points[m_.apex(h)], d = m_.points[m_.apex(m_.sym(h))];
      const Point q{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
      if (!in_supported_range(q)) continue;
      const int side = orient2d(a, b, q);
      // The triangle that must hold q strictly inside (or both, on the edge).
      if (side >= 0 && (orient2d(b, c, q) <= 0 || orient2d(c, a, q) <= 0)) continue;
      if (side <= 0 && (orient2d(a, d, q) <= 0 || orient2d(d, b, q) <= 0)) continue;
      if (!separated_at_edge(q, h)) continue;
      if (steiner_room() == 0) break;
      ++kick_trials_;
      begin_trial();
      const VertexId v = m_.add_vertex(q, VertexKind::kSteiner, 0);
      double delta = distance(q, a) + distance(q, b);
      Handle near = kNone;
      if (side == 0) {
        delta += distance(q, c) + distance(q, d) - distance(a, b);
        near = m_.split_edge(h, v)[0];
      } else if (side > 0) {
        delta += distance(q, c);
        near = m_.split_triangle(h >> 2, v)[0];
      } else {
        delta += distance(q, d);
        near = m_.split_triangle(m_.sym(h) >> 2, v)[0];
      }
      delta += polish_vertex(v, near);
      if (!(delta < -opt_.kick_min_relative_gain * weight)) delta += polish_neighbours(v);
      if (delta < -opt_.kick_min_relative_gain * weight) {
        keep_trial();
        ++stats_.kick_insertions;
        ++accepted;
      } else {
        undo_trial();
      }
    }
    return accepted;
  }

  // A handle with org u if u is a free Steiner vertex whose spokes are no subsegments and whose
  // triangles are all finite (one the relocation may move), else kNone.
  Handle free_steiner_handle(VertexId u) const {
    if (u >= m_.points.size() || m_.vertex_kind[u] != VertexKind::kSteiner) return kNone;
    const Handle h = handle_near(u, m_.any_live_handle());
    if (h == kNone) return kNone;
    Handle s = h;
    std::size_t guard = 0;
    do {
      if (m_.is_segment(s) || m_.is_ghost(s >> 2)) return kNone;
      s = m_.onext(s);
    } while (s != h && ++guard < 4096);
    return h;
  }

  // The cluster polish after a kick at v: the free Steiner neighbours of v polished (flips around
  // each, then each moved to the geometric median of its new neighbours), then v again, in two
  // sweeps — a joint relocation of the Steiner points around the kick, so that a kick that pays
  // only once its neighbours move is found. Returns the weight change (≤ 0: each step only lowers
  // the weight).
  double polish_neighbours(VertexId v) {
    double delta = 0.0;
    for (std::size_t sweep = 0; sweep < opt_.kick_neighbour_sweeps; ++sweep) {
      const Handle h = handle_near(v, m_.any_live_handle());
      if (h == kNone) break;
      neighbours_.clear();
      Handle s = h;
      std::size_t guard = 0;
      do {
        const VertexId u = m_.dest(s);
        if (u != kInfinite && m_.vertex_kind[u] == VertexKind::kSteiner) neighbours_.push_back(u);
        s = m_.onext(s);
      } while (s != h && ++guard < 4096);
      for (const VertexId u : neighbours_) {
        const Handle hu = free_steiner_handle(u);
        if (hu != kNone) delta += polish_vertex(u, hu);
      }
      const Handle hv = handle_near(v, m_.any_live_handle());
      if (hv == kNone) break;
      delta += polish_vertex(v, hv);
    }
    return delta;
  }

  // Adds a free Steiner vertex at q if q lies strictly inside a domain triangle (split 1 → 3) or
  // on an edge between two domain triangles that is no subsegment (split 2 → 4); adds the weight
  // change to `delta` and returns the vertex, or kInfinite if q is elsewhere.
  VertexId insert_free_point(const Point& q, double& delta) {
    if (!in_supported_range(q)) return kInfinite;
    const Location loc = m_.locate(q, m_.any_live_handle());
    const Handle h = loc.handle;
    if (loc.kind == Location::Kind::kInTriangle) {
      const TriangleId t = h >> 2;
      if (!m_.in_domain(t)) return kInfinite;
      const Triangle& T = m_.triangles[t];
      const Point a = m_.points[T.v[0]], b = m_.points[T.v[1]], c = m_.points[T.v[2]];
      if (orient2d(a, b, q) <= 0 || orient2d(b, c, q) <= 0 || orient2d(c, a, q) <= 0) return kInfinite;
      if (!separated_in_triangle(q, t)) return kInfinite;
      const VertexId v = m_.add_vertex(q, VertexKind::kSteiner, 0);
      delta += distance(q, a) + distance(q, b) + distance(q, c);
      m_.split_triangle(t, v);
      return v;
    }
    if (loc.kind != Location::Kind::kOnEdge) return kInfinite;
    if (m_.is_segment(h) || !m_.in_domain(h >> 2) || !m_.in_domain(m_.sym(h) >> 2)) return kInfinite;
    const Point a = m_.points[m_.org(h)], b = m_.points[m_.dest(h)];
    const Point c = m_.points[m_.apex(h)], d = m_.points[m_.apex(m_.sym(h))];
    if (!separated_at_edge(q, h)) return kInfinite;
    const VertexId v = m_.add_vertex(q, VertexKind::kSteiner, 0);
    delta += distance(q, a) + distance(q, b) + distance(q, c) + distance(q, d) - distance(a, b);
    m_.split_edge(h, v);
    return v;
  }

  // Pair kicks: two free Steiner vertices at a third and two thirds of each interior edge
  // (longest first), polished jointly (flips and geometric medians, alternately, with their
  // Steiner neighbours); kept only if the weight drops. A long edge crossing a bundle is often
  // replaced by a chain of two Steiner points where one point alone does not pay.
  std::size_t kick_pairs() {
    if (!opt_.kick_pairs) return 0;
    const double weight = measure(m_).weight_total;
    const std::vector<std::tuple<double, VertexId, VertexId>> edges = interior_edges_longest_first();
    std::size_t accepted = 0;
    for (const auto& [key, ia, ib] : edges) {
      (void)key;
      if (!may_kick()) break;
      if (m_.vertex_kind[ia] == VertexKind::kRemoved || m_.vertex_kind[ib] == VertexKind::kRemoved) continue;
      const Point a = m_.points[ia], b = m_.points[ib];
      const Point q1{a.x + (b.x - a.x) / 3.0, a.y + (b.y - a.y) / 3.0};
      const Point q2{a.x + 2.0 * (b.x - a.x) / 3.0, a.y + 2.0 * (b.y - a.y) / 3.0};
      if (steiner_room() < 2) break;
      ++kick_trials_;
      begin_trial();
      double delta = 0.0;
      const VertexId v1 = insert_free_point(q1, delta);
      const VertexId v2 = v1 == kInfinite ? kInfinite : insert_free_point(q2, delta);
      if (v2 == kInfinite) {
        undo_trial();
        continue;
      }
      for (int sweep = 0; sweep < 3; ++sweep) {
        for (const VertexId v : {v1, v2}) {
          const Handle h = handle_near(v, m_.any_live_handle());
          if (h != kNone) delta += polish_vertex(v, h);
        }
      }
      delta += polish_neighbours(v1);
      delta += polish_neighbours(v2);
      if (delta < -opt_.kick_min_relative_gain * weight) {
        keep_trial();
        stats_.kick_insertions += 2;
        ++stats_.kick_pairs;
        ++accepted;
      } else {
        undo_trial();
      }
    }
    return accepted;
  }

  // If the domain is one polygon without interior vertices (a simple polygon with its CDT), and
  // small enough for the O(d³) dynamic programme, replaces it by its exact minimum weight
  // triangulation (Gilbert 1979; Klincsek 1980): the best mesh on these vertices.
  void whole_domain_mwt() {
    std::vector<TriangleId> tris;
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (m_.in_domain(t)) tris.push_back(t);
    }
    const std::size_t corners = tris.size() + 2;  // if it is one polygon without interior vertices
    if (tris.empty() || corners > std::max(opt_.max_exact_polygon, opt_.max_exact_convex_polygon)) return;
    if (corners > opt_.max_exact_polygon) {
      // Only a convex polygon this large (its chords need no visibility test).
      if (!region_from(tris, region_)) return;
      polygon_.clear();
      for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
      if (!is_strictly_convex(polygon_)) return;
    }
    // Only the MWT: a star from one point is not what a whole polygon wants.
    if (try_region(tris, /*allow_star=*/false)) ++stats_.whole_polygon_mwt;
  }

  // Tries a Steiner vertex on each subsegment at the foot of the perpendicular from the opposite
  // domain corner, then flips and slides; kept only if the total weight drops.
  std::size_t kick_segment_insertions() {
    double weight = measure(m_).weight_total;
    struct Candidate {
      VertexId a, b;
      Point foot;
    };
    std::vector<Candidate> candidates;
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (!m_.in_domain(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (!m_.is_segment(h)) continue;
        const Point& a = m_.points[m_.org(h)];
        const Point& b = m_.points[m_.dest(h)];
        const Point& c = m_.points[m_.apex(h)];
        const double dx = b.x - a.x, dy = b.y - a.y;
        const double u = ((c.x - a.x) * dx + (c.y - a.y) * dy) / (dx * dx + dy * dy);
        if (!(u > 0.02 && u < 0.98)) continue;
        candidates.push_back({m_.org(h), m_.dest(h), Point{a.x + u * dx, a.y + u * dy}});
      }
    }
    std::size_t accepted = 0;
    for (const Candidate& cand : candidates) {
      if (!may_kick()) break;
      // The subsegment a→b, if it still exists.
      Handle h = handle_near(cand.a, m_.any_live_handle());
      if (h == kNone) continue;
      {
        const Handle first = h;
        std::size_t guard = 0;
        while (m_.dest(h) != cand.b && ++guard < 4096) {
          h = m_.onext(h);
          if (h == first) break;
        }
        if (m_.dest(h) != cand.b || !m_.is_segment(h) || !m_.in_domain(h >> 2)) continue;
      }
      const Point& a = m_.points[cand.a];
      const Point& b = m_.points[cand.b];
      const VertexId c = m_.apex(h), d = m_.apex(m_.sym(h));
      auto splits = [&](const Point& q) {
        if (!in_supported_range(q) || orient2d(a, b, q) != 0) return false;
        if (orient2d(a, q, m_.points[c]) <= 0 || orient2d(q, b, m_.points[c]) <= 0) return false;
        if (d != kInfinite && (orient2d(b, q, m_.points[d]) <= 0 || orient2d(q, a, m_.points[d]) <= 0)) return false;
        // Strictly between a and b (collinear): also catches the ghost side.
        if (!((q.x - a.x) * (b.x - a.x) + (q.y - a.y) * (b.y - a.y) > 0 &&
              (q.x - b.x) * (a.x - b.x) + (q.y - b.y) * (a.y - b.y) > 0)) {
          return false;
        }
        // Separated (on the hull, the ghost beyond ab holds nothing).
        return d == kInfinite ? separated(q, {Mesh::lnext(h), Mesh::lprev(h)}) : separated_at_edge(q, h);
      };
      Point q = cand.foot;
      bool found = false;
      for (int i = 0; i < 9 && !found; ++i) {
        const int dx = i % 3 - 1, dy = i / 3 - 1;
        Point r = cand.foot;
        if (dx) r.x = std::nextafter(r.x, dx > 0 ? std::numeric_limits<double>::infinity()
                                                 : -std::numeric_limits<double>::infinity());
        if (dy) r.y = std::nextafter(r.y, dy > 0 ? std::numeric_limits<double>::infinity()
                                                 : -std::numeric_limits<double>::infinity());
        if (splits(r)) {
          q = r;
          found = true;
        }
      }
      if (!found) continue;
      if (steiner_room() == 0) break;
      ++kick_trials_;
      begin_trial();
      const std::size_t relocations = stats_.relocations;
      const VertexId v = m_.add_vertex(q, VertexKind::kSteinerOnSegment, m_.marker(h));
      vertex_handle_.resize(m_.points.size(), kNone);
      const auto opposite = m_.split_edge(h, v);
      Handle near = opposite[0];
      for (int it = 0; it < 4; ++it) {
        const Handle hv = handle_near(v, near);
        if (hv == kNone) break;
        push_star(hv);
        local_flips();
        near = hv;
        vertex_handle_[v] = kNone;
        if (!try_slide(v)) break;
      }
      const double now = measure(m_).weight_total;
      if (now < weight * (1.0 - opt_.kick_min_relative_gain)) {
        keep_trial();
        weight = now;
        ++stats_.kick_insertions;
        ++accepted;
      } else {
        undo_trial();
        stats_.relocations = relocations;
      }
    }
    rebuild_vertex_handles();
    return accepted;
  }

  // Removes Steiner vertices on segments: v between its segment neighbours a and b goes, the two
  // subsegments merge into ab, and each side of ab is re-triangulated by its MWT, then flips
  // around; kept only if the weight drops. (Not on the convex hull: the ghost triangles there
  // would need merging too.)
  std::size_t kick_segment_removals() {
    const double weight = measure(m_).weight_total;
    std::size_t accepted = 0;
    std::vector<std::array<VertexId, 3>> tris;
    std::vector<std::uint8_t> flags;
    for (VertexId v = first_free_; v < m_.points.size(); ++v) {
      if (m_.vertex_kind[v] != VertexKind::kSteinerOnSegment && m_.vertex_kind[v] != VertexKind::kSteiner) continue;
      if (!may_kick()) break;
      const Handle h = handle_near(v, m_.any_live_handle());
      if (h == kNone || !star_of(m_, h, region_)) continue;  // star_of refuses ghosts
      const std::size_t d = region_.boundary.size();
      // The segment spokes, in star order: region_.boundary[i] is the i-th neighbour and
      // region_.triangles[i] the triangle between spokes i and i+1.
      std::size_t ends[2] = {0, 0};
      int count = 0;
      std::int32_t marker = 0;
      {
        Handle s = h;
        for (std::size_t i = 0; i < d; ++i) {
          if (m_.dest(s) != region_.boundary[i]) throw InternalError("optimize: star order");
          if (m_.is_segment(s)) {
            if (count < 2) ends[count] = i;
            ++count;
            marker = m_.marker(s);
          }
          s = m_.onext(s);
        }
      }
      if (count != 2) continue;
      const VertexId a = region_.boundary[ends[0]], b = region_.boundary[ends[1]];
      if (orient2d(m_.points[a], m_.points[b], m_.points[v]) != 0) continue;
      // The two sides: neighbours ends[0] .. ends[1] and ends[1] .. ends[0] (cyclically).
      double delta = 0.0;
      tris.clear();
      flags.clear();
      bool ok = true;
      for (int side = 0; side < 2 && ok; ++side) {
        const std::size_t from = ends[side], to = ends[1 - side];
        polygon_.clear();
        std::vector<VertexId> ids;
        for (std::size_t i = from;; i = (i + 1) % d) {
          polygon_.push_back(m_.points[region_.boundary[i]]);
          ids.push_back(region_.boundary[i]);
          if (i == to) break;
        }
        const TriangleId first = region_.triangles[from];
        const bool inside = m_.in_domain(first);
        const std::uint8_t flag = m_.flags[first] & kOutside;
        for (std::size_t i = from; i != to; i = (i + 1) % d) {
          if (m_.in_domain(region_.triangles[i]) != inside) ok = false;
        }
        if (!ok) break;
        if (polygon_.size() == 2) {
          ok = false;  // cannot happen for a valid star (each side holds a triangle)
          break;
        }
        local_.clear();
        const double diagonals = polygon_.size() == 3 ? 0.0 : polygon_mwt(polygon_, &local_);
        if (polygon_.size() == 3) local_.push_back({0, 1, 2});
        // The chain's edges are the star's boundary edges from `from`; its closing edge is the
        // merged segment a–b.
        const auto chain_edge_is_segment = [&](std::size_t i) {
          return i + 1 == ids.size() ? true : region_.segment[(from + i) % d] != 0;
        };
        if (!std::isfinite(diagonals) || spans_straight_angle(m_, ids, chain_edge_is_segment, local_) ||
            (inside && !within_area(polygon_, local_))) {
          ok = false;
          break;
        }
        if (inside) {
          double spokes = 0.0;
          for (std::size_t i = 1; i + 1 < ids.size(); ++i) spokes += distance(m_.points[v], m_.points[ids[i]]);
          delta += diagonals - spokes;
        }
        for (const auto& tri : local_) {
          tris.push_back({ids[tri[0]], ids[tri[1]], ids[tri[2]]});
          flags.push_back(flag);
        }
      }
      if (!ok) continue;
      ++kick_trials_;
      begin_trial();
      replace_region(m_, region_, tris, &flags);
      // The merged segment ab.
      Handle ab = handle_near(a, m_.any_live_handle());
      {
        const Handle first = ab;
        std::size_t guard = 0;
        while (ab != kNone && m_.dest(ab) != b && ++guard < 4096) {
          ab = m_.onext(ab);
          if (ab == first) break;
        }
      }
      if (ab == kNone || m_.dest(ab) != b) {
        undo_trial();
        continue;
      }
      m_.set_segment(ab, marker);
      for (const TriangleId t : region_.triangles) {
        if (m_.is_dead(t)) continue;
        for (unsigned e = 0; e < 3; ++e) flip_stack_.push_back(make_handle(t, e));
      }
      delta += local_flips();
      if (delta < -opt_.kick_min_relative_gain * weight) {
        keep_trial();
        m_.vertex_kind[v] = VertexKind::kRemoved;
        ++stats_.kick_removals;
        ++accepted;
      } else {
        undo_trial();
      }
    }
    rebuild_vertex_handles();
    return accepted;
  }

  // Removes free Steiner vertices whose removal (star re-triangulated by its MWT) followed by
  // flips around the hole lowers the weight, even when the MWT alone is heavier than the spokes.
  std::size_t kick_removals() {
    const double weight = measure(m_).weight_total;
    std::size_t accepted = 0;
    for (VertexId v = first_free_; v < m_.points.size(); ++v) {
      if (m_.vertex_kind[v] != VertexKind::kSteiner) continue;
      if (!may_kick()) break;
      const Handle h = handle_near(v, m_.any_live_handle());
      if (h == kNone || !star_of(m_, h, region_) || !star_in_domain(region_)) continue;
      bool on_segment = false;
      {
        Handle s = h;
        std::size_t guard = 0;
        do {
          on_segment = on_segment || m_.is_segment(s);
          s = m_.onext(s);
        } while (s != h && ++guard < 4096);
      }
      if (on_segment) continue;
      polygon_.clear();
      for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
      local_.clear();
      const double diagonals = polygon_mwt(polygon_, &local_);
      if (!std::isfinite(diagonals) || region_sliver(local_) || !within_area(polygon_, local_)) {
        continue;
      }
      ++kick_trials_;
      begin_trial();
      double delta = diagonals - spoke_sum(m_.points[v], polygon_);
      std::vector<std::array<VertexId, 3>> tris;
      for (const auto& tri : local_) {
        tris.push_back({region_.boundary[tri[0]], region_.boundary[tri[1]], region_.boundary[tri[2]]});
      }
      region_.outside_flag = 0;
      replace_region(m_, region_, tris);
      for (const TriangleId t : region_.triangles) {
        if (m_.is_dead(t)) continue;
        for (unsigned e = 0; e < 3; ++e) flip_stack_.push_back(make_handle(t, e));
      }
      delta += local_flips();
      if (delta < -opt_.kick_min_relative_gain * weight) {
        keep_trial();
        m_.vertex_kind[v] = VertexKind::kRemoved;
        ++stats_.kick_removals;
        ++accepted;
      } else {
        undo_trial();
      }
    }
    return accepted;
  }

  void rebuild_vertex_handles() {
    vertex_handle_.assign(m_.points.size(), kNone);
    for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
      if (m_.is_dead(t) || m_.is_ghost(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        vertex_handle_[m_.org(h)] = h;
      }
    }
  }

  // A current handle with org v (handles go stale when the triangles around v are replaced).
  Handle handle_of(VertexId v) {
    Handle h = vertex_handle_[v];
    if (h != kNone && !m_.is_dead(h >> 2) && m_.org(h) == v) return h;
    const Location loc = m_.locate(m_.points[v], h != kNone && !m_.is_dead(h >> 2) ? h : kNone);
    if (loc.kind != Location::Kind::kOnVertex || m_.org(loc.handle) != v) return kNone;
    vertex_handle_[v] = loc.handle;
    return loc.handle;
  }

  void refresh_handles_after(const Region& r) {
    for (const TriangleId t : r.triangles) {
      if (m_.is_dead(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const VertexId v = m_.org(h);
        if (v != kInfinite) vertex_handle_[v] = h;
      }
    }
  }

  // Number of subsegments among v's spokes (−1 if v has no current handle).
  int segment_spokes(VertexId v) {
    const Handle h = handle_of(v);
    if (h == kNone) return -1;
    int count = 0;
    Handle s = h;
    std::size_t guard = 0;
    do {
      count += m_.is_segment(s) ? 1 : 0;
      s = m_.onext(s);
    } while (s != h && ++guard < 4096);
    return count;
  }

  bool star_in_domain(const Region& r) const {
    for (const TriangleId t : r.triangles) {
      if (!m_.in_domain(t)) return false;
    }
    return true;
  }

  bool try_remove(VertexId v) {
    const Handle h = handle_of(v);
    if (h == kNone || !star_of(m_, h, region_) || !star_in_domain(region_)) return false;
    polygon_.clear();
    for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
    local_.clear();
    const double diagonals = polygon_mwt(polygon_, &local_);
    const double spokes = spoke_sum(m_.points[v], polygon_);
    if (!(diagonals < spokes * (1.0 - 1e-12))) return false;
    if (region_sliver(local_) || !within_area(polygon_, local_)) return false;
    std::vector<std::array<VertexId, 3>> tris;
    for (const auto& tri : local_) {
      tris.push_back({region_.boundary[tri[0]], region_.boundary[tri[1]], region_.boundary[tri[2]]});
    }
    region_.outside_flag = 0;
    replace_region(m_, region_, tris);
    m_.save_vertex(v);
    m_.vertex_kind[v] = VertexKind::kRemoved;
    vertex_handle_[v] = kNone;
    refresh_handles_after(region_);
    ++stats_.removals;
    return true;
  }

  bool try_relocate(VertexId v) {
    const Handle h = handle_of(v);
    if (h == kNone || !star_of(m_, h, region_) || !star_in_domain(region_)) return false;
    polygon_.clear();
    for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
    const Point p = m_.points[v];
    const double before = spoke_sum(p, polygon_);
    Point q = geometric_median(p, polygon_);
    for (int halving = 0; halving < 40; ++halving) {
      q = {snap_to_range(q.x), snap_to_range(q.y)};
      // (The cheap test first: in_kernel's margins cost a hypot per edge.)
      if (in_supported_range(q) && spoke_sum(q, polygon_) < before && in_kernel(q, polygon_) &&
          separated(q, region_.outer) && star_within_area(q, polygon_)) {
        m_.save_vertex(v);
        m_.points[v] = q;
        ++stats_.relocations;
        return true;
      }
      q = {0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
      if (q == p) break;
    }
    return false;
  }

  // A Steiner vertex on a segment slides along the line through its two segment neighbours, to
  // the point of the open subsegment that minimises its in-domain spokes (a convex function of
  // the position: golden-section search), as far as every finite triangle around it stays
  // counter-clockwise. On the convex hull the hull must also stay convex at v and at its two hull
  // neighbours. Staying on the line through the segment neighbours does not ensure that: those
  // are rounded points, the true hull line bends at them by an ulp, and the hull neighbours need
  // not be the segment neighbours at all where refinement folded thin outside triangles onto the
  // hull (refine.cpp, restore_hull). (Found by fuzz_triangulate, --convex-hull: a slide turned a
  // hull vertex reflex.)
  bool try_slide(VertexId v) {
    const Handle h = handle_of(v);
    if (h == kNone) return false;
    VertexId ends[2] = {kNone, kNone};
    int count = 0;
    slide_spokes_.clear();
    slide_triangles_.clear();
    slide_domain_triangles_.clear();
    slide_beyond_.clear();
    // On the hull, the hull vertices around v in the order mesh.hpp reads hull edges:
    // before2 → hull_prev → v → hull_next → after2.
    VertexId before2 = kNone, hull_prev = kNone, hull_next = kNone, after2 = kNone;
    Handle s = h;
    std::size_t guard = 0;
    do {
      const TriangleId t = s >> 2;
      if (m_.is_dead(t)) return false;
      const VertexId u = m_.dest(s);
      if (!m_.is_ghost(t)) {
        slide_triangles_.push_back({u, m_.apex(s)});  // triangle (v, u, apex)
        slide_beyond_.push_back(m_.sym(Mesh::lnext(s)));  // across its link edge u → apex
        if (m_.in_domain(t)) slide_domain_triangles_.push_back({u, m_.apex(s)});
      } else if (m_.apex(s) == kInfinite) {
        // The ghost (v, u, ∞); the next ghost (u, after2, ∞) lies across its edge u → ∞.
        hull_next = u;
        after2 = m_.apex(m_.sym(Mesh::lnext(s)));
      } else if (u == kInfinite) {
        // The ghost (hull_prev, v, ∞); the one before, (before2, hull_prev, ∞), lies across ∞ → hull_prev.
        hull_prev = m_.apex(s);
        before2 = m_.apex(m_.sym(Mesh::lnext(s)));
      }
      if (u != kInfinite) {
        if (m_.is_segment(s)) {
          if (count < 2) ends[count] = u;
          ++count;
        }
        // A spoke counts towards the weight if either of its triangles is in the domain.
        if (m_.in_domain(t) || m_.in_domain(m_.sym(s) >> 2)) slide_spokes_.push_back(m_.points[u]);
      }
      s = m_.onext(s);
    } while (s != h && ++guard < 4096);
    if (s != h || count != 2) return false;
    const Point a = m_.points[ends[0]], b = m_.points[ends[1]];
    // On the hull no hull vertex may be strictly left of the hull edge into it (mesh.hpp's
    // convexity, which validate() checks).
    const bool on_hull = hull_prev != kNone || hull_next != kNone;
    if (on_hull && (hull_prev == kNone || hull_next == kNone || before2 == kNone || after2 == kNone ||
                    before2 == kInfinite || after2 == kInfinite)) {
      return false;
    }
    auto weight_at = [&](const Point& p) { return spoke_sum(p, slide_spokes_); };
    auto valid_at = [&](const Point& q) {
      if (!in_supported_range(q) || orient2d(a, b, q) != 0) return false;
      for (const auto& [u, w] : slide_triangles_) {
        if (orient2d(q, m_.points[u], m_.points[w]) <= 0) return false;
      }
      for (const auto& [u, w] : slide_domain_triangles_) {
        if (!area_allows(q, m_.points[u], m_.points[w])) return false;
      }
      if (on_hull) {
        const Point& p_before = m_.points[hull_prev];
        const Point& p_after = m_.points[hull_next];
        if (orient2d(m_.points[before2], p_before, q) > 0 || orient2d(p_before, q, p_after) > 0 ||
            orient2d(q, p_after, m_.points[after2]) > 0) {
          return false;
        }
      }
      return true;
    };
    const Point p = m_.points[v];
    const double before = weight_at(p);
    // Golden-section search of the (convex) spoke length along the open segment ab.
    auto at = [&](double t) { return Point{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; };
    double lo = 0.0, hi = 1.0;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = weight_at(at(x1)), f2 = weight_at(at(x2));
    for (int it = 0; it < 60; ++it) {
      if (f1 < f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - g * (hi - lo);
        f1 = weight_at(at(x1));
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + g * (hi - lo);
        f2 = weight_at(at(x2));
      }
    }
    Point q = at(0.5 * (lo + hi));
    for (int halving = 0; halving < 40; ++halving) {
      q = {snap_to_range(q.x), snap_to_range(q.y)};
      if (valid_at(q) && weight_at(q) < before && separated(q, slide_beyond_)) {
        m_.save_vertex(v);
        m_.points[v] = q;
        ++stats_.relocations;
        return true;
      }
      q = {0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
      if (q == p) break;
    }
    return false;
  }

  // Builds the region made of the given triangles (must be live, in the domain, a topological
  // disk whose boundary is a simple cycle). Returns false otherwise.
  bool region_from(const std::vector<TriangleId>& tris, Region& r) {
    r.triangles = tris;
    r.boundary.clear();
    r.outer.clear();
    r.segment.clear();
    r.marker.clear();
    r.outside_flag = 0;
    member_.clear();
    for (const TriangleId t : tris) {
      if (!m_.in_domain(t)) return false;
      member_.push_back(t);
    }
    std::sort(member_.begin(), member_.end());
    if (std::adjacent_find(member_.begin(), member_.end()) != member_.end()) return false;
    auto inside = [&](TriangleId t) { return std::binary_search(member_.begin(), member_.end(), t); };
    // Boundary edges by their origin (sorted: a repeated origin means the boundary is not
    // simple), then chained from origin to origin.
    boundary_from_.clear();
    double interior = 0.0;
    for (const TriangleId t : tris) {
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const Handle s = m_.sym(h);
        if (inside(s >> 2)) {
          if (m_.is_segment(h)) return false;  // never remove a subsegment
          interior += 0.5 * distance(m_.points[m_.org(h)], m_.points[m_.dest(h)]);
          continue;
        }
        boundary_from_.emplace_back(m_.org(h), h);
      }
    }
    if (boundary_from_.empty()) return false;
    std::sort(boundary_from_.begin(), boundary_from_.end());
    const auto same_origin = [](const auto& x, const auto& y) { return x.first == y.first; };
    if (std::adjacent_find(boundary_from_.begin(), boundary_from_.end(), same_origin) != boundary_from_.end()) {
      return false;  // vertex repeated
    }
    region_interior_weight_ = interior;
    auto edge_from = [&](VertexId v) -> const std::pair<VertexId, Handle>* {
      const auto at = std::lower_bound(boundary_from_.begin(), boundary_from_.end(), std::pair<VertexId, Handle>(v, 0));
      return at != boundary_from_.end() && at->first == v ? &*at : nullptr;
    };
    // Start from the smallest origin for determinism.
    Handle h = boundary_from_.front().second;
    for (std::size_t i = 0; i < boundary_from_.size(); ++i) {
      r.boundary.push_back(m_.org(h));
      r.outer.push_back(m_.sym(h));
      r.segment.push_back(m_.is_segment(h) ? 1 : 0);
      r.marker.push_back(m_.marker(h));
      const auto* next = edge_from(m_.dest(h));
      if (next == nullptr) return false;
      h = next->second;
    }
    if (m_.org(h) != r.boundary.front()) return false;  // more than one boundary cycle
    // A disk with B boundary and I interior vertices has B + 2I − 2 triangles: insist on I = 0,
    // so that re-triangulating the region never loses a vertex.
    return tris.size() + 2 == r.boundary.size();
  }

  // Re-triangulates the region (no interior vertex) by whichever is lightest: its minimum weight
  // triangulation (a many-edge flip), or a star from a new Steiner vertex at the geometric median
  // of its corners. Returns true if the region changed.
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

  // A failed try_region() changes nothing, and what it decided was a function of what it read:
  // the triangles given (slots, in order), their corners, neighbour handles and flags, their
  // corners' points and kinds, and allow_star. The local search retries every region near a
  // change, in every round and every perturbation trial, and most of them have not changed since
  // they last failed, so such failures are remembered by a 128-bit fingerprint of that input and
  // not tried again. A lossy cache (one fingerprint per slot, the newest kept): forgetting only
  // costs a retry, and a match needs all 128 bits, so the results are those of trying every time.
  using RegionFingerprint = std::array<std::uint64_t, 2>;
  RegionFingerprint region_fingerprint(const std::vector<TriangleId>& tris, bool allow_star) const {
    std::uint64_t h1 = 0x9E3779B97F4A7C15ull ^ tris.size(), h2 = 0xC2B2AE3D27D4EB4Full + (allow_star ? 1u : 0u);
    // Two independent multiply-rotate chains (one multiplication per word each), finished below.
    const auto mix = [&](std::uint64_t w) {
      h1 = std::rotl(h1 ^ w, 27) * 0x87C37B91114253D5ull;
      h2 = std::rotl(h2 + w, 31) * 0x4CF5AD432745937Full;
    };
    for (const TriangleId t : tris) {
      const Triangle& T = m_.triangles[t];
      mix(t | std::uint64_t{m_.flags[t]} << 32);
      for (unsigned k = 0; k < 3; ++k) {
        const VertexId v = T.v[k];
        mix(v | std::uint64_t{T.n[k]} << 32);
        if (v == kInfinite) continue;
        mix(std::bit_cast<std::uint64_t>(m_.points[v].x));
        mix(std::bit_cast<std::uint64_t>(m_.points[v].y) ^ static_cast<std::uint64_t>(m_.vertex_kind[v]));
      }
    }
    const auto finish = [](std::uint64_t h) {
      h ^= h >> 33;
      h *= 0xFF51AFD7ED558CCDull;
      h ^= h >> 33;
      h *= 0xC4CEB9FE1A85EC53ull;
      return h ^ (h >> 33);
    };
    return {finish(h1), finish(h2) | 1u};  // (never {0, 0}, the empty slot)
  }
  RegionFingerprint* failed_region_slot(const RegionFingerprint& f) {
    if (failed_regions_.empty()) {
      // About 32 slots per triangle (each triangle starts several regions, and the mesh around it
      // keeps changing), a power of two between 2^14 and 2^21 (256 KiB to 32 MiB).
      const std::size_t want = std::clamp<std::size_t>(32 * m_.triangles.size(), std::size_t{1} << 14, std::size_t{1} << 21);
      failed_regions_.assign(std::bit_ceil(want), RegionFingerprint{0, 0});
    }
    return &failed_regions_[f[0] & (failed_regions_.size() - 1)];
  }

  bool try_region(const std::vector<TriangleId>& tris, bool allow_star = true) {
    bool depends_on_room = false;  // a failure for want of Steiner room is not remembered
    if (!opt_.remember_failed_regions) return try_region_once(tris, allow_star, depends_on_room);
    const RegionFingerprint fingerprint = region_fingerprint(tris, allow_star);
    RegionFingerprint* const slot = failed_region_slot(fingerprint);
    if ((*slot)[0] == fingerprint[0] && (*slot)[1] == fingerprint[1]) {
      ++stats_.region_tries_skipped;
      return false;
    }
    if (!try_region_once(tris, allow_star, depends_on_room)) {
      if (!depends_on_room) *slot = fingerprint;
      return false;
    }
    return true;
  }

  bool try_region_once(const std::vector<TriangleId>& tris, bool allow_star, bool& depends_on_room) {
    if (!region_from(tris, region_)) return false;
    polygon_.clear();
    Point centroid{0.0, 0.0};
    for (const VertexId u : region_.boundary) {
      polygon_.push_back(m_.points[u]);
      centroid.x += m_.points[u].x;
      centroid.y += m_.points[u].y;
    }
    const double current = region_interior_weight_ * (1.0 - 1e-12);
    local_.clear();
    const double mwt = polygon_mwt(polygon_, &local_);
    double star_weight = std::numeric_limits<double>::infinity();
    Point q{0.0, 0.0};
    // A lower bound on any star's spokes: by the triangle inequality, a point's distances to two
    // corners sum to at least the corners' distance, so pairing corner i with corner i + d/2
    // bounds the spoke sum from below. When even that cannot beat the region's edges or its
    // MWT, Weiszfeld's iteration (the costly part) is skipped; it could not win.
    double star_lower_bound = 0.0;
    {
      const std::size_t d = polygon_.size(), half = d / 2;
      for (std::size_t i = 0; i < half; ++i) star_lower_bound += distance(polygon_[i], polygon_[i + half]);
    }
    const bool star_may_win = star_lower_bound < std::min(current, mwt) * (1.0 + 1e-9);
    if (opt_.insert && allow_star && star_may_win) {
      centroid.x /= static_cast<double>(polygon_.size());
      centroid.y /= static_cast<double>(polygon_.size());
      q = geometric_median(centroid, polygon_);
      q = {snap_to_range(q.x), snap_to_range(q.y)};
      // (A star that cannot win is not tested for the kernel, whose margins cost a hypot per edge.)
      if (in_supported_range(q)) {
        const double spokes = spoke_sum(q, polygon_);
        if (spokes < current && spokes < mwt && in_kernel(q, polygon_) && separated(q, region_.outer) &&
            star_within_area(q, polygon_)) {
          star_weight = spokes;
        }
      }
    }
    const bool star_wins = std::isfinite(star_weight);  // (only a winning star's weight is kept)
    if (star_wins && steiner_room() == 0) depends_on_room = true;
    if (star_wins && !depends_on_room) {
      const VertexId v = m_.add_vertex(q, VertexKind::kSteiner, 0);
      vertex_handle_.push_back(kNone);
      std::vector<std::array<VertexId, 3>> star;
      const std::size_t d = region_.boundary.size();
      for (std::size_t i = 0; i < d; ++i) {
        star.push_back({v, region_.boundary[i], region_.boundary[(i + 1) % d]});
      }
      replace_region(m_, region_, star);
      ++stats_.insertions;
      return true;
    }
    if (mwt < current && !region_sliver(local_) && within_area(polygon_, local_)) {
      std::vector<std::array<VertexId, 3>> tris_new;
      for (const auto& tri : local_) {
        tris_new.push_back({region_.boundary[tri[0]], region_.boundary[tri[1]], region_.boundary[tri[2]]});
      }
      replace_region(m_, region_, tris_new);
      ++stats_.region_retriangulations;
      return true;
    }
    return false;
  }

  // Adds the in-domain neighbours of t across non-segment edges to `tris`; false if a neighbour
  // across a non-segment edge is outside the domain.
  bool add_neighbours(TriangleId t, std::vector<TriangleId>& tris) {
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (m_.is_segment(h)) continue;
      const TriangleId u = m_.sym(h) >> 2;
      if (!m_.in_domain(u)) return false;
      if (std::find(tris.begin(), tris.end(), u) == tris.end()) tris.push_back(u);
    }
    return true;
  }

  void try_insertions() {
    const auto slots = static_cast<TriangleId>(m_.triangles.size());
    std::vector<TriangleId> tris;
    for (TriangleId t = 0; t < slots; ++t) {
      if ((t & 1023u) == 0 && out_of_time()) break;
      if (!m_.in_domain(t) || !in_focus(m_.points[m_.triangles[t].v[0]])) continue;
      // Region 1: the triangle and its neighbours (a hexagon at most).
      tris.assign(1, t);
      if (add_neighbours(t, tris) && tris.size() >= 2 && try_region(tris)) continue;
      // Region 2: the two triangles of each edge with all their neighbours (an octagon at most).
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (m_.is_segment(h)) continue;
        const TriangleId u = m_.sym(h) >> 2;
        if (!m_.in_domain(u) || u < t) continue;
        tris.assign({t, u});
        if (add_neighbours(t, tris) && add_neighbours(u, tris) && try_region(tris)) break;
      }
    }
    rebuild_vertex_handles();
  }

  Mesh& m_;
  const OptimizeOptions& opt_;
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
  std::vector<std::array<std::uint64_t, 2>> failed_regions_;  // try_region(): fingerprints of failures
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

}  // namespace

double point_segment_distance(const Point& p, const Point& a, const Point& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  const double t = length2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

bool point_is_separated(const Mesh& mesh, const Point& q, const std::vector<Handle>& beyond, double separation) {
  // The disk of radius `separation` around q is searched outward from the polygon: a vertex x
  // nearer than that is a corner of the polygon, or the segment qx leaves the polygon through an
  // edge nearer than `separation` and reaches x through triangles whose entry edges are too.
  // Segments and domain boundary edges are not crossed: one that near refuses q.
  thread_local std::vector<TriangleId> visited;
  thread_local std::vector<Handle> stack;
  visited.clear();
  stack.clear();
  const auto near = [&](VertexId v) { return v != kInfinite && distance(q, mesh.points[v]) < separation; };
  for (const Handle h : beyond) {
    if (near(mesh.org(h)) || near(mesh.dest(h))) return false;
    visited.push_back(triangle_of(mesh.sym(h)));  // the polygon's own triangles
  }
  stack = beyond;
  constexpr std::size_t kMaxTriangles = 256;  // beyond this many, refuse (a disk that large is no "near")
  while (!stack.empty()) {
    const Handle h = stack.back();  // an edge, seen from the triangle beyond it
    stack.pop_back();
    const VertexId a = mesh.org(h), b = mesh.dest(h);
    if (a == kInfinite || b == kInfinite) continue;
    if (point_segment_distance(q, mesh.points[a], mesh.points[b]) >= separation) continue;
    const TriangleId t = triangle_of(h);
    const bool boundary = mesh.in_domain(t) != mesh.in_domain(triangle_of(mesh.sym(h)));
    if (mesh.is_segment(h) || boundary) return false;
    if (mesh.is_ghost(t) || std::find(visited.begin(), visited.end(), t) != visited.end()) continue;
    if (visited.size() >= kMaxTriangles) return false;
    visited.push_back(t);
    if (near(mesh.apex(h))) return false;
    stack.push_back(mesh.sym(Mesh::lnext(h)));
    stack.push_back(mesh.sym(Mesh::lprev(h)));
  }
  return true;
}

double default_min_separation(const Mesh& mesh) {
  return OptimizeOptions::kSeparationFraction * shortest_domain_edge(mesh);
}

bool exact_polish_mesh(Mesh& mesh, const OptimizeOptions& options) {
  compact(mesh);
  if (mesh.points.size() > options.exact_polish_max_vertices) return false;
  MwtOptions mwt_options;
  mwt_options.diamond_route = true;
  mwt_options.max_visibility_vertices = options.exact_polish_visibility_vertices;
  mwt_options.max_candidate_edges = options.exact_polish_candidates_per_vertex * mesh.points.size();
  mwt_options.max_crossing_pairs = options.exact_polish_max_crossing_pairs;
  const double weight = measure(mesh).weight_total;
  MwtResult mwt = exact_mwt(mesh, mwt_options);
  if (!mwt.solved || !(mwt.weight < weight - options.min_relative_gain * weight)) return false;
  if (options.max_area > 0.0) {
    for (TriangleId t = 0; t < mwt.mesh.triangles.size(); ++t) {
      if (!mwt.mesh.in_domain(t)) continue;
      const auto& v = mwt.mesh.triangles[t].v;
      if (triangle_area(mwt.mesh.points[v[0]], mwt.mesh.points[v[1]], mwt.mesh.points[v[2]]) > options.max_area) {
        return false;
      }
    }
  }
  mesh = std::move(mwt.mesh);
  return true;
}

OptimizeStats optimize(Mesh& mesh, const OptimizeOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto deadline = detail::deadline_after(t0, options.time_budget_seconds);
  OptimizeStats stats;
  if (options.exact_polish && options.exact_polish_start) {
    // Two searches: from the mesh as given, and from the MWT of its vertices (another basin);
    // the lighter result is kept, so the polish never makes the result heavier.
    Mesh from_mwt = mesh;
    OptimizeStats from_mwt_stats;
    Optimizer(mesh, options, stats, deadline).run(false);
    if (Optimizer(from_mwt, options, from_mwt_stats, deadline).run(true)) {
      from_mwt_stats.exact_polish_tries += stats.exact_polish_tries;
      if (from_mwt_stats.weight_after < stats.weight_after) {
        mesh = std::move(from_mwt);
        stats = from_mwt_stats;
      } else {
        stats.exact_polish_tries = from_mwt_stats.exact_polish_tries;
      }
    } else {
      stats.exact_polish_tries += from_mwt_stats.exact_polish_tries;
    }
  } else {
    Optimizer(mesh, options, stats, deadline).run(false);
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace mwst

// ---- independent pieces of the domain (issue 32: opt at scale) ------------------------------

namespace mwst {

bool split_domain(const Pslg& input, const Mesh& cdt, DomainPieces& out) {
  out = {};
  const std::size_t n = input.points.size();
  // Pieces need a plain input: every CDT vertex an input point (no crossings, no duplicates).
  if (cdt.points.size() != n) return false;
  for (std::size_t v = 0; v < n; ++v) {
    if (cdt.vertex_kind[v] != VertexKind::kInput) return false;
  }
  // Domain triangles joined across shared edges (segments included: a segment's Steiner points
  // serve both sides), by union-find.
  const std::size_t slots = cdt.triangles.size();
  std::vector<TriangleId> parent(slots);
  std::iota(parent.begin(), parent.end(), TriangleId{0});
  const auto find = [&](TriangleId t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (TriangleId t = 0; t < slots; ++t) {
    if (!cdt.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const TriangleId u = triangle_of(cdt.sym(make_handle(t, e)));
      if (cdt.in_domain(u)) parent[find(u)] = find(t);
    }
  }
  // Pieces numbered by their smallest vertex; each vertex in exactly one piece.
  constexpr std::uint32_t kNoPiece = 0xFFFFFFFFu;
  std::vector<std::uint32_t> piece_of_root(slots, kNoPiece), piece_of_vertex(n, kNoPiece);
  std::vector<TriangleId> root_of_vertex(n, kNone);
  for (TriangleId t = 0; t < slots; ++t) {
    if (!cdt.in_domain(t)) continue;
    for (const VertexId v : cdt.triangles[t].v) {
      const TriangleId r = find(t);
      if (root_of_vertex[v] != kNone && root_of_vertex[v] != r) return false;  // pieces touching at v
      root_of_vertex[v] = r;
    }
  }
  std::uint32_t pieces = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (root_of_vertex[v] == kNone) return false;  // a point off the domain
    std::uint32_t& p = piece_of_root[root_of_vertex[v]];
    if (p == kNoPiece) p = pieces++;
    piece_of_vertex[v] = p;
  }
  if (pieces < 2) return false;
  out.pslgs.resize(pieces);
  out.input_ids.resize(pieces);
  std::vector<std::uint32_t> local(n);
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint32_t p = piece_of_vertex[v];
    local[v] = static_cast<std::uint32_t>(out.input_ids[p].size());
    out.input_ids[p].push_back(static_cast<VertexId>(v));
    out.pslgs[p].points.push_back(input.points[v]);
    out.pslgs[p].point_markers.push_back(v < input.point_markers.size() ? input.point_markers[v] : 0);
  }
  for (const Segment& s : input.segments) {
    const std::uint32_t p = piece_of_vertex[s.a];
    if (piece_of_vertex[s.b] != p) return false;
    out.pslgs[p].segments.push_back({local[s.a], local[s.b], s.marker});
  }
  // Each piece keeps the hole seeds inside its bounding box (the others lie in other pieces or
  // outside; merge_pieces checks that the pieces' domains add up to the whole).
  for (std::uint32_t p = 0; p < pieces; ++p) {
    Pslg& g = out.pslgs[p];
    Point lo = g.points.front(), hi = lo;
    for (const Point& q : g.points) {
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y)};
    }
    for (const Point& h : input.holes) {
      if (lo.x <= h.x && h.x <= hi.x && lo.y <= h.y && h.y <= hi.y) g.holes.push_back(h);
    }
    g.is_poly = input.is_poly;
    g.first_index = input.first_index;
    g.source = input.source;
  }
  return true;
}

bool merge_pieces(const Pslg& input, const Mesh& cdt, const DomainPieces& pieces, const std::vector<Mesh>& results,
                  Mesh& out) {
  // One graph: the input points (same ids), every piece's Steiner points after them, and every
  // edge of every piece as a constraint (so its triangles come back as they are; the gaps between
  // pieces are triangulated afresh and carved as before). Edges that are no subsegments carry
  // kNotSegment and are cleared after.
  constexpr std::int32_t kNotSegment = std::numeric_limits<std::int32_t>::min();
  Pslg g;
  g.points = input.points;
  g.point_markers = input.point_markers;
  g.holes = input.holes;
  g.is_poly = input.is_poly;
  g.first_index = input.first_index;
  g.source = input.source;
  std::vector<VertexKind> kinds(input.points.size(), VertexKind::kInput);
  std::vector<std::int32_t> markers(input.points.size(), 0);
  double domain_area = 0.0, pieces_area = 0.0, pieces_weight = 0.0;
  std::size_t pieces_triangles = 0;
  for (std::size_t p = 0; p < results.size(); ++p) {
    const Mesh& m = results[p];
    const std::vector<VertexId>& ids = pieces.input_ids[p];
    std::vector<VertexId> global(m.points.size(), kNone);
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      if (v < ids.size()) {
        global[v] = ids[v];
      } else if (m.vertex_kind[v] == VertexKind::kSteiner || m.vertex_kind[v] == VertexKind::kSteinerOnSegment) {
        global[v] = static_cast<VertexId>(g.points.size());
        g.points.push_back(m.points[v]);
        g.point_markers.push_back(m.vertex_marker[v]);
        kinds.push_back(m.vertex_kind[v]);
        markers.push_back(m.vertex_marker[v]);
      }
    }
    const Metrics metrics = measure(m);
    pieces_area += metrics.area;
    pieces_weight += metrics.weight_total;
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
      if (m.is_dead(t) || m.is_ghost(t)) continue;
      pieces_triangles += m.in_domain(t) ? 1 : 0;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId u = triangle_of(m.sym(h));
        const bool segment = m.is_segment(h);
        if (!segment && !m.in_domain(t) && !m.in_domain(u)) continue;  // the piece's own outside
        if (!m.is_ghost(u) && !m.is_dead(u) && u < t) continue;       // each edge once
        const VertexId a = global[m.org(h)], b = global[m.dest(h)];
        if (a == kNone || b == kNone) return false;
        g.segments.push_back({a, b, segment ? m.marker(h) : kNotSegment});
      }
    }
  }
  domain_area = measure(cdt).area;
  Mesh merged = constrained_delaunay(g);
  if (merged.points.size() != g.points.size()) return false;
  for (TriangleId t = 0; t < merged.triangles.size(); ++t) {
    if (merged.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (merged.is_segment(h) && merged.marker(h) == kNotSegment) merged.clear_segment(h);
    }
  }
  merged.input_vertex_count = static_cast<std::uint32_t>(input.points.size());
  for (std::size_t v = input.points.size(); v < g.points.size(); ++v) {
    merged.vertex_kind[v] = kinds[v];
    merged.vertex_marker[v] = markers[v];
  }
  // The pieces add up to the domain, triangle for triangle.
  const Metrics m = measure(merged);
  const auto close = [](double x, double y) { return std::fabs(x - y) <= 1e-9 * std::max(std::fabs(x), std::fabs(y)); };
  if (merged.domain_triangle_count() != pieces_triangles || !close(m.area, pieces_area) ||
      !close(m.area, domain_area) || !close(m.weight_total, pieces_weight) || !validate(merged).empty()) {
    return false;
  }
  out = std::move(merged);
  return true;
}

}  // namespace mwst
