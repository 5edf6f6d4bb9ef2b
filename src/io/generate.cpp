// Synthetic point sets (mwst/generate.hpp): the distributions of the synthetic data sets of
// Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" (uniform, Kuzmin, ellipse) and
// two degenerate stress sets (integer grid, circle), generated bit-for-bit reproducibly.
#include "mwst/generate.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "mwst/error.hpp"

namespace mwst {

namespace {

// The point at parameter t = 2πk/n on the unit circle. Only 0 < t < π/4 is evaluated with
// cos/sin; the other octants are exact mirror images, so the set is exactly symmetric about both
// axes (and the diagonals when 8 | n) and its symmetric quadruples are exactly cocircular.
Point unit_circle_point(std::size_t k, std::size_t n) {
  if (k == 0) return {1.0, 0.0};
  if (2 * k > n) {  // lower half: mirror of t' = 2π - t
    const Point p = unit_circle_point(n - k, n);
    return {p.x, -p.y};
  }
  if (2 * k == n) return {-1.0, 0.0};
  if (n % 2 == 0 && 4 * k > n) {  // second quadrant: mirror of t' = π - t
    const Point p = unit_circle_point(n / 2 - k, n);
    return {-p.x, p.y};
  }
  if (4 * k == n) return {0.0, 1.0};
  if (n % 4 == 0 && 8 * k > n) {  // upper octant of the first quadrant: mirror of t' = π/2 - t
    const Point p = unit_circle_point(n / 4 - k, n);
    return {p.y, p.x};
  }
  if (8 * k == n) {
    const double h = std::sqrt(0.5);  // correctly rounded, so both coordinates agree
    return {h, h};
  }
  const double t = (static_cast<double>(2 * k) / static_cast<double>(n)) * std::numbers::pi;
  return {snap_to_range(std::cos(t)), snap_to_range(std::sin(t))};
}

// A direction uniform in angle, by rejection from the square [-1, 1)² onto the unit disk: only
// +, *, / and sqrt, which IEEE 754 rounds identically everywhere.
Point uniform_direction(std::mt19937_64& rng) {
  for (;;) {
    const double x = 2.0 * unit_double(rng()) - 1.0;
    const double y = 2.0 * unit_double(rng()) - 1.0;
    const double r2 = x * x + y * y;
    if (r2 > 0.0 && r2 <= 1.0) {
      const double r = std::sqrt(r2);
      return {x / r, y / r};
    }
  }
}

}  // namespace

std::string_view distribution_name(Distribution d) {
  switch (d) {
    case Distribution::kUniform: return "uniform";
    case Distribution::kKuzmin: return "kuzmin";
    case Distribution::kEllipse: return "ellipse";
    case Distribution::kGrid: return "grid";
    case Distribution::kCircle: return "circle";
  }
  throw InternalError("distribution_name: unknown distribution");
}

std::optional<Distribution> parse_distribution(std::string_view name) {
  for (const Distribution d : {Distribution::kUniform, Distribution::kKuzmin, Distribution::kEllipse,
                               Distribution::kGrid, Distribution::kCircle}) {
    if (distribution_name(d) == name) return d;
  }
  return std::nullopt;
}

std::vector<Point> generate_points(Distribution d, std::size_t n, std::uint64_t seed) {
  std::vector<Point> points;
  points.reserve(n);
  std::mt19937_64 rng(seed);
  switch (d) {
    case Distribution::kUniform:
      for (std::size_t i = 0; i < n; ++i) {
        const double x = unit_double(rng());
        const double y = unit_double(rng());
        points.push_back({x, y});
      }
      break;
    case Distribution::kKuzmin:
      // Kuzmin's disk: mass within radius r is 1 - 1/sqrt(1 + r²); inverting at u gives
      // r = sqrt(1/(1-u)² - 1) (Blelloch et al., "Design and implementation of a practical
      // parallel Delaunay algorithm", 1999). r < 2⁵³, far inside the supported range.
      for (std::size_t i = 0; i < n; ++i) {
        const Point dir = uniform_direction(rng);
        const double u = unit_double(rng());
        const double one_minus = 1.0 - u;
        const double r = std::sqrt(1.0 / (one_minus * one_minus) - 1.0);
        points.push_back({snap_to_range(r * dir.x), snap_to_range(r * dir.y)});
      }
      break;
    case Distribution::kEllipse:
      for (std::size_t k = 0; k < n; ++k) {
        const Point p = unit_circle_point(k, n);
        points.push_back({p.x, 0.5 * p.y});  // scaling by 0.5 is exact
      }
      break;
    case Distribution::kGrid: {
      std::size_t columns = static_cast<std::size_t>(std::sqrt(static_cast<double>(n)));
      while (columns * columns < n) ++columns;  // exact ceil(sqrt n)
      while (columns > 1 && (columns - 1) * (columns - 1) >= n) --columns;
      for (std::size_t i = 0; i < n; ++i) {
        points.push_back({static_cast<double>(i % columns), static_cast<double>(i / columns)});
      }
      break;
    }
    case Distribution::kCircle:
      for (std::size_t k = 0; k < n; ++k) points.push_back(unit_circle_point(k, n));
      break;
  }
  return points;
}

namespace io {

std::string node_text(const std::vector<Point>& points, std::string_view comment) {
  std::string s;
  s.reserve(64 + comment.size() + points.size() * 48);
  while (!comment.empty()) {
    const std::size_t end = comment.find('\n');
    s += "# ";
    s += comment.substr(0, end);
    s += '\n';
    if (end == std::string_view::npos) break;
    comment.remove_prefix(end + 1);
  }
  char buf[32];
  auto append = [&](auto value) {
    const auto r = std::to_chars(buf, buf + sizeof buf, value);  // shortest round-trip for doubles
    s.append(buf, r.ptr);
  };
  append(points.size());
  s += " 2 0 0\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    append(i + 1);
    s += ' ';
    append(points[i].x);
    s += ' ';
    append(points[i].y);
    s += '\n';
  }
  return s;
}

}  // namespace io

}  // namespace mwst
