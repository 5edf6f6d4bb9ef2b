// Delaunay triangulation of a point set: incremental insertion (Lawson flips) in Hilbert-curve
// order with a walking point location that starts at the previous insertion.
//
// Why this algorithm: Amenta, Choi and Rote ("Incremental constructions con BRIO", 2003) and
// Buchin's analysis show that inserting along a space-filling curve keeps walks O(1) on average, and
// CGAL's spatial-sort + walk measured twice as fast as Triangle's divide and conquer on our
// machines. Points are copied in curve order so that the vertices a walk touches are neighbours
// in memory; ids are mapped back to the input order at the end. The triangle array is reserved
// exactly (2n − 2 triangles, ghosts included, for n vertices) so it never reallocates.
//
// The sections below: the incremental construction (build_incremental), the merge of two halves
// separated by a vertical line (merge_halves, Guibas and Stolfi's ladder), and the entry points.
// The insertion order itself (Hilbert curve sort, BRIO rounds) is in insertion_order.cpp.
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "mwst/mesh/delaunay.hpp"
#include "mesh/insertion_order.hpp"
#include "support/huge_pages.hpp"
#include "mwst/error.hpp"

namespace mwst {

namespace {

using insertion_order::hilbert_order;
using insertion_order::kParallelThreshold;
using insertion_order::run_both;
using support::advise_huge_pages;

// ==== the incremental construction begins here ===================================================

// Builds the first real triangle on vertices (a, b, c), counter-clockwise, with its three ghosts.
void make_first_triangle(Mesh& m, VertexId a, VertexId b, VertexId c) {
  const TriangleId t = m.new_triangle();
  const TriangleId gab = m.new_triangle(), gbc = m.new_triangle(), gca = m.new_triangle();
  auto& T = m.triangles;
  T[t].v = {a, b, c};
  T[gab].v = {b, a, kInfinite};
  T[gbc].v = {c, b, kInfinite};
  T[gca].v = {a, c, kInfinite};
  auto link = [&](Handle x, Handle y) {
    T[x >> 2].n[x & 3] = y;
    T[y >> 2].n[y & 3] = x;
  };
  link(make_handle(t, 2), make_handle(gab, 2));  // a→b / b→a
  link(make_handle(t, 0), make_handle(gbc, 2));  // b→c / c→b
  link(make_handle(t, 1), make_handle(gca, 2));  // c→a / a→c
  link(make_handle(gab, 0), make_handle(gca, 1));  // a→∞ / ∞→a
  link(make_handle(gab, 1), make_handle(gbc, 0));  // ∞→b / b→∞
  link(make_handle(gbc, 1), make_handle(gca, 0));  // ∞→c / c→∞
}

}  // namespace

namespace {

enum class Degeneracy { kValid, kCoincident, kTwoDistinct, kCollinear };

// Builds the Delaunay triangulation of m.points (in insertion order) into m, with ghosts.
// kept[v] receives the vertex v was merged into (v itself unless v duplicates an earlier point).
Degeneracy build_incremental(Mesh& m, std::vector<VertexId>& kept) {
  const std::size_t n = m.points.size();
  kept.assign(n, kNone);
  m.triangles.reserve(2 * n);
  m.flags.reserve(2 * n);
  advise_huge_pages(m.triangles);
  // The first triangle: the first point, the next distinct one, the next not collinear with them.
  std::size_t second = 1;
  while (second < n && m.points[second] == m.points[0]) ++second;
  if (second >= n) return Degeneracy::kCoincident;
  std::size_t third = second + 1;
  while (third < n && orient2d(m.points[0], m.points[second], m.points[third]) == 0) ++third;
  if (third >= n) {
    for (std::size_t i = second + 1; i < n; ++i) {
      if (!(m.points[i] == m.points[0]) && !(m.points[i] == m.points[second])) {
        return Degeneracy::kCollinear;
      }
    }
    return Degeneracy::kTwoDistinct;
  }
  const auto s = static_cast<VertexId>(second), r = static_cast<VertexId>(third);
  if (orient2d(m.points[0], m.points[s], m.points[r]) > 0) {
    make_first_triangle(m, 0, s, r);
  } else {
    make_first_triangle(m, 0, r, s);
  }
  kept[0] = 0;
  kept[s] = s;
  kept[r] = r;
  Handle hint = make_handle(0, 0);
  for (VertexId v = 1; v < n; ++v) {
    if (v == s || v == r) continue;
    kept[v] = m.insert_vertex(v, hint, &hint);
  }
  return Degeneracy::kValid;
}
// ==== the incremental construction ends here =====================================================

// ==== merging two x-separated halves begins here =================================================
//
// merge_halves joins the Delaunay triangulations of two halves separated by a vertical line. Its
// steps, in order: append_right_half (one mesh, right's ids offset), HullGhosts (hull navigation),
// innermost_hull_pair and common_tangent (the two bridges), add_bottom_ghost, the ladder of rungs
// between the facing chains (SeamLadder), add_top_ghost, and Lawson flips near the seam.

// Appends right's points, flags and triangles to left, right's vertex ids offset by left's vertex
// count nl and its triangle ids by left's triangle count. The triangles are copied in chunks, and
// each copied chunk of the source is handed back to the kernel at once, so that the peak memory is
// the merged mesh plus one chunk rather than plus the whole right half (the source is never read
// again; the vector frees its block at the end).
void append_right_half(Mesh& left, Mesh&& right) {
  const auto nl = static_cast<VertexId>(left.points.size());
  const auto tl = static_cast<TriangleId>(left.triangles.size());
  left.points.insert(left.points.end(), right.points.begin(), right.points.end());
  std::vector<Point>().swap(right.points);
  left.flags.insert(left.flags.end(), right.flags.begin(), right.flags.end());
  std::vector<std::uint8_t>().swap(right.flags);
  left.triangles.reserve(left.triangles.size() + right.triangles.size() + 2);
  constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const auto* base = reinterpret_cast<const unsigned char*>(right.triangles.data());
  std::size_t released = 0;  // bytes of the source already released, from its start
  for (std::size_t i = 0; i < right.triangles.size(); ++i) {
    Triangle c = right.triangles[i];
    for (VertexId& v : c.v) {
      if (v != kInfinite) v += nl;
    }
    for (Handle& h : c.n) h += 4 * tl;
    left.triangles.push_back(c);
    const std::size_t done = (i + 1) * sizeof(Triangle);
    if (done - released >= kChunkBytes) {
      // Whole pages strictly inside [base + released, base + done).
      const auto first = (reinterpret_cast<std::uintptr_t>(base) + released + page - 1) / page * page;
      const auto last = (reinterpret_cast<std::uintptr_t>(base) + done) / page * page;
      if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
      released = done;
    }
  }
  right = Mesh();
}

// Hull navigation from the ghosts: ghost (a, b, ∞) is the hull edge b→a (counter-clockwise).
// Each hull vertex starts one hull edge and ends one, so both tables are sorted (vertex, ghost)
// pairs searched by vertex (hulls can be large: all the points of a circle).
struct HullGhosts {
  using Pairs = std::vector<std::pair<VertexId, TriangleId>>;
  const Mesh& m;
  Pairs from_pairs, to_pairs;  // keyed by b, resp. a

  explicit HullGhosts(const Mesh& mesh) : m(mesh) {
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
      // (A dead slot's corners are kNone, which equals kInfinite: skip it before asking is_ghost.)
      if (m.is_dead(t) || !m.is_ghost(t)) continue;
      VertexId a, b;
      finite_pair(t, a, b);
      from_pairs.emplace_back(b, t);
      to_pairs.emplace_back(a, t);
    }
    std::sort(from_pairs.begin(), from_pairs.end());
    std::sort(to_pairs.begin(), to_pairs.end());
  }
  // The finite corners of ghost g = (a, b, ∞).
  void finite_pair(TriangleId g, VertexId& a, VertexId& b) const {
    const Triangle& G = m.triangles[g];
    unsigned k = 0;
    while (G.v[k] != kInfinite) ++k;
    a = G.v[next3(k)];
    b = G.v[prev3(k)];
  }
  static TriangleId find(const Pairs& pairs, VertexId v) {
    const auto it = std::lower_bound(pairs.begin(), pairs.end(), std::pair<VertexId, TriangleId>{v, 0});
    if (it == pairs.end() || it->first != v) throw InternalError("merge_halves: vertex not on the hull");
    return it->second;
  }
  TriangleId ghost_from(VertexId v) const { return find(from_pairs, v); }  // hull edge v→ccw(v)
  TriangleId ghost_to(VertexId v) const { return find(to_pairs, v); }      // hull edge cw(v)→v
  VertexId ccw(VertexId v) const {
    VertexId a, b;
    finite_pair(ghost_from(v), a, b);
    return a;
  }
  VertexId cw(VertexId v) const {
    VertexId a, b;
    finite_pair(ghost_to(v), a, b);
    return b;
  }
  VertexId next(VertexId v, bool counter_clockwise) const { return counter_clockwise ? ccw(v) : cw(v); }
};

// Lexicographic (x, then y) order of points u and v.
inline bool lex_less(const std::vector<Point>& P, VertexId u, VertexId v) {
  return P[u].x < P[v].x || (P[u].x == P[v].x && P[u].y < P[v].y);
}

// True if q, collinear with a and b, lies strictly between them.
inline bool strictly_between(const std::vector<Point>& P, VertexId a, VertexId b, VertexId q) {
  const Point &pa = P[a], &pb = P[b], &pq = P[q];
  if (pa.x != pb.x) return (pa.x < pq.x && pq.x < pb.x) || (pb.x < pq.x && pq.x < pa.x);
  return (pa.y < pq.y && pq.y < pb.y) || (pb.y < pq.y && pq.y < pa.y);
}

// The innermost pair of hull vertices: l the lexicographically largest of the left half (ids below
// nl), r the smallest of the right half.
std::pair<VertexId, VertexId> innermost_hull_pair(const HullGhosts& hull, const std::vector<Point>& P,
                                                  VertexId nl) {
  VertexId l = kNone, r = kNone;
  for (const auto& [v, g] : hull.from_pairs) {
    (void)g;
    if (v < nl) {
      if (l == kNone || lex_less(P, l, v)) l = v;
    } else if (r == kNone || lex_less(P, v, r)) {
      r = v;
    }
  }
  return {l, r};
}

// A common tangent of the two hulls, walked from the innermost pair (l, r). The lower one has every
// point on or left of l→r: l walks clockwise and r counter-clockwise while the next vertex lies
// right of l→r. The upper one is the mirror image (every point on or right of l→r). Then, so that
// no vertex lies on the open bridge, each end slides along a collinear hull edge towards the other.
std::pair<VertexId, VertexId> common_tangent(const HullGhosts& hull, const std::vector<Point>& P, VertexId l,
                                             VertexId r, bool lower) {
  const int outside = lower ? -1 : 1;  // the side of l→r no point may lie on
  VertexId a = l, b = r;
  for (bool moved = true; moved;) {
    moved = false;
    while (orient2d(P[a], P[b], P[hull.next(a, !lower)]) == outside) {
      a = hull.next(a, !lower);
      moved = true;
    }
    while (orient2d(P[a], P[b], P[hull.next(b, lower)]) == outside) {
      b = hull.next(b, lower);
      moved = true;
    }
  }
  for (bool moved = true; moved;) {
    moved = false;
    const VertexId lc = hull.next(a, lower), rc = hull.next(b, !lower);
    if (orient2d(P[a], P[b], P[lc]) == 0 && strictly_between(P, a, b, lc)) {
      a = lc;
      moved = true;
    } else if (orient2d(P[a], P[b], P[rc]) == 0 && strictly_between(P, a, b, rc)) {
      b = rc;
      moved = true;
    }
  }
  return {a, b};
}

// The corner of triangle t at vertex v.
inline unsigned corner_of(const Mesh& m, TriangleId t, VertexId v) {
  unsigned k = 0;
  while (m.triangles[t].v[k] != v) ++k;
  return k;
}

// Makes the edges x and y twins.
inline void link_twins(Mesh& m, Handle x, Handle y) {
  m.triangles[x >> 2].n[x & 3] = y;
  m.triangles[y >> 2].n[y & 3] = x;
}

// The bottom ghost B = (r0, l0, ∞) for the new hull edge l0→r0 (the lower common tangent), linked
// to the hull edges p→l0 of L and r0→q of R, which stay unless a half is pinched.
TriangleId add_bottom_ghost(Mesh& m, const HullGhosts& hull, VertexId l0, VertexId r0) {
  const TriangleId below_l0 = hull.ghost_to(l0);    // (l0, p, ∞): hull edge p→l0
  const TriangleId after_r0 = hull.ghost_from(r0);  // (q, r0, ∞): hull edge r0→q
  const TriangleId bottom = m.new_triangle();
  m.triangles[bottom].v = {r0, l0, kInfinite};
  link_twins(m, make_handle(bottom, 0), make_handle(below_l0, corner_of(m, below_l0, hull.cw(l0))));   // l0→∞
  link_twins(m, make_handle(bottom, 1), make_handle(after_r0, corner_of(m, after_r0, hull.ccw(r0))));  // ∞→r0
  return bottom;
}

// The ladder is Guibas and Stolfi's merge ("Primitives for the manipulation of general
// subdivisions", 1985, section 9): each rung joins l and r, and its apex is the first candidate
// above l→r on the facing boundary of L (resp. R) whose circle through l, r is empty. A triangle
// of a half whose circumcircle contains the next candidate is deleted first, which exposes its
// two other edges as the new boundary. Every rung is then Delaunay, so the work is linear in
// the size of the seam (joining hull neighbours only and repairing with Lawson flips can need a
// quadratic number of flips, e.g. between a tiny inner arc and a cocircular outer arc).
//
// A facing boundary is a chain of directed edges with the half's triangle on their left: L's
// runs counter-clockwise from l (edges l→lc), R's clockwise from r (edges rc→r, as handles in
// the triangle of R on that side). Edges exposed by deletions are kept on a stack (the chain
// near l or r); below the stack the chain is the original hull, read from the ghosts.
struct SeamLadder {
  Mesh& m;
  const HullGhosts& hull;
  const std::vector<Point>& P;
  VertexId l, r;    // the current base l→r
  Handle pending;   // the twin of the next rung's base l→r
  std::vector<Handle> left_exposed, right_exposed;
  std::vector<TriangleId> freed;  // slots of deleted triangles and consumed ghosts
  std::vector<std::uint8_t> ghost_consumed;  // (its slot may hold a rung now)
  std::vector<Handle> suspects;              // rung edges for the Lawson flips

  SeamLadder(Mesh& mesh, const HullGhosts& h, VertexId l0, VertexId r0, TriangleId bottom)
      : m(mesh), hull(h), P(mesh.points), l(l0), r(r0), pending(make_handle(bottom, 2)),
        ghost_consumed(mesh.triangles.size(), 0) {}

  Handle hull_edge_inside(TriangleId g) const { return m.triangles[g].n[corner_of(m, g, kInfinite)]; }
  VertexId origin(Handle h) const { return m.triangles[h >> 2].v[next3(h & 3)]; }
  VertexId target(Handle h) const { return m.triangles[h >> 2].v[prev3(h & 3)]; }
  VertexId apex(Handle h) const { return m.triangles[h >> 2].v[h & 3]; }

  // The first edge l→lc of L's facing chain; kNone once a pinched half's chain has gone round its
  // whole hull.
  Handle left_front() const {
    if (!left_exposed.empty()) return left_exposed.back();
    const TriangleId g = hull.ghost_from(l);
    return ghost_consumed[g] ? kNone : hull_edge_inside(g);
  }
  // The first edge rc→r of R's facing chain (kNone as for left_front).
  Handle right_front() const {
    if (!right_exposed.empty()) return right_exposed.back();
    const TriangleId g = hull.ghost_to(r);
    return ghost_consumed[g] ? kNone : hull_edge_inside(g);
  }
  void pop_left() {
    if (!left_exposed.empty()) {
      left_exposed.pop_back();
    } else {
      const TriangleId g = hull.ghost_from(l);
      ghost_consumed[g] = 1;
      freed.push_back(g);
    }
  }
  void pop_right() {
    if (!right_exposed.empty()) {
      right_exposed.pop_back();
    } else {
      const TriangleId g = hull.ghost_to(r);
      ghost_consumed[g] = 1;
      freed.push_back(g);
    }
  }
  TriangleId take_slot() {
    if (freed.empty()) return m.new_triangle();
    const TriangleId t = freed.back();
    freed.pop_back();
    return t;
  }

  // True if candidate c lies strictly left of (above) the base l→r.
  bool above_base(VertexId c) const { return orient2d(P[l], P[r], P[c]) > 0; }
  // True if the apex of the chain's triangle on edge `front` (a finite vertex) lies strictly inside
  // the circle through l, r and the candidate c.
  bool apex_in_circle(Handle front, VertexId c) const {
    const VertexId x = apex(front);
    return x != kInfinite && incircle(P[l], P[r], P[c], P[x]) > 0;
  }
  // Deletes L's triangle (l, lc, x) on the chain edge lf = l→lc, exposing x→lc and l→x; the next
  // left candidate is x.
  void delete_left_triangle(Handle& lf, VertexId& lc) {
    const VertexId x = apex(lf);
    const TriangleId t = lf >> 2;
    const unsigned k = lf & 3;
    const Handle lc_x = m.sym(make_handle(t, next3(k))), x_l = m.sym(make_handle(t, prev3(k)));
    pop_left();
    left_exposed.push_back(lc_x);  // x→lc
    left_exposed.push_back(x_l);  // l→x
    freed.push_back(t);
    lf = x_l;
    lc = x;
  }
  // The mirror image on R: deletes (rc, r, y) on the chain edge rf = rc→r, exposing rc→y and y→r;
  // the next right candidate is y.
  void delete_right_triangle(Handle& rf, VertexId& rc) {
    const VertexId y = apex(rf);
    const TriangleId t = rf >> 2;
    const unsigned k = rf & 3;
    const Handle r_y = m.sym(make_handle(t, next3(k))), y_rc = m.sym(make_handle(t, prev3(k)));
    pop_right();
    right_exposed.push_back(y_rc);  // rc→y
    right_exposed.push_back(r_y);   // y→r
    freed.push_back(t);
    rf = r_y;
    rc = y;
  }
  // The rung (l, r, lc) on the boundary edge lf = l→lc; the base rises to lc→r.
  void add_left_rung(Handle lf, VertexId lc) {
    pop_left();
    const TriangleId g = take_slot();
    m.triangles[g].v = {l, r, lc};
    link_twins(m, make_handle(g, 1), lf);       // lc→l
    link_twins(m, make_handle(g, 2), pending);  // l→r
    pending = make_handle(g, 0);                // r→lc, twin of the next base lc→r
    suspects.push_back(make_handle(g, 1));
    suspects.push_back(make_handle(g, 2));
    l = lc;
  }
  // The rung (l, r, rc) on the boundary edge rf = rc→r; the base rises to l→rc.
  void add_right_rung(Handle rf, VertexId rc) {
    pop_right();
    const TriangleId g = take_slot();
    m.triangles[g].v = {l, r, rc};
    link_twins(m, make_handle(g, 0), rf);       // r→rc
    link_twins(m, make_handle(g, 2), pending);  // l→r
    pending = make_handle(g, 1);                // rc→l, twin of the next base l→rc
    suspects.push_back(make_handle(g, 0));
    suspects.push_back(make_handle(g, 2));
    r = rc;
  }

  // The top ghost U = (l, r, ∞) for the new hull edge r→l (the upper common tangent), linked to the
  // hull edges around it, and the slots left over freed. A half is pinched when its whole hull
  // faced the gap: its chain went round the full cycle and the hull edge after l (before r) was
  // consumed; the top bridge then meets the bottom one.
  void add_top_ghost(TriangleId bottom) {
    const bool left_pinched = ghost_consumed[hull.ghost_from(l)] != 0;
    const bool right_pinched = ghost_consumed[hull.ghost_to(r)] != 0;
    const TriangleId top = m.new_triangle();
    m.triangles[top].v = {l, r, kInfinite};
    // The hull edges around the top bridge r→l: before r, s→r of R (or, if R is pinched, the bottom
    // bridge l0→r0 itself); after l, l→u of L (or, if L is pinched, the bottom bridge).
    if (right_pinched) {
      link_twins(m, make_handle(top, 0), make_handle(bottom, 1));  // r→∞ with ∞→r0
    } else {
      const TriangleId below_r = hull.ghost_to(r);  // (r, s, ∞): hull edge s→r, stays
      link_twins(m, make_handle(top, 0), make_handle(below_r, corner_of(m, below_r, hull.cw(r))));  // r→∞
    }
    if (left_pinched) {
      link_twins(m, make_handle(top, 1), make_handle(bottom, 0));  // ∞→l with l0→∞
    } else {
      const TriangleId after_l = hull.ghost_from(l);  // (u, l, ∞): hull edge l→u, stays
      link_twins(m, make_handle(top, 1), make_handle(after_l, corner_of(m, after_l, hull.ccw(l))));  // ∞→l
    }
    for (const TriangleId t : freed) m.kill_triangle(t);  // (none left unless deletions outnumber rungs)
    link_twins(m, make_handle(top, 2), pending);  // l→r
    suspects.push_back(pending);
  }
};

// Merges the Delaunay triangulation `right` into `left`, where every point of right lies strictly
// right (larger x) of every point of left. Right's vertex ids are offset by left's vertex count.
// The two hulls are joined by a ladder of triangles between their facing chains, built upwards
// from the lower common tangent (Guibas and Stolfi's divide-and-conquer merge, see SeamLadder);
// Lawson flips then restore the Delaunay property near the seam.
void merge_halves(Mesh& left, Mesh&& right) {
  const auto nl = static_cast<VertexId>(left.points.size());
  append_right_half(left, std::move(right));
  Mesh& m = left;
  const auto& P = m.points;
  const HullGhosts hull(m);
  const auto [l_in, r_in] = innermost_hull_pair(hull, P, nl);
  const auto [l0, r0] = common_tangent(hull, P, l_in, r_in, true);
  const auto [lt, rt] = common_tangent(hull, P, l_in, r_in, false);
  const TriangleId bottom = add_bottom_ghost(m, hull, l0, r0);
  SeamLadder ladder(m, hull, l0, r0, bottom);
  const std::size_t limit = m.triangles.size();
  for (std::size_t step = 0;; ++step) {
    if (step > limit) throw InternalError("merge_halves: ladder does not terminate");
    Handle lf = ladder.left_front(), rf = ladder.right_front();
    VertexId lc = lf == kNone ? kNone : ladder.target(lf), rc = rf == kNone ? kNone : ladder.origin(rf);
    bool l_valid = lc != kNone && ladder.above_base(lc);
    bool r_valid = rc != kNone && ladder.above_base(rc);
    // Delete the triangles of L left of l→lc while their apex lies inside the circle (l, r, lc).
    while (l_valid && ladder.apex_in_circle(lf, lc)) {
      ladder.delete_left_triangle(lf, lc);
      l_valid = ladder.above_base(lc);
    }
    // The mirror image on R: triangles right of rc→r whose apex lies inside (l, r, rc).
    while (r_valid && ladder.apex_in_circle(rf, rc)) {
      ladder.delete_right_triangle(rf, rc);
      r_valid = ladder.above_base(rc);
    }
    if (ladder.l == lt && ladder.r == rt) break;  // (l, r) is the upper common tangent
    if (!l_valid && !r_valid) throw InternalError("merge_halves: no valid ladder step");
    // Both candidates possible: take the Delaunay choice (rc not inside the circle of (l, r, lc)).
    const bool take_left =
        l_valid && (!r_valid || incircle(P[ladder.l], P[ladder.r], P[lc], P[rc]) <= 0);
    if (take_left) {
      ladder.add_left_rung(lf, lc);
    } else {
      ladder.add_right_rung(rf, rc);
    }
  }
  ladder.add_top_ghost(bottom);
  restore_delaunay(m, ladder.suspects);
}

// ==== merging two x-separated halves ends here ===================================================

}  // namespace

// ==== the public entry points begin here =========================================================

namespace {

// Throws InputError unless the points are few enough for 32-bit handles, all in the supported range,
// and at least three.
void check_input_points(const std::vector<Point>& points) {
  const std::size_t n = points.size();
  if (n >= std::numeric_limits<std::uint32_t>::max() / 4) {
    throw InputError("", 0, "too many points (" + std::to_string(n) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!in_supported_range(points[i])) {
      throw InputError("", 0,
                       "point " + std::to_string(i + 1) +
                           " has a coordinate outside the supported range (0 or magnitude in "
                           "[1e-50, 1e50])");
    }
  }
  if (n < 3) throw InputError("", 0, "fewer than three points (" + std::to_string(n) + ")");
}

// Triangulates the two x-separated halves of the curve order (order[0, left_count) and the rest) on
// two threads and merges them into m. False, with m emptied, if a half is degenerate.
bool build_two_halves(Mesh& m, std::vector<VertexId>& kept, const std::vector<Point>& points,
                      const std::vector<std::uint32_t>& order, std::size_t left_count, bool parallel) {
  const std::size_t n = points.size();
  Mesh right;
  std::vector<VertexId> kept_right;
  // The left half's arrays are reserved for the whole mesh, so that merging the right half in
  // appends in place: no reallocation, and pages are touched only as they are used.
  m.points.reserve(n);
  m.triangles.reserve(2 * n + 16);
  m.flags.reserve(2 * n + 16);
  advise_huge_pages(m.points);
  m.points.resize(left_count);
  right.points.reserve(n - left_count);
  advise_huge_pages(right.points);
  right.points.resize(n - left_count);
  Degeneracy dl = Degeneracy::kValid, dr = Degeneracy::kValid;
  run_both(
      parallel,
      [&] {
        for (std::size_t i = left_count; i < n; ++i) right.points[i - left_count] = points[order[i]];
        dr = build_incremental(right, kept_right);
      },
      [&] {
        for (std::size_t i = 0; i < left_count; ++i) m.points[i] = points[order[i]];
        dl = build_incremental(m, kept);
      });
  if (dl == Degeneracy::kValid && dr == Degeneracy::kValid) {
    merge_halves(m, std::move(right));
    kept.reserve(n);
    for (const VertexId v : kept_right) kept.push_back(v + static_cast<VertexId>(left_count));
    return true;
  }
  m = Mesh();  // a degenerate half: the caller falls back to one sequential construction
  return false;
}

// Triangulates all points in curve order into m on one thread; throws InputError on degenerate input.
void build_sequential(Mesh& m, std::vector<VertexId>& kept, const std::vector<Point>& points,
                      const std::vector<std::uint32_t>& order) {
  const std::size_t n = points.size();
  m.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) m.points[i] = points[order[i]];
  switch (build_incremental(m, kept)) {
    case Degeneracy::kValid:
      break;
    case Degeneracy::kCoincident:
      throw InputError("", 0, "fewer than three distinct points (all points coincide)");
    case Degeneracy::kTwoDistinct:
      throw InputError("", 0, "fewer than three distinct points");
    case Degeneracy::kCollinear:
      throw InputError("", 0, "all points are collinear");
  }
}

// Duplicate points: the insertion order is random, so the copy that made it into the mesh need not
// be the first in the input. Each group of equal points is represented by its smallest input index
// (the documented contract): order[] is rewritten so that the kept vertex of a group maps to that
// index. member receives the input index of each curve-order vertex (order before rewriting).
// Returns false, leaving both alone, if there are no duplicates.
bool choose_representatives(std::vector<std::uint32_t>& order, const std::vector<VertexId>& kept,
                            std::vector<std::uint32_t>& member) {
  const std::size_t n = order.size();
  bool any_duplicate = false;
  for (VertexId v = 0; v < n && !any_duplicate; ++v) any_duplicate = kept[v] != v;
  if (any_duplicate) {
    member = order;
    std::vector<std::uint32_t>& representative = order;  // rewritten in place for kept vertices
    for (VertexId v = 0; v < n; ++v) {
      if (kept[v] != v) representative[kept[v]] = std::min(representative[kept[v]], member[v]);
    }
  }
  return any_duplicate;
}

// Maps the triangles' vertex ids from curve order back to the input numbering (two threads for
// large meshes).
void map_back_to_input_ids(Mesh& m, const std::vector<std::uint32_t>& order, bool parallel) {
  auto map_back = [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      for (VertexId& v : m.triangles[t].v) {
        if (v != kInfinite) v = order[v];
      }
    }
  };
  const std::size_t triangle_count = m.triangles.size();
  if (order.size() >= kParallelThreshold) {
    run_both(
        parallel, [&] { map_back(triangle_count / 2, triangle_count); }, [&] { map_back(0, triangle_count / 2); });
  } else {
    map_back(0, triangle_count);
  }
}

// Marks every duplicate input point and lists it with its group's representative in m.duplicates.
void record_duplicates(Mesh& m, const std::vector<std::uint32_t>& order, const std::vector<VertexId>& kept,
                       const std::vector<std::uint32_t>& member) {
  for (VertexId v = 0; v < order.size(); ++v) {
    const std::uint32_t group = order[kept[v]];  // the group's smallest input index
    if (member[v] != group) {
      m.vertex_kind[member[v]] = VertexKind::kDuplicate;
      m.duplicates.emplace_back(member[v], group);
    }
  }
}

}  // namespace

// Lawson's flip algorithm from a stack of suspect edges: flips every locally non-Delaunay,
// unconstrained edge and pushes the four edges around the new diagonal.
void restore_delaunay(Mesh& m, std::vector<Handle>& stack) {
  while (!stack.empty()) {
    const Handle h = stack.back();
    stack.pop_back();
    if (m.is_dead(h >> 2) || m.is_segment(h) || !m.is_locally_non_delaunay(h)) continue;
    const Handle diag = m.flip(h);  // d→c in (c, a, d); the other triangle is (d, b, c)
    const Handle other = m.sym(diag);
    stack.push_back(Mesh::lnext(diag));
    stack.push_back(Mesh::lprev(diag));
    stack.push_back(Mesh::lnext(other));
    stack.push_back(Mesh::lprev(other));
  }
}

// The Delaunay triangulation of points (ids in input order): curve order, incremental insertion
// (in two merged halves for large inputs), then the ids mapped back and duplicates recorded.
Mesh delaunay(std::vector<Point> points, DelaunayStats* stats, unsigned threads) {
  const bool parallel = threads != 1;
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const std::size_t n = points.size();
  check_input_points(points);

  std::size_t left_count = 0;
  std::vector<std::uint32_t> order = hilbert_order(points, &left_count, parallel);
  const auto t1 = Clock::now();

  // Work on copies in curve order (vertex id i here = order[i] in the input). Large inputs are
  // split into the two x-separated halves of the curve, triangulated on two threads and merged;
  // the split depends only on the input (never on the machine), so output is deterministic.
  Mesh m;
  std::vector<VertexId> kept;
  bool done = false;
  if (n >= kParallelThreshold && left_count >= n / 8 && n - left_count >= n / 8) {
    done = build_two_halves(m, kept, points, order, left_count, parallel);
  }
  if (!done) build_sequential(m, kept, points, order);
  const auto t2 = Clock::now();

  std::vector<std::uint32_t> member;  // input index of each curve-order vertex (order before rewriting)
  const bool any_duplicate = choose_representatives(order, kept, member);
  map_back_to_input_ids(m, order, parallel);
  m.points = std::move(points);
  m.vertex_kind.assign(n, VertexKind::kInput);
  m.vertex_marker.assign(n, 0);
  m.input_vertex_count = static_cast<std::uint32_t>(n);
  if (any_duplicate) record_duplicates(m, order, kept, member);
  std::sort(m.duplicates.begin(), m.duplicates.end());
  if (stats) {
    stats->duplicates = m.duplicates.size();
    stats->seconds_sort = std::chrono::duration<double>(t1 - t0).count();
    stats->seconds_insert = std::chrono::duration<double>(t2 - t1).count();
  }
  return m;
}

// ==== the public entry points end here ===========================================================

}  // namespace mwst
