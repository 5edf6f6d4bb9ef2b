// mwst/generate.hpp — synthetic point sets for experiments and tests (`mwst generate`).
//
// The distributions of the paper's synthetic data sets (uniform, Kuzmin, ellipse) plus two
// degenerate ones that stress the exact predicates (an integer grid: many cocircular and collinear
// points; a circle: every point cocircular). Generation is deterministic: std::mt19937_64 (whose
// output the C++ standard fixes) mapped to doubles by our own arithmetic, never by
// std::uniform_real_distribution (which differs between standard libraries), so a seed gives the
// same bytes everywhere. Only the circle and ellipse use std::cos / std::sin, on one octant,
// mirrored exactly into the others.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mwst/geometry.hpp"

namespace mwst {

enum class Distribution {
  kUniform,  // uniform in the unit square [0, 1)²
  kKuzmin,   // Kuzmin's distribution: uniform angle, radius sqrt(1/(1-u)² - 1), u uniform in [0, 1)
  kEllipse,  // N points evenly spaced in the parameter t on x = cos t, y = 0.5 sin t (no randomness)
  kGrid,     // the first N points, row by row, of the integer grid with ceil(sqrt N) columns
  kCircle,   // N points evenly spaced on the unit circle (no randomness)
};

MWST_API std::string_view distribution_name(Distribution d);  // "uniform", "kuzmin", ...
MWST_API std::optional<Distribution> parse_distribution(std::string_view name);

// N points of the distribution; `seed` matters for uniform and kuzmin only.
MWST_API std::vector<Point> generate_points(Distribution d, std::size_t n, std::uint64_t seed);

// A uniform double in [0, 1) from one 64-bit draw: its top 53 bits times 2⁻⁵³ (exact).
inline double unit_double(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1p-53; }

namespace io {
// Triangle .node text for a point set (1-based, no attributes or markers), coordinates as shortest
// round-trip decimals. Each line of `comment` becomes a '#' line at the top.
MWST_API std::string node_text(const std::vector<Point>& points, std::string_view comment = {});
}  // namespace io

}  // namespace mwst
