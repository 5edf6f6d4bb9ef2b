// mwst/io.hpp — Triangle's file formats (.node, .poly, .ele, .edge) in and out.
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

#include "mwst/mesh.hpp"
#include "mwst/pslg.hpp"

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

// Writes PREFIX.node, PREFIX.ele and (if the mesh has subsegments) PREFIX.poly, numbering from
// `first_index`. Only live, finite, in-domain triangles are written. Atomic per file.
MWST_API void write_mesh(const Mesh& mesh, const std::string& prefix, int first_index = 1);

// Writes `content` (the concatenation of `pieces`) to `path` atomically (temporary name in the
// same directory, then rename).
MWST_API void write_file_atomic(const std::string& path, std::span<const std::string_view> pieces);
MWST_API void write_file_atomic(const std::string& path, std::string_view content);

}  // namespace mwst::io
