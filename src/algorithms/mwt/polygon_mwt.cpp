// src/algorithms/mwt/polygon_mwt.cpp — the minimum weight triangulation of a simple polygon
// (polygon_mwt.hpp): Klincsek's interval dynamic program over the valid diagonals.
#include "algorithms/mwt/polygon_mwt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry/segments.hpp"

namespace mwst {

bool is_strictly_convex(const std::vector<Point>& P) {
  const std::size_t d = P.size();
  if (d < 3) return false;
  // Every corner turns left, and the fan from P[0] turns left throughout (so the boundary winds
  // once: a simple convex polygon).
  for (std::size_t i = 0; i < d; ++i) {
    if (orient2d(P[(i + d - 1) % d], P[i], P[(i + 1) % d]) <= 0) return false;
  }
  for (std::size_t i = 1; i + 1 < d; ++i) {
    if (orient2d(P[0], P[i], P[i + 1]) <= 0) return false;
  }
  return true;
}

double polygon_mwt(const std::vector<Point>& P, std::vector<std::array<std::uint32_t, 3>>* triangles) {
  const std::size_t d = P.size();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (d < 3) return kInf;
  // Scratch kept between calls (the optimiser calls this for every small region it tries, and
  // three allocations per call were a sizeable part of its time).
  thread_local std::vector<char> valid;
  thread_local std::vector<double> W, length;
  thread_local std::vector<std::uint32_t> choice;
  // valid[i][j]: the chord ij is a polygon edge or a diagonal lying inside the polygon. In a
  // strictly convex polygon every chord is (O(d) test instead of O(d³)).
  valid.assign(d * d, 0);
  for (std::size_t i = 0; i < d; ++i) {
    valid[i * d + (i + 1) % d] = valid[((i + 1) % d) * d + i] = 1;
  }
  const bool convex = is_strictly_convex(P);
  if (convex) std::fill(valid.begin(), valid.end(), 1);
  for (std::size_t i = 0; i < d && !convex; ++i) {
    for (std::size_t j = i + 2; j < d; ++j) {
      if (i == 0 && j == d - 1) continue;
      valid[i * d + j] = valid[j * d + i] = is_polygon_diagonal(P, d, i, j) ? 1 : 0;
    }
  }
  // W[i][j]: lightest triangulation of the sub-polygon i..j (diagonal weights only, chord ij
  // excluded); choice[i][j] the apex k of the triangle on chord ij.
  W.assign(d * d, kInf);
  choice.assign(d * d, 0);
  for (std::size_t i = 0; i + 1 < d; ++i) W[i * d + i + 1] = 0.0;
  // length[i][j] (i < j): the weight chord ij adds, 0 for a polygon edge; computed once per chord
  // rather than once per triangle of the recurrence that uses it.
  length.resize(d * d);
  for (std::size_t i = 0; i < d; ++i) {
    for (std::size_t j = i + 1; j < d; ++j) {
      length[i * d + j] = (j == i + 1 || (i == 0 && j == d - 1) || !valid[i * d + j]) ? 0.0 : distance(P[i], P[j]);
    }
  }
  auto chord = [&](std::size_t i, std::size_t j) { return length[i * d + j]; };
  for (std::size_t gap = 2; gap < d; ++gap) {
    for (std::size_t i = 0; i + gap < d; ++i) {
      const std::size_t j = i + gap;
      if (!valid[i * d + j]) continue;
      double best = kInf;
      std::uint32_t best_k = 0;
      for (std::size_t k = i + 1; k < j; ++k) {
        if (!valid[i * d + k] || !valid[k * d + j]) continue;
        if (W[i * d + k] == kInf || W[k * d + j] == kInf) continue;
        if (!convex && orient2d(P[i], P[k], P[j]) <= 0) continue;
        const double w = W[i * d + k] + W[k * d + j] + chord(i, k) + chord(k, j);
        if (w < best) {
          best = w;
          best_k = static_cast<std::uint32_t>(k);
        }
      }
      W[i * d + j] = best;
      choice[i * d + j] = best_k;
    }
  }
  const double total = W[0 * d + d - 1];
  if (total == kInf || !triangles) return total;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, d - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    const std::uint32_t k = choice[i * d + j];
    triangles->push_back({static_cast<std::uint32_t>(i), k, static_cast<std::uint32_t>(j)});
    stack.emplace_back(i, k);
    stack.emplace_back(k, j);
  }
  return total;
}

}  // namespace mwst
