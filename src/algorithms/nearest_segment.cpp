// NearestSegment (algorithms/nearest_segment.hpp): branch and bound over a bounding-volume tree of
// segment pieces, returning exactly the segment a scan in input order returns.
//
// Why a pruned piece can hold no better segment. The scan's foot point q = a + t (b − a), t in
// [0, 1], is computed in doubles; it lies within about 5 units in the last place of M (the largest
// coordinate magnitude of a and b) of the exact segment ab, which the exact pieces cover. Each
// piece's box is grown by 2^-44 M, hundreds of such units, so q lies in the box of some piece of
// its segment. The squared distance to q, rounded, is at least the exact one times (1 − 3u), and
// the exact one is at least the squared distance from p to that box, whose rounded value is at most
// (1 + 3u) times the exact one (u = 2^-53; an underflow loses less than 2^-1000). So a box whose
// lower_bound() exceeds the best squared distance so far holds no segment with a smaller or equal
// one: the search skips only boxes strictly worse, and among equal distances it keeps the least
// segment index, the scan's first.
#include "algorithms/nearest_segment.hpp"

#include <cmath>

namespace mwst::detail {

namespace {
constexpr std::uint32_t kLeafPieces = 4;
constexpr int kPadExponent = -44;          // the pieces' boxes grow by 2^-44 of M
constexpr double kShrink = 1.0 - 0x1p-40;  // the rounding of the box distance, and more
constexpr double kUnderflow = 0x1p-1000;   // what an underflow can lose, and more
}  // namespace

NearestSegment::NearestSegment(const std::vector<Point>& points, const std::vector<Segment>& segments,
                               std::size_t pieces)
    : points_(points), segments_(segments) {
  double total_length = 0.0;
  for (const Segment& s : segments) total_length += distance(points[s.a], points[s.b]);
  const double piece_length = pieces > 0 ? total_length / static_cast<double>(pieces) : 0.0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Point& a = points[segments[i].a];
    const Point& b = points[segments[i].b];
    std::size_t count = 1;
    if (piece_length > 0.0) {
      const double wanted = std::ceil(distance(a, b) / piece_length);
      count = wanted >= static_cast<double>(pieces) ? std::max<std::size_t>(pieces, 1)
                                                    : std::max<std::size_t>(static_cast<std::size_t>(wanted), 1);
    }
    const double magnitude = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(b.x), std::fabs(b.y)});
    const double pad = std::ldexp(magnitude, kPadExponent);
    const double dx = b.x - a.x, dy = b.y - a.y;
    Point from = a;
    for (std::size_t k = 1; k <= count; ++k) {
      const double t = static_cast<double>(k) / static_cast<double>(count);
      const Point to = k == count ? b : Point{a.x + t * dx, a.y + t * dy};
      pieces_.push_back(Piece{Box{std::min(from.x, to.x) - pad, std::min(from.y, to.y) - pad,
                                  std::max(from.x, to.x) + pad, std::max(from.y, to.y) + pad},
                              static_cast<std::uint32_t>(i)});
      from = to;
    }
  }
  if (!pieces_.empty()) {
    nodes_.reserve(2 * (pieces_.size() / kLeafPieces + 1));
    build(0, static_cast<std::uint32_t>(pieces_.size()));
  }
}

// The node over pieces_[begin, end): their union box, split at the median of the pieces' centres
// along the longer side of the centres' box, so that clustered pieces still give a balanced tree.
std::uint32_t NearestSegment::build(std::uint32_t begin, std::uint32_t end) {
  const auto id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back(Node{pieces_[begin].box, begin, end, 0, 0});
  Box box = pieces_[begin].box;
  Box centres{box.xmin + box.xmax, box.ymin + box.ymax, box.xmin + box.xmax, box.ymin + box.ymax};
  for (std::uint32_t k = begin; k < end; ++k) {
    const Box& b = pieces_[k].box;
    box = Box{std::min(box.xmin, b.xmin), std::min(box.ymin, b.ymin), std::max(box.xmax, b.xmax),
              std::max(box.ymax, b.ymax)};
    const double cx = b.xmin + b.xmax, cy = b.ymin + b.ymax;  // twice the centre
    centres = Box{std::min(centres.xmin, cx), std::min(centres.ymin, cy), std::max(centres.xmax, cx),
                  std::max(centres.ymax, cy)};
  }
  nodes_[id].box = box;
  if (end - begin <= kLeafPieces) return id;
  const bool by_x = centres.xmax - centres.xmin >= centres.ymax - centres.ymin;
  const std::uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(pieces_.begin() + begin, pieces_.begin() + middle, pieces_.begin() + end,
                   [by_x](const Piece& p, const Piece& q) {
                     return by_x ? p.box.xmin + p.box.xmax < q.box.xmin + q.box.xmax
                                 : p.box.ymin + p.box.ymax < q.box.ymin + q.box.ymax;
                   });
  const std::uint32_t left = build(begin, middle);
  const std::uint32_t right = build(middle, end);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

// At most the rounded squared distance from p to any point computed on a piece in `box` (see the
// file's comment).
double NearestSegment::lower_bound(const Box& box, const Point& p) {
  const double gx = std::max({box.xmin - p.x, p.x - box.xmax, 0.0});
  const double gy = std::max({box.ymin - p.y, p.y - box.ymax, 0.0});
  return (gx * gx + gy * gy) * kShrink - kUnderflow;
}

std::size_t NearestSegment::nearest(const Point& p) const {
  if (nodes_.empty()) return kNoSegment;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_segment = kNoSegment;
  std::uint32_t stack[128];  // two per level of a median-split tree of fewer than 2^32 pieces
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (lower_bound(node.box, p) > best) continue;
    if (node.left == 0) {
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const Piece& piece = pieces_[k];
        if (lower_bound(piece.box, p) > best) continue;
        const Segment& s = segments_[piece.segment];
        const double d = squared_distance_to_segment(points_[s.a], points_[s.b], p);
        if (d < best || (d == best && piece.segment < best_segment)) {
          best = d;
          best_segment = piece.segment;
        }
      }
      continue;
    }
    // The nearer child last, so that it is searched first and tightens the bound for the other.
    const bool left_nearer = lower_bound(nodes_[node.left].box, p) <= lower_bound(nodes_[node.right].box, p);
    stack[top++] = left_nearer ? node.right : node.left;
    stack[top++] = left_nearer ? node.left : node.right;
  }
  return best_segment;
}

}  // namespace mwst::detail
