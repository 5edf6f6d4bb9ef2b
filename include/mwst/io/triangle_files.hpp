// mwst/io/triangle_files.hpp — Triangle's file formats (.node, .poly, .ele, .area, .edge, .neigh, .v.node,
// .v.edge) in and out.
//
// Readers follow Triangle's conventions: '#' starts a comment anywhere on a line, blank lines are
// skipped, indices may start at 0 or 1 (decided by the first vertex's index, as Triangle does),
// attributes and boundary markers are tolerated, and so are further numbers at the end of a line
// (Triangle ignores them), but not words. Lines may end in "\n", "\r\n" or "\r"; a UTF-8
// byte-order mark at the start of a file is skipped. Every problem is an InputError naming the file
// and line. Coordinates outside the supported range (see geometry.hpp), NaN and Inf are rejected.
// Writers print shortest round-trip decimals, so coordinates read back as the same doubles; they
// write to a temporary name and rename when complete, so a failure leaves no partial file.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mwst/algorithms/arrays.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::io {

// Reads a .node file (points only).
MWST_API Pslg read_node(const std::string& path);
// Reads a .poly file; a vertex count of 0 reads the .node beside it (same stem).
MWST_API Pslg read_poly(const std::string& path);
// Dispatches on the extension (.node or .poly); anything else is an InputError.
MWST_API Pslg read_input(const std::string& path);

// Parses from memory (used by the fuzzers and tests); `name` is used in messages.
MWST_API Pslg parse_node(std::string_view text, const std::string& name);
MWST_API Pslg parse_poly(std::string_view text, const std::string& name);

// A mesh read back from PREFIX.node / PREFIX.ele (and PREFIX.poly when present): used by
// `mwst check`, `mwst bundle` and `mwst draw`.
struct MeshFiles {
  std::vector<Point> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // 0-based
  std::vector<Segment> segments;                        // from PREFIX.poly (may be empty)
};
MWST_API MeshFiles read_mesh(const std::string& prefix);

// Writes PREFIX.node, PREFIX.ele and (if the mesh has subsegments) PREFIX.poly of the domain
// triangles of `mesh`, numbered from `first_index`: to_arrays (mwst/algorithms/arrays.hpp), then
// format_triangle_files with mesh_files' choice and write_triangle_files. The .poly lists the
// `holes` and `regions` of the input after its subsegments, so that re-meshing it gives the same
// domain. A failure leaves none of the files behind.
MWST_API void write_mesh(const Mesh& mesh, const std::string& prefix, int first_index = 1,
                         const std::vector<Point>& holes = {}, const std::vector<Region>& regions = {});

// ---- an existing mesh to refine (Triangle's -r) ----

// Reads `ele_path` (a .ele naming vertices of pslg.points in pslg.first_index's numbering) into
// pslg.triangles (3 per triangle, 0-based). Extra nodes (six-node triangles) and attributes are
// ignored. A vertex that does not exist or a triangle naming one vertex twice is an InputError
// naming the file and line.
MWST_API void read_triangles(Pslg& pslg, const std::string& ele_path);
// Reads a Triangle .area file (its first line the triangle count, then "index maximum-area", a
// value <= 0 meaning no bound) into pslg.triangle_max_area; its count must be pslg.triangles'.
MWST_API void read_triangle_areas(Pslg& pslg, const std::string& area_path);
// The same from memory (fuzzers, tests): `points` vertices numbered from `base`.
MWST_API std::vector<std::uint32_t> parse_ele(std::string_view text, const std::string& name, std::size_t points,
                                              int base);
MWST_API std::vector<double> parse_area(std::string_view text, const std::string& name, std::size_t triangles);

// ---- Triangle's output files (`mwst triangle`) ----

// Which files to write and how, as Triangle's switches say (mwst/io/triangle_switches.hpp).
struct TriangleOutput {
  bool node = true;                  // PREFIX.node (-N: no)
  bool ele = true;                   // PREFIX.ele (-E: no)
  bool poly = false;                 // PREFIX.poly (-p or -c, unless -P)
  bool edges = false;                // PREFIX.edge (-e)
  bool neighbours = false;           // PREFIX.neigh (-n)
  bool voronoi = false;              // PREFIX.v.node and PREFIX.v.edge (-v)
  bool boundary_markers = true;      // markers in .node, .poly, .edge (-B: none)
  bool triangle_attributes = false;  // the regional attribute of each triangle in .ele (-A)
  bool jettison = false;             // leave vertices in no triangle out (-j), renumbering the rest
  int first_index = 1;               // the number of the first item of every file
  unsigned threads = 0;              // threads formatting a large file (0: one per hardware thread)
};

// The files of a mesh as `mwst triangulate` and write_mesh write them: PREFIX.node, PREFIX.ele and,
// when it has subsegments, PREFIX.poly, with boundary markers, numbered from `first_index`.
MWST_API TriangleOutput mesh_files(const MeshArrays& mesh, int first_index);

// One output file: its extension (".node", ".v.edge", ...) and its text, in pieces (a large file
// is formatted in parts on several threads; the pieces are never joined on the way to the disk).
struct MWST_API TriangleFile {
  std::string extension;
  std::vector<std::string> pieces;  // the text is their concatenation
  std::string text() const;         // that concatenation
};

// The files `what` asks for, in Triangle's formats and layouts:
//   .node   "N 2 A B", then "i x y [attributes] [marker]" (A = MeshArrays::attributes_per_vertex)
//   .ele    "T 3 A", then "i a b c [attribute]" (corners counter-clockwise)
//   .poly   "0 2 0 B" (the vertices are the .node's), "S B", "i a b [marker]" for every subsegment
//           and every boundary edge, then the holes "H", "i x y" and the regions "R",
//           "i x y attribute max-area" (when there are any), so that re-meshing it gives the same
//           domain
//   .edge   "E B", then "i a b [marker]" for every edge, triangle by triangle, the edge opposite
//           corner 0, 1, 2 (from the corner after it to the one before), where the neighbour
//           across it is none or later
//   .neigh  "T 3", then "i n0 n1 n2": the triangle opposite corner k, or -1
//   .v.node "T 2 0 0", then "i x y": the circumcentre of triangle i (the Voronoi vertex)
//   .v.edge "E 0", then "i p q" for the Voronoi edge dual to edge i of the .edge, or "i p -1 dx dy"
//           for a ray: from the circumcentre of the boundary edge's triangle, perpendicular to
//           the edge, outward (dx dy is the edge's direction turned clockwise)
// Boundary markers are carried as Triangle carries them: an edge keeps a nonzero marker of the
// segment it lies on, else it is 1 on the boundary of the triangulation (holes included) and 0
// inside; a vertex keeps a nonzero marker of its own, else takes a nonzero marker of a segment
// through it, else 1 on the boundary and 0 inside. Vertex attributes are MeshArrays::vertex_attributes.
// The files are the same text whatever TriangleOutput::threads.
MWST_API std::vector<TriangleFile> format_triangle_files(const MeshArrays& mesh, const std::vector<Point>& holes,
                                                        const std::vector<Region>& regions,
                                                        const TriangleOutput& what);

// Writes PREFIX + extension of each file, each atomically (write_file_atomic), two at a time; if
// one fails, those already written are removed again and the first failure is thrown.
MWST_API void write_triangle_files(const std::string& prefix, const std::vector<TriangleFile>& files);

// Writes `content` (the concatenation of `pieces`) to `path` atomically (temporary name in the
// same directory, then rename).
MWST_API void write_file_atomic(const std::string& path, std::span<const std::string_view> pieces);
MWST_API void write_file_atomic(const std::string& path, std::string_view content);

}  // namespace mwst::io
