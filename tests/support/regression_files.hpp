// tests/support/regression_files.hpp — the inputs that caught a bug, one file each under
// tests/regression/ (named after what it caught; its header comment says who found it, what went
// wrong and where it was fixed: tests/regression/README.md).
#pragma once

#include <string>

#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst::test {

// The path of tests/regression/NAME.
inline std::string regression_path(const std::string& name) { return std::string(MWST_REGRESSION_DIR) + "/" + name; }

// tests/regression/NAME read as the CLI reads it (a .node or a .poly).
inline Pslg read_regression(const std::string& name) { return io::read_input(regression_path(name)); }

}  // namespace mwst::test
