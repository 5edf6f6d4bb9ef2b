// tests/mesh/test_check_tables.cpp — the flat tables of the checker (src/mesh/check_tables.hpp)
// against std::map built the way the node-based hash maps they replaced were filled: every
// directed edge found with the apex and triangle of the first triangle listing it, every later
// listing returned as a duplicate in slot order, every absent pair not found, on a fan whose apex
// has thousands of edges (the circle's and the fan class's shape) with repeated and reversed
// triangles; vertices by exact coordinates, the first vertex at a point kept, +0.0 and -0.0 alike.
// Then the checker's messages on a fan with planted overlaps, in triangle order.
#include "mesh/check_tables.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "mwst/mesh/check.hpp"
#include "mwst/mesh/pslg.hpp"
#include "support/exact_checker.hpp"

namespace mwst {
namespace {

using test::joined;

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

// A fan of `blades` triangles around vertex 0, then some triangles again (some rotated, so that
// the same directed edges come from other corners), some reversed, and some named invalid.
Triangles planted_fan(std::uint32_t blades, std::vector<char>* valid) {
  Triangles t;
  for (std::uint32_t i = 1; i <= blades; ++i) t.push_back({0, i, i + 1});
  std::mt19937 random(5);
  for (int k = 0; k < 40; ++k) {
    const auto& f = t[random() % blades];
    switch (k % 3) {
      case 0: t.push_back(f); break;                     // the same triangle again
      case 1: t.push_back({f[1], f[2], f[0]}); break;    // rotated: same edges, other slots
      default: t.push_back({f[0], f[2], f[1]}); break;   // reversed: the opposite edges
    }
  }
  valid->assign(t.size(), 1);
  for (std::size_t i = 7; i < t.size(); i += 97) (*valid)[i] = 0;
  return t;
}

TEST(CheckTables, DirectedEdgesAgreeWithAMapFilledInTriangleOrder) {
  std::vector<char> valid;
  const std::uint32_t blades = 3000;
  const Triangles tri = planted_fan(blades, &valid);
  const std::size_t n = blades + 2;
  struct First {
    std::uint32_t apex, triangle;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, First> first;
  std::vector<detail::DirectedEdges::Duplicate> duplicates;
  for (std::uint32_t t = 0; t < tri.size(); ++t) {
    if (!valid[t]) continue;
    for (unsigned k = 0; k < 3; ++k) {
      const auto [it, inserted] = first.try_emplace({tri[t][k], tri[t][(k + 1) % 3]}, First{tri[t][(k + 2) % 3], t});
      if (!inserted) duplicates.push_back({3 * t + k, 3 * it->second.triangle + 0});
    }
  }
  detail::DirectedEdges edges;
  const auto got = edges.build(n, tri, valid);
  ASSERT_EQ(got.size(), duplicates.size());
  ASSERT_GT(got.size(), 30u);
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].slot, duplicates[i].slot) << "duplicate " << i;
    EXPECT_EQ(got[i].first_slot / 3, duplicates[i].first_slot / 3) << "duplicate " << i;
  }
  ASSERT_EQ(edges.size(), first.size());
  std::size_t listed = 0;
  for (std::uint32_t u = 0; u < n; ++u) {
    for (std::uint32_t e = edges.begin(u); e < edges.end(u); ++e, ++listed) {
      if (e > edges.begin(u)) {
        EXPECT_LT(edges.destination(e - 1), edges.destination(e));
      }
      const auto it = first.find({u, edges.destination(e)});
      ASSERT_NE(it, first.end());
      EXPECT_EQ(edges.apex(e), it->second.apex);
      EXPECT_EQ(edges.triangle(e), it->second.triangle);
    }
  }
  EXPECT_EQ(listed, first.size());
  // Every pair among the apex and some rim vertices: found exactly when the map has it, and the
  // undirected entry is the one from the smaller vertex when that exists.
  for (std::uint32_t u : {0u, 1u, 2u, 1500u, blades, blades + 1}) {
    for (std::uint32_t v = 0; v < n; ++v) {
      const bool has = first.count({u, v}) != 0, reverse = first.count({v, u}) != 0;
      const std::uint32_t e = edges.find(u, v);
      EXPECT_EQ(e != kNone, has) << u << "->" << v;
      if (has) {
        EXPECT_EQ(edges.destination(e), v);
      }
      const std::uint32_t d = edges.undirected(u, v);
      if (!has && !reverse) {
        EXPECT_EQ(d, kNone);
      } else {
        const bool from_smaller = first.count({std::min(u, v), std::max(u, v)}) != 0;
        EXPECT_EQ(d, from_smaller ? edges.find(std::min(u, v), std::max(u, v)) : edges.find(std::max(u, v), std::min(u, v)));
      }
    }
  }
}

TEST(CheckTables, PointTableKeepsTheFirstVertexAtEachExactPoint) {
  std::vector<Point> points;
  for (int i = 0; i < 2000; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / 2000.0;
    points.push_back({std::cos(angle), std::sin(angle)});         // a circle
    points.push_back({static_cast<double>(i % 40), static_cast<double>(i / 40)});  // a grid
  }
  points.push_back({0.0, -0.0});
  points.push_back({-0.0, 0.0});
  for (int i = 0; i < 300; ++i) points.push_back(points[(i * 7919) % points.size()]);  // repeats
  detail::PointTable table(points.size());
  std::map<std::pair<double, double>, std::uint32_t> first;  // -0.0 == 0.0 as keys of doubles
  for (std::uint32_t v = 0; v < points.size(); ++v) {
    const auto [it, inserted] = first.try_emplace({points[v].x, points[v].y}, v);
    EXPECT_EQ(table.insert(points[v], v), inserted ? kNone : it->second) << "vertex " << v;
  }
  for (const auto& [xy, v] : first) EXPECT_EQ(table.find({xy.first, xy.second}), v);
  EXPECT_EQ(table.find({0.5, 0.25}), kNone);
  EXPECT_EQ(table.find({std::nextafter(1.0, 2.0), 0.0}), kNone);
}

// The checker on a fan with two triangles listed twice: each overlap reported once, for the later
// triangle, naming the first, in the order of the triangles.
TEST(CheckTables, CheckerReportsOverlapsOfAFanInTriangleOrder) {
  Pslg input;
  const int blades = 200;
  input.points.push_back({0.0, 0.0});
  for (int i = 0; i <= blades; ++i) {
    const double angle = std::numbers::pi * i / (2.0 * blades);
    input.points.push_back({std::cos(angle), std::sin(angle)});
  }
  std::vector<std::array<std::uint32_t, 3>> tri;
  for (std::uint32_t i = 1; i <= static_cast<std::uint32_t>(blades); ++i) tri.push_back({0, i, i + 1});
  ASSERT_TRUE(check_triangulation(input, input.points, tri, {}).ok());
  tri.push_back({120, 121, 0});  // triangle 201: triangle 120 rotated
  tri.push_back({0, 31, 32});    // triangle 202: triangle 31 again
  const CheckResult r = check_triangulation(input, input.points, tri, {});
  std::vector<std::string> overlaps;
  for (const std::string& m : r.messages) {
    if (m.find("with the same orientation") != std::string::npos) overlaps.push_back(m);
  }
  ASSERT_EQ(overlaps.size(), 6u) << joined(r.messages);
  EXPECT_NE(overlaps[0].find("edge 121-122 "), std::string::npos) << overlaps[0];
  EXPECT_NE(overlaps[0].find("is in triangle 120 and triangle 201 "), std::string::npos) << joined(overlaps);
  EXPECT_NE(overlaps[2].find("edge 1-121 "), std::string::npos) << overlaps[2];
  EXPECT_NE(overlaps[3].find("edge 1-32 "), std::string::npos) << overlaps[3];
  EXPECT_NE(overlaps[5].find("is in triangle 31 and triangle 202 "), std::string::npos) << overlaps[5];
}

}  // namespace
}  // namespace mwst
