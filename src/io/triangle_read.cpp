// src/io/triangle_read.cpp — the readers of Triangle's files (mwst/io/triangle_files.hpp): .node,
// .poly, .ele and .area (read_node, read_poly, read_input, parse_node, parse_poly, parse_ele,
// parse_area, read_triangles, read_triangle_areas, read_mesh).
//
// A large file is mapped (a small one read with one read(2)) and scanned in place, after a UTF-8
// byte-order mark if it starts with one, by the Scanner of text_scanner.hpp. Every problem is an
// InputError naming the file and line. Header counts are checked against the size of the file,
// and storage is reserved only for as many records as the rest of the file can hold, so a bogus
// header never makes us allocate much. About 0.1 µs per point for a 1M-point .node.
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
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "io/text_scanner.hpp"

namespace mwst::io {
namespace {

// ---- reading files begins here ------------------------------------------------------------------

// A file's bytes, whole: a private read-only mapping of a large regular file, or malloc'ed storage
// filled by read(2) (uninitialised: no memset before reading).
struct FileBytes {
  FileBytes() = default;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  FileBytes(FileBytes&& other) noexcept { swap(other); }
  FileBytes& operator=(FileBytes&& other) noexcept {
    FileBytes gone(std::move(*this));
    swap(other);
    return *this;
  }
  ~FileBytes() {
    if (mapped_ != 0) ::munmap(data_, mapped_);
    else std::free(data_);
  }
  std::string_view view() const { return {data_, size_}; }
  void swap(FileBytes& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(size_, other.size_);
    std::swap(mapped_, other.mapped_);
  }
  char* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t mapped_ = 0;  // length of the mapping; 0: data_ is malloc'ed (or null)
};

// Frees malloc'ed storage (the buffer read_whole_file fills).
struct FreeDeleter {
  void operator()(char* p) const { std::free(p); }
};

// The text of an errno value, for messages.
std::string errno_message(int err) { return std::error_code(err, std::generic_category()).message(); }

// Files at least this large are mapped rather than read. Reading copies every byte into fresh
// anonymous memory, which the kernel must first zero: for a 1M-point .node (40 MB) that was 10 % of
// the whole `mwst triangulate` run. A mapping shares the page cache's pages (populated up front,
// read sequentially).
constexpr std::size_t kMapAtLeast = std::size_t{1} << 20;

// Reads the whole file: a regular file of at least kMapAtLeast bytes is mapped, anything else is
// read with read(2) (one call for a regular file; more only if it is not a regular file or grows).
// If `missing` is given and the file does not exist, sets *missing and returns an empty buffer
// instead of throwing.
FileBytes read_whole_file(const std::string& path, bool* missing = nullptr) {
  int fd;
  do {
    fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) {
    const int err = errno;
    if (missing != nullptr && err == ENOENT) {
      *missing = true;
      return {};
    }
    throw InputError(path, 0, "cannot open: " + errno_message(err));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw InputError(path, 0, "cannot read: " + errno_message(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, 0, "cannot read: is a directory");

  FileBytes out;
  if (S_ISREG(st.st_mode) && static_cast<std::size_t>(st.st_size) >= kMapAtLeast) {
    const auto length = static_cast<std::size_t>(st.st_size);
    void* p = ::mmap(nullptr, length, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    if (p != MAP_FAILED) {
      ::madvise(p, length, MADV_SEQUENTIAL);  // advice only
      out.data_ = static_cast<char*>(p);
      out.size_ = length;
      out.mapped_ = length;
      return out;
    }
    // Mapping refused (an unusual file system): read it instead.
  }
  // One byte more than the size, so that a regular file is read whole by the first read and
  // confirmed complete by the second (which returns 0) without growing the buffer.
  std::size_t capacity = (st.st_size > 0 ? static_cast<std::size_t>(st.st_size) : std::size_t{4095}) + 1;
  out.data_ = static_cast<char*>(std::malloc(capacity));
  if (out.data_ == nullptr) throw std::bad_alloc();
  for (;;) {
    if (out.size_ == capacity) {  // the file grew, or is not a regular file: enlarge
      const std::size_t bigger = capacity * 2;
      void* grown = std::realloc(out.data_, bigger);
      if (grown == nullptr) throw std::bad_alloc();
      out.data_ = static_cast<char*>(grown);
      capacity = bigger;
    }
    const ssize_t got = ::read(fd, out.data_ + out.size_, capacity - out.size_);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(path, 0, "cannot read: " + errno_message(errno));
    }
    if (got == 0) break;
    out.size_ += static_cast<std::size_t>(got);
  }
  return out;
}

// Whether `path` names an existing file.
bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

// "dir/foo.poly" -> "dir/foo.node" (the last extension of the last path component is replaced;
// a name without one gets ".node" appended).
std::string sibling_with_extension(const std::string& path, std::string_view ext) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  std::string stem = path;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash + 1)) {
    stem.resize(dot);
  }
  stem += ext;
  return stem;
}

// Whether the name `s` ends in `suffix` (an extension).
bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// ---- reading files ends here --------------------------------------------------------------------

// ---- records and indices begin here -------------------------------------------------------------

// The line scanner and its helpers (quote, coordinate_range_text, Item): io/text_scanner.hpp.
using namespace detail;

// Moves to the next line with data (a header or record); `what` names it for the end-of-file
// message.
void expect_line(Scanner& s, const std::string& what) {
  if (!s.next_line()) s.fail("unexpected end of file: expected " + what);
}

// Fails: the file ended after `found` of the `expected` records `what`.
[[noreturn]] void truncated(const Scanner& s, std::size_t expected, std::size_t found, const char* what) {
  s.fail("unexpected end of file: expected " + std::to_string(expected) + " " + what + ", found " +
         std::to_string(found));
}

// The valid vertex numbers of `count` vertices numbered from `base`, for messages.
std::string index_range_text(std::size_t count, int base) {
  if (count == 0) return "there are no vertices";
  return "vertices are numbered " + std::to_string(base) + " to " +
         std::to_string(static_cast<std::int64_t>(count) - 1 + base);
}

// Converts a vertex reference (in the vertices' base) to a 0-based index, or fails.
std::uint32_t vertex_reference(Scanner& s, const Item& item, const char* field, std::size_t count,
                               int base) {
  const std::int64_t v = s.integer(item, field);
  if (v < base || v - base >= static_cast<std::int64_t>(count)) {  // (v - base cannot overflow)
    s.fail(item.text() + " names vertex " + std::to_string(v) + ", which does not exist (" +
           index_range_text(count, base) + ")");
  }
  return static_cast<std::uint32_t>(v - base);
}

// The index at the start of a record: the first one decides the base (0 or 1), the rest must
// follow consecutively. Returns it.
std::int64_t record_index(Scanner& s, const char* kind, std::size_t ordinal, int& base) {
  const Item item{kind, static_cast<std::int64_t>(ordinal) + (base < 0 ? 1 : base)};
  const std::int64_t index = s.integer(item, "index");
  if (base < 0) {
    if (index != 0 && index != 1) {
      s.fail(std::string("the first ") + kind + " index must be 0 or 1, found " + std::to_string(index));
    }
    base = static_cast<int>(index);
  } else if (index != static_cast<std::int64_t>(ordinal) + base) {
    s.fail(std::string(kind) + " index " + std::to_string(index) + " out of sequence: expected " +
           std::to_string(static_cast<std::int64_t>(ordinal) + base));
  }
  return index;
}

// ---- records and indices end here ---------------------------------------------------------------

// ---- vertex sections begin here -----------------------------------------------------------------

// One vertex record (ordinal i): index, x, y, then the nattr attributes (into `attributes`; missing
// ones count as 0, as in Triangle) and the marker.
void read_vertex_record(Scanner& s, std::size_t i, int& base, std::int64_t nattr, std::int64_t nmarkers,
                        Point& p, std::int32_t& marker, double* attributes) {
  const std::int64_t index = record_index(s, "vertex", i, base);
  const Item item{"vertex", index};
  p.x = s.coordinate(item, "x coordinate");
  p.y = s.coordinate(item, "y coordinate");
  std::int64_t a = 0;
  for (; a < nattr && s.has_field(); ++a) attributes[a] = s.real(item, "attribute");
  for (std::int64_t missing = a; missing < nattr; ++missing) attributes[missing] = 0.0;
  marker = 0;
  if (nmarkers > 0 && a == nattr && s.has_field()) marker = s.marker(item);
  s.end_of_record(item);
}

// Large vertex sections are parsed in two halves on two threads. The second thread starts at the
// line nearest the middle (estimated from the first record's length) and learns its ordinal from
// the index written there; the halves are accepted only if the first ends exactly where the second
// began and both parsed without a problem. Anything else (an error, a comment or blank line at the
// seam, an estimate past the section) returns false, and the caller parses sequentially, which
// gives the canonical result and error messages.
bool read_vertex_records_in_halves(Scanner& s, std::size_t n, std::int64_t nattr, std::int64_t nmarkers,
                                   Pslg& out, int& base) {
  out.points.resize(n);
  out.point_markers.resize(n);
  Scanner first = s;
  const char* record0 = first.position();
  try {
    if (!first.next_line()) return false;
    read_vertex_record(first, 0, base, nattr, nmarkers, out.points[0], out.point_markers[0], nullptr);
  } catch (const InputError&) {
    return false;
  }
  const auto record_bytes = static_cast<std::size_t>(first.position() - record0);
  const auto room = static_cast<std::size_t>(first.text_end() - record0);
  if (record_bytes == 0 || room / record_bytes <= n / 2) return false;
  const char* guess = record0 + record_bytes * (n / 2);
  const auto* nl = static_cast<const char*>(std::memchr(guess, '\n', static_cast<std::size_t>(first.text_end() - guess)));
  if (nl == nullptr) return false;
  const char* seam = nl + 1;
  Scanner second = first.rest_from(seam);
  std::size_t middle = 0;  // the ordinal of the record at the seam
  try {
    Scanner peek = second;
    if (!peek.next_line()) return false;
    const std::int64_t index = peek.integer(Item{"vertex"}, "index");
    if (index <= base || index - base >= static_cast<std::int64_t>(n)) return false;
    middle = static_cast<std::size_t>(index - base);
  } catch (const InputError&) {
    return false;
  }
  bool second_ok = true;
  {
    std::jthread worker([&] {
      try {
        int second_base = base;
        for (std::size_t i = middle; i < n && second_ok; ++i) {
          if (!second.next_line()) second_ok = false;
          else read_vertex_record(second, i, second_base, nattr, nmarkers, out.points[i], out.point_markers[i], nullptr);
        }
      } catch (...) {
        second_ok = false;
      }
    });
    try {
      for (std::size_t i = 1; i < middle; ++i) {
        if (!first.next_line()) return false;  // (the worker joins on the way out)
        read_vertex_record(first, i, base, nattr, nmarkers, out.points[i], out.point_markers[i], nullptr);
      }
    } catch (const InputError&) {
      return false;
    }
  }
  if (!second_ok || first.position() != seam) return false;
  s.continue_as(second, first.lines_scanned());
  return true;
}

constexpr std::int64_t kMaxVertexAttributes = 1024;

// Reads a vertex section (header line already current): "N dim nattr nmarkers" then N vertices.
// Returns the count from the header; with count 0 nothing more is read.
std::size_t read_vertex_section(Scanner& s, Pslg& out) {
  const Item header{"header"};
  const std::int64_t declared = s.integer(header, "vertex count");
  const std::int64_t dim = s.optional_integer(header, "dimension", 2);
  if (dim != 2) s.fail("dimension must be 2, found " + std::to_string(dim));
  const std::size_t n = s.check_count(declared, "vertex count");
  const std::int64_t nattr = s.optional_integer(header, "attribute count", 0);
  if (nattr < 0) s.fail("negative attribute count " + std::to_string(nattr));
  // Every attribute is kept (8 bytes per vertex each, missing ones too): a bound keeps a header's
  // typo from asking for terabytes.
  if (nattr > kMaxVertexAttributes) {
    s.fail("attribute count " + std::to_string(nattr) + " is too large (at most " +
           std::to_string(kMaxVertexAttributes) + ")");
  }
  const std::int64_t nmarkers = s.optional_integer(header, "marker count", 0);
  if (nmarkers < 0) s.fail("negative marker count " + std::to_string(nmarkers));
  s.end_of_record(header);
  if (n == 0) return 0;
  if (n >= kInfinite) s.fail("vertex count " + std::to_string(n) + " is too large");

  int base = -1;
  constexpr std::size_t kParallelRecords = std::size_t{1} << 16;
  // (In halves only without attributes: a file with them is read by one thread.)
  if (nattr == 0 && n >= kParallelRecords && s.reservable(n, 6) == n) {
    if (read_vertex_records_in_halves(s, n, nattr, nmarkers, out, base)) {
      out.first_index = base;
      return n;
    }
    base = -1;
  }
  out.points.clear();
  out.point_markers.clear();
  out.points.reserve(s.reservable(n, 6));
  out.point_markers.reserve(s.reservable(n, 6));
  out.attributes_per_point = static_cast<std::size_t>(nattr);
  out.point_attributes.clear();
  std::vector<double> attributes(out.attributes_per_point);
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.next_line()) truncated(s, n, i, "vertices");
    Point p;
    std::int32_t marker = 0;
    read_vertex_record(s, i, base, nattr, nmarkers, p, marker, attributes.data());
    out.points.push_back(p);
    out.point_markers.push_back(marker);
    out.point_attributes.insert(out.point_attributes.end(), attributes.begin(), attributes.end());
  }
  out.first_index = base;
  return n;
}

// ---- vertex sections end here -------------------------------------------------------------------

// ---- the file parsers begin here ----------------------------------------------------------------

// Parses a .node file's text.
Pslg parse_node_text(std::string_view text, const std::string& name) {
  Pslg out;
  out.source = name;
  out.is_poly = false;
  if (text.empty()) throw InputError(name, 0, "empty file");
  Scanner s(without_byte_order_mark(text), name);
  if (!s.next_line()) s.fail("no data: the file holds only comments and blank lines");
  read_vertex_section(s, out);
  if (s.next_line()) {
    s.fail("unexpected data after the last vertex (the header says " + std::to_string(out.points.size()) +
           " vertices)");
  }
  return out;
}

// Parses a .poly file's text. `beside` (may be null) supplies the vertices when the .poly's
// vertex count is 0; otherwise they are read from the .node next to `name`.
Pslg parse_poly_text(std::string_view text, const std::string& name, const Pslg* beside,
                     bool* own_vertices = nullptr) {
  Pslg out;
  out.source = name;
  out.is_poly = true;
  if (text.empty()) throw InputError(name, 0, "empty file");
  Scanner s(without_byte_order_mark(text), name);
  if (!s.next_line()) s.fail("no data: the file holds only comments and blank lines");
  const std::size_t header_line = s.line();
  const std::size_t n = read_vertex_section(s, out);
  if (own_vertices != nullptr) *own_vertices = n > 0;
  if (n == 0) {
    if (beside != nullptr) {
      out.points = beside->points;
      out.point_markers = beside->point_markers;
      out.first_index = beside->first_index;
    } else {
      const std::string node_path = sibling_with_extension(name, ".node");
      bool missing = false;
      const FileBytes bytes = read_whole_file(node_path, &missing);
      if (missing) throw InputError(name, header_line, "vertex count 0 but " + node_path + " not found");
      Pslg nodes = parse_node_text(bytes.view(), node_path);
      out.points = std::move(nodes.points);
      out.point_markers = std::move(nodes.point_markers);
      out.first_index = nodes.first_index;
    }
  }
  const std::size_t nv = out.points.size();
  const int base = out.first_index;

  // Segments: "M markerflag", then "index a b [marker]".
  expect_line(s, "the segment count");
  {
    const std::size_t m = s.count("segment count");
    const bool markers = s.optional_integer(Item{"header"}, "marker flag", 0) != 0;
    s.end_of_record(Item{"the segment header"});
    out.segments.reserve(s.reservable(m, 6));
    out.segment_lines.reserve(s.reservable(m, 6));
    for (std::size_t i = 0; i < m; ++i) {
      if (!s.next_line()) truncated(s, m, i, "segments");
      const std::int64_t index = s.integer(Item{"segment", static_cast<std::int64_t>(i) + base}, "index");
      const Item item{"segment", index};
      Segment seg;
      seg.a = vertex_reference(s, item, "first endpoint", nv, base);
      seg.b = vertex_reference(s, item, "second endpoint", nv, base);
      if (markers && s.has_field()) seg.marker = s.marker(item);
      s.end_of_record(item);
      out.segments.push_back(seg);
      out.segment_lines.push_back(s.line());
    }
  }

  // Holes: "H", then "index x y". A file may end before this section (no holes).
  if (!s.next_line()) return out;
  {
    const std::size_t h = s.count("hole count");
    s.end_of_record(Item{"the hole header"});
    out.holes.reserve(s.reservable(h, 6));
    for (std::size_t i = 0; i < h; ++i) {
      if (!s.next_line()) truncated(s, h, i, "holes");
      const std::int64_t index = s.integer(Item{"hole", static_cast<std::int64_t>(i) + base}, "index");
      const Item item{"hole", index};
      Point p;
      p.x = s.coordinate(item, "x coordinate");
      p.y = s.coordinate(item, "y coordinate");
      s.end_of_record(item);
      out.holes.push_back(p);
    }
  }

  // Optional regional attributes: "R", then "index x y attribute [maxarea]".
  if (!s.next_line()) return out;
  {
    const std::size_t r = s.count("region count");
    s.end_of_record(Item{"the region header"});
    out.regions.reserve(s.reservable(r, 8));
    for (std::size_t i = 0; i < r; ++i) {
      if (!s.next_line()) truncated(s, r, i, "regions");
      const std::int64_t index = s.integer(Item{"region", static_cast<std::int64_t>(i) + base}, "index");
      const Item item{"region", index};
      Region region;
      region.seed.x = s.coordinate(item, "x coordinate");
      region.seed.y = s.coordinate(item, "y coordinate");
      region.attribute = s.real(item, "regional attribute");
      if (s.has_field()) region.max_area = s.real(item, "maximum area");
      region.line = s.line();
      s.end_of_record(item);
      out.regions.push_back(region);
    }
  }
  if (s.next_line()) s.fail("unexpected data after the regional attributes section");
  return out;
}

// Parses a .ele file's text against `points` vertices numbered from `base`. With
// `distinct_corners` a triangle naming one vertex twice is refused (a mesh to refine); without,
// it is read as written (`mwst check` reports it).
std::vector<std::array<std::uint32_t, 3>> parse_ele_text(std::string_view text, const std::string& name,
                                                         std::size_t points, int base,
                                                         bool distinct_corners = false) {
  if (text.empty()) throw InputError(name, 0, "empty file");
  Scanner s(without_byte_order_mark(text), name);
  if (!s.next_line()) s.fail("no data: the file holds only comments and blank lines");
  const Item header{"header"};
  const std::size_t t = s.count("triangle count");
  const std::int64_t corners = s.optional_integer(header, "nodes per triangle", 3);
  if (corners != 3 && corners != 6) {
    s.fail("nodes per triangle must be 3 or 6, found " + std::to_string(corners));
  }
  const std::int64_t nattr = s.optional_integer(header, "attribute count", 0);
  if (nattr < 0) s.fail("negative attribute count " + std::to_string(nattr));
  s.end_of_record(header);
  std::vector<std::array<std::uint32_t, 3>> triangles;
  triangles.reserve(s.reservable(t, 8));
  int tri_base = -1;
  for (std::size_t i = 0; i < t; ++i) {
    if (!s.next_line()) truncated(s, t, i, "triangles");
    const std::int64_t index = record_index(s, "triangle", i, tri_base);
    const Item item{"triangle", index};
    std::array<std::uint32_t, 3> tri{};
    for (auto& v : tri) v = vertex_reference(s, item, "corner", points, base);
    if (distinct_corners && (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])) {
      const std::uint32_t twice = tri[0] == tri[1] || tri[0] == tri[2] ? tri[0] : tri[1];
      s.fail(item.text() + " names vertex " + std::to_string(static_cast<std::int64_t>(twice) + base) + " twice");
    }
    // Further nodes (6-node triangles) and attributes are numbers, tolerated and ignored.
    s.end_of_record(item);
    triangles.push_back(tri);
  }
  if (s.next_line()) {
    s.fail("unexpected data after the last triangle (the header says " + std::to_string(t) + " triangles)");
  }
  return triangles;
}

// Parses a .area file's text: "T", then "index max-area" for each of `triangles` triangles (any
// finite number; <= 0 means no bound, as in Triangle).
std::vector<double> parse_area_text(std::string_view text, const std::string& name, std::size_t triangles) {
  if (text.empty()) throw InputError(name, 0, "empty file");
  Scanner s(without_byte_order_mark(text), name);
  if (!s.next_line()) s.fail("no data: the file holds only comments and blank lines");
  const std::size_t t = s.count("triangle count");
  s.end_of_record(Item{"the header"});
  if (t != triangles) {
    s.fail("triangle count " + std::to_string(t) + " differs from the mesh's " + std::to_string(triangles) +
           " triangles (one maximum area per triangle of the .ele)");
  }
  std::vector<double> areas;
  areas.reserve(s.reservable(t, 4));
  int base = -1;
  for (std::size_t i = 0; i < t; ++i) {
    if (!s.next_line()) truncated(s, t, i, "triangles");
    const Item item{"triangle", record_index(s, "triangle", i, base)};
    areas.push_back(s.real(item, "maximum area"));
    s.end_of_record(item);
  }
  if (s.next_line()) {
    s.fail("unexpected data after the last triangle (the header says " + std::to_string(t) + " triangles)");
  }
  return areas;
}

// ---- the file parsers end here ------------------------------------------------------------------

}  // namespace

// ---- the public readers begin here --------------------------------------------------------------


// A .node file's text, `name` naming it in messages.
Pslg parse_node(std::string_view text, const std::string& name) { return parse_node_text(text, name); }

// A .poly file's text (with a vertex count of 0, the vertices of the .node beside `name`).
Pslg parse_poly(std::string_view text, const std::string& name) {
  return parse_poly_text(text, name, nullptr);
}

// The file `path`, a .node.
Pslg read_node(const std::string& path) {
  const FileBytes bytes = read_whole_file(path);
  return parse_node_text(bytes.view(), path);
}

// The file `path`, a .poly (vertices from the .node beside it when it lists none).
Pslg read_poly(const std::string& path) {
  const FileBytes bytes = read_whole_file(path);
  return parse_poly_text(bytes.view(), path, nullptr);
}

// A .node or .poly input, by its extension.
Pslg read_input(const std::string& path) {
  if (ends_with(path, ".node")) return read_node(path);
  if (ends_with(path, ".poly")) return read_poly(path);
  throw InputError(path, 0, "unknown input type: expected a .node or .poly file");
}

// A .ele file's text as flat corner indices (0-based); a triangle naming a vertex twice is refused.
std::vector<std::uint32_t> parse_ele(std::string_view text, const std::string& name, std::size_t points, int base) {
  const std::vector<std::array<std::uint32_t, 3>> triangles = parse_ele_text(text, name, points, base, true);
  std::vector<std::uint32_t> flat;
  flat.reserve(3 * triangles.size());
  for (const auto& t : triangles) flat.insert(flat.end(), t.begin(), t.end());
  return flat;
}

// A .area file's text: the maximum area of each of `triangles` triangles.
std::vector<double> parse_area(std::string_view text, const std::string& name, std::size_t triangles) {
  return parse_area_text(text, name, triangles);
}

// Adds the triangles of `ele_path` to `pslg` (a mesh to refine), dropping earlier area bounds.
void read_triangles(Pslg& pslg, const std::string& ele_path) {
  const FileBytes bytes = read_whole_file(ele_path);
  pslg.triangles = parse_ele(bytes.view(), ele_path, pslg.points.size(), pslg.first_index);
  pslg.triangle_max_area.clear();
}

// Adds the per-triangle area bounds of `area_path` to `pslg` (after read_triangles).
void read_triangle_areas(Pslg& pslg, const std::string& area_path) {
  const FileBytes bytes = read_whole_file(area_path);
  pslg.triangle_max_area = parse_area_text(bytes.view(), area_path, pslg.triangles.size() / 3);
}

// The mesh PREFIX.node + PREFIX.ele, with the segments of PREFIX.poly if there is one (its own
// vertices, if it lists any, must be those of the .node).
MeshFiles read_mesh(const std::string& prefix) {
  MeshFiles out;
  const std::string node_path = prefix + ".node";
  Pslg nodes = read_node(node_path);
  {
    const std::string ele_path = prefix + ".ele";
    const FileBytes bytes = read_whole_file(ele_path);
    out.triangles = parse_ele_text(bytes.view(), ele_path, nodes.points.size(), nodes.first_index);
  }
  const std::string poly_path = prefix + ".poly";
  if (file_exists(poly_path)) {
    const FileBytes bytes = read_whole_file(poly_path);
    bool own_vertices = false;
    Pslg poly = parse_poly_text(bytes.view(), poly_path, &nodes, &own_vertices);
    if (own_vertices && poly.points != nodes.points) {
      throw InputError(poly_path, 0, "its vertices differ from those of " + node_path);
    }
    out.segments = std::move(poly.segments);
  }
  out.points = std::move(nodes.points);
  return out;
}

// ---- the public readers end here ----------------------------------------------------------------

}  // namespace mwst::io
