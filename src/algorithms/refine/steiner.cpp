// src/algorithms/refine/steiner.cpp — Steiner points of bad triangles (refiner.hpp): the circumcenter
// or Üngör's off-center, located by a walk and inserted (insert_for, insertion.cpp) or handed over
// to the subsegment it lies on or beyond.
#include "algorithms/refine/refiner.hpp"

namespace mwst::refinement {

// The Steiner point of bad triangle t: the caller's rule, or the circumcenter, or (angle-bad under
// kOffCenter) the off-center on the bisector of the shortest edge when it is nearer than the
// circumcenter.
Point Refiner::steiner_point(TriangleId t, const Eval& ev) const {
  if (opt_.steiner_point) return opt_.steiner_point(m_, t);
  const Triangle& T = m_.triangles[t];
  // p → q is the shortest edge, r the apex of the smallest angle; (p, q, r) counter-clockwise.
  const Point& p = m_.points[T.v[next3(ev.apex)]];
  const Point& q = m_.points[T.v[prev3(ev.apex)]];
  const Point& r = m_.points[T.v[ev.apex]];
  // Circumcenter relative to p. The denominator 2·orient2d is taken in floating point when the
  // filter certifies its sign and magnitude, else from the exact construction.
  const double qx = q.x - p.x, qy = q.y - p.y, rx = r.x - p.x, ry = r.y - p.y;
  const double left = qx * ry, right = qy * rx;
  const double det = left - right;
  Point center;
  if (std::fabs(det) > 1e-12 * (std::fabs(left) + std::fabs(right))) {
    const double q2 = qx * qx + qy * qy, r2 = rx * rx + ry * ry;
    const double inv = 0.5 / det;
    center = {p.x + (ry * q2 - qy * r2) * inv, p.y + (qx * r2 - rx * q2) * inv};
  } else {
    center = circumcenter(p, q, r);
  }
  if (opt_.rule == SteinerRule::kCircumcenter || offcenter_scale_ <= 0.0 || !ev.angle_bad) {
    return {snap_to_range(center.x), snap_to_range(center.y)};
  }
  // Off-center (Üngör): on the bisector of pq, on r's side, at distance
  // factor·(|pq|/2)·cot(α/2) from the midpoint m — unless the circumcenter is closer.
  const double mx = p.x + 0.5 * qx, my = p.y + 0.5 * qy;
  const double len = std::sqrt(qx * qx + qy * qy);
  const double d = offcenter_scale_ * len;
  const double cmx = center.x - mx, cmy = center.y - my;
  if (cmx * cmx + cmy * cmy <= d * d || len == 0.0) {
    return {snap_to_range(center.x), snap_to_range(center.y)};
  }
  // Left normal of p→q points to r's side.
  const double s = d / len;
  return {snap_to_range(mx - qy * s), snap_to_range(my + qx * s)};
}

// Splits bad triangle t at its Steiner point, or splits the subsegment that point lies on or beyond.
void Refiner::split_triangle(TriangleId t, const Eval& ev) {
  const Point p = steiner_point(t, ev);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !in_supported_range(p)) {
    ++stats_.precision_skips;
    return;
  }
  const WalkResult w = walk(p, t);
  switch (w.kind) {
    case WalkKind::kOnVertex:
      // The rounded point coincides with a vertex: nothing can be inserted at double precision.
      ++stats_.precision_skips;
      return;
    case WalkKind::kBlocked:
    case WalkKind::kOnEdge:
      if (w.kind == WalkKind::kBlocked || m_.is_segment(w.handle)) {
        if (!may_split(w.handle)) {
          // Beyond or on a subsegment that may not be split.
          split_at_centroid(t, ev);
          return;
        }
        // Beyond a subsegment or on one: that subsegment is encroached (Ruppert's lemma: a
        // circumcenter hidden behind a subsegment implies the triangle's vertices encroach it).
        ++stats_.rejected;
        push_pending(w.handle);
        if (split_all_pending()) {
          queue_.push(ev.key, t, m_.triangles[t].v[0]);
        } else {
          ++stats_.precision_skips;
        }
        return;
      }
      [[fallthrough]];
    case WalkKind::kInTriangle: {
      insert_for(t, ev, p, w.handle >> 2, true);
      return;
    }
  }
}

// The Steiner point of t lies on or beyond a subsegment that may not be split (segment_splitting).
// A triangle too large for its area bound gets its centroid instead, which lies inside it, so the
// area bounds are always met; a triangle bad by its angle alone is left as it is (Triangle's -Y
// warns of the same: the quality may suffer) and counted.
void Refiner::split_at_centroid(TriangleId t, const Eval& ev) {
  if (!ev.size_bad) {
    ++protected_skips_;
    return;
  }
  const Triangle& T = m_.triangles[t];
  const Point& a = m_.points[T.v[0]];
  const Point& b = m_.points[T.v[1]];
  const Point& c = m_.points[T.v[2]];
  const Point p{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
  const WalkResult w = walk(p, t);
  if (w.kind == WalkKind::kOnVertex || w.kind == WalkKind::kBlocked ||
      (w.kind == WalkKind::kOnEdge && m_.is_segment(w.handle))) {
    ++protected_skips_;  // (a sliver whose rounded centroid is not inside it)
    return;
  }
  insert_for(t, ev, p, w.handle >> 2, false);
}

}  // namespace mwst::refinement
