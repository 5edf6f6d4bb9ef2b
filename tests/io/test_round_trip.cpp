// tests/io/test_round_trip.cpp — "mwst reads back all it writes": every method (dt, dr, brh, qtr,
// opt at a small budget, with and without the weight-reducing flips) on data sets and random
// inputs; the mesh is written with io::write_mesh (PREFIX.node/.ele/.poly), read back with
// io::read_mesh, and must be the same mesh bit for bit (round_trip.hpp), and the file-level checker
// behind `mwst check` (check_triangulation, mwst/mesh/check.hpp) must accept what was read back. Then
// faults planted in written files (one coordinate one ulp off, a dropped triangle, two corners
// swapped, coordinates printed with 15 digits) show that the comparison and the checker catch them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mwst/mesh/check.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "support/round_trip.hpp"
#include "support/exact_checker.hpp"
#include "support/generators.hpp"

namespace mwst {
namespace {

namespace fs = std::filesystem;
using test::round_trip_differences;

// A fresh directory for the written files, removed at the end of the test.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::path(testing::TempDir()) /
            ("mwst_rt_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

using test::joined;

constexpr Method kMethods[] = {Method::kDt, Method::kDr, Method::kBrh, Method::kQtr, Method::kOpt};

// The options of one run: opt at a small budget (two trials per start, few Steiner points), the
// refinements with a Steiner budget that keeps the random inputs quick.
TriangulateOptions options_for(Method method, bool flip) {
  TriangulateOptions o;
  o.method = method;
  o.flip = flip;
  o.min_angle_deg = 20.0;
  o.max_steiner = 3000;
  if (method == Method::kOpt) {
    o.opt_trials = 2;
    o.max_steiner = 200;
  }
  return o;
}

// Meshes `input` with `options`, writes the mesh, reads it back and compares; the checker must
// accept what was read back. Returns the number of triangles written (for the caller's sanity
// checks).
std::size_t expect_round_trip(const Pslg& input, const TriangulateOptions& options, int first_index = 1) {
  SCOPED_TRACE(input.source + " --method " + std::string(method_name(options.method)) +
               (options.flip ? " --flip" : "") + " (numbered from " + std::to_string(first_index) + ")");
  Mesh mesh;
  try {
    triangulate(input, options, &mesh);
  } catch (const InputError& e) {
    ADD_FAILURE() << "refused: " << e.located();
    return 0;
  }
  ScratchDir dir;
  const std::string prefix = dir.file("mesh");
  io::write_mesh(mesh, prefix, first_index);
  io::MeshFiles back;
  try {
    back = io::read_mesh(prefix);
  } catch (const InputError& e) {
    ADD_FAILURE() << "mwst cannot read back what it wrote: " << e.located();
    return 0;
  }
  const std::vector<std::string> differences = round_trip_differences(mesh, back);
  EXPECT_TRUE(differences.empty()) << "read back is not the mesh written:" << joined(differences);
  const CheckResult check = check_triangulation(input, back.points, back.triangles, back.segments);
  EXPECT_TRUE(check.ok()) << check.violations << " violations, the first: "
                          << (check.messages.empty() ? std::string("?") : check.messages.front());
  EXPECT_GT(back.triangles.size(), 0u);
  return back.triangles.size();
}

Pslg points_input(std::vector<Point> points, const std::string& name) {
  Pslg p;
  p.points = std::move(points);
  p.point_markers.assign(p.points.size(), 0);
  p.source = name;
  return p;
}

// A star-shaped polygon with a star-shaped hole around the same centre.
Pslg polygon_with_hole(std::uint64_t seed, double scale) {
  std::mt19937_64 rng(seed);
  Pslg p;
  p.is_poly = true;
  p.source = "polygon_with_hole(seed " + std::to_string(seed) + ", scale " + std::to_string(scale) + ")";
  const Point centre{0.25 * scale, -0.5 * scale};
  test::add_ring(p, test::star_polygon(centre, 40, 0.6 * scale, 1.0 * scale, rng));
  test::add_ring(p, test::star_polygon(centre, 12, 0.15 * scale, 0.3 * scale, rng), 2);
  p.holes.push_back(centre);
  p.point_markers.assign(p.points.size(), 1);
  return p;
}

#ifdef MWST_DATA_DIR
TEST(RoundTrip, DataSetsEveryMethod) {
  for (const char* name : {"Plate.poly", "Airliner.poly", "Africa.poly"}) {
    const Pslg input = io::read_input(std::string(MWST_DATA_DIR) + "/" + name);
    for (const Method m : kMethods) {
      for (const bool flip : {false, true}) expect_round_trip(input, options_for(m, flip));
    }
  }
}

TEST(RoundTrip, PointSetDataSetZeroBased) {
  // A point set (the convex hull is the domain) and the other numbering base.
  Pslg input = io::read_input(std::string(MWST_DATA_DIR) + "/Ellipse.node");
  input.points.resize(300);  // every third of the ellipse's 1000 points: exact cocircular 4-tuples
  input.point_markers.resize(300);
  for (const Method m : {Method::kDt, Method::kDr, Method::kQtr}) expect_round_trip(input, options_for(m, false), 0);
}
#endif

TEST(RoundTrip, RandomPointSetsEveryMethod) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Pslg uniform = points_input(test::uniform_points(120, seed), "uniform(120, seed " + std::to_string(seed) + ")");
    const Pslg grid = points_input(test::grid_points(9, 7, seed), "grid(9 x 7, seed " + std::to_string(seed) + ")");
    for (const Method m : kMethods) {
      expect_round_trip(uniform, options_for(m, seed == 2));
      expect_round_trip(grid, options_for(m, seed == 3));
    }
  }
}

TEST(RoundTrip, RandomPolygonsWithHolesEveryMethod) {
  for (const std::uint64_t seed : {11u, 12u}) {
    for (const Method m : kMethods) expect_round_trip(polygon_with_hole(seed, 1.0), options_for(m, seed == 12));
  }
}

TEST(RoundTrip, RandomCrossingSegmentsEveryMethod) {
  // A unit square with random segments inside it that cross each other: the crossing points are
  // rounded intersections, written and read back like any other vertex.
  for (const std::uint64_t seed : {41u, 42u}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> inside(0.05, 0.95);
    Pslg p;
    p.is_poly = true;
    p.source = "crossing segments (seed " + std::to_string(seed) + ")";
    test::add_ring(p, {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    for (int k = 0; k < 8; ++k) {
      const auto first = static_cast<std::uint32_t>(p.points.size());
      p.points.push_back({inside(rng), inside(rng)});
      p.points.push_back({inside(rng), inside(rng)});
      p.segments.push_back({first, first + 1, 2});
    }
    p.point_markers.assign(p.points.size(), 1);
    for (const Method m : kMethods) expect_round_trip(p, options_for(m, seed == 42));
  }
}

TEST(RoundTrip, FarFromOneEveryMethod) {
  // The same shapes scaled by powers of two towards both ends of the supported range (1e±50): the
  // written decimals have up to 17 significant digits and three-digit exponents.
  for (const int exponent : {-140, 140}) {
    const double scale = std::ldexp(1.0, exponent);
    const Pslg points = points_input(test::scaled_pow2(test::uniform_points(60, 7), exponent),
                                     "uniform(60) * 2^" + std::to_string(exponent));
    for (const Method m : kMethods) {
      expect_round_trip(points, options_for(m, false));
      expect_round_trip(polygon_with_hole(21, scale), options_for(m, true));
    }
  }
}

// The two inputs of issue 36 at the edges of the supported range: a square of side 1e-50 and the
// corners (±1e50, ±1e50) with a point inside.
Pslg tiny_square() {
  Pslg p;
  p.is_poly = true;
  p.source = "tiny_square (side 1e-50)";
  test::add_ring(p, {{0, 0}, {1e-50, 0}, {1e-50, 1e-50}, {0, 1e-50}});
  p.point_markers.assign(p.points.size(), 1);
  return p;
}
Pslg big_square() {
  return points_input({{-1e50, -1e50}, {1e50, -1e50}, {1e50, 1e50}, {-1e50, 1e50}, {3e49, 1e49}},
                      "big1e50 (corners ±1e50)");
}

TEST(RoundTrip, EdgesOfTheRangeEveryMethodButQtr) {
  for (const Method m : {Method::kDt, Method::kDr, Method::kBrh, Method::kOpt}) {
    expect_round_trip(tiny_square(), options_for(m, false));
    expect_round_trip(big_square(), options_for(m, true));
  }
}

TEST(RoundTrip, EdgesOfTheRangeQtr) {
  expect_round_trip(tiny_square(), options_for(Method::kQtr, false));
  expect_round_trip(big_square(), options_for(Method::kQtr, true));
}

// ---- planted faults ----------------------------------------------------------------------------

// The mesh of a polygon with a hole under DR (circumcentres and off-centres: coordinates that need
// all 17 digits), written to PREFIX.*; the faults below are planted in those files.
struct Written {
  Pslg input = polygon_with_hole(31, 1.0);
  Mesh mesh;
  std::string prefix;
  explicit Written(const ScratchDir& dir) : prefix(dir.file("m")) {
    triangulate(input, options_for(Method::kDr, false), &mesh);
    io::write_mesh(mesh, prefix);
  }
  std::vector<std::string> differences() const { return round_trip_differences(mesh, io::read_mesh(prefix)); }
  bool checker_accepts() const {
    const io::MeshFiles back = io::read_mesh(prefix);
    return check_triangulation(input, back.points, back.triangles, back.segments).ok();
  }
};

// The lines of a text (without their '\n').
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string text_of(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

TEST(RoundTripFaults, UntouchedFilesPass) {
  ScratchDir dir;
  const Written w(dir);
  EXPECT_TRUE(w.differences().empty()) << joined(w.differences());
  EXPECT_TRUE(w.checker_accepts());
}

TEST(RoundTripFaults, OneCoordinateOneUlpOffIsCaught) {
  ScratchDir dir;
  const Written w(dir);
  // The last vertex (a Steiner point) with its x coordinate moved by one unit in the last place.
  std::vector<std::string> node = lines_of(read_text(w.prefix + ".node"));
  const std::size_t last = node.size() - 1;
  std::istringstream fields(node[last]);
  std::string index, x, y, marker;
  fields >> index >> x >> y >> marker;
  double value = 0.0;
  std::from_chars(x.data(), x.data() + x.size(), value);
  char moved[32];
  const auto end = std::to_chars(moved, moved + sizeof moved, std::nextafter(value, 1e300)).ptr;
  node[last] = index + " " + std::string(moved, end) + " " + y + " " + marker;
  write_text(w.prefix + ".node", text_of(node));
  const std::vector<std::string> differences = w.differences();
  ASSERT_FALSE(differences.empty());
  EXPECT_NE(differences.front().find("vertex " + index + " reads back as"), std::string::npos) << joined(differences);
}

TEST(RoundTripFaults, FifteenDigitCoordinatesAreCaught) {
  // A writer that printed %.15g (as many do) would lose the last bits of constructed points.
  ScratchDir dir;
  const Written w(dir);
  std::vector<std::string> node = lines_of(read_text(w.prefix + ".node"));
  for (std::size_t i = 1; i < node.size(); ++i) {
    std::istringstream fields(node[i]);
    std::string index, marker;
    double x = 0.0, y = 0.0;
    fields >> index >> x >> y >> marker;
    char line[128];
    std::snprintf(line, sizeof line, "%s %.15g %.15g %s", index.c_str(), x, y, marker.c_str());
    node[i] = line;
  }
  write_text(w.prefix + ".node", text_of(node));
  EXPECT_FALSE(w.differences().empty());
}

TEST(RoundTripFaults, DroppedTriangleIsCaught) {
  ScratchDir dir;
  const Written w(dir);
  std::vector<std::string> ele = lines_of(read_text(w.prefix + ".ele"));
  const std::size_t count = ele.size() - 1;
  ele.pop_back();
  ele[0] = std::to_string(count - 1) + " 3 0";
  write_text(w.prefix + ".ele", text_of(ele));
  const std::vector<std::string> differences = w.differences();
  ASSERT_FALSE(differences.empty());
  EXPECT_NE(joined(differences).find(std::to_string(count - 1) + " triangles read back, " + std::to_string(count) +
                                     " written"),
            std::string::npos)
      << joined(differences);
  EXPECT_FALSE(w.checker_accepts());  // a hole in the mesh
}

TEST(RoundTripFaults, SwappedCornersAreCaught) {
  ScratchDir dir;
  const Written w(dir);
  std::vector<std::string> ele = lines_of(read_text(w.prefix + ".ele"));
  std::istringstream fields(ele[1]);
  std::string index, a, b, c;
  fields >> index >> a >> b >> c;
  ele[1] = index + " " + b + " " + a + " " + c;  // triangle 1 turned clockwise
  write_text(w.prefix + ".ele", text_of(ele));
  const std::vector<std::string> differences = w.differences();
  ASSERT_FALSE(differences.empty());
  EXPECT_NE(differences.front().find("triangle 1 corner 1 reads back as"), std::string::npos) << joined(differences);
  EXPECT_FALSE(w.checker_accepts());
}

TEST(RoundTripFaults, DroppedSubsegmentIsCaught) {
  ScratchDir dir;
  const Written w(dir);
  std::vector<std::string> poly = lines_of(read_text(w.prefix + ".poly"));
  // "0 2 0 1", "S 1", S segment lines, "0".
  ASSERT_GE(poly.size(), 4u);
  const std::size_t segments = poly.size() - 3;
  poly.erase(poly.end() - 2);
  poly[1] = std::to_string(segments - 1) + " 1";
  write_text(w.prefix + ".poly", text_of(poly));
  const std::vector<std::string> differences = w.differences();
  ASSERT_FALSE(differences.empty());
  EXPECT_NE(differences.front().find("subsegments read back"), std::string::npos) << joined(differences);
}

}  // namespace
}  // namespace mwst
