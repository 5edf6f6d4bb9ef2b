// mwst/algorithms/mwt.hpp — the exact minimum weight triangulation (MWT) of a mesh's vertex set, with its
// segments as constraints, for measuring how far a locally minimal mesh (EFH, flip.hpp) is from
// optimal on the same vertices (the paper's open problem 3 asks for the MWT of well-spaced sets).
//
// Method (docs/algorithms/mwt.md): candidate edges (the diamond test of Drysdale, McElfresh and
// Snoeyink on the vertex set, or all visible pairs in the domain), the LMT-skeleton to fix most of
// them, and the polygon dynamic program over the faces left. Triangles with a straight corner at a
// segment's Steiner point (flip.hpp, is_straight_corner) are excluded. The answer is exact up to
// the summation of lengths in doubles; when a route's premise fails the result says "not solved"
// and why, and never reports a heuristic as optimal.
#pragma once

#include <cstddef>
#include <string>

#include "mwst/mesh/mesh.hpp"

namespace mwst {

struct MwtOptions {
  bool diamond_route = true;          // try the point-set route with the diamond test first
  // Base angle of the exclusion triangles: π/4.6 (Drysdale–McElfresh–Snoeyink); π/8 is Das and
  // Joseph's original, weaker bound (more candidates, same answer).
  double diamond_angle = 3.14159265358979323846 / 4.6;
  std::size_t max_visibility_vertices = 500;  // the visibility route only up to this many vertices
  std::size_t max_region = 600;       // largest skeleton face handed to the O(d³) polygon DP
  // Memory bounds (a route exceeding one gives up with "not solved"): candidate edges, candidate
  // triangles (about 13 bytes each) and crossing pairs of candidates (4 bytes each).
  std::size_t max_candidate_edges = 400000;
  std::size_t max_candidate_triangles = 8000000;
  std::size_t max_crossing_pairs = 20000000;
};

struct MwtResult {
  bool solved = false;
  std::string route;    // "diamond" or "visibility" (the route that solved it, or was tried last)
  std::string reason;   // why not solved (empty when solved)
  Mesh mesh;            // when solved: the input mesh with its domain re-triangulated by the MWT
  double weight = 0.0;  // measure(mesh).weight_total when solved
  std::size_t vertices = 0;         // vertices of the domain
  std::size_t candidate_edges = 0;  // candidates of the route that decided (before the skeleton)
  std::size_t skeleton_edges = 0;   // edges fixed by the LMT-skeleton (segments included)
  std::size_t result_edges = 0;     // edges of the triangulation the route computed (the whole
                                    // convex hull for the diamond route, the domain otherwise)
  std::size_t regions = 0;          // skeleton faces with more than three corners (DP regions)
  std::size_t largest_region = 0;   // corners of the largest such face
  double seconds = 0.0;
  // Fraction of the computed triangulation's edges already fixed by the skeleton.
  double fixed_fraction() const {
    return result_edges == 0 ? 0.0 : static_cast<double>(skeleton_edges) / static_cast<double>(result_edges);
  }
};

// The minimum weight triangulation of the domain of `mesh` (its in-domain triangles) on the
// vertices of those triangles, containing every subsegment. Input vertices, segments and markers
// are kept; the returned mesh passes validate(). Throws InternalError on broken invariants.
MWST_API MwtResult exact_mwt(const Mesh& mesh, const MwtOptions& options = {});

}  // namespace mwst
