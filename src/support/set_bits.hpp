// src/support/set_bits.hpp — the number of set bits of a word, inline. Internal.
//
// std::popcount compiles to a call of libgcc's __popcountdi2 unless the target has the POPCNT
// instruction (-mpopcnt, not in the x86-64 baseline the library is built for). In to_arrays'
// rank queries (three per triangle) that call took a tenth of the copy's samples at 1M points;
// the branch-free sum below is a dozen inline instructions.
#pragma once

#include <bit>
#include <cstdint>

namespace mwst::support {

constexpr unsigned set_bits(std::uint64_t x) {
#if defined(__POPCNT__)
  return static_cast<unsigned>(std::popcount(x));
#else
  x = x - ((x >> 1) & 0x5555555555555555u);                          // 2-bit sums
  x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);  // 4-bit sums
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Fu;                          // byte sums
  return static_cast<unsigned>((x * 0x0101010101010101u) >> 56);     // their total in the top byte
#endif
}

}  // namespace mwst::support
