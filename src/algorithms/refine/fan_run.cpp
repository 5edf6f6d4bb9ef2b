// src/algorithms/refine/fan_run.cpp — the walk's shortcut across a point fan (refiner.hpp).
//
// A point fan: triangles (c, w_i, w_i+1) around one vertex c, the hub, whose far edges w_i w_i+1
// all lie on one line. n points on a line and one above them make one of n − 1 slivers; each
// sliver's off-center lies beyond the hull edge at the fan's far end, and the walk to it turned
// about the apex through every sliver between, Θ(n) steps for each of n slivers (bench/README.md,
// docs/algorithms/refine.md "The point fan").
//
// In a fan triangle entered across a spoke, the walk's step is forced when p is not beyond the
// far edge (then the only edge with p strictly beyond it, other than the one it came across, is
// the next spoke): it crosses the next spoke whatever edge its random choice tries first. The
// far edges lie on one line, so one orientation test against that line settles the far edge of
// every triangle of the run. The spokes are in counter-clockwise order, each a positive turn of
// less than π from the one before: measured from the spoke the walk came across, their angles
// increase, and the walk keeps turning while the next spoke's angle is below p's. That test is
// monotone along the run, so a binary search finds where the walk stops turning, with the same
// exact orientation tests the walk would make. The walk then stands in the triangle it would have
// reached, having come across the same edge, with its random generator advanced by one draw per
// triangle crossed (walk_rng.hpp): everything after is as before, to the bit.
#include "algorithms/refine/refiner.hpp"

namespace mwst::refinement {

// Builds the run of fan triangles about `hub` through t (t has `hub` as a corner): in the domain,
// positively oriented, far edges on the line of t's far edge, joined by spokes that are not
// subsegments. A run shorter than a few triangles is kept all the same (it is simply of no use).
void Refiner::build_fan_run(VertexId hub, TriangleId t) {
  for (const Handle h : fan_spokes_) {
    if ((h >> 2) < fan_position_.size()) fan_position_[h >> 2] = 0;
  }
  fan_spokes_.clear();
  fan_credit_ = 0;
  fan_build_cost_ = 1;
  fan_hub_ = hub;
  fan_run_edits_ = mesh_edits_;
  const Triangle& T = m_.triangles[t];
  unsigned k = 0;
  while (k < 3 && T.v[k] != hub) ++k;
  if (k == 3 || !m_.in_domain(t)) return;
  const Handle start = make_handle(t, prev3(k));  // hub → w, apex w'
  const Point& c = m_.points[hub];
  fan_line_a_ = m_.points[m_.dest(start)];
  fan_line_b_ = m_.points[m_.apex(start)];
  if (orient2d(c, fan_line_a_, fan_line_b_) <= 0) return;
  // A fan triangle: its spoke h (org hub) and its far edge on the line, positively oriented.
  auto in_fan = [&](Handle h) {
    if (!m_.in_domain(h >> 2)) return false;
    const Point& w = m_.points[m_.dest(h)];
    const Point& w2 = m_.points[m_.apex(h)];
    return orient2d(c, w, w2) > 0 && orient2d(fan_line_a_, fan_line_b_, w) == 0 &&
           orient2d(fan_line_a_, fan_line_b_, w2) == 0;
  };
  // A spoke the walk may cross both ways: a subsegment on neither side.
  auto open = [&](Handle h) { return !m_.is_segment(h) && !m_.is_segment(m_.sym(h)); };
  const std::size_t most = m_.triangles.size();
  // Clockwise from t (collected backwards), then t and counter-clockwise.
  for (Handle h = start; fan_spokes_.size() < most && open(h) && in_fan(Mesh::lnext(m_.sym(h)));) {
    h = Mesh::lnext(m_.sym(h));
    fan_spokes_.push_back(h);
  }
  std::reverse(fan_spokes_.begin(), fan_spokes_.end());
  fan_spokes_.push_back(start);
  for (Handle h = start; fan_spokes_.size() < most && open(Mesh::lprev(h)) && in_fan(m_.sym(Mesh::lprev(h)));) {
    h = m_.sym(Mesh::lprev(h));
    fan_spokes_.push_back(h);
  }
  fan_build_cost_ = fan_spokes_.size() + 1;
  if (fan_position_.size() < m_.triangles.size()) fan_position_.resize(m_.triangles.size(), 0);
  for (std::size_t i = 0; i < fan_spokes_.size(); ++i) {
    fan_position_[fan_spokes_[i] >> 2] = static_cast<std::uint32_t>(i + 1);
  }
}

// The walk stands in run triangle t, having come across came_from. If it came across a spoke and
// its next steps are forced, crosses them: t and came_from become the triangle it reaches and the
// spoke it came across there, and the generator advances one draw per triangle left. Returns the
// number of triangles left behind (0: nothing done).
std::size_t Refiner::skip_fan_run(const Point& p, TriangleId& t, Handle& came_from) {
  // p beyond the far edges: the walk may leave the fan there, as its random choice decides.
  if (orient2d(fan_line_a_, fan_line_b_, p) < 0) return 0;
  const std::size_t j = fan_position_[t] - 1;
  const Handle spoke = fan_spokes_[j];  // hub → w_j; t = (hub, w_j, w_j+1)
  const Point& c = m_.points[fan_hub_];
  auto far = [&](std::size_t i) -> const Point& { return m_.points[m_.dest(fan_spokes_[i])]; };  // w_i
  std::size_t crossed = 0;
  if (came_from == spoke) {
    // Turning counter-clockwise: from triangle i − 1 the walk crosses spoke i iff
    // orient(w_i, c, p) < 0, p strictly within a half turn counter-clockwise of the ray c → w_i.
    // With w_i within a half turn counter-clockwise of w_j (orient(c, w_j, w_i) > 0), and p there
    // too (the walk crossed spoke j), that is "w_i's angle from w_j is below p's": true, then false.
    const Point& wj = far(j);
    auto turns_on = [&](std::size_t i) { return orient2d(c, wj, far(i)) > 0 && orient2d(far(i), c, p) < 0; };
    std::size_t lo = j, hi = fan_spokes_.size();  // spokes j+1..lo are crossed, hi and on not
    while (hi - lo > 1) {
      const std::size_t mid = lo + (hi - lo) / 2;
      (turns_on(mid) ? lo : hi) = mid;
    }
    crossed = lo - j;
    if (crossed != 0) {
      t = fan_spokes_[lo] >> 2;
      came_from = fan_spokes_[lo];
    }
  } else if (came_from == Mesh::lprev(spoke)) {
    // Turning clockwise (came across spoke j + 1): from triangle i the walk crosses spoke i iff
    // orient(c, w_i, p) < 0; with w_i within a half turn clockwise of w_j+1 that is monotone too.
    const Point& wn = m_.points[m_.apex(spoke)];  // w_j+1
    auto turns_on = [&](std::size_t i) { return orient2d(c, far(i), wn) > 0 && orient2d(c, far(i), p) < 0; };
    std::size_t lo = 0, hi = j + 1;  // spokes hi..j are crossed, lo and below not (spoke 0 leaves the run)
    while (hi - lo > 1) {
      const std::size_t mid = lo + (hi - lo) / 2;
      (turns_on(mid) ? hi : lo) = mid;
    }
    crossed = j + 1 - hi;
    if (crossed != 0) {
      t = fan_spokes_[hi - 1] >> 2;
      came_from = Mesh::lprev(fan_spokes_[hi - 1]);
    }
  }
  if (crossed != 0) walk_rng_ = xorshift_jump(walk_rng_, crossed);
  return crossed;
}

}  // namespace mwst::refinement
