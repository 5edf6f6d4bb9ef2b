// The bundle removal heuristic (BRH), Boyacı, Erten and Üngör, "Triangulations Loosing Bundles and
// Weight": Delaunay refinement relaxed so that a skinny triangle may stay as long as it is in no
// k-bundle. Their lemma: a mesh with minimum angle α is (4π/α + 3)-bundle-free; so with
// K ≥ ⌈4π/A⌉ + 3 every K-bundle must contain a triangle with an angle below A (otherwise the
// triangles of the bundle alone would violate the lemma's count), and splitting only the skinny
// triangles of K-bundles leaves a K-bundle-free mesh with fewer Steiner points — and less weight —
// than DR at the same A.
//
// Which triangles are in a K-bundle changes with every insertion, so we work in rounds. Each round
// marks skinny triangles certainly in a K-bundle by the circumdisk count (cheap, a lower bound:
// circumdisks of Delaunay triangles of all vertices are vertex-empty) and refines exactly those
// with the DR engine (its pluggable bad-triangle test). When the cheap test marks nothing, the exact
// pencil sweep (bundle.cpp) decides; BRH stops when it too marks nothing.
#include "mwst/brh.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <unordered_set>
#include <vector>

#include "mwst/bundle.hpp"
#include "mwst/metrics.hpp"

namespace mwst {

namespace {

struct TripleHash {
  std::size_t operator()(const std::array<VertexId, 3>& t) const {
    std::uint64_t h = t[0];
    h = h * 0x9E3779B97F4A7C15ull ^ t[1];
    h = h * 0x9E3779B97F4A7C15ull ^ t[2];
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

std::array<VertexId, 3> sorted_triple(const Mesh& m, TriangleId t) {
  std::array<VertexId, 3> v = m.triangles[t].v;
  std::sort(v.begin(), v.end());
  return v;
}

bool is_skinny(const Mesh& m, TriangleId t, double min_angle_deg) {
  double angles[3];
  triangle_angles_deg(m, t, angles);
  return std::min({angles[0], angles[1], angles[2]}) < min_angle_deg;
}

}  // namespace

BrhStats bundle_removal(Mesh& mesh, const BrhOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BrhStats stats;
  const double A = options.min_angle_deg;
  const std::uint32_t K = static_cast<std::uint32_t>(options.bundle_k);
  std::unordered_set<std::array<VertexId, 3>, TripleHash> marked;
  RefineOptions ro = options.refine;
  ro.min_angle_deg = A;
  ro.is_bad = [&](const Mesh& m, TriangleId t) {
    return marked.count(sorted_triple(m, t)) != 0 && is_skinny(m, t, A);
  };
  std::size_t steiner_budget = options.refine.max_steiner;
  stats.stop_reason = "bound reached";
  for (stats.rounds = 0; stats.rounds < options.max_rounds;) {
    if (options.refine.time_budget_seconds > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
            options.refine.time_budget_seconds) {
      stats.stop_reason = "time budget";
      break;
    }
    // Skinny triangles of the domain.
    std::vector<TriangleId> skinny;
    for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.in_domain(t) && is_skinny(mesh, t, A)) skinny.push_back(t);
    }
    if (skinny.empty()) break;
    marked.clear();
    const std::vector<std::uint32_t> cheap = circumdisk_bundle_per_triangle(mesh);
    for (const TriangleId t : skinny) {
      if (t < cheap.size() && cheap[t] >= K) marked.insert(sorted_triple(mesh, t));
    }
    if (marked.empty()) {
      BundleOptions bo;
      bo.per_triangle = true;
      const BundleResult exact = bundle_number(mesh, bo);
      ++stats.exact_evaluations;
      for (const TriangleId t : skinny) {
        if (t < exact.per_triangle.size() && exact.per_triangle[t] >= K) marked.insert(sorted_triple(mesh, t));
      }
    }
    if (marked.empty()) break;  // no skinny triangle is in a K-bundle
    ++stats.rounds;
    ro.max_steiner = steiner_budget;
    const RefineStats rs = refine(mesh, ro);
    const std::size_t added = rs.steiner_inserted + rs.segment_splits;
    stats.steiner_inserted += rs.steiner_inserted;
    stats.segment_splits += rs.segment_splits;
    stats.left_small_angle = rs.left_small_angle;
    if (rs.stop_reason == "steiner budget" || rs.stop_reason == "time budget") {
      stats.stop_reason = rs.stop_reason;
      break;
    }
    if (steiner_budget != static_cast<std::size_t>(-1)) steiner_budget -= std::min(steiner_budget, added);
    if (added == 0) {
      // Nothing could be split (the marked triangles sit at small input angles): stop honestly.
      stats.stop_reason = std::to_string(rs.left_small_angle) + " triangles left near small input angles";
      break;
    }
  }
  if (stats.rounds >= options.max_rounds) stats.stop_reason = "round limit";
  for (TriangleId t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.in_domain(t) && is_skinny(mesh, t, A)) ++stats.skinny_left;
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace mwst
