// A mesh file that includes only its own and lower layers: cmake/check_layers.cmake accepts it.
#include "mwst/error.hpp"
#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/mesh.hpp"
#include "support/time_budget.hpp"
