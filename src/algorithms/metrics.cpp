// Weight (sum of edge lengths, split into boundary and interior as the paper reports it) and the
// angle range of a mesh's domain triangles.
#include "mwst/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace mwst {

void triangle_angles_deg(const Mesh& mesh, TriangleId t, double out[3]) {
  const Triangle& T = mesh.triangles[t];
  const Point& a = mesh.points[T.v[0]];
  const Point& b = mesh.points[T.v[1]];
  const Point& c = mesh.points[T.v[2]];
  // Angle at each corner from the two edge vectors leaving it (atan2 of cross and dot is
  // accurate for tiny and near-straight angles alike).
  auto angle = [](const Point& p, const Point& q, const Point& r) {
    const double ux = q.x - p.x, uy = q.y - p.y, vx = r.x - p.x, vy = r.y - p.y;
    return std::atan2(std::fabs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / std::numbers::pi;
  };
  out[0] = angle(a, b, c);
  out[1] = angle(b, c, a);
  out[2] = angle(c, a, b);
}

Metrics measure(const Mesh& mesh) {
  Metrics r;
  std::vector<char> used(mesh.points.size(), 0);
  r.min_angle_deg = 180.0;
  r.max_angle_deg = 0.0;
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (!mesh.in_domain(t)) continue;
    ++r.triangles;
    const Triangle& T = mesh.triangles[t];
    for (unsigned e = 0; e < 3; ++e) {
      used[T.v[e]] = 1;
      const Handle h = make_handle(t, e);
      const TriangleId other = mesh.sym(h) >> 2;
      const bool other_in = mesh.in_domain(other);
      // Count each interior edge once (from its lower-numbered triangle), boundary edges once.
      if (other_in && other < t) continue;
      const double len = distance(mesh.points[mesh.org(h)], mesh.points[mesh.dest(h)]);
      r.weight_total += len;
      if (!other_in || mesh.is_segment(h)) r.weight_boundary += len;
    }
    double ang[3];
    triangle_angles_deg(mesh, t, ang);
    for (double a : ang) {
      r.min_angle_deg = std::min(r.min_angle_deg, a);
      r.max_angle_deg = std::max(r.max_angle_deg, a);
    }
    const Point& a = mesh.points[T.v[0]];
    r.area += signed_area(a, mesh.points[T.v[1]], mesh.points[T.v[2]]);
  }
  if (r.triangles == 0) r.min_angle_deg = 0.0;
  for (VertexId v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    ++r.vertices;
    if (v < mesh.vertex_kind.size() && (mesh.vertex_kind[v] == VertexKind::kSteiner ||
                                        mesh.vertex_kind[v] == VertexKind::kSteinerOnSegment)) {
      ++r.steiner;
    }
  }
  r.weight_interior = r.weight_total - r.weight_boundary;
  return r;
}

}  // namespace mwst
