// mwst/mesh/check.hpp — validates a triangulation given as plain triangles against its input graph
// (what `mwst check INPUT PREFIX` runs on files read back from disk, whoever wrote them).
//
// Unlike validate() (mesh.hpp), which checks our own Mesh structure, this trusts nothing but the
// input: exact counter-clockwise orientation, a consistent edge manifold, coverage of the domain
// (every input vertex and segment, the domain's boundary, total area), and optionally the
// constrained Delaunay property and a minimum angle. docs/checker.md says how the domain is taken,
// which tolerances apply to rounded points on segments, and how each segment is also checked
// against the input alone.
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
