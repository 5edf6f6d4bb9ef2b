// algorithms/quadtree/cells.hpp — the case table of untouched leaves (BEG's table), with its
// adjacency, built once from detail::quadtree_case_table(): for each mask of present side
// midpoints, the triangles over polygon positions and, per triangle edge, the polygon edge it lies
// on or the triangle edge across it inside the cell. Read per leaf by prepare_cells(),
// emit_cells() and cell_side(), so plain_cells() is inline.
#pragma once

#include <array>
#include <cstdint>

#include "algorithms/quadtree/builder.hpp"
#include "mwst/algorithms/quadtree.hpp"
#include "algorithms/quadtree/cell_triangulation.hpp"

namespace mwst::qtr {

// The case table with its adjacency: for each midpoint mask, the triangles over polygon positions
// (the present slots in order) and, per triangle edge, either the polygon edge it lies on or the
// triangle edge across it inside the cell.
struct PlainCell {
  std::uint8_t slots[8];        // polygon position → slot
  std::uint8_t size = 0;        // polygon vertices
  std::uint8_t count = 0;       // triangles
  std::uint8_t tri[6][3];       // polygon positions, counter-clockwise
  std::int8_t boundary[6][3];   // polygon edge index or -1
  std::uint8_t twin[6][3];      // 3·triangle + edge across, for inner edges
  std::uint32_t sides = 0;      // polygon positions of BR, TR, TL (8 bits each)
  std::uint8_t edge[8];         // polygon edge → 3·triangle + edge on it
};

inline const std::array<PlainCell, 16>& plain_cells() {
  static const auto table = [] {
    std::array<PlainCell, 16> out{};
    const auto& cases = detail::quadtree_case_table();
    for (unsigned mask = 0; mask < 16; ++mask) {
      PlainCell& c = out[mask];
      std::uint8_t position[8] = {};
      for (std::uint8_t slot = 0; slot < 8; ++slot) {
        if ((slot & 1) != 0 && (mask & (1u << (slot / 2))) == 0) continue;
        position[slot] = c.size;
        c.slots[c.size++] = slot;
      }
      for (unsigned q = 0; q < c.size; ++q) {
        if (c.slots[q] == kBR) c.sides |= q;
        if (c.slots[q] == kTR) c.sides |= q << 8;
        if (c.slots[q] == kTL) c.sides |= q << 16;
      }
      c.count = static_cast<std::uint8_t>(cases[mask].size());
      for (std::size_t i = 0; i < cases[mask].size(); ++i) {
        for (unsigned k = 0; k < 3; ++k) c.tri[i][k] = position[cases[mask][i][k]];
      }
      for (unsigned i = 0; i < c.count; ++i) {
        for (unsigned e = 0; e < 3; ++e) {
          const unsigned from = c.tri[i][next3(e)], to = c.tri[i][prev3(e)];
          c.boundary[i][e] = (to == (from + 1u) % c.size) ? static_cast<std::int8_t>(from) : std::int8_t{-1};
          if (c.boundary[i][e] >= 0) {
            c.edge[from] = static_cast<std::uint8_t>(3 * i + e);
            continue;
          }
          for (unsigned j = 0; j < c.count; ++j) {
            for (unsigned f = 0; f < 3; ++f) {
              if (c.tri[j][next3(f)] == to && c.tri[j][prev3(f)] == from) c.twin[i][e] = static_cast<std::uint8_t>(3 * j + f);
            }
          }
        }
      }
    }
    return out;
  }();
  return table;
}

}  // namespace mwst::qtr
