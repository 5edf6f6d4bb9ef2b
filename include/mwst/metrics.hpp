// mwst/metrics.hpp — weight and quality of a mesh.
#pragma once

#include <cstddef>

#include "mwst/mesh.hpp"

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
  double max_triangle_area = 0.0;  // the largest in-domain triangle's (what --max-area bounds)
};

MWST_API Metrics measure(const Mesh& mesh);

// The three angles (degrees) of triangle t, opposite corners 0, 1, 2.
MWST_API void triangle_angles_deg(const Mesh& mesh, TriangleId t, double out[3]);

}  // namespace mwst
