// tests/algorithms/optimize/test_optimize_limits.cpp — the budgets of method opt at scale
// (docs/algorithms/optimize.md, "Time budget" and "Memory"): --time-limit bounds the whole run,
// its BRH start's flips included, and the search's scratch stays within its stated size.
//
// Nothing here measures time: a budget of a microsecond has passed before the first clock check,
// whatever the machine's speed.
#include <gtest/gtest.h>

#include <string>

#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/mesh/check.hpp"
#include "support/exact_checker.hpp"

namespace mwst {
namespace {

// 5,000 points on an ellipse: the Delaunay triangulation is a fan of long chords that EFH's flips
// shorten by thousands of flips, as BRH's mesh is when the budget cuts it short. Before the flips
// of opt's BRH start read the deadline, they ran to their local minimum past any budget (1.5 s
// past a 10 s limit on 160k points on a spiral); now they stop at it, the largest gains taken
// first, and the run says "time budget".
TEST(OptimizeLimits, BrhStartFlipsStopAtTheTimeBudget) {
  const Pslg input = generate_input(Distribution::kEllipse, 5000, 1);
  TriangulateOptions options;
  options.method = Method::kOpt;
  options.time_budget_seconds = 1e-6;
  Mesh mesh;
  const Report report = triangulate(input, options, &mesh);
  EXPECT_EQ(report.stop.kind, StopKind::kTimeBudget);
  EXPECT_EQ(report.stop_reason, "time budget");
  ASSERT_TRUE(report.optimize.has_value());
  ASSERT_EQ(report.optimize->starts.size(), 1u);
  EXPECT_EQ(report.optimize->starts.front().first, "brh+efh");
  EXPECT_TRUE(validate(mesh).empty());
  const CheckResult check = test::check_mesh(input, mesh);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? "" : check.messages.front());
  // Cut short: flips are left (a run without a budget leaves none).
  EXPECT_GT(count_weight_reducing_flips(mesh), 0u);

  TriangulateOptions free = options;
  free.time_budget_seconds = -1.0;
  free.opt_trials = 0;
  Mesh unbounded;
  const Report full = triangulate(input, free, &unbounded);
  EXPECT_NE(full.stop.kind, StopKind::kTimeBudget);
  EXPECT_EQ(count_weight_reducing_flips(unbounded), 0u);
  EXPECT_LT(measure(unbounded).weight_total, measure(mesh).weight_total);
}

}  // namespace
}  // namespace mwst
