// src/mesh/insertion_order.hpp — the insertion order of delaunay(): BRIO rounds (Amenta, Choi and
// Rote 2003) of an adaptive Hilbert curve order, and for large inputs the split into two halves
// separated by a vertical line (merged by merge_halves in delaunay.cpp). Internal (not installed).
#pragma once

#include <cstddef>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

#include "mwst/geometry/geometry.hpp"

namespace mwst::insertion_order {

// Inputs of at least this many points are sorted and triangulated in two halves on two threads.
inline constexpr std::size_t kParallelThreshold = 1u << 15;

// Runs `beside` and `here` — on two threads if `parallel`, else one after the other — and returns
// when both are done. The work is split the same way either way, so results never depend on it.
template <class Beside, class Here>
void run_both(bool parallel, Beside&& beside, Here&& here) {
  if (!parallel) {
    here();
    beside();
    return;
  }
  std::jthread worker(std::forward<Beside>(beside));
  here();
  worker.join();
}

// Returns the input indices in insertion order: BRIO rounds of the adaptive Hilbert curve order.
// Inputs of at least kParallelThreshold points are first split at the median x coordinate (left: x
// below it; right: the rest) and each half is ordered in its own bounding box, on its own thread if
// `parallel`; *left_count receives the left half's size (0: no split).
std::vector<std::uint32_t> hilbert_order(const std::vector<Point>& points, std::size_t* left_count, bool parallel);

}  // namespace mwst::insertion_order
