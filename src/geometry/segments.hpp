// src/geometry/segments.hpp — exact tests on closed segments and on the chords of a simple polygon,
// built on the exact orient2d (geometry.hpp). Internal (not installed); inline, because the polygon
// dynamic programs (algorithms/mwt/polygon_mwt.cpp, algorithms/quadtree/quadtree_cells.cpp) run
// them O(d³) times per polygon.
#pragma once

#include <algorithm>
#include <cstddef>

#include "mwst/geometry/geometry.hpp"

namespace mwst {

// Do the closed segments pq and rs share a point (exact)? A proper crossing, or one endpoint on
// the other segment: when that endpoint is collinear with it, the bounding-box test is exact.
inline bool segments_intersect(const Point& p, const Point& q, const Point& r, const Point& s) {
  const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s);
  const int o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  auto on_segment = [](const Point& a, const Point& b, const Point& x) {
    return std::min(a.x, b.x) <= x.x && x.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= x.y &&
           x.y <= std::max(a.y, b.y);
  };
  if (o1 == 0 && on_segment(p, q, r)) return true;
  if (o2 == 0 && on_segment(p, q, s)) return true;
  if (o3 == 0 && on_segment(r, s, p)) return true;
  if (o4 == 0 && on_segment(r, s, q)) return true;
  return false;
}

// Does the segment from corner i of the closed polygon P (d corners, counter-clockwise) towards
// the point x leave i into the polygon's interior angle (strictly)? O'Rourke, "Computational
// Geometry in C", 2nd ed., section 1.6, InCone. `Polygon` is anything indexable by corner.
template <class Polygon>
inline bool in_cone(const Polygon& P, std::size_t d, std::size_t i, const Point& x) {
  const Point& prev = P[i == 0 ? d - 1 : i - 1];
  const Point& cur = P[i];
  const Point& next = P[i + 1 == d ? 0 : i + 1];
  if (orient2d(prev, cur, next) >= 0) {  // convex (or straight) corner
    return orient2d(cur, x, prev) > 0 && orient2d(x, cur, next) > 0;
  }
  return !(orient2d(cur, x, next) >= 0 && orient2d(x, cur, prev) >= 0);
}

// Is the chord between corners i and j (not neighbours) a diagonal of the simple polygon P: inside
// it at both ends (in_cone), and touching no polygon edge other than those at i and j? A chord
// through another corner touches that corner's edges, one of which is incident to neither i nor j
// unless the corner is the only one between them, where the cone test catches it (O'Rourke's
// Diagonal, section 1.6).
template <class Polygon>
inline bool is_polygon_diagonal(const Polygon& P, std::size_t d, std::size_t i, std::size_t j) {
  if (!in_cone(P, d, i, P[j]) || !in_cone(P, d, j, P[i])) return false;
  for (std::size_t k = 0; k < d; ++k) {
    const std::size_t k1 = k + 1 == d ? 0 : k + 1;
    if (k == i || k == j || k1 == i || k1 == j) continue;
    if (segments_intersect(P[i], P[j], P[k], P[k1])) return false;
  }
  return true;
}

}  // namespace mwst
