// tests/io/test_io.cpp — tests of src/io/triangle_read.cpp, triangle_write.cpp and src/io/atomic_file.cpp (mwst/io/triangle_files.hpp):
// Triangle's .node/.poly/.ele readers (bases, comments, attributes, markers, regions, every error
// with its line number), the mesh writer (bit-exact round trip, subsegments once, atomic files),
// and every data set in MWST_DATA_DIR against the counts in its header comment.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"

#include "support/regression_files.hpp"

namespace {

namespace fs = std::filesystem;
using mwst::InputError;
using mwst::Pslg;
using mwst::io::parse_node;
using mwst::io::parse_poly;

// A fresh directory under the test temporary directory, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::path(testing::TempDir()) /
            ("mwst_io_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Runs f, expects an InputError at `line` whose message contains `needle`.
void expect_error(const std::function<void()>& f, std::size_t line, const std::string& needle,
                  const std::string& file = "t") {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected line " << line << ": " << needle;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.located();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << "message: " << e.located() << "\nexpected to contain: " << needle;
    EXPECT_EQ(e.file(), file) << e.located();
  }
}

void node_error(const std::string& text, std::size_t line, const std::string& needle) {
  SCOPED_TRACE(text);
  expect_error([&] { parse_node(text, "t"); }, line, needle);
}

void poly_error(const std::string& text, std::size_t line, const std::string& needle) {
  SCOPED_TRACE(text);
  expect_error([&] { parse_poly(text, "t"); }, line, needle);
}

// ---- reading: the good cases ---------------------------------------------------------------

TEST(IoNode, OneBased) {
  const Pslg p = parse_node("3 2 0 0\n1 0 0\n2 1.5 -2\n3 0.1 1e10\n", "a.node");
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_EQ(p.first_index, 1);
  EXPECT_FALSE(p.is_poly);
  EXPECT_EQ(p.source, "a.node");
  EXPECT_EQ(p.points[1], (mwst::Point{1.5, -2.0}));
  EXPECT_TRUE(same_bits(p.points[2].x, 0.1));
  EXPECT_EQ(p.points[2].y, 1e10);
  ASSERT_EQ(p.point_markers.size(), 3u);
  EXPECT_EQ(p.point_markers[0], 0);
  EXPECT_TRUE(p.segments.empty());
}

TEST(IoNode, ZeroBased) {
  const Pslg p = parse_node("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n", "t");
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_EQ(p.first_index, 0);
  EXPECT_EQ(p.points[2], (mwst::Point{0.0, 1.0}));
}

TEST(IoNode, CommentsBlankLinesAndWhitespace) {
  const std::string text =
      "# a comment\n"
      "\n"
      "   \t\n"
      "3 2 0 0   # header comment\r\n"
      "#1 9 9\n"
      "1\t0 0#glued comment\r\n"
      "\n"
      "  2   +1   .5   \n"
      "# trailing\n"
      "3 5. -0x1.8p1\n"
      "# the end";
  const Pslg p = parse_node(text, "t");
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_EQ(p.points[0], (mwst::Point{0.0, 0.0}));
  EXPECT_EQ(p.points[1], (mwst::Point{1.0, 0.5}));
  EXPECT_EQ(p.points[2], (mwst::Point{5.0, -3.0}));
}

TEST(IoNode, NoTrailingNewline) {
  const Pslg p = parse_node("1 2 0 0\n1 3 4", "t");
  ASSERT_EQ(p.points.size(), 1u);
  EXPECT_EQ(p.points[0], (mwst::Point{3.0, 4.0}));
}

TEST(IoNode, HeaderDefaults) {
  // Triangle's defaults: dimension 2, no attributes, no markers.
  const Pslg p = parse_node("2\n1 0 0\n2 1 1\n", "t");
  EXPECT_EQ(p.points.size(), 2u);
}

TEST(IoNode, AttributesAndMarkers) {
  const Pslg p = parse_node(
      "4 2 2 1\n"
      "1 0 0 0.5 -7 3\n"
      "2 1 0 1e300 2 -4\n"
      "3 1 1 1 2\n"     // marker missing: 0
      "4 0 1\n",        // attributes and marker missing (tolerated, as Triangle does)
      "t");
  ASSERT_EQ(p.points.size(), 4u);
  EXPECT_EQ(p.point_markers, (std::vector<std::int32_t>{3, -4, 0, 0}));
  EXPECT_EQ(p.points[1], (mwst::Point{1.0, 0.0}));
}

TEST(IoNode, ExtraNumbersIgnored) {
  // Numbers beyond those the header announces are ignored, as in Triangle (which reads them as
  // attributes it does not need); words are not (IoNodeErrors.WordsAfterTheFields).
  const Pslg p = parse_node("2 2 0 0 5\n1 0 0 7 8\n2 1 1 -inf 0x1p3 1e999 # comment\n", "t");
  EXPECT_EQ(p.points.size(), 2u);
  EXPECT_EQ(p.point_markers[0], 0);
  EXPECT_EQ(p.points[1], (mwst::Point{1.0, 1.0}));
}

TEST(IoNode, LineEndings) {
  // "\n", "\r\n" and a lone "\r" each end a line, mixed in one file too.
  const std::string lf = "# c\n3 2 0 0\n1 0 0\n\n2 1 0.5\n3 0 1\n";
  for (const std::string& eol : {std::string("\r\n"), std::string("\r")}) {
    std::string text;
    for (const char c : lf) text += c == '\n' ? eol : std::string(1, c);
    const Pslg p = parse_node(text, "t");
    ASSERT_EQ(p.points.size(), 3u);
    EXPECT_EQ(p.points[1], (mwst::Point{1.0, 0.5}));
  }
  const Pslg mixed = parse_node("3 2 0 0\r1 0 0\r\n2 1 0.5\n\r3 0 1", "t");
  ASSERT_EQ(mixed.points.size(), 3u);
  EXPECT_EQ(mixed.points[2], (mwst::Point{0.0, 1.0}));
}

TEST(IoNode, ByteOrderMarkSkipped) {
  const Pslg p = parse_node("\xEF\xBB\xBF" "2 2 0 0\n1 0 0\n2 1 1\n", "t");
  EXPECT_EQ(p.points.size(), 2u);
  const Pslg q = parse_poly("\xEF\xBB\xBF" "# comment\r2 2 0 0\r1 0 0\r2 1 1\r1 0\r1 1 2\r", "t");
  EXPECT_EQ(q.segments.size(), 1u);
}

TEST(IoNode, ZeroAndRangeLimits) {
  const Pslg p = parse_node("5 2 0 0\n1 0 -0\n2 1e-50 -1e-50\n3 1e50 -1e50\n4 0.000 0e99\n5 0x0p0 -0.0e-400\n", "t");
  ASSERT_EQ(p.points.size(), 5u);
  EXPECT_TRUE(same_bits(p.points[0].y, -0.0));
  EXPECT_EQ(p.points[1].x, mwst::kMinCoordinate);
  EXPECT_EQ(p.points[2].y, -mwst::kMaxCoordinate);
  EXPECT_EQ(p.points[3], (mwst::Point{0.0, 0.0}));
  EXPECT_EQ(p.points[4], (mwst::Point{0.0, 0.0}));
}

TEST(IoNode, EmptyPointSetIsAllowed) {
  const Pslg p = parse_node("0 2 0 0\n", "t");
  EXPECT_TRUE(p.points.empty());
}

// ---- reading: errors, each with its line -------------------------------------------------------

TEST(IoNodeErrors, EmptyAndCommentsOnly) {
  expect_error([] { parse_node("", "t"); }, 0, "empty file");
  node_error("# nothing\n\n   \n# here\n", 4, "no data");
}

TEST(IoNodeErrors, Truncated) {
  node_error("3 2 0 0\n1 0 0\n2 1 0\n", 3, "expected 3 vertices, found 2");
  node_error("3 2 0 0\n1 0 0\n2 1 0\n# comment\n\n", 5, "expected 3 vertices, found 2");
  node_error("2 2 0 0\n", 1, "more than the rest of the file");
}

TEST(IoNodeErrors, NonNumeric) {
  node_error("2 2 0 0\n1 0 0\n2 abc 0\n", 3, "expected a number for the x coordinate, found 'abc'");
  node_error("2 2 0 0\n1 0 0\n2 1 1.5x\n", 3, "found '1.5x'");   // trailing garbage
  node_error("2 2 0 0\n1 0 0\n2 1 1,5\n", 3, "found '1,5'");
  node_error("2 2 0 0\n1 0 0\n2 1 --1\n", 3, "found '--1'");
  node_error("2 2 0 0\n1 0 0\n2 1 +-1\n", 3, "found '+-1'");
  node_error("2 2 0 0\n1 0 0\n2 1 0x\n", 3, "found '0x'");
  node_error("2 2 0 0\n1 0 0\n2 1 1e\n", 3, "found '1e'");
  node_error("2 2 0 0\n1 0 0\n2 1 .\n", 3, "found '.'");
  node_error(std::string("2 2 0 0\n1 0 0\n2 1 \x01\xff\n"), 3, "found '\\x01\\xff'");
  node_error("x 2 0 0\n", 1, "expected an integer for the vertex count, found 'x'");
  node_error("2.0 2 0 0\n1 0 0\n2 1 1\n", 1, "expected an integer");
  node_error("2 2 0 0\n1.0 0 0\n2 1 1\n", 2, "expected an integer for the index");
  node_error("2 2 0 1\n1 0 0 1\n2 1 1 1.5\n", 3, "expected an integer for the boundary marker");
  node_error("2 2 1 0\n1 0 0 1\n2 1 1 zz\n", 3, "expected a number for the attribute, found 'zz'");
}

TEST(IoNodeErrors, MissingFields) {
  node_error("2 2 0 0\n1 0 0\n2 1\n", 3, "vertex 2: missing y coordinate");
  node_error("2 2 0 0\n1 0 0\n2\n", 3, "vertex 2: missing x coordinate");
  node_error("2 2 0 0\n1 0 0\n2 # 1 1\n", 3, "vertex 2: missing x coordinate");
}

TEST(IoNodeErrors, NonFinite) {
  node_error("2 2 0 0\n1 0 0\n2 nan 0\n", 3, "non-finite coordinate 'nan'");
  node_error("2 2 0 0\n1 0 0\n2 0 -inf\n", 3, "non-finite coordinate '-inf'");
  node_error("2 2 0 0\n1 0 0\n2 0 Infinity\n", 3, "non-finite coordinate");
  node_error("2 2 0 0\n1 0 0\n2 NaN(1) 0\n", 3, "non-finite coordinate");
  node_error("2 2 1 0\n1 0 0 inf\n2 1 1\n", 2, "not a finite double");
}

TEST(IoNodeErrors, OutsideSupportedRange) {
  const std::string range = "0 or a magnitude between 1e-50 and 1e50";
  node_error("2 2 0 0\n1 0 0\n2 1e51 0\n", 3, "'1e51' is outside the supported range (" + range + ")");
  node_error("2 2 0 0\n1 0 0\n2 0 -1.0000000000000002e50\n", 3, range);
  node_error("2 2 0 0\n1 0 0\n2 9.99e-51 0\n", 3, range);
  node_error("2 2 0 0\n1 0 0\n2 5e-324 0\n", 3, range);                   // smallest subnormal
  node_error("2 2 0 0\n1 0 0\n2 2.2250738585072009e-308 0\n", 3, range);  // largest subnormal
  node_error("2 2 0 0\n1 0 0\n2 2.2250738585072014e-308 0\n", 3, range);  // smallest normal
  node_error("2 2 0 0\n1 0 0\n2 1e-400 0\n", 3, range);                   // underflows to 0
  node_error("2 2 0 0\n1 0 0\n2 -0x1p-2000 0\n", 3, range);
  node_error("2 2 0 0\n1 0 0\n2 1e400 0\n", 3, range);                    // overflows
  node_error("2 2 0 0\n1 0 0\n2 0x1p200 0\n", 3, range);
}

TEST(IoNodeErrors, HeaderProblems) {
  node_error("2 3 0 0\n1 0 0 0\n2 1 1 1\n", 1, "dimension must be 2, found 3");
  node_error("2 1 0 0\n1 0\n2 1\n", 1, "dimension must be 2");
  node_error("-1 2 0 0\n", 1, "negative vertex count -1");
  node_error("2 2 -1 0\n1 0 0\n2 1 1\n", 1, "negative attribute count");
  node_error("2 2 0 -1\n1 0 0\n2 1 1\n", 1, "negative marker count");
  node_error("1000000000 2 0 0\n1 0 0\n2 1 1\n", 1, "vertex count 1000000000 is more than the rest of the file can hold");
  node_error("99999999999999999999 2 0 0\n", 1, "'99999999999999999999' is out of range");
}

TEST(IoNodeErrors, Indices) {
  node_error("2 2 0 0\n2 0 0\n3 1 1\n", 2, "the first vertex index must be 0 or 1, found 2");
  node_error("2 2 0 0\n-1 0 0\n0 1 1\n", 2, "must be 0 or 1, found -1");
  node_error("3 2 0 0\n1 0 0\n3 1 1\n2 0 1\n", 3, "vertex index 3 out of sequence: expected 2");
  node_error("3 2 0 0\n0 0 0\n1 1 1\n1 0 1\n", 4, "vertex index 1 out of sequence: expected 2");
  node_error("2 2 0 1\n1 0 0 3000000000\n2 1 1\n", 2, "boundary marker 3000000000 is out of range");
}

TEST(IoNodeErrors, WordsAfterTheFields) {
  node_error("2 2 0 0\n1 0 0\n2 1 1 x\n", 3, "vertex 2: unexpected 'x' after its fields");
  node_error("2 2 0 0\n1 0 0 zzz\n2 1 1\n", 2, "vertex 1: unexpected 'zzz' after its fields");
  node_error("2 2 1 1\n1 0 0 0.5 1 7 word\n2 1 1\n", 2, "vertex 1: unexpected 'word'");
  node_error("2 2 0 0 vertices\n1 0 0\n2 1 1\n", 1, "header: unexpected 'vertices' after its fields");
  node_error("2 2 0 0\n1 0 0 1.5x\n2 1 1\n", 2, "unexpected '1.5x'");
  const std::string v = "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n";  // lines 1-4
  poly_error(v + "1 0 segments\n1 1 2\n", 5, "the segment header: unexpected 'segments'");
  poly_error(v + "1 0\n1 1 2 q\n", 6, "segment 1: unexpected 'q'");
  poly_error(v + "1 1\n1 1 2 3 q\n", 6, "segment 1: unexpected 'q'");
  poly_error(v + "0 0\n1 holes\n1 0.2 0.2\n", 6, "the hole header: unexpected 'holes'");
  poly_error(v + "0 0\n1\n1 0.2 0.2 here\n", 7, "hole 1: unexpected 'here'");
  poly_error(v + "0 0\n0\n1 r\n1 0.2 0.2 1 0.1\n", 7, "the region header: unexpected 'r'");
  poly_error(v + "0 0\n0\n1\n1 0.2 0.2 1 0.1 big\n", 8, "region 1: unexpected 'big'");
  // Numbers there are accepted.
  const Pslg p = parse_poly(v + "1 0 9\n1 1 2 5 6\n1 9\n1 0.2 0.2 3\n1\n1 0.2 0.2 1 0.1 7\n", "t");
  EXPECT_EQ(p.segments.size(), 1u);
  EXPECT_EQ(p.holes.size(), 1u);
  EXPECT_EQ(p.regions.size(), 1u);
}

TEST(IoNodeErrors, LinesAreCountedWhateverTheirEnding) {
  // The same error (vertex 3's y coordinate missing, on line 5) under each line ending.
  node_error("# c\n3 2 0 0\n1 0 0\n2 1 0\n3 1\n", 5, "vertex 3: missing y coordinate");
  node_error("# c\r\n3 2 0 0\r\n1 0 0\r\n2 1 0\r\n3 1\r\n", 5, "vertex 3: missing y coordinate");
  node_error("# c\r3 2 0 0\r1 0 0\r2 1 0\r3 1\r", 5, "vertex 3: missing y coordinate");
  node_error("# c\r3 2 0 0\n1 0 0\r\n2 1 0\r3 1", 5, "vertex 3: missing y coordinate");
  // "\r\r\n" is a lone CR (ending one line) then a CR LF (ending an empty one).
  node_error("2 2 0 0\r\r\n1 0 0\r\r\n2 x 0\r\r\n", 5, "found 'x'");
  // A lone-CR file whose header promises more than it holds is reported as truncated where it
  // ends, not as a count the file cannot hold.
  node_error("3 2 0 0\r1 0 0\r2 1 0\r", 3, "expected 3 vertices, found 2");
  // A lone CR last in the text ends the text too (it was taken for a CR LF; two files).
  for (const char* name : {"reader_lone_cr_last_taken_for_crlf.node", "reader_lone_cr_last_after_words.node"}) {
    const std::string path = mwst::test::regression_path(name);
    expect_error([&] { mwst::io::read_node(path); }, 7, "vertex count 2 is more than the rest of the file can hold", path);
  }
}

TEST(IoNodeErrors, ByteOrderMarkOnlyAtTheStart) {
  node_error("2 2 0 0\n\xEF\xBB\xBF" "1 0 0\n2 1 1\n", 2, "expected an integer for the index, found '\\xef\\xbb\\xbf1'");
  node_error("\xEF\xBB\xBF", 1, "no data");
  node_error("\xEF\xBB\xBF\xEF\xBB\xBF" "1 2 0 0\n1 0 0\n", 1, "found '\\xef\\xbb\\xbf1'");
}

TEST(IoNodeErrors, TrailingData) {
  node_error("2 2 0 0\n1 0 0\n2 1 1\n3 2 2\n", 4, "unexpected data after the last vertex");
}

// ---- .poly ---------------------------------------------------------------------------------

TEST(IoPoly, SegmentsHolesRegions) {
  const std::string text =
      "# square with a hole\n"
      "4 2 0 1\n"
      "1 0 0 1\n"
      "2 1 0 1\n"
      "3 1 1 1\n"
      "4 0 1 1\n"
      "4 1\n"
      "1 1 2 5\n"
      "2 2 3\n"       // marker missing: 1 (the default)
      "3 3 4 -2\n"
      "\n"
      "4 4 1 7\n"
      "1\n"
      "1 0.5 0.5\n"
      "2\n"
      "1 0.25 0.25 3 0.01\n"
      "2 0.75 0.75 4\n";
  const Pslg p = parse_poly(text, "t.poly");
  EXPECT_TRUE(p.is_poly);
  ASSERT_EQ(p.points.size(), 4u);
  ASSERT_EQ(p.segments.size(), 4u);
  EXPECT_EQ(p.segments[0].a, 0u);
  EXPECT_EQ(p.segments[0].b, 1u);
  EXPECT_EQ(p.segments[0].marker, 5);
  EXPECT_EQ(p.segments[1].marker, 1);
  EXPECT_EQ(p.segments[2].marker, -2);
  EXPECT_EQ(p.segments[3].a, 3u);
  EXPECT_EQ(p.segments[3].b, 0u);
  EXPECT_EQ(p.segment_lines, (std::vector<std::size_t>{8, 9, 10, 12}));
  ASSERT_EQ(p.holes.size(), 1u);
  EXPECT_EQ(p.holes[0], (mwst::Point{0.5, 0.5}));
  ASSERT_EQ(p.regions.size(), 2u);
  EXPECT_EQ(p.regions[0].seed, (mwst::Point{0.25, 0.25}));
  EXPECT_EQ(p.regions[0].attribute, 3.0);
  EXPECT_EQ(p.regions[0].max_area, 0.01);
  EXPECT_EQ(p.regions[1].attribute, 4.0);
  EXPECT_EQ(p.regions[1].max_area, -1.0);
}

TEST(IoPoly, ZeroBasedSegments) {
  const Pslg p = parse_poly("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n2 0\n0 0 1\n1 1 2\n0\n", "t");
  EXPECT_EQ(p.first_index, 0);
  ASSERT_EQ(p.segments.size(), 2u);
  EXPECT_EQ(p.segments[1].a, 1u);
  EXPECT_EQ(p.segments[1].b, 2u);
}

TEST(IoPoly, MissingHolesSectionMeansNoHoles) {
  const Pslg p = parse_poly("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 0\n1 1 2\n# end\n", "t");
  EXPECT_EQ(p.segments.size(), 1u);
  EXPECT_TRUE(p.holes.empty());
  EXPECT_TRUE(p.regions.empty());
}

TEST(IoPoly, NoSegments) {
  const Pslg p = parse_poly("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n", "t");
  EXPECT_TRUE(p.is_poly);
  EXPECT_TRUE(p.segments.empty());
}

TEST(IoPolyErrors, Sections) {
  const std::string v = "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n";  // lines 1-4
  poly_error(v, 4, "unexpected end of file: expected the segment count");
  poly_error(v + "2 0\n1 1 2\n", 6, "expected 2 segments, found 1");
  poly_error(v + "1 0\n1 1 4\n", 6, "segment 1 names vertex 4, which does not exist (vertices are numbered 1 to 3)");
  poly_error(v + "1 0\n1 0 1\n", 6, "segment 1 names vertex 0, which does not exist");
  poly_error(v + "1 0\n1 1 -3\n", 6, "names vertex -3");
  poly_error(v + "1 0\n1 1 -9223372036854775808\n", 6, "names vertex -9223372036854775808");
  poly_error(v + "1 0\n1 1 9223372036854775807\n", 6, "names vertex 9223372036854775807");
  poly_error(v + "1 0\n1 1 9223372036854775808\n", 6, "second endpoint '9223372036854775808' is out of range");
  poly_error(v + "1 0\n1 1\n", 6, "segment 1: missing second endpoint");
  poly_error(v + "1 0\n1 1 x\n", 6, "expected an integer for the second endpoint, found 'x'");
  poly_error(v + "1 1\n1 1 2 q\n", 6, "expected an integer for the boundary marker");
  poly_error(v + "-1 0\n", 5, "negative segment count -1");
  poly_error(v + "500 0\n1 1 2\n", 5, "segment count 500 is more than the rest of the file can hold");
  poly_error(v + "0 0\n2\n1 0.5 0.5\n", 7, "expected 2 holes, found 1");
  poly_error(v + "0 0\n1\n1 0.5 nan\n", 7, "non-finite coordinate");
  poly_error(v + "0 0\n1\n1 0.5 1e99\n", 7, "outside the supported range");
  poly_error(v + "0 0\n0\n1\n1 0.5 0.5\n", 8, "region 1: missing regional attribute");
  poly_error(v + "0 0\n0\n2\n1 0.5 0.5 1 1\n", 8, "expected 2 regions, found 1");
  poly_error(v + "0 0\n0\n0\n7\n", 8, "unexpected data after the regional attributes section");
  poly_error(v + "0 0\n0\n1\n1 0.5 0.5 1 nan\n", 8, "maximum area 'nan' is not a finite double");
}

TEST(IoPolyErrors, ZeroBasedVerticesRejectOneBasedSegmentEnd) {
  poly_error("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 0\n1 1 3\n", 6,
             "names vertex 3, which does not exist (vertices are numbered 0 to 2)");
}

TEST(IoPolyErrors, EmptyAndDimension) {
  expect_error([] { parse_poly("", "t"); }, 0, "empty file");
  poly_error("#\n#\n", 2, "no data");
  poly_error("3 3 0 0\n", 1, "dimension must be 2");
}

// ---- .poly with its vertices in the .node beside it ---------------------------------------------

TEST(IoPolyFiles, ZeroVerticesReadsNodeBeside) {
  TempDir dir;
  write_text(dir.file("shape.node"), "# beside\n3 2 0 1\n0 0 0 4\n1 1 0 5\n2 0 1 6\n");
  write_text(dir.file("shape.poly"), "0 2 0 1\n3 1\n0 0 1 9\n1 1 2 9\n2 2 0 9\n0\n");
  const Pslg p = mwst::io::read_poly(dir.file("shape.poly"));
  EXPECT_TRUE(p.is_poly);
  EXPECT_EQ(p.source, dir.file("shape.poly"));
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_EQ(p.first_index, 0);
  EXPECT_EQ(p.point_markers, (std::vector<std::int32_t>{4, 5, 6}));
  ASSERT_EQ(p.segments.size(), 3u);
  EXPECT_EQ(p.segments[2].a, 2u);
  EXPECT_EQ(p.segments[2].b, 0u);
  EXPECT_EQ(p.segments[2].marker, 9);
  // read_input dispatches on the extension.
  EXPECT_EQ(mwst::io::read_input(dir.file("shape.poly")).segments.size(), 3u);
  EXPECT_EQ(mwst::io::read_input(dir.file("shape.node")).points.size(), 3u);
}

TEST(IoPolyFiles, ZeroVerticesWithoutNode) {
  TempDir dir;
  const std::string poly = dir.file("lonely.poly");
  write_text(poly, "# no node beside\n0 2 0 0\n0 0\n0\n");
  expect_error([&] { mwst::io::read_poly(poly); }, 2, "vertex count 0 but " + dir.file("lonely.node") + " not found",
               poly);
}

TEST(IoPolyFiles, ErrorInNodeBesideNamesTheNode) {
  TempDir dir;
  write_text(dir.file("bad.node"), "2 2 0 0\n1 0 0\n2 1 oops\n");
  write_text(dir.file("bad.poly"), "0 2 0 0\n0 0\n");
  expect_error([&] { mwst::io::read_poly(dir.file("bad.poly")); }, 3, "found 'oops'", dir.file("bad.node"));
}

TEST(IoFiles, MissingFileAndUnknownExtension) {
  TempDir dir;
  expect_error([&] { mwst::io::read_node(dir.file("none.node")); }, 0, "cannot open", dir.file("none.node"));
  expect_error([&] { mwst::io::read_input(dir.file("x.txt")); }, 0, "expected a .node or .poly file",
               dir.file("x.txt"));
  expect_error([&] { mwst::io::read_node(dir.path().string()); }, 0, "cannot", dir.path().string());
}

// ---- writing -----------------------------------------------------------------------------------

// A unit square split along its diagonal (both triangles in the domain, every edge a subsegment,
// the diagonal seen from both sides), plus an outside triangle, a ghost and a dead slot.
mwst::Mesh square_mesh() {
  using mwst::kNone;
  mwst::Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0.5}};
  m.vertex_kind.assign(5, mwst::VertexKind::kInput);
  m.vertex_kind[4] = mwst::VertexKind::kSteiner;
  m.vertex_marker = {1, 1, 2, 1, 0};
  m.triangles = {
      {{0, 1, 2}, {kNone, kNone, kNone}},             // T0: edges 1→2 (e0), 2→0 (e1), 0→1 (e2)
      {{0, 2, 3}, {kNone, kNone, kNone}},             // T1: edges 2→3, 3→0, 0→2
      {{1, 4, 2}, {kNone, kNone, kNone}},             // T2 (outside): edges 4→2, 2→1, 1→4
      {{1, 0, mwst::kInfinite}, {kNone, kNone, kNone}},  // T3: a ghost
      {{0, 1, 3}, {kNone, kNone, kNone}},             // T4: dead
  };
  // Neighbours across the diagonal and across 1–2.
  m.triangles[0].n[1] = mwst::make_handle(1, 2);
  m.triangles[1].n[2] = mwst::make_handle(0, 1);
  m.triangles[0].n[0] = mwst::make_handle(2, 1);
  m.triangles[2].n[1] = mwst::make_handle(0, 0);
  m.flags = {7, 7, static_cast<std::uint8_t>(mwst::kOutside | 7), 1, mwst::kDead | 7};
  m.segment_marker.assign(3 * m.triangles.size(), 1);
  m.segment_marker[3 * 1 + 0] = 5;   // 2→3
  m.segment_marker[3 * 0 + 1] = 8;   // the diagonal, from T0
  m.segment_marker[3 * 1 + 2] = 8;   // the diagonal, from T1
  m.segment_marker[3 * 2 + 1] = 3;   // 1–2 seen from the outside triangle (T0 says 1)
  return m;
}

TEST(IoWrite, SquareMesh) {
  TempDir dir;
  const std::string prefix = dir.file("out.1");
  mwst::io::write_mesh(square_mesh(), prefix);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"out.1.ele", "out.1.node", "out.1.poly"}));
  EXPECT_EQ(read_text(prefix + ".node"), "5 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 2\n4 0 1 1\n5 2 0.5 0\n");
  EXPECT_EQ(read_text(prefix + ".ele"), "2 3 0\n1 1 2 3\n2 1 3 4\n");
  EXPECT_EQ(read_text(prefix + ".poly"),
            "0 2 0 1\n5 1\n"
            "1 2 3 1\n"   // T0 e0: 1→2, marker from the in-domain side
            "2 3 1 8\n"   // T0 e1: the diagonal, once
            "3 1 2 1\n"   // T0 e2
            "4 3 4 5\n"   // T1 e0
            "5 4 1 1\n"   // T1 e1
            "0\n");

  const mwst::io::MeshFiles back = mwst::io::read_mesh(prefix);
  ASSERT_EQ(back.points.size(), 5u);
  EXPECT_EQ(back.points[4], (mwst::Point{2.0, 0.5}));
  ASSERT_EQ(back.triangles.size(), 2u);
  EXPECT_EQ(back.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  ASSERT_EQ(back.segments.size(), 5u);
  EXPECT_EQ(back.segments[1].a, 2u);
  EXPECT_EQ(back.segments[1].b, 0u);
  EXPECT_EQ(back.segments[1].marker, 8);
}

TEST(IoWrite, ZeroBasedAndNoPolyWithoutSegments) {
  TempDir dir;
  mwst::Mesh m = square_mesh();
  for (auto& f : m.flags) f = static_cast<std::uint8_t>(f & ~7);
  const std::string prefix = dir.file("plain");
  mwst::io::write_mesh(m, prefix, 0);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"plain.ele", "plain.node"}));
  EXPECT_EQ(read_text(prefix + ".ele"), "2 3 0\n0 0 1 2\n1 0 2 3\n");
  const mwst::io::MeshFiles back = mwst::io::read_mesh(prefix);
  EXPECT_EQ(back.triangles.size(), 2u);
  EXPECT_TRUE(back.segments.empty());
}

TEST(IoWrite, RoundTripIsBitExact) {
  const std::vector<double> special = {0.1,     -0.1,   1.0 / 3.0, 2.0 / 3.0, 1e-50,  -1e-50,
                                       1e50,    -1e50,  -0.0,      0.0,       123456.789, 1e22,
                                       1e23,    5e-50,  9.999999999999999e49, 0.30000000000000004,
                                       std::nextafter(1.0, 2.0), std::nextafter(1e-50, 1.0),
                                       std::nextafter(1e50, 0.0), 4.35, 2.5e-17};
  mwst::Mesh m;
  for (std::size_t i = 0; i + 1 < special.size(); i += 2) m.points.push_back({special[i], special[i + 1]});
  m.points.push_back({special.back(), special.front()});
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<int> exponent(-165, 165);  // 2^±165 ≈ 1e±49.7
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  for (int i = 0; i < 20000; ++i) {
    const double x = std::ldexp(mantissa(rng), exponent(rng)) * ((rng() & 1) ? -1 : 1);
    const double y = std::ldexp(mantissa(rng), exponent(rng)) * ((rng() & 1) ? -1 : 1);
    m.points.push_back({x, y});
  }
  m.vertex_kind.assign(m.points.size(), mwst::VertexKind::kInput);
  m.vertex_marker.assign(m.points.size(), 0);
  TempDir dir;
  mwst::io::write_mesh(m, dir.file("rt"));
  const Pslg back = mwst::io::read_node(dir.file("rt.node"));
  ASSERT_EQ(back.points.size(), m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    ASSERT_TRUE(same_bits(back.points[i].x, m.points[i].x) && same_bits(back.points[i].y, m.points[i].y))
        << i << ": " << m.points[i].x << " " << m.points[i].y;
  }
  const mwst::io::MeshFiles mesh_back = mwst::io::read_mesh(dir.file("rt"));
  EXPECT_EQ(mesh_back.points.size(), m.points.size());
  EXPECT_TRUE(mesh_back.triangles.empty());
}

TEST(IoWrite, RejectedValuesDoNotSneakIn) {
  // A value outside the supported range would be written (the writer does not judge), but is
  // refused when read back: 5e-324 and subnormals are not silently accepted.
  for (const double v : {5e-324, 2.2250738585072009e-308, 1e-51, 2e50}) {
    mwst::Mesh m;
    m.points = {{v, 0.0}};
    m.vertex_kind = {mwst::VertexKind::kInput};
    m.vertex_marker = {0};
    TempDir dir;
    mwst::io::write_mesh(m, dir.file("bad"));
    expect_error([&] { mwst::io::read_node(dir.file("bad.node")); }, 2, "outside the supported range",
                 dir.file("bad.node"));
  }
}

TEST(IoWrite, AtomicWriteLeavesNoTemporaryFiles) {
  TempDir dir;
  const std::string path = dir.file("f.txt");
  mwst::io::write_file_atomic(path, "one\n");
  mwst::io::write_file_atomic(path, "two\n");
  EXPECT_EQ(read_text(path), "two\n");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"f.txt"}));

  // Into a missing directory: an InputError naming the path, nothing created.
  const std::string missing = dir.file("no/such/dir/f.txt");
  expect_error([&] { mwst::io::write_file_atomic(missing, "x"); }, 0, "cannot write", missing);
  // Over a directory: the rename fails and the temporary is removed.
  fs::create_directory(dir.file("adir"));
  expect_error([&] { mwst::io::write_file_atomic(dir.file("adir"), "x"); }, 0, "cannot write", dir.file("adir"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"adir", "f.txt"}));
}

TEST(IoWrite, FailedMeshWriteLeavesNothing) {
  TempDir dir;
  fs::create_directory(dir.file("m.ele"));  // the .ele cannot be written
  EXPECT_THROW(mwst::io::write_mesh(square_mesh(), dir.file("m")), InputError);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"m.ele"}));
}

// ---- read_mesh validation ----------------------------------------------------------------------

TEST(IoReadMesh, ValidatesIndices) {
  TempDir dir;
  const std::string prefix = dir.file("m");
  write_text(prefix + ".node", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n");
  write_text(prefix + ".ele", "1 3 0\n1 1 2 4\n");
  expect_error([&] { mwst::io::read_mesh(prefix); }, 2, "triangle 1 names vertex 4", prefix + ".ele");
  write_text(prefix + ".ele", "2 3 0\n1 1 2 3\n");
  expect_error([&] { mwst::io::read_mesh(prefix); }, 2, "expected 2 triangles, found 1", prefix + ".ele");
  write_text(prefix + ".ele", "1 4 0\n1 1 2 3 1\n");
  expect_error([&] { mwst::io::read_mesh(prefix); }, 1, "nodes per triangle must be 3 or 6", prefix + ".ele");
  write_text(prefix + ".ele", "1 3 0\n1 1 2 3\n");
  write_text(prefix + ".poly", "0 2 0 1\n1 1\n1 1 5 1\n0\n");
  expect_error([&] { mwst::io::read_mesh(prefix); }, 3, "segment 1 names vertex 5", prefix + ".poly");
  write_text(prefix + ".poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 2\n1 1\n1 1 2 1\n0\n");
  expect_error([&] { mwst::io::read_mesh(prefix); }, 0, "differ", prefix + ".poly");
  write_text(prefix + ".poly", "0 2 0 1\n1 1\n1 1 2 1\n0\n");
  const mwst::io::MeshFiles m = mwst::io::read_mesh(prefix);
  EXPECT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.segments.size(), 1u);
}

// ---- hostile inputs ----------------------------------------------------------------------------
// The edge cases met while writing and reviewing the reader, kept here so that the sanitizer builds
// of the tests see them too; the one that caught a bug (an endpoint of INT64_MIN overflowed
// `index - base`) is tests/regression/reader_segment_endpoint_int64_min.poly, read below.

// What reading a text gives: accepted with so many vertices and segments, or refused on a line
// with a message containing a phrase.
struct Outcome {
  bool accepted;
  std::size_t points_or_line;
  std::size_t segments;  // accepted only
  std::string phrase;    // refused only
};
Outcome accepted(std::size_t points, std::size_t segments = 0) { return {true, points, segments, ""}; }
Outcome refused(std::size_t line, const std::string& phrase) { return {false, line, 0, phrase}; }

void expect_outcome(const std::function<Pslg()>& read, const Outcome& want) {
  if (want.accepted) {
    try {
      const Pslg p = read();
      EXPECT_EQ(p.points.size(), want.points_or_line);
      EXPECT_EQ(p.segments.size(), want.segments);
    } catch (const InputError& e) {
      ADD_FAILURE() << "refused: " << e.located();
    }
  } else {
    expect_error([&] { read(); }, want.points_or_line, want.phrase);
  }
}

TEST(IoFuzzRegressions, Inputs) {
  // Each is read as a .node and as a .poly; each reading must give exactly its outcome (and none
  // may crash or allocate unboundedly, which the sanitizer builds check).
  struct Case {
    std::string text;
    Outcome as_node, as_poly;
  };
  const std::vector<Case> cases = {
      {"1 2 0 0\n-9223372036854775808 0 0\n",
       refused(2, "the first vertex index must be 0 or 1, found -9223372036854775808"),
       refused(2, "the first vertex index must be 0 or 1, found -9223372036854775808")},
      {"9223372036854775807 2 0 0\n", refused(1, "vertex count 9223372036854775807 is more than the rest of the file"),
       refused(1, "vertex count 9223372036854775807 is more than the rest of the file")},
      {"1 2 0 0\n1 0 0\n1 0\n1 1 1\n1\n1 0 0\n1\n1 0 0 -inf 1\n", refused(3, "unexpected data after the last vertex"),
       refused(8, "region 1: regional attribute '-inf' is not a finite double")},
      {std::string("1\0 2", 4), refused(1, "expected an integer for the vertex count, found '1\\x00'"),
       refused(1, "expected an integer for the vertex count, found '1\\x00'")},
      {"1 2 0 99999999999999999\n1 0 0 1\n", accepted(1), refused(2, "unexpected end of file: expected the segment count")},
      // Attributes are kept (8 bytes each per vertex, missing ones too), so their count is bounded.
      {"1 2 9223372036854775807 1\n1 0 0\n", refused(1, "attribute count 9223372036854775807 is too large (at most 1024)"),
       refused(1, "attribute count 9223372036854775807 is too large (at most 1024)")},
      {"0x", refused(1, "expected an integer for the vertex count, found '0x'"),
       refused(1, "expected an integer for the vertex count, found '0x'")},
      {"+", refused(1, "found '+'"), refused(1, "found '+'")},
      {"-", refused(1, "found '-'"), refused(1, "found '-'")},
      {"1 2 0 0\n1 -", refused(2, "vertex 1: expected a number for the x coordinate, found '-'"),
       refused(2, "vertex 1: expected a number for the x coordinate, found '-'")},
      {"1 2 0 0\n1 0x1p", refused(2, "found '0x1p'"), refused(2, "found '0x1p'")},
      {"1 2 0 0\n1 0 0x", refused(2, "vertex 1: expected a number for the y coordinate, found '0x'"),
       refused(2, "vertex 1: expected a number for the y coordinate, found '0x'")},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    expect_outcome([&] { return parse_node(c.text, "t"); }, c.as_node);
    expect_outcome([&] { return parse_poly(c.text, "t"); }, c.as_poly);
  }
}

// ---- the data sets ----------------------------------------------------------------------------

#ifdef MWST_DATA_DIR
TEST(IoData, EveryDataSetMatchesItsHeaderComment) {
  const fs::path data(MWST_DATA_DIR);
  std::vector<fs::path> files;
  if (fs::is_directory(data)) {
    for (const auto& e : fs::directory_iterator(data)) {
      const auto ext = e.path().extension();
      if (ext == ".node" || ext == ".poly") files.push_back(e.path());
    }
  }
  if (files.empty()) GTEST_SKIP() << "no data sets in " << data;
  std::sort(files.begin(), files.end());
  int checked = 0;
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    Pslg p;
    ASSERT_NO_THROW(p = mwst::io::read_input(f.string()));
    EXPECT_EQ(p.is_poly, f.extension() == ".poly");
    EXPECT_EQ(p.first_index, 1);
    EXPECT_EQ(p.points.size(), p.point_markers.size());
    EXPECT_EQ(p.segments.size(), p.segment_lines.size());
    for (const auto& pt : p.points) EXPECT_TRUE(mwst::in_supported_range(pt));
    const std::string text = read_text(f.string());
    // The header comment "# vertices: N, segments: M, holes: H".
    const std::size_t at = text.find("# vertices:");
    unsigned long nv = 0, ns = 0, nh = 0;
    if (at != std::string::npos &&
        std::sscanf(text.c_str() + at, "# vertices: %lu, segments: %lu, holes: %lu", &nv, &ns, &nh) == 3) {
      EXPECT_EQ(p.points.size(), nv);
      EXPECT_EQ(p.segments.size(), ns);
      EXPECT_EQ(p.holes.size(), nh);
      ++checked;
    } else {
      ADD_FAILURE() << "no '# vertices: N, segments: M, holes: H' comment";
    }
  }
  EXPECT_EQ(checked, static_cast<int>(files.size()));
}
#endif

#ifdef MWST_REGRESSION_DIR
// ---- reader corners kept as files (tests/regression/, each named after what it caught) ----------

using mwst::test::regression_path;

void expect_unit_square(const Pslg& p) {
  ASSERT_EQ(p.points.size(), 4u);
  EXPECT_EQ(p.points[0], (mwst::Point{0.0, 0.0}));
  EXPECT_EQ(p.points[2], (mwst::Point{1.0, 1.0}));
  EXPECT_EQ(p.point_markers, (std::vector<std::int32_t>{1, 1, 1, 1}));
}

TEST(IoRegressionFiles, ByteOrderMarkIsSkipped) {
  // The files start with EF BB BF, as some editors save them; it was refused before the header.
  for (const char* name : {"bom_node.node", "bom_header_node.node"}) {
    SCOPED_TRACE(name);
    ASSERT_EQ(read_text(regression_path(name)).substr(0, 3), "\xEF\xBB\xBF");
    expect_unit_square(mwst::io::read_node(regression_path(name)));
  }
  const Pslg poly = mwst::io::read_poly(regression_path("bom_poly.poly"));
  expect_unit_square(poly);
  EXPECT_EQ(poly.segments.size(), 4u);
  EXPECT_EQ(poly.segment_lines, (std::vector<std::size_t>{8, 9, 10, 11}));
}

TEST(IoRegressionFiles, LoneCrAndCrLfLineEndings) {
  // Lone-CR files read as one line before ("vertex count 4 is more than the rest of the file can
  // hold"); every line ending now ends a line, and errors name the right one.
  const std::string cr_node = read_text(regression_path("cr_only_node.node"));
  ASSERT_EQ(cr_node.find('\n'), std::string::npos);
  expect_unit_square(mwst::io::read_node(regression_path("cr_only_node.node")));
  for (const char* name : {"cr_only_poly.poly", "crlf_poly.poly"}) {
    SCOPED_TRACE(name);
    const Pslg p = mwst::io::read_poly(regression_path(name));
    expect_unit_square(p);
    EXPECT_EQ(p.segments.size(), 4u);
    EXPECT_EQ(p.segment_lines, (std::vector<std::size_t>{8, 9, 10, 11}));
  }
  expect_error([] { mwst::io::read_node(regression_path("cr_only_error_line.node")); }, 6,
               "vertex 3: missing y coordinate", regression_path("cr_only_error_line.node"));
  expect_error([] { mwst::io::read_poly(regression_path("crlf_error_line.poly")); }, 10,
               "segment 2 names vertex 5, which does not exist", regression_path("crlf_error_line.poly"));
}

TEST(IoRegressionFiles, WordsAfterTheFieldsAreRefused) {
  // `1 0 0 zzz` was silently accepted; Triangle allows further numbers there, not words.
  struct Case {
    const char* name;
    std::size_t line;
    const char* phrase;
  };
  for (const Case& c : {Case{"garbage_after_vertex.node", 5, "vertex 2: unexpected 'zzz' after its fields"},
                        Case{"garbage_after_header.node", 2, "header: unexpected 'vertices' after its fields"},
                        Case{"garbage_after_vertex.poly", 4, "vertex 2: unexpected 'zzz' after its fields"},
                        Case{"garbage_after_segment.poly", 9, "segment 2: unexpected 'oops' after its fields"},
                        Case{"garbage_after_hole.poly", 13, "hole 1: unexpected 'here' after its fields"},
                        Case{"garbage_after_region.poly", 14, "region 1: unexpected 'big' after its fields"}}) {
    SCOPED_TRACE(c.name);
    expect_error([&] { mwst::io::read_input(regression_path(c.name)); }, c.line, c.phrase, regression_path(c.name));
  }
  const Pslg numbers = mwst::io::read_node(regression_path("numbers_after_vertex.node"));
  ASSERT_EQ(numbers.points.size(), 3u);
  EXPECT_EQ(numbers.points[2], (mwst::Point{0.0, 1.0}));
  const std::string ele = regression_path("garbage_after_triangle.ele");
  expect_error([] { mwst::io::read_mesh(regression_path("garbage_after_triangle")); }, 5,
               "triangle 2: unexpected 'x' after its fields", ele);
}

TEST(IoRegressionFiles, MeshToRefineWithItsAreas) {
  // Triangle's -r input: a .node, a .ele naming its vertices, an .area with one bound per triangle.
  Pslg square = mwst::io::read_node(regression_path("refine_square.node"));
  mwst::io::read_triangles(square, regression_path("refine_square.ele"));
  EXPECT_EQ(square.triangles, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  mwst::io::read_triangle_areas(square, regression_path("refine_square.area"));
  EXPECT_EQ(square.triangle_max_area, (std::vector<double>{0.1, -1.0}));
  const std::string wrong_length = regression_path("refine_square_wrong_length.area");
  expect_error([&] { mwst::io::read_triangle_areas(square, wrong_length); }, 2,
               "triangle count 3 differs from the mesh's 2 triangles", wrong_length);
  for (const auto& [name, line, phrase] :
       {std::tuple<const char*, std::size_t, const char*>{"refine_missing_vertex.ele", 4,
                                                          "triangle 2 names vertex 5, which does not exist"},
        std::tuple<const char*, std::size_t, const char*>{"refine_repeated_vertex.ele", 4,
                                                          "triangle 2 names vertex 3 twice"}}) {
    SCOPED_TRACE(name);
    const std::string path = regression_path(name);
    expect_error([&] { mwst::io::read_triangles(square, path); }, line, phrase, path);
  }
}

// A segment endpoint of INT64_MIN overflowed `index - base` (read as a .node and as a .poly).
TEST(IoRegressionFiles, SegmentEndpointOfInt64MinIsRefused) {
  const std::string path = regression_path("reader_segment_endpoint_int64_min.poly");
  expect_error([&] { mwst::io::read_node(path); }, 10, "unexpected data after the last vertex", path);
  expect_error([&] { mwst::io::read_poly(path); }, 11, "names vertex -9223372036854775808", path);
}

TEST(IoRegressionFiles, MeshWithByteOrderMarkAndLoneCr) {
  const mwst::io::MeshFiles m = mwst::io::read_mesh(regression_path("bom_cr_only_mesh"));
  ASSERT_EQ(m.points.size(), 4u);
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
}
#endif

}  // namespace

// ---- large vertex sections (parsed in two halves on two threads) --------------------------------

namespace {

// A .node/.poly vertex section of n records; record i is (i + base, i * 0.25, -i, marker i % 7),
// with `comment_every` > 0 inserting a comment line after every that many records.
std::string big_vertex_section(std::size_t n, int base, std::size_t comment_every = 0) {
  std::string text = std::to_string(n) + " 2 0 1\n";
  for (std::size_t i = 0; i < n; ++i) {
    text += std::to_string(i + static_cast<std::size_t>(base)) + " " + std::to_string(static_cast<double>(i) * 0.25) +
            " " + std::to_string(-static_cast<double>(i)) + " " + std::to_string(i % 7) + "\n";
    if (comment_every > 0 && i % comment_every == comment_every - 1) text += "# a comment\n\n";
  }
  return text;
}

void expect_big_section(const Pslg& p, std::size_t n, int base) {
  ASSERT_EQ(p.points.size(), n);
  ASSERT_EQ(p.point_markers.size(), n);
  EXPECT_EQ(p.first_index, base);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < n; ++i) {
    wrong += p.points[i].x != static_cast<double>(i) * 0.25 || p.points[i].y != -static_cast<double>(i) ||
             p.point_markers[i] != static_cast<std::int32_t>(i % 7);
  }
  EXPECT_EQ(wrong, 0u);
}

}  // namespace

TEST(IoNodeLarge, HalvesGiveTheSequentialResult) {
  for (const int base : {0, 1}) {
    for (const std::size_t comment_every : {std::size_t{0}, std::size_t{1000}, std::size_t{1}}) {
      const std::size_t n = 100000;
      expect_big_section(parse_node(big_vertex_section(n, base, comment_every), "big.node"), n, base);
    }
  }
}

TEST(IoNodeLarge, ErrorsInEitherHalfNameTheirLine) {
  const std::size_t n = 100000;
  const std::string good = big_vertex_section(n, 1);
  // Line of record i (1-based index i + 1) is line i + 2 (after the header).
  for (const std::size_t bad : {std::size_t{10}, std::size_t{60000}, std::size_t{99999}}) {
    std::string text = good;
    const std::string needle = "\n" + std::to_string(bad + 1) + " ";
    const std::size_t at = text.find(needle);
    ASSERT_NE(at, std::string::npos);
    text.replace(at + needle.size(), 1, "x");  // the x coordinate becomes non-numeric
    expect_error([&] { parse_node(text, "big.node"); }, bad + 2, "x coordinate", "big.node");
  }
  // Out-of-sequence index in the second half, and a file cut short.
  std::string skipped = good;
  const std::size_t at = skipped.find("\n70001 ");
  skipped.replace(at + 1, 5, "70005");
  expect_error([&] { parse_node(skipped, "big.node"); }, 70002, "out of sequence", "big.node");
  const std::string cut = good.substr(0, good.find("\n90001 ") + 1);
  expect_error([&] { parse_node(cut, "big.node"); }, 90001, "vertices", "big.node");
}

TEST(IoPolyLarge, SegmentsAfterALargeVertexSectionKeepTheirLines) {
  const std::size_t n = 80000;
  std::string text = big_vertex_section(n, 1) + "2 0\n1 1 2\n2 2 99999999\n0\n";
  expect_error([&] { parse_poly(text, "big.poly"); }, n + 4, "does not exist", "big.poly");
  text = big_vertex_section(n, 1) + "1 0\n1 1 " + std::to_string(n) + "\n0\n";
  const Pslg p = parse_poly(text, "big.poly");
  expect_big_section(p, n, 1);
  ASSERT_EQ(p.segments.size(), 1u);
  EXPECT_EQ(p.segments[0].b, n - 1);
}

// Files of a megabyte or more are mapped rather than read: the parser must stop at the end of the
// mapping even when the file ends exactly at a page boundary without a final newline (a read past
// the end would fault there), and errors must still name the file and line.
TEST(IoNodeLarge, MappedFilesEndingAtAPageBoundary) {
  TempDir dir;
  const std::size_t n = 60000;
  std::string head = big_vertex_section(n, 1);
  head.erase(head.rfind(std::to_string(n) + " "));  // drop the last record: it ends the file
  const std::string last_record = std::to_string(n) + " " + std::to_string(static_cast<double>(n - 1) * 0.25) + " " +
                                  std::to_string(-static_cast<double>(n - 1)) + " " + std::to_string((n - 1) % 7);
  // A comment line pads the file so that it ends exactly at a 4096-byte boundary.
  auto paged = [&](const std::string& final_line) {
    const std::size_t unpadded = head.size() + 2 + final_line.size();  // "#" and "\n" of the comment
    return head + "#" + std::string((4096 - unpadded % 4096) % 4096, 'p') + "\n" + final_line;
  };
  const std::string text = paged(last_record);
  ASSERT_EQ(text.size() % 4096, 0u);
  ASSERT_GE(text.size(), std::size_t{1} << 20);
  const std::string path = dir.file("paged.node");
  write_text(path, text);
  expect_big_section(mwst::io::read_node(path), n, 1);

  // The same file with its last record cut short (its y coordinate missing) at the page boundary.
  const std::string cut = paged(std::to_string(n) + " " + std::to_string(static_cast<double>(n - 1) * 0.25));
  ASSERT_EQ(cut.size() % 4096, 0u);
  write_text(path, cut);
  expect_error([&] { mwst::io::read_node(path); }, n + 2, "y coordinate", path);
}
