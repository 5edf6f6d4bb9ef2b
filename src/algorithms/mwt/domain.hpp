// src/algorithms/mwt/domain.hpp — the domain of a mesh as the exact MWT sees it: its vertices renumbered
// from 0 (Index), its triangles, constraints (subsegments and boundary edges) and boundary, and the
// way back to a mesh. Internal (not installed).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mwst/mesh/mesh.hpp"

namespace mwst::mwt {

using Index = std::uint32_t;
using Tri = std::array<Index, 3>;

struct Domain {
  std::vector<VertexId> ids;   // local index → mesh vertex
  std::vector<Point> pts;      // local coordinates
  std::vector<Tri> triangles;  // the mesh's in-domain triangles (local, counter-clockwise)
  std::vector<std::array<Index, 2>> constraints;     // subsegments and boundary edges (a < b)
  std::vector<std::array<Index, 2>> boundary;        // directed boundary edges, domain on the left
  std::unordered_map<std::uint64_t, Handle> outer;   // (org, dest) mesh ids of a boundary edge → handle outside
  std::vector<std::array<std::int64_t, 3>> segments; // subsegments: mesh ids a, b and marker
  std::vector<std::vector<Index>> segment_neighbours;  // per local vertex, along subsegments
  std::vector<char> on_segment;  // a Steiner point splitting a segment (VertexKind::kSteinerOnSegment)
};
// A triangle whose corner at a segment's Steiner point has two subsegments as sides spans a
// straight angle in truth (the rounded point only looks convex): a sliver along the segment, which
// EFH may not make either (flip.hpp, is_straight_corner). Such triangles are excluded.
inline bool straight_corner(const Domain& d, Index apex, Index a, Index b) {
  if (!d.on_segment[apex]) return false;
  const auto& s = d.segment_neighbours[apex];
  return std::find(s.begin(), s.end(), a) != s.end() && std::find(s.begin(), s.end(), b) != s.end();
}
// The domain of `m` (its in-domain triangles), renumbered.
Domain collect_domain(const Mesh& m);

// The input mesh with its domain re-triangulated by `tris` (local indices, counter-clockwise):
// vertices, segments and markers kept.
Mesh rebuild(const Mesh& input, const Domain& d, const std::vector<Tri>& tris);

// The triangles of a triangulation of the convex hull lying in the domain: flood fill from the
// domain side of each boundary edge, never crossing a boundary edge. Empty if a boundary edge is
// missing.
std::vector<Tri> restrict_to_domain(const Domain& d, const std::vector<Tri>& tris);

}  // namespace mwst::mwt
