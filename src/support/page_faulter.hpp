// src/support/page_faulter.hpp — faulting pages in ahead of their first write. Internal.
//   PageFaulter          — ranges of reserved (allocated, unwritten) room, populated in blocks of
//                          2 MB by whichever threads call work() (MADV_POPULATE_WRITE).
//   release_pages(b, e)  — gives the whole pages inside [b, e) back to the system (MADV_DONTNEED):
//                          their contents become unspecified, a later write gets a fresh page.
// Neither reads nor writes the memory's values, so results never depend on them; without the
// flags (kernels before 5.14, C libraries without MADV_POPULATE_WRITE) pages fault on their first
// write as usual.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace mwst::support {

// Pages to fault in ahead of their first write, shared by whichever threads are free: ranges of
// reserved (allocated, not yet written) room are handed out in blocks, and each block's pages are
// populated by the kernel in one call (MADV_POPULATE_WRITE: no trap per page; the kernel still
// clears each page). The contents are not touched, so the arrays' values never depend on it;
// without the call (kernels before 5.14, C libraries without the flag) the pages fault on their
// first write as usual.
class PageFaulter {
 public:
  void add(const void* begin, std::size_t bytes) {
    static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    const auto first = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) / page * page;
    const auto last = (reinterpret_cast<std::uintptr_t>(begin) + bytes) / page * page;
    for (std::uintptr_t at = first; at < last; at += kBlock) blocks_.push_back({at, std::min(last, at + kBlock)});
  }
  // Populates blocks until none are left (several threads may call it at once).
  void work() {
    for (;;) {
      const std::size_t i = next_.fetch_add(1, std::memory_order_relaxed);
      if (i >= blocks_.size()) return;
#ifdef MADV_POPULATE_WRITE
      ::madvise(reinterpret_cast<void*>(blocks_[i].first), blocks_[i].second - blocks_[i].first, MADV_POPULATE_WRITE);
#endif
    }
  }

  // Hands out no more blocks (those being populated finish): the work is no longer wanted.
  void stop() { next_.store(blocks_.size(), std::memory_order_relaxed); }

 private:
  static constexpr std::uintptr_t kBlock = std::uintptr_t{1} << 21;
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> blocks_;
  std::atomic<std::size_t> next_{0};
};

// Gives the pages lying wholly inside [begin, end) back to the system.
inline void release_pages(const void* begin, const void* end) {
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const auto used = reinterpret_cast<std::uintptr_t>(begin);
  const auto room = reinterpret_cast<std::uintptr_t>(end);
  const std::uintptr_t first = (used + page - 1) / page * page, last = room / page * page;
  if (first < last) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
}

}  // namespace mwst::support
