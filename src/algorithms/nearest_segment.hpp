// src/algorithms/nearest_segment.hpp — the input segment nearest a point, exactly as a scan of all
// segments in input order picks it (least rounded squared distance, the first in input order among
// equal ones), in about logarithmic time: a bounding-volume tree over pieces of the segments,
// searched branch and bound with a lower bound that no rounding can undercut. Internal (not
// installed); used for the attributes of crossings of input segments (arrays.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::detail {

// The rounded squared distance from p to the point of segment ab nearest it, computed as the scan
// always computed it: the parameter t of the foot of p, clamped to [0, 1], then the distance to
// a + t (b − a). Both the scan and the tree call this one function, so they compare the same
// doubles.
inline double squared_distance_to_segment(const Point& a, const Point& b, const Point& p) {
  const double dx = b.x - a.x, dy = b.y - a.y, length2 = dx * dx + dy * dy;
  const double t = length2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0) : 0.0;
  return squared_distance(p, Point{a.x + t * dx, a.y + t * dy});
}

class NearestSegment {
 public:
  static constexpr std::size_t kNoSegment = std::numeric_limits<std::size_t>::max();

  // Indexes `segments` (into `points`), cut into pieces so that there are about `pieces` in all
  // (at least one per segment), each segment into pieces of equal length: a long segment crossed
  // by many others does not put one big box over all of its crossings.
  NearestSegment(const std::vector<Point>& points, const std::vector<Segment>& segments, std::size_t pieces);

  // The index of the segment with the least squared_distance_to_segment() from p, the first in
  // input order among equal ones; kNoSegment if there is no segment.
  std::size_t nearest(const Point& p) const;

 private:
  struct Box {
    double xmin, ymin, xmax, ymax;
  };
  struct Node {
    Box box;
    std::uint32_t begin, end;  // its pieces, [begin, end) of pieces_
    std::uint32_t left;        // the left child (the right one follows its subtree); 0: a leaf
    std::uint32_t right;
  };
  struct Piece {
    Box box;  // the piece's exact box grown by more than the rounding of any point computed on it
    std::uint32_t segment;
  };

  std::uint32_t build(std::uint32_t begin, std::uint32_t end);
  static double lower_bound(const Box& box, const Point& p);

  const std::vector<Point>& points_;
  const std::vector<Segment>& segments_;
  std::vector<Piece> pieces_;
  std::vector<Node> nodes_;
};

}  // namespace mwst::detail
