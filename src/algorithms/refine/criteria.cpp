// src/algorithms/refine/criteria.cpp — the engine's criteria (refiner.hpp): is a triangle bad, which
// subsegments are encroached, which may be split, and the Miller–Pav–Walkington exemption.
#include "algorithms/refine/refiner.hpp"

namespace mwst::refinement {

// ---- the quality criterion begins here -----------------------------------------------------------

// The default criterion (Triangle's): the smallest angle, from the shortest edge, against the bound;
// the area against RefineOptions::max_area and Mesh::area_bound; or the caller's test.
bool Refiner::evaluate(TriangleId t, Eval& ev) {
  const Triangle& T = m_.triangles[t];
  const Point& a = m_.points[T.v[0]];
  const Point& b = m_.points[T.v[1]];
  const Point& c = m_.points[T.v[2]];
  const double abx = b.x - a.x, aby = b.y - a.y;
  const double bcx = c.x - b.x, bcy = c.y - b.y;
  const double cax = a.x - c.x, cay = a.y - c.y;
  const double l2 = abx * abx + aby * aby;  // opposite corner 2
  const double l0 = bcx * bcx + bcy * bcy;  // opposite corner 0
  const double l1 = cax * cax + cay * cay;  // opposite corner 1
  // Shortest edge and the cosine² of the angle opposite it (the smallest angle), from the dot
  // product of the two longer edges at that corner, as Triangle does.
  unsigned k;
  double shortest, dot, la, lb;
  if (l0 <= l1 && l0 <= l2) {
    k = 0;
    shortest = l0;
    dot = -(abx * cax + aby * cay);  // (b−a)·(c−a)
    la = l2;
    lb = l1;
  } else if (l1 <= l2) {
    k = 1;
    shortest = l1;
    dot = -(abx * bcx + aby * bcy);  // (a−b)·(c−b)
    la = l2;
    lb = l0;
  } else {
    k = 2;
    shortest = l2;
    dot = -(bcx * cax + bcy * cay);  // (b−c)·(a−c)
    la = l0;
    lb = l1;
  }
  const double cos2 = dot > 0.0 ? dot * dot / (la * lb) : 0.0;
  ev.apex = k;
  ev.shortest2 = shortest;
  ev.angle_bad = alpha_ > 0.0 && cos2 > good_cos2_;
  ev.size_bad = false;
  if (max_area_ > 0.0 || own_bounds_) {
    const double area = triangle_area(a, b, c);
    ev.size_bad = max_area_ > 0.0 && area > max_area_;
    if (own_bounds_) {
      const double bound = m_.area_bound[t];
      ev.size_bad = ev.size_bad || (bound > 0.0 && area > bound);
    }
  }
  if (custom_test_) {
    // The area bound holds with a custom test too (bundle removal's --max-area); the test is
    // called first, whatever the area, as its caller may record what it is asked.
    ev.bad = opt_.is_bad(m_, t) || ev.size_bad;
  } else {
    ev.bad = ev.angle_bad || ev.size_bad;
  }
  ev.key = worst_first_ ? std::max(0.0, 1.0 - cos2) : shortest;
  return ev.bad;
}

// ---- encroachment begins here ----------------------------------------------------------------------

// Is x in the diametral lens (or circle) of the subsegment ab? (See the Encroachment option.)
bool Refiner::encroaches(const Point& x, const Point& a, const Point& b) const {
  if (!lens_) return in_diametral_circle(a, b, x) > 0;
  // Lens (a quality heuristic, decided in floating point as Triangle does; the circle test above
  // is exact): the angle axb is at least 180° − 2α.
  const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
  const double dot = ax * bx + ay * by;
  if (dot >= 0.0) return false;
  return dot * dot >= lens_cos2_ * (ax * ax + ay * ay) * (bx * bx + by * by);
}

// Queues subsegment h if the apex of an in-domain triangle beside it encroaches it.
void Refiner::check_subsegment(Handle h) {
  if (!may_split(h)) return;
  if (conforming_ && !m_.is_ghost(h >> 2) && !m_.is_ghost(m_.sym(h) >> 2) && m_.is_locally_non_delaunay(h)) {
    push_pending(h);
    return;
  }
  const VertexId a = m_.org(h), b = m_.dest(h);
  const Point& pa = m_.points[a];
  const Point& pb = m_.points[b];
  const Handle s = m_.sym(h);
  if (m_.in_domain(h >> 2) && encroaches(m_.points[m_.apex(h)], pa, pb)) {
    push_pending(h);
    return;
  }
  if (m_.in_domain(s >> 2) && encroaches(m_.points[m_.apex(s)], pa, pb)) push_pending(h);
}

// May refinement split subsegment h (RefineOptions::segment_splitting)? Triangle's -Y protects the
// subsegments on the boundary of the triangulation (a side not in the domain: a hole, the outside,
// the hull), -YY every subsegment.
bool Refiner::may_split(Handle h) const {
  switch (opt_.segment_splitting) {
    case SegmentSplitting::kAllowed: return true;
    case SegmentSplitting::kNever: return false;
    case SegmentSplitting::kNotBoundary: return m_.in_domain(h >> 2) && m_.in_domain(m_.sym(h) >> 2);
  }
  return true;
}

// The Miller–Pav–Walkington rule (in Triangle's form): a skinny triangle is left alone if the two
// ends of its shortest edge are split points on two different input segments that share an
// endpoint, at equal distances (within 0.1%) from it — the triangle subtends a small input angle
// and no Steiner point can improve it. Unlike Triangle we require the input angle to be below 60°.
bool Refiner::mpw_leaves(TriangleId t, const Eval& ev) const {
  if (segment_of_.empty()) return false;
  const Triangle& T = m_.triangles[t];
  const VertexId p = T.v[next3(ev.apex)], q = T.v[prev3(ev.apex)];
  const auto sp = original_segment(p);
  if (sp.first == kNone) return false;
  const auto sq = original_segment(q);
  if (sq.first == kNone || sp == sq) return false;
  VertexId join = kNone;
  if (sp.first == sq.first || sp.first == sq.second) join = sp.first;
  if (sp.second == sq.first || sp.second == sq.second) join = sp.second;
  if (join == kNone) return false;
  const Point& pj = m_.points[join];
  const double d1 = squared_distance(m_.points[p], pj);
  const double d2 = squared_distance(m_.points[q], pj);
  if (!(d1 < 1.001 * d2 && d1 > 0.999 * d2)) return false;
  // Only small input angles (below 60°) are exempt; at a wide angle the triangle can be fixed.
  const double dot = (m_.points[p].x - pj.x) * (m_.points[q].x - pj.x) +
                     (m_.points[p].y - pj.y) * (m_.points[q].y - pj.y);
  return dot > 0.0 && dot * dot > 0.25 * d1 * d2;
}

}  // namespace mwst::refinement
