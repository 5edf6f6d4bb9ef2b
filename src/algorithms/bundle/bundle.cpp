// src/algorithms/bundle/bundle.cpp — the exact bundle number of a triangulation
// (mwst/algorithms/bundle.hpp). docs/algorithms/bundle-number.md describes the method. The steps,
// in order:
//   Shared::build            (shared.cpp)        renumber the vertices, DT(V), the pencils
//   build_lists              (lists.cpp)         each circumdisk's candidate triangles, by floods
//   Worker::sweep            (worker_sweep.cpp)  each pencil's best disk, on worker threads
//   merge_workers                                the largest count, ties to the first pencil
//   bound_cut_lists                              with a budget that cut lists short: exact bounds
//   bound_cut_pencils        (upper_bound.cpp)   (the upper one, per pencil not swept)
// For a triangle list: compact_triangles, covering_mesh and find_input_triangles make the Mesh.
// in_k_bundle (k_bundle.cpp) asks "is this triangle in a k-bundle?" near a few triangles only.
#include "mwst/algorithms/bundle.hpp"

#include <algorithm>
#include <array>
#include <future>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/bundle/lists.hpp"
#include "algorithms/bundle/shared.hpp"
#include "algorithms/bundle/upper_bound.hpp"
#include "algorithms/bundle/worker.hpp"
#include "mesh/keys.hpp"
#include "mwst/error.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

KBundleCache::KBundleCache() : impl(std::make_unique<Impl>()) {}
KBundleCache::~KBundleCache() = default;

namespace {

using bundle::Shared;
using bundle::Worker;
using Workers = std::vector<std::unique_ptr<Worker>>;

// How many circumdisks cut short bundle_number counts in full for its lower bound.
constexpr std::size_t kFullCounts = 4;
// The floods of the pencils bound_cut_pencils sweeps in full visit at most this share of the
// candidate budget (an eighth: their sweeps cost several times a flood, in time and in memory).
constexpr std::size_t kRefineShare = 8;

// ---- bundle_number(Mesh) begins here ---------------------------------------------------------------

// The workers' results into `result`: the largest count, ties to the first pencil (no thread ever
// skips the first pencil reaching the maximum, so the witness does not depend on the threads).
void merge_workers(const Workers& workers, BundleResult& result) {
  const Worker* best = workers[0].get();
  for (const auto& w : workers) {
    if (w->best_count > best->best_count || (w->best_count == best->best_count && w->best_pencil < best->best_pencil)) {
      best = w.get();
    }
    result.circumdisk_bound = std::max(result.circumdisk_bound, w->circumdisk_best);
    result.pencils += w->pencils;
    result.candidate_pairs += w->candidate_pairs;
    result.exact_comparisons += w->exact_comparisons;
  }
  result.bundle_number = best->best_count;
  result.disk_center = best->best_center;
  result.disk_radius = best->best_radius;
  result.triangles = best->best_triangles;
  result.lower_bound = result.upper_bound = result.bundle_number;
}

// Some circumdisks meet more triangles than the budget lets their lists hold (points on a circle:
// every circumdisk is about the whole circle). The pencils with a list cut short were not swept;
// what was swept is exact. Lower bound: that, or a circumdisk counted in full (those whose cut
// lists met the most triangles; a circumdisk of DT(V) is vertex-empty, so it is a witness). Upper
// bound: bound_cut_pencils (upper_bound.cpp), which may also raise the lower bound. The cut lists
// are counted on every worker (each disk on its own: the counts do not depend on the threads);
// the rest runs on the first.
void bound_cut_lists(Shared& sh, Workers& workers, std::size_t work_budget, BundleResult& result) {
  Worker& worker = *workers[0];
  std::vector<std::pair<std::uint32_t, TriangleId>> cut;  // (met within the cut list, slot)
  for (TriangleId d = 0; d < sh.truncated.size(); ++d) {
    if (sh.truncated[d]) cut.emplace_back(0, d);
  }
  result.truncated_disks = cut.size();
  const std::size_t full = std::min(kFullCounts, cut.size());
  const std::size_t counted = bundle::count_cut_lists(sh, workers, cut, full);
  for (std::size_t k = 1; k < workers.size(); ++k) workers[k]->release_disk_scratch();
  std::partial_sort(cut.begin(), cut.begin() + static_cast<std::ptrdiff_t>(full),
                    cut.begin() + static_cast<std::ptrdiff_t>(counted),
                    [](const auto& x, const auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
  std::vector<TriangleId> met;
  for (std::size_t i = 0; i < full; ++i) {
    const TriangleId d = cut[i].second;
    worker.collect_meeting(d, met);
    const auto count = static_cast<std::uint32_t>(met.size());
    result.circumdisk_bound = std::max(result.circumdisk_bound, count);
    if (count <= result.lower_bound) continue;
    result.lower_bound = count;
    const auto& v = sh.dt.triangles[d].v;
    result.disk_center = circumcenter(sh.pts[v[0]], sh.pts[v[1]], sh.pts[v[2]]);
    result.disk_radius = distance(result.disk_center, sh.pts[v[0]]);
    result.triangles = met;
  }
  result.bundle_number = result.lower_bound;
  sh.release_lists();  // the cut lists are read no more
  bundle::release(sh.list_begin);
  bundle::bound_cut_pencils(sh, worker, work_budget, static_cast<unsigned>(workers.size()), result);
  result.bundle_number = result.lower_bound;
  result.exact = result.lower_bound == result.upper_bound;
}

// The per-triangle values of every worker, merged (the largest).
std::vector<std::uint32_t> merge_per_triangle(Workers& workers) {
  std::vector<std::uint32_t> merged = std::move(workers[0]->per_triangle());
  for (std::size_t k = 1; k < workers.size(); ++k) {
    const auto& other = workers[k]->per_triangle();
    for (std::size_t t = 0; t < other.size(); ++t) merged[t] = std::max(merged[t], other[t]);
  }
  return merged;
}

// bundle_number(Mesh); `release` runs once the mesh has been copied into Shared and is no longer
// read (the triangle-list version frees its covering mesh there).
// With `prior_dt`, DT(V) built already, its vertex i being mesh vertex (*prior_ids)[i] (see
// Shared::curve_order).
template <class Release>
BundleResult bundle_number_of(const Mesh& mesh, const BundleOptions& options, Release release, Mesh* prior_dt = nullptr,
                              const std::vector<VertexId>* prior_ids = nullptr) {
  BundleResult result;
  Shared sh(mesh, options.deadline);
  if (!sh.build(true, nullptr, prior_dt, prior_ids)) {
    if (options.per_triangle) result.per_triangle.assign(mesh.triangle_slots(), 0);
    return result;
  }
  sh.own_neighbours();  // (Shared reads the mesh's neighbours; `release` may free the mesh)
  release();
  const unsigned threads = bundle::worker_threads(options.threads, sh.pencils.size());
  result.disks = sh.share_cocircular_disks(threads);
  // DT(V)'s coordinates are sh.pts; from here on only its topology is read.
  bundle::release(sh.dt.points);
  bundle::release(sh.dt.vertex_kind);
  bundle::release(sh.dt.vertex_marker);
  // Without per-triangle values, a pencil with no more candidates than the best count so far
  // cannot improve it and is skipped (the first pencil reaching the maximum is never skipped, so
  // the witness does not depend on the number of threads).
  auto workers = bundle::make_workers(sh, threads, options.per_triangle, !options.per_triangle);
  const bool budgeted = options.candidate_budget > 0 && !options.per_triangle;
  bool complete = true;
  if (budgeted) {
    complete = bundle::build_lists_within_budget(sh, workers, options.candidate_budget);
  } else {
    bundle::build_lists(sh, workers);
  }
  for (auto& w : workers) w->release_flood_scratch();
  bundle::for_ranges(workers, sh.pencils.size(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t i = begin; i < end; ++i) {
      sh.check_deadline();
      w.sweep(i);
    }
  });
  merge_workers(workers, result);
  if (!complete) {
    for (auto& w : workers) w->release_sweep_scratch();
    bound_cut_lists(sh, workers, options.candidate_budget / kRefineShare, result);
  }
  std::sort(result.triangles.begin(), result.triangles.end());
  if (options.per_triangle) result.per_triangle = merge_per_triangle(workers);
  return result;
}

}  // namespace

BundleResult bundle_number(const Mesh& mesh, const BundleOptions& options) {
  return bundle_number_of(mesh, options, [] {});
}

std::vector<std::uint32_t> circumdisk_bundle_per_triangle(const Mesh& mesh, unsigned threads_requested) {
  std::vector<std::uint32_t> best(mesh.triangle_slots(), 0);
  Shared sh(mesh);
  if (!sh.build()) return best;
  const unsigned threads = bundle::worker_threads(threads_requested, sh.dt.triangle_slots());
  auto workers = bundle::make_workers(sh, threads, true, false);
  bundle::for_ranges(workers, sh.dt.triangle_slots(), [&](Worker& w, std::size_t begin, std::size_t end, std::size_t) {
    std::vector<TriangleId> list, met;
    auto& mine = w.per_triangle();
    for (std::size_t t = begin; t < end; ++t) {
      const auto dtt = static_cast<TriangleId>(t);
      if (sh.dt.is_dead(dtt) || sh.dt.is_ghost(dtt)) continue;
      w.flood(dtt, list);
      met.clear();
      const std::uint32_t count = w.circumdisk_count(dtt, list.data(), list.size(), &met);
      for (const TriangleId c : met) mine[c] = std::max(mine[c], count);
    }
  });
  for (const auto& w : workers) {
    const auto& mine = w->per_triangle();
    for (std::size_t t = 0; t < best.size(); ++t) best[t] = std::max(best[t], mine[t]);
  }
  return best;
}

// ---- bundle_number(points, triangles) begins here --------------------------------------------------

namespace {

std::string triangle_name(std::size_t i) { return "triangle " + std::to_string(i + 1); }

// A triangle list over the points it uses, renumbered densely, each triangle counter-clockwise.
struct CompactTriangles {
  Pslg pslg;                                         // the used points (no segments yet)
  std::vector<std::uint32_t> original;               // compact id → index into the points
  std::vector<std::array<std::uint32_t, 3>> tris;    // compact ids
};

CompactTriangles compact_triangles(const std::vector<Point>& points,
                                   const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  CompactTriangles c;
  std::vector<std::uint32_t> compact(points.size(), kNone);
  std::vector<std::uint32_t>& original = c.original;
  Pslg& pslg = c.pslg;
  std::vector<std::array<std::uint32_t, 3>>& tris = c.tris;
  tris.resize(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = triangles[i][k];
      if (v >= points.size()) {
        throw InputError("", 0, triangle_name(i) + " names vertex " + std::to_string(v) + ", which does not exist");
      }
      if (compact[v] == kNone) {
        compact[v] = static_cast<std::uint32_t>(original.size());
        original.push_back(v);
        pslg.points.push_back(points[v]);
      }
      tris[i][k] = compact[v];
    }
    auto& t = tris[i];
    const int o = orient2d(pslg.points[t[0]], pslg.points[t[1]], pslg.points[t[2]]);
    if (o == 0) throw InputError("", 0, triangle_name(i) + " is degenerate (its corners are collinear)");
    if (o < 0) std::swap(t[1], t[2]);
  }
  return c;
}

// The vertex ids in Morton (Z-)order of a 2^31 × 2^31 grid over their bounding box.
std::vector<std::uint32_t> morton_order(const std::vector<Point>& points) {
  using bundle::kInf;
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (const Point& p : points) {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
  }
  const double extent = std::max(x1 - x0, y1 - y0);
  const double scale = extent > 0.0 ? 2147483647.0 / extent : 0.0;
  auto spread = [](std::uint64_t v) {
    v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
    v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  auto cell = [scale](double v, double v0) {
    return static_cast<std::uint64_t>(std::clamp((v - v0) * scale, 0.0, 2147483647.0));
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::uint32_t v = 0; v < points.size(); ++v) {
    keyed[v] = {spread(cell(points[v].x, x0)) | (spread(cell(points[v].y, y0)) << 1), v};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(points.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = keyed[i].second;
  return order;
}

// Every edge of T is a segment: the constrained Delaunay triangulation then contains every
// triangle of T and fills the holes and concavities, so the mesh covers the convex hull.
// Each segment is inserted from its end of lower degree in T, grouped by that end: inserting a→b
// finds b by turning around a (detail::find_wedge), which costs the degree of a. A fan, whose apex
// is an end of half the edges of T, cost the square of its size when its edges were inserted from
// the apex; from the other end the turns cost O(1) each (the sum over the edges of the smaller end
// degree is O(n) in a planar graph: Chiba and Nishizeki, "Arboricity and subgraph listing
// algorithms", 1985).
Mesh covering_mesh(CompactTriangles& c) {
  Pslg& pslg = c.pslg;
  const std::vector<std::array<std::uint32_t, 3>>& tris = c.tris;
  const std::vector<std::uint32_t>& original = c.original;
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * tris.size());
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) edges.push_back(undirected_key(t[k], t[(k + 1) % 3]));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::uint32_t> degree(pslg.points.size(), 0);
  for (const std::uint64_t e : edges) {
    ++degree[e >> 32];
    ++degree[e & 0xFFFFFFFFu];
  }
  // Keyed (Morton rank of the first end, second end): the segments of one first end follow each
  // other (the last one's edge is where the next starts), and the walks (Mesh::locate) from one
  // first end to the next are short.
  const std::vector<std::uint32_t> by_rank = morton_order(pslg.points);
  std::vector<std::uint32_t> rank(by_rank.size());
  for (std::uint32_t r = 0; r < by_rank.size(); ++r) rank[by_rank[r]] = r;
  for (std::uint64_t& e : edges) {
    auto u = static_cast<std::uint32_t>(e >> 32), v = static_cast<std::uint32_t>(e & 0xFFFFFFFFu);
    if (degree[v] < degree[u]) std::swap(u, v);  // from the end of lower degree
    e = std::uint64_t{rank[u]} << 32 | v;
  }
  bundle::release(degree);
  bundle::release(rank);
  std::sort(edges.begin(), edges.end());
  pslg.segments.reserve(edges.size());
  for (const std::uint64_t e : edges) {
    pslg.segments.push_back({by_rank[e >> 32], static_cast<std::uint32_t>(e & 0xFFFFFFFFu), 1});
  }
  bundle::release(edges);
  ConstrainOptions constrain;
  constrain.strict = true;
  constrain.convex_hull = true;
  Mesh mesh;
  try {
    mesh = constrained_delaunay(pslg, constrain);
  } catch (const InputError& e) {
    throw InputError("", 0, std::string("the triangles do not form a triangulation: ") + e.what());
  }
  if (!mesh.duplicates.empty()) {
    const auto& [dup, kept] = mesh.duplicates.front();
    throw InputError("", 0, "vertices " + std::to_string(original[dup]) + " and " +
                                std::to_string(original[kept]) + " of the triangles coincide");
  }
  return mesh;
}

// Finds every triangle of T among the faces of the covering mesh (slot → index into the list);
// everything else is marked outside the domain. Each triangle is looked for around its corner of
// lowest degree in the mesh: O(n) turns in all (see covering_mesh), where turning around the first
// corner cost the square of a fan's size.
std::vector<std::uint32_t> find_input_triangles(Mesh& mesh, const std::vector<std::array<std::uint32_t, 3>>& tris) {
  std::vector<Handle> vertex_edge(mesh.points.size(), kNone);
  std::vector<std::uint32_t> degree(mesh.points.size(), 0);
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (mesh.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId o = mesh.org(h);
      if (o == kInfinite) continue;
      ++degree[o];
      if (vertex_edge[o] == kNone) vertex_edge[o] = h;
    }
    if (!mesh.is_ghost(t)) mesh.flags[t] = static_cast<std::uint8_t>(mesh.flags[t] | kOutside);
  }
  std::vector<std::uint32_t> slot_to_input(mesh.triangle_slots(), kNone);
  for (std::size_t i = 0; i < tris.size(); ++i) {
    std::array<std::uint32_t, 3> t = tris[i];
    while (degree[t[0]] > degree[t[1]] || degree[t[0]] > degree[t[2]]) t = {t[1], t[2], t[0]};
    TriangleId found = kNone;
    const Handle start = vertex_edge[t[0]];
    Handle h = start;
    for (std::size_t turn = 0; turn < mesh.triangle_slots(); ++turn) {
      if (mesh.dest(h) == t[1] && mesh.apex(h) == t[2]) {
        found = triangle_of(h);
        break;
      }
      h = mesh.onext(h);
      if (h == start) break;
    }
    if (found == kNone) {
      throw InputError("", 0, triangle_name(i) + " overlaps other triangles (or a vertex lies on its boundary)");
    }
    if (slot_to_input[found] != kNone) {
      throw InputError("", 0, triangle_name(i) + " repeats " + triangle_name(slot_to_input[found]));
    }
    slot_to_input[found] = static_cast<std::uint32_t>(i);
    mesh.flags[found] = static_cast<std::uint8_t>(mesh.flags[found] & ~kOutside);
  }
  return slot_to_input;
}

// The triangle-list versions: `release_input` runs once the input has been copied (compacted).
template <class Release>
BundleResult bundle_number_of_list(const std::vector<Point>& points,
                                   const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                   const BundleOptions& options, Release release_input) {
  if (triangles.empty()) return {};
  const std::size_t input_triangles = triangles.size();
  CompactTriangles compact = compact_triangles(points, triangles);
  release_input();
  // Every vertex of the covering mesh is a corner of a triangle of T, so DT(V) is known from the
  // points alone, in the order Shared::build numbers them: on a second thread, it is built while
  // the covering mesh is (which inserts its segments on one thread); if no thread can be started,
  // on this one when it is needed.
  std::vector<VertexId> dt_ids;
  std::future<Mesh> early_dt;
  if (bundle::worker_threads(options.threads, input_triangles) > 1) {
    dt_ids = Shared::curve_order(compact.pslg.points);
    std::vector<Point> dt_points(dt_ids.size());
    for (std::size_t i = 0; i < dt_ids.size(); ++i) dt_points[i] = compact.pslg.points[dt_ids[i]];
    early_dt = std::async(std::launch::async | std::launch::deferred, [pts = std::move(dt_points)]() mutable {
      return delaunay(std::move(pts), nullptr, 1);  // (the same mesh on any number of threads)
    });
  }
  Mesh mesh = covering_mesh(compact);
  compact.pslg = {};  // the mesh holds the points; what is not needed is freed as soon as it is not
  bundle::release(compact.original);
  const std::vector<std::uint32_t> slot_to_input = find_input_triangles(mesh, compact.tris);
  bundle::release(compact.tris);
  Mesh dt;
  if (early_dt.valid()) dt = early_dt.get();
  std::vector<VertexId>* ids = dt_ids.empty() ? nullptr : &dt_ids;
  BundleResult r = bundle_number_of(mesh, options, [&mesh, ids] {
    mesh = Mesh{};
    if (ids) bundle::release(*ids);
  }, ids ? &dt : nullptr, ids);
  for (std::uint32_t& t : r.triangles) t = slot_to_input[t];
  std::sort(r.triangles.begin(), r.triangles.end());
  if (options.per_triangle) {
    std::vector<std::uint32_t> by_input(input_triangles, 0);
    for (TriangleId t = 0; t < r.per_triangle.size(); ++t) {
      if (slot_to_input[t] != kNone) by_input[slot_to_input[t]] = r.per_triangle[t];
    }
    r.per_triangle = std::move(by_input);
  }
  return r;
}

}  // namespace

BundleResult bundle_number(const std::vector<Point>& points,
                           const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           const BundleOptions& options) {
  return bundle_number_of_list(points, triangles, options, [] {});
}

BundleResult bundle_number(std::vector<Point>&& points, std::vector<std::array<std::uint32_t, 3>>&& triangles,
                           const BundleOptions& options) {
  return bundle_number_of_list(points, triangles, options, [&] {
    bundle::release(points);
    bundle::release(triangles);
  });
}

}  // namespace mwst
