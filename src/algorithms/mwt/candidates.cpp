// src/algorithms/mwt/candidates.cpp — candidate edges for the exact MWT (candidates.hpp).
#include "algorithms/mwt/candidates.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "algorithms/mwt/box_tree.hpp"

namespace mwst::mwt {

namespace {

// ---- candidates: the diamond test ---------------------------------------------------------------

enum class Diamond { kKeep, kExcluded, kThroughVertex };

Diamond diamond_test(const std::vector<Point>& P, const PointGrid& grid, Index u, Index v,
                     double tan_angle) {
  const Point& a = P[u];
  const Point& b = P[v];
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double L = std::hypot(dx, dy);
  const double ex = dx / L, ey = dy / L;
  const double margin = 1e-12 * L + 1e-13 * grid.magnitude();
  const double h = 0.5 * L * tan_angle + margin;
  const double mx = 0.5 * (a.x + b.x), my = 0.5 * (a.y + b.y);
  const double xmin = std::min({a.x, b.x, mx - std::fabs(ey) * h}) - margin;
  const double xmax = std::max({a.x, b.x, mx + std::fabs(ey) * h}) + margin;
  const double ymin = std::min({a.y, b.y, my - std::fabs(ex) * h}) - margin;
  const double ymax = std::max({a.y, b.y, my + std::fabs(ex) * h}) + margin;
  bool left = false, right = false, through = false;
  grid.for_each_in_box(xmin, ymin, xmax, ymax, [&](Index k) {
    if (k == u || k == v) return true;
    const Point& p = P[k];
    const double qx = p.x - a.x, qy = p.y - a.y;
    const double t = qx * ex + qy * ey;
    const double s = ex * qy - ey * qx;  // signed distance, left of a→b positive
    if (std::fabs(s) <= margin + 1e-9 * L && on_open_segment(a, b, p)) {
      through = true;
      return false;
    }
    if (t <= margin || t >= L - margin || std::fabs(s) <= margin) return true;
    if (std::fabs(s) < tan_angle * std::min(t, L - t) - margin) {
      (s > 0 ? left : right) = true;
    }
    return true;  // keep scanning: a vertex on the edge must still be found
  });
  if (through) return Diamond::kThroughVertex;
  return (left && right) ? Diamond::kExcluded : Diamond::kKeep;
}

}  // namespace

std::vector<std::array<Index, 2>> diamond_candidates(const std::vector<Point>& P, double angle,
                                                     std::size_t max_edges, bool& too_many) {
  const PointGrid grid(P);
  const double shrunk = angle * (1.0 - 1e-6);
  const double tan_angle = std::tan(shrunk);
  const double gap_limit = shrunk - 3e-9;
  constexpr double kAngleSlack = 1e-9;
  std::vector<std::array<Index, 2>> edges;
  std::vector<double> angles;
  for (Index u = 0; u < P.size(); ++u) {
    const Point& a = P[u];
    auto visit_disk = [&](double radius, auto&& f) {
      grid.for_each_in_box(a.x - radius, a.y - radius, a.x + radius, a.y + radius, [&](Index k) {
        if (k != u) f(k, std::hypot(P[k].x - a.x, P[k].y - a.y));
        return true;
      });
    };
    auto test = [&](Index v) {
      if (v <= u) return;
      if (diamond_test(P, grid, u, v, tan_angle) == Diamond::kKeep) edges.push_back({u, v});
    };
    if (edges.size() > max_edges) {
      too_many = true;
      return {};
    }
    // Start at about the nearest-neighbour distance (doubling from a tiny radius until the square
    // of half-width r holds another point), so clustered inputs start at their local scale.
    double r = grid.diagonal() * 0x1p-40;
    for (bool found = false; !found && r < grid.diagonal();) {
      grid.for_each_in_box(a.x - r, a.y - r, a.x + r, a.y + r, [&](Index k) {
        found = k != u;
        return !found;
      });
      if (!found) r *= 2.0;
    }
    visit_disk(2.0 * r, [&](Index v, double dist) {
      if (dist <= 2.0 * r) test(v);
    });
    while (2.0 * r <= grid.diagonal() * (1.0 + 1e-9)) {
      // Dead sectors from the points within r (with a margin on r) for the edges longer than 2r.
      angles.clear();
      visit_disk(r, [&](Index k, double dist) {
        if (dist <= r * (1.0 - 1e-9)) angles.push_back(std::atan2(P[k].y - a.y, P[k].x - a.x));
      });
      std::sort(angles.begin(), angles.end());
      bool all_dead = angles.size() >= 2;
      for (std::size_t i = 0; all_dead && i < angles.size(); ++i) {
        const double next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2.0 * std::numbers::pi;
        if (next - angles[i] >= gap_limit) all_dead = false;
      }
      if (all_dead) break;
      auto dead = [&](double psi) {
        if (angles.size() < 2) return false;
        // first angle above psi + slack (cyclically) and last below psi − slack
        auto it = std::upper_bound(angles.begin(), angles.end(), psi + kAngleSlack);
        const double above = it != angles.end() ? *it : angles.front() + 2.0 * std::numbers::pi;
        auto jt = std::lower_bound(angles.begin(), angles.end(), psi - kAngleSlack);
        const double below = jt != angles.begin() ? *(jt - 1) : angles.back() - 2.0 * std::numbers::pi;
        return above - psi < shrunk - kAngleSlack && psi - below < shrunk - kAngleSlack &&
               above - psi > kAngleSlack && psi - below > kAngleSlack;
      };
      const double inner = 2.0 * r, outer = 4.0 * r;
      visit_disk(outer, [&](Index v, double dist) {
        if (v <= u || dist <= inner || dist > outer) return;
        if (dead(std::atan2(P[v].y - a.y, P[v].x - a.x))) return;
        test(v);
      });
      r *= 2.0;
    }
  }
  return edges;
}
// ---- candidates: visibility in the domain -------------------------------------------------------

std::vector<std::array<Index, 2>> visibility_candidates(const Domain& d) {
  const std::vector<Point>& P = d.pts;
  const std::size_t n = P.size();
  // Corners of the domain triangles at each vertex: (next, previous) counter-clockwise.
  std::vector<std::vector<std::array<Index, 2>>> corners(n);
  for (const Tri& t : d.triangles) {
    for (unsigned k = 0; k < 3; ++k) corners[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
  }
  auto enters_domain = [&](Index u, Index v) {
    for (const auto& c : corners[u]) {
      if (c[0] == v || c[1] == v) return true;
      if (orient2d(P[u], P[c[0]], P[v]) > 0 && orient2d(P[u], P[c[1]], P[v]) < 0) return true;
    }
    return false;
  };
  std::vector<std::array<Index, 2>> edges;
  for (Index u = 0; u < n; ++u) {
    for (Index v = u + 1; v < n; ++v) {
      bool ok = enters_domain(u, v);
      for (Index r : d.segment_neighbours[u]) ok = ok && !straight_corner(d, r, u, v);
      for (Index k = 0; ok && k < n; ++k) {
        if (k != u && k != v && on_open_segment(P[u], P[v], P[k])) ok = false;
      }
      for (std::size_t s = 0; ok && s < d.constraints.size(); ++s) {
        const auto& c = d.constraints[s];
        if (c[0] == u || c[0] == v || c[1] == u || c[1] == v) continue;
        if (properly_cross(P[u], P[v], P[c[0]], P[c[1]])) ok = false;
      }
      if (ok) edges.push_back({u, v});
    }
  }
  return edges;
}
}  // namespace mwst::mwt
