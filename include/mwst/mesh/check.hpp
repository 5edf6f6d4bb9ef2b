// mwst/mesh/check.hpp — validates a triangulation given as plain triangles against its input graph
// (what `mwst check INPUT PREFIX` runs on files read back from disk, whoever wrote them).
//
// Unlike validate() (mesh.hpp), which checks our own Mesh structure, this trusts nothing but the
// input: the triangles are checked for exact counter-clockwise orientation, a consistent edge
// manifold (every edge in at most two triangles, with opposite orientations; the triangles around
// each vertex turn once), coverage of the domain (every input vertex of the domain is a mesh
// vertex, every input segment and every boundary edge of the domain is a chain of mesh edges, and
// the mesh boundary lies on those chains; total area = domain area), and optionally the
// constrained Delaunay property (exact incircle across every edge that is not on an input segment)
// and a minimum angle.
//
// The domain is taken from the input by constrained_delaunay() (delaunay.hpp): what the segments
// enclose minus the holes, or — when the mesh covers more, as with --convex-hull or for a point
// set — the convex hull minus the holes. The mesh's area picks one; where the two differ by less
// than the area tolerance (a sliver), a mesh that fails against the one picked is checked against
// the other as well, and passes if it triangulates that one. Vertices the mesh puts on a segment
// (refinement) or at a crossing are rounded points; they count as on the segment when within
// 1e-12 of the segment's coordinate magnitude of its line (exactly collinear points always do). Where that tolerance
// cannot tell two pieces apart (a wedge thinner than it near its apex), the mesh's own boundary
// edges and listed subsegments say which piece a vertex is on: each piece is first followed along
// them, then, if that fails, along any mesh edges near its line. Mesh vertices and triangles are
// named by their position in the files, counted from 1.
//
// Independently of that reference (whose crossing points come from the same code as the meshes'),
// every input segment is checked against the input alone: from the mesh vertex at one end to the
// one at the other, a chain of mesh edges whose vertices advance along the segment and lie within
// 2048 ulps of the segment's largest coordinate magnitude of its line (exact orient2d); where the
// segment leaves the mesh (in a hole) the rest is walked from the other end. And every vertex lies
// in the supported coordinate range (geometry.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mwst/mesh/pslg.hpp"

namespace mwst {

struct CheckOptions {
  bool delaunay = false;         // constrained Delaunay across every edge not on an input segment
  bool conforming_delaunay = false;  // Delaunay across every interior edge, input segments included
  double min_angle_deg = 0.0;    // > 0: every angle at least this (up to 1e-9 degrees of rounding)
  std::size_t max_messages = 1000;  // violations beyond this are counted, not described
};

struct CheckResult {
  std::vector<std::string> messages;  // one line per violation (at most max_messages)
  std::size_t violations = 0;         // total number found
  bool convex_hull = false;           // the mesh covers the convex hull (not the carved domain)
  double area = 0.0;                  // total area of the triangles
  double domain_area = 0.0;           // area of the input's domain
  bool ok() const { return violations == 0; }
};

// `subsegments` are the mesh's own subsegments (PREFIX.poly), empty when it has none; when given
// they must be mesh edges lying on input segments, and every piece of an input segment must be
// listed. Throws InputError if the input itself is refused (as `mwst triangulate` would).
MWST_API CheckResult check_triangulation(const Pslg& input, const std::vector<Point>& points,
                                const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                const std::vector<Segment>& subsegments,
                                const CheckOptions& options = {});

}  // namespace mwst
