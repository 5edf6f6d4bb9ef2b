// src/algorithms/optimize/moves.cpp — the moves of one Steiner vertex: removal, relocation to the geometric
// median of its neighbours, a slide along its segment; and the polish of a new vertex (flips and
// geometric medians, alone or with its Steiner neighbours) that the kicks use.
#include "algorithms/optimize/optimizer.hpp"

#include <cmath>
#include <limits>

#include "mwst/algorithms/flip.hpp"
#include "algorithms/mwt/polygon_mwt.hpp"

namespace mwst::opt {

namespace {

// Golden-section search for the minimum of a convex function f on [0, 1]: 60 steps, each keeping
// the bracket that holds the smaller of two interior values; returns the middle of the last one.
template <class F>
double golden_section_minimum(F f) {
  double lo = 0.0, hi = 1.0;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 60; ++it) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

// Moves v to the first of q, (v + q) / 2, (v + (v + q) / 2) / 2, ... (each snapped to the
// supported range; at most 40) that `accept` takes, counting a relocation; false if none is.
template <class Accept>
bool Optimizer::move_towards(VertexId v, Point q, Accept accept) {
  const Point p = m_.points[v];
  for (int halving = 0; halving < 40; ++halving) {
    q = {snap_to_range(q.x), snap_to_range(q.y)};
    if (accept(q)) {
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

// A handle with org v, found by walking from `near`.
Handle Optimizer::handle_near(VertexId v, Handle near) const {
  const Location loc = m_.locate(m_.points[v], near);
  if (loc.kind != Location::Kind::kOnVertex || m_.org(loc.handle) != v) return kNone;
  return loc.handle;
}

// The edge a → b (a handle with org a and dest b), found by walking around a; kNone if a has no
// current handle or no edge to b.
Handle Optimizer::edge_between(VertexId a, VertexId b) const {
  Handle h = handle_near(a, m_.any_live_handle());
  if (h == kNone) return kNone;
  const Handle first = h;
  std::size_t guard = 0;
  while (m_.dest(h) != b && ++guard < 4096) {
    h = m_.onext(h);
    if (h == first) break;
  }
  return m_.dest(h) == b ? h : kNone;
}

// Pushes v's spokes and the edges of its star polygon onto flip_stack_.
void Optimizer::push_star(Handle h) {
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
double Optimizer::polish_vertex(VertexId v, Handle near) {
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

// A handle with org u if u is a free Steiner vertex whose spokes are no subsegments and whose
// triangles are all finite (one the relocation may move), else kNone.
Handle Optimizer::free_steiner_handle(VertexId u) const {
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
double Optimizer::polish_neighbours(VertexId v) {
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
VertexId Optimizer::insert_free_point(const Point& q, double& delta) {
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

bool Optimizer::try_remove(VertexId v) {
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

bool Optimizer::try_relocate(VertexId v) {
  const Handle h = handle_of(v);
  if (h == kNone || !star_of(m_, h, region_) || !star_in_domain(region_)) return false;
  polygon_.clear();
  for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
  const Point p = m_.points[v];
  const double before = spoke_sum(p, polygon_);
  return move_towards(v, geometric_median(p, polygon_), [&](const Point& q) {
    // (The cheap test first: in_kernel's margins cost a hypot per edge.)
    return in_supported_range(q) && spoke_sum(q, polygon_) < before && in_kernel(q, polygon_) &&
           separated(q, region_.outer) && star_within_area(q, polygon_);
  });
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
bool Optimizer::try_slide(VertexId v) {
  const Handle h = handle_of(v);
  if (h == kNone) return false;
  VertexId ends[2] = {kNone, kNone};
  // On the hull, the hull vertices around v in the order mesh.hpp reads hull edges:
  // hull[0] → hull[1] → v → hull[2] → hull[3].
  VertexId hull[4] = {kNone, kNone, kNone, kNone};
  if (!slide_star(h, ends, hull)) return false;
  const VertexId before2 = hull[0], hull_prev = hull[1], hull_next = hull[2], after2 = hull[3];
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
  auto at = [&](double t) { return Point{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; };
  return move_towards(v, at(golden_section_minimum([&](double t) { return weight_at(at(t)); })),
                      [&](const Point& q) { return valid_at(q) && weight_at(q) < before && separated(q, slide_beyond_); });
}

// try_slide's walk around the vertex v that h leaves: fills slide_spokes_ (the neighbours whose spokes count
// towards the weight), slide_triangles_ and slide_domain_triangles_ (the finite triangles around
// v, by their far edges), slide_beyond_ (the handles across those edges), v's two segment
// neighbours `ends` and, on the convex hull, the hull vertices `hull` around v. False unless the
// walk closes and v has exactly two subsegment spokes.
bool Optimizer::slide_star(Handle h, VertexId ends[2], VertexId hull[4]) {
  int count = 0;
  slide_spokes_.clear();
  slide_triangles_.clear();
  slide_domain_triangles_.clear();
  slide_beyond_.clear();
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
      hull[2] = u;
      hull[3] = m_.apex(m_.sym(Mesh::lnext(s)));
    } else if (u == kInfinite) {
      // The ghost (hull_prev, v, ∞); the one before, (before2, hull_prev, ∞), lies across ∞ → hull_prev.
      hull[1] = m_.apex(s);
      hull[0] = m_.apex(m_.sym(Mesh::lnext(s)));
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
  return s == h && count == 2;
}

}  // namespace mwst::opt
