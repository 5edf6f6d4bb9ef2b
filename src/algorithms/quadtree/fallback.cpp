// algorithms/quadtree/fallback.cpp — after the route: the fallback mesh (the carved CDT of the input
// plus the quadtree's free corners, when the route fails), and the output's last step on success,
// dropping the quadtree corners outside the domain and triangulating the rest of the hull anew.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "algorithms/quadtree/route.hpp"
#include "mwst/error.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mesh/insertion_order.hpp"
#include "mesh/keys.hpp"

namespace mwst::qtr {

// ==== the fallback begins here ===================================================================

// The fallback: the carved CDT of the input — the domain every method and the independent checker
// build — plus extra Steiner points (quadtree corners away from the features) inserted into it
// with Lawson flips that never cross a subsegment. Only points strictly inside a triangle of the
// domain are taken: the domain, its segments and their crossing points stay exactly the CDT's
// (taking the points as input points of a new CDT changed the segments' rounded crossings, and
// with them the domain, on inputs whose segments overlap and cross many times).
Mesh fallback_mesh(const Pslg& pslg, const QuadtreeOptions& options, std::vector<Point> extra, bool* out_of_time) {
  ConstrainOptions constrain;
  constrain.strict = options.strict;
  constrain.convex_hull = options.convex_hull;
  Mesh m = constrained_delaunay(pslg, constrain);
  auto less = [](const Point& a, const Point& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
  std::sort(extra.begin(), extra.end(), less);
  extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
  // Inserted in the Delaunay triangulation's own order (BRIO rounds of a Hilbert curve): each walk
  // starts next to its point. In x order, consecutive corners could lie far apart in y, and a walk
  // across a vertex of many segments (a wheel of 8,000 spokes: 93,000 corners) crossed thousands of
  // thin triangles: 68 % of the run.
  std::size_t left_count = 0;
  const std::vector<std::uint32_t> order = insertion_order::hilbert_order(extra, &left_count, false);
  Handle hint = kNone;
  for (std::size_t i = 0; i < order.size(); ++i) {
    // (Past the time budget the mesh as it stands is the answer: every insertion keeps it valid.)
    if (i % kClockStride == 0 && options.deadline != Clock::time_point::max() && Clock::now() >= options.deadline) {
      *out_of_time = true;
      break;
    }
    const Point& p = extra[order[i]];
    if (!in_supported_range(p)) continue;  // a grid corner finer than the range (see quadtree.cpp)
    const Location at = m.locate(p, hint);
    hint = at.handle;
    if (at.kind != Location::Kind::kInTriangle || !m.in_domain(at.handle >> 2)) continue;
    const VertexId v = m.add_vertex(p, VertexKind::kSteiner);
    m.insert_vertex(v, at.handle, &hint);
  }
  return m;
}

// ==== the fallback ends here =====================================================================

// ==== the kept vertices begins here ==============================================================

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

// ==== the kept vertices ends here ================================================================

// ==== dropping the unused corners begins here =======================================================

namespace {


// The kept mesh's parts that stay as they are: new vertex ids, the domain's triangles in their new
// slots, its boundary edges (new ids, domain on the left), and the vertices of the new CDT.
struct KeptDomain {
  std::vector<VertexId> new_id;      // old vertex → new id, or kNone
  VertexId count = 0;                // kept vertices
  std::vector<TriangleId> new_slot;  // old triangle → its slot, or kNone outside the domain
  TriangleId domain_triangles = 0;
  std::vector<std::pair<VertexId, VertexId>> boundary;
  std::vector<char> in_cdt;          // old vertex → does the new CDT take it
};

// The CDT of the rest of the hull: its mesh, and its vertices' new ids.
struct OuterCdt {
  Mesh c;
  std::vector<VertexId> cdt_vertex;  // CDT vertex → new id
  VertexId new_of(VertexId cv) const { return cv == kInfinite ? kInfinite : cdt_vertex[cv]; }
};

// The domain's triangles and boundary edges, and the vertices the new CDT takes: the boundary's
// and the input points in no triangle of the domain (in holes, or outside it), which must be
// covered too; those the domain uses lie inside it and stay out of that triangulation.
void find_domain_boundary(const Mesh& m, KeptDomain& d) {
  const std::size_t n = m.points.size();
  d.in_cdt.assign(n, 0);
  d.new_slot.assign(m.triangles.size(), kNone);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t)) d.new_slot[t] = d.domain_triangles++;
  }
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (d.new_slot[t] == kNone) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (d.new_slot[triangle_of(m.sym(h))] != kNone) continue;
      d.in_cdt[m.org(h)] = d.in_cdt[m.dest(h)] = 1;
      d.boundary.emplace_back(d.new_id[m.org(h)], d.new_id[m.dest(h)]);
    }
  }
  std::vector<char> used(m.input_vertex_count, 0);
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (d.new_slot[t] == kNone) continue;
    for (const VertexId v : m.triangles[t].v) {
      if (v < used.size()) used[v] = 1;
    }
  }
  for (VertexId v = 0; v < m.input_vertex_count && v < n; ++v) {
    if (!used[v] && m.vertex_kind[v] != VertexKind::kDuplicate) d.in_cdt[v] = 1;
  }
}

// The constrained Delaunay triangulation of the new CDT's vertices with the boundary edges as
// segments, over their whole convex hull.
OuterCdt triangulate_outside(const Mesh& m, const KeptDomain& d) {
  OuterCdt outer;
  Pslg input;
  std::vector<VertexId> cdt_of(d.count, kNone);
  for (VertexId v = 0; v < m.points.size(); ++v) {
    if (!d.in_cdt[v]) continue;
    cdt_of[d.new_id[v]] = static_cast<VertexId>(outer.cdt_vertex.size());
    outer.cdt_vertex.push_back(d.new_id[v]);
    input.points.push_back(m.points[v]);
  }
  for (const auto& [u, v] : d.boundary) input.segments.push_back({cdt_of[u], cdt_of[v], 0});
  ConstrainOptions whole;
  whole.convex_hull = true;
  outer.c = constrained_delaunay(input, whole);
  if (outer.c.points.size() != outer.cdt_vertex.size()) {
    throw InternalError("drop_unused_vertices: the boundary's triangulation added vertices");
  }
  return outer;
}

// Directed edges by key (mesh/keys.hpp), sorted once and searched: the maps this replaced spent
// most of drop_unused_vertices() allocating and freeing their nodes (1.3 s of 3.3 for a fan of 30
// spikes, whose domain's boundary has 100,000 edges).
class EdgeIndex {
 public:
  void add(std::uint64_t key, Handle h) { entries_.emplace_back(key, h); }
  void sort() { std::sort(entries_.begin(), entries_.end()); }
  // The handle of the directed edge `key`, or kNone.
  Handle find(std::uint64_t key) const {
    const auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(key, Handle{0}));
    return it != entries_.end() && it->first == key ? it->second : kNone;
  }

 private:
  std::vector<std::pair<std::uint64_t, Handle>> entries_;
};

// The CDT's triangles inside the domain: flooded from the near side of each boundary edge without
// crossing one (every component of the domain has boundary edges). The other finite ones are
// outside it (all of them when the domain is empty).
std::vector<char> cdt_inside_domain(const OuterCdt& outer, const KeptDomain& d) {
  const Mesh& c = outer.c;
  // The boundary edges are the CDT's input segments: only segment edges are indexed.
  EdgeIndex segment_edge;
  for (TriangleId t = 0; t < c.triangles.size(); ++t) {
    if (c.is_dead(t) || c.is_ghost(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (c.is_segment(h)) segment_edge.add(edge_key(outer.new_of(c.org(h)), outer.new_of(c.dest(h))), h);
    }
  }
  segment_edge.sort();
  // Both sides of every boundary edge, as bits per triangle (1 << edge).
  std::vector<std::uint8_t> on_boundary(c.triangles.size(), 0);
  std::vector<char> inside(c.triangles.size(), 0);
  std::vector<TriangleId> stack;
  for (const auto& [u, v] : d.boundary) {
    const Handle h = segment_edge.find(edge_key(u, v));
    if (h == kNone) throw InternalError("drop_unused_vertices: a boundary edge is not in the triangulation");
    on_boundary[triangle_of(h)] = static_cast<std::uint8_t>(on_boundary[triangle_of(h)] | (1u << edge_of(h)));
    const Handle s = c.sym(h);
    on_boundary[triangle_of(s)] = static_cast<std::uint8_t>(on_boundary[triangle_of(s)] | (1u << edge_of(s)));
    const TriangleId t = triangle_of(h);
    if (!inside[t]) {
      inside[t] = 1;
      stack.push_back(t);
    }
  }
  while (!stack.empty()) {
    const TriangleId t = stack.back();
    stack.pop_back();
    for (unsigned e = 0; e < 3; ++e) {
      if ((on_boundary[t] >> e) & 1u) continue;
      const TriangleId u = triangle_of(c.sym(make_handle(t, e)));
      if (inside[u] || c.is_ghost(u) || c.is_dead(u)) continue;
      inside[u] = 1;
      stack.push_back(u);
    }
  }
  return inside;
}

// The output's vertices: the kept ones, in order.
void copy_kept_vertices(const Mesh& m, const std::vector<char>& kept, VertexId count, Mesh& out) {
  out.points.reserve(count);
  out.vertex_kind.reserve(count);
  out.vertex_marker.reserve(count);
  for (VertexId v = 0; v < m.points.size(); ++v) {
    if (!kept[v]) continue;
    out.points.push_back(m.points[v]);
    out.vertex_kind.push_back(m.vertex_kind[v]);
    out.vertex_marker.push_back(v < m.vertex_marker.size() ? m.vertex_marker[v] : 0);
  }
  out.duplicates = m.duplicates;
  out.input_vertex_count = m.input_vertex_count;
}

// The CDT's carved triangles and ghosts, in the slots after the domain's (cdt_slot); returns the
// directed edges (new ids) across which they meet the domain, to be linked from its side.
EdgeIndex place_outer_triangles(const OuterCdt& outer, const std::vector<TriangleId>& cdt_slot, Mesh& out) {
  const Mesh& c = outer.c;
  EdgeIndex outer_edge;
  for (TriangleId t = 0; t < c.triangles.size(); ++t) {
    if (cdt_slot[t] == kNone) continue;
    Triangle& T = out.triangles[cdt_slot[t]];
    out.flags[cdt_slot[t]] = c.is_ghost(t) ? 0 : kOutside;
    for (unsigned e = 0; e < 3; ++e) {
      T.v[e] = outer.new_of(c.triangles[t].v[e]);
      const Handle h = make_handle(t, e);
      const Handle s = c.sym(h);
      if (cdt_slot[triangle_of(s)] != kNone) {
        T.n[e] = make_handle(cdt_slot[triangle_of(s)], edge_of(s));
      } else {
        T.n[e] = kNone;  // across a boundary edge: linked from the domain's side (place_domain_triangles())
        outer_edge.add(edge_key(outer.new_of(c.org(h)), outer.new_of(c.dest(h))), make_handle(cdt_slot[t], e));
      }
    }
  }
  outer_edge.sort();
  return outer_edge;
}

// The domain's triangles, unchanged in their new slots, linked to the outer triangles across the
// boundary (which then carry its subsegments too).
void place_domain_triangles(const Mesh& m, const KeptDomain& d,
                            const EdgeIndex& outer_edge, Mesh& out) {
  const bool markers = !m.segment_marker.empty();
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    const TriangleId nt = d.new_slot[t];
    if (nt == kNone) continue;
    Triangle& T = out.triangles[nt];
    out.flags[nt] = static_cast<std::uint8_t>(m.flags[t] & ~(kOutside | kDead));
    for (unsigned e = 0; e < 3; ++e) {
      T.v[e] = d.new_id[m.triangles[t].v[e]];
      const Handle h = make_handle(t, e);
      const Handle s = m.sym(h);
      if (markers) out.segment_marker[3 * std::size_t{nt} + e] = m.marker(h);
      if (d.new_slot[triangle_of(s)] != kNone) {
        T.n[e] = make_handle(d.new_slot[triangle_of(s)], edge_of(s));
        continue;
      }
      const Handle o = outer_edge.find(edge_key(d.new_id[m.dest(h)], d.new_id[m.org(h)]));
      if (o == kNone) throw InternalError("drop_unused_vertices: a boundary edge has no outer triangle");
      T.n[e] = o;
      out.triangles[triangle_of(o)].n[edge_of(o)] = make_handle(nt, e);
      if (m.is_segment(h)) {
        std::uint8_t& flags = out.flags[triangle_of(o)];
        flags = static_cast<std::uint8_t>(flags | (kSegmentEdge0 << edge_of(o)));
        if (markers) out.segment_marker[3 * std::size_t{triangle_of(o)} + edge_of(o)] = m.marker(h);
      }
    }
  }
}

}  // namespace

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
  KeptDomain d;
  d.new_id.assign(n, kNone);
  for (VertexId v = 0; v < n; ++v) {
    if (kept[v]) d.new_id[v] = d.count++;
  }
  if (d.count == n) return;
  find_domain_boundary(m, d);
  const OuterCdt outer = triangulate_outside(m, d);
  const std::vector<char> inside = cdt_inside_domain(outer, d);
  // The CDT's carved triangles and ghosts follow the domain's triangles.
  std::vector<TriangleId> cdt_slot(outer.c.triangles.size(), kNone);
  TriangleId slots = d.domain_triangles;
  for (TriangleId t = 0; t < outer.c.triangles.size(); ++t) {
    if (!outer.c.is_dead(t) && !inside[t]) cdt_slot[t] = slots++;
  }
  Mesh out;
  copy_kept_vertices(m, kept, d.count, out);
  out.triangles.resize(slots);
  out.flags.assign(slots, 0);
  if (!m.segment_marker.empty()) out.segment_marker.assign(3 * std::size_t{slots}, 0);
  const auto outer_edge = place_outer_triangles(outer, cdt_slot, out);
  place_domain_triangles(m, d, outer_edge, out);
  for (const Triangle& T : out.triangles) {
    for (const Handle h : T.n) {
      if (h == kNone) throw InternalError("drop_unused_vertices: an outer triangle is not linked");
    }
  }
  m = std::move(out);
}

// ==== dropping the unused corners ends here =========================================================

}  // namespace mwst::qtr
