// tests/io/test_triangle_switches.cpp — parse_triangle_switches (mwst/io/triangle_switches.hpp) against
// the meanings Triangle 1.6 documents for its switches: every supported switch, every no-op, every
// refusal, numbers after switches, and the method the switches choose.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "mwst/io/triangle_switches.hpp"

namespace {

using mwst::Method;
using mwst::SegmentSplitting;
using mwst::TriangleSwitches;
using mwst::parse_triangle_switches;

// The message of the std::invalid_argument that parsing `switches` throws ("" if none).
std::string refusal(const std::string& switches) {
  try {
    (void)parse_triangle_switches(switches);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(TriangleSwitches, NoSwitchesIsTheDelaunayTriangulationOfANodeFile) {
  for (const char* text : {"", "-"}) {
    const TriangleSwitches s = parse_triangle_switches(text);
    EXPECT_EQ(s.options.method, Method::kDt) << text;
    EXPECT_FALSE(s.poly || s.refine || s.quality || s.region_attributes || s.edges || s.neighbours || s.voronoi);
    EXPECT_FALSE(s.zero_based || s.jettison || s.no_boundary_markers || s.no_poly_output || s.no_node_output);
    EXPECT_FALSE(s.no_ele_output || s.no_iteration_numbers || s.ignore_holes || s.quiet || s.help);
    EXPECT_EQ(s.verbosity, 0u);
    EXPECT_FALSE(s.options.convex_hull);
    EXPECT_FALSE(s.options.conforming_delaunay);
    EXPECT_FALSE(s.options.regional_area_limits);
    EXPECT_EQ(s.options.segment_splitting, SegmentSplitting::kAllowed);
    EXPECT_LE(s.options.max_area, 0.0);
    EXPECT_EQ(s.options.max_steiner, mwst::TriangulateOptions{}.max_steiner);
    EXPECT_TRUE(s.ignored.empty());
  }
}

TEST(TriangleSwitches, LeadingDashIsOptional) {
  const TriangleSwitches with = parse_triangle_switches("-pq30");
  const TriangleSwitches without = parse_triangle_switches("pq30");
  EXPECT_TRUE(with.poly && without.poly);
  EXPECT_EQ(with.options.min_angle_deg, 30.0);
  EXPECT_EQ(without.options.min_angle_deg, 30.0);
}

TEST(TriangleSwitches, QualityWithoutAngleIsTwentyDegreesOfRefinement) {
  const TriangleSwitches s = parse_triangle_switches("-pq");
  EXPECT_TRUE(s.poly);
  EXPECT_TRUE(s.quality);
  EXPECT_EQ(s.options.method, Method::kDr);
  EXPECT_EQ(s.options.min_angle_deg, 20.0);
}

TEST(TriangleSwitches, QualityTakesADecimalAngle) {
  EXPECT_EQ(parse_triangle_switches("q32.5").options.min_angle_deg, 32.5);
  EXPECT_EQ(parse_triangle_switches("q.5").options.min_angle_deg, 0.5);
  EXPECT_EQ(parse_triangle_switches("q0").options.min_angle_deg, 0.0);
  // The number ends at the first character that is no digit or '.': the switches go on.
  const TriangleSwitches s = parse_triangle_switches("q25e");
  EXPECT_EQ(s.options.min_angle_deg, 25.0);
  EXPECT_TRUE(s.edges);
  // The last q wins, as in Triangle.
  EXPECT_EQ(parse_triangle_switches("q25q31").options.min_angle_deg, 31.0);
  // An angle no method can use is left to check_options, which names the field (min_angle_deg).
  EXPECT_EQ(parse_triangle_switches("q70").options.min_angle_deg, 70.0);
  EXPECT_THROW(mwst::check_options(parse_triangle_switches("q70").options), std::invalid_argument);
}

TEST(TriangleSwitches, AreaWithANumberBoundsEveryTriangleWithoutAnAngle) {
  const TriangleSwitches s = parse_triangle_switches("pa0.25");
  EXPECT_EQ(s.options.max_area, 0.25);
  EXPECT_FALSE(s.options.regional_area_limits);
  EXPECT_TRUE(s.quality);
  EXPECT_EQ(s.options.method, Method::kDr);
  // Triangle's a alone (no q) refines for area only: no angle bound.
  EXPECT_EQ(s.options.min_angle_deg, 0.0);
  EXPECT_EQ(parse_triangle_switches("a12").options.max_area, 12.0);
}

TEST(TriangleSwitches, AreaAloneReadsRegionalLimitsAndCombinesWithAFixedOne) {
  const TriangleSwitches alone = parse_triangle_switches("pa");
  EXPECT_TRUE(alone.options.regional_area_limits);
  EXPECT_LE(alone.options.max_area, 0.0);
  EXPECT_EQ(alone.options.method, Method::kDr);
  const TriangleSwitches both = parse_triangle_switches("pa0.5aq");
  EXPECT_TRUE(both.options.regional_area_limits);
  EXPECT_EQ(both.options.max_area, 0.5);
  EXPECT_EQ(both.options.min_angle_deg, 20.0);
  // "aA": a alone, then the regional attributes switch.
  const TriangleSwitches with_attributes = parse_triangle_switches("paA");
  EXPECT_TRUE(with_attributes.options.regional_area_limits);
  EXPECT_TRUE(with_attributes.region_attributes);
}

TEST(TriangleSwitches, ConformingDelaunayRefinesWithNoAngleBoundUnlessQualityIsAsked) {
  const TriangleSwitches d = parse_triangle_switches("pD");
  EXPECT_TRUE(d.options.conforming_delaunay);
  EXPECT_EQ(d.options.method, Method::kDr);
  EXPECT_EQ(d.options.min_angle_deg, 0.0);
  const TriangleSwitches dq = parse_triangle_switches("pDq28");
  EXPECT_TRUE(dq.options.conforming_delaunay);
  EXPECT_EQ(dq.options.min_angle_deg, 28.0);
}

TEST(TriangleSwitches, YOnceKeepsBoundarySegmentsWholeTwiceEverySegment) {
  EXPECT_EQ(parse_triangle_switches("pqY").options.segment_splitting, SegmentSplitting::kNotBoundary);
  EXPECT_EQ(parse_triangle_switches("pqYY").options.segment_splitting, SegmentSplitting::kNever);
  EXPECT_EQ(parse_triangle_switches("pYqY").options.segment_splitting, SegmentSplitting::kNever);
  EXPECT_EQ(parse_triangle_switches("pqYYY").options.segment_splitting, SegmentSplitting::kNever);
  // Y alone does not make Triangle refine.
  EXPECT_EQ(parse_triangle_switches("pY").options.method, Method::kDt);
}

TEST(TriangleSwitches, SteinerBudget) {
  EXPECT_EQ(parse_triangle_switches("pqS100").options.max_steiner, 100u);
  EXPECT_EQ(parse_triangle_switches("pqS0").options.max_steiner, 0u);
  // S alone: no Steiner points at all (Triangle's documented meaning).
  EXPECT_EQ(parse_triangle_switches("pqS").options.max_steiner, 0u);
  EXPECT_EQ(parse_triangle_switches("pS12q").options.max_steiner, 12u);
  EXPECT_EQ(parse_triangle_switches("pS12q").options.min_angle_deg, 20.0);
}

TEST(TriangleSwitches, EveryFlagSwitchSetsItsField) {
  struct Case {
    const char* text;
    bool TriangleSwitches::*field;
  };
  const Case cases[] = {
      {"p", &TriangleSwitches::poly},
      {"r", &TriangleSwitches::refine},
      {"A", &TriangleSwitches::region_attributes},
      {"e", &TriangleSwitches::edges},
      {"n", &TriangleSwitches::neighbours},
      {"v", &TriangleSwitches::voronoi},
      {"z", &TriangleSwitches::zero_based},
      {"j", &TriangleSwitches::jettison},
      {"B", &TriangleSwitches::no_boundary_markers},
      {"P", &TriangleSwitches::no_poly_output},
      {"N", &TriangleSwitches::no_node_output},
      {"E", &TriangleSwitches::no_ele_output},
      {"I", &TriangleSwitches::no_iteration_numbers},
      {"O", &TriangleSwitches::ignore_holes},
      {"Q", &TriangleSwitches::quiet},
      {"h", &TriangleSwitches::help},
  };
  for (const Case& c : cases) {
    const TriangleSwitches s = parse_triangle_switches(c.text);
    EXPECT_TRUE(s.*c.field) << c.text;
    // Only that one: every other flag stays off.
    for (const Case& other : cases) {
      if (other.field != c.field) {
        EXPECT_FALSE(s.*other.field) << c.text << " set " << other.text;
      }
    }
    EXPECT_EQ(s.options.method, Method::kDt) << c.text;
  }
  EXPECT_TRUE(parse_triangle_switches("c").options.convex_hull);
  EXPECT_EQ(parse_triangle_switches("V").verbosity, 1u);
  EXPECT_EQ(parse_triangle_switches("VVV").verbosity, 3u);
}

TEST(TriangleSwitches, RefineReadsAnExistingMesh) {
  const TriangleSwitches s = parse_triangle_switches("-rpq25a");
  EXPECT_TRUE(s.refine);
  EXPECT_TRUE(s.poly);
  EXPECT_TRUE(s.options.regional_area_limits);
  EXPECT_EQ(s.options.min_angle_deg, 25.0);
  // r alone re-triangulates without refining.
  EXPECT_EQ(parse_triangle_switches("r").options.method, Method::kDt);
}

TEST(TriangleSwitches, AlgorithmChoicesOfTriangleAreAcceptedAndDoNothing) {
  const TriangleSwitches none = parse_triangle_switches("pq30");
  const TriangleSwitches s = parse_triangle_switches("pq30iFlsCX");
  EXPECT_EQ(s.ignored, "iFlsCX");
  EXPECT_EQ(s.options.method, none.options.method);
  EXPECT_EQ(s.options.min_angle_deg, none.options.min_angle_deg);
  EXPECT_EQ(s.options.convex_hull, none.options.convex_hull);
  EXPECT_EQ(s.options.max_area, none.options.max_area);
  EXPECT_EQ(s.options.segment_splitting, none.options.segment_splitting);
}

TEST(TriangleSwitches, SeveralArgumentsAreOneSet) {
  const TriangleSwitches s = parse_triangle_switches(std::vector<std::string>{"-p", "-q30", "-Y", "Y", "-e"});
  EXPECT_TRUE(s.poly);
  EXPECT_TRUE(s.edges);
  EXPECT_EQ(s.options.min_angle_deg, 30.0);
  EXPECT_EQ(s.options.segment_splitting, SegmentSplitting::kNever);
}

TEST(TriangleSwitches, UnsupportedSwitchesAreRefusedNamingThem) {
  EXPECT_NE(refusal("-pu").find("-u: user-defined"), std::string::npos) << refusal("-pu");
  EXPECT_NE(refusal("-pg").find("-g: Object File Format"), std::string::npos) << refusal("-pg");
  EXPECT_NE(refusal("-po2").find("-o2: second-order"), std::string::npos) << refusal("-po2");
  EXPECT_NE(refusal("-po").find("-o: "), std::string::npos) << refusal("-po");
  for (const char* unknown : {"-pk", "-pW", "-p#", "-p-q", "-p q"}) {
    const std::string message = refusal(unknown);
    EXPECT_NE(message.find("unknown switch"), std::string::npos) << unknown << ": " << message;
  }
  EXPECT_EQ(refusal("-px").substr(0, 3), "-x:");
}

TEST(TriangleSwitches, MalformedNumbersAreRefusedNamingTheSwitch) {
  EXPECT_NE(refusal("-q30.5.2").find("-q: malformed number '30.5.2'"), std::string::npos) << refusal("-q30.5.2");
  EXPECT_NE(refusal("-a..").find("-a: malformed number"), std::string::npos) << refusal("-a..");
  EXPECT_NE(refusal("-a0").find("-a: the maximum area must be greater than zero"), std::string::npos);
  EXPECT_NE(refusal("-a0.0").find("greater than zero"), std::string::npos);
  EXPECT_NE(refusal("-S1.5").find("-S: expected a whole number"), std::string::npos) << refusal("-S1.5");
  EXPECT_NE(refusal("-S99999999999999999999999").find("-S: number"), std::string::npos);
  // A number after a switch that takes none, and a number with no switch.
  EXPECT_NE(refusal("-p5").find("-p: takes no number, found '5'"), std::string::npos) << refusal("-p5");
  EXPECT_NE(refusal("-YY2").find("-Y: takes no number"), std::string::npos) << refusal("-YY2");
  EXPECT_NE(refusal("-30").find("a number '30' with no switch"), std::string::npos) << refusal("-30");
  // "a1e3": a1, e, then a stray 3 (Triangle's numbers have no exponent).
  EXPECT_NE(refusal("-a1e3").find("-e: takes no number, found '3'"), std::string::npos) << refusal("-a1e3");
}

}  // namespace
