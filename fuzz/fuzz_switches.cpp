// fuzz/fuzz_switches.cpp — libFuzzer harness for Triangle's switch parser
// (mwst::parse_triangle_switches): any string either parses or raises std::invalid_argument whose
// message names a switch or a number; a leading '-' never changes the result; what is accepted is
// consistent (refinement exactly when q, a or D is given; an area bound is positive or absent).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "mwst/io/triangle_switches.hpp"

namespace {

std::string outcome(const std::string& text, mwst::TriangleSwitches* out) {
  try {
    *out = mwst::parse_triangle_switches(text);
    return "";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    if (message.empty()) __builtin_trap();
    return message;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  mwst::TriangleSwitches plain, dashed;
  const std::string a = outcome(text, &plain);
  if (!text.empty() && text[0] == '-') return 0;
  const std::string b = outcome("-" + text, &dashed);
  if (a != b) __builtin_trap();
  if (!a.empty()) return 0;
  const bool refines = plain.options.method == mwst::Method::kDr;
  if (refines != plain.quality) __builtin_trap();
  if (plain.options.max_area == plain.options.max_area && plain.options.max_area != -1.0 &&
      !(plain.options.max_area > 0.0)) {
    __builtin_trap();
  }
  if (plain.options.min_angle_deg != dashed.options.min_angle_deg || plain.ignored != dashed.ignored) __builtin_trap();
  return 0;
}
