// mwst/io/triangle_switches.hpp — Triangle's command-line switches ("-pq30a0.5AenQ") read into
// TriangulateOptions and the input/output choices they make. One parser for `mwst triangle`, the
// library's users and the Python binding.
//
// The switches have Triangle's documented meanings (Shewchuk, Triangle 1.6, "triangle -h"):
//   p  read a .poly (segments, holes, regions)       r  refine the mesh of INPUT.node + INPUT.ele
//   q  quality: minimum angle, 20° or q<deg>         a  area bound: a<area> for every triangle, a
//                                                       alone for the .poly regions' / .area bounds
//   A  regional attribute of each triangle in .ele   c  keep the convex hull (segments around it)
//   D  conforming Delaunay                           Y  no Steiner points on boundary segments;
//   S  at most S<n> Steiner points (S alone: none)      YY on no segment at all
//   j  leave unused vertices out of the .node        e  write the edges (.edge)
//   v  write the Voronoi diagram (.v.node, .v.edge)  n  write the neighbours (.neigh)
//   z  number from zero (the input's own numbering   B  no boundary markers in the output
//      wins when there is one)                       P, N, E  no .poly, .node, .ele output
//   I  no iteration number in the output names       O  ignore the .poly's holes
//   Q  quiet     V  verbose     h  help
// Triangle refines (our method dr) when q or a is given, or D (conforming Delaunay is Ruppert's
// refinement: with no q the angle bound is 0); otherwise the mesh is the (constrained) Delaunay
// triangulation (method dt).
//
// Switches that choose how Triangle itself computes the same mesh are accepted and do nothing:
// i (incremental), F (Fortune's sweepline), l (vertical cuts only), s (segments by splitting
// instead of a constrained Delaunay triangulation), C (check the final mesh: mwst's meshes are
// checked by construction and by `mwst check`), X (no exact arithmetic: mwst is always exact).
// Switches mwst does not do are refused with std::invalid_argument naming the switch and why:
// u (a user-compiled triunsuitable()), g (.off output), o2 (second-order triangles), and any
// character that is no Triangle switch. So are malformed numbers, a number after a switch that
// takes none, and a non-positive area (a0).
//
// Numbers follow their switch without a space and consist of digits and at most one '.' (no
// sign or exponent: Triangle reads "a1e3" as a1, e and a stray 3, and we refuse the stray digit).
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
