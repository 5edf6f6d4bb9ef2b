// algorithms/quadtree/builder_run.cpp — Builder::run(): the steps from the finished tree to the
// carved mesh, in order, with the memory moves that keep a large run from touching fresh pages
// (the grid positions become the mesh's points in place; a helper thread allocates and faults in
// the mesh's arrays while warp() and segments_pass() run); and the free corners for the fallback.
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <exception>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "algorithms/quadtree/builder.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "support/page_faulter.hpp"

namespace mwst::qtr {

namespace {


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

}  // namespace

// ==== the mesh's arrays begins here =================================================================

// The arrays the mesh is written into are allocated, and their pages first touched (the kernel
// clears each page on its first write), by a helper thread while warp() and segments_pass() run on
// the calling thread, which leaves the second core idle otherwise (small trees: in line); the
// calling thread joins the touching of the cells' arrays when it is done. Only pages the mesh
// surely uses (at least 2 triangles per cell; the warped and cut cells' boundary edges fault in as
// written) are touched, and every element is written later, so the output does not depend on it.
class Builder::ArrayHelper {
 public:
  // (Made before warp() and segments_pass(): the sizes are read before they change them.)
  ArrayHelper(Builder& builder, Mesh& mesh)
      : builder_(builder),
        mesh_(mesh),
        grid_room_(builder.gpos_.capacity()),
        warped_count_(builder.with_vertex_[0].size() + builder.with_vertex_[1].size()) {}
  // (Left early — the route stopped by its time budget or a failure — the helper touches no more
  // pages before it is joined.)
  ~ArrayHelper() { pages_.stop(); }
  ArrayHelper(const ArrayHelper&) = delete;
  ArrayHelper& operator=(const ArrayHelper&) = delete;
  // Starts the helper (large trees), or allocates the vertex arrays in line.
  void start(bool threaded) {
    if (!threaded) {
      builder_.allocate_vertex_arrays(mesh_, grid_room_, warped_count_);  // (the cells' arrays: finish())
      return;
    }
    thread_ = std::jthread([this] {
      try {
        builder_.allocate_vertex_arrays(mesh_, grid_room_, warped_count_);
      } catch (...) {
        error_[0] = std::current_exception();
      }
      stage_.store(1, std::memory_order_release);
      stage_.notify_all();
      try {
        if (!error_[0]) builder_.allocate_cell_arrays(mesh_, pages_);
      } catch (...) {
        error_[1] = std::current_exception();
      }
      stage_.store(2, std::memory_order_release);
      stage_.notify_all();
      if (!error_[1]) pages_.work();
    });
  }
  // The vertex arrays are ready (the helper's failure is rethrown here).
  void wait_for_vertex_arrays() {
    if (thread_.joinable()) stage_.wait(0, std::memory_order_acquire);
    if (error_[0]) std::rethrow_exception(error_[0]);
  }
  // The cells' arrays: the helper's, their pages touched by both threads, or allocated in line.
  void finish() {
    if (!thread_.joinable()) {
      builder_.allocate_cell_arrays(mesh_, pages_);
      return;
    }
    for (int stage = stage_.load(std::memory_order_acquire); stage < 2;) {
      stage_.wait(stage, std::memory_order_acquire);
      stage = stage_.load(std::memory_order_acquire);
    }
    if (!error_[1]) pages_.work();
    thread_.join();
    if (error_[1]) std::rethrow_exception(error_[1]);
  }

 private:
  Builder& builder_;
  Mesh& mesh_;
  std::size_t grid_room_;     // grid vertices and crossing points
  std::size_t warped_count_;  // grid vertices warped onto input vertices
  support::PageFaulter pages_;
  // 1 when the vertex arrays are ready (the helper then does the cells' arrays while the ids are
  // given), 2 when the cells' arrays are allocated (their pages are then touched by both threads).
  std::atomic<int> stage_{0};
  std::array<std::exception_ptr, 2> error_;
  std::jthread thread_;  // (last: joined before the rest is destroyed)
};

// The vertex arrays, with room for the Steiner points (the pass that gives final ids writes them).
// (The points are written over the grid positions: move_points_into_mesh().)
void Builder::allocate_vertex_arrays(Mesh& mesh, std::size_t grid_room, std::size_t warped_count) {
  const Mesh& base = in_.vertices_only;
  const std::size_t leaf_count = leaves_.size();
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
}

// The cells' arrays; `pages` gets the pages to fault in ahead of their first write.
void Builder::allocate_cell_arrays(const Mesh& mesh, support::PageFaulter& pages) {
  const std::size_t leaf_count = leaves_.size();
  cell_bound_ = make_spare_array<CellBound>(spare_, leaf_count);
  reserve_room(bound_, leaf_count * 6);
  if (!spare_.lent(cell_bound_.get())) pages.add(cell_bound_.get(), leaf_count * sizeof(CellBound));
  // (Not grown here: that would free the nodes, which warp() and segments_pass() are reading;
  // triangulate_cells() grows the array if the nodes' storage is too small.)
  if (mesh.triangles.capacity() >= leaf_count * 4) {
    pages.add(mesh.triangles.data(), leaf_count * 2 * sizeof(Triangle));
  }
}

// ==== the mesh's arrays ends here ===================================================================

// ==== from the tree to the mesh begins here =========================================================

// The steps in order: grid vertices and loops, warping, segments, final ids and points, the cells,
// the border and the subsegments; then carving to the domain.
Mesh Builder::run(const std::vector<Point>& holes) {
  const auto t0 = Clock::now();
  // (The time budget is checked between the steps, each linear in the leaves, and per chunk of
  // cells in triangulate_cells().)
  check_deadline(options_.deadline);
  number_vertices();
  check_deadline(options_.deadline);
  build_loops();
  check_deadline(options_.deadline);
  Mesh mesh;
  // The triangles are written over the nodes (NodeArray): the mesh owns their storage from here,
  // and they are read until triangulate_cells() starts.
  mesh.triangles = tree_.give_node_storage();
  nodes_given_away_ = true;
  ArrayHelper arrays(*this, mesh);
  arrays.start(leaves_.size() >= threaded_leaves_);
  warp();
  check_deadline(options_.deadline);
  segments_pass();
  check_deadline(options_.deadline);
  arrays.wait_for_vertex_arrays();
  const std::size_t steiner = give_final_ids(mesh);
  check_deadline(options_.deadline);
  move_points_into_mesh(mesh, steiner);
  arrays.finish();
  check_deadline(options_.deadline);
  assemble_cells(mesh);
  // The pages of the triangle array's room that the nodes touched past the last triangle (the
  // east lane's old block) go back to the system: the room's contents are unspecified, and a
  // later write there gets a fresh page.
  support::release_pages(mesh.triangles.data() + mesh.triangles.size(),
                         mesh.triangles.data() + mesh.triangles.capacity());
  stats_.seconds_mesh = seconds_since(t0);
  check_deadline(options_.deadline);
  const auto t1 = Clock::now();
  carve_to_domain(mesh, holes);
  stats_.seconds_carve = seconds_since(t1);
  return mesh;
}

// Final vertex ids: the clean input's vertices keep theirs; the Steiner points follow in Morton
// order of their leaves (crossing points last), with their kinds and markers. Returns the number
// of Steiner points.
std::size_t Builder::give_final_ids(Mesh& mesh) {
  const Mesh& base = in_.vertices_only;
  const std::size_t leaf_count = leaves_.size();
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
  support::parallel_ranges(workers_for(grid, threaded_leaves_), grid,
      [&](std::size_t, std::size_t begin, std::size_t end) {
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
  return steiner;
}

// The points are written over the grid positions, whose pages are already touched (a fresh array
// would be 16 bytes per grid vertex of new pages, and the positions are dead once moved): the
// Steiner point of grid vertex g goes to steiner_base + (g minus the warped vertices below g),
// which is at least g (steiner_base counts every input vertex, so at least as many as are warped),
// and these ids increase with g; so walking g downwards, each position is read before anything is
// written over it. Then the input points go in front (their grid positions, the warped corners,
// are dropped). The positions are restored if the route fails (assemble_cells()).
void Builder::move_points_into_mesh(Mesh& mesh, std::size_t steiner) {
  const Mesh& base = in_.vertices_only;
  const std::size_t grid = gpos_.size();
  const std::size_t steiner_base = base.points.size();
  const std::size_t point_room = steiner_base + steiner + leaves_.size() / 64 + 16;  // + centres
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
}

// The cells, the border and the subsegments; if one fails, the grid positions are restored for
// fallback_points() before the failure goes on.
void Builder::assemble_cells(Mesh& mesh) {
  try {
    triangulate_cells(mesh);
    close_border(mesh);
    mark_segments(mesh);
  } catch (...) {
    gpos_.resize(final_id_.size());
    for (std::size_t g = 0; g < final_id_.size(); ++g) gpos_[g] = mesh.points[final_id_[g]];
    throw;
  }
}

// Carve as the CDT does: flood from the root's border and from the hole seeds across every edge
// that is not a segment. The domain boundary of a point set is its hull (temporary segments).
void Builder::carve_to_domain(Mesh& mesh, const std::vector<Point>& holes) {
  carve(mesh, movable_seeds(mesh, holes), /*convex_hull=*/false, &stats_.warnings);
  refuse_rounded_sliver(mesh);
  bool hull_marks = false;
  for (const FeatureSegment& s : in_.segments) hull_marks = hull_marks || s.hull_only;
  if (hull_marks) {
    for (const auto& [h, s] : segment_edges_) {
      if (in_.segments[s].hull_only) mesh.clear_segment(h);
    }
  }
}

// ==== from the tree to the mesh ends here ===========================================================

// ==== free corners for the fallback begins here ======================================================

// Grid corners away from every feature (at least a quarter of their smallest leaf from it), for
// the fallback; empty unless number_vertices() and build_loops() ran on this tree.
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

// ==== free corners for the fallback ends here ========================================================

}  // namespace mwst::qtr
