// The exact minimum weight triangulation of a mesh's vertex set with its segments as constraints
// (mwst/algorithms/mwt.hpp), after Beirouti and Snoeyink, "Implementations of the LMT heuristic for
// minimum weight triangulation" (SoCG 1998); docs/algorithms/mwt.md tells the whole method. This
// file runs the two routes; their steps live beside it (domain, candidates, skeleton, polygon_mwt).
//  1. Candidate edges: the diamond test of Drysdale, McElfresh and Snoeyink (route "diamond",
//     enumerated in growing disks with "dead sectors"), or all visible pairs (route "visibility").
//     Witness and angle tests run in doubles with a margin that only ever keeps an edge; vertex-on-
//     edge and crossing tests are exact (orient2d).
//  2. The LMT-skeleton (Dickerson and Montague 1996): edges with no locally minimal empty pair of
//     candidate triangles die, edges no living candidate crosses are fixed; repeat.
//  3. The faces of the fixed edges: the polygon dynamic program (polygon_mwt.hpp) when simple,
//     else "not solved".
//  4. Route "diamond" answers for the domain only if its triangulation contains every subsegment
//     and boundary edge; otherwise the visibility route is tried.
// Lengths are summed in doubles: "exact" means exact up to the rounding of those sums.
#include "mwst/algorithms/mwt.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "algorithms/mwt/candidates.hpp"
#include "algorithms/mwt/domain.hpp"
#include "algorithms/mwt/skeleton.hpp"
#include "mesh/keys.hpp"

namespace mwst {

namespace {

using namespace mwt;  // the method's vocabulary: domain.hpp, candidates.hpp, skeleton.hpp

// A route's answer recorded in `result`: the input mesh re-triangulated by `tris`, validated.
void record_solution(MwtResult& result, const Mesh& mesh, const Domain& d, const std::vector<Tri>& tris,
                     const CoreResult& core, std::size_t candidates) {
  result.mesh = rebuild(mesh, d, tris);
  const std::vector<std::string> problems = validate(result.mesh);
  if (!problems.empty()) throw InternalError("mwt: the optimal triangulation is invalid: " + problems.front());
  result.solved = true;
  result.reason.clear();
  result.weight = measure(result.mesh).weight_total;
  result.candidate_edges = candidates;
  result.skeleton_edges = core.skeleton_edges;
  result.result_edges = core.result_edges;
  result.regions = core.regions;
  result.largest_region = core.largest_region;
}

// Route "diamond": the MWT of the vertex set as a point set; it answers for the domain when it
// contains every constraint and no straight-angle sliver (mwt.hpp).
void diamond_route(const Mesh& mesh, const Domain& d, const MwtOptions& options, MwtResult& result) {
  result.route = "diamond";
  bool too_many = false;
  std::vector<std::array<Index, 2>> candidates =
      diamond_candidates(d.pts, options.diamond_angle, options.max_candidate_edges, too_many);
  result.candidate_edges = candidates.size();
  Skeleton skeleton(d.pts, too_many ? std::vector<std::array<Index, 2>>{} : std::move(candidates), {},
                    options.max_candidate_triangles, options.max_crossing_pairs);
  if (too_many) {
    result.reason = "too many candidate edges (diamond route)";
    return;
  }
  if (!skeleton.overflow().empty()) {
    result.reason = skeleton.overflow() + " (diamond route)";
    return;
  }
  if (!skeleton.run({})) {
    result.reason = "two fixed edges cross (diamond route)";
    return;
  }
  // Every face inside the convex hull is triangulated (the MWT of the point set).
  CoreResult core = skeleton.triangulate_faces([](const std::vector<Index>&) { return false; },
                                               options.max_region, /*hull_outer=*/true);
  result.skeleton_edges = core.skeleton_edges;
  result.regions = core.regions;
  result.largest_region = core.largest_region;
  if (!core.solved) {
    result.reason = core.reason + " (diamond route)";
    return;
  }
  std::unordered_map<std::uint64_t, char> edges;
  for (const Tri& t : core.triangles) {
    for (unsigned k = 0; k < 3; ++k) edges.emplace(undirected_key(t[k], t[(k + 1) % 3]), 1);
  }
  bool contains_constraints = true;
  for (const auto& c : d.constraints) contains_constraints = contains_constraints && edges.count(edge_key(c[0], c[1]));
  if (!contains_constraints) {
    result.reason = "the point set's MWT misses a segment or boundary edge (diamond route)";
    return;
  }
  const std::vector<Tri> inside = restrict_to_domain(d, core.triangles);
  bool sliver = false;
  for (const Tri& t : inside) {
    for (unsigned k = 0; k < 3 && !sliver; ++k) sliver = straight_corner(d, t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
  }
  if (sliver) {
    result.reason = "the point set's MWT has a straight-angle sliver along a segment (diamond route)";
    return;
  }
  record_solution(result, mesh, d, inside, core, skeleton.initial_size());
}

// Route "visibility": every visible pair a candidate, the constraints forced; complete by
// construction. `earlier` prefixes the reason when it fails too.
void visibility_route(const Mesh& mesh, const Domain& d, const MwtOptions& options, MwtResult& result) {
  const std::string earlier = result.reason.empty() ? "" : result.reason + "; ";
  result.route = "visibility";
  Skeleton skeleton(d.pts, visibility_candidates(d), d.constraints, options.max_candidate_triangles,
                    options.max_crossing_pairs);
  result.candidate_edges = skeleton.initial_size();
  if (!skeleton.overflow().empty()) {
    result.reason = earlier + skeleton.overflow() + " (visibility route)";
    return;
  }
  if (!skeleton.run(d.constraints)) {
    result.reason = earlier + "two fixed edges cross (visibility route)";
    return;
  }
  std::unordered_map<std::uint64_t, char> reversed_boundary;
  for (const auto& b : d.boundary) reversed_boundary.emplace(edge_key(b[1], b[0]), 1);
  CoreResult core = skeleton.triangulate_faces(
      [&](const std::vector<Index>& walk) {
        for (std::size_t i = 0; i < walk.size(); ++i) {
          if (reversed_boundary.count(edge_key(walk[i], walk[(i + 1) % walk.size()]))) return true;
        }
        return false;
      },
      options.max_region, /*hull_outer=*/false);
  result.skeleton_edges = core.skeleton_edges;
  result.regions = core.regions;
  result.largest_region = core.largest_region;
  if (!core.solved) {
    result.reason = earlier + core.reason + " (visibility route)";
    return;
  }
  record_solution(result, mesh, d, core.triangles, core, skeleton.initial_size());
}

}  // namespace

MwtResult exact_mwt(const Mesh& mesh, const MwtOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  MwtResult result;
  const mwt::Domain d = mwt::collect_domain(mesh);
  result.vertices = d.pts.size();
  if (d.pts.size() < 3) {
    result.reason = "the domain has no triangle";
    return result;
  }
  if (options.diamond_route) diamond_route(mesh, d, options, result);
  if (!result.solved && d.pts.size() > options.max_visibility_vertices) {
    result.reason += (result.reason.empty() ? "" : "; ") + std::string("too many vertices for the visibility route");
  } else if (!result.solved) {
    visibility_route(mesh, d, options, result);
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace mwst
