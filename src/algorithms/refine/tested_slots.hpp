// src/algorithms/refine/tested_slots.hpp — TestedSlots: the slots of the skinny triangles a BRH
// pass tested, as a bit set over the mesh's slots.
//
// Why: every triangle a pass makes goes through BRH's is_bad, many of them several times (a
// triangle is tested again whenever it is taken from the queue), and BRH needs only which slots
// were tested (update_skinny sorts, deduplicates and filters them). On 40k points on a circle the
// first pass made a million entries for ~150k slots: their array, grown by doubling, was the peak
// of memory of the whole run (4 MiB live, 6 MiB while it grew). A bit a slot is 19 KB there.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mwst/mesh/mesh.hpp"

namespace mwst::brh {

class TestedSlots {
 public:
  void add(TriangleId t) {
    const std::size_t word = t >> 6;
    if (word >= bits_.size()) {
      // Grown by a quarter, as the mesh's own arrays grow (reserved first: resize alone doubles).
      const std::size_t words = std::max(word + 1, bits_.size() + bits_.size() / 4 + 64);
      bits_.reserve(words);
      bits_.resize(words, 0);
    }
    bits_[word] |= std::uint64_t{1} << (t & 63);
  }

  // Appends every slot added since the last release, each once, in increasing order.
  void append_to(std::vector<TriangleId>& out) const {
    for (std::size_t word = 0; word < bits_.size(); ++word) {
      for (std::uint64_t w = bits_[word]; w != 0; w &= w - 1) {
        out.push_back(static_cast<TriangleId>(word * 64 + static_cast<std::size_t>(std::countr_zero(w))));
      }
    }
  }

  std::size_t bytes() const { return bits_.capacity() * sizeof(std::uint64_t); }

  // Forgets them and frees the set.
  void release() { std::vector<std::uint64_t>().swap(bits_); }

 private:
  std::vector<std::uint64_t> bits_;  // bit t: slot t was added
};

}  // namespace mwst::brh
