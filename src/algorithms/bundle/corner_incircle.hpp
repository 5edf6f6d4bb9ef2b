// src/algorithms/bundle/corner_incircle.hpp — the incircle determinant of a small circle at a far
// point, rounded with a rigorous bound (internal): what the permissive floods of the bundle number
// and of in_k_bundle's first stage fall back on when incircle's own filter cannot vouch.
//   CornerCircle           — a circle through a, b, c, kept as its corner a and 2O·(centre − a)
//   corner_incircle        — the determinant at d from that form, with its error bound
//   incircle_from_either   — incircle's filter, then (undecided) the corner form
//
// Why: incircle(a, b, c, d) is evaluated from the differences to d, so its rounding error grows
// with |d − a|³·|b − a| while the value is O·(r² − |d − centre|²) with O = orient(a, b, c). For a
// sliver of a few micrometres (two corners 10⁻¹⁰ apart, as on the shells of segment points at the
// apex of a fan of narrow wedges) and a vertex at distance 1 the filter cannot give the sign, and a
// permissive flood then crosses every edge with such an end: on a fan of 10,000 vertices the floods
// of disks meeting 7 triangles popped 45,000 each, most of the first exact test's time.
#pragma once

#include <cmath>

#include "algorithms/bundle/approx.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst::bundle {

namespace corner_detail {
// Rounded arithmetic with forward error bounds: |x·y − x̃·ỹ| ≤ |x̃|δy + |ỹ|δx + δxδy, and each
// operation's own rounding at most 2ε of its result (ε the unit roundoff: a margin of 2).
inline Approx mul(const Approx& x, const Approx& y) {
  const double v = x.value * y.value;
  return {v, std::fabs(x.value) * y.error + std::fabs(y.value) * x.error + x.error * y.error + 2.0 * kEps * std::fabs(v)};
}
inline Approx add(const Approx& x, const Approx& y) {
  const double v = x.value + y.value;
  return {v, x.error + y.error + 2.0 * kEps * std::fabs(v)};
}
inline Approx sub(const Approx& x, const Approx& y) {
  const double v = x.value - y.value;
  return {v, x.error + y.error + 2.0 * kEps * std::fabs(v)};
}
inline Approx diff(double x, double y) {
  const double v = x - y;
  return {v, 2.0 * kEps * std::fabs(v)};
}
}  // namespace corner_detail

// The circle through a, b, c as seen from its corner a: with B = b − a, C = c − a,
// O = orient(a, b, c) = cross(B, C) and Y = 2O·(centre − a) = (C_y|B|² − B_y|C|², B_x|C|² − C_x|B|²),
// the incircle determinant at d is O·(r² − |d − centre|²) = D·Y − O|D|² with D = d − a (r² = |centre − a|²).
// Every term is of the size of the circle times |D|, not of |D|³: the form stays accurate for a
// small circle and a far d, where the differences to d cancel.
struct CornerCircle {
  Point a;
  Approx o, yx, yy;
};

inline CornerCircle corner_circle(const Point& a, const Point& b, const Point& c) {
  using namespace corner_detail;
  const Approx bx = diff(b.x, a.x), by = diff(b.y, a.y), cx = diff(c.x, a.x), cy = diff(c.y, a.y);
  const Approx b2 = add(mul(bx, bx), mul(by, by)), c2 = add(mul(cx, cx), mul(cy, cy));
  return {a, sub(mul(bx, cy), mul(by, cx)), sub(mul(cy, b2), mul(by, c2)), sub(mul(bx, c2), mul(cx, b2))};
}

// The incircle determinant of d against `circle` (the same value as incircle's, positive inside a
// counter-clockwise circle), rounded, with a rigorous bound on its error (doubled; infinite when a
// value is not finite or is near the subnormal range, where bounds relative to values fail).
inline Approx corner_incircle(const CornerCircle& circle, const Point& d) {
  using namespace corner_detail;
  const Approx dx = diff(d.x, circle.a.x), dy = diff(d.y, circle.a.y);
  const Approx g = sub(add(mul(dx, circle.yx), mul(dy, circle.yy)), mul(circle.o, add(mul(dx, dx), mul(dy, dy))));
  const double bound = 2.0 * g.error + 1e-280;
  if (!std::isfinite(g.value) || !std::isfinite(bound)) return {0.0, kInf};
  return {g.value, bound};
}

// incircle's filter (the rounded determinant with Shewchuk's bound); when it cannot vouch for the
// sign, the corner form if that can. Either value carries a rigorous bound: a permissive test
// reading it never rules out a point of the disk.
inline Approx incircle_from_either(const Point& a, const Point& b, const Point& c, const Point& d,
                                   const CornerCircle& circle) {
  const Approx g = incircle_approx(a, b, c, d);
  if (std::fabs(g.value) > g.error) return g;
  const Approx h = corner_incircle(circle, d);
  return std::fabs(h.value) > h.error ? h : g;
}

}  // namespace mwst::bundle
