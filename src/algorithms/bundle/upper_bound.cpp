// src/algorithms/bundle/upper_bound.cpp — bundle_number's upper bound when a candidate budget cut
// lists short (upper_bound.hpp).
#include "algorithms/bundle/upper_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "mwst/geometry/geometry.hpp"
#include "support/huge_pages.hpp"
#include "support/parallel.hpp"

namespace mwst::bundle {

namespace {

// Fenwick tree of counts over positions 0 .. n−1, in `tree` (n + 1 entries, zero to start).
struct Fenwick {
  std::vector<std::uint32_t>& tree;
  void add(std::size_t i) {
    for (++i; i < tree.size(); i += i & (~i + 1)) ++tree[i];
  }
  // The count at positions below i.
  std::uint32_t below(std::size_t i) const {
    std::uint32_t s = 0;
    for (; i > 0; i -= i & (~i + 1)) s += tree[i];
    return s;
  }
};

// Number of values of the ascending `v` below x / above x.
std::size_t count_below(const std::vector<float>& v, float x) {
  return static_cast<std::size_t>(std::lower_bound(v.begin(), v.end(), x) - v.begin());
}
std::size_t count_above(const std::vector<float>& v, float x) {
  return static_cast<std::size_t>(v.end() - std::upper_bound(v.begin(), v.end(), x));
}


float round_down(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

// With u = b − a, v = c − a, the centre is a + o, o = (v_y|u|² − u_y|v|², u_x|v|² − v_x|u|²) / d,
// d = 2 (u_x v_y − u_y v_x). Each term of a numerator is a product of three rounded differences
// rounded twice and summed once: relative error below 8ε (with ε = 2⁻⁵³), so the numerators are off
// by at most e_n = 8ε·(sum of the terms' magnitudes), d by e_d = 8ε·2(|u_x v_y| + |u_y v_x|). Then
// |ô − o| ≤ (e_n + |ô|·e_d) / (|d̂| − e_d), plus the division's and the final sum's rounding. The
// disk lies in the disk of centre ĉ and radius |ô| + 2δ (δ bounding |ĉ − c| in each coordinate,
// added over both), whose box is returned, widened by a few ulps for its own rounding. The factor 2
// on every bound is a margin.
bool circumdisk_box(const Point& a, const Point& b, const Point& c, std::array<double, 4>& out) {
  constexpr double eps = std::numeric_limits<double>::epsilon() / 2.0;
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - a.x, vy = c.y - a.y;
  const double u2 = ux * ux + uy * uy, v2 = vx * vx + vy * vy;
  const double d = 2.0 * (ux * vy - uy * vx);
  const double e_d = 2.0 * 8.0 * eps * 2.0 * (std::fabs(ux * vy) + std::fabs(uy * vx));
  if (!(std::fabs(d) > 4.0 * e_d) || !std::isfinite(d)) return false;
  const double nx = vy * u2 - uy * v2, ny = ux * v2 - vx * u2;
  const double e_nx = 2.0 * 8.0 * eps * (std::fabs(vy) * u2 + std::fabs(uy) * v2);
  const double e_ny = 2.0 * 8.0 * eps * (std::fabs(ux) * v2 + std::fabs(vx) * u2);
  const double ox = nx / d, oy = ny / d;
  const double cx = a.x + ox, cy = a.y + oy;
  const double slack = std::fabs(d) - e_d;
  const double dx = 2.0 * ((e_nx + std::fabs(ox) * e_d) / slack + 4.0 * eps * (std::fabs(ox) + std::fabs(cx)));
  const double dy = 2.0 * ((e_ny + std::fabs(oy) * e_d) / slack + 4.0 * eps * (std::fabs(oy) + std::fabs(cy)));
  const double radius = std::sqrt(ox * ox + oy * oy) * (1.0 + 8.0 * eps) + 2.0 * (dx + dy);
  const double wx = (radius + dx) * (1.0 + 8.0 * eps), wy = (radius + dy) * (1.0 + 8.0 * eps);
  out = {cx - wx - 4.0 * eps * std::fabs(cx), cy - wy - 4.0 * eps * std::fabs(cy),
         cx + wx + 4.0 * eps * std::fabs(cx), cy + wy + 4.0 * eps * std::fabs(cy)};
  return std::isfinite(out[0]) && std::isfinite(out[1]) && std::isfinite(out[2]) && std::isfinite(out[3]);
}

Box outward_box(double x0, double y0, double x1, double y1) {
  return {round_down(x0), round_down(y0), round_up(x1), round_up(y1)};
}

// ---- BoxCounter begins here -----------------------------------------------------------------------

BoxCounter::BoxCounter(const std::vector<Box>& boxes, unsigned threads) : n_(boxes.size()) {
  threads = std::min(threads, 2u);
  // Fresh arrays, each written whole: on huge pages (support/huge_pages.hpp; values unchanged).
  std::vector<std::uint32_t> rank_top, rank_bottom;
  support::resize_on_huge_pages(rank_top, n_);
  support::resize_on_huge_pages(rank_bottom, n_);
  support::resize_on_huge_pages(ys_top_, n_);
  support::resize_on_huge_pages(ys_bottom_, n_);
  support::parallel_for(2, threads, [&](std::size_t side) {  // ranks of y1 (top) and of y0 (bottom)
    std::vector<std::pair<float, std::uint32_t>> order;
    support::resize_on_huge_pages(order, n_);
    for (std::uint32_t i = 0; i < n_; ++i) order[i] = {boxes[i][side == 0 ? 3 : 1], i};
    std::sort(order.begin(), order.end());
    for (std::uint32_t r = 0; r < n_; ++r) {
      (side == 0 ? ys_top_ : ys_bottom_)[r] = order[r].first;
      (side == 0 ? rank_top : rank_bottom)[order[r].second] = r;
    }
  });
  support::resize_on_huge_pages(by_right_, n_);
  support::resize_on_huge_pages(by_left_, n_);
  support::parallel_for(2, threads, [&](std::size_t side) {  // by x1 ascending, by x0 descending
    std::vector<Keyed>& keyed = side == 0 ? by_right_ : by_left_;
    for (std::uint32_t i = 0; i < n_; ++i) keyed[i] = {boxes[i][side == 0 ? 2 : 0], rank_top[i], rank_bottom[i]};
    if (side == 0) {
      std::sort(keyed.begin(), keyed.end(), [](const Keyed& p, const Keyed& q) { return p.x < q.x; });
    } else {
      std::sort(keyed.begin(), keyed.end(), [](const Keyed& p, const Keyed& q) { return p.x > q.x; });
    }
  });
}

std::vector<std::uint32_t> BoxCounter::count(const std::vector<Box>& queries, unsigned threads) const {
  const std::size_t q = queries.size();
  std::vector<std::int64_t> met;  // (fresh arrays here too: on huge pages)
  support::resize_on_huge_pages(met, q);
  // Per query: how many boxes lie wholly below it (y1 < query y0) and how many do not lie wholly
  // above it (y0 ≤ query y1): positions in ys_top_ / ys_bottom_, found once.
  std::vector<std::array<std::uint32_t, 2>> y_rank;
  support::resize_on_huge_pages(y_rank, q);
  support::parallel_ranges(threads, q, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Box& b = queries[i];
      y_rank[i] = {static_cast<std::uint32_t>(count_below(ys_top_, b[1])),
                   static_cast<std::uint32_t>(n_ - count_above(ys_bottom_, b[3]))};
      // − D − U.
      met[i] = static_cast<std::int64_t>(n_) - y_rank[i][0] - static_cast<std::int64_t>(n_ - y_rank[i][1]);
    }
  });
  // One sweep per side: left (x1 < query x0, ascending) and right (x0 > query x1, descending),
  // independent of each other (each its own trees and terms, added up after).
  std::array<std::vector<std::int64_t>, 2> side_met;
  support::parallel_for(2, std::min(threads, 2u), [&](std::size_t side) {
    std::vector<std::int64_t>& terms = side_met[side];
    support::resize_on_huge_pages(terms, q);
    std::vector<std::uint32_t> order;
    support::resize_on_huge_pages(order, q);
    const std::vector<Keyed>& keyed = side == 0 ? by_right_ : by_left_;
    for (std::uint32_t i = 0; i < q; ++i) order[i] = i;
    if (side == 0) {
      std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return queries[x][0] < queries[y][0]; });
    } else {
      std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return queries[x][2] > queries[y][2]; });
    }
    // (Reused from call to call: fresh arrays of this size would be fresh mappings, faulted in.)
    support::reserve_on_huge_pages(fenwick_top_[side], n_ + 1);
    support::reserve_on_huge_pages(fenwick_bottom_[side], n_ + 1);
    fenwick_top_[side].assign(n_ + 1, 0);
    fenwick_bottom_[side].assign(n_ + 1, 0);
    Fenwick tops{fenwick_top_[side]}, bottoms{fenwick_bottom_[side]};
    std::size_t inserted = 0;
    for (const std::uint32_t i : order) {
      const Box& b = queries[i];
      while (inserted < n_ && (side == 0 ? keyed[inserted].x < b[0] : keyed[inserted].x > b[2])) {
        tops.add(keyed[inserted].y_top);
        bottoms.add(keyed[inserted].y_bottom);
        ++inserted;
      }
      // − L (or R), + LD (RD): also wholly below, + LU (RU): also wholly above.
      const std::uint32_t below = tops.below(y_rank[i][0]);
      const std::uint32_t above = static_cast<std::uint32_t>(inserted) - bottoms.below(y_rank[i][1]);
      terms[i] = -static_cast<std::int64_t>(inserted) + below + above;
    }
  });
  std::vector<std::uint32_t> out;
  support::resize_on_huge_pages(out, q);
  for (std::size_t i = 0; i < q; ++i) {
    const std::int64_t all = met[i] + side_met[0][i] + side_met[1][i];
    out[i] = static_cast<std::uint32_t>(std::clamp<std::int64_t>(all, 0, static_cast<std::int64_t>(n_)));
  }
  return out;
}

// ---- bound_cut_pencils begins here ----------------------------------------------------------------

namespace {

// The pencils not swept because a list of theirs was cut (and not cocircular: those hold only a
// circumdisk, the end of another pencil), in order; the pencils are tested on `threads` threads.
std::vector<std::uint32_t> cut_pencils(const Shared& sh, unsigned threads) {
  std::vector<std::uint8_t> is_cut(sh.pencils.size(), 0);
  support::parallel_ranges(threads, sh.pencils.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Handle h = sh.pencils[i], hs = sh.dt.sym(h);
      const bool ghost = sh.dt.is_ghost(triangle_of(hs));
      if (!sh.list_cut(triangle_of(h)) && (ghost || !sh.list_cut(triangle_of(hs)))) continue;
      if (!ghost && sh.cocircular_edge(h)) continue;
      is_cut[i] = 1;
    }
  });
  std::vector<std::uint32_t> cut;
  for (std::uint32_t i = 0; i < is_cut.size(); ++i) {
    if (is_cut[i]) cut.push_back(i);
  }
  return cut;
}

// Per cut pencil, the number of in-domain triangles whose bounding boxes meet a box holding its
// circumdisks (a hull edge's pencil: the one; its other disks meet the triangles only inside it).
std::vector<std::uint32_t> box_bounds(const Shared& sh, const std::vector<std::uint32_t>& cut, std::uint32_t domain,
                                      unsigned threads) {
  // The in-domain triangles' boxes, per range of slots on `threads` threads (the counts do not
  // depend on the boxes' order).
  std::vector<std::vector<Box>> part_boxes(std::max(threads, 1u));
  support::parallel_ranges(part_boxes.size(), sh.slots.size(), [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::vector<Box>& mine = part_boxes[k];
    for (std::size_t t = begin; t < end; ++t) {
      if (!sh.in_domain(static_cast<TriangleId>(t))) continue;
      double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
      for (const VertexId v : sh.slots[t].v) {
        const Point& p = sh.pts[v];
        x0 = std::min(x0, p.x);
        y0 = std::min(y0, p.y);
        x1 = std::max(x1, p.x);
        y1 = std::max(y1, p.y);
      }
      mine.push_back(outward_box(x0, y0, x1, y1));
    }
  });
  std::vector<Box> triangle_boxes;
  triangle_boxes.reserve(domain);
  for (auto& part : part_boxes) {
    triangle_boxes.insert(triangle_boxes.end(), part.begin(), part.end());
    release(part);
  }
  const BoxCounter counter(triangle_boxes, threads);
  release(triangle_boxes);
  // Queries per pass (about 36 bytes each): each pass inserts every triangle into the Fenwick
  // trees, so fewer passes cost less time and more memory.
  constexpr std::size_t kChunk = std::size_t{1} << 19;
  std::vector<std::uint32_t> bound(cut.size(), domain);
  std::vector<Box> queries;
  std::vector<std::uint32_t> which;
  std::vector<std::uint8_t> placed;
  for (std::size_t begin = 0; begin < cut.size(); begin += kChunk) {
    const std::size_t end = std::min(cut.size(), begin + kChunk);
    // The query boxes on `threads` threads, then those placed (in order) kept.
    queries.resize(end - begin);
    placed.assign(end - begin, 1);
    support::parallel_ranges(threads, end - begin, [&](std::size_t, std::size_t from, std::size_t to) {
      for (std::size_t i = from; i < to; ++i) {
        const Handle h = sh.pencils[cut[begin + i]], hs = sh.dt.sym(h);
        std::array<double, 4> box{kInf, kInf, -kInf, -kInf};
        for (const TriangleId d : {triangle_of(h), triangle_of(hs)}) {
          if (sh.dt.is_ghost(d)) continue;
          const auto& v = sh.dt.triangles[d].v;
          std::array<double, 4> one;
          if (!circumdisk_box(sh.pts[v[0]], sh.pts[v[1]], sh.pts[v[2]], one)) {
            placed[i] = 0;  // every triangle
            break;
          }
          box = {std::min(box[0], one[0]), std::min(box[1], one[1]), std::max(box[2], one[2]), std::max(box[3], one[3])};
        }
        if (placed[i]) queries[i] = outward_box(box[0], box[1], box[2], box[3]);
      }
    });
    which.clear();
    std::size_t kept = 0;
    for (std::size_t i = 0; i < end - begin; ++i) {
      if (!placed[i]) continue;
      queries[kept++] = queries[i];
      which.push_back(static_cast<std::uint32_t>(begin + i));
    }
    queries.resize(kept);
    const std::vector<std::uint32_t> counts = counter.count(queries, threads);
    for (std::size_t i = 0; i < which.size(); ++i) bound[which[i]] = counts[i];
  }
  return bound;
}

}  // namespace

void bound_cut_pencils(Shared& sh, Worker& worker, std::size_t work_budget, unsigned threads, BundleResult& result) {
  std::uint32_t domain = 0;
  for (TriangleId t = 0; t < sh.slots.size(); ++t) domain += sh.in_domain(t) ? 1 : 0;
  result.upper_bound = std::max(domain, result.lower_bound);
  if (result.lower_bound >= domain) return;
  worker.release_flood_scratch();  // bound_cut_lists's counts: allocated again by the sweeps below
  worker.release_disk_scratch();
  const std::vector<std::uint32_t> cut = cut_pencils(sh, threads);
  const std::vector<std::uint32_t> bound = box_bounds(sh, cut, domain, threads);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> order;  // (bound, pencil), largest first
  for (std::size_t k = 0; k < cut.size(); ++k) {
    if (bound[k] > result.lower_bound) order.emplace_back(bound[k], cut[k]);
  }
  std::sort(order.begin(), order.end(), [](const auto& x, const auto& y) {
    return x.first > y.first || (x.first == y.first && x.second < y.second);
  });
  // Sweep the pencils of the largest bounds exactly, from full floods: their true counts replace
  // their bounds. The first pencil not swept bounds the rest.
  // A sweep holds about 250 bytes per candidate: a pencil whose floods exceed a sixteenth of the
  // triangles is not swept (its bound stays, and bounds the rest).
  const std::size_t largest_flood = std::max<std::size_t>(std::size_t{1} << 12, domain / 16);
  worker.best_count = result.lower_bound;
  std::vector<TriangleId> left, right;
  auto flood_within = [&](TriangleId d, std::vector<TriangleId>& out) {
    out.clear();
    if (sh.dt.is_ghost(d)) return true;
    bool fits = true;
    worker.flood_each(d, [&](TriangleId t) {
      fits = out.size() < largest_flood;
      if (fits) out.push_back(t);
      return fits;
    });
    return fits;
  };
  std::size_t work = 0, next = 0;
  for (; next < order.size() && order[next].first > result.lower_bound; ++next) {
    const Handle h = sh.pencils[order[next].second], hs = sh.dt.sym(h);
    if (work >= work_budget) break;
    sh.check_deadline();
    const bool fits = flood_within(triangle_of(h), left) && flood_within(triangle_of(hs), right);
    work += left.size() + right.size();
    if (!fits) break;
    worker.sweep_with_lists(order[next].second, left, right);
    if (worker.best_count > result.lower_bound) {
      result.lower_bound = result.bundle_number = worker.best_count;
      result.disk_center = worker.best_center;
      result.disk_radius = worker.best_radius;
      result.triangles = worker.best_triangles;
    }
  }
  std::uint32_t upper = result.lower_bound;
  if (next < order.size()) upper = std::max(upper, order[next].first);
  result.upper_bound = upper;
}

}  // namespace mwst::bundle
