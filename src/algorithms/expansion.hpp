// src/algorithms/expansion.hpp — exact signs of small polynomials in double coordinates, for the
// tie-breaking comparisons of the exact bundle number (bundle.cpp), whose rational thresholds
// (pencil circles through a vertex or tangent to an edge at its endpoint) are ratios of degree-2
// polynomials and must be compared exactly when their rounded values are too close to call.
//
// Technique: floating-point expansion arithmetic after J. R. Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates" (1997): error-free Two-Sum,
// Two-Diff and Two-Product (by fused multiply-add), Grow-Expansion, Fast-Expansion-Sum,
// Scale-Expansion and Compress. An expansion is a sum of nonoverlapping doubles in increasing order
// of magnitude with zeros removed; its sign is the sign of its largest component. Exact for the
// coordinate range of geometry.hpp (no underflow or overflow up to degree 4, as argued in
// src/geometry/predicates.cpp). (predicates.cpp keeps its own private copy of the same machinery;
// the two could share this header.) Compile with -ffp-contract=off.
#pragma once

#include <cmath>
#include <cstring>

namespace mwst::exact {

// x + y == a + b exactly, x == fl(a + b) (Knuth).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

// x + y == a + b exactly, x == fl(a + b); requires |a| >= |b| or a == 0 (Dekker).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

// x + y == a * b exactly, x == fl(a * b): the rounding error of a product is exactly
// representable and an explicit fused multiply-add computes it.
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

template <int N>
struct Expansion {
  double c[N];
  int n = 0;
};

template <int N>
inline int sign(const Expansion<N>& e) {
  return e.n == 0 ? 0 : (e.c[e.n - 1] > 0.0 ? 1 : -1);
}

// A faithful approximation of the value (components summed from the smallest).
template <int N>
inline double estimate(const Expansion<N>& e) {
  double s = 0.0;
  for (int i = 0; i < e.n; ++i) s += e.c[i];
  return s;
}

// a − b exactly, as at most two components.
inline Expansion<2> difference(double a, double b) {
  Expansion<2> h;
  const double x = a - b;
  const double bv = a - x;
  const double av = x + bv;
  const double y = (a - av) + (bv - b);
  if (y != 0.0) h.c[h.n++] = y;
  if (x != 0.0) h.c[h.n++] = x;
  return h;
}

namespace detail {

// h = e + b (Grow-Expansion with zero elimination); h must not alias e.
inline int grow(const double* e, int n, double b, double* h) {
  double q = b;
  int hn = 0;
  for (int i = 0; i < n; ++i) {
    double s = 0.0, err = 0.0;
    two_sum(q, e[i], s, err);
    q = s;
    if (err != 0.0) h[hn++] = err;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = e + f (merge by magnitude, then a Two-Sum chain: Fast-Expansion-Sum with zero elimination).
inline int sum(const double* e, int n, const double* f, int m, double* h) {
  if (n == 0) {
    if (m > 0) std::memcpy(h, f, sizeof(double) * static_cast<unsigned>(m));
    return m;
  }
  if (m == 0) {
    std::memcpy(h, e, sizeof(double) * static_cast<unsigned>(n));
    return n;
  }
  if (m == 1) return grow(e, n, f[0], h);
  if (n == 1) return grow(f, m, e[0], h);
  int i = 0, j = 0, hn = 0;
  double q = 0.0;
  if (std::fabs(e[0]) < std::fabs(f[0])) {
    q = e[i++];
  } else {
    q = f[j++];
  }
  while (i < n || j < m) {
    double g = 0.0;
    if (j >= m || (i < n && std::fabs(e[i]) < std::fabs(f[j]))) {
      g = e[i++];
    } else {
      g = f[j++];
    }
    double s = 0.0, err = 0.0;
    two_sum(q, g, s, err);
    q = s;
    if (err != 0.0) h[hn++] = err;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = e * b (Scale-Expansion with zero elimination); h must not alias e.
inline int scale(const double* e, int n, double b, double* h) {
  if (n == 0 || b == 0.0) return 0;
  int hn = 0;
  double q = 0.0, err = 0.0;
  two_product(e[0], b, q, err);
  if (err != 0.0) h[hn++] = err;
  for (int i = 1; i < n; ++i) {
    double hi = 0.0, lo = 0.0, s = 0.0;
    two_product(e[i], b, hi, lo);
    two_sum(q, lo, s, err);
    if (err != 0.0) h[hn++] = err;
    fast_two_sum(hi, s, q, err);
    if (err != 0.0) h[hn++] = err;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

}  // namespace detail

// Renormalises e in place (Compress): fewest components, same value.
template <int N>
inline void compress(Expansion<N>& e) {
  if (e.n < 2) return;
  double g[N];
  int bottom = e.n;
  double q = e.c[e.n - 1];
  for (int i = e.n - 2; i >= 0; --i) {
    double s = 0.0, err = 0.0;
    two_sum(q, e.c[i], s, err);
    if (err != 0.0) {
      g[--bottom] = s;
      q = err;
    } else {
      q = s;
    }
  }
  g[--bottom] = q;
  int hn = 0;
  q = g[bottom];
  for (int i = bottom + 1; i < e.n; ++i) {
    double s = 0.0, err = 0.0;
    two_sum(g[i], q, s, err);
    if (err != 0.0) e.c[hn++] = err;
    q = s;
  }
  if (q != 0.0) e.c[hn++] = q;
  e.n = hn;
}

template <int N, int M>
inline Expansion<N + M> operator+(const Expansion<N>& e, const Expansion<M>& f) {
  Expansion<N + M> h;
  h.n = detail::sum(e.c, e.n, f.c, f.n, h.c);
  return h;
}

template <int N>
inline Expansion<N> operator-(Expansion<N> e) {
  for (int i = 0; i < e.n; ++i) e.c[i] = -e.c[i];
  return e;
}

template <int N, int M>
inline Expansion<N + M> operator-(const Expansion<N>& e, const Expansion<M>& f) {
  return e + (-f);
}

// Exact product: the sum over f's components of e scaled by each.
template <int N, int M>
inline Expansion<2 * N * M> operator*(const Expansion<N>& e, const Expansion<M>& f) {
  Expansion<2 * N * M> acc;
  if (e.n == 0 || f.n == 0) return acc;
  acc.n = detail::scale(e.c, e.n, f.c[0], acc.c);
  Expansion<2 * N * M> tmp;
  double scaled[2 * N];
  for (int j = 1; j < f.n; ++j) {
    const int sn = detail::scale(e.c, e.n, f.c[j], scaled);
    tmp.n = detail::sum(acc.c, acc.n, scaled, sn, tmp.c);
    std::memcpy(acc.c, tmp.c, sizeof(double) * static_cast<unsigned>(tmp.n));
    acc.n = tmp.n;
  }
  return acc;
}

}  // namespace mwst::exact
