// Quadtree refinement (QTR): Bern, Eppstein, Gilbert, "Provably good mesh generation" (FOCS 1990,
// JCSS 48(3) 1994) — split, balance, warp, triangulate by a case table — with polygons handled by
// warping corners onto segments and cutting cells along them; the QTR column of Boyacı, Erten,
// Üngör, "Triangulations Loosing Bundles and Weight". The route and the guarantees are described
// in include/mwst/algorithms/quadtree.hpp; the cell triangulations are in quadtree_cells.cpp.
//
// Data layout (flat arrays, indices, no per-cell allocation):
//  - Nodes live in one vector; the four children of a node are consecutive (SW, SE, NW, NE, i.e.
//    Morton order), each node knows its parent. A node is addressed by (level, ix, iy); the integer
//    coordinates map to the plane through the root's corner and side 2^e, so every cell corner is
//    the same double however it is reached. Each node has, per edge direction, a hint: a node
//    covering its same-size neighbour cell when it was created, its sibling or its parent's
//    neighbour (kept once per four siblings); nodes are never removed, so the neighbour is found
//    by descending from the hint, a step or two, without climbing. Other cells are found by climbing to the first ancestor that
//    covers the wanted cell and descending again (Samet), O(1) on average.
//  - Each leaf keeps the list of features (vertices as their ranks in Morton order, whose points
//    the tree copies in that order so that the lists are scanned with few cache misses, and
//    segment indices offset by the number of vertices) meeting its closed extended cell B(C)
//    (vertices: the leaf grown by half its size; segments: grown by its size; see the header).
//    Children filter their parent's list: a vertex sits in at most 9 lists per level and a segment
//    in those of the cells along it (output), so the build costs O(n log n + output).
//  - Vertices of the subdivision (leaf corners and the side midpoints smaller neighbours create)
//    are owned by the leaf for which they are the lower-left corner or a midpoint of the left or
//    bottom side (plus the root's top and right border), so ids come from one pass over the leaves
//    in Morton order with no hashing; every leaf then reads its loop of up to 8 vertices through
//    neighbour look-ups.
//  - Memory: the kernel clears each page on its first touch, and at a million points that is a
//    large part of the run, so dead arrays are reused rather than freed and new ones taken: the
//    tree's nodes live in the storage that becomes the mesh's triangle array, and the triangles
//    are written over them (NodeArray), the grid positions become the mesh's points in place
//    (Builder::run()), and the tree's dead list blocks and hints and the vertex ownership arrays
//    are lent to the arrays made after them (SpareRoom); arrays indexed by grid vertex that few
//    vertices use are bits and maps instead. At a million uniform points the run touches 1.9 GB
//    of fresh pages (2.8 GB before the nodes moved into the triangles).
//  - Cells are triangulated in chunks of leaves in Morton order, their triangles placed by prefix
//    sums in that order, and each cell links its left and bottom sides to the cells across them
//    (found by the look-ups that numbered the vertices) soon after it is written: those come
//    earlier in the order (it is monotone in x and in y), so their triangles are still close in
//    cache; no separate linking pass.
//
// Two threads (large inputs only; the output is byte-identical to one thread, whatever the timing):
//  - build(): each level's split decisions and children are computed in two halves of the
//    frontier, with every new node and list placed by prefix sums in frontier order;
//  - finish(): the first round of checks (every leaf) is a read-only scan in two halves; only the
//    leaves that fail it enter the work list, in the order they would have been processed;
//  - the balance / warp work list runs as two lanes, west and east of a vertical grid line that
//    halves the leaves, each with its own block of the arrays; a lane defers the leaves whose check
//    would reach across the line, and one lane over the whole tree finishes them after the blocks
//    are joined (see finish()); the list's result depends on its order, and this order is the
//    same with one thread.
//    (An order-free variant was measured: with the warp rule's coarse half read as "a node that
//    held the vertex, split or not, keeps its claim on the cells around its corner", the rules are
//    monotone and their least fixed point can be found in parallel rounds — check a set of nodes,
//    apply all the splits asked for, check what they touched. Its rounds cost 1.4–1.5 times the
//    CPU of a last-in-first-out list, which keeps what it touches in cache.)
//  - the per-leaf passes of the mesh (ownership, loops, levels around vertices, vertex ids) run in
//    two halves, and a helper allocates and first touches the mesh's arrays while warp() runs;
//  - the cells' chunks alternate between the two threads, each preparing (dynamic program, exact
//    checks, adjacency inside the cell), writing and linking its own: a chunk takes its places in
//    the arrays when the one before it has taken its own, and is linked once all earlier chunks
//    are written (see triangulate_cells()).
//
// Robustness: all sign decisions are exact (orient2d); constructed points (warped corners moved
// onto segments, crossing points) are rounded once. Every cell triangulation is checked exactly
// (strictly counter-clockwise triangles, diagonals inside). If any check fails — which needs
// features closer than the deepest level can separate, or rounding at the scale of an ulp — the
// result is instead the constrained Delaunay triangulation of the input plus the quadtree's free
// corners (QuadtreeStats::fallback), so every input still gets a valid mesh.
#include "mwst/algorithms/quadtree.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "mwst/error.hpp"

namespace mwst {

namespace {

// Reserves room for n elements up front: the big arrays are written once, and growing them by
// doubling would copy them (and touch their pages twice).
template <class T, class Allocator>
void reserve_room(std::vector<T, Allocator>& v, std::size_t n) {
  v.reserve(n);
}

// An allocator whose resize() leaves new elements unwritten, for arrays of trivially copyable
// aggregates that are always filled before they are read: the tree's arrays are sized up front
// for the two lanes of Tree::finish(), and writing their unused room would touch gigabytes.
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
// allocated until every borrower is gone (the tree outlives the Builder; the Builder's own lenders
// are declared before its borrowers, so they are destroyed after them). Thread-safe: the mesh's
// helper thread borrows while the main thread does.
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

// The four children's feature lists while a node is split: filter_children() makes room for a
// whole parent list in each and writes through pointers, so new room is left unwritten.
using FeatureList = std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>>;

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

 private:
  static constexpr std::uintptr_t kBlock = std::uintptr_t{1} << 21;
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> blocks_;
  std::atomic<std::size_t> next_{0};
};

using Clock = std::chrono::steady_clock;
// Set bits of a byte (std::popcount compiles to a library call without -mpopcnt).
constexpr std::uint32_t bits_in_byte(unsigned x) {
  x = x - ((x >> 1) & 0x55u);
  x = (x & 0x33u) + ((x >> 2) & 0x33u);
  return (x + (x >> 4)) & 0x0Fu;
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Runs body(begin, end) over [0, count) in two halves on two threads when count is large (the
// halves write disjoint ranges). An exception of the first half wins, as it would in one pass.
template <class Body>
void in_two_halves(std::size_t count, std::size_t threshold, Body&& body) {
  if (count < threshold || count < 2) {
    body(std::size_t{0}, count);
    return;
  }
  const std::size_t half = count / 2;
  std::exception_ptr second_error;
  std::exception_ptr first_error;
  {
    std::jthread worker([&] {
      try {
        body(half, count);
      } catch (...) {
        second_error = std::current_exception();
      }
    });
    try {
      body(std::size_t{0}, half);
    } catch (...) {
      first_error = std::current_exception();
    }
  }
  if (first_error) std::rethrow_exception(first_error);
  if (second_error) std::rethrow_exception(second_error);
}

// The size from which a pass splits over two threads: `large` by default, never with
// QuadtreeOptions::threads = 1, always with 2.
std::size_t threads_from(const QuadtreeOptions& options, std::size_t large) {
  if (options.threads == 1) return std::numeric_limits<std::size_t>::max();
  return options.threads == 2 ? 0 : large;
}

// The quadtree route could not finish (see the file comment); the caller builds the fallback.
struct RouteFailure {
  std::string reason;
  bool corners_usable = true;  // the fallback may add the quadtree's free corners
};

// Points the route puts on segments (crossings, snapped corners) are rounded, up to half an ulp off
// the segment's line; the domain's boundary moves with them, by at most the sum of each subsegment's
// length times the larger offset of its ends. That must stay below this fraction of the domain's
// area — it does by far unless the domain is a sliver thinner than a few ulps, where the rounding
// would decide the area and, for an independent check, which side of a segment a point is on.
constexpr double kBoundaryRoundingShare = 1e-10;

// ---- the clean input ------------------------------------------------------------------------------

struct FeatureSegment {
  VertexId a = 0, b = 0;
  std::int32_t marker = 0;
  bool hull_only = false;  // a convex hull edge that is not an input segment (domain boundary only)
};

struct CleanInput {
  Mesh vertices_only;                    // points, kinds, markers, duplicates; no triangles
  std::vector<VertexId> vertices;        // feature vertices (every vertex that is not a duplicate)
  std::vector<FeatureSegment> segments;  // subsegments of the clean graph, then hull edges
  double domain_area = 0.0;              // of the input's domain (in floating point)
  std::vector<Point> hole_seeds;         // where to carve the holes (see clean_graph())
};

// The centroid of finite triangle t of m, if it lies strictly inside t (exact orient2d; the
// rounded centroid of a sliver can fall on or beyond an edge): a point of t well clear of its
// edges, for a hole seed.
std::optional<Point> inner_centroid(const Mesh& m, TriangleId t) {
  const Triangle& T = m.triangles[t];
  const Point &a = m.points[T.v[0]], &b = m.points[T.v[1]], &c = m.points[T.v[2]];
  const Point g{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
  if (orient2d(a, b, g) > 0 && orient2d(b, c, g) > 0 && orient2d(c, a, g) > 0) return g;
  return std::nullopt;
}

// A PSLG with segments: its CDT resolves duplicates, vertices on segments and crossings; the
// subsegments of the CDT are the clean segments.
CleanInput clean_graph(const Pslg& pslg, const QuadtreeOptions& options, QuadtreeStats& stats) {
  ConstrainOptions constrain;
  constrain.strict = options.strict;
  constrain.convex_hull = options.convex_hull;
  Mesh cdt = constrained_delaunay(pslg, constrain, &stats.input);
  CleanInput in;
  in.domain_area = cdt.domain_area();
  in.vertices_only.points = cdt.points;
  in.vertices_only.vertex_kind = cdt.vertex_kind;
  in.vertices_only.vertex_marker = cdt.vertex_marker;
  in.vertices_only.duplicates = cdt.duplicates;
  in.vertices_only.input_vertex_count = cdt.input_vertex_count;
  for (VertexId v = 0; v < cdt.points.size(); ++v) {
    if (cdt.vertex_kind[v] != VertexKind::kDuplicate) in.vertices.push_back(v);
  }
  std::vector<std::pair<std::uint64_t, std::int32_t>> seen;
  std::vector<std::pair<VertexId, VertexId>> hull;
  for (TriangleId t = 0; t < cdt.triangles.size(); ++t) {
    if (cdt.is_dead(t)) continue;
    if (cdt.is_ghost(t)) {
      const Triangle& g = cdt.triangles[t];
      unsigned k = 0;
      while (g.v[k] != kInfinite) ++k;
      hull.emplace_back(g.v[next3(k)], g.v[prev3(k)]);
      continue;
    }
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (!cdt.is_segment(h)) continue;
      const VertexId u = cdt.org(h), w = cdt.dest(h);
      const std::uint64_t key = (std::uint64_t{std::min(u, w)} << 32) | std::max(u, w);
      seen.emplace_back(key, cdt.marker(h));
    }
  }
  // The holes are carved from the faces the CDT carved them from. A seed is a point of a face of
  // the segments' arrangement, but the clean segments are pieces between rounded crossing points,
  // and a seed on (or within rounding of) an input segment's line can lie on a piece in one mesh
  // and beside it in another: a seed exactly on such a line was beside the CDT's piece, and so
  // carved a face there, while the quadtree put a corner exactly on the line at the seed, which
  // made its carve ignore it (fuzz input; the domains then differed). So each seed the CDT
  // carved from is replaced by the centroid of its CDT triangle, a point well inside the same
  // face; the seeds the CDT ignored (on a segment or vertex, outside the hull, out of range) are
  // dropped — the CDT has warned about them.
  for (const Point& p : pslg.holes) {
    if (!in_supported_range(p)) continue;
    const Location loc = cdt.locate(p);
    if (loc.kind == Location::Kind::kOnVertex ||
        (loc.kind == Location::Kind::kOnEdge && cdt.is_segment(loc.handle))) {
      continue;
    }
    TriangleId t = loc.handle >> 2;
    if (cdt.is_ghost(t)) {
      if (loc.kind != Location::Kind::kOnEdge || cdt.is_ghost(cdt.sym(loc.handle) >> 2)) continue;
      t = cdt.sym(loc.handle) >> 2;  // on a hull edge: the triangle inside (as carve() takes it)
    }
    in.hole_seeds.push_back(inner_centroid(cdt, t).value_or(p));
  }
  std::sort(seen.begin(), seen.end());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (i > 0 && seen[i].first == seen[i - 1].first) continue;
    in.segments.push_back({static_cast<VertexId>(seen[i].first >> 32),
                           static_cast<VertexId>(seen[i].first & 0xFFFFFFFFu), seen[i].second, false});
  }
  // The domain is the convex hull when asked or when no segment survived (all of zero length).
  if (options.convex_hull || in.segments.empty()) {
    for (const auto& [a, b] : hull) {
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      const auto it = std::lower_bound(seen.begin(), seen.end(), std::make_pair(key, std::int32_t{0}),
                                       [](const auto& x, const auto& y) { return x.first < y.first; });
      if (it != seen.end() && it->first == key) continue;
      in.segments.push_back({a, b, 1, true});
    }
  }
  return in;
}

// A point set: duplicates by sorting, the convex hull by Andrew's monotone chain (exact), and the
// input points lying on hull edges inserted into them (the hull edges are the domain boundary, and
// a feature segment must not contain a vertex). O(n log n); the Delaunay triangulation of the CDT
// route would cost more than the whole quadtree for a million points. The refusals match delaunay().
CleanInput clean_point_set(const Pslg& pslg, const QuadtreeOptions& options) {
  const std::size_t n = pslg.points.size();
  if (n >= std::numeric_limits<std::uint32_t>::max() / 4) {
    throw InputError(pslg.source, 0, "too many points (" + std::to_string(n) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!in_supported_range(pslg.points[i])) {
      throw InputError(pslg.source, 0,
                       "point " + std::to_string(i + static_cast<std::size_t>(pslg.first_index)) +
                           " has a coordinate outside the supported range (0 or magnitude in "
                           "[1e-50, 1e50])");
    }
  }
  if (n < 3) throw InputError(pslg.source, 0, "fewer than three points (" + std::to_string(n) + ")");
  const std::vector<Point>& p = pslg.points;
  // Sorted by (x, y, index): the keys are sorted with their coordinates copied beside them (an
  // index sort reading p[a] in its comparisons missed the cache twice per comparison).
  struct Keyed {
    double x, y;
    VertexId id;
  };
  std::vector<Keyed> keyed(n);
  for (std::size_t i = 0; i < n; ++i) keyed[i] = {p[i].x, p[i].y, static_cast<VertexId>(i)};
  const auto before = [](const Keyed& a, const Keyed& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.id < b.id;
  };
  // The two halves are sorted on two threads (large inputs) and merged: the order is total, so the
  // result is the same as one sort.
  const std::size_t half = n / 2;
  in_two_halves(2, n >= threads_from(options, 65536) ? 0 : std::numeric_limits<std::size_t>::max(),
                [&](std::size_t begin, std::size_t end) {
                  for (std::size_t part = begin; part < end; ++part) {
                    std::sort(keyed.begin() + static_cast<std::ptrdiff_t>(part == 0 ? 0 : half),
                              part == 0 ? keyed.begin() + static_cast<std::ptrdiff_t>(half) : keyed.end(), before);
                  }
                });
  std::inplace_merge(keyed.begin(), keyed.begin() + static_cast<std::ptrdiff_t>(half), keyed.end(), before);
  std::vector<VertexId> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = keyed[i].id;
  CleanInput in;
  Mesh& m = in.vertices_only;
  m.points = p;
  m.vertex_kind.assign(n, VertexKind::kInput);
  m.vertex_marker = pslg.point_markers.size() == n ? pslg.point_markers : std::vector<std::int32_t>(n, 0);
  m.input_vertex_count = static_cast<std::uint32_t>(n);
  std::vector<VertexId> unique;  // sorted by (x, y)
  std::vector<Point> unique_point;  // their points, in the same order (read in sequence below)
  unique.reserve(n);
  unique_point.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const VertexId v = order[i];
    const Point q{keyed[i].x, keyed[i].y};
    if (!unique.empty() && unique_point.back() == q) {
      m.vertex_kind[v] = VertexKind::kDuplicate;
      m.duplicates.emplace_back(v, unique.back());
      continue;
    }
    unique.push_back(v);
    unique_point.push_back(q);
  }
  std::vector<Keyed>().swap(keyed);
  std::sort(m.duplicates.begin(), m.duplicates.end());
  if (unique.size() == 1) throw InputError(pslg.source, 0, "fewer than three distinct points (all points coincide)");
  if (unique.size() == 2) throw InputError(pslg.source, 0, "fewer than three distinct points");
  // Strict hull (collinear points popped): lower chain left to right, upper chain right to left.
  auto chain = [&](bool lower) {
    std::vector<VertexId> h;
    for (std::size_t k = 0; k < unique.size(); ++k) {
      const std::size_t r = lower ? k : unique.size() - 1 - k;
      const VertexId v = unique[r];
      while (h.size() >= 2 && orient2d(p[h[h.size() - 2]], p[h.back()], unique_point[r]) <= 0) h.pop_back();
      h.push_back(v);
    }
    return h;
  };
  const std::vector<VertexId> lower = chain(true), upper = chain(false);
  if (lower.size() + upper.size() < 5) throw InputError(pslg.source, 0, "all points are collinear");
  std::vector<VertexId> hull(lower.begin(), lower.end() - 1);
  hull.insert(hull.end(), upper.begin(), upper.end() - 1);
  for (std::size_t e = 1; e + 1 < hull.size(); ++e) {  // (a fan from the first hull vertex)
    in.domain_area += signed_area(p[hull[0]], p[hull[e]], p[hull[e + 1]]);
  }
  // Points on hull edges: an edge (a, b) of the counter-clockwise hull is found for a point by
  // binary search on the x-monotone chains; vertical edges only occur at the two extreme x.
  std::vector<std::vector<VertexId>> on_edge(hull.size());
  std::vector<char> is_hull(n, 0);
  for (VertexId v : hull) is_hull[v] = 1;
  const std::size_t lower_edges = lower.size() - 1;
  // The vertical hull edges: at most two, at the smallest and the largest x (found once: a scan of
  // the hull per point would be quadratic when many points lie on it).
  std::vector<std::size_t> vertical;
  for (std::size_t e = 0; e < hull.size(); ++e) {
    if (p[hull[e]].x == p[hull[(e + 1) % hull.size()]].x) vertical.push_back(e);
  }
  auto between = [&](const Point& a, const Point& b, const Point& x) {
    // x is collinear with a and b: strictly between them along the dominant axis (exact).
    if (a.x != b.x) return (a.x < x.x && x.x < b.x) || (b.x < x.x && x.x < a.x);
    return (a.y < x.y && x.y < b.y) || (b.y < x.y && x.y < a.y);
  };
  // The edge candidates move monotonically: the points are visited in increasing x, the lower
  // chain's right ends have increasing x and the upper chain's decreasing x.
  const std::size_t h = hull.size();
  const auto right_x = [&](std::size_t e) { return p[hull[e + 1 == h ? 0 : e + 1]].x; };
  std::size_t lower_at = 0;  // first lower-chain edge whose right end has x ≥ x.x
  std::size_t upper_at = h;  // first upper-chain edge whose right end has x ≤ x.x
  for (std::size_t r = 0; r < unique.size(); ++r) {
    const VertexId v = unique[r];
    const Point& x = unique_point[r];
    while (lower_at < lower_edges && right_x(lower_at) < x.x) ++lower_at;
    while (upper_at > lower_edges && right_x(upper_at - 1) <= x.x) --upper_at;
    if (is_hull[v]) continue;
    // Candidate edges: the lower-chain and upper-chain edges spanning x.x, and the vertical edges
    // at the extreme x.
    auto test = [&](std::size_t e) {
      const Point& a = p[hull[e]];
      const Point& b = p[hull[e + 1 == h ? 0 : e + 1]];
      if (orient2d(a, b, x) == 0 && between(a, b, x)) {
        on_edge[e].push_back(v);
        return true;
      }
      return false;
    };
    if (lower_at < lower_edges && test(lower_at)) continue;
    if (lower_at + 1 < lower_edges && test(lower_at + 1)) continue;
    if (upper_at < h && test(upper_at)) continue;
    if (upper_at + 1 < h && test(upper_at + 1)) continue;
    // Vertical edges at the extreme x (both ends share x).
    for (const std::size_t e : vertical) {
      if (p[hull[e]].x == x.x && test(e)) break;
    }
  }
  for (std::size_t e = 0; e < hull.size(); ++e) {
    const Point a = p[hull[e]];
    auto& list = on_edge[e];
    std::sort(list.begin(), list.end(), [&](VertexId u, VertexId w) {
      return std::fabs(p[u].x - a.x) + std::fabs(p[u].y - a.y) < std::fabs(p[w].x - a.x) + std::fabs(p[w].y - a.y);
    });
    VertexId from = hull[e];
    for (VertexId v : list) {
      in.segments.push_back({from, v, 1, true});
      from = v;
    }
    in.segments.push_back({from, hull[(e + 1) % hull.size()], 1, true});
  }
  // The distinct vertices in index order (every index but the duplicates; no sort needed).
  in.vertices.clear();
  in.vertices.reserve(unique.size());
  for (VertexId v = 0; v < n; ++v) {
    if (m.vertex_kind[v] != VertexKind::kDuplicate) in.vertices.push_back(v);
  }
  return in;
}

// ---- the quadtree ---------------------------------------------------------------------------------

constexpr std::uint8_t kFresh = 1;  // created after the first build: still to be checked
// Node::state bit (kBalanced << d): the hint in direction d is at the parent's level or there is
// no cell that way, so no edge neighbour that way is ever more than one level coarser (check()
// then skips reading the hint's node, a cache miss per leaf).
constexpr std::uint8_t kBalanced = 2;
// Node::state bit of a leaf whose feature list holds a segment (set where the list is written, so
// that the mesh passes find these leaves without reading every list).
constexpr std::uint8_t kHasSegment = 32;

// Node::child of a leaf has this bit set (kNone has it too): the Builder numbers the leaves there
// (Tree::number_leaves()), so a node's leaf ordinal is read from the node itself, with no array
// indexed by node.
constexpr std::uint32_t kLeafBit = 0x80000000u;

struct Node {
  std::int64_t ix = 0, iy = 0;         // cell index at its level
  std::uint32_t parent = kNone;
  std::uint32_t child = kNone;         // first of four consecutive children; for a leaf kNone, and
                                       // from Builder::number_vertices() on kLeafBit | its ordinal
  std::uint32_t feat_begin = 0;        // leaves: features meeting the closed B(C) in Tree::features
  std::uint32_t feat_count = 0;
  std::uint32_t vertex = kNone;        // leaves: the input vertex in the half-open cell, if any, as
                                       // its Morton rank (Tree::vertex_id, Tree::vertex_point)
  std::uint8_t level = 0;
  std::uint8_t state = 0;
};

struct Box {
  double x1, y1, x2, y2;
};

// The tree's nodes, kept in the address range that becomes the mesh's triangle array. The nodes
// are the largest array of the run (40 bytes per node, 1.3 nodes per leaf) and are dead once the
// Builder has read what it needs from them, just before the cells' triangles (2.4 per leaf, 24
// bytes each) are written: so they live in the capacity of a std::vector<Triangle> that the
// Builder hands to the mesh (Tree::give_node_storage()), and the triangles are written over pages
// the nodes already touched (the kernel clears each page of fresh memory on its first touch,
// which at a million points is a large part of the run). New elements of resize() are left
// unwritten, as with UninitializedAllocator: the arrays are sized up front for finish()'s lanes.
class NodeArray {
 public:
  static_assert(std::is_trivially_copyable_v<Node> && alignof(Node) <= alignof(std::max_align_t));
  NodeArray() = default;
  NodeArray(const NodeArray&) = delete;  // (a copy of the empty storage would alias the nodes)
  NodeArray& operator=(const NodeArray&) = delete;
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }
  Node* data() { return data_; }
  const Node* data() const { return data_; }
  Node& operator[](std::size_t i) { return data_[i]; }
  const Node& operator[](std::size_t i) const { return data_[i]; }
  void clear() { size_ = 0; }
  void reserve(std::size_t n) {
    if (n <= capacity_) return;
    std::vector<Triangle> grown;
    grown.reserve((n * sizeof(Node) + sizeof(Triangle) - 1) / sizeof(Triangle));
    // The storage is raw room for nodes (the vector holds no Triangle until the mesh takes it).
    Node* const moved = reinterpret_cast<Node*>(grown.data());
    if (size_ > 0) std::memcpy(static_cast<void*>(moved), data_, size_ * sizeof(Node));
    storage_ = std::move(grown);
    data_ = moved;
    capacity_ = storage_.capacity() * sizeof(Triangle) / sizeof(Node);
  }
  void resize(std::size_t n) {
    if (n > capacity_) reserve(std::max(n, capacity_ / 2 * 3));
    size_ = n;
  }
  void push_back(const Node& node) {
    if (size_ == capacity_) reserve(std::max<std::size_t>(64, capacity_ * 2));
    std::memcpy(static_cast<void*>(data_ + size_), &node, sizeof(Node));
    ++size_;
  }
  // The storage, as an empty triangle array with its capacity: the nodes stay readable where they
  // are until that array is written (or freed), and the tree no longer owns them.
  std::vector<Triangle> give_storage() { return std::move(storage_); }

 private:
  std::vector<Triangle> storage_;  // size 0: only its capacity is used
  Node* data_ = nullptr;
  std::size_t size_ = 0, capacity_ = 0;
};
void reserve_room(NodeArray& v, std::size_t n) { v.reserve(n); }

class Tree {
 public:
  // build(): a frontier cell and its list of features in the level's pool.
  struct Item {
    std::uint32_t node, begin, count;
  };
  using ItemList = std::vector<Item, UninitializedAllocator<Item>>;
  // build(): scratch of one half of a level's frontier: a split's four lists, and (second half
  // only) its children's lists, appended to the first half's after both.
  struct HalfScratch {
    std::vector<std::uint32_t> pool;
    std::array<FeatureList, 4> lists;
  };

  Tree(const CleanInput& in, const QuadtreeOptions& options, QuadtreeStats& stats)
      : in_(in), pts_(in.vertices_only.points), nv_(static_cast<std::uint32_t>(pts_.size())),
        max_level_(std::min(options.max_depth, 52u)), stats_(stats),
        max_leaves_(leaf_limit(options, in.vertices.size() + in.segments.size())),
        threaded_items_(threads_from(options, 8192)), threaded_nodes_(threads_from(options, 65536)) {
    // Root: a power-of-two square at least twice the bounding box, its corner aligned to 1/16 of
    // its side, so every vertex lies at least 3/16 of the root inside it: a warp target or a corner
    // moved onto a segment is never on the root's border (which must stay the convex hull).
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin;
    double xmax = -xmin, ymax = -xmin;
    for (VertexId v : in.vertices) {
      xmin = std::min(xmin, pts_[v].x);
      xmax = std::max(xmax, pts_[v].x);
      ymin = std::min(ymin, pts_[v].y);
      ymax = std::max(ymax, pts_[v].y);
    }
    const double span = std::max(xmax - xmin, ymax - ymin);
    int e = 0;
    std::frexp(span, &e);  // span < 2^e
    e += 1;
    for (;;) {
      const double side = std::ldexp(1.0, e), grid = std::ldexp(1.0, e - 4);
      x0_ = std::floor((0.5 * (xmin + xmax) - 0.5 * side) / grid) * grid;
      y0_ = std::floor((0.5 * (ymin + ymax) - 0.5 * side) / grid) * grid;
      const double margin = std::ldexp(1.0, e - 3);
      if (xmin - x0_ > margin && x0_ + side - xmax > margin && ymin - y0_ > margin &&
          y0_ + side - ymax > margin) {
        break;
      }
      ++e;
    }
    exponent_ = e;
    for (unsigned l = 0; l < step_.size(); ++l) step_[l] = std::ldexp(1.0, e - static_cast<int>(l));
    // Vertex features are ranks in Morton order of the root's 2^16 × 2^16 grid, with their points
    // copied in that order: the feature lists are scanned once per level, and input order would
    // make every point a cache miss.
    const double scale = 65536.0 / step_[0];
    auto cell = [&](double v, double origin) {
      return static_cast<std::uint64_t>(std::clamp(std::floor((v - origin) * scale), 0.0, 65535.0));
    };
    auto spread = [](std::uint64_t v) {
      v = (v | (v << 8)) & 0x00FF00FFu;
      v = (v | (v << 4)) & 0x0F0F0F0Fu;
      v = (v | (v << 2)) & 0x33333333u;
      return (v | (v << 1)) & 0x55555555u;
    };
    // Sorted by (Morton key, vertex): the keys have 32 bits and in.vertices is in increasing
    // order, so a stable two-pass radix sort on 16-bit digits gives exactly that order.
    using Keyed = std::pair<std::uint64_t, VertexId>;
    std::vector<Keyed> order;
    order.reserve(in.vertices.size());
    for (VertexId v : in.vertices) {
      order.emplace_back((spread(cell(pts_[v].y, y0_)) << 1) | spread(cell(pts_[v].x, x0_)), v);
    }
    {
      std::vector<Keyed> scratch(order.size());
      std::vector<std::uint32_t> bucket(65537);
      for (const unsigned shift : {0u, 16u}) {
        std::fill(bucket.begin(), bucket.end(), 0u);
        for (const Keyed& o : order) ++bucket[((o.first >> shift) & 0xFFFFu) + 1];
        for (std::size_t b = 1; b < bucket.size(); ++b) bucket[b] += bucket[b - 1];
        for (const Keyed& o : order) scratch[bucket[(o.first >> shift) & 0xFFFFu]++] = o;
        order.swap(scratch);
      }
    }
    rank_id_.resize(order.size());
    rank_point_.resize(order.size());
    for (std::size_t r = 0; r < order.size(); ++r) {
      rank_id_[r] = order[r].second;
      rank_point_[r] = pts_[order[r].second];
    }
  }

  // Plane coordinates of grid line i at a level (i may lie one or two cells outside the root).
  // (The products are exact: an integer below 2^53 times a power of two.)
  double X(std::int64_t i, unsigned level) const { return x0_ + static_cast<double>(i) * step_[level]; }
  double Y(std::int64_t i, unsigned level) const { return y0_ + static_cast<double>(i) * step_[level]; }
  double cell_size(unsigned level) const { return step_[level]; }
  Box box(const Node& n) const {
    return {X(n.ix, n.level), Y(n.iy, n.level), X(n.ix + 1, n.level),
            Y(n.iy + 1, n.level)};
  }

  bool is_vertex(std::uint32_t f) const { return f < nv_; }
  const FeatureSegment& segment(std::uint32_t f) const { return in_.segments[f - nv_]; }
  std::uint32_t vertex_count() const { return nv_; }

  // Does feature f meet the closed box? Exact (a segment and a box are convex: separating axes
  // x, y and the segment's normal, the last decided by orient2d at the box corners).
  bool meets(std::uint32_t f, const Box& b) const {
    if (is_vertex(f)) {
      const Point& q = rank_point_[f];
      return b.x1 <= q.x && q.x <= b.x2 && b.y1 <= q.y && q.y <= b.y2;
    }
    const FeatureSegment& s = segment(f);
    const Point& p = pts_[s.a];
    const Point& q = pts_[s.b];
    if (std::max(p.x, q.x) < b.x1 || std::min(p.x, q.x) > b.x2 || std::max(p.y, q.y) < b.y1 ||
        std::min(p.y, q.y) > b.y2) {
      return false;
    }
    const int o1 = orient2d(p, q, {b.x1, b.y1}), o2 = orient2d(p, q, {b.x2, b.y1});
    const int o3 = orient2d(p, q, {b.x2, b.y2}), o4 = orient2d(p, q, {b.x1, b.y2});
    return !((o1 > 0 && o2 > 0 && o3 > 0 && o4 > 0) || (o1 < 0 && o2 < 0 && o3 < 0 && o4 < 0));
  }

  // BEG's rule: does the feature list of an extended cell meet the input simply? At most one
  // vertex; with one, only segments incident to it; with none, at most one segment.
  bool simple(const std::uint32_t* list, std::size_t count) const {
    std::uint32_t vertex = kNone;
    for (std::size_t i = 0; i < count; ++i) {
      if (!is_vertex(list[i])) continue;
      if (vertex != kNone) return false;
      vertex = rank_id_[list[i]];
    }
    // Without a vertex, several segments are still "one vertex and its segments" if they share an
    // endpoint (lying outside B(C)): they are incident features and do not lower the local
    // feature size; splitting them apart would only refine towards their common vertex forever.
    std::uint32_t common_a = kNone, common_b = kNone;
    for (std::size_t i = 0; i < count; ++i) {
      if (is_vertex(list[i])) continue;
      const FeatureSegment& s = segment(list[i]);
      if (vertex != kNone) {
        if (s.a != vertex && s.b != vertex) return false;
        continue;
      }
      if (common_a == kNone && common_b == kNone) {
        common_a = s.a;
        common_b = s.b;
        continue;
      }
      if (common_a != s.a && common_a != s.b) common_a = kNone;
      if (common_b != s.a && common_b != s.b) common_b = kNone;
      if (common_a == kNone && common_b == kNone) return false;
    }
    return true;
  }

  // Does a feature list hold a segment?
  bool has_segment(const std::uint32_t* list, std::size_t count) const {
    for (std::size_t i = 0; i < count; ++i) {
      if (!is_vertex(list[i])) return true;
    }
    return false;
  }

  bool meets_any(const Node& n, const std::uint32_t* list, std::size_t count) const {
    const Box b = box(n);
    for (std::size_t i = 0; i < count; ++i) {
      if (meets(list[i], b)) return true;
    }
    return false;
  }

  // Does the leaf have to be split by the feature rule? (Levels 0 and 1 always split.)
  bool feature_split(const Node& n, const std::uint32_t* list, std::size_t count) const {
    if (n.level < 2) return true;
    if (simple(list, count)) return false;
    return meets_any(n, list, count);
  }

  // Appends to `out` the features of the parent's list that meet each child's extended cell.
  // (Written through raw pointers into room made first: this runs for every list entry of every
  // level, and push_back's growth check was a call per entry.)
  void filter_children(const Node& parent, const std::uint32_t* list, std::size_t count,
                       std::array<FeatureList, 4>& out) const {
    // Vertices: each child grown by half its size (one grid step of level parent + 2), columns
    // 4ix − 1 … 4ix + 3 and 4ix + 1 … 4ix + 5, the same for rows.
    const unsigned h = parent.level + 2u;
    const std::int64_t qx = parent.ix * 4, qy = parent.iy * 4;
    const double xa1 = X(qx - 1, h), xa2 = X(qx + 3, h), xb1 = X(qx + 1, h), xb2 = X(qx + 5, h);
    const double ya1 = Y(qy - 1, h), ya2 = Y(qy + 3, h), yb1 = Y(qy + 1, h), yb2 = Y(qy + 5, h);
    // Segments: each child grown by its size, columns cx − 1 … cx + 2 and cx … cx + 3.
    const unsigned l = parent.level + 1u;
    const std::int64_t cx = parent.ix * 2, cy = parent.iy * 2;
    const double sa1 = X(cx - 1, l), sa2 = X(cx + 2, l), sb1 = X(cx, l), sb2 = X(cx + 3, l);
    const double ta1 = Y(cy - 1, l), ta2 = Y(cy + 2, l), tb1 = Y(cy, l), tb2 = Y(cy + 3, l);
    const Box boxes[4] = {{sa1, ta1, sa2, ta2}, {sb1, ta1, sb2, ta2}, {sa1, tb1, sa2, tb2}, {sb1, tb1, sb2, tb2}};
    std::size_t used[4];
    std::uint32_t* w[4];
    for (unsigned k = 0; k < 4; ++k) {
      used[k] = out[k].size();
      out[k].resize(used[k] + count);
      w[k] = out[k].data();
    }
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t f = list[i];
      if (is_vertex(f)) {
        const Point& q = rank_point_[f];
        const bool col0 = xa1 <= q.x && q.x <= xa2, col1 = xb1 <= q.x && q.x <= xb2;
        const bool row0 = ya1 <= q.y && q.y <= ya2, row1 = yb1 <= q.y && q.y <= yb2;
        if (col0 && row0) w[0][used[0]++] = f;
        if (col1 && row0) w[1][used[1]++] = f;
        if (col0 && row1) w[2][used[2]++] = f;
        if (col1 && row1) w[3][used[3]++] = f;
      } else {
        for (unsigned k = 0; k < 4; ++k) {
          if (meets(f, boxes[k])) w[k][used[k]++] = f;
        }
      }
    }
    for (unsigned k = 0; k < 4; ++k) out[k].resize(used[k]);
  }

  // First build: breadth first, splitting by the feature rule. Each level runs in three steps:
  // decide which frontier cells split, give every new node and leaf list its place by prefix
  // sums in frontier order, then fill them in; the first and last steps run in two halves of the
  // frontier on two threads (they only read the levels above and write their own places), and the
  // result is the same arrays, index for index, as one pass in frontier order.
  void build() {
    constexpr std::size_t kLookAhead = 8;
    nodes.clear();
    // Room for what a uniform point set needs, so that the big arrays are not copied while they
    // grow: finish() sizes them to three times what this build makes (about 7 nodes and 7 list
    // entries per point) for its lanes' blocks. Unused room is never touched. The nodes get a
    // little more, 1200 bytes per feature: their storage becomes the mesh's triangle array, which
    // the cells want with room for 4 triangles (96 bytes) per leaf, 11.6 leaves per point.
    const std::size_t feature_count = rank_id_.size() + in_.segments.size();
    reserve_room(nodes, 30 * feature_count + 256);
    reserve_room(outer_hint_, 6 * feature_count + 64);
    reserve_room(features, 30 * feature_count + 64);
    nodes.push_back(Node{});
    outer_hint_.clear();
    std::vector<std::uint32_t> pool, next_pool;
    // A level's lists hold each vertex up to four times (its cell and the neighbours whose grown
    // cells reach it) and each segment once per cell along it.
    reserve_room(pool, 4 * feature_count + 64);
    reserve_room(next_pool, 4 * feature_count + 64);
    for (std::uint32_t r = 0; r < rank_id_.size(); ++r) pool.push_back(r);
    for (std::uint32_t s = 0; s < in_.segments.size(); ++s) pool.push_back(nv_ + s);
    ItemList frontier{{0, 0, static_cast<std::uint32_t>(pool.size())}}, next;
    reserve_room(frontier, 4 * feature_count + 64);
    reserve_room(next, 4 * feature_count + 64);
    std::vector<std::uint32_t> place;  // per frontier item: first child, or its list's place in features
    std::vector<std::uint8_t> splits;
    std::array<HalfScratch, 2> half;
    // (Room for the largest level up front: grown by doubling, every new block is fresh pages and
    // the old one is copied and freed; unused room is never touched.)
    reserve_room(half[1].pool, 8 * feature_count + 64);
    while (!frontier.empty()) {
      const std::size_t count = frontier.size();
      splits.resize(count);
      place.resize(count);
      // 1. Which cells split.
      in_two_halves(count, threaded_items_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const Item& item = frontier[i];
          const Node& n = nodes[item.node];
          splits[i] = n.level < max_level_ && feature_split(n, pool.data() + item.begin, item.count) ? 1 : 0;
        }
      });
      // 2. Places, in frontier order.
      auto next_node = static_cast<std::uint32_t>(nodes.size());
      std::size_t next_feature = features.size();
      for (std::size_t i = 0; i < count; ++i) {
        if (splits[i]) {
          if (nodes[frontier[i].node].level >= 2) ++stats_.splits_feature;
          place[i] = next_node;
          next_node += 4;
        } else {
          place[i] = static_cast<std::uint32_t>(next_feature);
          next_feature += frontier[i].count;
        }
      }
      if (next_feature > std::numeric_limits<std::uint32_t>::max()) throw RouteFailure{"too many feature list entries"};
      refuse_beyond_leaf_limit(next_node);
      // The next frontier is the new nodes, in order (four per split, placed in frontier order):
      // each child's item goes to its node's place, and its list to next_pool, where the first
      // half writes directly and the second half's lists follow after both.
      const auto node_base = static_cast<std::uint32_t>(nodes.size());
      next.resize(next_node - node_base);
      next_pool.clear();
      half[1].pool.clear();
      std::size_t second_half_first_child = next.size();
      nodes.resize(next_node);
      outer_hint_.resize(groups(next_node));
      features.resize(next_feature);
      // 3. Leaves and children.
      in_two_halves(count, threaded_items_, [&](std::size_t begin, std::size_t end) {
        HalfScratch& out = half[begin == 0 ? 0 : 1];
        std::vector<std::uint32_t>& lists_out = begin == 0 ? next_pool : out.pool;
        bool first_split = true;
        for (std::size_t i = begin; i < end; ++i) {
          // (A split reads the nodes its hints name, scattered over the level above: they are
          // fetched a few items ahead.)
          if (i + kLookAhead < end && splits[i + kLookAhead]) {
            const std::uint32_t ahead = frontier[i + kLookAhead].node;
            for (unsigned d = 0; d < 4; ++d) {
              const std::uint32_t h = hint(ahead, d);
              if (h != kNone) __builtin_prefetch(&nodes[h]);
            }
          }
          const Item& item = frontier[i];
          const std::uint32_t* list = pool.data() + item.begin;
          if (!splits[i]) {
            Node& leaf = nodes[item.node];
            leaf.feat_begin = place[i];
            leaf.feat_count = item.count;
            std::copy(list, list + item.count, features.begin() + place[i]);
            leaf.vertex = vertex_in(leaf);
            if (has_segment(list, item.count)) leaf.state = static_cast<std::uint8_t>(leaf.state | kHasSegment);
            continue;
          }
          const Node n = nodes[item.node];
          for (auto& l : out.lists) l.clear();
          filter_children(n, list, item.count, out.lists);
          const std::uint32_t first = place[i];
          if (begin != 0 && first_split) second_half_first_child = first - node_base;
          first_split = false;
          nodes[item.node].child = first;
          for (unsigned k = 0; k < 4; ++k) {
            Node& c = nodes[first + k];
            c = Node{};
            c.ix = 2 * n.ix + (k & 1);
            c.iy = 2 * n.iy + (k >> 1);
            c.parent = item.node;
            c.level = static_cast<std::uint8_t>(n.level + 1);
            if (lists_out.size() + out.lists[k].size() > std::numeric_limits<std::uint32_t>::max()) {
              throw RouteFailure{"too many feature list entries"};
            }
            next[first + k - node_base] = {first + k, static_cast<std::uint32_t>(lists_out.size()),
                                           static_cast<std::uint32_t>(out.lists[k].size())};
            lists_out.insert(lists_out.end(), out.lists[k].begin(), out.lists[k].end());
          }
          set_child_hints(item.node);
        }
      });
      {
        const std::vector<std::uint32_t>& second = half[1].pool;
        if (next_pool.size() + second.size() > std::numeric_limits<std::uint32_t>::max()) {
          throw RouteFailure{"too many feature list entries"};
        }
        const auto offset = static_cast<std::uint32_t>(next_pool.size());
        for (std::size_t j = second_half_first_child; j < next.size(); ++j) next[j].begin += offset;
        next_pool.insert(next_pool.end(), second.begin(), second.end());
      }
      if (!next.empty()) deepest_ = std::max(deepest_, static_cast<unsigned>(nodes[next.front().node].level));
      frontier.swap(next);
      pool.swap(next_pool);
    }
  }

  // The node covering cell (l, tx, ty): the cell itself if it exists (leaf or not), else the leaf
  // containing it; kNone outside the root. Climbs from `from`, then descends.
  std::uint32_t find(std::uint32_t from, unsigned l, std::int64_t tx, std::int64_t ty) const {
    const std::int64_t side = std::int64_t{1} << l;
    if (tx < 0 || ty < 0 || tx >= side || ty >= side) return kNone;
    std::uint32_t a = from;
    for (;;) {
      const Node& n = nodes[a];
      if (n.level <= l && (tx >> (l - n.level)) == n.ix && (ty >> (l - n.level)) == n.iy) break;
      a = n.parent;
    }
    while (nodes[a].level < l && (nodes[a].child & kLeafBit) == 0) {
      const unsigned d = l - nodes[a].level - 1u;
      a = nodes[a].child + static_cast<std::uint32_t>(((tx >> d) & 1) + 2 * ((ty >> d) & 1));
    }
    return a;
  }

  bool is_leaf(std::uint32_t a) const { return (nodes[a].child & kLeafBit) != 0; }
  // The leaf ordinal of node a (after number_leaves()), kNone for an inner node.
  std::uint32_t leaf_ordinal(std::uint32_t a) const {
    const std::uint32_t c = nodes[a].child;
    return (c & kLeafBit) != 0 ? c & ~kLeafBit : kNone;
  }
  // Writes each leaf's ordinal in Morton order into its child field (kLeafBit | k).
  void number_leaves(const std::vector<std::uint32_t>& leaves, std::size_t threaded) {
    if (nodes.size() >= kLeafBit || leaves.size() >= kLeafBit - 1) throw RouteFailure{"too many nodes"};
    in_two_halves(leaves.size(), threaded, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) nodes[leaves[k]].child = kLeafBit | static_cast<std::uint32_t>(k);
    });
  }

  // Edge directions: 0 east, 1 north, 2 west, 3 south.
  static constexpr int kDirX[4] = {1, 0, -1, 0};
  static constexpr int kDirY[4] = {0, 1, 0, -1};

  // Sibling groups among the first `node_count` nodes (after the root, nodes come in fours).
  static std::size_t groups(std::size_t node_count) { return node_count == 0 ? 0 : (node_count - 1) / 4; }
  // Node a's hint in direction d (see neighbour()): a node covering its same-size neighbour cell
  // when a was made. Across a side inside the parent that is the sibling there (no memory read);
  // across the parent's side, the parent's neighbour that way, kept once for the four siblings
  // (outer_hint_: 4 bytes per node, against 16 for a hint per node and direction).
  std::uint32_t hint(std::uint32_t a, unsigned d) const {
    assert(!hints_lent_ && "a look-up after Builder::build_loops() lent the hints away");
    if (a == 0) return kNone;
    const std::uint32_t k = (a - 1) & 3u;  // position among the siblings: SW, SE, NW, NE
    const std::uint32_t bit = (d & 1u) != 0 ? k >> 1 : k & 1u;  // north/south: row; east/west: column
    const std::uint32_t step = (d & 1u) != 0 ? 2u : 1u;
    if (d < 2 && bit == 0) return a + step;  // east of a west child, north of a south child
    if (d >= 2 && bit == 1) return a - step;
    return outer_hint_[(a - 1) >> 2][d];
  }

  // The node covering the same-size cell next to node a in direction d (what find(a, level,
  // ix + dx, iy + dy) returns), without climbing: each node keeps a hint, a node covering that
  // cell when the hint was set. Nodes are never removed, so a hint stays an ancestor of (or equal
  // to) the answer, and descending from it finds the answer in a step or two.
  std::uint32_t neighbour(std::uint32_t a, unsigned d) const {
    std::uint32_t h = hint(a, d);
    if (h == kNone) return kNone;
    const Node& n = nodes[a];
    const unsigned l = n.level;
    const std::int64_t tx = n.ix + kDirX[d], ty = n.iy + kDirY[d];
    while (nodes[h].level < l && (nodes[h].child & kLeafBit) == 0) {
      const unsigned shift = l - nodes[h].level - 1u;
      h = nodes[h].child + static_cast<std::uint32_t>(((tx >> shift) & 1) + 2 * ((ty >> shift) & 1));
    }
    return h;
  }

  // Passes that look up the neighbours of the leaves in Morton order (whose nodes lie scattered in
  // creation order) fetch ahead in two stages: a leaf's node and hints, then, once those are in
  // cache, the nodes its hints name (where neighbour() starts).
  void prefetch_node(std::uint32_t a) const {
    __builtin_prefetch(&nodes[a]);
    if (a != 0) __builtin_prefetch(&outer_hint_[(a - 1) >> 2]);
  }
  void prefetch_hinted(std::uint32_t a, unsigned d) const {
    const std::uint32_t h = hint(a, d);
    if (h != kNone) __builtin_prefetch(&nodes[h]);
  }

  // What find(a, level, ix + ox, iy + oy) returns for |ox|, |oy| ≤ 1, through the hints: an edge
  // neighbour directly, a diagonal one as the neighbour of a same-size edge neighbour (climbing
  // only when that edge neighbour is a coarser leaf).
  std::uint32_t cell_at(std::uint32_t a, int ox, int oy) const {
    if (ox == 0 && oy == 0) return a;
    if (oy == 0) return neighbour(a, ox > 0 ? 0u : 2u);
    if (ox == 0) return neighbour(a, oy > 0 ? 1u : 3u);
    const std::uint32_t side = neighbour(a, ox > 0 ? 0u : 2u);
    if (side == kNone) return kNone;
    return diagonal(a, side, ox, oy);
  }
  // cell_at(a, ox, oy) for a diagonal (|ox| = |oy| = 1), given side = neighbour(a, east or west as
  // ox says): the same-size neighbour of side, or found from side when side is a coarser leaf.
  std::uint32_t diagonal(std::uint32_t a, std::uint32_t side, int ox, int oy) const {
    const Node& n = nodes[a];
    if (nodes[side].level == n.level) return neighbour(side, oy > 0 ? 1u : 3u);
    return find(side, n.level, n.ix + ox, n.iy + oy);
  }

  // Sets the hints of the four new children of p (p's own hints are set).
  void set_child_hints(std::uint32_t p) {
    if (outer_hint_.size() < groups(nodes.size())) outer_hint_.resize(groups(nodes.size()));
    set_child_hints(p, edge_neighbours(p));
  }
  // neighbour(a, d) for the four directions.
  std::array<std::uint32_t, 4> edge_neighbours(std::uint32_t a) const {
    return {neighbour(a, 0), neighbour(a, 1), neighbour(a, 2), neighbour(a, 3)};
  }
  // The same, given p's edge neighbours (edge_neighbours(p)).
  void set_child_hints(std::uint32_t p, const std::array<std::uint32_t, 4>& outer) {
    const std::uint32_t c = nodes[p].child;
    std::array<bool, 4> outer_fine{};
    const unsigned parent_level = nodes[p].level;
    for (unsigned d = 0; d < 4; ++d) {
      outer_fine[d] = outer[d] == kNone || nodes[outer[d]].level == parent_level;
    }
    outer_hint_[(c - 1) >> 2] = outer;
    for (std::uint32_t k = 0; k < 4; ++k) {
      std::uint8_t state = nodes[c + k].state;
      for (unsigned d = 0; d < 4; ++d) {
        if (outer_fine[d]) state = static_cast<std::uint8_t>(state | (kBalanced << d));
      }
      nodes[c + k].state = state;
    }
  }

  // The input vertex of a leaf's Node::vertex rank, and its point (the Morton-ordered copy: ranks
  // of nearby leaves are close, so the reads stay in cache).
  VertexId vertex_id(std::uint32_t rank) const { return rank_id_[rank]; }
  const Point& vertex_point(std::uint32_t rank) const { return rank_point_[rank]; }

  // The input vertex in the half-open leaf [x1, x2) × [y1, y2), if any, as its rank.
  std::uint32_t vertex_in(const Node& n) const {
    return vertex_in(n, features.data() + n.feat_begin, n.feat_count);
  }
  // The same, from the leaf's list of features.
  std::uint32_t vertex_in(const Node& n, const std::uint32_t* list, std::size_t count) const {
    const Box b = box(n);
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t f = list[i];
      if (!is_vertex(f)) continue;
      const Point& q = rank_point_[f];
      if (b.x1 <= q.x && q.x < b.x2 && b.y1 <= q.y && q.y < b.y2) return f;
    }
    return kNone;
  }

  // Corner of leaf n nearest to q, as 0 BL, 1 BR, 2 TR, 3 TL, with (qx, qy) its offsets.
  void nearest_corner(const Node& n, const Point& q, unsigned& qx, unsigned& qy) const {
    qx = q.x >= X(n.ix * 2 + 1, n.level + 1u) ? 1u : 0u;
    qy = q.y >= Y(n.iy * 2 + 1, n.level + 1u) ? 1u : 0u;
  }

  // finish() works through lanes: a lane is a work list with its own room in the node, hint and
  // feature arrays. The two region lanes hold the leaves west and east of a vertical grid line
  // (chosen so that about as many leaves lie on each side) and run at the same time; a region lane
  // never reads or writes a node that the other may change, so their runs do not depend on each
  // other's timing (see finish()).
  struct Lane {
    int region = -1;  // 0 west, 1 east of the split line; -1 the whole tree (the arrays grow as needed)
    std::vector<std::uint32_t> work;
    std::vector<std::uint32_t> deferred;  // leaves whose check needs the other side (or more room)
    std::array<FeatureList, 4> lists;  // split(): the children's feature lists
    std::uint32_t node_begin = 0, node_next = 0, node_end = 0;  // region lanes: their block of node ids
    std::size_t feature_next = 0, feature_end = 0;     //   and of feature list entries
    bool full = false;                                 // a split found no room: stop the lane
    std::vector<std::uint32_t> split_before;           // split nodes made before the lane's block
    std::size_t splits_feature = 0, splits_balance = 0, splits_warp = 0;
    unsigned deepest = 0;
  };

  // The split line between the lanes: the left side of column lane_column_ of level lane_level_.
  // In cells of the level of n it lies at line / scale (whole cells at or below lane_level_).
  void split_line_at(const Node& n, std::int64_t& line, std::int64_t& scale) const {
    line = lane_column_;
    scale = 1;
    if (n.level >= lane_level_) {
      line <<= n.level - lane_level_;
    } else {
      scale = std::int64_t{1} << (lane_level_ - n.level);
    }
  }
  // Does the split line cross the columns ix − 1 … ix + 1 of the cell's level (the only cells
  // check() and split() reach from it, besides coarser leaves covering them and ancestors)? Such a
  // cell is left to the whole-tree lane. A cell off the line lies, with all it reaches, on one
  // side; a coarser leaf covering a reached cell either lies on that side too or is crossed by the
  // line (and then no region lane splits it), so the lanes never write what the other reads.
  bool near_split_line(const Node& n) const {
    std::int64_t line = 0, scale = 1;
    split_line_at(n, line, scale);
    return (n.ix - 1) * scale < line && line < (n.ix + 2) * scale;
  }
  // The side of the split line a cell lies on (0 west, 1 east), or -1 if the line crosses it.
  int side_of_split_line(const Node& n) const {
    std::int64_t line = 0, scale = 1;
    split_line_at(n, line, scale);
    if ((n.ix + 1) * scale <= line) return 0;
    if (n.ix * scale >= line) return 1;
    return -1;
  }
  // The column of level lane_level_ a leaf lies in (its first, if it is coarser).
  std::size_t lane_column_of(const Node& n) const {
    return static_cast<std::size_t>(n.level >= lane_level_ ? n.ix >> (n.level - lane_level_)
                                                           : n.ix << (lane_level_ - n.level));
  }
  // Chooses the split line: the column boundary of level lane_level_ with about half of the
  // leaves (a proxy for the work of the lanes) on each side, given the leaves per column (two
  // counts, one per half of the first round of checks).
  void choose_split_line(const std::array<std::vector<std::uint32_t>, 2>& leaves_per_column) {
    const std::size_t columns = leaves_per_column[0].size();
    std::size_t total = 0;
    for (std::size_t k = 0; k < columns; ++k) total += std::size_t{leaves_per_column[0][k]} + leaves_per_column[1][k];
    std::size_t below = 0;
    lane_column_ = static_cast<std::int64_t>(columns / 2);
    for (std::size_t k = 1; k < columns; ++k) {
      below += std::size_t{leaves_per_column[0][k - 1]} + leaves_per_column[1][k - 1];
      if (2 * below >= total) {
        lane_column_ = static_cast<std::int64_t>(k);
        break;
      }
    }
  }

  // May the lane split leaf b? A region lane splits only cells off the split line, within its room.
  bool may_split(Lane& lane, std::uint32_t b) {
    if (lane.region < 0) return true;
    const Node& n = nodes[b];
    if (near_split_line(n)) return false;
    if (lane.node_next + 4u > lane.node_end || lane.feature_next + 4u * std::size_t{n.feat_count} > lane.feature_end) {
      lane.full = true;
      return false;
    }
    return true;
  }

  // Splits leaf a; children get the features of a's list that meet their extended cells.
  void split(std::uint32_t a, Lane& lane) {
    const Node n = nodes[a];
    auto& lists = lane.lists;
    for (auto& list : lists) list.clear();
    // (The parent's list is read in place: filtering writes only to the lane's lists.)
    filter_children(n, features.data() + n.feat_begin, n.feat_count, lists);
    std::size_t list_total = 0;
    for (const auto& list : lists) list_total += list.size();
    std::uint32_t first = 0;
    std::size_t place = 0;
    if (lane.region < 0) {
      if (nodes.size() + 4u >= kNone || features.size() + list_total > std::numeric_limits<std::uint32_t>::max()) {
        throw RouteFailure{"too many quadtree nodes"};
      }
      refuse_beyond_leaf_limit(nodes.size() + 4u);
      first = static_cast<std::uint32_t>(nodes.size());
      nodes.resize(first + 4u);
      outer_hint_.resize(groups(first + 4u));
      place = features.size();
      features.resize(place + list_total);
    } else {
      first = lane.node_next;
      lane.node_next += 4u;
      place = lane.feature_next;
      lane.feature_next += list_total;
    }
    nodes[a].child = first;
    if (lane.region >= 0 && a < lane.node_begin) lane.split_before.push_back(a);
    lane.deepest = std::max(lane.deepest, n.level + 1u);
    for (unsigned k = 0; k < 4; ++k) {
      Node c;
      c.ix = 2 * n.ix + (k & 1);
      c.iy = 2 * n.iy + (k >> 1);
      c.parent = a;
      c.level = static_cast<std::uint8_t>(n.level + 1);
      c.state = has_segment(lists[k].data(), lists[k].size()) ? kFresh | kHasSegment : kFresh;
      c.feat_begin = static_cast<std::uint32_t>(place);
      c.feat_count = static_cast<std::uint32_t>(lists[k].size());
      std::copy(lists[k].begin(), lists[k].end(), features.begin() + static_cast<std::ptrdiff_t>(place));
      place += lists[k].size();
      c.vertex = vertex_in(c, lists[k].data(), lists[k].size());
      nodes[first + k] = c;
      lane.work.push_back(first + k);
    }
    // a's edge neighbours, for the children's hints and for the look below (the children lie
    // inside a, so they change none of them).
    const std::array<std::uint32_t, 4> edge = edge_neighbours(a);
    set_child_hints(a, edge);
    // A leaf around a that this split can make fail its check is looked at again (the edge
    // neighbours, then the diagonal ones, found from the east and west neighbours). Only the warp
    // rule can newly fail: a split makes no leaf coarser, so no balance test of a neighbour turns
    // false, and the children (fresh) are queued above. It fails for a leaf b of a's size whose
    // vertex will take a corner of a: a is one of the four cells around that corner and is no
    // longer a leaf. A leaf already failing is queued already. (Queueing every neighbour made
    // 21.7M checks instead of 12.2M at a million uniform points, nearly all of them passing.)
    const auto warp_corner_touches_a = [&](std::uint32_t b) {
      if (b == kNone) return false;
      const Node& m = nodes[b];
      if ((m.child & kLeafBit) == 0 || m.vertex == kNone || m.level != n.level) return false;
      unsigned qx = 0, qy = 0;
      nearest_corner(m, rank_point_[m.vertex], qx, qy);
      const std::int64_t cx = m.ix + qx, cy = m.iy + qy;  // the corner, in grid lines of the level
      return (n.ix == cx - 1 || n.ix == cx) && (n.iy == cy - 1 || n.iy == cy);
    };
    for (unsigned d = 0; d < 4; ++d) {
      if (warp_corner_touches_a(edge[d])) lane.work.push_back(edge[d]);
    }
    for (const int dx : {1, -1}) {
      const std::uint32_t side = edge[dx > 0 ? 0u : 2u];
      if (side == kNone) continue;
      for (const int dy : {1, -1}) {
        const std::uint32_t b = diagonal(a, side, dx, dy);
        if (warp_corner_touches_a(b)) lane.work.push_back(b);
      }
    }
  }

  // Splits leaf b for the check of leaf a (counted in `counter`) and queues a again if it is still
  // a leaf; returns false, with a deferred instead, where the lane may not split b.
  bool split_for(Lane& lane, std::uint32_t a, std::uint32_t b, std::size_t& counter) {
    if (!may_split(lane, b)) {
      lane.deferred.push_back(a);
      return false;
    }
    ++counter;
    split(b, lane);
    if (b != a) lane.work.push_back(a);
    return true;
  }

  // Checks leaf a against the feature rule (if fresh), balance and the warp rule, splitting what
  // must be split. A region lane defers a (leaves it for the whole-tree lane) where that would
  // reach across the split line or past its room.
  void check(std::uint32_t a, Lane& lane) {
    if (!is_leaf(a)) return;
    if (lane.region >= 0 && near_split_line(nodes[a])) {
      lane.deferred.push_back(a);
      return;
    }
    const unsigned l = nodes[a].level;
    if (nodes[a].state & kFresh) {
      const Node& n = nodes[a];
      if (l < max_level_ && feature_split(n, features.data() + n.feat_begin, n.feat_count)) {
        if (split_for(lane, a, a, lane.splits_feature)) {
          nodes[a].state = static_cast<std::uint8_t>(nodes[a].state & ~kFresh);
        }
        return;
      }
      nodes[a].state = static_cast<std::uint8_t>(nodes[a].state & ~kFresh);
    }
    bool changed = false;
    // Balance: an edge neighbour more than one level coarser is split. Two of a's edge neighbours
    // are its siblings (never coarser); across the other two, the hint covers the parent's
    // neighbour cell, and a hint at level l − 1 already proves the neighbour fine enough.
    const bool odd_x = (nodes[a].ix & 1) != 0, odd_y = (nodes[a].iy & 1) != 0;  // (nodes may move when b splits)
    const std::uint8_t state = nodes[a].state;
    for (unsigned d = 0; d < 4; ++d) {
      if (l == 0) break;
      const bool sibling = d == 0 ? !odd_x : d == 2 ? odd_x : d == 1 ? !odd_y : odd_y;
      if (sibling || (state & (kBalanced << d)) != 0) continue;
      const std::uint32_t h = hint(a, d);
      if (h == kNone || nodes[h].level + 1u >= l) continue;
      const std::uint32_t b = neighbour(a, d);
      if (b != kNone && nodes[b].level + 1u < l) {
        if (!split_for(lane, a, b, lane.splits_balance)) return;
        changed = true;
      }
    }
    if (changed) return;
    // Warp rule: the four leaves around the corner the vertex will move have a's size. A finer
    // one means a is split (the vertex gets a smaller leaf); a coarser one is split itself.
    const std::uint32_t v = nodes[a].vertex;
    if (v != kNone) {
      unsigned qx = 0, qy = 0;
      nearest_corner(nodes[a], rank_point_[v], qx, qy);
      // The cells around corner (ix + qx, iy + qy).
      for (int dy = -1; dy <= 0; ++dy) {
        for (int dx = -1; dx <= 0; ++dx) {
          const std::uint32_t b = cell_at(a, static_cast<int>(qx) + dx, static_cast<int>(qy) + dy);
          if (b == kNone || b == a) continue;
          if (nodes[b].level < l) {
            split_for(lane, a, b, lane.splits_warp);
            return;
          }
          if (is_leaf(b)) continue;
          if (l >= max_level_) return;  // counted by count_unresolved()
          split_for(lane, a, a, lane.splits_warp);
          return;
        }
      }
    }
  }

  // Works through the lane's list, last in first out (what it touches stays in cache). A region
  // lane that runs out of room defers the rest of its list.
  void run(Lane& lane) {
    while (!lane.work.empty()) {
      if (lane.full) {
        lane.deferred.insert(lane.deferred.end(), lane.work.begin(), lane.work.end());
        lane.work.clear();
        break;
      }
      const std::uint32_t a = lane.work.back();
      lane.work.pop_back();
      // (Most checks pass after a few reads: the next leaf's node and hints are fetched early.)
      if (!lane.work.empty()) {
        __builtin_prefetch(&nodes[lane.work.back()]);
        const std::uint32_t next = lane.work.back();
        if (next != 0) __builtin_prefetch(&outer_hint_[(next - 1) >> 2]);
      }
      check(a, lane);
    }
  }

  // Would check(a) split anything now? (The same tests, read only.)
  bool fails_check(std::uint32_t a) const {
    const Node& n = nodes[a];
    const unsigned l = n.level;
    if (n.state & kFresh) return true;
    if (l > 0) {
      const bool odd_x = (n.ix & 1) != 0, odd_y = (n.iy & 1) != 0;
      for (unsigned d = 0; d < 4; ++d) {
        const bool sibling = d == 0 ? !odd_x : d == 2 ? odd_x : d == 1 ? !odd_y : odd_y;
        if (sibling || (n.state & (kBalanced << d)) != 0) continue;
        const std::uint32_t h = hint(a, d);
        if (h == kNone || nodes[h].level + 1u >= l) continue;
        const std::uint32_t b = neighbour(a, d);
        if (b != kNone && nodes[b].level + 1u < l) return true;
      }
    }
    const std::uint32_t v = n.vertex;
    if (v == kNone) return false;
    unsigned qx = 0, qy = 0;
    nearest_corner(n, rank_point_[v], qx, qy);
    for (int dy = -1; dy <= 0; ++dy) {
      for (int dx = -1; dx <= 0; ++dx) {
        const std::uint32_t b = cell_at(a, static_cast<int>(qx) + dx, static_cast<int>(qy) + dy);
        if (b == kNone || b == a) continue;
        if (nodes[b].level < l) return true;
        if (is_leaf(b)) continue;
        return l < max_level_;
      }
    }
    return false;
  }

  // Balance and warp rule, to a fixed point.
  //
  // The work list's result depends on its order (the warp rule can ask for a split that a later
  // split would have made unnecessary), so the order is fixed whatever the number of threads:
  // first the west lane and the east lane, each with the leaves on its side of the split line (a
  // vertical grid line with about half of the leaves on each side); a region lane reads and
  // writes only nodes on its side (and ancestors and leaves the line crosses, which it never
  // changes), defers every leaf whose check would reach across the line (a cell in the column
  // next to it, or a split of one), and allocates in its own block of the arrays; then the blocks
  // are joined and one lane over the whole tree works through the deferred leaves. The two region
  // lanes run at the same time on large inputs and one after the other on small ones; the tree is
  // the same.
  void finish() {
    // The first round checks every leaf, and almost all pass: that round is done as a read-only
    // scan in two halves on two threads, and only the leaves that fail it are queued, in the same
    // order. This changes nothing: a leaf that passed at the start and is changed later is queued
    // again by the change (below) and checked after it, so its first-round check would have been
    // a no-op too.
    // The same scan counts the leaves per column of level lane_level_ (at most 10), to place the
    // lanes' split line.
    const auto node_count = static_cast<std::uint32_t>(nodes.size());
    std::vector<std::uint8_t> fails(node_count, 0);
    lane_level_ = std::min(10u, max_level_);
    std::array<std::vector<std::uint32_t>, 2> leaves_per_column;
    for (auto& count : leaves_per_column) count.assign(std::size_t{1} << lane_level_, 0);
    in_two_halves(node_count, threaded_nodes_, [&](std::size_t begin, std::size_t end) {
      std::vector<std::uint32_t>& count = leaves_per_column[begin == 0 ? 0 : 1];
      for (auto a = static_cast<std::uint32_t>(begin); a < end; ++a) {
        if (!is_leaf(a)) continue;
        ++count[lane_column_of(nodes[a])];
        fails[a] = fails_check(a) ? 1 : 0;
      }
    });
    choose_split_line(leaves_per_column);
    // Each region lane gets room for as many nodes and list entries as the tree has now (a
    // uniform point set needs about 0.7 of that in the busier half; a lane that runs out defers
    // the rest of its list). The room is never written unless used.
    const std::size_t feature_count = features.size();
    const std::size_t id_limit = std::numeric_limits<std::uint32_t>::max() - 8u;
    // (Never beyond the leaf limit: a lane that fills its room defers, and the last lane refuses.)
    const std::size_t node_room =
        std::min({std::size_t{node_count} + 64u, (id_limit - node_count) / 2, (node_limit() - node_count) / 2}) / 4 * 4;
    const std::size_t feature_room = std::min<std::size_t>(feature_count + 256u, (id_limit - feature_count) / 2);
    nodes.resize(node_count + 2 * node_room);
    outer_hint_.resize(groups(node_count + 2 * node_room));
    features.resize(feature_count + 2 * feature_room);
    std::array<Lane, 2> lanes;
    for (unsigned r = 0; r < 2; ++r) {
      Lane& lane = lanes[r];
      lane.region = static_cast<int>(r);
      lane.node_begin = static_cast<std::uint32_t>(node_count + r * node_room);
      lane.node_next = lane.node_begin;
      lane.node_end = static_cast<std::uint32_t>(lane.node_next + node_room);
      lane.feature_next = feature_count + r * feature_room;
      lane.feature_end = lane.feature_next + feature_room;
      reserve_room(lane.work, node_count / 2 + 64);
    }
    for (std::uint32_t a = 0; a < node_count; ++a) {
      if (!fails[a]) continue;
      const int region = side_of_split_line(nodes[a]);
      if (region < 0) {
        lanes[0].deferred.push_back(a);
      } else {
        lanes[static_cast<unsigned>(region)].work.push_back(a);
      }
    }
    std::vector<std::uint8_t>().swap(fails);
    // The work lists are complete: a balance violation needs a new leaf (each new leaf is
    // queued), and a warp-rule violation needs a split of one of the cells around the vertex's
    // corner (split() queues the vertex leaves whose corner cells it splits); a deferred leaf
    // stays queued for the last lane.
    const std::size_t threshold = node_count >= threaded_nodes_ ? 0 : std::numeric_limits<std::size_t>::max();
    in_two_halves(2, threshold, [&](std::size_t begin, std::size_t end) {
      for (std::size_t r = begin; r < end; ++r) run(lanes[r]);
    });
    join_lanes(node_count, feature_count, node_room, feature_room, lanes);
    Lane whole;
    whole.work = std::move(lanes[0].deferred);
    whole.work.insert(whole.work.end(), lanes[1].deferred.begin(), lanes[1].deferred.end());
    run(whole);
    for (const Lane* lane : {&lanes[0], &lanes[1], &whole}) {
      stats_.splits_feature += lane->splits_feature;
      stats_.splits_balance += lane->splits_balance;
      stats_.splits_warp += lane->splits_warp;
      deepest_ = std::max(deepest_, lane->deepest);
    }
    stats_.unresolved = count_unresolved();
    // (The nodes stay in creation order, breadth first and then split by split: copying them depth
    // first for locality cost more than it saved later, 1.0–1.5 s of 14 at a million points.)
  }

  // After the region lanes: moves the east lane's block of nodes and list entries down to follow
  // the west lane's, renumbering the references into it on the way, and trims the arrays. Only
  // the east lane's nodes and the older nodes it split (their child) refer to its block: the
  // west lane's hints point into its own half, and older nodes' hints are older nodes.
  void join_lanes(std::size_t node_count, std::size_t feature_count, std::size_t node_room, std::size_t feature_room,
                  std::array<Lane, 2>& lanes) {
    const std::size_t used0 = lanes[0].node_next - node_count;
    const std::size_t base1 = lanes[1].node_begin;
    const std::size_t used1 = lanes[1].node_next - base1;
    const std::size_t shift = node_room - used0;
    const std::size_t feature_used0 = lanes[0].feature_next - feature_count;
    const std::size_t feature_base1 = feature_count + feature_room;
    const std::size_t feature_used1 = lanes[1].feature_next - feature_base1;
    const auto feature_shift = static_cast<std::uint32_t>(feature_room - feature_used0);
    const auto renumber = [&](std::uint32_t& id) {
      if (id != kNone && id >= base1) id -= static_cast<std::uint32_t>(shift);
    };
    // In rounds of `shift` nodes, so that no round writes where it or a later one still reads;
    // each round in two halves.
    for (std::size_t round = 0; shift > 0 && round < used1; round += shift) {
      const std::size_t count = std::min(shift, used1 - round);
      in_two_halves(count, threaded_nodes_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = round + begin; i < round + end; ++i) {
          Node n = nodes[base1 + i];
          renumber(n.parent);
          renumber(n.child);
          n.feat_begin -= feature_shift;
          nodes[base1 + i - shift] = n;
          if (i % 4 == 0) {  // the first of a group of siblings (base1 − 1 and shift are multiples of 4)
            std::array<std::uint32_t, 4> h = outer_hint_[(base1 + i - 1) / 4];
            for (std::uint32_t& id : h) renumber(id);
            outer_hint_[(base1 + i - shift - 1) / 4] = h;
          }
        }
      });
    }
    for (const std::uint32_t a : lanes[1].split_before) renumber(nodes[a].child);
    std::copy(features.begin() + static_cast<std::ptrdiff_t>(feature_base1),
              features.begin() + static_cast<std::ptrdiff_t>(feature_base1 + feature_used1),
              features.begin() + static_cast<std::ptrdiff_t>(feature_count + feature_used0));
    nodes.resize(node_count + used0 + used1);
    outer_hint_.resize(groups(node_count + used0 + used1));
    features.resize(feature_count + feature_used0 + feature_used1);
    east_group_block_ = {(base1 - 1) / 4, (base1 - 1 + used1) / 4};
    east_feature_block_ = {feature_base1, feature_base1 + feature_used1};
    for (Lane& lane : lanes) {
      for (std::uint32_t& id : lane.deferred) renumber(id);
    }
  }

  // Leaves at the deepest level that still break the feature rule or the warp rule.
  std::size_t count_unresolved() const {
    if (deepest_ < max_level_) return 0;  // (no leaf at the deepest level: skip the pass over the nodes)
    std::size_t count = 0;
    for (std::uint32_t a = 0; a < nodes.size(); ++a) {
      if (!is_leaf(a) || nodes[a].level < max_level_) continue;
      const Node& n = nodes[a];
      bool bad = feature_split(n, features.data() + n.feat_begin, n.feat_count);
      const std::uint32_t v = n.vertex;
      if (!bad && v != kNone) {
        unsigned qx = 0, qy = 0;
        nearest_corner(n, rank_point_[v], qx, qy);
        for (int dy = -1; dy <= 0; ++dy) {
          for (int dx = -1; dx <= 0; ++dx) {
            const std::uint32_t b = find(a, n.level, n.ix + qx + dx, n.iy + qy + dy);
            if (b != kNone && b != a && (nodes[b].level != n.level || !is_leaf(b))) bad = true;
          }
        }
      }
      count += bad ? 1 : 0;
    }
    return count;
  }

  // Leaves in Morton (Z) order.
  std::vector<std::uint32_t> leaves_in_order() const {
    // The nodes at level 3 (and the leaves above it) in depth-first order are the roots of
    // subtrees whose leaves follow each other in the answer: two threads walk the first and the
    // second half of them, and the two lists are joined in order.
    std::vector<std::uint32_t> tops, stack{0};
    while (!stack.empty()) {
      const std::uint32_t a = stack.back();
      stack.pop_back();
      if (is_leaf(a) || nodes[a].level >= 3) {
        tops.push_back(a);
        continue;
      }
      for (int k = 3; k >= 0; --k) stack.push_back(nodes[a].child + static_cast<std::uint32_t>(k));
    }
    const std::size_t leaf_room = nodes.size() - nodes.size() / 4 + 1;  // 4 children per inner node: ¾ leaves
    std::array<std::vector<std::uint32_t>, 2> part;
    const std::size_t threshold = nodes.size() >= threaded_nodes_ ? 0 : std::numeric_limits<std::size_t>::max();
    in_two_halves(tops.size(), threshold, [&](std::size_t begin, std::size_t end) {
      std::vector<std::uint32_t>& out = part[begin == 0 ? 0 : 1];
      reserve_room(out, begin == 0 ? leaf_room : leaf_room / 2 + 64);
      std::vector<std::uint32_t> walk;
      for (std::size_t i = begin; i < end; ++i) {
        walk.push_back(tops[i]);
        while (!walk.empty()) {
          const std::uint32_t a = walk.back();
          walk.pop_back();
          if (is_leaf(a)) {
            out.push_back(a);
            continue;
          }
          for (int k = 3; k >= 0; --k) walk.push_back(nodes[a].child + static_cast<std::uint32_t>(k));
        }
      }
    });
    std::vector<std::uint32_t> out = std::move(part[0]);
    out.insert(out.end(), part[1].begin(), part[1].end());
    return out;
  }

  // After finish(): the east lane's old block (written while the lane ran, moved down by
  // join_lanes()) is dead where it lies past the arrays' final ends; the tree never grows after
  // finish(), so those pages of the arrays' capacity are lent (the lists' and the hints'; the
  // nodes' storage becomes the mesh's triangle array, see NodeArray).
  void lend_dead_room(SpareRoom& room) {
    const auto lend_tail = [&](auto& array, std::pair<std::size_t, std::size_t> block) {
      const std::size_t begin = std::max(block.first, array.size());
      if (begin < block.second && block.second <= array.capacity()) {
        room.lend(array.data() + begin, (block.second - begin) * sizeof(array[0]));
      }
    };
    lend_tail(features, east_feature_block_);
    // (The hints' dead block usually follows their live part: lent with it, as one region.)
    if (east_group_block_.first > outer_hint_.size()) lend_tail(outer_hint_, east_group_block_);
  }
  // After the last neighbour() / diagonal() look-up (Builder::build_loops()): the hints are dead
  // (4 bytes per node), and no look-up may follow.
  void lend_hints(SpareRoom& room) {
    std::size_t end = outer_hint_.size();
    const auto [dead_begin, dead_end] = east_group_block_;
    if (dead_begin <= end && dead_end <= outer_hint_.capacity()) end = std::max(end, dead_end);
    room.lend(outer_hint_.data(), end * sizeof(outer_hint_[0]));
    hints_lent_ = true;
  }

  // The nodes' storage, for the mesh's triangles (NodeArray::give_storage()): the nodes may still
  // be read until the first triangle is written, and not after.
  std::vector<Triangle> give_node_storage() { return nodes.give_storage(); }

  unsigned max_level() const { return max_level_; }
  // Leaves (1 + 3 per split: nodes come in fours) and the deepest level of any node.
  std::size_t leaf_count() const { return (nodes.size() - 1) / 4 * 3 + 1; }

  // QuadtreeOptions::max_leaves, resolved: the automatic limit grows with the input (1024 leaves
  // per feature; the 13 data sets need at most 26, uniform points 11.5) between 2^20 and 2^26 (about
  // 240 bytes per leaf at the peak: 16 GB). BEG's tree has O(Σ 1/lfs²) leaves, unbounded in the
  // number of features: two segments 30 apart running 3e15 long would need 1e14.
  static std::size_t leaf_limit(const QuadtreeOptions& options, std::size_t features) {
    if (options.max_leaves > 0) return options.max_leaves;
    constexpr std::size_t kPerFeature = 1024, kLeast = std::size_t{1} << 20, kMost = std::size_t{1} << 26;
    return std::clamp(kPerFeature * features, kLeast, kMost);
  }
  // Nodes in a tree of max_leaves_ leaves (each split turns one leaf into four nodes).
  std::size_t node_limit() const { return 1 + (max_leaves_ - 1) / 3 * 4; }
  void refuse_beyond_leaf_limit(std::size_t node_count) const {
    if (node_count <= node_limit()) return;
    throw RouteFailure{"the quadtree would need more than " + std::to_string(max_leaves_) +
                       " leaves (features very close for their extent, as in a long thin strip)"};
  }
  unsigned deepest() const { return deepest_; }

  NodeArray nodes;
  std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>> features;  // the leaves' lists

 private:
  const CleanInput& in_;
  const std::vector<Point>& pts_;
  std::uint32_t nv_;
  unsigned max_level_;
  QuadtreeStats& stats_;
  std::size_t max_leaves_;
  double x0_ = 0.0, y0_ = 0.0;
  int exponent_ = 0;
  std::array<double, 64> step_{};  // cell size at each level
  unsigned deepest_ = 0;                             // deepest level of any node made so far
  unsigned lane_level_ = 1;                          // finish(): the split line between the lanes
  std::int64_t lane_column_ = 1;
  // Per group of four siblings (nodes 4g + 1 … 4g + 4): their parent's edge neighbours (east,
  // north, west, south) when they were made; see hint().
  std::vector<std::array<std::uint32_t, 4>, UninitializedAllocator<std::array<std::uint32_t, 4>>> outer_hint_;
  bool hints_lent_ = false;                          // lend_hints() was called (checked by assert)
  std::pair<std::size_t, std::size_t> east_group_block_{0, 0};    // join_lanes(): the east lane's old
  std::pair<std::size_t, std::size_t> east_feature_block_{0, 0};  //   blocks (see lend_dead_room())
  std::vector<VertexId> rank_id_;                    // vertex feature (Morton rank) → vertex id
  std::vector<Point> rank_point_;                    // vertex feature → its point
  std::size_t threaded_items_;                       // build(): frontier size for two threads
  std::size_t threaded_nodes_;                       // finish(): tree size for two threads
};

// ---- from the quadtree to the mesh ----------------------------------------------------------------

// Loop slots of a leaf, counter-clockwise from the lower-left corner; odd slots are side midpoints.
enum Slot : unsigned { kBL = 0, kBottom = 1, kBR = 2, kRight = 3, kTR = 4, kTop = 5, kTL = 6, kLeft = 7 };
// Owned-vertex bits of a leaf.
enum Own : unsigned { kOwnLL = 0, kOwnLeftMid = 1, kOwnBottomMid = 2, kOwnUL = 3, kOwnLR = 4, kOwnUR = 5 };

class Builder {
 public:
  Builder(const CleanInput& in, const QuadtreeOptions& options, QuadtreeStats& stats, Tree& tree)
      : in_(in), options_(options), stats_(stats), tree_(tree), pts_(in.vertices_only.points) {}

  Mesh run(const std::vector<Point>& holes);

  // Free corners for the fallback (grid vertices not near a feature); valid after number_vertices().
  // `tree` is the Builder's tree or, once its nodes are given away, the same tree built again.
  std::vector<Point> fallback_points(const Tree& tree) const;
  // Did run() give the tree's nodes' storage to the mesh (NodeArray)? The nodes are then gone:
  // overwritten by the triangles, or freed with the mesh when the route failed.
  bool nodes_given_away() const { return nodes_given_away_; }

 private:
  using Tri = std::array<std::uint32_t, 3>;

  std::uint32_t own(std::uint32_t k, unsigned bit) const {
    if (((own_mask_[k] >> bit) & 1u) == 0) throw RouteFailure{"a leaf lacks an expected vertex"};
    return own_base_[k] + bits_in_byte(static_cast<unsigned>(own_mask_[k] & ((1u << bit) - 1u)));
  }
  std::uint32_t leaf_of(std::uint32_t node) const { return tree_.leaf_ordinal(node); }
  // The leaf containing the point just north-east of the lower-left corner of node a's cell.
  std::uint32_t leaf_sw(std::uint32_t a) const {
    if (a == kNone) throw RouteFailure{"neighbour outside the root"};
    while (!tree_.is_leaf(a)) a = tree_.nodes[a].child;
    return a;
  }
  // The vertex of leaf node d at grid point (tx, ty) of level l, which is d's lower-left corner or
  // the midpoint of its left or bottom side.
  std::uint32_t vertex_at(std::uint32_t d, unsigned l, std::int64_t tx, std::int64_t ty) const {
    const Node& n = tree_.nodes[d];
    const unsigned top = tree_.max_level();
    const std::int64_t dx = n.ix << (top - n.level), dy = n.iy << (top - n.level);
    const std::int64_t gx = tx << (top - l), gy = ty << (top - l);
    const std::uint32_t k = leaf_of(d);
    if (dx == gx && dy == gy) return own(k, kOwnLL);
    if (dx == gx) return own(k, kOwnLeftMid);
    if (dy == gy) return own(k, kOwnBottomMid);
    throw RouteFailure{"vertex ownership is inconsistent"};
  }

  void number_vertices();
  void build_loops();  // then own_base_, own_mask_ and the tree's hints are lent to spare_
  void warp();
  void segments_pass();
  void triangulate_cells(Mesh& mesh);
  struct PreparedChunk;
  void prepare_cells(const Mesh& mesh, PreparedChunk& out, std::uint32_t begin, std::uint32_t end,
                     std::size_t& next_crossing) const;
  struct EmitSink;
  void emit_cells(const PreparedChunk& in, std::uint32_t end, Triangle* tris, TriangleId first, Handle* bound,
                  std::uint32_t first_bound, VertexId centre_first, EmitSink& sink);
  struct CellSide;
  CellSide cell_side(std::uint32_t k, unsigned side) const;
  void link_cell(const std::vector<Point>& points, Triangle* tris, const Handle* bound, std::uint32_t k,
                 EmitSink& sink) const;
  void close_border(Mesh& mesh);
  void mark_segments(Mesh& mesh);
  // After carving: throws RouteFailure (no corners for the fallback) if the rounding of the points
  // on segments could move the domain boundary by more than kBoundaryRoundingShare of its area.
  void refuse_rounded_sliver(const Mesh& mesh) const;

  // Calls visit(k, slot, u, w, s, a, b) for every edge u→w of the loop of a leaf k in `near` (from
  // `slot` to the next present slot) that segment s = ab of k's feature list crosses properly: u
  // and w strictly on opposite sides of ab and a, b strictly on opposite sides of uw (exact); edges
  // with an end already on s only touch it. Positions are read when the edge is visited, so the
  // callback may move corners or append vertices.
  template <class Visit>
  void for_each_crossed_edge(const std::vector<std::uint32_t>& near, Visit&& visit) {
    const std::uint32_t nv = tree_.vertex_count();
    for (const std::uint32_t k : near) {
      const Node& n = tree_.nodes[leaves_[k]];
      const std::array<std::uint32_t, 8> loop = loop_of(k);
      for (std::uint32_t i = 0; i < n.feat_count; ++i) {
        const std::uint32_t f = tree_.features[n.feat_begin + i];
        if (f < nv) continue;
        const std::uint32_t s = f - nv;
        const Point a = pts_[in_.segments[s].a];
        const Point b = pts_[in_.segments[s].b];
        for (unsigned slot = 0; slot < 8; ++slot) {
          const std::uint32_t u = loop[slot];
          if (u == kNone) continue;
          unsigned next = (slot + 1) % 8;
          while (loop[next] == kNone) next = (next + 1) % 8;
          const std::uint32_t w = loop[next];
          if (on_segment(u, s) || on_segment(w, s)) continue;
          const Point pu = gpos_[u], pw = gpos_[w];
          if (orient2d(a, b, pu) * orient2d(a, b, pw) >= 0) continue;
          if (orient2d(pu, pw, a) * orient2d(pu, pw, b) >= 0) continue;
          visit(k, slot, u, w, s, a, b);
        }
      }
    }
  }

  // Room for the arrays indexed by grid vertex that grow with the crossing points and the centres
  // made later (about one per 64 leaves): a sixteenth more than the grid (at a million uniform
  // points the crossings are a few thousand; if there are more, the arrays grow). Not more, as
  // they borrow from spare_ and the room past their end would be lost there.
  std::size_t grid_reserve() const { return grid_count_ + grid_count_ / 16 + leaves_.size() / 64 + 16; }

  bool in_chain(std::uint32_t g) const { return g < gon_segment_.size() && (gon_segment_[g] || gwarped_[g]); }

  // The segment grid vertex g lies on (an exact corner, a snapped one or a crossing point), or kNone.
  bool on_any_segment(std::uint32_t g) const { return g < gon_segment_.size() && gon_segment_[g]; }
  std::uint32_t segment_of(std::uint32_t g) const {
    if (!on_any_segment(g)) return kNone;
    return gsegment_.find(g)->second;
  }
  void set_segment(std::uint32_t g, std::uint32_t s) {
    gon_segment_[g] = true;
    gsegment_[g] = s;
  }

  bool on_segment(std::uint32_t g, std::uint32_t s) const {
    if (segment_of(g) == s) return true;
    const FeatureSegment& seg = in_.segments[s];
    return input_gv_[seg.a] == g || input_gv_[seg.b] == g;
  }

  const CleanInput& in_;
  const QuadtreeOptions& options_;
  QuadtreeStats& stats_;
  Tree& tree_;
  const std::vector<Point>& pts_;
  // Dead memory lent to the arrays made later (see SpareRoom): the tree's dead blocks and hints,
  // and own_base_ and own_mask_ after build_loops(). Declared before every borrower and every
  // lender of the Builder, so that it is destroyed after them, and the lenders after the borrowers.
  SpareRoom spare_;

  std::vector<std::uint32_t> leaves_;      // leaf ordinal → node, Morton order
  // Per-leaf arrays that passes in two halves write in full are allocated without being filled
  // first: the fill of a vector would touch all their pages on one thread.
  // Per leaf: the id of its first owned vertex, and which it owns (Own bits); one block, so that it
  // is lent as one region after build_loops().
  std::unique_ptr<std::byte[]> own_storage_;
  // Its size: 5 bytes per leaf are used, but the block is as large as cell_bound_ (8 bytes per
  // leaf), which then borrows it whole and so reuses the pages the ownership touched (the tail
  // past them costs nothing until written).
  std::size_t own_storage_bytes() const;
  std::uint32_t* own_base_ = nullptr;
  std::uint8_t* own_mask_ = nullptr;
  // Per leaf, for link_cell(): what lies across its west and south sides, as leaf ordinals or as
  // a place in split_across_ (leaf_shape_ bits 12, 13 say which).
  SpareArray<std::array<std::uint32_t, 2>> west_south_;
  // Per leaf, for link_cell() (which then reads no node of its own): its level (bits 0–5), whether
  // the same-size cell west / south is split (bits 6, 7), which of its sides (bottom, right, top,
  // left: bits 8–11) lie on the root's border, and whether west_south_ holds the leaves across the
  // west / south side as leaf ordinals rather than a place in split_across_ (bits 12, 13).
  SpareArray<std::uint16_t> leaf_shape_;
  // Per half of the leaves (number_vertices()): the two leaf ordinals along the west or south side
  // of a leaf whose same-size neighbour there is split into leaves that are not next to each other
  // in Morton order; west_south_ holds the place here. The second half starts at split_half_.
  std::array<std::vector<std::array<std::uint32_t, 2>>, 2> split_across_;
  std::size_t split_half_ = 0;
  // Per leaf, its loop of up to 8 vertices (slots kBL … kLeft, counter-clockwise from the lower-left
  // corner), packed in 5 words (build_loops(); loop_of() unpacks): the ids of the lower-left corner
  // (with flags in its top bits), of the other three corners, and of the right or the top side's
  // midpoint. The left and bottom midpoints are the leaf's own vertices, the ids after its corner
  // (Own), and need no word; a leaf with both a right and a top midpoint (about 2 % of them) keeps
  // the top one in both_mids_. 20 bytes per leaf instead of 32: at a million points 139 MB fewer
  // fresh pages, which this kind of machine charges for (see the header).
  struct PackedLoop {
    std::uint32_t head, br, tr, tl, mid;
  };
  static constexpr unsigned kLoopIdBits = 28;  // grid ids below 2^28 (run() refuses more)
  static constexpr std::uint32_t kLoopIdMask = (1u << kLoopIdBits) - 1u;
  static constexpr std::uint32_t kHasLeftMid = 1u << 28, kHasBottomMid = 1u << 29, kHasRightMid = 1u << 30,
                                 kHasTopMid = 1u << 31;
  std::unique_ptr<PackedLoop[]> loops_;  // per leaf (null until built)
  // (leaf, its top midpoint) for the leaves with both a right and a top midpoint, in leaf order
  // (build_loops()).
  std::vector<std::array<std::uint32_t, 2>> both_mids_;
  std::array<std::uint32_t, 8> loop_of(std::uint32_t k) const {
    const PackedLoop& p = loops_[k];
    const std::uint32_t base = p.head & kLoopIdMask;
    const std::uint32_t left_mid = (p.head & kHasLeftMid) != 0 ? 1u : 0u;
    std::array<std::uint32_t, 8> loop;
    loop[kBL] = base;
    loop[kLeft] = left_mid != 0 ? base + 1u : kNone;
    loop[kBottom] = (p.head & kHasBottomMid) != 0 ? base + 1u + left_mid : kNone;
    loop[kBR] = p.br;
    loop[kTR] = p.tr;
    loop[kTL] = p.tl;
    loop[kRight] = (p.head & kHasRightMid) != 0 ? p.mid : kNone;
    loop[kTop] = (p.head & kHasTopMid) == 0 ? kNone : (p.head & kHasRightMid) == 0 ? p.mid : top_of_both(k);
    return loop;
  }
  std::uint32_t top_of_both(std::uint32_t k) const {
    const auto it = std::lower_bound(both_mids_.begin(), both_mids_.end(), k,
                                     [](const std::array<std::uint32_t, 2>& e, std::uint32_t leaf) { return e[0] < leaf; });
    if (it == both_mids_.end() || (*it)[0] != k) throw InternalError("quadtree: a leaf's top midpoint is missing from its table");
    return (*it)[1];
  }
  std::array<std::vector<std::uint32_t>, 2> near_segment_;  // leaves with a segment in their list (two
                                                             // halves, in order; build_loops())
  std::array<std::vector<std::uint32_t>, 2> with_vertex_;  // leaves with an input vertex (two halves,
                                                            // in order; build_loops() for warp())
  std::vector<Point> gpos_;                // grid vertex (then crossing point) positions
  std::vector<std::uint8_t> glevel_;       // deepest level of a leaf around each grid vertex
  std::vector<std::uint8_t> gtop_;         // shallowest level of a leaf around each grid vertex
  std::vector<bool> gwarped_;              // warped onto an input vertex (which one: input_gv_ is the
                                           // inverse); bits, as gmoved_
  // Which grid vertices lie on a segment (segments_pass(); empty without segments), as bits for the
  // per-leaf tests, and on which one: few vertices do, so a map rather than an array indexed by
  // grid vertex (4 bytes for each of them all).
  std::vector<bool> gon_segment_;
  std::unordered_map<std::uint32_t, std::uint32_t> gsegment_;
  std::vector<bool> gmoved_;               // moved off its grid position (warped or snapped); bits,
                                           // so that the per-leaf test stays in cache
  std::uint32_t grid_count_ = 0;
  SpareVector<std::uint32_t> input_gv_{SpareAllocator<std::uint32_t>(&spare_)};  // input vertex → its grid vertex
  // Crossing points per leaf edge: (leaf, start slot, vertex), sorted by leaf.
  struct EdgeCrossing {
    std::uint32_t leaf, slot, vertex;
  };
  std::vector<EdgeCrossing> crossings_;
  // Subsegment chains: the neighbours of each vertex along segments, as (other vertex, segment),
  // sorted by vertex (chain_of() finds a vertex's links by binary search: few vertices lie on
  // segments, and an array indexed by grid vertex would be 4 bytes for each of them all).
  struct ChainLink {
    std::uint32_t vertex, other, segment;
  };
  std::vector<ChainLink> chain_links_;
  std::pair<const ChainLink*, const ChainLink*> chain_of(std::uint32_t g) const {
    const ChainLink* const begin = chain_links_.data();
    const ChainLink* const end = begin + chain_links_.size();
    const ChainLink* const first =
        std::lower_bound(begin, end, g, [](const ChainLink& link, std::uint32_t v) { return link.vertex < v; });
    const ChainLink* last = first;
    while (last != end && last->vertex == g) ++last;
    return {first, last};
  }
  std::size_t subsegment_count_ = 0;
  // Final ids and the cells' boundary edges.
  SpareVector<VertexId> final_id_{SpareAllocator<VertexId>(&spare_)};
  // Per leaf, where its boundary edges are; together, so that a neighbour's sides cost one miss,
  // and each leaf's entry is written by the thread that writes the leaf alone:
  //  - a table cell: begin = kTableCell | its first triangle, sides = its case-table mask (its
  //    edges follow from the table, PlainCell::edge: nothing is stored for two thirds of the
  //    leaves, about 135 MB fewer bytes written at a million points);
  //  - a warped or cut cell: begin = its first boundary edge in bound_, sides = the polygon
  //    indices of its BR, TR, TL corners and its number of boundary edges (8 bits each).
  struct CellBound {
    std::uint32_t begin, sides;
  };
  static constexpr std::uint32_t kTableCell = 0x80000000u;
  SpareArray<CellBound> cell_bound_;
  std::vector<Handle> bound_;               // warped and cut cells' boundary edge handles, in polygon order
  struct Outer {
    double position;  // along the root's border, counter-clockwise from its lower-left corner
    Handle handle;
  };
  std::vector<Outer> outer_;                // boundary edges on the root's border
  std::vector<std::pair<Handle, std::uint32_t>> segment_edges_;  // (edge, segment) to mark
  // triangulate_cells(): a prepared warped or cut cell, as ranges in its PreparedChunk.
  struct SpecialCell {
    std::uint32_t tri_begin = 0, tri_count = 0, centre_begin = 0, centre_count = 0;
    std::uint32_t bound_begin = 0, bound_count = 0, segment_begin = 0, segment_count = 0;
    std::uint32_t sides = 0;
  };
  static constexpr std::uint8_t kSpecialCell = 16;         // PreparedChunk::kind of such a cell
  static constexpr std::uint32_t kCentre = 0x80000000u;    // a prepared triangle's j-th centre
  std::size_t centre_base_ = 0;                            // first centre's vertex id
  std::vector<Point> centre_points_;                       // centres in leaf order
  std::size_t threaded_leaves_ = threads_from(options_, 65536);  // leaves for two threads
  bool nodes_given_away_ = false;                          // see nodes_given_away()
  // For a pass over the leaves [.., end) that looks up neighbours in directions d0 and d1 of leaf
  // k: fetches the node and hints of the leaf 16 on, and the nodes those hints name for the leaf
  // 8 on (Tree::prefetch_node, prefetch_hinted).
  void prefetch_neighbours(std::size_t k, std::size_t end, unsigned d0, unsigned d1) const {
    constexpr std::size_t kAhead = 8;
    if (k + 2 * kAhead < end) tree_.prefetch_node(leaves_[k + 2 * kAhead]);
    if (k + kAhead < end) {
      tree_.prefetch_hinted(leaves_[k + kAhead], d0);
      tree_.prefetch_hinted(leaves_[k + kAhead], d1);
    }
  }
};


std::size_t Builder::own_storage_bytes() const {
  return leaves_.size() * std::max(sizeof(std::uint32_t) + 1, sizeof(CellBound));
}

void Builder::number_vertices() {
  tree_.lend_dead_room(spare_);
  leaves_ = tree_.leaves_in_order();
  // (The two largest borrowers first: the regions lent so far are the tree's dead blocks.)
  west_south_ = make_spare_array<std::array<std::uint32_t, 2>>(spare_, leaves_.size());
  leaf_shape_ = make_spare_array<std::uint16_t>(spare_, leaves_.size());
  tree_.number_leaves(leaves_, threaded_leaves_);
  own_storage_ = std::make_unique_for_overwrite<std::byte[]>(own_storage_bytes());
  own_base_ = reinterpret_cast<std::uint32_t*>(own_storage_.get());
  own_mask_ = reinterpret_cast<std::uint8_t*>(own_storage_.get() + leaves_.size() * sizeof(std::uint32_t));
  // Which vertices each leaf owns (neighbour look-ups: two threads), then their ids by a prefix
  // sum in leaf order, then their positions (two threads).
  split_half_ = leaves_.size();
  in_two_halves(leaves_.size(), threaded_leaves_, [&](std::size_t begin, std::size_t end) {
    auto& split_pairs = split_across_[begin == 0 ? 0 : 1];
    split_pairs.clear();
    if (begin != 0) split_half_ = begin;
    for (std::size_t k = begin; k < end; ++k) {
      prefetch_neighbours(k, end, 2, 3);  // west, south
      const std::uint32_t a = leaves_[k];
      const Node& n = tree_.nodes[a];
      const unsigned l = n.level;
      const std::int64_t side = std::int64_t{1} << l;
      unsigned mask = 1u << kOwnLL;
      const std::uint32_t w = tree_.neighbour(a, 2);
      if (w != kNone && tree_.nodes[w].level == l && !tree_.is_leaf(w)) mask |= 1u << kOwnLeftMid;
      const std::uint32_t s = tree_.neighbour(a, 3);
      if (s != kNone && tree_.nodes[s].level == l && !tree_.is_leaf(s)) mask |= 1u << kOwnBottomMid;
      // For link_cell(): the leaves across the west and south sides as leaf ordinals (bits 12, 13 of
      // the shape) when they are a leaf, or the two children of a split cell along the side that
      // follow each other as usual in Morton order (east column: SE, NE two apart; north row: NW,
      // NE next to each other).
      const auto leaf_across = [&](std::uint32_t b, unsigned own_bit, unsigned near_child, unsigned step,
                                   std::uint32_t& out) {
        if (b == kNone) return false;
        if (tree_.is_leaf(b)) {
          out = leaf_of(b);
          return true;
        }
        if (((mask >> own_bit) & 1u) == 0) return false;
        const std::uint32_t c = tree_.nodes[b].child;
        const std::uint32_t first = leaf_of(c + near_child);
        if (first == kNone || leaf_of(c + 3) != first + step) return false;
        out = first;
        return true;
      };
      // Otherwise (a split cell whose two leaves along the side are not next to each other) the
      // place of their two ordinals in this half's split_across_ (link_cell() reads no node: the
      // nodes' storage is the triangle array it writes, see NodeArray).
      const auto split_pair = [&](std::uint32_t b, unsigned near_child) {
        const std::uint32_t c = tree_.nodes[b].child;
        split_pairs.push_back({leaf_of(c + near_child), leaf_of(c + 3)});
        return static_cast<std::uint32_t>(split_pairs.size() - 1);
      };
      unsigned across = 0;
      std::uint32_t west = kNone, south = kNone;
      if (leaf_across(w, kOwnLeftMid, 1, 2, west)) {
        across |= 1u;
      } else if (w != kNone) {
        west = split_pair(w, 1);
      }
      if (leaf_across(s, kOwnBottomMid, 2, 1, south)) {
        across |= 2u;
      } else if (s != kNone) {
        south = split_pair(s, 2);
      }
      west_south_[k] = {west, south};
      const bool top = n.iy + 1 == side, right = n.ix + 1 == side;
      if (top) mask |= 1u << kOwnUL;
      if (right) mask |= 1u << kOwnLR;
      if (top && right) mask |= 1u << kOwnUR;
      own_mask_[k] = static_cast<std::uint8_t>(mask);
      const unsigned border = (n.iy == 0 ? 1u : 0u) | (right ? 2u : 0u) | (top ? 4u : 0u) | (n.ix == 0 ? 8u : 0u);
      leaf_shape_[k] = static_cast<std::uint16_t>(l | ((mask >> kOwnLeftMid) & 1u) << 6 |
                                                  ((mask >> kOwnBottomMid) & 1u) << 7 | border << 8 |
                                                  across << 12);
    }
  });
  std::uint32_t next = 0;
  for (std::size_t k = 0; k < leaves_.size(); ++k) {
    own_base_[k] = next;
    next += bits_in_byte(own_mask_[k]);
  }
  grid_count_ = next;
  gpos_.clear();
  // (Room for the crossing points and centres made later, and for the duplicate input points: the
  // array becomes the mesh's points in run(), without being copied.)
  reserve_room(gpos_, std::max<std::size_t>(grid_count_, leaves_.size() + leaves_.size() / 2) +
                          (pts_.size() - in_.vertices.size()) + 16);
  // resize() zero-fills, and so faults in, every page of the positions on this thread (16 bytes
  // per grid vertex: 0.3–0.6 s at a million points, the kernel clearing each page); both threads
  // fault them in first, and the fill then writes pages that are there.
  if (leaves_.size() >= threaded_leaves_) {
    PageFaulter pages;
    pages.add(gpos_.data(), grid_count_ * sizeof(Point));
    in_two_halves(2, 0, [&](std::size_t, std::size_t) { pages.work(); });
  }
  gpos_.resize(grid_count_);
  in_two_halves(leaves_.size(), threaded_leaves_, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const Node& n = tree_.nodes[leaves_[k]];
      const unsigned l = n.level;
      const std::int64_t ix = n.ix, iy = n.iy;
      const unsigned mask = own_mask_[k];
      Point* out = gpos_.data() + own_base_[k];
      *out++ = {tree_.X(ix, l), tree_.Y(iy, l)};
      if ((mask >> kOwnLeftMid) & 1u) *out++ = {tree_.X(ix, l), tree_.Y(2 * iy + 1, l + 1)};
      if ((mask >> kOwnBottomMid) & 1u) *out++ = {tree_.X(2 * ix + 1, l + 1), tree_.Y(iy, l)};
      if ((mask >> kOwnUL) & 1u) *out++ = {tree_.X(ix, l), tree_.Y(iy + 1, l)};
      if ((mask >> kOwnLR) & 1u) *out++ = {tree_.X(ix + 1, l), tree_.Y(iy, l)};
      if ((mask >> kOwnUR) & 1u) *out++ = {tree_.X(ix + 1, l), tree_.Y(iy + 1, l)};
    }
  });
}

void Builder::build_loops() {
  for (auto& half : with_vertex_) half.clear();
  for (auto& half : near_segment_) half.clear();
  if (grid_count_ > kLoopIdMask) throw RouteFailure{"too many grid vertices"};
  loops_ = std::make_unique_for_overwrite<PackedLoop[]>(leaves_.size());
  // With the loops, the deepest and shallowest leaf level around each grid vertex: each thread
  // updates the vertices that the leaves of its half own (ids are given in leaf order, so they are
  // a range); the few vertices owned by a leaf of the other half, near where the halves meet, are
  // set after both (max and min do not depend on the order).
  glevel_.assign(grid_count_, 0);
  gtop_.assign(grid_count_, 255);
  const std::size_t leaf_count = leaves_.size();
  std::array<std::vector<std::pair<std::uint32_t, std::uint8_t>>, 2> across_halves;
  std::array<std::vector<std::array<std::uint32_t, 2>>, 2> both_mids_per_half;
  in_two_halves(leaf_count, threaded_leaves_, [&](std::size_t begin, std::size_t end) {
    auto& with_vertex = with_vertex_[begin == 0 ? 0 : 1];
    auto& near_segment = near_segment_[begin == 0 ? 0 : 1];
    auto& both_mids = both_mids_per_half[begin == 0 ? 0 : 1];
    const std::uint32_t lo = own_base_[begin], hi = end == leaf_count ? grid_count_ : own_base_[end];
    auto& later = across_halves[begin == 0 ? 0 : 1];
    for (auto k = static_cast<std::uint32_t>(begin); k < end; ++k) {
      prefetch_neighbours(k, end, 0, 1);  // east, north
      const std::uint32_t a = leaves_[k];
      const Node& n = tree_.nodes[a];
      if (n.vertex != kNone) with_vertex.push_back(k);
      if ((n.state & kHasSegment) != 0) near_segment.push_back(k);
      const unsigned l = n.level;
      const std::int64_t side = std::int64_t{1} << l, ix = n.ix, iy = n.iy;
      const bool top = iy + 1 == side, right = ix + 1 == side;
      std::array<std::uint32_t, 8> loop;
      loop.fill(kNone);
      loop[kBL] = own(k, kOwnLL);
      if ((own_mask_[k] >> kOwnBottomMid) & 1u) loop[kBottom] = own(k, kOwnBottomMid);
      if ((own_mask_[k] >> kOwnLeftMid) & 1u) loop[kLeft] = own(k, kOwnLeftMid);
      // The same-size cells east and north (each looked up once).
      const std::uint32_t r = right ? kNone : tree_.neighbour(a, 0);
      const std::uint32_t t = top ? kNone : tree_.neighbour(a, 1);
      loop[kBR] = right ? own(k, kOwnLR) : vertex_at(leaf_sw(r), l, ix + 1, iy);
      if (top && right) {
        loop[kTR] = own(k, kOwnUR);
      } else if (top) {
        // The leaf to the east along the root's top border: (xR, yT) is its upper-left corner.
        std::uint32_t d = r;
        while (!tree_.is_leaf(d)) d = tree_.nodes[d].child + 2;
        loop[kTR] = own(leaf_of(d), kOwnUL);
      } else if (right) {
        std::uint32_t d = t;
        while (!tree_.is_leaf(d)) d = tree_.nodes[d].child + 1;
        loop[kTR] = own(leaf_of(d), kOwnLR);
      } else {
        // (Tree::cell_at(a, 1, 1), from the east cell found above.)
        loop[kTR] = vertex_at(leaf_sw(tree_.diagonal(a, r, 1, 1)), l, ix + 1, iy + 1);
      }
      loop[kTL] = top ? own(k, kOwnUL) : vertex_at(leaf_sw(t), l, ix, iy + 1);
      if (!right) {
        if (tree_.nodes[r].level == l && !tree_.is_leaf(r)) {
          const std::uint32_t nw = tree_.nodes[r].child + 2;
          if (!tree_.is_leaf(nw)) throw RouteFailure{"unbalanced quadtree"};
          loop[kRight] = own(leaf_of(nw), kOwnLL);
        }
      }
      if (!top) {
        if (tree_.nodes[t].level == l && !tree_.is_leaf(t)) {
          const std::uint32_t se = tree_.nodes[t].child + 1;
          if (!tree_.is_leaf(se)) throw RouteFailure{"unbalanced quadtree"};
          loop[kTop] = own(leaf_of(se), kOwnLL);
        }
      }
      // Packed (see PackedLoop): the own midpoints follow the corner's id.
      std::uint32_t head = loop[kBL];
      if (loop[kLeft] != kNone) head |= kHasLeftMid;
      if (loop[kBottom] != kNone) head |= kHasBottomMid;
      if (loop[kRight] != kNone) head |= kHasRightMid;
      if (loop[kTop] != kNone) head |= kHasTopMid;
      if (loop[kRight] != kNone && loop[kTop] != kNone) both_mids.push_back({k, loop[kTop]});
      loops_[k] = {head, loop[kBR], loop[kTR], loop[kTL], loop[kRight] != kNone ? loop[kRight] : loop[kTop]};
      const auto level = static_cast<std::uint8_t>(l);
      for (unsigned slot = 0; slot < 8; ++slot) {
        const std::uint32_t g = loop[slot];
        if (g == kNone) continue;
        if (g < lo || g >= hi) {
          later.emplace_back(g, level);
          continue;
        }
        glevel_[g] = std::max(glevel_[g], level);
        gtop_[g] = std::min(gtop_[g], level);
      }
    }
  });
  for (const auto& list : across_halves) {
    for (const auto& [g, l] : list) {
      glevel_[g] = std::max(glevel_[g], l);
      gtop_[g] = std::min(gtop_[g], l);
    }
  }
  both_mids_ = std::move(both_mids_per_half[0]);
  both_mids_.insert(both_mids_.end(), both_mids_per_half[1].begin(), both_mids_per_half[1].end());
  // Dead from here on (own() is never called again; neither are the tree's look-ups, whose last
  // use is above): lent to the arrays made later (final_id_, cell_bound_, ...).
  spare_.lend(own_storage_.get(), own_storage_bytes());
  tree_.lend_hints(spare_);
}

void Builder::warp() {
  gwarped_.reserve(gpos_.capacity());
  gwarped_.assign(grid_count_, false);
  gmoved_.reserve(gpos_.capacity());
  gmoved_.assign(grid_count_, false);
  reserve_room(input_gv_, pts_.size());
  input_gv_.assign(pts_.size(), kNone);
  // Each leaf knows the input vertex in its half-open square (at most one: the splitting rule);
  // build_loops() listed the leaves with one, in order.
  for (const auto& half : with_vertex_) {
    for (const std::uint32_t k : half) {
      const Node& n = tree_.nodes[leaves_[k]];
      const VertexId v = tree_.vertex_id(n.vertex);
      const Point& q = tree_.vertex_point(n.vertex);
      unsigned qx = 0, qy = 0;
      tree_.nearest_corner(n, q, qx, qy);
      static constexpr unsigned kCornerSlot[2][2] = {{kBL, kTL}, {kBR, kTR}};  // [qx][qy]
      const std::uint32_t g = loop_of(k)[kCornerSlot[qx][qy]];
      if (gwarped_[g] || input_gv_[v] != kNone) throw RouteFailure{"two input vertices warp the same corner"};
      gwarped_[g] = true;
      gmoved_[g] = true;
      gpos_[g] = q;
      input_gv_[v] = g;
      ++stats_.warped;
    }
  }
  for (auto& half : with_vertex_) std::vector<std::uint32_t>().swap(half);
  for (VertexId v : in_.vertices) {
    if (input_gv_[v] == kNone) throw RouteFailure{"an input vertex lies in no leaf"};
  }
}

// Corners onto segments, crossing points, and the chains of subsegments.
void Builder::segments_pass() {
  if (in_.segments.empty()) return;
  const std::uint32_t nv = tree_.vertex_count();
  gon_segment_.reserve(gpos_.capacity());
  gon_segment_.assign(grid_count_, false);
  gsegment_.clear();
  // The leaves that have a segment in their list (the only ones the passes below look at), listed
  // by build_loops().
  std::vector<std::uint32_t> near = std::move(near_segment_[0]);
  near.insert(near.end(), near_segment_[1].begin(), near_segment_[1].end());
  for (auto& half : near_segment_) std::vector<std::uint32_t>().swap(half);
  // 1. Corners exactly on a segment join its chain where they are.
  for (const std::uint32_t k : near) {
    const Node& n = tree_.nodes[leaves_[k]];
    const std::array<std::uint32_t, 8> loop = loop_of(k);
    for (std::uint32_t i = 0; i < n.feat_count; ++i) {
      const std::uint32_t f = tree_.features[n.feat_begin + i];
      if (f < nv) continue;
      const std::uint32_t s = f - nv;
      const Point& a = pts_[in_.segments[s].a];
      const Point& b = pts_[in_.segments[s].b];
      for (unsigned slot = 0; slot < 8; ++slot) {
        const std::uint32_t g = loop[slot];
        if (g == kNone || gwarped_[g] || gon_segment_[g]) continue;
        const Point& p = gpos_[g];
        if (orient2d(a, b, p) != 0) continue;
        const bool between = a.x != b.x ? ((a.x < p.x && p.x < b.x) || (b.x < p.x && p.x < a.x))
                                        : ((a.y < p.y && p.y < b.y) || (b.y < p.y && p.y < a.y));
        if (!between) continue;
        set_segment(g, s);
        ++stats_.on_segment;
      }
    }
  }
  // 2. BEG's warp towards segments: corners close to a segment move onto it, so that no sliver
  //    is cut off a cell. Two moves, scored as a fraction of the leaf size; a corner takes the
  //    best-scoring one (each corner moves at most once):
  //    X. a segment crosses an edge uc of a leaf of size S at x with |x − c| < snap_fraction·S and
  //       |x − c| < |uc|/2: c moves to x, along the edge (the leaves on both sides of the edge keep
  //       at least half of it; the others only grow);
  //    P. a corner lies nearer to a segment than snap_fraction × its largest incident leaf and
  //       0.4 × its smallest: it moves to its projection (a segment running almost along the cell
  //       edges crosses none near the corner). Two ends of one edge can both move only if the
  //       edge meets the segment at less than asin(0.8), so they stay 0.3 of the edge apart.
  struct Choice {
    std::uint32_t segment;
    double fraction;
    Point target;
  };
  std::unordered_map<std::uint32_t, Choice> choice;
  auto offer = [&](std::uint32_t c, const Choice& candidate) {
    const auto [it, fresh] = choice.emplace(c, candidate);
    if (!fresh && (candidate.fraction < it->second.fraction ||
                   (candidate.fraction == it->second.fraction && candidate.segment < it->second.segment))) {
      it->second = candidate;
    }
  };
  // Moving corners changes which edges a segment crosses (a corner left beside the moved
  // neighbours may now lie right next to the segment), so the two rules run to a fixed point;
  // every corner moves at most once.
  for (int round = 0; round < 4; ++round) {
    choice.clear();
    // 2a. Crossings.
    for_each_crossed_edge(near, [&](std::uint32_t k, unsigned, std::uint32_t u, std::uint32_t w, std::uint32_t s,
                                    const Point& a, const Point& b) {
      // (The exact crossing rounded: a corner moved there lies on the segment within rounding.)
      const Point x = exact_crossing(gpos_[std::min(u, w)], gpos_[std::max(u, w)], a, b);
      const double length = distance(gpos_[u], gpos_[w]);
      const double size = tree_.cell_size(tree_.nodes[leaves_[k]].level);
      for (const std::uint32_t c : {u, w}) {
        if (gwarped_[c] || gon_segment_[c]) continue;
        const double along = distance(gpos_[c], x);
        if (!(along < options_.snap_fraction * size) || !(along < 0.5 * length)) continue;
        offer(c, {s, along / size, x});
      }
    });
    // 2b. Projections.
    for (const std::uint32_t k : near) {
      const Node& n = tree_.nodes[leaves_[k]];
      const std::array<std::uint32_t, 8> loop = loop_of(k);
      for (std::uint32_t i = 0; i < n.feat_count; ++i) {
        const std::uint32_t f = tree_.features[n.feat_begin + i];
        if (f < nv) continue;
        const std::uint32_t s = f - nv;
        const Point& a = pts_[in_.segments[s].a];
        const Point& b = pts_[in_.segments[s].b];
        const double dx = b.x - a.x, dy = b.y - a.y;
        for (unsigned slot = 0; slot < 8; ++slot) {
          const std::uint32_t g = loop[slot];
          if (g == kNone || gwarped_[g] || gon_segment_[g]) continue;
          const Point& p = gpos_[g];
          const double t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy);
          if (!(t > 0.0 && t < 1.0)) continue;
          const Point proj{a.x + t * dx, a.y + t * dy};
          const double d = distance(p, proj);
          const double size = tree_.cell_size(gtop_[g]);
          if (!(d < options_.snap_fraction * size) || !(d < 0.4 * tree_.cell_size(glevel_[g])) ||
              !(d < distance(proj, a)) || !(d < distance(proj, b))) {
            continue;
          }
          offer(g, {s, d / size, proj});
        }
      }
    }
    for (const auto& [g, c] : choice) {
      set_segment(g, c.segment);
      gpos_[g] = c.target;
      gmoved_[g] = true;
      ++stats_.snapped;
    }
    if (choice.empty()) break;
  }
  // 2. Crossing points: every leaf edge properly crossed by a segment of the leaf's list (edges
  //    ending on that segment only touch it). One vertex per (edge, segment), shared by both sides.
  std::unordered_map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>> made;
  for_each_crossed_edge(near, [&](std::uint32_t k, unsigned slot, std::uint32_t u, std::uint32_t w, std::uint32_t s,
                                  const Point& a, const Point& b) {
    const std::uint64_t key = (std::uint64_t{std::min(u, w)} << 32) | std::max(u, w);
    auto& list = made[key];
    std::uint32_t x = kNone;
    for (const auto& [seg, vertex] : list) {
      if (seg == s) x = vertex;
    }
    if (x == kNone) {
      x = static_cast<std::uint32_t>(gpos_.size());
      const Point& lo = gpos_[std::min(u, w)];
      const Point& hi = gpos_[std::max(u, w)];
      // The exact crossing rounded, as the CDT places crossings. A coordinate it puts below the
      // supported range (segment_intersection snapped it to 0, off the segment by more than the
      // rounding of its coordinates) sends the input to the fallback (out_of_range_vertex).
      gpos_.push_back(exact_crossing(lo, hi, a, b));
      gon_segment_.push_back(true);
      gsegment_[x] = s;
      gwarped_.push_back(false);
      gmoved_.push_back(true);
      list.emplace_back(s, x);
      ++stats_.crossings;
    }
    crossings_.push_back({k, slot, x});
  });
  std::sort(crossings_.begin(), crossings_.end(), [](const EdgeCrossing& p, const EdgeCrossing& q) {
    return p.leaf != q.leaf ? p.leaf < q.leaf : p.slot != q.slot ? p.slot < q.slot : p.vertex < q.vertex;
  });
  crossings_.erase(std::unique(crossings_.begin(), crossings_.end(),
                               [](const EdgeCrossing& p, const EdgeCrossing& q) {
                                 return p.leaf == q.leaf && p.slot == q.slot && p.vertex == q.vertex;
                               }),
                   crossings_.end());
  // 3. Chains: along each segment, its endpoints and the vertices on it, by position.
  std::vector<std::vector<std::uint32_t>> on(in_.segments.size());
  {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> placed(gsegment_.begin(), gsegment_.end());
    std::sort(placed.begin(), placed.end());  // (by vertex: the map's order is unspecified)
    for (const auto& [g, s] : placed) on[s].push_back(g);
  }
  for (std::uint32_t s = 0; s < in_.segments.size(); ++s) {
    const FeatureSegment& seg = in_.segments[s];
    const Point& a = pts_[seg.a];
    const Point& b = pts_[seg.b];
    const double dx = b.x - a.x, dy = b.y - a.y;
    auto param = [&](std::uint32_t g) { return (gpos_[g].x - a.x) * dx + (gpos_[g].y - a.y) * dy; };
    auto& list = on[s];
    std::sort(list.begin(), list.end(), [&](std::uint32_t p, std::uint32_t q) { return param(p) < param(q); });
    const std::uint32_t first = input_gv_[seg.a], last = input_gv_[seg.b];
    list.insert(list.begin(), first);
    list.push_back(last);
    for (std::size_t i = 0; i + 1 < list.size(); ++i) {
      if (!(param(list[i]) < param(list[i + 1]))) {
        throw RouteFailure{"two vertices at the same place on a segment"};
      }
      chain_links_.push_back({list[i], list[i + 1], s});
      chain_links_.push_back({list[i + 1], list[i], s});
      ++subsegment_count_;
    }
  }
  std::stable_sort(chain_links_.begin(), chain_links_.end(),
                   [](const ChainLink& p, const ChainLink& q) { return p.vertex < q.vertex; });
}

// The case table with its adjacency: for each midpoint mask, the triangles over polygon positions
// (the present slots in order) and, per triangle edge, either the polygon edge it lies on or the
// triangle edge across it inside the cell.
struct PlainCell {
  std::uint8_t slots[8];        // polygon position → slot
  std::uint8_t size = 0;        // polygon vertices
  std::uint8_t count = 0;       // triangles
  std::uint8_t tri[6][3];       // polygon positions, counter-clockwise
  std::int8_t boundary[6][3];   // polygon edge index or -1
  std::uint8_t twin[6][3];      // 3·triangle + edge across, for inner edges
  std::uint32_t sides = 0;      // polygon positions of BR, TR, TL (8 bits each)
  std::uint8_t edge[8];         // polygon edge → 3·triangle + edge on it
};

const std::array<PlainCell, 16>& plain_cells() {
  static const auto table = [] {
    std::array<PlainCell, 16> out{};
    const auto& cases = detail::quadtree_case_table();
    for (unsigned mask = 0; mask < 16; ++mask) {
      PlainCell& c = out[mask];
      std::uint8_t position[8] = {};
      for (std::uint8_t slot = 0; slot < 8; ++slot) {
        if ((slot & 1) != 0 && (mask & (1u << (slot / 2))) == 0) continue;
        position[slot] = c.size;
        c.slots[c.size++] = slot;
      }
      for (unsigned q = 0; q < c.size; ++q) {
        if (c.slots[q] == kBR) c.sides |= q;
        if (c.slots[q] == kTR) c.sides |= q << 8;
        if (c.slots[q] == kTL) c.sides |= q << 16;
      }
      c.count = static_cast<std::uint8_t>(cases[mask].size());
      for (std::size_t i = 0; i < cases[mask].size(); ++i) {
        for (unsigned k = 0; k < 3; ++k) c.tri[i][k] = position[cases[mask][i][k]];
      }
      for (unsigned i = 0; i < c.count; ++i) {
        for (unsigned e = 0; e < 3; ++e) {
          const unsigned from = c.tri[i][next3(e)], to = c.tri[i][prev3(e)];
          c.boundary[i][e] = (to == (from + 1u) % c.size) ? static_cast<std::int8_t>(from) : std::int8_t{-1};
          if (c.boundary[i][e] >= 0) {
            c.edge[from] = static_cast<std::uint8_t>(3 * i + e);
            continue;
          }
          for (unsigned j = 0; j < c.count; ++j) {
            for (unsigned f = 0; f < 3; ++f) {
              if (c.tri[j][next3(f)] == to && c.tri[j][prev3(f)] == from) c.twin[i][e] = static_cast<std::uint8_t>(3 * j + f);
            }
          }
        }
      }
    }
    return out;
  }();
  return table;
}

// One chunk of leaves prepared for emission (see triangulate_cells()): everything about a cell that
// depends only on its own loop and the vertex positions, computed ahead of the emitting pass.
struct Builder::PreparedChunk {
  std::uint32_t begin = 0, end = 0;                // leaves [begin, end)
  std::vector<std::uint8_t> kind;                  // per leaf: its case-table mask, or kSpecialCell
  std::vector<SpecialCell> special;                // the warped or cut leaves, in order
  std::vector<Tri> tris;                           // their triangles: grid ids or kCentre | j
  std::vector<std::uint32_t> twin;                 // per triangle edge: 3·j + f inside the cell, or kNone
  std::vector<std::uint32_t> bound_local;          // per polygon edge: 3·i + e of its triangle
  std::vector<Point> centres;                      // the cells' vertex-average Steiner points
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segment_edges;  // (3·i + e, segment)
  std::uint32_t fail_leaf = kNone;                 // the first leaf whose preparation threw
  std::exception_ptr error;
};

// triangulate_cells(): what one thread collects while writing its chunks, joined in chunk order.
struct Builder::EmitSink {
  std::vector<Point> centres;
  std::vector<Outer> outer;
  std::vector<std::pair<Handle, std::uint32_t>> segment_edges;
  std::size_t table_cells = 0, program_cells = 0;
};

void Builder::prepare_cells(const Mesh& mesh, PreparedChunk& out, std::uint32_t begin, std::uint32_t end,
                            std::size_t& next_crossing) const {
  auto pos = [&](std::uint32_t g) -> const Point& { return mesh.points[final_id_[g]]; };
  const auto& plain = plain_cells();
  out.begin = begin;
  out.end = end;
  out.fail_leaf = kNone;
  out.error = nullptr;
  // Scratch for the program cells.
  std::vector<std::uint32_t> poly;           // vertices of the cell polygon
  std::vector<std::array<std::uint8_t, 3>> local;
  std::vector<Point> sub_points;
  struct Chord {
    std::uint32_t i, j, segment;
  };
  std::vector<Chord> chords;
  std::vector<std::pair<std::vector<std::uint32_t>, std::vector<Chord>>> pieces;  // polygon indices
  constexpr std::size_t kSmallPolygon = 16;
  std::array<std::uint32_t, (kSmallPolygon + 1) * (kSmallPolygon + 1)> edge_at;  // (from, to) → 3·i + e
  std::uint32_t k = begin;
  try {
    out.kind.assign(end - begin, 0);
    out.special.clear();
    out.tris.clear();
    out.twin.clear();
    out.bound_local.clear();
    out.centres.clear();
    out.segment_edges.clear();
    for (; k < end; ++k) {
      const std::array<std::uint32_t, 8> loop = loop_of(k);
      // The cell's positions are read below through final ids, a cache miss each when the
      // vertex belongs to a leaf far away in leaf order or is an input point (in input order):
      // fetch the ids of the leaf 2·kAhead on and the positions of the leaf kAhead on (the own
      // midpoints follow the corner's id, and a top midpoint in both_mids_ is rare: the packed
      // words are enough).
      constexpr std::uint32_t kAhead = 16;
      const auto ahead_ids = [&](std::uint32_t j) {
        const PackedLoop& p = loops_[j];
        return std::array<std::uint32_t, 5>{p.head & kLoopIdMask, p.br, p.tr, p.tl, p.mid};
      };
      if (end - k > 2 * kAhead) {
        for (const std::uint32_t g : ahead_ids(k + 2 * kAhead)) {
          if (g != kNone) __builtin_prefetch(&final_id_[g]);
        }
      }
      if (end - k > kAhead) {
        for (const std::uint32_t g : ahead_ids(k + kAhead)) {
          if (g != kNone) __builtin_prefetch(&mesh.points[final_id_[g]]);
        }
      }
      // Crossings on this leaf's edges.
      const std::size_t cross_begin = next_crossing;
      while (next_crossing < crossings_.size() && crossings_[next_crossing].leaf == k) ++next_crossing;
      bool special = cross_begin != next_crossing;
      for (unsigned s = 0; s < 8 && !special; ++s) {
        const std::uint32_t g = loop[s];
        if (g != kNone && (gmoved_[g] || on_any_segment(g))) special = true;
      }
      if (!special) {
        // Untouched square: the case table (its triangles are checked here, emitted later).
        unsigned mask = 0;
        for (unsigned side = 0; side < 4; ++side) {
          if (loop[2 * side + 1] != kNone) mask |= 1u << side;
        }
        const PlainCell& c = plain[mask];
        // The table's triangles join boundary points of the cell, never three on one side, listed
        // counter-clockwise; so all are strictly counter-clockwise when the corners form an
        // axis-parallel rectangle and each midpoint lies strictly inside its side (exact
        // comparisons). Otherwise each triangle is checked with orient2d.
        const Point& bl = pos(loop[kBL]);
        const Point& br = pos(loop[kBR]);
        const Point& tr = pos(loop[kTR]);
        const Point& tl = pos(loop[kTL]);
        bool square = bl.y == br.y && tl.y == tr.y && bl.x == tl.x && br.x == tr.x && bl.x < br.x && bl.y < tl.y;
        // (A midpoint lies strictly inside the axis-parallel side a–b.)
        const auto inside_side = [&](unsigned slot, const Point& a, const Point& b) {
          const Point& p = pos(loop[slot]);
          return a.x == b.x ? p.x == a.x && std::min(a.y, b.y) < p.y && p.y < std::max(a.y, b.y)
                            : p.y == a.y && std::min(a.x, b.x) < p.x && p.x < std::max(a.x, b.x);
        };
        if (square && (mask & 1u) != 0) square = inside_side(kBottom, bl, br);
        if (square && (mask & 2u) != 0) square = inside_side(kRight, br, tr);
        if (square && (mask & 4u) != 0) square = inside_side(kTop, tl, tr);
        if (square && (mask & 8u) != 0) square = inside_side(kLeft, bl, tl);
        for (unsigned i = 0; i < c.count && !square; ++i) {
          if (orient2d(pos(loop[c.slots[c.tri[i][0]]]), pos(loop[c.slots[c.tri[i][1]]]),
                       pos(loop[c.slots[c.tri[i][2]]])) <= 0) {
            throw RouteFailure{"a cell triangle is not counter-clockwise"};
          }
        }
        out.kind[k - begin] = static_cast<std::uint8_t>(mask);
        continue;
      }
      out.kind[k - begin] = kSpecialCell;
      SpecialCell cell;
      cell.tri_begin = static_cast<std::uint32_t>(out.tris.size());
      cell.centre_begin = static_cast<std::uint32_t>(out.centres.size());
      cell.bound_begin = static_cast<std::uint32_t>(out.bound_local.size());
      cell.segment_begin = static_cast<std::uint32_t>(out.segment_edges.size());
      // The polygon: loop slots with the crossing points of each edge inserted in order.
      poly.clear();
      std::uint8_t side_index[4] = {0, 0, 0, 0};  // polygon index of BL, BR, TR, TL
      for (unsigned s = 0; s < 8; ++s) {
        if (loop[s] == kNone) continue;
        if ((s & 1) == 0) side_index[s / 2] = static_cast<std::uint8_t>(poly.size());
        poly.push_back(loop[s]);
        if (cross_begin == next_crossing) continue;
        const std::size_t before = poly.size();
        for (std::size_t c = cross_begin; c < next_crossing; ++c) {
          if (crossings_[c].slot == s) poly.push_back(crossings_[c].vertex);
        }
        if (poly.size() - before > 1) {
          const Point origin = pos(loop[s]);
          std::sort(poly.begin() + static_cast<std::ptrdiff_t>(before), poly.end(), [&](std::uint32_t p, std::uint32_t q) {
            return squared_distance(origin, pos(p)) < squared_distance(origin, pos(q));
          });
        }
      }
      if (poly.size() > 250) throw RouteFailure{"a cell has too many boundary vertices"};
      // Chords: consecutive chain vertices that are both on this polygon and not adjacent on it.
      chords.clear();
      const std::size_t m = poly.size();
      for (std::size_t i = 0; i < m; ++i) {
        if (!in_chain(poly[i])) continue;
        const auto [links_begin, links_end] = chain_of(poly[i]);
        for (const ChainLink* link = links_begin; link != links_end; ++link) {
          const std::uint32_t other = link->other, s = link->segment;
          for (std::size_t j = i + 1; j < m; ++j) {
            if (poly[j] != other) continue;
            const bool adjacent = j == i + 1 || (i == 0 && j == m - 1);
            if (adjacent) continue;  // a boundary edge on the segment: marked below
            chords.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), s});
          }
        }
      }
      // Triangulates one piece, given as polygon indices (counter-clockwise).
      auto triangulate = [&](const std::uint32_t* index, std::size_t count) {
        sub_points.clear();
        for (std::size_t i = 0; i < count; ++i) sub_points.push_back(pos(poly[index[i]]));
        local.clear();
        Point centre;
        bool used_centre = false;
        if (!detail::triangulate_piece(sub_points, local, centre, used_centre)) {
          throw RouteFailure{"a warped or cut cell has no valid triangulation"};
        }
        std::uint32_t centre_id = kNone;
        if (used_centre) {
          // BEG add such points to distorted cells; it lifts the worst warped point-set cell from
          // 13.4° to 18.3° (tests/test_quadtree.cpp enumerates the configurations).
          centre_id = kCentre | (static_cast<std::uint32_t>(out.centres.size()) - cell.centre_begin);
          out.centres.push_back(centre);
        }
        for (const auto& t : local) {
          Tri v;
          for (unsigned c = 0; c < 3; ++c) v[c] = t[c] == count ? centre_id : poly[index[t[c]]];
          out.tris.push_back(v);
        }
      };
      if (chords.empty()) {
        // A warped cell: one piece.
        static constexpr auto kIdentity = [] {
          std::array<std::uint32_t, 256> a{};
          for (std::uint32_t i = 0; i < 256; ++i) a[i] = i;
          return a;
        }();
        triangulate(kIdentity.data(), m);
      } else {
        // Cut the polygon along the chords, then triangulate each piece.
        pieces.clear();
        std::vector<std::uint32_t> all(m);
        for (std::uint32_t i = 0; i < m; ++i) all[i] = i;
        pieces.emplace_back(std::move(all), chords);
        for (std::size_t p = 0; p < pieces.size(); ++p) {
          while (!pieces[p].second.empty()) {
            const Chord c = pieces[p].second.back();
            pieces[p].second.pop_back();
            const std::vector<std::uint32_t> idx = pieces[p].first;
            const auto pi = std::find(idx.begin(), idx.end(), c.i) - idx.begin();
            const auto pj = std::find(idx.begin(), idx.end(), c.j) - idx.begin();
            if (pi == static_cast<std::ptrdiff_t>(idx.size()) || pj == static_cast<std::ptrdiff_t>(idx.size())) {
              throw RouteFailure{"a chord leaves its piece"};
            }
            std::vector<std::uint32_t> one, two;
            for (auto q = pi;; q = (q + 1) % static_cast<std::ptrdiff_t>(idx.size())) {
              one.push_back(idx[static_cast<std::size_t>(q)]);
              if (q == pj) break;
            }
            for (auto q = pj;; q = (q + 1) % static_cast<std::ptrdiff_t>(idx.size())) {
              two.push_back(idx[static_cast<std::size_t>(q)]);
              if (q == pi) break;
            }
            std::vector<Chord> rest_one, rest_two;
            for (const Chord& d : pieces[p].second) {
              const bool in_one = std::find(one.begin(), one.end(), d.i) != one.end() &&
                                  std::find(one.begin(), one.end(), d.j) != one.end();
              const bool in_two = std::find(two.begin(), two.end(), d.i) != two.end() &&
                                  std::find(two.begin(), two.end(), d.j) != two.end();
              if (in_one) {
                rest_one.push_back(d);
              } else if (in_two) {
                rest_two.push_back(d);
              } else {
                throw RouteFailure{"crossing chords in a cell"};
              }
            }
            pieces[p] = {std::move(one), std::move(rest_one)};
            pieces.emplace_back(std::move(two), std::move(rest_two));
          }
        }
        for (const auto& piece : pieces) triangulate(piece.first.data(), piece.first.size());
      }
      // The edges inside the cell and the boundary edges. (Every triangle is strictly
      // counter-clockwise: triangulate_piece() checked each one exactly.)
      const Tri* tris = out.tris.data() + cell.tri_begin;
      const auto count = static_cast<std::uint32_t>(out.tris.size() - cell.tri_begin);
      out.twin.resize(out.twin.size() + 3 * std::size_t{count}, kNone);
      out.bound_local.resize(out.bound_local.size() + m, kNone);
      std::uint32_t* twin = out.twin.data() + 3 * std::size_t{cell.tri_begin};
      std::uint32_t* bound = out.bound_local.data() + cell.bound_begin;
      if (chords.empty() && m <= kSmallPolygon) {
        // One piece (a warped cell): its triangles in `local` are over polygon positions, m for
        // the centre, so an edge from → to is on the boundary when to follows from, and the edge
        // across an inner one is found in a table by its ends.
        const std::size_t width = m + 1;
        std::fill(edge_at.begin(), edge_at.begin() + static_cast<std::ptrdiff_t>(width * width), kNone);
        for (std::uint32_t i = 0; i < count; ++i) {
          for (unsigned e = 0; e < 3; ++e) {
            const std::size_t from = local[i][next3(e)], to = local[i][prev3(e)];
            std::uint32_t& slot = from < m && to == (from + 1 == m ? 0 : from + 1) ? bound[from] : edge_at[from * width + to];
            if (slot != kNone) throw RouteFailure{"a cell triangulation is not closed"};
            slot = 3 * i + e;
          }
        }
        for (std::uint32_t i = 0; i < count; ++i) {
          for (unsigned e = 0; e < 3; ++e) {
            const std::size_t from = local[i][next3(e)], to = local[i][prev3(e)];
            if (from < m && to == (from + 1 == m ? 0 : from + 1)) continue;
            const std::uint32_t across = edge_at[to * width + from];
            if (across == kNone) throw RouteFailure{"a cell triangulation is not closed"};
            twin[3 * i + e] = across;
          }
        }
      } else {
        for (std::uint32_t i = 0; i < count; ++i) {
          for (unsigned e = 0; e < 3; ++e) {
            // Edge e of triangle i runs from corner e+1 to corner e+2.
            const std::uint32_t from = tris[i][next3(e)], to = tris[i][prev3(e)];
            // A polygon edge?
            bool boundary = false;
            for (std::size_t q = 0; q < m; ++q) {
              if (poly[q] == from && poly[q + 1 == m ? 0 : q + 1] == to) {
                bound[q] = 3 * i + e;
                boundary = true;
                break;
              }
            }
            if (boundary || twin[3 * i + e] != kNone) continue;
            for (std::uint32_t j = i + 1; j < count && twin[3 * i + e] == kNone; ++j) {
              for (unsigned f = 0; f < 3; ++f) {
                if (tris[j][next3(f)] == to && tris[j][prev3(f)] == from) {
                  twin[3 * i + e] = 3 * j + f;
                  twin[3 * j + f] = 3 * i + e;
                  break;
                }
              }
            }
            if (twin[3 * i + e] == kNone) throw RouteFailure{"a cell triangulation is not closed"};
          }
        }
      }
      for (std::size_t q = 0; q < m; ++q) {
        if (bound[q] == kNone) throw RouteFailure{"a cell boundary edge has no triangle"};
      }
      // Segment edges: chords and boundary edges between consecutive chain vertices.
      if (!chain_links_.empty()) {
        for (std::uint32_t i = 0; i < count; ++i) {
          for (unsigned e = 0; e < 3; ++e) {
            const std::uint32_t from = tris[i][next3(e)], to = tris[i][prev3(e)];
            if ((from & kCentre) != 0 || !in_chain(from)) continue;
            const auto [links_begin, links_end] = chain_of(from);
            for (const ChainLink* link = links_begin; link != links_end; ++link) {
              if (link->other == to) out.segment_edges.emplace_back(3 * i + e, link->segment);
            }
          }
        }
      }
      cell.tri_count = count;
      cell.centre_count = static_cast<std::uint32_t>(out.centres.size()) - cell.centre_begin;
      cell.bound_count = static_cast<std::uint32_t>(m);
      cell.segment_count = static_cast<std::uint32_t>(out.segment_edges.size()) - cell.segment_begin;
      cell.sides = static_cast<std::uint32_t>(side_index[1]) | (static_cast<std::uint32_t>(side_index[2]) << 8) |
                   (static_cast<std::uint32_t>(side_index[3]) << 16);
      out.special.push_back(cell);
    }
  } catch (...) {
    out.fail_leaf = k;
    out.error = std::current_exception();
  }
}

// Writes the prepared cells of leaves [in.begin, end) at their places: triangles from `first`
// (tris points at triangle 0), the warped and cut cells' boundary edges from `first_bound` (bound
// points at bound_[0]; a table cell's follow from the table, see CellBound),
// centres numbered from centre_first; the centres, segment edges and counts go to `sink`.
void Builder::emit_cells(const PreparedChunk& in, std::uint32_t end, Triangle* tris, TriangleId first,
                         Handle* bound, std::uint32_t first_bound, VertexId centre_first, EmitSink& sink) {
  const auto& plain = plain_cells();
  std::size_t next_special = 0;
  for (std::uint32_t k = in.begin; k < end; ++k) {
    const std::array<std::uint32_t, 8> loop = loop_of(k);
    const std::uint8_t kind = in.kind[k - in.begin];
    Handle* cell_bound = bound + first_bound;
    Triangle* out = tris + first;
    if (kind != kSpecialCell) {
      // Untouched square: the case table, with its adjacency.
      const PlainCell& c = plain[kind];
      for (unsigned i = 0; i < c.count; ++i) {
        Triangle t{{final_id_[loop[c.slots[c.tri[i][0]]]], final_id_[loop[c.slots[c.tri[i][1]]]],
                    final_id_[loop[c.slots[c.tri[i][2]]]]},
                   {kNone, kNone, kNone}};
        for (unsigned e = 0; e < 3; ++e) {
          if (c.boundary[i][e] < 0) t.n[e] = make_handle(first + c.twin[i][e] / 3u, c.twin[i][e] % 3u);
        }
        out[i] = t;
      }
      cell_bound_[k] = {kTableCell | first, kind};
      first += c.count;
      ++sink.table_cells;
      continue;
    }
    const SpecialCell& cell = in.special[next_special++];
    ++sink.program_cells;
    // The cell's centres become vertices after all grid vertices, in leaf order.
    for (std::uint32_t j = 0; j < cell.centre_count; ++j) sink.centres.push_back(in.centres[cell.centre_begin + j]);
    const Tri* cell_tris = in.tris.data() + cell.tri_begin;
    const std::uint32_t* twin = in.twin.data() + 3 * std::size_t{cell.tri_begin};
    for (std::uint32_t i = 0; i < cell.tri_count; ++i) {
      Triangle t{{0, 0, 0}, {kNone, kNone, kNone}};
      for (unsigned c = 0; c < 3; ++c) {
        const std::uint32_t g = cell_tris[i][c];
        t.v[c] = (g & kCentre) != 0 ? centre_first + (g & ~kCentre) : final_id_[g];
      }
      for (unsigned e = 0; e < 3; ++e) {
        const std::uint32_t w = twin[3 * i + e];
        if (w != kNone) t.n[e] = make_handle(first + w / 3u, w % 3u);
      }
      out[i] = t;
    }
    for (std::uint32_t q = 0; q < cell.bound_count; ++q) {
      const std::uint32_t b = in.bound_local[cell.bound_begin + q];
      cell_bound[q] = make_handle(first + b / 3u, b % 3u);
    }
    cell_bound_[k] = {first_bound, cell.sides | (cell.bound_count << 24)};
    for (std::uint32_t s = 0; s < cell.segment_count; ++s) {
      const auto& [local_edge, segment] = in.segment_edges[cell.segment_begin + s];
      sink.segment_edges.emplace_back(make_handle(first + local_edge / 3u, local_edge % 3u), segment);
    }
    first += cell.tri_count;
    first_bound += cell.bound_count;
    centre_first += cell.centre_count;
  }
}

// Cells are triangulated in chunks of leaves, each in three steps: prepare_cells() computes each
// leaf's triangles, their adjacency inside the cell and their exact checks (the dynamic program of
// the warped and cut cells is most of the work); emit_cells() writes them into the mesh at their
// places; link_cell() links each cell to the cells across its left and bottom sides, which come
// earlier in leaf order. The places are prefix sums in leaf order (triangles, boundary edges,
// centres), so the ids are those of one pass over the leaves in order.
//
// On a large tree two threads take the chunks alternately (even, odd) and do all three steps for
// theirs, so the writing (page faults included) is shared too. A chunk takes its places (and
// extends the arrays within their room, zero-filling only its own range) when the chunk before it
// has taken its own: a token passed in chunk order. A chunk is linked once every earlier chunk is
// written (in practice after its thread has written its next chunk, so that the threads rarely
// wait for each other): a link writes the neighbour slots of the two triangles of one shared edge,
// each edge once, so the threads never write the same place. Per-chunk lists (centres, border
// edges, segment edges) are joined in chunk order at the end. The output does not depend on the
// timing. If a check fails or the room runs out, everything is redone on one thread, so the
// reported failure is the first in leaf order, as in a single pass.
void Builder::triangulate_cells(Mesh& mesh) {
  if (final_id_.size() >= kCentre) throw RouteFailure{"too many grid vertices"};
  const auto leaf_count = static_cast<std::uint32_t>(leaves_.size());
  constexpr std::uint32_t kChunk = 4096;
  const std::uint32_t chunks = (leaf_count + kChunk - 1) / kChunk;
  const unsigned threads = leaf_count < threaded_leaves_ || chunks < 2 ? 1u : 2u;
  if (!cell_bound_) cell_bound_ = make_spare_array<CellBound>(spare_, leaves_.size());  // (emit_cells())
  centre_base_ = mesh.points.size();
  // Room (address space only until written) past what the cells need, about 2.5 triangles per leaf
  // and 6 boundary edges per warped or cut leaf, so that the two threads can extend the arrays in
  // place.
  const std::size_t triangle_room = std::max(mesh.triangles.capacity(), leaves_.size() * 4);

  auto attempt = [&](unsigned thread_count) {
    mesh.triangles.clear();
    reserve_room(mesh.triangles, triangle_room);
    bound_.clear();
    reserve_room(bound_, leaves_.size() * 6);
    // Per chunk: its centres, border edges and segment edges (in its thread's sink).
    std::vector<std::array<std::uint32_t, 3>> chunk_counts(chunks);
    std::array<EmitSink, 2> sinks;
    std::atomic<std::uint32_t> token{0};
    std::array<std::atomic<std::uint32_t>, 2> written{};  // chunks each thread has written
    std::atomic<bool> stop{false};
    constexpr std::uint32_t kStopped = std::numeric_limits<std::uint32_t>::max();
    // Shared under the token: the arrays' ends and bases.
    std::size_t tri_end = 0, bound_end = 0, centre_end = 0;
    Triangle* tri_base = mesh.triangles.data();
    Handle* bound_base = bound_.data();
    // The other thread u's chunks below chunk c.
    auto below = [&](unsigned u, std::uint32_t c) -> std::uint32_t {
      if (thread_count == 1) return 0;
      return c > u ? (c - u + 1) / 2 : 0;
    };
    // Waits until `value` reaches `target` (false when stopped).
    auto wait_for = [&](std::atomic<std::uint32_t>& value, std::uint32_t target) {
      for (;;) {
        const std::uint32_t v = value.load(std::memory_order_acquire);
        if (stop.load(std::memory_order_acquire)) return false;
        if (v >= target) return true;
        value.wait(v, std::memory_order_acquire);
      }
    };
    auto work = [&](unsigned t) {
      const auto& plain = plain_cells();
      PreparedChunk chunk;
      EmitSink& sink = sinks[t];
      const unsigned u = 1 - t;
      const bool alone = thread_count == 1;
      // Links the leaves [begin, end) of chunk c, once every earlier chunk is written.
      auto link = [&](std::uint32_t c, std::uint32_t begin, std::uint32_t end) {
        if (!wait_for(written[u], below(u, c))) return false;
        const std::size_t outer_before = sink.outer.size();
        for (std::uint32_t k = begin; k < end; ++k) link_cell(mesh.points, tri_base, bound_base, k, sink);
        chunk_counts[c][1] = static_cast<std::uint32_t>(sink.outer.size() - outer_before);
        return true;
      };
      // On two threads a chunk is linked after the thread's next one is written, so that a
      // thread rarely waits for the other.
      std::uint32_t pending = kNone;
      for (std::uint32_t c = t; c < chunks; c += thread_count) {
        const std::uint32_t begin = c * kChunk, end = std::min(leaf_count, begin + kChunk);
        std::size_t next_crossing = static_cast<std::size_t>(
            std::lower_bound(crossings_.begin(), crossings_.end(), begin,
                             [](const EdgeCrossing& x, std::uint32_t leaf) { return x.leaf < leaf; }) -
            crossings_.begin());
        prepare_cells(mesh, chunk, begin, end, next_crossing);
        if (chunk.error && !alone) std::rethrow_exception(chunk.error);
        // A failed preparation still writes and links the leaves before it (their failures come first).
        const std::uint32_t limit = chunk.error ? chunk.fail_leaf : end;
        std::size_t tri_count = 0, bound_count = 0;
        for (std::uint32_t k = begin, j = 0; k < limit; ++k) {
          const std::uint8_t kind = chunk.kind[k - begin];
          if (kind != kSpecialCell) {
            tri_count += plain[kind].count;
          } else {
            tri_count += chunk.special[j].tri_count;
            bound_count += chunk.special[j].bound_count;
            ++j;
          }
        }
        std::size_t centre_count = 0;  // (a failed cell is not in chunk.special)
        for (const SpecialCell& cell : chunk.special) centre_count += cell.centre_count;
        // Take the places (growing the arrays past their room only on one thread).
        if (!wait_for(token, c)) return;
        if (tri_end + tri_count > mesh.triangles.capacity() || bound_end + bound_count > bound_.capacity()) {
          if (!alone) throw RouteFailure{"out of room"};  // (redone on one thread)
          mesh.triangles.reserve(std::max(tri_end + tri_count, mesh.triangles.capacity() / 2 * 3));
          bound_.reserve(std::max(bound_end + bound_count, bound_.capacity() / 2 * 3));
        }
        const auto first = static_cast<TriangleId>(tri_end);
        const auto first_bound = static_cast<std::uint32_t>(bound_end);
        const auto centre_first = static_cast<VertexId>(centre_base_ + centre_end);
        tri_end += tri_count;
        bound_end += bound_count;
        centre_end += centre_count;
        // (Below kTableCell, which marks triangle ids in cell_bound_.)
        if (tri_end >= kInfinite / 4 || bound_end >= kTableCell) throw RouteFailure{"too many triangles"};
        mesh.triangles.resize(tri_end);
        bound_.resize(bound_end);
        if (alone) {
          tri_base = mesh.triangles.data();
          bound_base = bound_.data();
        }
        token.store(c + 1, std::memory_order_release);
        token.notify_all();
        const std::size_t centres_before = sink.centres.size(), segments_before = sink.segment_edges.size();
        emit_cells(chunk, limit, tri_base, first, bound_base, first_bound, centre_first, sink);
        chunk_counts[c][0] = static_cast<std::uint32_t>(sink.centres.size() - centres_before);
        chunk_counts[c][2] = static_cast<std::uint32_t>(sink.segment_edges.size() - segments_before);
        written[t].fetch_add(1, std::memory_order_acq_rel);
        written[t].notify_all();
        if (alone) {
          link(c, begin, limit);
          if (chunk.error) std::rethrow_exception(chunk.error);
          continue;
        }
        if (pending != kNone && !link(pending, pending * kChunk, pending * kChunk + kChunk)) return;
        pending = c;
      }
      if (pending != kNone) link(pending, pending * kChunk, std::min(leaf_count, pending * kChunk + kChunk));
    };
    if (thread_count == 1) {
      work(0);
    } else {
      std::array<std::exception_ptr, 2> error;
      auto guarded = [&](unsigned t) {
        try {
          work(t);
        } catch (...) {
          error[t] = std::current_exception();
          stop.store(true, std::memory_order_seq_cst);
          for (auto* a : {&token, &written[0], &written[1]}) {
            a->store(kStopped, std::memory_order_seq_cst);
            a->notify_all();
          }
        }
      };
      {
        std::jthread worker([&] { guarded(1); });
        guarded(0);
      }
      if (error[0] || error[1]) return false;
    }
    // Join the per-chunk lists in chunk order.
    std::array<std::size_t, 2> at_centre{}, at_outer{}, at_segment{};
    outer_.clear();
    segment_edges_.clear();
    centre_points_.clear();
    for (std::uint32_t c = 0; c < chunks; ++c) {
      const unsigned t = c % thread_count;
      const EmitSink& s = sinks[t];
      const auto [centres, outer, segments] = chunk_counts[c];
      centre_points_.insert(centre_points_.end(), s.centres.begin() + static_cast<std::ptrdiff_t>(at_centre[t]),
                            s.centres.begin() + static_cast<std::ptrdiff_t>(at_centre[t] + centres));
      outer_.insert(outer_.end(), s.outer.begin() + static_cast<std::ptrdiff_t>(at_outer[t]),
                    s.outer.begin() + static_cast<std::ptrdiff_t>(at_outer[t] + outer));
      segment_edges_.insert(segment_edges_.end(), s.segment_edges.begin() + static_cast<std::ptrdiff_t>(at_segment[t]),
                            s.segment_edges.begin() + static_cast<std::ptrdiff_t>(at_segment[t] + segments));
      at_centre[t] += centres;
      at_outer[t] += outer;
      at_segment[t] += segments;
    }
    for (const EmitSink& s : sinks) {
      stats_.table_cells += s.table_cells;
      stats_.program_cells += s.program_cells;
    }
    stats_.centres += centre_points_.size();
    return true;
  };
  // A failure on two threads: redo on one, which throws the first failure in leaf order.
  if (!attempt(threads)) attempt(1);
  // The centres, after all grid vertices (their grid ids follow the grid's, as before).
  for (const Point& p : centre_points_) {
    gwarped_.push_back(false);
    gmoved_.push_back(true);
    if (!gon_segment_.empty()) gon_segment_.push_back(false);
    final_id_.push_back(mesh.add_vertex(p, VertexKind::kSteiner, 0));
  }
  std::vector<Point>().swap(centre_points_);
  west_south_.reset();
  leaf_shape_.reset();
}

// The edges of a leaf on one side: its polygon edges [begin, end), read from the case table (a
// table cell) or from bound_ (a warped or cut cell).
struct Builder::CellSide {
  std::uint32_t begin = 0, end = 0;
  std::uint32_t base = 0;               // a table cell's first triangle, else its first entry in bound_
  const std::uint8_t* table = nullptr;  // a table cell's PlainCell::edge
  Handle edge(const Handle* bound, std::uint32_t q) const {
    if (table != nullptr) return make_handle(base + table[q] / 3u, table[q] % 3u);
    return bound[base + q];
  }
};

// Edges of leaf k on side `side` (0 bottom, 1 right, 2 top, 3 left).
Builder::CellSide Builder::cell_side(std::uint32_t k, unsigned side) const {
  const CellBound b = cell_bound_[k];
  if ((b.begin & kTableCell) != 0) {
    const PlainCell& c = plain_cells()[b.sides];
    const std::uint32_t at[5] = {0, c.sides & 0xFFu, (c.sides >> 8) & 0xFFu, (c.sides >> 16) & 0xFFu, c.size};
    return {at[side], at[side + 1], b.begin & ~kTableCell, c.edge};
  }
  const std::uint32_t s = b.sides;
  const std::uint32_t at[5] = {0, s & 0xFFu, (s >> 8) & 0xFFu, (s >> 16) & 0xFFu, s >> 24};
  return {at[side], at[side + 1], b.begin, nullptr};
}

// Links the bottom and left sides of leaf k to the leaves across them, which come earlier in
// Morton order (the order is monotone in x and in y) and so are written already; collects the
// sides on the root's border for close_border(). (Through the arrays' bases: another thread may
// be growing them meanwhile, within their room.)
void Builder::link_cell(const std::vector<Point>& points, Triangle* tris, const Handle* bound, std::uint32_t k,
                        EmitSink& sink) const {
  const unsigned shape = leaf_shape_[k];
  const double root = tree_.cell_size(0);
  const Point o{tree_.X(0, 0), tree_.Y(0, 0)};
  auto org = [&](Handle h) { return tris[h >> 2].v[next3(h & 3)]; };
  auto dest = [&](Handle h) { return tris[h >> 2].v[prev3(h & 3)]; };
  // Position along the root's border, counter-clockwise from its lower-left corner.
  auto perimeter = [&](const Point& p, unsigned side) {
    switch (side) {
      case 0: return p.x - o.x;
      case 1: return root + (p.y - o.y);
      case 2: return 2 * root + (o.x + root - p.x);
      default: return 3 * root + (o.y + root - p.y);
    }
  };
  std::uint32_t across[2];
  for (unsigned side = 0; side < 4; ++side) {
    const bool border = ((shape >> (8 + side)) & 1u) != 0;
    const CellSide own = cell_side(k, side);
    if (border) {
      for (std::uint32_t q = own.begin; q < own.end; ++q) {
        const Handle h = own.edge(bound, q);
        sink.outer.push_back({perimeter(points[org(h)], side), h});
      }
      continue;
    }
    // Each shared side is linked once, from the leaf on its right or top (sides left, bottom).
    if (side != 0 && side != 3) continue;
    const std::uint32_t r = west_south_[k][side == 0 ? 1 : 0];
    const bool split = ((shape >> (side == 0 ? 7 : 6)) & 1u) != 0;  // a split cell of the same size
    std::size_t count = 0;
    const bool ordinals = ((shape >> (side == 0 ? 13 : 12)) & 1u) != 0;
    if (ordinals) {
      // The leaves across, numbered in number_vertices(): one, or the split cell's two along this
      // side (its SE and NE children for the left side, NW and NE for the bottom).
      across[0] = r;
      across[1] = r + (side == 3 ? 2u : 1u);
      count = split ? 2 : 1;
    } else if (split) {  // two leaves, their ordinals in split_across_ (number_vertices())
      const std::array<std::uint32_t, 2>& pair = split_across_[k < split_half_ ? 0 : 1][r];
      across[0] = pair[0];
      across[1] = pair[1];
      count = 2;
    } else {
      throw RouteFailure{"no cell across a side off the root's border"};
    }
    const unsigned opposite = side == 3 ? 1u : 2u;
    for (std::uint32_t q = own.begin; q < own.end; ++q) {
      const Handle h = own.edge(bound, q);
      const VertexId from = org(h), to = dest(h);
      bool linked = false;
      for (std::size_t c = 0; c < count && !linked; ++c) {
        const std::uint32_t other = across[c];
        if (other == kNone || other >= k) throw RouteFailure{"unbalanced quadtree"};
        const CellSide across_side = cell_side(other, opposite);
        for (std::uint32_t p = across_side.begin; p < across_side.end; ++p) {
          const Handle g = across_side.edge(bound, p);
          if (org(g) == to && dest(g) == from) {
            tris[h >> 2].n[h & 3] = g;
            tris[g >> 2].n[g & 3] = h;
            linked = true;
            break;
          }
        }
      }
      if (!linked) throw RouteFailure{"neighbouring cells do not share an edge"};
    }
  }
}

void Builder::close_border(Mesh& mesh) {
  auto& outer = outer_;
  // Ghost triangles around the root square (its border is the convex hull).
  std::sort(outer.begin(), outer.end(), [](const Outer& p, const Outer& q) { return p.position < q.position; });
  const auto first = static_cast<TriangleId>(mesh.triangles.size());
  const std::size_t count = outer.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Handle h = outer[i].handle;  // u→w, the root inside on its left
    // Ghost (w, u, ∞): edge 2 is w→u.
    mesh.triangles.push_back(Triangle{{mesh.dest(h), mesh.org(h), kInfinite}, {kNone, kNone, kNone}});
    const TriangleId g = first + static_cast<TriangleId>(i);
    mesh.triangles[g].n[2] = h;
    mesh.triangles[h >> 2].n[h & 3] = make_handle(g, 2);
  }
  for (std::size_t i = 0; i < count; ++i) {
    // Consecutive border edges e_i = u→w and e_{i+1} = w→x: ghost (x, w, ∞) edge 0 (w→∞) faces
    // ghost (w, u, ∞) edge 1 (∞→w).
    const TriangleId g = first + static_cast<TriangleId>(i);
    const TriangleId next = first + static_cast<TriangleId>((i + 1) % count);
    if (mesh.triangles[next].v[1] != mesh.triangles[g].v[0]) throw RouteFailure{"the root border is not closed"};
    mesh.triangles[next].n[0] = make_handle(g, 1);
    mesh.triangles[g].n[1] = make_handle(next, 0);
  }
  mesh.flags.assign(mesh.triangles.size(), 0);
}

void Builder::mark_segments(Mesh& mesh) {
  // Every subsegment must be one edge of the mesh (found from one or both sides).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> seen;
  bool any_marked = false;
  for (const FeatureSegment& s : in_.segments) any_marked = any_marked || !s.hull_only;
  if (any_marked) mesh.segment_marker.assign(3 * mesh.triangles.size(), 0);
  for (const auto& [h, s] : segment_edges_) {
    const FeatureSegment& seg = in_.segments[s];
    const Handle t = mesh.sym(h);
    const auto bit_h = static_cast<std::uint8_t>(kSegmentEdge0 << (h & 3));
    const auto bit_t = static_cast<std::uint8_t>(kSegmentEdge0 << (t & 3));
    mesh.flags[h >> 2] = static_cast<std::uint8_t>(mesh.flags[h >> 2] | bit_h);
    mesh.flags[t >> 2] = static_cast<std::uint8_t>(mesh.flags[t >> 2] | bit_t);
    if (any_marked) {
      const std::int32_t marker = seg.hull_only ? 0 : seg.marker;
      mesh.segment_marker[3 * (h >> 2) + (h & 3)] = marker;
      mesh.segment_marker[3 * (t >> 2) + (t & 3)] = marker;
    }
    const VertexId u = mesh.org(h), w = mesh.dest(h);
    seen.emplace_back((std::uint64_t{std::min(u, w)} << 32) | std::max(u, w), s);
  }
  std::sort(seen.begin(), seen.end());
  seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
  if (seen.size() != subsegment_count_) throw RouteFailure{"a subsegment is not an edge of the mesh"};
}

void Builder::refuse_rounded_sliver(const Mesh& mesh) const {
  double moved = 0.0;  // bound on the area between the subsegments and their segments
  for (const auto& [h, s] : segment_edges_) {
    const Point& sa = pts_[in_.segments[s].a];
    const Point& sb = pts_[in_.segments[s].b];
    const Point& pa = mesh.points[mesh.org(h)];
    const Point& pb = mesh.points[mesh.dest(h)];
    // |sa sb| times a point's distance to the segment's line (exactly 0 on it): twice the area
    // of the triangle it makes with the segment.
    const double off = 2.0 * std::max(std::fabs(signed_area(sa, sb, pa)), std::fabs(signed_area(sa, sb, pb)));
    if (off == 0.0) continue;
    // (The 13 data sets give moved / area of 2e-16 to 1.2e-15, the slivers that fail 1e-2 to 1e-1.)
    moved += distance(pa, pb) * off / distance(sa, sb);
  }
  // (The input domain's area: the mesh's differs from it by the rounding bounded here.)
  if (moved > kBoundaryRoundingShare * in_.domain_area) {
    throw RouteFailure{"the domain is a sliver thinner than the rounding of points on its segments", false};
  }
}

// Hole seeds that fall exactly on a quadtree vertex (round coordinates meet the aligned grid
// often) are moved into a triangle around it; the CDT has no vertex there, so for it the seed lies
// in a triangle. Seeds on input vertices stay (carve warns about them, as for the CDT).
std::vector<Point> movable_seeds(const Mesh& mesh, const std::vector<Point>& holes) {
  std::vector<Point> out;
  for (const Point& p : holes) {
    if (!in_supported_range(p)) {
      out.push_back(p);
      continue;
    }
    const Location loc = mesh.locate(p);
    const VertexId v = loc.kind == Location::Kind::kOnVertex ? mesh.org(loc.handle) : kInfinite;
    if (v == kInfinite || v < mesh.input_vertex_count || mesh.vertex_kind[v] != VertexKind::kSteiner) {
      out.push_back(p);
      continue;
    }
    Point moved = p;
    Handle h = loc.handle;
    do {
      const TriangleId t = h >> 2;
      if (!mesh.is_ghost(t)) {
        if (const std::optional<Point> g = inner_centroid(mesh, t)) {
          moved = *g;
          break;
        }
      }
      h = mesh.onext(h);
    } while (h != loc.handle);
    out.push_back(moved);
  }
  return out;
}

Mesh Builder::run(const std::vector<Point>& holes) {
  const auto t0 = Clock::now();
  number_vertices();
  build_loops();
  // The arrays the mesh is written into are allocated, and their pages first touched (the kernel
  // clears each page on its first write), by a helper thread while warp() and segments_pass() run
  // on this one, which leaves the second core idle otherwise (small trees: in line); this thread
  // joins the touching of the cells' arrays when it is done. Only pages the mesh surely uses (at
  // least 2 triangles per cell; the warped and cut cells' boundary edges fault in as written) are
  // touched, and every element is written later, so the output does not depend on it.
  Mesh mesh;
  // The triangles are written over the nodes (NodeArray): the mesh owns their storage from here,
  // and they are read until triangulate_cells() starts.
  mesh.triangles = tree_.give_node_storage();
  nodes_given_away_ = true;
  const Mesh& base = in_.vertices_only;
  const std::size_t leaf_count = leaves_.size();
  const std::size_t grid_room = gpos_.capacity();  // grid vertices and crossing points
  const std::size_t warped_count = with_vertex_[0].size() + with_vertex_[1].size();
  // First the vertex arrays (the pass below writes them), then the cells' arrays. (The points are
  // written over the grid positions, below.)
  auto allocate_vertices = [&] {
    const std::size_t point_room = base.points.size() + grid_room + leaf_count / 64 + 16;  // + centres
    const std::size_t known = base.points.size() + (grid_count_ >= warped_count ? grid_count_ - warped_count : 0);
    reserve_room(mesh.vertex_kind, point_room);
    mesh.vertex_kind.assign(base.vertex_kind.begin(), base.vertex_kind.end());
    mesh.vertex_kind.resize(known);
    reserve_room(mesh.vertex_marker, point_room);
    mesh.vertex_marker.assign(base.vertex_marker.begin(), base.vertex_marker.end());
    mesh.vertex_marker.resize(known);
    reserve_room(final_id_, grid_reserve());
    final_id_.resize(grid_count_);
  };
  PageFaulter cell_pages;
  auto allocate_cells = [&] {
    cell_bound_ = make_spare_array<CellBound>(spare_, leaf_count);
    reserve_room(bound_, leaf_count * 6);
    if (!spare_.lent(cell_bound_.get())) cell_pages.add(cell_bound_.get(), leaf_count * sizeof(CellBound));
    // (Not grown here: that would free the nodes, which warp() and segments_pass() are reading;
    // triangulate_cells() grows the array if the nodes' storage is too small.)
    if (mesh.triangles.capacity() >= leaf_count * 4) {
      cell_pages.add(mesh.triangles.data(), leaf_count * 2 * sizeof(Triangle));
    }
  };
  // The helper's stage: 1 when the vertex arrays are ready (it then does the cells' arrays while
  // the ids below are given), 2 when the cells' arrays are allocated (their pages are then touched
  // by both threads).
  std::atomic<int> helper_stage{0};
  std::array<std::exception_ptr, 2> helper_error;
  std::jthread helper;
  if (leaf_count >= threaded_leaves_) {
    helper = std::jthread([&] {
      try {
        allocate_vertices();
      } catch (...) {
        helper_error[0] = std::current_exception();
      }
      helper_stage.store(1, std::memory_order_release);
      helper_stage.notify_all();
      try {
        if (!helper_error[0]) allocate_cells();
      } catch (...) {
        helper_error[1] = std::current_exception();
      }
      helper_stage.store(2, std::memory_order_release);
      helper_stage.notify_all();
      if (!helper_error[1]) cell_pages.work();
    });
  } else {
    allocate_vertices();  // (the cells' arrays after the grid copies are released, below)
  }
  warp();
  segments_pass();
  if (helper.joinable()) helper_stage.wait(0, std::memory_order_acquire);
  if (helper_error[0]) std::rethrow_exception(helper_error[0]);
  // Final vertex ids: the clean input's vertices keep theirs; the Steiner points follow in Morton
  // order of their leaves (crossing points last).
  mesh.duplicates = base.duplicates;
  mesh.input_vertex_count = base.input_vertex_count;
  const std::size_t grid = gpos_.size();
  reserve_room(final_id_, grid + leaf_count / 64 + 16);
  final_id_.resize(grid);
  // The grid vertices warped onto input vertices (one input vertex each), in all and below the
  // middle of the grid order, where the second half of the pass below starts.
  const std::size_t middle = grid / 2;
  std::size_t warped = 0, warped_below_middle = 0;
  for (const std::uint32_t g : input_gv_) {
    if (g == kNone) continue;
    ++warped;
    if (g < middle) ++warped_below_middle;
  }
  const std::size_t steiner_base = base.points.size();
  const std::size_t steiner = grid - warped;
  if (steiner_base + steiner >= kInfinite) throw RouteFailure{"too many vertices"};
  const std::size_t point_room = steiner_base + steiner + leaf_count / 64 + 16;  // + centres
  reserve_room(mesh.vertex_kind, point_room);
  reserve_room(mesh.vertex_marker, point_room);
  mesh.vertex_kind.resize(steiner_base + steiner);
  mesh.vertex_marker.resize(steiner_base + steiner);
  // Ids in grid order (a prefix count: a half starts after the Steiner points below it), with the
  // kinds and markers, in two halves.
  in_two_halves(grid, threaded_leaves_, [&](std::size_t begin, std::size_t end) {
    auto next = static_cast<VertexId>(steiner_base + (begin == 0 ? 0 : begin - warped_below_middle));
    for (std::size_t g = begin; g < end; ++g) {
      if (gwarped_[g]) continue;  // (its input vertex's id: below)
      VertexKind kind = VertexKind::kSteiner;
      std::int32_t marker = 0;
      const std::uint32_t s = segment_of(static_cast<std::uint32_t>(g));
      if (s != kNone && !in_.segments[s].hull_only) {
        kind = VertexKind::kSteinerOnSegment;
        marker = in_.segments[s].marker;
      }
      const VertexId v = next++;
      final_id_[g] = v;
      mesh.vertex_kind[v] = kind;
      mesh.vertex_marker[v] = marker;
    }
  });
  for (const VertexId v : in_.vertices) final_id_[input_gv_[v]] = v;
  // The points are written over the grid positions, whose pages are already touched (a fresh
  // array would be 16 bytes per grid vertex of new pages, and the positions are dead once moved):
  // the Steiner point of grid vertex g goes to steiner_base + (g minus the warped vertices below g),
  // which is at least g (steiner_base counts every input vertex, so at least as many as are
  // warped), and these ids increase with g; so walking g downwards, each position is read before
  // anything is written over it. Then the input points go in front (their grid positions, the
  // warped corners, are dropped). The positions are restored if the route fails
  // (fallback_points()).
  mesh.points = std::move(gpos_);
  gpos_.clear();
  reserve_room(mesh.points, point_room);
  mesh.points.resize(steiner_base + steiner);
  Point* const points = mesh.points.data();
  for (std::size_t g = grid; g-- > 0;) {
    const VertexId v = final_id_[g];
    if (v >= steiner_base) points[v] = points[g];
  }
  std::copy(base.points.begin(), base.points.end(), points);
  std::vector<std::uint8_t>().swap(gtop_);
  if (helper.joinable()) {
    for (int stage = helper_stage.load(std::memory_order_acquire); stage < 2;
         stage = helper_stage.load(std::memory_order_acquire)) {
      helper_stage.wait(stage, std::memory_order_acquire);
    }
    if (!helper_error[1]) cell_pages.work();
    helper.join();
    if (helper_error[1]) std::rethrow_exception(helper_error[1]);
  } else {
    allocate_cells();
  }
  try {
    triangulate_cells(mesh);
    close_border(mesh);
    mark_segments(mesh);
  } catch (...) {
    gpos_.resize(final_id_.size());
    for (std::size_t g = 0; g < final_id_.size(); ++g) gpos_[g] = mesh.points[final_id_[g]];
    throw;
  }
  // The pages of the triangle array's room that the nodes touched past the last triangle (the
  // east lane's old block) go back to the system: the room's contents are unspecified, and a
  // later write there gets a fresh page.
  {
    static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    const auto used = reinterpret_cast<std::uintptr_t>(mesh.triangles.data() + mesh.triangles.size());
    const auto room = reinterpret_cast<std::uintptr_t>(mesh.triangles.data() + mesh.triangles.capacity());
    const std::uintptr_t first = (used + page - 1) / page * page, last = room / page * page;
    if (first < last) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
  }
  stats_.seconds_mesh = seconds_since(t0);
  const auto t1 = Clock::now();
  // Carve as the CDT does: flood from the root's border and from the hole seeds across every edge
  // that is not a segment. The domain boundary of a point set is its hull (temporary segments).
  carve(mesh, movable_seeds(mesh, holes), /*convex_hull=*/false, &stats_.warnings);
  refuse_rounded_sliver(mesh);
  bool hull_marks = false;
  for (const FeatureSegment& s : in_.segments) hull_marks = hull_marks || s.hull_only;
  if (hull_marks) {
    for (const auto& [h, s] : segment_edges_) {
      if (in_.segments[s].hull_only) mesh.clear_segment(h);
    }
  }
  stats_.seconds_carve = seconds_since(t1);
  return mesh;
}

std::vector<Point> Builder::fallback_points(const Tree& tree) const {
  // Grid corners away from every feature: at least a quarter of their smallest leaf from it.
  std::vector<Point> out;
  if (!loops_ || glevel_.size() != grid_count_ || tree.nodes.size() != tree_.nodes.size()) return out;
  std::vector<char> near(grid_count_, 0);
  for (std::uint32_t k = 0; k < leaves_.size(); ++k) {
    const Node& n = tree.nodes[leaves_[k]];
    const std::array<std::uint32_t, 8> loop = loop_of(k);
    for (unsigned slot = 0; slot < 8; ++slot) {
      const std::uint32_t g = loop[slot];
      if (g == kNone || near[g]) continue;
      const double r = 0.25 * tree.cell_size(glevel_[g]);
      const Point& p = gpos_[g];
      const Box b{p.x - r, p.y - r, p.x + r, p.y + r};
      for (std::uint32_t i = 0; i < n.feat_count && !near[g]; ++i) {
        const std::uint32_t f = tree.features[n.feat_begin + i];
        if (tree.meets(f, b)) near[g] = 1;
      }
    }
  }
  for (std::uint32_t g = 0; g < grid_count_; ++g) {
    if (!near[g] && (gwarped_.empty() || !gwarped_[g])) out.push_back(gpos_[g]);
  }
  return out;
}

// The fallback: the carved CDT of the input — the domain every method and the independent checker
// build — plus extra Steiner points (quadtree corners away from the features) inserted into it
// with Lawson flips that never cross a subsegment. Only points strictly inside a triangle of the
// domain are taken: the domain, its segments and their crossing points stay exactly the CDT's
// (taking the points as input points of a new CDT changed the segments' rounded crossings, and
// with them the domain, on inputs whose segments overlap and cross many times).
Mesh fallback_mesh(const Pslg& pslg, const QuadtreeOptions& options, std::vector<Point> extra) {
  ConstrainOptions constrain;
  constrain.strict = options.strict;
  constrain.convex_hull = options.convex_hull;
  Mesh m = constrained_delaunay(pslg, constrain);
  auto less = [](const Point& a, const Point& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
  std::sort(extra.begin(), extra.end(), less);  // (sorted: short walks from one to the next)
  extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
  Handle hint = kNone;
  for (const Point& p : extra) {
    if (!in_supported_range(p)) continue;  // a grid corner finer than the range (see above)
    const Location at = m.locate(p, hint);
    hint = at.handle;
    if (at.kind != Location::Kind::kInTriangle || !m.in_domain(at.handle >> 2)) continue;
    const VertexId v = m.add_vertex(p, VertexKind::kSteiner);
    m.insert_vertex(v, at.handle, &hint);
  }
  return m;
}

// The vertices the output keeps: every input point (ids are kept) and every Steiner point of a
// triangle of the domain. Quadtree corners outside the domain (the root square is twice the
// input's bounding box) are dropped, with the triangles around them.
std::vector<char> kept_vertices(const Mesh& m) {
  std::vector<char> kept(m.points.size(), 0);
  std::fill(kept.begin(), kept.begin() + std::min<std::size_t>(m.input_vertex_count, kept.size()), 1);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    for (const VertexId v : m.triangles[t].v) kept[v] = 1;
  }
  return kept;
}

// The first kept vertex outside the supported coordinate range, or kNone.
VertexId out_of_range_vertex(const Mesh& m, const std::vector<char>& kept) {
  for (VertexId v = 0; v < m.points.size(); ++v) {
    if (kept[v] && !in_supported_range(m.points[v])) return v;
  }
  return kNone;
}

// Drops the vertices kept_vertices() does not keep. The triangles of the domain stay as they are
// (same corners, same order, same subsegments); the rest of the convex hull of the kept vertices
// (holes, concavities, the pockets between the domain and the hull) is triangulated anew by the
// constrained Delaunay triangulation of the domain's boundary vertices and the input points
// outside the domain, with the domain's boundary edges as segments. Its triangles outside the
// domain (all but those a flood from the near side of the boundary edges reaches without crossing
// one) are carved (kOutside); its ghosts close the hull, which is the same, since the domain lies
// inside the hull of its boundary.
// Subsegments with carved triangles on both sides (none reach the output) are not kept.
void drop_unused_vertices(Mesh& m, const std::vector<char>& kept) {
  const std::size_t n = m.points.size();
  std::vector<VertexId> new_id(n, kNone);
  VertexId count = 0;
  for (VertexId v = 0; v < n; ++v) {
    if (kept[v]) new_id[v] = count++;
  }
  if (count == n) return;
  const auto key = [](VertexId u, VertexId v) { return (static_cast<std::uint64_t>(u) << 32) | v; };
  // Boundary edges of the domain (new ids, domain on the left) and the vertices of the new CDT.
  std::vector<char> in_cdt(n, 0);
  std::vector<std::pair<VertexId, VertexId>> boundary;
  std::vector<TriangleId> new_slot(m.triangles.size(), kNone);
  TriangleId domain_triangles = 0;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t)) new_slot[t] = domain_triangles++;
  }
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (new_slot[t] == kNone) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (new_slot[triangle_of(m.sym(h))] != kNone) continue;
      in_cdt[m.org(h)] = in_cdt[m.dest(h)] = 1;
      boundary.emplace_back(new_id[m.org(h)], new_id[m.dest(h)]);
    }
  }
  // Input points in no triangle of the domain (in holes, or outside it) must be covered too; those
  // the domain uses lie inside it and stay out of this triangulation.
  std::vector<char> used(m.input_vertex_count, 0);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (new_slot[t] == kNone) continue;
    for (const VertexId v : m.triangles[t].v) {
      if (v < used.size()) used[v] = 1;
    }
  }
  for (VertexId v = 0; v < m.input_vertex_count && v < n; ++v) {
    if (!used[v] && m.vertex_kind[v] != VertexKind::kDuplicate) in_cdt[v] = 1;
  }
  Pslg outer;
  std::vector<VertexId> cdt_vertex;  // CDT vertex → new id
  std::vector<VertexId> cdt_of(count, kNone);
  for (VertexId v = 0; v < n; ++v) {
    if (!in_cdt[v]) continue;
    cdt_of[new_id[v]] = static_cast<VertexId>(cdt_vertex.size());
    cdt_vertex.push_back(new_id[v]);
    outer.points.push_back(m.points[v]);
  }
  for (const auto& [u, v] : boundary) outer.segments.push_back({cdt_of[u], cdt_of[v], 0});
  ConstrainOptions whole;
  whole.convex_hull = true;
  const Mesh c = constrained_delaunay(outer, whole);
  if (c.points.size() != cdt_vertex.size()) {
    throw InternalError("drop_unused_vertices: the boundary's triangulation added vertices");
  }
  const auto new_of = [&](VertexId cv) { return cv == kInfinite ? kInfinite : cdt_vertex[cv]; };
  // The CDT's triangles inside the domain: flooded from the near side of each boundary edge
  // without crossing one (every component of the domain has boundary edges). The other finite
  // ones are outside it (all of them when the domain is empty).
  std::unordered_map<std::uint64_t, Handle> cdt_edge;
  for (TriangleId t = 0; t < c.triangles.size(); ++t) {
    if (c.is_dead(t) || c.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      cdt_edge.emplace(key(new_of(c.org(h)), new_of(c.dest(h))), h);
    }
  }
  std::unordered_set<std::uint64_t> boundary_keys;
  for (const auto& [u, v] : boundary) boundary_keys.insert(key(std::min(u, v), std::max(u, v)));
  std::vector<char> inside(c.triangles.size(), 0);
  std::vector<TriangleId> stack;
  for (const auto& [u, v] : boundary) {
    const auto it = cdt_edge.find(key(u, v));
    if (it == cdt_edge.end()) throw InternalError("drop_unused_vertices: a boundary edge is not in the triangulation");
    const TriangleId t = triangle_of(it->second);
    if (!inside[t]) {
      inside[t] = 1;
      stack.push_back(t);
    }
  }
  while (!stack.empty()) {
    const TriangleId t = stack.back();
    stack.pop_back();
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId a = new_of(c.org(h)), b = new_of(c.dest(h));
      if (boundary_keys.count(key(std::min(a, b), std::max(a, b))) != 0) continue;
      const TriangleId u = triangle_of(c.sym(h));
      if (inside[u] || c.is_ghost(u) || c.is_dead(u)) continue;
      inside[u] = 1;
      stack.push_back(u);
    }
  }
  // The CDT's carved triangles and ghosts follow the domain's triangles.
  std::vector<TriangleId> cdt_slot(c.triangles.size(), kNone);
  TriangleId slots = domain_triangles;
  for (TriangleId t = 0; t < c.triangles.size(); ++t) {
    if (!c.is_dead(t) && !inside[t]) cdt_slot[t] = slots++;
  }
  Mesh out;
  out.points.reserve(count);
  out.vertex_kind.reserve(count);
  out.vertex_marker.reserve(count);
  for (VertexId v = 0; v < n; ++v) {
    if (!kept[v]) continue;
    out.points.push_back(m.points[v]);
    out.vertex_kind.push_back(m.vertex_kind[v]);
    out.vertex_marker.push_back(v < m.vertex_marker.size() ? m.vertex_marker[v] : 0);
  }
  out.duplicates = m.duplicates;
  out.input_vertex_count = m.input_vertex_count;
  out.triangles.resize(slots);
  out.flags.assign(slots, 0);
  const bool markers = !m.segment_marker.empty();
  if (markers) out.segment_marker.assign(3 * std::size_t{slots}, 0);
  // Directed edges of the carved triangles and ghosts (new ids), to link the domain to them.
  std::unordered_map<std::uint64_t, Handle> outer_edge;
  for (TriangleId t = 0; t < c.triangles.size(); ++t) {
    if (cdt_slot[t] == kNone) continue;
    Triangle& T = out.triangles[cdt_slot[t]];
    out.flags[cdt_slot[t]] = c.is_ghost(t) ? 0 : kOutside;
    for (unsigned e = 0; e < 3; ++e) {
      T.v[e] = new_of(c.triangles[t].v[e]);
      const Handle h = make_handle(t, e);
      const Handle s = c.sym(h);
      if (cdt_slot[triangle_of(s)] != kNone) {
        T.n[e] = make_handle(cdt_slot[triangle_of(s)], edge_of(s));
      } else {
        T.n[e] = kNone;  // across a boundary edge: linked from the domain's side below
        outer_edge.emplace(key(new_of(c.org(h)), new_of(c.dest(h))), make_handle(cdt_slot[t], e));
      }
    }
  }
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    const TriangleId nt = new_slot[t];
    if (nt == kNone) continue;
    Triangle& T = out.triangles[nt];
    out.flags[nt] = static_cast<std::uint8_t>(m.flags[t] & ~(kOutside | kDead));
    for (unsigned e = 0; e < 3; ++e) {
      T.v[e] = new_id[m.triangles[t].v[e]];
      const Handle h = make_handle(t, e);
      const Handle s = m.sym(h);
      if (markers) out.segment_marker[3 * std::size_t{nt} + e] = m.marker(h);
      if (new_slot[triangle_of(s)] != kNone) {
        T.n[e] = make_handle(new_slot[triangle_of(s)], edge_of(s));
        continue;
      }
      const auto it = outer_edge.find(key(new_id[m.dest(h)], new_id[m.org(h)]));
      if (it == outer_edge.end()) throw InternalError("drop_unused_vertices: a boundary edge has no outer triangle");
      T.n[e] = it->second;
      out.triangles[triangle_of(it->second)].n[edge_of(it->second)] = make_handle(nt, e);
      if (m.is_segment(h)) {
        const Handle o = it->second;
        out.flags[triangle_of(o)] = static_cast<std::uint8_t>(out.flags[triangle_of(o)] | (kSegmentEdge0 << edge_of(o)));
        if (markers) out.segment_marker[3 * std::size_t{triangle_of(o)} + edge_of(o)] = m.marker(h);
      }
    }
  }
  for (const Triangle& T : out.triangles) {
    for (const Handle h : T.n) {
      if (h == kNone) throw InternalError("drop_unused_vertices: an outer triangle is not linked");
    }
  }
  m = std::move(out);
}

}  // namespace

Mesh quadtree_refinement(const Pslg& pslg, const QuadtreeOptions& options, QuadtreeStats* stats_out) {
  if (!(options.snap_fraction > 0.0 && options.snap_fraction < 0.5)) {
    throw std::invalid_argument("quadtree: snap_fraction must lie in (0, 0.5)");
  }
  QuadtreeStats stats;
  const auto t0 = Clock::now();
  const bool graph = !pslg.segments.empty();
  CleanInput in = graph ? clean_graph(pslg, options, stats) : clean_point_set(pslg, options);
  if (!graph) stats.input.duplicates = in.vertices_only.duplicates.size();
  if (!graph && !pslg.holes.empty()) {
    stats.warnings.push_back("the input has no segments, so its domain is the convex hull; " +
                             std::to_string(pslg.holes.size()) + " hole seed(s) ignored");
  }
  stats.features_vertices = in.vertices.size();
  stats.features_segments = in.segments.size();
  stats.seconds_input = seconds_since(t0);
  bool any_real_segment = false;
  for (const FeatureSegment& s : in.segments) any_real_segment = any_real_segment || !s.hull_only;
  const std::vector<Point> holes = any_real_segment ? in.hole_seeds : std::vector<Point>{};

  Mesh mesh;
  std::vector<Point> extra;
  const auto t1 = Clock::now();
  try {
    Tree tree(in, options, stats);
    tree.build();
    tree.finish();
    stats.seconds_tree = seconds_since(t1);
    // Leaf statistics: counted, not scanned (every split turns one leaf into four, and the
    // deepest node is a leaf); the leaves themselves only when asked, in node order.
    stats.leaves = tree.leaf_count();
    stats.depth = tree.deepest();
    if (options.keep_leaves) {
      for (std::uint32_t a = 0; a < tree.nodes.size(); ++a) {
        if (!tree.is_leaf(a)) continue;
        const Node& n = tree.nodes[a];
        const Box b = tree.box(n);
        stats.leaf_cells.push_back({b.x1, b.y1, b.x2 - b.x1,
                                    tree.meets_any(n, tree.features.data() + n.feat_begin, n.feat_count)});
      }
    }
    Builder builder(in, options, stats, tree);
    // The free corners for the fallback read the tree's nodes; once those went with the mesh
    // (NodeArray), from the same tree built again (the build is deterministic).
    const auto corners = [&] {
      if (!builder.nodes_given_away()) return builder.fallback_points(tree);
      QuadtreeStats scratch;
      Tree again(in, options, scratch);
      again.build();
      again.finish();
      return builder.fallback_points(again);
    };
    try {
      if (options.force_fallback) throw RouteFailure{"forced by the options"};
      if (stats.unresolved > 0) {
        throw RouteFailure{std::to_string(stats.unresolved) +
                           " leaves at the deepest level still see the input non-simply"};
      }
      mesh = builder.run(holes);
      // Round trip: what is written must lie in the supported coordinate range. A corner the
      // domain uses outside it (a grid finer than 1e-50 near an axis: a square of side 1e-50 got
      // a corner at x = 1.34e-51) sends the input to the fallback.
      const std::vector<char> kept = kept_vertices(mesh);
      if (const VertexId v = out_of_range_vertex(mesh, kept); v != kNone) {
        char where[64];
        std::snprintf(where, sizeof where, "(%.17g, %.17g)", mesh.points[v].x, mesh.points[v].y);
        // (No corners for the fallback: the grid's positions went into the mesh.)
        throw RouteFailure{"a quadtree vertex at " + std::string(where) +
                               " lies outside the supported coordinate range (0 or a magnitude between "
                               "1e-50 and 1e50)",
                           /*corners_usable=*/false};
      }
      drop_unused_vertices(mesh, kept);
    } catch (const RouteFailure& failure) {
      stats.fallback = true;
      stats.fallback_reason = failure.reason;
      if (failure.corners_usable) extra = corners();
    } catch (const InternalError& error) {
      // A broken invariant on the quadtree route (a bug; the tests assert no fallback on their
      // inputs): the user still gets a valid mesh, with a warning naming the invariant.
      stats.fallback = true;
      stats.fallback_reason = std::string("internal error: ") + error.what();
      extra = corners();
    }
  } catch (const RouteFailure& failure) {  // from the tree: its time until it gave up
    stats.fallback = true;
    stats.fallback_reason = failure.reason;
    stats.seconds_tree = seconds_since(t1);
  }
  if (stats.fallback) {
    const auto t2 = Clock::now();
    stats.warnings.push_back("quadtree refinement fell back to the constrained Delaunay triangulation "
                             "of the input" + std::string(extra.empty() ? "" : " plus quadtree corners") + ": " +
                             stats.fallback_reason);
    mesh = fallback_mesh(pslg, options, std::move(extra));
    stats.seconds_mesh = seconds_since(t2);
  }
  if (stats_out) *stats_out = std::move(stats);
  return mesh;
}

}  // namespace mwst
