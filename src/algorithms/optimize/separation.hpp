// src/algorithms/optimize/separation.hpp — OptimizeOptions::min_separation's tests: a Steiner vertex
// the search places keeps this distance from every other vertex and from every segment and domain
// boundary edge it is not on. Internal (not installed); used by the search and the seeded starts.
#pragma once

#include <vector>

#include "mwst/export.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {

// May a Steiner vertex be placed at q, inside the polygon of mesh triangles whose edges the
// handles `beyond` see from the triangles outside them (q's star to be, or the triangles q
// splits)? True if q is at least `separation` from every vertex of the mesh and from every segment
// and domain boundary edge other than the polygon's chords. The search runs outward from the
// polygon's edges across the ones nearer than `separation` to q (every nearer vertex lies beyond
// such edges), so it is local; past 256 triangles it says no.
MWST_API bool point_is_separated(const Mesh& mesh, const Point& q, const std::vector<Handle>& beyond, double separation);

// Distance from p to the closed segment ab, in floating point (the separation it is compared with
// is far above its rounding).
MWST_API double point_segment_distance(const Point& p, const Point& a, const Point& b);

// OptimizeOptions::min_separation's default for a search of `mesh`: kSeparationFraction × its
// shortest domain edge (0 for an empty domain).
MWST_API double default_min_separation(const Mesh& mesh);

}  // namespace mwst
