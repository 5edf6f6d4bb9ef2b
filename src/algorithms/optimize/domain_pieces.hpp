// src/algorithms/optimize/domain_pieces.hpp — independent pieces of the domain, for method opt at
// scale. Internal (not installed); the pipeline (pipeline.cpp, optimize_phase) searches each piece
// alone, as if it were the whole input, and puts the results back together.
#pragma once

#include <vector>

#include "mwst/export.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

// The search's budgets (trials per start, the starts tried) are per mesh, so an input of many
// disjoint parts got a thinner search per part than each part alone. split_domain cuts the input
// by the connected components of its carved CDT `cdt`'s domain (triangles joined across any shared
// edge, segments included) into one input per piece, with the input's points in their order
// (input_ids[p][i]: the input id of piece p's point i), its segments and the hole seeds in its
// bounding box. False (and no pieces) unless there are two or more and the input is plain: no
// crossing or duplicate points, every point on the domain, no two pieces touching at a point.
// merge_pieces puts the pieces' meshes (from method opt run on each alone) back together as one
// mesh of the input: the input points keep their ids, the pieces' Steiner points follow in piece
// order, every piece's triangles are kept as they are, the rest is triangulated and carved as
// before. It checks that the pieces add up to the domain (triangles, area, weight) and is valid,
// and returns false otherwise.
struct DomainPieces {
  std::vector<Pslg> pslgs;
  std::vector<std::vector<VertexId>> input_ids;
};
MWST_API bool split_domain(const Pslg& input, const Mesh& cdt, DomainPieces& out);
MWST_API bool merge_pieces(const Pslg& input, const Mesh& cdt, const DomainPieces& pieces,
                           const std::vector<Mesh>& results, Mesh& out);

}  // namespace mwst
