// src/algorithms/optimize/region.cpp — re-triangulating a region of the mesh in place, and reading a
// vertex's star (region.hpp).
#include "algorithms/optimize/region.hpp"

#include <unordered_map>

#include "mwst/error.hpp"
#include "mesh/keys.hpp"

namespace mwst::opt {

void replace_region(Mesh& m, const Region& r, const std::vector<std::array<VertexId, 3>>& tris,
                    const std::vector<std::uint8_t>* flags) {
  // (In a trial the slots and their outer neighbours are saved first: written directly below.)
  for (const TriangleId t : r.triangles) m.save_triangle(t);
  for (const Handle o : r.outer) m.save_triangle(o >> 2);
  std::vector<TriangleId> slots = r.triangles;
  while (slots.size() < tris.size()) slots.push_back(m.new_triangle());
  for (std::size_t i = tris.size(); i < slots.size(); ++i) m.kill_triangle(slots[i]);
  slots.resize(tris.size());
  std::unordered_map<std::uint64_t, std::size_t> boundary_index;
  for (std::size_t i = 0; i < r.boundary.size(); ++i) {
    boundary_index.emplace(edge_key(r.boundary[i], r.boundary[(i + 1) % r.boundary.size()]), i);
  }
  for (std::size_t i = 0; i < tris.size(); ++i) {
    m.triangles[slots[i]].v = tris[i];
    m.flags[slots[i]] = flags ? (*flags)[i] : r.outside_flag;
  }
  std::unordered_map<std::uint64_t, Handle> open;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = slots[i];
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const VertexId u = m.org(h), v = m.dest(h);
      const auto b = boundary_index.find(edge_key(u, v));
      if (b != boundary_index.end()) {
        const Handle o = r.outer[b->second];
        m.triangles[t].n[e] = o;
        m.triangles[o >> 2].n[o & 3] = h;
        if (r.segment[b->second]) m.set_segment(h, r.marker[b->second]);
        continue;
      }
      const auto twin = open.find(edge_key(v, u));
      if (twin != open.end()) {
        m.triangles[t].n[e] = twin->second;
        m.triangles[twin->second >> 2].n[twin->second & 3] = h;
        open.erase(twin);
      } else {
        open.emplace(edge_key(u, v), h);
      }
    }
  }
  if (!open.empty()) throw InternalError("optimize: re-triangulated region does not close");
}
bool star_of(const Mesh& m, Handle h, Region& r) {
  r.triangles.clear();
  r.boundary.clear();
  r.outer.clear();
  r.segment.clear();
  r.marker.clear();
  const Handle start = h;
  for (std::size_t guard = 0; guard < 4096; ++guard) {
    const TriangleId t = h >> 2;
    if (m.is_ghost(t) || m.is_dead(t)) return false;
    r.triangles.push_back(t);
    r.boundary.push_back(m.dest(h));
    const Handle opposite = Mesh::lnext(h);  // dest → apex, the star polygon's edge
    r.outer.push_back(m.sym(opposite));
    r.segment.push_back(m.is_segment(opposite) ? 1 : 0);
    r.marker.push_back(m.marker(opposite));
    h = m.onext(h);
    if (h == start) return true;
  }
  return false;
}
}  // namespace mwst::opt
