// _mwst: the compiled half of the Python package `mwst` (python/mwst/__init__.py is the other).
//
// Every call here takes numpy arrays that the Python side has already made C-contiguous with the
// dtype asked for (float64 coordinates, int64 indices, int32 markers): a contiguous float64 vertex
// array the caller passes is the very array read here, never converted. This side checks shapes and
// builds the library's input (Pslg), then releases the GIL for the computation (so other Python
// threads run meanwhile, and two triangulations can run at once). Results are the library's own
// vectors (MeshArrays) handed to numpy without a copy: each array owns its vector via a capsule.
//
// Errors: the library's InputError (and std::invalid_argument, which it throws for unusable
// options) become mwst.InputError, a ValueError, with the library's message; ResourceError becomes
// mwst.ResourceError (a MemoryError); InternalError a RuntimeError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mwst/io/report.hpp"
#include "mwst/algorithms/arrays.hpp"
#include "mwst/algorithms/bundle.hpp"
#include "mwst/mesh/check.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/algorithms/pipeline.hpp"
#include "mwst/io/triangle_switches.hpp"
#include "mwst/version.hpp"

namespace py = pybind11;

namespace {

static_assert(sizeof(mwst::Point) == 2 * sizeof(double) && std::is_standard_layout_v<mwst::Point>,
              "an (n, 2) float64 array is read as an array of Points");

using DoubleArray = py::array_t<double, py::array::c_style>;
using IndexArray = py::array_t<std::int64_t, py::array::c_style>;
using MarkerArray = py::array_t<std::int32_t, py::array::c_style>;

[[noreturn]] void input_error(const std::string& message) { throw mwst::InputError("", 0, message); }

// The library's option fields (mwst::TriangulateOptions) that mwst.triangulate takes under another
// keyword: an error message naming a field names the keyword instead.
constexpr std::array<std::pair<std::string_view, std::string_view>, 2> kKeywordOfField{{
    {"min_angle_deg", "min_angle"},
    {"time_budget_seconds", "time_limit"},
}};

bool is_name_char(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'; }

// `message` with each whole-word library field name of kKeywordOfField replaced by its keyword.
std::string with_python_keywords(std::string message) {
  for (const auto& [field, keyword] : kKeywordOfField) {
    for (std::size_t at = message.find(field); at != std::string::npos; at = message.find(field, at)) {
      const std::size_t end = at + field.size();
      if ((at > 0 && is_name_char(message[at - 1])) || (end < message.size() && is_name_char(message[end]))) {
        at = end;
        continue;
      }
      message.replace(at, field.size(), keyword);
      at += keyword.size();
    }
  }
  return message;
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// The rows of an (n, columns) array; InputError naming `name` otherwise.
std::size_t rows(const py::array& a, py::ssize_t columns, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != columns) {
    input_error(std::string(name) + ": expected an (n, " + std::to_string(columns) + ") array, got shape " +
                shape_text(a));
  }
  return static_cast<std::size_t>(a.shape(0));
}

// The n points of an (n, 2) float64 array, read in place (one copy, into the library's input, on
// `threads` threads: 0 for all).
std::vector<mwst::Point> points_of(const DoubleArray& a, const char* name, unsigned threads = 0) {
  return mwst::points_from_xy(a.data(), rows(a, 2, name), threads);
}

// An index that fits no point (negative, or past 2^32) becomes one past any point the library
// accepts, so that the library's own check reports it ("segment names a vertex that does not exist").
std::uint32_t index_of(std::int64_t i) {
  return i < 0 || i > std::numeric_limits<std::uint32_t>::max() ? std::numeric_limits<std::uint32_t>::max()
                                                                 : static_cast<std::uint32_t>(i);
}

std::vector<std::int32_t> markers_of(const std::optional<MarkerArray>& a, std::size_t n, const char* name) {
  if (!a) return {};
  if (a->ndim() != 1 || static_cast<std::size_t>(a->shape(0)) != n) {
    input_error(std::string(name) + ": expected " + std::to_string(n) + " markers (one per row), got shape " +
                shape_text(*a));
  }
  return {a->data(), a->data() + n};
}

// The library's input graph from the arrays (segments' markers default to 1, as Triangle's do).
mwst::Pslg pslg_of(const DoubleArray& vertices, const std::optional<IndexArray>& segments,
                   const std::optional<MarkerArray>& segment_markers, const std::optional<MarkerArray>& vertex_markers,
                   const std::optional<DoubleArray>& holes, const std::optional<DoubleArray>& regions,
                   unsigned threads = 0) {
  mwst::Pslg pslg;
  pslg.points = points_of(vertices, "vertices", threads);
  pslg.point_markers = markers_of(vertex_markers, pslg.points.size(), "vertex_markers");
  if (segments) {
    const std::size_t m = rows(*segments, 2, "segments");
    const std::vector<std::int32_t> markers = markers_of(segment_markers, m, "segment_markers");
    const std::int64_t* ends = segments->data();
    pslg.segments.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      pslg.segments[i] = {index_of(ends[2 * i]), index_of(ends[2 * i + 1]), markers.empty() ? 1 : markers[i]};
    }
    pslg.is_poly = true;
  } else if (segment_markers) {
    input_error("segment_markers given without segments");
  }
  if (holes) pslg.holes = points_of(*holes, "holes");
  if (regions) {
    const std::size_t r = rows(*regions, 4, "regions");
    const double* row = regions->data();
    for (std::size_t i = 0; i < r; ++i, row += 4) pslg.regions.push_back({{row[0], row[1]}, row[2], row[3], 0});
  }
  pslg.first_index = 0;
  return pslg;
}

// A numpy array owning `values` (moved to the heap; freed when the array is), of `dtype` (whose
// items must have the size of T's), in `shape`.
template <class T>
py::array adopt(std::vector<T>&& values, std::vector<py::ssize_t> shape, const py::dtype& dtype) {
  auto* heap = new std::vector<T>(std::move(values));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array(dtype, std::move(shape), heap->data(), owner);
}
template <class T>
py::array adopt(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  return adopt(std::move(values), std::move(shape), py::dtype::of<T>());
}

// Vertex indices as int32 (the `triangle` package's dtype, and signed like the neighbours' -1):
// the library's uint32 indices read as int32 in place while they fit, which they do below 2^31
// vertices; otherwise a copy as int64.
py::array indices(std::vector<std::uint32_t>&& values, std::size_t columns, std::size_t vertex_count) {
  const auto n = static_cast<py::ssize_t>(values.size() / columns);
  if (vertex_count <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    return adopt(std::move(values), {n, static_cast<py::ssize_t>(columns)}, py::dtype::of<std::int32_t>());
  }
  std::vector<std::int64_t> wide(values.begin(), values.end());
  return adopt(std::move(wide), {n, static_cast<py::ssize_t>(columns)});
}

py::dict arrays_dict(mwst::MeshArrays&& a) {
  const std::size_t nv = a.vertex_count(), nt = a.triangle_count(), ns = a.segment_count();
  py::dict out;
  out["vertices"] = adopt(std::move(a.vertices), {static_cast<py::ssize_t>(nv), 2});
  static_assert(sizeof(mwst::ArrayVertexKind) == 1);
  out["vertex_kind"] = adopt(std::move(a.vertex_kinds), {static_cast<py::ssize_t>(nv)}, py::dtype::of<std::uint8_t>());
  out["vertex_markers"] = adopt(std::move(a.vertex_markers), {static_cast<py::ssize_t>(nv)});
  out["triangles"] = indices(std::move(a.triangles), 3, nv);
  out["neighbors"] = adopt(std::move(a.neighbours), {static_cast<py::ssize_t>(nt), 3});
  out["segments"] = indices(std::move(a.segments), 2, nv);
  out["segment_markers"] = adopt(std::move(a.segment_markers), {static_cast<py::ssize_t>(ns)});
  if (a.triangle_attributes.empty()) {
    out["triangle_attributes"] = py::none();
  } else {
    out["triangle_attributes"] = adopt(std::move(a.triangle_attributes), {static_cast<py::ssize_t>(nt)});
  }
  return out;
}

mwst::Method method_of(const std::string& name) {
  if (const auto m = mwst::parse_method(name)) return *m;
  input_error("method: expected one of dt, dr, brh, qtr, opt, got '" + name + "'");
}

mwst::SteinerRule steiner_of(const std::string& name) {
  if (const auto r = mwst::parse_steiner_rule(name)) return *r;
  input_error("steiner: expected offcenter or circumcenter, got '" + name + "'");
}

std::size_t whole_number(std::int64_t value, const char* name) {
  if (value < 0) input_error(std::string(name) + ": expected a whole number >= 0, got " + std::to_string(value));
  return static_cast<std::size_t>(value);
}

py::dict triangulate(const DoubleArray& vertices, const std::optional<IndexArray>& segments,
                     const std::optional<DoubleArray>& holes, const std::optional<DoubleArray>& regions,
                     const std::optional<MarkerArray>& vertex_markers, const std::optional<MarkerArray>& segment_markers,
                     const std::string& method, std::optional<double> min_angle, const std::string& steiner,
                     std::optional<double> max_area, std::optional<std::int64_t> max_steiner,
                     std::optional<std::int64_t> bundle_k, bool flip, bool convex_hull, bool strict,
                     std::optional<double> time_limit, std::int64_t threads, const std::string& source) {
  mwst::TriangulateOptions options;
  options.method = method_of(method);
  if (min_angle) options.min_angle_deg = *min_angle;
  options.steiner = steiner_of(steiner);
  if (max_area) {
    if (!(*max_area > 0.0)) input_error("max_area: expected a number > 0, got " + std::to_string(*max_area));
    options.max_area = *max_area;
  }
  if (max_steiner) options.max_steiner = whole_number(*max_steiner, "max_steiner");
  if (bundle_k) options.bundle_k = whole_number(*bundle_k, "bundle_k");
  options.flip = flip;
  options.convex_hull = convex_hull;
  options.strict = strict;
  if (time_limit) {
    if (!(*time_limit > 0.0)) input_error("time_limit: expected seconds > 0, got " + std::to_string(*time_limit));
    options.time_budget_seconds = *time_limit;
  }
  options.threads = static_cast<unsigned>(whole_number(threads, "threads"));
  mwst::check_options(options);

  mwst::Pslg pslg = pslg_of(vertices, segments, segment_markers, vertex_markers, holes, regions, options.threads);
  pslg.source = source;
  mwst::MeshArrays arrays;
  std::string report;
  double seconds = 0.0;  // the library's whole call: triangulate() and to_arrays()
  {
    py::gil_scoped_release unlocked;
    const auto start = std::chrono::steady_clock::now();
    arrays = mwst::triangulate_arrays(pslg, options);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report = mwst::to_json(arrays.report).dump();
  }
  py::dict out = arrays_dict(std::move(arrays));
  out["report"] = report;
  out["library_seconds"] = seconds;
  return out;
}

std::vector<std::array<std::uint32_t, 3>> triangles_of(const IndexArray& triangles, std::size_t vertex_count,
                                                       const char* name) {
  const std::size_t m = rows(triangles, 3, name);
  std::vector<std::array<std::uint32_t, 3>> out(m);
  const std::int64_t* corners = triangles.data();
  for (std::size_t t = 0; t < m; ++t) {
    for (std::size_t i = 0; i < 3; ++i) {
      const std::int64_t v = corners[3 * t + i];
      if (v < 0 || static_cast<std::uint64_t>(v) >= vertex_count) {
        input_error(std::string(name) + ": triangle " + std::to_string(t) + " names vertex " + std::to_string(v) +
                    ", but there are " + std::to_string(vertex_count) + " vertices");
      }
      out[t][i] = static_cast<std::uint32_t>(v);
    }
  }
  return out;
}

py::dict bundle_number(const DoubleArray& vertices, const IndexArray& triangles, std::int64_t candidate_budget,
                       std::int64_t threads) {
  const std::vector<mwst::Point> points = points_of(vertices, "vertices");
  const auto list = triangles_of(triangles, points.size(), "triangles");
  mwst::BundleOptions options;
  // The command line's default (mwst bundle): 24 candidate pairs per triangle plus 2^20.
  options.candidate_budget = candidate_budget >= 0 ? static_cast<std::size_t>(candidate_budget)
                                                   : 24 * list.size() + (std::size_t{1} << 20);
  options.threads = static_cast<unsigned>(whole_number(threads, "threads"));
  mwst::BundleResult r;
  {
    py::gil_scoped_release unlocked;
    r = mwst::bundle_number(points, list, options);
  }
  py::dict out;
  out["bundle_number"] = r.bundle_number;
  out["exact"] = r.exact;
  out["lower_bound"] = r.lower_bound;
  out["upper_bound"] = r.upper_bound;
  out["center"] = py::make_tuple(r.disk_center.x, r.disk_center.y);
  out["radius"] = r.disk_radius;
  std::vector<std::int64_t> witness(r.triangles.begin(), r.triangles.end());
  out["triangles"] = adopt(std::move(witness), {static_cast<py::ssize_t>(r.triangles.size())});
  out["circumdisk_bound"] = r.circumdisk_bound;
  return out;
}

std::vector<mwst::Segment> subsegments_of(const std::optional<IndexArray>& segments, std::size_t vertex_count) {
  std::vector<mwst::Segment> out;
  if (!segments) return out;
  const std::size_t m = rows(*segments, 2, "mesh segments");
  const std::int64_t* ends = segments->data();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t k = 0; k < 2; ++k) {
      if (ends[2 * i + k] < 0 || static_cast<std::uint64_t>(ends[2 * i + k]) >= vertex_count) {
        input_error("mesh segments: segment " + std::to_string(i) + " names vertex " + std::to_string(ends[2 * i + k]) +
                    ", but the mesh has " + std::to_string(vertex_count) + " vertices");
      }
    }
    out.push_back({static_cast<std::uint32_t>(ends[2 * i]), static_cast<std::uint32_t>(ends[2 * i + 1]), 1});
  }
  return out;
}

py::dict check(const DoubleArray& vertices, const std::optional<IndexArray>& segments,
               const std::optional<DoubleArray>& holes, const DoubleArray& mesh_vertices,
               const IndexArray& mesh_triangles, const std::optional<IndexArray>& mesh_segments, bool delaunay,
               double min_angle, std::int64_t max_messages) {
  mwst::Pslg input = pslg_of(vertices, segments, std::nullopt, std::nullopt, holes, std::nullopt);
  const std::vector<mwst::Point> points = points_of(mesh_vertices, "mesh vertices");
  const auto triangles = triangles_of(mesh_triangles, points.size(), "mesh triangles");
  const std::vector<mwst::Segment> subsegments = subsegments_of(mesh_segments, points.size());
  mwst::CheckOptions options;
  options.delaunay = delaunay;
  options.min_angle_deg = min_angle;
  options.max_messages = whole_number(max_messages, "max_messages");
  mwst::CheckResult r;
  {
    py::gil_scoped_release unlocked;
    r = mwst::check_triangulation(input, points, triangles, subsegments, options);
  }
  py::dict out;
  out["ok"] = r.ok();
  out["violations"] = r.violations;
  out["messages"] = r.messages;
  out["convex_hull"] = r.convex_hull;
  out["area"] = r.area;
  out["domain_area"] = r.domain_area;
  return out;
}

py::array points_array(std::vector<mwst::Point>&& points) {
  std::vector<double> flat(2 * points.size());
  if (!points.empty()) std::memcpy(flat.data(), static_cast<const void*>(points.data()), flat.size() * sizeof(double));
  return adopt(std::move(flat), {static_cast<py::ssize_t>(points.size()), 2});
}

py::array segment_ends(const std::vector<mwst::Segment>& segments) {
  std::vector<std::int64_t> ends;
  ends.reserve(2 * segments.size());
  for (const mwst::Segment& s : segments) {
    ends.push_back(s.a);
    ends.push_back(s.b);
  }
  return adopt(std::move(ends), {static_cast<py::ssize_t>(segments.size()), 2});
}

py::array segment_markers(const std::vector<mwst::Segment>& segments) {
  std::vector<std::int32_t> markers;
  markers.reserve(segments.size());
  for (const mwst::Segment& s : segments) markers.push_back(s.marker);
  return adopt(std::move(markers), {static_cast<py::ssize_t>(segments.size())});
}

// A .node or .poly (io::read_input): the input graph, indices from 0.
py::dict read_input(const std::string& path) {
  mwst::Pslg pslg;
  {
    py::gil_scoped_release unlocked;
    pslg = mwst::io::read_input(path);
  }
  py::dict out;
  const std::size_t n = pslg.points.size();
  std::vector<std::int32_t> markers = pslg.point_markers;
  markers.resize(n, 0);
  out["vertices"] = points_array(std::move(pslg.points));
  out["vertex_markers"] = adopt(std::move(markers), {static_cast<py::ssize_t>(n)});
  out["segments"] = segment_ends(pslg.segments);
  out["segment_markers"] = segment_markers(pslg.segments);
  out["holes"] = points_array(std::move(pslg.holes));
  std::vector<double> regions;
  for (const mwst::Region& r : pslg.regions) regions.insert(regions.end(), {r.seed.x, r.seed.y, r.attribute, r.max_area});
  out["regions"] = adopt(std::move(regions), {static_cast<py::ssize_t>(pslg.regions.size()), 4});
  out["is_poly"] = pslg.is_poly;
  out["first_index"] = pslg.first_index;
  out["source"] = pslg.source;
  return out;
}

// PREFIX.node / .ele (/ .poly) (io::read_mesh), indices from 0.
py::dict read_mesh(const std::string& prefix) {
  mwst::io::MeshFiles mesh;
  {
    py::gil_scoped_release unlocked;
    mesh = mwst::io::read_mesh(prefix);
  }
  py::dict out;
  const std::size_t n = mesh.points.size();
  std::vector<std::uint32_t> corners;
  corners.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) corners.insert(corners.end(), t.begin(), t.end());
  out["vertices"] = points_array(std::move(mesh.points));
  out["triangles"] = indices(std::move(corners), 3, n);
  out["segments"] = segment_ends(mesh.segments);
  out["segment_markers"] = segment_markers(mesh.segments);
  return out;
}

// Writes the mesh given as arrays with the library's writer (io::format_triangle_files with
// io::mesh_files' choice: PREFIX.node, .ele and, with segments, .poly; io::write_triangle_files:
// each atomically). The writer reads flat arrays (MeshArrays): the neighbours across the edges of
// the given triangles are found here, and every segment must be an edge of them.
void write_mesh(const std::string& prefix, const DoubleArray& vertices, const std::optional<MarkerArray>& vertex_markers,
                const IndexArray& triangles, const std::optional<IndexArray>& segments,
                const std::optional<MarkerArray>& segment_markers, int first_index,
                const std::optional<DoubleArray>& holes, const std::optional<DoubleArray>& regions) {
  if (first_index != 0 && first_index != 1) input_error("first_index: expected 0 or 1");
  // The input's holes and regions, for the .poly (so that re-meshing it gives the same domain).
  const mwst::Pslg domain = pslg_of(vertices, std::nullopt, std::nullopt, std::nullopt, holes, regions);
  const std::size_t n = domain.points.size();
  mwst::MeshArrays mesh;
  mesh.vertices.resize(2 * n);
  if (n > 0) std::memcpy(mesh.vertices.data(), static_cast<const void*>(domain.points.data()), 2 * n * sizeof(double));
  mesh.vertex_kinds.assign(n, mwst::ArrayVertexKind::kInput);
  mesh.vertex_markers = markers_of(vertex_markers, n, "vertex_markers");
  mesh.vertex_markers.resize(n, 0);
  const auto list = triangles_of(triangles, n, "triangles");
  mesh.neighbours.assign(3 * list.size(), -1);
  // Edge k of a triangle is opposite corner k: from corner k+1 to corner k+2. The first triangle
  // seen with an edge waits in `edge_at` for the second.
  std::unordered_map<std::uint64_t, std::size_t> edge_at;  // undirected edge → 3 * triangle + k
  auto key = [](std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
  };
  for (std::size_t t = 0; t < list.size(); ++t) {
    mesh.triangles.insert(mesh.triangles.end(), list[t].begin(), list[t].end());
    for (unsigned k = 0; k < 3; ++k) {
      const auto [at, first] = edge_at.emplace(key(list[t][mwst::next3(k)], list[t][mwst::prev3(k)]), 3 * t + k);
      if (first) continue;
      mesh.neighbours[3 * t + k] = static_cast<std::int32_t>(at->second / 3);
      mesh.neighbours[at->second] = static_cast<std::int32_t>(t);
    }
  }
  if (segments) {
    const std::vector<mwst::Segment> subsegments = subsegments_of(segments, n);
    const std::vector<std::int32_t> markers = markers_of(segment_markers, subsegments.size(), "segment_markers");
    for (std::size_t i = 0; i < subsegments.size(); ++i) {
      if (edge_at.count(key(subsegments[i].a, subsegments[i].b)) == 0) {
        input_error("segments: segment " + std::to_string(i) + " (" + std::to_string(subsegments[i].a) + ", " +
                    std::to_string(subsegments[i].b) + ") is not an edge of the triangles");
      }
      mesh.segments.insert(mesh.segments.end(), {subsegments[i].a, subsegments[i].b});
      mesh.segment_markers.push_back(markers.empty() ? 1 : markers[i]);
    }
  }
  py::gil_scoped_release unlocked;
  mwst::io::write_triangle_files(prefix, mwst::io::format_triangle_files(mesh, domain.holes, domain.regions,
                                                                         mwst::io::mesh_files(mesh, first_index)));
}

const char* segment_splitting_name(mwst::SegmentSplitting s) {
  switch (s) {
    case mwst::SegmentSplitting::kAllowed: return "allowed";
    case mwst::SegmentSplitting::kNotBoundary: return "not_boundary";
    case mwst::SegmentSplitting::kNever: return "never";
  }
  return "";
}

// What the library's parser makes of a Triangle switch string: the TriangleSwitches fields and
// the options they set (the field names of TriangleSwitches and TriangulateOptions).
py::dict switches_dict(const mwst::TriangleSwitches& s) {
  py::dict out;
  const mwst::TriangulateOptions& o = s.options;
  out["method"] = std::string(mwst::method_name(o.method));
  out["min_angle"] = o.min_angle_deg;
  out["max_area"] = o.max_area > 0.0 ? py::object(py::float_(o.max_area)) : py::object(py::none());
  out["max_steiner"] = o.max_steiner == std::numeric_limits<std::size_t>::max() ? py::object(py::none())
                                                                                : py::object(py::int_(o.max_steiner));
  out["convex_hull"] = o.convex_hull;
  out["conforming_delaunay"] = o.conforming_delaunay;
  out["segment_splitting"] = segment_splitting_name(o.segment_splitting);
  out["regional_area_limits"] = o.regional_area_limits;
  out["poly"] = s.poly;
  out["refine"] = s.refine;
  out["quality"] = s.quality;
  out["region_attributes"] = s.region_attributes;
  out["edges"] = s.edges;
  out["neighbours"] = s.neighbours;
  out["voronoi"] = s.voronoi;
  out["zero_based"] = s.zero_based;
  out["jettison"] = s.jettison;
  out["no_boundary_markers"] = s.no_boundary_markers;
  out["no_poly_output"] = s.no_poly_output;
  out["no_node_output"] = s.no_node_output;
  out["no_ele_output"] = s.no_ele_output;
  out["no_iteration_numbers"] = s.no_iteration_numbers;
  out["ignore_holes"] = s.ignore_holes;
  out["quiet"] = s.quiet;
  out["verbosity"] = s.verbosity;
  out["help"] = s.help;
  out["ignored"] = s.ignored;
  return out;
}

py::dict parse_switches(const std::string& switches) { return switches_dict(mwst::parse_triangle_switches(switches)); }

// The numbers of a text that format_triangle_files wrote, line by line (one record per line,
// numbers separated by single spaces, no comments).
struct NumberLines {
  std::vector<double> numbers;
  std::vector<std::size_t> starts{0};  // line i is numbers[starts[i], starts[i + 1])
  std::size_t count() const { return starts.size() - 1; }
  std::size_t width(std::size_t i) const { return starts[i + 1] - starts[i]; }
  double at(std::size_t i, std::size_t k) const { return numbers[starts[i] + k]; }
};

NumberLines number_lines(std::string_view text, const std::string& name) {
  NumberLines out;
  const char* p = text.data();
  const char* const end = p + text.size();
  while (p < end) {
    if (*p == '\n') {
      out.starts.push_back(out.numbers.size());
      ++p;
    } else if (*p == ' ') {
      ++p;
    } else {
      double value = 0.0;
      const auto [next, ec] = std::from_chars(p, end, value);
      if (ec != std::errc()) throw mwst::InternalError("reading back " + name + ": not a number");
      out.numbers.push_back(value);
      p = next;
    }
  }
  return out;
}

// Rows first..first+count-1 of `lines`, columns [from, from + columns), as an (count, columns) array
// of T (count taken from the header: rows may be followed by other sections, as in .poly).
template <class T>
py::array columns_of(const NumberLines& lines, std::size_t first, std::size_t count, std::size_t from,
                     std::size_t columns) {
  std::vector<T> values;
  values.reserve(count * columns);
  for (std::size_t i = first; i < first + count; ++i) {
    for (std::size_t k = from; k < from + columns; ++k) values.push_back(static_cast<T>(lines.at(i, k)));
  }
  return adopt(std::move(values), {static_cast<py::ssize_t>(count), static_cast<py::ssize_t>(columns)});
}

// One file of format_triangle_files as the `triangle` package's arrays (keys as it names them).
void read_triangle_file(const mwst::io::TriangleFile& file, py::dict& out) {
  const NumberLines lines = number_lines(file.text(), file.extension);
  const auto count = static_cast<std::size_t>(lines.at(0, 0));
  if (file.extension == ".node") {  // "N 2 A B", then "i x y [A attributes] [marker]"
    const auto attributes = static_cast<std::size_t>(lines.at(0, 2));
    out["vertices"] = columns_of<double>(lines, 1, count, 1, 2);
    if (attributes > 0) out["vertex_attributes"] = columns_of<double>(lines, 1, count, 3, attributes);
    out["vertex_markers"] = columns_of<std::int32_t>(lines, 1, count, 3 + attributes, 1);
  } else if (file.extension == ".ele") {  // "T 3 A", then "i a b c [attribute]"
    out["triangles"] = columns_of<std::int32_t>(lines, 1, count, 1, 3);
    if (lines.at(0, 2) > 0) out["triangle_attributes"] = columns_of<double>(lines, 1, count, 4, 1);
  } else if (file.extension == ".poly") {  // "0 2 0 B", "S B", then "i a b [marker]", holes, regions
    const auto segments = static_cast<std::size_t>(lines.at(1, 0));
    out["segments"] = columns_of<std::int32_t>(lines, 2, segments, 1, 2);
    out["segment_markers"] = columns_of<std::int32_t>(lines, 2, segments, 3, 1);
  } else if (file.extension == ".edge") {  // "E B", then "i a b [marker]"
    out["edges"] = columns_of<std::int32_t>(lines, 1, count, 1, 2);
    out["edge_markers"] = columns_of<std::int32_t>(lines, 1, count, 3, 1);
  } else if (file.extension == ".neigh") {  // "T 3", then "i n0 n1 n2"
    out["neighbors"] = columns_of<std::int32_t>(lines, 1, count, 1, 3);
  } else if (file.extension == ".v.node") {  // "T 2 0 0", then "i x y"
    out["voronoi_vertices"] = columns_of<double>(lines, 1, count, 1, 2);
  } else if (file.extension == ".v.edge") {  // "E 0", then "i p q" or "i p -1 dx dy" (a ray)
    std::vector<std::int32_t> ends;
    std::vector<double> directions;
    for (std::size_t i = 1; i <= count; ++i) {
      ends.push_back(static_cast<std::int32_t>(lines.at(i, 1)));
      ends.push_back(static_cast<std::int32_t>(lines.at(i, 2)));
      const bool ray = lines.width(i) == 5;
      directions.push_back(ray ? lines.at(i, 3) : 0.0);
      directions.push_back(ray ? lines.at(i, 4) : 0.0);
    }
    const auto n = static_cast<py::ssize_t>(count);
    out["voronoi_edges"] = adopt(std::move(ends), {n, 2});
    out["voronoi_directions"] = adopt(std::move(directions), {n, 2});
  }
}

// Triangle's triangulate(): the switches parsed by the library's parser give the options; the
// input graph is what they say Triangle reads (segments, holes and regions only with p, holes not
// with O, the triangles to refine with r). Returns Triangle's outputs as arrays, the report and the
// parsed switches.
py::dict triangulate_switches(const DoubleArray& vertices, const std::optional<IndexArray>& segments,
                              const std::optional<DoubleArray>& holes, const std::optional<DoubleArray>& regions,
                              const std::optional<MarkerArray>& vertex_markers,
                              const std::optional<MarkerArray>& segment_markers,
                              const std::optional<IndexArray>& triangles,
                              const std::optional<DoubleArray>& triangle_max_area,
                              const std::optional<DoubleArray>& vertex_attributes, const std::string& switches) {
  const mwst::TriangleSwitches parsed = mwst::parse_triangle_switches(switches);
  mwst::TriangulateOptions options = parsed.options;
  mwst::check_options(options);
  const bool poly = parsed.poly;
  mwst::Pslg pslg = pslg_of(vertices, poly ? segments : std::nullopt, poly ? segment_markers : std::nullopt,
                            vertex_markers, poly && !parsed.ignore_holes ? holes : std::nullopt,
                            poly ? regions : std::nullopt);
  if (vertex_attributes) {  // (n, A): Triangle's vertex attributes, carried to the output's vertices
    if (vertex_attributes->ndim() != 2 || static_cast<std::size_t>(vertex_attributes->shape(0)) != pslg.points.size()) {
      input_error("vertex_attributes: expected one row per vertex (" + std::to_string(pslg.points.size()) +
                  "), got shape " + shape_text(*vertex_attributes));
    }
    pslg.attributes_per_point = static_cast<std::size_t>(vertex_attributes->shape(1));
    pslg.point_attributes.assign(vertex_attributes->data(), vertex_attributes->data() + vertex_attributes->size());
  }
  if (parsed.refine) {
    if (!triangles) input_error("-r: refining needs the triangles of the mesh to refine ('triangles')");
    for (const auto& t : triangles_of(*triangles, pslg.points.size(), "triangles")) {
      pslg.triangles.insert(pslg.triangles.end(), t.begin(), t.end());
    }
    if (triangle_max_area) {
      const std::size_t m = pslg.triangles.size() / 3;
      if (triangle_max_area->ndim() != 1 || static_cast<std::size_t>(triangle_max_area->shape(0)) != m) {
        input_error("triangle_max_area: expected one area per triangle (" + std::to_string(m) + "), got shape " +
                    shape_text(*triangle_max_area));
      }
      pslg.triangle_max_area.assign(triangle_max_area->data(), triangle_max_area->data() + m);
    }
  }
  // Triangle's outputs as the library writes them (mwst::io::format_triangle_files: its boundary
  // markers, edges, neighbours, Voronoi diagram, -j and -A), numbered from 0 as the `triangle`
  // package numbers, read back into arrays. Every file is asked for; what the switches leave out
  // (-N, -E, -P, -B) the Python side drops.
  mwst::io::TriangleOutput what;
  what.poly = parsed.poly || options.convex_hull;
  what.edges = parsed.edges;
  what.neighbours = parsed.neighbours;
  what.voronoi = parsed.voronoi;
  what.triangle_attributes = parsed.region_attributes;
  what.jettison = parsed.jettison;
  what.first_index = 0;
  std::vector<mwst::io::TriangleFile> files;
  std::vector<std::uint8_t> used;  // with -j: which vertices the output keeps
  std::string report;
  {
    py::gil_scoped_release unlocked;
    const mwst::MeshArrays arrays = mwst::triangulate_arrays(pslg, options);
    files = mwst::io::format_triangle_files(arrays, pslg.holes, pslg.regions, what);
    report = mwst::to_json(arrays.report).dump();
    if (parsed.jettison) {
      used.assign(arrays.vertex_count(), 0);
      for (const std::uint32_t v : arrays.triangles) used[v] = 1;
    }
  }
  py::dict out;
  for (const mwst::io::TriangleFile& file : files) read_triangle_file(file, out);
  if (parsed.jettison) {
    std::vector<std::int64_t> kept;
    for (std::size_t v = 0; v < used.size(); ++v) {
      if (used[v]) kept.push_back(static_cast<std::int64_t>(v));
    }
    const auto n = static_cast<py::ssize_t>(kept.size());
    out["kept_vertices"] = adopt(std::move(kept), {n});
  }
  out["report"] = report;
  out["switches"] = switches_dict(parsed);
  return out;
}

}  // namespace

PYBIND11_MODULE(_mwst, m) {
  m.doc() = "The compiled core of mwst (use the package `mwst`, not this module).";
  m.attr("__version__") = mwst::kVersionString;

  static py::exception<mwst::InputError> input_error_type(m, "InputError", PyExc_ValueError);
  input_error_type.doc() = "Input mwst refuses (a ValueError), with the library's message.";
  static py::exception<mwst::ResourceError> resource_error_type(m, "ResourceError", PyExc_MemoryError);
  resource_error_type.doc() = "A request that does not fit in the memory budget (a MemoryError).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const mwst::InputError& e) {
      input_error_type(with_python_keywords(e.located()).c_str());
    } catch (const std::invalid_argument& e) {
      input_error_type(with_python_keywords(e.what()).c_str());
    } catch (const mwst::ResourceError& e) {
      resource_error_type(e.what());
    } catch (const mwst::InternalError& e) {
      PyErr_SetString(PyExc_RuntimeError, (std::string("mwst internal error: ") + e.what()).c_str());
    }
  });

  m.def("triangulate", &triangulate, py::arg("vertices"), py::arg("segments"), py::arg("holes"), py::arg("regions"),
        py::arg("vertex_markers"), py::arg("segment_markers"), py::arg("method"), py::arg("min_angle"),
        py::arg("steiner"), py::arg("max_area"), py::arg("max_steiner"), py::arg("bundle_k"), py::arg("flip"),
        py::arg("convex_hull"), py::arg("strict"), py::arg("time_limit"), py::arg("threads"), py::arg("source"),
        "triangulate_arrays() of the library on arrays already converted by mwst.triangulate.");
  m.def("bundle_number", &bundle_number, py::arg("vertices"), py::arg("triangles"), py::arg("candidate_budget"),
        py::arg("threads"), "The library's bundle_number() of a triangle list.");
  m.def("check", &check, py::arg("vertices"), py::arg("segments"), py::arg("holes"), py::arg("mesh_vertices"),
        py::arg("mesh_triangles"), py::arg("mesh_segments"), py::arg("delaunay"), py::arg("min_angle"),
        py::arg("max_messages"), "The library's check_triangulation().");
  m.def("parse_triangle_switches", &parse_switches, py::arg("switches"),
        "The library's parse_triangle_switches(): what a Triangle switch string sets.");
  m.def("triangulate_switches", &triangulate_switches, py::arg("vertices"), py::arg("segments"), py::arg("holes"),
        py::arg("regions"), py::arg("vertex_markers"), py::arg("segment_markers"), py::arg("triangles"),
        py::arg("triangle_max_area"), py::arg("vertex_attributes"), py::arg("switches"),
        "triangulate_arrays() with the options of a Triangle switch string (mwst.triangle).");
  m.def("read_input", &read_input, py::arg("path"), "io::read_input: a .node or .poly file.");
  m.def("read_mesh", &read_mesh, py::arg("prefix"), "io::read_mesh: PREFIX.node, .ele and .poly.");
  m.def("write_mesh", &write_mesh, py::arg("prefix"), py::arg("vertices"), py::arg("vertex_markers"),
        py::arg("triangles"), py::arg("segments"), py::arg("segment_markers"), py::arg("first_index"),
        py::arg("holes"), py::arg("regions"), "The library's Triangle writer (format_triangle_files) for a mesh given as arrays.");
}
