// src/algorithms/bundle/lists.hpp — the bundle number's workers and candidate lists (internal).
//   worker_threads             — how many threads a job gets (small inputs: one)
//   make_workers               — one Worker per thread
//   for_ranges                 — body(worker, begin, end, k) on contiguous ranges, one thread each
//   build_lists                — the candidates of every Delaunay triangle, by floods
//   build_lists_within_budget  — the same within BundleOptions::candidate_budget
//   count_cut_lists            — the counts of the cut lists that can be among the largest few
// Threads come from support/parallel.hpp; results are merged in range order, so they do not
// depend on the number of threads.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/worker.hpp"
#include "support/parallel.hpp"
#include "support/set_bits.hpp"

namespace mwst::bundle {

// The threads for `work` items: 1 below 20000 (threads cost more than they save), else the
// requested number (0: one per hardware thread), at most 16.
unsigned worker_threads(unsigned requested, std::size_t work);

std::vector<std::unique_ptr<Worker>> make_workers(const Shared& sh, unsigned threads, bool per_triangle,
                                                  bool prune);

// Runs body(worker, begin, end, k) on workers.size() contiguous ranges of [0, n), worker k on
// range k, one thread each.
template <class Body>
void for_ranges(std::vector<std::unique_ptr<Worker>>& workers, std::size_t n, Body body) {
  support::parallel_ranges(workers.size(), n, [&](std::size_t k, std::size_t begin, std::size_t end) {
    body(*workers[k], begin, end, k);
  });
}

// The boxes of the floods build_lists runs (Worker::flood_box), one per flooded DT slot: a bit per
// slot with a count per 64 slots (the rank of a flooded slot among them: 12 bytes per 64 slots)
// and the boxes of the flooded slots in slot order, in floats rounded outwards (a box only has to
// hold every triangle its disk meets: in_k_bundle's reach boxes). A box of doubles per slot of
// DT(V) was 32 bytes a slot, held through in_k_bundle's peak; a slot not flooded reads kEmpty.
class FloodBoxes {
 public:
  using Box = std::array<double, 4>;  // x0, y0, x1, y1
  static constexpr Box kEmpty{kInf, kInf, -kInf, -kInf};

  // No boxes yet; slot d will have one if flooded(d).
  template <class Flooded>
  void reset(std::size_t slots, Flooded flooded) {
    bits_.assign(slots / 64 + 1, 0);
    before_.assign(bits_.size(), 0);
    std::uint32_t count = 0;
    for (std::size_t d = 0; d < slots; ++d) {
      if (d % 64 == 0) before_[d / 64] = count;
      if (!flooded(static_cast<TriangleId>(d))) continue;
      bits_[d / 64] |= std::uint64_t{1} << (d % 64);
      ++count;
    }
    boxes_.assign(count, {kInfFloat, kInfFloat, -kInfFloat, -kInfFloat});
  }

  // (Slot d must be flooded.) Threads may set the boxes of different slots at once.
  void set(TriangleId d, const Box& box) {
    boxes_[rank(d)] = {down(box[0]), down(box[1]), up(box[2]), up(box[3])};
  }

  // A box holding the one set (the same where floats hold it exactly).
  Box box(TriangleId d) const {
    if (std::size_t{d} / 64 >= bits_.size() || (bits_[d / 64] >> (d % 64) & 1u) == 0) return kEmpty;
    const auto& b = boxes_[rank(d)];
    return {b[0], b[1], b[2], b[3]};
  }

 private:
  static constexpr float kInfFloat = std::numeric_limits<float>::infinity();
  // The nearest float at most / at least x.
  static float down(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) > x ? std::nextafter(f, -kInfFloat) : f;
  }
  static float up(double x) {
    const auto f = static_cast<float>(x);
    return static_cast<double>(f) < x ? std::nextafter(f, kInfFloat) : f;
  }
  std::uint32_t rank(TriangleId d) const {
    const std::uint64_t below = bits_[d / 64] & ((std::uint64_t{1} << (d % 64)) - 1);
    return before_[d / 64] + support::set_bits(below);
  }

  std::vector<std::uint64_t> bits_;
  std::vector<std::uint32_t> before_;  // per 64 slots: the flooded slots before them
  std::vector<std::array<float, 4>> boxes_;
};

// Fills sh.list_chunks / sh.list_begin (Shared::list_data reads them): the candidates of every
// Delaunay triangle (or of those flagged in `needed`; the others get empty lists), by floods. A
// slot sharing another's disk (Shared::disk) gets an empty list: it reads that slot's.
// With `cap`, a list stops at cap triangles and its flag in sh.truncated is set if the flood had
// more to give.
void build_lists(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers,
                 const std::vector<std::uint8_t>* needed = nullptr,
                 FloodBoxes* boxes = nullptr,
                 std::uint32_t cap = std::numeric_limits<std::uint32_t>::max());

// bundle_number's lists within options.candidate_budget: every list capped at an equal share of
// the budget, then the lists cut short again with an equal share of what is left. False if some
// list is still cut short (sh.truncated says which).
bool build_lists_within_budget(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers, std::size_t budget);

// For bundle_number's lower bound, the `full` cut lists (cut: (0, DT slot) in slot order, each
// slot's list cut at the budget's cap) whose own triangles meet their disk most often (ties to
// the lower slot): sets cut[i].first to that count (Worker::circumdisk_count) for a prefix of `cut`
// that holds them, and returns the prefix's length. A count is at most its list's length, so the
// counts stop once the `full`-th largest reaches the longest list left: on meshes whose cut disks
// meet all of their lists (circular holes, points on an ellipse) after the first block.
std::size_t count_cut_lists(const Shared& sh, std::vector<std::unique_ptr<Worker>>& workers,
                            std::vector<std::pair<std::uint32_t, TriangleId>>& cut, std::size_t full);

}  // namespace mwst::bundle
