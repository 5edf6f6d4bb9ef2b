// TestedSlots (the slots a BRH pass tested): every slot added comes back once, in increasing
// order, however often it was added, and the set takes a bit a slot (grown by a quarter), not an
// entry per addition (a pass on 40k points on a circle tested ~150k slots a million times).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "algorithms/refine/tested_slots.hpp"

namespace mwst {
namespace {

TEST(TestedSlots, EachSlotOnceInOrderWithinABitASlot) {
  std::mt19937_64 rng(11);
  for (const std::size_t slots : {std::size_t{1}, std::size_t{100}, std::size_t{5000}, std::size_t{150000}}) {
    brh::TestedSlots tested;
    std::set<TriangleId> added;
    TriangleId largest = 0;
    // 20 additions a slot, the first over the slots in order (as a pass makes new slots), the rest
    // at random among them, some slots never added.
    for (std::size_t i = 0; i < 20 * slots; ++i) {
      const auto t = static_cast<TriangleId>(i < slots ? i : rng() % slots) * 3 / 2;
      tested.add(t);
      added.insert(t);
      largest = std::max(largest, t);
      // 64 bits a word, the words grown by a quarter plus 64 past the largest slot.
      ASSERT_LE(tested.bytes(), 8 * ((largest / 64 + 1) + (largest / 64 + 1) / 4 + 64)) << "after " << i + 1 << " additions";
    }
    std::vector<TriangleId> out{42};  // (appended to, not replaced)
    tested.append_to(out);
    ASSERT_EQ(out.size(), added.size() + 1);
    EXPECT_EQ(out[0], 42u);
    EXPECT_EQ(std::vector<TriangleId>(out.begin() + 1, out.end()), std::vector<TriangleId>(added.begin(), added.end()));
    tested.release();
    EXPECT_EQ(tested.bytes(), 0u);
    out.clear();
    tested.append_to(out);
    EXPECT_TRUE(out.empty());
  }
}

}  // namespace
}  // namespace mwst
