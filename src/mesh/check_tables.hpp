// src/mesh/check_tables.hpp — the flat tables check.cpp looks a mesh's edges and vertices up in:
// its directed edges grouped by origin and sorted by destination (found by a binary search among
// the origin's few edges), and its vertices by their exact coordinates (open addressing). They
// replace node-based hash maps, whose allocations and pointer chasing made `mwst check` grow
// faster than the mesh. Internal (not installed).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/keys.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::detail {

// The directed edges u → v of a list of triangles, each the edge of one corner slot 3t + k
// (from corner k to corner k + 1 of triangle t, the apex corner k + 2). Entries of an origin are
// consecutive and sorted by destination; an edge listed by several triangles is kept once, for
// the least slot, and the others are returned as duplicates.
class DirectedEdges {
 public:
  struct Duplicate {
    std::uint32_t slot;        // the corner slot whose edge was listed before
    std::uint32_t first_slot;  // the least slot listing it
  };

  // Builds the table of the triangles with valid[t] != 0 (vertices below vertex_count); returns
  // the duplicates in slot order.
  std::vector<Duplicate> build(std::size_t vertex_count, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                               const std::vector<char>& valid) {
    triangles_ = &triangles;
    std::vector<std::uint32_t> count(vertex_count + 1, 0);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      if (!valid[t]) continue;
      for (const std::uint32_t u : triangles[t]) ++count[u + 1];
    }
    for (std::size_t u = 0; u < vertex_count; ++u) count[u + 1] += count[u];
    // Destination in the high half, slot in the low: sorting an origin's words orders its edges
    // by destination and, for one destination, by slot.
    std::vector<std::uint64_t> words(count[vertex_count]);
    std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      if (!valid[t]) continue;
      for (unsigned k = 0; k < 3; ++k) {
        const auto slot = static_cast<std::uint32_t>(3 * t + k);
        words[fill[triangles[t][k]]++] = edge_key(triangles[t][(k + 1) % 3], slot);
      }
    }
    std::vector<Duplicate> duplicates;
    start_.assign(vertex_count + 1, 0);
    destination_.clear();
    slot_.clear();
    destination_.reserve(words.size());
    slot_.reserve(words.size());
    for (std::size_t u = 0; u < vertex_count; ++u) {
      std::sort(words.begin() + count[u], words.begin() + count[u + 1]);
      for (std::uint32_t i = count[u]; i < count[u + 1]; ++i) {
        const auto v = static_cast<std::uint32_t>(words[i] >> 32), slot = static_cast<std::uint32_t>(words[i]);
        if (destination_.size() > start_[u] && destination_.back() == v) {
          duplicates.push_back(Duplicate{slot, slot_.back()});
          continue;
        }
        destination_.push_back(v);
        slot_.push_back(slot);
      }
      start_[u + 1] = static_cast<std::uint32_t>(destination_.size());
    }
    std::sort(duplicates.begin(), duplicates.end(),
              [](const Duplicate& a, const Duplicate& b) { return a.slot < b.slot; });
    return duplicates;
  }

  std::size_t size() const { return destination_.size(); }
  std::uint32_t begin(std::uint32_t u) const { return start_[u]; }
  std::uint32_t end(std::uint32_t u) const { return start_[u + 1]; }
  std::uint32_t destination(std::uint32_t e) const { return destination_[e]; }
  std::uint32_t triangle(std::uint32_t e) const { return slot_[e] / 3; }
  std::uint32_t apex(std::uint32_t e) const { return (*triangles_)[slot_[e] / 3][(slot_[e] % 3 + 2) % 3]; }

  // The entry of u → v, or kNone.
  std::uint32_t find(std::uint32_t u, std::uint32_t v) const {
    const auto first = destination_.begin() + start_[u], last = destination_.begin() + start_[u + 1];
    const auto it = std::lower_bound(first, last, v);
    return it != last && *it == v ? static_cast<std::uint32_t>(it - destination_.begin()) : kNone;
  }
  bool contains(std::uint32_t u, std::uint32_t v) const { return find(u, v) != kNone; }
  // The entry that stands for the undirected edge {u, v}: u → v from the smaller vertex if the
  // mesh has it, else the other direction; kNone if neither.
  std::uint32_t undirected(std::uint32_t u, std::uint32_t v) const {
    const std::uint32_t forward = find(std::min(u, v), std::max(u, v));
    return forward != kNone ? forward : find(std::max(u, v), std::min(u, v));
  }

 private:
  const std::vector<std::array<std::uint32_t, 3>>* triangles_ = nullptr;
  std::vector<std::uint32_t> start_;        // per origin, its first entry; one more at the end
  std::vector<std::uint32_t> destination_;  // per entry
  std::vector<std::uint32_t> slot_;         // per entry: the least corner slot listing it
};

// Vertices by their exact coordinates (+0.0 and -0.0 alike, as PointKey): open addressing with
// linear probing over a power-of-two table at most half full, hashed by PointKeyHash.
class PointTable {
 public:
  explicit PointTable(std::size_t capacity = 0) {
    entries_.assign(std::bit_ceil(std::max<std::size_t>(16, 2 * capacity)), Entry{});
    mask_ = entries_.size() - 1;
  }
  // Records `vertex` at p unless a vertex is there already; returns that one, or kNone.
  std::uint32_t insert(const Point& p, std::uint32_t vertex) {
    const PointKey key(p);
    for (std::size_t i = PointKeyHash{}(key) & mask_;; i = (i + 1) & mask_) {
      Entry& e = entries_[i];
      if (e.vertex == kNone) {
        e = Entry{key.x, key.y, vertex};
        return kNone;
      }
      if (e.x == key.x && e.y == key.y) return e.vertex;
    }
  }
  // The vertex recorded at p, or kNone.
  std::uint32_t find(const Point& p) const {
    const PointKey key(p);
    for (std::size_t i = PointKeyHash{}(key) & mask_;; i = (i + 1) & mask_) {
      const Entry& e = entries_[i];
      if (e.vertex == kNone) return kNone;
      if (e.x == key.x && e.y == key.y) return e.vertex;
    }
  }

 private:
  struct Entry {
    std::uint64_t x = 0, y = 0;
    std::uint32_t vertex = kNone;
  };
  std::vector<Entry> entries_;
  std::size_t mask_ = 0;
};

}  // namespace mwst::detail
