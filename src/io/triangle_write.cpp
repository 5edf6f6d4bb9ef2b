// src/io/triangle_write.cpp — the writer of Triangle's files (mwst/io/triangle_files.hpp):
// format_triangle_files (the files of flat arrays: .node, .ele, .poly, .edge, .neigh, .v.node,
// .v.edge), write_triangle_files, and write_mesh (to_arrays, then those two). write_file_atomic
// lives in atomic_file.cpp.
//
// Each file is formatted record by record (numbers via std::to_chars, doubles shortest
// round-trip); a large one in contiguous ranges of records on several threads, each range into
// its own piece of text (on huge pages: support/huge_pages.hpp), so that the pieces in order are
// the text one thread would write. The files are written two at a time, each atomically
// (temporary name, rename); if one fails, those already written are removed again.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <charconv>
#include <exception>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "support/huge_pages.hpp"
#include "support/parallel.hpp"

namespace mwst::io {

namespace {

// ---- text begins here ---------------------------------------------------------------------------

constexpr std::size_t kMaxIntChars = 20, kMaxDoubleChars = 24;

// A text built by appending: numbers with std::to_chars (doubles shortest round-trip) written
// straight into the string's storage, with one room check per piece.
class Text {
 public:
  Text& operator<<(std::string_view piece) {
    room(piece.size());
    std::memcpy(text_.data() + used_, piece.data(), piece.size());
    used_ += piece.size();
    return *this;
  }
  Text& operator<<(char c) {
    room(1);
    text_[used_++] = c;
    return *this;
  }
  Text& integer(std::int64_t v) {
    room(kMaxIntChars);
    used_ = static_cast<std::size_t>(std::to_chars(text_.data() + used_, text_.data() + text_.size(), v).ptr - text_.data());
    return *this;
  }
  Text& real(double v) {
    room(kMaxDoubleChars + 8);
    used_ = static_cast<std::size_t>(std::to_chars(text_.data() + used_, text_.data() + text_.size(), v).ptr - text_.data());
    return *this;
  }
  // Room for n characters; a large room on huge pages (its first touch faults once per 2 MiB).
  void reserve(std::size_t n) {
    text_.reserve(n);
    if (n >= support::kHugePageWorthwhile) support::advise_huge_pages(text_.data(), text_.capacity());
  }
  std::string take() {
    text_.resize(used_);
    used_ = 0;
    return std::move(text_);
  }

 private:
  // The string's size runs at most 64 KiB ahead of the text (so that only what is written is
  // zeroed first); its capacity grows by doubling when reserve() was too small.
  void room(std::size_t n) {
    if (used_ + n > text_.size()) text_.resize(used_ + n + 65536);
  }
  std::string text_;
  std::size_t used_ = 0;
};

// Below this many records a file is formatted by one thread.
constexpr std::size_t kParallelRecords = std::size_t{1} << 15;

// The pieces of a file: `header`, then records 0..n-1, `line(i, text)` appending record i (or
// nothing) to `text`. Large files are cut into one contiguous range of records per worker, each
// formatted into its own piece (reserved for `line_bound` characters per record), so the pieces
// in order are what one thread writes.
template <class Line>
std::vector<std::string> format_records(std::string header, std::size_t n, std::size_t line_bound, unsigned threads,
                                        const Line& line) {
  const std::size_t ranges = n >= kParallelRecords ? support::worker_count(threads) : 1;
  std::vector<std::string> pieces(ranges + 1);
  pieces[0] = std::move(header);
  support::parallel_ranges(ranges, n, [&](std::size_t k, std::size_t begin, std::size_t end) {
    Text text;
    text.reserve((end - begin) * line_bound + 64);
    for (std::size_t i = begin; i < end; ++i) line(i, text);
    pieces[k + 1] = text.take();
  });
  return pieces;
}

// ---- text ends here -----------------------------------------------------------------------------

// The end of an output .poly: "H", then "i x y" per hole, and, when there are regions, "R", then
// "i x y attribute max-area" per region (Triangle's layout, numbered from `base`).
std::string poly_holes_and_regions(const std::vector<Point>& holes, const std::vector<Region>& regions,
                                   std::int64_t base) {
  Text out;
  out.integer(static_cast<std::int64_t>(holes.size())) << '\n';
  for (std::size_t i = 0; i < holes.size(); ++i) {
    out.integer(static_cast<std::int64_t>(i) + base) << ' ';
    out.real(holes[i].x) << ' ';
    out.real(holes[i].y) << '\n';
  }
  if (!regions.empty()) {
    out.integer(static_cast<std::int64_t>(regions.size())) << '\n';
    for (std::size_t i = 0; i < regions.size(); ++i) {
      out.integer(static_cast<std::int64_t>(i) + base) << ' ';
      out.real(regions[i].seed.x) << ' ';
      out.real(regions[i].seed.y) << ' ';
      out.real(regions[i].attribute) << ' ';
      out.real(regions[i].max_area) << '\n';
    }
  }
  return out.take();
}

// ---- the files of flat arrays (format_triangle_files) begin here --------------------------------

// The edges of the triangulation in Triangle's order: triangle by triangle, the edge opposite
// corner k = 0, 1, 2 (from corner k+1 to corner k+2), where the neighbour across it is none or a
// later triangle. Each edge with its triangle, the corner opposite, and its subsegment (or -1).
struct MeshEdge {
  std::uint32_t triangle;
  unsigned opposite;
  std::uint32_t a, b;
  std::int64_t segment;
};

// Triangle's boundary markers of the vertices and subsegments of `mesh` (see format_triangle_files),
// and the edges.
struct Carried {
  std::vector<MeshEdge> edges;
  std::vector<std::int32_t> vertex_marker;
  std::vector<std::int32_t> segment_marker;
  std::vector<std::array<std::uint32_t, 2>> boundary_edges;  // on the boundary, no subsegment
};

// The segments of a mesh by their lower endpoint: row v (first_[v] to first_[v + 1]) holds the
// segments {v, w} with w ≥ v, sorted by w and then by index, so that the first of repeated
// segments is the one found. Flat arrays built by a counting sort, and a binary search in a row:
// a vertex with many segments (the apex of a fan of thousands of wedges) costs a logarithm, and a
// million segments no allocation each (a hash map of them took half a second at 1M vertices).
class SegmentsByVertex {
 public:
  explicit SegmentsByVertex(const MeshArrays& mesh) {
    const std::size_t segments = mesh.segment_count();
    first_.assign(mesh.vertex_count() + 1, 0);
    for (std::size_t s = 0; s < segments; ++s) ++first_[lower(mesh, s) + 1];
    for (std::size_t v = 1; v < first_.size(); ++v) first_[v] += first_[v - 1];
    std::vector<std::uint32_t> next(first_.begin(), first_.end() - 1);
    row_.resize(segments);
    for (std::size_t s = 0; s < segments; ++s) {
      const std::uint32_t a = mesh.segments[2 * s], b = mesh.segments[2 * s + 1];
      row_[next[lower(mesh, s)]++] = {std::max(a, b), static_cast<std::uint32_t>(s)};
    }
    for (std::size_t v = 0; v + 1 < first_.size(); ++v) {
      if (first_[v + 1] - first_[v] > 1) std::sort(row_.begin() + first_[v], row_.begin() + first_[v + 1]);
    }
  }

  // The index of segment {a, b} (either direction), or -1.
  std::int64_t find(std::uint32_t a, std::uint32_t b) const {
    const std::uint32_t low = std::min(a, b), high = std::max(a, b);
    const auto begin = row_.begin() + first_[low], end = row_.begin() + first_[low + 1];
    const auto at = std::lower_bound(begin, end, std::pair<std::uint32_t, std::uint32_t>{high, 0});
    return at != end && at->first == high ? static_cast<std::int64_t>(at->second) : -1;
  }

 private:
  static std::uint32_t lower(const MeshArrays& mesh, std::size_t s) {
    return std::min(mesh.segments[2 * s], mesh.segments[2 * s + 1]);
  }
  std::vector<std::uint32_t> first_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> row_;  // (other endpoint, segment index)
};

// Carries the markers over to the triangulation (Carried). `list_edges`: fill Carried::edges (for
// .edge and .v.edge); otherwise only the boundary edges are looked at.
Carried carry_markers(const MeshArrays& mesh, bool list_edges) {
  Carried out;
  const std::size_t nt = mesh.triangle_count();
  const std::size_t nv = mesh.vertex_count();
  const SegmentsByVertex segment_of(mesh);
  std::vector<bool> segment_on_boundary(mesh.segment_count(), false);
  std::vector<bool> vertex_on_boundary(nv, false);
  if (list_edges) out.edges.reserve(3 * nt / 2 + 3);
  for (std::size_t t = 0; t < nt; ++t) {
    for (unsigned k = 0; k < 3; ++k) {
      const std::int32_t across = mesh.neighbours[3 * t + k];
      if (across >= 0 && (!list_edges || static_cast<std::size_t>(across) < t)) continue;
      const std::uint32_t a = mesh.triangles[3 * t + (k + 1) % 3], b = mesh.triangles[3 * t + (k + 2) % 3];
      const std::int64_t segment = segment_of.find(a, b);
      if (across < 0) {
        vertex_on_boundary[a] = vertex_on_boundary[b] = true;
        if (segment >= 0) {
          segment_on_boundary[static_cast<std::size_t>(segment)] = true;
        } else {
          out.boundary_edges.push_back({a, b});
        }
      }
      if (list_edges) out.edges.push_back({static_cast<std::uint32_t>(t), k, a, b, segment});
    }
  }
  // Segments: a nonzero marker stays; else 1 on the boundary, 0 inside.
  out.segment_marker.resize(mesh.segment_count());
  for (std::size_t s = 0; s < mesh.segment_count(); ++s) {
    const std::int32_t own = mesh.segment_markers[s];
    out.segment_marker[s] = own != 0 ? own : segment_on_boundary[s] ? 1 : 0;
  }
  // Vertices: a nonzero marker stays; else a nonzero marker of a segment through it; else 1 on
  // the boundary, 0 inside.
  out.vertex_marker.assign(mesh.vertex_markers.begin(), mesh.vertex_markers.end());
  std::vector<std::int32_t> from_segment(nv, 0);
  for (std::size_t s = 0; s < mesh.segment_count(); ++s) {
    const std::int32_t own = mesh.segment_markers[s];
    if (own == 0) continue;
    for (const std::uint32_t v : {mesh.segments[2 * s], mesh.segments[2 * s + 1]}) {
      if (from_segment[v] == 0) from_segment[v] = own;
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (out.vertex_marker[v] != 0) continue;
    out.vertex_marker[v] = from_segment[v] != 0 ? from_segment[v] : vertex_on_boundary[v] ? 1 : 0;
  }
  return out;
}


// Output numbers of the vertices, from `base`: all of them, or with -j (jettison) only those of
// some triangle (the others left out, -1).
class VertexNumbers {
 public:
  VertexNumbers(const MeshArrays& mesh, const TriangleOutput& what) : base_(what.first_index) {
    const std::size_t nv = mesh.vertex_count();
    if (!what.jettison) {
      kept_ = nv;
      return;
    }
    std::vector<bool> used(nv, false);
    for (const std::uint32_t v : mesh.triangles) used[v] = true;
    number_.assign(nv, -1);
    for (std::size_t v = 0; v < nv; ++v) {
      if (used[v]) number_[v] = static_cast<std::int64_t>(kept_++) + base_;
    }
  }
  std::int64_t operator[](std::size_t v) const { return number_.empty() ? static_cast<std::int64_t>(v) + base_ : number_[v]; }
  std::size_t kept() const { return kept_; }

 private:
  std::int64_t base_;
  std::vector<std::int64_t> number_;  // empty: vertex v is v + base
  std::size_t kept_ = 0;
};

// A header line of numbers.
std::string header_line(std::initializer_list<std::int64_t> numbers) {
  Text out;
  bool first = true;
  for (const std::int64_t n : numbers) {
    if (!first) out << ' ';
    out.integer(n);
    first = false;
  }
  out << '\n';
  return out.take();
}

// PREFIX.node: the numbered vertices, with their attributes, and their boundary markers when
// `markers`.
std::vector<std::string> node_file(const MeshArrays& mesh, const Carried& carried, const VertexNumbers& number,
                                   bool markers, unsigned threads) {
  const std::size_t attributes = mesh.attributes_per_vertex;
  const std::string header = header_line({static_cast<std::int64_t>(number.kept()), 2,
                                          static_cast<std::int64_t>(attributes), markers ? 1 : 0});
  const std::size_t line_bound = 2 * kMaxIntChars + (2 + attributes) * (kMaxDoubleChars + 1) + 4;
  return format_records(header, mesh.vertex_count(), line_bound, threads, [&](std::size_t v, Text& out) {
    if (number[v] < 0) return;
    out.integer(number[v]) << ' ';
    out.real(mesh.vertices[2 * v]) << ' ';
    out.real(mesh.vertices[2 * v + 1]);
    for (std::size_t k = 0; k < attributes; ++k) (out << ' ').real(mesh.vertex_attributes[v * attributes + k]);
    if (markers) (out << ' ').integer(carried.vertex_marker[v]);
    out << '\n';
  });
}

// PREFIX.ele: every triangle, corners counter-clockwise, with its regional attribute when asked.
std::vector<std::string> ele_file(const MeshArrays& mesh, const VertexNumbers& number, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t nt = mesh.triangle_count();
  const bool attribute = what.triangle_attributes;
  const std::string header = header_line({static_cast<std::int64_t>(nt), 3, attribute ? 1 : 0});
  const std::size_t line_bound = 4 * (kMaxIntChars + 1) + kMaxDoubleChars + 2;
  return format_records(header, nt, line_bound, what.threads, [&](std::size_t t, Text& out) {
    out.integer(static_cast<std::int64_t>(t) + base);
    for (unsigned k = 0; k < 3; ++k) (out << ' ').integer(number[mesh.triangles[3 * t + k]]);
    if (attribute) {
      out << ' ';
      out.real(mesh.triangle_attributes.empty() ? 0.0 : mesh.triangle_attributes[t]);
    }
    out << '\n';
  });
}

// PREFIX.poly: no vertices (they are in PREFIX.node), every subsegment, then the boundary edges
// that are none (the hull of a point set) with marker 1, then the holes and regions.
std::vector<std::string> poly_file(const MeshArrays& mesh, const Carried& carried, const VertexNumbers& number,
                                   const std::vector<Point>& holes, const std::vector<Region>& regions,
                                   const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const bool markers = what.boundary_markers;
  const std::size_t subsegments = mesh.segment_count(), boundary = carried.boundary_edges.size();
  const std::string header = "0 2 0 " + std::string(markers ? "1" : "0") + '\n' +
                             header_line({static_cast<std::int64_t>(subsegments + boundary), markers ? 1 : 0});
  const auto segment_line = [&](std::size_t i, Text& out) {
    const bool is_subsegment = i < subsegments;
    const std::uint32_t a = is_subsegment ? mesh.segments[2 * i] : carried.boundary_edges[i - subsegments][0];
    const std::uint32_t b = is_subsegment ? mesh.segments[2 * i + 1] : carried.boundary_edges[i - subsegments][1];
    out.integer(static_cast<std::int64_t>(i) + base) << ' ';
    out.integer(number[a]) << ' ';
    out.integer(number[b]);
    if (markers) (out << ' ').integer(is_subsegment ? carried.segment_marker[i] : 1);
    out << '\n';
  };
  std::vector<std::string> pieces =
      format_records(header, subsegments + boundary, 4 * (kMaxIntChars + 1), what.threads, segment_line);
  pieces.push_back(poly_holes_and_regions(holes, regions, base));
  return pieces;
}

// PREFIX.edge: the edges in Triangle's order (Carried::edges), with markers when `markers`: a
// subsegment's marker, else 1 on the boundary, 0 inside.
std::vector<std::string> edge_file(const MeshArrays& mesh, const Carried& carried, const VertexNumbers& number,
                                   const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const bool markers = what.boundary_markers;
  const std::string header = header_line({static_cast<std::int64_t>(carried.edges.size()), markers ? 1 : 0});
  return format_records(header, carried.edges.size(), 4 * (kMaxIntChars + 1), what.threads, [&](std::size_t i, Text& out) {
    const MeshEdge& e = carried.edges[i];
    out.integer(static_cast<std::int64_t>(i) + base) << ' ';
    out.integer(number[e.a]) << ' ';
    out.integer(number[e.b]);
    if (markers) {
      const bool boundary = mesh.neighbours[3 * e.triangle + e.opposite] < 0;
      const std::int32_t marker = e.segment >= 0 ? carried.segment_marker[static_cast<std::size_t>(e.segment)]
                                  : boundary     ? 1
                                                 : 0;
      (out << ' ').integer(marker);
    }
    out << '\n';
  });
}

// PREFIX.neigh: per triangle the triangles across its edges opposite corners 0, 1, 2 (-1: none).
std::vector<std::string> neigh_file(const MeshArrays& mesh, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t nt = mesh.triangle_count();
  return format_records(header_line({static_cast<std::int64_t>(nt), 3}), nt, 4 * (kMaxIntChars + 1), what.threads,
                        [&](std::size_t t, Text& out) {
                          out.integer(static_cast<std::int64_t>(t) + base);
                          for (unsigned k = 0; k < 3; ++k) {
                            const std::int32_t across = mesh.neighbours[3 * t + k];
                            (out << ' ').integer(across < 0 ? -1 : across + base);
                          }
                          out << '\n';
                        });
}

// The Voronoi diagram (-v). Its vertices are the circumcentres of the triangles; each edge of the
// triangulation is dual to a Voronoi edge between the circumcentres on either side, or, on the
// boundary, to a ray from the one triangle's circumcentre perpendicular to the edge, outward.

// PREFIX.v.node: the circumcentre of each triangle.
std::vector<std::string> voronoi_node_file(const MeshArrays& mesh, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t nt = mesh.triangle_count();
  const std::size_t line_bound = kMaxIntChars + 2 * kMaxDoubleChars + 3;
  return format_records(header_line({static_cast<std::int64_t>(nt), 2, 0, 0}), nt, line_bound, what.threads,
                        [&](std::size_t t, Text& out) {
                          const auto corner = [&](unsigned k) {
                            const std::uint32_t v = mesh.triangles[3 * t + k];
                            return Point{mesh.vertices[2 * v], mesh.vertices[2 * v + 1]};
                          };
                          const Point c = circumcenter(corner(0), corner(1), corner(2));
                          out.integer(static_cast<std::int64_t>(t) + base) << ' ';
                          out.real(c.x) << ' ';
                          out.real(c.y) << '\n';
                        });
}

// PREFIX.v.edge: per edge of the triangulation (Carried::edges) its two Voronoi vertices, or its
// one Voronoi vertex, -1 and the direction of the ray.
std::vector<std::string> voronoi_edge_file(const MeshArrays& mesh, const Carried& carried, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t line_bound = 3 * (kMaxIntChars + 1) + 2 * (kMaxDoubleChars + 1) + 4;
  const std::string header = header_line({static_cast<std::int64_t>(carried.edges.size()), 0});
  return format_records(header, carried.edges.size(), line_bound, what.threads, [&](std::size_t i, Text& out) {
    const MeshEdge& e = carried.edges[i];
    out.integer(static_cast<std::int64_t>(i) + base) << ' ';
    out.integer(static_cast<std::int64_t>(e.triangle) + base) << ' ';
    const std::int32_t across = mesh.neighbours[3 * e.triangle + e.opposite];
    if (across >= 0) {
      out.integer(across + base) << '\n';
    } else {
      // The triangle lies left of a→b (counter-clockwise), so (b - a) turned clockwise,
      // (by - ay, ax - bx), points out of the triangulation.
      const double ax = mesh.vertices[2 * e.a], ay = mesh.vertices[2 * e.a + 1];
      const double bx = mesh.vertices[2 * e.b], by = mesh.vertices[2 * e.b + 1];
      out << "-1 ";
      out.real(by - ay) << ' ';
      out.real(ax - bx) << '\n';
    }
  });
}

}  // namespace

std::string TriangleFile::text() const {
  std::size_t size = 0;
  for (const std::string& piece : pieces) size += piece.size();
  std::string joined;
  joined.reserve(size);
  for (const std::string& piece : pieces) joined += piece;
  return joined;
}

// The steps: carry_markers, the vertex numbers, then one formatter per file, in Triangle's order.
std::vector<TriangleFile> format_triangle_files(const MeshArrays& mesh, const std::vector<Point>& holes,
                                                const std::vector<Region>& regions, const TriangleOutput& what) {
  if (mesh.vertex_attributes.size() != mesh.attributes_per_vertex * mesh.vertex_count()) {
    throw InternalError("format_triangle_files: vertex_attributes do not hold attributes_per_vertex per vertex");
  }
  const Carried carried = carry_markers(mesh, what.edges || what.voronoi);
  const VertexNumbers numbers(mesh, what);
  std::vector<TriangleFile> files;
  if (what.node) files.push_back({".node", node_file(mesh, carried, numbers, what.boundary_markers, what.threads)});
  if (what.ele) files.push_back({".ele", ele_file(mesh, numbers, what)});
  if (what.poly) files.push_back({".poly", poly_file(mesh, carried, numbers, holes, regions, what)});
  if (what.edges) files.push_back({".edge", edge_file(mesh, carried, numbers, what)});
  if (what.neighbours) files.push_back({".neigh", neigh_file(mesh, what)});
  if (what.voronoi) {
    files.push_back({".v.node", voronoi_node_file(mesh, what)});
    files.push_back({".v.edge", voronoi_edge_file(mesh, carried, what)});
  }
  return files;
}

// ---- the files of flat arrays end here ----------------------------------------------------------

// Two files at a time (the kernel's copies of one overlap the other's); if any fails, the others
// are removed again and the first failure (in the order of `files`) is thrown.
void write_triangle_files(const std::string& prefix, const std::vector<TriangleFile>& files) {
  std::vector<char> written(files.size(), 0);
  try {
    support::parallel_for(files.size(), 2, [&](std::size_t i) {
      std::vector<std::string_view> pieces(files[i].pieces.begin(), files[i].pieces.end());
      write_file_atomic(prefix + files[i].extension, pieces);
      written[i] = 1;
    });
  } catch (...) {
    for (std::size_t i = 0; i < files.size(); ++i) {
      if (written[i]) ::unlink((prefix + files[i].extension).c_str());
    }
    throw;
  }
}

void write_mesh(const Mesh& mesh, const std::string& prefix, int first_index, const std::vector<Point>& holes,
                const std::vector<Region>& regions) {
  const MeshArrays arrays = to_arrays(mesh);
  write_triangle_files(prefix, format_triangle_files(arrays, holes, regions, mesh_files(arrays, first_index)));
}

TriangleOutput mesh_files(const MeshArrays& mesh, int first_index) {
  TriangleOutput what;
  what.poly = mesh.segment_count() > 0;
  what.first_index = first_index;
  return what;
}

}  // namespace mwst::io
