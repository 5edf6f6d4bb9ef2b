// fuzz/fuzz_poly.cpp — libFuzzer harness for the .poly reader (mwst::io::parse_poly): any byte
// string must either parse or raise InputError; crashes, sanitizer reports, other exceptions and
// unbounded allocations are bugs. What a text reads as must not depend on its line endings or a
// byte-order mark (reader_invariance.hpp). (A vertex count of 0 looks for a .node beside the given
// name; the name points into a directory that does not exist, so that path is exercised as an
// error.)
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "reader_invariance.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const mwst::Pslg p = mwst::io::parse_poly(text, "/nonexistent-mwst-fuzz/fuzz.poly");
    // Whatever is accepted must satisfy the reader's promises.
    if (p.points.size() != p.point_markers.size()) __builtin_trap();
    if (p.segments.size() != p.segment_lines.size()) __builtin_trap();
    for (const auto& s : p.segments) {
      if (s.a >= p.points.size() || s.b >= p.points.size()) __builtin_trap();
    }
    for (const auto& q : p.points) {
      if (!mwst::in_supported_range(q)) __builtin_trap();
    }
    for (const auto& q : p.holes) {
      if (!mwst::in_supported_range(q)) __builtin_trap();
    }
  } catch (const mwst::InputError&) {
  }
  mwst_fuzz::check_reader_invariance(text, [](const std::string& t) { return mwst::io::parse_poly(t, "/nonexistent-mwst-fuzz/fuzz.poly"); });
  return 0;
}
