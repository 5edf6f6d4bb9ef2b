// The machinery of `mwst experiment` (src/experiments/experiment.hpp): finding the data sets, running
// independent (data set, options) runs of mwst::triangulate on a pool of worker threads, and
// reporting progress on stderr. The runs reproduce the experiments of Boyacı, Erten, Üngör,
// "Triangulations Loosing Bundles and Weight"; each result lands in the slot of its spec, so the
// outputs never depend on which worker ran what or when.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <new>
#include <numeric>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "experiments/experiment.hpp"
#include "support/parallel.hpp"
#include "mwst/error.hpp"
#include "mwst/io/triangle_files.hpp"
#include "mwst/mesh/mesh.hpp"

namespace mwst::experiments {

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string clock_text(double seconds) {
  char buf[32];
  const auto s = static_cast<long>(seconds);
  std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

}  // namespace

// ---- data sets ---------------------------------------------------------------------------------

std::vector<DataSet> find_data_sets(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir, 0, "not a directory (give the data sets with --data DIR)");
  std::map<std::string, std::string> chosen;  // stem → path (.poly wins over .node)
  fs::directory_iterator it(dir, ec);
  if (ec) throw InputError(dir, 0, "cannot read the directory: " + ec.message());
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) throw InputError(dir, 0, "cannot read the directory: " + ec.message());
    const fs::path& p = it->path();
    const std::string ext = p.extension().string();
    if (ext != ".poly" && ext != ".node") continue;
    if (!it->is_regular_file(ec)) continue;
    const std::string stem = p.stem().string();
    // Triangle's outputs (NAME.1.node, ...) are meshes, not data sets.
    const std::size_t dot = stem.find_last_of('.');
    if (dot != std::string::npos && dot + 1 < stem.size() &&
        std::all_of(stem.begin() + static_cast<long>(dot) + 1, stem.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      continue;
    }
    auto [pos, inserted] = chosen.emplace(stem, p.string());
    if (!inserted && ext == ".poly") pos->second = p.string();
  }
  if (chosen.empty()) throw InputError(dir, 0, "holds no .poly or .node data set");
  std::vector<DataSet> sets;
  for (const auto& [stem, path] : chosen) {
    DataSet d;
    d.name = stem;
    d.path = path;
    d.pslg = io::read_input(path);
    sets.push_back(std::move(d));
  }
  return sets;
}

// ---- names -------------------------------------------------------------------------------------

const char* column_name(Column column) {
  switch (column) {
    case Column::kDt: return "DT";
    case Column::kQtr: return "QTR";
    case Column::kDr: return "DR";
    case Column::kBrh: return "BRH";
    case Column::kBrhEfh: return "BRH+EFH";
    case Column::kOpt: return "OPT";
  }
  return "?";
}

std::string fixed(double value, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, value);
  return buf;
}

std::string angle_text(double degrees) {
  if (degrees == std::floor(degrees)) return fixed(degrees, 0);
  return fixed(degrees, 1);
}

std::string describe(const TriangulateOptions& o) {
  std::string s(method_name(o.method));
  if (o.method == Method::kDr || o.method == Method::kBrh || o.method == Method::kOpt) {
    s += " " + angle_text(o.min_angle_deg) + "°";
    if (o.method != Method::kDr) {
      s += " k=" + (o.bundle_k != 0 ? std::to_string(o.bundle_k)
                                     : (o.min_angle_deg > 0.0 ? std::to_string(default_bundle_k(o.min_angle_deg)) : "?"));
    }
    s += " " + std::string(steiner_rule_name(o.steiner));
  }
  if (o.flip) s += " +efh";
  if (o.bundle) s += " +bundle";
  return s;
}

// ---- progress ----------------------------------------------------------------------------------

Progress::Progress() : tty_(::isatty(STDERR_FILENO) == 1), start_(now_seconds()) {}

double Progress::elapsed() const { return now_seconds() - start_; }

void Progress::status(const std::string& text) {
  if (!tty_) return;
  // At most ten updates a second: a terminal is slower than the short runs.
  const double t = now_seconds();
  if (status_shown_ && t - last_status_ < 0.1) return;
  last_status_ = t;
  std::string line = text;
  if (line.size() > 110) {
    std::size_t cut = 110;
    while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
    line.resize(cut);
  }
  std::cerr << "\r\033[K" << line << std::flush;
  status_shown_ = true;
}

void Progress::line(const std::string& text) {
  if (tty_ && status_shown_) std::cerr << "\r\033[K";
  status_shown_ = false;
  std::cerr << "mwst: experiment: " << text << " [" << clock_text(elapsed()) << "]" << std::endl;
}

void Progress::done() {
  if (tty_ && status_shown_) std::cerr << "\r\033[K" << std::flush;
  status_shown_ = false;
}

// ---- the pool ----------------------------------------------------------------------------------


namespace {

RunResult run_one(const DataSet& data_set, const RunSpec& spec) {
  RunResult r;
  const double start = now_seconds();
  try {
    Mesh mesh;
    r.report = triangulate(data_set.pslg, spec.options, spec.keep_picture ? &mesh : nullptr);
    r.ok = true;
    if (spec.keep_picture) {
      r.violations = validate(mesh);
      r.picture = io::picture_of(mesh);
    }
  } catch (const InputError& e) {
    r.reason = e.located();
  } catch (const std::invalid_argument& e) {
    // Options the method cannot use.
    r.reason = e.what();
  } catch (const InternalError& e) {
    r.reason = std::string("internal error: ") + e.what();
    r.internal_error = true;
  } catch (const std::bad_alloc&) {
    r.reason = "out of memory";
    r.internal_error = true;
  } catch (const std::exception& e) {
    r.reason = std::string("error: ") + e.what();
    r.internal_error = true;
  }
  if (!r.ok) r.report = Report{};
  r.seconds = now_seconds() - start;
  return r;
}

}  // namespace

std::vector<RunResult> run_all(const std::vector<DataSet>& data_sets, const std::vector<RunSpec>& specs,
                               std::size_t workers, Progress& progress, const std::string& phase) {
  std::vector<RunResult> results(specs.size());
  if (specs.empty()) return results;

  // Bigger inputs first, so that the last runs to finish are short ones (results do not depend on
  // the order).
  std::vector<std::size_t> order(specs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return data_sets[specs[a].data_set].pslg.points.size() > data_sets[specs[b].data_set].pslg.points.size();
  });

  // Runs left per (data set, group): a line is printed when a group completes (non-terminal).
  std::map<std::pair<std::size_t, std::string>, std::size_t> left;
  std::map<std::pair<std::size_t, std::string>, double> group_seconds;
  for (const RunSpec& s : specs) ++left[{s.data_set, s.group}];
  std::mutex mutex;
  std::size_t finished = 0;
  std::size_t failed = 0;

  progress.line(phase + ": " + std::to_string(specs.size()) + " runs on " +
                std::to_string(std::max<std::size_t>(1, std::min(workers, specs.size()))) + " threads");
  support::parallel_for(specs.size(), workers, [&](std::size_t k) {
    const std::size_t i = order[k];
    const RunSpec& spec = specs[i];
    const DataSet& data_set = data_sets[spec.data_set];
    RunResult r = run_one(data_set, spec);
    const std::lock_guard<std::mutex> lock(mutex);
    ++finished;
    if (!r.ok) ++failed;
    const std::pair<std::size_t, std::string> key{spec.data_set, spec.group};
    group_seconds[key] += r.seconds;
    const std::size_t group_left = --left[key];
    if (progress.tty()) {
      progress.status("[" + std::to_string(finished) + "/" + std::to_string(specs.size()) + "] " + data_set.name +
                      " " + describe(spec.options) + ": " + (r.ok ? fixed(r.seconds, 2) + " s" : "NA") +
                      "  (elapsed " + clock_text(progress.elapsed()) + ")");
    } else if (group_left == 0) {
      progress.line(phase + ": " + data_set.name + " " + spec.group + ": " + fixed(group_seconds[key], 2) +
                    " s of runs (" + std::to_string(finished) + "/" + std::to_string(specs.size()) + " done)");
    }
    results[i] = std::move(r);
  });
  progress.done();
  progress.line(phase + ": done" + (failed > 0 ? " (" + std::to_string(failed) + " runs NA)" : std::string()));
  return results;
}

}  // namespace mwst::experiments
