// mwst/mesh/mesh.hpp — the triangle mesh every stage of mwst works on.
//
// Storage is flat and index-based: a vertex array, a triangle array whose entries hold three vertex
// ids in counter-clockwise order and three packed neighbour handles, and a flag byte per triangle.
// The convex hull is closed by ghost triangles that use the infinite vertex kInfinite, so every
// edge has exactly two triangles and walks never fall off the mesh (as in CGAL; unlike a finite
// super-triangle, no special cases enter the Delaunay test).
//
// Navigation vocabulary (after Triangle). A handle h = 4*t + e names triangle t and its edge e,
// the edge opposite corner e, directed counter-clockwise around t:
//
//                 apex(h) = v[e]
//                   /      ^
//         lnext(h) /        \ lprev(h)
//                 v          \ .
//     org(h) = v[e+1] ───h───▶ dest(h) = v[e+2]        (corner indices mod 3)
//                   ◀──sym(h)──
//                (the neighbouring triangle, below)
//
//   sym(h)    the same edge seen from the neighbouring triangle: org and dest swapped.
//   lnext(h)  the next edge counter-clockwise in the same triangle: dest → apex.
//   lprev(h)  the previous edge in the same triangle: apex → org.
//   onext(h)  the next edge counter-clockwise around org(h): sym(lprev(h)).
//   oprev(h)  the next edge clockwise around org(h): lnext(sym(h)).
//
// A ghost triangle has kInfinite at one corner; its two finite corners a, b (in the order such that
// the triangle reads (a, b, ∞)) span a hull edge, the domain lying to the right of a→b. Its
// "circumcircle" is the open half-plane left of a→b, so one Delaunay test serves hull and interior.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mwst/geometry/geometry.hpp"

namespace mwst {

using VertexId = std::uint32_t;
using TriangleId = std::uint32_t;
using Handle = std::uint32_t;  // 4 * triangle + edge, edge in {0, 1, 2}

inline constexpr VertexId kInfinite = 0xFFFFFFFFu;  // the vertex at infinity of ghost triangles
inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;

inline constexpr Handle make_handle(TriangleId t, unsigned e) { return 4u * t + e; }
inline constexpr TriangleId triangle_of(Handle h) { return h >> 2; }
inline constexpr unsigned edge_of(Handle h) { return h & 3u; }
inline constexpr unsigned next3(unsigned i) { return i == 2 ? 0 : i + 1; }
inline constexpr unsigned prev3(unsigned i) { return i == 0 ? 2 : i - 1; }

struct Triangle {
  std::array<VertexId, 3> v;  // counter-clockwise; one may be kInfinite (ghost)
  std::array<Handle, 3> n;    // n[e] = handle of edge e as seen from the neighbour across it
};

// Per-triangle flag bits.
inline constexpr std::uint8_t kSegmentEdge0 = 1;  // bit e (0..2): edge e is a subsegment
inline constexpr std::uint8_t kOutside = 8;       // carved away: not part of the domain
inline constexpr std::uint8_t kDead = 16;         // free slot (removed triangle)

enum class VertexKind : std::uint8_t {
  kInput = 0,             // an input point (never moved or removed)
  kDuplicate = 1,         // an input point equal to an earlier one; not in any triangle
  kSteiner = 2,           // a free Steiner point in the interior
  kSteinerOnSegment = 3,  // a Steiner point splitting an input segment
  kRemoved = 4,           // a Steiner point taken out again (not in any triangle; see compact)
};

// Where a point lies relative to the mesh (result of Mesh::locate).
struct Location {
  enum class Kind : std::uint8_t { kInTriangle, kOnEdge, kOnVertex };
  Kind kind = Kind::kInTriangle;
  // kInTriangle: any edge of the containing triangle (which may be a ghost: the point lies
  // outside the hull, beyond that ghost's hull edge). kOnEdge: the edge containing the point.
  // kOnVertex: an edge whose org is the vertex at the point.
  Handle handle = kNone;
};

class MWST_API Mesh {
 public:
  std::vector<Point> points;          // vertex coordinates, indexed by VertexId
  std::vector<VertexKind> vertex_kind;
  std::vector<std::int32_t> vertex_marker;  // Triangle's boundary markers (0 if none)
  std::vector<Triangle> triangles;    // including ghosts and dead slots
  std::vector<std::uint8_t> flags;    // one per triangle (kSegmentEdge0 << e, kOutside, kDead)
  // Boundary marker of each subsegment, 3 per triangle (index 3*t+e); sized only once a segment
  // exists. Meaningful where the segment bit is set.
  std::vector<std::int32_t> segment_marker;
  // Per-triangle area bounds (Triangle's regional -a and .area files), one per slot; empty: none.
  // A value <= 0 means no bound. Once sized, the local operations keep it: the triangles a split
  // makes inherit their parent's bound, and a flip gives both new triangles the mean of the two
  // old bounds (none if either had none) — Triangle's rule, which keeps a small bound from
  // travelling far through flips. Trials do not journal it (the optimiser does not use it).
  std::vector<double> area_bound;
  std::vector<std::pair<VertexId, VertexId>> duplicates;  // (duplicate input point, the vertex kept)
  std::uint32_t input_vertex_count = 0;  // vertices [0, input_vertex_count) are input points

  // ---- navigation ------------------------------------------------------------------------------
  VertexId org(Handle h) const { return triangles[h >> 2].v[next3(h & 3)]; }
  VertexId dest(Handle h) const { return triangles[h >> 2].v[prev3(h & 3)]; }
  VertexId apex(Handle h) const { return triangles[h >> 2].v[h & 3]; }
  Handle sym(Handle h) const { return triangles[h >> 2].n[h & 3]; }
  static Handle lnext(Handle h) { return (h & ~3u) | next3(h & 3); }
  static Handle lprev(Handle h) { return (h & ~3u) | prev3(h & 3); }
  Handle onext(Handle h) const { return sym(lprev(h)); }
  Handle oprev(Handle h) const { return lnext(sym(h)); }

  std::size_t triangle_slots() const { return triangles.size(); }
  bool is_ghost(TriangleId t) const {
    const auto& v = triangles[t].v;
    return v[0] == kInfinite || v[1] == kInfinite || v[2] == kInfinite;
  }
  bool is_dead(TriangleId t) const { return (flags[t] & kDead) != 0; }
  bool is_outside(TriangleId t) const { return (flags[t] & kOutside) != 0; }
  // A live, finite triangle of the domain (what the output .ele holds).
  bool in_domain(TriangleId t) const { return (flags[t] & (kDead | kOutside)) == 0 && !is_ghost(t); }
  bool is_segment(Handle h) const { return (flags[h >> 2] & (kSegmentEdge0 << (h & 3))) != 0; }
  std::int32_t marker(Handle h) const;

  // Marks the edge h (both sides) as a subsegment with the given boundary marker.
  void set_segment(Handle h, std::int32_t marker);
  void clear_segment(Handle h);

  // Adds a vertex (not yet in any triangle); returns its id.
  VertexId add_vertex(const Point& p, VertexKind kind, std::int32_t marker = 0);
  const Point& point(VertexId v) const { return points[v]; }

  // ---- local operations ------------------------------------------------------------------------
  // flip(h): replaces the diagonal of the quadrilateral formed by the two triangles of edge h.
  //
  //          c                       c
  //         / \                     /|\          h = a→b, apex c; sym(h) has apex d.
  //        /   \                   / | \         Precondition (not checked): the quadrilateral
  //       a──h──b       ──▶       a  |  b        a d b c is strictly convex, h is not a segment.
  //        \   /                   \ | /         Returns the new edge d→c, in the triangle
  //         \ /                     \|/          (c, a, d), which reuses h's slot; the other
  //          d                       d           slot becomes (d, b, c).
  Handle flip(Handle h);

  // split_triangle(t, p): connects p to the corners of t (1 → 3). Precondition: p lies strictly
  // inside t (for a ghost: strictly beyond its hull edge). Returns the three edges opposite p.
  std::array<Handle, 3> split_triangle(TriangleId t, VertexId p);

  // split_edge(h, p): splits edge h and both its triangles at p (2 → 4). Precondition: p lies on
  // the open edge h. A subsegment stays a subsegment in both halves (same marker). Returns the
  // four edges opposite p.
  std::array<Handle, 4> split_edge(Handle h, VertexId p);

  // ---- location and insertion ------------------------------------------------------------------
  // Walks from `start` (any live triangle's edge; kNone = anywhere) towards p with exact
  // orientation tests (a stochastic visibility walk, which terminates in any triangulation).
  Location locate(const Point& p, Handle start = kNone) const;

  // Inserts vertex v (already added) at its location and restores the (constrained) Delaunay
  // property by Lawson flips that never cross a subsegment. If v coincides with an existing
  // vertex nothing is inserted and that vertex's id is returned; otherwise v. `hint`, when given,
  // receives an edge of a triangle next to the new vertex (a good start for the next walk).
  VertexId insert_vertex(VertexId v, Handle start = kNone, Handle* hint = nullptr);

  // Lawson flipping: each edge on the stack whose far apex lies inside the (generalised)
  // circumcircle of its own triangle is flipped, unless it is a subsegment; the two new edges
  // opposite `apex_vertex` are pushed. Used by insertion and by segment splitting.
  void legalize(VertexId apex_vertex, std::vector<Handle>& stack, Handle* last = nullptr);

  // True if the apex of sym(h) lies strictly inside the generalised circumcircle of h's triangle
  // (exact; ghost triangles use their half-plane). The Delaunay test of edge h.
  bool is_locally_non_delaunay(Handle h) const;

  // Any live edge, for starting walks.
  Handle any_live_handle() const;

  // Number of live triangles in the domain / ghosts (linear scans).
  std::size_t domain_triangle_count() const;
  // Area of the domain: the sum of the live finite in-domain triangles' areas (each accurately
  // rounded, signed_area(); the sum in floating point).
  double domain_area() const;

  // Adds a triangle slot (reusing a dead slot if any).
  TriangleId new_triangle();
  void kill_triangle(TriangleId t);
  void clear_free_slots() { free_slots_.clear(); }

  // ---- trials --------------------------------------------------------------------------------
  // A trial move that is kept only if it pays (the optimiser's kicks) is undone in time
  // proportional to what it changed, not by copying the mesh: between begin_trial() and
  // commit_trial() or undo_trial(), the local operations above (flip, splits, segment marks,
  // new and killed slots, added vertices, insert_vertex, locate's walk state) save what they are
  // about to change, and undo_trial() puts the mesh back as it was at begin_trial(). A caller that
  // writes the public arrays directly during a trial announces it first: save_triangle(t) before
  // writing triangles[t], flags[t] or t's segment markers, save_vertex(v) before writing points[v],
  // vertex_kind[v] or vertex_marker[v]. No compact() inside a trial.
  void begin_trial();
  void commit_trial();
  void undo_trial();
  bool in_trial() const { return trial_.open; }
  void save_triangle(TriangleId t) {
    if (trial_.open && t < trial_.triangles) save_triangle_slot(t);
  }
  void save_vertex(VertexId v) {
    if (trial_.open && v < trial_.points) trial_.vertices.push_back({v, points[v], vertex_kind[v], vertex_marker[v]});
  }

 private:
  struct SavedTriangle {
    TriangleId t;
    Triangle triangle;
    std::uint8_t flags;
    bool has_markers;
    std::array<std::int32_t, 3> markers;
  };
  struct SavedVertex {
    VertexId v;
    Point point;
    VertexKind kind;
    std::int32_t marker;
  };
  struct Trial {
    bool open = false;
    std::size_t triangles = 0, points = 0, segment_markers = 0;
    std::size_t free_low = 0;  // the free list's smallest size during the trial (below it: untouched)
    std::uint32_t walk_rng = 0;
    std::vector<SavedTriangle> saved;
    std::vector<SavedVertex> vertices;
    std::vector<TriangleId> popped_free_slots;  // the free list's entries from free_low up, as taken
  };
  void save_triangle_slot(TriangleId t);
  void close_trial();  // open = false, journal cleared

  std::vector<TriangleId> free_slots_;
  std::vector<Handle> flip_stack_;  // scratch for insert_vertex (no allocation per insertion)
  mutable std::uint32_t walk_rng_ = 0x9E3779B9u;  // deterministic stochastic-walk state
  Trial trial_;
};

// Drops dead triangle slots and removed vertices (VertexKind::kRemoved), renumbering both.
// Input vertices keep their ids (they come first and are never removed).
MWST_API void compact(Mesh& mesh);

// ---- validation --------------------------------------------------------------------------------
struct ValidateOptions {
  bool delaunay = false;          // every non-segment edge locally Delaunay (exact)
  double min_angle_deg = 0.0;     // every in-domain triangle has all angles ≥ this (if > 0)
};
// Checks reciprocal neighbours, counter-clockwise orientation (exact), the Euler count of the
// closed triangulation (V+1 − E + F = 2 with the infinite vertex), convexity of the hull, that
// segment flags and markers agree on both sides, and the options. Returns one line per violation
// (empty when valid).
MWST_API std::vector<std::string> validate(const Mesh& mesh, const ValidateOptions& options = {});

}  // namespace mwst
