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

}  // namespace
}  // namespace mwst
