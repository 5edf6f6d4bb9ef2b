// Partition crossover of two triangulations of one domain (crossover.hpp; method opt's last step).
//
// Two light Steiner triangulations A and B of the same input usually agree on most edges (the fans
// along a coastline, the input segments) and differ in separate places, each the choice of a local
// search between several local minima. Cut the domain along the edges A and B share: every piece
// X that A's triangles make between shared edges is also a union of B's triangles (a B triangle
// cannot cross an edge that B has; a B triangle reached from X across an edge A does not have
// stays in X), and the pieces are independent — replacing A's triangles in X by B's changes only
// the edges inside X. So the child that takes, piece by piece, the lighter of the two is never
// heavier than either parent and is often lighter than both. This is the partition crossover of
// Whitley, Hains and Howe (GPX, 2009) for the travelling salesman problem, here for triangulations;
// a piece is taken from B only if its boundary in B is the same chain of edges (a segment split by
// different Steiner points in A and B leaves its piece to A) with the same subsegments on it.
// The marks matter at coarse doubles (1 apart near 7.7e15): there the CDT resolves crossings
// within its rounding, and one parent can hold a segment both as an edge u-v and as a chain
// u-w-v of subsegments around a flat triangle (u, v, w) on the piece's side, with u-v left
// unmarked, while the other parent marks u-v itself. Spliced with A's marks, the child kept u-v
// unmarked and lost the chain: a piece is not taken unless both parents mark its boundary alike.
#include "algorithms/optimize/crossover.hpp"

#include <algorithm>
#include <compare>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mesh/keys.hpp"

namespace mwst {

namespace {

// The pieces of a mesh: its in-domain triangles joined across the edges not in `shared` (undirected
// keys in the ids id_of(v) gives the mesh's vertices; kNone: a vertex the other mesh lacks). Each
// piece's triangles are listed together (ascending ids) with the sum of their perimeters.
struct Pieces {
  std::vector<std::uint32_t> of;       // per triangle slot: its piece, kNone outside the domain
  std::vector<std::uint32_t> first;    // piece p's triangles: triangles[first[p], first[p + 1])
  std::vector<TriangleId> triangles;
  std::vector<double> perimeter;
  std::uint32_t count() const { return static_cast<std::uint32_t>(perimeter.size()); }
  const TriangleId* begin(std::uint32_t p) const { return triangles.data() + first[p]; }
  const TriangleId* end(std::uint32_t p) const { return triangles.data() + first[p + 1]; }
};

template <class IdOf>
Pieces pieces_of(const Mesh& m, IdOf id_of, const std::unordered_set<std::uint64_t>& shared) {
  Pieces out;
  out.of.assign(m.triangles.size(), kNone);
  std::vector<TriangleId> stack;
  std::uint32_t count = 0;
  for (TriangleId s = 0; s < m.triangles.size(); ++s) {
    if (!m.in_domain(s) || out.of[s] != kNone) continue;
    out.of[s] = count;
    stack.push_back(s);
    while (!stack.empty()) {
      const TriangleId t = stack.back();
      stack.pop_back();
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId u = m.sym(h) >> 2;
        if (!m.in_domain(u) || out.of[u] != kNone) continue;
        const VertexId a = id_of(m.org(h)), b = id_of(m.dest(h));
        if (a != kNone && b != kNone && shared.count(undirected_key(a, b))) continue;
        out.of[u] = count;
        stack.push_back(u);
      }
    }
    ++count;
  }
  // Counting sort of the triangles by piece; perimeters.
  out.first.assign(count + 1, 0);
  out.perimeter.assign(count, 0.0);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (out.of[t] == kNone) continue;
    ++out.first[out.of[t] + 1];
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      out.perimeter[out.of[t]] += distance(m.points[m.org(h)], m.points[m.dest(h)]);
    }
  }
  for (std::uint32_t p = 0; p < count; ++p) out.first[p + 1] += out.first[p];
  out.triangles.resize(out.first[count]);
  std::vector<std::uint32_t> next(out.first.begin(), out.first.end() - 1);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (out.of[t] != kNone) out.triangles[next[out.of[t]]++] = t;
  }
  return out;
}

// One edge of a piece's boundary: directed with the piece on its left (edge_key in the ids id_of
// gives), and whether it is a subsegment, with which marker.
struct BoundaryEdge {
  std::uint64_t key = 0;
  bool segment = false;
  std::int32_t marker = 0;  // (0 when not a subsegment)
  auto operator<=>(const BoundaryEdge&) const = default;
};

// The boundary of piece p, sorted; false if a boundary vertex has no such id.
template <class IdOf>
bool boundary_of(const Mesh& m, const Pieces& pieces, std::uint32_t p, IdOf id_of, std::vector<BoundaryEdge>& out) {
  out.clear();
  for (const TriangleId* t = pieces.begin(p); t != pieces.end(p); ++t) {
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(*t, e);
      if (pieces.of[m.sym(h) >> 2] == p) continue;
      const VertexId u = id_of(m.org(h)), v = id_of(m.dest(h));
      if (u == kNone || v == kNone) return false;
      const bool segment = m.is_segment(h);
      out.push_back({edge_key(u, v), segment, segment ? m.marker(h) : 0});
    }
  }
  std::sort(out.begin(), out.end());
  return true;
}

// B's vertices as A's ids, matched by exact coordinates among the vertices of the two domains
// (kNone: not a vertex of A).
std::vector<VertexId> match_vertices(const Mesh& a, const Mesh& b) {
  std::vector<char> a_used(a.points.size(), 0), b_used(b.points.size(), 0);
  for (TriangleId t = 0; t < a.triangles.size(); ++t) {
    if (a.in_domain(t)) for (VertexId v : a.triangles[t].v) a_used[v] = 1;
  }
  for (TriangleId t = 0; t < b.triangles.size(); ++t) {
    if (b.in_domain(t)) for (VertexId v : b.triangles[t].v) b_used[v] = 1;
  }
  std::unordered_map<PointKey, VertexId, PointKeyHash> a_at;
  for (VertexId v = 0; v < a.points.size(); ++v) {
    if (a_used[v]) a_at.emplace(PointKey(a.points[v]), v);
  }
  std::vector<VertexId> b_to_a(b.points.size(), kNone);
  for (VertexId v = 0; v < b.points.size(); ++v) {
    if (!b_used[v]) continue;
    const auto it = a_at.find(PointKey(b.points[v]));
    if (it != a_at.end()) b_to_a[v] = it->second;
  }
  return b_to_a;
}

// The domain edges A and B share (undirected, A's ids), and B's directed domain edges by A's ids.
void shared_edges(const Mesh& a, const Mesh& b, const std::vector<VertexId>& b_to_a,
                  std::unordered_set<std::uint64_t>& shared, std::unordered_map<std::uint64_t, Handle>& b_directed) {
  std::unordered_set<std::uint64_t> a_edges;
  for (TriangleId t = 0; t < a.triangles.size(); ++t) {
    if (!a.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      a_edges.insert(undirected_key(a.org(h), a.dest(h)));
    }
  }
  for (TriangleId t = 0; t < b.triangles.size(); ++t) {
    if (!b.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId u = b_to_a[b.org(h)], v = b_to_a[b.dest(h)];
      if (u == kNone || v == kNone) continue;
      b_directed.emplace(edge_key(u, v), h);
      if (a_edges.count(undirected_key(u, v))) shared.insert(undirected_key(u, v));
    }
  }
}

// Splicing B's pieces into A: A's triangles of a taken piece give way to B's; B's vertices that A
// lacks are added.
class Splicer {
 public:
  Splicer(Mesh& a, const Mesh& b, const std::vector<VertexId>& b_to_a, const Pieces& a_pieces, const Pieces& b_pieces)
      : a_(a), b_(b), b_to_a_(b_to_a), a_pieces_(a_pieces), b_pieces_(b_pieces), b_new_(b.points.size(), kNone),
        a_kind_(a.vertex_kind), piece_of_(a_pieces.of) {}

  // Replaces A's piece p by B's piece q.
  void splice(std::uint32_t p, std::uint32_t q) {
    Mesh& a = a_;
    const Mesh& b = b_;
    std::unordered_map<std::uint64_t, Handle> outer;  // boundary edge → the handle outside it
    std::unordered_map<std::uint64_t, std::int32_t> segment;  // boundary subsegments → marker
    for (const TriangleId* tp = a_pieces_.begin(p); tp != a_pieces_.end(p); ++tp) {
      const TriangleId t = *tp;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (piece_of_[a.sym(h) >> 2] == p) continue;
        outer.emplace(edge_key(a.org(h), a.dest(h)), a.sym(h));
        if (a.is_segment(h)) segment.emplace(edge_key(a.org(h), a.dest(h)), a.marker(h));
      }
    }
    // A's Steiner points of the piece go, unless B's triangles use them again (child_id).
    for (const TriangleId* tp = a_pieces_.begin(p); tp != a_pieces_.end(p); ++tp) {
      const TriangleId t = *tp;
      for (VertexId v : a.triangles[t].v) {
        if (v >= a.input_vertex_count) a.vertex_kind[v] = VertexKind::kRemoved;
      }
    }
    for (const TriangleId* t = a_pieces_.begin(p); t != a_pieces_.end(p); ++t) a.kill_triangle(*t);
    std::unordered_map<std::uint64_t, Handle> open;
    for (const TriangleId* sp = b_pieces_.begin(q); sp != b_pieces_.end(q); ++sp) {
      const TriangleId s = *sp;
      const TriangleId t = a.new_triangle();
      if (t >= piece_of_.size()) piece_of_.resize(t + 1, kNone);
      piece_of_[t] = kNone;
      for (unsigned k = 0; k < 3; ++k) a.triangles[t].v[k] = child_id(b.triangles[s].v[k]);
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const std::uint64_t k = edge_key(a.org(h), a.dest(h));
        const auto o = outer.find(k);
        if (o != outer.end()) {
          a.triangles[t].n[e] = o->second;
          a.triangles[o->second >> 2].n[o->second & 3] = h;
          const auto sg = segment.find(k);
          if (sg != segment.end()) a.set_segment(h, sg->second);
          continue;
        }
        const auto twin = open.find(edge_key(a.dest(h), a.org(h)));
        if (twin == open.end()) {
          open.emplace(k, h);
          continue;
        }
        a.triangles[t].n[e] = twin->second;
        a.triangles[twin->second >> 2].n[twin->second & 3] = h;
        const Handle bh = make_handle(s, e);
        if (b.is_segment(bh)) a.set_segment(h, b.marker(bh));
        open.erase(twin);
      }
    }
    if (!open.empty()) throw InternalError("crossover: a spliced piece does not close");
  }

 private:
  // A's id of B's vertex v: its match (restoring its kind: on the piece's boundary, or a point
  // both parents have), or a vertex added to A once.
  VertexId child_id(VertexId v) {
    if (b_to_a_[v] != kNone) {
      const VertexId u = b_to_a_[v];
      a_.vertex_kind[u] = a_kind_[u];
      return u;
    }
    if (b_new_[v] == kNone) b_new_[v] = a_.add_vertex(b_.points[v], b_.vertex_kind[v], b_.vertex_marker[v]);
    return b_new_[v];
  }

  Mesh& a_;
  const Mesh& b_;
  const std::vector<VertexId>& b_to_a_;
  const Pieces& a_pieces_;
  const Pieces& b_pieces_;
  std::vector<VertexId> b_new_;
  const std::vector<VertexKind> a_kind_;
  // The piece of a slot of A; the slots the splices fill (reused or new) belong to no piece left.
  std::vector<std::uint32_t> piece_of_;
};

}  // namespace

CrossoverStats partition_crossover(Mesh& a, const Mesh& b) {
  CrossoverStats stats;
  if (a.input_vertex_count != b.input_vertex_count) throw InternalError("crossover: different inputs");
  const std::vector<VertexId> b_to_a = match_vertices(a, b);
  std::unordered_set<std::uint64_t> shared;
  std::unordered_map<std::uint64_t, Handle> b_directed;
  shared_edges(a, b, b_to_a, shared, b_directed);
  const auto a_id = [](VertexId v) { return v; };
  const auto b_id = [&b_to_a](VertexId v) { return b_to_a[v]; };
  // The sums of perimeters compare interior weights: a piece is compared only when its boundary is
  // the same chain in both parents, with the same subsegments on it (the splice keeps A's marks on
  // the boundary, B's inside).
  const Pieces a_pieces = pieces_of(a, a_id, shared);
  const Pieces b_pieces = pieces_of(b, b_id, shared);
  const std::uint32_t a_count = a_pieces.count();
  stats.pieces = a_count;
  std::vector<BoundaryEdge> a_boundary, b_boundary;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> take;  // (A piece, the B piece replacing it)
  for (std::uint32_t p = 0; p < a_count; ++p) {
    boundary_of(a, a_pieces, p, a_id, a_boundary);
    // B's piece on the same side of a shared boundary edge.
    std::uint32_t q = kNone;
    for (const BoundaryEdge& edge : a_boundary) {
      const std::uint64_t k = edge.key;
      const auto it = b_directed.find(k);
      if (it != b_directed.end() && shared.count(undirected_key(static_cast<VertexId>(k >> 32), static_cast<VertexId>(k)))) {
        q = b_pieces.of[it->second >> 2];
        break;
      }
    }
    if (q == kNone) continue;
    if (!boundary_of(b, b_pieces, q, b_id, b_boundary) || b_boundary != a_boundary) {
      ++stats.mismatched;
      continue;
    }
    if (b_pieces.perimeter[q] < a_pieces.perimeter[p] * (1.0 - 1e-12)) {
      take.emplace_back(p, q);
      stats.gain += 0.5 * (a_pieces.perimeter[p] - b_pieces.perimeter[q]);
    }
  }
  Splicer splicer(a, b, b_to_a, a_pieces, b_pieces);
  for (const auto& [p, q] : take) {
    splicer.splice(p, q);
    ++stats.taken;
  }
  compact(a);
  return stats;
}

}  // namespace mwst
