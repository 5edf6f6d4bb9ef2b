// The candidate lists build_lists leaves in the floods' chunks (Shared::list_chunks, no copy) read
// the same through Shared::list_data as each Delaunay triangle's own flood, on several threads
// (several parts, each of several chunks), and again once flattened into one array.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "algorithms/bundle/lists.hpp"
#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/worker.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {
namespace {

std::vector<Point> uniform_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(0.0, 1.0);
  std::vector<Point> pts(n);
  for (Point& p : pts) p = {coord(rng), coord(rng)};
  return pts;
}

// Each DT slot's list as list_data reads it.
std::vector<std::vector<TriangleId>> read_lists(const bundle::Shared& sh) {
  std::vector<std::vector<TriangleId>> lists(sh.dt.triangle_slots());
  for (TriangleId d = 0; d < lists.size(); ++d) {
    const TriangleId* data = sh.list_data(d);
    lists[d].assign(data, data + sh.list_size(d));
  }
  return lists;
}

// Each DT slot's flood by a worker of its own (empty for slots not flooded).
std::vector<std::vector<TriangleId>> own_floods(const bundle::Shared& sh, const std::vector<std::uint8_t>* needed) {
  bundle::Worker w(sh, false, false);
  std::vector<std::vector<TriangleId>> lists(sh.dt.triangle_slots());
  for (TriangleId d = 0; d < lists.size(); ++d) {
    if (sh.dt.is_dead(d) || sh.dt.is_ghost(d) || (needed && (*needed)[d] == 0)) continue;
    w.flood(d, lists[d]);
  }
  return lists;
}

TEST(BundleLists, ChunkedListsReadAsTheFloodsAndAsFlattened) {
  const Mesh m = delaunay(uniform_points(4000, 11));
  bundle::Shared sh(m);
  ASSERT_TRUE(sh.build());
  auto workers = bundle::make_workers(sh, 3, false, false);
  bundle::build_lists(sh, workers);
  EXPECT_TRUE(sh.list.empty());
  EXPECT_GT(sh.list_chunks.size(), 3u);  // several chunks in each of the three parts
  const auto expected = own_floods(sh, nullptr);
  std::size_t total = 0;
  for (const auto& l : expected) total += l.size();
  EXPECT_EQ(sh.list_begin.back(), total);
  EXPECT_EQ(read_lists(sh), expected);
  sh.flatten_lists();
  EXPECT_TRUE(sh.list_chunks.empty());
  EXPECT_EQ(sh.list.size(), total);
  EXPECT_EQ(read_lists(sh), expected);
  sh.release_lists();
  EXPECT_TRUE(sh.list.empty() && sh.list_chunks.empty() && sh.list_chunk_first.empty());
}

TEST(BundleLists, OnlyTheNeededSlotsAreListed) {
  const Mesh m = delaunay(uniform_points(3000, 12));
  bundle::Shared sh(m);
  ASSERT_TRUE(sh.build());
  std::vector<std::uint8_t> needed(sh.dt.triangle_slots(), 0);
  for (std::size_t d = 0; d < needed.size(); d += 3) needed[d] = 1;
  auto workers = bundle::make_workers(sh, 2, false, false);
  bundle::build_lists(sh, workers, &needed);
  EXPECT_EQ(read_lists(sh), own_floods(sh, &needed));
}

// FloodBoxes keeps a box per flooded slot behind a rank directory: it reads as a box per slot,
// empty where no flood ran, whatever the pattern (runs across 64-slot words, none, all).
TEST(BundleLists, FloodBoxesReadAsABoxPerSlot) {
  std::mt19937_64 rng(5);
  for (const double density : {0.0, 0.03, 0.5, 0.97, 1.0}) {
    const std::size_t slots = 1000;
    std::bernoulli_distribution pick(density);
    std::vector<std::uint8_t> flooded(slots);
    for (auto& f : flooded) f = pick(rng) ? 1 : 0;
    bundle::FloodBoxes boxes;
    boxes.reset(slots, [&](TriangleId d) { return flooded[d] != 0; });
    std::vector<bundle::FloodBoxes::Box> plain(slots, bundle::FloodBoxes::kEmpty);
    for (TriangleId d = 0; d < slots; ++d) {
      if (!flooded[d]) continue;
      plain[d] = {double(d), -double(d), double(d) + 1, 2.0 * d};
      boxes.set(d, plain[d]);
    }
    for (TriangleId d = 0; d < slots; ++d) EXPECT_EQ(boxes.box(d), plain[d]) << "slot " << d << " density " << density;
    EXPECT_EQ(boxes.box(static_cast<TriangleId>(slots + 100)), bundle::FloodBoxes::kEmpty);
  }
}

// build_lists' boxes are each flooded slot's own flood box (Worker::flood_box), on several threads.
TEST(BundleLists, BoxesAreTheFloodsOwn) {
  const Mesh m = delaunay(uniform_points(3000, 13));
  bundle::Shared sh(m);
  ASSERT_TRUE(sh.build());
  std::vector<std::uint8_t> needed(sh.dt.triangle_slots(), 0);
  for (std::size_t d = 0; d < needed.size(); d += 2) needed[d] = 1;
  auto workers = bundle::make_workers(sh, 3, false, false);
  bundle::FloodBoxes boxes;
  bundle::build_lists(sh, workers, &needed, &boxes);
  bundle::Worker w(sh, false, false);
  w.want_flood_box = true;
  std::vector<TriangleId> list;
  std::size_t flooded = 0;
  for (TriangleId d = 0; d < sh.dt.triangle_slots(); ++d) {
    if (sh.dt.is_dead(d) || sh.dt.is_ghost(d) || needed[d] == 0) {
      EXPECT_EQ(boxes.box(d), bundle::FloodBoxes::kEmpty);
      continue;
    }
    w.flood(d, list);
    EXPECT_EQ(boxes.box(d), w.flood_box);
    ++flooded;
  }
  EXPECT_GT(flooded, 1000u);
}

}  // namespace
}  // namespace mwst
