// algorithms/quadtree/quadtree.cpp — quadtree_refinement(): clean the input, build and finish the
// balanced quadtree, build the mesh from its leaves, drop the corners outside the domain; if any
// step fails (features closer than the deepest level separates, rounding at the scale of an ulp,
// a tree beyond the leaf limit), the fallback: the CDT of the input plus the quadtree's free
// corners; if the time budget (QuadtreeOptions::deadline) runs out, the CDT alone. The steps and their files are listed in route.hpp; docs/algorithms/quadtree.md explains
// the method, its guarantees and its data layout.
#include "mwst/algorithms/quadtree.hpp"

#include <cstdint>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/quadtree/builder.hpp"
#include "algorithms/quadtree/route.hpp"
#include "algorithms/quadtree/testing.hpp"
#include "algorithms/quadtree/tree.hpp"
#include "mwst/error.hpp"

namespace mwst {

namespace qtr {

namespace {

// Stage 1 (route.hpp), with its statistics; `holes` receives the seeds to carve (none unless a segment that is
// not a hull edge bounds the domain).
CleanInput clean_input(const Pslg& pslg, const QuadtreeOptions& options, QuadtreeStats& stats,
                       std::vector<Point>& holes) {
  const auto t0 = Clock::now();
  const bool graph = !pslg.segments.empty();
  CleanInput in = graph ? clean_graph(pslg, options, stats) : clean_point_set(pslg, options);
  if (!graph && options.deadline != Clock::time_point::max()) {
    // Under a time budget a point set's Delaunay triangulation (the fallback) is made first, as a
    // graph's cleaning CDT is: out of time, the route then stops with its answer at hand instead of
    // building it past the deadline.
    bool unused = false;
    in.cdt_for_fallback = fallback_mesh(pslg, options, {}, &unused);
  }
  if (!graph) stats.input.duplicates = in.vertices_only.duplicates.size();
  if (!graph && !pslg.holes.empty()) {
    stats.warnings.push_back("the input has no segments, so its domain is the convex hull; " +
                             std::to_string(pslg.holes.size()) + " hole seed(s) ignored");
  }
  stats.features_vertices = in.vertices.size();
  stats.features_segments = in.segments.size();
  stats.seconds_input = seconds_since(t0);
  bool any_real_segment = false;
  for (const FeatureSegment& s : in.segments) any_real_segment = any_real_segment || !s.hull_only;
  holes = any_real_segment ? in.hole_seeds : std::vector<Point>{};
  return in;
}

// The final quadtree's leaves, in node order (TestSwitches::keep_leaves).
void collect_leaves(const Tree& tree, std::vector<QuadtreeLeaf>& leaves) {
  for (std::uint32_t a = 0; a < tree.nodes.size(); ++a) {
    if (!tree.is_leaf(a)) continue;
    const Node& n = tree.nodes[a];
    const Box b = tree.box(n);
    leaves.push_back({b.x1, b.y1, b.x2 - b.x1, tree.meets_any(n, tree.features.data() + n.feat_begin, n.feat_count)});
  }
}

// Stages 3 and 4 on a finished tree: the mesh with the corners outside the domain dropped, or
// RouteFailure.
Mesh mesh_from_tree(Builder& builder, const std::vector<Point>& holes, bool force_fallback,
                    const QuadtreeStats& stats) {
  if (force_fallback) throw RouteFailure{"forced by the options"};
  if (stats.unresolved > 0) {
    throw RouteFailure{std::to_string(stats.unresolved) +
                       " leaves at the deepest level still see the input non-simply"};
  }
  Mesh mesh = builder.run(holes);
  // Round trip: what is written must lie in the supported coordinate range. A corner the domain
  // uses outside it (a grid finer than 1e-50 near an axis: a square of side 1e-50 got a corner at
  // x = 1.34e-51) sends the input to the fallback.
  const std::vector<char> kept = kept_vertices(mesh);
  if (const VertexId v = out_of_range_vertex(mesh, kept); v != kNone) {
    char where[64];
    std::snprintf(where, sizeof where, "(%.17g, %.17g)", mesh.points[v].x, mesh.points[v].y);
    // (No corners for the fallback: the grid's positions went into the mesh.)
    throw RouteFailure{"a quadtree vertex at " + std::string(where) +
                           " lies outside the supported coordinate range (0 or a magnitude between "
                           "1e-50 and 1e50)",
                       /*corners_usable=*/false};
  }
  drop_unused_vertices(mesh, kept);
  return mesh;
}

// Stages 2 to 4. On failure stats.fallback is set, with its reason, and `extra` receives the free
// corners the fallback may add.
Mesh quadtree_route(const CleanInput& in, const QuadtreeOptions& options, const TestSwitches& switches,
                    const std::vector<Point>& holes, QuadtreeStats& stats, std::vector<QuadtreeLeaf>* leaves,
                    std::vector<Point>& extra) {
  Mesh mesh;
  const auto t1 = Clock::now();
  try {
    check_deadline(options.deadline);  // (the cleaning CDT may have used it all)
    Tree tree(in, options, stats);
    tree.build();
    tree.finish();
    stats.seconds_tree = seconds_since(t1);
    // Leaf statistics: counted, not scanned (every split turns one leaf into four, and the
    // deepest node is a leaf).
    stats.leaves = tree.leaf_count();
    stats.depth = tree.deepest();
    if (switches.keep_leaves && leaves != nullptr) collect_leaves(tree, *leaves);
    const auto t_mesh = Clock::now();
    // The mesh is built against the deadline less the writing of its vertices (about one per leaf);
    // a deadline that has passed by then sends the route to its fallback at the builder's first check.
    QuadtreeOptions mesh_options = options;
    if (options.deadline != Clock::time_point::max()) {
      const double reserve = options.time_reserve_per_vertex * static_cast<double>(stats.leaves);
      mesh_options.deadline -= std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(reserve));
    }
    Builder builder(in, mesh_options, stats, tree);
    // The free corners for the fallback read the tree's nodes; once those went with the mesh
    // (NodeArray), from the same tree built again (the build is deterministic).
    const auto corners = [&] {
      if (!builder.nodes_given_away()) return builder.fallback_points(tree);
      QuadtreeStats scratch;
      Tree again(in, options, scratch);
      again.build();
      again.finish();
      return builder.fallback_points(again);
    };
    try {
      mesh = mesh_from_tree(builder, holes, switches.force_fallback, stats);
    } catch (const RouteFailure& failure) {
      stats.fallback = true;
      stats.fallback_reason = failure.reason;
      stats.out_of_time = failure.out_of_time;
      if (failure.corners_usable) extra = corners();
      stats.seconds_mesh = seconds_since(t_mesh);  // (the builder's time until it gave up)
    } catch (const InternalError& error) {
      // A broken invariant on the quadtree route (a bug; the tests assert no fallback on their
      // inputs): the user still gets a valid mesh, with a warning naming the invariant.
      stats.fallback = true;
      stats.fallback_reason = std::string("internal error: ") + error.what();
      extra = corners();
    }
  } catch (const RouteFailure& failure) {  // from the tree: its time until it gave up
    stats.fallback = true;
    stats.fallback_reason = failure.reason;
    stats.out_of_time = failure.out_of_time;
    stats.seconds_tree = seconds_since(t1);
  }
  return mesh;
}

}  // namespace

// quadtree_refinement() with test switches (testing.hpp): clean, route, or the fallback.
Mesh refine_with_switches(const Pslg& pslg, const QuadtreeOptions& options, const TestSwitches& switches,
                          QuadtreeStats* stats_out, std::vector<QuadtreeLeaf>* leaves) {
  if (!(options.snap_fraction > 0.0 && options.snap_fraction < 0.5)) {
    throw std::invalid_argument("quadtree: snap_fraction must lie in (0, 0.5)");
  }
  QuadtreeStats stats;
  std::vector<Point> holes;
  CleanInput in = clean_input(pslg, options, stats, holes);
  if (switches.skip_size_bound) in.leaf_lower_bound = 0.0;
  std::vector<Point> extra;
  Mesh mesh = quadtree_route(in, options, switches, holes, stats, leaves, extra);
  if (stats.fallback) {
    std::optional<Mesh> cdt = std::move(in.cdt_for_fallback);
    in = CleanInput{};  // (the fallback builds its own CDT: the clean input's memory goes first)
    const auto t2 = Clock::now();
    stats.warnings.push_back("quadtree refinement fell back to the constrained Delaunay triangulation "
                             "of the input" + std::string(extra.empty() ? "" : " plus quadtree corners") + ": " +
                             stats.fallback_reason);
    bool corners_cut_short = false;
    if (cdt && extra.empty()) {
      mesh = std::move(*cdt);  // (the same mesh as fallback_mesh()'s, made once)
    } else {
      cdt.reset();
      mesh = fallback_mesh(pslg, options, std::move(extra), &corners_cut_short);
    }
    if (corners_cut_short) {
      stats.out_of_time = true;
      stats.warnings.push_back("the time budget ran out while the fallback added quadtree corners: some were left out");
    }
    stats.seconds_mesh += seconds_since(t2);
  }
  if (stats_out) *stats_out = std::move(stats);
  return mesh;
}

}  // namespace qtr

// The public entry point (mwst/algorithms/quadtree.hpp): no test switches.
Mesh quadtree_refinement(const Pslg& pslg, const QuadtreeOptions& options, QuadtreeStats* stats) {
  return qtr::refine_with_switches(pslg, options, qtr::TestSwitches{}, stats, nullptr);
}

}  // namespace mwst
