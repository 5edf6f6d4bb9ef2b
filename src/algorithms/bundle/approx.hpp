// src/algorithms/bundle/approx.hpp — rounded values with rigorous error bounds, the currency of
// the bundle number's filters (internal).
//   Approx             — a double and a bound on its distance to the exact value
//   incircle_approx    — incircle determinant, rounded, with Shewchuk's first-stage bound
//   orient_approx      — orient2d, rounded, exact when the filter cannot vouch for its sign
#pragma once

#include <cmath>
#include <limits>

#include "geometry/expansion.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst::bundle {

inline constexpr double kEps = detail::kEpsilon;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

struct Approx {
  double value = 0.0;
  double error = 0.0;  // |value − exact| ≤ error
};

// The incircle determinant of geometry.hpp (positive inside the circle through the
// counter-clockwise a, b, c), rounded, with Shewchuk's first-stage error bound. As a function of d
// it equals orient(a, b, c) · (r² − |d − centre|²).
inline Approx incircle_approx(const Point& a, const Point& b, const Point& c, const Point& d) {
  const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, c, d);
  return {det.value, det.bound};
}

// The orient2d determinant of (a, b, c), rounded, with an error bound; recomputed exactly (and
// rounded once) when the filter cannot vouch for its sign.
inline Approx orient_approx(const Point& a, const Point& b, const Point& c) {
  const double l = (a.x - c.x) * (b.y - c.y);
  const double r = (a.y - c.y) * (b.x - c.x);
  const double det = l - r;
  const double bound = detail::kOrientBound * (std::fabs(l) + std::fabs(r));
  if (std::fabs(det) > bound) return {det, bound};
  using namespace exact;
  const auto e = difference(a.x, c.x) * difference(b.y, c.y) - difference(a.y, c.y) * difference(b.x, c.x);
  const double v = estimate(e);
  return {v, 4.0 * kEps * std::fabs(v)};
}

}  // namespace mwst::bundle
