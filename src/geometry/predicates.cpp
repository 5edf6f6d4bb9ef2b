// src/geometry/predicates.cpp — exact stages of the geometric predicates of mwst/geometry/geometry.hpp.
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
#include "mwst/geometry/geometry.hpp"

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

// ==== the exact stages begin here ================================================================
//
// incircle after the inline filter (stage A, geometry.hpp) is adaptive, after Shewchuk's paper
// (§4.5): each stage either decides the sign with a proven error bound or passes on.
//   - Exact differences, exact doubles: if every coordinate difference is exact and no product or
//     sum of the plain double evaluation rounds (grids, most exactly cocircular inputs), the double
//     is the determinant.
//   - Double-double: the determinant in normalised double-double arithmetic from the exact
//     differences (rounded value and tail), within a proven 2⁻⁹⁸ · permanent (far-apart chords of
//     points rounded onto a circle end here). Stages B, C and D below are then rarely reached.
//   - Stage B: the determinant of the rounded differences in expansion arithmetic (fixed arrays,
//     at most 96 components). Exact when the differences are; otherwise within iccerrboundB ·
//     permanent of the true value.
//   - Stage C: plus the first-order correction for the differences' roundoff tails, in doubles;
//     within iccerrboundC · permanent + resulterrbound · |det|.
//   - Stage D: everything exactly, with each difference a two-component expansion.
// orient2d evaluates exactly at once: in at most 4 components when its differences are exact,
// otherwise with two-component differences (its exact stage is short anyway).
//
// With GCC on x86-64 the exact stages are compiled twice: for CPUs with fused multiply-add
// (Two-Product's error term is then one inline instruction) and for the baseline x86-64 (where
// std::fma is the C library's correctly rounded fma, a call); the choice is made once at load time
// (target_clones). The results are identical: both are exact. (Not under ThreadSanitizer: its
// runtime is not yet set up when the loader runs the choice, and the program would crash at start.)

namespace {

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(MWST_DEKKER_PRODUCT) && \
    !defined(__SANITIZE_THREAD__)
#define MWST_EXACT_CLONES __attribute__((target_clones("fma", "default")))
#else
#define MWST_EXACT_CLONES
#endif

// A double-double: the unevaluated sum hi + lo of two doubles, kept normalised (|lo| <= ulp(hi)/2,
// by an error-free Two-Sum after every operation). Used only by incircle's double-double stage,
// whose error bound is derived there.
struct DoubleDouble {
  double hi, lo;
};

// hi + lo renormalised by an error-free Two-Sum.
MWST_EXACT_INLINE DoubleDouble dd_normalised(double hi, double lo) {
  DoubleDouble r{0.0, 0.0};
  two_sum(hi, lo, r.hi, r.lo);
  return r;
}

// u·v: the exact product of the high parts plus the rounded cross terms; u.lo·v.lo is dropped.
MWST_EXACT_INLINE DoubleDouble dd_mul(const DoubleDouble& u, const DoubleDouble& v) {
  double p = 0.0, e = 0.0;
  two_product(u.hi, v.hi, p, e);
  return dd_normalised(p, e + (u.hi * v.lo + u.lo * v.hi));
}

// u + v: Two-Sum of the high parts, the low parts added to the error term.
MWST_EXACT_INLINE DoubleDouble dd_add(const DoubleDouble& u, const DoubleDouble& v) {
  double s = 0.0, t = 0.0;
  two_sum(u.hi, v.hi, s, t);
  return dd_normalised(s, t + (u.lo + v.lo));
}

// u − v = u + (−v).
MWST_EXACT_INLINE DoubleDouble dd_sub(const DoubleDouble& u, const DoubleDouble& v) {
  return dd_add(u, DoubleDouble{-v.hi, -v.lo});
}

// a·b − c·d exactly, as an expansion of at most four components.
MWST_EXACT_INLINE Expansion<4> product_difference(double a, double b, double c, double d) {
  double p = 0.0, pe = 0.0, q = 0.0, qe = 0.0;
  two_product(a, b, p, pe);
  two_product(c, d, q, qe);
  Expansion<2> left, right;
  left.push(pe);
  left.push(p);
  right.push(-qe);
  right.push(-q);
  Expansion<4> h;
  h.n = expansion_sum(left.c, left.n, right.c, right.n, h.c);
  return h;
}

// (x² + y²)·m exactly, for a minor m: x·(x·m) + y·(y·m), at most 32 components.
MWST_EXACT_INLINE Expansion<32> lifted(double x, double y, const Expansion<4>& minor) {
  Expansion<8> xm, ym;
  xm.n = scale_expansion(minor.c, minor.n, x, xm.c);
  ym.n = scale_expansion(minor.c, minor.n, y, ym.c);
  Expansion<16> xxm, yym;
  xxm.n = scale_expansion(xm.c, xm.n, x, xxm.c);
  yym.n = scale_expansion(ym.c, ym.n, y, yym.c);
  Expansion<32> h;
  h.n = expansion_sum(xxm.c, xxm.n, yym.c, yym.n, h.c);
  return h;
}

// The exact sign of incircle(a, b, c, d), by the stages listed above. The stages stay in one
// function: they share the six differences and their six tails, so splitting them would only add
// a dozen parameters to each piece without naming anything the comments do not already name.
MWST_EXACT_CLONES int incircle_sign_exact(const Point& a, const Point& b, const Point& c,
                                          const Point& d) {
  double adx = 0.0, ady = 0.0, bdx = 0.0, bdy = 0.0, cdx = 0.0, cdy = 0.0;
  double adxt = 0.0, adyt = 0.0, bdxt = 0.0, bdyt = 0.0, cdxt = 0.0, cdyt = 0.0;
  two_diff(a.x, d.x, adx, adxt);
  two_diff(a.y, d.y, ady, adyt);
  two_diff(b.x, d.x, bdx, bdxt);
  two_diff(b.y, d.y, bdy, bdyt);
  two_diff(c.x, d.x, cdx, cdxt);
  two_diff(c.y, d.y, cdy, cdyt);
  if (adxt == 0.0 && adyt == 0.0 && bdxt == 0.0 && bdyt == 0.0 && cdxt == 0.0 && cdyt == 0.0) {
    // det = |a−d|²·(b−d)×(c−d) + |b−d|²·(c−d)×(a−d) + |c−d|²·(a−d)×(b−d), every factor exact.
    // First in plain doubles, with every rounding error measured by an error-free transformation:
    // if none rounded (integer grids, and most exactly cocircular inputs), the double is the exact
    // determinant. (The errors are accumulated as a sum of magnitudes: zero iff all are zero.)
    double rounding = 0.0;
    auto mul = [&rounding](double x, double y) {
      double p = 0.0, e = 0.0;
      two_product(x, y, p, e);
      rounding += std::fabs(e);
      return p;
    };
    auto add = [&rounding](double x, double y) {
      double s = 0.0, e = 0.0;
      two_sum(x, y, s, e);
      rounding += std::fabs(e);
      return s;
    };
    const double bc = add(mul(bdx, cdy), -mul(cdx, bdy));
    const double ca = add(mul(cdx, ady), -mul(adx, cdy));
    const double ab = add(mul(adx, bdy), -mul(bdx, ady));
    const double alift = add(mul(adx, adx), mul(ady, ady));
    const double blift = add(mul(bdx, bdx), mul(bdy, bdy));
    const double clift = add(mul(cdx, cdx), mul(cdy, cdy));
    const double det = add(add(mul(alift, bc), mul(blift, ca)), mul(clift, ab));
    if (rounding == 0.0) return (det > 0.0) - (det < 0.0);
  }
  // Double-double stage: every difference as the exact pair (rounded, tail), the determinant in
  // normalised double-double arithmetic. Error bound (ε = 2⁻⁵³; A(x) the sum of absolute values of
  // the exact terms of x, so that A(det) is the permanent P): a product of two pairs with errors
  // a·ε²·A and b·ε²·A is within (a + b + 8)·ε²·A of the exact product (8ε² from dropping lo·lo
  // and rounding the cross terms and their sum); a sum is within (max(a, b) + 3)·ε²·A. The
  // differences are exact (a = 0), so products of differences are within 8ε², the minors and lifts
  // within 11ε², the three terms within 30ε² and the determinant within 36ε²·P. Rounding hi + lo
  // keeps its sign. The bound used, 2⁻⁹⁸ = 256ε² times the permanent of the rounded differences
  // (which differs from P by a few ε), leaves a factor 7 for the O(ε³) terms. Points rounded onto
  // a circle with far-apart chords end here: their determinant is ~10⁻¹⁶ of the permanent, far
  // below the double filter's reach and far above this stage's.
  {
    const DoubleDouble ax{adx, adxt}, ay{ady, adyt}, bx{bdx, bdxt}, by{bdy, bdyt}, cx{cdx, cdxt},
        cy{cdy, cdyt};
    const DoubleDouble bc = dd_sub(dd_mul(bx, cy), dd_mul(cx, by));
    const DoubleDouble ca = dd_sub(dd_mul(cx, ay), dd_mul(ax, cy));
    const DoubleDouble ab = dd_sub(dd_mul(ax, by), dd_mul(bx, ay));
    const DoubleDouble alift = dd_add(dd_mul(ax, ax), dd_mul(ay, ay));
    const DoubleDouble blift = dd_add(dd_mul(bx, bx), dd_mul(by, by));
    const DoubleDouble clift = dd_add(dd_mul(cx, cx), dd_mul(cy, cy));
    const DoubleDouble det_dd = dd_add(dd_add(dd_mul(alift, bc), dd_mul(blift, ca)), dd_mul(clift, ab));
    const double value = det_dd.hi + det_dd.lo;
    const double permanent =
        (std::fabs(bdx * cdy) + std::fabs(cdx * bdy)) * (adx * adx + ady * ady) +
        (std::fabs(cdx * ady) + std::fabs(adx * cdy)) * (bdx * bdx + bdy * bdy) +
        (std::fabs(adx * bdy) + std::fabs(bdx * ady)) * (cdx * cdx + cdy * cdy);
    const double bound = 0x1p-98 * permanent;
    if (value > bound) return 1;
    if (-value > bound) return -1;
  }
  // Stage B: the determinant of the rounded differences, exactly (at most 96 components). When the
  // differences are exact this is the determinant itself. Otherwise the neglected tails change it
  // by less than iccerrboundB · permanent (Shewchuk 1997, §4.5, incircle's stage B bound).
  const Expansion<32> rounded_a = lifted(adx, ady, product_difference(bdx, cdy, cdx, bdy));
  const Expansion<32> rounded_b = lifted(bdx, bdy, product_difference(cdx, ady, adx, cdy));
  const Expansion<32> rounded_c = lifted(cdx, cdy, product_difference(adx, bdy, bdx, ady));
  const Expansion<64> rounded_ab = rounded_a + rounded_b;
  const Expansion<96> rounded_det = rounded_ab + rounded_c;
  if (adxt == 0.0 && adyt == 0.0 && bdxt == 0.0 && bdyt == 0.0 && cdxt == 0.0 && cdyt == 0.0) {
    return sign_of(rounded_det);
  }
  constexpr double kEps = detail::kEpsilon;
  constexpr double kBoundB = (4.0 + 48.0 * kEps) * kEps;
  constexpr double kBoundC = (44.0 + 576.0 * kEps) * kEps * kEps;
  constexpr double kResultBound = (3.0 + 8.0 * kEps) * kEps;
  const double permanent =
      (std::fabs(bdx * cdy) + std::fabs(cdx * bdy)) * (adx * adx + ady * ady) +
      (std::fabs(cdx * ady) + std::fabs(adx * cdy)) * (bdx * bdx + bdy * bdy) +
      (std::fabs(adx * bdy) + std::fabs(bdx * ady)) * (cdx * cdx + cdy * cdy);
  double det = estimate(rounded_det);
  const double bound_b = kBoundB * permanent;
  if (det > bound_b) return 1;
  if (-det > bound_b) return -1;
  // Stage C: add the first-order effect of the tails (the derivative of the determinant in each
  // difference, times its tail), in doubles; what is left (second-order tail terms and the
  // rounding of this correction) is below iccerrboundC · permanent plus the rounding of det
  // (Shewchuk 1997, §4.5).
  const double bound_c = kBoundC * permanent + kResultBound * std::fabs(det);
  det += ((adx * adx + ady * ady) * ((bdx * cdyt + cdy * bdxt) - (bdy * cdxt + cdx * bdyt)) +
          2.0 * (adx * adxt + ady * adyt) * (bdx * cdy - bdy * cdx)) +
         ((bdx * bdx + bdy * bdy) * ((cdx * adyt + ady * cdxt) - (cdy * adxt + adx * cdyt)) +
          2.0 * (bdx * bdxt + bdy * bdyt) * (cdx * ady - cdy * adx)) +
         ((cdx * cdx + cdy * cdy) * ((adx * bdyt + bdy * adxt) - (ady * bdxt + bdx * adyt)) +
          2.0 * (cdx * cdxt + cdy * cdyt) * (adx * bdy - ady * bdx));
  if (det > bound_c) return 1;
  if (-det > bound_c) return -1;
  // Stage D, exactly: the differences as two-component expansions.
  const Expansion<2> eadx = difference(a.x, d.x), eady = difference(a.y, d.y);
  const Expansion<2> ebdx = difference(b.x, d.x), ebdy = difference(b.y, d.y);
  const Expansion<2> ecdx = difference(c.x, d.x), ecdy = difference(c.y, d.y);
  Expansion<16> bc = ebdx * ecdy - ecdx * ebdy;
  Expansion<16> ca = ecdx * eady - eadx * ecdy;
  Expansion<16> ab = eadx * ebdy - ebdx * eady;
  Expansion<16> alift = eadx * eadx + eady * eady;
  Expansion<16> blift = ebdx * ebdx + ebdy * ebdy;
  Expansion<16> clift = ecdx * ecdx + ecdy * ecdy;
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
  return sign_of(abterm + cterm);
}

// The exact sign of orient2d(a, b, c): four components when the differences are exact, else with
// two-component differences.
MWST_EXACT_CLONES int orient2d_sign_exact(const Point& a, const Point& b, const Point& c) {
  double acx = 0.0, acy = 0.0, bcx = 0.0, bcy = 0.0;
  double acxt = 0.0, acyt = 0.0, bcxt = 0.0, bcyt = 0.0;
  two_diff(a.x, c.x, acx, acxt);
  two_diff(a.y, c.y, acy, acyt);
  two_diff(b.x, c.x, bcx, bcxt);
  two_diff(b.y, c.y, bcy, bcyt);
  if (acxt == 0.0 && acyt == 0.0 && bcxt == 0.0 && bcyt == 0.0) {
    return sign_of(product_difference(acx, bcy, acy, bcx));
  }
  return sign_of(orient2d_expansion(a, b, c));
}

}  // namespace

// ==== the exact stages end here ==================================================================

// ==== the entry points begin here ================================================================

namespace detail {

// The exact stages behind the inline filters of geometry.hpp.
int orient2d_exact(const Point& a, const Point& b, const Point& c) {
  return orient2d_sign_exact(a, b, c);
}

// The orient2d determinant, exactly, rounded to double (see the declaration above).
double orient2d_value(const Point& a, const Point& b, const Point& c) {
  return estimate(orient2d_expansion(a, b, c));
}

int incircle_exact(const Point& a, const Point& b, const Point& c, const Point& d) {
  return incircle_sign_exact(a, b, c, d);
}

}  // namespace detail

// The sign of |ab|² − |cd|²: a floating-point filter, then the exact squared lengths.
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

// +1 if p lies strictly inside the circle with diameter ab, 0 on it, −1 outside: the sign of
// −(p−a)·(p−b), filtered, then exact.
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

// ==== the entry points end here ==================================================================

}  // namespace mwst
