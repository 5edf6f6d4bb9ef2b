// src/algorithms/refine/walk_rng.hpp — the walk's xorshift32 generator and its jump-ahead (internal).
// Refiner::walk draws one number per triangle it stands in, to pick which edge to try first. Where
// the walk skips a run of triangles whose step was forced (a point fan, fan_run.cpp), the
// generator must still advance by one draw per skipped triangle, or every later walk would take
// other tie-breaks than before. One xorshift step is linear over GF(2)^32, so k steps are the
// k-th power of a 32×32 bit matrix: applying the powers 2^b for the set bits of k costs at most
// 32 × 32 XORs, whatever k is.
#pragma once

#include <array>
#include <cstdint>

namespace mwst::refinement {

constexpr std::uint32_t xorshift_step(std::uint32_t x) {
  x ^= x << 13;
  x ^= x >> 17;
  x ^= x << 5;
  return x;
}

// A linear map of GF(2)^32 by the images of the 32 unit vectors.
using BitMatrix = std::array<std::uint32_t, 32>;

constexpr std::uint32_t apply_bits(const BitMatrix& m, std::uint32_t x) {
  std::uint32_t y = 0;
  for (unsigned b = 0; b < 32; ++b) {
    if ((x >> b) & 1u) y ^= m[b];
  }
  return y;
}

// powers[b] = the map of 2^b xorshift steps.
constexpr std::array<BitMatrix, 64> xorshift_powers() {
  std::array<BitMatrix, 64> powers{};
  for (unsigned b = 0; b < 32; ++b) powers[0][b] = xorshift_step(std::uint32_t{1} << b);
  for (unsigned k = 1; k < 64; ++k) {
    for (unsigned b = 0; b < 32; ++b) powers[k][b] = apply_bits(powers[k - 1], powers[k - 1][b]);
  }
  return powers;
}

// The state after `steps` xorshift steps from x.
inline std::uint32_t xorshift_jump(std::uint32_t x, std::uint64_t steps) {
  static constexpr std::array<BitMatrix, 64> kPowers = xorshift_powers();
  for (unsigned k = 0; steps != 0; ++k, steps >>= 1) {
    if (steps & 1u) x = apply_bits(kPowers[k], x);
  }
  return x;
}

}  // namespace mwst::refinement
