// Mesh trials (Mesh::begin_trial / undo_trial / commit_trial): a trial of local operations —
// insertions with Lawson flips, edge and triangle splits, segment marks, killed and reused slots,
// moved points announced with save_vertex — is undone exactly: every public array equal to a copy
// made before the trial, and the private state too (the free-slot list, by the slots new_triangle
// hands out next; the walk's random state, by the handles locate() returns next).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "mwst/mesh/delaunay.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst {
namespace {

void expect_same_arrays(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.vertex_kind, b.vertex_kind);
  EXPECT_EQ(a.vertex_marker, b.vertex_marker);
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (TriangleId t = 0; t < a.triangles.size(); ++t) {
    EXPECT_EQ(a.triangles[t].v, b.triangles[t].v) << t;
    EXPECT_EQ(a.triangles[t].n, b.triangles[t].n) << t;
  }
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.segment_marker, b.segment_marker);
}

// The private state, by what it does next: the same slots from new_triangle() and the same
// handles from locate() (whose stochastic walk draws from the mesh's random state).
void expect_same_behaviour(Mesh a, Mesh b, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    const Point p{u(rng) * 30.0 - 5.0, u(rng) * 30.0 - 5.0};
    EXPECT_EQ(a.locate(p).handle, b.locate(p).handle);
  }
  for (int i = 0; i < 8; ++i) EXPECT_EQ(a.new_triangle(), b.new_triangle());
}

// Flips one interior non-segment edge whose quadrilateral is strictly convex (if one is found).
void flip_one(Mesh& m, std::mt19937_64& rng) {
  for (int tries = 0; tries < 200; ++tries) {
    const auto t = static_cast<TriangleId>(rng() % m.triangles.size());
    const Handle h = make_handle(t, static_cast<unsigned>(rng() % 3));
    if (m.is_dead(t) || m.is_ghost(t) || m.is_ghost(m.sym(h) >> 2) || m.is_segment(h)) continue;
    const Point& a = m.points[m.org(h)];
    const Point& b = m.points[m.dest(h)];
    const Point& c = m.points[m.apex(h)];
    const Point& d = m.points[m.apex(m.sym(h))];
    if (orient2d(c, a, d) > 0 && orient2d(d, b, c) > 0) {
      m.flip(h);
      return;
    }
  }
}

// Random local operations that keep m a triangulation: insertions (a split, then Lawson flips),
// flips of convex quadrilaterals, segment marks set and cleared, and isolated slots taken and
// killed again (which moves entries of the free list).
void random_operations(Mesh& m, std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const auto pick = rng() % 5;
    if (pick <= 1) {
      const VertexId v = m.add_vertex({u(rng) * 20.0, u(rng) * 20.0}, VertexKind::kSteiner, 7);
      m.insert_vertex(v);
    } else if (pick == 2) {
      flip_one(m, rng);
    } else if (pick == 3) {
      const auto t = static_cast<TriangleId>(rng() % m.triangles.size());
      if (m.is_dead(t)) continue;
      const Handle h = make_handle(t, static_cast<unsigned>(rng() % 3));
      if (m.is_segment(h)) {
        m.clear_segment(h);
      } else {
        m.set_segment(h, static_cast<std::int32_t>(rng() % 5));
      }
    } else {
      std::vector<TriangleId> taken;
      for (auto k = rng() % 4; k-- > 0;) {
        const TriangleId t = m.new_triangle();
        m.save_triangle(t);  // (written directly: announced)
        m.triangles[t].v = {0, 1, 2};
        taken.push_back(t);
      }
      for (auto k = taken.size(); k-- > 0;) {
        if (rng() % 3 != 0) m.kill_triangle(taken[k]);
      }
      for (const TriangleId t : taken) {
        if (!m.is_dead(t)) m.kill_triangle(t);
      }
    }
  }
}

// Direct writes to existing vertices, announced (last in a trial: moved points would tangle the
// triangulation for later walks).
void move_points(Mesh& m, std::mt19937_64& rng) {
  for (auto k = 1 + rng() % 4; k-- > 0;) {
    const auto v = static_cast<VertexId>(rng() % m.points.size());
    m.save_vertex(v);
    m.points[v].x += 1e-3;
    m.vertex_kind[v] = VertexKind::kRemoved;
    m.vertex_marker[v] = 99;
  }
}

TEST(MeshTrial, UndoRestoresTheMeshExactly) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
  Mesh m = constrained_delaunay(g);
  std::mt19937_64 rng(12345);
  // A few dead slots first, so that trials both reuse and add to the free list.
  random_operations(m, rng, 40);
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE(trial);
    const Mesh before = m;
    m.begin_trial();
    random_operations(m, rng, 1 + static_cast<int>(rng() % 12));
    if (trial % 3 == 0) {
      m.commit_trial();  // kept: the next trial starts from here
      continue;
    }
    move_points(m, rng);
    m.undo_trial();
    expect_same_arrays(m, before);
    if (::testing::Test::HasFailure()) return;  // (walks on a broken mesh would not end well)
    expect_same_behaviour(m, before, static_cast<std::uint64_t>(trial));
    if (::testing::Test::HasFailure()) return;
  }
}

// Each kind of operation alone, so that none is covered only by what another one saved.
TEST(MeshTrial, EachOperationAloneIsUndone) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
  Mesh m = constrained_delaunay(g);
  std::mt19937_64 rng(777);
  for (int op = 0; op < 4; ++op) {
    for (int trial = 0; trial < 60; ++trial) {
      SCOPED_TRACE("operation " + std::to_string(op) + ", trial " + std::to_string(trial));
      const Mesh before = m;
      m.begin_trial();
      if (op == 0) {
        flip_one(m, rng);
      } else if (op == 1) {
        const VertexId v = m.add_vertex({static_cast<double>(rng() % 2000) / 100.0, static_cast<double>(rng() % 2000) / 100.0},
                                        VertexKind::kSteiner, 0);
        m.insert_vertex(v);
      } else if (op == 2) {
        const auto t = static_cast<TriangleId>(rng() % m.triangles.size());
        const Handle h = make_handle(t, static_cast<unsigned>(rng() % 3));
        if (!m.is_dead(t)) m.is_segment(h) ? m.clear_segment(h) : m.set_segment(h, 3);
      } else {
        move_points(m, rng);
      }
      m.undo_trial();
      expect_same_arrays(m, before);
      if (::testing::Test::HasFailure()) return;
    }
  }
}

TEST(MeshTrial, MisuseIsAnInternalError) {
  const Pslg g = io::read_input(std::string(MWST_DATA_DIR) + "/Plate.poly");
  Mesh m = constrained_delaunay(g);
  EXPECT_THROW(m.undo_trial(), InternalError);
  m.begin_trial();
  EXPECT_THROW(m.begin_trial(), InternalError);
  EXPECT_THROW(compact(m), InternalError);
  m.commit_trial();
  EXPECT_FALSE(m.in_trial());
}

}  // namespace
}  // namespace mwst
