// src/algorithms/bundle/bundle.cpp — the exact bundle number of a triangulation (mwst/algorithms/bundle.hpp).
//
// Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" define k-bundles (k triangles
// whose interiors meet one vertex-empty open disk) and prove that a k-bundle-free triangulation
// respecting the local feature size weighs O(1)·MWST. This file measures the largest bundle exactly,
// following the method of docs/algorithms/bundle-number.md.
//
// Geometry of one pencil. Let pq be an edge of DT(V), V the vertices of the triangulation T. In
// local coordinates p = (−1, 0), q = (1, 0) the disk D_s has centre (0, s) and radius √(1 + s²).
// With f(x) = (|x|² − 1) / (2 x₂), a point x above the line (x₂ > 0) lies in D_s iff s > f(x), and
// one below iff s < f(x): the upper part of D_s grows with s, the lower part shrinks. D_s contains
// no vertex iff s_lo ≤ s ≤ s_hi, the values of f at the apices of the two Delaunay triangles on pq
// (−∞ / +∞ on a hull side). D_s always contains the open chord pq. So a triangle t of T
//   - meets every D_s if the closed t meets the open chord pq ("always");
//   - otherwise meets D_s iff s > a_t (a_t = inf of f over t above the line) or s < b_t (b_t = sup
//     of f over t below the line).
// f has no critical point, so a_t is reached on t's boundary: at a vertex (but every vertex above
// the line has f ≥ s_hi, so vertices never matter), in the limit at p or q along an edge of t
// incident to p or q (the pencil circle tangent to that edge at p or q; along such an edge f is
// linear, so nothing else of it matters), or at an interior point of an edge where a pencil circle
// is tangent to it. That last case happens iff f decreases into the edge from each end that is a
// vertex above the line (an end where the edge crosses the line outside the chord has f = +∞), i.e.
// iff the edge direction at each such end u enters the circle through p, q and u — an exact
// predicate of degree 4. f restricted to a line is convex on the part above the line when the line
// crosses the line pq outside the chord (or is parallel to it) and concave when it crosses the
// chord, so the tangency, when it exists, is the minimum.
//
// Thresholds are rational in the coordinates except the tangencies: s_lo, s_hi (circle through a
// vertex x: s = (x−p)·(x−q) / orient(p, q, x)) and the tangents at p or q (s = (x−p)·(p−q) / orient
// and (x−q)·(q−p) / orient). Their rounded values carry a rigorous error bound; when two of them are
// too close to order by their values they are compared exactly (expansion arithmetic,
// src/geometry/expansion.hpp). Exact ties are common in meshes (grids, collinear edges: the tangent
// at p along an edge above the line equals the tangent along the collinear edge below it, and then
// no disk meets both triangles). Tangencies to edge interiors are ordered by their rounded values.
//
// Sweep. The events (a_t, b_t, s_lo, s_hi) are sorted and grouped into classes of equal value; the
// count on the open interval between consecutive classes is (always) + #{a_t below} + #{b_t above}.
// Only open intervals inside (s_lo, s_hi) are needed: the triangles met by the end disk D_{s_lo}
// are also met by D_s for s slightly above s_lo (and likewise at s_hi), and when s_lo = s_hi
// (cocircular vertices) the only disk is a circumdisk, which is the end of another pencil.
//
// Candidates. Every disk of the pencil lies in D_{s_lo} ∪ D_{s_hi}, the circumdisks of the two
// Delaunay triangles on pq. For each Delaunay triangle we flood over the mesh — across holes and
// concavities through its carved-away triangles, which is why a Mesh covering the convex hull is
// used — collecting the triangles whose edges meet the circumdisk (a permissive floating-point
// test: the incircle determinant is a concave quadratic along an edge; a superset is harmless).
//
// Work. A pencil's candidates are classified edge by edge, each edge once for both triangles on it;
// likewise a circumdisk's count decides each edge, and each corner's exact incircle, once per disk.
// Without per-triangle values, a pencil with no more candidates than the best count so far is
// skipped. Vertices are renumbered along a Morton curve for locality; floods and pencils are split
// over worker threads in contiguous ranges and merged deterministically (largest count, ties to the
// first pencil, which no thread ever skips).
#include "mwst/algorithms/bundle.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include <gmp.h>

#include "geometry/expansion.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

namespace {

constexpr double kEps = detail::kEpsilon;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- floating-point values with error bounds ------------------------------------------------

struct Approx {
  double value = 0.0;
  double error = 0.0;  // |value − exact| ≤ error
};

// The incircle determinant of geometry.hpp (positive inside the circle through the
// counter-clockwise a, b, c), rounded, with Shewchuk's first-stage error bound. As a function of d
// it equals orient(a, b, c) · (r² − |d − centre|²).
Approx incircle_approx(const Point& a, const Point& b, const Point& c, const Point& d) {
  const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, c, d);
  return {det.value, det.bound};
}

// The orient2d determinant of (a, b, c), rounded, with an error bound; recomputed exactly (and
// rounded once) when the filter cannot vouch for its sign.
Approx orient_approx(const Point& a, const Point& b, const Point& c) {
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

// The value of an exact expansion rounded, with a rigorous bound: summing from the smallest
// component, each addition errs by at most ε of its rounded result (doubled for the rounding of
// the bound itself).
template <int N>
Approx estimate_with_error(const exact::Expansion<N>& e) {
  double sum = 0.0, partial = 0.0;
  for (int i = 0; i < e.n; ++i) {
    sum += e.c[i];
    partial += std::fabs(sum);
  }
  return {sum, 2.0 * kEps * partial};
}

// x·y rounded, with a rigorous bound: |xy − x̃ỹ| ≤ |x̃|δy + |ỹ|δx + δxδy, plus the product's own
// rounding (at most 2ε of it, with margin).
Approx approx_mul(const Approx& x, const Approx& y) {
  const double v = x.value * y.value;
  return {v, std::fabs(x.value) * y.error + std::fabs(y.value) * x.error + x.error * y.error +
                 2.0 * kEps * std::fabs(v)};
}

// a·b + c·d for doubles a, b, c, d, rounded, with a rigorous bound: the two products split exactly
// into value and error (two_product), the four parts summed (the two values first: they cancel
// when the sum is small), each addition erring by at most ε of its result (doubled, as in
// estimate_with_error, for the rounding of the bound itself). two_product is exact without
// underflow: for supported coordinates (0 or magnitude in [1e-50, 1e50]) a nonzero difference is at
// least an ulp of 1e-50 (about 1e-66), so products and their error terms stay far above it.
Approx sum_of_products(double a, double b, double c, double d) {
  double x1 = 0.0, y1 = 0.0, x2 = 0.0, y2 = 0.0;
  exact::two_product(a, b, x1, y1);
  exact::two_product(c, d, x2, y2);
  const double s1 = x1 + x2;
  const double s2 = s1 + y1;
  const double s3 = s2 + y2;
  return {s3, 2.0 * kEps * (std::fabs(s1) + std::fabs(s2) + std::fabs(s3))};
}

}  // namespace

// (Declared in mwst/algorithms/bundle.hpp, where its geometry is described.)
int detail::enters_circle(const Point& p, const Point& q, const Point& u, const Point& w, int orient_pqu) {
  const double pux = p.x - u.x, puy = p.y - u.y;
  const double qux = q.x - u.x, quy = q.y - u.y;
  const double ex = w.x - u.x, ey = w.y - u.y;
  const double plift = pux * pux + puy * puy;
  const double qlift = qux * qux + quy * quy;
  const double exquy = ex * quy, eyqux = ey * qux;
  const double expuy = ex * puy, eypux = ey * pux;
  const double det = plift * (exquy - eyqux) - qlift * (expuy - eypux);
  const double permanent = plift * (std::fabs(exquy) + std::fabs(eyqux)) +
                           qlift * (std::fabs(expuy) + std::fabs(eypux));
  // Two of the three terms of incircle, same structure: incircle's bound covers it.
  const double bound = detail::kIncircleBound * permanent;
  int s = 0;
  if (det > bound) {
    s = 1;
  } else if (-det > bound) {
    s = -1;
  } else {
    using namespace exact;
    // Second stage: the four factors |p'|², |q'|², cross(e, q'), cross(e, p'), each rounded with a
    // rigorous error bound (each addition's rounding is at most ε of the partial sum). The first
    // stage fails when the cross products cancel (near-tangent edges: nearly collinear p, q, u, as
    // on flat hulls or along segments that cross many times, where most calls end up here); the
    // terms pl·cq and ql·cp rarely cancel then, and the products of 16 × 16 components are needed
    // only when they do. When the six differences are exact doubles (coordinates within a factor
    // 2 of each other, Sterbenz, or otherwise exactly representable), each factor is a sum of two
    // exact products: four doubles, no expansion arithmetic.
    double dx[6], tail[6];
    two_diff(p.x, u.x, dx[0], tail[0]);
    two_diff(p.y, u.y, dx[1], tail[1]);
    two_diff(q.x, u.x, dx[2], tail[2]);
    two_diff(q.y, u.y, dx[3], tail[3]);
    two_diff(w.x, u.x, dx[4], tail[4]);
    two_diff(w.y, u.y, dx[5], tail[5]);
    const bool exact_differences =
        tail[0] == 0.0 && tail[1] == 0.0 && tail[2] == 0.0 && tail[3] == 0.0 && tail[4] == 0.0 && tail[5] == 0.0;
    // The factors as exact expansions (compressed).
    struct ExactFactors {
      Expansion<16> pl, ql, cq, cp;
    };
    auto exact_factors = [&] {
      Expansion<2> d[6];  // the differences above, exactly: rounded value and tail
      for (int i = 0; i < 6; ++i) {
        d[i].push(tail[i]);
        d[i].push(dx[i]);
      }
      const auto &epx = d[0], &epy = d[1], &eqx = d[2], &eqy = d[3], &eex = d[4], &eey = d[5];
      ExactFactors f{epx * epx + epy * epy, eqx * eqx + eqy * eqy, eex * eqy - eey * eqx, eex * epy - eey * epx};
      compress(f.pl);
      compress(f.ql);
      compress(f.cq);
      compress(f.cp);
      return f;
    };
    Approx apl, aql, acq, acp;
    if (exact_differences) {
      apl = sum_of_products(dx[0], dx[0], dx[1], dx[1]);
      aql = sum_of_products(dx[2], dx[2], dx[3], dx[3]);
      acq = sum_of_products(dx[4], dx[3], -dx[5], dx[2]);
      acp = sum_of_products(dx[4], dx[1], -dx[5], dx[0]);
    } else {
      const ExactFactors f = exact_factors();
      apl = estimate_with_error(f.pl);
      aql = estimate_with_error(f.ql);
      acq = estimate_with_error(f.cq);
      acp = estimate_with_error(f.cp);
    }
    const Approx term_q = approx_mul(apl, acq), term_p = approx_mul(aql, acp);
    const double det2 = term_q.value - term_p.value;
    const double bound2 = 2.0 * (term_q.error + term_p.error + 2.0 * kEps * std::fabs(det2)) + 1e-290;
    if (std::isfinite(det2) && std::isfinite(bound2) && std::fabs(det2) > bound2) {
      s = det2 > 0.0 ? 1 : -1;
    } else {
      const ExactFactors f = exact_factors();
      s = sign(f.pl * f.cq - f.ql * f.cp);
    }
  }
  return s * orient_pqu;
}

namespace {

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
                                         const Point& w) {
  const Point* const points[5] = {&a, &b, &c, &u, &w};
  int min_exponent = std::numeric_limits<int>::max();
  for (const Point* p : points) {
    for (const double v : {p->x, p->y}) {
      if (v == 0.0) continue;
      int e = 0;
      std::frexp(v, &e);
      min_exponent = std::min(min_exponent, e - 53);
    }
  }
  // v = m · 2^(e − 53) with |m| < 2^53 an integer; as an integer multiple of 2^min_exponent.
  auto to_integer = [min_exponent](mpz_t out, double v) {
    if (v == 0.0) {
      mpz_set_ui(out, 0);
      return;
    }
    int e = 0;
    const double m = std::ldexp(std::frexp(v, &e), 53);
    mpz_set_d(out, m);  // exact: m is an integer below 2^53 in magnitude
    mpz_mul_2exp(out, out, static_cast<mp_bitcnt_t>(e - 53 - min_exponent));
  };
  // Coordinates relative to u: A, B, Cc (circle), E = w − u.
  // Integers of a few hundred bits; one set per thread, allocated once.
  struct Registers {
    mpz_t ux, uy, ax, ay, bx, by, cx, cy, ex, ey, t1, t2, term, lift_a, lift_b, lift_c, gu, gw, orient, coef,
        slope, disc;
    Registers() {
      for (mpz_t* z : all()) mpz_init2(*z, 512);
    }
    ~Registers() {
      for (mpz_t* z : all()) mpz_clear(*z);
    }
    Registers(const Registers&) = delete;
    Registers& operator=(const Registers&) = delete;
    std::array<mpz_t*, 22> all() {
      return {&ux, &uy, &ax, &ay, &bx, &by, &cx, &cy, &ex, &ey, &t1, &t2, &term, &lift_a, &lift_b, &lift_c,
              &gu, &gw, &orient, &coef, &slope, &disc};
    }
  };
  thread_local Registers r;
  // Named references (not a structured binding: lambdas below use them).
  auto& ux = r.ux; auto& uy = r.uy; auto& ax = r.ax; auto& ay = r.ay; auto& bx = r.bx; auto& by = r.by;
  auto& cx = r.cx; auto& cy = r.cy; auto& ex = r.ex; auto& ey = r.ey; auto& t1 = r.t1;
  auto& t2 = r.t2; auto& term = r.term; auto& lift_a = r.lift_a; auto& lift_b = r.lift_b;
  auto& lift_c = r.lift_c; auto& gu = r.gu; auto& gw = r.gw; auto& orient = r.orient;
  auto& coef = r.coef; auto& slope = r.slope; auto& disc = r.disc;
  to_integer(ux, u.x);
  to_integer(uy, u.y);
  // p −= d, in place.
  auto translate = [](mpz_t px, mpz_t py, const mpz_t dx, const mpz_t dy) {
    mpz_sub(px, px, dx);
    mpz_sub(py, py, dy);
  };
  auto relative = [&](mpz_t out_x, mpz_t out_y, const Point& p) {
    to_integer(out_x, p.x);
    to_integer(out_y, p.y);
    translate(out_x, out_y, ux, uy);
  };
  relative(ax, ay, a);
  relative(bx, by, b);
  relative(cx, cy, c);
  relative(ex, ey, w);
  // cross(p, q) = p.x q.y − p.y q.x into `out`.
  auto cross = [&](mpz_t out, const mpz_t px, const mpz_t py, const mpz_t qx, const mpz_t qy) {
    mpz_mul(t1, px, qy);
    mpz_mul(t2, py, qx);
    mpz_sub(out, t1, t2);
  };
  auto lift = [&](mpz_t out, const mpz_t px, const mpz_t py) {
    mpz_mul(t1, px, px);
    mpz_mul(t2, py, py);
    mpz_add(out, t1, t2);
  };
  // g at the origin (u) of the circle through A, B, Cc: the incircle determinant with d = u.
  auto incircle_at_origin = [&](mpz_t out) {
    lift(lift_a, ax, ay);
    lift(lift_b, bx, by);
    lift(lift_c, cx, cy);
    cross(term, bx, by, cx, cy);
    mpz_mul(out, lift_a, term);
    cross(term, cx, cy, ax, ay);
    mpz_addmul(out, lift_b, term);
    cross(term, ax, ay, bx, by);
    mpz_addmul(out, lift_c, term);
  };
  incircle_at_origin(gu);
  // g at w: shift the circle's points by −E.
  translate(ax, ay, ex, ey);
  translate(bx, by, ex, ey);
  translate(cx, cy, ex, ey);
  incircle_at_origin(gw);
  // orient(a, b, c) = cross(b − a, c − a) (translation invariant).
  translate(bx, by, ax, ay);
  translate(cx, cy, ax, ay);
  cross(orient, bx, by, cx, cy);
  lift(lift_a, ex, ey);  // |E|²
  mpz_mul(coef, orient, lift_a);
  mpz_sub(slope, gw, gu);
  mpz_add(slope, slope, coef);
  bool meets = false;
  if (mpz_sgn(slope) > 0) {
    mpz_mul_2exp(t1, coef, 1);
    if (mpz_cmp(slope, t1) < 0) {
      mpz_mul(disc, slope, slope);
      mpz_mul(t1, coef, gu);
      mpz_mul_2exp(t1, t1, 2);
      mpz_add(disc, disc, t1);
      meets = mpz_sgn(disc) > 0;
    }
  }
  return meets;
}

// The same question, filtered: rounded values with rigorous error bounds decide when they can;
// +1 meets, 0 does not, −1 undecided. Also right when u or w lies on the circle (g ≤ 0 at both
// ends: then g(1) = S − C ≤ 0 rules out S ≥ 2C, and the three conditions still say whether g is
// positive somewhere inside).
int segment_meets_open_circumdisk_filtered(const Point& a, const Point& b, const Point& c, const Point& u,
                                           const Point& w) {
  // The filter does not form S from g_w − g_u (which cancels for flat circles) but from the centre:
  // with O = orient(a, b, c), Y = 2O·(centre − a) (degree 3, from B = b − a, C = c − a) and
  // X = 2O·(centre − u) = Y + 2O·(a − u):
  //   S = g'(0) = X·e,   2C − S = 2O|e|² − X·e,   S² + 4C g_u = |e|²|Y|² − cross(e, X)²
  // (the last: 4O²(r²|e|² − cross(e, centre − u)²), Lagrange's identity). These cancel only when
  // the geometry is borderline (the foot of the centre at an end of the segment, the line tangent
  // to the circle); then the exact integer evaluation decides.
  // Rounded values with rigorous forward error bounds: |x·y − x̃·ỹ| ≤ |x̃|δy + |ỹ|δx + δxδy, and
  // each operation's own rounding at most 2ε of its result.
  auto mul = [](const Approx& x, const Approx& y) {
    const double v = x.value * y.value;
    return Approx{v, std::fabs(x.value) * y.error + std::fabs(y.value) * x.error + x.error * y.error +
                         2.0 * kEps * std::fabs(v)};
  };
  auto add = [](const Approx& x, const Approx& y) {
    const double v = x.value + y.value;
    return Approx{v, x.error + y.error + 2.0 * kEps * std::fabs(v)};
  };
  auto sub = [](const Approx& x, const Approx& y) {
    const double v = x.value - y.value;
    return Approx{v, x.error + y.error + 2.0 * kEps * std::fabs(v)};
  };
  auto diff = [](double x, double y) {
    const double v = x - y;
    return Approx{v, 2.0 * kEps * std::fabs(v)};
  };
  const Approx o = orient_approx(a, b, c);
  const Approx two_o{2.0 * o.value, 2.0 * o.error};
  const Approx bx = diff(b.x, a.x), by = diff(b.y, a.y), cx = diff(c.x, a.x), cy = diff(c.y, a.y);
  const Approx b2 = add(mul(bx, bx), mul(by, by)), c2 = add(mul(cx, cx), mul(cy, cy));
  const Approx yx = sub(mul(cy, b2), mul(by, c2)), yy = sub(mul(bx, c2), mul(cx, b2));
  const Approx xx = add(yx, mul(two_o, diff(a.x, u.x))), xy = add(yy, mul(two_o, diff(a.y, u.y)));
  const Approx ex = diff(w.x, u.x), ey = diff(w.y, u.y);
  const Approx e2 = add(mul(ex, ex), mul(ey, ey));
  const Approx slope = add(mul(xx, ex), mul(xy, ey));
  const Approx top_right = sub(mul(two_o, e2), slope);
  const Approx cross_ex = sub(mul(ex, xy), mul(ey, xx));
  const Approx disc = sub(mul(e2, add(mul(yx, yx), mul(yy, yy))), mul(cross_ex, cross_ex));
  // Decided only from finite values well clear of the subnormal range (where bounds relative to
  // the values would no longer hold); a margin of 2 on every bound.
  auto sign_of = [](const Approx& x) {
    const double bound = 2.0 * x.error + 1e-280;
    if (!std::isfinite(x.value) || !std::isfinite(bound)) return 2;
    return x.value > bound ? 1 : (x.value < -bound ? -1 : 2);
  };
  const int s_slope = sign_of(slope), s_top = sign_of(top_right), s_disc = sign_of(disc);
  if (s_slope == -1 || s_top == -1 || s_disc == -1) return 0;
  if (s_slope == 1 && s_top == 1 && s_disc == 1) return 1;
  return -1;
}

// Exact: the filter, then integers.
bool segment_meets_open_circumdisk(const Point& a, const Point& b, const Point& c, const Point& u, const Point& w) {
  const int filtered = segment_meets_open_circumdisk_filtered(a, b, c, u, w);
  return filtered >= 0 ? filtered == 1 : segment_meets_open_circumdisk_exact(a, b, c, u, w);
}

// ---- thresholds of one pencil -----------------------------------------------------------------

enum class Kind : std::uint8_t {
  kThroughVertex,  // the pencil circle through vertex x (s_lo, s_hi)
  kTangentAtP,     // the pencil circle tangent at p to the edge p→x
  kTangentAtQ,     // the pencil circle tangent at q to the edge q→x
  kTangentToEdge,  // the pencil circle tangent to an edge at an interior point (irrational)
};

struct Threshold {
  double value = 0.0;
  double error = 0.0;  // rigorous bound for the rational kinds; 0 for kTangentToEdge
  VertexId xv = kNone; // the vertex defining a rational threshold
  Kind kind = Kind::kTangentToEdge;
};

struct Pencil {
  Point p, q;
  VertexId pv = kNone, qv = kNone;
  double bx = 0.0, by = 0.0;        // q − p, rounded
  double local_scale = 0.0;         // 2 / |q − p|²
  const Point* points = nullptr;    // vertex coordinates, for the exact comparisons
};

// Numerator and denominator of a rational threshold, exactly: s = N / D with D = orient(p, q, x).
void rational_exact(const Pencil& pc, Kind kind, const Point& x, exact::Expansion<16>& num,
                    exact::Expansion<16>& den) {
  using namespace exact;
  const Expansion<2> bx = difference(pc.q.x, pc.p.x), by = difference(pc.q.y, pc.p.y);
  const Expansion<2> dpx = difference(x.x, pc.p.x), dpy = difference(x.y, pc.p.y);
  den = bx * dpy - by * dpx;
  switch (kind) {
    case Kind::kThroughVertex: {
      const Expansion<2> dqx = difference(x.x, pc.q.x), dqy = difference(x.y, pc.q.y);
      num = dpx * dqx + dpy * dqy;
      break;
    }
    case Kind::kTangentAtP:
      num = -(dpx * bx + dpy * by);
      break;
    case Kind::kTangentAtQ: {
      const Expansion<2> dqx = difference(x.x, pc.q.x), dqy = difference(x.y, pc.q.y);
      num = dqx * bx + dqy * by;
      break;
    }
    case Kind::kTangentToEdge:
      throw InternalError("bundle: rational_exact on a tangency threshold");
  }
  compress(num);
  compress(den);
}

// A rational threshold: the pencil circle through x (kThroughVertex) or tangent at p / q to the
// edge towards x. x must not lie on the line pq.
//   through x:          centre c with |c − p| = |c − x|  ⇒ s = (x−p)·(x−q) / cross(q−p, x−p)
//   tangent at p to px: (c − p)·(x − p) = 0             ⇒ s = (x−p)·(p−q) / cross(q−p, x−p)
//   tangent at q to qx: (c − q)·(x − q) = 0             ⇒ s = (x−q)·(q−p) / cross(q−p, x−p)
Threshold rational_threshold(const Pencil& pc, Kind kind, VertexId xv, const Point& x) {
  Threshold t;
  t.kind = kind;
  t.xv = xv;
  const double dpx = x.x - pc.p.x, dpy = x.y - pc.p.y;
  const double d1 = pc.bx * dpy, d2 = pc.by * dpx;
  const double den = d1 - d2;
  const double den_abs = std::fabs(d1) + std::fabs(d2);
  double n1 = 0.0, n2 = 0.0;
  if (kind == Kind::kTangentAtP) {
    n1 = -(dpx * pc.bx);
    n2 = -(dpy * pc.by);
  } else {
    const double dqx = x.x - pc.q.x, dqy = x.y - pc.q.y;
    if (kind == Kind::kThroughVertex) {
      n1 = dpx * dqx;
      n2 = dpy * dqy;
    } else {
      n1 = dqx * pc.bx;
      n2 = dqy * pc.by;
    }
  }
  const double num = n1 + n2;
  const double num_abs = std::fabs(n1) + std::fabs(n2);
  // Each of num, den is within 4ε of its absolute sum (rounded differences, products, one sum);
  // while |den| > 8ε·den_abs, |N/D − num/den| ≤ 8ε(num_abs + |s|·den_abs)/|den|, plus the division.
  // Accept only well-conditioned quotients, so that error windows stay narrow.
  if (std::fabs(den) > 1e-4 * den_abs) {
    t.value = num / den;
    t.error = 9.0 * kEps * (num_abs + std::fabs(t.value) * den_abs) / std::fabs(den) +
              2.0 * kEps * std::fabs(t.value);
    return t;
  }
  exact::Expansion<16> en, ed;
  rational_exact(pc, kind, x, en, ed);
  t.value = exact::estimate(en) / exact::estimate(ed);
  t.error = 8.0 * kEps * std::fabs(t.value);
  return t;
}

// The exact comparison of two rational thresholds (see compare_thresholds).
[[gnu::noinline]] int compare_rational_exact(const Pencil& pc, const Threshold& a, const Threshold& b) {
  using namespace exact;
  Expansion<16> na, da, nb, db;
  rational_exact(pc, a.kind, pc.points[a.xv], na, da);
  rational_exact(pc, b.kind, pc.points[b.xv], nb, db);
  // a − b = (na·db − nb·da) / (da·db).
  const int s = sign(na * db - nb * da);
  return s * sign(da) * sign(db);
}

// −1, 0, +1 as a < b, a = b, a > b: exact unless a tangency threshold is involved (then by the
// rounded values).
inline int compare_thresholds(const Pencil& pc, const Threshold& a, const Threshold& b,
                              std::size_t& exact_count) {
  const double gap = a.value - b.value;
  const double window = a.error + b.error;
  if (gap > window) return 1;
  if (-gap > window) return -1;
  if (a.kind == Kind::kTangentToEdge || b.kind == Kind::kTangentToEdge) return (gap > 0.0) - (gap < 0.0);
  if (a.kind == b.kind && a.xv == b.xv) return 0;
  ++exact_count;
  return compare_rational_exact(pc, a, b);
}

// The minimum of f over the part above the line of the segment u→w (local coordinates, u₂ > 0),
// given that it lies inside the segment (a pencil circle tangent to it). Along x = u + λe,
// f' = 0 iff A λ² + B λ + C = 0 with A = |e|² e₂, B = 2 |e|² u₂, C = 2 u₂ (u·e) − e₂ (|u|² − 1).
double tangency_minimum(const Point& u, const Point& w) {
  const double ex = w.x - u.x, ey = w.y - u.y;
  const double lambda_end = w.y > 0.0 ? 1.0 : u.y / (u.y - w.y);
  const double e2 = ex * ex + ey * ey;
  const double qa = e2 * ey;
  const double qb = 2.0 * e2 * u.y;
  const double qc = 2.0 * u.y * (u.x * ex + u.y * ey) - ey * ((u.x * u.x + u.y * u.y) - 1.0);
  double best = kInf;
  auto consider = [&](double lambda) {
    if (!(lambda > 0.0)) lambda = 0.0;
    if (lambda > lambda_end) lambda = lambda_end;
    const double x = u.x + lambda * ex, y = u.y + lambda * ey;
    if (!(y > 0.0)) return;
    best = std::min(best, ((x * x + y * y) - 1.0) / (2.0 * y));
  };
  if (qa == 0.0) {
    consider(-qc / qb);
  } else {
    const double disc = std::max(qb * qb - 4.0 * qa * qc, 0.0);
    const double root = std::sqrt(disc);
    const double qq = -0.5 * (qb + std::copysign(root, qb));  // qb > 0: no cancellation
    consider(qq / qa);
    if (qq != 0.0) consider(qc / qq);
  }
  if (best == kInf) consider(0.0);  // cannot happen unless rounding pushed both roots away
  return best;
}

// ---- data shared by the workers -----------------------------------------------------------------

// Morton (Z-order) key, 30 bits, of the cell of (x, y) in a 2^15 × 2^15 grid over the bounding box.
std::uint32_t morton_key(const Point& p, double x0, double y0, double scale) {
  auto cell = [scale](double v, double v0) {
    const double c = (v - v0) * scale;
    return static_cast<std::uint32_t>(std::clamp(c, 0.0, 32767.0));
  };
  auto spread = [](std::uint32_t v) {
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
  };
  return spread(cell(p.x, x0)) | (spread(cell(p.y, y0)) << 1);
}

// Dense ids 0, 1, ... for 32-bit keys (mesh slots or vertex ids) in the order they are inserted:
// an open-addressing hash table, so that in_k_bundle's local attempt costs what its region holds,
// not what the mesh holds.
class DenseIds {
 public:
  explicit DenseIds(std::size_t expected = 0) { rehash(std::bit_ceil(2 * expected + 16)); }

  std::size_t size() const { return keys_.size(); }
  std::uint32_t key(std::uint32_t id) const { return keys_[id]; }

  // The id of `key`, or kNone.
  std::uint32_t find(std::uint32_t key) const {
    for (std::size_t i = hash(key);; i = (i + 1) & mask_) {
      const Cell& c = table_[i];
      if (c.id == kNone || c.key == key) return c.id;
    }
  }

  // The id of `key`, and whether it was added now.
  std::pair<std::uint32_t, bool> insert(std::uint32_t key) {
    if (2 * (keys_.size() + 1) > table_.size()) rehash(2 * table_.size());
    std::size_t i = hash(key);
    for (;; i = (i + 1) & mask_) {
      const Cell& c = table_[i];
      if (c.id == kNone) break;
      if (c.key == key) return {c.id, false};
    }
    const auto id = static_cast<std::uint32_t>(keys_.size());
    table_[i] = {key, id};
    keys_.push_back(key);
    return {id, true};
  }

 private:
  struct Cell {
    std::uint32_t key = 0;
    std::uint32_t id = kNone;  // kNone: empty
  };
  // Fibonacci hashing: the top bits of key · 2^64/φ.
  std::size_t hash(std::uint32_t key) const {
    return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void rehash(std::size_t capacity) {
    table_.assign(capacity, Cell{});
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    for (std::uint32_t id = 0; id < keys_.size(); ++id) {
      std::size_t i = hash(keys_[id]);
      while (table_[i].id != kNone) i = (i + 1) & mask_;
      table_[i] = {keys_[id], id};
    }
  }

  std::vector<Cell> table_;
  std::vector<std::uint32_t> keys_;  // by id
  std::size_t mask_ = 0;
  int shift_ = 64;
};

// What every worker reads: the mesh with its vertices renumbered along a Morton curve (so that the
// per-vertex scratch of neighbouring pencils is close in memory), DT(V), the candidate list of
// every Delaunay triangle, and the pencils (one Delaunay edge each).
struct Shared {
  explicit Shared(const Mesh& mesh,
                  std::chrono::steady_clock::time_point until = std::chrono::steady_clock::time_point::max())
      : m(mesh), deadline(until) {}

  // Throws KBundleTimeout once the deadline (in_k_bundle's) has passed; called once per item of
  // the costly loops (floods, circumdisk counts, sweeps), each of which costs far more.
  void check_deadline() const {
    if (deadline != std::chrono::steady_clock::time_point::max() && std::chrono::steady_clock::now() > deadline) {
      throw KBundleTimeout();
    }
  }

  const Mesh& m;
  std::chrono::steady_clock::time_point deadline;
  std::vector<Point> pts;                   // by renumbered vertex id
  std::vector<VertexId> mesh_id;            // by renumbered vertex id: the mesh's id
  struct Slot {
    std::array<VertexId, 3> v;  // corners, renumbered (kInfinite for ghosts and dead slots)
    std::array<Handle, 3> n;    // neighbours, as in Triangle::n (renumbered slots in a region)
  };
  // Every mesh slot (build), or the slots of a region of the mesh renumbered densely followed by
  // one slot, `outside`, that stands for every triangle beyond the region (build_region).
  std::vector<Slot> slots;
  std::vector<std::uint8_t> domain;         // per slot: in the domain (Mesh::in_domain)
  TriangleId outside = kNone;               // the slot beyond a region (kNone: the whole mesh)
  std::vector<Handle> vertex_edge;          // renumbered id → a mesh edge leaving the vertex
  std::uint32_t used = 0;                   // ids [0, used) are the vertices of T, and DT ids
  Mesh dt;
  std::vector<std::uint32_t> list_begin;    // per DT slot: its candidates in `list`
  std::vector<TriangleId> list;
  std::vector<Handle> pencils;              // per Delaunay edge: a DT handle with a finite left side
  // Per DT slot (empty: none): its list was cut at the budget's cap (bundle_number with a budget).
  std::vector<std::uint8_t> truncated;
  bool kept_dt = false;                     // dt is a kept DT(V) with the new vertices inserted

  Handle sym(Handle h) const { return slots[h >> 2].n[h & 3]; }
  VertexId org(Handle h) const { return slots[h >> 2].v[next3(h & 3)]; }
  VertexId dest(Handle h) const { return slots[h >> 2].v[prev3(h & 3)]; }
  VertexId apex(Handle h) const { return slots[h >> 2].v[h & 3]; }
  Handle onext(Handle h) const { return sym(Mesh::lprev(h)); }
  bool is_ghost(TriangleId t) const {
    const auto& v = slots[t].v;
    return v[0] == kInfinite || v[1] == kInfinite || v[2] == kInfinite;
  }
  bool in_domain(TriangleId t) const { return domain[t] != 0; }

  // Renumbers, builds DT(V) and (if asked) lists the pencils. False if T has no triangle. With a
  // `subset` W (mesh vertex ids), `dt` is the Delaunay triangulation of the vertices of T in W only
  // (ids below `used`, in mesh id order); the other vertices of T follow them (in_k_bundle's local
  // attempt over the whole mesh, when a flood leaves the regions of build_region).
  //
  // With `prior_dt` (a Delaunay triangulation whose vertex i is mesh vertex (*prior_ids)[i]) and no
  // subset: if every vertex of prior_dt is still a vertex of T at the same place, those vertices
  // keep their DT ids (first, in prior order), and `dt` is prior_dt (moved from) with the other
  // vertices of T inserted by Lawson flips — DT(V) again, without building it from scratch.
  bool build(bool list_pencils = true, const std::vector<VertexId>* subset = nullptr, Mesh* prior_dt = nullptr,
             const std::vector<VertexId>* prior_ids = nullptr) {
    const std::size_t nv = m.points.size();
    std::vector<std::uint8_t> state(nv, 0);  // 1: corner of a live triangle, 2: vertex of T
    bool any = false;
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      if (m.is_dead(t)) continue;
      const std::uint8_t s = m.in_domain(t) ? 2 : 1;
      any = any || s == 2;
      for (const VertexId v : m.triangles[t].v) {
        if (v != kInfinite) state[v] = std::max(state[v], s);
      }
    }
    if (!any) return false;
    if (subset) {
      std::vector<std::uint8_t> in_subset(nv, 0);
      for (const VertexId v : *subset) in_subset[v] = 1;
      bool some = false;
      for (VertexId v = 0; v < nv; ++v) {
        if (state[v] == 2 && !in_subset[v]) state[v] = 1;
        some = some || state[v] == 2;
      }
      if (!some) return false;
    }
    double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
    for (VertexId v = 0; v < nv; ++v) {
      if (state[v] == 0) continue;
      x0 = std::min(x0, m.points[v].x);
      y0 = std::min(y0, m.points[v].y);
      x1 = std::max(x1, m.points[v].x);
      y1 = std::max(y1, m.points[v].y);
    }
    const double extent = std::max(x1 * 0.5 - x0 * 0.5, y1 * 0.5 - y0 * 0.5);
    const double scale = extent > 0.0 ? 16383.0 / extent : 0.0;  // extent is half the range
    // Vertices of T first (they are the DT ids), each group in Morton order: group in bit 62,
    // the 30-bit key in bits 32..61, the old id below.
    // (With a subset the DT is small and the sweeps few: the groups in id order, without a sort.)
    std::vector<std::uint64_t> order;
    std::vector<std::uint8_t> in_prior;
    if (!subset && prior_dt && prior_ids && prior_dt->triangle_slots() > 0 &&
        prior_dt->points.size() == prior_ids->size()) {
      in_prior.assign(nv, 0);
      for (std::size_t i = 0; i < prior_ids->size(); ++i) {
        const VertexId v = (*prior_ids)[i];
        if (v >= nv || state[v] != 2 || in_prior[v] || !(m.points[v] == prior_dt->points[i])) {
          in_prior.clear();
          break;
        }
        in_prior[v] = 1;
      }
    }
    if (!in_prior.empty()) {
      prior_ = prior_dt;
      prior_used_ = static_cast<std::uint32_t>(prior_ids->size());
      for (const VertexId v : *prior_ids) order.push_back(v);  // group 0, key 0: kept in front
      const std::size_t kept = order.size();
      for (VertexId v = 0; v < nv; ++v) {
        if (state[v] == 0 || in_prior[v]) continue;
        const std::uint64_t group = state[v] == 2 ? 0 : 1;
        order.push_back((group << 62) | (std::uint64_t{morton_key(m.points[v], x0, y0, scale)} << 32) | v);
      }
      std::sort(order.begin() + static_cast<std::ptrdiff_t>(kept), order.end());
    } else if (subset) {
      for (const int group : {2, 1}) {
        for (VertexId v = 0; v < nv; ++v) {
          if (state[v] == group) order.push_back(std::uint64_t{group == 2 ? 0u : 1u} << 62 | v);
        }
      }
    } else {
      for (VertexId v = 0; v < nv; ++v) {
        if (state[v] == 0) continue;
        const std::uint64_t group = state[v] == 2 ? 0 : 1;
        order.push_back((group << 62) | (std::uint64_t{morton_key(m.points[v], x0, y0, scale)} << 32) | v);
      }
      std::sort(order.begin(), order.end());
    }
    std::vector<VertexId> renumber(nv, kInfinite);
    pts.resize(order.size());
    mesh_id.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      const auto v = static_cast<VertexId>(order[i] & 0xFFFFFFFFu);
      renumber[v] = static_cast<VertexId>(i);
      mesh_id[i] = v;
      pts[i] = m.points[v];
      if (state[v] == 2) used = static_cast<std::uint32_t>(i + 1);
    }
    slots.resize(m.triangle_slots());
    domain.resize(m.triangle_slots());
    vertex_edge.assign(pts.size(), kNone);
    for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
      domain[t] = m.in_domain(t) ? 1 : 0;
      for (unsigned k = 0; k < 3; ++k) {
        const VertexId v = m.triangles[t].v[k];
        slots[t].v[k] = (v == kInfinite || m.is_dead(t)) ? kInfinite : renumber[v];
        slots[t].n[k] = m.triangles[t].n[k];
      }
      if (m.is_dead(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const VertexId o = org(h);
        if (o != kInfinite && vertex_edge[o] == kNone) vertex_edge[o] = h;
      }
    }
    return finish(list_pencils);
  }

  // build() for in_k_bundle's local attempt, in time proportional to a region of the mesh: the
  // mesh slots `region` (live; every triangle around each vertex of `w` among them, and every ghost
  // next to a finite one) become slots 0, 1, ... and `outside` stands for the rest; `dt` is the
  // Delaunay triangulation of the vertices of T in `w` (mesh ids, ascending: the order build()
  // gives them with a subset). False if none of `w` is a vertex of T.
  bool build_region(const std::vector<TriangleId>& region, const DenseIds& region_ids, const std::vector<VertexId>& w) {
    DenseIds ids(w.size() + region.size());
    std::vector<std::uint8_t> in_t;  // per region vertex (in `ids` order): a corner of an in-domain slot
    for (const VertexId v : w) ids.insert(v);
    in_t.assign(w.size(), 0);
    for (const TriangleId t : region) {
      const bool in = m.in_domain(t);
      for (const VertexId v : m.triangles[t].v) {
        if (v == kInfinite) continue;
        const auto [id, added] = ids.insert(v);
        if (added) in_t.push_back(0);
        if (in) in_t[id] = 1;
      }
    }
    // DT ids: the vertices of w that are vertices of T (a vertex of w has all its triangles in the
    // region, so in_t is exact for it), then the other region vertices.
    std::vector<VertexId> renumber(ids.size(), kNone);  // by `ids` id
    pts.clear();
    pts.reserve(ids.size());
    mesh_id.clear();
    for (std::uint32_t i = 0; i < w.size(); ++i) {
      if (!in_t[i]) continue;
      renumber[i] = static_cast<VertexId>(pts.size());
      pts.push_back(m.points[w[i]]);
      mesh_id.push_back(w[i]);
    }
    used = static_cast<std::uint32_t>(pts.size());
    if (used == 0) return false;
    for (std::uint32_t i = 0; i < ids.size(); ++i) {
      if (renumber[i] != kNone) continue;
      renumber[i] = static_cast<VertexId>(pts.size());
      pts.push_back(m.points[ids.key(i)]);
      mesh_id.push_back(ids.key(i));
    }
    outside = static_cast<TriangleId>(region.size());
    slots.resize(region.size() + 1);
    domain.assign(region.size() + 1, 0);
    vertex_edge.assign(pts.size(), kNone);
    for (TriangleId t = 0; t < region.size(); ++t) {
      const Triangle& tri = m.triangles[region[t]];
      domain[t] = m.in_domain(region[t]) ? 1 : 0;
      for (unsigned k = 0; k < 3; ++k) {
        const VertexId v = tri.v[k];
        slots[t].v[k] = v == kInfinite ? kInfinite : renumber[ids.find(v)];
        const TriangleId n = region_ids.find(triangle_of(tri.n[k]));
        slots[t].n[k] = n == kNone ? make_handle(outside, 0) : make_handle(n, edge_of(tri.n[k]));
      }
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const VertexId o = org(h);
        if (o != kInfinite && vertex_edge[o] == kNone) vertex_edge[o] = h;
      }
    }
    slots[outside].v = {kInfinite, kInfinite, kInfinite};
    for (unsigned k = 0; k < 3; ++k) slots[outside].n[k] = make_handle(outside, k);
    return finish(false);
  }

 private:
  Mesh* prior_ = nullptr;        // build(): the Delaunay triangulation of vertices [0, prior_used_)
  std::uint32_t prior_used_ = 0;

  // DT of the vertices [0, used), and (if asked) the pencils.
  bool finish(bool list_pencils) {
    if (prior_) {
      dt = std::move(*prior_);
      prior_ = nullptr;
      kept_dt = true;
      Handle hint = kNone;
      for (std::uint32_t i = prior_used_; i < used; ++i) {
        dt.points.push_back(pts[i]);
        dt.vertex_kind.push_back(VertexKind::kSteiner);
        dt.vertex_marker.push_back(0);
        if (dt.insert_vertex(i, hint, &hint) != i) throw InternalError("bundle: two vertices of the mesh coincide");
      }
    } else {
      dt = delaunay(std::vector<Point>(pts.begin(), pts.begin() + used));
    }
    if (!dt.duplicates.empty()) throw InternalError("bundle: two vertices of the mesh coincide");
    if (!list_pencils) return true;
    for (TriangleId t = 0; t < dt.triangle_slots(); ++t) {
      if (dt.is_dead(t) || dt.is_ghost(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId other = triangle_of(dt.sym(h));
        if (!dt.is_ghost(other) && other < t) continue;  // each interior edge once
        pencils.push_back(h);
      }
    }
    return true;
  }
};

// ---- one worker's computations ------------------------------------------------------------------

enum : std::uint8_t { kRoleLo = 0, kRoleA = 1, kRoleB = 2, kRoleHi = 3 };

struct Event {
  Threshold th;
  std::uint32_t candidate = kNone;
  std::uint8_t role = kRoleA;
};

struct Candidate {
  TriangleId triangle = 0;
  bool always = false;
  std::uint32_t a_group = kNone;  // class of a_t (counts on the intervals above it)
  std::uint32_t b_group = kNone;  // class of b_t (counts on the intervals below it)
};

// What one edge of a candidate contributes for the current pencil (the same for both triangles
// on the edge, so it is computed once per pencil).
struct EdgeInfo {
  bool crosses = false;  // the edge crosses the open chord pq
  bool has_a = false, has_b = false;
  Threshold a, b;        // infimum of f above the line along the edge / supremum below
};

constexpr std::int8_t kSideP = 2;
constexpr std::int8_t kSideQ = 3;

// A pencil sweep's result kept across in_k_bundle calls (KBundleCache): the key is everything the
// sweep reads — the directed edge p→q, the apices (mesh vertex ids; kInfinite on the hull side)
// and the candidate triangles as vertex triples (mesh ids, rotated to start at the smallest,
// sorted) — and the value is, per candidate in that order, its largest count over the pencil.
// Only pencils with at least kCachedCandidates candidates are kept: the small ones are cheap.
constexpr std::size_t kCachedCandidates = 64;

struct CachedSweep {
  VertexId lv = kNone, rv = kNone;
  std::vector<std::array<VertexId, 3>> triangles;
  std::vector<std::uint32_t> best;
};

using SweepKey = std::uint64_t;  // p << 32 | q (mesh ids)

}  // namespace

struct KBundleCache::Impl {
  std::unordered_map<SweepKey, CachedSweep> sweeps;
  Mesh dt;                          // DT(V) of the last call over the whole mesh (empty: none)
  std::vector<VertexId> dt_mesh_id;  // its vertex i is mesh vertex dt_mesh_id[i]
};

KBundleCache::KBundleCache() : impl(std::make_unique<Impl>()) {}
KBundleCache::~KBundleCache() = default;

namespace {

class Worker {
 public:
  Worker(const Shared& shared, bool per_triangle, bool prune)
      : sh_(shared), per_triangle_enabled_(per_triangle), prune_(prune) {
    flood_vertex_.assign(sh_.pts.size(), FloodVertex{});
    pencil_vertex_.assign(sh_.pts.size(), PencilVertex{});
    disk_side_.assign(sh_.pts.size(), DiskSide{});
    edge_meets_.assign(4 * sh_.slots.size(), 0u);
    triangle_stamp_.assign(sh_.slots.size(), 0);
    candidate_stamp_.assign(sh_.slots.size(), 0);
    candidate_index_.assign(sh_.slots.size(), 0);
    if (per_triangle) per_triangle_.assign(sh_.slots.size(), 0);
  }

  // Results.
  std::uint32_t best_count = 0;
  std::size_t best_pencil = static_cast<std::size_t>(-1);
  Point best_center;
  double best_radius = 0.0;
  std::vector<TriangleId> best_triangles;
  std::uint32_t circumdisk_best = 0;
  std::size_t pencils = 0, candidate_pairs = 0, exact_comparisons = 0;
  std::size_t flood_visits = 0;      // triangles popped by floods (in the domain or not)
  std::uint32_t min_candidates = 0;  // pencils with fewer candidates are not swept
  bool escaped = false;              // a flood reached Shared::outside (see Shared::build_region)
  // The bounding box (x0, y0, x1, y1) of the corners of every triangle the last flood visited
  // (in the domain or not): it holds every mesh triangle meeting the circumdisk.
  std::array<double, 4> flood_box{};
  bool want_flood_box = false;
  // Sweep results of an earlier call (read only while the workers run), the keys reused and the
  // results made now (merged into the cache afterwards).
  const KBundleCache::Impl* reuse = nullptr;
  std::size_t pencils_reused = 0;
  std::vector<SweepKey> reused_keys;
  std::vector<std::pair<SweepKey, CachedSweep>> made;
  std::vector<std::uint32_t>& per_triangle() { return per_triangle_; }

  // ---- floods ----

  // Collects into `out` the in-domain mesh triangles (a superset of those) meeting the open
  // circumdisk of Delaunay triangle `dtt`, by a flood across mesh edges that meet it. The mesh
  // triangles meeting the disk are connected that way: the disk's intersection with the convex
  // hull is convex, and a path inside it avoiding vertices crosses edges at points inside the disk.
  void flood(TriangleId dtt, std::vector<TriangleId>& out) {
    out.clear();
    flood_each(dtt, [&out](TriangleId t) {
      out.push_back(t);
      return true;
    });
  }

  // The flood of flood(), calling visit(t) for each in-domain triangle t it reaches (a superset of
  // those meeting the disk), in the same order; it stops when visit returns false.
  template <class Visit>
  void flood_each(TriangleId dtt, Visit visit) {
    flood_box = {kInf, kInf, -kInf, -kInf};
    const auto& v = sh_.dt.triangles[dtt].v;
    circle_[0] = sh_.pts[v[0]];
    circle_[1] = sh_.pts[v[1]];
    circle_[2] = sh_.pts[v[2]];
    circle_orient_ = orient_approx(circle_[0], circle_[1], circle_[2]);
    bump(flood_stamp_, [this] {
      for (auto& f : flood_vertex_) f.stamp = 0;
    });
    bump(triangle_mark_, [this] { std::fill(triangle_stamp_.begin(), triangle_stamp_.end(), 0); });
    // The chord from v[0] to v[1] lies in the open disk, and so does the corner of the mesh
    // triangle it leaves v[0] by.
    const TriangleId start = triangle_towards(v[0], circle_[1]);
    stack_.clear();
    stack_.push_back(start);
    triangle_stamp_[start] = triangle_mark_;
    while (!stack_.empty()) {
      const TriangleId t = stack_.back();
      stack_.pop_back();
      ++flood_visits;
      if (sh_.in_domain(t) && !visit(t)) return;
      for (unsigned i = 0; i < 3 && want_flood_box; ++i) {
        const VertexId c = sh_.slots[t].v[i];
        const Point& pt = sh_.pts[c];
        flood_box[0] = std::min(flood_box[0], pt.x);
        flood_box[1] = std::min(flood_box[1], pt.y);
        flood_box[2] = std::max(flood_box[2], pt.x);
        flood_box[3] = std::max(flood_box[3], pt.y);
      }
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const TriangleId n = triangle_of(sh_.sym(h));
        if (n == sh_.outside) {
          // The flood would leave the region (in_k_bundle's local attempt): it cannot be trusted.
          escaped = escaped || edge_may_meet(sh_.org(h), sh_.dest(h));
          continue;
        }
        if (triangle_stamp_[n] == triangle_mark_ || sh_.is_ghost(n)) continue;
        if (edge_may_meet(sh_.org(h), sh_.dest(h))) {
          triangle_stamp_[n] = triangle_mark_;
          stack_.push_back(n);
        }
      }
    }
  }

  // The number of in-domain triangles meeting the open circumdisk of Delaunay triangle `dtt`
  // (exactly: meets_circumdisk), counted along its flood, which stops as soon as `enough` are
  // found: on a disk meeting many triangles (points on a circle: every circumdisk is the whole
  // circle) the cost is that of `enough` triangles, not of all it meets.
  std::uint32_t count_meeting(TriangleId dtt, std::uint32_t enough) {
    const auto& v = sh_.dt.triangles[dtt].v;
    start_disk();
    std::uint32_t count = 0;
    flood_each(dtt, [&](TriangleId t) {
      if (meets_circumdisk(t, v[0], v[1], v[2])) ++count;
      return count < enough;
    });
    return count;
  }

  // The in-domain triangles meeting the open circumdisk of Delaunay triangle `dtt` (exactly), all
  // of them, by one flood: no list is kept but `met`.
  void collect_meeting(TriangleId dtt, std::vector<TriangleId>& met) {
    const auto& v = sh_.dt.triangles[dtt].v;
    start_disk();
    met.clear();
    flood_each(dtt, [&](TriangleId t) {
      if (meets_circumdisk(t, v[0], v[1], v[2])) met.push_back(t);
      return true;
    });
  }

  // Does mesh triangle t meet the open circumdisk of Delaunay triangle `dtt`? (Exact.)
  bool disk_meets(TriangleId dtt, TriangleId t) {
    const auto& v = sh_.dt.triangles[dtt].v;
    start_disk();
    return meets_circumdisk(t, v[0], v[1], v[2]);
  }

  // The number of triangles of `list` meeting the open circumdisk of Delaunay triangle `dtt`
  // (see meets_circumdisk); appends them to `met` if it is not null.
  std::uint32_t circumdisk_count(TriangleId dtt, const TriangleId* list, std::size_t size,
                                 std::vector<TriangleId>* met) {
    const auto& v = sh_.dt.triangles[dtt].v;
    start_disk();
    std::uint32_t count = 0;
    for (std::size_t i = 0; i < size; ++i) {
      if (meets_circumdisk(list[i], v[0], v[1], v[2])) {
        ++count;
        if (met) met->push_back(list[i]);
      }
    }
    return count;
  }

  // ---- one pencil ----

  void sweep(std::size_t index) {
    const Mesh& dt = sh_.dt;
    const Handle h = sh_.pencils[index];
    const Handle hs = dt.sym(h);
    const VertexId lv = dt.apex(h), rv = dt.apex(hs);  // rv = kInfinite on a hull edge
    pc_.pv = dt.org(h);
    pc_.qv = dt.dest(h);
    pc_.p = sh_.pts[pc_.pv];
    pc_.q = sh_.pts[pc_.qv];
    pc_.points = sh_.pts.data();
    // s_lo = s_hi: the four vertices are cocircular; the only disk is a circumdisk, which the
    // neighbouring pencils reach as a limit (see the file comment).
    if (rv != kInfinite && incircle(pc_.p, pc_.q, sh_.pts[lv], sh_.pts[rv]) == 0) return;
    // A list cut at the budget's cap: the sweep would not be exact (bundle_number bounds it).
    if (!sh_.truncated.empty() && (sh_.truncated[triangle_of(h)] || (rv != kInfinite && sh_.truncated[triangle_of(hs)]))) {
      return;
    }
    ++pencils;

    bump(candidate_mark_, [this] { std::fill(candidate_stamp_.begin(), candidate_stamp_.end(), 0); });
    candidates_.clear();
    auto gather = [&](TriangleId dtt) {
      for (std::uint32_t i = sh_.list_begin[dtt]; i < sh_.list_begin[dtt + 1]; ++i) {
        const TriangleId t = sh_.list[i];
        if (candidate_stamp_[t] == candidate_mark_) continue;
        candidate_stamp_[t] = candidate_mark_;
        candidate_index_[t] = static_cast<std::uint32_t>(candidates_.size());
        Candidate c;
        c.triangle = t;
        candidates_.push_back(c);
      }
    };
    gather(triangle_of(h));
    if (rv != kInfinite) gather(triangle_of(hs));
    candidate_pairs += candidates_.size();
    // No disk of this pencil meets more triangles than it has candidates: below the count asked
    // for (in_k_bundle), the pencil cannot matter.
    if (candidates_.size() < min_candidates) return;
    // A result of an earlier call with the same key (see CachedSweep).
    const bool cacheable = reuse != nullptr && per_triangle_enabled_ && candidates_.size() >= kCachedCandidates;
    SweepKey key = 0;
    if (cacheable) {
      key = SweepKey{sh_.mesh_id[pc_.pv]} << 32 | sh_.mesh_id[pc_.qv];
      key_order_.resize(candidates_.size());
      key_triangles_.resize(candidates_.size());
      for (std::uint32_t i = 0; i < candidates_.size(); ++i) {
        key_order_[i] = i;
        const auto& tv = sh_.slots[candidates_[i].triangle].v;
        std::array<VertexId, 3> m{sh_.mesh_id[tv[0]], sh_.mesh_id[tv[1]], sh_.mesh_id[tv[2]]};
        while (m[0] > m[1] || m[0] > m[2]) m = {m[1], m[2], m[0]};
        key_triangles_[i] = m;
      }
      std::sort(key_order_.begin(), key_order_.end(),
                [this](std::uint32_t x, std::uint32_t y) { return key_triangles_[x] < key_triangles_[y]; });
      const VertexId lm = sh_.mesh_id[lv], rm = rv == kInfinite ? kInfinite : sh_.mesh_id[rv];
      const auto it = reuse->sweeps.find(key);
      if (it != reuse->sweeps.end() && it->second.lv == lm && it->second.rv == rm &&
          it->second.triangles.size() == candidates_.size()) {
        const CachedSweep& c = it->second;
        bool same = true;
        for (std::size_t j = 0; j < key_order_.size() && same; ++j) same = c.triangles[j] == key_triangles_[key_order_[j]];
        if (same) {
          for (std::size_t j = 0; j < key_order_.size(); ++j) {
            std::uint32_t& slot = per_triangle_[candidates_[key_order_[j]].triangle];
            slot = std::max(slot, c.best[j]);
          }
          ++pencils_reused;
          reused_keys.push_back(key);
          return;
        }
      }
      made.emplace_back(key, CachedSweep{lm, rm, {}, {}});
      CachedSweep& c = made.back().second;
      c.triangles.reserve(candidates_.size());
      for (const std::uint32_t i : key_order_) c.triangles.push_back(key_triangles_[i]);
      c.best.assign(candidates_.size(), 0);
    }
    // No disk of this pencil meets more triangles than it has candidates. Its two circumdisks
    // are still counted (directly, when their lists could beat the best circumdisk so far).
    if (prune_ && candidates_.size() <= best_count) {
      for (const TriangleId dtt : {triangle_of(h), triangle_of(hs)}) {
        if (dt.is_ghost(dtt)) continue;
        const std::uint32_t size = sh_.list_begin[dtt + 1] - sh_.list_begin[dtt];
        if (size <= circumdisk_best) continue;
        circumdisk_best = std::max(circumdisk_best, circumdisk_count(dtt, sh_.list.data() + sh_.list_begin[dtt], size, nullptr));
      }
      return;
    }

    pc_.bx = pc_.q.x - pc_.p.x;
    pc_.by = pc_.q.y - pc_.p.y;
    pc_.local_scale = 2.0 / (pc_.bx * pc_.bx + pc_.by * pc_.by);
    bump(pencil_stamp_, [this] {
      for (auto& x : pencil_vertex_) x.stamp = 0;
    });

    const auto n_cand = static_cast<std::uint32_t>(candidates_.size());
    if (edge_ref_.size() < 3 * static_cast<std::size_t>(n_cand)) edge_ref_.resize(3 * static_cast<std::size_t>(n_cand));
    edge_info_.clear();
    events_.clear();
    std::uint32_t always_count = 0, b_total = 0;
    for (std::uint32_t i = 0; i < n_cand; ++i) {
      bool has_a = false, has_b = false;
      Threshold a, b;
      classify(i, has_a, a, has_b, b);
      if (candidates_[i].always) {
        ++always_count;
        continue;
      }
      if (has_a) events_.push_back({a, i, kRoleA});
      if (has_b) {
        events_.push_back({b, i, kRoleB});
        ++b_total;
      }
    }
    events_.push_back({rational_threshold(pc_, Kind::kThroughVertex, lv, sh_.pts[lv]), kNone, kRoleHi});
    if (rv != kInfinite) {
      events_.push_back({rational_threshold(pc_, Kind::kThroughVertex, rv, sh_.pts[rv]), kNone, kRoleLo});
    }

    // Sort by rounded value, then repair runs whose error windows overlap with exact comparisons
    // (an insertion sort per run: runs are short).
    std::sort(events_.begin(), events_.end(), [](const Event& x, const Event& y) {
      if (x.th.value != y.th.value) return x.th.value < y.th.value;
      if (x.role != y.role) return x.role < y.role;
      return x.candidate < y.candidate;
    });
    const std::size_t n = events_.size();
    for (std::size_t i = 0; i < n;) {
      std::size_t j = i + 1;
      while (j < n && events_[j].th.value - events_[j - 1].th.value <=
                          events_[j].th.error + events_[j - 1].th.error) {
        ++j;
      }
      for (std::size_t k = i + 1; k < j; ++k) {
        const Event moving = events_[k];
        std::size_t l = k;
        while (l > i && compare_thresholds(pc_, events_[l - 1].th, moving.th, exact_comparisons) > 0) {
          events_[l] = events_[l - 1];
          --l;
        }
        events_[l] = moving;
      }
      i = j;
    }

    // Classes of equal thresholds. Interval j lies below class j (j = 0: below everything).
    group_start_.clear();
    group_a_.clear();
    group_b_.clear();
    std::uint32_t lo_group = kNone, hi_group = kNone;
    for (std::size_t i = 0; i < n; ++i) {
      if (i == 0 || compare_thresholds(pc_, events_[i - 1].th, events_[i].th, exact_comparisons) != 0) {
        group_start_.push_back(static_cast<std::uint32_t>(i));
        group_a_.push_back(0);
        group_b_.push_back(0);
      }
      const auto g = static_cast<std::uint32_t>(group_start_.size() - 1);
      const Event& ev = events_[i];
      if (ev.role == kRoleLo) {
        lo_group = g;
      } else if (ev.role == kRoleHi) {
        hi_group = g;
      } else if (ev.role == kRoleA) {
        candidates_[ev.candidate].a_group = g;
        ++group_a_[g];
      } else {
        candidates_[ev.candidate].b_group = g;
        ++group_b_[g];
      }
    }
    // The circumdisks (the ends of the pencil): thresholds strictly below / above the end count.
    const auto groups = static_cast<std::uint32_t>(group_start_.size());
    auto count_at = [&](std::uint32_t g) {
      std::uint32_t a_lt = 0, b_gt = 0;
      for (std::uint32_t k = 0; k < g; ++k) a_lt += group_a_[k];
      for (std::uint32_t k = g + 1; k < groups; ++k) b_gt += group_b_[k];
      return always_count + a_lt + b_gt;
    };
    circumdisk_best = std::max(circumdisk_best, count_at(hi_group));
    if (lo_group != kNone) circumdisk_best = std::max(circumdisk_best, count_at(lo_group));
    // Valid intervals: above the class of s_lo (if any), not above the class of s_hi.
    const std::uint32_t j_min = lo_group == kNone ? 0 : lo_group + 1;
    const std::uint32_t j_max = hi_group;
    if (j_min > j_max) return;  // cannot happen: s_lo < s_hi strictly here
    counts_.resize(static_cast<std::size_t>(j_max) + 1);
    std::uint32_t a_below = 0, b_below = 0, best_j = j_min;
    for (std::uint32_t j = 0; j <= j_max; ++j) {
      counts_[j] = always_count + a_below + (b_total - b_below);
      if (j >= j_min && counts_[j] > counts_[best_j]) best_j = j;
      a_below += group_a_[j];
      b_below += group_b_[j];
    }
    if (counts_[best_j] > best_count) record_witness(index, best_j, counts_[best_j]);

    if (per_triangle_enabled_) {
      if (cacheable) key_best_.assign(candidates_.size(), 0);
      prefix_max_.resize(counts_.size());
      suffix_max_.resize(counts_.size() + 1);
      std::uint32_t run = 0;
      for (std::uint32_t j = j_min; j <= j_max; ++j) prefix_max_[j] = run = std::max(run, counts_[j]);
      run = 0;
      suffix_max_[j_max + 1] = 0;
      for (std::uint32_t j = j_max + 1; j-- > j_min;) suffix_max_[j] = run = std::max(run, counts_[j]);
      for (const Candidate& c : candidates_) {
        std::uint32_t best = 0;
        if (c.always) {
          best = prefix_max_[j_max];
        } else {
          if (c.a_group != kNone) {
            const std::uint32_t j = std::max(c.a_group + 1, j_min);
            if (j <= j_max) best = std::max(best, suffix_max_[j]);
          }
          if (c.b_group != kNone) {
            const std::uint32_t j = std::min(c.b_group, j_max);
            if (j >= j_min) best = std::max(best, prefix_max_[j]);
          }
        }
        std::uint32_t& slot = per_triangle_[c.triangle];
        slot = std::max(slot, best);
        if (cacheable) key_best_[candidate_index_[c.triangle]] = best;
      }
      if (cacheable) {
        std::vector<std::uint32_t>& out = made.back().second.best;
        for (std::size_t j = 0; j < key_order_.size(); ++j) out[j] = key_best_[key_order_[j]];
      }
    }
  }

 private:
  struct FloodVertex {
    std::uint32_t stamp = 0;
    Approx value;  // incircle determinant of the current circle at the vertex
  };
  struct PencilVertex {
    std::uint32_t stamp = 0;
    std::int8_t side = 0;  // +1 left of p→q ("above"), −1 right, 0 on the line, kSideP, kSideQ
    Point local;           // local coordinates: p = (−1, 0), q = (1, 0)
  };

  // A new disk for meets_circumdisk's caches. (Stamps below 2^31: edge_meets_ keeps the stamp
  // shifted by one bit.)
  void start_disk() {
    if (++disk_stamp_ == (1u << 31)) {
      for (auto& d : disk_side_) d.stamp = 0;
      std::fill(edge_meets_.begin(), edge_meets_.end(), 0u);
      disk_stamp_ = 1;
    }
  }

  // Advances a stamp; on wrap-around clears the marks it guards.
  template <class Clear>
  static void bump(std::uint32_t& stamp, Clear clear) {
    if (++stamp == 0) {
      clear();
      stamp = 1;
    }
  }

  // The finite mesh triangle around vertex a whose closed corner at a contains the direction
  // towards `target` (a point of the convex hull other than a).
  TriangleId triangle_towards(VertexId a, const Point& target) const {
    const Point& pa = sh_.pts[a];
    const Handle start = sh_.vertex_edge[a];
    Handle h = start;
    for (std::size_t turn = 0; turn < sh_.slots.size() && triangle_of(h) != sh_.outside; ++turn) {
      const VertexId d = sh_.dest(h), x = sh_.apex(h);
      if (d != kInfinite && x != kInfinite && orient2d(pa, sh_.pts[d], target) >= 0 &&
          orient2d(pa, target, sh_.pts[x]) >= 0) {
        return triangle_of(h);
      }
      h = sh_.onext(h);
      if (h == start) break;
    }
    throw InternalError("bundle: no mesh triangle around a vertex faces its Delaunay neighbour");
  }

  const Approx& circle_value(VertexId v) {
    FloodVertex& f = flood_vertex_[v];
    if (f.stamp != flood_stamp_) {
      f.stamp = flood_stamp_;
      f.value = incircle_approx(circle_[0], circle_[1], circle_[2], sh_.pts[v]);
    }
    return f.value;
  }

  // Permissive: true whenever the closed segment uw might meet the open circumdisk (never false
  // when it does). g(λ) = incircle value at u + λ(w − u) = (1−λ) g(u) + λ g(w) + O|e|² λ(1−λ),
  // O = orient(a, b, c) > 0: a concave quadratic.
  bool edge_may_meet(VertexId u, VertexId w) {
    const Approx& gu = circle_value(u);
    const Approx& gw = circle_value(w);
    if (gu.value > -gu.error || gw.value > -gw.error) return true;
    const Point& pu = sh_.pts[u];
    const Point& pw = sh_.pts[w];
    const double ex = pw.x - pu.x, ey = pw.y - pu.y;
    const double e2 = ex * ex + ey * ey;
    const double a = circle_orient_.value * e2;
    const double a_error = (circle_orient_.error + 4.0 * kEps * circle_orient_.value) * e2;
    const double slope = gw.value - gu.value + a;
    const double lambda = a > 0.0 ? std::clamp(slope / (2.0 * a), 0.0, 1.0) : 0.0;
    const double gmax = gu.value + lambda * (slope - a * lambda);
    const double slack = 2.0 * (gu.error + gw.error + a_error +
                                8.0 * kEps * (std::fabs(gu.value) + std::fabs(gw.value) + a));
    if (gmax <= -slack) return false;
    if (gmax > slack) return true;
    // Undecided: g_w − g_u cancels for the huge circles of flat Delaunay triangles (nearly
    // collinear hull vertices), which would flood along the whole hull; the centre-based filter
    // rules most such edges out.
    return segment_meets_open_circumdisk_filtered(circle_[0], circle_[1], circle_[2], pu, pw) != 0;
  }

  // Does mesh triangle t meet the open circumdisk of the vertices ca, cb, cc (counter-clockwise)?
  // A corner strictly inside (exact incircle), a corner on the circle whose edge enters the disk
  // (exact), or an edge passing through between two corners outside (exact:
  // segment_meets_open_circumdisk). Only within circumdisk_count(), which starts each disk.
  bool meets_circumdisk(TriangleId t, VertexId ca, VertexId cb, VertexId cc) {
    const Point& a = sh_.pts[ca];
    const Point& b = sh_.pts[cb];
    const Point& c = sh_.pts[cc];
    const auto& tv = sh_.slots[t].v;
    int inside[3];
    for (int i = 0; i < 3; ++i) {
      const VertexId v = tv[i];
      if (v == ca || v == cb || v == cc) {
        inside[i] = 0;
        continue;
      }
      // incircle(a, b, c, v): the filter, and the exact stage at most once per vertex and disk (a
      // vertex is a corner of several candidates; on meshes of slivers the disks are nearly flat
      // and most corners need the exact stage).
      const detail::FilteredDeterminant det = detail::incircle_determinant(a, b, c, sh_.pts[v]);
      if (det.value > det.bound) return true;
      if (-det.value > det.bound) {
        inside[i] = -1;
        continue;
      }
      DiskSide& side = disk_side_[v];
      if (side.stamp != disk_stamp_) side = {disk_stamp_, static_cast<std::int8_t>(detail::incircle_exact(a, b, c, sh_.pts[v]))};
      inside[i] = side.sign;
      if (inside[i] > 0) return true;
    }
    const VertexId circle_ids[3] = {ca, cb, cc};
    for (int i = 0; i < 3; ++i) {
      if (inside[i] != 0) continue;
      const VertexId u = tv[i];
      // u is on the circle: two circle-defining vertices other than u span the same circle.
      VertexId pa = kNone, pb = kNone;
      for (const VertexId z : circle_ids) {
        if (z == u) continue;
        if (pa == kNone) {
          pa = z;
        } else if (pb == kNone) {
          pb = z;
        }
      }
      const Point& p = sh_.pts[pa];
      const Point& q = sh_.pts[pb];
      const Point& pu = sh_.pts[u];
      const int o = orient2d(p, q, pu);
      for (int k = 1; k <= 2; ++k) {
        if (detail::enters_circle(p, q, pu, sh_.pts[tv[(i + k) % 3]], o) > 0) return true;
      }
    }
    for (int i = 0; i < 3; ++i) {
      const int iu = (i + 1) % 3, iw = (i + 2) % 3;
      if (inside[iu] == 0 || inside[iw] == 0) continue;  // decided above
      // Edge i of t (from corner i + 1 to i + 2), decided once per disk for both triangles on it.
      const Handle h = make_handle(t, static_cast<unsigned>(i));
      const std::uint32_t known = edge_meets_[h];
      if ((known >> 1) == disk_stamp_) {
        if ((known & 1u) != 0) return true;
        continue;
      }
      const bool meets = segment_meets_open_circumdisk(a, b, c, sh_.pts[tv[iu]], sh_.pts[tv[iw]]);
      const std::uint32_t value = disk_stamp_ << 1 | (meets ? 1u : 0u);
      edge_meets_[h] = value;
      // (Only in-domain triangles are candidates; a region's edges out of it all lead to the one
      // `outside` slot, which is not.)
      const Handle twin = sh_.sym(h);
      if (sh_.in_domain(triangle_of(twin))) edge_meets_[twin] = value;
      if (meets) return true;
    }
    return false;
  }

  // Side of vertex v relative to the directed line p→q, cached per pencil with its local
  // coordinates.
  const PencilVertex& vertex(VertexId v) {
    PencilVertex& x = pencil_vertex_[v];
    if (x.stamp != pencil_stamp_) {
      x.stamp = pencil_stamp_;
      if (v == pc_.pv) {
        x.side = kSideP;
      } else if (v == pc_.qv) {
        x.side = kSideQ;
      } else {
        const Point& pt = sh_.pts[v];
        x.side = static_cast<std::int8_t>(orient2d(pc_.p, pc_.q, pt));
        const double dx = pt.x - pc_.p.x, dy = pt.y - pc_.p.y;
        x.local = {(dx * pc_.bx + dy * pc_.by) * pc_.local_scale - 1.0,
                   (pc_.bx * dy - pc_.by * dx) * pc_.local_scale};
      }
    }
    return x;
  }

  // Keeps the smaller (sigma = +1) or larger (sigma = −1) threshold in `best`.
  void keep_extreme(int sigma, bool& has, Threshold& best, const Threshold& t) {
    if (!has) {
      has = true;
      best = t;
    } else if (compare_thresholds(pc_, t, best, exact_comparisons) * sigma < 0) {
      best = t;
    }
  }

  // The contribution of edge uw (see EdgeInfo); `info` starts empty.
  void classify_edge(VertexId u, VertexId w, EdgeInfo& info) {
    const PencilVertex& xu = vertex(u);
    const PencilVertex& xw = vertex(w);
    const std::int8_t su = xu.side, sw = xw.side;
    const Point& pu = sh_.pts[u];
    const Point& pw = sh_.pts[w];
    if ((su == 1 && sw == -1) || (su == -1 && sw == 1)) {
      // No vertex lies on the open chord of a Delaunay edge: crossing is proper or absent.
      if (orient2d(pu, pw, pc_.p) * orient2d(pu, pw, pc_.q) < 0) {
        info.crosses = true;
        return;
      }
    }
    const bool u_end = su == kSideP || su == kSideQ;
    const bool w_end = sw == kSideP || sw == kSideQ;
    if (u_end || w_end) {
      if (u_end && w_end) return;  // the edge pq itself: its triangles meet the chord
      // An edge from p or q: f is linear along it, its infimum is the tangent at that end.
      const std::int8_t end_side = u_end ? su : sw;
      const std::int8_t far_side = u_end ? sw : su;
      const VertexId far = u_end ? w : u;
      if (far_side != 1 && far_side != -1) return;
      const Threshold th = rational_threshold(pc_, end_side == kSideP ? Kind::kTangentAtP : Kind::kTangentAtQ,
                                              far, sh_.pts[far]);
      if (far_side == 1) {
        info.has_a = true;
        info.a = th;
      } else {
        info.has_b = true;
        info.b = th;
      }
      return;
    }
    for (const int sigma : {1, -1}) {
      const bool in_u = su == sigma, in_w = sw == sigma;
      if (!in_u && !in_w) continue;
      bool interior = false;
      if (in_u && in_w) {
        interior = detail::enters_circle(pc_.p, pc_.q, pu, pw, su) > 0 && detail::enters_circle(pc_.p, pc_.q, pw, pu, sw) > 0;
      } else if (in_u) {
        interior = detail::enters_circle(pc_.p, pc_.q, pu, pw, su) > 0;
      } else {
        interior = detail::enters_circle(pc_.p, pc_.q, pw, pu, sw) > 0;
      }
      if (!interior) continue;
      // Local coordinates, mirrored for the lower side (f(x₁, −x₂) = −f(x₁, x₂)).
      Point lu = in_u ? xu.local : xw.local;
      Point lw = in_u ? xw.local : xu.local;
      if (sigma < 0) {
        lu.y = -lu.y;
        lw.y = -lw.y;
      }
      Threshold th;
      th.kind = Kind::kTangentToEdge;
      th.value = sigma * tangency_minimum(lu, lw);
      if (sigma > 0) {
        info.has_a = true;
        info.a = th;
      } else {
        info.has_b = true;
        info.b = th;
      }
    }
  }

  // Classifies candidate i for the current pencil: "always", and/or the thresholds a_t (above:
  // counts for s > a_t) and b_t (below: counts for s < b_t). Edge contributions are shared with
  // the neighbouring candidate across each edge.
  void classify(std::uint32_t i, bool& has_a, Threshold& a, bool& has_b, Threshold& b) {
    Candidate& cand = candidates_[i];
    const TriangleId t = cand.triangle;
    const auto& tv = sh_.slots[t].v;
    bool always = false;
    int ip = -1, iq = -1;
    for (int k = 0; k < 3; ++k) {
      const std::int8_t s = vertex(tv[k]).side;
      if (s == kSideP) ip = k;
      if (s == kSideQ) iq = k;
    }
    if (ip >= 0 && iq >= 0) always = true;  // pq is an edge of t
    // The open chord pq enters t at its corner p (or q): q strictly inside the corner's angle.
    if (!always && ip >= 0) {
      const Point& x = sh_.pts[tv[next3(static_cast<unsigned>(ip))]];
      const Point& y = sh_.pts[tv[prev3(static_cast<unsigned>(ip))]];
      always = orient2d(pc_.p, x, pc_.q) > 0 && orient2d(pc_.p, pc_.q, y) > 0;
    }
    if (!always && iq >= 0) {
      const Point& x = sh_.pts[tv[next3(static_cast<unsigned>(iq))]];
      const Point& y = sh_.pts[tv[prev3(static_cast<unsigned>(iq))]];
      always = orient2d(pc_.q, x, pc_.p) > 0 && orient2d(pc_.q, pc_.p, y) > 0;
    }
    has_a = has_b = false;
    const auto& neighbours = sh_.slots[t].n;
    for (unsigned k = 0; k < 3; ++k) {
      const Handle across = neighbours[k];
      const TriangleId n = triangle_of(across);
      std::uint32_t& ref = edge_ref_[3 * static_cast<std::size_t>(i) + k];
      if (candidate_stamp_[n] == candidate_mark_ && candidate_index_[n] < i) {
        ref = edge_ref_[3 * static_cast<std::size_t>(candidate_index_[n]) + edge_of(across)];
      } else {
        ref = static_cast<std::uint32_t>(edge_info_.size());
        edge_info_.emplace_back();
        classify_edge(tv[next3(k)], tv[prev3(k)], edge_info_.back());
      }
      const EdgeInfo& info = edge_info_[ref];
      always = always || info.crosses;
      if (info.has_a) keep_extreme(1, has_a, a, info.a);
      if (info.has_b) keep_extreme(-1, has_b, b, info.b);
    }
    cand.always = always;
    // A triangle that misses the chord cannot meet one disk of the pencil both above and below
    // the line (the segment joining the two meeting points would cross the open chord), so
    // b_t ≤ a_t; keep rounded tangencies from contradicting that.
    if (!always && has_a && has_b && compare_thresholds(pc_, b, a, exact_comparisons) > 0) b = a;
  }

  // A disk of the current pencil inside interval j, and the triangles it meets.
  void record_witness(std::size_t index, std::uint32_t j, std::uint32_t count) {
    best_count = count;
    best_pencil = index;
    const double upper = events_[group_start_[j]].th.value;
    double s = 0.0;
    if (j == 0) {
      s = upper - std::max(1.0, std::fabs(upper));
    } else {
      const double lower = events_[group_start_[j - 1]].th.value;
      s = 0.5 * lower + 0.5 * upper;
    }
    // Centre m + s·h with h = (q − p)⊥ / 2.
    const double mx = 0.5 * pc_.p.x + 0.5 * pc_.q.x, my = 0.5 * pc_.p.y + 0.5 * pc_.q.y;
    best_center = {mx - s * 0.5 * pc_.by, my + s * 0.5 * pc_.bx};
    best_radius = distance(best_center, pc_.p);
    best_triangles.clear();
    for (const Candidate& c : candidates_) {
      if (c.always || (c.a_group != kNone && c.a_group < j) || (c.b_group != kNone && c.b_group >= j)) {
        best_triangles.push_back(c.triangle);
      }
    }
  }

  const Shared& sh_;
  bool per_triangle_enabled_;
  bool prune_;
  std::vector<std::uint32_t> per_triangle_;

  // Flood scratch.
  Point circle_[3];
  Approx circle_orient_;
  std::uint32_t flood_stamp_ = 0, triangle_mark_ = 0;
  std::vector<FloodVertex> flood_vertex_;
  std::vector<std::uint32_t> triangle_stamp_;
  std::vector<TriangleId> stack_;

  // Pencil scratch.
  Pencil pc_;
  std::uint32_t pencil_stamp_ = 0, candidate_mark_ = 0;
  std::vector<PencilVertex> pencil_vertex_;
  // circumdisk_count(): the exact incircle signs of the vertices the filter left undecided, and per
  // edge handle whether the edge meets the disk (stamp << 1 | answer), per disk.
  struct DiskSide {
    std::uint32_t stamp = 0;
    std::int8_t sign = 0;
  };
  std::uint32_t disk_stamp_ = 0;
  std::vector<DiskSide> disk_side_;
  std::vector<std::uint32_t> edge_meets_;
  std::vector<std::uint32_t> candidate_stamp_, candidate_index_;
  std::vector<Candidate> candidates_;
  std::vector<EdgeInfo> edge_info_;        // the edges classified for the current pencil
  std::vector<std::uint32_t> edge_ref_;    // per candidate edge: its index in edge_info_
  std::vector<Event> events_;
  std::vector<std::uint32_t> group_start_, group_a_, group_b_, counts_, prefix_max_, suffix_max_;
  std::vector<std::uint32_t> key_order_, key_best_;       // the cache key's order; results by candidate
  std::vector<std::array<VertexId, 3>> key_triangles_;   // by candidate
};

// ---- driver -------------------------------------------------------------------------------------

unsigned thread_count(unsigned requested, std::size_t work) {
  if (work < 20000) return 1;  // small inputs: threads cost more than they save
  unsigned n = requested != 0 ? requested : std::thread::hardware_concurrency();
  return std::clamp(n, 1u, 16u);
}

// Runs body(worker, begin, end) on `threads` contiguous ranges of [0, n), one thread each.
template <class Body>
void for_ranges(std::vector<std::unique_ptr<Worker>>& workers, std::size_t n, Body body) {
  const std::size_t threads = workers.size();
  if (threads == 1) {
    body(*workers[0], 0, n, 0);
    return;
  }
  std::vector<std::exception_ptr> errors(threads);
  std::vector<std::thread> pool;
  for (std::size_t k = 0; k < threads; ++k) {
    pool.emplace_back([&, k] {
      try {
        body(*workers[k], n * k / threads, n * (k + 1) / threads, k);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  }
  for (auto& th : pool) th.join();
  for (auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

// Fills sh.list / sh.list_begin: the candidates of every Delaunay triangle (or of those flagged in
// `needed`; the others get empty lists), by floods.
// With `cap`, a list stops at cap triangles and its flag in sh.truncated is set if the flood had
// more to give.
void build_lists(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers,
                 const std::vector<std::uint8_t>* needed = nullptr,
                 std::vector<std::array<double, 4>>* boxes = nullptr,
                 std::uint32_t cap = std::numeric_limits<std::uint32_t>::max()) {
  if (boxes) boxes->assign(sh.dt.triangle_slots(), {kInf, kInf, -kInf, -kInf});
  for (auto& w : workers) w->want_flood_box = boxes != nullptr;
  const std::size_t slots = sh.dt.triangle_slots();
  std::vector<std::vector<TriangleId>> parts(workers.size());
  std::vector<std::uint32_t> local_begin(slots + 1, 0);
  for_ranges(workers, slots, [&](Worker& w, std::size_t begin, std::size_t end, std::size_t k) {
    std::vector<TriangleId>& part = parts[k];
    part.reserve((end - begin) * 12);
    std::vector<TriangleId> one;
    for (std::size_t t = begin; t < end; ++t) {
      sh.check_deadline();
      local_begin[t] = static_cast<std::uint32_t>(part.size());
      const auto dtt = static_cast<TriangleId>(t);
      if (sh.dt.is_dead(dtt) || sh.dt.is_ghost(dtt) || (needed && (*needed)[t] == 0)) continue;
      if (cap == std::numeric_limits<std::uint32_t>::max()) {
        w.flood(dtt, one);
      } else {
        one.clear();
        bool over = false;
        w.flood_each(dtt, [&](TriangleId c) {
          if (one.size() == cap) {
            over = true;
            return false;
          }
          one.push_back(c);
          return true;
        });
        sh.truncated[t] = over ? 1 : 0;
      }
      if (boxes) (*boxes)[t] = w.flood_box;
      part.insert(part.end(), one.begin(), one.end());
    }
  });
  std::size_t total = 0;
  for (const auto& part : parts) total += part.size();
  if (total > 0xFFFFFFF0u) throw InternalError("bundle: candidate lists too long");
  sh.list.clear();
  sh.list.reserve(total);
  sh.list_begin.assign(slots + 1, 0);
  for (std::size_t k = 0; k < workers.size(); ++k) {
    const std::size_t begin = slots * k / workers.size(), end = slots * (k + 1) / workers.size();
    const auto offset = static_cast<std::uint32_t>(sh.list.size());
    for (std::size_t t = begin; t < end; ++t) sh.list_begin[t] = local_begin[t] + offset;
    sh.list.insert(sh.list.end(), parts[k].begin(), parts[k].end());
    parts[k] = {};
  }
  sh.list_begin[slots] = static_cast<std::uint32_t>(sh.list.size());
}

std::vector<std::unique_ptr<Worker>> make_workers(const Shared& sh, unsigned threads, bool per_triangle,
                                                  bool prune) {
  std::vector<std::unique_ptr<Worker>> workers;
  for (unsigned k = 0; k < threads; ++k) workers.push_back(std::make_unique<Worker>(sh, per_triangle, prune));
  return workers;
}

std::string triangle_name(std::size_t i) { return "triangle " + std::to_string(i + 1); }

}  // namespace

namespace {

// bundle_number's lists within options.candidate_budget: every list capped at an equal share of
// the budget, then the lists cut short again with an equal share of what is left. False if some
// list is still cut short (sh.truncated says which).
bool build_lists_within_budget(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers, std::size_t budget) {
  const std::size_t slots = sh.dt.triangle_slots();
  std::size_t disks = 0;
  for (TriangleId d = 0; d < slots; ++d) disks += sh.dt.is_dead(d) || sh.dt.is_ghost(d) ? 0 : 1;
  const auto share = [](std::size_t total, std::size_t parts) {
    return static_cast<std::uint32_t>(std::min<std::size_t>(total / std::max<std::size_t>(parts, 1), 0xFFFFFFF0u));
  };
  const std::uint32_t first_cap = std::max<std::uint32_t>(1, share(budget, disks));
  sh.truncated.assign(slots, 0);
  build_lists(sh, workers, nullptr, nullptr, first_cap);
  std::vector<std::uint8_t> again(slots, 0);
  std::size_t cut = 0;
  for (TriangleId d = 0; d < slots; ++d) {
    again[d] = sh.truncated[d];
    cut += again[d];
  }
  if (cut == 0) {
    sh.truncated.clear();
    return true;
  }
  const std::size_t used = sh.list.size();
  const std::uint32_t second_cap = share(budget > used ? budget - used : 0, cut);
  if (second_cap > first_cap) {
    std::vector<TriangleId> first_list = std::move(sh.list);
    std::vector<std::uint32_t> first_begin = std::move(sh.list_begin);
    build_lists(sh, workers, &again, nullptr, second_cap);
    std::vector<TriangleId> list;
    std::vector<std::uint32_t> begin(slots + 1, 0);
    list.reserve(first_list.size() + sh.list.size());
    cut = 0;
    for (TriangleId d = 0; d < slots; ++d) {
      begin[d] = static_cast<std::uint32_t>(list.size());
      if (again[d]) {
        list.insert(list.end(), sh.list.begin() + sh.list_begin[d], sh.list.begin() + sh.list_begin[d + 1]);
        cut += sh.truncated[d];
      } else {
        list.insert(list.end(), first_list.begin() + first_begin[d], first_list.begin() + first_begin[d + 1]);
      }
    }
    begin[slots] = static_cast<std::uint32_t>(list.size());
    sh.list = std::move(list);
    sh.list_begin = std::move(begin);
    for (TriangleId d = 0; d < slots; ++d) {
      if (!again[d]) sh.truncated[d] = 0;
    }
  }
  if (cut == 0) sh.truncated.clear();
  return cut == 0;
}

// How many circumdisks cut short bundle_number counts in full for its lower bound.
constexpr std::size_t kFullCounts = 4;

}  // namespace

BundleResult bundle_number(const Mesh& mesh, const BundleOptions& options) {
  BundleResult result;
  Shared sh(mesh, options.deadline);
  if (!sh.build()) {
    if (options.per_triangle) result.per_triangle.assign(mesh.triangle_slots(), 0);
    return result;
  }
  const unsigned threads = thread_count(options.threads, sh.pencils.size());
  // Without per-triangle values, a pencil with no more candidates than the best count so far
  // cannot improve it and is skipped (the first pencil reaching the maximum is never skipped, so
  // the witness does not depend on the number of threads).
  auto workers = make_workers(sh, threads, options.per_triangle, !options.per_triangle);
  const bool budgeted = options.candidate_budget > 0 && !options.per_triangle;
  bool complete = true;
  if (budgeted) {
    complete = build_lists_within_budget(sh, workers, options.candidate_budget);
  } else {
    build_lists(sh, workers);
  }
  for_ranges(workers, sh.pencils.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t i = begin; i < end; ++i) {
      sh.check_deadline();
      w.sweep(i);
    }
  });
  // Merge: the largest count, ties to the first pencil.
  const Worker* best = workers[0].get();
  for (const auto& w : workers) {
    if (w->best_count > best->best_count || (w->best_count == best->best_count && w->best_pencil < best->best_pencil)) {
      best = w.get();
    }
    result.circumdisk_bound = std::max(result.circumdisk_bound, w->circumdisk_best);
    result.pencils += w->pencils;
    result.candidate_pairs += w->candidate_pairs;
    result.exact_comparisons += w->exact_comparisons;
  }
  result.bundle_number = best->best_count;
  result.disk_center = best->best_center;
  result.disk_radius = best->best_radius;
  result.triangles = best->best_triangles;
  result.lower_bound = result.upper_bound = result.bundle_number;
  if (!complete) {
    // Some circumdisks meet more triangles than the budget lets their lists hold (points on a
    // circle: every circumdisk is about the whole circle). The pencils with a list cut short were
    // not swept; what was swept is exact. Lower bound: that, or a circumdisk counted in full
    // (those whose cut lists met the most triangles; a circumdisk of DT(V) is vertex-empty, so it
    // is a witness). Upper bound: no disk meets more than every triangle.
    std::vector<std::pair<std::uint32_t, TriangleId>> cut;  // (met within the cut list, slot)
    for (TriangleId d = 0; d < sh.truncated.size(); ++d) {
      if (!sh.truncated[d]) continue;
      ++result.truncated_disks;
      const std::uint32_t size = sh.list_begin[d + 1] - sh.list_begin[d];
      cut.emplace_back(workers[0]->circumdisk_count(d, sh.list.data() + sh.list_begin[d], size, nullptr), d);
    }
    const std::size_t full = std::min(kFullCounts, cut.size());
    std::partial_sort(cut.begin(), cut.begin() + static_cast<std::ptrdiff_t>(full), cut.end(),
                      [](const auto& x, const auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
    std::vector<TriangleId> met;
    for (std::size_t i = 0; i < full; ++i) {
      const TriangleId d = cut[i].second;
      workers[0]->collect_meeting(d, met);
      const auto count = static_cast<std::uint32_t>(met.size());
      result.circumdisk_bound = std::max(result.circumdisk_bound, count);
      if (count <= result.lower_bound) continue;
      result.lower_bound = count;
      const auto& v = sh.dt.triangles[d].v;
      result.disk_center = circumcenter(sh.pts[v[0]], sh.pts[v[1]], sh.pts[v[2]]);
      result.disk_radius = distance(result.disk_center, sh.pts[v[0]]);
      result.triangles = met;
    }
    std::uint32_t domain = 0;
    for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) domain += mesh.in_domain(t) ? 1 : 0;
    result.upper_bound = std::max(domain, result.lower_bound);
    result.bundle_number = result.lower_bound;
    result.exact = result.lower_bound == result.upper_bound;
  }
  std::sort(result.triangles.begin(), result.triangles.end());
  if (options.per_triangle) {
    result.per_triangle = std::move(workers[0]->per_triangle());
    for (std::size_t k = 1; k < workers.size(); ++k) {
      const auto& other = workers[k]->per_triangle();
      for (std::size_t t = 0; t < other.size(); ++t) result.per_triangle[t] = std::max(result.per_triangle[t], other[t]);
    }
  }
  return result;
}

std::vector<std::uint32_t> circumdisk_bundle_per_triangle(const Mesh& mesh, unsigned threads_requested) {
  std::vector<std::uint32_t> best(mesh.triangle_slots(), 0);
  Shared sh(mesh);
  if (!sh.build()) return best;
  const unsigned threads = thread_count(threads_requested, sh.dt.triangle_slots());
  auto workers = make_workers(sh, threads, true, false);
  for_ranges(workers, sh.dt.triangle_slots(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
    std::vector<TriangleId> list, met;
    auto& mine = w.per_triangle();
    for (std::size_t t = begin; t < end; ++t) {
      const auto dtt = static_cast<TriangleId>(t);
      if (sh.dt.is_dead(dtt) || sh.dt.is_ghost(dtt)) continue;
      w.flood(dtt, list);
      met.clear();
      const std::uint32_t count = w.circumdisk_count(dtt, list.data(), list.size(), &met);
      for (const TriangleId c : met) mine[c] = std::max(mine[c], count);
    }
  });
  for (const auto& w : workers) {
    const auto& mine = w->per_triangle();
    for (std::size_t t = 0; t < best.size(); ++t) best[t] = std::max(best[t], mine[t]);
  }
  return best;
}

namespace {

// Permissive: true whenever the open circumdisk of the counter-clockwise a, b, c might meet the
// interior of the triangle x[0], x[1], x[2] (never false when it does). If it meets the interior
// and holds no corner, it meets an edge (a disk cannot lie inside a mesh triangle with its three
// defining vertices on the triangle's boundary, and a convex corner meeting the disk near a corner
// on the circle has an edge entering it); along an edge the incircle value is a concave
// quadratic, bounded as in Worker::edge_may_meet.
bool circumdisk_may_meet(const Point& a, const Point& b, const Point& c, const Point* const x[3]) {
  Approx g[3];
  for (int i = 0; i < 3; ++i) {
    g[i] = incircle_approx(a, b, c, *x[i]);
    if (g[i].value > -g[i].error) return true;
  }
  const Approx o = orient_approx(a, b, c);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double ex = x[j]->x - x[i]->x, ey = x[j]->y - x[i]->y;
    const double e2 = ex * ex + ey * ey;
    const double quad = o.value * e2;
    const double quad_error = (o.error + 4.0 * kEps * o.value) * e2;
    const double slope = g[j].value - g[i].value + quad;
    const double lambda = quad > 0.0 ? std::clamp(slope / (2.0 * quad), 0.0, 1.0) : 0.0;
    const double gmax = g[i].value + lambda * (slope - quad * lambda);
    const double slack = 2.0 * (g[i].error + g[j].error + quad_error +
                                8.0 * kEps * (std::fabs(g[i].value) + std::fabs(g[j].value) + quad));
    if (gmax > -slack) return true;
  }
  return false;
}

}  // namespace

namespace {

// in_k_bundle with DT(V) (subset null), or with the Delaunay triangulation of a subset W of the
// vertices around the queries. A triangle of DT(W) whose open circumdisk holds no vertex of V is a
// triangle of DT(V) (a Delaunay triangulation of V; with cocircular vertices any one serves: the
// empty disks are the same). The local attempt checks that of every DT(W) triangle it uses — the
// fan around the flood's starting corner, S(t) and the neighbours across its edges — and that none
// of those lies on the hull of DT(W) except along hull edges of the mesh; then the floods over
// DT(W) are the floods over DT(V) and the answer is exact. Otherwise it gives up (kGaveUp). The
// local attempt sees only a region of the mesh (Shared::build_region); a flood that would leave it
// makes it give up too (kEscaped: a larger region may do).
enum class Attempt : std::uint8_t { kAnswered, kGaveUp, kEscaped };

// `sh` is built (DT(V): Shared::build(false); DT(W): Shared::build_region, `subset` true);
// `queries` are slots of sh (kNone for a query outside the domain).
Attempt in_k_bundle_attempt(Shared& sh, std::uint32_t k, const std::vector<TriangleId>& queries, KBundleStats& st,
                            unsigned threads_requested, bool subset, std::vector<std::uint8_t>& answer,
                            KBundleCache* cache) {
  answer.assign(queries.size(), 0);
  st = {};
  auto in_domain = [&](TriangleId t) { return t < sh.slots.size() && sh.in_domain(t); };
  const Mesh& dt = sh.dt;
  const std::size_t dt_slots = dt.triangle_slots();
  // A Delaunay edge leaving every vertex of V (DT ids are the renumbered ids below `used`).
  std::vector<Handle> dt_vertex_edge(sh.used, kNone);
  for (TriangleId t = 0; t < dt_slots; ++t) {
    if (dt.is_dead(t) || dt.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const VertexId o = dt.org(make_handle(t, e));
      if (dt_vertex_edge[o] == kNone) dt_vertex_edge[o] = make_handle(t, e);
    }
  }
  // S(t): the Delaunay triangles whose open circumdisk meets query t. Every pencil disk meeting t
  // lies in the union of the circumdisks of the two Delaunay triangles on its edge, so one of them
  // is in S(t). S(t) is connected across Delaunay edges (for a point x the triangles whose
  // circumdisks hold x form the connected Bowyer–Watson cavity of x, and the cavities of nearby
  // points share triangles), and it holds a triangle around each corner of t (the one overlapping
  // t's corner): a flood with the permissive test from the triangles around one corner finds it.
  //
  // Stage 1, per query, stopping at the first answer: each Delaunay triangle d of S(t) the flood
  // reaches is asked whether its circumdisk (vertex-empty) meets at least k triangles — counted
  // by a flood over the mesh that stops at k (Worker::count_meeting), once per d for all queries
  // — and if so whether it meets t (exactly). So a query in a large circumdisk costs O(k), not
  // what the disk meets (points on a circle: every circumdisk is the whole circle and meets every
  // triangle). Only the queries left undecided keep their S(t), for the pencils of stage 2.
  const unsigned threads = thread_count(threads_requested, 64 * queries.size());
  auto workers = make_workers(sh, threads, true, false);
  // Per Delaunay triangle: 0 not yet counted; 1 its circumdisk meets fewer than k triangles; 2 at
  // least k; 3 at least k, but not shown vertex-empty in V (local attempt; stage 2 then gives up).
  const std::unique_ptr<std::atomic<std::uint8_t>[]> disk_state(new std::atomic<std::uint8_t>[dt_slots]());
  struct Part {
    std::vector<TriangleId> s_list, fan;
    std::vector<std::uint32_t> dt_stamp;
    std::size_t decided = 0, disks_counted = 0;
    bool gave_up = false;
  };
  std::vector<Part> parts(workers.size());
  std::vector<std::uint32_t> s_count(queries.size(), 0);
  auto large_disk = [&](Worker& w, Part& part, TriangleId d) {
    std::uint8_t state = disk_state[d].load(std::memory_order_relaxed);
    if (state != 0) return state == 2;
    ++part.disks_counted;
    state = w.count_meeting(d, k) >= k ? 2 : 1;
    if (state == 2 && subset) {
      // DT(W) is Delaunay for W only: the disk must hold no other vertex of V, which would be a
      // corner of an in-domain triangle meeting it (a full flood, which must stay in the region).
      std::vector<TriangleId> list;
      const bool escaped_before = w.escaped;
      w.escaped = false;
      w.flood(d, list);
      const auto& dv = dt.triangles[d].v;
      bool empty = !w.escaped;
      for (std::size_t i = 0; i < list.size() && empty; ++i) {
        for (const VertexId v : sh.slots[list[i]].v) {
          if (v >= sh.used && incircle(sh.pts[dv[0]], sh.pts[dv[1]], sh.pts[dv[2]], sh.pts[v]) > 0) empty = false;
        }
      }
      w.escaped = escaped_before;
      if (!empty) state = 3;
    }
    disk_state[d].store(state, std::memory_order_relaxed);
    return state == 2;
  };
  for_ranges(workers, queries.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t k_part) {
    Part& part = parts[k_part];
    part.dt_stamp.assign(dt_slots, 0);
    std::vector<TriangleId> stack;
    for (std::size_t qi = begin; qi < end; ++qi) {
      const TriangleId t = queries[qi];
      if (!in_domain(t)) continue;
      sh.check_deadline();
      const auto& tv = sh.slots[t].v;
      const Point* const corners[3] = {&sh.pts[tv[0]], &sh.pts[tv[1]], &sh.pts[tv[2]]};
      const auto stamp = static_cast<std::uint32_t>(qi - begin + 1);
      const std::size_t first = part.s_list.size(), first_fan = part.fan.size();
      stack.clear();
      auto consider = [&](TriangleId d) {
        if (part.dt_stamp[d] == stamp || dt.is_ghost(d)) return;
        part.dt_stamp[d] = stamp;
        const auto& dv = dt.triangles[d].v;
        if (!circumdisk_may_meet(sh.pts[dv[0]], sh.pts[dv[1]], sh.pts[dv[2]], corners)) return;
        stack.push_back(d);
        part.s_list.push_back(d);
      };
      // The seed corner: with a subset, one whose fan in DT(W) has no ghost (a corner on the hull
      // of V has ghosts around it in any Delaunay triangulation; another corner serves as well).
      unsigned corner = 0;
      if (subset) {
        corner = 3;
        for (unsigned c = 0; c < 3 && corner == 3; ++c) {
          if (tv[c] >= sh.used) break;  // a corner outside W
          const Handle first_edge = dt_vertex_edge[tv[c]];
          Handle g = first_edge;
          bool ghost = false;
          do {
            ghost = ghost || dt.is_ghost(triangle_of(g));
            g = dt.onext(g);
          } while (g != first_edge);
          if (!ghost) corner = c;
        }
        if (corner == 3) {
          part.gave_up = true;
          return;
        }
      }
      // The fan around the seed corner, one triangle at a time, each followed by the flood it
      // starts (a vertex of DT(V) may have thousands of neighbours, e.g. on a circle: a query
      // decided near its first fan triangle does not walk the whole fan).
      const Handle start = dt_vertex_edge[tv[corner]];
      Handle h = start;
      bool decided = false;
      do {
        if (subset) part.fan.push_back(triangle_of(h));
        consider(triangle_of(h));
        while (!stack.empty()) {
          const TriangleId d = stack.back();
          stack.pop_back();
          decided = large_disk(w, part, d) && w.disk_meets(d, t);
          if (decided) break;
          for (unsigned e = 0; e < 3; ++e) consider(triangle_of(dt.sym(make_handle(d, e))));
        }
        h = dt.onext(h);
      } while (h != start && !decided);
      if (decided) {
        answer[qi] = 1;
        ++part.decided;
        part.s_list.resize(first);
        part.fan.resize(first_fan);
      } else {
        s_count[qi] = static_cast<std::uint32_t>(part.s_list.size() - first);
      }
    }
  });
  std::vector<std::uint32_t> s_begin(queries.size() + 1, 0);
  std::vector<TriangleId> s_list, fan;
  for (Part& part : parts) {
    if (part.gave_up) return Attempt::kGaveUp;
    st.decided_by_circumdisks += part.decided;
    st.disks_counted += part.disks_counted;
    s_list.insert(s_list.end(), part.s_list.begin(), part.s_list.end());
    fan.insert(fan.end(), part.fan.begin(), part.fan.end());
    part = Part{};
  }
  for (std::size_t qi = 0; qi < queries.size(); ++qi) s_begin[qi + 1] = s_begin[qi] + s_count[qi];
  // Stage 2, for the queries left: S(t) and its neighbours across edges are flooded in full (the
  // candidate lists of the pencils).
  std::vector<std::uint8_t> needed(dt_slots, 0);  // 1: in some S(t); 2: a partner across an edge
  for (const TriangleId d : s_list) {
    needed[d] = 1;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(d, e);
      const TriangleId n = triangle_of(dt.sym(h));
      if (!dt.is_ghost(n) && needed[n] == 0) needed[n] = 2;
      if (subset && dt.is_ghost(n)) {
        // A hull edge of DT(W) is one of DT(V) if it is a hull edge of the mesh (whose hull holds V).
        const VertexId a = dt.org(h), b = dt.dest(h);
        const Handle first = sh.vertex_edge[a];
        Handle g = first;
        bool hull = false;
        for (std::size_t turn = 0; turn < sh.slots.size(); ++turn) {
          if (sh.dest(g) == b) {
            hull = sh.is_ghost(triangle_of(sh.sym(g))) && !sh.is_ghost(triangle_of(g));
            break;
          }
          g = sh.onext(g);
          if (g == first) break;
        }
        if (!hull) return Attempt::kGaveUp;
      }
    }
  }
  for (const TriangleId d : fan) {
    if (needed[d] == 0) needed[d] = 2;
  }
  for (TriangleId d = 0; d < dt_slots; ++d) {
    if (needed[d] != 0) ++st.flooded;
  }
  for (auto& w : workers) w->escaped = false;  // (stage 1's floods that left a region were cut short)
  std::vector<std::array<double, 4>> boxes;
  build_lists(sh, workers, &needed, cache ? &boxes : nullptr);
  if (cache) {
    // Per query, the box of every mesh triangle meeting a circumdisk of S(t) or of a neighbour of
    // S(t): every vertex-empty disk meeting t lies in two such circumdisks (or, on the hull side of
    // a pencil, meets the mesh only inside one), so every triangle it meets is in the box.
    // A query answered 1 gets its own box (bundle removal keeps the boxes of queries answered 0
    // only).
    cache->reach.assign(queries.size(), {kInf, kInf, -kInf, -kInf});
    for (std::size_t qi = 0; qi < queries.size(); ++qi) {
      if (!answer[qi]) continue;
      auto& r = cache->reach[qi];
      for (const VertexId v : sh.slots[queries[qi]].v) {
        const Point& p = sh.pts[v];
        r = {std::min(r[0], p.x), std::min(r[1], p.y), std::max(r[2], p.x), std::max(r[3], p.y)};
      }
    }
    auto widen = [&](std::array<double, 4>& r, TriangleId d) {
      const auto& b = boxes[d];
      r = {std::min(r[0], b[0]), std::min(r[1], b[1]), std::max(r[2], b[2]), std::max(r[3], b[3])};
    };
    for (std::size_t qi = 0; qi < queries.size(); ++qi) {
      auto& r = cache->reach[qi];
      for (std::uint32_t i = s_begin[qi]; i < s_begin[qi + 1]; ++i) {
        const TriangleId d = s_list[i];
        widen(r, d);
        for (unsigned e = 0; e < 3; ++e) {
          const TriangleId n = triangle_of(dt.sym(make_handle(d, e)));
          if (!dt.is_ghost(n)) widen(r, n);
        }
      }
    }
  }
  auto list_size = [&](TriangleId d) { return dt.is_ghost(d) ? 0u : sh.list_begin[d + 1] - sh.list_begin[d]; };
  if (subset) {
    // Each DT(W) triangle used must have a vertex-empty circumdisk: a vertex of V strictly inside
    // would be a corner of an in-domain triangle meeting the disk, hence of its candidate list.
    // Only vertices outside W need the test (ids from sh.used on): DT(W) is Delaunay, exactly, so
    // no vertex of W lies strictly inside one of its circumdisks. Each is tested once per disk
    // (it is a corner of several candidates; on meshes of slivers the disks are nearly flat and
    // most of these tests need the exact stage).
    std::vector<TriangleId> tested_for(sh.pts.size(), kNone);
    for (TriangleId d = 0; d < dt_slots; ++d) {
      if (needed[d] == 0) continue;
      const auto& dv = dt.triangles[d].v;
      const Point& a = sh.pts[dv[0]];
      const Point& b = sh.pts[dv[1]];
      const Point& c = sh.pts[dv[2]];
      for (std::uint32_t i = sh.list_begin[d]; i < sh.list_begin[d + 1]; ++i) {
        for (const VertexId v : sh.slots[sh.list[i]].v) {
          if (v < sh.used || tested_for[v] == d) continue;
          tested_for[v] = d;
          if (incircle(a, b, c, sh.pts[v]) > 0) return Attempt::kGaveUp;
        }
      }
    }
  }

  // A flood that left the region (checked after the test above: a list cut short that already
  // shows a vertex inside its disk gives up for good).
  for (const auto& w : workers) {
    if (w->escaped) return Attempt::kEscaped;
  }

  // The rest: pencils of the edges of S(t) whose two candidate lists together reach k (the only
  // ones whose disks can meet t and k triangles), swept exactly.
  std::vector<Handle> pencils;
  for (std::size_t qi = 0; qi < queries.size(); ++qi) {
    const TriangleId t = queries[qi];
    if (!in_domain(t) || answer[qi]) continue;
    bool any = false;
    for (std::uint32_t i = s_begin[qi]; i < s_begin[qi + 1]; ++i) {
      const TriangleId d = s_list[i];
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(d, e);
        const TriangleId n = triangle_of(dt.sym(h));
        if (list_size(d) + list_size(n) < k) continue;
        any = true;
        // Each edge once, directed from its smaller mesh vertex id (so that a KBundleCache key
        // does not depend on the slots of this call's Delaunay triangulation); a hull edge with
        // its finite side on the left.
        const Handle hs = dt.sym(h);
        pencils.push_back(dt.is_ghost(n) || sh.mesh_id[dt.org(h)] < sh.mesh_id[dt.dest(h)] ? h : hs);
      }
    }
    if (!any) ++st.decided_by_bound;
  }
  std::sort(pencils.begin(), pencils.end());
  pencils.erase(std::unique(pencils.begin(), pencils.end()), pencils.end());
  st.pencils_swept = pencils.size();
  if (!pencils.empty()) {
    sh.pencils = std::move(pencils);
    for (auto& w : workers) {
      w->min_candidates = k;
      if (cache) w->reuse = cache->impl.get();
    }
    for_ranges(workers, sh.pencils.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
      for (std::size_t i = begin; i < end; ++i) {
        sh.check_deadline();
        w.sweep(i);
      }
    });
    if (cache) {
      // Keep what this call used or made; drop the rest (stale keys of the mesh before).
      std::unordered_map<SweepKey, CachedSweep> next;
      auto& old = cache->impl->sweeps;
      for (auto& w : workers) {
        st.pencils_reused += w->pencils_reused;
        for (const SweepKey key : w->reused_keys) {
          const auto it = old.find(key);
          if (it != old.end()) next.insert_or_assign(key, std::move(it->second));
        }
        for (auto& [key, sweep] : w->made) next.insert_or_assign(key, std::move(sweep));
      }
      old = std::move(next);
    }
    for (std::size_t qi = 0; qi < queries.size(); ++qi) {
      const TriangleId t = queries[qi];
      if (!in_domain(t) || answer[qi]) continue;
      for (const auto& w : workers) {
        if (w->per_triangle()[t] >= k) answer[qi] = 1;
      }
      if (answer[qi]) ++st.decided_by_pencils;
    }
  }
  for (const auto& w : workers) st.flood_visits += w->flood_visits;
  return Attempt::kAnswered;
}

}  // namespace

namespace {

// The local attempt: W holds the vertices of the mesh triangles fewer than kSubsetRings steps
// (across edges, ghosts skipped) from the queries; the region holds the triangles at most
// `region_rings` steps away, every triangle around a vertex of W, and the ghosts next to them.
constexpr std::uint32_t kSubsetRings = 12;
constexpr std::uint32_t kRegionRings[] = {12, 32};

// Fills `region` / `region_ids` and `w` (ascending) for the queries.
void local_region(const Mesh& mesh, const std::vector<TriangleId>& queries, std::uint32_t region_rings,
                  std::vector<TriangleId>& region, DenseIds& region_ids, std::vector<VertexId>& w) {
  region.clear();
  region_ids = DenseIds(queries.size() * 256);
  std::vector<std::pair<VertexId, Handle>> corners;  // the corners of W, with an edge leaving each
  std::vector<TriangleId> frontier, next;
  for (const TriangleId t : queries) {
    if (t < mesh.triangle_slots() && !mesh.is_dead(t) && !mesh.is_ghost(t) && region_ids.insert(t).second) {
      region.push_back(t);
      frontier.push_back(t);
    }
  }
  for (std::uint32_t ring = 0; ring < region_rings && !frontier.empty(); ++ring) {
    next.clear();
    for (const TriangleId t : frontier) {
      const Triangle& tri = mesh.triangles[t];
      if (ring < kSubsetRings) {
        // Corner c is the origin of edge prev3(c).
        for (unsigned c = 0; c < 3; ++c) corners.emplace_back(tri.v[c], make_handle(t, prev3(c)));
      }
      for (unsigned e = 0; e < 3; ++e) {
        const TriangleId n = triangle_of(tri.n[e]);
        if (mesh.is_ghost(n) || mesh.is_dead(n) || !region_ids.insert(n).second) continue;
        region.push_back(n);
        next.push_back(n);
      }
    }
    frontier.swap(next);
  }
  std::sort(corners.begin(), corners.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  w.clear();
  for (std::size_t i = 0; i < corners.size(); ++i) {
    if (i > 0 && corners[i].first == corners[i - 1].first) continue;
    w.push_back(corners[i].first);
    const Handle start = corners[i].second;
    Handle h = start;
    do {
      if (region_ids.insert(triangle_of(h)).second) region.push_back(triangle_of(h));
      h = mesh.onext(h);
    } while (h != start);
  }
  const std::size_t finite = region.size();
  for (std::size_t i = 0; i < finite; ++i) {
    if (mesh.is_ghost(region[i])) continue;
    for (const Handle nh : mesh.triangles[region[i]].n) {
      const TriangleId n = triangle_of(nh);
      if (mesh.is_ghost(n) && region_ids.insert(n).second) region.push_back(n);
    }
  }
}

}  // namespace

std::vector<std::uint8_t> in_k_bundle(const Mesh& mesh, std::uint32_t k, const std::vector<TriangleId>& queries,
                                      KBundleStats* stats, unsigned threads, KBundleCache* cache_given,
                                      std::chrono::steady_clock::time_point deadline) {
  std::vector<std::uint8_t> answer(queries.size(), 0);
  // `cache`: sweeps and reach boxes; `cache_given`: also DT(V) (see KBundleCache::reuse_sweeps).
  KBundleCache* const cache = cache_given && cache_given->reuse_sweeps ? cache_given : nullptr;
  KBundleStats local_stats;
  KBundleStats& st = stats ? *stats : local_stats;
  st = {};
  if (cache) cache->reach.assign(queries.size(), {kInf, kInf, -kInf, -kInf});  // empty: nothing known
  if (queries.empty()) return answer;
  // Few queries in a large mesh: try the Delaunay triangulation of the vertices within a few
  // rings of mesh triangles around them (verified, see in_k_bundle_attempt) before DT(V), over a
  // region of the mesh around them (its cost is what the region holds); if a flood leaves the
  // region, over a larger one.
  if (queries.size() * 256 < mesh.triangle_slots()) {
    std::vector<TriangleId> region;
    DenseIds region_ids;
    std::vector<VertexId> w;
    Attempt a = Attempt::kGaveUp;
    for (const std::uint32_t rings : kRegionRings) {
      local_region(mesh, queries, rings, region, region_ids, w);
      Shared sh(mesh, deadline);
      if (!sh.build_region(region, region_ids, w)) break;
      std::vector<TriangleId> local_queries(queries.size());
      for (std::size_t qi = 0; qi < queries.size(); ++qi) local_queries[qi] = region_ids.find(queries[qi]);
      a = in_k_bundle_attempt(sh, k, local_queries, st, threads, true, answer, cache);
      if (a == Attempt::kAnswered) {
        st.local = true;
        return answer;
      }
      if (a == Attempt::kGaveUp) break;
    }
    if (a == Attempt::kEscaped) {
      // Floods reach far (long Delaunay disks, e.g. along the hull of a point set): the same
      // attempt over the whole mesh, still cheaper than DT(V).
      Shared sh(mesh, deadline);
      if (sh.build(false, &w) && in_k_bundle_attempt(sh, k, queries, st, threads, true, answer, cache) == Attempt::kAnswered) {
        st.local = true;
        return answer;
      }
    }
  }
  Shared sh(mesh, deadline);
  KBundleCache::Impl* const keep = cache_given ? cache_given->impl.get() : nullptr;
  if (!sh.build(false, nullptr, keep ? &keep->dt : nullptr, keep ? &keep->dt_mesh_id : nullptr)) {
    st = {};
    answer.assign(queries.size(), 0);
    if (cache) cache->reach.assign(queries.size(), {kInf, kInf, -kInf, -kInf});  // nothing known
    return answer;
  }
  in_k_bundle_attempt(sh, k, queries, st, threads, false, answer, cache);
  st.kept_dt = sh.kept_dt;
  if (keep) {
    keep->dt = std::move(sh.dt);
    keep->dt_mesh_id.assign(sh.mesh_id.begin(), sh.mesh_id.begin() + sh.used);
  }
  return answer;
}

BundleResult bundle_number(const std::vector<Point>& points,
                           const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           const BundleOptions& options) {
  if (triangles.empty()) return {};
  // The used points, renumbered densely.
  std::vector<std::uint32_t> compact(points.size(), kNone);
  std::vector<std::uint32_t> original;  // compact id → index into points
  Pslg pslg;
  std::vector<std::array<std::uint32_t, 3>> tris(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[i][k];
      if (v >= points.size()) {
        throw InputError("", 0, triangle_name(i) + " names vertex " + std::to_string(v) + ", which does not exist");
      }
      if (compact[v] == kNone) {
        compact[v] = static_cast<std::uint32_t>(original.size());
        original.push_back(v);
        pslg.points.push_back(points[v]);
      }
      tris[i][k] = compact[v];
    }
    auto& t = tris[i];
    const int o = orient2d(pslg.points[t[0]], pslg.points[t[1]], pslg.points[t[2]]);
    if (o == 0) throw InputError("", 0, triangle_name(i) + " is degenerate (its corners are collinear)");
    if (o < 0) std::swap(t[1], t[2]);
  }
  // Every edge of T is a segment: the constrained Delaunay triangulation then contains every
  // triangle of T and fills the holes and concavities, so the mesh covers the convex hull.
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * tris.size());
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edges.push_back(a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  pslg.segments.reserve(edges.size());
  for (const std::uint64_t e : edges) {
    pslg.segments.push_back({static_cast<std::uint32_t>(e >> 32), static_cast<std::uint32_t>(e & 0xFFFFFFFFu), 1});
  }
  ConstrainOptions constrain;
  constrain.strict = true;
  constrain.convex_hull = true;
  Mesh mesh;
  try {
    mesh = constrained_delaunay(pslg, constrain);
  } catch (const InputError& e) {
    throw InputError("", 0, std::string("the triangles do not form a triangulation: ") + e.what());
  }
  if (!mesh.duplicates.empty()) {
    const auto& [dup, kept] = mesh.duplicates.front();
    throw InputError("", 0, "vertices " + std::to_string(original[dup]) + " and " +
                                std::to_string(original[kept]) + " of the triangles coincide");
  }
  // Find every triangle of T among the faces; everything else is outside the domain.
  std::vector<Handle> vertex_edge(mesh.points.size(), kNone);
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (mesh.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId o = mesh.org(h);
      if (o != kInfinite && vertex_edge[o] == kNone) vertex_edge[o] = h;
    }
    if (!mesh.is_ghost(t)) mesh.flags[t] = static_cast<std::uint8_t>(mesh.flags[t] | kOutside);
  }
  std::vector<std::uint32_t> slot_to_input(mesh.triangle_slots(), kNone);
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const auto& t = tris[i];
    TriangleId found = kNone;
    const Handle start = vertex_edge[t[0]];
    Handle h = start;
    for (std::size_t turn = 0; turn < mesh.triangle_slots(); ++turn) {
      if (mesh.dest(h) == t[1] && mesh.apex(h) == t[2]) {
        found = triangle_of(h);
        break;
      }
      h = mesh.onext(h);
      if (h == start) break;
    }
    if (found == kNone) {
      throw InputError("", 0, triangle_name(i) + " overlaps other triangles (or a vertex lies on its boundary)");
    }
    if (slot_to_input[found] != kNone) {
      throw InputError("", 0, triangle_name(i) + " repeats " + triangle_name(slot_to_input[found]));
    }
    slot_to_input[found] = static_cast<std::uint32_t>(i);
    mesh.flags[found] = static_cast<std::uint8_t>(mesh.flags[found] & ~kOutside);
  }
  BundleResult r = bundle_number(mesh, options);
  for (std::uint32_t& t : r.triangles) t = slot_to_input[t];
  std::sort(r.triangles.begin(), r.triangles.end());
  if (options.per_triangle) {
    std::vector<std::uint32_t> by_input(triangles.size(), 0);
    for (TriangleId t = 0; t < r.per_triangle.size(); ++t) {
      if (slot_to_input[t] != kNone) by_input[slot_to_input[t]] = r.per_triangle[t];
    }
    r.per_triangle = std::move(by_input);
  }
  return r;
}

}  // namespace mwst
