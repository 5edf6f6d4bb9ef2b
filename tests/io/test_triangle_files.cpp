// tests/io/test_triangle_files.cpp — Triangle's output files of `mwst triangle`
// (io::format_triangle_files, mwst/io/triangle_files.hpp) and the readers of an existing mesh for -r
// (io::parse_ele, io::parse_area, io::read_triangles, io::read_triangle_areas):
//   - the output .poly keeps holes and regions: re-meshing it gives the same domain (Plate: 5
//     holes, area checked independently by check_triangulation);
//   - .ele carries the regional attributes (-A), .edge and .neigh agree with .ele, the Voronoi
//     files are Triangle's layout (circumcentres; rays perpendicular to the boundary, outward);
//   - boundary markers follow Triangle's rules, -B drops them, -j drops unused vertices;
//   - every error of the .ele and .area readers is one InputError naming the file and line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mwst/algorithms/arrays.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mwst;

// A fresh directory under the test temporary directory, removed at the end of the test.
class Scratch {
 public:
  Scratch() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::path(testing::TempDir()) /
            ("mwst_trifiles_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// The lines of a text, each split into its fields.
std::vector<std::vector<std::string>> records(const std::string& text) {
  std::vector<std::vector<std::string>> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::vector<std::string> row;
    for (std::string f; fields >> f;) row.push_back(f);
    if (!row.empty()) out.push_back(row);
  }
  return out;
}

std::string text_of(const std::vector<io::TriangleFile>& files, const std::string& extension) {
  for (const io::TriangleFile& f : files) {
    if (f.extension == extension) return f.text();
  }
  ADD_FAILURE() << "no " << extension << " file";
  return {};
}

std::vector<std::string> extensions(const std::vector<io::TriangleFile>& files) {
  std::vector<std::string> out;
  for (const io::TriangleFile& f : files) out.push_back(f.extension);
  return out;
}

void write_all(const std::vector<io::TriangleFile>& files, const std::string& prefix) {
  io::write_triangle_files(prefix, files);
}

io::TriangleOutput every_file() {
  io::TriangleOutput what;
  what.poly = what.edges = what.neighbours = what.voronoi = true;
  what.triangle_attributes = true;
  return what;
}

// A 4 x 2 rectangle split by a segment at x = 2 (marker 7), outer boundary marker 0 (Triangle then
// gives the boundary 1), a dangling segment (marker 0) inside the right half, and one region per
// half.
Pslg two_rooms() {
  const char* text =
      "8 2 0 1\n"
      "1 0 0 0\n2 2 0 0\n3 4 0 0\n4 4 2 0\n5 2 2 0\n6 0 2 0\n"
      "7 2.9 0.9 0\n8 3.1 0.9 0\n"
      "8 1\n"
      "1 1 2 0\n2 2 3 0\n3 3 4 0\n4 4 5 0\n5 5 6 0\n6 6 1 0\n7 2 5 7\n8 7 8 0\n"
      "0\n"
      "2\n1 1 1 10 -1\n2 3 1.5 20 0.25\n";
  return io::parse_poly(text, "two_rooms.poly");
}

double triangle_area(const std::vector<double>& xy, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return 0.5 * ((xy[2 * b] - xy[2 * a]) * (xy[2 * c + 1] - xy[2 * a + 1]) -
                (xy[2 * c] - xy[2 * a]) * (xy[2 * b + 1] - xy[2 * a + 1]));
}

TEST(TriangleFiles, PlateRoundTripKeepsTheFiveHolesAndTheDomain) {
  const Pslg plate = io::read_poly(std::string(MWST_DATA_DIR) + "/Plate.poly");
  ASSERT_EQ(plate.holes.size(), 5u);
  TriangulateOptions options;
  options.method = Method::kDr;
  options.min_angle_deg = 30.0;
  const MeshArrays mesh = triangulate_arrays(plate, options);
  io::TriangleOutput what;
  what.poly = true;
  const std::vector<io::TriangleFile> files = io::format_triangle_files(mesh, plate.holes, plate.regions, what);
  EXPECT_EQ(extensions(files), (std::vector<std::string>{".node", ".ele", ".poly"}));
  Scratch dir;
  const std::string prefix = dir.file("Plate.1");
  write_all(files, prefix);

  // The files are a valid triangulation of the input, checked independently.
  const io::MeshFiles back = io::read_mesh(prefix);
  const CheckResult check = check_triangulation(plate, back.points, back.triangles, back.segments);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());

  // The output .poly has the holes, and re-meshing it gives the same domain.
  const Pslg again = io::read_poly(prefix + ".poly");
  ASSERT_EQ(again.holes.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(again.holes[i].x, plate.holes[i].x);
    EXPECT_EQ(again.holes[i].y, plate.holes[i].y);
  }
  const MeshArrays remeshed = triangulate_arrays(again, TriangulateOptions{});
  double area = 0.0, area_before = 0.0;
  for (std::size_t t = 0; t < remeshed.triangle_count(); ++t) {
    area += triangle_area(remeshed.vertices, remeshed.triangles[3 * t], remeshed.triangles[3 * t + 1],
                          remeshed.triangles[3 * t + 2]);
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    area_before += triangle_area(mesh.vertices, mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]);
  }
  EXPECT_NEAR(area, check.domain_area, 1e-9 * check.domain_area);
  EXPECT_NEAR(area_before, check.domain_area, 1e-9 * check.domain_area);
  // 200 x 120 less the rounded corners and the holes: about 20287, not the 23775 of a filled plate.
  EXPECT_NEAR(area, 20287.42, 0.01);
  // And the re-meshed output is a valid triangulation of the original input too.
  const CheckResult check_again =
      check_triangulation(plate, [&] {
        std::vector<Point> p(remeshed.vertex_count());
        for (std::size_t v = 0; v < p.size(); ++v) p[v] = {remeshed.vertices[2 * v], remeshed.vertices[2 * v + 1]};
        return p;
      }(), [&] {
        std::vector<std::array<std::uint32_t, 3>> t(remeshed.triangle_count());
        for (std::size_t i = 0; i < t.size(); ++i) {
          t[i] = {remeshed.triangles[3 * i], remeshed.triangles[3 * i + 1], remeshed.triangles[3 * i + 2]};
        }
        return t;
      }(), {});
  EXPECT_TRUE(check_again.ok()) << (check_again.messages.empty() ? "" : check_again.messages.front());
}

TEST(TriangleFiles, RegionsSurviveTheOutputPolyAndGiveTheEleItsAttributes) {
  const Pslg input = two_rooms();
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  const std::vector<io::TriangleFile> files = io::format_triangle_files(mesh, input.holes, input.regions, every_file());
  // .ele: "T 3 1", then each triangle's regional attribute: 10 left of x = 2, 20 right of it.
  const auto ele = records(text_of(files, ".ele"));
  ASSERT_EQ(ele.front(), (std::vector<std::string>{std::to_string(mesh.triangle_count()), "3", "1"}));
  ASSERT_EQ(ele.size(), mesh.triangle_count() + 1);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    double cx = 0.0;
    for (unsigned k = 0; k < 3; ++k) cx += mesh.vertices[2 * mesh.triangles[3 * t + k]] / 3.0;
    ASSERT_EQ(ele[t + 1].size(), 5u);
    EXPECT_EQ(ele[t + 1][4], cx < 2.0 ? "10" : "20") << "triangle " << t + 1;
  }
  // .poly: the regions come back as read.
  Scratch dir;
  write_all(files, dir.file("rooms.1"));
  const Pslg again = io::read_poly(dir.file("rooms.1.poly"));
  ASSERT_EQ(again.regions.size(), 2u);
  for (std::size_t r = 0; r < 2; ++r) {
    EXPECT_EQ(again.regions[r].seed.x, input.regions[r].seed.x);
    EXPECT_EQ(again.regions[r].seed.y, input.regions[r].seed.y);
    EXPECT_EQ(again.regions[r].attribute, input.regions[r].attribute);
    EXPECT_EQ(again.regions[r].max_area, input.regions[r].max_area);
  }
  // Without -A no attribute column.
  io::TriangleOutput plain;
  const auto plain_ele = records(text_of(io::format_triangle_files(mesh, input.holes, input.regions, plain), ".ele"));
  EXPECT_EQ(plain_ele.front()[2], "0");
  EXPECT_EQ(plain_ele[1].size(), 4u);
}

// The edges of the .ele as unordered vertex pairs.
std::set<std::pair<std::string, std::string>> ele_edges(const std::vector<std::vector<std::string>>& ele) {
  std::set<std::pair<std::string, std::string>> edges;
  for (std::size_t i = 1; i < ele.size(); ++i) {
    for (unsigned k = 0; k < 3; ++k) {
      std::string a = ele[i][1 + (k + 1) % 3], b = ele[i][1 + (k + 2) % 3];
      if (std::stoll(b) < std::stoll(a)) std::swap(a, b);
      edges.insert({a, b});
    }
  }
  return edges;
}

TEST(TriangleFiles, EdgeAndNeighAgreeWithEle) {
  const Pslg input = two_rooms();
  TriangulateOptions options;
  options.method = Method::kDr;
  options.max_area = 0.05;
  const MeshArrays mesh = triangulate_arrays(input, options);
  const std::vector<io::TriangleFile> files = io::format_triangle_files(mesh, input.holes, input.regions, every_file());
  const auto ele = records(text_of(files, ".ele"));
  const auto edge = records(text_of(files, ".edge"));
  const auto neigh = records(text_of(files, ".neigh"));
  // .edge: "E 1", every edge of the .ele exactly once, numbered from 1.
  const auto expected = ele_edges(ele);
  ASSERT_EQ(edge.front(), (std::vector<std::string>{std::to_string(expected.size()), "1"}));
  std::set<std::pair<std::string, std::string>> listed;
  for (std::size_t i = 1; i < edge.size(); ++i) {
    ASSERT_EQ(edge[i].size(), 4u);
    EXPECT_EQ(edge[i][0], std::to_string(i));
    std::string a = edge[i][1], b = edge[i][2];
    if (std::stoll(b) < std::stoll(a)) std::swap(a, b);
    EXPECT_TRUE(listed.insert({a, b}).second) << "edge listed twice: " << a << " " << b;
  }
  EXPECT_EQ(listed, expected);
  // Euler for a disk: V - E + F = 1, over the vertices used.
  EXPECT_EQ(static_cast<long>(mesh.report.vertices) - static_cast<long>(expected.size()) +
                static_cast<long>(mesh.triangle_count()),
            1);
  // .neigh: "T 3"; neighbour k of t shares the edge opposite corner k, and says t back; -1 on the
  // boundary, which is then an edge of that triangle alone.
  ASSERT_EQ(neigh.front(), (std::vector<std::string>{std::to_string(mesh.triangle_count()), "3"}));
  std::map<std::pair<std::string, std::string>, int> uses;
  for (std::size_t t = 1; t < ele.size(); ++t) {
    for (unsigned k = 0; k < 3; ++k) {
      std::string a = ele[t][1 + (k + 1) % 3], b = ele[t][1 + (k + 2) % 3];
      if (std::stoll(b) < std::stoll(a)) std::swap(a, b);
      ++uses[{a, b}];
    }
  }
  for (std::size_t t = 1; t < neigh.size(); ++t) {
    ASSERT_EQ(neigh[t].size(), 4u);
    EXPECT_EQ(neigh[t][0], std::to_string(t));
    for (unsigned k = 0; k < 3; ++k) {
      const std::string& a = ele[t][1 + (k + 1) % 3];
      const std::string& b = ele[t][1 + (k + 2) % 3];
      const long n = std::stol(neigh[t][1 + k]);
      const auto key = std::stoll(a) < std::stoll(b) ? std::make_pair(a, b) : std::make_pair(b, a);
      if (n == -1) {
        EXPECT_EQ(uses[key], 1) << "triangle " << t << " corner " << k;
        continue;
      }
      ASSERT_GE(n, 1);
      ASSERT_LT(static_cast<std::size_t>(n), ele.size());
      const auto& other = ele[static_cast<std::size_t>(n)];
      const std::set<std::string> corners(other.begin() + 1, other.begin() + 4);
      EXPECT_TRUE(corners.count(a) && corners.count(b)) << "triangle " << t << " corner " << k;
      const auto& back = neigh[static_cast<std::size_t>(n)];
      EXPECT_TRUE(std::find(back.begin() + 1, back.end(), std::to_string(t)) != back.end());
    }
  }
}

TEST(TriangleFiles, VoronoiIsCircumcentresAndOutwardRays) {
  const Pslg input = io::parse_node("5 2 0 0\n1 0 0\n2 3 0\n3 3 2\n4 0 2\n5 1 0.8\n", "five.node");
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  const std::vector<io::TriangleFile> files = io::format_triangle_files(mesh, {}, {}, every_file());
  const auto vnode = records(text_of(files, ".v.node"));
  const auto vedge = records(text_of(files, ".v.edge"));
  const auto edge = records(text_of(files, ".edge"));
  ASSERT_EQ(vnode.front(), (std::vector<std::string>{std::to_string(mesh.triangle_count()), "2", "0", "0"}));
  // Each Voronoi vertex is equidistant from its triangle's corners.
  std::vector<Point> centre(mesh.triangle_count());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    ASSERT_EQ(vnode[t + 1].size(), 3u);
    centre[t] = {std::stod(vnode[t + 1][1]), std::stod(vnode[t + 1][2])};
    double r[3];
    for (unsigned k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[3 * t + k];
      r[k] = std::hypot(mesh.vertices[2 * v] - centre[t].x, mesh.vertices[2 * v + 1] - centre[t].y);
    }
    EXPECT_NEAR(r[0], r[1], 1e-12);
    EXPECT_NEAR(r[0], r[2], 1e-12);
  }
  // One Voronoi edge per edge, in the .edge's order: between the triangles on either side, or a ray
  // perpendicular to a boundary edge pointing away from its triangle.
  ASSERT_EQ(vedge.front(), (std::vector<std::string>{edge.front()[0], "0"}));
  ASSERT_EQ(vedge.size(), edge.size());
  std::size_t rays = 0;
  for (std::size_t i = 1; i < vedge.size(); ++i) {
    const std::size_t a = std::stoul(edge[i][1]) - 1, b = std::stoul(edge[i][2]) - 1;
    const std::size_t t = std::stoul(vedge[i][1]) - 1;
    const std::set<std::uint32_t> corners(mesh.triangles.begin() + 3 * t, mesh.triangles.begin() + 3 * t + 3);
    EXPECT_TRUE(corners.count(static_cast<std::uint32_t>(a)) && corners.count(static_cast<std::uint32_t>(b)));
    if (vedge[i][2] != "-1") {
      ASSERT_EQ(vedge[i].size(), 3u);
      continue;
    }
    ++rays;
    ASSERT_EQ(vedge[i].size(), 5u);
    const double dx = std::stod(vedge[i][3]), dy = std::stod(vedge[i][4]);
    const double ex = mesh.vertices[2 * b] - mesh.vertices[2 * a], ey = mesh.vertices[2 * b + 1] - mesh.vertices[2 * a + 1];
    EXPECT_EQ(dx * ex + dy * ey, 0.0) << "ray " << i << " not perpendicular";
    // Outward: away from the triangle's third corner.
    std::uint32_t third = 0;
    for (const std::uint32_t c : corners) {
      if (c != a && c != b) third = c;
    }
    const double mx = 0.5 * (mesh.vertices[2 * a] + mesh.vertices[2 * b]);
    const double my = 0.5 * (mesh.vertices[2 * a + 1] + mesh.vertices[2 * b + 1]);
    EXPECT_GT(dx * (mx - mesh.vertices[2 * third]) + dy * (my - mesh.vertices[2 * third + 1]), 0.0) << "ray " << i;
  }
  EXPECT_EQ(rays, 4u);  // the hull of the five points is the rectangle
}

TEST(TriangleFiles, BoundaryMarkersFollowTriangleAndDashBDropsThem) {
  const Pslg input = two_rooms();
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  const std::vector<io::TriangleFile> files = io::format_triangle_files(mesh, input.holes, input.regions, every_file());
  const auto node = records(text_of(files, ".node"));
  ASSERT_EQ(node.front(), (std::vector<std::string>{"8", "2", "0", "1"}));
  // Vertices 2 and 5 lie on the segment of marker 7; the other outer corners on the boundary (1);
  // the ends of the dangling segment 7-8 (marker 0) inside the right room: 0.
  const std::vector<std::string> expected = {"1", "7", "1", "1", "7", "1", "0", "0"};
  for (std::size_t v = 0; v < 8; ++v) EXPECT_EQ(node[v + 1][3], expected[v]) << "vertex " << v + 1;
  // Segments: marker 7 stays, the outer ones (0 in the input) become 1, the inside one stays 0.
  const auto poly = records(text_of(files, ".poly"));
  ASSERT_EQ(poly[0], (std::vector<std::string>{"0", "2", "0", "1"}));
  std::map<std::pair<std::string, std::string>, std::string> marker;
  const std::size_t segments = std::stoul(poly[1][0]);
  for (std::size_t i = 0; i < segments; ++i) {
    const auto& row = poly[2 + i];
    marker[std::minmax(row[1], row[2])] = row[3];
  }
  EXPECT_EQ(marker[std::minmax(std::string("2"), std::string("5"))], "7");
  EXPECT_EQ(marker[std::minmax(std::string("1"), std::string("2"))], "1");
  EXPECT_EQ(marker[std::minmax(std::string("7"), std::string("8"))], "0");
  // The same markers in the .edge, and 0 for the edges that are no segment.
  for (const auto& row : records(text_of(files, ".edge"))) {
    if (row.size() != 4) continue;
    const auto key = std::minmax(row[1], row[2]);
    const auto found = marker.find(key);
    EXPECT_EQ(row[3], found == marker.end() ? "0" : found->second) << row[1] << "-" << row[2];
  }

  io::TriangleOutput bare = every_file();
  bare.boundary_markers = false;
  const std::vector<io::TriangleFile> unmarked = io::format_triangle_files(mesh, input.holes, input.regions, bare);
  const auto node_bare = records(text_of(unmarked, ".node"));
  EXPECT_EQ(node_bare.front()[3], "0");
  for (std::size_t v = 1; v < node_bare.size(); ++v) EXPECT_EQ(node_bare[v].size(), 3u);
  const auto edge_bare = records(text_of(unmarked, ".edge"));
  EXPECT_EQ(edge_bare.front()[1], "0");
  for (std::size_t i = 1; i < edge_bare.size(); ++i) EXPECT_EQ(edge_bare[i].size(), 3u);
  const auto poly_bare = records(text_of(unmarked, ".poly"));
  EXPECT_EQ(poly_bare[0][3], "0");
  EXPECT_EQ(poly_bare[1][1], "0");
  EXPECT_EQ(poly_bare[2].size(), 3u);
}

TEST(TriangleFiles, JettisonDropsUnusedVerticesAndRenumbers) {
  // Vertex 3 duplicates vertex 1, vertex 6 lies outside the domain's segments.
  const Pslg input = io::parse_poly(
      "6 2 0 0\n0 0 0\n1 1 0\n2 0 0\n3 1 1\n4 0 1\n5 5 5\n4 0\n0 0 1\n1 1 3\n2 3 4\n3 4 0\n0\n", "j.poly");
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  io::TriangleOutput keep, drop;
  keep.first_index = drop.first_index = 0;
  drop.jettison = true;
  const auto all = records(text_of(io::format_triangle_files(mesh, {}, {}, keep), ".node"));
  const auto used = records(text_of(io::format_triangle_files(mesh, {}, {}, drop), ".node"));
  EXPECT_EQ(all.front()[0], "6");
  ASSERT_EQ(used.front()[0], "4");
  const auto ele = records(text_of(io::format_triangle_files(mesh, {}, {}, drop), ".ele"));
  // Every corner names one of the 4 vertices kept, numbered from 0, at the same place.
  for (std::size_t t = 1; t < ele.size(); ++t) {
    EXPECT_EQ(ele[t][0], std::to_string(t - 1));
    for (unsigned k = 1; k <= 3; ++k) {
      const std::size_t v = std::stoul(ele[t][k]);
      ASSERT_LT(v, 4u);
    }
  }
  std::set<std::pair<std::string, std::string>> kept;
  for (std::size_t v = 1; v < used.size(); ++v) kept.insert({used[v][1], used[v][2]});
  EXPECT_EQ(kept, (std::set<std::pair<std::string, std::string>>{{"0", "0"}, {"1", "0"}, {"1", "1"}, {"0", "1"}}));
}

TEST(TriangleFiles, ConvexHullOfAPointSetIsWrittenAsSegments) {
  const Pslg input = io::parse_node("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n", "sq.node");
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  io::TriangleOutput what;
  what.poly = true;
  const auto poly = records(text_of(io::format_triangle_files(mesh, {}, {}, what), ".poly"));
  ASSERT_EQ(poly[1][0], "4");  // the four hull edges, marker 1
  for (std::size_t i = 2; i < 6; ++i) EXPECT_EQ(poly[i][3], "1");
  EXPECT_EQ(poly[6], std::vector<std::string>{"0"});  // no holes, no regions section
  EXPECT_EQ(poly.size(), 7u);
}

// ---- .ele and .area for -r --------------------------------------------------------------------

std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    // (located() itself, inlined here, trips GCC 12's -Wrestrict: built by hand instead.)
    std::ostringstream where;
    where << e.file();
    if (e.line() > 0) where << ':' << e.line();
    where << ": " << e.what();
    return where.str();
  }
  return "";
}

TEST(TriangleFiles, EleIsReadForRefinement) {
  EXPECT_EQ(io::parse_ele("2 3 0\n1 1 2 3\n2 1 3 4\n", "m.ele", 4, 1),
            (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(io::parse_ele("# zero-based\n1 3 1\n0 2 1 0 7.5 # attribute\n", "m.ele", 3, 0),
            (std::vector<std::uint32_t>{2, 1, 0}));
  // Six-node triangles: the first three nodes are the corners.
  EXPECT_EQ(io::parse_ele("1 6\n1 1 2 3 4 5 6\n", "m.ele", 6, 1), (std::vector<std::uint32_t>{0, 1, 2}));
}

TEST(TriangleFiles, EleErrorsNameFileAndLine) {
  EXPECT_EQ(input_error([] { (void)io::parse_ele("2 3 0\n1 1 2 3\n2 1 3 9\n", "m.ele", 4, 1); }),
            "m.ele:3: triangle 2 names vertex 9, which does not exist (vertices are numbered 1 to 4)");
  EXPECT_EQ(input_error([] { (void)io::parse_ele("1 3 0\n1 2 3 2\n", "m.ele", 4, 1); }),
            "m.ele:2: triangle 1 names vertex 2 twice");
  EXPECT_EQ(input_error([] { (void)io::parse_ele("1 3 0\n1 0 1 2\n", "m.ele", 4, 1); }),
            "m.ele:2: triangle 1 names vertex 0, which does not exist (vertices are numbered 1 to 4)");
  EXPECT_EQ(input_error([] { (void)io::parse_ele("3 3 0\n1 1 2 3\n", "m.ele", 4, 1); }),
            "m.ele:2: unexpected end of file: expected 3 triangles, found 1");
  EXPECT_EQ(input_error([] { (void)io::parse_ele("1 4 0\n1 1 2 3\n", "m.ele", 4, 1); }),
            "m.ele:1: nodes per triangle must be 3 or 6, found 4");
  EXPECT_EQ(input_error([] { (void)io::parse_ele("1 3 0\n1 1 2 x\n", "m.ele", 4, 1); }),
            "m.ele:2: triangle 1: expected an integer for the corner, found 'x'");
  EXPECT_EQ(input_error([] { (void)io::parse_ele("", "m.ele", 4, 1); }), "m.ele: empty file");
}

TEST(TriangleFiles, AreaIsOneBoundPerTriangle) {
  EXPECT_EQ(io::parse_area("3\n1 0.5\n2 -1\n3 2e-3 # small\n", "m.area", 3), (std::vector<double>{0.5, -1.0, 2e-3}));
  EXPECT_EQ(input_error([] { (void)io::parse_area("2\n1 0.5\n2 1\n", "m.area", 3); }),
            "m.area:1: triangle count 2 differs from the mesh's 3 triangles (one maximum area per triangle of the .ele)");
  EXPECT_EQ(input_error([] { (void)io::parse_area("2\n1 0.5\n", "m.area", 2); }),
            "m.area:2: unexpected end of file: expected 2 triangles, found 1");
  EXPECT_EQ(input_error([] { (void)io::parse_area("1\n1 big\n", "m.area", 1); }),
            "m.area:2: triangle 1: expected a number for the maximum area, found 'big'");
  EXPECT_EQ(input_error([] { (void)io::parse_area("1\n1 1\n2 1\n", "m.area", 1); }),
            "m.area:3: unexpected data after the last triangle (the header says 1 triangles)");
  EXPECT_EQ(input_error([] { (void)io::parse_area("1\n1 nan\n", "m.area", 1); }),
            "m.area:2: triangle 1: maximum area 'nan' is not a finite double");
}

TEST(TriangleFiles, ReadTrianglesAndAreasFillThePslg) {
  Scratch dir;
  io::write_file_atomic(dir.file("m.node"), "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n");
  io::write_file_atomic(dir.file("m.ele"), "2 3 0\n0 0 1 2\n1 0 2 3\n");
  io::write_file_atomic(dir.file("m.area"), "2\n0 0.1\n1 -1\n");
  io::write_file_atomic(dir.file("bad.area"), "3\n0 0.1\n1 -1\n2 1\n");
  Pslg pslg = io::read_node(dir.file("m.node"));
  io::read_triangles(pslg, dir.file("m.ele"));
  EXPECT_EQ(pslg.triangles, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  io::read_triangle_areas(pslg, dir.file("m.area"));
  EXPECT_EQ(pslg.triangle_max_area, (std::vector<double>{0.1, -1.0}));
  const std::string bad = dir.file("bad.area");
  EXPECT_EQ(input_error([&] { io::read_triangle_areas(pslg, bad); }),
            bad + ":1: triangle count 3 differs from the mesh's 2 triangles (one maximum area per triangle of the .ele)");
  const std::string missing = dir.file("none.ele");
  EXPECT_NE(input_error([&] { io::read_triangles(pslg, missing); }).find(missing + ": cannot open"), std::string::npos);
}

}  // namespace

namespace {

// A square with a square hole whose .node has two attributes per vertex, both linear in the
// coordinates (a = x + 2y, b = 3 - y): interpolated linearly, they stay those functions at every
// Steiner point.
constexpr const char* kAttributedPoly =
    "8 2 2 1\n"
    "1 0 0 0 3 1\n2 4 0 4 3 1\n3 4 4 12 -1 1\n4 0 4 8 -1 1\n"
    "5 1 1 3 2 2\n6 3 1 5 2 2\n7 3 3 9 0 2\n8 1 3 7 0 2\n"
    "8 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 2\n6 6 7 2\n7 7 8 2\n8 8 5 2\n"
    "1\n1 2 2\n";

}  // namespace

// Triangle's vertex attributes: read from the .node header's A, kept by the input vertices,
// interpolated linearly to the Steiner points, written to the .node as "N 2 A B" and read back.
TEST(TriangleFiles, VertexAttributesAreCarriedAndInterpolated) {
  const Pslg input = io::parse_poly(kAttributedPoly, "attributed.poly");
  ASSERT_EQ(input.attributes_per_point, 2u);
  ASSERT_EQ(input.point_attributes.size(), 16u);
  EXPECT_EQ(input.point_attributes[4], 12.0);
  TriangulateOptions options;
  options.method = Method::kDr;
  options.min_angle_deg = 30.0;
  options.max_area = 0.2;
  const MeshArrays mesh = triangulate_arrays(input, options);
  ASSERT_GT(mesh.vertex_count(), 8u) << "no Steiner point was added";
  ASSERT_EQ(mesh.attributes_per_vertex, 2u);
  ASSERT_EQ(mesh.vertex_attributes.size(), 2 * mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const double x = mesh.vertices[2 * v], y = mesh.vertices[2 * v + 1];
    EXPECT_NEAR(mesh.vertex_attributes[2 * v], x + 2 * y, 1e-12) << "vertex " << v;
    EXPECT_NEAR(mesh.vertex_attributes[2 * v + 1], 3 - y, 1e-12) << "vertex " << v;
  }
  for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(mesh.vertex_attributes[i], input.point_attributes[i]);

  io::TriangleOutput what;
  const std::string node = text_of(io::format_triangle_files(mesh, input.holes, input.regions, what), ".node");
  const auto rows = records(node);
  ASSERT_EQ(rows[0], (std::vector<std::string>{std::to_string(mesh.vertex_count()), "2", "2", "1"}));
  ASSERT_EQ(rows[1].size(), 6u);  // i x y a b marker
  const Pslg back = io::parse_node(node, "back.node");
  EXPECT_EQ(back.attributes_per_point, 2u);
  EXPECT_EQ(back.point_attributes, mesh.vertex_attributes);
}

// Many Steiner points (thousands, spread over a point set): each is located in the input's
// triangulation by a walk from where the last one was found, in Hilbert curve order; every one
// still gets the linear attributes of its own place (a = x + 2y, b = 3 - y).
TEST(TriangleFiles, VertexAttributesOfManySteinerPointsAreTheirOwnPlaces) {
  Pslg input;
  input.attributes_per_point = 2;
  std::uint64_t state = 12345;
  const auto next = [&state] {  // a fixed linear congruential sequence in [0, 10)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53 * 10.0;
  };
  for (int i = 0; i < 3000; ++i) {
    const Point p{next(), next()};
    input.points.push_back(p);
    input.point_attributes.push_back(p.x + 2 * p.y);
    input.point_attributes.push_back(3 - p.y);
  }
  TriangulateOptions options;
  options.method = Method::kDr;
  options.min_angle_deg = 30.0;
  options.max_area = 0.005;
  const MeshArrays mesh = triangulate_arrays(input, options);
  ASSERT_GT(mesh.vertex_count(), 3000u + 10000u) << "too few Steiner points to test";
  ASSERT_EQ(mesh.vertex_attributes.size(), 2 * mesh.vertex_count());
  std::size_t wrong = 0;
  for (std::size_t v = 3000; v < mesh.vertex_count(); ++v) {
    const double x = mesh.vertices[2 * v], y = mesh.vertices[2 * v + 1];
    if (std::abs(mesh.vertex_attributes[2 * v] - (x + 2 * y)) > 1e-9 ||
        std::abs(mesh.vertex_attributes[2 * v + 1] - (3 - y)) > 1e-9) {
      ++wrong;
    }
  }
  EXPECT_EQ(wrong, 0u);
}

// Without attributes nothing is added, and a .node's "N 2 0 B" is unchanged.
TEST(TriangleFiles, NoVertexAttributesWithoutThem) {
  const Pslg input = io::parse_node("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "t.node");
  EXPECT_EQ(input.attributes_per_point, 0u);
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  EXPECT_EQ(mesh.attributes_per_vertex, 0u);
  EXPECT_TRUE(mesh.vertex_attributes.empty());
  EXPECT_EQ(records(text_of(io::format_triangle_files(mesh, {}, {}, io::TriangleOutput{}), ".node"))[0],
            (std::vector<std::string>{"3", "2", "0", "1"}));
}

// A large file is formatted in pieces on several threads: the same text as one thread writes.
TEST(TriangleFiles, ThreadsDoNotChangeTheText) {
  Pslg input;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 200; ++j) input.points.push_back({i + 0.001 * j * j, j + 0.0007 * i * i});
  }
  const MeshArrays mesh = triangulate_arrays(input, TriangulateOptions{});
  io::TriangleOutput one = every_file(), many = every_file();
  one.threads = 1;
  many.threads = 3;
  const std::vector<io::TriangleFile> a = io::format_triangle_files(mesh, {}, {}, one);
  const std::vector<io::TriangleFile> b = io::format_triangle_files(mesh, {}, {}, many);
  ASSERT_EQ(extensions(a), extensions(b));
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].text(), b[i].text()) << a[i].extension;
    // (The .poly holds only the hull's few edges: too few records to cut.)
    if (a[i].extension != ".poly") {
      EXPECT_LT(a[i].pieces.size(), b[i].pieces.size()) << a[i].extension << " was not cut into ranges";
    }
  }
}
