// tests/support/mesh_queries.hpp — reading a mesh in the tests: its triangles, angles and subsegments,
// a canonical form to compare triangulations, and check_mesh (the library's file-level checker
// on a Mesh, as `mwst check` sees it after write_mesh).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/algorithms/metrics.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::test {

using Tri = std::array<std::uint32_t, 3>;


// Delaunay refinement with an area bound and no angle bound: the triangles larger than max_area
// are split (the start the area-bound tests give the flips and the optimiser).
inline void refine_to_area(Mesh& m, double max_area) {
  RefineOptions options;
  options.min_angle_deg = 0.0;
  options.max_area = max_area;
  refine(m, options);
}

// ---- reading a mesh ----------------------------------------------------------------------------

// Smallest angle of triangle t, in degrees.
inline double min_angle_of(const Mesh& m, TriangleId t) {
  double a[3];
  triangle_angles_deg(m, t, a);
  return std::min({a[0], a[1], a[2]});
}

// The live finite triangles of a mesh (all of them, or only those in the domain).
inline std::vector<Tri> finite_triangles(const Mesh& m, bool domain_only = false) {
  std::vector<Tri> out;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.is_dead(t) || m.is_ghost(t)) continue;
    if (domain_only && m.is_outside(t)) continue;
    out.push_back(m.triangles[t].v);
  }
  return out;
}

// Triangles as sorted vertex triples, sorted: a canonical form to compare triangulations.
inline std::vector<Tri> canonical(std::vector<Tri> tris) {
  for (auto& t : tris) std::sort(t.begin(), t.end());
  std::sort(tris.begin(), tris.end());
  return tris;
}

// The mesh as `mwst check` sees it after write_mesh(): its domain triangles and each subsegment
// bordering the domain once, handed to the library's file-level checker (check_triangulation).
inline CheckResult check_mesh(const Pslg& input, const Mesh& m, const CheckOptions& options = {}) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Segment> subsegments;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    triangles.push_back(m.triangles[t].v);
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!m.is_segment(h)) continue;
      const TriangleId other = m.sym(h) >> 2;
      if (!m.in_domain(other) || other > t) subsegments.push_back({m.org(h), m.dest(h), m.marker(h)});
    }
  }
  return check_triangulation(input, m.points, triangles, subsegments, options);
}

// The subsegments of a mesh as undirected (min, max) pairs, sorted.
inline std::vector<std::pair<std::uint32_t, std::uint32_t>> subsegments(const Mesh& m) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> s;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!m.is_segment(h)) continue;
      const VertexId a = m.org(h), b = m.dest(h);
      if (a == kInfinite || b == kInfinite) continue;
      s.insert({std::min(a, b), std::max(a, b)});
    }
  }
  return {s.begin(), s.end()};
}

// The subsegments bordering in-domain triangles (carved ones left out) as (min, max) pairs.
inline std::set<std::pair<VertexId, VertexId>> domain_subsegments(const Mesh& m) {
  std::set<std::pair<VertexId, VertexId>> s;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (m.is_segment(h)) s.insert(std::minmax(m.org(h), m.dest(h)));
    }
  }
  return s;
}


}  // namespace mwst::test
