// src/support/huge_pages.hpp — transparent huge pages for large fresh arrays. Internal.
//   advise_huge_pages(v)        — asks the kernel to back the reserved, untouched storage of
//                                 vector v with 2 MiB pages.
//   reserve_on_huge_pages(v, n) — v.reserve(n) and that advice: room for n elements to be filled by
//                                 push_back, whose first touch costs one fault per 2 MiB instead
//                                 of one per 4 KiB (and no pass of zeros before the values).
//   resize_on_huge_pages(v, n)  — the same, then v.resize(n) (value-initialised).
//   allocate_on_huge_pages(b)   — b bytes from malloc's family, starting on a 2 MiB boundary, the
//                                 first half advised huge pages (released by free()).
// The first write to a fresh 4 KiB page traps into the kernel, which clears the page; on a
// virtual machine each trap cost about 9 µs in measurements, so filling 80 MB of fresh 4 KiB
// pages took 0.74 s, and 0.03 s with huge pages. Large arrays touched all over (the mesh's
// triangles and points) also miss the TLB far less. Advice only: without THP, or if madvise fails,
// nothing changes but the time; the arrays' values never depend on it.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace mwst::support {

// Below this many bytes the advice is not worth a system call.
inline constexpr std::size_t kHugePageWorthwhile = std::size_t{4} << 20;

// A transparent huge page on x86-64 and arm64 with 4 KiB base pages.
inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

// Advises huge pages for the whole 2 MiB pages inside [begin, begin + bytes).
inline void advise_huge_pages(const void* begin, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
  constexpr std::uintptr_t kHuge = kHugePage;
  const auto first_byte = reinterpret_cast<std::uintptr_t>(begin);
  const std::uintptr_t first = (first_byte + kHuge - 1) / kHuge * kHuge, last = (first_byte + bytes) / kHuge * kHuge;
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)begin;
  (void)bytes;
#endif
}

template <class T>
void advise_huge_pages(const std::vector<T>& v) {
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

// Room for n elements in `v`, its storage fresh and advised huge pages when it is large and was
// not allocated yet.
template <class T>
void reserve_on_huge_pages(std::vector<T>& v, std::size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(n);
  if (n * sizeof(T) >= kHugePageWorthwhile) advise_huge_pages(v);
}

// `v` resized to n elements (value-initialised) on storage as reserve_on_huge_pages gives.
template <class T>
void resize_on_huge_pages(std::vector<T>& v, std::size_t n) {
  reserve_on_huge_pages(v, n);
  v.resize(n);
}

// `bytes` bytes starting on a huge page's boundary (posix_memalign; the alignment costs address
// space, not memory), its first half advised huge pages, so that the whole 2 MiB pages there fault
// once each when the block is a fresh mapping (a block this large is one when the mmap threshold is
// below it, as `mwst bundle` sets it). Only the first half: a huge page is resident as a whole once
// touched, and a vector grown by doubling fills the first half at once (the copy) but its second
// half only as it grows; advising all of it held up to 2 MiB of unused room per growing array (5 MB
// more at the peak of `mwst bundle` on a 160k coastline). nullptr if out of memory; free() releases
// it.
inline void* allocate_on_huge_pages(std::size_t bytes) {
  void* p = nullptr;
  if (::posix_memalign(&p, kHugePage, bytes) != 0) return nullptr;
  advise_huge_pages(p, bytes / 2);
  return p;
}

}  // namespace mwst::support
