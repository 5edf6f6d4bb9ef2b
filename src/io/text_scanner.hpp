// io/text_scanner.hpp — the line scanner of the readers of Triangle's files (triangle_read.cpp).
// Internal. A Scanner walks a text line by line (lines end in "\n", "\r\n" or a lone "\r"; one
// memchr per line; '#' ends a line's content wherever it appears) and hands out the fields of the
// current line; after a record's fields only numbers may follow (Triangle's extra attributes),
// never words. Numbers are converted directly from the text with std::from_chars (no iostreams, no
// copies), with inline fast paths for plain integers and in-range decimals.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "mwst/error.hpp"
#include "mwst/geometry/geometry.hpp"

namespace mwst::io::detail {
// ---- characters and messages begin here ---------------------------------------------------------

// The blanks between fields (a line ending is not one: the Scanner splits lines first).
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// A token quoted for a message: at most 32 characters, control and non-ASCII bytes escaped.
inline std::string quote(std::string_view token) {
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

// The supported coordinate range (geometry.hpp's in_supported_range), for messages.
inline std::string coordinate_range_text() { return "0 or a magnitude between 1e-50 and 1e50"; }

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
inline std::string_view without_byte_order_mark(std::string_view text) {
  constexpr std::string_view kMark = "\xEF\xBB\xBF";
  return text.substr(0, kMark.size()) == kMark ? text.substr(kMark.size()) : text;
}

// ---- characters and messages end here -----------------------------------------------------------

// ---- the Scanner begins here --------------------------------------------------------------------

// The scanner of one text named `name` (for messages): next_line() moves to the next line with
// data, the field readers below take its fields in order, and every problem is an InputError
// naming the file and the line.
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

  // The number of the current line (1 before the first), for messages.
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

  // Fails with an InputError naming the file, the current line and `message`.
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
  // ---- the slow paths and the messages ----

  // What parse_double found: a number, no number, or a number outside double's range.
  enum class Status { kOk, kMalformed, kOutOfRange };

  // Whether a number's text ends at p: at the end of the line, a blank or a '#'.
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

  // The messages of a field that is missing, not a number, or outside the supported range.
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
  const char* after_ = nullptr;    // the end of the number parse_double read
  std::size_t line_ = 0;           // number of the current line (1-based)
  const std::string& name_;
};

// ---- the Scanner ends here ----------------------------------------------------------------------

}  // namespace mwst::io::detail
