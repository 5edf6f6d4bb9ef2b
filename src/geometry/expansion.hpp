// src/geometry/expansion.hpp — floating-point expansion arithmetic: exact sums and products of
// doubles, after J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates", Discrete & Computational Geometry 18:305–363, 1997 (error-free Two-Sum /
// Fast-Two-Sum / Two-Diff / Two-Product, Grow-Expansion, Fast-Expansion-Sum, Scale-Expansion and
// Compress, with zero elimination). Written from the paper's theorems.
//
// The exact stages of the predicates (predicates.cpp) and the exact tie-breaking of the bundle
// number (src/algorithms/bundle/) share it. Exact for the coordinate range of geometry.hpp (no
// underflow or overflow up to degree 4; the argument is in predicates.cpp). Internal to the
// library (not installed). Everything including it must be compiled with -ffp-contract=off.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>

namespace mwst::exact {

// The routines are forced inline so that callers compiled for a richer instruction set (the
// predicates' fused-multiply-add clones, predicates.cpp) get that instruction set in them too.
#if defined(__GNUC__)
#define MWST_EXACT_INLINE inline __attribute__((always_inline))
#else
#define MWST_EXACT_INLINE inline
#endif


// ---- error-free transformations ---------------------------------------------------------------

// x + y == a + b exactly, x == fl(a + b). No precondition (Knuth's Two-Sum).
MWST_EXACT_INLINE void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  const double b_roundoff = b - b_virtual;
  const double a_roundoff = a - a_virtual;
  y = a_roundoff + b_roundoff;
}

// x + y == a + b exactly, x == fl(a + b). Precondition: |a| >= |b| (or a == 0) (Dekker).
MWST_EXACT_INLINE void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  y = b - b_virtual;
}

// x + y == a - b exactly, x == fl(a - b).
MWST_EXACT_INLINE void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double b_virtual = a - x;
  const double a_virtual = x + b_virtual;
  const double b_roundoff = b_virtual - b;
  const double a_roundoff = a - a_virtual;
  y = a_roundoff + b_roundoff;
}

// x + y == a * b exactly, x == fl(a * b). The error term comes from an explicit fused multiply-add,
// which is exact here (the error of a product is representable when nothing underflows). With
// hardware FMA (-mfma) this is one instruction; otherwise glibc dispatches std::fma to the FMA
// instruction at run time when the CPU has it. Dekker's splitting is the portable alternative and
// is used when MWST_DEKKER_PRODUCT is defined (kept for machines without fast fma).
#if defined(MWST_DEKKER_PRODUCT)
MWST_EXACT_INLINE void split(double a, double& hi, double& lo) {
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  const double c = kSplitter * a;
  const double a_big = c - a;
  hi = c - a_big;
  lo = a - hi;
}
MWST_EXACT_INLINE void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi = 0.0, alo = 0.0, bhi = 0.0, blo = 0.0;
  split(a, ahi, alo);
  split(b, bhi, blo);
  const double err1 = x - ahi * bhi;
  const double err2 = err1 - alo * bhi;
  const double err3 = err2 - ahi * blo;
  y = alo * blo - err3;
}
#else
MWST_EXACT_INLINE void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}
#endif

// ---- expansions -------------------------------------------------------------------------------
//
// An expansion is a sum of doubles stored in increasing order of magnitude, nonoverlapping (in
// fact strongly nonoverlapping, as all the routines below produce under round-to-even), with no
// zero components. The empty expansion is 0. N is a compile-time capacity.

template <int N>
struct Expansion {
  double c[N];
  int n = 0;
  void push(double v) {
    if (v != 0.0) c[n++] = v;
  }
};

template <int N>
inline int sign_of(const Expansion<N>& e) {
  if (e.n == 0) return 0;
  return e.c[e.n - 1] > 0.0 ? 1 : -1;
}

// Approximation of the value (within a few ulps): components summed from the smallest.
template <int N>
inline double estimate(const Expansion<N>& e) {
  double s = 0.0;
  for (int i = 0; i < e.n; ++i) s += e.c[i];
  return s;
}

// The exact difference a - b as an expansion of at most two components.
inline Expansion<2> difference(double a, double b) {
  double x = 0.0, y = 0.0;
  two_diff(a, b, x, y);
  Expansion<2> h;
  h.push(y);
  h.push(x);
  return h;
}

template <int N>
inline void negate(Expansion<N>& e) {
  for (int i = 0; i < e.n; ++i) e.c[i] = -e.c[i];
}

// h = e + b (Grow-Expansion, Shewchuk Theorem 10, with zero elimination). h may not alias e.
MWST_EXACT_INLINE int grow_expansion(const double* e, int n, double b, double* h) {
  double q = b;
  int hn = 0;
  for (int i = 0; i < n; ++i) {
    double sum = 0.0, err = 0.0;
    two_sum(q, e[i], sum, err);
    q = sum;
    if (err != 0.0) h[hn++] = err;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = e + f by merging the components by magnitude and running a Two-Sum chain through them
// (Fast-Expansion-Sum, Shewchuk Theorem 13, with zero elimination). h may not alias e or f.
MWST_EXACT_INLINE int expansion_sum(const double* e, int n, const double* f, int m, double* h) {
  if (n == 0) {
    std::memcpy(h, f, sizeof(double) * static_cast<std::size_t>(m));
    return m;
  }
  if (m == 0) {
    std::memcpy(h, e, sizeof(double) * static_cast<std::size_t>(n));
    return n;
  }
  if (m == 1) return grow_expansion(e, n, f[0], h);
  if (n == 1) return grow_expansion(f, m, e[0], h);
  // Merge by magnitude, written without data-dependent branches (the comparison outcomes are
  // unpredictable, and mispredictions dominated the cost). Zero elimination by a conditional
  // advance of the output index.
  int i = 0, j = 0, hn = 0;
  double q = 0.0;
  if (std::fabs(e[0]) < std::fabs(f[0])) {
    q = e[0];
    i = 1;
  } else {
    q = f[0];
    j = 1;
  }
  while (i < n && j < m) {
    const double ei = e[i], fj = f[j];
    const bool take_e = std::fabs(ei) < std::fabs(fj);
    const double g = take_e ? ei : fj;
    i += take_e ? 1 : 0;
    j += take_e ? 0 : 1;
    double sum = 0.0, err = 0.0;
    two_sum(q, g, sum, err);
    q = sum;
    h[hn] = err;
    hn += err != 0.0 ? 1 : 0;
  }
  for (; i < n; ++i) {
    double sum = 0.0, err = 0.0;
    two_sum(q, e[i], sum, err);
    q = sum;
    h[hn] = err;
    hn += err != 0.0 ? 1 : 0;
  }
  for (; j < m; ++j) {
    double sum = 0.0, err = 0.0;
    two_sum(q, f[j], sum, err);
    q = sum;
    h[hn] = err;
    hn += err != 0.0 ? 1 : 0;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = e * b (Scale-Expansion, Shewchuk Theorem 19, with zero elimination). h may not alias e.
MWST_EXACT_INLINE int scale_expansion(const double* e, int n, double b, double* h) {
  if (n == 0 || b == 0.0) return 0;
  int hn = 0;
  double q = 0.0, err = 0.0;
  two_product(e[0], b, q, err);
  if (err != 0.0) h[hn++] = err;
  for (int i = 1; i < n; ++i) {
    double p_hi = 0.0, p_lo = 0.0;
    two_product(e[i], b, p_hi, p_lo);
    double s = 0.0;
    two_sum(q, p_lo, s, err);
    if (err != 0.0) h[hn++] = err;
    fast_two_sum(p_hi, s, q, err);  // |p_hi| >= |s| by Theorem 19's argument
    if (err != 0.0) h[hn++] = err;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// Renormalizes e in place (Compress, Shewchuk §2.8): a top-down pass folds the components into
// as few full-precision words as possible, a bottom-up pass restores increasing order. The value is
// unchanged (every step is a Two-Sum); the result is nonadjacent, so its length is bounded by the
// bit span of the value, and its largest component approximates the value to within about one ulp.
// Keeps the expansions short before they are multiplied.
template <int N>
inline void compress(Expansion<N>& e) {
  if (e.n < 3) return;  // not worth it: short expansions stay short
  double g[N];
  int bottom = e.n;  // g[bottom..e.n) holds the first pass's output, largest first at the bottom
  double q = e.c[e.n - 1];
  for (int i = e.n - 2; i >= 0; --i) {
    double sum = 0.0, err = 0.0;
    two_sum(q, e.c[i], sum, err);
    if (err != 0.0) {
      g[--bottom] = sum;
      q = err;
    } else {
      q = sum;
    }
  }
  g[--bottom] = q;
  // g[bottom] is the smallest word, g[e.n - 1] the largest. Second pass: bottom-up.
  int hn = 0;
  q = g[bottom];
  for (int i = bottom + 1; i < e.n; ++i) {
    double sum = 0.0, err = 0.0;
    two_sum(g[i], q, sum, err);
    if (err != 0.0) e.c[hn++] = err;
    q = sum;
  }
  if (q != 0.0) e.c[hn++] = q;
  e.n = hn;
}

template <int N, int M>
inline Expansion<N + M> operator+(const Expansion<N>& e, const Expansion<M>& f) {
  Expansion<N + M> h;
  h.n = expansion_sum(e.c, e.n, f.c, f.n, h.c);
  return h;
}

template <int N, int M>
inline Expansion<N + M> operator-(const Expansion<N>& e, Expansion<M> f) {
  negate(f);
  return e + f;
}

template <int N>
inline Expansion<2 * N> scale(const Expansion<N>& e, double b) {
  Expansion<2 * N> h;
  h.n = scale_expansion(e.c, e.n, b, h.c);
  return h;
}

// Exact product of two expansions: the sum over f's components of e scaled by each.
template <int N, int M>
inline Expansion<2 * N * M> operator*(const Expansion<N>& e, const Expansion<M>& f) {
  Expansion<2 * N * M> result;
  if (e.n == 0 || f.n == 0) return result;
  if (f.n == 1) {
    result.n = scale_expansion(e.c, e.n, f.c[0], result.c);
    return result;
  }
  if (e.n == 1) {
    result.n = scale_expansion(f.c, f.n, e.c[0], result.c);
    return result;
  }
  // Ping-pong between two buffers, starting so that the last sum lands in result.
  Expansion<2 * N * M> other;
  const bool odd_merges = (f.n - 1) % 2 != 0;
  Expansion<2 * N * M>* acc = odd_merges ? &other : &result;
  Expansion<2 * N * M>* tmp = odd_merges ? &result : &other;
  acc->n = scale_expansion(e.c, e.n, f.c[0], acc->c);
  double scaled[2 * N];
  for (int j = 1; j < f.n; ++j) {
    const int sn = scale_expansion(e.c, e.n, f.c[j], scaled);
    tmp->n = expansion_sum(acc->c, acc->n, scaled, sn, tmp->c);
    Expansion<2 * N * M>* t = acc;
    acc = tmp;
    tmp = t;
  }
  return result;  // acc == &result here
}

// The sign of an expansion (the sign of its largest component).
template <int N>
inline int sign(const Expansion<N>& e) {
  return sign_of(e);
}

template <int N>
inline Expansion<N> operator-(Expansion<N> e) {
  negate(e);
  return e;
}

}  // namespace mwst::exact
