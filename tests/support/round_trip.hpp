// tests/support/round_trip.hpp — is a mesh read back from PREFIX.node/.ele/.poly (io::read_mesh) the Mesh
// that io::write_mesh wrote? Shared by tests/io/test_round_trip.cpp and fuzz/fuzz_triangulate.cpp, so
// it needs nothing but the library (no GoogleTest, no GMP).
//
// "The same mesh" is geometric and bit-exact: the same triangles, in the order written, each with
// the same corners (bit for bit, so one ulp or the sign of a zero is a difference) in the same
// counter-clockwise order, and the same subsegments. Vertex numbers may differ (a writer may leave
// out vertices no triangle uses), but then every vertex read back must be one of the mesh's; when
// the counts agree, vertex i must read back as vertex i.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::test {

// A point's bits (+0.0 and -0.0 differ: the writer must keep the sign of a zero).
using PointBits = std::pair<std::uint64_t, std::uint64_t>;
inline PointBits point_bits(const Point& p) {
  return {std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y)};
}

inline std::string exact_text(const Point& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%a, %a)", p.x, p.y);
  return buf;
}

// The differences between `mesh` as write_mesh() writes it (its in-domain triangles in slot order,
// each subsegment bordering the domain once) and `back`, one line each; empty if they are the same
// mesh. At most `max_lines` lines (then a last line saying that there are more).
inline std::vector<std::string> round_trip_differences(const Mesh& mesh, const io::MeshFiles& back,
                                                       std::size_t max_lines = 20) {
  std::vector<std::string> out;
  std::size_t found = 0;
  auto differ = [&](const std::string& line) {
    if (++found <= max_lines) out.push_back(line);
  };

  // Vertices: index for index when nothing was left out, else each one of the mesh's.
  if (back.points.size() == mesh.points.size()) {
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      if (point_bits(back.points[i]) != point_bits(mesh.points[i])) {
        differ("vertex " + std::to_string(i + 1) + " reads back as " + exact_text(back.points[i]) + ", written " +
               exact_text(mesh.points[i]));
      }
    }
  } else {
    std::set<PointBits> written;
    for (const Point& p : mesh.points) written.insert(point_bits(p));
    for (std::size_t i = 0; i < back.points.size(); ++i) {
      if (written.count(point_bits(back.points[i])) == 0) {
        differ("vertex " + std::to_string(i + 1) + " reads back as " + exact_text(back.points[i]) +
               ", which is no vertex of the mesh");
      }
    }
  }

  // Triangles, in the order written, corner by corner.
  std::size_t written_triangles = 0;
  std::set<std::pair<PointBits, PointBits>> written_segments;
  bool has_subsegments = false;
  for (TriangleId t = 0; t < mesh.triangles.size() && !has_subsegments; ++t) {
    if (!mesh.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) has_subsegments = has_subsegments || mesh.is_segment(make_handle(t, e));
  }
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (!mesh.in_domain(t)) continue;
    const std::size_t i = written_triangles++;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      // A mesh with subsegments gets a .poly, which lists every subsegment and every boundary
      // edge of the domain (as Triangle's does: the hull edges of a -c / convex_hull mesh too).
      const bool boundary = has_subsegments && !mesh.in_domain(mesh.sym(h) >> 2);
      if (!mesh.is_segment(h) && !boundary) continue;
      PointBits a = point_bits(mesh.points[mesh.org(h)]), b = point_bits(mesh.points[mesh.dest(h)]);
      if (b < a) std::swap(a, b);
      written_segments.insert({a, b});
    }
    if (i >= back.triangles.size()) continue;
    for (unsigned k = 0; k < 3; ++k) {
      const Point& want = mesh.points[mesh.triangles[t].v[k]];
      const Point& got = back.points[back.triangles[i][k]];
      if (point_bits(got) != point_bits(want)) {
        differ("triangle " + std::to_string(i + 1) + " corner " + std::to_string(k + 1) + " reads back as " +
               exact_text(got) + ", written " + exact_text(want));
      }
    }
  }
  if (back.triangles.size() != written_triangles) {
    differ(std::to_string(back.triangles.size()) + " triangles read back, " + std::to_string(written_triangles) +
           " written");
  }

  // Subsegments, as unordered pairs of endpoints.
  std::set<std::pair<PointBits, PointBits>> read_segments;
  for (const Segment& s : back.segments) {
    PointBits a = point_bits(back.points[s.a]), b = point_bits(back.points[s.b]);
    if (b < a) std::swap(a, b);
    read_segments.insert({a, b});
  }
  if (read_segments != written_segments || back.segments.size() != written_segments.size()) {
    differ(std::to_string(back.segments.size()) + " subsegments read back (" + std::to_string(read_segments.size()) +
           " distinct), " + std::to_string(written_segments.size()) + " written, not the same");
  }
  if (found > max_lines) out.push_back("... and " + std::to_string(found - max_lines) + " more differences");
  return out;
}

}  // namespace mwst::test
