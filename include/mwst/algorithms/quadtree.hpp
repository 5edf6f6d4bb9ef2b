// mwst/algorithms/quadtree.hpp — quadtree refinement (QTR): a balanced-quadtree Steiner triangulation of a
// point set or of a polygonal domain with holes, after Bern, Eppstein and Gilbert, "Provably good
// mesh generation" (FOCS 1990; JCSS 48, 1994), the QTR column of Boyacı, Erten, Üngör,
// "Triangulations Loosing Bundles and Weight". Eppstein (1994) shows such a triangulation weighs
// O(1) times the minimum weight Steiner triangulation.
//
// The route (src/algorithms/quadtree/quadtree.cpp has the details and the reasons):
//  1. Clean input. A PSLG goes through the constrained Delaunay triangulation (duplicates merged,
//     segments split at vertices on them and at crossings); features = its vertices and
//     subsegments. A point set is cleaned by sorting (duplicates) and an exact monotone-chain hull.
//     When the domain is the convex hull (a point set, or --convex-hull) the hull edges are
//     features too: they bound the domain.
//  2. Split. A square root cell, at least twice the input's bounding box, is split until every
//     leaf C of size s that meets a feature sees the input "simply" in its extended cell B(C): the
//     vertices in C grown by s/2 on every side and the segments meeting C grown by s (the 3×3 block
//     of same-size cells) are at most one vertex; with one vertex, only segments incident to it;
//     with none, segments that share an endpoint (at most one segment, or one vertex's segments).
//     The tree is refused (fallback) beyond QuadtreeOptions::max_leaves leaves: its size grows
//     with the integral of 1/lfs², not with the number of features.
//     For a point set: each point is alone in its leaf grown by half its size (hull edges keep the
//     full block, as all segments do). Half is the least growth that keeps two points from
//     claiming one corner in step 4 (the square of side s centred on a corner, where the points
//     that move it lie, is inside each incident leaf grown by s/2); BEG's 3×3 block for vertices
//     made 21 % more triangles on uniform points. Segments keep the full block: with half of it,
//     cells cut near small input angles fell below the cut-cell bound (3.4° next to a 4.2° input
//     angle in the star-polygon tests).
//  3. Balance: edge-adjacent leaves differ in size by at most a factor 2. Warp rule: the four
//     leaves around the corner a vertex will take have the vertex's leaf size (finer ones split
//     the vertex's leaf, coarser ones are split).
//  4. Warp. The corner of its leaf nearest each vertex moves onto it. Towards segments (BEG's
//     warping of corners to nearby crossings): a corner moves along a cell edge onto the crossing
//     point of a segment that lies within snap_fraction of a leaf size of it (and within half the
//     edge), or onto its projection if it lies nearer to a segment than snap_fraction × its
//     largest leaf and 0.4 × its smallest (a segment running along cell edges).
//  5. Cut and triangulate. Segments cross the remaining cell edges at Steiner points; each leaf
//     is cut along its segment pieces (chords) into pieces, and triangulated:
//       - an untouched square (no moved corner, no segment) by the case table below;
//       - a warped square or a piece of a cut one by the max–min-angle triangulation of its
//         boundary (dynamic program), or, if that keeps an angle below 20°, by the fan from a
//         Steiner point at its vertex average when that is better.
//     The triangles of all leaves form one Mesh over the root square (ghost triangles on its
//     border), the segment pieces are subsegments, and the mesh is carved to the domain exactly
//     as the CDT carves (flood from the outside and from the hole seeds, stopped by segments;
//     each seed is taken at the centroid of the CDT triangle it carved from, and the seeds the
//     CDT ignored are dropped, so that a seed on a segment's line carves the same face in both).
//     Input vertices are never moved and keep their ids; every input segment is a chain of
//     subsegments (corners moved onto it and crossing points are rounded to double once).
//
// Case table (an untouched leaf with corners BL, BR, TR, TL and the midpoints b, r, t, l of the
// sides whose neighbours are smaller; computed once as the max–min-angle triangulation of the unit
// square, ties to the lighter one; see quadtree_case_table()):
//   no midpoint     (BL BR TL) (BR TR TL): the diagonal BR–TL, angles 45/45/90
//   one midpoint    joined to the two far corners, e.g. b: (BL b TL) (b TR TL) (b BR TR)
//   more            corners next to two midpoints are cut off by right isosceles triangles, the
//                   rest is fanned, e.g. all four: the four corners cut off, the diamond split r–l
// Every case-table triangle has its angles in [atan(1/2), 90°] = [26.57°, 90°]: none is obtuse.
//
// Guarantees and measurements (tests/test_quadtree.cpp checks each):
//  - Validity: validate() passes; every input vertex is a vertex; every input segment is a chain
//    of subsegments; the domain's area equals the CDT's; every Steiner point is a corner of a
//    triangle of the domain and lies in the closed domain (the quadtree corners outside it are
//    dropped, and the rest of the hull is triangulated anew); every vertex lies in the supported
//    coordinate range (else the route gives way to the fallback), so the output reads back.
//  - Leaf size s against the local feature size lfs (the radius of the smallest disk centred at x
//    that meets two features that do not touch): s ≤ 2·lfs(x) at every x of a leaf that meets a
//    feature (the splitting rule: a disk of radius below s/2 centred in C lies in C grown by s/2,
//    where the features are pairwise touching), s ≤ 2·lfs(centre) for an empty leaf (a feature
//    within s/2 of the centre would meet it), and lfs(centre) ≤ 12·s (grading; 7.4 is the
//    largest ratio on the 13 data sets).
//  - Angles. Untouched squares: [26.57°, 90°]. Warped squares of a point set: at least 18.3° (the
//    worst case over an enumeration of their configurations with points outside each other's
//    leaves grown by half, not a proof; BEG's 3×3 separation gives the same worst case). Cells cut by segments
//    or the hull: no proof; on the data sets and the random tests the smallest angle is at least
//    min(9°, 0.9 θ), θ the smallest input angle (between two segments at a vertex, or of the hull).
//    BEG's point-set construction avoids obtuse triangles; this one does not (the largest angle
//    seen is 160°, next to a 6.5° input angle of Florida; 139° in the point sets).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

struct QuadtreeOptions {
  bool convex_hull = false;    // keep the whole convex hull (Triangle's -c); holes still carve
  bool strict = false;         // refuse crossing segments (InputError) instead of splitting them
  // BEG's warp towards segments (step 4 above): a corner moves onto a segment crossing one of its
  // edges within this fraction of the leaf size, or lying this fraction of its largest leaf from
  // it (and 0.4 of its smallest). In (0, 0.5); larger values move more corners and leave fewer,
  // fatter pieces in cut cells.
  double snap_fraction = 0.4;
  // Deepest level of the quadtree (cells of size root / 2^max_depth); at most 52 (cell corners
  // are then still distinct doubles for inputs near the origin).
  unsigned max_depth = 50;
  // Most leaves the quadtree may have; beyond it the route falls back (QuadtreeStats::fallback)
  // instead of running out of memory or time. 0: automatic, 1024 per input feature (vertex or
  // segment) but at least 2^20 and at most 2^26.
  std::size_t max_leaves = 0;
  bool keep_leaves = false;    // fill QuadtreeStats::leaf_cells (used by the tests)
  // 0: two threads on large inputs (about 10^4 points and up); 1: one thread; 2: two threads
  // whatever the size (testing). The output is byte-identical in all three.
  unsigned threads = 0;
  // Testing only: skip the quadtree route and build the fallback (see QuadtreeStats::fallback).
  bool force_fallback = false;
};

// A leaf of the final quadtree: lower-left corner, side, and whether its closed square meets a
// feature (a vertex or a segment).
struct QuadtreeLeaf {
  double x = 0.0, y = 0.0, size = 0.0;
  bool meets_feature = false;
};

struct QuadtreeStats {
  ConstrainStats input;              // the cleaning CDT (duplicates, crossings, warnings)
  std::size_t features_vertices = 0;
  std::size_t features_segments = 0; // subsegments of the clean input (plus hull edges if any)
  std::size_t leaves = 0;
  unsigned depth = 0;                // deepest leaf level
  std::size_t splits_feature = 0;    // splits by the "meets the input simply" rule
  std::size_t splits_balance = 0;    // splits to balance neighbours
  std::size_t splits_warp = 0;       // splits by the warp rule
  std::size_t unresolved = 0;        // leaves at max_depth that still see the input non-simply
  std::size_t warped = 0;            // corners moved onto input vertices
  std::size_t snapped = 0;           // corners moved onto segments
  std::size_t on_segment = 0;        // corners lying exactly on a segment (not moved)
  std::size_t crossings = 0;         // Steiner points where segments cross cell edges
  std::size_t centres = 0;           // Steiner points at the centre of a distorted cell or piece
  std::size_t table_cells = 0;       // leaves triangulated by the case table
  std::size_t program_cells = 0;     // warped or cut leaves triangulated by the dynamic program
  bool fallback = false;             // the quadtree route failed; the output is the CDT of the
  std::string fallback_reason;       //   input plus the quadtree's corners (valid, no guarantees)
  std::vector<std::string> warnings;
  double seconds_input = 0.0;        // cleaning (CDT or, for a point set, sort + hull)
  double seconds_tree = 0.0;         // splitting, balancing
  double seconds_mesh = 0.0;         // warping, cutting, triangulating, assembling
  double seconds_carve = 0.0;
  std::vector<QuadtreeLeaf> leaf_cells;  // only with QuadtreeOptions::keep_leaves
};

// Quadtree refinement of a point set (.node: the domain is the convex hull) or a PSLG (.poly: the
// domain the segments enclose minus the holes). Input points keep their ids (duplicates are
// VertexKind::kDuplicate); Steiner points come after them, VertexKind::kSteinerOnSegment on input
// segments and kSteiner elsewhere, only those the domain's triangles use (quadtree corners outside
// the domain are dropped; carved kOutside triangles of the kept vertices fill the rest of the
// hull). Throws InputError for input the CDT refuses.
MWST_API Mesh quadtree_refinement(const Pslg& pslg, const QuadtreeOptions& options = {},
                         QuadtreeStats* stats = nullptr);

namespace detail {

// Max–min-angle triangulation of a simple polygon given counter-clockwise (collinear and slightly
// reflex vertices allowed), by dynamic programming over its diagonals (O(k³), k ≤ 64). Every
// triangle is strictly counter-clockwise (exact orient2d) and every diagonal lies inside the
// polygon (exact tests). Ties are broken by the smaller total diagonal length. Returns false if the
// polygon has no such triangulation (degenerate); otherwise appends k − 2 triangles of local
// indices to `out`.
MWST_API bool triangulate_polygon(const std::vector<Point>& polygon,
                         std::vector<std::array<std::uint8_t, 3>>& out);

// Testing only: triangulate_polygon() giving the program's smallest-angle sine too (the value
// triangulate_piece() compares with the fan), with its shortcut for weakly convex quadrilaterals
// (general = false) or the general program for every k (general = true). The two must agree
// exactly: the same triangles in the same order and the same quality.
MWST_API bool triangulate_polygon_quality(const std::vector<Point>& polygon,
                                 std::vector<std::array<std::uint8_t, 3>>& out, double& quality, bool general);

// Sine of the smallest angle over the given triangles of a polygon (+inf if there are none).
MWST_API double triangulation_quality(const std::vector<Point>& polygon,
                             const std::vector<std::array<std::uint8_t, 3>>& triangles);

// The fan from the polygon's vertex average: false unless every triangle (centre, v_i, v_i+1) is
// strictly counter-clockwise (exact); `quality` receives its smallest-angle sine.
MWST_API bool centroid_fan(const std::vector<Point>& polygon, Point& centre, double& quality);

// Triangulates a warped or cut piece of a cell: the max–min-angle triangulation of its boundary,
// unless that has an angle below 20° and the fan from the polygon's vertex average is better; then
// that fan (its triangles use index polygon.size() for `centre`, and used_centre is set). Returns
// false if neither is valid.
MWST_API bool triangulate_piece(const std::vector<Point>& polygon, std::vector<std::array<std::uint8_t, 3>>& out,
                       Point& centre, bool& used_centre);

// The case table: for each mask of present side midpoints (bit 0 bottom, 1 right, 2 top, 3 left),
// triangles over the slots 0 BL, 1 bottom-mid, 2 BR, 3 right-mid, 4 TR, 5 top-mid, 6 TL, 7 left-mid.
MWST_API const std::array<std::vector<std::array<std::uint8_t, 3>>, 16>& quadtree_case_table();

}  // namespace detail

}  // namespace mwst
