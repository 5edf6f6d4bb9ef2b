// src/algorithms/optimize/separation.cpp — OptimizeOptions::min_separation: how near a new Steiner
// vertex may come to the mesh (separation.hpp).
#include "algorithms/optimize/separation.hpp"

#include "mwst/algorithms/optimize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mwst {

namespace {

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

}  // namespace mwst
