// fuzz/fuzz_triangulate.cpp — libFuzzer harness for the whole mesher (mwst::triangulate of
// mwst/algorithms/pipeline.hpp): bytes are decoded into a small planar straight-line graph (points, segments,
// hole seeds) and options, every method — DT, DR, BRH, QTR, OPT, each optionally followed by the
// weight-reducing flips (EFH) of Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and
// Weight" — is run with a small Steiner budget, and the result must pass validate()
// (mwst/mesh/mesh.hpp, our own structure), then round-trip through the files `mwst triangulate` writes:
// written with io::write_mesh to a scratch directory, read back with io::read_mesh, it must be the
// same mesh bit for bit (tests/support/round_trip.hpp) and pass the independent checker
// check_triangulation() (mwst/mesh/check.hpp) on what was read back, as `mwst check` would run it.
// An InputError from the mesher is an acceptable answer; any other exception, a crash, a sanitizer
// report, a file mwst cannot read back, a difference or a checker violation is a bug (abort).
//
// Decoding. Bytes that parse as a Triangle .poly or .node (the seed corpus is data/) give that
// graph, cut to its first kMaxTextPoints vertices (segments among them, all holes), with options
// drawn from a hash of the bytes. Any other bytes are read as a compact binary form in which
// mutations stay meaningful: byte 0 picks the method and flags, byte 1 the angle, byte 2 the
// Steiner budget, then records until the bytes run out — a tag byte chooses a point on a coarse
// grid (x/4, many collinear and cocircular 4-tuples, duplicates, vertices on segments), a point
// from raw double bits (huge, tiny, NaN, out of range), a segment between two earlier points, a
// hole seed, a point a few units in the last place from an earlier one, or a shift of everything so
// far by a power of two (the same shapes far from the origin, where grid coordinates round).
// Coarse-grid data is what stresses the exact predicates most.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/mesh/pslg.hpp"
#include "../tests/support/round_trip.hpp"

namespace {

constexpr std::size_t kMaxPoints = 96;
constexpr std::size_t kMaxSegments = 96;
constexpr std::size_t kMaxHoles = 4;
constexpr std::size_t kMaxTextPoints = 64;  // keeps each run of every method fast under ASan
constexpr std::size_t kMaxBundleTriangles = 1000;  // exact bundle numbers only of meshes this small

class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  double raw_double() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits = (bits << 8) | byte();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  // A coordinate on the grid {-32, -31.75, ..., 31.75}: exact, and dense in degeneracies.
  double grid() { return static_cast<double>(static_cast<std::int8_t>(byte())) / 4.0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// x moved by `steps` units in the last place (towards +∞ if positive): pairs of points this close
// make the quadtree as deep as it goes and the predicates' exact stages decide.
double ulps_away(double x, int steps) {
  for (; steps > 0; --steps) x = std::nextafter(x, std::numeric_limits<double>::infinity());
  for (; steps < 0; ++steps) x = std::nextafter(x, -std::numeric_limits<double>::infinity());
  return x;
}

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_triangulate: %s: %s\n", what, detail.c_str());
  std::fflush(stderr);
  std::abort();
}

// A directory of this process for the written meshes (removed at exit; one per process, so that
// libFuzzer's -jobs and -fork workers do not share it).
const std::string& scratch_prefix() {
  static const std::string prefix = [] {
    std::string dir = (std::filesystem::temp_directory_path() / "mwst-fuzz-XXXXXX").string();
    if (::mkdtemp(dir.data()) == nullptr) fail("mkdtemp", dir);
    static const std::string removed_at_exit = dir;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(removed_at_exit, ec);
    });
    return dir + "/mesh";
  }();
  return prefix;
}

// The round trip: write the mesh as `mwst triangulate` does, read it back as `mwst check` does,
// compare, and check what was read back against the input.
void check_round_trip(const mwst::Pslg& input, const mwst::Mesh& mesh) {
  const std::string& prefix = scratch_prefix();
  std::filesystem::remove(prefix + ".poly");  // a mesh without subsegments writes none
  mwst::io::MeshFiles back;
  try {
    mwst::io::write_mesh(mesh, prefix);
    back = mwst::io::read_mesh(prefix);
  } catch (const mwst::InputError& e) {
    fail("mwst cannot read back what it wrote", e.located());
  }
  const std::vector<std::string> differences = mwst::test::round_trip_differences(mesh, back, 1);
  if (!differences.empty()) fail("read back differs", differences.front());
  const mwst::CheckResult check = mwst::check_triangulation(input, back.points, back.triangles, back.segments);
  if (!check.ok()) fail("check_triangulation", check.messages.empty() ? "?" : check.messages.front());
}

// The bytes as a Triangle file, if they are one (a .poly whose vertices are in a .node beside it
// is an error here: the name points into a directory that does not exist).
bool parse_text(const std::uint8_t* data, std::size_t size, mwst::Pslg& out) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    out = mwst::io::parse_poly(text, "/nonexistent-mwst-fuzz/fuzz.poly");
    return true;
  } catch (const mwst::InputError&) {
  }
  try {
    out = mwst::io::parse_node(text, "/nonexistent-mwst-fuzz/fuzz.node");
    return true;
  } catch (const mwst::InputError&) {
  }
  return false;
}

// Keeps the first kMaxTextPoints vertices and the segments among them (a big data set would make
// every run of every method slow; the shapes of its first part are what matters here).
void cut(mwst::Pslg& p) {
  if (p.points.size() <= kMaxTextPoints) return;
  p.points.resize(kMaxTextPoints);
  p.point_markers.resize(kMaxTextPoints);
  std::vector<mwst::Segment> kept;
  std::vector<std::size_t> lines;
  for (std::size_t i = 0; i < p.segments.size(); ++i) {
    if (p.segments[i].a < kMaxTextPoints && p.segments[i].b < kMaxTextPoints) {
      kept.push_back(p.segments[i]);
      if (i < p.segment_lines.size()) lines.push_back(p.segment_lines[i]);
    }
  }
  p.segments = std::move(kept);
  p.segment_lines = std::move(lines);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mwst::Pslg pslg;
  const bool text = parse_text(data, size, pslg);
  std::uint8_t mode = 0, angle_byte = 0, budget_byte = 0;
  Bytes in(data, text ? 0 : size);
  if (text) {
    cut(pslg);
    std::uint32_t hash = 2166136261u;  // FNV-1a of the whole text
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 16777619u;
    mode = static_cast<std::uint8_t>(hash);
    angle_byte = static_cast<std::uint8_t>(hash >> 8);
    budget_byte = static_cast<std::uint8_t>(hash >> 16);
  } else {
    mode = in.byte();
    angle_byte = in.byte();
    budget_byte = in.byte();
    pslg.source = "fuzz.poly";
    pslg.first_index = 1;
  }

  mwst::TriangulateOptions options;
  static constexpr mwst::Method kMethods[] = {mwst::Method::kDt, mwst::Method::kDr, mwst::Method::kBrh,
                                              mwst::Method::kQtr, mwst::Method::kOpt};
  options.method = kMethods[mode % 5];
  options.flip = (mode & 0x08) != 0;
  options.convex_hull = (mode & 0x10) != 0;
  options.strict = (mode & 0x20) != 0;
  options.steiner = (mode & 0x40) != 0 ? mwst::SteinerRule::kCircumcenter : mwst::SteinerRule::kOffCenter;
  // The exact bundle number (--bundle) is costly on a mesh of thousands of triangles, which a
  // refinement of a few points can make (QTR of four points, two of them an ulp apart: 23 710
  // triangles, 4 s in a release build, past libFuzzer's 60 s here): it is computed below, on
  // meshes of at most kMaxBundleTriangles, with the same bundle_number() the pipeline calls.
  const bool bundle = (mode & 0x80) != 0 && !text && options.method != mwst::Method::kOpt;
  static constexpr double kAngles[] = {20.0, 5.0, 10.0, 15.0, 25.0, 28.0, 30.0, 33.0};
  options.min_angle_deg = kAngles[angle_byte % 8];
  if ((angle_byte & 0x08) != 0 && options.method != mwst::Method::kBrh) options.min_angle_deg = 0.0;
  if ((angle_byte & 0x10) != 0) options.max_area = 1.0 + (angle_byte >> 5);
  options.max_steiner = budget_byte % 48;
  options.time_budget_seconds = 2.0;  // a safety net; max_steiner is the real budget
  // The time budget also stops opt's searches, but a run cut by it depends on the machine's speed:
  // opt's iterated local search counts trials, up to 600 per start by default (on a 64-vertex
  // seed 6 s in a release build, far past the budget under the sanitizers). A few trials reach
  // every move and kick of the search, and mostly finish within the budget; how many is up to the
  // bytes.
  options.opt_trials = budget_byte >> 6;
  // QTR's tree grows with the integral of 1/lfs², not with the input: four points, two of them 0.5
  // apart at one end of a hull 92 000 long, made 1.27M triangles (2.8 s in a release build; with
  // the flips and both checkers past libFuzzer's 60 s here). A limit of 2^16 leaves (about 150 000
  // triangles) keeps every run short and sends such inputs down the fallback, which gets tested too.
  options.quadtree_max_leaves = std::size_t{1} << 16;

  while (!in.empty()) {
    const std::uint8_t tag = in.byte();
    const unsigned kind = tag % 16;
    if (kind < 8) {  // a grid point
      if (pslg.points.size() >= kMaxPoints) continue;
      const double x = in.grid();
      const double y = in.grid();
      pslg.points.push_back({x, y});
      pslg.point_markers.push_back(0);
    } else if (kind == 8) {  // a point from raw bits (only the reader filters the range)
      if (pslg.points.size() >= kMaxPoints) continue;
      const double x = in.raw_double();
      const double y = in.raw_double();
      pslg.points.push_back({x, y});
      pslg.point_markers.push_back(0);
    } else if (kind < 14) {  // a segment between two earlier points (the reader checks indices)
      const std::uint8_t a = in.byte();
      const std::uint8_t b = in.byte();
      if (pslg.points.empty() || pslg.segments.size() >= kMaxSegments) continue;
      const auto n = static_cast<std::uint32_t>(pslg.points.size());
      pslg.segments.push_back({a % n, b % n, 1 + (tag >> 6)});
      pslg.segment_lines.push_back(pslg.segments.size());
      pslg.is_poly = true;
    } else if (kind == 14) {  // a hole seed on the half grid
      const double x = in.grid() + 0.125;
      const double y = in.grid() + 0.125;
      if (pslg.holes.size() < kMaxHoles) pslg.holes.push_back({x, y});
      pslg.is_poly = true;
    } else if ((tag & 0x10) == 0) {  // a point a few units in the last place from an earlier one
      const std::uint8_t which = in.byte();
      const auto dx = static_cast<std::int8_t>(in.byte());
      const auto dy = static_cast<std::int8_t>(in.byte());
      if (pslg.points.empty() || pslg.points.size() >= kMaxPoints) continue;
      const mwst::Point p = pslg.points[which % pslg.points.size()];
      pslg.points.push_back({ulps_away(p.x, dx), ulps_away(p.y, dy)});
      pslg.point_markers.push_back(0);
    } else {  // everything so far moved by ±2^e, e in [-16, 47]: the same shapes far from the origin
      const std::uint8_t e = in.byte();
      const double shift = std::ldexp((e & 0x80) != 0 ? -1.0 : 1.0, static_cast<int>(e % 64) - 16);
      for (mwst::Point& p : pslg.points) p = {p.x + shift, p.y + shift};
      for (mwst::Point& h : pslg.holes) h = {h.x + shift, h.y + shift};
    }
  }

  mwst::Mesh mesh;
  try {
    mwst::triangulate(pslg, options, &mesh);
  } catch (const mwst::InputError&) {
    return 0;
  } catch (const std::exception& e) {
    fail("triangulate threw", e.what());
  }
  const std::vector<std::string> problems = mwst::validate(mesh);
  if (!problems.empty()) fail("validate", problems.front());
  if (bundle && mesh.domain_triangle_count() <= kMaxBundleTriangles) {
    const mwst::BundleResult b = mwst::bundle_number(mesh);
    // Every triangle is a 1-bundle (its inscribed disk); the circumdisk bound is a lower bound.
    if (mesh.domain_triangle_count() > 0 && (b.bundle_number < 1 || b.circumdisk_bound > b.bundle_number)) {
      fail("bundle_number", std::to_string(b.bundle_number) + " with circumdisk bound " +
                                std::to_string(b.circumdisk_bound));
    }
  }
  try {
    check_round_trip(pslg, mesh);
  } catch (const std::exception& e) {
    fail("round trip or check_triangulation threw", e.what());
  }
  return 0;
}
