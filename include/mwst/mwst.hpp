// mwst/mwst.hpp — the whole public API of mwst in one include. Layers, lowest first (a header only
// includes headers above it in this list):
//   geometry  — points, exact predicates (orient2d, incircle), rounded constructions;
//   pslg, mesh, delaunay — the input graph, the triangle mesh, (constrained) Delaunay triangulation;
//   refine, brh, bundle, flip, optimize, quadtree — the methods (DR, BRH, the exact bundle number,
//             EFH, our optimiser, QTR) and metrics / check (weight, angles, independent validation);
//   pipeline  — one call that runs a method on an input and reports it;
//   arrays    — the same call handing back flat arrays (vertices, triangles, neighbours, ...);
//   io, draw, generate — Triangle's file formats, pictures, synthetic point sets.
// Errors are exceptions (error.hpp); nothing in the library prints or exits.
#pragma once

#include "mwst/version.hpp"
#include "mwst/error.hpp"
#include "mwst/geometry.hpp"
#include "mwst/pslg.hpp"
#include "mwst/mesh.hpp"
#include "mwst/delaunay.hpp"
#include "mwst/metrics.hpp"
#include "mwst/check.hpp"
#include "mwst/refine.hpp"
#include "mwst/bundle.hpp"
#include "mwst/brh.hpp"
#include "mwst/flip.hpp"
#include "mwst/optimize.hpp"
#include "mwst/mwt.hpp"
#include "mwst/quadtree.hpp"
#include "mwst/pipeline.hpp"
#include "mwst/arrays.hpp"
#include "mwst/triangle_switches.hpp"
#include "mwst/io.hpp"
#include "mwst/draw.hpp"
#include "mwst/generate.hpp"
