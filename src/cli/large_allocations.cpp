// The command line's allocation policies (src/cli/commands.hpp). use_one_heap, for the meshing
// commands, sets glibc's heap up (mallopt) so that fewer fresh pages are faulted in; commands.hpp
// says why. advise_huge_pages_for_large_allocations is for `mwst bundle`, which puts its large
// arrays in their own mappings instead: once a command asks for it, every allocation by operator
// new of 4 MiB or more starts on a huge page's boundary and its first half is advised transparent huge pages before it is returned
// (support::allocate_on_huge_pages, which says why only that half).
//
// Why: `mwst bundle` puts arrays of 1 MB or more in their own mappings (mallopt, cmd_bundle.cpp), so
// that what each phase frees leaves the resident set; every phase's arrays are then fresh pages,
// and the first write to each 4 KiB page traps into the kernel. On a 1M-triangle mesh that was
// 325,000 traps (1.3 GB faulted for a 300 MB peak) and 2–3 s of system time on a virtual
// machine, spread over some twenty arrays in as many places (the mesh files' parsing, the
// covering mesh, the renumbering, the lists, the box counts). Advising each allocation in one place
// covers them all: the advised 2 MiB pages then fault once each (holes 1M: 325,000 faults →
// 217,000; peak resident size unchanged).
//
// operator new is replaced for the whole program, but nothing changes until a command asks:
// the replacement allocates with malloc exactly as the library's default does (and calls the
// new-handler the same way); when asked, blocks of 4 MiB or more come from posix_memalign instead.
// operator delete is not replaced: free() releases both. The advice
// never touches the memory's values, so no result depends on it. Sanitizer builds keep their own
// operator new (it is how they track the heap).
#include <malloc.h>

#include <cstddef>
#include <cstdlib>
#include <limits>
#include <new>

#include "cli/commands.hpp"
#include "support/huge_pages.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MWST_REPLACE_OPERATOR_NEW 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define MWST_REPLACE_OPERATOR_NEW 0
#endif
#endif
#ifndef MWST_REPLACE_OPERATOR_NEW
#define MWST_REPLACE_OPERATOR_NEW 1
#endif

namespace mwst::cli {

namespace {

// Set once, before the command's threads start; read by every allocation.
bool g_advise_large = false;

}  // namespace

void advise_huge_pages_for_large_allocations() { g_advise_large = MWST_REPLACE_OPERATOR_NEW != 0; }

bool huge_pages_for_large_allocations() { return g_advise_large; }

void use_one_heap() {
#if defined(__GLIBC__) && MWST_REPLACE_OPERATOR_NEW
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

}  // namespace mwst::cli

#if MWST_REPLACE_OPERATOR_NEW

namespace {

// Blocks from this size on (their first half holds a whole huge page or more).
constexpr std::size_t kLargeBlock = std::size_t{4} << 20;

// malloc, or the new-handler's loop and std::bad_alloc, as the default operator new does; when
// asked for, a block of kLargeBlock bytes or more from support::allocate_on_huge_pages.

void* allocate_advising_large(std::size_t bytes) {
  if (bytes == 0) bytes = 1;
  const bool large = mwst::cli::g_advise_large && bytes >= kLargeBlock;
  for (;;) {
    if (void* p = large ? mwst::support::allocate_on_huge_pages(bytes) : std::malloc(bytes)) return p;
    std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}

}  // namespace

void* operator new(std::size_t bytes) { return allocate_advising_large(bytes); }
void* operator new[](std::size_t bytes) { return allocate_advising_large(bytes); }
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept {
  try {
    return allocate_advising_large(bytes);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept {
  try {
    return allocate_advising_large(bytes);
  } catch (...) {
    return nullptr;
  }
}

#endif
