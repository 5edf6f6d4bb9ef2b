// mwst/io/generate.hpp — synthetic inputs for experiments, tests and the scaling benchmark
// (`mwst generate`, bench/scaling.py).
//
// Point sets: the distributions of the paper's synthetic data sets (uniform, Kuzmin, ellipse), two
// degenerate ones that stress the exact predicates (an integer grid: many cocircular and collinear
// points; a circle: every point cocircular), points on a spiral, and clusters at scales from 1 to
// 2⁻²⁰. Polygons (.poly, with segments): a square with a grid of circular holes, a narrow fan of
// wedges, a long thin strip and a fractal coastline; each is a simple polygon (with holes) whose
// segments neither cross nor touch, so its constrained Delaunay triangulation needs no repair.
//
// Generation is deterministic: std::mt19937_64 (whose output the C++ standard fixes) mapped to
// doubles by our own arithmetic, never by std::uniform_real_distribution (which differs between
// standard libraries). The circle, ellipse, holes and coastline evaluate std::cos / std::sin on one
// octant only and mirror it exactly into the others; the spiral and the fan call std::cos / std::sin
// at arbitrary angles, so their last bits follow the C library's (glibc's are correctly rounded in
// practice).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mwst/geometry/geometry.hpp"
#include "mwst/mesh/pslg.hpp"

namespace mwst {

enum class Distribution {
  kUniform,  // uniform in the unit square [0, 1)²
  kKuzmin,   // Kuzmin's distribution: uniform angle, radius sqrt(1/(1-u)² - 1), u uniform in [0, 1)
  kEllipse,  // N points evenly spaced in the parameter t on x = cos t, y = 0.5 sin t (no randomness)
  kGrid,     // the first N points, row by row, of the integer grid with ceil(sqrt N) columns
  kCircle,   // N points evenly spaced on the unit circle (no randomness)
  kSpiral,   // N points on the Archimedean spiral r = θ / (2π·kSpiralTurns), kSpiralTurns turns,
             // about evenly spaced in arc length: θ_k = 2π·turns·sqrt((k + 1/2) / N) (no randomness)
  kClusters, // ceil(sqrt N) clusters, centres uniform in [0, 1)², cluster c of "radius" r_c = 2^-e,
             // e uniform in 0..20 (1 down to 1e-6 of the box); a point is its cluster's centre plus
             // r_c·(s - 2) in x and in y, s a sum of four uniforms in [0, 1) (Irwin–Hall: nearly
             // Gaussian, standard deviation r_c / √3); point i belongs to cluster i mod ceil(sqrt N)
  // Polygons (segments; written as .poly):
  kHoles,      // the square [0, g]² with g² circular holes of radius 1/4 centred at (i+½, j+½), each
               // a regular kHolePolygonPoints-gon; g = floor(sqrt((N - 4) / kHolePolygonPoints)),
               // the other vertices evenly on the square's sides (no randomness)
  kFan,        // a star-shaped fan: an apex at the origin, then vertices alternating between radius
               // 1 and radius kFanInnerRadius at angular steps of min(0.01°, 45° / wedges) (no
               // randomness); (N - 2) / 2 wedges, 1,000 of 0.01° at N = 2002
  kStrip,      // the rectangle [0, 1] × [0, 1e-3] with its N vertices on the two long sides (no
               // randomness)
  kCoastline,  // a fractal coastline: the star-shaped polygon r(θ) ∈ [1/2, 3/2] at θ = 2πk/N, r by
               // random midpoint displacement of Hurst exponent 3/4 (fractal dimension 1.25, that of
               // Britain's west coast, Mandelbrot 1967); the coarse levels use the same draws at
               // every N, so a larger N refines the same coast
};

inline constexpr double kSpiralTurns = 10.0;
inline constexpr std::size_t kHolePolygonPoints = 64;
inline constexpr double kFanInnerRadius = 1e-3;

MWST_API std::string_view distribution_name(Distribution d);  // "uniform", "kuzmin", ...
MWST_API std::optional<Distribution> parse_distribution(std::string_view name);
// Every distribution, in the order of the enum (for --help and tests).
MWST_API std::vector<Distribution> all_distributions();
// True for the polygon classes (holes, fan, strip, coastline): they have segments.
MWST_API bool has_segments(Distribution d);
// True when `seed` changes the output (uniform, kuzmin, clusters, coastline).
MWST_API bool uses_seed(Distribution d);
// The smallest N the distribution accepts (1 for the point sets; a polygon needs a few vertices).
MWST_API std::size_t minimum_count(Distribution d);

// The N vertices (points) of the distribution; for a polygon class, its vertices.
MWST_API std::vector<Point> generate_points(Distribution d, std::size_t n, std::uint64_t seed);
// The whole input: points, and for a polygon class its segments (closed rings) and hole seeds
// (is_poly set). N below minimum_count(d) is an InputError.
MWST_API Pslg generate_input(Distribution d, std::size_t n, std::uint64_t seed);

// A uniform double in [0, 1) from one 64-bit draw: its top 53 bits times 2⁻⁵³ (exact).
inline double unit_double(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1p-53; }

namespace io {
// Triangle .node text for a point set (1-based, no attributes or markers), coordinates as shortest
// round-trip decimals. Each line of `comment` becomes a '#' line at the top.
MWST_API std::string node_text(const std::vector<Point>& points, std::string_view comment = {});
// Triangle .poly text for a planar straight-line graph: its vertices (as node_text), segments with
// their boundary markers, and hole seeds; 1-based.
MWST_API std::string poly_text(const Pslg& pslg, std::string_view comment = {});
}  // namespace io

}  // namespace mwst
