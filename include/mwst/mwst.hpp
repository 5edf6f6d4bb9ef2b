// mwst/mwst.hpp — the whole API of the library mwst::mwst in one include. The folders are the
// layers, lowest first (a header includes only its own and lower layers):
//   geometry/   — points, exact predicates (orient2d, incircle), rounded constructions;
//   mesh/       — the input graph (pslg), the triangle mesh, (constrained) Delaunay, the checker;
//   algorithms/ — the methods (refine: DR, brh: BRH, bundle: the exact bundle number, flip: EFH,
//                 optimize, mwt, quadtree: QTR), metrics, the pipeline (one call that runs a
//                 method and reports it) and arrays (the same call handing back flat arrays);
//   io/         — Triangle's file formats and switches, synthetic point sets.
// Pictures (mwst/io/draw.hpp) are a library of their own, mwst::draw, which needs cairo.
// Errors are exceptions (error.hpp); nothing in the library prints or exits.
#pragma once

#include "mwst/version.hpp"
#include "mwst/error.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/pslg.hpp"
#include "mwst/mesh/mesh.hpp"
#include "mwst/mesh/delaunay.hpp"
#include "mwst/algorithms/metrics.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/algorithms/refine.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/algorithms/brh.hpp"
#include "mwst/algorithms/flip.hpp"
#include "mwst/algorithms/optimize.hpp"
#include "mwst/algorithms/mwt.hpp"
#include "mwst/algorithms/quadtree.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/algorithms/arrays.hpp"
#include "mwst/io/triangle_switches.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/io/generate.hpp"
#include "mwst/io/report.hpp"
