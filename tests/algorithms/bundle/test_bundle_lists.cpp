// The candidate lists build_lists leaves in the floods' chunks (Shared::list_chunks, no copy) read
// the same through Shared::list_data as each Delaunay triangle's own flood, on several threads
// (several parts, each of several chunks), and again once flattened into one array.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
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

// FloodBoxes keeps a box per flooded slot behind a rank directory: it reads as a box per slot,
// empty where no flood ran, whatever the pattern (runs across 64-slot words, none, all). (Boxes
// of small integers: floats hold them exactly.)
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

// Boxes floats cannot hold come back rounded outwards: they hold the box set, and floats next to
// it (the nearest float outside each side).
TEST(BundleLists, FloodBoxesRoundOutwards) {
  bundle::FloodBoxes boxes;
  boxes.reset(3, [](TriangleId d) { return d != 1; });
  const bundle::FloodBoxes::Box set = {0.1, -0.3, 1.0 / 3.0, 1e300};
  boxes.set(0, set);
  boxes.set(2, {-1e300, 5e-324, 2.0, 2.0});
  const auto b = boxes.box(0);
  EXPECT_LT(b[0], set[0]);
  EXPECT_LT(b[1], set[1]);
  EXPECT_GT(b[2], set[2]);
  EXPECT_GE(b[3], set[3]);
  // The nearest floats: the next float inwards is on the wrong side.
  EXPECT_GT(static_cast<double>(std::nextafter(static_cast<float>(b[0]), 1.0f)), set[0]);
  EXPECT_LT(static_cast<double>(std::nextafter(static_cast<float>(b[2]), 0.0f)), set[2]);
  const auto c = boxes.box(2);
  EXPECT_EQ(c[0], -std::numeric_limits<double>::infinity());  // beyond the floats
  EXPECT_EQ(c[1], 0.0);
  EXPECT_EQ(c[2], 2.0);
  EXPECT_EQ(boxes.box(1), bundle::FloodBoxes::kEmpty);
}

// With `needed`, only those slots are listed (the others' lists are empty), and build_lists'
// boxes hold each flooded slot's own flood box (Worker::flood_box), rounded outwards to floats,
// on several threads.
TEST(BundleLists, NeededSlotsGetTheirFloodsAndBoxes) {
  const Mesh m = delaunay(uniform_points(3000, 13));
  bundle::Shared sh(m);
  ASSERT_TRUE(sh.build());
  std::vector<std::uint8_t> needed(sh.dt.triangle_slots(), 0);
  for (std::size_t d = 0; d < needed.size(); d += 2) needed[d] = 1;
  auto workers = bundle::make_workers(sh, 3, false, false);
  bundle::FloodBoxes boxes;
  bundle::build_lists(sh, workers, &needed, &boxes);
  EXPECT_EQ(read_lists(sh), own_floods(sh, &needed));
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
    const auto b = boxes.box(d);
    const auto& f = w.flood_box;
    EXPECT_TRUE(b[0] <= f[0] && b[1] <= f[1] && b[2] >= f[2] && b[3] >= f[3]) << "slot " << d;
    EXPECT_EQ(b[0], static_cast<double>(static_cast<float>(b[0])));
    EXPECT_LE(f[0] - b[0], 1e-6);  // (the coordinates lie in [0, 1])
    EXPECT_LE(b[2] - f[2], 1e-6);
    ++flooded;
  }
  EXPECT_GT(flooded, 1000u);
}

// Over the whole mesh Shared reads the mesh's own neighbour handles (no copy); own_neighbours
// copies them for a caller that frees the mesh (bundle_number of a triangle list): afterwards the
// mesh's triangles are not read for adjacency, and every slot's neighbours are still the mesh's.
TEST(BundleShared, NeighboursReadFromTheMeshOrOwnedOnceItIsFreed) {
  Mesh m = delaunay(uniform_points(2000, 5));
  bundle::Shared sh(m);
  ASSERT_TRUE(sh.build(false));
  const std::vector<Triangle> original = m.triangles;
  EXPECT_TRUE(sh.neighbours_held.empty());
  for (TriangleId t = 0; t < original.size(); ++t) {
    for (unsigned e = 0; e < 3; ++e) ASSERT_EQ(sh.sym(make_handle(t, e)), original[t].n[e]);
  }
  sh.own_neighbours();
  ASSERT_EQ(sh.neighbours_held.size(), original.size());
  for (Triangle& tri : m.triangles) tri.n = {kNone, kNone, kNone};  // as if freed
  std::size_t checked = 0;
  for (TriangleId t = 0; t < original.size(); ++t) {
    EXPECT_EQ(sh.neighbours(t), original[t].n);
    for (unsigned e = 0; e < 3; ++e) {
      ASSERT_EQ(sh.sym(make_handle(t, e)), original[t].n[e]);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 3 * original.size());
}

}  // namespace
}  // namespace mwst
