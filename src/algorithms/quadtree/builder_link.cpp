// algorithms/quadtree/builder_link.cpp — the cells put together: triangulate_cells() runs the chunks
// (prepare, emit, link) on one or two threads with places given by prefix sums in leaf order;
// link_cell() joins each cell to the cells across its left and bottom sides; close_border() adds
// the ghost triangles around the root square; mark_segments() flags the subsegments.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include "algorithms/quadtree/builder.hpp"
#include "algorithms/quadtree/cells.hpp"
#include "mesh/keys.hpp"

namespace mwst::qtr {

// ==== the chunks begins here =====================================================================

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
  const std::uint32_t chunks = (leaf_count + kCellChunk - 1) / kCellChunk;
  const unsigned threads = leaf_count < threaded_leaves_ || chunks < 2 ? 1u : 2u;
  if (!cell_bound_) cell_bound_ = make_spare_array<CellBound>(spare_, leaves_.size());  // (emit_cells())
  centre_base_ = mesh.points.size();
  // Room (address space only until written) past what the cells need, about 2.5 triangles per leaf
  // and 6 boundary edges per warped or cut leaf, so that the two threads can extend the arrays in
  // place.
  const std::size_t triangle_room = std::max(mesh.triangles.capacity(), leaves_.size() * 4);
  // A failure on two threads: redo on one, which throws the first failure in leaf order.
  if (!write_cells(mesh, threads, triangle_room)) write_cells(mesh, 1, triangle_room);
  add_centres(mesh);
}

// The state the chunks' threads share: the token that hands out places in chunk order, the chunks
// each thread has written, and, under the token, the arrays' ends and bases.
struct Builder::ChunkSchedule {
  static constexpr std::uint32_t kStopped = std::numeric_limits<std::uint32_t>::max();
  unsigned thread_count = 1;
  std::uint32_t leaf_count = 0, chunks = 0;
  // Per chunk: its centres, border edges and segment edges (in its thread's sink).
  std::vector<std::array<std::uint32_t, 3>> chunk_counts;
  std::array<EmitSink, 2> sinks;
  std::atomic<std::uint32_t> token{0};
  std::array<std::atomic<std::uint32_t>, 2> written{};  // chunks each thread has written
  std::atomic<bool> stop{false};
  std::size_t tri_end = 0, bound_end = 0, centre_end = 0;
  Triangle* tri_base = nullptr;
  Handle* bound_base = nullptr;

  // The other thread u's chunks below chunk c.
  std::uint32_t below(unsigned u, std::uint32_t c) const {
    if (thread_count == 1) return 0;
    return c > u ? (c - u + 1) / 2 : 0;
  }
  // Waits until `value` reaches `target` (false when stopped).
  bool wait_for(std::atomic<std::uint32_t>& value, std::uint32_t target) {
    for (;;) {
      const std::uint32_t v = value.load(std::memory_order_acquire);
      if (stop.load(std::memory_order_acquire)) return false;
      if (v >= target) return true;
      value.wait(v, std::memory_order_acquire);
    }
  }
  // Stops both threads (after a failure on one of them).
  void stop_all() {
    stop.store(true, std::memory_order_seq_cst);
    for (auto* a : {&token, &written[0], &written[1]}) {
      a->store(kStopped, std::memory_order_seq_cst);
      a->notify_all();
    }
  }
};

// One attempt at every cell on `thread_count` threads; false if a thread failed (the caller then
// redoes it on one). On one thread a failure is thrown.
bool Builder::write_cells(Mesh& mesh, unsigned thread_count, std::size_t triangle_room) {
  mesh.triangles.clear();
  reserve_room(mesh.triangles, triangle_room);
  bound_.clear();
  reserve_room(bound_, leaves_.size() * 6);
  ChunkSchedule schedule;
  schedule.thread_count = thread_count;
  schedule.leaf_count = static_cast<std::uint32_t>(leaves_.size());
  schedule.chunks = (schedule.leaf_count + kCellChunk - 1) / kCellChunk;
  schedule.chunk_counts.resize(schedule.chunks);
  schedule.tri_base = mesh.triangles.data();
  schedule.bound_base = bound_.data();
  if (thread_count == 1) {
    write_chunks(mesh, schedule, 0);
  } else {
    std::array<std::exception_ptr, 2> error;
    auto guarded = [&](unsigned t) {
      try {
        write_chunks(mesh, schedule, t);
      } catch (...) {
        error[t] = std::current_exception();
        schedule.stop_all();
      }
    };
    support::parallel_ranges(2, 2, [&](std::size_t t, std::size_t, std::size_t) { guarded(static_cast<unsigned>(t)); });
    if (error[0] || error[1]) return false;
  }
  join_chunk_lists(schedule);
  return true;
}

// Thread t's chunks (t, t + thread_count, ...): each prepared, given its places when the chunk
// before it has taken its own, written, and linked once every earlier chunk is written (on two
// threads after the thread's next chunk is written, so that a thread rarely waits for the other).
void Builder::write_chunks(Mesh& mesh, ChunkSchedule& schedule, unsigned t) {
  const auto& plain = plain_cells();
  const std::uint32_t leaf_count = schedule.leaf_count;
  PreparedChunk chunk;
  EmitSink& sink = schedule.sinks[t];
  const unsigned u = 1 - t;
  const bool alone = schedule.thread_count == 1;
  // Links the leaves [begin, end) of chunk c, once every earlier chunk is written.
  auto link = [&](std::uint32_t c, std::uint32_t begin, std::uint32_t end) {
    if (!schedule.wait_for(schedule.written[u], schedule.below(u, c))) return false;
    const std::size_t outer_before = sink.outer.size();
    for (std::uint32_t k = begin; k < end; ++k) link_cell(mesh.points, schedule.tri_base, schedule.bound_base, k, sink);
    schedule.chunk_counts[c][1] = static_cast<std::uint32_t>(sink.outer.size() - outer_before);
    return true;
  };
  std::uint32_t pending = kNone;
  for (std::uint32_t c = t; c < schedule.chunks; c += schedule.thread_count) {
    // (Out of time on two threads: both stop, and the redo on one stops at its first chunk.)
    check_deadline(options_.deadline);
    const std::uint32_t begin = c * kCellChunk, end = std::min(leaf_count, begin + kCellChunk);
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
    if (!schedule.wait_for(schedule.token, c)) return;
    if (schedule.tri_end + tri_count > mesh.triangles.capacity() ||
        schedule.bound_end + bound_count > bound_.capacity()) {
      if (!alone) throw RouteFailure{"out of room"};  // (redone on one thread)
      mesh.triangles.reserve(std::max(schedule.tri_end + tri_count, mesh.triangles.capacity() / 2 * 3));
      bound_.reserve(std::max(schedule.bound_end + bound_count, bound_.capacity() / 2 * 3));
    }
    const auto first = static_cast<TriangleId>(schedule.tri_end);
    const auto first_bound = static_cast<std::uint32_t>(schedule.bound_end);
    const auto centre_first = static_cast<VertexId>(centre_base_ + schedule.centre_end);
    schedule.tri_end += tri_count;
    schedule.bound_end += bound_count;
    schedule.centre_end += centre_count;
    // (Below kTableCell, which marks triangle ids in cell_bound_.)
    if (schedule.tri_end >= kInfinite / 4 || schedule.bound_end >= kTableCell) throw RouteFailure{"too many triangles"};
    mesh.triangles.resize(schedule.tri_end);
    bound_.resize(schedule.bound_end);
    if (alone) {
      schedule.tri_base = mesh.triangles.data();
      schedule.bound_base = bound_.data();
    }
    schedule.token.store(c + 1, std::memory_order_release);
    schedule.token.notify_all();
    const std::size_t centres_before = sink.centres.size(), segments_before = sink.segment_edges.size();
    emit_cells(chunk, limit, schedule.tri_base, first, schedule.bound_base, first_bound, centre_first, sink);
    schedule.chunk_counts[c][0] = static_cast<std::uint32_t>(sink.centres.size() - centres_before);
    schedule.chunk_counts[c][2] = static_cast<std::uint32_t>(sink.segment_edges.size() - segments_before);
    schedule.written[t].fetch_add(1, std::memory_order_acq_rel);
    schedule.written[t].notify_all();
    if (alone) {
      link(c, begin, limit);
      if (chunk.error) std::rethrow_exception(chunk.error);
      continue;
    }
    if (pending != kNone && !link(pending, pending * kCellChunk, pending * kCellChunk + kCellChunk)) return;
    pending = c;
  }
  if (pending != kNone) link(pending, pending * kCellChunk, std::min(leaf_count, pending * kCellChunk + kCellChunk));
}

// Joins the per-chunk lists (centres, border edges, segment edges) in chunk order, and the counts.
void Builder::join_chunk_lists(const ChunkSchedule& schedule) {
  std::array<std::size_t, 2> at_centre{}, at_outer{}, at_segment{};
  outer_.clear();
  segment_edges_.clear();
  centre_points_.clear();
  for (std::uint32_t c = 0; c < schedule.chunks; ++c) {
    const unsigned t = c % schedule.thread_count;
    const EmitSink& s = schedule.sinks[t];
    const auto [centres, outer, segments] = schedule.chunk_counts[c];
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
  for (const EmitSink& s : schedule.sinks) {
    stats_.table_cells += s.table_cells;
    stats_.program_cells += s.program_cells;
  }
  stats_.centres += centre_points_.size();
}

// The centres become vertices after all grid vertices (their grid ids follow the grid's); the
// per-leaf arrays of the linking are freed.
void Builder::add_centres(Mesh& mesh) {
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

// ==== the chunks ends here =======================================================================

// ==== linking the cells begins here ==============================================================

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

// ==== linking the cells ends here ================================================================

// ==== the border and the subsegments begins here =================================================

// Ghost triangles around the root square (its border is the convex hull), from the border edges
// link_cell() collected.
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

// Flags and marks the subsegments (both sides of each), and checks that every subsegment of the
// chains is one edge of the mesh.
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
    seen.emplace_back(undirected_key(u, w), s);
  }
  std::sort(seen.begin(), seen.end());
  seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
  if (seen.size() != subsegment_count_) throw RouteFailure{"a subsegment is not an edge of the mesh"};
}

// See the declaration: the rounding of the points on segments, bounded against the domain's area.
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

// ==== the border and the subsegments ends here ===================================================

}  // namespace mwst::qtr
