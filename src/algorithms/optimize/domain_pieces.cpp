// src/algorithms/optimize/domain_pieces.cpp — independent pieces of the domain (domain_pieces.hpp):
// the input cut along the connected components of its domain, and the pieces' meshes put back
// together.
#include "algorithms/optimize/domain_pieces.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

#include "mwst/algorithms/metrics.hpp"
#include "mwst/mesh/delaunay.hpp"

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
