// src/geometry/constructions.cpp — rounded geometric constructions of mwst/geometry/geometry.hpp.
//
// Implements distance, squared_distance, midpoint, circumcenter, off_center, segment_intersection
// and signed_area. Results are rounded to double ("exact predicates, inexact constructions").
// Sources: circumcenter relative to a vertex with the denominator 2·orient2d computed robustly, as
// in J. R. Shewchuk's Triangle and "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates" (1997), whose expansion arithmetic (src/geometry/predicates.cpp) supplies
// that determinant; off-centers after A. Üngör, "Off-centers: A new type of Steiner points for
// computing size-optimal quality-guaranteed Delaunay triangulations", LATIN 2004 / CGTA 2009.
// Constructed Steiner points are passed through snap_to_range.

#include <algorithm>
#include <cmath>

#include "mwst/geometry/geometry.hpp"

namespace mwst {
namespace detail {
// Defined in predicates.cpp: the orient2d determinant of (a, b, c) computed exactly and rounded to
// double (within a few ulps). Its sign is exact; it is 0 only for collinear points.
double orient2d_value(const Point& a, const Point& b, const Point& c);
}  // namespace detail

namespace {
inline Point snapped(double x, double y) { return Point{snap_to_range(x), snap_to_range(y)}; }
}  // namespace

double squared_distance(const Point& a, const Point& b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

double distance(const Point& a, const Point& b) { return std::sqrt(squared_distance(a, b)); }

Point midpoint(const Point& a, const Point& b) {
  // One rounding (the halving is exact: no subnormals in the supported range).
  return snapped(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
}

Point circumcenter(const Point& a, const Point& b, const Point& c) {
  const double bx = b.x - a.x, by = b.y - a.y;
  const double cx = c.x - a.x, cy = c.y - a.y;
  const double blift = bx * bx + by * by;
  const double clift = cx * cx + cy * cy;
  // det [b-a, c-a] == orient2d(a, b, c); exact sign, never 0 for a non-degenerate triangle.
  const double inv = 0.5 / detail::orient2d_value(a, b, c);
  const double ux = (cy * blift - by * clift) * inv;
  const double uy = (bx * clift - cx * blift) * inv;
  return snapped(a.x + ux, a.y + uy);
}

Point off_center(const Point& p, const Point& q, const Point& circumcenter_pqr, double alpha,
                 double factor) {
  const Point& c = circumcenter_pqr;
  const double mx = 0.5 * (p.x + q.x), my = 0.5 * (p.y + q.y);
  const double ex = q.x - p.x, ey = q.y - p.y;
  const double len = std::sqrt(ex * ex + ey * ey);
  // Distance from m at which pq subtends the angle alpha: (|pq|/2)·cot(alpha/2), scaled by factor.
  const double d = factor * 0.5 * len / std::tan(0.5 * alpha);
  const double cmx = c.x - mx, cmy = c.y - my;
  const double mc = std::sqrt(cmx * cmx + cmy * cmy);
  if (!(d > 0.0) || !std::isfinite(d) || len == 0.0 || mc <= d) return c;
  // Unit normal of pq, pointing to the side of the circumcenter. c lies on the bisector, so the
  // normal is the exact direction of mc; using it rather than c - m keeps the apex angle accurate
  // even when c carries rounding error.
  double nx = -ey / len, ny = ex / len;
  const double side = nx * cmx + ny * cmy;
  if (side < 0.0) {
    nx = -nx;
    ny = -ny;
  } else if (side == 0.0) {  // numerically along pq: fall back to the direction of c
    nx = cmx / mc;
    ny = cmy / mc;
  }
  return snapped(mx + d * nx, my + d * ny);
}

Point segment_intersection(const Point& a, const Point& b, const Point& c, const Point& d) {
  // Parametrize the shorter segment (smaller absolute error) from its endpoint nearer to the
  // crossing. With o_a = orient(c, d, a) and o_b = orient(c, d, b) of opposite signs for a proper
  // crossing, t = o_a / (o_a - o_b) in [0, 1] has no cancellation; the orientations are computed
  // exactly and rounded once.
  const bool ab_shorter = squared_distance(a, b) <= squared_distance(c, d);
  const Point& p0 = ab_shorter ? a : c;
  const Point& p1 = ab_shorter ? b : d;
  const Point& s0 = ab_shorter ? c : a;
  const Point& s1 = ab_shorter ? d : b;
  const double o0 = detail::orient2d_value(s0, s1, p0);
  const double o1 = detail::orient2d_value(s0, s1, p1);
  const double denom = o0 - o1;
  double t = denom != 0.0 ? o0 / denom : 0.5;
  if (!(t >= 0.0)) t = 0.0;  // also catches NaN
  if (t > 1.0) t = 1.0;
  double x = 0.0, y = 0.0;
  if (t <= 0.5) {
    x = p0.x + t * (p1.x - p0.x);
    y = p0.y + t * (p1.y - p0.y);
  } else {
    const double u = 1.0 - t;
    x = p1.x + u * (p0.x - p1.x);
    y = p1.y + u * (p0.y - p1.y);
  }
  // The exact crossing lies in both bounding boxes; keep the rounded point there too.
  const double lox = std::max(std::min(a.x, b.x), std::min(c.x, d.x));
  const double hix = std::min(std::max(a.x, b.x), std::max(c.x, d.x));
  const double loy = std::max(std::min(a.y, b.y), std::min(c.y, d.y));
  const double hiy = std::min(std::max(a.y, b.y), std::max(c.y, d.y));
  if (lox <= hix) x = std::clamp(x, lox, hix);
  if (loy <= hiy) y = std::clamp(y, loy, hiy);
  return snapped(x, y);
}

double signed_area(const Point& a, const Point& b, const Point& c) {
  return 0.5 * detail::orient2d_value(a, b, c);
}

}  // namespace mwst
