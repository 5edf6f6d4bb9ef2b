// algorithms/quadtree/builder_cells.cpp — each leaf's triangles. An untouched square takes the case
// table (checked exactly, cheaply when its corners form an axis-parallel rectangle); a warped or
// cut leaf is its loop with the crossing points inserted, cut along its chords (subsegments joining
// two of its vertices), and each piece triangulated by detail::triangulate_piece(); its adjacency
// inside the cell and its boundary edges are found here. emit_cells() writes a chunk at its places.
#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <utility>
#include <vector>

#include "algorithms/quadtree/builder.hpp"
#include "algorithms/quadtree/cell_triangulation.hpp"
#include "algorithms/quadtree/cells.hpp"

namespace mwst::qtr {

// ==== preparing a chunk begins here =================================================================

// Prepares leaves [begin, end): each leaf's kind, and for the warped and cut ones their triangles
// (grid ids or kCentre | j), adjacency inside the cell, boundary edges and segment edges. The
// first failure is kept in out.error with its leaf (out.fail_leaf); the leaves before it are done.
void Builder::prepare_cells(const Mesh& mesh, PreparedChunk& out, std::uint32_t begin, std::uint32_t end,
                            std::size_t& next_crossing) const {
  out.begin = begin;
  out.end = end;
  out.fail_leaf = kNone;
  out.error = nullptr;
  CellScratch scratch;
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
        out.kind[k - begin] = static_cast<std::uint8_t>(prepare_table_cell(mesh, loop));
        continue;
      }
      out.kind[k - begin] = kSpecialCell;
      prepare_special_cell(mesh, loop, cross_begin, next_crossing, out, scratch);
    }
  } catch (...) {
    out.fail_leaf = k;
    out.error = std::current_exception();
  }
}

// An untouched square: the case table (its triangles are checked here, emitted later). Returns
// its mask of present side midpoints.
unsigned Builder::prepare_table_cell(const Mesh& mesh, const std::array<std::uint32_t, 8>& loop) const {
  auto pos = [&](std::uint32_t g) -> const Point& { return mesh.points[final_id_[g]]; };
  unsigned mask = 0;
  for (unsigned side = 0; side < 4; ++side) {
    if (loop[2 * side + 1] != kNone) mask |= 1u << side;
  }
  const PlainCell& c = plain_cells()[mask];
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
    if (orient2d(pos(loop[c.slots[c.tri[i][0]]]), pos(loop[c.slots[c.tri[i][1]]]), pos(loop[c.slots[c.tri[i][2]]])) <=
        0) {
      throw RouteFailure{"a cell triangle is not counter-clockwise"};
    }
  }
  return mask;
}

// A warped or cut leaf, with the crossing points crossings_[cross_begin, cross_end) on its edges:
// its polygon, cut along its chords into pieces, each piece triangulated; then the adjacency inside
// the cell, its boundary edges and its segment edges, appended to `out` as one SpecialCell.
void Builder::prepare_special_cell(const Mesh& mesh, const std::array<std::uint32_t, 8>& loop, std::size_t cross_begin,
                                   std::size_t cross_end, PreparedChunk& out, CellScratch& scratch) const {
  SpecialCell cell;
  cell.tri_begin = static_cast<std::uint32_t>(out.tris.size());
  cell.centre_begin = static_cast<std::uint32_t>(out.centres.size());
  cell.bound_begin = static_cast<std::uint32_t>(out.bound_local.size());
  cell.segment_begin = static_cast<std::uint32_t>(out.segment_edges.size());
  cell_polygon(mesh, loop, cross_begin, cross_end, scratch);
  find_chords(scratch);
  const std::size_t m = scratch.poly.size();
  if (scratch.chords.empty()) {
    // A warped cell: one piece.
    static constexpr auto kIdentity = [] {
      std::array<std::uint32_t, 256> a{};
      for (std::uint32_t i = 0; i < 256; ++i) a[i] = i;
      return a;
    }();
    triangulate_cell_piece(mesh, kIdentity.data(), m, cell.centre_begin, out, scratch);
  } else {
    cut_along_chords(scratch);
    for (const auto& piece : scratch.pieces) {
      triangulate_cell_piece(mesh, piece.first.data(), piece.first.size(), cell.centre_begin, out, scratch);
    }
  }
  cell.tri_count = static_cast<std::uint32_t>(out.tris.size() - cell.tri_begin);
  cell.bound_count = static_cast<std::uint32_t>(m);
  link_inside_cell(cell, out, scratch);
  collect_segment_edges(cell, out);
  cell.centre_count = static_cast<std::uint32_t>(out.centres.size()) - cell.centre_begin;
  cell.segment_count = static_cast<std::uint32_t>(out.segment_edges.size()) - cell.segment_begin;
  const std::uint8_t* side_index = scratch.side_index;
  cell.sides = static_cast<std::uint32_t>(side_index[1]) | (static_cast<std::uint32_t>(side_index[2]) << 8) |
               (static_cast<std::uint32_t>(side_index[3]) << 16);
  out.special.push_back(cell);
}

// The cell polygon: the loop's slots with the crossing points of each edge inserted in order along
// it; scratch.side_index gets the polygon indices of the corners.
void Builder::cell_polygon(const Mesh& mesh, const std::array<std::uint32_t, 8>& loop, std::size_t cross_begin,
                           std::size_t cross_end, CellScratch& scratch) const {
  auto pos = [&](std::uint32_t g) -> const Point& { return mesh.points[final_id_[g]]; };
  std::vector<std::uint32_t>& poly = scratch.poly;
  poly.clear();
  std::uint8_t* side_index = scratch.side_index;
  for (unsigned c = 0; c < 4; ++c) side_index[c] = 0;
  for (unsigned s = 0; s < 8; ++s) {
    if (loop[s] == kNone) continue;
    if ((s & 1) == 0) side_index[s / 2] = static_cast<std::uint8_t>(poly.size());
    poly.push_back(loop[s]);
    if (cross_begin == cross_end) continue;
    const std::size_t before = poly.size();
    for (std::size_t c = cross_begin; c < cross_end; ++c) {
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
}

// Chords: consecutive chain vertices that are both on the polygon and not adjacent on it.
void Builder::find_chords(CellScratch& scratch) const {
  const std::vector<std::uint32_t>& poly = scratch.poly;
  scratch.chords.clear();
  const std::size_t m = poly.size();
  for (std::size_t i = 0; i < m; ++i) {
    if (!in_chain(poly[i])) continue;
    const auto [links_begin, links_end] = chain_of(poly[i]);
    for (const ChainLink* link = links_begin; link != links_end; ++link) {
      const std::uint32_t other = link->other, s = link->segment;
      for (std::size_t j = i + 1; j < m; ++j) {
        if (poly[j] != other) continue;
        const bool adjacent = j == i + 1 || (i == 0 && j == m - 1);
        if (adjacent) continue;  // a boundary edge on the segment: marked by collect_segment_edges()
        scratch.chords.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), s});
      }
    }
  }
}

// Cuts the polygon along the chords into scratch.pieces (polygon indices, counter-clockwise): a
// chord splits the piece holding both its ends in two, and the other chords follow their ends.
void Builder::cut_along_chords(CellScratch& scratch) const {
  using Chord = CellScratch::Chord;
  auto& pieces = scratch.pieces;
  const std::size_t m = scratch.poly.size();
  pieces.clear();
  std::vector<std::uint32_t> all(m);
  for (std::uint32_t i = 0; i < m; ++i) all[i] = i;
  pieces.emplace_back(std::move(all), scratch.chords);
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
        const bool in_one =
            std::find(one.begin(), one.end(), d.i) != one.end() && std::find(one.begin(), one.end(), d.j) != one.end();
        const bool in_two =
            std::find(two.begin(), two.end(), d.i) != two.end() && std::find(two.begin(), two.end(), d.j) != two.end();
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
}

// Triangulates one piece, given as `count` polygon indices (counter-clockwise), by
// detail::triangulate_piece(); its triangles (and its centre, if the fan won) are appended to
// `out`; the piece's local triangles stay in scratch.local.
void Builder::triangulate_cell_piece(const Mesh& mesh, const std::uint32_t* index, std::size_t count,
                                     std::uint32_t centre_begin, PreparedChunk& out, CellScratch& scratch) const {
  const std::vector<std::uint32_t>& poly = scratch.poly;
  scratch.sub_points.clear();
  for (std::size_t i = 0; i < count; ++i) scratch.sub_points.push_back(mesh.points[final_id_[poly[index[i]]]]);
  scratch.local.clear();
  Point centre;
  bool used_centre = false;
  if (!detail::triangulate_piece(scratch.sub_points, scratch.local, centre, used_centre)) {
    throw RouteFailure{"a warped or cut cell has no valid triangulation"};
  }
  std::uint32_t centre_id = kNone;
  if (used_centre) {
    // BEG add such points to distorted cells; it lifts the worst warped point-set cell from
    // 13.4° to 18.3° (tests/algorithms/quadtree/test_quadtree.cpp enumerates the configurations).
    centre_id = kCentre | (static_cast<std::uint32_t>(out.centres.size()) - centre_begin);
    out.centres.push_back(centre);
  }
  for (const auto& t : scratch.local) {
    Tri v;
    for (unsigned c = 0; c < 3; ++c) v[c] = t[c] == count ? centre_id : poly[index[t[c]]];
    out.tris.push_back(v);
  }
}

// The edges inside the cell (twin) and its boundary edges (bound_local), each found exactly once.
// (Every triangle is strictly counter-clockwise: triangulate_piece() checked each one exactly.)
void Builder::link_inside_cell(const SpecialCell& cell, PreparedChunk& out, CellScratch& scratch) const {
  const std::vector<std::uint32_t>& poly = scratch.poly;
  const std::size_t m = poly.size();
  const Tri* tris = out.tris.data() + cell.tri_begin;
  const std::uint32_t count = cell.tri_count;
  out.twin.resize(out.twin.size() + 3 * std::size_t{count}, kNone);
  out.bound_local.resize(out.bound_local.size() + m, kNone);
  std::uint32_t* twin = out.twin.data() + 3 * std::size_t{cell.tri_begin};
  std::uint32_t* bound = out.bound_local.data() + cell.bound_begin;
  const auto& local = scratch.local;
  if (scratch.chords.empty() && m <= CellScratch::kSmallPolygon) {
    // One piece (a warped cell): its triangles in `local` are over polygon positions, m for
    // the centre, so an edge from → to is on the boundary when to follows from, and the edge
    // across an inner one is found in a table by its ends.
    auto& edge_at = scratch.edge_at;
    const std::size_t width = m + 1;
    std::fill(edge_at.begin(), edge_at.begin() + static_cast<std::ptrdiff_t>(width * width), kNone);
    for (std::uint32_t i = 0; i < count; ++i) {
      for (unsigned e = 0; e < 3; ++e) {
        const std::size_t from = local[i][next3(e)], to = local[i][prev3(e)];
        const bool on_boundary = from < m && to == (from + 1 == m ? 0 : from + 1);
        std::uint32_t& slot = on_boundary ? bound[from] : edge_at[from * width + to];
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
}

// Segment edges of the cell: chords and boundary edges between consecutive chain vertices.
void Builder::collect_segment_edges(const SpecialCell& cell, PreparedChunk& out) const {
  if (chain_links_.empty()) return;
  const Tri* tris = out.tris.data() + cell.tri_begin;
  for (std::uint32_t i = 0; i < cell.tri_count; ++i) {
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

// ==== preparing a chunk ends here ===================================================================

// ==== writing a chunk begins here ===================================================================

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

// ==== writing a chunk ends here =====================================================================

}  // namespace mwst::qtr
