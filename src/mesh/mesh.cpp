// Mesh: local operations (flip, 1→3 and 2→4 splits), point location by a stochastic visibility
// walk, vertex insertion with Lawson flips (Lawson 1977; the generalised circumcircle of ghost
// triangles follows CGAL's infinite-vertex convention), and segment flag bookkeeping.
#include "mwst/mesh/mesh.hpp"

#include "mwst/error.hpp"

namespace mwst {

namespace {

// Writes the reciprocal link: the edge `from` now has `to` as its neighbour and vice versa.
inline void link(std::vector<Triangle>& tri, Handle a, Handle b) {
  tri[a >> 2].n[a & 3] = b;
  tri[b >> 2].n[b & 3] = a;
}

}  // namespace

std::int32_t Mesh::marker(Handle h) const {
  if (!is_segment(h) || segment_marker.empty()) return 0;
  return segment_marker[3 * (h >> 2) + (h & 3)];
}

void Mesh::save_triangle_slot(TriangleId t) {
  SavedTriangle saved{t, triangles[t], flags[t], false, {0, 0, 0}};
  if (3 * std::size_t{t} + 2 < segment_marker.size()) {
    saved.has_markers = true;
    for (unsigned e = 0; e < 3; ++e) saved.markers[e] = segment_marker[3 * std::size_t{t} + e];
  }
  trial_.saved.push_back(saved);
}

void Mesh::begin_trial() {
  if (trial_.open) throw InternalError("Mesh::begin_trial: a trial is already open");
  trial_.open = true;
  trial_.triangles = triangles.size();
  trial_.points = points.size();
  trial_.segment_markers = segment_marker.size();
  trial_.free_low = free_slots_.size();
  trial_.walk_rng = walk_rng_;  // (the journal is empty: close_trial() clears it)
}

void Mesh::close_trial() {
  trial_.open = false;
  trial_.saved.clear();
  trial_.vertices.clear();
  trial_.popped_free_slots.clear();
}

void Mesh::commit_trial() { close_trial(); }

void Mesh::undo_trial() {
  if (!trial_.open) throw InternalError("Mesh::undo_trial: no trial is open");
  triangles.resize(trial_.triangles);
  flags.resize(trial_.triangles);
  if (!area_bound.empty()) area_bound.resize(trial_.triangles, -1.0);
  segment_marker.resize(trial_.segment_markers);
  points.resize(trial_.points);
  vertex_kind.resize(trial_.points);
  vertex_marker.resize(trial_.points);
  // Latest first, so that a slot saved several times ends as it was first saved.
  for (auto it = trial_.saved.rbegin(); it != trial_.saved.rend(); ++it) {
    triangles[it->t] = it->triangle;
    flags[it->t] = it->flags;
    if (it->has_markers && 3 * std::size_t{it->t} + 2 < segment_marker.size()) {
      for (unsigned e = 0; e < 3; ++e) segment_marker[3 * std::size_t{it->t} + e] = it->markers[e];
    }
  }
  for (auto it = trial_.vertices.rbegin(); it != trial_.vertices.rend(); ++it) {
    points[it->v] = it->point;
    vertex_kind[it->v] = it->kind;
    vertex_marker[it->v] = it->marker;
  }
  // The free list: below free_low it never changed; above it, its entries from the start were
  // taken one by one from the top (popped_free_slots, top first), and whatever lies there now
  // was pushed during the trial.
  free_slots_.resize(trial_.free_low);
  for (auto it = trial_.popped_free_slots.rbegin(); it != trial_.popped_free_slots.rend(); ++it) {
    free_slots_.push_back(*it);
  }
  walk_rng_ = trial_.walk_rng;
  close_trial();
}

void Mesh::set_segment(Handle h, std::int32_t marker_value) {
  if (segment_marker.size() < 3 * triangles.size()) segment_marker.resize(3 * triangles.size(), 0);
  const Handle s = sym(h);
  save_triangle(h >> 2);
  save_triangle(s >> 2);
  flags[h >> 2] = static_cast<std::uint8_t>(flags[h >> 2] | (kSegmentEdge0 << (h & 3)));
  flags[s >> 2] = static_cast<std::uint8_t>(flags[s >> 2] | (kSegmentEdge0 << (s & 3)));
  segment_marker[3 * (h >> 2) + (h & 3)] = marker_value;
  segment_marker[3 * (s >> 2) + (s & 3)] = marker_value;
}

void Mesh::clear_segment(Handle h) {
  const Handle s = sym(h);
  save_triangle(h >> 2);
  save_triangle(s >> 2);
  flags[h >> 2] = static_cast<std::uint8_t>(flags[h >> 2] & ~(kSegmentEdge0 << (h & 3)));
  flags[s >> 2] = static_cast<std::uint8_t>(flags[s >> 2] & ~(kSegmentEdge0 << (s & 3)));
}

VertexId Mesh::add_vertex(const Point& p, VertexKind kind, std::int32_t marker_value) {
  const auto id = static_cast<VertexId>(points.size());
  points.push_back(p);
  vertex_kind.push_back(kind);
  vertex_marker.push_back(marker_value);
  return id;
}

TriangleId Mesh::new_triangle() {
  if (!free_slots_.empty()) {
    const TriangleId t = free_slots_.back();
    free_slots_.pop_back();
    if (trial_.open) {
      if (free_slots_.size() < trial_.free_low) {  // an entry from before the trial
        trial_.free_low = free_slots_.size();
        trial_.popped_free_slots.push_back(t);
      }
      save_triangle(t);
    }
    flags[t] = 0;
    return t;
  }
  const auto t = static_cast<TriangleId>(triangles.size());
  triangles.push_back(Triangle{{kNone, kNone, kNone}, {kNone, kNone, kNone}});
  flags.push_back(0);
  if (!segment_marker.empty()) segment_marker.resize(3 * triangles.size(), 0);
  if (!area_bound.empty()) area_bound.resize(triangles.size(), -1.0);
  return t;
}

void Mesh::kill_triangle(TriangleId t) {
  save_triangle(t);
  flags[t] = kDead;
  triangles[t].v = {kNone, kNone, kNone};
  triangles[t].n = {kNone, kNone, kNone};
  free_slots_.push_back(t);
}

// Moves the segment bit and marker of edge `from` (in its old place) to edge `to`.
// Used by the local operations when an edge changes slot.
namespace {
struct EdgeMark {
  bool segment;
  std::int32_t marker;
};
inline EdgeMark read_mark(const Mesh& m, Handle h) {
  return {m.is_segment(h), m.segment_marker.empty() ? 0 : m.segment_marker[3 * (h >> 2) + (h & 3)]};
}
inline void write_mark(Mesh& m, Handle h, EdgeMark mark) {
  auto& f = m.flags[h >> 2];
  const auto bit = static_cast<std::uint8_t>(kSegmentEdge0 << (h & 3));
  f = static_cast<std::uint8_t>(mark.segment ? (f | bit) : (f & ~bit));
  if (!m.segment_marker.empty()) m.segment_marker[3 * (h >> 2) + (h & 3)] = mark.marker;
}
}  // namespace

Handle Mesh::flip(Handle h) {
  const TriangleId t = h >> 2, u = sym(h) >> 2;
  const unsigned e = h & 3, f = sym(h) & 3;
  const unsigned e1 = next3(e), e2 = prev3(e), f1 = next3(f), f2 = prev3(f);
  Triangle& T = triangles[t];
  Triangle& U = triangles[u];
  // T = (c, a, b) at corners (e, e1, e2); U = (d, b, a) at corners (f, f1, f2).
  const VertexId d = U.v[f];
  const Handle n_bc = T.n[e1];  // edge b→c, opposite a in T
  const Handle n_ad = U.n[f1];  // edge a→d, opposite b in U
  if (trial_.open) {
    for (const TriangleId w : {t, u, n_bc >> 2, n_ad >> 2}) save_triangle(w);
  }
  const bool marked = (flags[t] | flags[u]) & 7;
  EdgeMark m_bc{}, m_ad{};
  if (marked) {
    m_bc = read_mark(*this, make_handle(t, e1));
    m_ad = read_mark(*this, make_handle(u, f1));
  }
  // T becomes (c, a, d): corner e1 keeps a, corner e2 becomes d.
  T.v[e2] = d;
  // U becomes (d, b, c): corner f keeps d, corner f1 keeps b, corner f2 becomes c.
  U.v[f2] = T.v[e];
  link(triangles, make_handle(t, e), n_ad);  // T's edge opposite c: a→d
  link(triangles, make_handle(u, f), n_bc);  // U's edge opposite d: b→c
  link(triangles, make_handle(t, e1), make_handle(u, f1));  // the new diagonal d–c
  if (marked) {
    write_mark(*this, make_handle(t, e), m_ad);
    write_mark(*this, make_handle(u, f), m_bc);
    write_mark(*this, make_handle(t, e1), {false, 0});
    write_mark(*this, make_handle(u, f1), {false, 0});
  }
  if (!area_bound.empty()) {
    const double bt = area_bound[t], bu = area_bound[u];
    const double mean = bt > 0.0 && bu > 0.0 ? 0.5 * (bt + bu) : -1.0;
    area_bound[t] = mean;
    area_bound[u] = mean;
  }
  return make_handle(t, e1);
}

std::array<Handle, 3> Mesh::split_triangle(TriangleId t, VertexId p) {
  // t = (a, b, c) becomes (a, b, p) in place; t1 = (b, c, p); t2 = (c, a, p).
  const TriangleId t1 = new_triangle();
  const TriangleId t2 = new_triangle();
  Triangle& T = triangles[t];
  const VertexId a = T.v[0], b = T.v[1], c = T.v[2];
  const Handle n_a = T.n[0];  // edge b→c
  const Handle n_b = T.n[1];  // edge c→a
  if (trial_.open) {
    for (const TriangleId w : {t, n_a >> 2, n_b >> 2}) save_triangle(w);
  }
  const bool marked = flags[t] & 7;
  EdgeMark m_a{}, m_b{};
  if (marked) {
    m_a = read_mark(*this, make_handle(t, 0));
    m_b = read_mark(*this, make_handle(t, 1));
  }
  // (a, b, p): corner 2 = p, edge 2 (a→b) keeps its neighbour.
  T.v = {a, b, p};
  triangles[t1].v = {b, c, p};
  triangles[t2].v = {c, a, p};
  link(triangles, make_handle(t1, 2), n_a);  // b→c
  link(triangles, make_handle(t2, 2), n_b);  // c→a
  link(triangles, make_handle(t, 0), make_handle(t1, 1));  // b→p / p→b
  link(triangles, make_handle(t1, 0), make_handle(t2, 1));  // c→p / p→c
  link(triangles, make_handle(t2, 0), make_handle(t, 1));   // a→p / p→a
  flags[t1] = static_cast<std::uint8_t>(flags[t] & kOutside);
  flags[t2] = static_cast<std::uint8_t>(flags[t] & kOutside);
  if (!area_bound.empty()) area_bound[t1] = area_bound[t2] = area_bound[t];
  if (marked) {
    write_mark(*this, make_handle(t1, 2), m_a);
    write_mark(*this, make_handle(t2, 2), m_b);
    write_mark(*this, make_handle(t, 0), {false, 0});
    write_mark(*this, make_handle(t, 1), {false, 0});
  }
  return {make_handle(t, 2), make_handle(t1, 2), make_handle(t2, 2)};
}

std::array<Handle, 4> Mesh::split_edge(Handle h, VertexId p) {
  // h = a→b in t = (a, b, c) [c = apex]; sym(h) = b→a in u = (b, a, d).
  // After: t = (a, p, c), t1 = (p, b, c), u = (b, p, d), u1 = (p, a, d).
  const Handle s = sym(h);
  const TriangleId t = h >> 2, u = s >> 2;
  const unsigned e = h & 3, f = s & 3;
  const TriangleId t1 = new_triangle();
  const TriangleId u1 = new_triangle();
  Triangle& T = triangles[t];
  Triangle& U = triangles[u];
  const VertexId c = T.v[e], a = T.v[next3(e)], b = T.v[prev3(e)];
  const VertexId d = U.v[f];
  const Handle n_bc = T.n[next3(e)];  // edge b→c (opposite a)
  const Handle n_ad = U.n[next3(f)];  // edge a→d (opposite b)
  if (trial_.open) {
    for (const TriangleId w : {t, u, n_bc >> 2, n_ad >> 2}) save_triangle(w);
  }
  const EdgeMark m_h = read_mark(*this, h);
  const EdgeMark m_bc = read_mark(*this, make_handle(t, next3(e)));
  const EdgeMark m_ad = read_mark(*this, make_handle(u, next3(f)));
  // Rewrite t = (c, a, p) at corners (e, e+1, e+2): edge e = a→p, edge e+1 = p→c, edge e+2 = c→a.
  T.v[prev3(e)] = p;
  // Rewrite u = (d, b, p) at corners (f, f+1, f+2): edge f = b→p, edge f+1 = p→d, edge f+2 = d→b.
  U.v[prev3(f)] = p;
  triangles[t1].v = {p, b, c};  // edges: 0 = b→c, 1 = c→p, 2 = p→b
  triangles[u1].v = {p, a, d};  // edges: 0 = a→d, 1 = d→p, 2 = p→a
  link(triangles, make_handle(t1, 0), n_bc);
  link(triangles, make_handle(u1, 0), n_ad);
  link(triangles, make_handle(t, next3(e)), make_handle(t1, 1));  // p→c / c→p
  link(triangles, make_handle(u, next3(f)), make_handle(u1, 1));  // p→d / d→p
  link(triangles, make_handle(t, e), make_handle(u1, 2));         // a→p / p→a
  link(triangles, make_handle(u, f), make_handle(t1, 2));         // b→p / p→b
  if (m_h.segment || m_bc.segment || m_ad.segment) {
    write_mark(*this, make_handle(t1, 0), m_bc);
    write_mark(*this, make_handle(u1, 0), m_ad);
    write_mark(*this, make_handle(t, next3(e)), {false, 0});
    write_mark(*this, make_handle(u, next3(f)), {false, 0});
    write_mark(*this, make_handle(t, e), m_h);
    write_mark(*this, make_handle(u1, 2), m_h);
    write_mark(*this, make_handle(u, f), m_h);
    write_mark(*this, make_handle(t1, 2), m_h);
  }
  // The outside flag of the two halves follows their parent triangles.
  flags[t1] = static_cast<std::uint8_t>((flags[t1] & 7) | (flags[t] & kOutside));
  flags[u1] = static_cast<std::uint8_t>((flags[u1] & 7) | (flags[u] & kOutside));
  if (!area_bound.empty()) {
    area_bound[t1] = area_bound[t];
    area_bound[u1] = area_bound[u];
  }
  return {make_handle(t, prev3(e)), make_handle(t1, 0), make_handle(u, prev3(f)), make_handle(u1, 0)};
}

bool Mesh::is_locally_non_delaunay(Handle h) const {
  // Triangle of h: (apex p, org u, dest w); far apex x across h.
  const TriangleId t = h >> 2;
  const unsigned e = h & 3;
  const Triangle& T = triangles[t];
  const VertexId p = T.v[e], u = T.v[next3(e)], w = T.v[prev3(e)];
  const VertexId x = apex(sym(h));
  if (x == kInfinite) {
    // The far triangle is a ghost with hull edge w→u; p is in its half-plane only if (u, w, p)
    // were clockwise, impossible for a real triangle. A ghost h-triangle cannot face a ghost here
    // since both would contain the edge u-w and the infinite vertex.
    return false;
  }
  if (p == kInfinite || u == kInfinite || w == kInfinite) {
    // h's triangle is a ghost reading (a, b, ∞): x is inside its circle iff x is left of a→b.
    VertexId a, b;
    if (p == kInfinite) {
      a = u;
      b = w;
    } else if (u == kInfinite) {
      a = w;
      b = p;
    } else {
      a = p;
      b = u;
    }
    return orient2d(points[a], points[b], points[x]) > 0;
  }
  // incircle of (u, w, p) is counter-clockwise as (p, u, w).
  return incircle(points[p], points[u], points[w], points[x]) > 0;
}

void Mesh::legalize(VertexId apex_vertex, std::vector<Handle>& stack, Handle* last) {
  (void)apex_vertex;
  while (!stack.empty()) {
    const Handle h = stack.back();
    stack.pop_back();
    if ((!segment_marker.empty() && is_segment(h)) || !is_locally_non_delaunay(h)) continue;
    // h's apex is the new vertex c; the flip leaves triangles (c, a, d) and (d, b, c).
    const Handle diag = flip(h);  // d→c, edge e1 of t = (c, a, d) stored at corners (e, e1, e2)
    stack.push_back(make_handle(diag >> 2, prev3(diag & 3)));  // a→d, opposite c
    // sym(diag) = c→d is edge f1 of (d, b, c) at corners (f, f1, f2); c sits at f2 = next3(f1).
    const Handle other = sym(diag);
    stack.push_back(make_handle(other >> 2, next3(other & 3)));  // d→b, opposite c
    if (last) *last = diag;
  }
}

Handle Mesh::any_live_handle() const {
  for (TriangleId t = 0; t < triangles.size(); ++t) {
    if (!(flags[t] & kDead) && !is_ghost(t)) return make_handle(t, 0);
  }
  return kNone;
}

std::size_t Mesh::domain_triangle_count() const {
  std::size_t n = 0;
  for (TriangleId t = 0; t < triangles.size(); ++t) n += in_domain(t) ? 1 : 0;
  return n;
}

double Mesh::domain_area() const {
  double area = 0.0;
  for (TriangleId t = 0; t < triangles.size(); ++t) {
    if (!in_domain(t)) continue;
    const auto& v = triangles[t].v;
    area += signed_area(points[v[0]], points[v[1]], points[v[2]]);
  }
  return area;
}

Location Mesh::locate(const Point& p, Handle start) const {
  if (start == kNone || (flags[start >> 2] & kDead)) start = any_live_handle();
  if (start == kNone) throw InternalError("locate: the mesh has no live triangle");
  TriangleId t = start >> 2;
  if (is_ghost(t)) {
    // Step to the finite triangle across the ghost's hull edge.
    const Triangle& G = triangles[t];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    t = G.n[k] >> 2;
  }
  Handle came_from = kNone;  // the edge (in t) we entered through: never leave by it
  const std::size_t limit = 64 + 4 * triangles.size();
  for (std::size_t steps = 0; steps < limit; ++steps) {
    const Triangle& T = triangles[t];
    if (T.v[0] == kInfinite || T.v[1] == kInfinite || T.v[2] == kInfinite) {
      // We crossed a hull edge with p strictly beyond it: p lies in this ghost's half-plane.
      return {Location::Kind::kInTriangle, make_handle(t, 0)};
    }
    // Stochastic visibility walk (Devillers, Pion, Teillaud 2002): test the edges starting at a
    // pseudo-random one, cross the first edge that has p strictly on its far side.
    walk_rng_ ^= walk_rng_ << 13;
    walk_rng_ ^= walk_rng_ >> 17;
    walk_rng_ ^= walk_rng_ << 5;
    const unsigned first = walk_rng_ % 3;
    int zero_count = 0;
    unsigned zero_edge = 0;
    bool moved = false;
    for (unsigned i = 0; i < 3; ++i) {
      const unsigned e = (first + i) % 3;
      const Handle h = make_handle(t, e);
      if (h == came_from) continue;
      const int o = orient2d(points[T.v[next3(e)]], points[T.v[prev3(e)]], p);
      if (o < 0) {
        came_from = T.n[e];
        t = came_from >> 2;
        moved = true;
        break;
      }
      if (o == 0) {
        ++zero_count;
        zero_edge = e;
      }
    }
    if (moved) continue;
    // The entry edge was skipped: p lies strictly on its near side (we crossed it for that).
    if (zero_count == 0) return {Location::Kind::kInTriangle, make_handle(t, 0)};
    if (zero_count == 1) return {Location::Kind::kOnEdge, make_handle(t, zero_edge)};
    // Two edges through p: p is their common vertex (the corner not opposite either).
    for (unsigned k = 0; k < 3; ++k) {
      if (points[T.v[k]] == p) return {Location::Kind::kOnVertex, make_handle(t, prev3(k))};
    }
    throw InternalError("locate: inconsistent orientation tests");
  }
  throw InternalError("locate: walk did not terminate (corrupt mesh)");
}

VertexId Mesh::insert_vertex(VertexId v, Handle start, Handle* hint) {
  const Location loc = locate(points[v], start);
  if (loc.kind == Location::Kind::kOnVertex) {
    if (hint) *hint = loc.handle;
    return org(loc.handle);
  }
  std::vector<Handle>& stack = flip_stack_;
  stack.clear();
  if (loc.kind == Location::Kind::kInTriangle) {
    const auto opp = split_triangle(loc.handle >> 2, v);
    stack.assign(opp.begin(), opp.end());
  } else {
    const auto opp = split_edge(loc.handle, v);
    stack.assign(opp.begin(), opp.end());
  }
  Handle last = stack.front();
  legalize(v, stack, &last);
  if (hint) *hint = last;
  return v;
}

}  // namespace mwst

namespace mwst {

void compact(Mesh& m) {
  if (m.in_trial()) throw InternalError("compact: a trial is open");
  // New vertex ids: every vertex except removed Steiner points, in order.
  std::vector<VertexId> new_vertex(m.points.size(), kNone);
  VertexId nv = 0;
  for (VertexId v = 0; v < m.points.size(); ++v) {
    if (m.vertex_kind[v] == VertexKind::kRemoved) continue;
    new_vertex[v] = nv;
    m.points[nv] = m.points[v];
    m.vertex_kind[nv] = m.vertex_kind[v];
    m.vertex_marker[nv] = m.vertex_marker[v];
    ++nv;
  }
  m.points.resize(nv);
  m.vertex_kind.resize(nv);
  m.vertex_marker.resize(nv);
  for (auto& [dup, kept] : m.duplicates) {
    dup = new_vertex[dup];
    kept = new_vertex[kept];
  }
  // New triangle ids: live slots in order.
  std::vector<TriangleId> new_triangle(m.triangles.size(), kNone);
  TriangleId nt = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!(m.flags[t] & kDead)) new_triangle[t] = nt++;
  }
  const bool markers = !m.segment_marker.empty();
  const bool bounds = !m.area_bound.empty();
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    const TriangleId u = new_triangle[t];
    if (u == kNone) continue;
    if (bounds) m.area_bound[u] = m.area_bound[t];
    Triangle T = m.triangles[t];
    for (VertexId& v : T.v) {
      if (v != kInfinite) v = new_vertex[v];
    }
    for (Handle& h : T.n) h = make_handle(new_triangle[h >> 2], h & 3);
    m.triangles[u] = T;
    m.flags[u] = m.flags[t];
    if (markers) {
      for (unsigned e = 0; e < 3; ++e) m.segment_marker[3 * u + e] = m.segment_marker[3 * t + e];
    }
  }
  m.triangles.resize(nt);
  m.flags.resize(nt);
  if (markers) m.segment_marker.resize(3 * static_cast<std::size_t>(nt));
  if (bounds) m.area_bound.resize(nt);
  m.clear_free_slots();
}

}  // namespace mwst
