// mwst/io/triangle_switches.hpp — Triangle's command-line switches ("-pq30a0.5AenQ") read into
// TriangulateOptions and the input/output choices they make. One parser for `mwst triangle`, the
// library's users and the Python binding.
//
// The switches have Triangle's documented meanings (Shewchuk, Triangle 1.6, "triangle -h"); the
// table, what mwst accepts and ignores (Triangle's own algorithm choices), and what it refuses
// are in docs/triangle-switches.md. Refused switches, malformed numbers, a number after a switch
// that takes none and a non-positive area throw std::invalid_argument naming the switch and why.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mwst/export.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace mwst {

struct TriangleSwitches {
  // Method, angle, area, -D, -Y, -c, -S (max_steiner) as the switches say; the rest default.
  TriangulateOptions options;

  bool poly = false;                 // p: the input is a .poly
  bool refine = false;               // r: refine INPUT.node + INPUT.ele (Pslg::triangles)
  bool quality = false;              // q, a or D given: the method is refinement (dr)
  bool region_attributes = false;    // A: one attribute per triangle in the .ele
  bool edges = false;                // e: write .edge
  bool neighbours = false;           // n: write .neigh
  bool voronoi = false;              // v: write .v.node and .v.edge
  bool zero_based = false;           // z: number output from 0 when the input does not decide
  bool jettison = false;             // j: leave vertices in no triangle out of the .node
  bool no_boundary_markers = false;  // B
  bool no_poly_output = false;       // P
  bool no_node_output = false;       // N
  bool no_ele_output = false;        // E
  bool no_iteration_numbers = false; // I
  bool ignore_holes = false;         // O
  bool quiet = false;                // Q
  unsigned verbosity = 0;            // V, once per V
  bool help = false;                 // h
  std::string ignored;               // the no-op switches given (i, F, l, s, C, X), in order
};

// Parses a switch string such as "-pq30a0.5" or "pq30a0.5" (the leading '-' is optional; an
// empty string is no switch). Throws std::invalid_argument naming the switch for anything Triangle
// does not document, mwst does not do, or a malformed number: "-u: user-defined size constraints
// (a compiled triunsuitable()) are not supported".
MWST_API TriangleSwitches parse_triangle_switches(std::string_view switches);

// Parses several switch arguments ("-p", "-q30") into one set, as Triangle takes them.
MWST_API TriangleSwitches parse_triangle_switches(const std::vector<std::string>& arguments);

}  // namespace mwst
