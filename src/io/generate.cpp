// Synthetic inputs (mwst/io/generate.hpp): the distributions of the synthetic data sets of
// Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight" (uniform, Kuzmin, ellipse),
// degenerate and multi-scale point sets (integer grid, circle, spiral, clusters) and polygons that
// stress meshers (circular holes, a narrow fan, a thin strip, a fractal coastline), generated
// bit-for-bit reproducibly.
#include "mwst/io/generate.hpp"

#include <algorithm>
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

// ceil(sqrt(n)) in exact integer arithmetic (the rounded sqrt is corrected by at most a step).
std::size_t ceil_sqrt(std::size_t n) {
  std::size_t c = static_cast<std::size_t>(std::sqrt(static_cast<double>(n)));
  while (c * c < n) ++c;
  while (c > 1 && (c - 1) * (c - 1) >= n) --c;
  return c;
}

// floor(sqrt(n)), exactly.
std::size_t floor_sqrt(std::size_t n) {
  std::size_t f = static_cast<std::size_t>(std::sqrt(static_cast<double>(n)));
  while (f * f > n) --f;
  while ((f + 1) * (f + 1) <= n) ++f;
  return f;
}

// A closed ring of segments through points [first, first + count) in order.
void add_ring(Pslg& g, std::size_t first, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = i + 1 == count ? 0 : i + 1;
    g.segments.push_back({static_cast<std::uint32_t>(first + i), static_cast<std::uint32_t>(first + j), 1});
  }
}

// `count` points strictly inside the segment from a to b, evenly spaced, in order from a.
void add_between(std::vector<Point>& out, Point a, Point b, std::size_t count) {
  for (std::size_t j = 1; j <= count; ++j) {
    const double t = static_cast<double>(j) / static_cast<double>(count + 1);
    out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
}

// Square [0, g]² with g² regular kHolePolygonPoints-gon holes of radius 1/4 (see kHoles). The
// hole vertices are centre + exact quarter of unit_circle_point, so each hole is exactly symmetric.
void make_holes(Pslg& g, std::size_t n) {
  const std::size_t m = kHolePolygonPoints;
  const std::size_t side = floor_sqrt((n - 4) / m);
  const std::size_t boundary = n - side * side * m;  // >= 4
  const double s = static_cast<double>(side);
  const Point corners[4] = {{0.0, 0.0}, {s, 0.0}, {s, s}, {0.0, s}};
  for (std::size_t c = 0; c < 4; ++c) {
    g.points.push_back(corners[c]);
    const std::size_t extra = (boundary - 4) / 4 + (c < (boundary - 4) % 4 ? 1 : 0);
    add_between(g.points, corners[c], corners[(c + 1) % 4], extra);
  }
  add_ring(g, 0, boundary);
  for (std::size_t i = 0; i < side; ++i) {
    for (std::size_t j = 0; j < side; ++j) {
      const Point centre{static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5};
      const std::size_t first = g.points.size();
      for (std::size_t k = 0; k < m; ++k) {
        const Point u = unit_circle_point(k, m);
        g.points.push_back({centre.x + 0.25 * u.x, centre.y + 0.25 * u.y});
      }
      add_ring(g, first, m);
      g.holes.push_back(centre);
    }
  }
}

// The narrow fan (see kFan): apex, then 2w + 1 vertices alternating radius 1 / kFanInnerRadius,
// and for odd n the midpoint of the closing edge (exactly on it: halving is exact).
void make_fan(Pslg& g, std::size_t n) {
  const std::size_t wedges = (n - 2) / 2;
  const double step_degrees = std::min(0.01, 45.0 / static_cast<double>(wedges));
  const double step = step_degrees * (std::numbers::pi / 180.0);
  g.points.push_back({0.0, 0.0});
  for (std::size_t k = 0; k <= 2 * wedges; ++k) {
    const double t = static_cast<double>(k) * step;
    const double r = k % 2 == 0 ? 1.0 : kFanInnerRadius;
    g.points.push_back({snap_to_range(r * std::cos(t)), snap_to_range(r * std::sin(t))});
  }
  if (n % 2 == 1) {
    const Point last = g.points.back();
    g.points.push_back({0.5 * last.x, 0.5 * last.y});
  }
  add_ring(g, 0, g.points.size());
}

// The rectangle [0, 1] × [0, 1e-3] with n vertices: corners and the rest on the long sides.
void make_strip(Pslg& g, std::size_t n) {
  constexpr double kWidth = 1e-3;
  const std::size_t bottom = (n - 4 + 1) / 2, top = (n - 4) / 2;
  g.points.push_back({0.0, 0.0});
  add_between(g.points, {0.0, 0.0}, {1.0, 0.0}, bottom);
  g.points.push_back({1.0, 0.0});
  g.points.push_back({1.0, kWidth});
  add_between(g.points, {1.0, kWidth}, {0.0, kWidth}, top);
  g.points.push_back({0.0, kWidth});
  add_ring(g, 0, n);
}

// The fractal coastline (see kCoastline). Random midpoint displacement (Fournier, Fussell,
// Carpenter, "Computer rendering of stochastic models", CACM 1982) on a periodic array: 8 values
// uniform in [-1, 1), then each level inserts between neighbours their mean plus a uniform
// displacement whose amplitude shrinks by 2^-H per level, H = 3/4, until the array has at least n
// values; the n vertices sample it linearly at θ = 2πk/n. Vertices at strictly increasing angles
// with positive radii make a star-shaped, hence simple, polygon.
void make_coastline(Pslg& g, std::size_t n, std::mt19937_64& rng) {
  const double shrink = 1.0 / std::sqrt(std::sqrt(8.0));  // 2^-(3/4), by correctly rounded sqrt
  std::vector<double> level;
  for (int j = 0; j < 8; ++j) level.push_back(2.0 * unit_double(rng()) - 1.0);
  double amplitude = 1.0;
  std::vector<double> finer;
  while (level.size() < n) {
    amplitude *= shrink;
    finer.clear();
    for (std::size_t j = 0; j < level.size(); ++j) {
      const double next = level[j + 1 == level.size() ? 0 : j + 1];
      finer.push_back(level[j]);
      finer.push_back(0.5 * (level[j] + next) + amplitude * (2.0 * unit_double(rng()) - 1.0));
    }
    level.swap(finer);
  }
  const std::uint64_t size = level.size();
  std::vector<double> f(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t at = static_cast<std::uint64_t>(k) * size;  // position k·size/n, exactly
    const std::uint64_t q = at / n;
    const double t = static_cast<double>(at % n) / static_cast<double>(n);
    f[k] = (1.0 - t) * level[q] + t * level[(q + 1) % size];
  }
  const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
  const double low = *lo, span = *hi - *lo;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = span > 0.0 ? 0.5 + (f[k] - low) / span : 1.0;
    const Point u = unit_circle_point(k, n);
    g.points.push_back({snap_to_range(r * u.x), snap_to_range(r * u.y)});
  }
  add_ring(g, 0, n);
}

}  // namespace

std::string_view distribution_name(Distribution d) {
  switch (d) {
    case Distribution::kUniform: return "uniform";
    case Distribution::kKuzmin: return "kuzmin";
    case Distribution::kEllipse: return "ellipse";
    case Distribution::kGrid: return "grid";
    case Distribution::kCircle: return "circle";
    case Distribution::kSpiral: return "spiral";
    case Distribution::kClusters: return "clusters";
    case Distribution::kHoles: return "holes";
    case Distribution::kFan: return "fan";
    case Distribution::kStrip: return "strip";
    case Distribution::kCoastline: return "coastline";
  }
  throw InternalError("distribution_name: unknown distribution");
}

std::vector<Distribution> all_distributions() {
  return {Distribution::kUniform, Distribution::kKuzmin,   Distribution::kEllipse, Distribution::kGrid,
          Distribution::kCircle,  Distribution::kSpiral,   Distribution::kClusters, Distribution::kHoles,
          Distribution::kFan,     Distribution::kStrip,    Distribution::kCoastline};
}

std::optional<Distribution> parse_distribution(std::string_view name) {
  for (const Distribution d : all_distributions()) {
    if (distribution_name(d) == name) return d;
  }
  return std::nullopt;
}

bool has_segments(Distribution d) {
  return d == Distribution::kHoles || d == Distribution::kFan || d == Distribution::kStrip ||
         d == Distribution::kCoastline;
}

bool uses_seed(Distribution d) {
  return d == Distribution::kUniform || d == Distribution::kKuzmin || d == Distribution::kClusters ||
         d == Distribution::kCoastline;
}

std::size_t minimum_count(Distribution d) {
  switch (d) {
    case Distribution::kHoles: return 4 + kHolePolygonPoints;  // the square and one hole
    case Distribution::kFan: return 4;                          // apex and one wedge
    case Distribution::kStrip: return 4;
    case Distribution::kCoastline: return 3;
    default: return 1;
  }
}

Pslg generate_input(Distribution d, std::size_t n, std::uint64_t seed) {
  if (n < minimum_count(d)) {
    throw InputError("", 0, "generate " + std::string(distribution_name(d)) + ": N must be at least " +
                     std::to_string(minimum_count(d)) + ", found " + std::to_string(n));
  }
  Pslg g;
  g.source = "generate " + std::string(distribution_name(d));
  if (!has_segments(d)) {
    g.points = generate_points(d, n, seed);
  } else {
    g.is_poly = true;
    g.points.reserve(n);
    g.segments.reserve(n);
    std::mt19937_64 rng(seed);
    switch (d) {
      case Distribution::kHoles: make_holes(g, n); break;
      case Distribution::kFan: make_fan(g, n); break;
      case Distribution::kStrip: make_strip(g, n); break;
      case Distribution::kCoastline: make_coastline(g, n, rng); break;
      default: throw InternalError("generate_input: not a polygon class");
    }
  }
  g.point_markers.assign(g.points.size(), 0);
  return g;
}

std::vector<Point> generate_points(Distribution d, std::size_t n, std::uint64_t seed) {
  if (has_segments(d)) return generate_input(d, n, seed).points;
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
      const std::size_t columns = ceil_sqrt(n);
      for (std::size_t i = 0; i < n; ++i) {
        points.push_back({static_cast<double>(i % columns), static_cast<double>(i / columns)});
      }
      break;
    }
    case Distribution::kCircle:
      for (std::size_t k = 0; k < n; ++k) points.push_back(unit_circle_point(k, n));
      break;
    case Distribution::kSpiral:
      // Arc length of r = aθ grows like θ², so θ ∝ sqrt(k) spaces the points nearly evenly.
      for (std::size_t k = 0; k < n; ++k) {
        const double r = std::sqrt((static_cast<double>(k) + 0.5) / static_cast<double>(n));
        const double t = 2.0 * std::numbers::pi * kSpiralTurns * r;
        points.push_back({snap_to_range(r * std::cos(t)), snap_to_range(r * std::sin(t))});
      }
      break;
    case Distribution::kClusters: {
      const std::size_t clusters = ceil_sqrt(n);
      std::vector<Point> centres(clusters);
      std::vector<double> radii(clusters);
      for (std::size_t c = 0; c < clusters; ++c) {
        centres[c].x = unit_double(rng());
        centres[c].y = unit_double(rng());
        radii[c] = std::ldexp(1.0, -static_cast<int>(rng() % 21));  // 2^-e, e in 0..20: exact
      }
      auto offset = [&] {  // Irwin–Hall: four uniforms minus their mean, in (-2, 2)
        const double a = unit_double(rng()), b = unit_double(rng());
        const double c = unit_double(rng()), e = unit_double(rng());
        return ((a + b) + (c + e)) - 2.0;
      };
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t c = i % clusters;
        const double dx = offset();
        const double dy = offset();
        points.push_back({snap_to_range(centres[c].x + radii[c] * dx), snap_to_range(centres[c].y + radii[c] * dy)});
      }
      break;
    }
    default: throw InternalError("generate_points: unknown distribution");
  }
  return points;
}

namespace io {

namespace {
// Appends an integer, or a double as its shortest round-trip decimal.
template <typename T>
void append_decimal(std::string& s, T value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  s.append(buf, r.ptr);
}
}  // namespace

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
  auto append = [&s](auto value) { append_decimal(s, value); };
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

std::string poly_text(const Pslg& pslg, std::string_view comment) {
  std::string s = node_text(pslg.points, comment);
  s.reserve(s.size() + pslg.segments.size() * 24 + pslg.holes.size() * 48 + 32);
  auto append = [&s](auto value) { append_decimal(s, value); };
  append(pslg.segments.size());
  s += " 1\n";
  for (std::size_t i = 0; i < pslg.segments.size(); ++i) {
    const Segment& e = pslg.segments[i];
    append(i + 1), s += ' ', append(std::size_t{e.a} + 1), s += ' ', append(std::size_t{e.b} + 1);
    s += ' ', append(e.marker), s += '\n';
  }
  append(pslg.holes.size());
  s += '\n';
  for (std::size_t i = 0; i < pslg.holes.size(); ++i) {
    append(i + 1), s += ' ', append(pslg.holes[i].x), s += ' ', append(pslg.holes[i].y), s += '\n';
  }
  return s;
}

}  // namespace io

}  // namespace mwst
