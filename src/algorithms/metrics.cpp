// Weight (sum of edge lengths, split into boundary and interior as the paper reports it) and the
// angle range of a mesh's domain triangles.
#include "mwst/algorithms/metrics.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
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

bool below_angle_bound(const Point& a, const Point& b, const Point& c, double bound_cos2) {
  const double abx = b.x - a.x, aby = b.y - a.y;
  const double bcx = c.x - b.x, bcy = c.y - b.y;
  const double cax = a.x - c.x, cay = a.y - c.y;
  const double l2 = abx * abx + aby * aby;  // opposite corner c
  const double l0 = bcx * bcx + bcy * bcy;  // opposite corner a
  const double l1 = cax * cax + cay * cay;  // opposite corner b
  double dot, la, lb;
  if (l0 <= l1 && l0 <= l2) {
    dot = -(abx * cax + aby * cay);  // (b−a)·(c−a)
    la = l2;
    lb = l1;
  } else if (l1 <= l2) {
    dot = -(abx * bcx + aby * bcy);  // (a−b)·(c−b)
    la = l2;
    lb = l0;
  } else {
    dot = -(bcx * cax + bcy * cay);  // (b−c)·(a−c)
    la = l0;
    lb = l1;
  }
  const double cos2 = dot > 0.0 ? dot * dot / (la * lb) : 0.0;
  return cos2 > bound_cos2;
}

// ==== triangles near small input angles begin here ===============================================

namespace {

constexpr VertexId kNoNeighbour = static_cast<VertexId>(-1);

// A constraint edge: a subsegment, or an edge of the domain's boundary.
inline bool is_constraint(const Mesh& mesh, Handle h) {
  return mesh.is_segment(h) || !mesh.in_domain(mesh.sym(h) >> 2);
}

// A split point: a Steiner vertex inside an input segment.
inline bool is_split_point(const Mesh& mesh, VertexId v) {
  return v < mesh.vertex_kind.size() && mesh.vertex_kind[v] == VertexKind::kSteinerOnSegment;
}

// The chains of subsegments through split points: the two chain neighbours of every split point (a
// split point lies inside one input segment: exactly two subsegments meet there).
struct SplitChains {
  const Mesh& mesh;
  std::vector<std::array<VertexId, 2>> along;

  explicit SplitChains(const Mesh& m) : mesh(m), along(m.points.size(), {kNoNeighbour, kNoNeighbour}) {}

  // Records w as a chain neighbour of v if v is a split point.
  void link(VertexId v, VertexId w) {
    if (!is_split_point(mesh, v)) return;
    auto& n = along[v];
    if (n[0] == w || n[1] == w) return;
    (n[0] == kNoNeighbour ? n[0] : n[1]) = w;
  }
  // Links the ends of every constraint edge of the domain; false if there is none.
  bool link_constraints() {
    bool any_constraint = false;
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      if (!mesh.in_domain(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (!is_constraint(mesh, h)) continue;
        any_constraint = true;
        link(mesh.org(h), mesh.dest(h));
        link(mesh.dest(h), mesh.org(h));
      }
    }
    return any_constraint;
  }
  // Follows the chain of subsegments from `from` through `next` to its far end (the first vertex
  // that is not a split point), appending the vertices after `from` to `out`; returns the far end.
  VertexId follow(VertexId from, VertexId next, std::vector<VertexId>& out) const {
    out.clear();
    VertexId previous = from, at = next;
    for (std::size_t steps = 0; steps <= mesh.points.size(); ++steps) {
      out.push_back(at);
      if (!is_split_point(mesh, at)) break;
      const auto& n = along[at];
      const VertexId ahead = n[0] == previous ? n[1] : n[0];
      if (ahead == kNoNeighbour) break;
      previous = at;
      at = ahead;
    }
    return out.back();
  }
};

// (vertex, wedge · 2 + side) for the chain vertices of every small wedge.
using WedgeLabels = std::vector<std::pair<VertexId, std::uint32_t>>;

// Marks the fan of every input angle under 60° (a wedge between two constraint chains at an input
// vertex, measured between the chains' far ends) in `near`, and labels the chains' vertices.
void mark_small_wedges(const Mesh& mesh, const SplitChains& chains, std::vector<std::uint8_t>& near,
                       WedgeLabels& labels) {
  const std::size_t slots = mesh.triangles.size();
  std::vector<VertexId> chain[2];
  std::uint32_t wedges = 0;
  std::vector<TriangleId> fan;
  for (TriangleId t = 0; t < slots; ++t) {
    if (!mesh.in_domain(t)) continue;
    for (unsigned k = 0; k < 3; ++k) {
      const VertexId j = mesh.triangles[t].v[k];
      if (is_split_point(mesh, j)) continue;
      const Handle first = make_handle(t, prev3(k));  // j → v[k+1]: the wedge starts on its left
      if (!is_constraint(mesh, first)) continue;
      // The fan of in-domain triangles around j, counter-clockwise from `first` to the next
      // constraint edge.
      fan.assign(1, t);
      Handle last = Mesh::lprev(first);  // v[k+2] → j
      while (!is_constraint(mesh, last) && fan.size() <= slots) {
        last = Mesh::lprev(mesh.sym(last));
        fan.push_back(last >> 2);
      }
      const VertexId a = chains.follow(j, mesh.dest(first), chain[0]);
      const VertexId b = chains.follow(j, mesh.org(last), chain[1]);
      const Point& pj = mesh.points[j];
      const double ux = mesh.points[a].x - pj.x, uy = mesh.points[a].y - pj.y;
      const double vx = mesh.points[b].x - pj.x, vy = mesh.points[b].y - pj.y;
      const double cross = ux * vy - uy * vx, dot = ux * vx + uy * vy;
      // Under 60°, counter-clockwise from a to b: cross > 0, cos > 1/2.
      if (!(cross > 0.0 && dot > 0.0 && dot * dot > 0.25 * (ux * ux + uy * uy) * (vx * vx + vy * vy))) continue;
      for (const TriangleId f : fan) near[f] = 1;
      for (unsigned side = 0; side < 2; ++side) {
        for (const VertexId v : chain[side]) labels.emplace_back(v, 2 * wedges + side);
      }
      ++wedges;
    }
  }
}

// Marks in `near` every triangle with a vertex on one side of a small wedge and another vertex on
// the other side of the same wedge (labels sorted).
void mark_across_wedges(const Mesh& mesh, const WedgeLabels& labels, std::vector<std::uint8_t>& near) {
  const auto labels_of = [&](VertexId v) {
    const auto lo = std::lower_bound(labels.begin(), labels.end(), std::pair<VertexId, std::uint32_t>{v, 0});
    auto hi = lo;
    while (hi != labels.end() && hi->first == v) ++hi;
    return std::pair{lo, hi};
  };
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (near[t] || !mesh.in_domain(t)) continue;
    const auto& v = mesh.triangles[t].v;
    for (unsigned k = 0; k < 3 && !near[t]; ++k) {
      const auto [lo, hi] = labels_of(v[k]);
      for (auto it = lo; it != hi && !near[t]; ++it) {
        const std::uint32_t other = it->second ^ 1u;
        for (unsigned m = 0; m < 3 && !near[t]; ++m) {
          if (m == k) continue;
          const auto [olo, ohi] = labels_of(v[m]);
          for (auto o = olo; o != ohi; ++o) {
            if (o->second == other) {
              near[t] = 1;
              break;
            }
          }
        }
      }
    }
  }
}

}  // namespace

// The triangles in the fan of a small input angle or spanning one (see mark_small_wedges and
// mark_across_wedges): the angle bound is exempt there.
std::vector<std::uint8_t> near_small_input_angles(const Mesh& mesh) {
  std::vector<std::uint8_t> near(mesh.triangles.size(), 0);
  SplitChains chains(mesh);
  if (!chains.link_constraints()) return near;
  WedgeLabels labels;
  mark_small_wedges(mesh, chains, near, labels);
  if (labels.empty()) return near;
  std::sort(labels.begin(), labels.end());
  mark_across_wedges(mesh, labels, near);
  return near;
}

// ==== triangles near small input angles end here =================================================

BoundCheck check_bounds(const Mesh& mesh, double min_angle_deg, double max_area) {
  BoundCheck r;
  const bool angle = min_angle_deg > 0.0;
  const double c = std::cos(std::max(0.0, min_angle_deg) * std::numbers::pi / 180.0);
  const double bound_cos2 = c * c;
  std::vector<std::uint8_t> near;
  bool near_known = false;
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (!mesh.in_domain(t)) continue;
    const auto& v = mesh.triangles[t].v;
    const Point &a = mesh.points[v[0]], &b = mesh.points[v[1]], &p = mesh.points[v[2]];
    const bool small = angle && below_angle_bound(a, b, p, bound_cos2);
    const bool large = max_area > 0.0 && triangle_area(a, b, p) > max_area;
    r.below_angle += small;
    r.above_area += large;
    if (!small && !large) continue;
    if (small && !large) {
      if (!near_known) {
        near = near_small_input_angles(mesh);
        near_known = true;
      }
      if (near[t]) {
        ++r.exempt;
        continue;
      }
    }
    ++r.violations;
  }
  return r;
}

}  // namespace mwst
