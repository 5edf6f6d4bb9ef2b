// src/algorithms/bundle/part_lists.hpp — PartLists: one list made in parts, each part the output
// of one worker over a contiguous range of queries, read as their concatenation without being
// copied into it.
//
// Why: in_k_bundle's stage 1 writes the S(t) lists of the queries it leaves undecided per worker;
// they were copied into one array held through stage 2, and the copy and the parts together were
// BRH's peak of memory (strip and coastline, 160k: the S(t) lists ~12 MB, twice, of ~125 MB).
// A query's entries lie in one part (its worker wrote them all), so a range of them is a span of
// that part.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "mwst/mesh/mesh.hpp"

namespace mwst::bundle {

class PartLists {
 public:
  // Appends the next part (its entries follow the last part's in the concatenation).
  void append(std::vector<TriangleId>&& part) {
    first_.push_back(size_);
    size_ += part.size();
    parts_.push_back(std::move(part));
  }

  // Entries [begin, end) of the concatenation; they must lie in one part (any empty range does).
  std::span<const TriangleId> range(std::size_t begin, std::size_t end) const {
    if (begin >= end) return {};
    // Parts starting at the same offset are empty but the last of them, which holds `begin`.
    const auto after = std::upper_bound(first_.begin(), first_.end(), begin);
    const auto c = static_cast<std::size_t>(after - first_.begin()) - 1;
    return {parts_[c].data() + (begin - first_[c]), end - begin};
  }

  // The parts in order (their concatenation is the list).
  const std::vector<std::vector<TriangleId>>& parts() const { return parts_; }
  std::size_t size() const { return size_; }

 private:
  std::vector<std::vector<TriangleId>> parts_;
  std::vector<std::size_t> first_;  // per part: the offset of its first entry
  std::size_t size_ = 0;
};

}  // namespace mwst::bundle
