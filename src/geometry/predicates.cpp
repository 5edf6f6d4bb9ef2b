// src/geometry/predicates.cpp — exact stages of the geometric predicates of mwst/geometry.hpp.
//
// Implements detail::orient2d_exact, detail::incircle_exact, compare_squared_lengths,
// in_diametral_circle and the internal detail::orient2d_value (an accurate rounding of the
// orient2d determinant, used by the constructions). Technique: floating-point expansion arithmetic
// after J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", Discrete & Computational Geometry 18:305–363, 1997 (error-free transformations
// Two-Sum / Fast-Two-Sum / Two-Product, Grow-Expansion, Fast-Expansion-Sum and Scale-Expansion with
// zero elimination). Written from the paper's theorems; no code is taken from his predicates.c.
//
// Why the result is exact in the supported range (coordinates 0 or of magnitude in [1e-50, 1e50]):
// every such coordinate is an integer multiple of 2^-219 (the ulp of 1e-50), so every coordinate
// difference and every component produced by an error-free transformation on degree-k quantities is
// an integer multiple of 2^(-219k) >= 2^-876 > 2^-1074 (incircle has degree 4): no operation
// underflows, and every product stays far below overflow (|value| <= ~1e203). In that regime the
// transformations below are exact, so the expansions hold the exact value of the determinant, and
// the sign of a nonoverlapping expansion is the sign of its largest component.
//
// The whole file must be compiled with -ffp-contract=off (a contracted a*b-c would break the
// Dekker form of Two-Product and the filter bounds), and in round-to-nearest-even.

#include <cmath>
#include <cstddef>
#include <cstring>

#include "geometry/expansion.hpp"
#include "mwst/geometry.hpp"

namespace mwst {
namespace detail {
// Internal (not in the public header): the orient2d determinant of (a, b, c), computed exactly and
// then rounded to double (within a few ulps; exact sign, 0 only if collinear). Used by
// constructions.cpp, which repeats this declaration.
double orient2d_value(const Point& a, const Point& b, const Point& c);
}  // namespace detail

namespace {

using namespace exact;

// Exact orient2d determinant (a.x-c.x)(b.y-c.y) - (a.y-c.y)(b.x-c.x), up to 16 components.
inline Expansion<16> orient2d_expansion(const Point& a, const Point& b, const Point& c) {
  const Expansion<2> acx = difference(a.x, c.x), bcx = difference(b.x, c.x);
  const Expansion<2> acy = difference(a.y, c.y), bcy = difference(b.y, c.y);
  return acx * bcy - acy * bcx;
}

}  // namespace

namespace detail {

int orient2d_exact(const Point& a, const Point& b, const Point& c) {
  return sign_of(orient2d_expansion(a, b, c));
}

double orient2d_value(const Point& a, const Point& b, const Point& c) {
  return estimate(orient2d_expansion(a, b, c));
}

int incircle_exact(const Point& a, const Point& b, const Point& c, const Point& d) {
  // det [[adx, ady, adx²+ady²], [bdx, bdy, ...], [cdx, cdy, ...]] with the differences kept exact
  // as (at most) two-component expansions. When the differences are exact (the usual case for
  // nearby points) every factor has one component and the expansions stay short.
  const Expansion<2> adx = difference(a.x, d.x), ady = difference(a.y, d.y);
  const Expansion<2> bdx = difference(b.x, d.x), bdy = difference(b.y, d.y);
  const Expansion<2> cdx = difference(c.x, d.x), cdy = difference(c.y, d.y);

  Expansion<16> bc = bdx * cdy - cdx * bdy;
  Expansion<16> ca = cdx * ady - adx * cdy;
  Expansion<16> ab = adx * bdy - bdx * ady;
  Expansion<16> alift = adx * adx + ady * ady;
  Expansion<16> blift = bdx * bdx + bdy * bdy;
  Expansion<16> clift = cdx * cdx + cdy * cdy;
  // Renormalize the factors before the expensive products.
  compress(bc);
  compress(ca);
  compress(ab);
  compress(alift);
  compress(blift);
  compress(clift);

  const Expansion<512> aterm = alift * bc;
  const Expansion<512> bterm = blift * ca;
  const Expansion<512> cterm = clift * ab;
  const Expansion<1024> abterm = aterm + bterm;
  const Expansion<1536> det = abterm + cterm;
  return sign_of(det);
}

}  // namespace detail

int compare_squared_lengths(const Point& a, const Point& b, const Point& c, const Point& d) {
  // Filter. Each computed squared length is l·(1+θ) with |θ| <= (1+ε)^4 - 1 (difference, square,
  // sum), both nonnegative; the final subtraction adds ε. The error of l1 - l2 is therefore below
  // (5ε + 33ε² + O(ε³))·(l1 + l2) including the rounding of the bound itself; we use (5 + 64ε)ε.
  constexpr double kBound = (5.0 + 64.0 * detail::kEpsilon) * detail::kEpsilon;
  const double abx = a.x - b.x, aby = a.y - b.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double l1 = abx * abx + aby * aby;
  const double l2 = cdx * cdx + cdy * cdy;
  const double det = l1 - l2;
  const double bound = kBound * (l1 + l2);
  if (det > bound) return 1;
  if (-det > bound) return -1;

  const Expansion<2> eabx = difference(a.x, b.x), eaby = difference(a.y, b.y);
  const Expansion<2> ecdx = difference(c.x, d.x), ecdy = difference(c.y, d.y);
  const Expansion<16> len1 = eabx * eabx + eaby * eaby;
  const Expansion<16> len2 = ecdx * ecdx + ecdy * ecdy;
  return sign_of(len1 - len2);
}

int in_diametral_circle(const Point& a, const Point& b, const Point& p) {
  // s = (p-a)·(p-b) = l + r with two products of rounded differences: the same error analysis as
  // orient2d's first stage (Shewchuk's ccwerrboundA applies to l + r as to l - r).
  const double pax = p.x - a.x, pbx = p.x - b.x;
  const double pay = p.y - a.y, pby = p.y - b.y;
  const double l = pax * pbx;
  const double r = pay * pby;
  const double s = l + r;
  const double bound = detail::kOrientBound * (std::fabs(l) + std::fabs(r));
  if (s > bound) return -1;
  if (-s > bound) return 1;

  const Expansion<2> epax = difference(p.x, a.x), epbx = difference(p.x, b.x);
  const Expansion<2> epay = difference(p.y, a.y), epby = difference(p.y, b.y);
  return -sign_of(epax * epbx + epay * epby);
}

}  // namespace mwst
