// src/algorithms/refine/steiner.cpp — Steiner points of bad triangles (refiner.hpp): the circumcenter
// or Üngör's off-center, located by a walk and inserted (insert_for, insertion.cpp) or handed over
// to the subsegment it lies on or beyond.
#include "algorithms/refine/refiner.hpp"

namespace mwst::refinement {

// The circumcenter of t (not yet snapped into the supported range). The denominator 2·orient2d is taken in
// floating point when the filter certifies its sign and magnitude, else from the exact
// construction.
Point Refiner::circumcenter_of(TriangleId t, const Eval& ev) const {
  const Triangle& T = m_.triangles[t];
  // p → q is the shortest edge, r the apex of the smallest angle; (p, q, r) counter-clockwise.
  const Point& p = m_.points[T.v[next3(ev.apex)]];
  const Point& q = m_.points[T.v[prev3(ev.apex)]];
  const Point& r = m_.points[T.v[ev.apex]];
  // Relative to p.
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
  return center;
}

// The Steiner point of bad triangle t: the caller's rule, or the circumcenter, or (angle-bad under
// kOffCenter) the off-center on the bisector of the shortest edge when it is nearer than the
// circumcenter; `offcenter` says whether it is an off-center.
Point Refiner::steiner_point(TriangleId t, const Eval& ev, bool& offcenter) const {
  offcenter = false;
  if (opt_.steiner_point) return opt_.steiner_point(m_, t);
  const Point center = circumcenter_of(t, ev);
  const Point snapped{snap_to_range(center.x), snap_to_range(center.y)};
  if (opt_.rule == SteinerRule::kCircumcenter || offcenter_scale_ <= 0.0 || !ev.angle_bad) return snapped;
  // Off-center (Üngör): on the bisector of pq, on r's side, at distance
  // factor·(|pq|/2)·cot(α/2) from the midpoint m — unless the circumcenter is closer.
  const Triangle& T = m_.triangles[t];
  const Point& p = m_.points[T.v[next3(ev.apex)]];
  const Point& q = m_.points[T.v[prev3(ev.apex)]];
  const double qx = q.x - p.x, qy = q.y - p.y;
  const double mx = p.x + 0.5 * qx, my = p.y + 0.5 * qy;
  const double len = std::sqrt(qx * qx + qy * qy);
  const double d = offcenter_scale_ * len;
  const double cmx = center.x - mx, cmy = center.y - my;
  if (cmx * cmx + cmy * cmy <= d * d || len == 0.0) return snapped;
  // Left normal of p→q points to r's side.
  const double s = d / len;
  offcenter = true;
  return {snap_to_range(mx - qy * s), snap_to_range(my + qx * s)};
}

// Splits bad triangle t at its Steiner point, or splits the subsegment that point lies on or beyond.
void Refiner::split_triangle(TriangleId t, const Eval& ev) {
  bool offcenter = false;
  const Point p = steiner_point(t, ev, offcenter);
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
        push_pending(w.handle);
        split_pending_for(t, ev);
        return;
      }
      [[fallthrough]];
    case WalkKind::kInTriangle: {
      const TriangleId t0 = w.handle >> 2;
      const InsertKind r = insert_for(t, ev, p, t0, offcenter ? kOffCenterCavityLimit : kNoCavityLimit);
      if (r == InsertKind::kProtected) split_at_centroid(t, ev);
      if (r == InsertKind::kTooLarge) {
        if (cavity_is_one_fan(t, ev)) {
          split_at_circumcenter(t, ev, p, t0);
        } else {
          insert_or_split_at_centroid(t, ev, p, t0);
        }
      }
      return;
    }
  }
}

// The cavity grown so far (cavity_, kOffCenterCavityLimit + 1 triangles) is one fan of nearly
// cocircular points: the circumcenters of its middle and last triangles lie within 1/1000 of t's
// circumradius of t's circumcenter.
bool Refiner::cavity_is_one_fan(TriangleId t, const Eval& ev) const {
  const Point c0 = circumcenter_of(t, ev);
  const Point& a = m_.points[m_.triangles[t].v[0]];
  const double r2 = squared_distance(c0, a);
  for (const TriangleId u : {cavity_[cavity_.size() / 2], cavity_.back()}) {
    Eval eu;
    eu.apex = 0;
    const Point cu = circumcenter_of(u, eu);
    if (!(squared_distance(cu, c0) <= 1e-6 * r2)) return false;
  }
  return true;
}

// The off-center p (lying in t0) of bad triangle t would have a cavity of more than
// kOffCenterCavityLimit triangles (insertion.cpp): t gets its circumcenter instead, Ruppert's
// own choice, so the angle bound and the termination argument are those of circumcenters (an
// off-center is only a point nearer to the shortest edge; Üngör 2004). Where that is not possible
// (the circumcenter coincides with a vertex, or lies on or beyond a subsegment that may not be
// split), the off-center is inserted after all.
void Refiner::split_at_circumcenter(TriangleId t, const Eval& ev, const Point& offcenter, TriangleId t0) {
  ++stats_.circumcenters_for_large_cavities;
  const Point center = circumcenter_of(t, ev);
  const Point c{snap_to_range(center.x), snap_to_range(center.y)};
  if (std::isfinite(c.x) && std::isfinite(c.y) && in_supported_range(c)) {
    const WalkResult w = walk(c, t);
    const bool behind = w.kind == WalkKind::kBlocked || (w.kind == WalkKind::kOnEdge && m_.is_segment(w.handle));
    if (behind && may_split(w.handle)) {
      // Ruppert's lemma, as in split_triangle: the subsegment is encroached; split it.
      push_pending(w.handle);
      split_pending_for(t, ev);
      return;
    }
    if (!behind && w.kind != WalkKind::kOnVertex &&
        insert_for(t, ev, c, w.handle >> 2, kNoCavityLimit) != InsertKind::kProtected) {
      return;
    }
  }
  insert_or_split_at_centroid(t, ev, offcenter, t0);
}

// Inserts p (in or beside t0) for t whatever its cavity; where p lies on or beyond a subsegment
// that may not be split (kProtected), t is split at its centroid instead (split_at_centroid).
void Refiner::insert_or_split_at_centroid(TriangleId t, const Eval& ev, const Point& p, TriangleId t0) {
  if (insert_for(t, ev, p, t0, kNoCavityLimit) == InsertKind::kProtected) split_at_centroid(t, ev);
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
  if (insert_for(t, ev, p, w.handle >> 2, kNoCavityLimit) == InsertKind::kProtected) ++protected_skips_;
}

// The subsegments pending were encroached by t's Steiner point (or hid it): they are split, and t
// is queued again (its Steiner point may have moved, or t may be gone).
void Refiner::split_pending_for(TriangleId t, const Eval& ev) {
  ++stats_.rejected;
  if (split_all_pending()) {
    queue_.push(ev.key, t, m_.triangles[t].v[0]);
  } else {
    ++stats_.precision_skips;
  }
}

}  // namespace mwst::refinement
