// tests/geometry/test_predicates.cpp — exactness tests of the predicates and accuracy tests of the
// constructions in mwst/geometry/geometry.hpp (src/geometry/predicates.cpp, src/geometry/constructions.cpp).
//
// Oracle: GMP rationals (mpq_class). Every double is a dyadic rational, so the oracle's sign is the
// true sign. Inputs are adversarial after Shewchuk, "Adaptive Precision Floating-Point Arithmetic
// and Fast Robust Geometric Predicates" (1997): near-collinear points on y = x perturbed by ulps,
// his orient2d grid near (0.5, 0.5) against (12, 12), (24, 24), exactly cocircular symmetric sets,
// near-cocircular points, huge (1e50), tiny (1e-50) and mixed scales, random exponents. Both the
// public predicates (filter + exact stage) and the exact stages alone are checked.

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "mwst/geometry/geometry.hpp"

namespace mwst {
namespace {

// ---- oracle -----------------------------------------------------------------------------------

// The oracle works on rationals. Since every double is a dyadic rational and the determinants are
// homogeneous, all coordinates of one case are first scaled by the same power of two (exactly) so
// that they become integers: the signs are unchanged and GMP's canonicalization stays cheap.
struct QPoint {
  mpq_class x, y;
  explicit QPoint(const Point& p, int shift = 0)
      : x(std::ldexp(p.x, shift)), y(std::ldexp(p.y, shift)) {}
};

template <typename... P>
int integer_shift(const P&... p) {
  int lowest = 0;
  bool any = false;
  auto visit = [&](double v) {
    if (v == 0.0) return;
    const int e = std::ilogb(v) - 52;  // v is a multiple of 2^e
    lowest = any ? std::min(lowest, e) : e;
    any = true;
  };
  (visit(p.x), ...);
  (visit(p.y), ...);
  return -lowest;
}

int sign(const mpq_class& v) { return sgn(v); }

int oracle_orient(const Point& pa, const Point& pb, const Point& pc) {
  const int k = integer_shift(pa, pb, pc);
  const QPoint a(pa, k), b(pb, k), c(pc, k);
  const mpq_class det = (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
  return sign(det);
}

int oracle_incircle(const Point& pa, const Point& pb, const Point& pc, const Point& pd) {
  const int k = integer_shift(pa, pb, pc, pd);
  const QPoint a(pa, k), b(pb, k), c(pc, k), d(pd, k);
  const mpq_class adx = a.x - d.x, ady = a.y - d.y;
  const mpq_class bdx = b.x - d.x, bdy = b.y - d.y;
  const mpq_class cdx = c.x - d.x, cdy = c.y - d.y;
  const mpq_class alift = adx * adx + ady * ady;
  const mpq_class blift = bdx * bdx + bdy * bdy;
  const mpq_class clift = cdx * cdx + cdy * cdy;
  const mpq_class det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
                        clift * (adx * bdy - bdx * ady);
  return sign(det);
}

int oracle_compare_lengths(const Point& pa, const Point& pb, const Point& pc, const Point& pd) {
  const int k = integer_shift(pa, pb, pc, pd);
  const QPoint a(pa, k), b(pb, k), c(pc, k), d(pd, k);
  const mpq_class abx = a.x - b.x, aby = a.y - b.y, cdx = c.x - d.x, cdy = c.y - d.y;
  return sign(abx * abx + aby * aby - cdx * cdx - cdy * cdy);
}

int oracle_diametral(const Point& pa, const Point& pb, const Point& pp) {
  const int k = integer_shift(pa, pb, pp);
  const QPoint a(pa, k), b(pb, k), p(pp, k);
  return -sign((p.x - a.x) * (p.x - b.x) + (p.y - a.y) * (p.y - b.y));
}

// ---- checkers (the oracle's sign, and every permutation identity too) -------------------------

std::int64_t g_failures = 0;
constexpr std::int64_t kMaxReported = 20;  // keep the log readable if something is badly wrong

// Reports the first kMaxReported mismatches in full; every mismatch is counted, and each test
// checks its count through a FailureScope.
#define MWST_CHECK_SIGN(got, want, what)                                                     \
  do {                                                                                        \
    const int got_ = (got), want_ = (want);                                                   \
    if (got_ != want_ && ++g_failures <= kMaxReported)                                        \
      ADD_FAILURE() << what << ": got " << got_ << ", want " << want_;                        \
  } while (false)

struct FailureScope {
  std::int64_t start = g_failures;
  FailureScope() = default;
  FailureScope(const FailureScope&) = delete;
  FailureScope& operator=(const FailureScope&) = delete;
  ~FailureScope() { EXPECT_EQ(g_failures - start, 0) << "sign mismatches in this test"; }
};

template <typename... P>
bool all_in_range(const P&... p) {
  return (in_supported_range(p) && ...);
}

std::string show(const Point& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%a, %a)", p.x, p.y);
  return buf;
}

// Returns the oracle sign.
int check_orient(const Point& a, const Point& b, const Point& c) {
  const int s = oracle_orient(a, b, c);
  const auto where = [&] { return "orient2d" + show(a) + show(b) + show(c); };
  MWST_CHECK_SIGN(orient2d(a, b, c), s, where());
  MWST_CHECK_SIGN(detail::orient2d_exact(a, b, c), s, where() + " [exact]");
  // Cyclic rotations keep the sign; transpositions flip it.
  MWST_CHECK_SIGN(orient2d(b, c, a), s, where() + " [bca]");
  MWST_CHECK_SIGN(orient2d(c, a, b), s, where() + " [cab]");
  MWST_CHECK_SIGN(orient2d(b, a, c), -s, where() + " [bac]");
  MWST_CHECK_SIGN(orient2d(a, c, b), -s, where() + " [acb]");
  MWST_CHECK_SIGN(detail::orient2d_exact(c, b, a), -s, where() + " [cba exact]");
  return s;
}

int check_incircle(const Point& a, const Point& b, const Point& c, const Point& d) {
  const int s = oracle_incircle(a, b, c, d);
  const auto where = [&] { return "incircle" + show(a) + show(b) + show(c) + show(d); };
  MWST_CHECK_SIGN(incircle(a, b, c, d), s, where());
  MWST_CHECK_SIGN(detail::incircle_exact(a, b, c, d), s, where() + " [exact]");
  // The 4x4 lifted determinant is alternating in its four rows: an even permutation keeps the
  // sign, a transposition flips it.
  MWST_CHECK_SIGN(incircle(b, c, a, d), s, where() + " [bcad]");
  MWST_CHECK_SIGN(incircle(b, a, c, d), -s, where() + " [bacd]");
  MWST_CHECK_SIGN(incircle(d, b, c, a), -s, where() + " [dbca]");
  MWST_CHECK_SIGN(detail::incircle_exact(a, d, c, b), -s, where() + " [adcb exact]");
  MWST_CHECK_SIGN(incircle(b, a, d, c), s, where() + " [badc]");
  return s;
}

int check_lengths(const Point& a, const Point& b, const Point& c, const Point& d) {
  const int s = oracle_compare_lengths(a, b, c, d);
  const auto where = [&] {
    return "compare_squared_lengths" + show(a) + show(b) + show(c) + show(d);
  };
  MWST_CHECK_SIGN(compare_squared_lengths(a, b, c, d), s, where());
  MWST_CHECK_SIGN(compare_squared_lengths(c, d, a, b), -s, where() + " [swapped]");
  MWST_CHECK_SIGN(compare_squared_lengths(b, a, d, c), s, where() + " [reversed]");
  return s;
}

int check_diametral(const Point& a, const Point& b, const Point& p) {
  const int s = oracle_diametral(a, b, p);
  const auto where = [&] { return "in_diametral_circle" + show(a) + show(b) + show(p); };
  MWST_CHECK_SIGN(in_diametral_circle(a, b, p), s, where());
  MWST_CHECK_SIGN(in_diametral_circle(b, a, p), s, where() + " [ba]");
  return s;
}

// ---- generators -------------------------------------------------------------------------------

using Rng = std::mt19937_64;

// Uniform mantissa in [1, 2), exponent uniform in [emin, emax], random sign. With emin >= -166 and
// emax <= 165 the magnitude lies in [2^-166, 2^166) ⊂ [1e-50, 1e50].
double random_coordinate(Rng& rng, int emin, int emax) {
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> ex(emin, emax);
  const double v = std::ldexp(mant(rng), ex(rng));
  return (rng() & 1U) ? -v : v;
}

double random_wide(Rng& rng) {
  if (rng() % 16 == 0) return 0.0;
  return random_coordinate(rng, -166, 165);
}

// Moves v by k ulps (k may be negative).
double nudge(double v, int k) {
  const double dir = k > 0 ? std::numeric_limits<double>::infinity()
                           : -std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::abs(k); ++i) v = std::nextafter(v, dir);
  return v;
}

double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Scales that keep every generated coordinate in the supported range: 1, huge, tiny.
constexpr std::array<double, 3> kScales = {1.0, 0x1p150, 0x1p-150};

void expect_in_range(const Point& p) {
  ASSERT_TRUE(in_supported_range(p)) << show(p);
}

// The oracle's integer scaling against plain rationals (no scaling) on random wide inputs.
TEST(Oracle, ScalingPreservesSigns) {
  Rng rng(1);
  for (int iter = 0; iter < 300; ++iter) {
    const Point a{random_wide(rng), random_wide(rng)}, b{random_wide(rng), random_wide(rng)};
    const Point c{random_wide(rng), random_wide(rng)}, d{random_wide(rng), random_wide(rng)};
    const QPoint qa(a), qb(b), qc(c), qd(d);
    const mpq_class orient = (qa.x - qc.x) * (qb.y - qc.y) - (qa.y - qc.y) * (qb.x - qc.x);
    EXPECT_EQ(oracle_orient(a, b, c), sgn(orient));
    const mpq_class adx = qa.x - qd.x, ady = qa.y - qd.y, bdx = qb.x - qd.x, bdy = qb.y - qd.y;
    const mpq_class cdx = qc.x - qd.x, cdy = qc.y - qd.y;
    const mpq_class det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                          (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                          (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
    EXPECT_EQ(oracle_incircle(a, b, c, d), sgn(det));
  }
}

// ---- orient2d ---------------------------------------------------------------------------------

// Shewchuk's figure: p = (0.5 + i·u, 0.5 + j·u), u = ulp(0.5) = 2^-53, against (12,12), (24,24),
// at three scales (exact power-of-two scaling) and with the line through the other end.
TEST(Orient2d, ShewchukGrid) {
  const FailureScope scope;
  constexpr double u = 0x1p-53;
  int positives = 0, negatives = 0, zeros = 0;
  for (const double scale : {1.0, 0x1p160, 0x1p-160}) {
    const Point b{12 * scale, 12 * scale}, c{24 * scale, 24 * scale};
    for (int i = 0; i < 256; ++i) {
      for (int j = 0; j < 256; ++j) {
        const Point p{(0.5 + i * u) * scale, (0.5 + j * u) * scale};
        expect_in_range(p);
        const int s = check_orient(p, b, c);
        (s > 0 ? positives : s < 0 ? negatives : zeros) += 1;
      }
    }
  }
  EXPECT_EQ(zeros, 3 * 256);  // the diagonal i == j is exactly collinear
  EXPECT_GT(positives, 0);
  EXPECT_GT(negatives, 0);
  // The same near (0.5, 0.5) with a line through points on the other side (differences with tails).
  for (int i = -64; i < 64; ++i) {
    for (int j = -64; j < 64; ++j) {
      const Point p{0.5 + i * u, 0.5 + j * u};
      check_orient(p, Point{-12.0, -12.0}, Point{0x1p-60, 0x1p-60});
    }
  }
}

// Points on y = x perturbed by a few ulps, at every scale and across scales.
TEST(Orient2d, NearLineYEqualsX) {
  const FailureScope scope;
  Rng rng(12345);
  for (int iter = 0; iter < 12000; ++iter) {
    const double scale = kScales[iter % 3];
    const double x1 = uniform(rng, -1.0, 1.0) * scale;
    const double x2 = uniform(rng, -1.0, 1.0) * scale;
    const double x3 = uniform(rng, -1.0, 1.0) * scale;
    if (x1 == 0.0 || x2 == 0.0 || x3 == 0.0) continue;
    const int k = static_cast<int>(rng() % 7) - 3, l = static_cast<int>(rng() % 7) - 3;
    const Point a{x1, x1}, b{x2, x2}, c{nudge(x3, k), nudge(x3, l)};
    if (!in_supported_range(a) || !in_supported_range(b) || !in_supported_range(c)) continue;
    const int s = check_orient(a, b, c);
    if (k == l) {
      EXPECT_EQ(s, 0);
    }
    // Mixed: one point far away on the same line (huge against tiny).
    const double far = (rng() & 1U ? 1.0 : -1.0) * 0x1p160 * uniform(rng, 0.5, 1.0);
    const double tiny = x1 / scale * 0x1p-150;
    const Point t{nudge(tiny, k), tiny};
    if (all_in_range(t)) check_orient(Point{far, far}, t, b);
  }
}

// c on the line through a and b rounded, with random exponents: near-collinear in general position.
TEST(Orient2d, RoundedCollinearRandomExponents) {
  const FailureScope scope;
  Rng rng(777);
  for (int iter = 0; iter < 30000; ++iter) {
    const int e = static_cast<int>(rng() % 300) - 150;
    const int spread = static_cast<int>(rng() % 12);
    const Point a{random_coordinate(rng, e - spread, e + spread),
                  random_coordinate(rng, e - spread, e + spread)};
    const Point b{random_coordinate(rng, e - spread, e + spread),
                  random_coordinate(rng, e - spread, e + spread)};
    const double t = uniform(rng, -2.0, 3.0);
    Point c{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    c = Point{snap_to_range(c.x), snap_to_range(c.y)};
    if (!in_supported_range(c) || !in_supported_range(a) || !in_supported_range(b)) continue;
    check_orient(a, b, c);
  }
}

// Fully random coordinates over the whole range (exact stage called directly as well).
TEST(Orient2d, RandomWideExponents) {
  const FailureScope scope;
  Rng rng(4242);
  for (int iter = 0; iter < 30000; ++iter) {
    const Point a{random_wide(rng), random_wide(rng)};
    const Point b{random_wide(rng), random_wide(rng)};
    const Point c{random_wide(rng), random_wide(rng)};
    check_orient(a, b, c);
    // Repeated and axis-degenerate cases.
    check_orient(a, a, c);
    check_orient(a, Point{a.x, b.y}, Point{a.x, c.y});
  }
}

// ---- incircle ---------------------------------------------------------------------------------

// Exactly cocircular sets (±a, ±b), (±b, ±a) and one-ulp perturbations of them.
TEST(Incircle, SymmetricCocircular) {
  const FailureScope scope;
  Rng rng(99);
  for (int iter = 0; iter < 8000; ++iter) {
    const double scale = kScales[iter % 3];
    const double p = uniform(rng, 0.01, 1.0) * scale, q = uniform(rng, 0.01, 1.0) * scale;
    const std::array<Point, 8> ring = {Point{p, q},   Point{-q, p}, Point{-p, q}, Point{-q, -p},
                                       Point{-p, -q}, Point{q, -p}, Point{p, -q}, Point{q, p}};
    std::array<int, 4> idx{};
    for (int& i : idx) i = static_cast<int>(rng() % 8);
    const Point a = ring[idx[0]], b = ring[idx[1]], c = ring[idx[2]], d = ring[idx[3]];
    EXPECT_EQ(check_incircle(a, b, c, d), 0);
    const int k = static_cast<int>(rng() % 5) - 2;
    const Point d2{nudge(d.x, k), nudge(d.y, static_cast<int>(rng() % 5) - 2)};
    check_incircle(a, b, c, d2);
  }
}

// Shewchuk-style grid for incircle: d = (0.5 + i·u, 0.5 + j·u) against the circle through
// (-0.5, 0.5), (-0.5, -0.5), (0.5, -0.5), which passes through (0.5, 0.5). The differences have
// tails for odd i, j, so the general expansion path is exercised.
TEST(Incircle, Grid) {
  const FailureScope scope;
  constexpr double u = 0x1p-53;
  int zeros = 0;
  for (const double scale : {1.0, 0x1p150, 0x1p-150}) {
    const Point a{-0.5 * scale, 0.5 * scale}, b{-0.5 * scale, -0.5 * scale},
        c{0.5 * scale, -0.5 * scale};
    for (int i = -48; i < 48; ++i) {
      for (int j = -48; j < 48; ++j) {
        const Point d{(0.5 + i * u) * scale, (0.5 + j * u) * scale};
        zeros += check_incircle(a, b, c, d) == 0;
      }
    }
  }
  EXPECT_EQ(zeros, 3);
}

// Lattice circles: integer points on x² + y² = 5^4 · 13² (many representations), scaled by 2^k
// and translated by a dyadic offset that keeps them exact; then perturbed.
TEST(Incircle, LatticeCircles) {
  const FailureScope scope;
  std::vector<Point> base;
  const long long r2 = 625LL * 169LL;  // 105625
  for (long long x = -325; x <= 325; ++x) {
    const long long y2 = r2 - x * x;
    const auto y = static_cast<long long>(std::llround(std::sqrt(static_cast<double>(y2))));
    if (y * y == y2) {
      base.push_back(Point{static_cast<double>(x), static_cast<double>(y)});
      if (y != 0) base.push_back(Point{static_cast<double>(x), static_cast<double>(-y)});
    }
  }
  ASSERT_GT(base.size(), 20U);
  Rng rng(2024);
  for (int iter = 0; iter < 9000; ++iter) {
    const int shift = static_cast<int>(rng() % 300) - 150;
    const double s = std::ldexp(1.0, shift);
    const double ox = std::ldexp(static_cast<double>(rng() % 4096), shift),
                 oy = std::ldexp(static_cast<double>(rng() % 4096), shift);
    auto pick = [&] {
      const Point& p = base[rng() % base.size()];
      return Point{snap_to_range(p.x * s + ox), snap_to_range(p.y * s + oy)};
    };
    const Point a = pick(), b = pick(), c = pick(), d = pick();
    EXPECT_EQ(check_incircle(a, b, c, d), 0);
    const Point d2{nudge(d.x, static_cast<int>(rng() % 3) - 1), nudge(d.y, 1)};
    if (in_supported_range(d2)) check_incircle(a, b, c, d2);
  }
}

// d on the circumcircle of a random triangle, rounded: near-cocircular, random exponents, mixed.
TEST(Incircle, NearCocircularRandom) {
  const FailureScope scope;
  Rng rng(31337);
  for (int iter = 0; iter < 25000; ++iter) {
    const int e = static_cast<int>(rng() % 300) - 150;
    const double s = std::ldexp(1.0, e);
    const Point center{uniform(rng, -1.0, 1.0) * s, uniform(rng, -1.0, 1.0) * s};
    const double radius = uniform(rng, 0.01, 1.0) * s;
    auto on_circle = [&] {
      const double th = uniform(rng, 0.0, 2.0 * std::numbers::pi);
      return Point{snap_to_range(center.x + radius * std::cos(th)),
                   snap_to_range(center.y + radius * std::sin(th))};
    };
    const Point a = on_circle(), b = on_circle(), c = on_circle(), d = on_circle();
    check_incircle(a, b, c, d);
    // Mixed scales: a point near the origin at the tiny end and a triangle at the huge end.
    if (iter % 5 == 0) {
      const Point tiny{random_coordinate(rng, -166, -140), random_coordinate(rng, -166, -140)};
      check_incircle(Point{0x1p160, 0.0}, Point{0.0, 0x1p160}, Point{-0x1p160, 0.0}, tiny);
      check_incircle(Point{tiny.x, 0.0}, Point{0.0, tiny.y}, Point{-tiny.x, 0.0},
                     Point{0.0, -tiny.y});
    }
  }
}

// The adaptive stages B and C of incircle_exact (predicates.cpp) decide near-cocircular points
// whose coordinate differences round: points on a circle far from the origin compared with its
// radius (so every difference has a roundoff tail), with d moved by 0-3 ulps in each coordinate
// so the exact sign is sometimes 0-adjacent and sometimes decided only by the tails.
TEST(Incircle, OffsetCirclesUlpPerturbations) {
  const FailureScope scope;
  Rng rng(2718);
  for (int iter = 0; iter < 20000; ++iter) {
    const int e = static_cast<int>(rng() % 200) - 100;
    const double s = std::ldexp(1.0, e);
    const double offset = uniform(rng, 1.0, 1e6) * s;
    const Point center{offset * uniform(rng, 0.5, 1.0), -offset * uniform(rng, 0.5, 1.0)};
    const double radius = uniform(rng, 1e-3, 1.0) * s;
    auto on_circle = [&] {
      const double th = uniform(rng, 0.0, 2.0 * std::numbers::pi);
      return Point{center.x + radius * std::cos(th), center.y + radius * std::sin(th)};
    };
    const Point a = on_circle(), b = on_circle(), c = on_circle();
    Point d = on_circle();
    for (int k = static_cast<int>(rng() % 4); k > 0; --k) d.x = std::nextafter(d.x, 0.0);
    for (int k = static_cast<int>(rng() % 4); k > 0; --k) d.y = std::nextafter(d.y, 1e300);
    check_incircle(a, b, c, d);
  }
}

// The double-double stage of incircle_exact (exact differences, ≈106-bit evaluation, bound
// 2⁻⁹⁸·permanent). Two families whose differences are exact:
//  - far-apart chords of points rounded onto small circles away from the origin (the holes of
//    bench_cdt): the determinant is ~10⁻¹⁶ of the permanent, decided by this stage;
//  - integer points exactly on x² + y² = R with R = 5·13·17·29·37·41·53·61·73·89·97·101 (about
//    10¹⁹, 2048 representations from Gaussian-integer products): the terms need ~132 bits, so the
//    double-double value of an exactly cocircular quadruple is rounding noise that must stay below
//    the bound (the sign is 0), and d moved by one unit gives a determinant ~2⁻³³ of the
//    permanent.
TEST(Incircle, DoubleDoubleStage) {
  const FailureScope scope;
  Rng rng(4242);
  std::int64_t exact_differences = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    const Point center{0.1 * static_cast<double>(rng() % 19 + 1), 0.1 * static_cast<double>(rng() % 19 + 1)};
    const double radius = uniform(rng, 0.01, 0.04);
    auto on_circle = [&] {
      const double th = uniform(rng, 0.0, 2.0 * std::numbers::pi);
      return Point{center.x + radius * std::cos(th), center.y + radius * std::sin(th)};
    };
    const Point a = on_circle(), b = on_circle(), c = on_circle();
    Point d = on_circle();
    for (int k = static_cast<int>(rng() % 3); k > 0; --k) d.x = std::nextafter(d.x, 0.0);
    for (int k = static_cast<int>(rng() % 3); k > 0; --k) d.y = std::nextafter(d.y, 1.0);
    exact_differences += (a.x - d.x) + d.x == a.x && (b.y - d.y) + d.y == b.y;
    check_incircle(a, b, c, d);
  }
  EXPECT_GT(exact_differences, 10000);  // the family does reach the stage

  const std::array<std::int64_t, 12> primes = {5, 13, 17, 29, 37, 41, 53, 61, 73, 89, 97, 101};
  std::vector<std::pair<std::int64_t, std::int64_t>> roots;  // p = u² + v²
  for (const std::int64_t p : primes) {
    for (std::int64_t u = 1; u * u < p; ++u) {
      const auto v = static_cast<std::int64_t>(std::llround(std::sqrt(static_cast<double>(p - u * u))));
      if (v * v == p - u * u) {
        roots.push_back({u, v});
        break;
      }
    }
  }
  ASSERT_EQ(roots.size(), primes.size());
  std::vector<Point> ring;
  for (std::uint32_t mask = 0; mask < (1u << primes.size()); ++mask) {
    std::int64_t x = 1, y = 0;  // the product of u ± v·i over the primes, as x + y·i
    for (std::size_t i = 0; i < roots.size(); ++i) {
      const std::int64_t u = roots[i].first, v = (mask >> i) & 1u ? -roots[i].second : roots[i].second;
      const std::int64_t nx = x * u - y * v, ny = x * v + y * u;
      x = nx;
      y = ny;
    }
    ring.push_back(Point{static_cast<double>(x), static_cast<double>(y)});
  }
  for (int iter = 0; iter < 6000; ++iter) {
    const Point a = ring[rng() % ring.size()], b = ring[rng() % ring.size()],
                c = ring[rng() % ring.size()], d = ring[rng() % ring.size()];
    EXPECT_EQ(check_incircle(a, b, c, d), 0);
    const Point d2{d.x + static_cast<double>(static_cast<int>(rng() % 3) - 1), d.y + 1.0};
    check_incircle(a, b, c, d2);
  }
}

TEST(Incircle, RandomWideExponents) {
  const FailureScope scope;
  Rng rng(8080);
  // Few iterations: with exponents spread over the whole range the exact stage is slow (~10 µs).
  for (int iter = 0; iter < 8000; ++iter) {
    const Point a{random_wide(rng), random_wide(rng)};
    const Point b{random_wide(rng), random_wide(rng)};
    const Point c{random_wide(rng), random_wide(rng)};
    const Point d{random_wide(rng), random_wide(rng)};
    check_incircle(a, b, c, d);
    // Degenerate: a repeated point, and collinear a, b, c with d on their line: always 0.
    EXPECT_EQ(check_incircle(a, a, c, d), 0);  // two equal rows
    const Point v1{a.x, b.y}, v2{a.x, c.y}, v3{a.x, d.y};
    EXPECT_EQ(check_incircle(v1, v2, v3, a), 0);
  }
}

// ---- squared lengths and diametral circles ----------------------------------------------------

TEST(CompareSquaredLengths, TiesAndNearTies) {
  const FailureScope scope;
  Rng rng(5);
  // Pythagorean pairs: (3,4) vs (5,0), (0,5), (4,3); (5,12) vs (13,0); (20,21) vs (29,0).
  const std::array<std::array<Point, 2>, 3> pairs = {
      {{Point{3, 4}, Point{5, 0}}, {Point{5, 12}, Point{0, 13}}, {Point{20, 21}, Point{-29, 0}}}};
  for (int iter = 0; iter < 20000; ++iter) {
    const int shift = static_cast<int>(rng() % 290) - 150;
    const auto& pr = pairs[rng() % pairs.size()];
    const double s = std::ldexp(1.0, shift);
    // Integer multiples of s below 2^20·s: every sum below is exact, so the tie is exact.
    const double ox = static_cast<double>(rng() % (1U << 20)) * s;
    const double oy = static_cast<double>(rng() % (1U << 20)) * s;
    const Point a{ox, oy};
    const Point b{ox + pr[0].x * s, oy + pr[0].y * s};
    const Point c{oy, ox};
    const Point d{oy + pr[1].x * s, ox + pr[1].y * s};
    EXPECT_EQ(check_lengths(a, b, c, d), 0);
    const int k = static_cast<int>(rng() % 5) - 2;
    const Point b2{nudge(b.x, k), b.y};
    if (all_in_range(b2)) check_lengths(a, b2, c, d);
    // Offsets at a much larger exponent: the differences round, the oracle decides.
    const double big = random_coordinate(rng, std::min(shift + 30, 165), 165);
    const Point a3{a.x + big, a.y}, b3{b.x + big, b.y};
    if (all_in_range(a3, b3)) check_lengths(a3, b3, c, d);
    // Random lengths of nearly equal size across scales.
    const Point e{random_wide(rng), random_wide(rng)};
    const Point f{nudge(e.x, static_cast<int>(rng() % 5) - 2), random_wide(rng)};
    const Point g{0.0, 0.0}, h{nudge(e.x - f.x, 1), e.y - f.y};
    if (!all_in_range(e, f, h)) continue;
    check_lengths(e, f, Point{f.x, e.y}, Point{e.x, f.y});
    check_lengths(e, f, g, h);
  }
  // Exact ties with no rounding anywhere.
  EXPECT_EQ(check_lengths(Point{0, 0}, Point{3, 4}, Point{1, 1}, Point{6, 1}), 0);
  EXPECT_EQ(check_lengths(Point{0, 0}, Point{0x1p-160, 0}, Point{0, 0}, Point{0, -0x1p-160}), 0);
}

TEST(InDiametralCircle, ThalesAndRandom) {
  const FailureScope scope;
  Rng rng(6);
  for (int iter = 0; iter < 20000; ++iter) {
    const int shift = static_cast<int>(rng() % 300) - 150;
    const double s = std::ldexp(1.0, shift);
    // (7, 24) lies on the circle with diameter (-25, 0)–(25, 0); rotate by 90° too.
    const bool rot = rng() & 1U;
    auto make = [&](double x, double y) {
      return rot ? Point{-y * s, x * s} : Point{x * s, y * s};
    };
    const Point a = make(-25, 0), b = make(25, 0);
    const int sx = rng() & 1U ? 1 : -1, sy = rng() & 1U ? 1 : -1;
    const Point p = make(7 * sx, 24 * sy);
    EXPECT_EQ(check_diametral(a, b, p), 0);
    EXPECT_EQ(check_diametral(a, b, a), 0);
    check_diametral(a, b, Point{nudge(p.x, static_cast<int>(rng() % 5) - 2),
                                nudge(p.y, static_cast<int>(rng() % 5) - 2)});
    const Point q{random_wide(rng), random_wide(rng)};
    const Point r{random_wide(rng), random_wide(rng)};
    const Point m{random_wide(rng), random_wide(rng)};
    check_diametral(q, r, m);
    const Point near{nudge(q.x, 1), nudge(r.y, -1)};
    if (all_in_range(near)) check_diametral(q, r, near);
  }
}

// ---- constructions ----------------------------------------------------------------------------

double rel_err(double got, double want) {
  return std::fabs(got - want) / std::max(std::fabs(want), std::numeric_limits<double>::min());
}

TEST(Constructions, CircumcenterEquidistant) {
  Rng rng(11);
  for (int iter = 0; iter < 20000; ++iter) {
    const int e = static_cast<int>(rng() % 280) - 140;
    const double s = std::ldexp(1.0, e);
    const Point o{uniform(rng, -8, 8) * s, uniform(rng, -8, 8) * s};
    const Point a{o.x + uniform(rng, -1, 1) * s, o.y + uniform(rng, -1, 1) * s};
    const Point b{o.x + uniform(rng, -1, 1) * s, o.y + uniform(rng, -1, 1) * s};
    const Point c{o.x + uniform(rng, -1, 1) * s, o.y + uniform(rng, -1, 1) * s};
    // Keep reasonably shaped triangles: area against the longest edge squared.
    const double l2 =
        std::max({squared_distance(a, b), squared_distance(b, c), squared_distance(c, a)});
    if (std::fabs(signed_area(a, b, c)) < 0.05 * l2) continue;
    const Point cc = circumcenter(a, b, c);
    const double ra = distance(cc, a), rb = distance(cc, b), rc = distance(cc, c);
    EXPECT_LT(rel_err(rb, ra), 1e-12) << show(a) << show(b) << show(c);
    EXPECT_LT(rel_err(rc, ra), 1e-12) << show(a) << show(b) << show(c);
    // Against the exact circumcenter (GMP), relative to the radius.
    const QPoint qa(a), qb(b), qc(c);
    const mpq_class bx = qb.x - qa.x, by = qb.y - qa.y, cx = qc.x - qa.x, cy = qc.y - qa.y;
    const mpq_class den = 2 * (bx * cy - by * cx);
    const mpq_class bl = bx * bx + by * by, cl = cx * cx + cy * cy;
    const mpq_class ux = qa.x + (cy * bl - by * cl) / den, uy = qa.y + (bx * cl - cx * bl) / den;
    EXPECT_LT(std::hypot(cc.x - ux.get_d(), cc.y - uy.get_d()) / ra, 1e-13);
  }
}

TEST(Constructions, CircumcenterSkinnyIsOnCorrectSide) {
  // Nearly collinear triangles, c a few ulps off the segment ab: the angle at c is obtuse, so the
  // (huge) circumcircle's center lies on the other side of ab than c. The robust denominator keeps
  // it there: orient(a, b, cc) == -orient(a, b, c).
  Rng rng(12);
  for (int iter = 0; iter < 5000; ++iter) {
    const Point a{uniform(rng, 0, 1), uniform(rng, 0, 1)};
    const Point b{uniform(rng, 2, 3), uniform(rng, 2, 3)};
    const double t = uniform(rng, 0.2, 0.8);
    Point c{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    c.y = nudge(c.y, static_cast<int>(rng() % 64) + 1);
    const int o = orient2d(a, b, c);
    if (o == 0) continue;
    const Point cc = circumcenter(a, b, c);
    ASSERT_TRUE(std::isfinite(cc.x) && std::isfinite(cc.y));
    EXPECT_EQ(orient2d(a, b, cc), -o) << show(a) << show(b) << show(c);
  }
}

TEST(Constructions, OffCenterApexAngle) {
  Rng rng(13);
  for (int iter = 0; iter < 5000; ++iter) {
    const int e = static_cast<int>(rng() % 280) - 140;
    const double s = std::ldexp(1.0, e);
    const double alpha = uniform(rng, 10.0, 40.0) * std::numbers::pi / 180.0;
    // Skinny triangle pqr with shortest edge pq: r far from pq, so the circumcenter is farther
    // from m than the off-center.
    const Point p{uniform(rng, -1, 1) * s, uniform(rng, -1, 1) * s};
    const double th = uniform(rng, 0, 2 * std::numbers::pi);
    const double len = uniform(rng, 0.1, 1.0) * s;
    const Point q{p.x + len * std::cos(th), p.y + len * std::sin(th)};
    // The circumcenter is about h/2 from m; the off-center is (len/2)·cot(alpha/2) from m.
    const double h = len / std::tan(alpha / 2) * uniform(rng, 1.5, 6.0);
    const double shift = uniform(rng, -0.3, 0.3);
    const Point r{0.5 * (p.x + q.x) - h * std::sin(th) + shift * (q.x - p.x),
                  0.5 * (p.y + q.y) + h * std::cos(th) + shift * (q.y - p.y)};
    const Point cc = circumcenter(p, q, r);
    const Point o = off_center(p, q, cc, alpha, 1.0);
    ASSERT_NE(o, cc);
    // Apex angle at o is alpha; o is on the bisector, on the side of cc, at the right distance.
    const double vpx = p.x - o.x, vpy = p.y - o.y, vqx = q.x - o.x, vqy = q.y - o.y;
    const double angle = std::atan2(std::fabs(vpx * vqy - vpy * vqx), vpx * vqx + vpy * vqy);
    EXPECT_NEAR(angle, alpha, 1e-10 * alpha);
    EXPECT_LT(rel_err(distance(o, p), distance(o, q)), 1e-12);
    EXPECT_EQ(orient2d(p, q, o), orient2d(p, q, cc));
    const Point m = midpoint(p, q);
    EXPECT_LT(rel_err(distance(m, o), 0.5 * distance(p, q) / std::tan(alpha / 2)), 1e-12);
    // factor scales the distance.
    const Point o2 = off_center(p, q, cc, alpha, 0.95);
    EXPECT_LT(rel_err(distance(m, o2), 0.95 * 0.5 * distance(p, q) / std::tan(alpha / 2)), 1e-12);
  }
}

TEST(Constructions, OffCenterFallsBackToCircumcenter) {
  // Equilateral-ish triangle: |mc| = |pq|/(2√3) < (|pq|/2)·cot(15°), so the circumcenter is used.
  const Point p{0, 0}, q{1, 0}, r{0.5, 0.8};
  const Point cc = circumcenter(p, q, r);
  EXPECT_EQ(off_center(p, q, cc, 30.0 * std::numbers::pi / 180.0, 1.0), cc);
  // Borderline: alpha such that the off-center distance equals |mc| exactly → circumcenter.
  const Point r2{0.5, 10.0};
  const Point cc2 = circumcenter(p, q, r2);
  const double mc = distance(midpoint(p, q), cc2);
  EXPECT_EQ(off_center(p, q, cc2, 2.0 * std::atan(0.5 / mc) * (1.0 - 1e-9), 1.0), cc2);
  EXPECT_NE(off_center(p, q, cc2, 2.0 * std::atan(0.5 / mc) * (1.0 + 1e-9), 1.0), cc2);
}

TEST(Constructions, SegmentIntersection) {
  Rng rng(14);
  int tested = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    const int e = static_cast<int>(rng() % 280) - 140;
    const double s = std::ldexp(1.0, e);
    const Point a{uniform(rng, -1, 1) * s, uniform(rng, -1, 1) * s};
    const Point b{uniform(rng, -1, 1) * s, uniform(rng, -1, 1) * s};
    const Point c{uniform(rng, -1, 1) * s, uniform(rng, -1, 1) * s};
    const Point d{uniform(rng, -1, 1) * s, uniform(rng, -1, 1) * s};
    if (orient2d(a, b, c) * orient2d(a, b, d) >= 0 || orient2d(c, d, a) * orient2d(c, d, b) >= 0)
      continue;
    ++tested;
    const Point x = segment_intersection(a, b, c, d);
    const QPoint qa(a), qb(b), qc(c), qd(d);
    const mpq_class oa = (qc.x - qa.x) * (qd.y - qa.y) - (qc.y - qa.y) * (qd.x - qa.x);
    const mpq_class ob = (qc.x - qb.x) * (qd.y - qb.y) - (qc.y - qb.y) * (qd.x - qb.x);
    const mpq_class t = oa / (oa - ob);
    const mpq_class ex = qa.x + t * (qb.x - qa.x), ey = qa.y + t * (qb.y - qa.y);
    // A few ulps of the coordinates' magnitude, plus a few ulps of the segment lengths.
    const double scale = std::max({distance(a, b), distance(c, d), std::fabs(a.x), std::fabs(a.y),
                                   std::fabs(b.x), std::fabs(b.y), std::fabs(c.x), std::fabs(c.y),
                                   std::fabs(d.x), std::fabs(d.y)});
    EXPECT_LT(std::hypot(x.x - ex.get_d(), x.y - ey.get_d()) / scale, 8 * detail::kEpsilon);
    EXPECT_EQ(segment_intersection(c, d, a, b), x);
    EXPECT_GE(x.x, std::max(std::min(a.x, b.x), std::min(c.x, d.x)));
    EXPECT_LE(x.x, std::min(std::max(a.x, b.x), std::max(c.x, d.x)));
  }
  EXPECT_GT(tested, 1000);
}

TEST(Constructions, BasicsAndSignedArea) {
  EXPECT_EQ(distance(Point{0, 0}, Point{3, 4}), 5.0);
  EXPECT_EQ(squared_distance(Point{1, 1}, Point{4, 5}), 25.0);
  EXPECT_EQ(midpoint(Point{0, 0}, Point{2, -4}), (Point{1, -2}));
  EXPECT_EQ(midpoint(Point{0x1p-166, 0}, Point{0, 0}), (Point{0, 0}));  // snapped to 0
  EXPECT_EQ(signed_area(Point{0, 0}, Point{1, 0}, Point{0, 1}), 0.5);
  EXPECT_EQ(signed_area(Point{0, 0}, Point{0, 1}, Point{1, 0}), -0.5);
  // Nearly collinear: the rounded area carries the exact sign and is accurate.
  Rng rng(15);
  for (int iter = 0; iter < 5000; ++iter) {
    const Point a{random_wide(rng), random_wide(rng)};
    const Point b{random_wide(rng), random_wide(rng)};
    const Point c{nudge(a.x, static_cast<int>(rng() % 3) - 1), b.y};
    if (!all_in_range(c)) continue;
    const double area = signed_area(a, b, c);
    const QPoint qa(a), qb(b), qc(c);
    const mpq_class exact = ((qa.x - qc.x) * (qb.y - qc.y) - (qa.y - qc.y) * (qb.x - qc.x)) / 2;
    EXPECT_EQ((area > 0) - (area < 0), sgn(exact));
    if (exact != 0) {
      EXPECT_LT(rel_err(area, exact.get_d()), 1e-15);
    }
  }
}

// Does the floating-point filter decide these points, or do they go to the exact stage? The
// orient2d filter is inline in geometry.hpp; this is the same test (its error bound kOrientBound);
// incircle's filter is detail::incircle_determinant itself.
bool orient_filter_decides(const Point& a, const Point& b, const Point& c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  return std::fabs(left - right) > detail::kOrientBound * (std::fabs(left) + std::fabs(right));
}
bool incircle_filter_decides(const Point& a, const Point& b, const Point& c, const Point& d) {
  const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, c, d);
  return std::fabs(det.value) > det.bound;
}

// Where the exact stage is reached: always for exactly degenerate cases (a filter that decided
// one would return a non-zero sign for a zero determinant), for most of the near-degenerate
// families the tests above use (so that they test the exact stage, not only the filter), and never
// for well-separated points (so that the filter does its job: the exact stage is ~100 times
// slower). Every sign is checked against the oracle as well.
TEST(Predicates, ExactStageReachedExactlyWhereNeeded) {
  const FailureScope scope;
  Rng rng(606);
  // Exactly collinear (points on y = x, and Shewchuk's diagonal i == j) and exactly cocircular
  // (the symmetric ring): the filter must never decide.
  std::int64_t degenerate = 0, degenerate_decided = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    const double scale = kScales[iter % 3];
    const double x1 = uniform(rng, -1.0, 1.0) * scale, x2 = uniform(rng, -1.0, 1.0) * scale,
                 x3 = uniform(rng, -1.0, 1.0) * scale;
    const Point a{x1, x1}, b{x2, x2}, c{x3, x3};
    if (!all_in_range(a, b, c)) continue;
    EXPECT_EQ(check_orient(a, b, c), 0);
    ++degenerate;
    degenerate_decided += orient_filter_decides(a, b, c);
    const double p = uniform(rng, 0.01, 1.0) * scale, q = uniform(rng, 0.01, 1.0) * scale;
    const std::array<Point, 4> ring = {Point{p, q}, Point{-q, p}, Point{-p, -q}, Point{q, -p}};
    EXPECT_EQ(check_incircle(ring[0], ring[1], ring[2], ring[3]), 0);
    ++degenerate;
    degenerate_decided += incircle_filter_decides(ring[0], ring[1], ring[2], ring[3]);
  }
  EXPECT_GT(degenerate, 5000);
  EXPECT_EQ(degenerate_decided, 0);

  // Near-degenerate: Shewchuk's orient2d grid (one-ulp steps near (0.5, 0.5) against (12, 12),
  // (24, 24)), whose determinants (at most 12 · 64 ulps of 0.5, about 8.5e-14) are all below the
  // filter's bound (about 1.9e-13), and the incircle grid near the circle through (±0.5, ±0.5),
  // where the bound (about 4.4e-15) is of the order of the determinants (up to 64 ulps of 0.5,
  // about 7e-15, in the grid's far corners): the orient2d cases all reach the exact stage, most of
  // the incircle ones (86 % when this was written).
  constexpr double u = 0x1p-53;
  std::int64_t near = 0, orient_near_exact = 0, incircle_near_exact = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const Point p{0.5 + i * u, 0.5 + j * u};
      check_orient(p, Point{12, 12}, Point{24, 24});
      orient_near_exact += !orient_filter_decides(p, Point{12, 12}, Point{24, 24});
      const Point d{0.5 + (i - 32) * u, 0.5 + (j - 32) * u};
      check_incircle(Point{-0.5, 0.5}, Point{-0.5, -0.5}, Point{0.5, -0.5}, d);
      incircle_near_exact += !incircle_filter_decides(Point{-0.5, 0.5}, Point{-0.5, -0.5}, Point{0.5, -0.5}, d);
      ++near;
    }
  }
  EXPECT_EQ(orient_near_exact, near);
  EXPECT_GT(incircle_near_exact, near * 3 / 4) << incircle_near_exact << " of " << near;

  // Well separated: random triangles in the unit square whose orientation determinant is at least
  // 1e-3 (the filter's bound there is below 1e-14), and points at least 1e-3 (relative to the
  // circle's size) inside or outside the circumcircle: the filter decides every one.
  std::int64_t easy = 0, easy_exact = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    const Point a{uniform(rng, 0, 1), uniform(rng, 0, 1)}, b{uniform(rng, 0, 1), uniform(rng, 0, 1)},
        c{uniform(rng, 0, 1), uniform(rng, 0, 1)}, d{uniform(rng, 0, 1), uniform(rng, 0, 1)};
    const double orientation = (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
    if (std::fabs(orientation) < 1e-3) continue;
    check_orient(a, b, c);
    ++easy;
    easy_exact += !orient_filter_decides(a, b, c);
    const Point centre = circumcenter(a, b, c);
    const double r = distance(centre, a), from_centre = distance(centre, d);
    if (r > 10.0 || std::fabs(from_centre - r) < 1e-3 * r) continue;
    check_incircle(a, b, c, d);
    ++easy;
    easy_exact += !incircle_filter_decides(a, b, c, d);
  }
  EXPECT_GT(easy, 20000);
  EXPECT_EQ(easy_exact, 0);
}

}  // namespace
}  // namespace mwst
