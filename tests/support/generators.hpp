// tests/support/generators.hpp — inputs for the tests: point sets and polygons.
// Point sets: uniform, Kuzmin (Blelloch et al. 1999), integer grids (many cocircular 4-tuples),
// exactly cocircular lattice points (all n points on one circle), points on a few lines (exactly
// collinear), clusters, power-of-two scaling (keeps every degeneracy exact), duplicates. Polygons:
// star-shaped rings, added to a PSLG with add_ring.
#pragma once

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::test {

// ---- point generators --------------------------------------------------------------------------

inline std::vector<Point> uniform_points(std::size_t n, std::uint64_t seed, double lo = 0.0,
                                         double hi = 1.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Point> p(n);
  for (auto& q : p) {
    q.x = u(rng);
    q.y = u(rng);
  }
  return p;
}

// 2-D Kuzmin distribution: uniform angle, radius with CDF 1 − 1/sqrt(1 + r²); heavily clustered
// near the origin with a long tail (PBBS randKuzmin).
inline std::vector<Point> kuzmin_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> p(n);
  for (auto& q : p) {
    const double theta = 2.0 * std::numbers::pi * u(rng);
    const double s = u(rng);
    const double r = std::sqrt(1.0 / ((1.0 - s) * (1.0 - s)) - 1.0);
    q = {r * std::cos(theta), r * std::sin(theta)};
  }
  return p;
}

// The nx × ny integer grid {0..nx-1} × {0..ny-1}, shuffled (every unit square is cocircular).
inline std::vector<Point> grid_points(int nx, int ny, std::uint64_t seed) {
  std::vector<Point> p;
  p.reserve(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) p.push_back({double(i), double(j)});
  std::mt19937_64 rng(seed);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

// All integer points on the circle x² + y² = r², r the product of the first `primes` primes
// ≡ 1 (mod 4): 4·3^primes points, all exactly cocircular. Each such prime is a norm p = a² + b² of
// the Gaussian prime a + bi; the lattice points are the products over the primes of one of
// (a+bi)², p, (a−bi)², times the four units (unique factorisation in Z[i]).
inline std::vector<Point> cocircular_lattice_points(int primes) {
  static constexpr int kA[] = {1, 2, 1, 2, 1, 4, 2, 5, 3, 5};  // 5 13 17 29 37 41 53 61 73 89
  static constexpr int kB[] = {2, 3, 4, 5, 6, 5, 7, 6, 8, 8};
  std::vector<std::pair<mpz_class, mpz_class>> z{{1, 0}};
  for (int k = 0; k < primes; ++k) {
    const long a = kA[k], b = kB[k];
    const std::pair<mpz_class, mpz_class> f[3] = {
        {a * a - b * b, 2 * a * b}, {a * a + b * b, 0}, {a * a - b * b, -2 * a * b}};
    std::vector<std::pair<mpz_class, mpz_class>> next;
    for (const auto& [x, y] : z)
      for (const auto& [u, v] : f) next.push_back({x * u - y * v, x * v + y * u});
    z.swap(next);
  }
  std::vector<Point> p;
  for (const auto& [x, y] : z) {
    const double dx = x.get_d(), dy = y.get_d();  // exact: |x|, |y| ≤ r < 2^53
    p.push_back({dx, dy});
    p.push_back({-dy, dx});
    p.push_back({-dx, -dy});
    p.push_back({dy, -dx});
  }
  return p;
}

// n points spread over `lines` random lines, exactly collinear on each: a + (k/1024)(b − a) with
// integer a, b in [−1000, 1000] (every coordinate is exact in double).
inline std::vector<Point> points_on_lines(std::size_t n, int lines, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coord(-1000, 1000), step(0, 1024);
  std::vector<std::pair<Point, Point>> ends;
  for (int i = 0; i < lines; ++i) {
    Point a{double(coord(rng)), double(coord(rng))}, b{double(coord(rng)), double(coord(rng))};
    if (a == b) b.x += 1.0;
    ends.push_back({a, b});
  }
  std::vector<Point> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& [a, b] = ends[i % ends.size()];
    const double t = step(rng) / 1024.0;
    p[i] = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
  }
  return p;
}

// Clusters of very different spreads (1e-9 to 1e-1) around uniform centres in [0, 1]².
inline std::vector<Point> clustered_points(std::size_t n, int clusters, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> centres;
  std::vector<double> spread;
  for (int c = 0; c < clusters; ++c) {
    centres.push_back({u(rng), u(rng)});
    spread.push_back(std::pow(10.0, -1.0 - 8.0 * u(rng)));
  }
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Point> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = i % centres.size();
    p[i] = {centres[c].x + spread[c] * g(rng), centres[c].y + spread[c] * g(rng)};
  }
  return p;
}

// Multiplies every coordinate by 2^exponent: exact, so collinearity and cocircularity survive.
inline std::vector<Point> scaled_pow2(std::vector<Point> p, int exponent) {
  for (auto& q : p) q = {std::ldexp(q.x, exponent), std::ldexp(q.y, exponent)};
  return p;
}

// Multiplies by a factor (rounded: degeneracies do not survive).
inline std::vector<Point> scaled(std::vector<Point> p, double factor) {
  for (auto& q : p) q = {q.x * factor, q.y * factor};
  return p;
}

// Appends `count` copies of random points of p and shuffles the result.
inline std::vector<Point> with_duplicates(std::vector<Point> p, std::size_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < count; ++i) p.push_back(p[rng() % n]);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}


// A star-shaped polygon around `centre` (which lies strictly inside it): n ≥ 4 vertices at jittered,
// increasing angles (consecutive gaps below π) and random radii in [r_min, r_max]; counter-clockwise.
inline std::vector<Point> star_polygon(Point centre, std::size_t n, double r_min, double r_max,
                                       std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double phase = 2.0 * std::numbers::pi * u(rng);
  std::vector<Point> p;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = phase + 2.0 * std::numbers::pi * (static_cast<double>(k) + 0.8 * u(rng)) / static_cast<double>(n);
    const double r = r_min + (r_max - r_min) * u(rng);
    p.push_back({centre.x + r * std::cos(a), centre.y + r * std::sin(a)});
  }
  return p;
}

// Appends a closed ring of points to a PSLG (segments between consecutive points).
inline void add_ring(Pslg& g, const std::vector<Point>& ring, std::int32_t marker = 1) {
  const auto first = static_cast<std::uint32_t>(g.points.size());
  for (std::size_t k = 0; k < ring.size(); ++k) {
    g.points.push_back(ring[k]);
    g.segments.push_back({first + static_cast<std::uint32_t>(k),
                          first + static_cast<std::uint32_t>((k + 1) % ring.size()), marker});
  }
}

inline long double polygon_area(const std::vector<Point>& r) {
  long double s = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    const Point &p = r[k], &q = r[(k + 1) % r.size()];
    s += (long double)p.x * q.y - (long double)q.x * p.y;
  }
  return std::fabs(s / 2);
}


}  // namespace mwst::test
