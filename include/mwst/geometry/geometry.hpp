// mwst/geometry/geometry.hpp — points, exact predicates and rounded constructions.
//
// Predicates follow Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates" (1997): a floating-point filter with his first-stage error bounds decides
// almost every call inline; the rest go to an exact stage (expansion arithmetic) in
// src/geometry/predicates.cpp. The sign returned is never wrong for coordinates in the supported
// range below. Everything that includes this header must be compiled with -ffp-contract=off.
//
// Constructions (circumcenter, off-center, split points, intersections) are rounded once to double;
// every predicate on their result is exact again ("exact predicates, inexact constructions").
#pragma once

#include <cmath>
#include <cstdint>

#include "mwst/export.hpp"

namespace mwst {

struct Point {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point&, const Point&) = default;
};

// Supported coordinate range: every coordinate is 0 or has magnitude in
// [kMinCoordinate, kMaxCoordinate]. Within it, no product formed by the exact stage of incircle
// (degree 4 in coordinate differences) overflows or underflows, so the signs are exact. Input
// outside it is rejected with an error (we do not rescale silently); constructed Steiner points
// with a coordinate below kMinCoordinate in magnitude are snapped to 0 (see snap_to_range).
inline constexpr double kMaxCoordinate = 1e50;
inline constexpr double kMinCoordinate = 1e-50;

// True iff v is a finite double that is 0 or lies in the supported magnitude range.
inline bool in_supported_range(double v) {
  const double a = std::fabs(v);
  return a == 0.0 || (a >= kMinCoordinate && a <= kMaxCoordinate);
}
inline bool in_supported_range(const Point& p) {
  return in_supported_range(p.x) && in_supported_range(p.y);
}
// Rounds a constructed coordinate into the supported range (tiny magnitudes become 0).
inline double snap_to_range(double v) { return std::fabs(v) < kMinCoordinate ? 0.0 : v; }

namespace detail {
// Exact stages; called only when the filter cannot decide. Return the sign of the determinant.
MWST_API int orient2d_exact(const Point& a, const Point& b, const Point& c);
MWST_API int incircle_exact(const Point& a, const Point& b, const Point& c, const Point& d);
inline constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: the unit roundoff
inline constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
inline constexpr double kIncircleBound = (10.0 + 96.0 * kEpsilon) * kEpsilon;
}  // namespace detail

// Sign of the signed area of (a, b, c): +1 if c lies left of the directed line a→b (a, b, c
// counter-clockwise), -1 if right, 0 if the three points are collinear. Exact.
inline int orient2d(const Point& a, const Point& b, const Point& c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right;
  const double bound = detail::kOrientBound * (std::fabs(left) + std::fabs(right));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return detail::orient2d_exact(a, b, c);
}

// For a, b, c in counter-clockwise order: +1 if d lies strictly inside their circumcircle, -1 if
// strictly outside, 0 if the four points are cocircular. (The sign flips if a, b, c are clockwise;
// it is 0 whenever a, b, c are collinear and d is on their line.) Exact.
namespace detail {
// The incircle determinant rounded to double, with Shewchuk's first-stage bound on its error: the
// sign of `value` is exact whenever |value| > bound. (Shared by incircle and by the bundle sweep,
// which also needs the value itself.)
struct FilteredDeterminant {
  double value;
  double bound;
};
inline FilteredDeterminant incircle_determinant(const Point& a, const Point& b, const Point& c,
                                                const Point& d) {
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double alift = adx * adx + ady * ady;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double blift = bdx * bdx + bdy * bdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  return {det, kIncircleBound * permanent};
}
}  // namespace detail

inline int incircle(const Point& a, const Point& b, const Point& c, const Point& d) {
  const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, c, d);
  if (det.value > det.bound) return 1;
  if (-det.value > det.bound) return -1;
  return detail::incircle_exact(a, b, c, d);
}

// Exact comparison of squared distances: sign of |a-b|² − |c-d|² (used by weight-reducing flips
// and shortest-edge tests, where near-ties must not be decided by rounding).
MWST_API int compare_squared_lengths(const Point& a, const Point& b, const Point& c, const Point& d);

// Exact test: does p lie in the closed diametral disk of segment ab? Returns +1 strictly inside,
// 0 on the circle, -1 outside. (Sign of −(p−a)·(p−b).)
MWST_API int in_diametral_circle(const Point& a, const Point& b, const Point& p);

// ---- constructions (rounded) -------------------------------------------------------------------

MWST_API double distance(const Point& a, const Point& b);
MWST_API double squared_distance(const Point& a, const Point& b);
MWST_API Point midpoint(const Point& a, const Point& b);

// Circumcenter of a non-degenerate triangle, computed relative to a for accuracy.
MWST_API Point circumcenter(const Point& a, const Point& b, const Point& c);

// Üngör's off-center of triangle (a, b, c) whose shortest edge is pq (p, q two of its corners):
// the point on the perpendicular bisector of pq, on the side of the circumcenter, at distance
// factor·(|pq|/2)·cot(alpha/2) from the midpoint of pq — unless the circumcenter is closer, in
// which case the circumcenter. alpha is the target minimum angle in radians.
MWST_API Point off_center(const Point& p, const Point& q, const Point& circumcenter_pqr, double alpha,
                 double factor);

// Intersection point of the segments ab and cd, which must properly cross (rounded).
MWST_API Point segment_intersection(const Point& a, const Point& b, const Point& c, const Point& d);

// The crossing point of the segments ab and cd, which must properly cross, each coordinate the
// exact intersection rounded to the nearest double (rational arithmetic; src/mesh/constrain.cpp):
// on both segments within rounding. Unlike segment_intersection it is not snapped into the
// supported range: a coordinate may fall between 0 and kMinCoordinate in magnitude, and the caller
// decides what that means (the CDT refuses the input, qtr falls back to it).
MWST_API Point exact_crossing(const Point& a, const Point& b, const Point& c, const Point& d);

// Signed area of triangle (a, b, c) (rounded; positive when counter-clockwise).
MWST_API double signed_area(const Point& a, const Point& b, const Point& c);

// The area an area bound (max_area) is tested and reported with: ½ (b − a) × (c − a) in plain
// double arithmetic (a few ulps from signed_area's accurate rounding, and cheap), taken from the
// corner that is least in (x, y) order, so that it does not depend on which corner a caller
// names first (a move checks a triangle in one rotation, measure() reads it in another).
// Refinement, the flips, the optimiser and measure() all use this one, so a mesh that keeps the
// bound reports a largest triangle within it.
inline double triangle_area(const Point& a, const Point& b, const Point& c) {
  const auto less = [](const Point& p, const Point& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); };
  const auto area_from = [](const Point& p, const Point& q, const Point& r) {
    return 0.5 * ((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x));
  };
  if (less(a, b) && less(a, c)) return area_from(a, b, c);
  if (less(b, c)) return area_from(b, c, a);
  return area_from(c, a, b);
}

}  // namespace mwst
