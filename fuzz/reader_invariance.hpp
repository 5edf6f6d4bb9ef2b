// fuzz/reader_invariance.hpp — a property both reader harnesses (fuzz_node.cpp, fuzz_poly.cpp)
// check: what a text reads as does not depend on its line endings or on a UTF-8 byte-order mark.
// A text without '\r' must read exactly the same (the same points bit for bit, markers, segments
// with their line numbers, holes; or the same error on the same line) with every "\n" made a lone
// "\r", and with a byte-order mark put in front (of a text that is not empty and has none). With
// "\r\n" endings the file is longer, so a header count refused as more than the rest of the file
// can hold may pass that check and be refused later as truncated: there only acceptance and the
// result read must agree.
#pragma once

#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst_fuzz {

struct ReadOutcome {
  bool accepted = false;
  mwst::Pslg pslg;
  std::size_t line = 0;
  std::string message;
};

template <typename Parse>
ReadOutcome read_outcome(const Parse& parse, const std::string& text) {
  ReadOutcome out;
  try {
    out.pslg = parse(text);
    out.accepted = true;
  } catch (const mwst::InputError& e) {
    out.line = e.line();
    out.message = e.what();
  }
  return out;
}

inline bool same_bits(const std::vector<mwst::Point>& a, const std::vector<mwst::Point>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(mwst::Point)) == 0);
}

inline bool same_result(const mwst::Pslg& a, const mwst::Pslg& b) {
  if (!same_bits(a.points, b.points) || !same_bits(a.holes, b.holes)) return false;
  if (a.point_markers != b.point_markers || a.segment_lines != b.segment_lines) return false;
  if (a.segments.size() != b.segments.size() || a.first_index != b.first_index) return false;
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const mwst::Segment &s = a.segments[i], &t = b.segments[i];
    if (s.a != t.a || s.b != t.b || s.marker != t.marker) return false;
  }
  return true;
}

[[noreturn]] inline void invariance_broken(const char* variant, const ReadOutcome& lf, const ReadOutcome& other) {
  std::fprintf(stderr, "reader invariance broken (%s): LF text %s (line %zu: %s), %s text %s (line %zu: %s)\n", variant,
               lf.accepted ? "accepted" : "refused", lf.line, lf.message.c_str(), variant,
               other.accepted ? "accepted" : "refused", other.line, other.message.c_str());
  __builtin_trap();
}

template <typename Parse>
void check_reader_invariance(std::string_view text, const Parse& parse) {
  if (text.find('\r') != std::string_view::npos) return;
  const std::string lf(text);
  std::string cr = lf, crlf;
  for (char& c : cr) c = c == '\n' ? '\r' : c;
  for (const char c : lf) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const ReadOutcome base = read_outcome(parse, lf);
  auto exactly_equal = [&](const ReadOutcome& o) {
    return o.accepted == base.accepted &&
           (base.accepted ? same_result(o.pslg, base.pslg) : o.line == base.line && o.message == base.message);
  };
  if (const ReadOutcome o = read_outcome(parse, cr); !exactly_equal(o)) invariance_broken("CR", base, o);
  // (An empty text is "empty file", a lone mark "no data"; a second mark is not skipped.)
  if (!lf.empty() && lf.rfind("\xEF\xBB\xBF", 0) != 0) {
    if (const ReadOutcome o = read_outcome(parse, "\xEF\xBB\xBF" + lf); !exactly_equal(o)) invariance_broken("BOM", base, o);
  }
  if (const ReadOutcome o = read_outcome(parse, crlf);
      o.accepted != base.accepted || (base.accepted && !same_result(o.pslg, base.pslg))) {
    invariance_broken("CR LF", base, o);
  }
}

}  // namespace mwst_fuzz
