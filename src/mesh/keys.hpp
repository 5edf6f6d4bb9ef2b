// mesh/keys.hpp — hash keys of the mesh vocabulary: an edge as one 64-bit word, a point by its exact
// coordinates. Internal (not installed); the one definition for every layer above geometry.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "mwst/geometry/geometry.hpp"

namespace mwst {

// The directed edge u→v as one word: u in the high half, v in the low half.
inline std::uint64_t edge_key(std::uint32_t u, std::uint32_t v) {
  return (static_cast<std::uint64_t>(u) << 32) | v;
}
// The undirected edge {u, v}: the directed key from the smaller vertex.
inline std::uint64_t undirected_key(std::uint32_t u, std::uint32_t v) {
  return u < v ? edge_key(u, v) : edge_key(v, u);
}

// A point by its exact coordinates (+0.0 and -0.0 are the same point).
struct PointKey {
  std::uint64_t x, y;
  explicit PointKey(const Point& p)
      : x(std::bit_cast<std::uint64_t>(p.x + 0.0)), y(std::bit_cast<std::uint64_t>(p.y + 0.0)) {}
  friend bool operator==(const PointKey&, const PointKey&) = default;
};
// Mixes both words (a splitmix finaliser), so that points on a line or a grid spread over buckets.
struct PointKeyHash {
  std::size_t operator()(const PointKey& k) const {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull ^ (k.y + 0x632BE59BD9B4E019ull + (k.x << 6) + (k.x >> 2));
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace mwst
