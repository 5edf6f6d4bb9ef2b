// mwst/algorithms/arrays.hpp — a triangulation as plain flat arrays, for programs that want the triangles
// and not the mesh data structure (as CDT hands out its vertices and triangles).
//
// Every array is flat: vertex v has coordinates vertices[2v], vertices[2v+1]; triangle t has the
// corners triangles[3t..3t+2] (counter-clockwise) and the neighbours neighbours[3t..3t+2], where
// neighbours[3t+i] is the triangle across the edge opposite corner i (Triangle's .neigh
// convention) or -1 where that edge is on the boundary of the domain. Only triangles of the domain
// are listed (not those carved away by holes or outside the segments). Input point i of the Pslg
// is vertex i (duplicates and points outside the domain included, in no triangle), so indices
// into the caller's own point array stay valid; Steiner points follow.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mwst/mesh/mesh.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

// What a vertex of MeshArrays is. The Steiner kinds are read off the mesh: a Steiner point on no
// subsegment is interior, one on two subsegments splits an input segment, one where three or more
// subsegments meet is a crossing point of input segments.
enum class ArrayVertexKind : std::uint8_t {
  kInput = 0,           // an input point, at its input index
  kDuplicate = 1,       // an input point equal to an earlier one; merged, so in no triangle
  kSteiner = 2,         // a Steiner point in the interior of the domain
  kSegmentSteiner = 3,  // a Steiner point splitting an input segment
  kCrossing = 4,        // a point where input segments cross
};

struct MeshArrays {
  std::vector<double> vertices;               // 2 per vertex: x, y
  std::vector<ArrayVertexKind> vertex_kinds;  // 1 per vertex
  std::vector<std::int32_t> vertex_markers;   // 1 per vertex: Triangle's boundary markers
  // Triangle's vertex attributes (the A of a .node's "N 2 A B"): attributes_per_vertex per vertex,
  // vertex v's at [v * attributes_per_vertex, (v + 1) * attributes_per_vertex). Empty when 0.
  std::size_t attributes_per_vertex = 0;
  std::vector<double> vertex_attributes;
  std::vector<std::uint32_t> triangles;       // 3 per triangle: vertex indices, counter-clockwise
  std::vector<std::int32_t> neighbours;       // 3 per triangle: across the edge opposite corner i; -1 none
  std::vector<std::uint32_t> segments;        // 2 per subsegment bounding a domain triangle
  std::vector<std::int32_t> segment_markers;  // 1 per subsegment
  // 1 per triangle when the input has regions (.poly regional attributes, Triangle's -A): the
  // attribute of the region whose seed reaches the triangle without crossing a subsegment (a
  // later region wins, as in Triangle), 0 where none does. Empty without regions.
  std::vector<double> triangle_attributes;
  Report report;  // filled by triangulate_arrays; to_arrays leaves it empty but for warnings

  std::size_t vertex_count() const { return vertex_kinds.size(); }
  std::size_t triangle_count() const { return triangles.size() / 3; }
  std::size_t segment_count() const { return segment_markers.size(); }
};

// Triangle's regions: for each triangle slot of `mesh`, the index of the region whose seed reaches
// it without crossing a subsegment (regions applied in order, a later one winning), or -1 (outside
// the domain, or reached by no seed). A seed on an edge or a vertex is in the domain triangle of
// least slot beside it. A seed outside the domain (outside the segments, or in a hole) is bad
// input: an InputError naming `source` and the region's line.
MWST_API std::vector<std::int32_t> region_of_triangles(const Mesh& mesh, const std::vector<Region>& regions,
                                                       const std::string& source);

// The domain triangles of `mesh` as flat arrays. Vertices removed from the mesh
// (VertexKind::kRemoved) are left out and the rest numbered in order. `regions` (a Pslg's) give
// triangle_attributes; a region seed outside the domain is an InputError naming `source` (the
// input's file) and the region's line (region_of_triangles). Large meshes are copied in ranges on
// `threads` threads (0: one per hardware thread); the arrays do not depend on the number.
MWST_API MeshArrays to_arrays(const Mesh& mesh, const std::vector<Region>& regions = {},
                              const std::string& source = {}, unsigned threads = 0);

// Triangle's vertex attributes of `input` (Pslg::point_attributes) carried to `arrays`, a
// triangulation of it: each input point keeps its own; every other vertex (a Steiner point) gets
// them interpolated linearly from the constrained Delaunay triangulation of the input (with
// `convex_hull` as the triangulation had it): barycentric in the triangle holding the point, along
// the edge or hull edge nearest it when it lies on an edge or outside by rounding. (Triangle
// interpolates at each insertion in the mesh of that moment; with piecewise linear attributes over
// the input's triangulation, as here, a Steiner point's attributes do not depend on the order of
// insertion or on the method.) A crossing of input segments, a vertex of that triangulation but
// not an input point, takes them linearly along the input segment through it. Nothing happens
// when the input has no attributes.
MWST_API void interpolate_vertex_attributes(const Pslg& input, bool convex_hull, MeshArrays& arrays);

// The points of a flat array of `count` (x, y) pairs, xy[2i] and xy[2i + 1] (a numpy (n, 2)
// float64 array's buffer, say), as a Pslg's points. The copy goes to fresh storage faulted in on
// `threads` threads (0: one per hardware thread) in 2 MiB pages where the kernel allows: written
// one 4 KiB page at a time, 16 MB of fresh points took 40-160 ms on a virtual machine, most of a
// Python caller's overhead over triangulate().
MWST_API std::vector<Point> points_from_xy(const double* xy, std::size_t count, unsigned threads = 0);

// triangulate(pslg, options) (mwst/algorithms/pipeline.hpp) and to_arrays of its mesh, with its
// report, and the input's vertex attributes (interpolate_vertex_attributes). If `mesh` is not
// null the mesh itself is moved there too.
MWST_API MeshArrays triangulate_arrays(const Pslg& pslg, const TriangulateOptions& options, Mesh* mesh = nullptr);

}  // namespace mwst
