// Tests of the optimiser's seeded starts (src/algorithms/optimize/seed_points.hpp): Steiner points at the
// circumcenters of the CDT's junction triangles (no edge on the domain boundary) or at every
// triangle's centroid. The seeded mesh is a valid, conforming constrained Delaunay triangulation
// of the same domain (independent checker), keeps the input vertices, and its new vertices are
// exactly seeds of the rule (recomputed here from the CDT); the optimiser reports both starts and
// is never heavier than either.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <utility>

#include "mwst/io/report.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "algorithms/optimize/seed_points.hpp"

#include "support/exact_checker.hpp"
#include "support/generators.hpp"

namespace mwst {
namespace {

using test::check_mesh;

// The seeds of `which` in the CDT m, recomputed from its triangles: a triangle is a junction if
// each of its three neighbours is an in-domain triangle across a non-segment edge.
std::set<std::pair<double, double>> expected_seeds(const Mesh& m, SeedPoints which) {
  std::set<std::pair<double, double>> out;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    const auto& v = m.triangles[t].v;
    const Point a = m.points[v[0]], b = m.points[v[1]], c = m.points[v[2]];
    if (which == SeedPoints::kCentroids) {
      out.insert({(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0});
      continue;
    }
    bool junction = true;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      junction = junction && !m.is_segment(h) && m.in_domain(triangle_of(m.sym(h)));
    }
    if (junction) {
      const Point p = circumcenter(a, b, c);
      out.insert({p.x, p.y});
    }
  }
  return out;
}

TEST(SeedPoints, SeededMeshIsAConformingCdtWithTheRulesSeeds) {
  for (const char* name : {"Florida.poly", "Superior.poly", "Plate.poly", "Kuzmin2K.node"}) {
    const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    const Mesh cdt = constrained_delaunay(g);
    for (const SeedPoints which : {SeedPoints::kJunctionCircumcenters, SeedPoints::kCentroids}) {
      const std::string label = std::string(name) + (which == SeedPoints::kCentroids ? " centroids" : " junctions");
      Mesh m = cdt;
      const std::size_t inserted = seed_steiner_points(m, which);
      const std::set<std::pair<double, double>> seeds = expected_seeds(cdt, which);
      EXPECT_GT(inserted, 0u) << label;
      EXPECT_LE(inserted, seeds.size()) << label;
      if (which == SeedPoints::kCentroids) {
        EXPECT_GE(inserted, seeds.size() * 9 / 10) << label;
      }
      EXPECT_EQ(m.points.size(), cdt.points.size() + inserted) << label;
      for (VertexId v = 0; v < cdt.points.size(); ++v) EXPECT_EQ(m.points[v], cdt.points[v]) << label;
      for (VertexId v = static_cast<VertexId>(cdt.points.size()); v < m.points.size(); ++v) {
        EXPECT_EQ(m.vertex_kind[v], VertexKind::kSteiner) << label;
        EXPECT_EQ(seeds.count({m.points[v].x, m.points[v].y}), 1u) << label << ": vertex " << v << " is no seed";
      }
      EXPECT_TRUE(validate(m).empty()) << label;
      // Conforming, covering the input's domain and nothing more (mesh boundary on the domain's
      // boundary, area = domain area: no seed was inserted outside), and still constrained Delaunay.
      CheckOptions delaunay;
      delaunay.delaunay = true;
      const CheckResult check = check_mesh(g, m, delaunay);
      EXPECT_TRUE(check.ok()) << label << ": " << (check.messages.empty() ? "" : check.messages.front());
      EXPECT_NEAR(check.area, measure(cdt).area, 1e-9 * measure(cdt).area) << label;
      // Deterministic.
      Mesh again = cdt;
      EXPECT_EQ(seed_steiner_points(again, which), inserted) << label;
      EXPECT_EQ(again.points, m.points) << label;
    }
  }
}

// A square has no junction triangle (each of its two triangles has two boundary edges): nothing
// is seeded there; its two centroids are.
TEST(SeedPoints, SquareHasNoJunction) {
  Pslg g;
  g.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Mesh m = constrained_delaunay(g);
  EXPECT_EQ(seed_steiner_points(m, SeedPoints::kJunctionCircumcenters), 0u);
  EXPECT_EQ(m.points.size(), 4u);
  EXPECT_EQ(seed_steiner_points(m, SeedPoints::kCentroids), 2u);
  EXPECT_TRUE(validate(m).empty());
  EXPECT_TRUE(check_mesh(g, m).ok());
}

// method opt searches from both seeded starts too on a polygon (its report lists them) and is never
// heavier than any start's result; the mesh is valid and conforming. A point set has no seeded starts.
TEST(SeedPoints, OptimiserSearchesFromTheSeededStarts) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/NewYork.poly");
  TriangulateOptions o;
  o.method = Method::kOpt;
  o.min_angle_deg = 5.0;
  o.bundle_k = 24;
  o.opt_trials = 20;
  Mesh m;
  const Report r = triangulate(g, o, &m);
  const nlohmann::json starts = to_json(r).at("optimize").at("starts");
  ASSERT_TRUE(starts.contains("dt+junctions"));
  ASSERT_TRUE(starts.contains("dt+centroids"));
  for (const auto& [name, weight] : starts.items()) {
    EXPECT_LE(r.weight_total, weight.get<double>() * (1 + 1e-12)) << name;
  }
  EXPECT_TRUE(validate(m).empty());
  const CheckResult check = check_mesh(g, m);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
  // A point set (no segments) skips the seeded starts.
  Pslg points;
  points.points = test::uniform_points(200, 3);
  const Report rp = triangulate(points, o);
  EXPECT_FALSE(to_json(rp).at("optimize").at("starts").contains("dt+junctions"));
  EXPECT_FALSE(to_json(rp).at("optimize").at("starts").contains("dt+centroids"));
  EXPECT_TRUE(to_json(rp).at("optimize").at("starts").contains("dt"));
}

}  // namespace
}  // namespace mwst
