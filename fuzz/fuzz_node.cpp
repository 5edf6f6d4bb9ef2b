// fuzz/fuzz_node.cpp — libFuzzer harness for the .node reader (mwst::io::parse_node): any byte
// string must either parse or raise InputError; crashes, sanitizer reports, other exceptions and
// unbounded allocations are bugs. What a text reads as must not depend on its line endings or a
// byte-order mark (reader_invariance.hpp).
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
    const mwst::Pslg p = mwst::io::parse_node(text, "fuzz.node");
    // Whatever is accepted must satisfy the reader's promises.
    if (p.points.size() != p.point_markers.size()) __builtin_trap();
    for (const auto& q : p.points) {
      if (!mwst::in_supported_range(q)) __builtin_trap();
    }
  } catch (const mwst::InputError&) {
  }
  mwst_fuzz::check_reader_invariance(text, [](const std::string& t) { return mwst::io::parse_node(t, "fuzz.node"); });
  return 0;
}
