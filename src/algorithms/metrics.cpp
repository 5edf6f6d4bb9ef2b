// Weight (sum of edge lengths, split into boundary and interior as the paper reports it) and the
// angle range of a mesh's domain triangles.
#include "mwst/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <thread>
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

namespace {

// The sums and extremes of measure() over a range of triangle slots.
struct PartialMetrics {
  std::size_t triangles = 0;
  double weight_total = 0.0, weight_boundary = 0.0;
  double area = 0.0;
  double max_area = 0.0;  // the largest triangle's (triangle_area)
  // Angle extremes without a trigonometric call per triangle: a triangle's smallest angle is
  // opposite its shortest edge and is at most 60°, so it is atan(|cross| / dot) with dot > 0 and
  // the ratio is monotone in it; its largest angle is opposite its longest edge, and
  // cot = dot / |cross| decreases with the angle on (0°, 180°). The extremes of the ratios are kept
  // and converted to degrees once at the end.
  double min_tan = std::numeric_limits<double>::infinity();
  double max_cross = 0.0, max_dot = 1.0;  // the corner with the largest angle so far (0° at start)

  void add_largest_corner(double cross, double dot) {
    // Is atan2(cross, dot) larger than atan2(max_cross, max_dot)? Both cross ≥ 0: compare by the
    // sign of the 2×2 determinant (the rotation from the stored corner's direction to this one).
    if (dot * max_cross - cross * max_dot < 0.0) {
      max_cross = cross;
      max_dot = dot;
    }
  }
};

PartialMetrics measure_range(const Mesh& mesh, TriangleId begin, TriangleId end) {
  PartialMetrics r;
  // The triangles are visited in slot order, but their vertices are numbered in input order and
  // their neighbours' slots follow the insertion history, so each corner and each neighbour is a
  // cache miss in a large mesh: request them a few triangles ahead so that the misses overlap
  // (the loop is otherwise bound by memory latency).
  constexpr TriangleId kAhead = 12;
  for (TriangleId t = begin; t < end; ++t) {
    if (t + kAhead < end) {
      const Triangle& A = mesh.triangles[t + kAhead];
      for (unsigned k = 0; k < 3; ++k) {
        if (A.v[k] < mesh.points.size()) __builtin_prefetch(&mesh.points[A.v[k]]);
        const TriangleId u = A.n[k] >> 2;
        if (u < mesh.triangles.size()) {
          __builtin_prefetch(&mesh.triangles[u]);
          __builtin_prefetch(&mesh.flags[u]);
        }
      }
    }
    if (!mesh.in_domain(t)) continue;
    ++r.triangles;
    const Triangle& T = mesh.triangles[t];
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const TriangleId other = mesh.sym(h) >> 2;
      const bool other_in = mesh.in_domain(other);
      // Count each interior edge once (from its lower-numbered triangle), boundary edges once.
      if (other_in && other < t) continue;
      const Point& a = mesh.points[mesh.org(h)];
      const Point& b = mesh.points[mesh.dest(h)];
      // sqrt of the squared length: no overflow or underflow in the supported coordinate range.
      const double len = std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y));
      r.weight_total += len;
      if (!other_in || mesh.is_segment(h)) r.weight_boundary += len;
    }
    const Point* p[3] = {&mesh.points[T.v[0]], &mesh.points[T.v[1]], &mesh.points[T.v[2]]};
    // Squared length of the edge opposite corner k.
    double opposite[3];
    for (unsigned k = 0; k < 3; ++k) {
      const Point& u = *p[next3(k)];
      const Point& w = *p[prev3(k)];
      opposite[k] = (u.x - w.x) * (u.x - w.x) + (u.y - w.y) * (u.y - w.y);
    }
    const unsigned smallest = static_cast<unsigned>(std::min_element(opposite, opposite + 3) - opposite);
    const unsigned largest = static_cast<unsigned>(std::max_element(opposite, opposite + 3) - opposite);
    auto corner = [&](unsigned k, double& cross, double& dot) {
      const Point& c = *p[k];
      const Point& u = *p[next3(k)];
      const Point& w = *p[prev3(k)];
      const double ux = u.x - c.x, uy = u.y - c.y, wx = w.x - c.x, wy = w.y - c.y;
      cross = std::fabs(ux * wy - uy * wx);
      dot = ux * wx + uy * wy;
    };
    double cross = 0.0, dot = 0.0;
    corner(smallest, cross, dot);
    if (dot > 0.0) r.min_tan = std::min(r.min_tan, cross / dot);
    else if (cross == 0.0) r.min_tan = 0.0;  // a degenerate triangle (never in a valid mesh)
    corner(largest, cross, dot);
    r.add_largest_corner(cross, dot);
    const Point& a = *p[0];
    const double area = triangle_area(a, *p[1], *p[2]);
    r.area += area;
    r.max_area = std::max(r.max_area, area);
  }
  return r;
}

}  // namespace

Metrics measure(const Mesh& mesh) {
  // Large meshes are measured in two halves on two threads (the split depends only on the mesh
  // size, so the sums are the same run after run).
  const auto slots = static_cast<TriangleId>(mesh.triangles.size());
  PartialMetrics part;
  if (slots >= (TriangleId{1} << 16)) {
    PartialMetrics second;
    std::jthread worker([&] { second = measure_range(mesh, slots / 2, slots); });
    part = measure_range(mesh, 0, slots / 2);
    worker.join();
    part.triangles += second.triangles;
    part.weight_total += second.weight_total;
    part.weight_boundary += second.weight_boundary;
    part.area += second.area;
    part.max_area = std::max(part.max_area, second.max_area);
    part.min_tan = std::min(part.min_tan, second.min_tan);
    part.add_largest_corner(second.max_cross, second.max_dot);
  } else {
    part = measure_range(mesh, 0, slots);
  }
  Metrics r;
  r.triangles = part.triangles;
  r.weight_total = part.weight_total;
  r.weight_boundary = part.weight_boundary;
  r.area = part.area;
  r.max_triangle_area = part.max_area;
  r.min_angle_deg = r.triangles == 0 ? 0.0 : std::atan(part.min_tan) * 180.0 / std::numbers::pi;
  r.max_angle_deg = r.triangles == 0 ? 0.0 : std::atan2(part.max_cross, part.max_dot) * 180.0 / std::numbers::pi;
  std::vector<char> used(mesh.points.size(), 0);
  for (TriangleId t = 0; t < slots; ++t) {
    if (!mesh.in_domain(t)) continue;
    for (const VertexId v : mesh.triangles[t].v) used[v] = 1;
  }
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
