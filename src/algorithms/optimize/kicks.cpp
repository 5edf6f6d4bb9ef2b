// src/algorithms/optimize/kicks.cpp — kicks: trial moves that first raise the weight and are kept only if a
// local re-optimisation brings it below where it was (insertions at centroids, at edge midpoints,
// in pairs and on segments; removals of free and on-segment Steiner points).
#include "algorithms/optimize/optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mwst/error.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "algorithms/mwt/polygon_mwt.hpp"

namespace mwst::opt {

// Tries a free Steiner vertex at p inside domain triangle t: split t, polish, keep if lighter.
bool Optimizer::kick_insert(TriangleId t, const Point& p, double weight) {
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

std::size_t Optimizer::kick_insertions() {
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
std::vector<std::tuple<double, VertexId, VertexId>> Optimizer::interior_edges_longest_first() const {
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
std::size_t Optimizer::kick_edge_splits() {
  const double weight = measure(m_).weight_total;
  const std::vector<std::tuple<double, VertexId, VertexId>> edges = interior_edges_longest_first();
  std::size_t accepted = 0;
  for (const auto& [key, ia, ib] : edges) {
    (void)key;
    if (!may_kick()) break;
    const Handle h = edge_between(ia, ib);
    if (h == kNone || m_.is_segment(h) || !m_.in_domain(h >> 2) || !m_.in_domain(m_.sym(h) >> 2)) continue;
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

// Pair kicks: two free Steiner vertices at a third and two thirds of each interior edge
// (longest first), polished jointly (flips and geometric medians, alternately, with their
// Steiner neighbours); kept only if the weight drops. A long edge crossing a bundle is often
// replaced by a chain of two Steiner points where one point alone does not pay.
std::size_t Optimizer::kick_pairs() {
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

// Where kick_segment_insertions puts its Steiner point on the subsegment ia → ib (handle h): the
// foot of the perpendicular given in `foot`, or one of its eight floating-point neighbours, the
// first that lies exactly on the segment line, strictly between ia and ib, inside both triangles
// of the subsegment and separated. False (foot unchanged) if none does.
bool Optimizer::segment_kick_point(VertexId ia, VertexId ib, Handle h, Point& foot) {
  const Point& a = m_.points[ia];
  const Point& b = m_.points[ib];
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
  bool found = false;
  for (int i = 0; i < 9 && !found; ++i) {
    const int dx = i % 3 - 1, dy = i / 3 - 1;
    Point r = foot;
    if (dx) r.x = std::nextafter(r.x, dx > 0 ? std::numeric_limits<double>::infinity()
                                             : -std::numeric_limits<double>::infinity());
    if (dy) r.y = std::nextafter(r.y, dy > 0 ? std::numeric_limits<double>::infinity()
                                             : -std::numeric_limits<double>::infinity());
    if (splits(r)) {
      foot = r;
      found = true;
    }
  }
  return found;
}

// Tries a Steiner vertex on each subsegment at the foot of the perpendicular from the opposite
// domain corner, then flips and slides; kept only if the total weight drops.
std::size_t Optimizer::kick_segment_insertions() {
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
    const Handle h = edge_between(cand.a, cand.b);
    if (h == kNone || !m_.is_segment(h) || !m_.in_domain(h >> 2)) continue;
    Point q = cand.foot;
    if (!segment_kick_point(cand.a, cand.b, h, q)) continue;
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

// The end of a kick removal, once v's star (region_) was re-triangulated without v in a trial that
// changed the weight by `delta`: flips from the new triangles, then the trial kept (v removed) if
// the weight dropped below `weight` by kick_min_relative_gain, else undone.
bool Optimizer::finish_kick_removal(VertexId v, double delta, double weight) {
  for (const TriangleId t : region_.triangles) {
    if (m_.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) flip_stack_.push_back(make_handle(t, e));
  }
  delta += local_flips();
  if (delta < -opt_.kick_min_relative_gain * weight) {
    keep_trial();
    m_.vertex_kind[v] = VertexKind::kRemoved;
    ++stats_.kick_removals;
    return true;
  }
  undo_trial();
  return false;
}

// kick_segment_removals' re-triangulation of the star of v (region_) without v: the two sides of
// the merged segment, neighbours ends[0] .. ends[1] and ends[1] .. ends[0] (cyclically), each by
// its MWT. Appends the triangles to `tris` (cleared first) with their flags, adds the in-domain
// weight change to `delta`; false if a side mixes domain and outside triangles, cannot be
// triangulated, or would make a straight-angle sliver or break the area bound.
bool Optimizer::merge_segment_sides(VertexId v, const std::size_t ends[2], std::vector<std::array<VertexId, 3>>& tris,
                                    std::vector<std::uint8_t>& flags, double& delta) {
  const std::size_t d = region_.boundary.size();
  tris.clear();
  flags.clear();
  for (int side = 0; side < 2; ++side) {
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
    bool ok = true;
    for (std::size_t i = from; i != to; i = (i + 1) % d) {
      if (m_.in_domain(region_.triangles[i]) != inside) ok = false;
    }
    if (!ok) return false;
    if (polygon_.size() == 2) return false;  // cannot happen for a valid star (each side holds a triangle)
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
      return false;
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
  return true;
}

// Removes Steiner vertices on segments: v between its segment neighbours a and b goes, the two
// subsegments merge into ab, and each side of ab is re-triangulated by its MWT, then flips
// around; kept only if the weight drops. (Not on the convex hull: the ghost triangles there
// would need merging too.)
std::size_t Optimizer::kick_segment_removals() {
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
    double delta = 0.0;
    if (!merge_segment_sides(v, ends, tris, flags, delta)) continue;
    ++kick_trials_;
    begin_trial();
    replace_region(m_, region_, tris, &flags);
    // The merged segment ab.
    const Handle ab = edge_between(a, b);
    if (ab == kNone) {
      undo_trial();
      continue;
    }
    m_.set_segment(ab, marker);
    if (finish_kick_removal(v, delta, weight)) ++accepted;
  }
  rebuild_vertex_handles();
  return accepted;
}

// Removes free Steiner vertices whose removal (star re-triangulated by its MWT) followed by
// flips around the hole lowers the weight, even when the MWT alone is heavier than the spokes.
std::size_t Optimizer::kick_removals() {
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
    if (finish_kick_removal(v, delta, weight)) ++accepted;
  }
  return accepted;
}

}  // namespace mwst::opt
