// The start mesh of Triangle's -r (Pslg::triangles): a given triangulation validated, oriented and
// made the run's mesh, with the input's segments, holes and area bounds (pipeline/phases.hpp).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "algorithms/pipeline/phases.hpp"
#include "algorithms/triangle_key.hpp"
#include "mesh/keys.hpp"
#include "mwst/error.hpp"
#include "mwst/mesh/delaunay.hpp"

namespace mwst::phases {

namespace {

// Lawson flips of every non-subsegment edge between two finite triangles on the same side of the
// domain's boundary until each is locally Delaunay (an edge failing the test has a convex
// quadrilateral, so every flip is legal, and the flips end: Lawson). `domain` says whether edges
// between two domain triangles are flipped too, or only those of the outside region.
void flip_to_constrained_delaunay(Mesh& mesh, bool domain) {
  std::vector<Handle> stack;
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.is_dead(t) || mesh.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) stack.push_back(make_handle(t, e));
  }
  while (!stack.empty()) {
    const Handle h = stack.back();
    stack.pop_back();
    const TriangleId t = h >> 2, u = mesh.sym(h) >> 2;
    if (mesh.is_dead(t) || mesh.is_segment(h) || mesh.is_ghost(t) || mesh.is_ghost(u) ||
        mesh.is_outside(t) != mesh.is_outside(u) || (!domain && !mesh.is_outside(t)) ||
        !mesh.is_locally_non_delaunay(h)) {
      continue;
    }
    const Handle diagonal = mesh.flip(h);
    for (const TriangleId w : {diagonal >> 2, mesh.sym(diagonal) >> 2}) {
      for (unsigned e = 0; e < 3; ++e) stack.push_back(make_handle(w, e));
    }
  }
}

// Triangle's 1-based (or 0-based) numbering of the input, for messages.
std::string numbered(const Pslg& pslg, std::size_t i) {
  return std::to_string(i + static_cast<std::size_t>(pslg.first_index));
}

// The triangles of Pslg::triangles with their corners checked and counter-clockwise (`reoriented`
// counts those turned); throws InputError for a corner out of range or collinear corners.
std::vector<std::array<VertexId, 3>> oriented_triangles(const Pslg& pslg, std::size_t& reoriented) {
  const std::size_t n = pslg.points.size(), count = pslg.triangles.size() / 3;
  std::vector<std::array<VertexId, 3>> triangles(count);
  reoriented = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::array<VertexId, 3> v{pslg.triangles[3 * i], pslg.triangles[3 * i + 1], pslg.triangles[3 * i + 2]};
    for (const VertexId x : v) {
      if (x >= n) {
        throw InputError(pslg.source, 0, "triangle " + numbered(pslg, i) + " names vertex " + numbered(pslg, x) +
                                             ", but there are only " + std::to_string(n) + " vertices");
      }
    }
    const int o = orient2d(pslg.points[v[0]], pslg.points[v[1]], pslg.points[v[2]]);
    if (o == 0) throw InputError(pslg.source, 0, "triangle " + numbered(pslg, i) + " is degenerate: its corners are collinear");
    if (o < 0) {
      std::swap(v[1], v[2]);
      ++reoriented;
    }
    triangles[i] = v;
  }
  return triangles;
}

// Each undirected edge (undirected_key): the triangles on it (at most two), and the origin of its
// direction in the first (counter-clockwise triangles on the two sides traverse it in opposite
// directions).
struct EdgeUse {
  std::size_t first = 0;
  VertexId first_org = 0;
  std::size_t uses = 0;
};
using EdgeUses = std::unordered_map<std::uint64_t, EdgeUse>;

// The edges of the triangles; throws InputError for an edge of three triangles, or two triangles on
// the same side of their edge (overlap).
EdgeUses edge_uses(const Pslg& pslg, const std::vector<std::array<VertexId, 3>>& triangles) {
  EdgeUses edges;
  edges.reserve(2 * triangles.size() + 16);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    for (unsigned e = 0; e < 3; ++e) {
      const VertexId a = triangles[i][next3(e)], b = triangles[i][prev3(e)];
      EdgeUse& use = edges[undirected_key(a, b)];
      const auto edge = [&] { return "(" + numbered(pslg, a) + ", " + numbered(pslg, b) + ")"; };
      if (use.uses == 2) {
        throw InputError(pslg.source, 0, "edge " + edge() + " belongs to more than two triangles (triangle " +
                                             numbered(pslg, i) + " is the third): the triangles do not form a triangulation");
      }
      if (use.uses == 1 && use.first_org == a) {
        throw InputError(pslg.source, 0, "triangles " + numbered(pslg, use.first) + " and " + numbered(pslg, i) +
                                             " overlap: both lie on the same side of their edge " + edge());
      }
      if (use.uses == 0) {
        use.first = i;
        use.first_org = a;
      }
      ++use.uses;
    }
  }
  return edges;
}

// The input segments' markers by edge; throws InputError for a segment that is no edge of the
// triangles.
std::unordered_map<std::uint64_t, std::int32_t> segment_markers(const Pslg& pslg, const EdgeUses& edges) {
  const std::size_t n = pslg.points.size();
  std::unordered_map<std::uint64_t, std::int32_t> segment_marker;
  for (std::size_t k = 0; k < pslg.segments.size(); ++k) {
    const Segment& seg = pslg.segments[k];
    if (seg.a >= n || seg.b >= n || !edges.count(undirected_key(seg.a, seg.b))) {
      const std::size_t line = k < pslg.segment_lines.size() ? pslg.segment_lines[k] : 0;
      throw InputError(pslg.source, line, "segment " + numbered(pslg, k) + " (" + numbered(pslg, seg.a) + ", " +
                                              numbered(pslg, seg.b) + ") is not an edge of the triangles");
    }
    segment_marker[undirected_key(seg.a, seg.b)] = seg.marker;
  }
  return segment_marker;
}

// The constrained Delaunay triangulation of the points with every edge of the triangles as a
// constraint: the boundary (used once) and the input segments with their markers, the other edges
// with marker 0 (unmarked again by keep_input_subsegments). It contains exactly the triangles when
// they form a triangulation.
Mesh mesh_with_triangle_edges(const Pslg& pslg, const EdgeUses& edges,
                              const std::unordered_map<std::uint64_t, std::int32_t>& segment_marker, unsigned threads) {
  Pslg constraints;
  constraints.points = pslg.points;
  constraints.point_markers = pslg.point_markers;
  constraints.source = pslg.source;
  constraints.segments.reserve(edges.size());
  for (const auto& [k, use] : edges) {
    const auto a = static_cast<VertexId>(k >> 32), b = static_cast<VertexId>(k & 0xFFFFFFFFu);
    const auto marked = segment_marker.find(k);
    const std::int32_t marker = marked != segment_marker.end() ? marked->second : use.uses == 1 ? 1 : 0;
    constraints.segments.push_back({a, b, marker});
  }
  // (The hash map's order is not the input's: sorted, so that the mesh does not depend on it.)
  std::sort(constraints.segments.begin(), constraints.segments.end(),
            [](const Segment& x, const Segment& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); });
  ConstrainOptions constrain;
  constrain.strict = true;
  constrain.convex_hull = true;
  constrain.threads = threads;
  ConstrainStats stats;
  try {
    return constrained_delaunay(constraints, constrain, &stats);
  } catch (const InputError& e) {
    throw InputError(pslg.source, 0, std::string("the triangles do not form a triangulation: ") + e.what());
  }
}

// The domain is the given triangles (matched by their sorted corners), with their area bounds
// (Pslg::triangle_max_area); the rest of the hull is outside. Throws InputError unless every
// given triangle is a triangle of the mesh.
void mark_given_triangles(Mesh& mesh, const Pslg& pslg, const std::vector<std::array<VertexId, 3>>& triangles) {
  std::unordered_map<std::array<VertexId, 3>, std::size_t, detail::TripleHash> input_index;
  input_index.reserve(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    std::array<VertexId, 3> v = triangles[i];
    std::sort(v.begin(), v.end());
    input_index.emplace(v, i);
  }
  const bool bounds = !pslg.triangle_max_area.empty();
  if (bounds) mesh.area_bound.assign(mesh.triangle_slots(), -1.0);
  std::size_t matched = 0;
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (mesh.is_dead(t) || mesh.is_ghost(t)) continue;
    std::array<VertexId, 3> v = mesh.triangles[t].v;
    std::sort(v.begin(), v.end());
    const auto it = input_index.find(v);
    if (it == input_index.end()) {
      mesh.flags[t] = static_cast<std::uint8_t>(mesh.flags[t] | kOutside);
      continue;
    }
    mesh.flags[t] = static_cast<std::uint8_t>(mesh.flags[t] & ~kOutside);
    if (bounds) mesh.area_bound[t] = pslg.triangle_max_area[it->second];
    ++matched;
  }
  if (matched != triangles.size()) {
    throw InputError(pslg.source, 0, "the triangles do not form a triangulation: " +
                                         std::to_string(triangles.size() - matched) +
                                         " of them overlap others, or have a vertex inside them");
  }
}

// Subsegments: the input segments and the domain's boundary only.
void keep_input_subsegments(Mesh& mesh, const std::unordered_map<std::uint64_t, std::int32_t>& segment_marker) {
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (mesh.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!mesh.is_segment(h)) continue;
      const bool inside = mesh.in_domain(t), across = mesh.in_domain(mesh.sym(h) >> 2);
      if (inside != across) continue;  // the domain's boundary
      if (inside && segment_marker.count(undirected_key(mesh.org(h), mesh.dest(h)))) continue;  // an input segment
      mesh.clear_segment(h);
    }
  }
}

}  // namespace

// Triangle's -r: the start mesh is the triangulation the input gives (Pslg::triangles), not the
// constrained Delaunay triangulation. It is validated — corner indices in range, no collinear
// corners, clockwise triangles turned counter-clockwise (with a warning), every edge in at most
// two triangles and on opposite sides of it, every input segment an edge, the triangles covering
// their union without overlap — and an InputError names the first problem. The mesh is built as
// the constrained Delaunay triangulation of the points with every edge of the triangles as a
// constraint, which contains exactly those triangles when they form a triangulation; the rest of
// the convex hull is marked outside. The domain's boundary edges and the input segments are
// subsegments (marker: the segment's, else 1); the outside region is made Delaunay, and with
// `make_delaunay` (the refining methods: their insertions need a constrained Delaunay mesh) the
// domain too, by flips that keep the subsegments. Pslg::triangle_max_area goes to Mesh::area_bound.
// Holes are not used (the triangles say where the domain is).
Mesh mesh_from_triangles(const Pslg& pslg, bool make_delaunay, unsigned threads, Report& report) {
  if (pslg.triangles.size() % 3 != 0) {
    throw InputError(pslg.source, 0, "the triangle list has " + std::to_string(pslg.triangles.size()) +
                                         " corner indices, not a multiple of 3");
  }
  const std::size_t count = pslg.triangles.size() / 3;
  if (!pslg.triangle_max_area.empty() && pslg.triangle_max_area.size() != count) {
    throw InputError(pslg.source, 0, "the area bounds list " + std::to_string(pslg.triangle_max_area.size()) +
                                         " values for " + std::to_string(count) + " triangles");
  }
  std::size_t reoriented = 0;
  const std::vector<std::array<VertexId, 3>> triangles = oriented_triangles(pslg, reoriented);
  if (reoriented > 0) {
    report.warnings.push_back(plural(reoriented, "triangle was", "triangles were") +
                              " clockwise and turned counter-clockwise");
  }
  const EdgeUses edges = edge_uses(pslg, triangles);
  const auto segment_marker = segment_markers(pslg, edges);
  Mesh mesh = mesh_with_triangle_edges(pslg, edges, segment_marker, threads);
  mark_given_triangles(mesh, pslg, triangles);
  keep_input_subsegments(mesh, segment_marker);
  flip_to_constrained_delaunay(mesh, make_delaunay);
  report.start = StartSummary{count, reoriented};
  return mesh;
}

}  // namespace mwst::phases
