// src/algorithms/bundle/shared.cpp — renumbering the mesh, DT(V) and the pencils (shared.hpp).
#include "algorithms/bundle/shared.hpp"

#include <algorithm>

#include "algorithms/bundle/approx.hpp"
#include "mwst/error.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "support/huge_pages.hpp"
#include "support/parallel.hpp"

namespace mwst::bundle {

namespace {

// Morton (Z-order) key, 30 bits, of the cell of (x, y) in a 2^15 × 2^15 grid over the bounding box.
std::uint32_t morton_key(const Point& p, double x0, double y0, double scale) {
  auto cell = [scale](double v, double v0) {
    const double c = (v - v0) * scale;
    return static_cast<std::uint32_t>(std::clamp(c, 0.0, 32767.0));
  };
  auto spread = [](std::uint32_t v) {
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
  };
  return spread(cell(p.x, x0)) | (spread(cell(p.y, y0)) << 1);
}

// The bounding box of the points with state[v] != 0 (every point without `state`), and the scale
// of morton_key over it.
struct MortonGrid {
  double x0 = kInf, y0 = kInf, scale = 0.0;
};
MortonGrid morton_grid(const std::vector<Point>& points, const std::vector<std::uint8_t>* state) {
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (VertexId v = 0; v < points.size(); ++v) {
    if (state && (*state)[v] == 0) continue;
    x0 = std::min(x0, points[v].x);
    y0 = std::min(y0, points[v].y);
    x1 = std::max(x1, points[v].x);
    y1 = std::max(y1, points[v].y);
  }
  const double extent = std::max(x1 * 0.5 - x0 * 0.5, y1 * 0.5 - y0 * 0.5);
  return {x0, y0, extent > 0.0 ? 16383.0 / extent : 0.0};  // extent is half the range
}

}  // namespace

std::vector<VertexId> Shared::curve_order(const std::vector<Point>& points) {
  const MortonGrid g = morton_grid(points, nullptr);
  std::vector<std::uint64_t> keyed(points.size());
  for (VertexId v = 0; v < points.size(); ++v) keyed[v] = std::uint64_t{morton_key(points[v], g.x0, g.y0, g.scale)} << 32 | v;
  std::sort(keyed.begin(), keyed.end());
  std::vector<VertexId> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<VertexId>(keyed[i] & 0xFFFFFFFFu);
  return order;
}

// ---- Shared::build begins here --------------------------------------------------------------------

bool Shared::build(bool list_pencils, const std::vector<VertexId>* subset, Mesh* prior_dt,
                   const std::vector<VertexId>* prior_ids) {
  std::vector<std::uint8_t> state;  // 1: corner of a live triangle, 2: vertex of T
  if (!mark_vertices(subset, state)) return false;
  apply_order(vertex_order(state, subset, prior_dt, prior_ids), state);
  return finish(list_pencils);
}

// Marks the corners of live triangles (1) and the vertices of T (2; with a subset, only those in
// it). False if T has no vertex (in the subset).
bool Shared::mark_vertices(const std::vector<VertexId>* subset, std::vector<std::uint8_t>& state) const {
  const std::size_t nv = m.points.size();
  state.assign(nv, 0);
  bool any = false;
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    if (m.is_dead(t)) continue;
    const std::uint8_t s = m.in_domain(t) ? 2 : 1;
    any = any || s == 2;
    for (const VertexId v : m.triangles[t].v) {
      if (v != kInfinite) state[v] = std::max(state[v], s);
    }
  }
  if (!any) return false;
  if (subset) {
    std::vector<std::uint8_t> in_subset(nv, 0);
    for (const VertexId v : *subset) in_subset[v] = 1;
    bool some = false;
    for (VertexId v = 0; v < nv; ++v) {
      if (state[v] == 2 && !in_subset[v]) state[v] = 1;
      some = some || state[v] == 2;
    }
    if (!some) return false;
  }
  return true;
}

// The renumbering: vertices of T first (they are the DT ids), each group in Morton order — group
// in bit 62, the 30-bit key in bits 32..61, the old id below. With a prior DT(V) its vertices come
// first in its order (and prior_ is set for finish()); with a subset the DT is small and the sweeps
// few: the groups in id order, without a sort.
std::vector<std::uint64_t> Shared::vertex_order(const std::vector<std::uint8_t>& state,
                                                const std::vector<VertexId>* subset, Mesh* prior_dt,
                                                const std::vector<VertexId>* prior_ids) {
  const std::size_t nv = m.points.size();
  const auto [x0, y0, scale] = morton_grid(m.points, &state);
  std::vector<std::uint64_t> order;
  std::vector<std::uint8_t> in_prior;
  if (!subset && prior_dt && prior_ids && prior_dt->triangle_slots() > 0 &&
      prior_dt->points.size() == prior_ids->size()) {
    in_prior.assign(nv, 0);
    for (std::size_t i = 0; i < prior_ids->size(); ++i) {
      const VertexId v = (*prior_ids)[i];
      if (v >= nv || state[v] != 2 || in_prior[v] || !(m.points[v] == prior_dt->points[i])) {
        in_prior.clear();
        break;
      }
      in_prior[v] = 1;
    }
  }
  if (!in_prior.empty()) {
    prior_ = prior_dt;
    prior_used_ = static_cast<std::uint32_t>(prior_ids->size());
    for (const VertexId v : *prior_ids) order.push_back(v);  // group 0, key 0: kept in front
    const std::size_t kept = order.size();
    for (VertexId v = 0; v < nv; ++v) {
      if (state[v] == 0 || in_prior[v]) continue;
      const std::uint64_t group = state[v] == 2 ? 0 : 1;
      order.push_back((group << 62) | (std::uint64_t{morton_key(m.points[v], x0, y0, scale)} << 32) | v);
    }
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(kept), order.end());
  } else if (subset) {
    for (const int group : {2, 1}) {
      for (VertexId v = 0; v < nv; ++v) {
        if (state[v] == group) order.push_back(std::uint64_t{group == 2 ? 0u : 1u} << 62 | v);
      }
    }
  } else {
    for (VertexId v = 0; v < nv; ++v) {
      if (state[v] == 0) continue;
      const std::uint64_t group = state[v] == 2 ? 0 : 1;
      order.push_back((group << 62) | (std::uint64_t{morton_key(m.points[v], x0, y0, scale)} << 32) | v);
    }
    std::sort(order.begin(), order.end());
  }
  return order;
}

// Applies the order: pts, mesh_id, used, and the slots with renumbered corners.
void Shared::apply_order(const std::vector<std::uint64_t>& order, const std::vector<std::uint8_t>& state) {
  // Fresh arrays, each written whole: on huge pages (support/huge_pages.hpp; values unchanged).
  const std::size_t nv = m.points.size();
  std::vector<VertexId> renumber;
  support::reserve_on_huge_pages(renumber, nv);
  renumber.assign(nv, kInfinite);
  support::resize_on_huge_pages(pts, order.size());
  support::resize_on_huge_pages(mesh_id, order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto v = static_cast<VertexId>(order[i] & 0xFFFFFFFFu);
    renumber[v] = static_cast<VertexId>(i);
    mesh_id[i] = v;
    pts[i] = m.points[v];
    if (state[v] == 2) used = static_cast<std::uint32_t>(i + 1);
  }
  support::resize_on_huge_pages(slots, m.triangle_slots());
  read_mesh_neighbours();
  support::resize_on_huge_pages(domain, m.triangle_slots());
  support::reserve_on_huge_pages(vertex_edge, pts.size());
  vertex_edge.assign(pts.size(), kNone);
  for (TriangleId t = 0; t < m.triangle_slots(); ++t) {
    domain[t] = m.in_domain(t) ? 1 : 0;
    for (unsigned k = 0; k < 3; ++k) {
      const VertexId v = m.triangles[t].v[k];
      slots[t].v[k] = (v == kInfinite || m.is_dead(t)) ? kInfinite : renumber[v];
    }
    if (m.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId o = org(h);
      if (o != kInfinite && vertex_edge[o] == kNone) vertex_edge[o] = h;
    }
  }
}

// ---- Shared::build_region begins here -------------------------------------------------------------

bool Shared::build_region(const std::vector<TriangleId>& region, const DenseIds& region_ids,
                          const std::vector<VertexId>& w) {
  DenseIds ids(w.size() + region.size());
  std::vector<std::uint8_t> in_t;  // per region vertex (in `ids` order): a corner of an in-domain slot
  for (const VertexId v : w) ids.insert(v);
  in_t.assign(w.size(), 0);
  for (const TriangleId t : region) {
    const bool in = m.in_domain(t);
    for (const VertexId v : m.triangles[t].v) {
      if (v == kInfinite) continue;
      const auto [id, added] = ids.insert(v);
      if (added) in_t.push_back(0);
      if (in) in_t[id] = 1;
    }
  }
  // DT ids: the vertices of w that are vertices of T (a vertex of w has all its triangles in the
  // region, so in_t is exact for it), then the other region vertices.
  std::vector<VertexId> renumber(ids.size(), kNone);  // by `ids` id
  pts.clear();
  pts.reserve(ids.size());
  mesh_id.clear();
  for (std::uint32_t i = 0; i < w.size(); ++i) {
    if (!in_t[i]) continue;
    renumber[i] = static_cast<VertexId>(pts.size());
    pts.push_back(m.points[w[i]]);
    mesh_id.push_back(w[i]);
  }
  used = static_cast<std::uint32_t>(pts.size());
  if (used == 0) return false;
  for (std::uint32_t i = 0; i < ids.size(); ++i) {
    if (renumber[i] != kNone) continue;
    renumber[i] = static_cast<VertexId>(pts.size());
    pts.push_back(m.points[ids.key(i)]);
    mesh_id.push_back(ids.key(i));
  }
  outside = static_cast<TriangleId>(region.size());
  slots.resize(region.size() + 1);
  neighbours_held.resize(region.size() + 1);
  read_held_neighbours();
  domain.assign(region.size() + 1, 0);
  vertex_edge.assign(pts.size(), kNone);
  for (TriangleId t = 0; t < region.size(); ++t) {
    const Triangle& tri = m.triangles[region[t]];
    domain[t] = m.in_domain(region[t]) ? 1 : 0;
    for (unsigned k = 0; k < 3; ++k) {
      const VertexId v = tri.v[k];
      slots[t].v[k] = v == kInfinite ? kInfinite : renumber[ids.find(v)];
      const TriangleId n = region_ids.find(triangle_of(tri.n[k]));
      neighbours_held[t][k] = n == kNone ? make_handle(outside, 0) : make_handle(n, edge_of(tri.n[k]));
    }
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId o = org(h);
      if (o != kInfinite && vertex_edge[o] == kNone) vertex_edge[o] = h;
    }
  }
  slots[outside].v = {kInfinite, kInfinite, kInfinite};
  for (unsigned k = 0; k < 3; ++k) neighbours_held[outside][k] = make_handle(outside, k);
  return finish(false);
}

// ---- the candidate lists' storage begins here -----------------------------------------------------

void Shared::release_lists() {
  std::vector<TriangleId>().swap(list);
  std::vector<std::vector<TriangleId>>().swap(list_chunks);
  std::vector<std::uint32_t>().swap(list_chunk_first);
}

void Shared::flatten_lists(std::size_t capacity) {
  if (list_chunks.empty()) return;
  std::size_t total = 0;
  for (const auto& chunk : list_chunks) total += chunk.size();
  std::vector<TriangleId>().swap(list);
  list.reserve(std::max(total, std::min(capacity, 2 * total)));
  for (auto& chunk : list_chunks) {
    list.insert(list.end(), chunk.begin(), chunk.end());
    std::vector<TriangleId>().swap(chunk);
  }
  std::vector<std::vector<TriangleId>>().swap(list_chunks);
  std::vector<std::uint32_t>().swap(list_chunk_first);
}

// ---- cocircular Delaunay triangles begin here --------------------------------------------------

std::size_t Shared::share_cocircular_disks(unsigned threads) {
  // Per finite live triangle, bit e: the four vertices of it and of its neighbour across edge e
  // (finite) are cocircular. Each edge is tested once, by its triangle of lower slot (cocircular
  // vertices need the exact stage of incircle, and points on circles have many such edges), then
  // copied to the other.
  cocircular.assign(dt.triangle_slots(), 0);
  support::parallel_ranges(threads, dt.triangle_slots(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto t = static_cast<TriangleId>(i);
      if (dt.is_dead(t) || dt.is_ghost(t)) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        const Handle hs = dt.sym(h);
        if (triangle_of(hs) < t || dt.is_ghost(triangle_of(hs))) continue;
        if (incircle(pts[dt.org(h)], pts[dt.dest(h)], pts[dt.apex(h)], pts[dt.apex(hs)]) == 0) {
          cocircular[t] = static_cast<std::uint8_t>(cocircular[t] | 1u << e);
        }
      }
    }
  });
  for (TriangleId t = 0; t < dt.triangle_slots(); ++t) {
    if (dt.is_dead(t) || dt.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle hs = dt.sym(make_handle(t, e));
      if (triangle_of(hs) > t || dt.is_ghost(triangle_of(hs))) continue;
      if ((cocircular[triangle_of(hs)] >> edge_of(hs) & 1u) != 0) {
        cocircular[t] = static_cast<std::uint8_t>(cocircular[t] | 1u << e);
      }
    }
  }
  disk_rep.assign(dt.triangle_slots(), kNone);
  std::size_t distinct = 0;
  std::vector<TriangleId> stack;
  for (TriangleId t = 0; t < dt.triangle_slots(); ++t) {
    if (dt.is_dead(t) || dt.is_ghost(t)) {
      disk_rep[t] = t;
      continue;
    }
    if (disk_rep[t] != kNone) continue;
    ++distinct;
    disk_rep[t] = t;
    stack.assign(1, t);
    while (!stack.empty()) {
      const TriangleId u = stack.back();
      stack.pop_back();
      for (unsigned e = 0; e < 3; ++e) {
        const TriangleId n = triangle_of(dt.sym(make_handle(u, e)));
        if (disk_rep[n] != kNone || dt.is_ghost(n)) continue;
        // The four vertices of the two triangles on the edge are cocircular: one circumcircle.
        if ((cocircular[u] >> e & 1u) == 0) continue;
        disk_rep[n] = t;
        stack.push_back(n);
      }
    }
  }
  return distinct;
}

// ---- Shared::finish begins here -------------------------------------------------------------------

bool Shared::finish(bool list_pencils) {
  if (prior_) {
    dt = std::move(*prior_);
    prior_ = nullptr;
    kept_dt = true;
    Handle hint = kNone;
    for (std::uint32_t i = prior_used_; i < used; ++i) {
      dt.points.push_back(pts[i]);
      dt.vertex_kind.push_back(VertexKind::kSteiner);
      dt.vertex_marker.push_back(0);
      if (dt.insert_vertex(i, hint, &hint) != i) throw InternalError("bundle: two vertices of the mesh coincide");
    }
  } else {
    dt = delaunay(std::vector<Point>(pts.begin(), pts.begin() + used));
  }
  if (!dt.duplicates.empty()) throw InternalError("bundle: two vertices of the mesh coincide");
  if (!list_pencils) return true;
  for (TriangleId t = 0; t < dt.triangle_slots(); ++t) {
    if (dt.is_dead(t) || dt.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const TriangleId other = triangle_of(dt.sym(h));
      if (!dt.is_ghost(other) && other < t) continue;  // each interior edge once
      pencils.push_back(h);
    }
  }
  return true;
}

}  // namespace mwst::bundle
