// tests/algorithms/quadtree/test_quadtree_limits.cpp — the budgets of quadtree refinement: the time
// budget (QuadtreeOptions::deadline, TriangulateOptions::time_budget_seconds, --time-limit) and the
// memory budget (--max-memory).
//
// Out of time, the route stops at its next clock check and the output is the carved CDT of the
// input (docs/algorithms/quadtree.md, "Budgets"); the stop reason is "time budget". Nothing here
// measures time: a deadline that has already passed is caught by the first check, and one an
// hour away by none, whatever the machine's speed.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/quadtree.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "support/cli_sandbox.hpp"
#include "support/exact_checker.hpp"

namespace mwst {
namespace {

using Clock = std::chrono::steady_clock;

// Inputs on which the quadtree route runs for a while (tens of thousands of leaves or more): a point
// set, and a polygon with holes (whose cleaning CDT is kept for the fallback under a deadline).
std::vector<std::pair<std::string, Pslg>> long_inputs() {
  return {{"uniform 20000", generate_input(Distribution::kUniform, 20000, 1)},
          {"holes 4000", generate_input(Distribution::kHoles, 4000, 1)}};
}

bool same_mesh(const Mesh& a, const Mesh& b) {
  if (a.points.size() != b.points.size() || a.triangles.size() != b.triangles.size()) return false;
  for (std::size_t v = 0; v < a.points.size(); ++v) {
    if (a.points[v].x != b.points[v].x || a.points[v].y != b.points[v].y) return false;
  }
  for (std::size_t t = 0; t < a.triangles.size(); ++t) {
    if (a.triangles[t].v != b.triangles[t].v) return false;
  }
  return true;
}

// A deadline that has passed: the route stops at once, the output is the input's carved CDT (the
// very mesh constrained_delaunay() makes), valid by the independent checker, and the stats and
// the warning say why.
TEST(QuadtreeLimits, PassedDeadlineGivesTheCdtWithTheReason) {
  for (const auto& [name, g] : long_inputs()) {
    SCOPED_TRACE(name);
    QuadtreeStats free_stats;
    const Mesh free_mesh = quadtree_refinement(g, QuadtreeOptions{}, &free_stats);
    ASSERT_FALSE(free_stats.fallback) << "without a deadline the route finishes";
    ASSERT_GT(free_stats.leaves, 10000u) << "the input keeps the route busy";

    QuadtreeOptions options;
    options.deadline = Clock::now();
    QuadtreeStats stats;
    const Mesh mesh = quadtree_refinement(g, options, &stats);
    EXPECT_TRUE(stats.fallback);
    EXPECT_TRUE(stats.out_of_time);
    EXPECT_EQ(stats.fallback_reason, "the time budget ran out");
    ASSERT_FALSE(stats.warnings.empty());
    EXPECT_NE(stats.warnings.back().find("the time budget ran out"), std::string::npos) << stats.warnings.back();
    EXPECT_TRUE(same_mesh(mesh, constrained_delaunay(g, ConstrainOptions{})));
    EXPECT_LT(mesh.triangles.size(), free_mesh.triangles.size());
    const CheckResult check = test::check_mesh(g, mesh);
    EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
  }
}

// A deadline that does not pass changes nothing: the same mesh as without one, byte for byte
// (the clock checks only read the clock; the kept CDT is not used).
TEST(QuadtreeLimits, DistantDeadlineChangesNothing) {
  for (const auto& [name, g] : long_inputs()) {
    SCOPED_TRACE(name);
    QuadtreeStats free_stats, timed_stats;
    const Mesh free_mesh = quadtree_refinement(g, QuadtreeOptions{}, &free_stats);
    QuadtreeOptions options;
    options.deadline = Clock::now() + std::chrono::hours(1);
    const Mesh timed_mesh = quadtree_refinement(g, options, &timed_stats);
    EXPECT_FALSE(timed_stats.out_of_time);
    EXPECT_EQ(timed_stats.leaves, free_stats.leaves);
    EXPECT_TRUE(same_mesh(free_mesh, timed_mesh));
  }
}

// Issue 32: the writing of the mesh is set aside before the deadline (time_reserve_per_vertex, one
// vertex per leaf). An hour ahead, but with an hour per vertex set aside, the tree is built and the
// mesh is not: the output is the carved CDT, and the reason the time budget.
TEST(QuadtreeLimits, ReservePerVertexGivesTheCdtOnceTheTreeIsDone) {
  const Pslg g = generate_input(Distribution::kUniform, 20000, 1);
  QuadtreeOptions options;
  options.deadline = Clock::now() + std::chrono::hours(1);
  options.time_reserve_per_vertex = 3600.0;
  QuadtreeStats stats;
  const Mesh mesh = quadtree_refinement(g, options, &stats);
  EXPECT_GT(stats.leaves, 10000u);
  EXPECT_TRUE(stats.fallback);
  EXPECT_TRUE(stats.out_of_time);
  EXPECT_TRUE(same_mesh(mesh, constrained_delaunay(g, ConstrainOptions{})));
}

// triangulate() passes its time budget to qtr: stopped by it, the report's stop reason is "time
// budget", the mesh is the CDT's and valid; without a budget qtr has no stop reason.
TEST(QuadtreeLimits, PipelineStopReasonIsTimeBudget) {
  const Pslg g = generate_input(Distribution::kUniform, 20000, 1);
  TriangulateOptions options;
  options.method = Method::kQtr;
  EXPECT_TRUE(method_reads_option(Method::kQtr, "time_budget_seconds"));
  Mesh mesh;
  const Report free_report = triangulate(g, options, &mesh);
  EXPECT_EQ(free_report.stop_reason, "");
  EXPECT_FALSE(free_report.qtr->fallback);
  options.time_budget_seconds = 1e-9;
  const Report report = triangulate(g, options, &mesh);
  EXPECT_EQ(report.stop_reason, "time budget");
  ASSERT_TRUE(report.qtr.has_value());
  EXPECT_TRUE(report.qtr->fallback);
  // The fallback is the CDT: dt's mesh, triangle for triangle.
  options.method = Method::kDt;
  options.time_budget_seconds = -1.0;
  const Report dt_report = triangulate(g, options);
  EXPECT_EQ(report.triangles, dt_report.triangles);
  EXPECT_EQ(report.weight_total, dt_report.weight_total);
  const CheckResult check = test::check_mesh(g, mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
}

}  // namespace
}  // namespace mwst

namespace mwst_cli_test {
namespace {

// `mwst triangulate --method qtr --time-limit`: no "has no effect" warning, the fallback's warning
// instead, "time budget" in the report, and a mesh the independent checker accepts.
TEST(QuadtreeLimitsCli, TimeLimitStopsQtrWithAValidMesh) {
  Sandbox box;
  box.put("in.node", mwst::io::node_text(mwst::generate_points(mwst::Distribution::kUniform, 50000, 1)));
  const Outcome r = box.run({"triangulate", "in.node", "-o", "t", "--method", "qtr", "--time-limit", "1e-6",
                             "--json", "t.json"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.err.find("has no effect"), std::string::npos) << describe(r);
  EXPECT_NE(r.err.find("quadtree refinement fell back to the constrained Delaunay triangulation of the input: "
                       "the time budget ran out"),
            std::string::npos)
      << describe(r);
  const auto report = nlohmann::json::parse(box.get("t.json"));
  EXPECT_EQ(report.at("stop_reason").get<std::string>(), "time budget");
  EXPECT_TRUE(report.at("qtr").at("fallback").get<bool>());
  const Outcome check = box.run({"check", "in.node", "t"});
  EXPECT_EQ(check.exit_code, 0) << describe(check);
}

// A qtr run past --max-memory (50,000 points make a tree of some 180 MB) stops with exit code 4,
// one line, and no output files.
TEST(QuadtreeLimitsCli, MaxMemoryStopsQtrWithExitCode4AndNoFiles) {
  if (!kAddressLimit) GTEST_SKIP() << "sanitizer build: no address-space limit";
  Sandbox box;
  box.put("in.node", mwst::io::node_text(mwst::generate_points(mwst::Distribution::kUniform, 50000, 1)));
  const Outcome r = box.run({"triangulate", "in.node", "-o", "u", "--method", "qtr", "--max-memory", "40M",
                             "--json", "u.json"});
  EXPECT_EQ(r.exit_code, 4) << describe(r);
  ASSERT_EQ(r.err_lines().size(), 1u) << describe(r);
  EXPECT_EQ(r.err.rfind("mwst: out of memory: ", 0), 0u) << describe(r);
  EXPECT_TRUE(r.out.empty());
  EXPECT_EQ(box.entries(), std::set<std::string>{"in.node"}) << "no output file may be left behind";
}

}  // namespace
}  // namespace mwst_cli_test
