// fuzz/fuzz_ele.cpp — libFuzzer harness for the readers of an existing mesh (Triangle's -r):
// mwst::io::parse_ele and parse_area. The first byte chooses the reader, the numbering base and the
// number of vertices (or triangles) the text is read against; the rest is the text. Any text must
// either parse or raise InputError; what is accepted must keep the readers' promises (every corner
// a vertex that exists, three distinct corners per triangle, one finite area per triangle).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned choice = data[0];
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  const bool area = (choice & 1) != 0;
  const int base = (choice >> 1) & 1;
  const std::size_t count = choice >> 2;  // 0 to 63
  try {
    if (area) {
      const std::vector<double> areas = mwst::io::parse_area(text, "fuzz.area", count);
      if (areas.size() != count) __builtin_trap();
      for (const double a : areas) {
        if (!std::isfinite(a)) __builtin_trap();
      }
    } else {
      const std::vector<std::uint32_t> triangles = mwst::io::parse_ele(text, "fuzz.ele", count, base);
      if (triangles.size() % 3 != 0) __builtin_trap();
      for (std::size_t t = 0; t < triangles.size(); t += 3) {
        const std::uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
        if (a >= count || b >= count || c >= count || a == b || b == c || c == a) __builtin_trap();
      }
    }
  } catch (const mwst::InputError&) {
  }
  return 0;
}
