// carve(): removes what is not the domain. Triangles are flooded ("infected", as Triangle calls it)
// across non-segment edges, starting from hull edges that are not segments (concavities) and from
// the triangles holding hole seeds; flooded triangles get the kOutside flag. They stay in the
// triangulation (so walks and later refinement keep a complete triangulation of the hull), but
// are never output, measured or refined.
#include <string>

#include "mwst/mesh/delaunay.hpp"

namespace mwst {

namespace {

std::string point_text(const Point& p) {
  // Appended piece by piece: "(" + std::string&& trips GCC 12's -Wrestrict false positive (-Werror).
  std::string s = "(";
  s += std::to_string(p.x);
  s += ", ";
  s += std::to_string(p.y);
  s += ')';
  return s;
}

}  // namespace

void carve(Mesh& m, const std::vector<Point>& holes, bool convex_hull,
           std::vector<std::string>* warnings) {
  std::vector<TriangleId> stack;
  auto infect = [&](TriangleId t) {
    if (m.is_dead(t) || m.is_ghost(t) || m.is_outside(t)) return;
    m.flags[t] = static_cast<std::uint8_t>(m.flags[t] | kOutside);
    stack.push_back(t);
  };
  if (!convex_hull) {
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
      if (m.is_dead(t) || !m.is_ghost(t)) continue;
      const Triangle& G = m.triangles[t];
      unsigned k = 0;
      while (G.v[k] != kInfinite) ++k;
      const Handle hull_edge = make_handle(t, k);
      if (!m.is_segment(hull_edge)) infect(m.sym(hull_edge) >> 2);
    }
  }
  auto flood = [&] {
    while (!stack.empty()) {
      const TriangleId t = stack.back();
      stack.pop_back();
      for (unsigned e = 0; e < 3; ++e) {
        const Handle h = make_handle(t, e);
        if (!m.is_segment(h)) infect(m.sym(h) >> 2);
      }
    }
  };
  flood();
  Handle hint = kNone;
  for (std::size_t i = 0; i < holes.size(); ++i) {
    const Point& p = holes[i];
    const std::string name = "hole " + std::to_string(i + 1) + " at " + point_text(p);
    if (!in_supported_range(p)) {
      if (warnings) warnings->push_back(name + " has a coordinate outside the supported range; ignored");
      continue;
    }
    const Location loc = m.locate(p, hint);
    hint = loc.handle;
    const TriangleId t = loc.handle >> 2;
    if (loc.kind == Location::Kind::kOnVertex ||
        (loc.kind == Location::Kind::kOnEdge && m.is_segment(loc.handle))) {
      if (warnings) warnings->push_back(name + " lies on a segment or vertex; ignored");
      continue;
    }
    if (m.is_ghost(t) || m.is_outside(t)) {
      // On a non-segment edge, either side will do; outside means outside.
      const bool other_side_inside = loc.kind == Location::Kind::kOnEdge &&
                                     !m.is_ghost(m.sym(loc.handle) >> 2) &&
                                     !m.is_outside(m.sym(loc.handle) >> 2);
      if (!other_side_inside) {
        if (warnings) warnings->push_back(name + " lies outside the domain; ignored");
        continue;
      }
      infect(m.sym(loc.handle) >> 2);
    } else {
      infect(t);
    }
    flood();
  }
}

}  // namespace mwst
