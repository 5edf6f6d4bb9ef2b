// The mesh header that tests/layers/upward/src/geometry/predicates.cpp includes.
#pragma once
