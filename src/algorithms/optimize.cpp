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
// Rounds repeat until a round gains less than a relative threshold. Everything is sequential and
// ordered by ids, so results are deterministic.
#include "mwst/optimize.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/flip.hpp"
#include "mwst/metrics.hpp"

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

double polygon_mwt(const std::vector<Point>& P, std::vector<std::array<std::uint32_t, 3>>* triangles) {
  const std::size_t d = P.size();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (d < 3) return kInf;
  // valid[i][j]: the chord ij is a polygon edge or a diagonal lying inside the polygon.
  std::vector<char> valid(d * d, 0);
  for (std::size_t i = 0; i < d; ++i) {
    valid[i * d + (i + 1) % d] = valid[((i + 1) % d) * d + i] = 1;
  }
  for (std::size_t i = 0; i < d; ++i) {
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
  std::vector<double> W(d * d, kInf);
  std::vector<std::uint32_t> choice(d * d, 0);
  for (std::size_t i = 0; i + 1 < d; ++i) W[i * d + i + 1] = 0.0;
  auto chord = [&](std::size_t i, std::size_t j) {
    return (j == i + 1 || (i == 0 && j == d - 1)) ? 0.0 : distance(P[i], P[j]);
  };
  for (std::size_t gap = 2; gap < d; ++gap) {
    for (std::size_t i = 0; i + gap < d; ++i) {
      const std::size_t j = i + gap;
      if (!valid[i * d + j]) continue;
      double best = kInf;
      std::uint32_t best_k = 0;
      for (std::size_t k = i + 1; k < j; ++k) {
        if (!valid[i * d + k] || !valid[k * d + j]) continue;
        if (W[i * d + k] == kInf || W[k * d + j] == kInf) continue;
        if (orient2d(P[i], P[k], P[j]) <= 0) continue;
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
void replace_region(Mesh& m, const Region& r, const std::vector<std::array<VertexId, 3>>& tris) {
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
    m.flags[slots[i]] = r.outside_flag;
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

// Is p strictly inside the kernel of the closed polygon (all fan triangles counter-clockwise)?
bool in_kernel(const Point& p, const std::vector<Point>& polygon) {
  const std::size_t d = polygon.size();
  for (std::size_t i = 0; i < d; ++i) {
    if (orient2d(p, polygon[i], polygon[(i + 1) % d]) <= 0) return false;
  }
  return true;
}

class Optimizer {
 public:
  Optimizer(Mesh& m, const OptimizeOptions& o, OptimizeStats& s) : m_(m), opt_(o), stats_(s) {}

  void run() {
    double weight = measure(m_).weight_total;
    stats_.weight_before = weight;
    for (stats_.rounds = 0; stats_.rounds < opt_.max_rounds;) {
      ++stats_.rounds;
      const FlipStats f = flip_to_local_minimum(m_);
      stats_.flips += f.flips;
      rebuild_vertex_handles();
      const std::size_t n = m_.points.size();
      for (VertexId v = m_.input_vertex_count; v < n; ++v) {
        const VertexKind kind = m_.vertex_kind[v];
        if (kind != VertexKind::kSteiner && kind != VertexKind::kSteinerOnSegment) continue;
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
    const FlipStats f = flip_to_local_minimum(m_);
    stats_.flips += f.flips;
    compact(m_);
    stats_.weight_after = measure(m_).weight_total;
  }

 private:
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
    std::vector<std::array<VertexId, 3>> tris;
    for (const auto& tri : local_) {
      tris.push_back({region_.boundary[tri[0]], region_.boundary[tri[1]], region_.boundary[tri[2]]});
    }
    region_.outside_flag = 0;
    replace_region(m_, region_, tris);
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
      if (in_supported_range(q) && in_kernel(q, polygon_) && spoke_sum(q, polygon_) < before) {
        m_.points[v] = q;
        ++stats_.relocations;
        return true;
      }
      q = {0.5 * (p.x + q.x), 0.5 * (p.y + q.y)};
      if (q == p) break;
    }
    return false;
  }

  // A Steiner vertex on a segment slides along the line through its two segment neighbours.
  bool try_slide(VertexId v) {
    const Handle h = handle_of(v);
    if (h == kNone || !star_of(m_, h, region_)) return false;
    // The segment neighbours are the boundary vertices reached by subsegment spokes.
    VertexId ends[2] = {kNone, kNone};
    int count = 0;
    Handle s = h;
    std::vector<char> spoke_in_domain;
    do {
      if (m_.is_segment(s)) {
        if (count < 2) ends[count] = m_.dest(s);
        ++count;
      }
      // A spoke counts towards the weight if either of its triangles is in the domain.
      spoke_in_domain.push_back(m_.in_domain(s >> 2) || m_.in_domain(m_.sym(s) >> 2));
      s = m_.onext(s);
    } while (s != h);
    if (count != 2) return false;
    polygon_.clear();
    for (const VertexId u : region_.boundary) polygon_.push_back(m_.points[u]);
    const Point a = m_.points[ends[0]], b = m_.points[ends[1]];
    auto weight_at = [&](const Point& p) {
      double w = 0.0;
      for (std::size_t i = 0; i < polygon_.size(); ++i) {
        if (spoke_in_domain[i]) w += distance(p, polygon_[i]);
      }
      return w;
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
      // The whole star (inside and outside the domain) must stay valid, and q must stay on the
      // open subsegment: strictly between a and b, collinear with them.
      if (in_supported_range(q) && in_kernel(q, polygon_) && orient2d(a, b, q) == 0 &&
          weight_at(q) < before) {
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
    // Boundary edges, then chain them by their origin.
    std::unordered_map<VertexId, Handle> from;
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
        if (!from.emplace(m_.org(h), h).second) return false;  // vertex repeated: not simple
      }
    }
    region_interior_weight_ = interior;
    if (from.empty()) return false;
    // Start from the smallest origin for determinism.
    VertexId smallest = kInfinite;
    for (const auto& [v, hh] : from) {
      (void)hh;
      smallest = std::min(smallest, v);
    }
    Handle h = from.at(smallest);
    for (std::size_t i = 0; i < from.size(); ++i) {
      r.boundary.push_back(m_.org(h));
      r.outer.push_back(m_.sym(h));
      r.segment.push_back(m_.is_segment(h) ? 1 : 0);
      r.marker.push_back(m_.marker(h));
      const auto next = from.find(m_.dest(h));
      if (next == from.end()) return false;
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
  bool try_region(const std::vector<TriangleId>& tris) {
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
    if (opt_.insert) {
      centroid.x /= static_cast<double>(polygon_.size());
      centroid.y /= static_cast<double>(polygon_.size());
      q = geometric_median(centroid, polygon_);
      q = {snap_to_range(q.x), snap_to_range(q.y)};
      if (in_supported_range(q) && in_kernel(q, polygon_)) star_weight = spoke_sum(q, polygon_);
    }
    if (star_weight < current && star_weight < mwt) {
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
    if (mwt < current) {
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
      if (!m_.in_domain(t)) continue;
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
  std::vector<Handle> vertex_handle_;
  Region region_;
  std::vector<Point> polygon_;
  std::vector<std::array<std::uint32_t, 3>> local_;
  std::vector<TriangleId> member_;
  double region_interior_weight_ = 0.0;
};

}  // namespace

OptimizeStats optimize(Mesh& mesh, const OptimizeOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizeStats stats;
  Optimizer(mesh, options, stats).run();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace mwst
