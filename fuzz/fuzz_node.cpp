// fuzz/fuzz_node.cpp — libFuzzer harness for the .node reader (mwst::io::parse_node): any byte
// string must either parse or raise InputError; crashes, sanitizer reports, other exceptions and
// unbounded allocations are bugs.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "mwst/error.hpp"
#include "mwst/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const mwst::Pslg p = mwst::io::parse_node(text, "fuzz.node");
    // Whatever is accepted must satisfy the reader's promises.
    if (p.points.size() != p.point_markers.size()) __builtin_trap();
    for (const auto& q : p.points) {
      if (!mwst::in_supported_range(q)) __builtin_trap();
    }
  } catch (const mwst::InputError&) {
  }
  return 0;
}
