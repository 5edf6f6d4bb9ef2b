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
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/worker.hpp"
#include "support/parallel.hpp"

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

// Fills sh.list_chunks / sh.list_begin (Shared::list_data reads them): the candidates of every
// Delaunay triangle (or of those flagged in `needed`; the others get empty lists), by floods. A
// slot sharing another's disk (Shared::disk) gets an empty list: it reads that slot's.
// With `cap`, a list stops at cap triangles and its flag in sh.truncated is set if the flood had
// more to give.
void build_lists(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers,
                 const std::vector<std::uint8_t>* needed = nullptr,
                 std::vector<std::array<double, 4>>* boxes = nullptr,
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
