// src/algorithms/bundle/circle_predicates.hpp — the exact circle tests of the bundle number
// (internal). Each is a sign: filtered first, then exact (expansions or GMP integers).
//   detail::enters_circle               — does the edge u→w enter the circle through p, q, u? (the
//                                         sweep's tangency test; exposed for the tests)
//   segment_meets_open_circumdisk       — does an edge cross a circumdisk between two corners
//                                         outside it? (filtered, then exact)
//   circumdisk_may_meet                 — permissive: might a circumdisk meet a triangle?
#pragma once

#include "algorithms/bundle/approx.hpp"
#include "mwst/export.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst {

namespace detail {
// Does the segment from u towards w, at u, enter the open disk bounded by the circle through p, q
// and u? +1 enters, −1 leaves, 0 tangent. `orient_pqu` = orient2d(p, q, u) ≠ 0. With p' = p − u,
// q' = q − u, e = w − u, the centre of that circle is u + c' with
// c' · 2 cross(p', q') = |p'|² (q'⊥) − |q'|² (p'⊥), so the sign of e · c' is the sign of
// (|p'|² cross(e, q') − |q'|² cross(e, p')) · orient(p, q, u): the incircle determinant without
// its |e|² term (its derivative at u). Filtered (first stage: incircle's bound; second: the four
// factors rounded with rigorous bounds), then exact.
MWST_API int enters_circle(const Point& p, const Point& q, const Point& u, const Point& w, int orient_pqu);
}  // namespace detail

namespace bundle {

// Does the open segment u→w meet the open disk bounded by the circle through the
// counter-clockwise a, b, c, given that u and w lie strictly outside that circle? Along
// x = u + λ(w − u) the incircle determinant is the concave quadratic
//   g(λ) = g_u + S λ − C λ²,  C = orient(a, b, c) · |w − u|² > 0,  S = g_w − g_u + C = g'(0),
// so the segment meets the disk iff the top of the parabola lies inside (0, 1) — g'(0) = S > 0 and
// g'(1) = S − 2C < 0 — and is positive there: S² + 4 C g_u > 0 (g_u < 0). That is a polynomial of
// degree 8 in the coordinates. Its rounded value is useless for the flat Delaunay triangles of
// nearly collinear hull vertices (circles of radius 10¹⁷ around a unit mesh: S and C are smaller
// than the rounding of g_u and g_w), so each of the three signs is decided from a rigorous forward
// error bound when it can be and otherwise exactly, in integers (GMP): every coordinate is an
// integer multiple of 2^E for the smallest exponent E among them, so the polynomial is evaluated
// on integers without rounding, overflow or underflow anywhere in the supported range.
bool segment_meets_open_circumdisk_exact(const Point& a, const Point& b, const Point& c, const Point& u,
                                         const Point& w);

// The same question, filtered: rounded values with rigorous error bounds decide when they can;
// +1 meets, 0 does not, −1 undecided. Also right when u or w lies on the circle (g ≤ 0 at both
// ends: then g(1) = S − C ≤ 0 rules out S ≥ 2C, and the three conditions still say whether g is
// positive somewhere inside).
int segment_meets_open_circumdisk_filtered(const Point& a, const Point& b, const Point& c, const Point& u,
                                           const Point& w);

// Exact: the filter, then integers.
inline bool segment_meets_open_circumdisk(const Point& a, const Point& b, const Point& c, const Point& u,
                                          const Point& w) {
  const int filtered = segment_meets_open_circumdisk_filtered(a, b, c, u, w);
  return filtered >= 0 ? filtered == 1 : segment_meets_open_circumdisk_exact(a, b, c, u, w);
}

// Permissive: true whenever the open circumdisk of the counter-clockwise a, b, c might meet the
// interior of the triangle x[0], x[1], x[2] (never false when it does). If it meets the interior
// and holds no corner, it meets an edge (a disk cannot lie inside a mesh triangle with its three
// defining vertices on the triangle's boundary, and a convex corner meeting the disk near a corner
// on the circle has an edge entering it); along an edge the incircle value is a concave
// quadratic, bounded as in Worker::edge_may_meet.
bool circumdisk_may_meet(const Point& a, const Point& b, const Point& c, const Point* const x[3]);

}  // namespace bundle

}  // namespace mwst
