// validate(): the mesh's self-check, run by the tests after every phase of every algorithm.
// Topology (reciprocal neighbours, Euler count of the closed triangulation), geometry (exact
// orientation, convex hull), segment bookkeeping, and the Delaunay / angle properties when claimed.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_set>

#include "mwst/mesh/mesh.hpp"

namespace mwst {

namespace {

// "edge a->b of triangle t", for the problem reports.
std::string handle_name(const Mesh& m, Handle h) {
  auto vname = [](VertexId v) { return v == kInfinite ? std::string("inf") : std::to_string(v); };
  return "edge " + vname(m.org(h)) + "->" + vname(m.dest(h)) + " of triangle " +
         std::to_string(h >> 2);
}

// Smallest angle (degrees) of a real triangle.
double min_angle_deg(const Point& a, const Point& b, const Point& c) {
  const double la = std::hypot(b.x - c.x, b.y - c.y);
  const double lb = std::hypot(c.x - a.x, c.y - a.y);
  const double lc = std::hypot(a.x - b.x, a.y - b.y);
  // The smallest angle is opposite the shortest side; law of cosines in a stable form.
  double s1 = la, s2 = lb, s3 = lc;  // s1 shortest
  if (s2 < s1) std::swap(s1, s2);
  if (s3 < s1) std::swap(s1, s3);
  const double cosine = std::clamp((s2 * s2 + s3 * s3 - s1 * s1) / (2.0 * s2 * s3), -1.0, 1.0);
  return std::acos(cosine) * 180.0 / std::numbers::pi;
}

// The problems found, the first 50 of them.
struct Problems {
  std::vector<std::string> list;
  void report(std::string s) {
    if (list.size() < 50) list.push_back(std::move(s));
  }
};

// Checks the corners of live triangle t and marks its finite vertices used. Returns the number of
// infinite corners, or -1 if a corner names a vertex that does not exist (validation stops there).
int check_corners(const Mesh& m, TriangleId t, std::vector<char>& used, Problems& problems) {
  const Triangle& T = m.triangles[t];
  int infinite = 0;
  for (unsigned k = 0; k < 3; ++k) {
    if (T.v[k] == kInfinite) {
      ++infinite;
    } else if (T.v[k] >= m.points.size()) {
      problems.report("triangle " + std::to_string(t) + " names vertex " + std::to_string(T.v[k]) +
                      " which does not exist");
      return -1;
    } else {
      used[T.v[k]] = 1;
    }
  }
  if (infinite > 1) problems.report("triangle " + std::to_string(t) + " has two infinite corners");
  if (T.v[0] == T.v[1] || T.v[1] == T.v[2] || T.v[0] == T.v[2]) {
    problems.report("triangle " + std::to_string(t) + " repeats a vertex");
  }
  return infinite;
}

// Checks the neighbour links of live triangle t: each is live, reciprocal, shares the edge and
// carries the same segment mark on both sides.
void check_neighbours(const Mesh& m, TriangleId t, Problems& problems) {
  const std::size_t slots = m.triangles.size();
  for (unsigned e = 0; e < 3; ++e) {
    const Handle h = make_handle(t, e);
    const Handle s = m.triangles[t].n[e];
    if (s == kNone || (s >> 2) >= slots || (s & 3) == 3 || m.is_dead(s >> 2)) {
      problems.report(handle_name(m, h) + " has no live neighbour");
      continue;
    }
    if (m.sym(s) != h) problems.report(handle_name(m, h) + ": neighbour link is not reciprocal");
    if (m.org(s) != m.dest(h) || m.dest(s) != m.org(h)) {
      problems.report(handle_name(m, h) + ": neighbour does not share the edge");
    }
    if (m.is_segment(h) != m.is_segment(s)) {
      problems.report(handle_name(m, h) + ": segment flag differs between its two sides");
    } else if (m.is_segment(h) && m.marker(h) != m.marker(s)) {
      problems.report(handle_name(m, h) + ": segment marker differs between its two sides");
    }
  }
}

// Checks the geometry of live triangle t with `infinite` infinite corners: a real triangle is
// counter-clockwise (exactly); at a ghost's second finite corner the hull is convex.
void check_orientation(const Mesh& m, TriangleId t, int infinite, Problems& problems) {
  const Triangle& T = m.triangles[t];
  if (infinite == 0) {
    if (orient2d(m.points[T.v[0]], m.points[T.v[1]], m.points[T.v[2]]) <= 0) {
      problems.report("triangle " + std::to_string(t) + " is not counter-clockwise (or degenerate)");
    }
  } else if (infinite == 1) {
    // Hull convexity at the ghost's second finite corner b: the next hull vertex c must not be
    // strictly outside the hull edge a→b.
    unsigned k = 0;
    while (T.v[k] != kInfinite) ++k;
    const VertexId a = T.v[next3(k)], b = T.v[prev3(k)];
    const Handle next_ghost_edge = m.sym(make_handle(t, next3(k)));  // edge b→∞ seen from next ghost
    if (next_ghost_edge != kNone && !m.is_dead(next_ghost_edge >> 2)) {
      const VertexId c = m.apex(next_ghost_edge);
      if (c != kInfinite && c < m.points.size() && orient2d(m.points[a], m.points[b], m.points[c]) > 0) {
        problems.report("convex hull is not convex at vertex " + std::to_string(b));
      }
    }
  }
}

// Euler: the triangulation with the infinite vertex is a sphere: V − E + F = 2, E = 3F/2. And
// every vertex that is neither a duplicate nor removed is in a triangle.
void check_euler_count(const Mesh& m, const std::vector<char>& used, std::size_t faces, Problems& problems) {
  std::size_t vertices = 1;  // the infinite vertex
  for (char u : used) vertices += u ? 1 : 0;
  if (faces % 2 != 0 || vertices != 2 + faces / 2) {
    problems.report("Euler count fails: V=" + std::to_string(vertices) + " (with infinity), F=" +
                    std::to_string(faces));
  }
  for (VertexId v = 0; v < m.points.size(); ++v) {
    if (!used[v] && v < m.vertex_kind.size() && m.vertex_kind[v] != VertexKind::kDuplicate &&
        m.vertex_kind[v] != VertexKind::kRemoved) {
      problems.report("vertex " + std::to_string(v) + " is in no triangle");
    }
  }
}

// Every unconstrained edge between two real triangles is locally Delaunay.
void check_delaunay(const Mesh& m, Problems& problems) {
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (m.is_segment(h) || m.apex(h) == kInfinite) continue;
      if (m.is_locally_non_delaunay(h)) problems.report(handle_name(m, h) + " is not locally Delaunay");
    }
  }
}

// Every triangle of the domain has all its angles at least min_angle_deg degrees.
void check_min_angle(const Mesh& m, double min_angle, Problems& problems) {
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    const Triangle& T = m.triangles[t];
    const double a = min_angle_deg(m.points[T.v[0]], m.points[T.v[1]], m.points[T.v[2]]);
    if (a < min_angle) {
      problems.report("triangle " + std::to_string(t) + " has an angle of " + std::to_string(a) +
                      " degrees, below " + std::to_string(min_angle));
    }
  }
}

}  // namespace

// The checks in order: the flags array's size, then per live triangle its corners, neighbour links
// and orientation, then the Euler count, and the Delaunay and angle properties when claimed.
std::vector<std::string> validate(const Mesh& m, const ValidateOptions& options) {
  Problems problems;
  const std::size_t slots = m.triangles.size();
  if (m.flags.size() != slots) {
    problems.report("flags array has " + std::to_string(m.flags.size()) + " entries for " +
                    std::to_string(slots) + " triangles");
    return problems.list;
  }
  std::size_t faces = 0;
  std::vector<char> used(m.points.size(), 0);
  for (TriangleId t = 0; t < slots; ++t) {
    if (m.is_dead(t)) continue;
    ++faces;
    const int infinite = check_corners(m, t, used, problems);
    if (infinite < 0) return problems.list;
    check_neighbours(m, t, problems);
    check_orientation(m, t, infinite, problems);
  }
  check_euler_count(m, used, faces, problems);
  if (options.delaunay) check_delaunay(m, problems);
  if (options.min_angle_deg > 0.0) check_min_angle(m, options.min_angle_deg, problems);
  return problems.list;
}

}  // namespace mwst
