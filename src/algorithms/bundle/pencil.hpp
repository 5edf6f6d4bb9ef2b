// src/algorithms/bundle/pencil.hpp — the thresholds of one pencil of disks (internal).
// A pencil is the family of disks through the two ends p, q of a Delaunay edge; a disk of it is
// named by s (docs/algorithms/bundle-number.md, "One pencil"). A triangle starts or stops meeting
// the disks at thresholds of s:
//   Kind, Threshold, Pencil  — what a threshold is and the pencil it belongs to
//   rational_threshold       — a circle through a vertex, or tangent at p or q (rational in s)
//   compare_thresholds       — their order, exact unless a tangency to an edge is involved
//   tangency_minimum         — the irrational kind: a circle tangent to an edge's interior
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "algorithms/bundle/approx.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::bundle {

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

// A rational threshold: the pencil circle through x (kThroughVertex) or tangent at p / q to the
// edge towards x. x must not lie on the line pq (pencil.cpp has the formulas).
Threshold rational_threshold(const Pencil& pc, Kind kind, VertexId xv, const Point& x);

// The exact comparison of two rational thresholds (see compare_thresholds).
[[gnu::noinline]] int compare_rational_exact(const Pencil& pc, const Threshold& a, const Threshold& b);

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
inline double tangency_minimum(const Point& u, const Point& w) {
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

}  // namespace mwst::bundle
