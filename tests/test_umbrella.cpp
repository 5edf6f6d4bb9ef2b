// tests/test_umbrella.cpp — the umbrella header mwst/mwst.hpp compiles on its own and gives the
// whole API: a point set read from text, triangulated by the pipeline, checked independently.
#include "mwst/mwst.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(Umbrella, OneIncludeRunsThePipeline) {
  const mwst::Pslg input = mwst::io::parse_node("5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.5 0.4\n", "square.node");
  mwst::Mesh mesh;
  const mwst::Report report = mwst::triangulate(input, mwst::TriangulateOptions{}, &mesh);
  EXPECT_TRUE(mwst::validate(mesh).empty());
  EXPECT_EQ(report.triangles, 4u);
  EXPECT_EQ(report.vertices, 5u);
}

}  // namespace
