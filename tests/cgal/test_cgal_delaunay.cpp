// tests/cgal/test_cgal_delaunay.cpp — differential tests of mwst::delaunay and
// mwst::constrained_delaunay against CGAL's Delaunay_triangulation_2 and
// Constrained_Delaunay_triangulation_2 (Exact_predicates_inexact_constructions_kernel), used here
// only as an oracle.
//
// In general position the (constrained) Delaunay triangulation is unique, so both must produce the
// same set of triangles, compared as sorted vertex-index triples. For degenerate inputs (grids,
// cocircular points) any choice among cocircular diagonals is correct: there we require the same
// number of triangles and that every triangle of ours that CGAL lacks has an edge whose flip is a
// cocircular tie (decided exactly with GMP, tests/support/exact_checker.hpp).
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/triangle_files.hpp"
#include "support/exact_checker.hpp"
#include "support/generators.hpp"

namespace mwst {
namespace {

namespace fs = std::filesystem;
using test::Tri;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using DtTds = CGAL::Triangulation_data_structure_2<Vb>;
using CgalDt = CGAL::Delaunay_triangulation_2<K, DtTds>;
using CVb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using CFb = CGAL::Constrained_triangulation_face_base_2<K>;
using CdtTds = CGAL::Triangulation_data_structure_2<CVb, CFb>;
using CgalCdt = CGAL::Constrained_Delaunay_triangulation_2<K, CdtTds, CGAL::Exact_predicates_tag>;

std::vector<Tri> cgal_delaunay(const std::vector<Point>& pts) {
  std::vector<std::pair<K::Point_2, std::uint32_t>> input;
  for (std::uint32_t i = 0; i < pts.size(); ++i) input.push_back({K::Point_2(pts[i].x, pts[i].y), i});
  CgalDt dt(input.begin(), input.end());
  std::vector<Tri> tris;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    tris.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return tris;
}

std::vector<Tri> cgal_constrained_delaunay(const Pslg& g) {
  std::vector<std::pair<K::Point_2, std::uint32_t>> input;
  for (std::uint32_t i = 0; i < g.points.size(); ++i) input.push_back({K::Point_2(g.points[i].x, g.points[i].y), i});
  CgalCdt cdt;
  cdt.insert(input.begin(), input.end());
  std::vector<CgalCdt::Vertex_handle> handle(g.points.size());
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) handle[v->info()] = v;
  for (const Segment& s : g.segments) cdt.insert_constraint(handle[s.a], handle[s.b]);
  std::vector<Tri> tris;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    tris.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return tris;
}

// Every triangle of ours missing from CGAL's must have a non-segment edge across which the four
// points are exactly cocircular (so the other diagonal is equally Delaunay).
void expect_same_up_to_cocircular_ties(const Mesh& m, const std::vector<Tri>& theirs, bool general_position) {
  const auto ours = test::canonical(test::finite_triangles(m));
  const auto cgal = test::canonical(theirs);
  EXPECT_EQ(ours.size(), cgal.size());
  if (general_position) {
    EXPECT_TRUE(ours == cgal) << "triangle sets differ on an input in general position";
    return;
  }
  const test::ExactPlane ep(m.points);
  std::size_t differing = 0, unexplained = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.is_dead(t) || m.is_ghost(t)) continue;
    Tri key = m.triangles[t].v;
    std::sort(key.begin(), key.end());
    if (std::binary_search(cgal.begin(), cgal.end(), key)) continue;
    ++differing;
    bool tie = false;
    for (unsigned e = 0; e < 3 && !tie; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId far = m.apex(m.sym(h));
      if (m.is_segment(h) || far == kInfinite) continue;
      const auto& v = m.triangles[t].v;
      tie = ep.incircle(v[0], v[1], v[2], far) == 0;
    }
    if (!tie) ++unexplained;
  }
  EXPECT_EQ(unexplained, 0u) << differing << " triangles differ from CGAL's, " << unexplained
                             << " of them without a cocircular tie";
}

struct Case {
  std::string name;
  std::vector<Point> points;
  bool general_position;
};

TEST(CgalDelaunay, SameTrianglesAsCgal) {
  const std::vector<Case> cases = {
      {"uniform", test::uniform_points(20000, 1), true},
      {"uniform small", test::uniform_points(50, 2), true},
      {"kuzmin", test::kuzmin_points(20000, 3), true},
      {"clustered", test::clustered_points(10000, 8, 4), true},
      {"tiny", test::scaled(test::uniform_points(5000, 5, 1.0, 2.0), 1e-40), true},
      {"huge", test::scaled(test::kuzmin_points(5000, 6), 1e40), true},
      {"grid", test::grid_points(70, 70, 7), false},
      {"lattice circle", test::cocircular_lattice_points(4), false},
      {"lines", test::points_on_lines(3000, 4, 8), false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    // Drop repeated points first: which copy of a duplicate each library keeps is arbitrary, and
    // the comparison is by vertex index.
    std::vector<Point> distinct;
    std::set<std::pair<double, double>> seen;
    for (const Point& p : c.points) {
      if (seen.insert({p.x, p.y}).second) distinct.push_back(p);
    }
    const Mesh m = delaunay(distinct);
    expect_same_up_to_cocircular_ties(m, cgal_delaunay(distinct), c.general_position);
  }
}

TEST(CgalConstrainedDelaunay, SameTrianglesAsCgalOnStarPolygons) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    Pslg g;
    test::add_ring(g, test::star_polygon({0, 0}, 300, 0.5, 1.0, rng), 1);
    test::add_ring(g, test::star_polygon({0.1, 0.0}, 40, 0.1, 0.3, rng), 2);
    std::uniform_real_distribution<double> u(-0.45, 0.45);
    for (int k = 0; k < 500; ++k) g.points.push_back({u(rng), u(rng)});
    g.holes.push_back({0.1, 0.0});
    const Mesh m = constrained_delaunay(g);
    expect_same_up_to_cocircular_ties(m, cgal_constrained_delaunay(g), true);
  }
}

class CgalDataSet : public ::testing::TestWithParam<std::string> {};

TEST_P(CgalDataSet, SameTrianglesAsCgal) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/" + GetParam());
  const Mesh m = constrained_delaunay(g);
  // The synthetic sets (Ellipse, Plate: regular polygons) have exact cocircular 4-tuples.
  expect_same_up_to_cocircular_ties(m, cgal_constrained_delaunay(g), false);
}

std::vector<std::string> data_files() {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(MWST_DATA_DIR)) {
    const auto ext = e.path().extension();
    if (ext == ".poly" || ext == ".node") files.push_back(e.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

INSTANTIATE_TEST_SUITE_P(Data, CgalDataSet, ::testing::ValuesIn(data_files()),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                           std::string s = param_info.param;
                           for (char& ch : s)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return s;
                         });

}  // namespace
}  // namespace mwst
