// src/algorithms/bundle/pencil.cpp — rational thresholds of a pencil, rounded with a rigorous
// bound, and exactly (pencil.hpp).
#include "algorithms/bundle/pencil.hpp"

#include "geometry/expansion.hpp"
#include "mwst/error.hpp"

namespace mwst::bundle {

namespace {

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


}  // namespace

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
int compare_rational_exact(const Pencil& pc, const Threshold& a, const Threshold& b) {
  using namespace exact;
  Expansion<16> na, da, nb, db;
  rational_exact(pc, a.kind, pc.points[a.xv], na, da);
  rational_exact(pc, b.kind, pc.points[b.xv], nb, db);
  // a − b = (na·db − nb·da) / (da·db).
  const int s = sign(na * db - nb * da);
  return s * sign(da) * sign(db);
}

}  // namespace mwst::bundle
