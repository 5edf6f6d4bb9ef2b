// Constrained Delaunay triangulation: segment insertion by cavity retriangulation.
//
// A segment ab that is not already an edge crosses a run of triangles. We remove them and
// retriangulate the two pseudo-polygons on either side of ab, choosing for each base edge the
// chain vertex whose circle through the base contains no other chain vertex (Anglada 1997;
// Shewchuk and Brown 2015, "Fast segment insertion and incremental construction of constrained
// Delaunay triangulations"). The result is again constrained Delaunay.
//
// Degenerate graphs are resolved on the way (constrained_delaunay): duplicate points merge, zero
// length segments drop, a vertex lying inside a segment splits it, collinear overlaps merge, and
// crossing segments are split at their exact intersection point rounded to doubles (or at an end
// of either segment within rounding of it), or refused with --strict. A crossing whose rounded
// point would leave the supported coordinate range is refused: snapping it into the range would
// move it off both segments.
#include <gmp.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>

#include "mwst/mesh/delaunay.hpp"
#include "mesh/keys.hpp"
#include "mwst/error.hpp"
#include "geometry/expansion.hpp"

namespace mwst {

// ==== the cavity retriangulation begins here =====================================================

namespace {

// Finds an edge with org a whose triangle the direction a→b enters, rotating around a.
// Returns the handle h = a→v1 with apex v2 such that b is strictly left of a→v1 and strictly
// right of a→v2 (the ray crosses the open triangle), or, if a vertex v lies on the ray from a
// towards b, the handle a→v (with *collinear set).
Handle find_wedge(const Mesh& m, Handle start, VertexId b, bool* collinear) {
  const VertexId a = m.org(start);
  const Point& pa = m.points[a];
  const Point& pb = m.points[b];
  // Most segments are already Delaunay edges: look for b among a's neighbours first, without a
  // predicate (orient2d(a, b, b) is an exact zero, which the filter cannot decide cheaply).
  Handle h = start;
  for (std::size_t turn = 0; turn < m.triangles.size() + 8; ++turn) {
    if (m.dest(h) == b) {
      *collinear = true;
      return h;
    }
    h = m.onext(h);
    if (h == start) break;
  }
  // Bounded by the degree of a; a full turn without success means a corrupt mesh.
  for (std::size_t turn = 0; turn < m.triangles.size() + 8; ++turn) {
    const VertexId v1 = m.dest(h), v2 = m.apex(h);
    if (v1 != kInfinite) {
      const Point& p1 = m.points[v1];
      const int o1 = orient2d(pa, p1, pb);
      if (o1 == 0 && (p1.x - pa.x) * (pb.x - pa.x) + (p1.y - pa.y) * (pb.y - pa.y) > 0.0) {
        *collinear = true;
        return h;
      }
      if (o1 > 0 && v2 != kInfinite && orient2d(pa, m.points[v2], pb) < 0) {
        *collinear = false;
        return h;
      }
    }
    h = m.onext(h);
    if (h == start) break;
  }
  throw InternalError("insert_segment: no triangle around the first endpoint faces the second");
}

// Retriangulates the pseudo-polygon with base edge a→b and the chain (left of a→b, listed from
// a's end to b's end) by the Delaunay-vertex rule; appends triangles (a, b, c) counter-clockwise.
void retriangulate(const Mesh& m, VertexId a, VertexId b, const std::vector<VertexId>& chain,
                   std::vector<std::array<VertexId, 3>>& out) {
  struct Task {
    VertexId a, b;
    std::size_t lo, hi;  // chain[lo, hi) between a and b
  };
  std::vector<Task> tasks{{a, b, 0, chain.size()}};
  while (!tasks.empty()) {
    const Task t = tasks.back();
    tasks.pop_back();
    if (t.lo == t.hi) continue;
    // A chain may pass a vertex twice (see insert_segment_step); an entry equal to an end of the
    // base is never a candidate.
    std::size_t best = t.lo;
    while (best < t.hi && (chain[best] == t.a || chain[best] == t.b)) ++best;
    if (best == t.hi) throw InternalError("insert_segment: degenerate cavity chain");
    const Point& pa = m.points[t.a];
    const Point& pbb = m.points[t.b];
    for (std::size_t i = best + 1; i < t.hi; ++i) {
      if (chain[i] == t.a || chain[i] == t.b) continue;
      if (incircle(pa, pbb, m.points[chain[best]], m.points[chain[i]]) > 0) best = i;
    }
    const VertexId c = chain[best];
    out.push_back({t.a, t.b, c});
    tasks.push_back({t.a, c, t.lo, best});
    tasks.push_back({c, t.b, best + 1, t.hi});
  }
}

// ==== the cavity retriangulation ends here =======================================================

// ==== the exact crossing point begins here =======================================================

// Rational numbers for the exact crossing point (GMP; every double is a dyadic rational).
class Rational {
 public:
  Rational() { mpq_init(q_); }
  explicit Rational(double v) : Rational() { mpq_set_d(q_, v); }
  Rational(const Rational&) = delete;
  Rational& operator=(const Rational&) = delete;
  ~Rational() { mpq_clear(q_); }
  mpq_ptr get() { return q_; }
  mpq_srcptr get() const { return q_; }

 private:
  mpq_t q_;
};

// The double nearest to q (ties to even). mpq_get_d truncates toward zero, so the nearest double is
// that value or its neighbour away from zero; the exact distances decide. Called only with values
// inside the coordinate range's bounding boxes, far from overflow.
double round_to_double(mpq_srcptr q) {
  const double toward_zero = mpq_get_d(q);
  const int sign = mpq_sgn(q);
  if (sign == 0) return 0.0;
  const double away = std::nextafter(toward_zero, sign > 0 ? std::numeric_limits<double>::infinity()
                                                           : -std::numeric_limits<double>::infinity());
  Rational low(toward_zero), high(away), near_zero, far_from_zero;
  mpq_sub(near_zero.get(), q, low.get());       // q - toward_zero: the sign of q (or 0)
  mpq_sub(far_from_zero.get(), high.get(), q);  // away - q: the sign of q
  if (sign < 0) {  // distances
    mpq_neg(near_zero.get(), near_zero.get());
    mpq_neg(far_from_zero.get(), far_from_zero.get());
  }
  const int c = mpq_cmp(near_zero.get(), far_from_zero.get());
  if (c == 0) return (std::bit_cast<std::uint64_t>(toward_zero) & 1u) == 0 ? toward_zero : away;
  return c < 0 ? toward_zero : away;
}

// orient2d(c, d, p) = (d - c) × (p - c), exactly.
void exact_orient(const Point& c, const Point& d, const Point& p, Rational& out) {
  Rational dcx(d.x), dcy(d.y), pcx(p.x), pcy(p.y), cx(c.x), cy(c.y), t;
  mpq_sub(dcx.get(), dcx.get(), cx.get());
  mpq_sub(dcy.get(), dcy.get(), cy.get());
  mpq_sub(pcx.get(), pcx.get(), cx.get());
  mpq_sub(pcy.get(), pcy.get(), cy.get());
  mpq_mul(out.get(), dcx.get(), pcy.get());
  mpq_mul(t.get(), dcy.get(), pcx.get());
  mpq_sub(out.get(), out.get(), t.get());
}

// v with 17 significant digits (round-trips), for error messages.
std::string coordinate_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// orient2d(c, d, p) = (d - c) × (p - c), exactly, as a floating-point expansion.
exact::Expansion<16> orient_expansion(const Point& c, const Point& d, const Point& p) {
  exact::Expansion<16> e = exact::difference(d.x, c.x) * exact::difference(p.y, c.y) -
                           exact::difference(d.y, c.y) * exact::difference(p.x, c.x);
  exact::compress(e);
  return e;
}

// The double nearest to n/d (d ≠ 0) when exact sign tests certify it, else NaN (the caller then
// rounds with rationals: a tie, a quotient outside the supported range, or a poor estimate). The
// candidate q, the quotient of the estimates (a few ulps off), is the nearest double iff n/d lies
// strictly between the midpoints q − h₋ and q + h₊ to its neighbours (h = half the gap: exact, no
// subnormals at these magnitudes), i.e. iff n − q·d + h₋·d and n − q·d − h₊·d have opposite signs,
// the first that of d; each is an exact expansion (Shewchuk's Scale-Expansion and sums). Inputs in
// the supported range keep every product far from underflow and overflow (components are multiples
// of 2⁻⁶⁶⁰ and below 1e160). Otherwise q moves one ulp toward n/d, a few times at most.
double certified_quotient(const exact::Expansion<64>& n, const exact::Expansion<32>& d) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double q = exact::estimate(n) / exact::estimate(d);
  const int sd = exact::sign(d);
  for (int step = 0; step < 4; ++step) {
    if (!(std::fabs(q) >= kMinCoordinate && std::fabs(q) <= kMaxCoordinate)) return nan;
    const double below = std::nextafter(q, -kInf), above = std::nextafter(q, kInf);
    exact::Expansion<128> rest = n - exact::scale(d, q);  // n − q·d
    exact::compress(rest);
    const int low = exact::sign(rest + exact::scale(d, 0.5 * (q - below))) * sd;   // vs q − h₋
    const int high = exact::sign(rest - exact::scale(d, 0.5 * (above - q))) * sd;  // vs q + h₊
    if (low > 0 && high < 0) return q;
    if (low == 0 || high == 0) return nan;  // exactly halfway: ties to even, with rationals
    q = low < 0 ? below : above;
  }
  return nan;
}

}  // namespace

// (geometry.hpp) With o_a = orient(c, d, a) and o_b = orient(c, d, b), the point is
// a + o_a/(o_a - o_b)·(b - a) = (o_a·b - o_b·a)/(o_a - o_b), each coordinate rounded once. First
// with floating-point expansions, whose certified rounding (certified_quotient) decides almost
// always at a small fraction of the cost of rationals (qtr computes a crossing for every cell edge
// a segment crosses); then, where it cannot, with GMP rationals.
Point exact_crossing(const Point& a, const Point& b, const Point& c, const Point& d) {
  if (in_supported_range(a) && in_supported_range(b) && in_supported_range(c) && in_supported_range(d)) {
    const exact::Expansion<16> oa = orient_expansion(c, d, a), ob = orient_expansion(c, d, b);
    const exact::Expansion<32> denominator = oa - ob;
    if (exact::sign(denominator) == 0) return segment_intersection(a, b, c, d);  // parallel: no crossing
    auto coordinate = [&](double av, double bv) {
      exact::Expansion<64> numerator = exact::scale(oa, bv) - exact::scale(ob, av);
      if (exact::sign(numerator) == 0) return 0.0;
      exact::compress(numerator);
      return certified_quotient(numerator, denominator);
    };
    const Point fast{coordinate(a.x, b.x), coordinate(a.y, b.y)};
    if (!std::isnan(fast.x) && !std::isnan(fast.y)) return fast;
  }
  Rational oa, ob, denominator, numerator, t;
  exact_orient(c, d, a, oa);
  exact_orient(c, d, b, ob);
  mpq_sub(denominator.get(), oa.get(), ob.get());
  if (mpq_sgn(denominator.get()) == 0) return segment_intersection(a, b, c, d);  // parallel: no crossing
  auto coordinate = [&](double av, double bv) {
    Rational va(av), vb(bv);
    mpq_mul(numerator.get(), oa.get(), vb.get());
    mpq_mul(t.get(), ob.get(), va.get());
    mpq_sub(numerator.get(), numerator.get(), t.get());
    mpq_div(numerator.get(), numerator.get(), denominator.get());
    return round_to_double(numerator.get());
  };
  const double x = coordinate(a.x, b.x);
  const double y = coordinate(a.y, b.y);
  return {x, y};
}

// ==== the exact crossing point ends here =========================================================

// ==== inserting one segment begins here ==========================================================
//
// insert_segment_step's steps: find_wedge (the first crossed triangle), walk_cavity (the triangles
// the segment crosses and the chains on either side), retriangulate_cavity (the two pseudo-
// polygons), read_cavity_border (the border edges and their marks) and fill_cavity (the new
// triangles into the old slots, linked to the border and to each other).

namespace {

// The cavity of a segment piece a→end: the triangles it crosses in walk order, the chains of
// vertices left (upper) and right (lower) of it from a to end, and the chain edges, keyed in the
// cavity's orientation, with the handles outside them.
struct Cavity {
  std::vector<TriangleId> triangles;
  std::vector<VertexId> upper, lower;
  std::vector<std::pair<std::uint64_t, Handle>> outer;
  VertexId end = kNone;
};

// Walks from `first` = a→v1 (apex v2; v1 right of a→b, v2 left) across the triangles the open
// segment a→b crosses, recording the cavity, up to b or the first vertex on the open segment
// (cavity.end). Returns the first subsegment edge it would cross instead (the mesh is never
// changed), or kNone.
Handle walk_cavity(const Mesh& m, Handle first, VertexId b, Cavity& cavity) {
  const VertexId a = m.org(first);
  const Point pa = m.points[a], pb = m.points[b];
  cavity.upper.push_back(a);
  cavity.lower.push_back(a);
  Handle h = first;
  {
    cavity.triangles.push_back(h >> 2);
    const VertexId v1 = m.dest(h), v2 = m.apex(h);
    cavity.lower.push_back(v1);
    cavity.upper.push_back(v2);
    cavity.outer.emplace_back(edge_key(a, v1), m.sym(h));
    cavity.outer.emplace_back(edge_key(v2, a), m.sym(Mesh::lprev(h)));
    h = Mesh::lnext(h);  // v1→v2, the crossed edge
  }
  for (;;) {
    if (m.is_segment(h)) return h;
    const Handle s = m.sym(h);  // v2→v1 in the next triangle
    const VertexId w = m.apex(s);
    if (w == kInfinite) throw InternalError("insert_segment: the segment leaves the convex hull");
    cavity.triangles.push_back(s >> 2);
    const VertexId vr = m.dest(s), vl = m.org(s);  // right (lower) and left (upper) ends
    // w == b, or w on the open segment: this piece ends at w.
    const int o = w == b ? 0 : orient2d(pa, pb, m.points[w]);
    if (o == 0) {
      cavity.outer.emplace_back(edge_key(vr, w), m.sym(Mesh::lnext(s)));
      cavity.outer.emplace_back(edge_key(w, vl), m.sym(Mesh::lprev(s)));
      cavity.lower.push_back(w);
      cavity.upper.push_back(w);
      cavity.end = w;
      return kNone;
    }
    if (o > 0) {
      // w is on the upper side: edge w→vl is an upper chain edge; cross vr→w next.
      cavity.outer.emplace_back(edge_key(w, vl), m.sym(Mesh::lprev(s)));
      cavity.upper.push_back(w);
      h = Mesh::lnext(s);  // vr→w
    } else {
      cavity.outer.emplace_back(edge_key(vr, w), m.sym(Mesh::lnext(s)));
      cavity.lower.push_back(w);
      h = Mesh::lprev(s);  // w→vl
    }
  }
}

// The cavity's new triangles: the upper pseudo-polygon on base a→end (chain left of it), then the
// lower one on base end→a, one triangle per old slot.
void retriangulate_cavity(const Mesh& m, VertexId a, const Cavity& cavity,
                          std::vector<std::array<VertexId, 3>>& tris) {
  tris.reserve(cavity.triangles.size());
  const std::vector<VertexId> upper_chain(cavity.upper.begin() + 1, cavity.upper.end() - 1);
  std::vector<VertexId> lower_chain(cavity.lower.begin() + 1, cavity.lower.end() - 1);
  std::reverse(lower_chain.begin(), lower_chain.end());
  retriangulate(m, a, cavity.end, upper_chain, tris);
  retriangulate(m, cavity.end, a, lower_chain, tris);
  if (tris.size() != cavity.triangles.size()) throw InternalError("insert_segment: cavity count mismatch");
}

// A border edge of the cavity: the handle outside it and its segment mark.
struct OuterEdge {
  Handle handle;
  bool segment;
  std::int32_t marker;
};
using OuterEdges = std::unordered_map<std::uint64_t, OuterEdge>;
using InnerSegments = std::vector<std::pair<std::uint64_t, std::int32_t>>;

// Reads the border edges' segment marks before the slots are rewritten. A vertex whose whole star
// is crossed (it lies on one side, but the segment passes around it) hangs into the cavity by an
// edge whose two triangles are both in the cavity: the chain walks that edge out and back, so it
// was recorded in both directions. It is inside the cavity, not on its border: it leaves the
// border, and if it was a subsegment it goes to inner_segments (to be marked again).
void read_cavity_border(const Mesh& m, const Cavity& cavity, OuterEdges& outer_map, InnerSegments& inner_segments) {
  outer_map.reserve(cavity.outer.size() * 2);
  for (const auto& [key, oh] : cavity.outer) outer_map.emplace(key, OuterEdge{oh, m.is_segment(oh), m.marker(oh)});
  for (const auto& entry : cavity.outer) {
    const std::uint64_t reverse = (entry.first << 32) | (entry.first >> 32);
    const auto it = outer_map.find(reverse);
    if (it == outer_map.end()) continue;
    if (it->second.segment) {
      const auto u = static_cast<VertexId>(entry.first >> 32), v = static_cast<VertexId>(entry.first);
      inner_segments.emplace_back(undirected_key(u, v), it->second.marker);
    }
    outer_map.erase(it);
    outer_map.erase(entry.first);
  }
}

// Writes tris into the cavity's slots and links every edge: a border edge to the handle outside it
// (keeping its mark), an inner edge to its twin; then marks the hanging subsegments again. Returns
// the new edge end→a.
Handle fill_cavity(Mesh& m, VertexId a, const Cavity& cavity, const std::vector<std::array<VertexId, 3>>& tris,
                   const OuterEdges& outer_map, const InnerSegments& inner_segments) {
  std::unordered_map<std::uint64_t, Handle> inner;
  inner.reserve(tris.size() * 4);
  Handle result_hint = kNone;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = cavity.triangles[i];
    m.triangles[t].v = tris[i];
    m.flags[t] = static_cast<std::uint8_t>(m.flags[t] & kOutside);
  }
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = cavity.triangles[i];
    for (unsigned e = 0; e < 3; ++e) {
      const Handle he = make_handle(t, e);
      const VertexId u = m.org(he), v = m.dest(he);
      const auto it = outer_map.find(edge_key(u, v));
      if (it != outer_map.end()) {
        m.triangles[t].n[e] = it->second.handle;
        m.triangles[it->second.handle >> 2].n[it->second.handle & 3] = he;
        if (it->second.segment) m.set_segment(he, it->second.marker);
        continue;
      }
      const auto twin = inner.find(edge_key(v, u));
      if (twin != inner.end()) {
        m.triangles[t].n[e] = twin->second;
        m.triangles[twin->second >> 2].n[twin->second & 3] = he;
        inner.erase(twin);
      } else {
        inner.emplace(edge_key(u, v), he);
      }
      if (u == cavity.end && v == a) result_hint = he;  // end→a: org is the piece's end
    }
  }
  if (!inner.empty()) throw InternalError("insert_segment: unmatched cavity edge");
  for (const auto& [key, mark] : inner_segments) {
    for (const TriangleId t : cavity.triangles) {
      for (unsigned e = 0; e < 3; ++e) {
        const Handle he = make_handle(t, e);
        if (undirected_key(m.org(he), m.dest(he)) == key) m.set_segment(he, mark);
      }
    }
  }
  return result_hint;
}

}  // namespace

namespace detail {

// What insert_segment_step found on the way from a towards b.
struct SegmentStep {
  enum class Kind { kDone, kVertex, kCrossing } kind = Kind::kDone;
  VertexId vertex = kNone;  // kVertex: a vertex on the open segment where this piece ended
  Handle crossed = kNone;   // kCrossing: a subsegment edge crossing ab
  Handle hint = kNone;      // an edge whose org is the vertex where this piece ended
  bool overlap = false;     // the piece was already a subsegment (a collinear overlap)
};

// Inserts the part of segment a→b up to the first vertex on it (or b) as a constrained edge, or
// reports the first subsegment it crosses without changing the mesh. `start` must have org a.
SegmentStep insert_segment_step(Mesh& m, Handle start, VertexId b, std::int32_t marker) {
  const VertexId a = m.org(start);
  bool collinear = false;
  const Handle first = find_wedge(m, start, b, &collinear);
  SegmentStep step;
  if (collinear) {
    // The edge a→v lies along the segment: mark it.
    const VertexId v = m.dest(first);
    step.overlap = m.is_segment(first);
    if (!step.overlap) m.set_segment(first, marker);  // an overlap keeps the first marker
    step.kind = v == b ? SegmentStep::Kind::kDone : SegmentStep::Kind::kVertex;
    step.vertex = v;
    step.hint = m.sym(first);
    return step;
  }
  Cavity cavity;
  const Handle crossed = walk_cavity(m, first, b, cavity);
  if (crossed != kNone) {
    step.kind = SegmentStep::Kind::kCrossing;
    step.crossed = crossed;
    return step;  // nothing changed yet
  }
  std::vector<std::array<VertexId, 3>> tris;
  retriangulate_cavity(m, a, cavity, tris);
  OuterEdges outer_map;
  InnerSegments inner_segments;
  read_cavity_border(m, cavity, outer_map, inner_segments);
  const Handle result_hint = fill_cavity(m, a, cavity, tris, outer_map, inner_segments);
  m.set_segment(result_hint, marker);
  step.kind = cavity.end == b ? SegmentStep::Kind::kDone : SegmentStep::Kind::kVertex;
  step.vertex = cavity.end;
  step.hint = result_hint;
  return step;
}

}  // namespace detail

// ==== inserting one segment ends here ============================================================

// ==== inserting a graph begins here ==============================================================

// Inserts segment a→b into a constrained Delaunay triangulation, piece by piece through the
// vertices on it; a crossed subsegment is an internal error here (constrained_delaunay splits).
void insert_segment(Mesh& m, VertexId a, VertexId b, std::int32_t marker) {
  Handle start = kNone;
  VertexId from = a;
  while (from != b) {
    const Location loc = m.locate(m.points[from], start);
    if (loc.kind != Location::Kind::kOnVertex || m.org(loc.handle) != from) {
      throw InternalError("insert_segment: endpoint is not a vertex of the mesh");
    }
    const auto step = detail::insert_segment_step(m, loc.handle, b, marker);
    if (step.kind == detail::SegmentStep::Kind::kCrossing) {
      throw InternalError("insert_segment: the segment crosses a subsegment");
    }
    from = step.vertex;
    start = step.hint;
  }
}

namespace {

// Inserts the segments of a graph into its Delaunay triangulation, resolving degeneracies.
class SegmentInserter {
 public:
  SegmentInserter(Mesh& mesh, const Pslg& pslg, const ConstrainOptions& options,
                  ConstrainStats& stats)
      : m_(mesh), pslg_(pslg), options_(options), stats_(stats) {}

  // Inserts input segment `id` (a→b), and the pieces its crossings leave, until none is pending.
  void insert(VertexId a, VertexId b, std::int32_t marker, std::uint32_t id) {
    pending_.push_back({a, b, marker, id});
    while (!pending_.empty()) {
      const Piece p = pending_.back();
      pending_.pop_back();
      insert_piece(p);
    }
  }

 private:
  struct Piece {
    VertexId a, b;
    std::int32_t marker;
    std::uint32_t id;  // index of the input segment it belongs to
  };

  // "segment N (line L)", in the input's numbering.
  std::string describe(std::uint32_t id) const {
    std::string s = "segment " + std::to_string(id + static_cast<std::uint32_t>(pslg_.first_index));
    if (id < pslg_.segment_lines.size()) s += " (line " + std::to_string(pslg_.segment_lines[id]) + ")";
    return s;
  }

  // Inserts piece p step by step through the vertices on it; a crossed subsegment hands over to
  // resolve_crossing.
  void insert_piece(Piece p) {
    VertexId from = p.a;
    while (from != p.b) {
      // The previous piece usually ended where this one starts (chains of segments): its hint is
      // then an edge out of `from`, and no walk is needed.
      Handle start = hint_;
      if (start == kNone || m_.is_dead(start >> 2) || m_.org(start) != from) {
        const Location loc = m_.locate(m_.points[from], hint_);
        if (loc.kind != Location::Kind::kOnVertex || m_.org(loc.handle) != from) {
          throw InternalError("segment endpoint is not a vertex of the mesh");
        }
        start = loc.handle;
      }
      // Mark overlaps: the part of the segment that is already a subsegment.
      const auto step = detail::insert_segment_step(m_, start, p.b, p.marker);
      if (step.kind == detail::SegmentStep::Kind::kCrossing) {
        resolve_crossing(p, from, step.crossed);
        return;  // the remaining pieces were queued
      }
      if (step.overlap) ++stats_.overlaps;
      if (options_.strict) subsegment_ids_.push_back({undirected_key(from, step.vertex), p.id});
      if (step.vertex != p.b && m_.vertex_kind[step.vertex] != VertexKind::kSteinerOnSegment) {
        ++stats_.split_by_vertex;
      }
      from = step.vertex;
      hint_ = step.hint;
    }
  }

  // Splits the piece p (now from `from`) and the subsegment `crossed` it crosses at their crossing
  // point, or at an endpoint of either within rounding of it, and queues the pieces left.
  void resolve_crossing(const Piece& p, VertexId from, Handle crossed) {
    const VertexId c = m_.org(crossed), d = m_.dest(crossed);
    const std::uint32_t other_id = input_segment_of(undirected_key(c, d), p.id);
    count_crossing(p, other_id);
    const std::int32_t other_marker = m_.marker(crossed);
    // The exact crossing rounded to doubles (possibly outside the supported range: see
    // place_crossing_vertex).
    const Point x = exact_crossing(m_.points[from], m_.points[p.b], m_.points[c], m_.points[d]);
    const VertexId snap = crossing_snap(p, from, c, d, x);
    if (snap == c || snap == d) {
      // The piece passes (within rounding) through an end of the crossed subsegment: split the
      // piece there and leave the subsegment alone.
      --stats_.crossings;
      ++stats_.snapped;
      queue_piece(snap, p.b, p.marker, p.id);
      queue_piece(from, snap, p.marker, p.id);
      return;
    }
    const VertexId v = place_crossing_vertex(p, crossed, snap, x);
    queue_piece(v, p.b, p.marker, p.id);
    queue_piece(from, v, p.marker, p.id);
    queue_piece(v, d, other_marker, other_id);
    queue_piece(c, v, other_marker, other_id);
  }

  // Refuses a crossing under --strict (naming both segments) or past the crossing limits; counts it.
  void count_crossing(const Piece& p, std::uint32_t other_id) {
    if (options_.strict) {
      throw InputError(pslg_.source, p.id < pslg_.segment_lines.size() ? pslg_.segment_lines[p.id] : 0,
                       describe(p.id) + " crosses " + describe(other_id));
    }
    // (Resolutions at an existing vertex make none, so they are capped apart: a cycle of them
    // would otherwise never end.)
    if (++stats_.crossings > crossing_limit() || ++resolutions_ > 4 * crossing_limit()) {
      throw InputError(pslg_.source, 0, "too many segment crossings to resolve");
    }
  }

  // Queues the piece u→w unless it is empty.
  void queue_piece(VertexId u, VertexId w, std::int32_t marker, std::uint32_t id) {
    if (u != w) pending_.push_back({u, w, marker, id});
  }

  // The endpoint of the piece from→p.b or of the crossed subsegment c→d where the two cross, or
  // kNone. An endpoint of either piece that lies within a few hundred times the rounding of the
  // crossing point x, or of the other piece's line (between its ends), is where the two cross: the
  // crossing is resolved there, with no new vertex. Otherwise nearly coincident chains (a segment
  // given twice, overlapping near-collinear segments) make each rounded crossing point cross the
  // other chain again, one ulp further on; and where long segments cross at a tiny angle θ the
  // rounded point is off by rounding/θ along them (6e9 long, θ ≈ 1e-9: hundreds of units), so
  // that each new point made a new crossing with the chains it had just passed (7 points and 4
  // distinct segments of a fuzzed input took 2183 crossing points), while the points already made
  // lie within rounding of those chains' lines.
  //
  // The rounding is that of the points involved, where they are: x's own, and each piece's line's
  // at x, which interpolates its ends' (an end is an input point, or a crossing rounded to within
  // an ulp of its magnitude); along the pieces it grows as 1/sin θ. It is capped by a few hundred
  // ulps of the larger of x's magnitude and the pieces' lengths. That cap alone let a segment 13
  // long near 1e11 (doubles 1.5e-5 apart) snap by 0.5 to the end of a segment 5.8e15 long that
  // crosses it at 57°, off it by 33,000 of its ulps (a fuzzed input: the mesh's triangle then
  // straddled the segment).
  VertexId crossing_snap(const Piece& p, VertexId from, VertexId c, VertexId d, const Point& x) const {
    const Point& pf = m_.points[from];
    const Point& pb = m_.points[p.b];
    const Point& pc = m_.points[c];
    const Point& pd = m_.points[d];
    const double cap = kSnapRoundings * 0x1p-52 *
                       std::max({std::fabs(x.x), std::fabs(x.y), distance(pf, pb), distance(pc, pd)});
    const double piece_dx = pb.x - pf.x, piece_dy = pb.y - pf.y, crossed_dx = pd.x - pc.x, crossed_dy = pd.y - pc.y;
    const double sin_angle = std::fabs(piece_dx * crossed_dy - piece_dy * crossed_dx) /
                             (std::hypot(piece_dx, piece_dy) * std::hypot(crossed_dx, crossed_dy));
    const double at_x = kSnapRoundings * (rounding_of(x) + line_rounding_at(x, pf, pb) + line_rounding_at(x, pc, pd));
    const double near_x = sin_angle > 0.0 ? std::min(cap, at_x / sin_angle) : cap;
    // Is w within rounding of the line through u and v, and strictly between u and v along it?
    const auto on_line = [&](const Point& w, const Point& u, const Point& v) {
      const double ux = v.x - u.x, uy = v.y - u.y, wx = w.x - u.x, wy = w.y - u.y;
      const double length = std::hypot(ux, uy);
      const double along = ux * wx + uy * wy;
      const double tolerance = std::min(cap, kSnapRoundings * (rounding_of(w) + line_rounding_at(w, u, v)));
      return along > 0.0 && along < length * length && std::fabs(ux * wy - uy * wx) <= tolerance * length;
    };
    double nearest = std::numeric_limits<double>::infinity();
    VertexId snap = kNone;
    for (const VertexId w : {c, d, from, p.b}) {
      const double dist = distance(x, m_.points[w]);
      const bool is_end_of_crossed = w == c || w == d;
      const bool near = dist <= near_x ||
                        (is_end_of_crossed ? on_line(m_.points[w], pf, pb) : on_line(m_.points[w], pc, pd));
      if (near && dist < nearest) {
        nearest = dist;
        snap = w;
      }
    }
    return snap;
  }
  static constexpr double kSnapRoundings = 256.0;

  // How far a point's coordinates may be from where exact arithmetic would put them: an ulp of
  // its magnitude (2^-52 of it, rounded up to a power of two or not: within a factor 2).
  static double rounding_of(const Point& q) { return 0x1p-52 * std::max(std::fabs(q.x), std::fabs(q.y)); }

  // How far the line through u and v may be, at q (between them), from the line through where
  // exact arithmetic would put u and v: their roundings, interpolated.
  static double line_rounding_at(const Point& q, const Point& u, const Point& v) {
    const double length = distance(u, v);
    if (!(length > 0.0)) return std::max(rounding_of(u), rounding_of(v));
    const double to_u = std::min(1.0, distance(q, u) / length), to_v = std::min(1.0, distance(q, v) / length);
    return rounding_of(u) * to_v + rounding_of(v) * to_u;
  }

  // Unmarks the crossed subsegment (it is re-inserted in two pieces) and returns the vertex both
  // continue through: `snap` (an end of the piece), an existing vertex at x, or a new one at x.
  VertexId place_crossing_vertex(const Piece& p, Handle crossed, VertexId snap, const Point& x) {
    m_.clear_segment(crossed);
    VertexId v = snap;
    if (snap == kNone && !in_supported_range(x)) {
      // No double in the range lies within rounding of the crossing (a coordinate between 0 and
      // 1e-50 in magnitude): moving it to 0 would put the vertex off both segments.
      throw InputError(pslg_.source, p.id < pslg_.segment_lines.size() ? pslg_.segment_lines[p.id] : 0,
                       describe(p.id) + " crosses another segment at (" + coordinate_text(x.x) + ", " +
                           coordinate_text(x.y) +
                           "), outside the supported coordinate range (0 or a magnitude between 1e-50 "
                           "and 1e50): the crossing vertex cannot be placed on both segments");
    }
    if (snap != kNone) {
      --stats_.crossings;
      ++stats_.snapped;
    } else {
      v = m_.add_vertex(x, VertexKind::kSteinerOnSegment, 0);
      const VertexId got = m_.insert_vertex(v, crossed, &hint_);
      if (got != v) {
        // The rounded point coincides with an existing vertex: use it, drop the new one.
        m_.points.pop_back();
        m_.vertex_kind.pop_back();
        m_.vertex_marker.pop_back();
        v = got;
        --stats_.crossings;
        ++stats_.snapped;
      }
    }
    return v;
  }

  // The input segment of the subsegment with undirected key `key` (under --strict), else otherwise.
  std::uint32_t input_segment_of(std::uint64_t key, std::uint32_t otherwise) const {
    for (auto it = subsegment_ids_.rbegin(); it != subsegment_ids_.rend(); ++it) {
      if (it->first == key) return it->second;
    }
    return otherwise;
  }

  // Segments cross at most s(s − 1)/2 times in exact arithmetic; rounded crossing points add a
  // few (a piece moved by an ulp may cross a neighbour again), but counts far beyond that are
  // rounding feeding on itself (segments almost on top of each other at coordinates where the
  // spacing of doubles is coarse): refused past 4096 + 4 s² (more than 8 times the exact
  // bound), and never past kMaxCrossings. (The fixed cap alone let 96 segments near 2e16 run
  // 3 s before the refusal.)
  static constexpr std::size_t kMaxCrossings = 1u << 20;
  std::size_t crossing_limit() const {
    const std::size_t s = pslg_.segments.size();
    return std::min(kMaxCrossings, std::size_t{4096} + 4 * s * s) + 4 * s;
  }
  std::size_t resolutions_ = 0;  // crossings resolved, at new vertices or existing ones
  Mesh& m_;
  const Pslg& pslg_;
  const ConstrainOptions& options_;
  ConstrainStats& stats_;
  std::vector<Piece> pending_;
  // Which input segment each subsegment came from, kept only under --strict, where the first
  // crossing is an error that names both segments (the search is linear: it runs once).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> subsegment_ids_;
  Handle hint_ = kNone;
};

}  // namespace

// The constrained Delaunay triangulation of a graph: the Delaunay triangulation of its points,
// then its segments inserted one by one in input order (SegmentInserter).
Mesh constrained_delaunay(const Pslg& pslg, const ConstrainOptions& options, ConstrainStats* stats_out) {
  using Clock = std::chrono::steady_clock;
  ConstrainStats stats;
  const auto t0 = Clock::now();
  Mesh m;
  try {
    m = delaunay(pslg.points, nullptr, options.threads);
  } catch (const InputError& e) {
    throw InputError(pslg.source, e.line(), e.what());
  }
  if (!pslg.point_markers.empty() && pslg.point_markers.size() == pslg.points.size()) {
    m.vertex_marker = pslg.point_markers;
  }
  stats.duplicates = m.duplicates.size();
  const auto t1 = Clock::now();
  // Where each duplicate went.
  std::vector<VertexId> representative;
  if (!m.duplicates.empty()) {
    representative.resize(pslg.points.size());
    for (VertexId v = 0; v < representative.size(); ++v) representative[v] = v;
    for (const auto& [dup, kept] : m.duplicates) representative[dup] = kept;
  }
  auto rep = [&](std::uint32_t v) { return representative.empty() ? v : representative[v]; };
  SegmentInserter inserter(m, pslg, options, stats);
  bool any_segment = false;
  for (std::uint32_t i = 0; i < pslg.segments.size(); ++i) {
    const Segment& s = pslg.segments[i];
    if (s.a >= pslg.points.size() || s.b >= pslg.points.size()) {
      throw InputError(pslg.source, i < pslg.segment_lines.size() ? pslg.segment_lines[i] : 0,
                       "segment names a vertex that does not exist");
    }
    const VertexId a = rep(s.a), b = rep(s.b);
    if (a == b) {
      ++stats.zero_length;
      continue;
    }
    any_segment = true;
    inserter.insert(a, b, s.marker, i);
  }
  if (stats.crossings > 0 || stats.snapped > 0) {
    // Un-marking a crossed subsegment and re-inserting it through a rounded crossing point can
    // leave edges near it that only the old subsegment made legal: restore the constrained
    // Delaunay property everywhere by Lawson flips (subsegments are never flipped).
    std::vector<Handle> all;
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
      if (m.is_dead(t)) continue;
      for (unsigned e = 0; e < 3; ++e) all.push_back(make_handle(t, e));
    }
    restore_delaunay(m, all);
  }
  const auto t2 = Clock::now();
  if (any_segment || !pslg.holes.empty()) {
    carve(m, any_segment ? pslg.holes : std::vector<Point>{}, options.convex_hull || !any_segment,
          &stats.warnings);
    if (!any_segment && !pslg.holes.empty()) {
      stats.warnings.push_back("the input has no segments, so its domain is the convex hull; " +
                               std::to_string(pslg.holes.size()) + " hole seed(s) ignored");
    }
  }
  const auto t3 = Clock::now();
  stats.seconds_delaunay = std::chrono::duration<double>(t1 - t0).count();
  stats.seconds_segments = std::chrono::duration<double>(t2 - t1).count();
  stats.seconds_carve = std::chrono::duration<double>(t3 - t2).count();
  if (stats_out) *stats_out = std::move(stats);
  return m;
}

// ==== inserting a graph ends here ================================================================

}  // namespace mwst
