// src/io/triangle_write.cpp — the writers of Triangle's files (mwst/io/triangle_files.hpp): the
// mesh writer (write_mesh) and format_triangle_files (the files of flat arrays: .node, .ele,
// .poly, .edge, .neigh, .v.node, .v.edge). write_file_atomic lives in atomic_file.cpp.
//
// Each file is formatted into buffers sized for its longest possible text (numbers via
// std::to_chars, shortest round-trip), large meshes in two halves on two threads, and written with
// write_file_atomic (temporary name, rename); if a later file of a mesh fails, the earlier ones are
// removed again.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <algorithm>
#include <array>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mesh/keys.hpp"

namespace mwst::io {

namespace {

// ---- text buffers begin here --------------------------------------------------------------------

// A text being written into storage sized for its longest possible content (uninitialised; only
// the pages written are ever touched): numbers go straight in with std::to_chars, with no capacity
// check per character. (Plain allocation without huge-page advice: for output buffers the kernel's
// huge-page compaction cost twice the system time in measurements.)
class TextBuffer {
 public:
  // (new char[] leaves the storage uninitialised, as malloc does, and throws std::bad_alloc.)
  explicit TextBuffer(std::size_t capacity) : data_(new char[capacity]), end_(data_.get()) {}
  void put(char c) { *end_++ = c; }
  void put(std::string_view text) {
    std::memcpy(end_, text.data(), text.size());
    end_ += text.size();
  }
  void put_int(std::int64_t v) { end_ = std::to_chars(end_, end_ + 24, v).ptr; }
  void put_double(double v) { end_ = std::to_chars(end_, end_ + 32, v).ptr; }  // shortest round-trip
  std::string_view view() const { return {data_.get(), static_cast<std::size_t>(end_ - data_.get())}; }

 private:
  std::unique_ptr<char[]> data_;
  char* end_;
};

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
  void reserve(std::size_t n) { text_.reserve(n); }
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

// ---- text buffers end here ----------------------------------------------------------------------

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

// ---- the mesh writer (write_mesh) begins here ---------------------------------------------------

// Lines first..last-1 of PREFIX.node (vertex i is record i + base).
void format_node_lines(const Mesh& mesh, std::size_t first, std::size_t last, std::int64_t base,
                       TextBuffer& out) {
  for (std::size_t i = first; i < last; ++i) {
    out.put_int(static_cast<std::int64_t>(i) + base);
    out.put(' ');
    out.put_double(mesh.points[i].x);
    out.put(' ');
    out.put_double(mesh.points[i].y);
    out.put(' ');
    out.put_int(i < mesh.vertex_marker.size() ? mesh.vertex_marker[i] : 0);
    out.put('\n');
  }
}

// The PREFIX.ele lines of the in-domain triangles in slots first..last-1, numbered from `number`.
void format_ele_lines(const Mesh& mesh, TriangleId first, TriangleId last, std::int64_t number,
                      std::int64_t base, TextBuffer& out) {
  const std::size_t nv = mesh.points.size();
  for (TriangleId t = first; t < last; ++t) {
    if (!mesh.in_domain(t)) continue;
    out.put_int(number++);
    for (const VertexId v : mesh.triangles[t].v) {
      if (v >= nv) throw InternalError("write_mesh: triangle names a vertex that does not exist");
      out.put(' ');
      out.put_int(static_cast<std::int64_t>(v) + base);
    }
    out.put('\n');
  }
}

// The in-domain triangles among slots first..last-1.
std::int64_t count_in_domain(const Mesh& mesh, TriangleId first, TriangleId last) {
  std::int64_t count = 0;
  for (TriangleId t = first; t < last; ++t) count += mesh.in_domain(t) ? 1 : 0;
  return count;
}

// The texts of PREFIX.node (every vertex, with its boundary marker) and PREFIX.ele (the live,
// finite, in-domain triangles, corners counter-clockwise): each file is its header line followed
// by its first and second half.
struct NodeAndEleText {
  TextBuffer node_head, ele_head;
  TextBuffer node_first, node_second;
  TextBuffer ele_first, ele_second;
};

// Formats PREFIX.node and PREFIX.ele. A large mesh (`parallel`) is split at its middle vertex and
// its middle triangle slot, and the second halves are formatted on a second thread, each half of
// each file into its own buffer: the concatenations are the same text as one thread writes.
// Otherwise the second halves stay empty.
NodeAndEleText format_node_and_ele(const Mesh& mesh, std::int64_t base, bool parallel) {
  const std::size_t nv = mesh.points.size();
  const auto slots = static_cast<TriangleId>(mesh.triangles.size());
  const std::size_t node_split = parallel ? nv / 2 : nv;
  const TriangleId ele_split = parallel ? slots / 2 : slots;
  const std::int64_t count_first = count_in_domain(mesh, 0, ele_split);
  const std::int64_t count_second = count_in_domain(mesh, ele_split, slots);
  constexpr std::size_t kNodeLine = 2 * kMaxIntChars + 2 * kMaxDoubleChars + 4;
  constexpr std::size_t kEleLine = 4 * (kMaxIntChars + 1);
  NodeAndEleText text{TextBuffer(64), TextBuffer(64), TextBuffer(node_split * kNodeLine + 1),
                      TextBuffer((nv - node_split) * kNodeLine + 1),
                      TextBuffer(static_cast<std::size_t>(count_first) * kEleLine + 1),
                      TextBuffer(static_cast<std::size_t>(count_second) * kEleLine + 1)};
  text.node_head.put_int(static_cast<std::int64_t>(nv));
  text.node_head.put(" 2 0 1\n");
  text.ele_head.put_int(count_first + count_second);
  text.ele_head.put(" 3 0\n");
  std::exception_ptr worker_error;
  {
    std::jthread worker;  // joins on every way out of this block (a throw below included)
    auto second_halves = [&] {
      try {
        format_node_lines(mesh, node_split, nv, base, text.node_second);
        format_ele_lines(mesh, ele_split, slots, base + count_first, base, text.ele_second);
      } catch (...) {
        worker_error = std::current_exception();
      }
    };
    if (parallel) worker = std::jthread(second_halves);
    format_node_lines(mesh, 0, node_split, base, text.node_first);
    format_ele_lines(mesh, 0, ele_split, base, base, text.ele_first);
  }
  if (worker_error) std::rethrow_exception(worker_error);
  return text;
}

// Whether edge e of in-domain triangle t (of `slots`) gets a line in PREFIX.poly: every
// subsegment bordering the domain, once (seen from both sides, it is written from the
// lower-numbered triangle only).
inline bool poly_segment_from(const Mesh& mesh, TriangleId slots, TriangleId t, unsigned e) {
  const Handle h = make_handle(t, e);
  if (!mesh.is_segment(h)) return false;
  const Handle other = mesh.triangles[t].n[e];
  if (other == kNone) return true;
  const TriangleId u = triangle_of(other);
  return !(u < slots && u < t && mesh.in_domain(u) && mesh.is_segment(other));
}

// The number of segment lines of PREFIX.poly.
std::size_t count_poly_segments(const Mesh& mesh) {
  const auto slots = static_cast<TriangleId>(mesh.triangles.size());
  std::size_t segments = 0;
  for (TriangleId t = 0; t < slots; ++t) {
    if (!mesh.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) segments += poly_segment_from(mesh, slots, t, e) ? 1 : 0;
  }
  return segments;
}

// PREFIX.poly up to its holes: no vertices (they are in PREFIX.node), then the `segments`
// subsegments with their markers, numbered from `base`; empty when there are none.
TextBuffer format_poly_segments(const Mesh& mesh, std::size_t segments, std::int64_t base) {
  const auto slots = static_cast<TriangleId>(mesh.triangles.size());
  TextBuffer poly(segments * 4 * (kMaxIntChars + 1) + 64);
  if (segments == 0) return poly;
  poly.put("0 2 0 1\n");
  poly.put_int(static_cast<std::int64_t>(segments));
  poly.put(" 1\n");
  std::int64_t number = base;
  for (TriangleId t = 0; t < slots; ++t) {
    if (!mesh.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      if (!poly_segment_from(mesh, slots, t, e)) continue;
      const Handle h = make_handle(t, e);
      const std::size_t slot = 3 * static_cast<std::size_t>(t) + e;
      const std::int32_t marker = slot < mesh.segment_marker.size() ? mesh.segment_marker[slot] : 1;
      poly.put_int(number++);
      poly.put(' ');
      poly.put_int(static_cast<std::int64_t>(mesh.org(h)) + base);
      poly.put(' ');
      poly.put_int(static_cast<std::int64_t>(mesh.dest(h)) + base);
      poly.put(' ');
      poly.put_int(marker);
      poly.put('\n');
    }
  }
  return poly;
}

// Writes PREFIX.node, PREFIX.ele and (when `poly` is not empty) PREFIX.poly. Each file is atomic;
// if a later one fails, the earlier ones are removed again so that a failure leaves no partial
// mesh behind. With `parallel` the .node is written by a second thread while this one writes the
// .ele (the kernel's copies overlap).
void write_node_ele_poly(const std::string& prefix, const NodeAndEleText& text,
                         std::span<const std::string_view> poly, bool parallel) {
  const std::string node_path = prefix + ".node", ele_path = prefix + ".ele", poly_path = prefix + ".poly";
  const std::string_view node_text[3] = {text.node_head.view(), text.node_first.view(), text.node_second.view()};
  const std::string_view ele_text[3] = {text.ele_head.view(), text.ele_first.view(), text.ele_second.view()};
  std::exception_ptr node_error, ele_error;
  bool ele_written = false;
  {
    std::jthread node_writer;  // joins at the end of this block, and on every way out of it
    auto write_node = [&] {
      try {
        write_file_atomic(node_path, node_text);
      } catch (...) {
        node_error = std::current_exception();
      }
    };
    if (parallel) {
      node_writer = std::jthread(write_node);
    } else {
      write_node();
    }
    if (parallel || !node_error) {
      try {
        write_file_atomic(ele_path, ele_text);
        ele_written = true;
        if (!poly.empty()) write_file_atomic(poly_path, poly);
      } catch (...) {
        ele_error = std::current_exception();
      }
    }
  }
  if (node_error || ele_error) {
    if (!node_error) ::unlink(node_path.c_str());
    if (ele_written) ::unlink(ele_path.c_str());
    std::rethrow_exception(node_error ? node_error : ele_error);  // the first file's error first
  }
}

}  // namespace

// The steps: format_node_and_ele (two threads for a large mesh), count_poly_segments and
// format_poly_segments, poly_holes_and_regions, then write_node_ele_poly.
void write_mesh(const Mesh& mesh, const std::string& prefix, int first_index, const std::vector<Point>& holes,
                const std::vector<Region>& regions) {
  if (mesh.flags.size() != mesh.triangles.size()) {
    throw InternalError("write_mesh: flags and triangles differ in size");
  }
  const std::int64_t base = first_index;
  const auto slots = static_cast<TriangleId>(mesh.triangles.size());
  const bool parallel = mesh.points.size() + slots >= (std::size_t{1} << 16);
  const NodeAndEleText text = format_node_and_ele(mesh, base, parallel);
  const std::size_t segments = count_poly_segments(mesh);
  const TextBuffer poly = format_poly_segments(mesh, segments, base);
  const std::string holes_and_regions = segments > 0 ? poly_holes_and_regions(holes, regions, base) : std::string();
  const std::string_view poly_text[2] = {poly.view(), holes_and_regions};
  write_node_ele_poly(prefix, text, segments > 0 ? std::span<const std::string_view>(poly_text)
                                                 : std::span<const std::string_view>(), parallel);
}

// ---- the mesh writer ends here ------------------------------------------------------------------

// ---- the files of flat arrays (format_triangle_files) begin here --------------------------------

namespace {

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

// Carries the markers over to the triangulation (Carried). `list_edges`: fill Carried::edges (for
// .edge and .v.edge); otherwise only the boundary edges are looked at.
Carried carry_markers(const MeshArrays& mesh, bool list_edges) {
  Carried out;
  const std::size_t nt = mesh.triangle_count();
  const std::size_t nv = mesh.vertex_count();
  std::unordered_map<std::uint64_t, std::uint32_t> segment_of;
  segment_of.reserve(2 * mesh.segment_count());
  for (std::size_t s = 0; s < mesh.segment_count(); ++s) {
    segment_of.emplace(undirected_key(mesh.segments[2 * s], mesh.segments[2 * s + 1]), static_cast<std::uint32_t>(s));
  }
  std::vector<bool> segment_on_boundary(mesh.segment_count(), false);
  std::vector<bool> vertex_on_boundary(nv, false);
  if (list_edges) out.edges.reserve(3 * nt / 2 + 3);
  for (std::size_t t = 0; t < nt; ++t) {
    for (unsigned k = 0; k < 3; ++k) {
      const std::int32_t across = mesh.neighbours[3 * t + k];
      if (across >= 0 && (!list_edges || static_cast<std::size_t>(across) < t)) continue;
      const std::uint32_t a = mesh.triangles[3 * t + (k + 1) % 3], b = mesh.triangles[3 * t + (k + 2) % 3];
      std::int64_t segment = -1;
      if (!segment_of.empty()) {
        const auto found = segment_of.find(undirected_key(a, b));
        if (found != segment_of.end()) segment = found->second;
      }
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
// some triangle; -1 for a vertex left out. `kept` counts those numbered.
struct VertexNumbers {
  std::vector<std::int64_t> number;
  std::size_t kept = 0;
};

// Numbers the vertices for `what` (see VertexNumbers).
VertexNumbers number_vertices(const MeshArrays& mesh, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t nv = mesh.vertex_count();
  VertexNumbers out{std::vector<std::int64_t>(nv, 0), 0};
  std::vector<bool> used(nv, !what.jettison);
  if (what.jettison) {
    for (const std::uint32_t v : mesh.triangles) used[v] = true;
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (used[v]) out.number[v] = static_cast<std::int64_t>(out.kept++) + base;
    else out.number[v] = -1;
  }
  return out;
}

// PREFIX.node: the numbered vertices, with their boundary markers when `markers`.
std::string node_file(const MeshArrays& mesh, const Carried& carried, const VertexNumbers& numbers,
                      bool markers) {
  const std::vector<std::int64_t>& number = numbers.number;
  Text out;
  out.reserve(64 + numbers.kept * 64);
  out.integer(static_cast<std::int64_t>(numbers.kept)) << " 2 0 " << (markers ? "1" : "0") << '\n';
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (number[v] < 0) continue;
    out.integer(number[v]) << ' ';
    out.real(mesh.vertices[2 * v]) << ' ';
    out.real(mesh.vertices[2 * v + 1]);
    if (markers) (out << ' ').integer(carried.vertex_marker[v]);
    out << '\n';
  }
  return out.take();
}

// PREFIX.ele: every triangle, corners counter-clockwise, with its regional attribute when asked.
std::string ele_file(const MeshArrays& mesh, const VertexNumbers& numbers, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t nt = mesh.triangle_count();
  const std::vector<std::int64_t>& number = numbers.number;
  Text out;
  out.reserve(64 + nt * 48);
  out.integer(static_cast<std::int64_t>(nt)) << " 3 " << (what.triangle_attributes ? "1" : "0") << '\n';
  for (std::size_t t = 0; t < nt; ++t) {
    out.integer(static_cast<std::int64_t>(t) + base);
    for (unsigned k = 0; k < 3; ++k) (out << ' ').integer(number[mesh.triangles[3 * t + k]]);
    if (what.triangle_attributes) {
      out << ' ';
      out.real(mesh.triangle_attributes.empty() ? 0.0 : mesh.triangle_attributes[t]);
    }
    out << '\n';
  }
  return out.take();
}

// PREFIX.poly: no vertices (they are in PREFIX.node), every subsegment, then the boundary edges
// that are none (the hull of a point set) with marker 1, then the holes and regions.
std::string poly_file(const MeshArrays& mesh, const Carried& carried, const VertexNumbers& numbers,
                      const std::vector<Point>& holes, const std::vector<Region>& regions, std::int64_t base,
                      bool markers) {
  const std::vector<std::int64_t>& number = numbers.number;
  Text out;
  const std::size_t segments = mesh.segment_count() + carried.boundary_edges.size();
  out.reserve(128 + segments * 40);
  out << "0 2 0 " << (markers ? "1" : "0") << '\n';
  out.integer(static_cast<std::int64_t>(segments)) << ' ' << (markers ? "1" : "0") << '\n';
  std::int64_t index = base;
  const auto segment_line = [&](std::uint32_t a, std::uint32_t b, std::int32_t marker) {
    out.integer(index++) << ' ';
    out.integer(number[a]) << ' ';
    out.integer(number[b]);
    if (markers) (out << ' ').integer(marker);
    out << '\n';
  };
  for (std::size_t s = 0; s < mesh.segment_count(); ++s) {
    segment_line(mesh.segments[2 * s], mesh.segments[2 * s + 1], carried.segment_marker[s]);
  }
  for (const auto& [a, b] : carried.boundary_edges) segment_line(a, b, 1);
  out << poly_holes_and_regions(holes, regions, base);
  return out.take();
}

// PREFIX.edge: the edges in Triangle's order (Carried::edges), with markers when `markers`: a
// subsegment's marker, else 1 on the boundary, 0 inside.
std::string edge_file(const MeshArrays& mesh, const Carried& carried, const VertexNumbers& numbers,
                      std::int64_t base, bool markers) {
  const std::vector<std::int64_t>& number = numbers.number;
  Text out;
  out.reserve(32 + carried.edges.size() * 32);
  out.integer(static_cast<std::int64_t>(carried.edges.size())) << ' ' << (markers ? "1" : "0") << '\n';
  std::int64_t index = base;
  for (const MeshEdge& e : carried.edges) {
    out.integer(index++) << ' ';
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
  }
  return out.take();
}

// PREFIX.neigh: per triangle the triangles across its edges opposite corners 0, 1, 2 (-1: none).
std::string neigh_file(const MeshArrays& mesh, std::int64_t base) {
  const std::size_t nt = mesh.triangle_count();
  Text out;
  out.reserve(32 + nt * 40);
  out.integer(static_cast<std::int64_t>(nt)) << " 3\n";
  for (std::size_t t = 0; t < nt; ++t) {
    out.integer(static_cast<std::int64_t>(t) + base);
    for (unsigned k = 0; k < 3; ++k) {
      const std::int32_t across = mesh.neighbours[3 * t + k];
      (out << ' ').integer(across < 0 ? -1 : across + base);
    }
    out << '\n';
  }
  return out.take();
}

// The Voronoi diagram (-v). Its vertices are the circumcentres of the triangles; each edge of the
// triangulation is dual to a Voronoi edge between the circumcentres on either side, or, on the
// boundary, to a ray from the one triangle's circumcentre perpendicular to the edge, outward.

// PREFIX.v.node: the circumcentre of each triangle.
std::string voronoi_node_file(const MeshArrays& mesh, std::int64_t base) {
  const std::size_t nt = mesh.triangle_count();
  Text vertices;
  vertices.reserve(32 + nt * 48);
  vertices.integer(static_cast<std::int64_t>(nt)) << " 2 0 0\n";
  for (std::size_t t = 0; t < nt; ++t) {
    const auto corner = [&](unsigned k) {
      const std::uint32_t v = mesh.triangles[3 * t + k];
      return Point{mesh.vertices[2 * v], mesh.vertices[2 * v + 1]};
    };
    const Point c = circumcenter(corner(0), corner(1), corner(2));
    vertices.integer(static_cast<std::int64_t>(t) + base) << ' ';
    vertices.real(c.x) << ' ';
    vertices.real(c.y) << '\n';
  }
  return vertices.take();
}

// PREFIX.v.edge: per edge of the triangulation (Carried::edges) its two Voronoi vertices, or its
// one Voronoi vertex, -1 and the direction of the ray.
std::string voronoi_edge_file(const MeshArrays& mesh, const Carried& carried, std::int64_t base) {
  Text edges;
  edges.reserve(32 + carried.edges.size() * 40);
  edges.integer(static_cast<std::int64_t>(carried.edges.size())) << " 0\n";
  std::int64_t index = base;
  for (const MeshEdge& e : carried.edges) {
    edges.integer(index++) << ' ';
    edges.integer(static_cast<std::int64_t>(e.triangle) + base) << ' ';
    const std::int32_t across = mesh.neighbours[3 * e.triangle + e.opposite];
    if (across >= 0) {
      edges.integer(across + base) << '\n';
    } else {
      // The triangle lies left of a→b (counter-clockwise), so (b - a) turned clockwise,
      // (by - ay, ax - bx), points out of the triangulation.
      const double ax = mesh.vertices[2 * e.a], ay = mesh.vertices[2 * e.a + 1];
      const double bx = mesh.vertices[2 * e.b], by = mesh.vertices[2 * e.b + 1];
      edges << "-1 ";
      edges.real(by - ay) << ' ';
      edges.real(ax - bx) << '\n';
    }
  }
  return edges.take();
}

}  // namespace

// The steps: carry_markers, number_vertices, then one formatter per file, in Triangle's order.
std::vector<TriangleFile> format_triangle_files(const MeshArrays& mesh, const std::vector<Point>& holes,
                                                const std::vector<Region>& regions, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const Carried carried = carry_markers(mesh, what.edges || what.voronoi);
  const bool markers = what.boundary_markers;
  const VertexNumbers numbers = number_vertices(mesh, what);
  std::vector<TriangleFile> files;
  if (what.node) files.push_back({".node", node_file(mesh, carried, numbers, markers)});
  if (what.ele) files.push_back({".ele", ele_file(mesh, numbers, what)});
  if (what.poly) files.push_back({".poly", poly_file(mesh, carried, numbers, holes, regions, base, markers)});
  if (what.edges) files.push_back({".edge", edge_file(mesh, carried, numbers, base, markers)});
  if (what.neighbours) files.push_back({".neigh", neigh_file(mesh, base)});
  if (what.voronoi) {
    files.push_back({".v.node", voronoi_node_file(mesh, base)});
    files.push_back({".v.edge", voronoi_edge_file(mesh, carried, base)});
  }
  return files;
}

// ---- the files of flat arrays end here ----------------------------------------------------------

}  // namespace mwst::io
