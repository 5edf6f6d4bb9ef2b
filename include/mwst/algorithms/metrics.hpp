// mwst/algorithms/metrics.hpp — weight and quality of a mesh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mwst/mesh/mesh.hpp"

namespace mwst {

// Weight = sum of edge lengths of the in-domain triangles. The boundary part is every edge that is
// a subsegment or borders a triangle outside the domain (or a ghost): the input segments, or the
// convex hull of a point set, which every triangulation of the input contains. Interior = the rest.
struct Metrics {
  std::size_t vertices = 0;   // vertices used by in-domain triangles
  std::size_t triangles = 0;  // in-domain triangles
  std::size_t steiner = 0;    // used vertices that are not input points
  double weight_total = 0.0;
  double weight_boundary = 0.0;
  double weight_interior = 0.0;
  double min_angle_deg = 0.0;  // over in-domain triangles
  double max_angle_deg = 0.0;
  double area = 0.0;           // total area of in-domain triangles
  double max_triangle_area = 0.0;  // the largest in-domain triangle's (what max_area bounds)
};

MWST_API Metrics measure(const Mesh& mesh);

// The three angles (degrees) of triangle t, opposite corners 0, 1, 2.
MWST_API void triangle_angles_deg(const Mesh& mesh, TriangleId t, double out[3]);

// Is the smallest angle of triangle (a, b, c) below the bound whose cosine squared is
// `bound_cos2` (cos²α)? The test Delaunay refinement applies (src/algorithms/refine/refine.cpp, as
// Triangle does): the cosine² of the angle opposite the shortest edge, from the dot product of the
// two longer edges, against cos²α. Shared so that a stop reason checked against the final mesh
// agrees with the refinement that made it, triangle for triangle.
bool below_angle_bound(const Point& a, const Point& b, const Point& c, double bound_cos2);

// Per triangle slot: 1 if the triangle lies next to an input angle under 60°, where Delaunay
// refinement cannot improve it (Miller, Pav, Walkington, "When and why Ruppert's algorithm works",
// and Shewchuk's "Mesh generation for domains with small angles": near an input angle θ < 60° some
// triangle keeps an angle ≤ θ, whatever the Steiner points). "Input angle": two chains of
// subsegments (input segments, split or not; the hull of a point set once refinement has marked
// it) leaving a vertex that is not a segment's split point, with in-domain triangles between them,
// whose directions (to the chains' far ends) make an angle under 60°. "Next to it": a triangle of
// the fan at the angle's vertex between the two chains, or a triangle with a vertex on each chain
// (the triangles across the wedge, which the Miller–Pav–Walkington rule of refine.cpp leaves).
// Read off the mesh alone (subsegment flags, the domain, vertex kinds), in O(triangles).
std::vector<std::uint8_t> near_small_input_angles(const Mesh& mesh);

// The in-domain triangles that do not meet the bounds of a refinement: smallest angle below
// min_angle_deg (> 0; below_angle_bound) or area above max_area (> 0). A triangle below the angle
// bound next to a small input angle (near_small_input_angles) and not above the area bound is
// exempt; every other one is a violation.
struct BoundCheck {
  std::size_t below_angle = 0;  // below the angle bound (exempt or not)
  std::size_t above_area = 0;   // larger than the area bound (never exempt)
  std::size_t exempt = 0;       // below the angle bound only, next to a small input angle
  std::size_t violations = 0;   // the others: below the angle bound or above the area bound
};
BoundCheck check_bounds(const Mesh& mesh, double min_angle_deg, double max_area);

}  // namespace mwst
