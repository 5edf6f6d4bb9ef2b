// src/algorithms/optimize/region.hpp — the polygons the optimiser re-triangulates (a vertex's star,
// a few triangles around one) and the geometry of a star from one point: its spokes' length, the
// geometric median that minimises it, and the kernel test. Internal (not installed); the small
// routines are inline because the local search calls them for every vertex and region it tries.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mwst/algorithms/flip.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::opt {

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

// True if a triangulation `tris` (corner indices into a polygon of `ids.size()` corners whose edge
// i → i+1 is a subsegment iff edge_is_segment(i)) has a triangle cornered at a Steiner point on a
// segment with both of its sides there being the polygon's subsegments. The two subsegments are
// straight in truth (the rounded point only looks convex or reflex), so that triangle would be a
// sliver lying along the segment, with its third side on the segment too: refused everywhere the
// optimiser retriangulates a polygon (the same rule as flip.cpp's flippable).
template <class EdgeIsSegment>
bool spans_straight_angle(const Mesh& m, const std::vector<VertexId>& ids, EdgeIsSegment edge_is_segment,
                          const std::vector<std::array<std::uint32_t, 3>>& tris) {
  const std::size_t d = ids.size();
  for (const auto& tri : tris) {
    for (unsigned k = 0; k < 3; ++k) {
      const std::size_t j = tri[k], a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
      const std::size_t before = (j + d - 1) % d, after = (j + 1) % d;
      const bool both_sides_on_boundary = (a == before && b == after) || (a == after && b == before);
      if (both_sides_on_boundary && is_straight_corner(m, ids[j], edge_is_segment(before), edge_is_segment(j))) {
        return true;
      }
    }
  }
  return false;
}

// Replaces the region's triangles by `tris` (vertex triples, counter-clockwise, covering the same
// polygon, using only boundary vertices and possibly one new vertex), reusing slots.
// `flags`, when given, holds each new triangle's flag (kOutside or 0) instead of r.outside_flag.
void replace_region(Mesh& m, const Region& r, const std::vector<std::array<VertexId, 3>>& tris,
                    const std::vector<std::uint8_t>* flags = nullptr);

// The star of vertex v (h has org v): its neighbours counter-clockwise and its triangles. False if
// it meets a ghost or dead triangle.
bool star_of(const Mesh& m, Handle h, Region& r);

inline double spoke_sum(const Point& p, const std::vector<Point>& nb) {
  double s = 0.0;
  for (const Point& q : nb) s += distance(p, q);
  return s;
}

// Weiszfeld's iteration for the geometric median of `nb`, from `start`.
inline Point geometric_median(Point p, const std::vector<Point>& nb) {
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

// Is p strictly inside the kernel of the closed polygon (all fan triangles counter-clockwise), and
// clear of every polygon edge's line by a margin far above the rounding of constructed points?
// (A free Steiner point a few ulps from a segment would be taken for a point on it by any
// tolerant checker, and makes needle triangles.)
inline bool in_kernel(const Point& p, const std::vector<Point>& polygon) {
  const std::size_t d = polygon.size();
  constexpr double kMargin = 1e-9;  // times the coordinate magnitude
  for (std::size_t i = 0; i < d; ++i) {
    const Point& a = polygon[i];
    const Point& b = polygon[(i + 1) % d];
    if (orient2d(p, a, b) <= 0) return false;
    const double scale = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(b.x), std::fabs(b.y), std::fabs(p.x),
                                   std::fabs(p.y)});
    const double dx = b.x - a.x, dy = b.y - a.y;
    if (dx * (p.y - a.y) - dy * (p.x - a.x) <= kMargin * scale * std::hypot(dx, dy)) return false;
  }
  return true;
}

}  // namespace mwst::opt
