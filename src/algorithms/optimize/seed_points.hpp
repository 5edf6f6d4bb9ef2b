// src/algorithms/optimize/seed_points.hpp — seeded starting meshes for method opt (seed_points.cpp).
// Internal (not installed).
#pragma once

#include <cstddef>

#include "mwst/export.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {

// Steiner points inserted (constrained Delaunay insertion, insert_vertex) into a carved CDT at
//  - kJunctionCircumcenters: the circumcenter of every in-domain triangle with no edge on the
//    domain boundary, where the approximate medial axis (the CDT's dual) branches;
//  - kCentroids: the centroid of every in-domain triangle.
// Seeds off the domain or on an edge are skipped. Returns the number inserted. The mesh stays a
// valid constrained Delaunay triangulation; the optimiser then keeps what pays.
enum class SeedPoints { kJunctionCircumcenters, kCentroids };
MWST_API std::size_t seed_steiner_points(Mesh& mesh, SeedPoints which);

}  // namespace mwst
