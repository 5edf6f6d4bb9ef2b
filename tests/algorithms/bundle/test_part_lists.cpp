// PartLists (in_k_bundle's S(t) lists, left in the parts the workers wrote): every query's range
// reads back as in the concatenation, whatever the split into parts (empty parts and empty lists
// at their ends included), and the parts are the workers' own arrays, not copies of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "algorithms/bundle/part_lists.hpp"

namespace mwst {
namespace {

TEST(PartLists, RangesReadAsTheConcatenation) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    // Per query a list of 0–5 entries (a third of them empty), split into parts of consecutive
    // queries at random cuts (some parts with no query, some with only empty lists).
    const std::size_t queries = rng() % 40;
    std::vector<std::vector<TriangleId>> lists(queries);
    for (auto& list : lists) {
      const std::size_t n = rng() % 3 == 0 ? 0 : rng() % 6;
      for (std::size_t i = 0; i < n; ++i) list.push_back(static_cast<TriangleId>(rng() % 1000));
    }
    const std::size_t part_count = 1 + rng() % 5;
    std::vector<std::size_t> cut(part_count + 1, 0);
    for (std::size_t k = 1; k < part_count; ++k) cut[k] = rng() % (queries + 1);
    cut[part_count] = queries;
    std::sort(cut.begin(), cut.end());
    bundle::PartLists lists_in_parts;
    std::vector<TriangleId> concatenation;
    std::vector<std::size_t> begin(queries + 1, 0);
    std::vector<const TriangleId*> part_data;
    for (std::size_t k = 0; k < part_count; ++k) {
      std::vector<TriangleId> part;
      for (std::size_t q = cut[k]; q < cut[k + 1]; ++q) {
        begin[q] = concatenation.size();
        part.insert(part.end(), lists[q].begin(), lists[q].end());
        concatenation.insert(concatenation.end(), lists[q].begin(), lists[q].end());
      }
      part_data.push_back(part.data());
      lists_in_parts.append(std::move(part));
    }
    begin[queries] = concatenation.size();
    ASSERT_EQ(lists_in_parts.size(), concatenation.size());
    ASSERT_EQ(lists_in_parts.parts().size(), part_count);
    for (std::size_t k = 0; k < part_count; ++k) {
      EXPECT_EQ(lists_in_parts.parts()[k].data(), part_data[k]) << "part " << k << " was copied";
    }
    for (std::size_t q = 0; q < queries; ++q) {
      const auto span = lists_in_parts.range(begin[q], begin[q + 1]);
      ASSERT_EQ(std::vector<TriangleId>(span.begin(), span.end()), lists[q]) << "trial " << trial << " query " << q;
    }
  }
}

}  // namespace
}  // namespace mwst
