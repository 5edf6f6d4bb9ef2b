// tests/test_fuzz_regressions.cpp — inputs found by fuzz/fuzz_triangulate.cpp (libFuzzer over the
// whole pipeline of mwst/algorithms/pipeline.hpp: DT, DR, BRH, QTR and OPT of Boyacı, Erten, Üngör,
// "Triangulations Loosing Bundles and Weight", and the weight-reducing flips), each kept as a
// regression test. Every case runs triangulate() the way the harness does and demands what the
// harness demands: an InputError, or a mesh that passes validate() (mwst/mesh/mesh.hpp) and the
// independent checker check_triangulation() (mwst/mesh/check.hpp) on the triangles and subsegments
// write_mesh() would write.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/mesh/pslg.hpp"

#include "support/exact_checker.hpp"

namespace {

using namespace mwst;
using mwst::test::check_mesh;

// The mesh passes validate() and the independent checker.
void expect_checked(const Pslg& pslg, const Mesh& mesh) {
  const std::vector<std::string> problems = validate(mesh);
  EXPECT_TRUE(problems.empty()) << problems.front();
  const CheckResult check = check_mesh(pslg, mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
}

// Runs the method; an InputError is an answer, anything else must give a checked mesh.
void expect_valid_or_input_error(const Pslg& pslg, const TriangulateOptions& options) {
  Mesh mesh;
  try {
    triangulate(pslg, options, &mesh);
  } catch (const InputError&) {
    return;
  }
  expect_checked(pslg, mesh);
}

// The first `n` vertices of a data set and the segments among them (what the harness triangulates
// when its input is a Triangle file).
Pslg first_vertices(const std::string& name, std::size_t n) {
  Pslg p = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
  if (p.points.size() > n) {
    p.points.resize(n);
    p.point_markers.resize(n);
    std::vector<Segment> kept;
    std::vector<std::size_t> lines;
    for (std::size_t i = 0; i < p.segments.size(); ++i) {
      if (p.segments[i].a < n && p.segments[i].b < n) {
        kept.push_back(p.segments[i]);
        if (i < p.segment_lines.size()) lines.push_back(p.segment_lines[i]);
      }
    }
    p.segments = std::move(kept);
    p.segment_lines = std::move(lines);
  }
  return p;
}

// Found by fuzz_triangulate on its seed Texas.poly (first 256 vertices, qtr, --convex-hull,
// --flip): QTR splits a boundary segment at rounded Steiner points; EFH then flipped an edge
// from one of them into an edge along the segment, leaving a sliver whose two other sides were
// both subsegments (true angle 180° at the Steiner point). check_triangulation reported
// "subsegment ... lies on no input segment". Fixed in flip.cpp: a flip may not give a triangle
// whose two sides at a segment's Steiner point are both subsegments.
TEST(FuzzRegressions, QtrConvexHullFlipKeepsSegmentsStraight) {
  const Pslg texas = first_vertices("Texas.poly", 256);
  TriangulateOptions options;
  options.method = Method::kQtr;
  options.convex_hull = true;
  options.flip = true;
  expect_valid_or_input_error(texas, options);
}

// Found by fuzz_triangulate (ASan) on its seed Kuzmin2K.poly (first 256 vertices; opt, --flip,
// --strict, --min-angle 5, --max-area 7, --max-steiner 23): heap-use-after-free in
// Optimizer::kick_insert (src/algorithms/optimize/kicks.cpp), which kept references to three vertices of m_.points
// across add_vertex(), whose push_back may reallocate the vector. Fixed by copying the points. In
// a Release build the stale read usually goes unnoticed: this case matters in the sanitizer build.
TEST(FuzzRegressions, OptKickInsertionSurvivesVertexReallocation) {
  const Pslg kuzmin = first_vertices("Kuzmin2K.poly", 256);
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.flip = true;
  options.strict = true;
  options.min_angle_deg = 5.0;
  options.max_area = 7.0;
  options.max_steiner = 23;
  // The fault was in the kicks, which run before the iterated local search: a few trials keep the
  // search exercised at a fraction of its default cost (which is large under the sanitizers).
  options.opt_trials = 20;
  expect_valid_or_input_error(kuzmin, options);
}

// Found by fuzz_triangulate on a mutated Florida.poly; the unmutated first 64 vertices of
// Florida.poly with opt and --convex-hull (default angle) reproduce it. The optimiser's polygon
// retriangulation (minimum weight triangulation of a region or a star) cut an "ear" at a Steiner
// point on a hull segment between its two subsegments: a sliver along the segment, so
// check_triangulation reported "subsegment ... lies on no input segment". Same shape as the EFH bug
// above; fixed in src/algorithms/optimize/region.hpp (spans_straight_angle refuses such a triangulation).
TEST(FuzzRegressions, OptConvexHullKeepsSegmentsStraight) {
  const Pslg florida = first_vertices("Florida.poly", 64);
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.convex_hull = true;
  expect_valid_or_input_error(florida, options);
}

// Found by fuzz_triangulate's records that place a point a few ulps from an earlier one: the
// convex hull of three points, two of them some 50 ulps apart, is a sliver thinner than rounding
// near its long sides. DR (with --convex-hull, so the hull edges are subsegments) split the long hull edges,
// encroached by the far apex, at rounded points up to half an ulp off their lines: the mesh lost
// 11 % of the domain's area and the checker could not tell which long side a split point was on
// ("the triangles cover an area of 1.32e-13, the domain 1.49e-13"; "... lies on the domain
// boundary but its triangle is outside the domain"). Fixed in refine.cpp: no split beside a
// domain triangle thinner than 1e-7 of the coordinates' magnitude (kThinSide).
TEST(FuzzRegressions, DrDoesNotSplitTheSidesOfASliverThinnerThanRounding) {
  const auto ulps_away = [](double x, int steps) {
    for (; steps > 0; --steps) x = std::nextafter(x, 1e300);
    for (; steps < 0; ++steps) x = std::nextafter(x, -1e300);
    return x;
  };
  struct Case {
    Point p;
    int dx, dy;
    double min_angle, max_area;
    bool flip;
  };
  for (const Case& c : {Case{{25.25, 27.25}, 97, 108, 0.0, 5.0, true}, Case{{8.0, -2.0}, 45, 51, 20.0, 0.0, false}}) {
    Pslg pslg;
    pslg.points = {c.p, {ulps_away(c.p.x, c.dx), ulps_away(c.p.y, c.dy)}, {0.0, 0.0}};
    pslg.point_markers.assign(3, 0);
    TriangulateOptions options;
    options.method = Method::kDr;
    options.convex_hull = true;
    options.min_angle_deg = c.min_angle;
    options.max_area = c.max_area;
    options.flip = c.flip;
    options.max_steiner = 32;
    SCOPED_TRACE("sliver at (" + std::to_string(c.p.x) + ", " + std::to_string(c.p.y) + ")");
    expect_valid_or_input_error(pslg, options);
  }
}

// Found by fuzz_triangulate's record that shifts everything by a power of two (QTR, --flip):
// three points whose hull is 27 wide and 5.6e14 long. The mesh was right, but the
// checker could not tell the two long hull sides apart near their common end (-2^49, 0): its
// on-line tolerance, 1e-12 of the coordinates' magnitude, is 563 units there, and it walked from
// one side onto the other ("... lies on the domain boundary but has triangles on both sides").
// Fixed in check.cpp: a piece of the domain's boundary or of a segment is first followed along
// the mesh's own boundary edges and listed subsegments (guided_chain), which name the side.
TEST(FuzzRegressions, CheckerTellsApartTheSidesOfAWedgeThinnerThanItsTolerance) {
  Pslg pslg;
  pslg.points = {{0.0, 12.25}, {2.5, -15.25}, {-std::ldexp(1.0, 49), 0.0}};
  pslg.point_markers.assign(3, 0);
  TriangulateOptions options;
  options.method = Method::kQtr;
  options.flip = true;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  EXPECT_GT(mesh.points.size(), 3u);  // Steiner points on the long sides: the case the checker met
  expect_checked(pslg, mesh);
}

// Found by fuzz_triangulate (a shift by 2^37 of a polygon with crossing segments; OPT), reduced
// to 9 points and 6 segments: long, nearly collinear segments from near (2^20, 2^20) to near
// (2^37, 2^37) cross at rounded points, and where their pieces merge a crossing point is left
// with two collinear subsegments, like any Steiner point on a segment. OPT's segment kicks removed
// it ("crossing point (137440002044.38794, 137440002045.13794) is not a vertex of the mesh"); every
// other method keeps the crossing points. Fixed in src/algorithms/optimize/ and pipeline.cpp: the crossing
// points the CDT adds are fixed vertices of the search (OptimizeOptions::fixed_vertices).
TEST(FuzzRegressions, OptKeepsCrossingPointsOnAStraightChain) {
  Pslg pslg;
  pslg.is_poly = true;
  pslg.points = {{137440002048, 137440002048}, {137440002048.25, 137440002076.5}, {137440002075.75, 137440002076.5},
                 {137440002060, 137440002061.75}, {1048587.25, 1048588.25}, {1048587.5, 1048589},
                 {1048588, 1048588}, {1048576, 1048576}, {1048589.75, 1048584}};
  pslg.point_markers.assign(pslg.points.size(), 0);
  pslg.segments = {{1, 0, 1}, {3, 4, 1}, {6, 5, 1}, {7, 2, 1}, {2, 8, 1}, {7, 2, 1}};
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.opt_trials = 0;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  expect_checked(pslg, mesh);
}

// Found by fuzz_triangulate (every method with --convex-hull): 96 points near the line y = x,
// about 3.5e15 from the origin, with segments among them. The convex hull is a sliver, and the
// part of it the segments do not enclose is below the checker's area tolerance (1e-8 of the
// area), so the checker took the carved domain for the mesh's, and rejected the hull mesh ("edge
// 8-1 ... lies on the domain boundary but has triangles on both sides"). The meshes were right;
// the checker now also tries the other domain when the one the area picked fails. The same shape,
// small: a square whose top side has a notch 1e-10 deep.
TEST(FuzzRegressions, CheckerTellsTheHullFromACarvedDomainASliverSmaller) {
  Pslg pslg;
  pslg.is_poly = true;
  pslg.points = {{0, 0}, {1, 0}, {1, 1}, {0.5, 1 - 1e-10}, {0, 1}};
  pslg.point_markers.assign(pslg.points.size(), 0);
  pslg.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 4, 1}, {4, 0, 1}};
  for (const bool hull : {false, true}) {
    TriangulateOptions options;
    options.method = Method::kDt;
    options.convex_hull = hull;
    Mesh mesh;
    triangulate(pslg, options, &mesh);
    EXPECT_EQ(mesh.domain_triangle_count(), hull ? 4u : 3u);
    const CheckResult check = check_mesh(pslg, mesh);
    EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
    EXPECT_EQ(check.convex_hull, hull);
    // Still strict: without one of its triangles the mesh covers neither domain.
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.in_domain(t)) triangles.push_back(mesh.triangles[t].v);
    }
    for (std::size_t drop = 0; drop < triangles.size(); ++drop) {
      std::vector<std::array<std::uint32_t, 3>> fewer = triangles;
      fewer.erase(fewer.begin() + static_cast<std::ptrdiff_t>(drop));
      // (The hull mesh without its sliver triangle, the one on the notch, is the carved mesh.)
      std::array<std::uint32_t, 3> corners = triangles[drop];
      std::sort(corners.begin(), corners.end());
      const bool sliver = hull && corners == std::array<std::uint32_t, 3>{2, 3, 4};
      EXPECT_EQ(check_triangulation(pslg, mesh.points, fewer, {}).ok(), sliver) << "without triangle " << drop;
    }
  }
}

// Found by fuzz_triangulate (OPT, --convex-hull, circumcenters, 20°, at most 34 Steiner points):
// duplicate points at (0, 0) and at (2^-16, 2^-16) beside a hull edge 16.75 long on x = 0. The
// refinement put a cluster of Steiner points on that edge within 1e-20 of each other near
// y = 2^-16. The checker ordered the vertices along the edge by the rounded parameter t, which
// is the same for all of them, so it saw the boundary chain stall ("the domain boundary edge from
// input vertex 10 (0, 16.75) to input vertex 8 (0, 0) is not a chain of mesh edges") and then
// reported gaps. The mesh was right; the checker now orders them by the edge's dominant coordinate,
// exactly.
TEST(FuzzRegressions, CheckerOrdersAClusterOfPointsOnALongEdge) {
  Pslg pslg;
  pslg.is_poly = true;
  const double e = 1.52587890625e-05;  // 2^-16
  pslg.points = {{27.500015258789062, 25.000015258789062}, {e, e}, {e, e}, {e, e},
                 {30.500015258789062, 12.750015258789062}, {0.2500152587890625, 8.0000152587890625},
                 {e, e}, {0, 0}, {0, 0}, {0, 16.75}, {0, 0}, {11.25, 26.75}, {0, 0}};
  pslg.point_markers.assign(pslg.points.size(), 0);
  pslg.holes = {{-0.1249847412109375, -0.1249847412109375}};
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.flip = true;
  options.convex_hull = true;
  options.steiner = SteinerRule::kCircumcenter;
  options.min_angle_deg = 20.0;
  options.max_steiner = 34;
  options.opt_trials = 1;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  expect_checked(pslg, mesh);
}

// Found by fuzz_triangulate (OPT, --convex-hull, --flip, circumcenters, no angle bound, area 7,
// at most 27 Steiner points): four points about 4.2e14 from the origin, far down the diagonal from
// a cluster of small ones, so the convex hull is a needle. validate() rejected OPT's mesh:
// "convex hull is not convex at vertex 53". A Steiner vertex on a hull edge slid along the line
// through its segment neighbours, which are rounded points off the true hull line, and the hull
// turned reflex there. Fixed in src/algorithms/optimize/moves.cpp (try_slide): a slide on the
// hull keeps the hull convex at the vertex and at its two hull neighbours. (The degenerate
// segments are the harness's; they are ignored.)
TEST(FuzzRegressions, OptKeepsTheConvexHullOfANeedleConvex) {
  Pslg pslg;
  pslg.is_poly = true;
  pslg.points = {
      {-422212465065976, -422212465065953.75}, {-422212465065958.5, -422212465065956.25},
      {-422212465065956.75, -422212465065959.75}, {-422212465065969.5, -422212465065976},
      {25.25, 28.5}, {21, 24.75}, {27, 25.5}, {11.5, 28}, {25.25000000000043, 28.500000000000114},
      {27.75, 28.5}, {18.75, 8}, {27.75, 25.25}, {24.25, 27}, {25.25, 28.5}, {10.5, 24.25},
      {12.25, 13.75}, {13.5, 12.25}, {12, -9.25}, {8, 30.25}, {25.5, 27.75}, {27.25, 24.25},
      {14.5, 8}, {25.250000000000387, 28.500000000000345}, {14.5, 8}, {24.75, 29}, {26.25, 24.25},
      {28.5, 27.5}, {27, 25.5}, {11.5, 11.5}, {12.75, 14.25}, {12, 12.25}, {12, 11.5}, {12.5, 12},
      {14.25, 14}, {-9.25, -9.25}, {26.25, 27.5}, {25.25, 28.5}, {26.25, 27.75}, {17, 28.75},
      {17.5, 29.5}, {8, 29.75}, {29, 28.5}, {0, 0}};
  pslg.point_markers.assign(pslg.points.size(), 0);
  pslg.segments = {
      {1, 2, 2}, {7, 6, 4}, {5, 2, 1}, {7, 2, 2}, {5, 0, 2}, {2, 7, 2}, {11, 2, 2}, {10, 0, 1},
      {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 2}, {9, 9, 4}, {3, 1, 4},
      {15, 2, 1}, {3, 3, 4}, {3, 3, 4}, {9, 5, 4}, {10, 14, 2}, {15, 15, 1}, {15, 15, 4},
      {15, 11, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4},
      {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4}, {9, 9, 4},
      {9, 9, 4}, {9, 1, 4}, {12, 7, 4}};
  pslg.holes = {{24.375, 25.375}, {28.875, 8.125}};
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.flip = true;
  options.convex_hull = true;
  options.steiner = SteinerRule::kCircumcenter;
  options.min_angle_deg = 0.0;
  options.max_area = 7.0;
  options.max_steiner = 27;
  options.opt_trials = 3;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  expect_checked(pslg, mesh);
}

// fuzz_triangulate (QTR, with and without --convex-hull): "the triangles cover an area of
// 22.68, the domain 22.07" — a hole was not carved. Its seed lies exactly on the line of the
// segment from (131084.75, 131085) to (131083.25, 131084.5), whose pieces end at rounded crossing
// points: in the CDT the seed lay beside its piece and carved the face there, while the quadtree
// put a corner exactly on the line at the seed and its carve ignored the seed as lying on a
// segment. Fixed in quadtree/clean_input.cpp (clean_graph): QTR carves from the centroid of the CDT triangle
// each seed carved, and drops the seeds the CDT ignored. (Reduced from the fuzz input by removing
// segments, holes and points while it still failed.)
TEST(FuzzRegressions, QuadtreeCarvesTheHoleTheCdtCarvesFromASeedOnASegmentLine) {
  Pslg pslg;
  pslg.is_poly = true;
  pslg.points = {{131072, 131072},      {131084.75, 131085}, {131072, 131072},     {131086, 131084.75},
                 {131074.5, 131084.5},  {131080, 131084.25}, {131085.75, 131083.5}, {131084.5, 131085.25},
                 {131083.25, 131084.5}, {131083.5, 131085},  {131085.25, 131080}};
  pslg.point_markers.assign(pslg.points.size(), 0);
  pslg.segments = {{3, 2, 1}, {6, 7, 2}, {9, 6, 1}, {4, 10, 2}, {0, 5, 2}, {8, 1, 2}};
  pslg.holes = {{131084.375, 131084.875}};
  for (const bool hull : {false, true}) {
    SCOPED_TRACE(hull);
    TriangulateOptions options;
    options.method = Method::kQtr;
    options.convex_hull = hull;
    Mesh mesh;
    triangulate(pslg, options, &mesh);
    expect_checked(pslg, mesh);
    ConstrainOptions constrain;
    constrain.convex_hull = hull;
    const Mesh cdt = constrained_delaunay(pslg, constrain);
    EXPECT_NEAR(mesh.domain_area(), cdt.domain_area(), 1e-9 * cdt.domain_area());
  }
}

// Found by fuzz_triangulate (a slow unit, every method): 96 segments lying almost on top of each
// other near -2e16, where doubles are 2 or 4 apart. Each rounded crossing point makes new
// crossings, without end. The CDT refuses the input with a one-line InputError; it used to do so
// only after a million crossings (3 s), and now does past 4096 + 4 s², more than 8 times the
// s(s − 1)/2 crossings that s segments can have in exact arithmetic (src/mesh/constrain.cpp,
// crossing_limit()).
TEST(FuzzRegressions, RoundedCrossingsThatBreedCrossingsAreRefused) {
  const Pslg pslg = io::read_input(std::string(MWST_TEST_DATA_DIR) + "/rounding_cascade.poly");
  ASSERT_EQ(pslg.segments.size(), 96u);
  try {
    constrained_delaunay(pslg);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("too many segment crossings to resolve"), std::string::npos) << error.what();
  }
}

}  // namespace
