// to_arrays() and triangulate_arrays() (mwst/algorithms/arrays.hpp): the domain triangles of a mesh as flat
// arrays of vertices, triangles, neighbours and subsegments, in time linear in the mesh (plus one
// point location per region seed).
#include "mwst/algorithms/arrays.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>
#include <utility>

#include "algorithms/nearest_segment.hpp"
#include "mesh/insertion_order.hpp"
#include "mwst/error.hpp"
#include "support/huge_pages.hpp"
#include "support/page_faulter.hpp"
#include "support/parallel.hpp"
#include "support/set_bits.hpp"

namespace mwst {

namespace {

inline constexpr std::int32_t kNoTriangle = -1;

// The in-domain triangle of least id holding the point of `where` (found by Mesh::locate), or
// kNone: a point on an edge or a vertex belongs to the domain triangles beside it, and the least
// id makes the choice independent of the walk that found it.
TriangleId domain_triangle_at(const Mesh& mesh, const Location& where) {
  TriangleId best = kNone;
  const auto consider = [&](TriangleId t) {
    if (mesh.in_domain(t) && (best == kNone || t < best)) best = t;
  };
  switch (where.kind) {
    case Location::Kind::kInTriangle:
      consider(triangle_of(where.handle));
      break;
    case Location::Kind::kOnEdge:
      consider(triangle_of(where.handle));
      consider(triangle_of(mesh.sym(where.handle)));
      break;
    case Location::Kind::kOnVertex: {
      // The triangles around org(handle), counter-clockwise (onext), until back at the start.
      Handle h = where.handle;
      do {
        consider(triangle_of(h));
        h = mesh.onext(h);
      } while (h != where.handle);
      break;
    }
  }
  return best;
}

}  // namespace

std::vector<std::int32_t> region_of_triangles(const Mesh& mesh, const std::vector<Region>& regions,
                                              const std::string& source) {
  // The seeds located in Hilbert curve order, each walk starting where the last one ended: from
  // anywhere, each walk crossed O(sqrt n) triangles (40,000 regional seeds in a grid of cells took
  // most of `mwst triangle -pqAa`'s 28 s).
  std::vector<TriangleId> start(regions.size(), kNone);
  std::vector<std::uint32_t> supported;
  std::vector<Point> seeds;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (!in_supported_range(regions[r].seed)) continue;
    supported.push_back(static_cast<std::uint32_t>(r));
    seeds.push_back(regions[r].seed);
  }
  std::size_t left_half = 0;  // (where the order splits in two halves: not needed here)
  Handle hint = kNone;
  for (const std::uint32_t i : insertion_order::hilbert_order(seeds, &left_half, false)) {
    const Location where = mesh.locate(seeds[i], hint);
    hint = where.handle;
    start[supported[i]] = domain_triangle_at(mesh, where);
  }
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (start[r] != kNone) continue;
    const Point& seed = regions[r].seed;
    std::ostringstream message;
    message.precision(17);
    message << "region " << r + 1 << ": its seed (" << seed.x << ", " << seed.y
            << ") lies outside the domain (outside the segments, or in a hole)";
    throw InputError(source, regions[r].line, message.str());
  }
  // Each region spreads from the triangle holding its seed to every domain triangle reachable
  // without crossing a subsegment, and a later region wins where two reach the same triangles.
  // Two seeds reach either the same triangles (the same piece of the domain between subsegments)
  // or disjoint ones, so the regions are spread last first, and one whose seed's triangle a later
  // region already holds is skipped: every triangle is visited once (in the given order, 40,000
  // seeds in one piece flooded it 40,000 times).
  std::vector<std::int32_t> region(mesh.triangle_slots(), -1);
  std::vector<TriangleId> stack;
  for (std::size_t r = regions.size(); r-- > 0;) {
    if (region[start[r]] >= 0) continue;
    const auto mark = static_cast<std::int32_t>(r);
    region[start[r]] = mark;
    stack.assign(1, start[r]);
    while (!stack.empty()) {
      const TriangleId t = stack.back();
      stack.pop_back();
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (mesh.is_segment(h)) continue;
        const TriangleId u = triangle_of(mesh.sym(h));
        if (region[u] < 0 && mesh.in_domain(u)) {
          region[u] = mark;
          stack.push_back(u);
        }
      }
    }
  }
  return region;
}

namespace {

// The array index of each triangle slot: the domain triangles numbered in slot order. Kept as
// one bit per slot (in the domain or not) and, per word of 64 slots, the domain triangles before
// it: an index is that count plus the set bits below the slot in its word. That is 3/16 of a
// byte per slot, against 4 for a table of indices: the neighbours' look-ups stay in cache, and
// there is no fresh table to fault in (a 2M-triangle mesh: 380 KB against 8 MB).
class DomainNumbering {
 public:
  // Numbers the domain triangles of `mesh` in `ranges` contiguous ranges of words: each range
  // counts its own, then adds the counts of the ranges before it.
  DomainNumbering(const Mesh& mesh, std::size_t ranges) {
    const std::size_t slots = mesh.triangle_slots(), words = slots / 64 + 1;  // a word for slot `slots`
    bits_.assign(words, 0);
    before_.assign(words, 0);
    std::vector<std::size_t> first_of_range(ranges + 1, 0);
    support::parallel_ranges(ranges, words, [&](std::size_t k, std::size_t begin, std::size_t end) {
      std::size_t in_range = 0;
      for (std::size_t w = begin; w < end; ++w) {
        std::uint64_t bits = 0;
        for (std::size_t t = 64 * w; t < std::min(slots, 64 * w + 64); ++t) {
          bits |= std::uint64_t{mesh.in_domain(static_cast<TriangleId>(t))} << (t - 64 * w);
        }
        bits_[w] = bits;
        before_[w] = static_cast<std::uint32_t>(in_range);
        in_range += support::set_bits(bits);
      }
      first_of_range[k + 1] = in_range;
    });
    for (std::size_t k = 0; k < ranges; ++k) first_of_range[k + 1] += first_of_range[k];
    count_ = first_of_range[ranges];
    support::parallel_ranges(ranges, words, [&](std::size_t k, std::size_t begin, std::size_t end) {
      for (std::size_t w = begin; w < end; ++w) before_[w] += static_cast<std::uint32_t>(first_of_range[k]);
    });
  }

  // The number of domain triangles.
  std::size_t count() const { return count_; }
  // The domain triangles in slots [0, t), for t up to the number of slots.
  std::size_t before(TriangleId t) const {
    const std::size_t w = t >> 6;
    return before_[w] + support::set_bits(bits_[w] & ((std::uint64_t{1} << (t & 63)) - 1));
  }
  // Slot t's array index; kNoTriangle outside the domain.
  std::int32_t index(TriangleId t) const {
    return ((bits_[t >> 6] >> (t & 63)) & 1) != 0 ? static_cast<std::int32_t>(before(t)) : kNoTriangle;
  }

 private:
  std::vector<std::uint64_t> bits_;
  std::vector<std::uint32_t> before_;
  std::size_t count_ = 0;
};

// Triangle's regional attributes (region_of_triangles), 0 where no region reaches.
void spread_region_attributes(const Mesh& mesh, const std::vector<Region>& regions, const std::string& source,
                              const DomainNumbering& numbering, MeshArrays& out) {
  out.triangle_attributes.assign(out.triangle_count(), 0.0);
  const std::vector<std::int32_t> region = region_of_triangles(mesh, regions, source);
  for (TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    const std::int32_t index = numbering.index(t);
    if (index == kNoTriangle || region[t] < 0) continue;
    out.triangle_attributes[static_cast<std::size_t>(index)] = regions[static_cast<std::size_t>(region[t])].attribute;
  }
}


constexpr std::uint8_t kSegmentEdges = kSegmentEdge0 * 7;  // the three subsegment bits of Mesh::flags

// What the vertex kinds ask of to_arrays: a Steiner point (kept or removed) needs the subsegment
// ends for its array kind; removed Steiner points, if any, make the kept vertices renumbered.
struct VertexCensus {
  bool has_steiner = false;
  std::size_t removed_count = 0;
};

// Counts the kinds of the mesh's vertices (VertexCensus).
VertexCensus census_of_vertices(const Mesh& mesh) {
  VertexCensus census;
  const std::size_t point_count = mesh.points.size();
  for (VertexId v = 0; v < point_count; ++v) {
    const VertexKind kind = mesh.vertex_kind[v];
    census.has_steiner |= kind != VertexKind::kInput && kind != VertexKind::kDuplicate;
    census.removed_count += kind == VertexKind::kRemoved;
  }
  return census;
}

// Subsegment ends per vertex: each subsegment has a live triangle on either side, and each side
// counts the origin of its directed edge, so both ends are counted once.
std::vector<std::uint32_t> subsegment_ends(const Mesh& mesh) {
  const std::size_t slots = mesh.triangle_slots();
  std::vector<std::uint32_t> segment_ends;
  support::resize_on_huge_pages(segment_ends, mesh.points.size());
  for (TriangleId t = 0; t < slots; ++t) {
    if ((mesh.flags[t] & kSegmentEdges) == 0 || mesh.is_dead(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (mesh.is_segment(h)) ++segment_ends[mesh.org(h)];
    }
  }
  return segment_ends;
}

// The array kind of a kept vertex of `kind`; a Steiner point's follows from the subsegment ends at
// it: none (free), at most two (on a segment), more (a crossing of segments).
inline ArrayVertexKind array_kind_of(VertexKind kind, const std::vector<std::uint32_t>& segment_ends, VertexId v) {
  if (kind == VertexKind::kDuplicate) return ArrayVertexKind::kDuplicate;
  if (kind == VertexKind::kInput) return ArrayVertexKind::kInput;
  return segment_ends[v] == 0   ? ArrayVertexKind::kSteiner
         : segment_ends[v] <= 2 ? ArrayVertexKind::kSegmentSteiner
                                : ArrayVertexKind::kCrossing;
}

// Below this many vertices or triangle slots a step runs on one thread: starting threads costs
// more than the copy.
inline constexpr std::size_t kParallelCopy = std::size_t{1} << 16;

// The number of contiguous ranges a copy of n items is cut into (one per thread, or one).
std::size_t copy_ranges(std::size_t n, unsigned threads) {
  return n >= kParallelCopy ? support::worker_count(threads) : 1;
}

// Room for n elements in each of the vectors `v`, fresh storage faulted in by `ranges` threads at
// once before anything is written (support::PageFaulter: the kernel clears each page on the
// thread that first touches it, so one thread writing fresh arrays spends most of its time in
// page faults), then sized to n, value-initialised.
template <class... Vectors>
void size_on_populated_pages(std::size_t ranges, std::size_t n, Vectors&... v) {
  (support::reserve_on_huge_pages(v, n), ...);
  if (ranges > 1) {
    support::PageFaulter faulter;
    (faulter.add(v.data() + v.size(), (v.capacity() - v.size()) * sizeof(*v.data())), ...);
    support::parallel_ranges(ranges, ranges, [&](std::size_t, std::size_t, std::size_t) { faulter.work(); });
  }
  (v.resize(n), ...);
}

// Copies the vertices into `out`: all but removed Steiner points, in order (input points keep
// their indices), with their array kinds and markers. Returns the array index of each mesh vertex
// (kNone for a removed one); without a removed point every vertex keeps its index, the table stays
// empty, and the copy runs in ranges on `threads` threads.
std::vector<std::uint32_t> copy_kept_vertices(const Mesh& mesh, const VertexCensus& census,
                                              const std::vector<std::uint32_t>& segment_ends, unsigned threads,
                                              MeshArrays& out) {
  const std::size_t point_count = mesh.points.size();
  const std::size_t marked = mesh.vertex_marker.size();
  const auto marker_of = [&](VertexId v) { return v < marked ? mesh.vertex_marker[v] : 0; };
  std::vector<std::uint32_t> index_of_vertex;
  if (census.removed_count == 0) {
    const std::size_t ranges = copy_ranges(point_count, threads);
    size_on_populated_pages(ranges, 2 * point_count, out.vertices);
    size_on_populated_pages(ranges, point_count, out.vertex_kinds);
    size_on_populated_pages(ranges, point_count, out.vertex_markers);
    support::parallel_ranges(ranges, point_count,
                             [&](std::size_t, std::size_t begin, std::size_t end) {
                               for (VertexId v = static_cast<VertexId>(begin); v < end; ++v) {
                                 out.vertices[2 * v] = mesh.points[v].x;
                                 out.vertices[2 * v + 1] = mesh.points[v].y;
                                 out.vertex_kinds[v] = array_kind_of(mesh.vertex_kind[v], segment_ends, v);
                                 out.vertex_markers[v] = marker_of(v);
                               }
                             });
    return index_of_vertex;
  }
  support::reserve_on_huge_pages(index_of_vertex, point_count);
  index_of_vertex.assign(point_count, kNone);
  const std::size_t kept = point_count - census.removed_count;
  support::reserve_on_huge_pages(out.vertices, 2 * kept);
  support::reserve_on_huge_pages(out.vertex_kinds, kept);
  support::reserve_on_huge_pages(out.vertex_markers, kept);
  for (VertexId v = 0; v < point_count; ++v) {
    const VertexKind kind = mesh.vertex_kind[v];
    if (kind == VertexKind::kRemoved) continue;
    index_of_vertex[v] = static_cast<std::uint32_t>(out.vertex_kinds.size());
    out.vertices.push_back(mesh.points[v].x);
    out.vertices.push_back(mesh.points[v].y);
    out.vertex_kinds.push_back(array_kind_of(kind, segment_ends, v));
    out.vertex_markers.push_back(marker_of(v));
  }
  return index_of_vertex;
}

// The array index of mesh vertex v (copy_kept_vertices' table, or v itself when none was removed).
struct ArrayVertex {
  const std::vector<std::uint32_t>& index_of_vertex;
  bool has_removed;
  std::uint32_t operator()(VertexId v) const {
    if (!has_removed) return v;
    if (index_of_vertex[v] == kNone) throw InternalError("to_arrays: a domain triangle uses a removed vertex");
    return index_of_vertex[v];
  }
};

// The subsegments one range of slots contributes, in slot order.
struct RangeSegments {
  std::vector<std::uint32_t> ends;
  std::vector<std::int32_t> markers;
};

// Copies the domain triangles into `out` at their numbers: corners, neighbours and the
// subsegments (each once, from the lower-numbered domain triangle beside it) with their markers.
// Each of `ranges` contiguous ranges of slots writes its triangles and collects its subsegments,
// which are appended range by range: the arrays do not depend on the number of ranges.
void copy_domain_triangles(const Mesh& mesh, const DomainNumbering& numbering, const ArrayVertex& array_vertex,
                           std::size_t ranges, MeshArrays& out) {
  // The array index of the triangle of handle h: kNoTriangle outside the domain, and for an edge
  // with no triangle across (kNone: a mesh put together by hand, not closed by ghosts).
  const auto slot_index = [&](Handle h) { return h == kNone ? kNoTriangle : numbering.index(triangle_of(h)); };
  size_on_populated_pages(ranges, 3 * numbering.count(), out.triangles);
  size_on_populated_pages(ranges, 3 * numbering.count(), out.neighbours);
  std::vector<RangeSegments> segments(ranges);
  support::parallel_ranges(ranges, mesh.triangle_slots(), [&](std::size_t k, std::size_t begin, std::size_t end) {
    auto next = static_cast<std::int32_t>(numbering.before(static_cast<TriangleId>(begin)));
    for (TriangleId t = static_cast<TriangleId>(begin); t < end; ++t) {
      if (!mesh.in_domain(t)) continue;
      const std::int32_t index = next++;
      const Triangle& triangle = mesh.triangles[t];
      const std::size_t at = 3 * static_cast<std::size_t>(index);
      for (unsigned i = 0; i < 3; ++i) {
        out.triangles[at + i] = array_vertex(triangle.v[i]);
        // Edge i of t is opposite corner i; its neighbour is the triangle of sym (-1 outside).
        out.neighbours[at + i] = slot_index(triangle.n[i]);
      }
      if ((mesh.flags[t] & kSegmentEdges) == 0) continue;
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (!mesh.is_segment(h)) continue;
        const std::int32_t other = slot_index(mesh.sym(h));
        if (other != kNoTriangle && other < index) continue;
        segments[k].ends.push_back(array_vertex(mesh.org(h)));
        segments[k].ends.push_back(array_vertex(mesh.dest(h)));
        segments[k].markers.push_back(mesh.marker(h));
      }
    }
  });
  if (ranges == 1) {
    out.segments = std::move(segments[0].ends);
    out.segment_markers = std::move(segments[0].markers);
    return;
  }
  for (const RangeSegments& range : segments) {
    out.segments.insert(out.segments.end(), range.ends.begin(), range.ends.end());
    out.segment_markers.insert(out.segment_markers.end(), range.markers.begin(), range.markers.end());
  }
}

}  // namespace

// The steps: census_of_vertices, subsegment_ends (only for Steiner points' kinds),
// copy_kept_vertices, DomainNumbering, copy_domain_triangles, spread_region_attributes.
MeshArrays to_arrays(const Mesh& mesh, const std::vector<Region>& regions, const std::string& source,
                     unsigned threads) {
  MeshArrays out;
  const VertexCensus census = census_of_vertices(mesh);
  const std::vector<std::uint32_t> segment_ends = census.has_steiner ? subsegment_ends(mesh) : std::vector<std::uint32_t>();
  const std::vector<std::uint32_t> index_of_vertex = copy_kept_vertices(mesh, census, segment_ends, threads, out);
  const std::size_t ranges = copy_ranges(mesh.triangle_slots(), threads);
  const DomainNumbering numbering(mesh, ranges);
  copy_domain_triangles(mesh, numbering, ArrayVertex{index_of_vertex, census.removed_count != 0}, ranges, out);
  if (!regions.empty()) spread_region_attributes(mesh, regions, source, numbering, out);
  return out;
}

namespace {

// The attributes of `a` and `b` at the point of segment ab nearest p: (1 - s) a + s b, s in [0, 1].
void along_segment(const Point& a, const Point& b, const double* at_a, const double* at_b, const Point& p,
                   std::size_t count, double* out) {
  const double dx = b.x - a.x, dy = b.y - a.y, length2 = dx * dx + dy * dy;
  const double s = length2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0) : 0.0;
  for (std::size_t k = 0; k < count; ++k) out[k] = (1.0 - s) * at_a[k] + s * at_b[k];
}

// Piecewise linear attributes over a triangulation (the input's constrained Delaunay
// triangulation): `values` holds `count` per vertex of `mesh`.
struct LinearAttributes {
  const Mesh& mesh;
  const std::vector<double>& values;
  std::size_t count;

  const double* of(VertexId v) const { return values.data() + static_cast<std::size_t>(v) * count; }

  // The attributes at p, into out[0, count). The walk to p starts at `hint` (kNone: anywhere) and
  // leaves there the triangle p was found in, the start for a point near p.
  void at(const Point& p, double* out, Handle& hint) const {
    const Location where = mesh.locate(p, hint);
    const Handle h = where.handle;
    hint = h;
    if (where.kind == Location::Kind::kOnVertex) {
      std::copy(of(mesh.org(h)), of(mesh.org(h)) + count, out);
      return;
    }
    const TriangleId t = triangle_of(h);
    if (where.kind == Location::Kind::kOnEdge || mesh.is_ghost(t)) {
      // On an edge, or outside the hull beyond the ghost's hull edge: along that edge.
      Handle edge = h;
      for (unsigned e = 0; e < 3 && (mesh.org(edge) == kInfinite || mesh.dest(edge) == kInfinite); ++e) {
        edge = make_handle(t, e);
      }
      const VertexId a = mesh.org(edge), b = mesh.dest(edge);
      along_segment(mesh.points[a], mesh.points[b], of(a), of(b), p, count, out);
      return;
    }
    // Barycentric: the weight of each corner is the area of the triangle p makes with the other
    // two, over the whole triangle's.
    const auto& v = mesh.triangles[t].v;
    const Point &a = mesh.points[v[0]], &b = mesh.points[v[1]], &c = mesh.points[v[2]];
    const double whole = signed_area(a, b, c);
    const double wa = signed_area(p, b, c) / whole, wb = signed_area(a, p, c) / whole, wc = 1.0 - wa - wb;
    for (std::size_t k = 0; k < count; ++k) out[k] = wa * of(v[0])[k] + wb * of(v[1])[k] + wc * of(v[2])[k];
  }
};

// The attributes of the vertices of `cdt`, the constrained Delaunay triangulation of `input`:
// an input point's own; a crossing of input segments linearly along the input segment nearest it
// (the least rounded squared distance, the first in input order among equal ones). The segments
// are found in a tree of their pieces, about one per vertex of `cdt`: a scan of all segments for
// each crossing took O(crossings × segments) (a grid of 400 × 400 crossing segments: 1.9 s of a
// 2.2 s run).
std::vector<double> attributes_of_cdt_vertices(const Pslg& input, const Mesh& cdt) {
  const std::size_t count = input.attributes_per_point, inputs = input.points.size();
  std::vector<double> values(cdt.points.size() * count, 0.0);
  std::copy(input.point_attributes.begin(), input.point_attributes.end(), values.begin());
  if (cdt.points.size() <= inputs || input.segments.empty()) return values;
  const detail::NearestSegment segments(input.points, input.segments, cdt.points.size());
  const double* attributes = input.point_attributes.data();
  for (std::size_t v = inputs; v < cdt.points.size(); ++v) {
    const Point& p = cdt.points[v];
    const Segment& nearest = input.segments[segments.nearest(p)];
    along_segment(input.points[nearest.a], input.points[nearest.b], attributes + nearest.a * count,
                  attributes + nearest.b * count, p, count, values.data() + v * count);
  }
  return values;
}

}  // namespace

void interpolate_vertex_attributes(const Pslg& input, bool convex_hull, MeshArrays& arrays) {
  const std::size_t count = input.attributes_per_point;
  if (count == 0) return;
  if (input.point_attributes.size() != count * input.points.size()) {
    throw InputError(input.source, 0, "vertex attributes: expected " + std::to_string(count) + " per vertex");
  }
  arrays.attributes_per_vertex = count;
  arrays.vertex_attributes.assign(arrays.vertex_count() * count, 0.0);
  const std::size_t inputs = std::min(input.points.size(), arrays.vertex_count());
  std::copy(input.point_attributes.begin(), input.point_attributes.begin() + static_cast<std::ptrdiff_t>(inputs * count),
            arrays.vertex_attributes.begin());
  if (arrays.vertex_count() == inputs) return;  // no Steiner point
  TriangulateOptions plain;
  plain.method = Method::kDt;
  plain.convex_hull = convex_hull;
  Mesh cdt;
  (void)triangulate(input, plain, &cdt);
  const std::vector<double> at_cdt_vertices = attributes_of_cdt_vertices(input, cdt);
  const LinearAttributes linear{cdt, at_cdt_vertices, count};
  // The Steiner points in the Delaunay insertion order (Hilbert curve order in BRIO rounds), each
  // walk starting where the last ended: a few steps each. From anywhere, every walk crossed
  // O(sqrt n) triangles: DR on 160k uniform points with one attribute took 3.7 s of CPU instead of
  // 0.7 s, growing like n^1.8.
  std::vector<Point> steiner(arrays.vertex_count() - inputs);
  for (std::size_t i = 0; i < steiner.size(); ++i) {
    steiner[i] = Point{arrays.vertices[2 * (inputs + i)], arrays.vertices[2 * (inputs + i) + 1]};
  }
  Handle hint = kNone;
  std::size_t left_half = 0;  // (where the order splits in two halves: not needed here)
  for (const std::uint32_t i : insertion_order::hilbert_order(steiner, &left_half, false)) {
    linear.at(steiner[i], arrays.vertex_attributes.data() + (inputs + i) * count, hint);
  }
}

std::vector<Point> points_from_xy(const double* xy, std::size_t count, unsigned threads) {
  static_assert(sizeof(Point) == 2 * sizeof(double), "a Point is its two coordinates");
  std::vector<Point> points;
  const std::size_t ranges = copy_ranges(count, threads);
  size_on_populated_pages(ranges, count, points);
  support::parallel_ranges(ranges, count, [&](std::size_t, std::size_t begin, std::size_t end) {
    if (end > begin) std::memcpy(static_cast<void*>(points.data() + begin), xy + 2 * begin, (end - begin) * sizeof(Point));
  });
  return points;
}

MeshArrays triangulate_arrays(const Pslg& pslg, const TriangulateOptions& options, Mesh* mesh) {
  Mesh result;
  Report report = triangulate(pslg, options, &result);
  MeshArrays out = to_arrays(result, pslg.regions, pslg.source, options.threads);
  interpolate_vertex_attributes(pslg, options.convex_hull, out);
  for (std::string& warning : out.report.warnings) report.warnings.push_back(std::move(warning));
  out.report = std::move(report);
  if (mesh) *mesh = std::move(result);
  return out;
}

}  // namespace mwst
