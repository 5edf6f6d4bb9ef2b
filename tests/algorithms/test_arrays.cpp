// tests/algorithms/test_arrays.cpp — the flat arrays of mwst/algorithms/arrays.hpp against the Mesh they come from: every
// domain triangle listed once and counter-clockwise (exact orient2d), neighbours symmetric and
// sharing the edge they are across, -1 only on the domain's boundary, subsegments are mesh edges
// with the mesh's markers, input points at their input indices, vertex kinds as the mesh's
// topology says, and the whole passing the independent checker (mwst/mesh/check.hpp). Then regional
// attributes spread as Triangle spreads them.
#include "mwst/algorithms/arrays.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mwst/error.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace {

using mwst::ArrayVertexKind;
using mwst::Mesh;
using mwst::MeshArrays;
using mwst::Point;

Point vertex(const MeshArrays& a, std::uint32_t v) { return {a.vertices[2 * v], a.vertices[2 * v + 1]}; }

// A triangle as its three corner points, rotated to start at the least one (x, then y): the same
// triangle in either numbering gives the same key.
using TriangleKey = std::array<std::pair<double, double>, 3>;
TriangleKey key_of(Point a, Point b, Point c) {
  TriangleKey k = {{{a.x, a.y}, {b.x, b.y}, {c.x, c.y}}};
  std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
  return k;
}

// Every property of the arrays that the mesh they came from determines.
void expect_arrays_match_mesh(const mwst::Pslg& input, const MeshArrays& a, const Mesh& mesh) {
  const std::size_t n = a.vertex_count();
  ASSERT_EQ(a.vertices.size(), 2 * n);
  ASSERT_EQ(a.vertex_markers.size(), n);
  ASSERT_EQ(a.triangles.size(), 3 * a.triangle_count());
  ASSERT_EQ(a.neighbours.size(), a.triangles.size());
  ASSERT_EQ(a.segments.size(), 2 * a.segment_count());
  EXPECT_EQ(a.triangle_count(), a.report.triangles);
  EXPECT_EQ(a.triangle_count(), mesh.domain_triangle_count());

  // Input point i is vertex i.
  ASSERT_GE(n, input.points.size());
  for (std::uint32_t i = 0; i < input.points.size(); ++i) {
    EXPECT_EQ(vertex(a, i), input.points[i]) << "input point " << i;
    EXPECT_TRUE(a.vertex_kinds[i] == ArrayVertexKind::kInput || a.vertex_kinds[i] == ArrayVertexKind::kDuplicate);
  }

  // The same triangles as the mesh's domain, each once.
  std::multiset<TriangleKey> from_mesh, from_arrays;
  for (mwst::TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (!mesh.in_domain(t)) continue;
    const auto& v = mesh.triangles[t].v;
    from_mesh.insert(key_of(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]]));
  }
  std::set<std::uint32_t> used;
  for (std::size_t t = 0; t < a.triangle_count(); ++t) {
    const Point p = vertex(a, a.triangles[3 * t]), q = vertex(a, a.triangles[3 * t + 1]),
                r = vertex(a, a.triangles[3 * t + 2]);
    EXPECT_EQ(mwst::orient2d(p, q, r), 1) << "triangle " << t << " is not counter-clockwise";
    from_arrays.insert(key_of(p, q, r));
    for (int i = 0; i < 3; ++i) used.insert(a.triangles[3 * t + i]);
  }
  EXPECT_EQ(from_arrays, from_mesh);
  EXPECT_EQ(std::set<TriangleKey>(from_arrays.begin(), from_arrays.end()).size(), from_arrays.size());

  // Steiner vertices in triangles: what the report counts; no duplicate in a triangle.
  std::size_t steiner_used = 0;
  for (const std::uint32_t v : used) {
    EXPECT_NE(a.vertex_kinds[v], ArrayVertexKind::kDuplicate);
    if (a.vertex_kinds[v] != ArrayVertexKind::kInput) ++steiner_used;
  }
  EXPECT_EQ(steiner_used, a.report.steiner);

  // Subsegments: an undirected edge → its marker.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::int32_t> segment_marker;
  for (std::size_t s = 0; s < a.segment_count(); ++s) {
    const auto ab = std::minmax(a.segments[2 * s], a.segments[2 * s + 1]);
    EXPECT_TRUE(segment_marker.emplace(ab, a.segment_markers[s]).second) << "subsegment listed twice";
  }

  // Neighbours: symmetric, across the same edge in opposite directions; -1 only on a subsegment
  // (a domain bounded by segments) or, for a point set, on the convex hull.
  std::set<std::pair<std::uint32_t, std::uint32_t>> triangle_edges;
  for (std::size_t t = 0; t < a.triangle_count(); ++t) {
    for (int i = 0; i < 3; ++i) {
      // The edge opposite corner i runs from corner i+1 to corner i+2.
      const std::uint32_t org = a.triangles[3 * t + (i + 1) % 3], dest = a.triangles[3 * t + (i + 2) % 3];
      triangle_edges.insert(std::minmax(org, dest));
      const std::int32_t u = a.neighbours[3 * t + i];
      if (u < 0) {
        EXPECT_EQ(u, -1);
        if (input.is_poly && !input.segments.empty() && !a.report.options.convex_hull) {
          EXPECT_TRUE(segment_marker.count(std::minmax(org, dest)))
              << "triangle " << t << " has no neighbour across an edge that is not a subsegment";
        }
        continue;
      }
      ASSERT_LT(static_cast<std::size_t>(u), a.triangle_count());
      int back = -1;
      for (int j = 0; j < 3; ++j) {
        if (a.neighbours[3 * u + j] == static_cast<std::int32_t>(t)) back = j;
      }
      ASSERT_GE(back, 0) << "triangle " << u << " does not list " << t << " back";
      EXPECT_EQ(a.triangles[3 * u + (back + 1) % 3], dest);
      EXPECT_EQ(a.triangles[3 * u + (back + 2) % 3], org);
    }
  }
  // Subsegments are mesh edges, with the mesh's markers and every one of the domain listed. Mesh
  // vertex v is array vertex v less the removed vertices before it.
  std::vector<std::uint32_t> array_id(mesh.points.size(), UINT32_MAX);
  for (std::uint32_t v = 0, next = 0; v < mesh.points.size(); ++v) {
    if (mesh.vertex_kind[v] != mwst::VertexKind::kRemoved) array_id[v] = next++;
  }
  std::size_t mesh_segments = 0;
  for (const auto& [ab, marker] : segment_marker) EXPECT_TRUE(triangle_edges.count(ab)) << "a subsegment is no mesh edge";
  for (mwst::TriangleId t = 0; t < mesh.triangle_slots(); ++t) {
    if (!mesh.in_domain(t)) continue;
    for (unsigned e = 0; e < 3; ++e) {
      const mwst::Handle h = mwst::make_handle(t, e);
      if (!mesh.is_segment(h)) continue;
      const mwst::TriangleId other = mwst::triangle_of(mesh.sym(h));
      if (mesh.in_domain(other) && other < t) continue;
      ++mesh_segments;
      const auto it = segment_marker.find(std::minmax(array_id[mesh.org(h)], array_id[mesh.dest(h)]));
      ASSERT_NE(it, segment_marker.end());
      EXPECT_EQ(it->second, mesh.marker(h));
    }
  }
  EXPECT_EQ(mesh_segments, a.segment_count());
  for (std::uint32_t v = 0; v < mesh.points.size(); ++v) {
    if (array_id[v] != UINT32_MAX) {
      EXPECT_EQ(a.vertex_markers[array_id[v]], mesh.vertex_marker[v]);
    }
  }

  // The independent checker on the arrays alone.
  std::vector<Point> points(n);
  for (std::uint32_t v = 0; v < n; ++v) points[v] = vertex(a, v);
  std::vector<std::array<std::uint32_t, 3>> triangles(a.triangle_count());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    triangles[t] = {a.triangles[3 * t], a.triangles[3 * t + 1], a.triangles[3 * t + 2]};
  }
  std::vector<mwst::Segment> subsegments;
  for (std::size_t s = 0; s < a.segment_count(); ++s) {
    subsegments.push_back({a.segments[2 * s], a.segments[2 * s + 1], a.segment_markers[s]});
  }
  const mwst::CheckResult check = mwst::check_triangulation(input, points, triangles, subsegments);
  EXPECT_TRUE(check.ok()) << (check.messages.empty() ? std::string() : check.messages.front());
}

mwst::TriangulateOptions options_for(mwst::Method method, double min_angle = 20.0) {
  mwst::TriangulateOptions o;
  o.method = method;
  o.min_angle_deg = min_angle;
  return o;
}

TEST(Arrays, AgreeWithTheMeshOnDataSets) {
  const std::string data = MWST_DATA_DIR;
  const std::pair<const char*, mwst::Method> cases[] = {
      {"Plate.poly", mwst::Method::kDt},       {"Plate.poly", mwst::Method::kDr},
      {"Africa.poly", mwst::Method::kDr},      {"Airliner.poly", mwst::Method::kBrh},
      {"PuertoRico.poly", mwst::Method::kQtr}, {"Ellipse.node", mwst::Method::kDt},
      {"Ellipse.node", mwst::Method::kDr},
  };
  for (const auto& [file, method] : cases) {
    SCOPED_TRACE(std::string(file) + " " + std::string(mwst::method_name(method)));
    const mwst::Pslg input = mwst::io::read_input(data + "/" + file);
    Mesh mesh;
    const MeshArrays a = mwst::triangulate_arrays(input, options_for(method), &mesh);
    EXPECT_GT(a.triangle_count(), 0u);
    expect_arrays_match_mesh(input, a, mesh);
    // The report is triangulate()'s (same mesh, same counts).
    const mwst::Report again = mwst::triangulate(input, options_for(method));
    EXPECT_EQ(a.report.triangles, again.triangles);
    EXPECT_EQ(a.report.weight_total, again.weight_total);
  }
}

// A square with an X of two segments inside: one crossing point, where four subsegments meet.
constexpr const char* kCrossedSquare =
    "6 2 0 1\n1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n5 1 1 0\n6 3 3 0\n"
    "6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 7\n6 2 4 8\n0\n";

TEST(Arrays, VertexKindsOfCrossingsAndSegmentSplits) {
  const mwst::Pslg input = mwst::io::parse_poly(kCrossedSquare, "crossed.poly");
  for (const mwst::Method method : {mwst::Method::kDt, mwst::Method::kDr, mwst::Method::kQtr}) {
    SCOPED_TRACE(std::string(mwst::method_name(method)));
    Mesh mesh;
    const MeshArrays a = mwst::triangulate_arrays(input, options_for(method, 30.0), &mesh);
    expect_arrays_match_mesh(input, a, mesh);
    EXPECT_EQ(a.report.crossings, 1u);
    std::size_t crossings = 0, on_segments = 0, interior = 0;
    for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
      switch (a.vertex_kinds[v]) {
        case ArrayVertexKind::kCrossing: {
          ++crossings;
          // The X crosses at (2, 2), rounded once.
          EXPECT_NEAR(a.vertices[2 * v], 2.0, 1e-15);
          EXPECT_NEAR(a.vertices[2 * v + 1], 2.0, 1e-15);
          break;
        }
        case ArrayVertexKind::kSegmentSteiner: ++on_segments; break;
        case ArrayVertexKind::kSteiner: ++interior; break;
        default: break;
      }
    }
    EXPECT_EQ(crossings, 1u);
    // Every subsegment end on a segment Steiner point: two subsegments meet there.
    std::vector<int> ends(a.vertex_count(), 0);
    for (const std::uint32_t v : a.segments) ++ends[v];
    for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
      if (a.vertex_kinds[v] == ArrayVertexKind::kSegmentSteiner) {
        EXPECT_EQ(ends[v], 2);
      }
      if (a.vertex_kinds[v] == ArrayVertexKind::kCrossing) {
        EXPECT_EQ(ends[v], 4);
      }
      if (a.vertex_kinds[v] == ArrayVertexKind::kSteiner) {
        EXPECT_EQ(ends[v], 0);
      }
    }
    // The segments' own markers survive on their pieces: 7 and 8 on the diagonals.
    std::set<std::int32_t> markers(a.segment_markers.begin(), a.segment_markers.end());
    EXPECT_EQ(markers, (std::set<std::int32_t>{1, 7, 8}));
    if (method == mwst::Method::kDt) {
      EXPECT_EQ(on_segments + interior, 0u);
    }
    if (method == mwst::Method::kDr) {
      EXPECT_GT(on_segments + interior, 0u);
    }
  }
}

TEST(Arrays, PointArrayDelaunay) {
  mwst::Pslg input;
  input.points = {{0, 0}, {2, 0}, {2, 1}, {0, 1}, {1, 0.5}, {2, 0}};  // the last one a duplicate
  Mesh mesh;
  const MeshArrays a = mwst::triangulate_arrays(input, {}, &mesh);
  expect_arrays_match_mesh(input, a, mesh);
  EXPECT_EQ(a.triangle_count(), 4u);
  EXPECT_EQ(a.vertex_count(), 6u);
  EXPECT_EQ(a.vertex_kinds[5], ArrayVertexKind::kDuplicate);
  EXPECT_TRUE(a.segments.empty());
  EXPECT_TRUE(a.triangle_attributes.empty());
  // Four triangles around the centre: each has two neighbours and one hull edge.
  for (std::size_t t = 0; t < 4; ++t) {
    EXPECT_EQ(std::count(a.neighbours.begin() + 3 * t, a.neighbours.begin() + 3 * t + 3, -1), 1);
  }
}

// Two rooms split by a wall (segment 5-6), a hole in the right one, and three region seeds: the
// left room gets 1.5, the right one 2 then (a later seed) 3; a seed in the hole is skipped.
constexpr const char* kTwoRooms =
    "10 2 0 0\n1 0 0\n2 2 0\n3 4 0\n4 4 2\n5 2 2\n6 0 2\n7 2.8 0.8\n8 3.2 0.8\n9 3.2 1.2\n10 2.8 1.2\n"
    "11 0\n1 1 2\n2 2 3\n3 3 4\n4 4 5\n5 5 6\n6 6 1\n7 2 5\n8 7 8\n9 8 9\n10 9 10\n11 10 7\n"
    "1\n1 3 1\n"
    "3\n1 0.5 0.5 1.5 0\n2 3.5 1.5 2 0\n3 2.5 0.2 3 0\n";

TEST(Arrays, RegionalAttributesSpreadUpToSegments) {
  const mwst::Pslg input = mwst::io::parse_poly(kTwoRooms, "rooms.poly");
  ASSERT_EQ(input.regions.size(), 3u);
  Mesh mesh;
  const MeshArrays a = mwst::triangulate_arrays(input, options_for(mwst::Method::kDr, 25.0), &mesh);
  expect_arrays_match_mesh(input, a, mesh);
  ASSERT_EQ(a.triangle_attributes.size(), a.triangle_count());
  for (std::size_t t = 0; t < a.triangle_count(); ++t) {
    const Point p = vertex(a, a.triangles[3 * t]), q = vertex(a, a.triangles[3 * t + 1]),
                r = vertex(a, a.triangles[3 * t + 2]);
    const double cx = (p.x + q.x + r.x) / 3.0;
    EXPECT_EQ(a.triangle_attributes[t], cx < 2.0 ? 1.5 : 3.0) << "triangle " << t << " centroid x " << cx;
  }
}

// A grid of 12 x 12 unit cells walled by segments, three seeds in every cell listed in a scrambled
// order: every triangle takes the attribute of the last region listed whose seed is in its cell
// (later regions win; seeds are located and regions spread in another order, for speed).
TEST(Arrays, LaterRegionsWinInEveryCellOfAGrid) {
  constexpr int k = 12;
  mwst::Pslg input;
  const auto id = [](int i, int j) { return static_cast<std::uint32_t>(i * (k + 1) + j); };
  for (int i = 0; i <= k; ++i) {
    for (int j = 0; j <= k; ++j) input.points.push_back(Point{static_cast<double>(i), static_cast<double>(j)});
  }
  for (int i = 0; i <= k; ++i) {
    for (int j = 0; j < k; ++j) {
      input.segments.push_back({id(i, j), id(i, j + 1), 0});
      input.segments.push_back({id(j, i), id(j + 1, i), 0});
    }
  }
  std::map<std::pair<int, int>, double> last;  // cell -> the attribute of its last region
  for (int round = 0; round < 3; ++round) {
    for (int c = 0; c < k * k; ++c) {
      const int scrambled = (c * 37 + round * 11) % (k * k);  // 37 is prime to 144
      const int i = scrambled / k, j = scrambled % k;
      mwst::Region region;
      region.seed = Point{i + 0.25 + 0.25 * round, j + 0.5};
      region.attribute = 1000.0 * round + scrambled;
      input.regions.push_back(region);
      last[{i, j}] = region.attribute;
    }
  }
  const MeshArrays a = mwst::triangulate_arrays(input, options_for(mwst::Method::kDt, 0.0));
  ASSERT_EQ(a.triangle_attributes.size(), a.triangle_count());
  ASSERT_EQ(a.triangle_count(), 2u * k * k);
  for (std::size_t t = 0; t < a.triangle_count(); ++t) {
    const Point p = vertex(a, a.triangles[3 * t]), q = vertex(a, a.triangles[3 * t + 1]),
                r = vertex(a, a.triangles[3 * t + 2]);
    const int i = static_cast<int>((p.x + q.x + r.x) / 3.0), j = static_cast<int>((p.y + q.y + r.y) / 3.0);
    EXPECT_EQ(a.triangle_attributes[t], (last[{i, j}])) << "triangle " << t << " in cell " << i << ", " << j;
  }
}

// A region whose seed lies outside the domain is bad input: an InputError naming the file, the
// region's line and the seed, whatever the method (the attributes are spread for every one).
TEST(Arrays, RegionSeedOutsideTheDomainIsAnInputError) {
  const std::string text = std::string(kTwoRooms).replace(std::string(kTwoRooms).rfind("3\n1 0.5"), 1, "4") +
                           "4 9 9 4 0\n";
  const mwst::Pslg input = mwst::io::parse_poly(text, "rooms.poly");
  ASSERT_EQ(input.regions.size(), 4u);
  EXPECT_EQ(input.regions[3].line, 30u);
  for (const mwst::Method method : {mwst::Method::kDt, mwst::Method::kDr}) {
    try {
      (void)mwst::triangulate_arrays(input, options_for(method, 25.0));
      ADD_FAILURE() << "accepted with method " << mwst::method_name(method);
    } catch (const mwst::InputError& e) {
      EXPECT_EQ(e.located(), "rooms.poly:30: region 4: its seed (9, 9) lies outside the domain (outside the segments, "
                             "or in a hole)");
    }
  }
  // In the hole (3, 1) too.
  const std::string in_hole = std::string(kTwoRooms).replace(std::string(kTwoRooms).rfind("3\n1 0.5"), 1, "4") +
                              "4 3 1 4 0\n";
  EXPECT_THROW((void)mwst::triangulate_arrays(mwst::io::parse_poly(in_hole, "rooms.poly"),
                                              options_for(mwst::Method::kDt, 0.0)),
               mwst::InputError);
}

// to_arrays on a mesh with Steiner points taken out again (VertexKind::kRemoved): they are left out
// and the rest renumbered, the triangles still naming the right points.
TEST(Arrays, RemovedVerticesAreLeftOut) {
  mwst::Pslg input;
  input.points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  Mesh mesh;
  mwst::triangulate(input, {}, &mesh);
  // A Steiner point added at the end and marked removed without entering the mesh (as the
  // optimiser leaves one before compact()), then one that is inserted.
  mesh.add_vertex({1, 1}, mwst::VertexKind::kRemoved);
  const mwst::VertexId kept = mesh.add_vertex({3, 2}, mwst::VertexKind::kSteiner);
  mesh.insert_vertex(kept);
  const MeshArrays a = mwst::to_arrays(mesh);
  ASSERT_EQ(a.vertex_count(), 5u);
  EXPECT_EQ(vertex(a, 4), (Point{3, 2}));
  EXPECT_EQ(a.vertex_kinds[4], ArrayVertexKind::kSteiner);
  EXPECT_EQ(a.triangle_count(), 4u);
  EXPECT_EQ(std::count(a.triangles.begin(), a.triangles.end(), 4u), 4);
}

// to_arrays copies a large mesh in ranges on several threads; the arrays are the same with any
// number of them, subsegments (here with Steiner points on them) in the same order. Superior's
// lake refined to a small area bound gives over 2^16 triangle slots, enough to be cut.
TEST(Arrays, AnyNumberOfThreadsGivesTheSameArrays) {
  const mwst::Pslg input = mwst::io::read_input(std::string(MWST_DATA_DIR) + "/Superior.poly");
  mwst::TriangulateOptions options = options_for(mwst::Method::kDr);
  double min_x = input.points[0].x, max_x = min_x, min_y = input.points[0].y, max_y = min_y;
  for (const Point& p : input.points) {
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  options.max_area = (max_x - min_x) * (max_y - min_y) / 150000.0;
  Mesh mesh;
  const mwst::Report report = mwst::triangulate(input, options, &mesh);
  ASSERT_GT(mesh.triangle_slots(), std::size_t{1} << 16);
  MeshArrays one = mwst::to_arrays(mesh, {}, {}, 1);
  one.report = report;  // what expect_arrays_match_mesh checks the counts against
  expect_arrays_match_mesh(input, one, mesh);
  ASSERT_GT(one.segment_count(), input.segments.size());
  for (const unsigned threads : {2u, 3u, 7u}) {
    SCOPED_TRACE(threads);
    const MeshArrays many = mwst::to_arrays(mesh, {}, {}, threads);
    EXPECT_EQ(many.vertices, one.vertices);
    EXPECT_EQ(many.vertex_kinds, one.vertex_kinds);
    EXPECT_EQ(many.vertex_markers, one.vertex_markers);
    EXPECT_EQ(many.triangles, one.triangles);
    EXPECT_EQ(many.neighbours, one.neighbours);
    EXPECT_EQ(many.segments, one.segments);
    EXPECT_EQ(many.segment_markers, one.segment_markers);
  }
}

// points_from_xy copies every pair, in order, on any number of threads; sizes below, at and
// above the parallel threshold (2^16) and none at all.
TEST(Arrays, PointsFromXyCopiesEveryPair) {
  for (const std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{65535}, std::size_t{65536},
                                  std::size_t{200003}}) {
    std::vector<double> xy(2 * count);
    for (std::size_t i = 0; i < xy.size(); ++i) xy[i] = static_cast<double>(i) * 0.5 - 7.0;
    for (const unsigned threads : {0u, 1u, 3u}) {
      SCOPED_TRACE(std::to_string(count) + " points, " + std::to_string(threads) + " threads");
      const std::vector<Point> points = mwst::points_from_xy(xy.data(), count, threads);
      ASSERT_EQ(points.size(), count);
      for (std::size_t i = 0; i < count; ++i) {
        if (points[i].x != xy[2 * i] || points[i].y != xy[2 * i + 1]) {
          ADD_FAILURE() << "point " << i << " is (" << points[i].x << ", " << points[i].y << ")";
          break;
        }
      }
    }
  }
}

}  // namespace
