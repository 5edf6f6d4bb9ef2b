// src/algorithms/optimize/region_search.cpp — regions re-triangulated whole: each triangle with its neighbours
// (or an edge's two triangles with theirs) replaced by its minimum weight triangulation or by a star
// from a new Steiner point at the geometric median of its corners, whichever is lightest.
#include "algorithms/optimize/optimizer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "algorithms/mwt/polygon_mwt.hpp"

namespace mwst::opt {

void Optimizer::try_insertions() {
  const auto slots = static_cast<TriangleId>(m_.triangles.size());
  std::vector<TriangleId> tris;
  for (TriangleId t = 0; t < slots; ++t) {
    if ((t & 1023u) == 0 && out_of_time()) break;
    if (!m_.in_domain(t) || !in_focus(m_.points[m_.triangles[t].v[0]])) continue;
    // Region 1: the triangle and its neighbours (a hexagon at most).
    tris.assign(1, t);
    if (add_neighbours(t, tris) && tris.size() >= 2 && try_region(tris)) continue;
    // Region 2: the two triangles of each edge with all their neighbours (an octagon at most).
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      if (m_.is_segment(h)) continue;
      const TriangleId u = m_.sym(h) >> 2;
      if (!m_.in_domain(u) || u < t) continue;
      tris.assign({t, u});
      if (add_neighbours(t, tris) && add_neighbours(u, tris) && try_region(tris)) break;
    }
  }
  rebuild_vertex_handles();
}

// Adds the in-domain neighbours of t across non-segment edges to `tris`; false if a neighbour
// across a non-segment edge is outside the domain.
bool Optimizer::add_neighbours(TriangleId t, std::vector<TriangleId>& tris) {
  for (unsigned e = 0; e < 3; ++e) {
    const Handle h = make_handle(t, e);
    if (m_.is_segment(h)) continue;
    const TriangleId u = m_.sym(h) >> 2;
    if (!m_.in_domain(u)) return false;
    if (std::find(tris.begin(), tris.end(), u) == tris.end()) tris.push_back(u);
  }
  return true;
}

// Builds the region made of the given triangles (must be live, in the domain, a topological
// disk whose boundary is a simple cycle). Returns false otherwise.
bool Optimizer::region_from(const std::vector<TriangleId>& tris, Region& r) {
  r.triangles = tris;
  r.boundary.clear();
  r.outer.clear();
  r.segment.clear();
  r.marker.clear();
  r.outside_flag = 0;
  member_.clear();
  for (const TriangleId t : tris) {
    if (!m_.in_domain(t)) return false;
    member_.push_back(t);
  }
  std::sort(member_.begin(), member_.end());
  if (std::adjacent_find(member_.begin(), member_.end()) != member_.end()) return false;
  auto inside = [&](TriangleId t) { return std::binary_search(member_.begin(), member_.end(), t); };
  // Boundary edges by their origin (sorted: a repeated origin means the boundary is not
  // simple), then chained from origin to origin.
  boundary_from_.clear();
  double interior = 0.0;
  for (const TriangleId t : tris) {
    for (unsigned e = 0; e < 3; ++e) {
      const Handle h = make_handle(t, e);
      const Handle s = m_.sym(h);
      if (inside(s >> 2)) {
        if (m_.is_segment(h)) return false;  // never remove a subsegment
        interior += 0.5 * distance(m_.points[m_.org(h)], m_.points[m_.dest(h)]);
        continue;
      }
      boundary_from_.emplace_back(m_.org(h), h);
    }
  }
  if (boundary_from_.empty()) return false;
  std::sort(boundary_from_.begin(), boundary_from_.end());
  const auto same_origin = [](const auto& x, const auto& y) { return x.first == y.first; };
  if (std::adjacent_find(boundary_from_.begin(), boundary_from_.end(), same_origin) != boundary_from_.end()) {
    return false;  // vertex repeated
  }
  region_interior_weight_ = interior;
  auto edge_from = [&](VertexId v) -> const std::pair<VertexId, Handle>* {
    const auto at = std::lower_bound(boundary_from_.begin(), boundary_from_.end(), std::pair<VertexId, Handle>(v, 0));
    return at != boundary_from_.end() && at->first == v ? &*at : nullptr;
  };
  // Start from the smallest origin for determinism.
  Handle h = boundary_from_.front().second;
  for (std::size_t i = 0; i < boundary_from_.size(); ++i) {
    r.boundary.push_back(m_.org(h));
    r.outer.push_back(m_.sym(h));
    r.segment.push_back(m_.is_segment(h) ? 1 : 0);
    r.marker.push_back(m_.marker(h));
    const auto* next = edge_from(m_.dest(h));
    if (next == nullptr) return false;
    h = next->second;
  }
  if (m_.org(h) != r.boundary.front()) return false;  // more than one boundary cycle
  // A disk with B boundary and I interior vertices has B + 2I − 2 triangles: insist on I = 0,
  // so that re-triangulating the region never loses a vertex.
  return tris.size() + 2 == r.boundary.size();
}

// Re-triangulates the region (no interior vertex) by whichever is lightest: its minimum weight
// triangulation (a many-edge flip), or a star from a new Steiner vertex at the geometric median
// of its corners. Returns true if the region changed.
bool Optimizer::try_region(const std::vector<TriangleId>& tris, bool allow_star) {
  bool depends_on_room = false;  // a failure for want of Steiner room is not remembered
  if (!test_.remember_failed_regions) return try_region_once(tris, allow_star, depends_on_room);
  const RegionFingerprint fingerprint = region_fingerprint(tris, allow_star);
  FailedRegionSet& set = failed_region_set(fingerprint);
  // The set is kept in order of last use (most recent first; a miss forgets the least recent), so
  // the fingerprints of regions that have since changed, never asked for again, leave first.
  const auto found = std::find(set.way.begin(), set.way.end(), fingerprint);
  if (found != set.way.end()) {
    std::rotate(set.way.begin(), found, found + 1);
    ++stats_.region_tries_skipped;
    return false;
  }
  if (!try_region_once(tris, allow_star, depends_on_room)) {
    if (!depends_on_room) {
      std::copy_backward(set.way.begin(), set.way.end() - 1, set.way.end());
      set.way.front() = fingerprint;
    }
    return false;
  }
  return true;
}

bool Optimizer::try_region_once(const std::vector<TriangleId>& tris, bool allow_star, bool& depends_on_room) {
  if (!region_from(tris, region_)) return false;
  polygon_.clear();
  Point centroid{0.0, 0.0};
  for (const VertexId u : region_.boundary) {
    polygon_.push_back(m_.points[u]);
    centroid.x += m_.points[u].x;
    centroid.y += m_.points[u].y;
  }
  const double current = region_interior_weight_ * (1.0 - 1e-12);
  local_.clear();
  const double mwt = polygon_mwt(polygon_, &local_);
  double star_weight = std::numeric_limits<double>::infinity();
  Point q{0.0, 0.0};
  // A lower bound on any star's spokes: by the triangle inequality, a point's distances to two
  // corners sum to at least the corners' distance, so pairing corner i with corner i + d/2
  // bounds the spoke sum from below. When even that cannot beat the region's edges or its
  // MWT, Weiszfeld's iteration (the costly part) is skipped; it could not win.
  double star_lower_bound = 0.0;
  {
    const std::size_t d = polygon_.size(), half = d / 2;
    for (std::size_t i = 0; i < half; ++i) star_lower_bound += distance(polygon_[i], polygon_[i + half]);
  }
  const bool star_may_win = star_lower_bound < std::min(current, mwt) * (1.0 + 1e-9);
  if (opt_.insert && allow_star && star_may_win) {
    centroid.x /= static_cast<double>(polygon_.size());
    centroid.y /= static_cast<double>(polygon_.size());
    q = geometric_median(centroid, polygon_);
    q = {snap_to_range(q.x), snap_to_range(q.y)};
    // (A star that cannot win is not tested for the kernel, whose margins cost a hypot per edge.)
    if (in_supported_range(q)) {
      const double spokes = spoke_sum(q, polygon_);
      if (spokes < current && spokes < mwt && in_kernel(q, polygon_) && separated(q, region_.outer) &&
          star_within_area(q, polygon_)) {
        star_weight = spokes;
      }
    }
  }
  const bool star_wins = std::isfinite(star_weight);  // (only a winning star's weight is kept)
  if (star_wins && steiner_room() == 0) depends_on_room = true;
  if (star_wins && !depends_on_room) {
    const VertexId v = m_.add_vertex(q, VertexKind::kSteiner, 0);
    vertex_handle_.push_back(kNone);
    std::vector<std::array<VertexId, 3>> star;
    const std::size_t d = region_.boundary.size();
    for (std::size_t i = 0; i < d; ++i) {
      star.push_back({v, region_.boundary[i], region_.boundary[(i + 1) % d]});
    }
    replace_region(m_, region_, star);
    ++stats_.insertions;
    return true;
  }
  if (mwt < current && !region_sliver(local_) && within_area(polygon_, local_)) {
    std::vector<std::array<VertexId, 3>> tris_new;
    for (const auto& tri : local_) {
      tris_new.push_back({region_.boundary[tri[0]], region_.boundary[tri[1]], region_.boundary[tri[2]]});
    }
    replace_region(m_, region_, tris_new);
    ++stats_.region_retriangulations;
    return true;
  }
  return false;
}

Optimizer::RegionFingerprint Optimizer::region_fingerprint(const std::vector<TriangleId>& tris, bool allow_star) const {
  std::uint64_t h1 = 0x9E3779B97F4A7C15ull ^ tris.size(), h2 = 0xC2B2AE3D27D4EB4Full + (allow_star ? 1u : 0u);
  // Two independent multiply-rotate chains (one multiplication per word each), finished below.
  const auto mix = [&](std::uint64_t w) {
    h1 = std::rotl(h1 ^ w, 27) * 0x87C37B91114253D5ull;
    h2 = std::rotl(h2 + w, 31) * 0x4CF5AD432745937Full;
  };
  for (const TriangleId t : tris) {
    const Triangle& T = m_.triangles[t];
    mix(t | std::uint64_t{m_.flags[t]} << 32);
    for (unsigned k = 0; k < 3; ++k) {
      const VertexId v = T.v[k];
      mix(v | std::uint64_t{T.n[k]} << 32);
      if (v == kInfinite) continue;
      mix(std::bit_cast<std::uint64_t>(m_.points[v].x));
      mix(std::bit_cast<std::uint64_t>(m_.points[v].y) ^ static_cast<std::uint64_t>(m_.vertex_kind[v]));
    }
  }
  const auto finish = [](std::uint64_t h) {
    h ^= h >> 33;
    h *= 0xFF51AFD7ED558CCDull;
    h ^= h >> 33;
    h *= 0xC4CEB9FE1A85EC53ull;
    return h ^ (h >> 33);
  };
  return {finish(h1), finish(h2) | 1u};  // (never {0, 0}, the empty slot)
}

Optimizer::FailedRegionSet& Optimizer::failed_region_set(const RegionFingerprint& f) {
  if (failed_regions_.empty()) {
    // This table is most of what a search adds to the mesh it searches, and so it bounds opt's
    // memory (multistart.cpp counts the rest): two sets of four fingerprints, 128 bytes, per
    // triangle slot. Each triangle starts one region and its edges one and a half more on average
    // (try_insertions), and the kicks' and perturbations' trials add failures of their own; at
    // eight fingerprints per triangle the local search skips as many retries as it did with 32
    // direct-mapped ones rounded up to a power of two (0.5 to 1 KB per triangle, 32 MiB of the
    // 46 MiB opt took on 40,000 uniform points), and a quarter fewer with four.
    failed_regions_.resize(std::max<std::size_t>(2 * m_.triangles.size(), 1024));
  }
  return failed_regions_[f[0] % failed_regions_.size()];  // (any size: no power of two, no rounding up)
}

}  // namespace mwst::opt
