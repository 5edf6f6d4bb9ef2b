// tests/cli/test_cli.cpp — the `mwst` command line (src/cli/) against the contract of docs/DESIGN.md, run as
// a real process (the binary at MWST_BINARY) on files in a fresh temporary directory:
//   - every bad input exits 1 with exactly one stderr line "mwst: FILE[:LINE]: ..." and leaves no
//     output file behind; every bad usage exits 2 and writes nothing;
//   - `triangulate` (dt, dr) on every data set writes .node/.ele(/.poly) that `mwst check` accepts
//     (constrained Delaunay; DR's angle bound except where it reports triangles it cannot fix);
//   - `check` rejects corrupted meshes (clockwise triangle, missing triangle, moved vertex, flipped
//     non-Delaunay edge, missing subsegment);
//   - the JSON report has the documented keys and agrees with the files;
//   - `generate` is deterministic and its point sets triangulate validly;
//   - two runs give byte-identical outputs.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "mwst/geometry/geometry.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "support/cli_sandbox.hpp"
#include "support/regression_files.hpp"

namespace {

using namespace mwst_cli_test;

std::vector<std::string> data_sets() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(MWST_DATA_DIR)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".poly" || ext == ".node") names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Number of segments of a Triangle .poly file (0 for .node).
std::size_t segment_count(const std::string& path) {
  if (fs::path(path).extension() != ".poly") return 0;
  return mwst::io::read_poly(path).segments.size();
}

// ---- stop reasons and weights, checked from the files alone --------------------------------------

// An input angle: segments from `apex` to `a` and to `b` (their far ends).
struct InputAngle {
  mwst::Point apex, a, b;
};

// The input angles under 60°: two segments of a .poly sharing an endpoint, or two consecutive edges
// of the convex hull of a .node point set (refinement makes the hull its boundary).
std::vector<InputAngle> small_input_angles(const mwst::Pslg& input) {
  const auto small = [](const mwst::Point& j, const mwst::Point& a, const mwst::Point& b) {
    const double ux = a.x - j.x, uy = a.y - j.y, vx = b.x - j.x, vy = b.y - j.y;
    const double dot = ux * vx + uy * vy;
    return dot > 0.0 && dot * dot > 0.25 * (ux * ux + uy * uy) * (vx * vx + vy * vy);
  };
  std::vector<InputAngle> angles;
  const auto& p = input.points;
  if (!input.segments.empty()) {
    for (std::size_t i = 0; i < input.segments.size(); ++i) {
      for (std::size_t k = i + 1; k < input.segments.size(); ++k) {
        const auto& s = input.segments[i];
        const auto& t = input.segments[k];
        for (const std::uint32_t j : {s.a, s.b}) {
          if (j != t.a && j != t.b) continue;
          const std::uint32_t a = s.a == j ? s.b : s.a, b = t.a == j ? t.b : t.a;
          if (a != b && small(p[j], p[a], p[b])) angles.push_back({p[j], p[a], p[b]});
        }
      }
    }
    return angles;
  }
  // Andrew's monotone chain (strict corners only).
  std::vector<mwst::Point> sorted = p;
  std::sort(sorted.begin(), sorted.end(), [](const mwst::Point& u, const mwst::Point& w) {
    return u.x < w.x || (u.x == w.x && u.y < w.y);
  });
  sorted.erase(std::unique(sorted.begin(), sorted.end(),
                           [](const mwst::Point& u, const mwst::Point& w) { return u.x == w.x && u.y == w.y; }),
               sorted.end());
  std::vector<mwst::Point> hull(2 * sorted.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    while (k >= 2 && mwst::orient2d(hull[k - 2], hull[k - 1], sorted[i]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  for (std::size_t i = sorted.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && mwst::orient2d(hull[k - 2], hull[k - 1], sorted[i]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  hull.resize(k - 1);
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const mwst::Point& j = hull[i];
    const mwst::Point& a = hull[(i + 1) % hull.size()];
    const mwst::Point& b = hull[(i + hull.size() - 1) % hull.size()];
    if (small(j, a, b)) angles.push_back({j, a, b});
  }
  return angles;
}

double smallest_angle_deg(const mwst::Point& p, const mwst::Point& q, const mwst::Point& r) {
  const auto at = [](const mwst::Point& c, const mwst::Point& u, const mwst::Point& w) {
    const double ux = u.x - c.x, uy = u.y - c.y, wx = w.x - c.x, wy = w.y - c.y;
    return std::atan2(std::fabs(ux * wy - uy * wx), ux * wx + uy * wy) * 180.0 / 3.14159265358979323846;
  };
  return std::min({at(p, q, r), at(q, r, p), at(r, p, q)});
}

// Is the triangle next to the input angle: a corner at its apex, with the triangle inside the
// angle, or a vertex on each of its two segments (within rounding)?
bool next_to(const InputAngle& g, const std::array<mwst::Point, 3>& tri) {
  const auto on = [&](const mwst::Point& v, const mwst::Point& far) {
    const double ux = far.x - g.apex.x, uy = far.y - g.apex.y, vx = v.x - g.apex.x, vy = v.y - g.apex.y;
    const double cross = ux * vy - uy * vx, dot = ux * vx + uy * vy;
    return dot > 0.0 && dot <= (ux * ux + uy * uy) * (1.0 + 1e-9) &&
           std::fabs(cross) <= 1e-9 * std::hypot(ux, uy) * std::hypot(vx, vy);
  };
  bool on_a = false, on_b = false, at_apex = false;
  for (const mwst::Point& v : tri) {
    if (v.x == g.apex.x && v.y == g.apex.y) {
      at_apex = true;
      continue;
    }
    on_a = on_a || on(v, g.a);
    on_b = on_b || on(v, g.b);
  }
  if (on_a && on_b) return true;
  if (!at_apex) return false;
  // Inside the angle: the centroid strictly between the two rays.
  const mwst::Point c{(tri[0].x + tri[1].x + tri[2].x) / 3.0, (tri[0].y + tri[1].y + tri[2].y) / 3.0};
  const int turn = mwst::orient2d(g.apex, g.a, g.b);
  return turn != 0 && mwst::orient2d(g.apex, g.a, c) == turn && mwst::orient2d(g.apex, c, g.b) == turn;
}

// What the files show against a Delaunay refinement's stop reason at `min_angle`: one line per
// contradiction (empty: the reason holds). "bound reached" admits no triangle below the bound;
// "N triangles left near small input angles" admits at most N, each next to an input angle under
// 60°; a budget stop admits anything.
std::vector<std::string> stop_reason_contradictions(const mwst::Pslg& input, const mwst::io::MeshFiles& mesh,
                                                    double min_angle, const std::string& stop_reason) {
  std::size_t admitted = 0;
  static const std::regex left("^([0-9]+) triangles left near small input angles$");
  std::smatch m;
  if (stop_reason == "bound reached") {
    admitted = 0;
  } else if (std::regex_match(stop_reason, m, left)) {
    admitted = std::stoul(m[1]);
  } else if (stop_reason == "steiner budget" || stop_reason == "time budget") {
    return {};
  } else {
    return {"unknown stop reason '" + stop_reason + "'"};
  }
  const std::vector<InputAngle> angles = small_input_angles(input);
  std::vector<std::string> problems;
  std::size_t below = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::array<mwst::Point, 3> tri = {mesh.points[mesh.triangles[t][0]], mesh.points[mesh.triangles[t][1]],
                                            mesh.points[mesh.triangles[t][2]]};
    const double angle = smallest_angle_deg(tri[0], tri[1], tri[2]);
    if (!(angle < min_angle - 1e-9)) continue;
    ++below;
    const bool near = std::any_of(angles.begin(), angles.end(), [&](const InputAngle& g) { return next_to(g, tri); });
    if (!near) {
      problems.push_back("triangle " + std::to_string(t + 1) + " (smallest angle " + std::to_string(angle) +
                         ") is below the bound and next to no input angle under 60 degrees");
    }
  }
  if (below > admitted) {
    problems.push_back(std::to_string(below) + " triangles below the bound, the stop reason '" + stop_reason +
                       "' admits " + std::to_string(admitted));
  }
  return problems;
}

// The weight of the mesh files, independently: every edge once (total), and the boundary part:
// the edges of one triangle only, or listed in PREFIX.poly.
std::pair<double, double> weight_of_files(const mwst::io::MeshFiles& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : mesh.triangles) {
    for (unsigned k = 0; k < 3; ++k) {
      const std::uint32_t u = t[k], w = t[(k + 1) % 3];
      ++uses[{std::min(u, w), std::max(u, w)}];
    }
  }
  std::set<std::pair<std::uint32_t, std::uint32_t>> segments;
  for (const auto& s : mesh.segments) segments.insert({std::min(s.a, s.b), std::max(s.a, s.b)});
  long double total = 0.0L, boundary = 0.0L;
  for (const auto& [edge, count] : uses) {
    const mwst::Point& p = mesh.points[edge.first];
    const mwst::Point& q = mesh.points[edge.second];
    const long double length = std::hypot(static_cast<long double>(p.x) - q.x, static_cast<long double>(p.y) - q.y);
    total += length;
    if (count == 1 || segments.count(edge)) boundary += length;
  }
  return {static_cast<double>(total), static_cast<double>(boundary)};
}

// The checker above can fail: a planted false stop reason. A square with a point near its bottom
// side (a sliver) and a 10° wedge; its Delaunay triangulation claimed "bound reached" or "1
// triangles left near small input angles" at 20° is refused, while the wedge's own skinny
// triangle at its 10° angle is admitted as "left near small input angles".
TEST(Cli, StopReasonCheckerCatchesAPlantedFalseReason) {
  Sandbox box;
  box.put("sliver.poly", "5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.5 0.02\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  const Outcome r = box.run({"triangulate", "sliver.poly", "-o", "s", "-q"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const mwst::Pslg sliver = mwst::io::read_input(box.path("sliver.poly"));
  const mwst::io::MeshFiles mesh = mwst::io::read_mesh(box.path("s"));
  EXPECT_FALSE(stop_reason_contradictions(sliver, mesh, 20.0, "bound reached").empty());
  EXPECT_FALSE(stop_reason_contradictions(sliver, mesh, 20.0, "1 triangles left near small input angles").empty());
  EXPECT_TRUE(stop_reason_contradictions(sliver, mesh, 20.0, "steiner budget").empty());
  // A single triangle with a 10° angle between two segments: next to it, so admitted as left.
  box.put("wedge.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0.98480775301220802 0.17364817766693033\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n");
  ASSERT_EQ(box.run({"triangulate", "wedge.poly", "-o", "w", "-q"}).exit_code, 0);
  const mwst::Pslg wedge = mwst::io::read_input(box.path("wedge.poly"));
  const mwst::io::MeshFiles w = mwst::io::read_mesh(box.path("w"));
  ASSERT_EQ(w.triangles.size(), 1u);
  EXPECT_TRUE(stop_reason_contradictions(wedge, w, 20.0, "1 triangles left near small input angles").empty());
  EXPECT_FALSE(stop_reason_contradictions(wedge, w, 20.0, "bound reached").empty());
}

// ---- 1. bad input: exit 1, one line, no output ------------------------------------------------

struct BadInput {
  const char* name;
  std::map<std::string, std::string> files;  // written before the run
  std::vector<std::string> args;
  std::string where;  // the stderr line must start with "mwst: " + where
};

const std::string kSquare = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n";

std::vector<BadInput> bad_inputs() {
  return {
      {"bad_number", {{"in.node", "4 2 0 0\n1 0 0\n2 1 0\n3 1 x\n4 0 1\n"}}, {"triangulate", "in.node"}, "in.node:4: "},
      {"bad_number_dr", {{"in.node", "4 2 0 0\n1 0 0\n2 1 0\n3 1 x\n4 0 1\n"}},
       {"triangulate", "in.node", "--method", "dr", "--json", "r.json"}, "in.node:4: "},
      {"missing_file", {}, {"triangulate", "nothere.poly"}, "nothere.poly: "},
      {"unknown_extension", {{"in.txt", kSquare}}, {"triangulate", "in.txt"}, "in.txt: "},
      {"too_large", {{"in.node", "3 2 0 0\n1 0 0\n2 1e60 0\n3 0 1\n"}}, {"triangulate", "in.node"}, "in.node:3: "},
      {"too_small", {{"in.node", "3 2 0 0\n1 0 0\n2 1 0\n# comment\n3 0 1e-60\n"}}, {"triangulate", "in.node"},
       "in.node:5: "},
      {"not_finite", {{"in.node", "3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n"}}, {"triangulate", "in.node"}, "in.node:3: "},
      {"truncated", {{"in.node", "5 2 0 0\n1 0 0\n2 1 0\n3 0 1\n"}}, {"triangulate", "in.node"}, "in.node:"},
      {"collinear", {{"in.node", "3 2 0 0\n1 0 0\n2 1 1\n3 2 2\n"}}, {"triangulate", "in.node"}, "in.node: "},
      {"two_points", {{"in.node", "3 2 0 0\n1 0 0\n2 1 1\n3 0 0\n"}}, {"triangulate", "in.node"}, "in.node: "},
      {"missing_vertex", {{"in.poly", kSquare + "1 0\n1 1 7\n0\n"}}, {"triangulate", "in.poly"}, "in.poly:7: "},
      {"crossing_strict", {{"in.poly", kSquare + "2 0\n1 1 3\n2 2 4\n0\n"}}, {"triangulate", "in.poly", "--strict"},
       "in.poly:8: "},
      {"output_dir_missing", {{"in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"}},
       {"triangulate", "in.poly", "-o", "nodir/out"}, "nodir/out.node: "},
      // The mesh files are written first; they must be removed again when the report cannot be.
      {"json_dir_missing", {{"in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"}},
       {"triangulate", "in.poly", "--json", "nodir/r.json"}, "nodir/r.json: "},
      // Warnings (a crossing is split) are not printed when the run fails.
      {"warning_then_failure", {{"in.poly", kSquare + "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n6 2 4\n0\n"}},
       {"triangulate", "in.poly", "--json", "nodir/r.json"}, "nodir/r.json: "},
      {"check_missing_mesh", {{"in.node", kSquare}}, {"check", "in.node", "nomesh"}, "nomesh.node: "},
      {"check_bad_input", {{"in.node", "4 2 0 0\n1 0 0\n2 1 0\n3 1 x\n4 0 1\n"}}, {"check", "in.node", "m"},
       "in.node:4: "},
      {"generate_dir_missing", {}, {"generate", "uniform", "10", "-o", "nodir/p.node"}, "nodir/p.node: "},
      // The error contract audit (issue 9): each bad input is refused with its place.
      {"empty_file", {{"in.node", ""}}, {"triangulate", "in.node"}, "in.node: "},
      {"empty_poly", {{"in.poly", "# only a comment\n"}}, {"triangulate", "in.poly"}, "in.poly:1: "},
      {"truncated_poly", {{"in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n"}}, {"triangulate", "in.poly"}, "in.poly:"},
      {"non_numeric_segment", {{"in.poly", kSquare + "1 0\n1 1 two\n0\n"}}, {"triangulate", "in.poly"},
       "in.poly:7: "},
      {"infinite", {{"in.node", "3 2 0 0\n1 0 0\n2 -inf 0\n3 0 1\n"}}, {"triangulate", "in.node"}, "in.node:3: "},
      {"nan_hole", {{"in.poly", kSquare + "0 0\n1\n1 nan 0.5\n"}}, {"triangulate", "in.poly"}, "in.poly:8: "},
      {"hole_too_large", {{"in.poly", kSquare + "0 0\n1\n1 0.5 1e300\n"}}, {"triangulate", "in.poly"},
       "in.poly:8: "},
      {"wrong_dimension", {{"in.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"}}, {"triangulate", "in.node"},
       "in.node:1: "},
      {"negative_count", {{"in.node", "-3 2 0 0\n1 0 0\n"}}, {"triangulate", "in.node"}, "in.node:1: "},
      // 1e12 vertices must be refused before anything is allocated for them.
      {"absurd_count", {{"in.node", "1000000000000 2 0 0\n1 0 0\n2 1 0\n3 0 1\n"}}, {"triangulate", "in.node"},
       "in.node:1: "},
      {"absurd_segment_count", {{"in.poly", kSquare + "1000000000000 0\n1 1 2\n"}}, {"triangulate", "in.poly"},
       "in.poly:6: "},
      {"index_out_of_range", {{"in.poly", kSquare + "1 0\n1 0 5\n0\n"}}, {"triangulate", "in.poly"},
       "in.poly:7: "},
      // Vertices numbered from 0: a segment naming vertex 4 of four is one-based, hence wrong.
      {"index_wrong_base", {{"in.poly", "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n1 0\n0 3 4\n0\n"}},
       {"triangulate", "in.poly"}, "in.poly:7: "},
      {"first_index_not_0_or_1", {{"in.node", "3 2 0 0\n2 0 0\n3 1 0\n4 0 1\n"}}, {"triangulate", "in.node"},
       "in.node:2: "},
      {"poly_zero_vertices_no_node", {{"in.poly", "0 2 0 0\n0 0\n0\n"}}, {"triangulate", "in.poly"},
       "in.poly:1: "},
      {"fewer_than_three", {{"in.node", "2 2 0 0\n1 0 0\n2 1 1\n"}}, {"triangulate", "in.node"}, "in.node: "},
      {"collinear_poly", {{"in.poly", "3 2 0 0\n1 0 0\n2 1 1\n3 2 2\n2 0\n1 1 2\n2 2 3\n0\n"}},
       {"triangulate", "in.poly", "--method", "dr"}, "in.poly: "},
      {"collinear_qtr", {{"in.node", "4 2 0 0\n1 0 0\n2 1 1\n3 2 2\n4 3 3\n"}},
       {"triangulate", "in.node", "--method", "qtr"}, "in.node: "},
  };
}

class BadInputTest : public testing::TestWithParam<BadInput> {};

TEST_P(BadInputTest, ExitsOneWithOneLocatedLineAndNoOutput) {
  const BadInput& c = GetParam();
  Sandbox box;
  std::set<std::string> before;
  for (const auto& [name, content] : c.files) {
    box.put(name, content);
    before.insert(name);
  }
  const Outcome r = box.run(c.args);
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  const auto lines = r.err_lines();
  ASSERT_EQ(lines.size(), 1u) << describe(r);
  EXPECT_EQ(lines[0].rfind("mwst: " + c.where, 0), 0u) << lines[0];
  EXPECT_GT(lines[0].size(), ("mwst: " + c.where).size()) << "the message says what is wrong";
  EXPECT_EQ(box.entries(), before) << "no output file may be left behind";
}

INSTANTIATE_TEST_SUITE_P(Cli, BadInputTest, testing::ValuesIn(bad_inputs()),
                         [](const testing::TestParamInfo<BadInput>& p) { return p.param.name; });

// Odd but meaningful inputs (the rest of the error contract audit): every method, and the flips,
// must give a mesh `mwst check` accepts — or, where `may_refuse`, exit 1 with one located line and
// no output file.
struct OddInput {
  const char* name;
  std::string file;     // in.node or in.poly
  std::string content;
  bool may_refuse = false;
};

std::vector<OddInput> odd_inputs() {
  const std::string square2 = "4 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n";
  const std::string ring = "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n";
  return {
      {"duplicate_points", "in.node", "6 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 1 0\n6 0 0\n"},
      {"duplicate_poly_vertices", "in.poly",
       "5 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 2 2\n5 0\n1 1 2\n2 2 3\n3 5 4\n4 4 1\n5 3 5\n0\n"},
      {"crossing_segments", "in.poly", square2 + "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n6 2 4\n0\n"},
      // (1,0) lies on segment 1-2, and segment 1-5 lies on top of part of it.
      {"overlapping_segments", "in.poly",
       "5 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 1 0\n5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 5\n0\n"},
      {"vertex_on_segment", "in.poly",
       "6 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 1 0\n6 0 1\n" + ring + "0\n"},
      {"segment_through_vertex", "in.poly",
       "5 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 1 1\n5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n0\n"},
      {"hole_outside_domain", "in.poly", square2 + ring + "1\n1 5 5\n"},
      {"hole_on_segment", "in.poly", square2 + ring + "1\n1 1 0\n"},
      // A boundary that does not close encloses nothing: an empty mesh (with a warning) or a
      // clear refusal are both acceptable, a crash or an invalid mesh are not.
      {"open_polyline", "in.poly", square2 + "3 0\n1 1 2\n2 2 3\n3 3 4\n0\n", true},
      {"open_polyline_with_hull", "in.poly", square2 + "3 0\n1 1 2\n2 2 3\n3 3 4\n0\n", true},
      {"dangling_segment_inside", "in.poly",
       "5 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n5 1 1\n5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 5\n0\n"},
  };
}

// True when `r` is a refusal as the contract wants it: exit 1, one line "mwst: FILE...: what".
::testing::AssertionResult is_clean_refusal(const Outcome& r, const std::string& file) {
  if (r.exit_code != 1) return ::testing::AssertionFailure() << describe(r);
  const auto lines = r.err_lines();
  if (lines.size() != 1 || lines[0].rfind("mwst: " + file, 0) != 0) {
    return ::testing::AssertionFailure() << "not one located line: " << describe(r);
  }
  return ::testing::AssertionSuccess();
}

class OddInputTest : public testing::TestWithParam<OddInput> {};

TEST_P(OddInputTest, EveryMethodGivesACheckedMeshOrACleanRefusal) {
  const OddInput& c = GetParam();
  Sandbox box;
  box.put(c.file, c.content);
  const std::vector<std::vector<std::string>> methods = {
      {"--method", "dt"}, {"--method", "dr"}, {"--method", "brh"}, {"--method", "qtr"},
      {"--method", "opt"}, {"--method", "dt", "--flip"}, {"--method", "dr", "--flip", "--convex-hull"}};
  for (const auto& method : methods) {
    std::vector<std::string> args = {"triangulate", c.file, "-o", "m", "-q"};
    args.insert(args.end(), method.begin(), method.end());
    if (std::string(c.name) == "open_polyline_with_hull") args.push_back("--convex-hull");
    SCOPED_TRACE(method[1] + (method.size() > 2 ? " " + method[2] : std::string()));
    const Outcome r = box.run(args);
    if (r.exit_code == 0) {
      EXPECT_TRUE(box.has("m.node") && box.has("m.ele"));
      const Outcome check = box.run({"check", c.file, "m"});
      EXPECT_EQ(check.exit_code, 0) << describe(check);
    } else {
      EXPECT_TRUE(c.may_refuse) << describe(r);
      EXPECT_TRUE(is_clean_refusal(r, c.file));
      EXPECT_EQ(box.entries(), std::set<std::string>{c.file}) << "no output file may be left behind";
    }
    for (const char* ext : {".node", ".ele", ".poly"}) fs::remove(box.dir() / (std::string("m") + ext));
  }
}

INSTANTIATE_TEST_SUITE_P(Cli, OddInputTest, testing::ValuesIn(odd_inputs()),
                         [](const testing::TestParamInfo<OddInput>& p) { return p.param.name; });

// Random bytes, and random byte edits of a valid .poly: a checked mesh or a clean refusal, never a
// crash, an internal error, or an output file left behind after a failure. Fixed seed.
TEST(Cli, RandomBytesGiveACheckedMeshOrACleanRefusal) {
  Sandbox box;
  std::mt19937 rng(20261121);
  const std::string valid = "5 2 0 1\n1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n5 2 2 0\n"
                            "4 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n1\n1 2.5 2.5\n";
  const std::string alphabet = "0123456789 \n.-+eE#xn\t";
  for (int round = 0; round < 40; ++round) {
    std::string text;
    if (round < 10) {  // raw bytes
      const std::size_t n = rng() % 200;
      for (std::size_t i = 0; i < n; ++i) text.push_back(static_cast<char>(rng() & 0xFF));
    } else {  // a few edits of a valid file, mostly with characters a parser cares about
      text = valid;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits; ++e) {
        const std::size_t at = rng() % (text.size() + 1);
        const char ch = (rng() % 4 == 0) ? static_cast<char>(rng() & 0xFF) : alphabet[rng() % alphabet.size()];
        switch (rng() % 3) {
          case 0: text.insert(at, 1, ch); break;
          case 1: if (at < text.size()) text.erase(at, 1); break;
          default: if (at < text.size()) text[at] = ch; break;
        }
      }
    }
    const std::string file = round % 3 == 0 ? "in.node" : "in.poly";
    box.put(file, text);
    const std::string method = std::vector<std::string>{"dt", "dr", "brh", "qtr", "opt"}[round % 5];
    const Outcome r = box.run({"triangulate", file, "-o", "m", "-q", "--method", method, "--max-steiner", "200"});
    SCOPED_TRACE("round " + std::to_string(round) + " " + method + "\n" + text);
    if (r.exit_code == 0) {
      const Outcome check = box.run({"check", file, "m"});
      EXPECT_EQ(check.exit_code, 0) << describe(check);
    } else {
      EXPECT_TRUE(is_clean_refusal(r, file));
      EXPECT_EQ(box.entries(), std::set<std::string>{file}) << "no output file may be left behind";
    }
    for (const auto& e : fs::directory_iterator(box.dir())) fs::remove(e.path());
  }
}

// --time-limit (TriangulateOptions::time_budget_seconds): a refinement or search stopped by it
// still writes a valid mesh, and says why it stopped; opt makes no start after its BRH start once
// the budget has passed. (Nothing here measures time: a budget of a microsecond is exhausted long
// before a refinement of this size finishes, whatever the machine. The area bound makes about
// 1.6e5 triangles of Superior's 82131 square units; 1e-6 would make 1.6e11, now refused up front.)
TEST(Cli, TimeLimitStopsRefinementWithAValidMesh) {
  Sandbox box;
  for (const std::string method : {"dr", "brh", "opt"}) {
    SCOPED_TRACE(method);
    const Outcome r = box.run({"triangulate", data("Superior.poly"), "-o", "t", "-q", "--method", method,
                               "--min-angle", "30", "--max-area", "1", "--time-limit", "1e-6",
                               "--json", "t.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const auto report = nlohmann::json::parse(box.get("t.json"));
    EXPECT_EQ(report.at("stop_reason").get<std::string>(), "time budget");
    EXPECT_EQ(report.at("parameters").at("time_budget").get<double>(), 1e-6);
    if (method == "opt") {
      const auto& starts = report.at("optimize").at("starts");
      EXPECT_EQ(starts.size(), 1u) << starts.dump();
      EXPECT_TRUE(starts.contains("brh+efh")) << starts.dump();
    }
    const Outcome check = box.run({"check", data("Superior.poly"), "t"});
    EXPECT_EQ(check.exit_code, 0) << describe(check);
  }
}

// Issue 32: --time-limit bounds every method that reads it, the flips after it included, on a
// runaway input (points on a circle: every Steiner point inside has all triangles in its star):
// each stops with "time budget", exit code 0, and a mesh the checker accepts. (No timing asserted:
// a microsecond is spent before any method begins.)
TEST(Cli, TimeLimitStopsEveryMethodOnPointsOnACircle) {
  Sandbox box;
  ASSERT_EQ(box.run({"generate", "circle", "3000", "-o", "c.node"}).exit_code, 0);
  for (const std::string method : {"dr", "brh", "qtr", "opt"}) {
    SCOPED_TRACE(method);
    const Outcome r = box.run({"triangulate", "c.node", "-o", "c-" + method, "-q", "--method", method, "--flip",
                               "--time-limit", "1e-6", "--json", "c.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const auto report = nlohmann::json::parse(box.get("c.json"));
    EXPECT_EQ(report.at("stop_reason").get<std::string>(), "time budget");
    const Outcome check = box.run({"check", "c.node", "c-" + method});
    EXPECT_EQ(check.exit_code, 0) << describe(check);
  }
}

// --time-limit counts the reading of the input: the library gets what is left of it, but the
// report gives the limit as the user wrote it (a distant limit, so nothing stops).
TEST(Cli, TimeLimitIsReportedAsGiven) {
  Sandbox box;
  const Outcome r = box.run({"triangulate", data("Superior.poly"), "-o", "t", "-q", "--method", "dr",
                             "--time-limit", "1000", "--json", "t.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const auto report = nlohmann::json::parse(box.get("t.json"));
  EXPECT_EQ(report.at("parameters").at("time_budget").get<double>(), 1000.0);
  EXPECT_NE(report.at("stop_reason").get<std::string>(), "time budget");
}

// --max-steiner with opt bounds every start and search: at most that many Steiner points in the
// mesh written (Plate has no crossing segments, so every Steiner point counts), and valid; opt
// without it uses more.
TEST(Cli, MaxSteinerBoundsOpt) {
  Sandbox box;
  const std::string input = data("Plate.poly");
  const Outcome free = box.run({"triangulate", input, "-o", "f", "-q", "--method", "opt", "--opt-trials", "5",
                                "--json", "f.json"});
  ASSERT_EQ(free.exit_code, 0) << describe(free);
  const auto jf = nlohmann::json::parse(box.get("f.json"));
  for (const int budget : {0, 3}) {
    SCOPED_TRACE(budget);
    ASSERT_GT(jf.at("steiner").get<int>(), budget);
    const Outcome r = box.run({"triangulate", input, "-o", "b", "-q", "--method", "opt", "--opt-trials", "5",
                               "--max-steiner", std::to_string(budget), "--json", "b.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const auto jb = nlohmann::json::parse(box.get("b.json"));
    EXPECT_EQ(jb.at("crossings").get<int>(), 0);
    EXPECT_LE(jb.at("steiner").get<int>(), budget);
    const Outcome check = box.run({"check", input, "b"});
    EXPECT_EQ(check.exit_code, 0) << describe(check);
  }
}

// ---- limits that hold, stop reasons that are true (regression inputs in tests/regression/) --------


// The output files a triangulate run with prefix "u" and report "u.json" may write.
bool wrote_nothing(const Sandbox& box) {
  for (const std::string& name : box.entries()) {
    if (name.rfind("u.", 0) == 0) return false;
  }
  return true;
}

// --max-area 1e-12 on the unit square would make about 2e12 triangles: refused up front by every
// refinement method with exit code 4, one line giving the number, and no output files (it ran
// until 5.5 GB and then said "internal error: out of memory", exit 3).
TEST(Cli, AreaBoundThatCannotFitIsRefusedUpFront) {
  Sandbox box;
  for (const std::string method : {"dr", "brh", "opt"}) {
    SCOPED_TRACE(method);
    const Outcome r = box.run({"triangulate", mwst::test::regression_path("unit_square_area_runaway.poly"), "-o", "u", "--method",
                               method, "--max-area", "1e-12", "--json", "u.json"});
    EXPECT_EQ(r.exit_code, 4) << describe(r);
    ASSERT_EQ(r.err_lines().size(), 1u) << describe(r);
    EXPECT_NE(r.err.find("would make about 2e+12 triangles"), std::string::npos) << describe(r);
    EXPECT_NE(r.err.find("--max-memory"), std::string::npos) << describe(r);
    EXPECT_TRUE(r.out.empty());
    EXPECT_TRUE(wrote_nothing(box));
  }
  // With a budget that holds it, the same request at a larger area bound runs.
  const Outcome ok = box.run({"triangulate", mwst::test::regression_path("unit_square_area_runaway.poly"), "-o", "u", "-q",
                              "--method", "dr", "--max-area", "1e-3", "--max-memory", "1G"});
  EXPECT_EQ(ok.exit_code, 0) << describe(ok);
}

// A run that passes the estimate but needs more than --max-memory: 1e-5 on the unit square (about
// 1.5e5 triangles, some 20 MB of mesh, more of address space) under a budget of 40 MB stops with
// std::bad_alloc at the address-space limit: exit code 4, one line saying what ran out and what to
// try, no output files.
TEST(Cli, MaxMemoryStopsARunawayWithExitCode4AndNoFiles) {
  if (!kAddressLimit) GTEST_SKIP() << "sanitizer build: no address-space limit";
  Sandbox box;
  const Outcome r = box.run({"triangulate", mwst::test::regression_path("unit_square_area_runaway.poly"), "-o", "u", "--method", "dr",
                             "--max-area", "1e-5", "--max-memory", "40M", "--json", "u.json"});
  EXPECT_EQ(r.exit_code, 4) << describe(r);
  ASSERT_EQ(r.err_lines().size(), 1u) << describe(r);
  EXPECT_EQ(r.err.rfind("mwst: out of memory: ", 0), 0u) << describe(r);
  EXPECT_NE(r.err.find("--max-memory"), std::string::npos) << describe(r);
  EXPECT_TRUE(r.out.empty());
  EXPECT_TRUE(wrote_nothing(box)) << "left behind after running out of memory";
}

TEST(Cli, MaxMemoryValues) {
  Sandbox box;
  box.put("in.node", kSquare);
  for (const std::string bad : {"0", "-5M", "12X", "M", "1e400", "nan"}) {
    const Outcome r = box.run({"triangulate", "in.node", "--max-memory", bad});
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << describe(r);
    EXPECT_EQ(r.err_lines().size(), 2u) << describe(r);  // the error and the hint to --help
  }
  // 24M: a small input fits in a small budget.
  for (const std::string good : {"512M", "1.5G", "2000000000", "1T", "300000k", "24M"}) {
    const Outcome r = box.run({"triangulate", "in.node", "-o", "g", "-q", "--max-memory", good});
    EXPECT_EQ(r.exit_code, 0) << good << "\n" << describe(r);
  }
}

// Stop reasons checked against the final mesh (issue: each was false).
TEST(Cli, StopReasonsAreTrue) {
  Sandbox box;
  {  // A square of side 1e-50 and --max-area 1e-103: no Steiner point can be placed (the
     // coordinates fall below 1e-50); it said "2 triangles left near small input angles" of a
     // square whose angles are 45° and 90°.
    const Outcome r = box.run({"triangulate", mwst::test::regression_path("tiny_square_area_underflow.poly"), "-o", "u", "--method",
                               "dr", "--max-area", "1e-103", "--json", "u.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const auto j = nlohmann::json::parse(box.get("u.json"));
    EXPECT_GT(j.at("max_triangle_area").get<double>(), 1e-103);
    EXPECT_EQ(j.at("stop_reason").get<std::string>(), "2 triangles left outside the bounds");
    EXPECT_NE(r.err.find("mwst: warning: 2 triangles do not meet the bounds"), std::string::npos) << describe(r);
  }
  {  // opt with an area bound its steiner budget cannot reach: "steiner budget", not "local minimum".
    const Outcome r = box.run({"triangulate", mwst::test::regression_path("unit_square_area_runaway.poly"), "-o", "u", "-q",
                               "--method", "opt", "--max-area", "1e-2", "--max-steiner", "10", "--opt-trials", "0",
                               "--json", "u.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const auto j = nlohmann::json::parse(box.get("u.json"));
    EXPECT_GT(j.at("max_triangle_area").get<double>(), 1e-2);
    EXPECT_EQ(j.at("stop_reason").get<std::string>(), "steiner budget");
  }
  {  // dr --flip: the flips leave triangles below 20°; it said "bound reached". The number is the
     // files' count (smallest angle below 20° by atan2; none of them lies at an input angle
     // under 60°... or if one does, it is still below the bound after the flips).
    const std::string input = mwst::test::regression_path("dr_flip_angles_below_bound.poly");
    const Outcome r = box.run({"triangulate", input, "-o", "u", "-q", "--method", "dr", "--flip", "--json", "u.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const std::string stop = nlohmann::json::parse(box.get("u.json")).at("stop_reason").get<std::string>();
    const mwst::io::MeshFiles mesh = mwst::io::read_mesh(box.path("u"));
    std::size_t below = 0;
    for (const auto& t : mesh.triangles) {
      below += smallest_angle_deg(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]) < 20.0 - 1e-9;
    }
    ASSERT_GT(below, 0u);
    EXPECT_EQ(stop, std::to_string(below) + " triangles below the angle bound after the flips");
    EXPECT_FALSE(stop_reason_contradictions(mwst::io::read_input(input), mesh, 20.0, "bound reached").empty());
    // Without the flips the same input reaches the bound, as the files show.
    const Outcome plain = box.run({"triangulate", input, "-o", "p", "-q", "--method", "dr", "--json", "p.json"});
    ASSERT_EQ(plain.exit_code, 0) << describe(plain);
    const std::string plain_stop = nlohmann::json::parse(box.get("p.json")).at("stop_reason").get<std::string>();
    const auto problems =
        stop_reason_contradictions(mwst::io::read_input(input), mwst::io::read_mesh(box.path("p")), 20.0, plain_stop);
    EXPECT_TRUE(problems.empty()) << plain_stop << "\n" << problems.front();
  }
}

// --bundle within --time-limit: past the budget the bundle number is not computed (it grows
// quadratically on points on a circle) and a warning says so; the stop reason is the budget's.
TEST(Cli, TimeLimitBoundsTheBundleNumber) {
  Sandbox box;
  const Outcome r = box.run({"triangulate", data("Superior.poly"), "-o", "u", "--method", "dr", "--bundle",
                             "--max-area", "1", "--time-limit", "1e-6", "--json", "u.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const auto j = nlohmann::json::parse(box.get("u.json"));
  EXPECT_EQ(j.at("stop_reason").get<std::string>(), "time budget");
  EXPECT_FALSE(j.contains("bundle_number"));
  EXPECT_NE(r.err.find("the bundle number was not computed: the time budget (--time-limit) ran out"),
            std::string::npos)
      << describe(r);
  EXPECT_EQ(box.run({"check", data("Superior.poly"), "u"}).exit_code, 0);
}

// The progress line is for terminals only: a run of more than 2 s whose stderr is a file writes no
// progress (no carriage return), with or without --quiet.
TEST(Cli, NoProgressLineWhenStderrIsNotATerminal) {
  Sandbox box;
  const Outcome r = box.run({"triangulate", data("Superior.poly"), "-o", "u", "--method", "opt", "--time-limit", "2.5"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << describe(r);
  EXPECT_EQ(r.err.find("mwst: opt:"), std::string::npos) << describe(r);
}

// --exact-polish (opt): accepted, reported, valid, and never heavier than opt without it.
TEST(Cli, ExactPolishIsReportedValidAndNeverHeavier) {
  Sandbox box;
  const std::string input = data("Airliner.poly");
  const Outcome plain = box.run({"triangulate", input, "-o", "p", "-q", "--method", "opt", "--json", "p.json"});
  ASSERT_EQ(plain.exit_code, 0) << describe(plain);
  const Outcome polished = box.run({"triangulate", input, "-o", "q", "-q", "--method", "opt", "--exact-polish",
                                    "--json", "q.json"});
  ASSERT_EQ(polished.exit_code, 0) << describe(polished);
  const auto jp = nlohmann::json::parse(box.get("p.json"));
  const auto jq = nlohmann::json::parse(box.get("q.json"));
  EXPECT_FALSE(jp.at("optimize").contains("exact_polish_tries"));
  EXPECT_TRUE(jq.at("optimize").contains("exact_polish_tries"));
  EXPECT_LE(jq.at("weight_total").get<double>(), jp.at("weight_total").get<double>());
  const Outcome check = box.run({"check", input, "q"});
  EXPECT_EQ(check.exit_code, 0) << describe(check);
}

// --opt-trials bounds the iterated local search: its kept trials never exceed the budget, 0 turns
// it off, the budget is echoed in the report, and the mesh is valid either way.
TEST(Cli, OptTrialsBoundTheSearch) {
  Sandbox box;
  const std::string input = data("Africa.poly");
  for (const std::size_t trials : {std::size_t{0}, std::size_t{30}}) {
    SCOPED_TRACE(trials);
    const Outcome r = box.run({"triangulate", input, "-o", "t", "-q", "--method", "opt", "--opt-trials",
                               std::to_string(trials), "--json", "t.json"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    const auto j = nlohmann::json::parse(box.get("t.json"));
    EXPECT_EQ(j.at("parameters").at("opt_trials").get<std::size_t>(), trials);
    EXPECT_LE(j.at("optimize").at("perturbations").get<std::size_t>(), trials);
    const Outcome check = box.run({"check", input, "t"});
    EXPECT_EQ(check.exit_code, 0) << describe(check);
  }
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  for (const std::string bad : {"-1", "abc", "1.5", ""}) {
    const Outcome r = box.run({"triangulate", "in.poly", "-o", "bad", "--method", "opt", "--opt-trials", bad});
    EXPECT_EQ(r.exit_code, 2) << "'" << bad << "'\n" << describe(r);
    EXPECT_FALSE(box.has("bad.node")) << bad;
  }
}

TEST(Cli, BadTimeLimitIsAUsageError) {
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  for (const std::string bad : {"-1", "0", "nan", "NaN", "inf", "-inf", "abc", "1s", ""}) {
    const Outcome r = box.run({"triangulate", "in.poly", "--method", "dr", "--time-limit", bad});
    // Bad usage (docs/DESIGN.md): exit 2, the problem on the first line (a hint to --help follows).
    EXPECT_EQ(r.exit_code, 2) << "'" << bad << "'\n" << describe(r);
    EXPECT_EQ(r.err.rfind("mwst: --time-limit: ", 0), 0u) << describe(r);
    EXPECT_EQ(box.entries(), std::set<std::string>{"in.poly"}) << bad;
  }
  EXPECT_NE(box.run({"triangulate", "--help"}).out.find("--time-limit"), std::string::npos);
}

// A bad number is named in one short line (no option's message may print a range bound in full:
// CLI11's own non-negative check printed DBL_MAX in 309 digits).
TEST(Cli, BadNumbersAreNamedInOneShortLine) {
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"triangulate", "in.poly", "--max-steiner", "-1"},
       "mwst: --max-steiner: must be a whole number >= 0, found '-1'"},
      {{"triangulate", "in.poly", "--max-steiner", "1.5"},
       "mwst: --max-steiner: must be a whole number >= 0, found '1.5'"},
      {{"triangulate", "in.poly", "--bundle-k", "+3"}, "mwst: --bundle-k: must be a whole number >= 0, found '+3'"},
      {{"triangulate", "in.poly", "--opt-trials", "99999999999999999999"},
       "mwst: --opt-trials: must be a whole number >= 0, found '99999999999999999999'"},
      {{"triangulate", "in.poly", "--max-area", "0"}, "mwst: --max-area: must be a number > 0, found '0'"},
      {{"triangulate", "in.poly", "--max-area", "inf"}, "mwst: --max-area: must be a number > 0, found 'inf'"},
      {{"triangulate", "in.poly", "--min-angle", "60"}, "mwst: --min-angle: must be a number in [0, 60), found '60'"},
      {{"triangulate", "in.poly", "--time-limit", "nan"}, "mwst: --time-limit: must be a number > 0, found 'nan'"},
      {{"generate", "uniform", "-3", "-o", "p.node"}, "mwst: N: must be a whole number >= 0, found '-3'"},
      {{"generate", "uniform", "3", "--seed", "x", "-o", "p.node"},
       "mwst: --seed: must be a whole number >= 0, found 'x'"},
      {{"experiment", "all", "--opt-trials", "-2"}, "mwst: --opt-trials: must be a whole number >= 0, found '-2'"},
  };
  for (const auto& [args, message] : cases) {
    const Outcome r = box.run(args);
    EXPECT_EQ(r.exit_code, 2) << message << "\n" << describe(r);
    EXPECT_EQ(r.err.substr(0, r.err.find('\n')), message) << describe(r);
    EXPECT_EQ(box.entries(), std::set<std::string>{"in.poly"}) << message;
  }
}

// ---- 2. bad usage: exit 2, nothing written -----------------------------------------------------

TEST(Cli, BadUsageExitsTwoAndWritesNothing) {
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  const std::vector<std::vector<std::string>> cases = {
      {},
      {"frobnicate"},
      {"triangulate"},
      {"triangulate", "in.poly", "--bogus"},
      {"triangulate", "in.poly", "--method", "xyz"},
      {"triangulate", "in.poly", "--min-angle", "60"},
      {"triangulate", "in.poly", "--min-angle", "-1"},
      {"triangulate", "in.poly", "--min-angle", "abc"},
      {"triangulate", "in.poly", "--steiner", "incenter"},
      {"triangulate", "in.poly", "--bundle-k", "2"},
      {"triangulate", "in.poly", "--max-area", "-3"},
      {"triangulate", "in.poly", "--max-steiner", "-1"},
      {"triangulate", "in.poly", "--bundle-k", "-5"},
      {"generate", "uniform", "-3", "-o", "p.node"},
      {"generate", "uniform", "10", "--seed", "-1", "-o", "p.node"},
      {"triangulate", "in.poly", "extra-argument"},
      {"triangulate", "in.poly", "-o", "in"},  // would overwrite in.poly
      {"check", "in.poly"},
      {"check", "in.poly", "m", "--min-angle", "x"},
      {"generate", "uniform", "10"},
      {"generate", "gaussian", "10", "-o", "p.node"},
      {"generate", "uniform", "ten", "-o", "p.node"},
      {"generate", "uniform", "0", "-o", "p.node"},
      {"generate", "uniform", "10", "-o", "p.txt"},
  };
  for (const auto& args : cases) {
    const Outcome r = box.run(args);
    std::string cmd;
    for (const auto& a : args) cmd += a + " ";
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << describe(r);
    EXPECT_EQ(r.err.rfind("mwst: ", 0), 0u) << cmd << "\n" << describe(r);
    EXPECT_EQ(box.entries(), std::set<std::string>{"in.poly"}) << cmd;
  }
}

TEST(Cli, HelpExitsZero) {
  Sandbox box;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--help"}, {"triangulate", "--help"}, {"check", "--help"}, {"generate", "--help"}}) {
    const Outcome r = box.run(args);
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    EXPECT_NE(r.out.find("--"), std::string::npos) << describe(r);
  }
  EXPECT_NE(box.run({"triangulate", "--help"}).out.find("--min-angle"), std::string::npos);
}

// ---- 3. every data set: triangulate, then check --------------------------------------------------

class DataSetTest : public testing::TestWithParam<std::string> {};

// "N triangles left near small input angles" → N (0 for any other stop reason).
std::size_t triangles_left(const std::string& stop_reason) {
  static const std::regex pattern("^([0-9]+) triangles? left");
  std::smatch m;
  return std::regex_search(stop_reason, m, pattern) ? std::stoul(m[1]) : 0;
}

TEST_P(DataSetTest, TriangulationsPassCheck) {
  const std::string input = data(GetParam());
  const bool has_segments = segment_count(input) > 0;
  Sandbox box;
  // DT: constrained Delaunay, checked exactly.
  Outcome r = box.run({"triangulate", input, "-o", "dt", "--quiet", "--json", "dt.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_TRUE(r.out.empty() && r.err.empty()) << "--quiet prints nothing\n" << describe(r);
  EXPECT_TRUE(box.has("dt.node") && box.has("dt.ele"));
  EXPECT_EQ(box.has("dt.poly"), has_segments);
  r = box.run({"check", input, "dt", "--delaunay"});
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  const auto dt = nlohmann::json::parse(box.get("dt.json"));
  EXPECT_EQ(dt["steiner"].get<std::size_t>(), 0u);

  // DR at 20°: constrained Delaunay, and every angle ≥ 20° except in the triangles refinement
  // reports it left near small input angles.
  r = box.run({"triangulate", input, "-o", "dr", "--method", "dr", "--min-angle", "20", "--quiet", "--json", "dr.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  if (has_segments) {
    EXPECT_TRUE(box.has("dr.poly"));  // (refinement may also mark hull edges of a point set)
  }
  r = box.run({"check", input, "dr", "--delaunay"});
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  const auto dr = nlohmann::json::parse(box.get("dr.json"));
  const std::string stop = dr.at("stop_reason").get<std::string>();
  const std::size_t left = triangles_left(stop);
  r = box.run({"check", input, "dr", "--min-angle", "20"});
  if (left == 0) {
    EXPECT_EQ(r.exit_code, 0) << "stop reason: " << stop << "\n" << describe(r);
    EXPECT_GE(dr["min_angle"].get<double>(), 20.0 - 1e-9);
  } else {
    // Every violation is one of the triangles refinement says it left.
    EXPECT_LE(r.err_lines().size(), left) << "stop reason: " << stop << "\n" << describe(r);
  }
  // ... and each of those really lies next to an input angle under 60° (from the files alone).
  const mwst::io::MeshFiles dr_mesh = mwst::io::read_mesh(box.path("dr"));
  const std::vector<std::string> contradictions =
      stop_reason_contradictions(mwst::io::read_input(input), dr_mesh, 20.0, stop);
  EXPECT_TRUE(contradictions.empty()) << "stop reason: " << stop << "\n" << contradictions.front();
  // The report's weights are the files' (every edge once; boundary = edges of one triangle or in
  // the .poly), and interior = total - boundary.
  const auto [total, boundary] = weight_of_files(dr_mesh);
  EXPECT_NEAR(dr["weight_total"].get<double>(), total, 1e-12 * total);
  EXPECT_NEAR(dr["weight_boundary"].get<double>(), boundary, 1e-12 * total);
  EXPECT_NEAR(dr["weight_interior"].get<double>(), total - boundary, 1e-12 * total);
  EXPECT_GT(total - boundary, 0.0);
  EXPECT_NEAR(dr["weight_boundary"].get<double>(), dt["weight_boundary"].get<double>(),
              1e-9 * dt["weight_boundary"].get<double>())
      << "refinement splits boundary segments but keeps their total length";
}

INSTANTIATE_TEST_SUITE_P(Cli, DataSetTest, testing::ValuesIn(data_sets()),
                         [](const testing::TestParamInfo<std::string>& p) {
                           std::string s = p.param;
                           for (char& c : s) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return s;
                         });

// ---- 4. check rejects corrupted meshes ----------------------------------------------------------

struct MeshText {
  std::string header;
  std::vector<std::array<long, 4>> rows;  // index, a, b, c
};

MeshText read_ele(const std::string& text) {
  MeshText m;
  std::istringstream in(text);
  std::getline(in, m.header);
  for (std::array<long, 4> row; in >> row[0] >> row[1] >> row[2] >> row[3];) m.rows.push_back(row);
  return m;
}

std::string write_ele(const MeshText& m, std::size_t count) {
  std::string s = std::to_string(count) + " 3 0\n";
  for (std::size_t i = 0; i < count; ++i) {
    const auto& r = m.rows[i];
    s += std::to_string(i + 1) + " " + std::to_string(r[1]) + " " + std::to_string(r[2]) + " " +
         std::to_string(r[3]) + "\n";
  }
  return s;
}

void copy_mesh(const Sandbox& box, const std::string& from, const std::string& to) {
  for (const char* ext : {".node", ".ele", ".poly"}) {
    if (box.has(from + ext)) box.put(to + ext, box.get(from + ext));
  }
}

TEST(Cli, CheckRejectsCorruptedMeshes) {
  Sandbox box;
  const std::string input = data("Random.poly");
  ASSERT_EQ(box.run({"triangulate", input, "-o", "m", "-q"}).exit_code, 0);
  ASSERT_EQ(box.run({"check", input, "m", "--delaunay"}).exit_code, 0);
  const MeshText ele = read_ele(box.get("m.ele"));
  ASSERT_GT(ele.rows.size(), 10u);

  auto expect_rejected = [&](const std::string& prefix, const std::vector<std::string>& extra, const char* what) {
    std::vector<std::string> args = {"check", input, prefix};
    args.insert(args.end(), extra.begin(), extra.end());
    const Outcome r = box.run(args);
    EXPECT_EQ(r.exit_code, 1) << what << "\n" << describe(r);
    const auto lines = r.err_lines();
    EXPECT_FALSE(lines.empty()) << what;
    for (const auto& line : lines) EXPECT_EQ(line.rfind("mwst: " + prefix + ": ", 0), 0u) << what << ": " << line;
  };

  {  // A clockwise triangle.
    MeshText bad = ele;
    std::swap(bad.rows[3][1], bad.rows[3][2]);
    copy_mesh(box, "m", "cw");
    box.put("cw.ele", write_ele(bad, bad.rows.size()));
    expect_rejected("cw", {}, "clockwise triangle");
  }
  {  // A missing triangle (a gap).
    MeshText bad = ele;
    std::swap(bad.rows[5], bad.rows.back());
    copy_mesh(box, "m", "gap");
    box.put("gap.ele", write_ele(bad, bad.rows.size() - 1));
    expect_rejected("gap", {}, "missing triangle");
  }
  {  // An input vertex moved.
    copy_mesh(box, "m", "moved");
    std::string node = box.get("moved.node");
    const std::size_t line2 = node.find('\n') + 1;             // vertex 1
    const std::size_t line3 = node.find('\n', line2) + 1;     // vertex 2
    std::istringstream row(node.substr(line2, line3 - line2));
    long index;
    double x, y;
    row >> index >> x >> y;
    node.replace(line2, line3 - line2, std::to_string(index) + " " + std::to_string(x * 0.5 + 0.25) + " " +
                                           std::to_string(y * 0.5 + 0.25) + " 0\n");
    box.put("moved.node", node);
    expect_rejected("moved", {}, "moved vertex");
  }
  {  // A subsegment missing from the .poly.
    copy_mesh(box, "m", "noseg");
    std::string poly = box.get("noseg.poly");
    std::istringstream in(poly);
    std::string vertices_line, header;
    std::getline(in, vertices_line);
    std::getline(in, header);
    std::istringstream h(header);
    long n, markers;
    h >> n >> markers;
    std::string rest, line;
    std::getline(in, line);  // drop the first subsegment
    for (long i = 1; i < n; ++i) {
      std::getline(in, line);
      std::istringstream f(line);
      long idx, a, b, mk;
      f >> idx >> a >> b >> mk;
      rest += std::to_string(i) + " " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(mk) + "\n";
    }
    box.put("noseg.poly", vertices_line + "\n" + std::to_string(n - 1) + " " + std::to_string(markers) + "\n" + rest + "0\n");
    expect_rejected("noseg", {}, "missing subsegment");
  }
  {  // A flipped interior edge: still a valid triangulation, but not Delaunay.
    const mwst::io::MeshFiles mesh = mwst::io::read_mesh(box.path("m"));
    std::set<std::pair<std::uint32_t, std::uint32_t>> segments;
    for (const auto& s : mesh.segments) segments.insert({std::min(s.a, s.b), std::max(s.a, s.b)});
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::size_t, std::uint32_t>> directed;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (unsigned k = 0; k < 3; ++k) {
        directed[{mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]}] = {t, mesh.triangles[t][(k + 2) % 3]};
      }
    }
    bool flipped = false;
    for (const auto& [edge, side] : directed) {
      const auto [u, v] = edge;
      const auto other = directed.find({v, u});
      if (u > v || other == directed.end() || segments.count({std::min(u, v), std::max(u, v)})) continue;
      const std::uint32_t c = side.second, d = other->second.second;
      const auto& p = mesh.points;
      // Strictly Delaunay edge in a strictly convex quadrilateral: flipping makes it non-Delaunay.
      if (mwst::incircle(p[u], p[v], p[c], p[d]) >= 0) continue;
      if (mwst::orient2d(p[c], p[d], p[u]) >= 0 || mwst::orient2d(p[c], p[d], p[v]) <= 0) continue;
      auto tris = mesh.triangles;
      tris[side.first] = {c, u, d};  // u→v with apex c, v→u with apex d become c→d / d→c
      tris[other->second.first] = {d, v, c};
      std::string s = std::to_string(tris.size()) + " 3 0\n";
      for (std::size_t t = 0; t < tris.size(); ++t) {
        s += std::to_string(t + 1) + " " + std::to_string(tris[t][0] + 1) + " " + std::to_string(tris[t][1] + 1) +
             " " + std::to_string(tris[t][2] + 1) + "\n";
      }
      copy_mesh(box, "m", "flip");
      box.put("flip.ele", s);
      flipped = true;
      break;
    }
    ASSERT_TRUE(flipped);
    const Outcome ok = box.run({"check", input, "flip"});
    EXPECT_EQ(ok.exit_code, 0) << "a flipped edge is still a valid triangulation\n" << describe(ok);
    expect_rejected("flip", {"--delaunay"}, "flipped edge");
  }
}

// ---- 5. the JSON report ------------------------------------------------------------------------

TEST(Cli, JsonReportHasTheDocumentedKeys) {
  Sandbox box;
  const std::string input = data("Superior.poly");
  const Outcome r = box.run({"triangulate", input, "-o", "m", "--method", "dr", "--min-angle", "15", "--json", "r.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const auto j = nlohmann::json::parse(box.get("r.json"));
  for (const char* key : {"vertices", "triangles", "steiner", "weight_total", "weight_boundary", "weight_interior",
                          "min_angle", "max_angle", "max_triangle_area", "seconds", "stop_reason", "input", "method", "parameters",
                          "duplicates", "crossings", "warnings"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["method"], "dr");
  EXPECT_EQ(j["parameters"]["min_angle"].get<double>(), 15.0);
  EXPECT_TRUE(j["seconds"].is_object());
  EXPECT_TRUE(j["seconds"].contains("total"));
  EXPECT_TRUE(j["seconds"].contains("refine"));
  EXPECT_NEAR(j["weight_total"].get<double>(), j["weight_boundary"].get<double>() + j["weight_interior"].get<double>(),
              1e-9 * j["weight_total"].get<double>());
  const mwst::io::MeshFiles mesh = mwst::io::read_mesh(box.path("m"));
  EXPECT_EQ(j["triangles"].get<std::size_t>(), mesh.triangles.size());
  std::set<std::uint32_t> used;
  for (const auto& t : mesh.triangles) used.insert(t.begin(), t.end());
  EXPECT_EQ(j["vertices"].get<std::size_t>(), used.size());
  EXPECT_GT(j["steiner"].get<std::size_t>(), 0u);
  EXPECT_LE(j["min_angle"].get<double>(), j["max_angle"].get<double>());
  // The human summary names the method and the files written.
  EXPECT_NE(r.out.find("dr"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("m.ele"), std::string::npos) << r.out;

  // --json - prints the report, and nothing else, to stdout.
  const Outcome s = box.run({"triangulate", input, "-o", "m2", "--json", "-"});
  ASSERT_EQ(s.exit_code, 0) << describe(s);
  const auto j2 = nlohmann::json::parse(s.out);
  EXPECT_EQ(j2["method"], "dt");
  EXPECT_FALSE(j2.contains("stop_reason"));
  EXPECT_EQ(j2["steiner"].get<std::size_t>(), 0u);
}

TEST(Cli, WarningsGoToStderrUnlessQuiet) {
  Sandbox box;
  // Two crossing diagonals inside a square, and a duplicate point.
  box.put("in.poly", "5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 1 1\n6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n6 2 4\n0\n");
  Outcome r = box.run({"triangulate", "in.poly", "--json", "r.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const auto lines = r.err_lines();
  ASSERT_EQ(lines.size(), 2u) << describe(r);
  for (const auto& line : lines) EXPECT_EQ(line.rfind("mwst: warning: ", 0), 0u) << line;
  const auto j = nlohmann::json::parse(box.get("r.json"));
  EXPECT_EQ(j["crossings"].get<std::size_t>(), 1u);
  EXPECT_EQ(j["duplicates"].get<std::size_t>(), 1u);
  EXPECT_EQ(j["warnings"].size(), 2u);
  EXPECT_EQ(box.run({"check", "in.poly", "in.1", "--delaunay"}).exit_code, 0);
  r = box.run({"triangulate", "in.poly", "--quiet"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(r.err.empty() && r.out.empty()) << describe(r);
}

// An option the chosen method does not read is named in a warning (and in the report), not
// silently dropped; the options a method reads give none.
TEST(Cli, OptionsTheMethodDoesNotReadAreWarnedAbout) {
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  Outcome r = box.run({"triangulate", "in.poly", "--method", "qtr", "--max-steiner", "10", "--min-angle", "25",
                       "--json", "q.json", "-o", "q"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const std::vector<std::string> expected = {"--min-angle has no effect with --method qtr",
                                             "--max-steiner has no effect with --method qtr"};
  ASSERT_EQ(r.err_lines().size(), 2u) << describe(r);
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(r.err_lines()[i], "mwst: warning: " + expected[i]);
  const auto j = nlohmann::json::parse(box.get("q.json"));
  EXPECT_EQ(j["warnings"], nlohmann::json(expected));
  r = box.run({"triangulate", "in.poly", "--method", "dr", "--bundle-k", "9", "--opt-trials", "2", "-o", "d"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.err_lines(), (std::vector<std::string>{"mwst: warning: --bundle-k has no effect with --method dr",
                                                     "mwst: warning: --opt-trials has no effect with --method dr"}));
  r = box.run({"triangulate", "in.poly", "--method", "dt", "--flip", "--max-area", "0.01", "-o", "o"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.err_lines(), (std::vector<std::string>{"mwst: warning: --max-area has no effect with --method dt"}));
  // What each method reads: no warning.
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--method", "dr", "--min-angle", "25", "--steiner", "circumcenter", "--max-area", "1", "--max-steiner", "5",
            "--time-limit", "10"},
           {"--method", "brh", "--min-angle", "25", "--bundle-k", "9", "--max-steiner", "5", "--max-area", "1"},
           {"--method", "opt", "--bundle-k", "9", "--opt-trials", "1", "--exact-polish"},
           {"--method", "opt", "--max-area", "0.1", "--opt-trials", "1", "--flip"},
           {"--method", "qtr", "--flip", "--convex-hull", "--strict", "--bundle"}}) {
    std::vector<std::string> call = {"triangulate", "in.poly", "-o", "ok"};
    call.insert(call.end(), args.begin(), args.end());
    r = box.run(call);
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    EXPECT_TRUE(r.err.empty()) << describe(r);
  }
  r = box.run({"triangulate", "in.poly", "--method", "dt", "--min-angle", "30", "--quiet", "-o", "quiet"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(r.err.empty() && r.out.empty()) << describe(r);
}

// --max-area holds in what is written: after dr with --flip (EFH takes only flips that keep the
// bound) and after opt (every start refined to it, no move of the search exceeds it). Checked on
// the .ele/.node files and in the report's max_triangle_area; the check command accepts the mesh.
TEST(Cli, AreaBoundHoldsAfterFlipsAndOpt) {
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  for (const std::vector<std::string>& method : {std::vector<std::string>{"--method", "dr", "--flip"},
                                                 std::vector<std::string>{"--method", "opt", "--opt-trials", "5"},
                                                 std::vector<std::string>{"--method", "brh", "--flip"}}) {
    SCOPED_TRACE(method[1]);
    std::vector<std::string> call = {"triangulate", "in.poly", "--max-area", "0.01", "--json", "r.json", "-o", "m"};
    call.insert(call.end(), method.begin(), method.end());
    const Outcome r = box.run(call);
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    EXPECT_TRUE(r.err.empty()) << describe(r);
    const auto j = nlohmann::json::parse(box.get("r.json"));
    EXPECT_LE(j["max_triangle_area"].get<double>(), 0.01);
    const mwst::io::MeshFiles mesh = mwst::io::read_mesh(box.path("m"));
    ASSERT_GE(mesh.triangles.size(), 100u);  // 1 / 0.01, at least
    double largest = 0.0;
    for (const auto& t : mesh.triangles) {
      largest = std::max(largest, mwst::triangle_area(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]));
    }
    EXPECT_LE(largest, 0.01);
    EXPECT_EQ(j["max_triangle_area"].get<double>(), largest);  // (the files keep every bit)
    EXPECT_EQ(box.run({"check", "in.poly", "m"}).exit_code, 0);
  }
}

// ---- 6. default prefix -------------------------------------------------------------------------

TEST(Cli, MinAngleWithOptIsWarnedToBeNoAngleBound) {
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  Outcome r = box.run({"triangulate", "in.poly", "--method", "opt", "--min-angle", "20", "--opt-trials", "1",
                       "--json", "o.json", "-o", "o"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  ASSERT_EQ(r.err_lines().size(), 1u) << describe(r);
  EXPECT_NE(r.err_lines()[0].find("mwst: warning: --min-angle bounds only the angles of opt's starting meshes"),
            std::string::npos)
      << describe(r);
  EXPECT_EQ(nlohmann::json::parse(box.get("o.json"))["warnings"].size(), 1u);
  // Not given: no warning (the default angle still shapes the starts, as documented).
  r = box.run({"triangulate", "in.poly", "--method", "opt", "--opt-trials", "1", "-o", "p"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_TRUE(r.err.empty()) << describe(r);
}

TEST(Cli, OptionErrorsOfTheLibraryNameTheFlags) {
  // check_options names the field (min_angle_deg); each command names its own flag.
  mwst::TriangulateOptions options;
  options.min_angle_deg = 75.0;
  try {
    mwst::check_options(options);
    ADD_FAILURE() << "an angle of 75 degrees was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "min_angle_deg must be in [0, 60) degrees");
  }
  Sandbox box;
  box.put("in.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  const Outcome r = box.run({"triangle", "-pq75", "in.poly"});
  EXPECT_EQ(r.exit_code, 2) << describe(r);
  EXPECT_EQ(r.err, "mwst: -q must be in [0, 60) degrees\n");
  EXPECT_EQ(box.entries(), (std::set<std::string>{"in.poly"}));
}

// The library's other messages name fields too (issue 34: "the library speaks its own language"),
// and method_reads_option takes field names; `mwst triangulate` maps them back to its flags.
TEST(Cli, LibraryMessagesNameFieldsAndTheCliMapsThem) {
  try {
    (void)mwst::default_bundle_k(0.0);
    ADD_FAILURE() << "a default bundle size without an angle";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("needs min_angle_deg > 0; give bundle_k"), std::string::npos) << what;
    EXPECT_EQ(what.find("--"), std::string::npos) << what;
  }
  mwst::TriangulateOptions options;
  options.method = mwst::Method::kDr;
  options.max_area = 1e-12;
  options.memory_budget_bytes = 1e9;
  try {
    (void)mwst::triangulate(mwst::io::read_input(mwst::test::regression_path("unit_square_area_runaway.poly")), options);
    ADD_FAILURE() << "an area bound of 2e12 triangles was accepted";
  } catch (const mwst::ResourceError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("max_area 1e-12 on a domain of area 1 would make about 2e+12 triangles", 0), 0u) << what;
    EXPECT_NE(what.find("(memory_budget_bytes): give a larger max_area"), std::string::npos) << what;
    EXPECT_EQ(what.find("--"), std::string::npos) << what;
  }
  EXPECT_FALSE(mwst::method_reads_option(mwst::Method::kDt, "max_area"));
  EXPECT_TRUE(mwst::method_reads_option(mwst::Method::kDr, "max_area"));
  EXPECT_FALSE(mwst::method_reads_option(mwst::Method::kDr, "bundle_k"));
  EXPECT_TRUE(mwst::method_reads_option(mwst::Method::kBrh, "bundle_k"));
  EXPECT_TRUE(mwst::method_reads_option(mwst::Method::kQtr, "time_budget_seconds"));
  EXPECT_FALSE(mwst::method_reads_option(mwst::Method::kQtr, "max_area"));
  EXPECT_TRUE(mwst::method_reads_option(mwst::Method::kOpt, "opt_trials"));
  // The CLI: the refusal names the flags (exit 4, one line).
  Sandbox box;
  const Outcome r = box.run({"triangulate", mwst::test::regression_path("unit_square_area_runaway.poly"), "-o", "u", "--method", "dr",
                             "--max-area", "1e-12", "--max-memory", "1G"});
  EXPECT_EQ(r.exit_code, 4) << describe(r);
  EXPECT_EQ(r.err.rfind("mwst: --max-area 1e-12 on a domain of area 1 would make about 2e+12 triangles", 0), 0u)
      << describe(r);
  EXPECT_NE(r.err.find("(--max-memory): give a larger --max-area, or a larger --max-memory"), std::string::npos)
      << describe(r);
}

TEST(Cli, DefaultPrefixFollowsTriangle) {
  Sandbox box;
  box.put("shape.poly", kSquare + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  ASSERT_EQ(box.run({"triangulate", "shape.poly", "-q"}).exit_code, 0);
  EXPECT_TRUE(box.has("shape.1.node") && box.has("shape.1.ele") && box.has("shape.1.poly"));
  // Triangle increments an iteration number: shape.1.node → shape.2.*
  ASSERT_EQ(box.run({"triangulate", "shape.1.node", "-q"}).exit_code, 0);
  EXPECT_TRUE(box.has("shape.2.node") && box.has("shape.2.ele"));
  EXPECT_FALSE(box.has("shape.2.poly")) << "a point set has no subsegments";
  // A stale PREFIX.poly from an earlier run is removed when the new mesh has no subsegments.
  box.put("pts.1.poly", "junk\n");
  box.put("pts.node", kSquare);
  ASSERT_EQ(box.run({"triangulate", "pts.node", "-q"}).exit_code, 0);
  EXPECT_FALSE(box.has("pts.1.poly"));
  EXPECT_EQ(box.run({"check", "pts.node", "pts.1", "--delaunay"}).exit_code, 0);
}

// ---- 7. generate -------------------------------------------------------------------------------

TEST(Cli, GenerateIsDeterministicAndTriangulatesValidly) {
  Sandbox box;
  for (const std::string dist : {"uniform", "kuzmin", "ellipse", "grid", "circle"}) {
    SCOPED_TRACE(dist);
    ASSERT_EQ(box.run({"generate", dist, "500", "--seed", "7", "-o", "a.node"}).exit_code, 0);
    ASSERT_EQ(box.run({"generate", dist, "500", "--seed", "7", "-o", "b.node"}).exit_code, 0);
    ASSERT_EQ(box.run({"generate", dist, "500", "--seed", "8", "-o", "c.node"}).exit_code, 0);
    EXPECT_EQ(box.get("a.node"), box.get("b.node"));
    const bool random = dist == "uniform" || dist == "kuzmin";
    EXPECT_EQ(box.get("a.node") != box.get("c.node"), random) << "the seed matters exactly for random sets";
    const mwst::Pslg p = mwst::io::read_node(box.path("a.node"));
    ASSERT_EQ(p.points.size(), 500u);
    std::set<std::pair<double, double>> distinct;
    for (const auto& q : p.points) distinct.insert({q.x, q.y});
    EXPECT_EQ(distinct.size(), 500u);
    Outcome r = box.run({"triangulate", "a.node", "-o", "t", "-q"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    r = box.run({"check", "a.node", "t", "--delaunay"});
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    if (dist != "circle") {  // refining 500 cocircular points to 20° is slow-ish and adds nothing
      r = box.run({"triangulate", "a.node", "-o", "r", "-q", "--method", "dr"});
      ASSERT_EQ(r.exit_code, 0) << describe(r);
      r = box.run({"check", "a.node", "r", "--delaunay"});
      EXPECT_EQ(r.exit_code, 0) << describe(r);
    }
  }
}

// The polygon classes are written as .poly (and refused as .node); the point classes may be
// written as a .poly without segments. Each output triangulates and checks.
TEST(Cli, GeneratePolygonsAsPoly) {
  Sandbox box;
  for (const std::string cls : {"holes", "fan", "strip", "coastline", "spiral", "clusters"}) {
    SCOPED_TRACE(cls);
    ASSERT_EQ(box.run({"generate", cls, "700", "-o", "a.poly"}).exit_code, 0);
    const mwst::Pslg g = mwst::io::read_poly(box.path("a.poly"));
    EXPECT_EQ(g.points.size(), 700u);
    const bool polygon = cls != "spiral" && cls != "clusters";
    EXPECT_EQ(g.segments.size(), polygon ? 700u : 0u);
    Outcome r = box.run({"triangulate", "a.poly", "-o", "t", "-q"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    r = box.run({"check", "a.poly", "t", "--delaunay"});
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    r = box.run({"generate", cls, "700", "-o", "a.node"});
    EXPECT_EQ(r.exit_code, polygon ? 2 : 0) << describe(r);
  }
  const Outcome r = box.run({"generate", "holes", "67", "-o", "h.poly"});  // the minimum is 68
  EXPECT_EQ(r.exit_code, 2) << describe(r);
  EXPECT_FALSE(std::filesystem::exists(box.path("h.poly")));
}

// ---- 8. determinism ----------------------------------------------------------------------------

TEST(Cli, TwoRunsGiveIdenticalFiles) {
  Sandbox box;
  // Every method, and the flips, on Plate (five holes); DT and DR on two larger sets as well.
  const std::vector<std::pair<std::string, std::vector<std::string>>> runs = {
      {"Kuzmin2K.node", {"--method", "dt"}},    {"Kuzmin2K.node", {"--method", "dr"}},
      {"Superior.poly", {"--method", "dt"}},    {"Superior.poly", {"--method", "dr"}},
      {"Plate.poly", {"--method", "dt"}},       {"Plate.poly", {"--method", "dr"}},
      {"Plate.poly", {"--method", "brh"}},      {"Plate.poly", {"--method", "qtr"}},
      {"Plate.poly", {"--method", "opt", "--opt-trials", "40"}},
      {"Plate.poly", {"--method", "dt", "--flip"}},
      {"Plate.poly", {"--method", "brh", "--flip"}}};
  for (const auto& [name, method] : runs) {
    std::string trace = name;
    for (const std::string& m : method) trace += " " + m;
    SCOPED_TRACE(trace);
    const std::string input = data(name);
    std::vector<std::string> one = {"triangulate", input, "-o", "one", "-q"};
    std::vector<std::string> two = {"triangulate", input, "-o", "two", "-q"};
    one.insert(one.end(), method.begin(), method.end());
    two.insert(two.end(), method.begin(), method.end());
    ASSERT_EQ(box.run(one).exit_code, 0);
    ASSERT_EQ(box.run(two).exit_code, 0);
    if (name.ends_with(".poly")) {
      EXPECT_TRUE(box.has("one.poly")) << "a .poly gives subsegments";
    }
    for (const char* ext : {".node", ".ele", ".poly"}) {
      EXPECT_EQ(box.has(std::string("one") + ext), box.has(std::string("two") + ext));
      if (box.has(std::string("one") + ext)) {
        EXPECT_TRUE(box.get(std::string("one") + ext) == box.get(std::string("two") + ext)) << ext;
      }
    }
    for (const auto& e : fs::directory_iterator(box.dir())) fs::remove(e.path());
  }
}

// TriangulateOptions::threads (--threads N): the results do not depend on N. One and two worker
// threads give byte-identical files for the phases that use them: the Delaunay triangulation,
// BRH's K-bundle test, opt's pieces, and the bundle number (compared in the report).
TEST(Cli, ThreadCountDoesNotChangeTheOutput) {
  Sandbox box;
  EXPECT_NE(box.run({"triangulate", "--help"}).out.find("--threads"), std::string::npos);
  const std::vector<std::pair<std::string, std::vector<std::string>>> runs = {
      {"Kuzmin2K.node", {"--method", "dt"}},
      {"Superior.poly", {"--method", "dr", "--bundle"}},
      {"Plate.poly", {"--method", "brh", "--flip"}},
      {"Plate.poly", {"--method", "opt", "--opt-trials", "40"}}};
  for (const auto& [name, method] : runs) {
    std::string trace = name;
    for (const std::string& m : method) trace += " " + m;
    SCOPED_TRACE(trace);
    for (const std::string threads : {"1", "2"}) {
      std::vector<std::string> call = {"triangulate", data(name), "-o", "t" + threads, "-q", "--threads", threads,
                                       "--json", "t" + threads + ".json"};
      call.insert(call.end(), method.begin(), method.end());
      const Outcome r = box.run(call);
      ASSERT_EQ(r.exit_code, 0) << describe(r);
    }
    for (const char* ext : {".node", ".ele", ".poly"}) {
      EXPECT_EQ(box.has(std::string("t1") + ext), box.has(std::string("t2") + ext)) << ext;
      if (box.has(std::string("t1") + ext)) {
        EXPECT_TRUE(box.get(std::string("t1") + ext) == box.get(std::string("t2") + ext)) << ext;
      }
    }
    ASSERT_TRUE(box.has("t1.node") && box.has("t1.ele"));
    const auto one = nlohmann::json::parse(box.get("t1.json"));
    const auto two = nlohmann::json::parse(box.get("t2.json"));
    for (const char* key : {"weight_total", "vertices", "triangles", "stop_reason", "bundle_number"}) {
      EXPECT_EQ(one.contains(key), two.contains(key)) << key;
      if (one.contains(key)) {
        EXPECT_EQ(one[key], two[key]) << key;
      }
    }
    if (method[1] == "dr") {
      EXPECT_TRUE(one.contains("bundle_number"));
    }
    for (const auto& e : fs::directory_iterator(box.dir())) fs::remove(e.path());
  }
}

}  // namespace
