// src/algorithms/mwt/domain.cpp — from a mesh to the exact MWT's domain and back (domain.hpp).
#include "algorithms/mwt/domain.hpp"

#include <string>

#include "mwst/error.hpp"
#include "mesh/keys.hpp"

namespace mwst::mwt {

Domain collect_domain(const Mesh& m) {
  Domain d;
  std::unordered_map<VertexId, Index> local;
  auto local_of = [&](VertexId v) {
    auto [it, inserted] = local.emplace(v, static_cast<Index>(d.ids.size()));
    if (inserted) {
      d.ids.push_back(v);
      d.pts.push_back(m.points[v]);
    }
    return it->second;
  };
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (!m.in_domain(t)) continue;
    const auto& v = m.triangles[t].v;
    d.triangles.push_back({local_of(v[0]), local_of(v[1]), local_of(v[2])});
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const TriangleId other = m.sym(h) >> 2;
      const bool boundary = !m.in_domain(other);
      const bool segment = m.is_segment(h);
      const Index a = local_of(m.org(h)), b = local_of(m.dest(h));
      if (boundary) {
        d.boundary.push_back({a, b});
        d.outer.emplace(edge_key(m.org(h), m.dest(h)), m.sym(h));
      }
      if (boundary || (segment && t < other)) d.constraints.push_back({std::min(a, b), std::max(a, b)});
      if (segment && (boundary || t < other)) d.segments.push_back({m.org(h), m.dest(h), m.marker(h)});
    }
  }
  d.segment_neighbours.assign(d.ids.size(), {});
  d.on_segment.assign(d.ids.size(), 0);
  for (const auto& s : d.segments) {
    const Index a = local.at(static_cast<VertexId>(s[0])), b = local.at(static_cast<VertexId>(s[1]));
    d.segment_neighbours[a].push_back(b);
    d.segment_neighbours[b].push_back(a);
  }
  for (Index i = 0; i < d.ids.size(); ++i) {
    d.on_segment[i] = d.ids[i] < m.vertex_kind.size() && m.vertex_kind[d.ids[i]] == VertexKind::kSteinerOnSegment;
  }
  return d;
}
Mesh rebuild(const Mesh& input, const Domain& d, const std::vector<Tri>& tris) {
  Mesh m = input;
  std::vector<TriangleId> slots;
  for (TriangleId t = 0; t < m.triangles.size(); ++t) {
    if (m.in_domain(t)) slots.push_back(t);
  }
  if (slots.size() != tris.size()) {
    throw InternalError("mwt: the optimal triangulation has " + std::to_string(tris.size()) +
                        " triangles, the domain " + std::to_string(slots.size()));
  }
  std::unordered_map<std::uint64_t, Handle> directed;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const TriangleId t = slots[i];
    m.flags[t] = static_cast<std::uint8_t>(m.flags[t] & ~std::uint8_t{7});
    for (unsigned k = 0; k < 3; ++k) m.triangles[t].v[k] = d.ids[tris[i][k]];
    for (unsigned e = 0; e < 3; ++e) directed.emplace(edge_key(m.org(make_handle(t, e)), m.dest(make_handle(t, e))), make_handle(t, e));
  }
  for (const auto& [k, h] : directed) {
    const VertexId a = static_cast<VertexId>(k >> 32), b = static_cast<VertexId>(k & 0xFFFFFFFFu);
    auto it = directed.find(edge_key(b, a));
    if (it != directed.end()) {
      m.triangles[h >> 2].n[h & 3] = it->second;
      continue;
    }
    auto out = d.outer.find(k);
    if (out == d.outer.end()) throw InternalError("mwt: an edge of the optimal triangulation has no neighbour");
    m.triangles[h >> 2].n[h & 3] = out->second;
    m.triangles[out->second >> 2].n[out->second & 3] = h;
  }
  for (const auto& s : d.segments) {
    const auto it = directed.find(edge_key(static_cast<VertexId>(s[0]), static_cast<VertexId>(s[1])));
    if (it == directed.end()) throw InternalError("mwt: a subsegment is missing from the optimal triangulation");
    m.set_segment(it->second, static_cast<std::int32_t>(s[2]));
  }
  return m;
}

std::vector<Tri> restrict_to_domain(const Domain& d, const std::vector<Tri>& tris) {
  std::unordered_map<std::uint64_t, Index> owner;
  for (Index i = 0; i < tris.size(); ++i) {
    for (unsigned k = 0; k < 3; ++k) owner.emplace(edge_key(tris[i][k], tris[i][(k + 1) % 3]), i);
  }
  std::unordered_map<std::uint64_t, char> barrier;
  for (const auto& b : d.boundary) barrier.emplace(edge_key(b[0], b[1]), 1), barrier.emplace(edge_key(b[1], b[0]), 1);
  std::vector<char> inside(tris.size(), 0);
  std::vector<Index> stack;
  for (const auto& b : d.boundary) {
    auto it = owner.find(edge_key(b[0], b[1]));
    if (it == owner.end()) return {};
    if (!inside[it->second]) inside[it->second] = 1, stack.push_back(it->second);
  }
  while (!stack.empty()) {
    const Index t = stack.back();
    stack.pop_back();
    for (unsigned k = 0; k < 3; ++k) {
      const Index a = tris[t][k], b = tris[t][(k + 1) % 3];
      if (barrier.count(edge_key(a, b))) continue;
      auto it = owner.find(edge_key(b, a));
      if (it != owner.end() && !inside[it->second]) inside[it->second] = 1, stack.push_back(it->second);
    }
  }
  std::vector<Tri> out;
  for (Index i = 0; i < tris.size(); ++i) {
    if (inside[i]) out.push_back(tris[i]);
  }
  return out;
}

}  // namespace mwst::mwt
