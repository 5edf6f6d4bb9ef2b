// src/algorithms/bundle/circle_predicates.cpp — the exact circle tests of the bundle number
// (circle_predicates.hpp has the list).
#include "algorithms/bundle/circle_predicates.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <gmp.h>

#include "algorithms/bundle/corner_incircle.hpp"
#include "geometry/expansion.hpp"

namespace mwst {

namespace bundle {

// ---- rounded values with rigorous bounds begin here ----------------------------------------------

namespace {

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

}  // namespace bundle

// ---- the sweep's tangency test begins here -------------------------------------------------------

// (Its geometry is described in circle_predicates.hpp.)
int detail::enters_circle(const Point& p, const Point& q, const Point& u, const Point& w, int orient_pqu) {
  using namespace bundle;  // Approx and its rounded arithmetic
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

namespace bundle {

// ---- edges crossing a circumdisk begin here ------------------------------------------------------

namespace {

// The smallest exponent E such that every nonzero coordinate of the points is an integer multiple
// of 2^E (a double is m · 2^(e − 53) with |m| < 2^53 an integer).
int smallest_exponent(const Point* const (&points)[5]) {
  int min_exponent = std::numeric_limits<int>::max();
  for (const Point* p : points) {
    for (const double v : {p->x, p->y}) {
      if (v == 0.0) continue;
      int e = 0;
      std::frexp(v, &e);
      min_exponent = std::min(min_exponent, e - 53);
    }
  }
  return min_exponent;
}

// v = m · 2^(e − 53) with |m| < 2^53 an integer, as an integer multiple of 2^min_exponent.
void to_integer(mpz_t out, double v, int min_exponent) {
  if (v == 0.0) {
    mpz_set_ui(out, 0);
    return;
  }
  int e = 0;
  const double m = std::ldexp(std::frexp(v, &e), 53);
  mpz_set_d(out, m);  // exact: m is an integer below 2^53 in magnitude
  mpz_mul_2exp(out, out, static_cast<mp_bitcnt_t>(e - 53 - min_exponent));
}

// The integers of segment_meets_open_circumdisk_exact (a few hundred bits): one set per thread,
// allocated once.
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

}  // namespace

// The degree-8 sign of circle_predicates.hpp, evaluated on integers (GMP).
bool segment_meets_open_circumdisk_exact(const Point& a, const Point& b, const Point& c, const Point& u,
                                         const Point& w) {
  const Point* const points[5] = {&a, &b, &c, &u, &w};
  const int min_exponent = smallest_exponent(points);
  auto integer_of = [min_exponent](mpz_t out, double v) { to_integer(out, v, min_exponent); };
  // Coordinates relative to u: A, B, Cc (circle), E = w − u.
  thread_local Registers r;
  // Named references (not a structured binding: lambdas below use them).
  auto& ux = r.ux; auto& uy = r.uy; auto& ax = r.ax; auto& ay = r.ay; auto& bx = r.bx; auto& by = r.by;
  auto& cx = r.cx; auto& cy = r.cy; auto& ex = r.ex; auto& ey = r.ey; auto& t1 = r.t1;
  auto& t2 = r.t2; auto& term = r.term; auto& lift_a = r.lift_a; auto& lift_b = r.lift_b;
  auto& lift_c = r.lift_c; auto& gu = r.gu; auto& gw = r.gw; auto& orient = r.orient;
  auto& coef = r.coef; auto& slope = r.slope; auto& disc = r.disc;
  integer_of(ux, u.x);
  integer_of(uy, u.y);
  // p −= d, in place.
  auto translate = [](mpz_t px, mpz_t py, const mpz_t dx, const mpz_t dy) {
    mpz_sub(px, px, dx);
    mpz_sub(py, py, dy);
  };
  auto relative = [&](mpz_t out_x, mpz_t out_y, const Point& p) {
    integer_of(out_x, p.x);
    integer_of(out_y, p.y);
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

// The filter (see circle_predicates.hpp).
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

// ---- the permissive test of in_k_bundle's first stage --------------------------------------------

// (See circle_predicates.hpp.)
bool circumdisk_may_meet(const Point& a, const Point& b, const Point& c, const Point* const x[3]) {
  Approx g[3];
  CornerCircle circle;
  bool have_circle = false;
  for (int i = 0; i < 3; ++i) {
    g[i] = incircle_approx(a, b, c, *x[i]);
    if (g[i].value > -g[i].error) {
      // Undecided: a small circle far from x[i] (the corner form decides where the differences to
      // x[i] cancel; see corner_incircle.hpp).
      if (!have_circle) circle = corner_circle(a, b, c);
      have_circle = true;
      const Approx h = corner_incircle(circle, *x[i]);
      if (!(h.value < -h.error) || g[i].value > g[i].error) return true;
      g[i] = h;
    }
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

}  // namespace bundle

}  // namespace mwst
