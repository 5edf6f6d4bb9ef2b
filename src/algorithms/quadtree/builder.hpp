// algorithms/quadtree/builder.hpp — stage 3 of quadtree refinement: from the finished tree to the
// mesh. Grid vertices (leaf corners and the side midpoints that smaller neighbours create) are
// owned by one leaf each, so ids come from one pass over the leaves in Morton order with no
// hashing; every leaf reads its loop of up to 8 vertices through neighbour look-ups. Corners move
// onto input vertices and segments (BEG's warping), segments cross the remaining cell edges at
// Steiner points, and each leaf is triangulated by the case table or, warped or cut, by the
// dynamic program of quadtree_cells.cpp. The triangles of all leaves form one Mesh over the root
// square, carved to the domain as the CDT carves. Builder::run() lists the steps in order; the
// class below declares them in that order. Per-leaf helpers are inline (they run per leaf).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "algorithms/quadtree/tree.hpp"
#include "mwst/error.hpp"
#include "support/page_faulter.hpp"
#include "support/set_bits.hpp"
#include "support/spare_room.hpp"

namespace mwst::qtr {

using support::make_spare_array;
using support::SpareAllocator;
using support::SpareArray;
using support::SpareVector;

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

  // ---- per-leaf look-ups (inline) ----
  // The id of the vertex leaf k owns as Own bit `bit`.
  std::uint32_t own(std::uint32_t k, unsigned bit) const {
    if (((own_mask_[k] >> bit) & 1u) == 0) throw RouteFailure{"a leaf lacks an expected vertex"};
    return own_base_[k] + support::set_bits(static_cast<unsigned>(own_mask_[k] & ((1u << bit) - 1u)));
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

  // ---- the steps, in the order run() takes them ----
  // (run() itself, with the memory moves between the steps, is in builder_run.cpp:
  // ArrayHelper, allocate_*_arrays(), give_final_ids(), move_points_into_mesh(), assemble_cells(),
  // carve_to_domain().)
  // Leaves in Morton order; which grid vertices each leaf owns, their ids and positions; for
  // link_cell(), what lies across each leaf's west and south sides.             (builder_grid.cpp)
  void number_vertices();
  void own_vertices_of_leaf(std::size_t k, std::vector<std::array<std::uint32_t, 2>>& split_pairs);
  void place_owned_vertices(std::size_t begin, std::size_t end);
  // Each leaf's loop of up to 8 vertices, the levels around each grid vertex, the leaves with a
  // vertex or a segment; then own_base_, own_mask_ and the tree's hints are lent to spare_.
  void build_loops();
  std::array<std::uint32_t, 8> find_loop(std::uint32_t k) const;
  // The corner of its leaf nearest each input vertex moves onto it.
  void warp();
  // Corners onto segments, crossing points, and the chains of subsegments. (builder_segments.cpp)
  void segments_pass();
  //   1. corners exactly on a segment join its chain where they are
  void corners_on_segments(const std::vector<std::uint32_t>& near);
  //   2. BEG's warp towards segments, rules X and P, to a fixed point
  struct SnapChoice {
    std::uint32_t segment;
    double fraction;  // the move's length in leaf sizes (its score: smaller is better)
    Point target;
  };
  using SnapChoices = std::unordered_map<std::uint32_t, SnapChoice>;  // corner → its best move
  void snap_corners_to_segments(const std::vector<std::uint32_t>& near);
  void offer_crossing_snaps(const std::vector<std::uint32_t>& near, SnapChoices& choice);
  void offer_projection_snaps(const std::vector<std::uint32_t>& near, SnapChoices& choice) const;
  static void offer_snap(SnapChoices& choice, std::uint32_t c, const SnapChoice& candidate);
  //   3. a crossing point on every leaf edge a segment still crosses properly
  void add_crossing_points(const std::vector<std::uint32_t>& near);
  //   4. each segment a chain of subsegments through the vertices on it
  void build_chains();
  // Every leaf's triangles, in chunks on one or two threads.                   (builder_link.cpp)
  void triangulate_cells(Mesh& mesh);
  static constexpr std::uint32_t kCellChunk = 4096;  // leaves per chunk
  struct ChunkSchedule;  // the threads' shared state: places handed out in chunk order
  bool write_cells(Mesh& mesh, unsigned thread_count, std::size_t triangle_room);
  void write_chunks(Mesh& mesh, ChunkSchedule& schedule, unsigned t);
  void join_chunk_lists(const ChunkSchedule& schedule);
  void add_centres(Mesh& mesh);
  //   one chunk: each cell's triangles, adjacency and exact checks             (builder_cells.cpp)
  struct PreparedChunk;
  void prepare_cells(const Mesh& mesh, PreparedChunk& out, std::uint32_t begin, std::uint32_t end,
                     std::size_t& next_crossing) const;
  //     an untouched square: its case-table mask, its triangles checked exactly
  unsigned prepare_table_cell(const Mesh& mesh, const std::array<std::uint32_t, 8>& loop) const;
  //     a warped or cut leaf: its polygon cut along its chords, each piece triangulated
  struct SpecialCell;
  struct CellScratch;
  void prepare_special_cell(const Mesh& mesh, const std::array<std::uint32_t, 8>& loop, std::size_t cross_begin,
                            std::size_t cross_end, PreparedChunk& out, CellScratch& scratch) const;
  void cell_polygon(const Mesh& mesh, const std::array<std::uint32_t, 8>& loop, std::size_t cross_begin,
                    std::size_t cross_end, CellScratch& scratch) const;
  void find_chords(CellScratch& scratch) const;
  void cut_along_chords(CellScratch& scratch) const;
  void triangulate_cell_piece(const Mesh& mesh, const std::uint32_t* index, std::size_t count,
                              std::uint32_t centre_begin, PreparedChunk& out, CellScratch& scratch) const;
  void link_inside_cell(const SpecialCell& cell, PreparedChunk& out, CellScratch& scratch) const;
  void collect_segment_edges(const SpecialCell& cell, PreparedChunk& out) const;
  //   the chunk written at its places in the mesh                              (builder_cells.cpp)
  struct EmitSink;
  void emit_cells(const PreparedChunk& in, std::uint32_t end, Triangle* tris, TriangleId first, Handle* bound,
                  std::uint32_t first_bound, VertexId centre_first, EmitSink& sink);
  //   each cell linked to the cells across its left and bottom sides           (builder_link.cpp)
  struct CellSide;
  CellSide cell_side(std::uint32_t k, unsigned side) const;
  void link_cell(const std::vector<Point>& points, Triangle* tris, const Handle* bound, std::uint32_t k,
                 EmitSink& sink) const;
  // Ghost triangles around the root square.                                    (builder_link.cpp)
  void close_border(Mesh& mesh);
  // Subsegments flagged and marked; each must be one edge of the mesh.         (builder_link.cpp)
  void mark_segments(Mesh& mesh);
  // After carving: throws RouteFailure (no corners for the fallback) if the rounding of the points
  // on segments could move the domain boundary by more than kBoundaryRoundingShare of its area.
  void refuse_rounded_sliver(const Mesh& mesh) const;

  // ---- run()'s own steps and memory moves (builder_run.cpp) ----
  class ArrayHelper;  // allocates the mesh's arrays on a helper thread while warp() runs
  void allocate_vertex_arrays(Mesh& mesh, std::size_t grid_room, std::size_t warped_count);
  void allocate_cell_arrays(const Mesh& mesh, support::PageFaulter& pages);
  std::size_t give_final_ids(Mesh& mesh);                         // returns the Steiner point count
  void move_points_into_mesh(Mesh& mesh, std::size_t steiner);    // over the grid positions
  void assemble_cells(Mesh& mesh);       // triangulate_cells(), close_border(), mark_segments()
  void carve_to_domain(Mesh& mesh, const std::vector<Point>& holes);

  // ---- per-leaf passes and grid-vertex look-ups (inline) ----
  // Calls visit(k, slot, u, w, s, a, b) for every edge u→w of the loop of a leaf k in `near` (from
  // `slot` to the next present slot) that segment s = ab of k's feature list crosses properly: u
  // and w strictly on opposite sides of ab and a, b strictly on opposite sides of uw (exact); edges
  // with an end already on s only touch it. Positions are read when the edge is visited, so the
  // callback may move corners or append vertices.
  template <class Visit>
  void for_each_crossed_edge(const std::vector<std::uint32_t>& near, Visit&& visit) {
    for_each_leaf_segment(near, [&](std::uint32_t k, const std::array<std::uint32_t, 8>& loop, std::uint32_t s,
                                    const Point& segment_a, const Point& segment_b) {
      const Point a = segment_a, b = segment_b;
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
    });
  }
  // Calls visit(k, loop, s, a, b) for every leaf k in `near` (its loop read once, before the
  // visits) and every segment s = ab of k's feature list. (The time budget is checked here: these
  // passes are most of segments_pass().)
  template <class Visit>
  void for_each_leaf_segment(const std::vector<std::uint32_t>& near, Visit&& visit) const {
    const std::uint32_t nv = tree_.vertex_count();
    for (std::size_t i_near = 0; i_near < near.size(); ++i_near) {
      check_deadline_at(i_near, options_.deadline);
      const std::uint32_t k = near[i_near];
      const Node& n = tree_.nodes[leaves_[k]];
      const std::array<std::uint32_t, 8> loop = loop_of(k);
      for (std::uint32_t i = 0; i < n.feat_count; ++i) {
        const std::uint32_t f = tree_.features[n.feat_begin + i];
        if (f < nv) continue;
        const std::uint32_t s = f - nv;
        visit(k, loop, s, pts_[in_.segments[s].a], pts_[in_.segments[s].b]);
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

  // Does grid vertex g lie on segment s (on it by segments_pass(), or warped onto an endpoint)?
  bool on_segment(std::uint32_t g, std::uint32_t s) const {
    if (segment_of(g) == s) return true;
    const FeatureSegment& seg = in_.segments[s];
    return input_gv_[seg.a] == g || input_gv_[seg.b] == g;
  }

  // ---- data ----
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
  // fresh pages, which this kind of machine charges for (docs/algorithms/quadtree.md).
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

// prepare_cells(): scratch for the warped and cut cells of a chunk, reused from cell to cell.
struct Builder::CellScratch {
  struct Chord {
    std::uint32_t i, j, segment;  // polygon indices of its ends, and its segment
  };
  static constexpr std::size_t kSmallPolygon = 16;
  std::vector<std::uint32_t> poly;                  // vertices of the cell polygon
  std::uint8_t side_index[4] = {0, 0, 0, 0};        // polygon index of BL, BR, TR, TL
  std::vector<std::array<std::uint8_t, 3>> local;   // the last piece's triangles, local indices
  std::vector<Point> sub_points;
  std::vector<Chord> chords;
  std::vector<std::pair<std::vector<std::uint32_t>, std::vector<Chord>>> pieces;  // polygon indices
  std::array<std::uint32_t, (kSmallPolygon + 1) * (kSmallPolygon + 1)> edge_at;  // (from, to) → 3·i + e
};

// triangulate_cells(): what one thread collects while writing its chunks, joined in chunk order.
struct Builder::EmitSink {
  std::vector<Point> centres;
  std::vector<Outer> outer;
  std::vector<std::pair<Handle, std::uint32_t>> segment_edges;
  std::size_t table_cells = 0, program_cells = 0;
};

}  // namespace mwst::qtr
