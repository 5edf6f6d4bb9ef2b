// src/algorithms/optimize/optimizer.cpp — the phases of the search (optimizer.hpp lists them in order): the
// whole-domain MWT, the local search and its flips, the kick passes, the iterated local search; and
// the table of vertex handles the local search keeps.
#include "algorithms/optimize/optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "algorithms/mwt/polygon_mwt.hpp"

namespace mwst::opt {

// With polish_start, first replaces the mesh by the MWT of its vertices, and returns false
// without searching if that was not kept (not solved, too large or not lighter).
bool Optimizer::run(bool polish_start) {
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

// If the domain is one polygon without interior vertices (a simple polygon with its CDT), and
// small enough for the O(d³) dynamic programme, replaces it by its exact minimum weight
// triangulation (Gilbert 1979; Klincsek 1980): the best mesh on these vertices.
void Optimizer::whole_domain_mwt() {
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

void Optimizer::local_search() {
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
void Optimizer::focused_flips() {
  if (!focused_) {
    const FlipStats flipped = flip_to_local_minimum(m_, opt_.max_area, deadline_);
    stats_.flips += flipped.flips;
    stats_.out_of_time |= flipped.out_of_time;
    return;
  }
  for (TriangleId t = 0; t < m_.triangles.size(); ++t) {
    if (!m_.in_domain(t) || !in_focus(m_.points[m_.triangles[t].v[0]])) continue;
    for (unsigned e = 0; e < 3; ++e) flip_stack_.push_back(make_handle(t, e));
  }
  local_flips();
}

// Weight-reducing flips from the edges on `flip_stack_` (and the edges they expose); returns the
// change in weight (≤ 0). Each flip lowers the weight strictly (exact test), so it terminates.
double Optimizer::local_flips() {
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

void Optimizer::kicks_and_search() {
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
void Optimizer::perturbation_search() {
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

void Optimizer::rebuild_vertex_handles() {
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
Handle Optimizer::handle_of(VertexId v) {
  Handle h = vertex_handle_[v];
  if (h != kNone && !m_.is_dead(h >> 2) && m_.org(h) == v) return h;
  const Location loc = m_.locate(m_.points[v], h != kNone && !m_.is_dead(h >> 2) ? h : kNone);
  if (loc.kind != Location::Kind::kOnVertex || m_.org(loc.handle) != v) return kNone;
  vertex_handle_[v] = loc.handle;
  return loc.handle;
}

void Optimizer::refresh_handles_after(const Region& r) {
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
int Optimizer::segment_spokes(VertexId v) {
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

}  // namespace mwst::opt
