// mwst/io/draw.hpp — pictures of triangulations (PNG, SVG or PDF, drawn with cairo, which is
// loaded when the first picture is drawn).
//
// What `mwst draw`, `mwst triangulate --draw` and the Figure 4 panels of `mwst experiment` draw
// (after the figures of Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight"): the
// domain triangles lightly filled with thin edges, the input segments and the domain boundary bold,
// and the Steiner points marked by small red disks. Several pictures can be set side by side in one
// file, each fitted to its own panel with a title above it. The format is chosen by the file name's
// extension: .png (raster, pixels), .svg or .pdf (vector, points).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::io {

// One panel: a triangulation and what to emphasise in it. All coordinates are the mesh's own.
struct Picture {
  std::vector<Point> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into points
  std::vector<std::array<Point, 2>> bold_segments;      // input segments and domain boundary
  std::vector<std::uint32_t> marked;                    // Steiner points (indices into points)
  std::string title;  // printed above the panel (may be empty)
  std::string note;   // printed in the middle of the panel (e.g. why there is no mesh)
};

// The domain triangles of `mesh`; bold: its subsegments and the edges between a domain triangle and
// a triangle outside the domain (the boundary: segments, or the convex hull of a point set);
// marked: the vertices of domain triangles that are not input points.
MWST_API Picture picture_of(const Mesh& mesh);

// A mesh read back from files (read_mesh) for the graph `input` it was made from. Bold: the input
// segments and the mesh's boundary edges (edges of one triangle only); marked: the vertices used by
// triangles whose coordinates are not those of an input point.
MWST_API Picture picture_of(const MeshFiles& mesh, const Pslg& input);

enum class PictureFormat { kPng, kSvg, kPdf };

// The format named by the extension of `path` (.png, .svg, .pdf; any letter case). Anything else is
// an InputError naming the path.
MWST_API PictureFormat picture_format(const std::string& path);

struct DrawOptions {
  // The larger side of each panel's drawing area: pixels for PNG, points (1/72 inch) for SVG/PDF.
  double panel_size = 600.0;
  std::size_t columns = 0;      // panels per row; 0 = all in one row
  double edge_width = 0.6;      // triangle edges
  double bold_width = 2.0;      // input segments and boundary
  // Steiner point disks: this radius, or less where the mesh is fine (at most a third of the
  // shortest edge at the point, at least a quarter of this radius), so dense regions stay legible.
  double marker_radius = 2.2;
  double font_size = 14.0;      // panel titles; the caption is 1.2 times larger
  std::string caption;          // a heading over all panels (may be empty)
};

// Renders the panels and returns the file's bytes in the given format. Throws InputError if the
// panels are empty, ResourceError (mwst/algorithms/pipeline.hpp) if cairo's library
// (libcairo.so.2, loaded by the first drawing) cannot be loaded, and InternalError if cairo fails.
MWST_API std::string render_pictures(const std::vector<Picture>& panels, PictureFormat format,
                            const DrawOptions& options = {});

// Renders and writes `path` atomically (write_file_atomic), the format chosen by its extension.
MWST_API void draw_pictures(const std::vector<Picture>& panels, const std::string& path,
                   const DrawOptions& options = {});

}  // namespace mwst::io
