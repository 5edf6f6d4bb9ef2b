// src/algorithms/triangle_key.hpp — a hash of a triangle's three vertex ids (sorted by the caller),
// for maps from a triangle's corners to its slot. Internal to the algorithms layer.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "mwst/mesh/mesh.hpp"

namespace mwst::detail {

struct TripleHash {
  std::size_t operator()(const std::array<VertexId, 3>& t) const {
    std::uint64_t h = t[0];
    h = h * 0x9E3779B97F4A7C15ull ^ t[1];
    h = h * 0x9E3779B97F4A7C15ull ^ t[2];
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

}  // namespace mwst::detail
