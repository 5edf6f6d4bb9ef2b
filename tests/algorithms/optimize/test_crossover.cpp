// Tests of the partition crossover (src/algorithms/optimize/crossover.hpp): the child of two triangulations of
// one domain is valid and conforming (independent checker), made only of the parents' triangles,
// never heavier than the first parent, as heavy as it says, and, where every piece could be
// compared, no heavier than the second parent either.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>

#include "mwst/io/report.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/refine.hpp"
#include "algorithms/optimize/crossover.hpp"

#include "support/exact_checker.hpp"
#include "support/generators.hpp"

namespace mwst {
namespace {

using test::check_mesh;

using Corner = std::pair<double, double>;
using CornerTriple = std::array<Corner, 3>;

// In-domain triangles by their corners' coordinates (vertex ids differ between meshes).
std::set<CornerTriple> triangles_by_coordinates(const Mesh& m) {
  std::set<CornerTriple> out;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    CornerTriple c;
    for (unsigned k = 0; k < 3; ++k) c[k] = {m.points[m.triangles[t].v[k]].x, m.points[m.triangles[t].v[k]].y};
    std::sort(c.begin(), c.end());
    out.insert(c);
  }
  return out;
}

Mesh optimised_from(const Pslg& g, double angle, std::size_t trials, std::uint64_t seed) {
  Mesh m = constrained_delaunay(g);
  RefineOptions r;
  r.min_angle_deg = angle;
  refine(m, r);
  OptimizeOptions o;
  o.perturbation_trials = trials;
  o.perturbation_seed = seed;
  optimize(m, o);
  return m;
}

void expect_valid_child(const Pslg& g, const Mesh& a, const Mesh& b, const Mesh& child, const CrossoverStats& stats,
                        const std::string& name) {
  EXPECT_TRUE(validate(child).empty()) << name;
  const CheckResult check = check_mesh(g, child);
  EXPECT_TRUE(check.ok()) << name << ": " << (check.messages.empty() ? "" : check.messages.front());
  for (VertexId v = 0; v < g.points.size(); ++v) EXPECT_EQ(child.points[v], g.points[v]) << name;
  const double wa = measure(a).weight_total, wb = measure(b).weight_total, wc = measure(child).weight_total;
  EXPECT_LE(wc, wa) << name;
  EXPECT_NEAR(wc, wa - stats.gain, 1e-9 * wa) << name;
  EXPECT_NEAR(measure(child).area, measure(a).area, 1e-9 * measure(a).area) << name;
  if (stats.mismatched == 0) {
    EXPECT_LE(wc, wb * (1 + 1e-12)) << name;
  }
  // Every triangle of the child is a triangle of a parent.
  const std::set<CornerTriple> ta = triangles_by_coordinates(a), tb = triangles_by_coordinates(b);
  std::size_t from_b = 0;
  for (const CornerTriple& c : triangles_by_coordinates(child)) {
    const bool in_a = ta.count(c) != 0, in_b = tb.count(c) != 0;
    EXPECT_TRUE(in_a || in_b) << name;
    from_b += !in_a && in_b;
  }
  EXPECT_EQ(from_b > 0, stats.taken > 0) << name;
  EXPECT_LE(stats.taken, stats.pieces) << name;
}

// Two local minima of each data set, from different starts and seeds: the child combines them.
TEST(Crossover, ChildOfTwoLocalMinimaIsValidAndNoHeavier) {
  std::size_t taken = 0;
  for (const char* name : {"Africa.poly", "Plate.poly", "Turkey.poly", "PuertoRico.poly"}) {
    const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    const Mesh a = optimised_from(g, 10.0, 20, 1);
    const Mesh b = optimised_from(g, 20.0, 20, 2);
    for (const bool swap : {false, true}) {
      const Mesh& first = swap ? b : a;
      const Mesh& second = swap ? a : b;
      Mesh child = first;
      const CrossoverStats stats = partition_crossover(child, second);
      expect_valid_child(g, first, second, child, stats, std::string(name) + (swap ? " (b, a)" : " (a, b)"));
      taken += stats.taken;
      // Deterministic.
      Mesh again = first;
      partition_crossover(again, second);
      EXPECT_EQ(again.points, child.points) << name;
      ASSERT_EQ(again.triangles.size(), child.triangles.size()) << name;
      for (std::size_t t = 0; t < child.triangles.size(); ++t) EXPECT_EQ(again.triangles[t].v, child.triangles[t].v);
    }
  }
  EXPECT_GT(taken, 0u);  // the pieces do differ somewhere: the crossover is exercised
}

// A mesh crossed with itself, or with its own copy renumbered by compaction, keeps every triangle.
TEST(Crossover, IdenticalParentsGiveTheSameMesh) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/Africa.poly");
  const Mesh a = optimised_from(g, 10.0, 0, 1);
  Mesh child = a;
  const CrossoverStats stats = partition_crossover(child, a);
  EXPECT_EQ(stats.taken, 0u);
  EXPECT_EQ(stats.gain, 0.0);
  EXPECT_EQ(triangles_by_coordinates(child), triangles_by_coordinates(a));
  EXPECT_EQ(measure(child).weight_total, measure(a).weight_total);
}

// The parent that is lighter everywhere is taken whole: the DT of a point set crossed with its
// flipped (EFH) version becomes the flipped one, piece by piece, and the reverse keeps it.
TEST(Crossover, LighterEverywhereWins) {
  const std::vector<Point> pts = test::uniform_points(300, 17);
  Pslg g;
  g.points = pts;
  const Mesh dt = constrained_delaunay(g);
  Mesh flipped = dt;
  flip_to_local_minimum(flipped);
  ASSERT_LT(measure(flipped).weight_total, measure(dt).weight_total);
  Mesh child = dt;
  const CrossoverStats stats = partition_crossover(child, flipped);
  expect_valid_child(g, dt, flipped, child, stats, "dt x efh");
  EXPECT_EQ(stats.mismatched, 0u);
  EXPECT_EQ(triangles_by_coordinates(child), triangles_by_coordinates(flipped));
  Mesh kept = flipped;
  EXPECT_EQ(partition_crossover(kept, dt).taken, 0u);
  EXPECT_EQ(triangles_by_coordinates(kept), triangles_by_coordinates(flipped));
}

// Steiner points on segments: pieces whose segment is split differently in the two parents are
// left to the first parent; the child stays conforming.
TEST(Crossover, SegmentsSplitDifferentlyStayConforming) {
  Pslg g;
  g.is_poly = true;
  std::mt19937_64 rng(5);
  test::add_ring(g, test::star_polygon({0.0, 0.0}, 40, 0.6, 1.0, rng));
  Mesh a = constrained_delaunay(g), b = constrained_delaunay(g);
  RefineOptions r;
  r.min_angle_deg = 25.0;
  refine(a, r);
  r.min_angle_deg = 30.0;
  r.rule = SteinerRule::kCircumcenter;
  refine(b, r);
  Mesh child = a;
  const CrossoverStats stats = partition_crossover(child, b);
  expect_valid_child(g, a, b, child, stats, "star");
  EXPECT_GT(stats.mismatched + stats.taken, 0u);
}

// The optimiser (method opt) crosses its starts' results: its report's gain is what the mesh weighs
// below its lightest start's result, never negative, with pieces taken when it gains; the mesh is
// valid and conforming. Florida at BRH+EFH's Table 1 setting gains from the crossover (also with
// a short iterated local search).
TEST(Crossover, OptimiserReportsWhatItGains) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/Florida.poly");
  TriangulateOptions o;
  o.method = Method::kOpt;
  o.min_angle_deg = 25.0;
  o.bundle_k = 18;
  o.opt_trials = 30;
  Mesh m;
  const Report r = triangulate(g, o, &m);
  const nlohmann::json j = to_json(r).at("optimize");
  double lightest_start = std::numeric_limits<double>::infinity();
  for (const auto& [name, weight] : j.at("starts").items()) lightest_start = std::min(lightest_start, weight.get<double>());
  const double gain = j.at("crossover_gain").get<double>();
  EXPECT_GT(gain, 0.0);
  EXPECT_GT(j.at("crossover_pieces").get<std::size_t>(), 0u);
  EXPECT_NEAR(measure(m).weight_total, lightest_start - gain, 1e-9 * lightest_start);
  EXPECT_DOUBLE_EQ(j.at("weight_after").get<double>(), r.weight_total);
  EXPECT_TRUE(validate(m).empty());
  const CheckResult check = check_mesh(g, m);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
}

}  // namespace
}  // namespace mwst
