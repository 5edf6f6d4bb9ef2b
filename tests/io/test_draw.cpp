// tests/io/test_draw.cpp — the picture renderer (mwst/io/draw.hpp, src/io/draw.cpp) and `mwst draw`:
//   - picture_of(Mesh) marks exactly the Steiner points measure() counts and draws bold exactly the
//     boundary and segment edges; picture_of(MeshFiles, Pslg) of the same mesh written and read back
//     agrees with it (same triangles, same Steiner points, every input segment bold);
//   - PNG, SVG and PDF files are written (non-empty, with their format's signature), panels side by
//     side make a proportionally wider image, notes for missing meshes render;
//   - a bad extension is an InputError and leaves no file; `mwst draw` writes a PNG and refuses a
//     bad extension with exit code 2.
#include <dlfcn.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/io/draw.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace {

namespace fs = std::filesystem;
using mwst::Point;

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh temporary directory per test.
class TempDir {
 public:
  TempDir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::path(testing::TempDir()) /
            ("mwst_draw_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  std::string path(const std::string& name) const { return (root_ / name).string(); }
  const fs::path& root() const { return root_; }

 private:
  fs::path root_;
};

// An L-shaped polygon with a square hole: segments, a concavity, a hole.
mwst::Pslg l_shape() {
  mwst::Pslg p;
  p.points = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4},  // the L
              {0.25, 0.25}, {0.75, 0.25}, {0.75, 0.75}, {0.25, 0.75}};  // the hole
  for (std::uint32_t i = 0; i < 6; ++i) p.segments.push_back({i, (i + 1) % 6, 1});
  for (std::uint32_t i = 0; i < 4; ++i) p.segments.push_back({6 + i, 6 + (i + 1) % 4, 2});
  p.holes = {{0.5, 0.5}};
  p.is_poly = true;
  p.source = "l_shape";
  return p;
}

// The refined L: DR at 25° puts Steiner points inside and on the segments.
mwst::Mesh refined_l_shape() {
  mwst::TriangulateOptions o;
  o.method = mwst::Method::kDr;
  o.min_angle_deg = 25.0;
  mwst::Mesh mesh;
  mwst::triangulate(l_shape(), o, &mesh);
  return mesh;
}

using Edge = std::pair<Point, Point>;
bool point_less(const Point& a, const Point& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }
Edge normalised_edge(const Point& a, const Point& b) { return point_less(a, b) ? Edge{a, b} : Edge{b, a}; }
struct EdgeLess {
  bool operator()(const Edge& a, const Edge& b) const {
    if (a.first != b.first) return point_less(a.first, b.first);
    return point_less(a.second, b.second);
  }
};

TEST(PictureOfMesh, MarksTheSteinerPointsAndDrawsBoundaryAndSegmentsBold) {
  const mwst::Mesh mesh = refined_l_shape();
  ASSERT_TRUE(mwst::validate(mesh).empty());
  const mwst::Metrics m = mwst::measure(mesh);
  ASSERT_GT(m.steiner, 0u) << "the test needs Steiner points";
  const mwst::io::Picture pic = mwst::io::picture_of(mesh);
  EXPECT_EQ(pic.triangles.size(), m.triangles);
  EXPECT_EQ(pic.marked.size(), m.steiner);
  for (const std::uint32_t v : pic.marked) {
    ASSERT_LT(v, mesh.vertex_kind.size());
    EXPECT_TRUE(mesh.vertex_kind[v] == mwst::VertexKind::kSteiner ||
                mesh.vertex_kind[v] == mwst::VertexKind::kSteinerOnSegment);
  }
  // The bold edges weigh exactly the boundary weight measure() reports, and each appears once.
  double bold_weight = 0.0;
  std::set<Edge, EdgeLess> seen;
  for (const auto& s : pic.bold_segments) {
    bold_weight += mwst::distance(s[0], s[1]);
    EXPECT_TRUE(seen.insert(normalised_edge(s[0], s[1])).second) << "an edge is drawn bold twice";
  }
  EXPECT_NEAR(bold_weight, m.weight_boundary, 1e-9 * m.weight_boundary);
}

TEST(PictureOfMeshFiles, AgreesWithThePictureOfTheMeshItWasWrittenFrom) {
  TempDir dir;
  const mwst::Pslg input = l_shape();
  const mwst::Mesh mesh = refined_l_shape();
  mwst::io::write_mesh(mesh, dir.path("l"), 1);
  const mwst::io::MeshFiles files = mwst::io::read_mesh(dir.path("l"));
  const mwst::io::Picture from_mesh = mwst::io::picture_of(mesh);
  const mwst::io::Picture from_files = mwst::io::picture_of(files, input);
  EXPECT_EQ(from_files.triangles.size(), from_mesh.triangles.size());

  std::set<std::pair<double, double>> marked_mesh, marked_files;
  for (const auto v : from_mesh.marked) marked_mesh.insert({from_mesh.points[v].x, from_mesh.points[v].y});
  for (const auto v : from_files.marked) marked_files.insert({from_files.points[v].x, from_files.points[v].y});
  EXPECT_EQ(marked_files, marked_mesh);

  // Every boundary edge of the mesh and every input segment is bold in the file picture.
  std::set<Edge, EdgeLess> bold;
  for (const auto& s : from_files.bold_segments) bold.insert(normalised_edge(s[0], s[1]));
  for (const auto& s : from_mesh.bold_segments) {
    EXPECT_TRUE(bold.contains(normalised_edge(s[0], s[1])))
        << "boundary edge (" << s[0].x << "," << s[0].y << ")-(" << s[1].x << "," << s[1].y << ") not bold";
  }
  for (const mwst::Segment& s : input.segments) {
    EXPECT_TRUE(bold.contains(normalised_edge(input.points[s.a], input.points[s.b])));
  }
}

TEST(DrawPictures, WritesPngSvgAndPdfWithTheirSignatures) {
  TempDir dir;
  mwst::io::Picture pic = mwst::io::picture_of(refined_l_shape());
  pic.title = "refined L, 25°";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"mesh.png", std::string("\x89PNG\r\n\x1a\n", 8)},
      {"mesh.svg", "<?xml"},
      {"mesh.pdf", "%PDF-"},
      {"MESH.PNG", std::string("\x89PNG\r\n\x1a\n", 8)},  // the extension in any letter case
  };
  for (const auto& [name, signature] : cases) {
    mwst::io::draw_pictures({pic}, dir.path(name));
    ASSERT_TRUE(fs::exists(dir.path(name))) << name;
    const std::string bytes = read_bytes(dir.path(name));
    EXPECT_GT(bytes.size(), 100u) << name;
    EXPECT_EQ(bytes.substr(0, signature.size()), signature) << name;
  }
  EXPECT_NE(read_bytes(dir.path("mesh.svg")).find("<svg"), std::string::npos);
  // Only the pictures: no temporary files left behind.
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.root())) {
    (void)e;
    ++entries;
  }
  EXPECT_EQ(entries, cases.size());
}

// Width and height of a PNG from its IHDR chunk.
std::pair<std::uint32_t, std::uint32_t> png_size(const std::string& png) {
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t(std::uint8_t(png[at])) << 24) | (std::uint32_t(std::uint8_t(png[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(png[at + 2])) << 8) | std::uint32_t(std::uint8_t(png[at + 3]));
  };
  return {be32(16), be32(20)};
}

TEST(DrawPictures, PanelsSideBySideAndInRows) {
  mwst::io::Picture pic = mwst::io::picture_of(refined_l_shape());
  pic.title = "DR";  // every panel has a title band when one has
  mwst::io::Picture missing;
  missing.title = "BRH";
  missing.note = "NA: method brh is not implemented yet";
  mwst::io::DrawOptions o;
  o.panel_size = 200.0;
  const auto one = png_size(mwst::io::render_pictures({pic}, mwst::io::PictureFormat::kPng, o));
  const auto three = png_size(mwst::io::render_pictures({pic, missing, pic}, mwst::io::PictureFormat::kPng, o));
  o.columns = 2;
  const auto grid = png_size(mwst::io::render_pictures({pic, missing, pic}, mwst::io::PictureFormat::kPng, o));
  EXPECT_GT(one.first, 200u);
  EXPECT_NEAR(double(three.first), 3.0 * one.first, 3.0);
  EXPECT_EQ(three.second, one.second);
  EXPECT_NEAR(double(grid.first), 2.0 * one.first, 2.0);
  EXPECT_NEAR(double(grid.second), 2.0 * one.second, 2.0);
  // The L is as tall as it is wide: a square drawing area.
  EXPECT_GE(one.second, one.first);
}

TEST(DrawPictures, RejectsAnUnknownExtensionAndWritesNothing) {
  TempDir dir;
  const mwst::io::Picture pic = mwst::io::picture_of(refined_l_shape());
  for (const std::string name : {"mesh.jpg", "mesh", "mesh.png.txt", "dir.png/mesh"}) {
    EXPECT_THROW(mwst::io::draw_pictures({pic}, dir.path(name)), mwst::InputError) << name;
  }
  EXPECT_THROW(mwst::io::picture_format("mesh.gif"), mwst::InputError);
  EXPECT_EQ(mwst::io::picture_format("a.b/mesh.Pdf"), mwst::io::PictureFormat::kPdf);
  EXPECT_THROW(mwst::io::render_pictures({}, mwst::io::PictureFormat::kPng), mwst::InputError);
  EXPECT_TRUE(fs::is_empty(dir.root()));
}

// cairo is not linked (neither into this test program nor into mwst_draw): the first drawing loads
// libcairo.so.2. Checked in a fresh process (the threadsafe death-test style re-runs this test
// alone), where no other test has drawn yet: not loaded before render_pictures, loaded after.
TEST(DrawPictures, LoadsCairoOnlyWhenTheFirstPictureIsDrawn) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        const auto loaded = [] { return ::dlopen("libcairo.so.2", RTLD_LAZY | RTLD_NOLOAD) != nullptr; };
        const bool before = loaded();
        const std::string png =
            mwst::io::render_pictures({mwst::io::picture_of(refined_l_shape())}, mwst::io::PictureFormat::kPng);
        std::exit(!before && loaded() && png.substr(1, 3) == "PNG" ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

// ---- the command line --------------------------------------------------------------------------

int run_mwst(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> storage = {MWST_BINARY};
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : storage) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || ::dup2(fd, 1) < 0 || ::dup2(fd, 2) < 0) ::_exit(127);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  if (pid < 0 || ::waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

TEST(DrawCommand, DrawsAMeshAndRefusesABadExtension) {
  TempDir dir;
  const std::string input = std::string(MWST_DATA_DIR) + "/Africa.poly";
  const fs::path log = dir.root() / "log";
  ASSERT_EQ(run_mwst({"triangulate", input, "--method", "dr", "-o", dir.path("africa"), "-q"}, log), 0)
      << read_bytes(log);
  ASSERT_EQ(run_mwst({"draw", input, dir.path("africa"), "-o", dir.path("africa.png")}, log), 0) << read_bytes(log);
  const std::string png = read_bytes(dir.path("africa.png"));
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  ASSERT_EQ(run_mwst({"draw", input, dir.path("africa"), "-o", dir.path("africa.svg"), "--title", ""}, log), 0);
  EXPECT_EQ(read_bytes(dir.path("africa.svg")).substr(0, 5), "<?xml");

  EXPECT_EQ(run_mwst({"draw", input, dir.path("africa"), "-o", dir.path("africa.jpg")}, log), 2);
  EXPECT_FALSE(fs::exists(dir.path("africa.jpg")));
  // A missing mesh is bad input (exit 1), and no picture is left.
  EXPECT_EQ(run_mwst({"draw", input, dir.path("nothing"), "-o", dir.path("nothing.png")}, log), 1);
  EXPECT_FALSE(fs::exists(dir.path("nothing.png")));
}

}  // namespace
