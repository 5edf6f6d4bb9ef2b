// src/support/spare_room.hpp — reusing memory a run has already touched. Internal (not installed).
//   UninitializedAllocator<T>  — a std::vector allocator whose resize() leaves new elements unwritten
//                                (trivially copyable elements that are always written before read).
//   SpareRoom                  — dead regions lent by their owners, handed out by bumping a pointer.
//   SpareAllocator<T>, SpareVector<T>
//                              — a vector that borrows from a SpareRoom when a region fits.
//   SpareArray<T>, make_spare_array<T>(room, n)
//                              — an unwritten array of trivial elements, borrowed the same way.
// Why: the kernel clears every page on its first touch, and the allocator hands big arrays straight
// from the system and back, so a dead array's pages are reused only when lent by hand. The values
// stored never depend on where the memory came from.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace mwst::support {

// An allocator whose resize() leaves new elements unwritten, for arrays of trivially copyable
// aggregates that are always filled before they are read: arrays sized up front for work that may
// or may not need the room (quadtree refinement's lanes) would touch gigabytes writing it.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}  // NOLINT: rebinding
  template <class U>
  void construct(U*) noexcept {
    static_assert(std::is_trivially_copyable_v<U>);
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// Memory the run has already touched and no longer needs, lent to arrays made later. The kernel
// clears every page on its first touch, which is a large part of a big run (at a million points
// about 3.5 GB of fresh pages, and clear_page the largest single item of the profile); the
// allocator hands big arrays straight from the system and gives them back when they are freed,
// so a dead array's pages are never reused unless they are lent by hand. A lent region is given
// out by bumping a pointer and never taken back (a borrower that frees its block leaves a hole).
// Whoever lends a region promises that its owner neither reads nor writes it again and keeps it
// allocated until every borrower is gone (declare the room and its lenders before the borrowers,
// so that they are destroyed after them). Thread-safe: several threads may lend and borrow.
class SpareRoom {
 public:
  void lend(void* begin, std::size_t bytes) {
    if (begin == nullptr || bytes < kSmallest) return;
    const auto at = reinterpret_cast<std::uintptr_t>(begin);
    const std::lock_guard lock(mutex_);
    regions_.push_back({at, at, at + bytes});
  }
  // A block of `bytes` from the region that fits it most tightly, or null.
  void* borrow(std::size_t bytes, std::size_t alignment) {
    const std::lock_guard lock(mutex_);
    Region* best = nullptr;
    std::uintptr_t best_at = 0;
    for (Region& r : regions_) {
      const std::uintptr_t at = (r.next + alignment - 1) / alignment * alignment;
      if (at > r.end || r.end - at < bytes) continue;
      if (best == nullptr || r.end - at < best->end - best_at) {
        best = &r;
        best_at = at;
      }
    }
    if (best == nullptr) return nullptr;
    best->next = best_at + bytes;
    return reinterpret_cast<void*>(best_at);
  }
  bool lent(const void* p) const {
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    const std::lock_guard lock(mutex_);
    for (const Region& r : regions_) {
      if (at >= r.begin && at < r.end) return true;
    }
    return false;
  }

 private:
  static constexpr std::size_t kSmallest = std::size_t{1} << 20;  // smaller regions are not worth it
  struct Region {
    std::uintptr_t begin, next, end;
  };
  mutable std::mutex mutex_;
  std::vector<Region> regions_;
};

// A vector allocator that borrows from a SpareRoom when a region fits, and from the heap otherwise.
template <class T>
struct SpareAllocator {
  using value_type = T;
  using propagate_on_container_copy_assignment = std::true_type;
  using propagate_on_container_move_assignment = std::true_type;
  using propagate_on_container_swap = std::true_type;
  SpareAllocator() = default;
  explicit SpareAllocator(SpareRoom* spare) noexcept : room(spare) {}
  template <class U>
  SpareAllocator(const SpareAllocator<U>& other) noexcept : room(other.room) {}  // NOLINT: rebinding
  T* allocate(std::size_t n) {
    if (room != nullptr) {
      if (void* p = room->borrow(n * sizeof(T), alignof(T))) return static_cast<T*>(p);
    }
    return std::allocator<T>().allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (room != nullptr && room->lent(p)) return;
    std::allocator<T>().deallocate(p, n);
  }
  template <class U>
  bool operator==(const SpareAllocator<U>& other) const noexcept {
    return room == other.room;
  }
  SpareRoom* room = nullptr;
};
template <class T>
using SpareVector = std::vector<T, SpareAllocator<T>>;

// An array of trivial elements left unwritten (as std::make_unique_for_overwrite), borrowed from a
// SpareRoom when a region fits.
template <class T>
struct SpareDeleter {
  SpareRoom* room = nullptr;
  void operator()(T* p) const noexcept {
    if (room == nullptr || !room->lent(p)) delete[] p;
  }
};
template <class T>
using SpareArray = std::unique_ptr<T[], SpareDeleter<T>>;
template <class T>
SpareArray<T> make_spare_array(SpareRoom& room, std::size_t n) {
  static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>);
  if (void* p = room.borrow(n * sizeof(T), alignof(T))) {
    T* first = static_cast<T*>(p);
    std::uninitialized_default_construct_n(first, n);  // (no writes: the elements are trivial)
    return SpareArray<T>(first, SpareDeleter<T>{&room});
  }
  return SpareArray<T>(new T[n], SpareDeleter<T>{&room});
}

}  // namespace mwst::support
