// tests/regression/test_regressions.cpp — inputs found by fuzz/fuzz_triangulate.cpp (libFuzzer over
// the whole pipeline of mwst/algorithms/pipeline.hpp: DT, DR, BRH, QTR and OPT of Boyacı, Erten,
// Üngör, "Triangulations Loosing Bundles and Weight", and the weight-reducing flips), each kept as a
// regression test. Every input is a file beside this one, named after what it caught; its header
// comment says which run found it, what went wrong and where it was fixed (README.md here). Every
// case runs triangulate() the way the harness does and demands what the harness demands: an
// InputError, or a mesh that passes validate() (mwst/mesh/mesh.hpp) and the independent checker
// check_triangulation() (mwst/mesh/check.hpp) on the triangles and subsegments write_mesh() would
// write.
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
#include "support/regression_files.hpp"

namespace {

using namespace mwst;
using mwst::test::check_mesh;
using mwst::test::read_regression;

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

// The constrained Delaunay triangulation of the graph, of its carved domain or its convex hull.
Mesh dt_mesh(const Pslg& pslg, bool convex_hull) {
  TriangulateOptions options;
  options.method = Method::kDt;
  options.convex_hull = convex_hull;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  return mesh;
}

// Options as the harness draws them for a run on the convex hull with circumcenters and an area
// bound (the flags of several fuzzed needles).
TriangulateOptions hull_circumcenter_options(Method method, double min_angle, double max_area,
                                             std::size_t max_steiner, std::size_t opt_trials) {
  TriangulateOptions options;
  options.method = method;
  options.flip = true;
  options.convex_hull = true;
  options.steiner = SteinerRule::kCircumcenter;
  options.min_angle_deg = min_angle;
  options.max_area = max_area;
  options.max_steiner = max_steiner;
  options.opt_trials = opt_trials;
  return options;
}

// EFH flipped QTR's split boundary segment into a sliver with two subsegment sides (Texas.poly cut).
TEST(FuzzRegressions, QtrConvexHullFlipKeepsSegmentsStraight) {
  const Pslg texas = read_regression("qtr_hull_flip_sliver_along_segment.poly");
  TriangulateOptions options;
  options.method = Method::kQtr;
  options.convex_hull = true;
  options.flip = true;
  expect_valid_or_input_error(texas, options);
}

// OPT's kick insertion read vertices across a reallocation (ASan; Kuzmin2K.poly cut).
TEST(FuzzRegressions, OptKickInsertionSurvivesVertexReallocation) {
  const Pslg kuzmin = read_regression("opt_kick_insert_use_after_free.poly");
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

// OPT's crossover took a piece whose boundary edge only the other parent marked as a subsegment
// (coarse doubles, where a segment was both an edge and a chain around a flat triangle).
TEST(FuzzRegressions, OptCrossoverKeepsSegmentMarksOnPieceBoundaries) {
  const Pslg pslg = read_regression("opt_crossover_boundary_edge_loses_segment_mark.poly");
  // (2 and 3 trials both took the piece; 0 and 1 ended in other meshes.)
  for (const std::size_t trials : {std::size_t{2}, std::size_t{3}}) {
    TriangulateOptions options;
    options.method = Method::kOpt;
    options.convex_hull = true;
    options.min_angle_deg = 20.0;
    options.max_steiner = 15;
    options.opt_trials = trials;
    Mesh mesh;
    triangulate(pslg, options, &mesh);
    SCOPED_TRACE(trials);
    expect_checked(pslg, mesh);
  }
}

// OPT's polygon MWT cut an ear along a hull segment at its Steiner point (Florida.poly cut).
TEST(FuzzRegressions, OptConvexHullKeepsSegmentsStraight) {
  const Pslg florida = read_regression("opt_hull_mwt_ear_along_segment.poly");
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.convex_hull = true;
  expect_valid_or_input_error(florida, options);
}

// DR split the long sides of a hull sliver thinner than rounding, off their lines (two cases).
TEST(FuzzRegressions, DrDoesNotSplitTheSidesOfASliverThinnerThanRounding) {
  struct Case {
    const char* file;
    double min_angle, max_area;
    bool flip;
  };
  for (const Case& c : {Case{"dr_sliver_thinner_than_rounding_flip.node", 0.0, 5.0, true},
                        Case{"dr_sliver_thinner_than_rounding_20deg.node", 20.0, 0.0, false}}) {
    const Pslg pslg = read_regression(c.file);
    TriangulateOptions options;
    options.method = Method::kDr;
    options.convex_hull = true;
    options.min_angle_deg = c.min_angle;
    options.max_area = c.max_area;
    options.flip = c.flip;
    options.max_steiner = 32;
    SCOPED_TRACE(c.file);
    expect_valid_or_input_error(pslg, options);
  }
}

// The checker walked from one long side of a wedge 5.6e14 long onto the other (QTR's mesh was right).
TEST(FuzzRegressions, CheckerTellsApartTheSidesOfAWedgeThinnerThanItsTolerance) {
  const Pslg pslg = read_regression("check_wedge_thinner_than_tolerance.node");
  TriangulateOptions options;
  options.method = Method::kQtr;
  options.flip = true;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  EXPECT_GT(mesh.points.size(), 3u);  // Steiner points on the long sides: the case the checker met
  expect_checked(pslg, mesh);
}

// OPT's segment kicks removed a crossing point left between two collinear subsegments.
TEST(FuzzRegressions, OptKeepsCrossingPointsOnAStraightChain) {
  const Pslg pslg = read_regression("opt_crossing_point_on_straight_chain.poly");
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.opt_trials = 0;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  expect_checked(pslg, mesh);
}

// The checker took the carved domain for a hull mesh's when they differ by less than its tolerance.
TEST(FuzzRegressions, CheckerTellsTheHullFromACarvedDomainASliverSmaller) {
  const Pslg pslg = read_regression("check_hull_or_carved_domain_notch.poly");
  for (const bool hull : {false, true}) {
    const Mesh mesh = dt_mesh(pslg, hull);
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

// The checker ordered a cluster of Steiner points on a long hull edge by a rounded parameter.
TEST(FuzzRegressions, CheckerOrdersAClusterOfPointsOnALongEdge) {
  const Pslg pslg = read_regression("check_cluster_of_points_on_long_edge.poly");
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

// An OPT slide along a needle-shaped hull's edge turned the hull reflex.
TEST(FuzzRegressions, OptKeepsTheConvexHullOfANeedleConvex) {
  const Pslg pslg = read_regression("opt_slide_makes_needle_hull_reflex.poly");
  const TriangulateOptions options = hull_circumcenter_options(Method::kOpt, 0.0, 7.0, 27, 3);
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  expect_checked(pslg, mesh);
}

// QTR ignored a hole seed lying exactly on a segment's line that the CDT carved from.
TEST(FuzzRegressions, QuadtreeCarvesTheHoleTheCdtCarvesFromASeedOnASegmentLine) {
  const Pslg pslg = read_regression("qtr_hole_seed_on_segment_line.poly");
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

// Rounded crossings that breed crossings without end are refused with one InputError, early
// (src/mesh/constrain.cpp, crossing_limit()).
TEST(FuzzRegressions, RoundedCrossingsThatBreedCrossingsAreRefused) {
  const Pslg pslg = read_regression("cdt_rounded_crossings_breed_crossings.poly");
  ASSERT_EQ(pslg.segments.size(), 96u);
  try {
    constrained_delaunay(pslg);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("too many segment crossings to resolve"), std::string::npos) << error.what();
  }
}

// The checker followed a segment to a vertex 2.1 units off it (within its tolerance) and reported
// the segment running into the sliver beyond, which the segment misses (the CDT was right).
TEST(FuzzRegressions, CheckerReportsASegmentOnlyWhereItMeetsATriangle) {
  const Pslg pslg = read_regression("check_vertex_near_segment_with_sliver_beyond.poly");
  const Mesh mesh = dt_mesh(pslg, false);
  ASSERT_EQ(mesh.domain_triangle_count(), 1u);  // the sliver 5-3-2 closed by crossings resolved at ends
  expect_checked(pslg, mesh);
  // Still strict: with segment 1's far end moved into the sliver's side of vertex 2 (between the
  // sliver's two long sides), the segment does run through the sliver, and that is reported.
  Pslg moved = pslg;
  moved.points[3] = {-703653081972708.0, -703653081972710.0};
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.in_domain(t)) triangles.push_back(mesh.triangles[t].v);
  }
  const CheckResult check = check_triangulation(moved, mesh.points, triangles, {});
  const bool reported = std::any_of(check.messages.begin(), check.messages.end(), [](const std::string& m) {
    return m.find("input segment 1 ") != std::string::npos && m.find("runs into a triangle") != std::string::npos;
  });
  EXPECT_TRUE(reported);
}

// The checker judged a segment only from the furthest vertex its walk reached, though the chain the
// CDT made (through other vertices within the tolerance) ran out of the mesh before it.
TEST(FuzzRegressions, CheckerStopsWhereTheSegmentLeavesTheMesh) {
  const Pslg pslg = read_regression("check_segment_leaves_from_a_vertex_not_furthest.poly");
  for (const bool hull : {false, true}) {
    const Mesh mesh = dt_mesh(pslg, hull);
    EXPECT_EQ(mesh.domain_triangle_count(), hull ? 8u : 3u);
    expect_checked(pslg, mesh);
  }
}

// The CDT resolved a crossing at a segment's end 0.66 away, where doubles are 1.5e-5 apart: its
// snapping tolerance grew with the length of the other segment, 5.8e15.
TEST(FuzzRegressions, CrossingSnapsOnlyWithinTheRoundingWhereItIs) {
  const Pslg pslg = read_regression("cdt_crossing_snapped_by_a_long_segments_length.poly");
  TriangulateOptions options;
  options.method = Method::kDt;
  Mesh mesh;
  triangulate(pslg, options, &mesh);
  // The crossing of segments 1 and 2 is a vertex of its own, within an ulp of both segments.
  ASSERT_EQ(mesh.points.size(), 7u);
  const Point& x = mesh.points[6];
  const Point &a = pslg.points[3], &b = pslg.points[4], &c = pslg.points[5], &d = pslg.points[0];
  const double ulp = 0x1p-52 * 103079215133.0;
  EXPECT_LE(std::fabs((b.x - a.x) * (x.y - a.y) - (b.y - a.y) * (x.x - a.x)) / std::hypot(b.x - a.x, b.y - a.y), 2 * ulp);
  EXPECT_LE(std::fabs((d.x - c.x) * (x.y - c.y) - (d.y - c.y) * (x.x - c.x)) / std::hypot(d.x - c.x, d.y - c.y), 2 * ulp);
  expect_checked(pslg, mesh);
}

// DR's rounded split point of a subsegment 1.1 long, where doubles are 0.5 apart, fell level with
// one end of it: the segment's chain doubled back.
TEST(FuzzRegressions, DrSplitPointsKeepTheChainInOrderAtCoarseDoubles) {
  const Pslg pslg = read_regression("dr_split_chain_doubles_back_at_coarse_doubles.poly");
  for (const bool flip : {false, true}) {
    TriangulateOptions options = hull_circumcenter_options(Method::kDr, 0.0, 7.0, 31, kDefaultOptTrials);
    options.flip = flip;
    Mesh mesh;
    triangulate(pslg, options, &mesh);
    EXPECT_GT(mesh.points.size(), 14u);  // past the split that went wrong (the 7th Steiner point)
    expect_checked(pslg, mesh);
  }
}

// BRH's splits on a needle 3.7e19 long turned its convex hull reflex.
TEST(FuzzRegressions, BrhKeepsTheHullOfAHugeNeedleConvex) {
  const Pslg pslg = read_regression("brh_hull_reflex_after_split_of_huge_needle.node");
  expect_valid_or_input_error(pslg, hull_circumcenter_options(Method::kBrh, 33.0, 7.0, 32, 0));
}

// The checker ordered a segment's chain by the coordinate that changes most; the CDT's chain,
// through vertices within its rounding tolerance on either side of the line, stepped back in it.
TEST(FuzzRegressions, CheckerOrdersAChainAlongTheSegmentItself) {
  const Pslg pslg = read_regression("check_chain_steps_back_in_its_larger_coordinate.poly");
  const Mesh mesh = dt_mesh(pslg, false);
  EXPECT_EQ(mesh.domain_triangle_count(), 3u);
  expect_checked(pslg, mesh);
}

// The CDT resolved a segment's crossings at ends of the crossed subsegments within its rounding,
// where doubles are as coarse as the input's features; the segment's chain then steps sideways.
TEST(FuzzRegressions, CheckerFollowsAChainThatStepsSideways) {
  const Pslg pslg = read_regression("check_chain_steps_sideways_at_coarse_doubles.poly");
  const Mesh mesh = dt_mesh(pslg, false);
  EXPECT_EQ(mesh.domain_triangle_count(), 4u);
  expect_checked(pslg, mesh);
}

// The CDT snapped two crossings a few units apart on a segment, where doubles are 1 apart, to
// vertices in the reverse order along it; the segment's chain steps back by less than rounding.
TEST(FuzzRegressions, CheckerFollowsAChainThatStepsBackWithinRounding) {
  const Pslg pslg = read_regression("check_chain_steps_back_within_snapping_at_coarse_doubles.poly");
  const Mesh mesh = dt_mesh(pslg, true);
  EXPECT_EQ(mesh.domain_triangle_count(), 6u);
  // Segment 2's chain runs through input vertices 3 and 4 (0-based 2 and 3), the second of which
  // lies behind the first along the segment: the case the test is about.
  const Point& a = pslg.points[0];
  const Point& b = pslg.points[6];
  const Point& third = pslg.points[2];
  const Point& fourth = pslg.points[3];
  EXPECT_LT((fourth.x - third.x) * (b.x - a.x) + (fourth.y - third.y) * (b.y - a.y), 0.0);
  expect_checked(pslg, mesh);
  TriangulateOptions dr;
  dr.method = Method::kDr;
  dr.flip = true;
  dr.convex_hull = true;
  dr.min_angle_deg = 0.0;
  dr.max_area = 5.0;
  dr.max_steiner = 12;
  expect_valid_or_input_error(pslg, dr);
}

}  // namespace
