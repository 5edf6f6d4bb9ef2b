// bench/bench_predicates.cpp — the exact predicates of mwst/geometry/geometry.hpp (filter + exact stage,
// src/geometry/predicates.cpp) against CGAL 5.5's Exact_predicates_inexact_constructions_kernel
// (interval filter + exact fallback), side by side on the same inputs (Google Benchmark).
//
// Inputs, 4096 queries each, cycled:
//   random     — uniform points in the unit square: the floating-point filter decides;
//   grid       — unit squares of an integer grid offset to 1000: exactly cocircular, every query
//                reaches the exact stage and its answer is 0 (Delaunay of grids, Kuzmin cores);
//   circle     — four consecutive vertices of a 200k-gon from rounded cos/sin (the CDT
//                benchmark's polygon, bench_cdt): nearly cocircular, but the filter mostly decides;
//   circle far — four random vertices of that 200k-gon, in counter-clockwise order: nearly
//                cocircular at full scale, the filter fails (Delaunay of points on a circle);
//   collinear  — orient2d of three points on a line y = x/3 rounded: the exact stage decides.
// Usage: bench_predicates [Google Benchmark flags, e.g. --benchmark_repetitions=3]
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "mwst/geometry/geometry.hpp"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr std::size_t kQueries = 4096;

using Quad = std::array<mwst::Point, 4>;

std::vector<Quad> random_quads() {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Quad> q(kQueries);
  for (Quad& x : q) {
    for (mwst::Point& p : x) p = {u(rng), u(rng)};
    if (mwst::orient2d(x[0], x[1], x[2]) < 0) std::swap(x[1], x[2]);
  }
  return q;
}

std::vector<Quad> grid_quads() {
  std::vector<Quad> q(kQueries);
  for (std::size_t i = 0; i < kQueries; ++i) {
    const double x = 1000.0 + static_cast<double>(i % 64), y = 1000.0 + static_cast<double>(i / 64);
    q[i] = {mwst::Point{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}};
  }
  return q;
}

std::vector<Quad> circle_quads() {
  constexpr double n = 200000.0;
  auto at = [&](double k) {
    const double t = 2.0 * std::numbers::pi * k / n;
    return mwst::Point{std::cos(t), std::sin(t)};
  };
  std::vector<Quad> q(kQueries);
  for (std::size_t i = 0; i < kQueries; ++i) {
    const double k = static_cast<double>(i * 37);
    q[i] = {at(k), at(k + 1), at(k + 2), at(k + 3)};
  }
  return q;
}

std::vector<Quad> circle_far_quads() {
  constexpr int n = 200000;
  auto at = [&](int k) {
    const double t = 2.0 * std::numbers::pi * k / n;
    return mwst::Point{std::cos(t), std::sin(t)};
  };
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> u(0, n - 1);
  std::vector<Quad> q(kQueries);
  for (Quad& x : q) {
    std::array<int, 4> k{};
    do {
      for (int& v : k) v = u(rng);
      std::sort(k.begin(), k.end());
    } while (std::adjacent_find(k.begin(), k.end()) != k.end());
    for (std::size_t i = 0; i < 4; ++i) x[i] = at(k[i]);
  }
  return q;
}

std::vector<Quad> collinear_triples() {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1000.0);
  std::vector<Quad> q(kQueries);
  for (Quad& x : q) {
    for (int k = 0; k < 3; ++k) {
      const double t = u(rng);
      x[static_cast<std::size_t>(k)] = {t, t / 3.0};
    }
  }
  return q;
}

const std::vector<Quad>& inputs(int which) {
  static const std::vector<Quad> r = random_quads(), g = grid_quads(), c = circle_quads(),
                                 l = collinear_triples(), f = circle_far_quads();
  switch (which) {
    case 0: return r;
    case 1: return g;
    case 2: return c;
    case 3: return l;
    default: return f;
  }
}

const char* kNames[] = {"random", "grid", "circle", "collinear", "circle far"};

// Times `predicate` cycling over the queries of input state.range(0), each query given as its
// points in the representation `convert` makes of an mwst point (mwst's own, or CGAL's).
template <class Convert, class Predicate>
void run_queries(benchmark::State& state, Convert convert, Predicate predicate) {
  const auto& q = inputs(static_cast<int>(state.range(0)));
  state.SetLabel(kNames[state.range(0)]);
  using P = decltype(convert(mwst::Point{}));
  std::vector<std::array<P, 4>> c(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    for (std::size_t k = 0; k < 4; ++k) c[i][k] = convert(q[i][k]);
  }
  std::size_t i = 0;
  int acc = 0;
  for (auto _ : state) acc += static_cast<int>(predicate(c[i++ % kQueries]));
  benchmark::DoNotOptimize(acc);
  state.SetItemsProcessed(state.iterations());
}

const auto as_mwst = [](const mwst::Point& p) { return p; };
const auto as_cgal = [](const mwst::Point& p) { return K::Point_2(p.x, p.y); };

void mwst_incircle(benchmark::State& state) {
  run_queries(state, as_mwst, [](const auto& x) { return mwst::incircle(x[0], x[1], x[2], x[3]); });
}

void cgal_incircle(benchmark::State& state) {
  const auto side = K().side_of_oriented_circle_2_object();
  run_queries(state, as_cgal, [&](const auto& x) { return side(x[0], x[1], x[2], x[3]); });
}

void mwst_orient2d(benchmark::State& state) {
  run_queries(state, as_mwst, [](const auto& x) { return mwst::orient2d(x[0], x[1], x[2]); });
}

void cgal_orient2d(benchmark::State& state) {
  const auto orientation = K().orientation_2_object();
  run_queries(state, as_cgal, [&](const auto& x) { return orientation(x[0], x[1], x[2]); });
}

BENCHMARK(mwst_incircle)->Arg(0)->Arg(1)->Arg(2)->Arg(4);
BENCHMARK(cgal_incircle)->Arg(0)->Arg(1)->Arg(2)->Arg(4);
BENCHMARK(mwst_orient2d)->Arg(0)->Arg(3);
BENCHMARK(cgal_orient2d)->Arg(0)->Arg(3);

}  // namespace

BENCHMARK_MAIN();
