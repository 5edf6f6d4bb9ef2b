// mwst/mesh/pslg.hpp — the input: a planar straight-line graph (points, segments, hole seeds).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mwst/geometry/geometry.hpp"

namespace mwst {

struct Segment {
  std::uint32_t a = 0;  // 0-based point indices
  std::uint32_t b = 0;
  std::int32_t marker = 1;  // Triangle's boundary marker (copied to output subsegments)
};

// A regional attribute / area constraint seed of Triangle's .poly: the attribute goes to the
// triangles its seed reaches (arrays.hpp), the area limit bounds them with
// TriangulateOptions::regional_area_limits (≤ 0: none).
struct Region {
  Point seed;
  double attribute = 0.0;
  double max_area = -1.0;
  std::size_t line = 0;  // its line in the .poly (0: not read from a file)
};

struct Pslg {
  std::vector<Point> points;            // as read; duplicates are kept here and merged by the mesher
  std::vector<std::int32_t> point_markers;  // per point (0 when the file had none)
  // Triangle's vertex attributes (the A of "N 2 A B"): attributes_per_point per point, point i's at
  // [i * attributes_per_point, (i + 1) * attributes_per_point); empty when 0. The output carries
  // them (interpolate_vertex_attributes, mwst/algorithms/arrays.hpp).
  std::size_t attributes_per_point = 0;
  std::vector<double> point_attributes;
  std::vector<Segment> segments;        // empty for a .node input
  std::vector<Point> holes;             // hole seeds
  std::vector<Region> regions;
  // An existing triangulation of `points` to refine instead of starting from the constrained
  // Delaunay triangulation (Triangle's -r, read from a .ele): 3 point indices per triangle,
  // 0-based. Empty: none.
  std::vector<std::uint32_t> triangles;
  // Per triangle of `triangles`, its area bound (Triangle's .area file, read with -r -a); a value
  // <= 0 means none. Empty: no per-triangle bounds.
  std::vector<double> triangle_max_area;
  bool is_poly = false;                 // read from a .poly (segments section present)
  int first_index = 1;                  // 0 or 1: the numbering base the input used
  std::string source;                   // file name, for messages
  // Line number of each segment in the source file (for "segment names a missing vertex" and
  // "crossing segments" messages); empty when not read from a file.
  std::vector<std::size_t> segment_lines;
};

}  // namespace mwst
