// src/io/triangle_format.cpp — Triangle's file formats (declared in mwst/io/triangle_files.hpp): the readers of
// .node, .poly and .ele (read_node, read_poly, read_input, parse_node, parse_poly, read_mesh) and
// the mesh writer (write_mesh). write_file_atomic lives in atomic_file.cpp.
//
// Reading: a large file is mapped (a small one read with one read(2)) and scanned in place, after a
// UTF-8 byte-order mark if it starts with one. A Scanner walks the text line by line (lines end in
// "\n", "\r\n" or a lone "\r"; one memchr per line; '#' ends a line's content wherever it
// appears) and hands out the fields of the current line; after a record's fields only numbers may
// follow (Triangle's extra attributes), never words;
// numbers are converted directly from the text with std::from_chars (no iostreams, no copies), with
// inline fast paths for plain integers and in-range decimals. Every problem is an InputError
// naming the file and line. Header counts are checked against the size of the file, and storage is
// reserved only for as many records as the rest of the file can hold, so a bogus header never
// makes us allocate much. About 0.1 µs per point for a 1M-point .node.
//
// Writing: each file is formatted into buffers sized for its longest possible text (numbers via
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

// ---- files -------------------------------------------------------------------------------------

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

struct FreeDeleter {
  void operator()(char* p) const { std::free(p); }
};

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

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// ---- scanning ----------------------------------------------------------------------------------

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// A token quoted for a message: at most 32 characters, control and non-ASCII bytes escaped.
std::string quote(std::string_view token) {
  std::string s = "'";
  const std::size_t n = token.size() < 32 ? token.size() : 32;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7F) {
      s += static_cast<char>(c);
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      s += "\\x";
      s += kHex[c >> 4];
      s += kHex[c & 15];
    }
  }
  if (token.size() > n) s += "...";
  return s + "'";
}

std::string coordinate_range_text() { return "0 or a magnitude between 1e-50 and 1e50"; }

// What is being read, for messages: "vertex 7", "segment 3", "the header".
struct Item {
  const char* kind;          // "vertex", "segment", ... or a complete phrase when number < 0
  std::int64_t number = -1;  // the item's index as written in the file (or ordinal)
  std::string text() const {
    return number < 0 ? std::string(kind) : std::string(kind) + " " + std::to_string(number);
  }
};

// A UTF-8 byte-order mark (EF BB BF), which some editors put at the start of a text file: it is
// not data, and is skipped (only at the start of a file).
std::string_view without_byte_order_mark(std::string_view text) {
  constexpr std::string_view kMark = "\xEF\xBB\xBF";
  return text.substr(0, kMark.size()) == kMark ? text.substr(kMark.size()) : text;
}

class Scanner {
 public:
  Scanner(std::string_view text, const std::string& name)
      : next_(text.data()), end_(text.data() + text.size()), name_(name) {
    next_lf_ = find(next_, '\n');
    next_cr_ = find(next_, '\r');
  }

  // Advances to the next line that holds data (skipping blank and comment-only lines). Returns
  // false at the end of the file. A line ends at "\n", "\r\n" or a lone "\r" (files from classic
  // Mac OS), so line numbers are right whichever ending a file uses. The next '\n' and the next
  // '\r' are each found with memchr and remembered until passed: a file of one ending costs one
  // memchr per line plus one over the whole file for the ending it does not use (never a rescan).
  // A '#' ends a line's content wherever it appears; it is found lazily (fields stop at it).
  bool next_line() {
    while (next_ < end_) {
      const char* start = next_;
      if (next_lf_ < start) next_lf_ = find(start, '\n');
      if (next_cr_ < start) next_cr_ = find(start, '\r');
      // The line ends at the nearer of the two; a '\r' right before a '\n' ends it together with
      // that '\n' (end_ stands for "none found": a '\r' last in the text is a lone one).
      const char* line_end = next_lf_ <= next_cr_ ? next_lf_ : next_cr_;
      const bool crlf = line_end == next_cr_ && line_end + 1 == next_lf_ && next_lf_ != end_;
      next_ = line_end == end_ ? end_ : line_end + (crlf ? 2 : 1);
      ++line_;
      while (start < line_end && is_blank(*start)) ++start;
      if (start < line_end && *start != '#') {
        cur_ = start;
        cur_end_ = line_end;
        return true;
      }
    }
    cur_ = cur_end_ = end_;
    return false;
  }

  std::size_t line() const { return line_ == 0 ? 1 : line_; }
  // For splitting a section between two threads: where the next unscanned line starts; a scanner
  // of the rest of the text from the line start p (its lines counted from 0); and taking over the
  // state of such a scanner that continued this one (`lines_before` = this one's line count where
  // it started).
  const char* position() const { return next_; }
  const char* text_end() const { return end_; }
  Scanner rest_from(const char* p) const {
    return Scanner(std::string_view(p, static_cast<std::size_t>(end_ - p)), name_);
  }
  std::size_t lines_scanned() const { return line_; }
  void continue_as(const Scanner& later, std::size_t lines_before) {
    next_ = later.next_;
    next_lf_ = later.next_lf_;
    next_cr_ = later.next_cr_;
    cur_ = later.cur_;
    cur_end_ = later.cur_end_;
    line_ = lines_before + later.line_;
  }
  // Bytes not yet scanned (an upper bound for what the rest of the file can hold).
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - next_); }

  // True if the current line has another field (skips the blanks before it).
  bool has_field() {
    while (cur_ < cur_end_ && is_blank(*cur_)) ++cur_;
    return cur_ < cur_end_ && *cur_ != '#';
  }

  [[noreturn]] void fail(const std::string& message) const { throw InputError(name_, line(), message); }

  // ---- fields (each skips leading blanks; a missing required field is an error) ----

  // An integer field. Fast path: up to 18 plain decimal digits.
  std::int64_t integer(const Item& item, const char* field) {
    if (!has_field()) missing(item, field);
    const char* p = cur_;
    const char* const start = p;
    std::uint64_t v = 0;
    while (p < cur_end_ && p - start < 18 && static_cast<unsigned>(*p - '0') < 10u) {
      v = v * 10 + static_cast<unsigned>(*p - '0');
      ++p;
    }
    if (p > start && delimited(p)) {
      cur_ = p;
      return static_cast<std::int64_t>(v);
    }
    return integer_slow(item, field);
  }

  // An optional integer field: `fallback` if the line has no more fields.
  std::int64_t optional_integer(const Item& item, const char* field, std::int64_t fallback) {
    return has_field() ? integer(item, field) : fallback;
  }

  // A count in a section header: non-negative and not absurd: no larger than the rest of the file
  // could hold if every record took two bytes.
  std::size_t count(const char* what) { return check_count(integer(Item{"header"}, what), what); }
  std::size_t check_count(std::int64_t n, const char* what) const {
    if (n < 0) fail(std::string("negative ") + what + " " + std::to_string(n));
    if (static_cast<std::uint64_t>(n) > remaining() / 2) {
      fail(std::string(what) + " " + std::to_string(n) + " is more than the rest of the file can hold");
    }
    return static_cast<std::size_t>(n);
  }
  // How many records of at least `min_record` bytes ("1 0 0\n" is 6) the rest of the file can
  // really hold: what we reserve for a count of n, so that storage stays within a few times the
  // file's size even when a header lies (a truncated file is then reported where it ends).
  std::size_t reservable(std::size_t n, std::size_t min_record) const {
    const std::size_t fit = (remaining() + 1) / min_record;  // +1: the last line may lack '\n'
    return n < fit ? n : fit;
  }

  // The end of a record or header: fields after those read may only be numbers (Triangle reads
  // further numbers as attributes and ignores those it does not need), then an optional '#'
  // comment. A word there ("1 0 0 zzz") is refused: it is a typo or another format, not data to
  // drop silently.
  void end_of_record(const Item& item) {
    if (has_field()) fields_after_record(item);
  }

  // A boundary marker (an int32).
  std::int32_t marker(const Item& item) {
    const std::int64_t v = integer(item, "boundary marker");
    if (v < std::numeric_limits<std::int32_t>::min() || v > std::numeric_limits<std::int32_t>::max()) {
      fail(item.text() + ": boundary marker " + std::to_string(v) + " is out of range");
    }
    return static_cast<std::int32_t>(v);
  }

  // Any finite double (attributes, area constraints).
  double real(const Item& item, const char* field) {
    if (!has_field()) missing(item, field);
    double v = 0.0;
    const Status s = parse_double(v);
    if (s == Status::kMalformed) not_a_number(item, field);
    if (s == Status::kOutOfRange || !std::isfinite(v)) {
      fail(item.text() + ": " + field + " " + quote(token()) + " is not a finite double");
    }
    cur_ = after_;
    return v;
  }

  // A coordinate: finite and in the supported range (see geometry.hpp). Fast path: a plain
  // decimal that from_chars takes whole and that lies in the range.
  double coordinate(const Item& item, const char* field) {
    if (!has_field()) missing(item, field);
    double v = 0.0;
    const auto r = std::from_chars(cur_, cur_end_, v);
    if (r.ec == std::errc() && delimited(r.ptr) && v != 0.0 && in_supported_range(v)) {
      cur_ = r.ptr;
      return v;
    }
    return coordinate_slow(item, field);
  }

 private:
  enum class Status { kOk, kMalformed, kOutOfRange };

  bool delimited(const char* p) const { return p == cur_end_ || is_blank(*p) || *p == '#'; }

  // The current token (up to the next blank or '#'), for messages.
  std::string_view token() const {
    const char* e = cur_;
    while (e < cur_end_ && !is_blank(*e) && *e != '#') ++e;
    return {cur_, static_cast<std::size_t>(e - cur_)};
  }

  // The fields after a record's own (end_of_record): numbers are skipped, a word is refused.
  [[gnu::noinline]] void fields_after_record(const Item& item) {
    while (has_field()) {
      double ignored = 0.0;
      if (parse_double(ignored) == Status::kMalformed) {
        fail(item.text() + ": unexpected " + quote(token()) +
             " after its fields (only numbers may follow them; '#' starts a comment)");
      }
      cur_ = after_;
    }
  }

  [[noreturn, gnu::cold, gnu::noinline]] void missing(const Item& item, const char* field) const {
    fail(item.text() + ": missing " + field);
  }
  [[noreturn, gnu::cold, gnu::noinline]] void not_a_number(const Item& item, const char* field) const {
    fail(item.text() + ": expected a number for the " + field + ", found " + quote(token()));
  }
  [[noreturn, gnu::cold, gnu::noinline]] void out_of_range(const Item& item, const char* field) const {
    fail(item.text() + ": " + field + " " + quote(token()) + " is outside the supported range (" +
         coordinate_range_text() + ")");
  }

  // Integers with a sign, many digits, or errors.
  [[gnu::noinline]] std::int64_t integer_slow(const Item& item, const char* field) {
    std::int64_t v = 0;
    const char* p = cur_;
    if (*p == '+' && p + 1 < cur_end_ && p[1] != '-' && p[1] != '+') ++p;
    const auto r = std::from_chars(p, cur_end_, v);
    if (r.ec == std::errc::result_out_of_range && delimited(r.ptr)) {
      fail(item.text() + ": " + field + " " + quote(token()) + " is out of range");
    }
    if (r.ec != std::errc() || !delimited(r.ptr)) {
      fail(item.text() + ": expected an integer for the " + field + ", found " + quote(token()));
    }
    cur_ = r.ptr;
    return v;
  }

  // Zero, a sign '+', hexadecimal, or errors.
  [[gnu::noinline]] double coordinate_slow(const Item& item, const char* field) {
    double v = 0.0;
    const Status s = parse_double(v);
    if (s == Status::kMalformed) not_a_number(item, field);
    if (s == Status::kOutOfRange) out_of_range(item, field);
    if (!std::isfinite(v)) fail(item.text() + ": non-finite coordinate " + quote(token()));
    if (!in_supported_range(v)) out_of_range(item, field);
    cur_ = after_;
    return v;
  }

  // Parses the double at cur_: decimal as strtod (without the locale) or C99 hexadecimal
  // ("0x1.8p3"), with an optional sign. Leaves the end in after_ (cur_ stays at the token, for
  // messages; the caller advances). A number with a non-zero digit
  // that underflows to zero is out of range.
  Status parse_double(double& v) {
    const char* p = cur_;
    bool negative = false;
    if (*p == '+' || *p == '-') {
      negative = *p == '-';
      ++p;
      if (p == cur_end_ || *p == '+' || *p == '-') return Status::kMalformed;
    }
    const bool hex = cur_end_ - p >= 2 && p[0] == '0' && (p[1] == 'x' || p[1] == 'X');
    const char* digits = hex ? p + 2 : p;
    if (hex && (digits == cur_end_ || *digits == '+' || *digits == '-')) return Status::kMalformed;
    const auto r = hex ? std::from_chars(digits, cur_end_, v, std::chars_format::hex)
                       : std::from_chars(digits, cur_end_, v);
    if (r.ec == std::errc::invalid_argument || !delimited(r.ptr)) return Status::kMalformed;
    after_ = r.ptr;
    if (r.ec == std::errc::result_out_of_range) return Status::kOutOfRange;
    if (v == 0.0) {
      for (const char* q = digits; q < r.ptr; ++q) {
        const char c = *q;
        if (c == 'e' || c == 'E' || (hex && (c == 'p' || c == 'P'))) break;
        if (c != '0' && c != '.') return Status::kOutOfRange;
      }
    }
    if (negative) v = -v;
    return Status::kOk;
  }

  // The first c at or after p, or end_.
  const char* find(const char* p, char c) const {
    if (p == end_) return end_;
    const auto* q = static_cast<const char*>(std::memchr(p, c, static_cast<std::size_t>(end_ - p)));
    return q != nullptr ? q : end_;
  }

  const char* next_;               // start of the next unscanned line
  const char* end_;
  const char* next_lf_;            // the next '\n' at or after where it was last looked for (or end_)
  const char* next_cr_;            // the same for '\r'
  const char* cur_ = nullptr;      // position in the current line
  const char* cur_end_ = nullptr;  // end of the current line (its line ending or the end of the text)
  const char* after_ = nullptr;
  std::size_t line_ = 0;           // number of the current line (1-based)
  const std::string& name_;
};

// Reads the header line of a section; `what` names the section for the end-of-file message.
void expect_line(Scanner& s, const std::string& what) {
  if (!s.next_line()) s.fail("unexpected end of file: expected " + what);
}

[[noreturn]] void truncated(const Scanner& s, std::size_t expected, std::size_t found, const char* what) {
  s.fail("unexpected end of file: expected " + std::to_string(expected) + " " + what + ", found " +
         std::to_string(found));
}

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

// Reads a vertex section (header line already current): "N dim nattr nmarkers" then N vertices.
// Returns the count from the header; with count 0 nothing more is read.
// One vertex record (ordinal i): index, x, y, then attributes (tolerated, ignored; missing ones
// count as 0, as in Triangle) and the marker.
void read_vertex_record(Scanner& s, std::size_t i, int& base, std::int64_t nattr, std::int64_t nmarkers,
                        Point& p, std::int32_t& marker) {
  const std::int64_t index = record_index(s, "vertex", i, base);
  const Item item{"vertex", index};
  p.x = s.coordinate(item, "x coordinate");
  p.y = s.coordinate(item, "y coordinate");
  std::int64_t a = 0;
  for (; a < nattr && s.has_field(); ++a) s.real(item, "attribute");
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
    read_vertex_record(first, 0, base, nattr, nmarkers, out.points[0], out.point_markers[0]);
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
          else read_vertex_record(second, i, second_base, nattr, nmarkers, out.points[i], out.point_markers[i]);
        }
      } catch (...) {
        second_ok = false;
      }
    });
    try {
      for (std::size_t i = 1; i < middle; ++i) {
        if (!first.next_line()) return false;  // (the worker joins on the way out)
        read_vertex_record(first, i, base, nattr, nmarkers, out.points[i], out.point_markers[i]);
      }
    } catch (const InputError&) {
      return false;
    }
  }
  if (!second_ok || first.position() != seam) return false;
  s.continue_as(second, first.lines_scanned());
  return true;
}

std::size_t read_vertex_section(Scanner& s, Pslg& out) {
  const Item header{"header"};
  const std::int64_t declared = s.integer(header, "vertex count");
  const std::int64_t dim = s.optional_integer(header, "dimension", 2);
  if (dim != 2) s.fail("dimension must be 2, found " + std::to_string(dim));
  const std::size_t n = s.check_count(declared, "vertex count");
  const std::int64_t nattr = s.optional_integer(header, "attribute count", 0);
  if (nattr < 0) s.fail("negative attribute count " + std::to_string(nattr));
  const std::int64_t nmarkers = s.optional_integer(header, "marker count", 0);
  if (nmarkers < 0) s.fail("negative marker count " + std::to_string(nmarkers));
  s.end_of_record(header);
  if (n == 0) return 0;
  if (n >= kInfinite) s.fail("vertex count " + std::to_string(n) + " is too large");

  int base = -1;
  constexpr std::size_t kParallelRecords = std::size_t{1} << 16;
  if (n >= kParallelRecords && s.reservable(n, 6) == n) {
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
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.next_line()) truncated(s, n, i, "vertices");
    Point p;
    std::int32_t marker = 0;
    read_vertex_record(s, i, base, nattr, nmarkers, p, marker);
    out.points.push_back(p);
    out.point_markers.push_back(marker);
  }
  out.first_index = base;
  return n;
}

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

}  // namespace

// ---- public API --------------------------------------------------------------------------------

Pslg parse_node(std::string_view text, const std::string& name) { return parse_node_text(text, name); }

Pslg parse_poly(std::string_view text, const std::string& name) {
  return parse_poly_text(text, name, nullptr);
}

Pslg read_node(const std::string& path) {
  const FileBytes bytes = read_whole_file(path);
  return parse_node_text(bytes.view(), path);
}

Pslg read_poly(const std::string& path) {
  const FileBytes bytes = read_whole_file(path);
  return parse_poly_text(bytes.view(), path, nullptr);
}

Pslg read_input(const std::string& path) {
  if (ends_with(path, ".node")) return read_node(path);
  if (ends_with(path, ".poly")) return read_poly(path);
  throw InputError(path, 0, "unknown input type: expected a .node or .poly file");
}

std::vector<std::uint32_t> parse_ele(std::string_view text, const std::string& name, std::size_t points, int base) {
  const std::vector<std::array<std::uint32_t, 3>> triangles = parse_ele_text(text, name, points, base, true);
  std::vector<std::uint32_t> flat;
  flat.reserve(3 * triangles.size());
  for (const auto& t : triangles) flat.insert(flat.end(), t.begin(), t.end());
  return flat;
}

std::vector<double> parse_area(std::string_view text, const std::string& name, std::size_t triangles) {
  return parse_area_text(text, name, triangles);
}

void read_triangles(Pslg& pslg, const std::string& ele_path) {
  const FileBytes bytes = read_whole_file(ele_path);
  pslg.triangles = parse_ele(bytes.view(), ele_path, pslg.points.size(), pslg.first_index);
  pslg.triangle_max_area.clear();
}

void read_triangle_areas(Pslg& pslg, const std::string& area_path) {
  const FileBytes bytes = read_whole_file(area_path);
  pslg.triangle_max_area = parse_area_text(bytes.view(), area_path, pslg.triangles.size() / 3);
}

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

namespace {

// A text being written into storage sized for its longest possible content (uninitialised; only
// the pages written are ever touched): numbers go straight in with std::to_chars, with no capacity
// check per character. (Plain malloc without huge-page advice: for output buffers the kernel's
// huge-page compaction cost twice the system time in measurements.)
class TextBuffer {
 public:
  explicit TextBuffer(std::size_t capacity) : data_(static_cast<char*>(std::malloc(capacity))), end_(data_.get()) {
    if (data_ == nullptr) throw std::bad_alloc();
  }
  void put(char c) { *end_++ = c; }
  void put(std::string_view text) {
    std::memcpy(end_, text.data(), text.size());
    end_ += text.size();
  }
  void put_int(std::int64_t v) { end_ = std::to_chars(end_, end_ + 24, v).ptr; }
  void put_double(double v) { end_ = std::to_chars(end_, end_ + 32, v).ptr; }  // shortest round-trip
  std::string_view view() const { return {data_.get(), static_cast<std::size_t>(end_ - data_.get())}; }

 private:
  std::unique_ptr<char, FreeDeleter> data_;
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

}  // namespace

void write_mesh(const Mesh& mesh, const std::string& prefix, int first_index, const std::vector<Point>& holes,
                const std::vector<Region>& regions) {
  if (mesh.flags.size() != mesh.triangles.size()) {
    throw InternalError("write_mesh: flags and triangles differ in size");
  }
  const std::int64_t base = first_index;
  const std::size_t nv = mesh.points.size();
  const auto slots = static_cast<TriangleId>(mesh.triangles.size());

  // PREFIX.node (every vertex, with its boundary marker) and PREFIX.ele (the live, finite,
  // in-domain triangles, corners counter-clockwise). Large meshes are formatted in two halves on
  // two threads, each half of each file into its own buffer; the files are the concatenations, the
  // same text as one thread writes.
  const bool parallel = nv + slots >= (std::size_t{1} << 16);
  const std::size_t node_split = parallel ? nv / 2 : nv;
  const TriangleId ele_split = parallel ? slots / 2 : slots;
  std::int64_t count_first = 0, count_second = 0;
  for (TriangleId t = 0; t < ele_split; ++t) count_first += mesh.in_domain(t) ? 1 : 0;
  for (TriangleId t = ele_split; t < slots; ++t) count_second += mesh.in_domain(t) ? 1 : 0;
  constexpr std::size_t kNodeLine = 2 * kMaxIntChars + 2 * kMaxDoubleChars + 4;
  constexpr std::size_t kEleLine = 4 * (kMaxIntChars + 1);
  TextBuffer node_head(64), ele_head(64);
  node_head.put_int(static_cast<std::int64_t>(nv));
  node_head.put(" 2 0 1\n");
  ele_head.put_int(count_first + count_second);
  ele_head.put(" 3 0\n");
  TextBuffer node_first(node_split * kNodeLine + 1), node_second((nv - node_split) * kNodeLine + 1);
  TextBuffer ele_first(static_cast<std::size_t>(count_first) * kEleLine + 1);
  TextBuffer ele_second(static_cast<std::size_t>(count_second) * kEleLine + 1);
  {
    std::exception_ptr worker_error;
    std::jthread worker;  // joins on every way out of this block (a throw below included)
    auto second_halves = [&] {
      try {
        format_node_lines(mesh, node_split, nv, base, node_second);
        format_ele_lines(mesh, ele_split, slots, base + count_first, base, ele_second);
      } catch (...) {
        worker_error = std::current_exception();
      }
    };
    if (parallel) worker = std::jthread(second_halves);
    format_node_lines(mesh, 0, node_split, base, node_first);
    format_ele_lines(mesh, 0, ele_split, base, base, ele_first);
    if (worker.joinable()) worker.join();
    if (worker_error) std::rethrow_exception(worker_error);
  }

  // PREFIX.poly: every subsegment bordering the domain, once (seen from both sides, it is written
  // from the lower-numbered triangle only).
  auto written_from_here = [&](TriangleId t, unsigned e) {
    const Handle h = make_handle(t, e);
    if (!mesh.is_segment(h)) return false;
    const Handle other = mesh.triangles[t].n[e];
    if (other == kNone) return true;
    const TriangleId u = triangle_of(other);
    return !(u < slots && u < t && mesh.in_domain(u) && mesh.is_segment(other));
  };
  std::size_t segments = 0;
  for (TriangleId t = 0; t < slots; ++t) {
    if (!mesh.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) segments += written_from_here(t, e) ? 1 : 0;
  }
  TextBuffer poly(segments * 4 * (kMaxIntChars + 1) + 64);
  if (segments > 0) {
    poly.put("0 2 0 1\n");
    poly.put_int(static_cast<std::int64_t>(segments));
    poly.put(" 1\n");
    std::int64_t number = base;
    for (TriangleId t = 0; t < slots; ++t) {
      if (!mesh.in_domain(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        if (!written_from_here(t, e)) continue;
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
  }
  const std::string holes_and_regions = segments > 0 ? poly_holes_and_regions(holes, regions, base) : std::string();

  // Each file is atomic; if a later one fails, the earlier ones are removed again so that a
  // failure leaves no partial mesh behind. Large .node files are written by the second thread
  // while this one writes the .ele (the kernel's copies overlap).
  const std::string node_path = prefix + ".node", ele_path = prefix + ".ele", poly_path = prefix + ".poly";
  const std::string_view node_text[3] = {node_head.view(), node_first.view(), node_second.view()};
  const std::string_view ele_text[3] = {ele_head.view(), ele_first.view(), ele_second.view()};
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
        const std::string_view poly_text[2] = {poly.view(), holes_and_regions};
        if (segments > 0) write_file_atomic(poly_path, poly_text);
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

}  // namespace mwst::io

// ---- Triangle's output files of flat arrays --------------------------------------------------------

namespace mwst::io {
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

// `list_edges`: fill Carried::edges (for .edge and .v.edge); otherwise only the boundary edges are
// looked at.
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

}  // namespace

std::vector<TriangleFile> format_triangle_files(const MeshArrays& mesh, const std::vector<Point>& holes,
                                                const std::vector<Region>& regions, const TriangleOutput& what) {
  const std::int64_t base = what.first_index;
  const std::size_t nt = mesh.triangle_count();
  const std::size_t nv = mesh.vertex_count();
  const Carried carried = carry_markers(mesh, what.edges || what.voronoi);
  const bool markers = what.boundary_markers;

  // Output numbers of the vertices: all of them, or with -j only those of some triangle.
  std::vector<std::int64_t> number(nv, 0);
  std::size_t kept = 0;
  {
    std::vector<bool> used(nv, !what.jettison);
    if (what.jettison) {
      for (const std::uint32_t v : mesh.triangles) used[v] = true;
    }
    for (std::size_t v = 0; v < nv; ++v) {
      if (used[v]) number[v] = static_cast<std::int64_t>(kept++) + base;
      else number[v] = -1;
    }
  }

  std::vector<TriangleFile> files;
  if (what.node) {
    Text out;
    out.reserve(64 + kept * 64);
    out.integer(static_cast<std::int64_t>(kept)) << " 2 0 " << (markers ? "1" : "0") << '\n';
    for (std::size_t v = 0; v < nv; ++v) {
      if (number[v] < 0) continue;
      out.integer(number[v]) << ' ';
      out.real(mesh.vertices[2 * v]) << ' ';
      out.real(mesh.vertices[2 * v + 1]);
      if (markers) (out << ' ').integer(carried.vertex_marker[v]);
      out << '\n';
    }
    files.push_back({".node", out.take()});
  }
  if (what.ele) {
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
    files.push_back({".ele", out.take()});
  }
  if (what.poly) {
    // Every subsegment, then the boundary edges that are none (the hull of a point set), marker 1.
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
    files.push_back({".poly", out.take()});
  }
  if (what.edges) {
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
    files.push_back({".edge", out.take()});
  }
  if (what.neighbours) {
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
    files.push_back({".neigh", out.take()});
  }
  if (what.voronoi) {
    // The Voronoi vertices are the circumcentres of the triangles; each edge of the triangulation
    // is dual to a Voronoi edge between the circumcentres on either side, or, on the boundary, to
    // a ray from the one triangle's circumcentre perpendicular to the edge, outward.
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
    files.push_back({".v.node", vertices.take()});
    files.push_back({".v.edge", edges.take()});
  }
  return files;
}

}  // namespace mwst::io
