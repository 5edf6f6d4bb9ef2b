// tests/mesh/test_delaunay.cpp — property tests of the exact Delaunay triangulation of point sets,
// mwst::delaunay (src/mesh/delaunay.cpp: Hilbert-order incremental insertion with Lawson flips;
// src/mesh/mesh.cpp: walk, splits, flips).
//
// Every case is checked twice: by validate(mesh, {.delaunay = true}) and by the independent checker
// of tests/support/exact_checker.hpp (GMP integers only: counter-clockwise triangles, each distinct point used
// exactly once, boundary = convex hull by monotone chain, area = hull area exactly, Euler count, and
// for small sets a brute-force empty-circumcircle test against every point). Inputs are the hard
// cases of the literature: Kuzmin's clustered distribution, integer grids (every unit square is
// cocircular), all points on one circle (exactly, on the integer lattice), few lines, 1e-40 and 1e40
// scales, multi-scale clusters, duplicates. Also determinism, invariance of the triangle set under
// permutation (general position), the duplicate bookkeeping, and the input errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/mesh/mesh.hpp"
#include "support/exact_checker.hpp"
#include "support/generators.hpp"

namespace mwst {
namespace {

using test::Tri;

using test::joined;

std::size_t distinct_count(std::vector<Point> p) {
  std::sort(p.begin(), p.end(), [](const Point& a, const Point& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  return static_cast<std::size_t>(std::unique(p.begin(), p.end()) - p.begin());
}

// The narrow fan of `mwst generate fan`: the apex (0, 0), then points alternating between radius 1
// and radius 1e-3 at steps of 45/(n/2) degrees; x is multiplied by `mirror_x`.
std::vector<Point> fan_points(std::size_t n, double mirror_x) {
  const std::size_t wedges = (n - 2) / 2;
  const double step = 45.0 / static_cast<double>(wedges) * (std::numbers::pi / 180.0);
  std::vector<Point> p{{0.0, 0.0}};
  for (std::size_t k = 0; k <= 2 * wedges; ++k) {
    const double t = static_cast<double>(k) * step, r = k % 2 == 0 ? 1.0 : 1e-3;
    p.push_back({mirror_x * r * std::cos(t), r * std::sin(t)});
  }
  return p;
}

// Triangulates `pts` and runs every check; returns the mesh for further checks.
Mesh check_delaunay(const std::vector<Point>& pts, bool brute_force) {
  DelaunayStats stats;
  Mesh m = delaunay(pts, &stats);
  const auto problems = validate(m, {.delaunay = true});
  EXPECT_TRUE(problems.empty()) << "validate:\n" << joined(problems);
  EXPECT_TRUE(m.points == pts) << "vertex ids must be the input indices, coordinates unchanged";
  EXPECT_EQ(m.input_vertex_count, pts.size());
  test::CheckOptions options;
  options.empty_circles = brute_force;
  const auto result = test::check_triangulation(pts, test::finite_triangles(m), options);
  EXPECT_TRUE(result.problems.empty()) << "independent check:\n" << joined(result.problems);
  if (brute_force && result.distinct_points > 3) {
    EXPECT_GT(result.circle_tests, 0u);
  }
  // Duplicates: each names the first point (smallest index) at its location, which is kept.
  const std::size_t distinct = distinct_count(pts);
  EXPECT_EQ(stats.duplicates, pts.size() - distinct);
  EXPECT_EQ(m.duplicates.size(), pts.size() - distinct);
  std::vector<char> used(pts.size(), 0);
  for (const Tri& t : test::finite_triangles(m))
    for (auto v : t) used[v] = 1;
  std::map<std::pair<double, double>, std::uint32_t> first_at;
  for (std::uint32_t v = 0; v < pts.size(); ++v) first_at.emplace(std::make_pair(pts[v].x, pts[v].y), v);
  std::size_t marked = 0, bad_pairs = 0;
  for (std::size_t v = 0; v < pts.size(); ++v) marked += m.vertex_kind[v] == VertexKind::kDuplicate ? 1 : 0;
  EXPECT_EQ(marked, pts.size() - distinct);
  for (const auto& [dup, kept] : m.duplicates) {
    const bool ok = dup < pts.size() && kept < pts.size() && pts[dup] == pts[kept] &&
                    first_at.at({pts[kept].x, pts[kept].y}) == kept && kept < dup &&
                    m.vertex_kind[dup] == VertexKind::kDuplicate && m.vertex_kind[kept] == VertexKind::kInput &&
                    !used[dup] && used[kept];
    if (!ok && ++bad_pairs <= 5) ADD_FAILURE() << "bad duplicate pair (" << dup << ", " << kept << ")";
  }
  return m;
}

// ---- property tests over point distributions -----------------------------------------------------

struct PointCase {
  std::string name;
  std::function<std::vector<Point>()> make;
  bool brute_force;  // run the O(n · candidates) empty-circle test
};

void PrintTo(const PointCase& c, std::ostream* os) { *os << c.name; }

class DelaunayProperty : public ::testing::TestWithParam<PointCase> {};

TEST_P(DelaunayProperty, ValidAndIndependentlyChecked) {
  const std::vector<Point> pts = GetParam().make();
  SCOPED_TRACE(GetParam().name + " with " + std::to_string(pts.size()) + " points");
  check_delaunay(pts, GetParam().brute_force);
}

std::vector<Point> concat(std::vector<Point> a, const std::vector<Point>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// A disc of lattice points strictly inside the lattice circle of `primes` primes, scaled down.
std::vector<Point> lattice_circle_with_interior(int primes, std::size_t interior, std::uint64_t seed) {
  auto circle = test::cocircular_lattice_points(primes);
  double r = 0;
  for (const auto& p : circle) r = std::max(r, p.x);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-r, r);
  for (std::size_t i = 0; i < interior;) {
    const Point p{std::round(u(rng)), std::round(u(rng))};
    if (p.x * p.x + p.y * p.y < 0.81 * r * r) {
      circle.push_back(p);
      ++i;
    }
  }
  return circle;
}

const PointCase kPointCases[] = {
    {"Uniform300", [] { return test::uniform_points(300, 1); }, true},
    {"Uniform3000", [] { return test::uniform_points(3000, 2, -1.0, 1.0); }, true},
    {"Uniform100k", [] { return test::uniform_points(100000, 3); }, false},
    {"Kuzmin300", [] { return test::kuzmin_points(300, 4); }, true},
    {"Kuzmin3000", [] { return test::kuzmin_points(3000, 5); }, true},
    {"Kuzmin100k", [] { return test::kuzmin_points(100000, 6); }, false},
    {"Grid2x2", [] { return test::grid_points(2, 2, 7); }, true},
    {"Grid3x3", [] { return test::grid_points(3, 3, 7); }, true},
    {"Grid20x20", [] { return test::grid_points(20, 20, 8); }, true},
    {"Grid60x50", [] { return test::grid_points(60, 50, 9); }, true},
    {"Grid300x300", [] { return test::grid_points(300, 300, 10); }, false},
    {"Grid1x50Plus1", [] { return concat(test::grid_points(1, 50, 11), {{5.0, 3.0}}); }, true},
    {"LatticeCircle108", [] { return test::cocircular_lattice_points(3); }, true},
    {"LatticeCircle972", [] { return test::cocircular_lattice_points(5); }, true},
    {"LatticeCircleWithInterior", [] { return lattice_circle_with_interior(4, 400, 12); }, true},
    {"LatticeCircleWithCentre", [] { return concat(test::cocircular_lattice_points(4), {{0.0, 0.0}}); }, true},
    {"CosSinCircle500",
     [] {
       std::vector<Point> p;
       for (int i = 0; i < 500; ++i) p.push_back({std::cos(i * 0.012566370614359173), std::sin(i * 0.012566370614359173)});
       return p;
     },
     true},
    {"ThreeLines300", [] { return test::points_on_lines(300, 3, 13); }, true},
    {"FiveLines3000", [] { return test::points_on_lines(3000, 5, 14); }, true},
    {"TwoLines20k", [] { return test::points_on_lines(20000, 2, 15); }, false},
    {"TinyUniform", [] { return test::scaled(test::uniform_points(500, 16, 1.0, 2.0), 1e-40); }, true},
    {"TinyGrid", [] { return test::scaled_pow2(test::grid_points(25, 25, 17), -140); }, true},
    {"TinyLatticeCircle", [] { return test::scaled_pow2(lattice_circle_with_interior(4, 100, 18), -150); }, true},
    {"TinyKuzmin", [] { return test::scaled(test::kuzmin_points(2000, 19), 1e-40); }, true},
    {"HugeUniform", [] { return test::scaled(test::uniform_points(500, 20, -1.0, 1.0), 1e40); }, true},
    {"HugeGrid", [] { return test::scaled_pow2(test::grid_points(25, 25, 21), 133); }, true},
    {"HugeLines", [] { return test::scaled_pow2(test::points_on_lines(400, 4, 22), 120); }, true},
    {"HugeKuzmin", [] { return test::scaled(test::kuzmin_points(2000, 23), 1e40); }, true},
    {"NearRangeLimits",
     [] {
       auto p = test::scaled(test::uniform_points(300, 24, 0.1, 1.0), 1e50);
       p.push_back({1e-50, 1e-50});
       p.push_back({-1e50, 1e50});
       p.push_back({0.0, -1e50});
       return p;
     },
     true},
    {"Clustered2000", [] { return test::clustered_points(2000, 10, 25); }, true},
    {"Clustered50k", [] { return test::clustered_points(50000, 7, 26); }, false},
    {"UniformWithDuplicates", [] { return test::with_duplicates(test::uniform_points(300, 27), 150, 28); }, true},
    {"GridWithDuplicates", [] { return test::with_duplicates(test::grid_points(12, 12, 29), 300, 30); }, true},
    {"LatticeCircleWithDuplicates", [] { return test::with_duplicates(test::cocircular_lattice_points(3), 60, 31); }, true},
    {"KuzminWithDuplicates", [] { return test::with_duplicates(test::kuzmin_points(20000, 32), 20000, 33); }, false},
    {"LinesWithDuplicates", [] { return test::with_duplicates(test::points_on_lines(500, 3, 34), 500, 35); }, true},
    // At and above 2^15 points the curve order is split into two x-separated halves triangulated
    // on two threads and merged (src/mesh/delaunay.cpp): degenerate inputs across that seam.
    {"ParallelUniform40k", [] { return test::uniform_points(40000, 36); }, false},
    {"ParallelKuzmin40k", [] { return test::kuzmin_points(40000, 37); }, true},
    {"ParallelGrid200x200", [] { return test::grid_points(200, 200, 38); }, true},
    {"ParallelGrid400x90", [] { return test::grid_points(400, 90, 39); }, false},
    {"ParallelLatticeCircle78k", [] { return test::cocircular_lattice_points(9); }, false},
    {"ParallelLatticeCircleWithInterior", [] { return lattice_circle_with_interior(8, 15000, 40); }, false},
    {"ParallelFourLines", [] { return test::points_on_lines(40000, 4, 41); }, false},
    {"ParallelClustered", [] { return test::clustered_points(40000, 6, 42); }, false},
    {"ParallelWithDuplicates", [] { return test::with_duplicates(test::uniform_points(30000, 43), 20000, 44); }, true},
    {"ParallelTinyGrid", [] { return test::scaled_pow2(test::grid_points(190, 190, 45), -150); }, false},
    {"ParallelHugeKuzmin", [] { return test::scaled(test::kuzmin_points(40000, 46), 1e40); }, false},
    // A narrow fan (as `mwst generate fan`): the apex and the tiny inner arc form one half, the
    // cocircular unit arc the other, so the merge deletes almost every triangle of both halves
    // near the seam (the ladder of hull neighbours needed a quadratic number of Lawson flips).
    // Mirrored, the deleting half is R instead of L.
    {"ParallelFan40k", [] { return fan_points(40000, 1.0); }, false},
    {"ParallelFanMirrored40k", [] { return fan_points(40000, -1.0); }, false},
    // Pinched halves: the other half's far outliers wrap around one half so that both common
    // tangents touch the same vertex of it and its whole hull is zipped (these seeds do; before
    // the fix the merge looked up consumed ghosts and corrupted the mesh).
    {"ParallelKuzminPinched40k", [] { return test::kuzmin_points(40000, 5); }, false},
    {"ParallelKuzminPinched100k", [] { return test::kuzmin_points(100000, 2); }, false},
    {"ParallelTwoVerticalLines",  // each half is collinear: the sequential fallback
     [] {
       std::vector<Point> p;
       for (int i = 0; i < 20000; ++i) p.insert(p.end(), {{0.0, double(i)}, {1.0, double(i)}});
       return p;
     },
     true},
    {"ParallelLeftHalfCollinear",
     [] {
       auto p = test::uniform_points(20000, 47, 0.6, 1.0);
       for (int i = 0; i < 20000; ++i) p.push_back({0.0, i / 16384.0});
       return p;
     },
     false},
    {"ParallelDenseColumnAtTheSeam",  // x = 100 is the last column of the left half
     [] {
       auto p = test::grid_points(201, 170, 48);
       for (int k = 0; k < 2 * 169; ++k) p.push_back({100.0, k * 0.5 + 0.25});
       return p;
     },
     true},
    {"ThreeDistinctManyCopies",
     [] {
       std::vector<Point> p;
       for (int i = 0; i < 40; ++i) p.insert(p.end(), {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}});
       return p;
     },
     true},
};

INSTANTIATE_TEST_SUITE_P(Distributions, DelaunayProperty, ::testing::ValuesIn(kPointCases),
                         [](const ::testing::TestParamInfo<PointCase>& param_info) { return param_info.param.name; });

// ---- small exact cases ---------------------------------------------------------------------------

TEST(Delaunay, SingleTriangleIsCounterClockwise) {
  for (const auto& pts : {std::vector<Point>{{0, 0}, {1, 0}, {0, 1}}, std::vector<Point>{{0, 0}, {0, 1}, {1, 0}}}) {
    const Mesh m = check_delaunay(pts, true);
    ASSERT_EQ(test::finite_triangles(m).size(), 1u);
    EXPECT_EQ(m.domain_triangle_count(), 1u);
  }
}

TEST(Delaunay, SquareWithCentreHasFourTriangles) {
  const Mesh m = check_delaunay({{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}}, true);
  const auto tris = test::canonical(test::finite_triangles(m));
  const std::vector<Tri> expected = test::canonical({{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
  EXPECT_EQ(tris, expected);
}

TEST(Delaunay, ThinTriangleFlipsToTheDelaunayDiagonal) {
  // A flat rhombus: the long diagonal 0–1 would leave two obtuse triangles; the short one 2–3 wins.
  const Mesh m = check_delaunay({{0, 0}, {10, 0}, {5, 1}, {5, -1}}, true);
  const auto tris = test::canonical(test::finite_triangles(m));
  const std::vector<Tri> expected = test::canonical({{0, 3, 2}, {3, 1, 2}});
  EXPECT_EQ(tris, expected);
}

TEST(Delaunay, CollinearPointsPlusOneApexFan) {
  // n − 1 collinear points and one apex: the only triangulation is the fan.
  std::vector<Point> pts;
  for (int i = 0; i < 30; ++i) pts.push_back({double(i), 0.0});
  pts.push_back({7.5, 1e-3});
  const Mesh m = check_delaunay(pts, true);
  EXPECT_EQ(test::finite_triangles(m).size(), 29u);
}

TEST(Delaunay, FirstPointsCollinearThenGeneral) {
  // The first triangle search must skip a long collinear prefix in curve order (all points on one
  // horizontal line except a few far away).
  std::vector<Point> pts;
  for (int i = 0; i < 500; ++i) pts.push_back({i * 0.5, 3.0});
  pts.push_back({100.0, 1000.0});
  pts.push_back({900.0, -1000.0});
  check_delaunay(pts, true);
}

TEST(Delaunay, ExtremeCoordinatesInOneSet) {
  // Magnitudes 1e-50 .. 1e50 mixed: the exact stage must not overflow or underflow.
  check_delaunay({{0, 0}, {1e50, 0}, {0, 1e50}, {1e-50, 1e-50}, {-1e50, -1e-50}, {1e-50, -1e50}, {3e-50, 2e-50}},
                 true);
}

// ---- determinism and permutation invariance ------------------------------------------------------

TEST(Delaunay, DeterministicTriangleArrays) {
  for (const auto& pts : {test::uniform_points(20000, 40), test::grid_points(80, 80, 41),
                          test::uniform_points(60000, 44), test::grid_points(250, 250, 45),
                          test::with_duplicates(test::kuzmin_points(5000, 42), 500, 43),
                          test::cocircular_lattice_points(4)}) {
    const Mesh a = delaunay(pts), b = delaunay(pts);
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    bool same = true;
    for (std::size_t t = 0; t < a.triangles.size() && same; ++t) {
      same = a.triangles[t].v == b.triangles[t].v && a.triangles[t].n == b.triangles[t].n;
    }
    EXPECT_TRUE(same) << "two runs on the same input differ";
    EXPECT_EQ(a.flags, b.flags);
    EXPECT_EQ(a.duplicates, b.duplicates);
  }
}

TEST(Delaunay, TriangleSetInvariantUnderPermutation) {
  // In general position the Delaunay triangulation is unique, so it cannot depend on input order.
  for (const auto& pts : {test::uniform_points(5000, 50), test::kuzmin_points(5000, 51),
                          test::clustered_points(3000, 5, 52), test::kuzmin_points(50000, 54)}) {
    const auto reference = test::canonical(test::finite_triangles(delaunay(pts)));
    std::mt19937_64 rng(53);
    for (int round = 0; round < 3; ++round) {
      std::vector<std::uint32_t> perm(pts.size());  // new index i holds old point perm[i]
      std::iota(perm.begin(), perm.end(), 0u);
      std::shuffle(perm.begin(), perm.end(), rng);
      std::vector<Point> shuffled(pts.size());
      for (std::size_t i = 0; i < pts.size(); ++i) shuffled[i] = pts[perm[i]];
      auto tris = test::finite_triangles(delaunay(shuffled));
      for (auto& t : tris)
        for (auto& v : t) v = perm[v];
      EXPECT_EQ(test::canonical(tris), reference) << "round " << round;
    }
  }
}

// ---- input errors ----------------------------------------------------------------------------------

// Expects delaunay(pts) to throw an InputError whose message contains every needle.
void expect_input_error(const std::vector<Point>& pts, const std::vector<std::string>& needles) {
  try {
    (void)delaunay(pts);
    ADD_FAILURE() << "no InputError for " << pts.size() << " points";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const auto& needle : needles) {
      EXPECT_NE(what.find(needle), std::string::npos) << "message \"" << what << "\" lacks \"" << needle << "\"";
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

TEST(DelaunayErrors, FewerThanThreeDistinctPoints) {
  expect_input_error({}, {"fewer than three"});
  expect_input_error({{0, 0}}, {"fewer than three"});
  expect_input_error({{0, 0}, {1, 1}}, {"fewer than three"});
  expect_input_error({{0, 0}, {1, 1}, {0, 0}}, {"fewer than three distinct"});
  expect_input_error({{1, 1}, {0, 0}, {1, 1}, {0, 0}, {1, 1}}, {"fewer than three distinct"});
  expect_input_error(std::vector<Point>(100, Point{0.5, 0.25}), {"fewer than three distinct", "coincide"});
}

TEST(DelaunayErrors, AllCollinear) {
  std::vector<Point> line;  // y = 3x − 7 at integers: exactly collinear
  for (int i = 0; i < 100; ++i) line.push_back({double(i), 3.0 * i - 7.0});
  expect_input_error(line, {"collinear"});
  expect_input_error({{0, 0}, {1, 1}, {2, 2}}, {"collinear"});
  expect_input_error({{0, 5}, {0, -3}, {0, 1e10}, {0, 5}}, {"collinear"});
  auto with_dups = test::with_duplicates(line, 100, 60);
  expect_input_error(with_dups, {"collinear"});
  expect_input_error(test::scaled_pow2(line, -160), {"collinear"});
}

TEST(DelaunayErrors, CoordinatesOutOfRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Point> base{{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  struct Bad {
    Point p;
    const char* what;
  };
  for (const Bad& bad : {Bad{{nan, 0}, "NaN x"}, Bad{{0, nan}, "NaN y"}, Bad{{inf, 0}, "Inf"}, Bad{{0, -inf}, "-Inf"},
                         Bad{{1e60, 0}, "1e60"}, Bad{{0, -1e60}, "-1e60"}, Bad{{1e-60, 0.5}, "1e-60"},
                         Bad{{0.5, -1e-60}, "-1e-60"}, Bad{{1.0000001e50, 1}, "just above 1e50"},
                         Bad{{9.9e-51, 1}, "just below 1e-50"}}) {
    SCOPED_TRACE(bad.what);
    auto pts = base;
    pts.insert(pts.begin() + 2, bad.p);  // the bad point is point 3 (1-based)
    expect_input_error(pts, {"point 3", "outside the supported range"});
  }
  // The range limits themselves are accepted.
  check_delaunay({{0, 0}, {1e50, 0}, {0, -1e50}, {1e-50, 1e-50}, {-1e-50, 5}}, true);
}

}  // namespace
}  // namespace mwst
