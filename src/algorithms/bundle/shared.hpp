// src/algorithms/bundle/shared.hpp — what every worker of the bundle number reads (internal):
// the mesh with its vertices renumbered for locality, DT(V), the candidate lists of the Delaunay
// triangles and the pencils.
//   DenseIds              — dense ids for 32-bit keys (an open-addressing table)
//   Shared::build         — renumber the whole mesh, DT(V) (or DT of a subset W), the pencils
//   Shared::build_region  — the same over a region of the mesh (in_k_bundle's local attempt)
//   Shared::finish        — DT of the renumbered vertices (kept from an earlier call if it can be)
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::bundle {

// Dense ids 0, 1, ... for 32-bit keys (mesh slots or vertex ids) in the order they are inserted:
// an open-addressing hash table, so that in_k_bundle's local attempt costs what its region holds,
// not what the mesh holds.
class DenseIds {
 public:
  explicit DenseIds(std::size_t expected = 0) { rehash(std::bit_ceil(2 * expected + 16)); }

  std::size_t size() const { return keys_.size(); }
  std::uint32_t key(std::uint32_t id) const { return keys_[id]; }

  // The id of `key`, or kNone.
  std::uint32_t find(std::uint32_t key) const {
    for (std::size_t i = hash(key);; i = (i + 1) & mask_) {
      const Cell& c = table_[i];
      if (c.id == kNone || c.key == key) return c.id;
    }
  }

  // The id of `key`, and whether it was added now.
  std::pair<std::uint32_t, bool> insert(std::uint32_t key) {
    if (2 * (keys_.size() + 1) > table_.size()) rehash(2 * table_.size());
    std::size_t i = hash(key);
    for (;; i = (i + 1) & mask_) {
      const Cell& c = table_[i];
      if (c.id == kNone) break;
      if (c.key == key) return {c.id, false};
    }
    const auto id = static_cast<std::uint32_t>(keys_.size());
    table_[i] = {key, id};
    keys_.push_back(key);
    return {id, true};
  }

 private:
  struct Cell {
    std::uint32_t key = 0;
    std::uint32_t id = kNone;  // kNone: empty
  };
  // Fibonacci hashing: the top bits of key · 2^64/φ.
  std::size_t hash(std::uint32_t key) const {
    return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void rehash(std::size_t capacity) {
    table_.assign(capacity, Cell{});
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    for (std::uint32_t id = 0; id < keys_.size(); ++id) {
      std::size_t i = hash(keys_[id]);
      while (table_[i].id != kNone) i = (i + 1) & mask_;
      table_[i] = {keys_[id], id};
    }
  }

  std::vector<Cell> table_;
  std::vector<std::uint32_t> keys_;  // by id
  std::size_t mask_ = 0;
  int shift_ = 64;
};

// What every worker reads: the mesh with its vertices renumbered along a Morton curve (so that the
// per-vertex scratch of neighbouring pencils is close in memory), DT(V), the candidate list of
// every Delaunay triangle, and the pencils (one Delaunay edge each).
struct Shared {
  explicit Shared(const Mesh& mesh,
                  std::chrono::steady_clock::time_point until = std::chrono::steady_clock::time_point::max())
      : m(mesh), deadline(until) {}

  // Throws KBundleTimeout once the deadline (in_k_bundle's) has passed; called once per item of
  // the costly loops (floods, circumdisk counts, sweeps), each of which costs far more.
  void check_deadline() const {
    if (deadline != std::chrono::steady_clock::time_point::max() && std::chrono::steady_clock::now() > deadline) {
      throw KBundleTimeout();
    }
  }

  const Mesh& m;
  std::chrono::steady_clock::time_point deadline;
  std::vector<Point> pts;                   // by renumbered vertex id
  std::vector<VertexId> mesh_id;            // by renumbered vertex id: the mesh's id
  struct Slot {
    std::array<VertexId, 3> v;  // corners, renumbered (kInfinite for ghosts and dead slots)
  };
  // Every mesh slot (build), or the slots of a region of the mesh renumbered densely followed by
  // one slot, `outside`, that stands for every triangle beyond the region (build_region).
  std::vector<Slot> slots;
  // The slots' neighbours (as in Triangle::n): over the whole mesh (build) the mesh's own
  // triangles' `n`, read through mesh_triangles_ (slot numbers are the mesh's, so its neighbour
  // handles are right as they are: a copy of them was 12 bytes a slot at in_k_bundle's peak); over
  // a region (build_region), or once the mesh is to be freed (own_neighbours), `neighbours_held`.
  std::vector<std::array<Handle, 3>> neighbours_held;
  // Copies the mesh's neighbours into neighbours_held (build over the whole mesh only): for a
  // caller that frees the mesh while Shared is still read (bundle_number of a triangle list).
  void own_neighbours() {
    if (mesh_triangles_ == nullptr) return;
    neighbours_held.resize(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) neighbours_held[t] = m.triangles[t].n;
    read_held_neighbours();
  }
  std::vector<std::uint8_t> domain;         // per slot: in the domain (Mesh::in_domain)
  TriangleId outside = kNone;               // the slot beyond a region (kNone: the whole mesh)
  std::vector<Handle> vertex_edge;          // renumbered id → a mesh edge leaving the vertex
  std::uint32_t used = 0;                   // ids [0, used) are the vertices of T, and DT ids
  Mesh dt;
  // The candidate lists in DT slot order, list_begin[d] the offset of DT slot d's among them
  // (list_begin[d + 1] the end), held in one of two ways: in `list` (flat), or, as build_lists
  // leaves them, in `list_chunks` (each worker's chunks, in slot order; no list straddles two),
  // chunk c starting at offset list_chunk_first[c]. The chunks are the floods' own output: copying
  // them into one array would hold the lists twice at the peak of in_k_bundle.
  std::vector<std::uint32_t> list_begin;
  std::vector<TriangleId> list;
  std::vector<std::vector<TriangleId>> list_chunks;
  std::vector<std::uint32_t> list_chunk_first;
  std::vector<Handle> pencils;              // per Delaunay edge: a DT handle with a finite left side
  // Per DT slot (empty: none): its list was cut at the budget's cap (bundle_number with a budget).
  std::vector<std::uint8_t> truncated;
  // Per DT slot (empty: every slot is its own): the slot whose circumdisk and candidate list it
  // shares. Delaunay triangles with one circumcircle (cocircular vertices: points on a circle) tile
  // the convex polygon of the vertices on it, joined across edges whose four vertices are
  // cocircular; the first slot of each such group is flooded, the others use its list
  // (share_cocircular_disks).
  std::vector<TriangleId> disk_rep;
  // Per DT slot (empty: not computed), bit e: the four vertices of the slot and of its finite
  // neighbour across edge e are cocircular (share_cocircular_disks; read by cocircular_edge).
  std::vector<std::uint8_t> cocircular;
  bool kept_dt = false;                     // dt is a kept DT(V) with the new vertices inserted

  Handle sym(Handle h) const { return neighbours(h >> 2)[h & 3]; }
  const std::array<Handle, 3>& neighbours(TriangleId t) const {
    return mesh_triangles_ != nullptr ? mesh_triangles_[t].n : neighbours_held[t];
  }
  VertexId org(Handle h) const { return slots[h >> 2].v[next3(h & 3)]; }
  VertexId dest(Handle h) const { return slots[h >> 2].v[prev3(h & 3)]; }
  VertexId apex(Handle h) const { return slots[h >> 2].v[h & 3]; }
  Handle onext(Handle h) const { return sym(Mesh::lprev(h)); }
  bool is_ghost(TriangleId t) const {
    const auto& v = slots[t].v;
    return v[0] == kInfinite || v[1] == kInfinite || v[2] == kInfinite;
  }
  bool in_domain(TriangleId t) const { return domain[t] != 0; }
  // The DT slot whose candidate list (and circumdisk) DT slot d uses.
  TriangleId disk(TriangleId d) const { return disk_rep.empty() ? d : disk_rep[d]; }
  // The candidate list of DT slot d (its disk's): size and first entry.
  std::uint32_t list_size(TriangleId d) const { return list_begin[disk(d) + 1] - list_begin[disk(d)]; }
  const TriangleId* list_data(TriangleId d) const { return list_at(list_begin[disk(d)]); }
  // The list entry at `offset` (see list_begin); an offset at the end of the lists is never read.
  const TriangleId* list_at(std::uint32_t offset) const {
    if (list_chunks.empty()) return list.data() + offset;
    const auto after = std::upper_bound(list_chunk_first.begin(), list_chunk_first.end(), offset);
    const auto c = static_cast<std::size_t>(after - list_chunk_first.begin()) - 1;  // (chunk 0 starts at 0)
    return list_chunks[c].data() + (offset - list_chunk_first[c]);
  }
  // Frees the lists, in either form.
  void release_lists();
  // Moves chunked lists into `list` (room for `capacity` triangles, at most twice what they hold:
  // pages not written to are not resident), freeing each chunk once copied.
  void flatten_lists(std::size_t capacity = 0);
  bool list_cut(TriangleId d) const { return !truncated.empty() && truncated[disk(d)] != 0; }

  // Are the four vertices of the two finite Delaunay triangles on DT edge h cocircular (the pencil
  // of h holds one disk)? From `cocircular` when share_cocircular_disks filled it, else exact.
  bool cocircular_edge(Handle h) const {
    if (!cocircular.empty()) return (cocircular[triangle_of(h)] >> edge_of(h) & 1u) != 0;
    return incircle(pts[dt.org(h)], pts[dt.dest(h)], pts[dt.apex(h)], pts[dt.apex(dt.sym(h))]) == 0;
  }

  // Fills disk_rep: the Delaunay triangles of one circumcircle share the first one's slot. Returns
  // the number of distinct circumdisks (live finite DT slots that are their own), and fills
  // `cocircular`. The edges' incircle tests (one per edge, exact when the vertices are cocircular)
  // run on `threads` threads; the grouping, which reads them, on one.
  std::size_t share_cocircular_disks(unsigned threads = 1);


  // Renumbers, builds DT(V) and (if asked) lists the pencils. False if T has no triangle. With a
  // `subset` W (mesh vertex ids), `dt` is the Delaunay triangulation of the vertices of T in W only
  // (ids below `used`, in mesh id order); the other vertices of T follow them (in_k_bundle's local
  // attempt over the whole mesh, when a flood leaves the regions of build_region).
  //
  // With `prior_dt` (a Delaunay triangulation whose vertex i is mesh vertex (*prior_ids)[i]) and no
  // subset: if every vertex of prior_dt is still a vertex of T at the same place, those vertices
  // keep their DT ids (first, in prior order), and `dt` is prior_dt (moved from) with the other
  // vertices of T inserted by Lawson flips — DT(V) again, without building it from scratch.
  bool build(bool list_pencils = true, const std::vector<VertexId>* subset = nullptr, Mesh* prior_dt = nullptr,
             const std::vector<VertexId>* prior_ids = nullptr);

  // The order build() (without a subset or a prior DT) numbers the vertices of a mesh in when every
  // vertex is a corner of a triangle of T: a mesh made from T alone (bundle_number of a triangle
  // list), whose DT(V) can then be built from the points alone, before the mesh, and given to
  // build() as its prior DT with these ids — the same DT(V), vertex for vertex and slot for slot.
  static std::vector<VertexId> curve_order(const std::vector<Point>& points);

  // build() for in_k_bundle's local attempt, in time proportional to a region of the mesh: the
  // mesh slots `region` (live; every triangle around each vertex of `w` among them, and every ghost
  // next to a finite one) become slots 0, 1, ... and `outside` stands for the rest; `dt` is the
  // Delaunay triangulation of the vertices of T in `w` (mesh ids, ascending: the order build()
  // gives them with a subset). False if none of `w` is a vertex of T.
  bool build_region(const std::vector<TriangleId>& region, const DenseIds& region_ids, const std::vector<VertexId>& w);

 private:
  const Triangle* mesh_triangles_ = nullptr;  // the mesh's triangles whose `n` are read, or none
  void read_mesh_neighbours() { mesh_triangles_ = m.triangles.data(); }
  void read_held_neighbours() { mesh_triangles_ = nullptr; }

  Mesh* prior_ = nullptr;        // build(): the Delaunay triangulation of vertices [0, prior_used_)
  std::uint32_t prior_used_ = 0;

  // build()'s steps.
  bool mark_vertices(const std::vector<VertexId>* subset, std::vector<std::uint8_t>& state) const;
  std::vector<std::uint64_t> vertex_order(const std::vector<std::uint8_t>& state, const std::vector<VertexId>* subset,
                                          Mesh* prior_dt, const std::vector<VertexId>* prior_ids);
  void apply_order(const std::vector<std::uint64_t>& order, const std::vector<std::uint8_t>& state);
  // DT of the vertices [0, used), and (if asked) the pencils.
  bool finish(bool list_pencils);
};

}  // namespace mwst::bundle
