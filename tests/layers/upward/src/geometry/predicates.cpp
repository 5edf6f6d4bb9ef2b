// A geometry file that includes a mesh header: cmake/check_layers.cmake must refuse this tree.
#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/mesh.hpp"
