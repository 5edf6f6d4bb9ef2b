// bench/bench_common.hpp — measurement helpers shared by the benchmarks (bench_delaunay,
// bench_cdt, ...): every measured run happens in a child process so that runs cannot warm or
// fragment each other's heaps, and so that peak memory can be read per run.
//
// Algorithm-only runs: the child is forked from the benchmark (it inherits the input already in
// memory); it returns the free heap it inherited to the system (malloc_trim), resets its
// resident-set high-water mark (writing 5 to /proc/self/clear_refs, Linux
// ≥ 4.0), records VmRSS, runs the algorithm, and reports the seconds and VmHWM − VmRSS_before: the
// memory the algorithm added at its peak, input excluded. Whole-process runs exec a fresh program
// (the mwst command line, or this benchmark in a child mode) and report wall seconds and the
// process's whole peak RSS (wait4's ru_maxrss). Timings are best of N (default 3); the peak is the
// largest seen.
#pragma once

#include <malloc.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mwst/geometry/geometry.hpp"

namespace mwst::bench {

// ---- /proc readings -------------------------------------------------------------------------------

// A "Vm..." field of /proc/self/status in KiB (0 if absent).
inline long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::size_t len = std::strlen(field);
  while (std::getline(in, line)) {
    if (line.compare(0, len, field) == 0 && line.size() > len && line[len] == ':') {
      return std::strtol(line.c_str() + len + 1, nullptr, 10);
    }
  }
  return 0;
}

inline bool reset_peak_rss() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

inline std::string hardware_line() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown";
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  std::ifstream mem("/proc/meminfo");
  std::string memline;
  std::getline(mem, memline);
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = -1;
  char buf[512];
  std::snprintf(buf, sizeof buf, "nproc %ld, %s, %s, load average %.2f", sysconf(_SC_NPROCESSORS_ONLN),
                model.c_str(), memline.c_str(), load[0]);
  return buf;
}

// ---- runs in child processes ------------------------------------------------------------------

// Handed to the measured function in the child: call start() after any untimed preparation and
// stop() right after the algorithm.
class Probe {
 public:
  void start() {
    // Free heap memory inherited from the parent is resident; without trimming it, the run would
    // reuse it without growing the resident set, and its peak would be underestimated.
    malloc_trim(0);
    peak_reset_ = reset_peak_rss();
    rss_before_kib_ = status_kib("VmRSS");
    cpu0_ = process_cpu_seconds();
    t0_ = std::chrono::steady_clock::now();
  }
  void stop() {
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    cpu_seconds_ = process_cpu_seconds() - cpu0_;
    hwm_kib_ = status_kib("VmHWM");
  }
  double seconds() const { return seconds_; }
  // CPU seconds of the whole process (all threads) over the run.
  double cpu_seconds() const { return cpu_seconds_; }
  // Peak memory added since start(), MiB; if the high-water mark could not be reset it is the
  // whole process's peak (an overestimate) — marked by peak_reset() == false.
  double added_peak_mib() const {
    return static_cast<double>(peak_reset_ ? hwm_kib_ - rss_before_kib_ : hwm_kib_) / 1024.0;
  }
  bool peak_reset() const { return peak_reset_; }
  // A size the run produced (e.g. its triangle count), reported for a sanity check.
  void set_count(std::size_t count) { count_ = count; }
  std::size_t count() const { return count_; }

 private:
  static double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  std::chrono::steady_clock::time_point t0_;
  double seconds_ = 0.0, cpu0_ = 0.0, cpu_seconds_ = 0.0;
  long rss_before_kib_ = 0, hwm_kib_ = 0;
  bool peak_reset_ = false;
  std::size_t count_ = 0;
};

struct Measurement {
  bool ok = false;
  std::string error;
  double best_seconds = 0.0;  // wall
  double best_cpu = 0.0;      // CPU seconds, all threads (best of the runs, independently)
  double peak_mib = 0.0;
  std::size_t count = 0;  // Probe::set_count of the last run
};

// Runs fn(probe) `repeats` times, each in a forked child; the best time and the largest peak.
inline Measurement measure_forked(const std::function<void(Probe&)>& fn, int repeats = 3) {
  Measurement m;
  m.best_seconds = m.best_cpu = 1e300;
  for (int r = 0; r < repeats; ++r) {
    int fds[2];
    if (pipe(fds) != 0) {
      m.error = "pipe failed";
      return m;
    }
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      double result[5] = {0, 0, 0, 0, 0};
      try {
        Probe probe;
        fn(probe);
        result[0] = probe.seconds();
        result[1] = probe.added_peak_mib();
        result[2] = probe.peak_reset() ? 1 : 0;
        result[3] = static_cast<double>(probe.count());
        result[4] = probe.cpu_seconds();
      } catch (const std::exception& e) {
        result[0] = -1;
        std::fprintf(stderr, "child failed: %s\n", e.what());
      }
      if (write(fds[1], result, sizeof result) != static_cast<ssize_t>(sizeof result)) _exit(2);
      _exit(0);
    }
    close(fds[1]);
    double result[5] = {-1, 0, 0, 0, 0};
    const ssize_t got = read(fds[0], result, sizeof result);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (got != static_cast<ssize_t>(sizeof result) || result[0] < 0 || !WIFEXITED(status) ||
        WEXITSTATUS(status) != 0) {
      m.error = "child process failed";
      return m;
    }
    m.best_seconds = std::min(m.best_seconds, result[0]);
    m.best_cpu = std::min(m.best_cpu, result[4]);
    m.peak_mib = std::max(m.peak_mib, result[1]);
    m.count = static_cast<std::size_t>(result[3]);
    if (result[2] == 0) m.error = "peak is the whole process (clear_refs unavailable)";
  }
  m.ok = true;
  return m;
}

// Runs a program `repeats` times (stdout to /dev/null); best wall time, best CPU time (user + system)
// and the largest peak RSS of the process (ru_maxrss).
inline Measurement measure_process(const std::vector<std::string>& argv, int repeats = 3) {
  Measurement m;
  m.best_seconds = m.best_cpu = 1e300;
  for (int r = 0; r < repeats; ++r) {
    std::fflush(stdout);
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
      std::vector<char*> args;
      for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      if (std::freopen("/dev/null", "w", stdout) == nullptr) _exit(126);
      execv(args[0], args.data());
      _exit(127);
    }
    int status = 0;
    struct rusage usage {};
    wait4(pid, &status, 0, &usage);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      m.error = argv[0] + " exited with status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1);
      return m;
    }
    m.best_seconds = std::min(m.best_seconds, seconds);
    const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                       1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    m.best_cpu = std::min(m.best_cpu, cpu);
    m.peak_mib = std::max(m.peak_mib, static_cast<double>(usage.ru_maxrss) / 1024.0);
  }
  m.ok = true;
  return m;
}

inline bool executable_exists(const std::string& path) { return access(path.c_str(), X_OK) == 0; }

// ---- tables -------------------------------------------------------------------------------------

struct Row {
  std::string method, data;
  std::size_t n = 0;
  Measurement m;
  double cgal_seconds = 0.0;  // the CGAL row's wall time for the same data and mode (0: none)
  double cgal_cpu = 0.0;      // and its CPU time
};

// Makes `cgal` the reference of the ratio columns of `row`.
inline void set_reference(Row& row, const Measurement& cgal) {
  row.cgal_seconds = cgal.ok ? cgal.best_seconds : 0.0;
  row.cgal_cpu = cgal.ok ? cgal.best_cpu : 0.0;
}

inline void print_header(const std::string& title) {
  std::printf("\n%s\n\n", title.c_str());
  std::printf("| method | data | n | wall s | CPU s | points/s (wall) | peak MiB | bytes/point | wall / CGAL | CPU / CGAL |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::fflush(stdout);
}

inline void print_row(const Row& r) {
  if (!r.m.ok) {
    std::printf("| %s | %s | %zu | failed: %s | | | | | | |\n", r.method.c_str(), r.data.c_str(), r.n,
                r.m.error.c_str());
    std::fflush(stdout);
    return;
  }
  const double n = static_cast<double>(r.n);
  char ratio[32] = "—", cpu_ratio[32] = "—";
  if (r.cgal_seconds > 0) std::snprintf(ratio, sizeof ratio, "%.2f", r.m.best_seconds / r.cgal_seconds);
  if (r.cgal_cpu > 0) std::snprintf(cpu_ratio, sizeof cpu_ratio, "%.2f", r.m.best_cpu / r.cgal_cpu);
  std::printf("| %s | %s | %zu | %.3f | %.3f | %.3g | %.1f | %.0f | %s | %s |\n", r.method.c_str(), r.data.c_str(),
              r.n, r.m.best_seconds, r.m.best_cpu, n / r.m.best_seconds, r.m.peak_mib, r.m.peak_mib * 1048576.0 / n,
              ratio, cpu_ratio);
  std::fflush(stdout);
}

// ---- inputs -------------------------------------------------------------------------------------

inline std::vector<Point> uniform_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> p(n);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

// Kuzmin's distribution (PBBS randKuzmin): uniform angle, radius CDF 1 − 1/sqrt(1 + r²).
inline std::vector<Point> kuzmin_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Point> p(n);
  for (auto& q : p) {
    const double theta = 2.0 * std::numbers::pi * u(rng), s = u(rng);
    const double r = std::sqrt(1.0 / ((1.0 - s) * (1.0 - s)) - 1.0);
    q = {r * std::cos(theta), r * std::sin(theta)};
  }
  return p;
}

// The side × side integer grid, shuffled.
inline std::vector<Point> grid_points(int side, std::uint64_t seed) {
  std::vector<Point> p;
  p.reserve(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) p.push_back({double(i), double(j)});
  std::mt19937_64 rng(seed);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

// n points on the unit circle (cos, sin of evenly spaced angles, rounded), shuffled.
inline std::vector<Point> circle_points(std::size_t n, std::uint64_t seed) {
  std::vector<Point> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    p[i] = {std::cos(a), std::sin(a)};
  }
  std::mt19937_64 rng(seed);
  std::shuffle(p.begin(), p.end(), rng);
  return p;
}

// ---- a small fast reader and writer for Triangle's .node/.ele (the CGAL side of whole-process runs)
// std::from_chars / std::to_chars (shortest round trip), as mwst's own reader and writer use.

// Reads a .node file (header "n 2 attributes markers", then "index x y [attributes] [marker]";
// '#' comments, blank lines). Minimal: no validation beyond what parsing needs.
inline std::vector<Point> fast_read_node(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open " + path);
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  std::fseek(f, 0, SEEK_SET);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (std::fread(text.data(), 1, text.size(), f) != text.size()) throw std::runtime_error("short read");
  std::fclose(f);
  const char* p = text.data();
  const char* const end = p + text.size();
  auto next_line = [&] {
    while (p < end && *p != '\n') ++p;
    if (p < end) ++p;
  };
  auto skip_space = [&] {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  };
  auto skip_blank_lines = [&] {
    for (;;) {
      skip_space();
      if (p < end && (*p == '#' || *p == '\n')) {
        next_line();
        continue;
      }
      return;
    }
  };
  skip_blank_lines();
  std::size_t n = 0;
  p = std::from_chars(p, end, n).ptr;
  next_line();
  std::vector<Point> pts(n);
  for (std::size_t i = 0; i < n; ++i) {
    skip_blank_lines();
    long index = 0;
    p = std::from_chars(p, end, index).ptr;
    skip_space();
    p = std::from_chars(p, end, pts[i].x).ptr;
    skip_space();
    p = std::from_chars(p, end, pts[i].y).ptr;
    next_line();
  }
  return pts;
}

// Writes PREFIX.node and PREFIX.ele (1-based), as `mwst triangulate` does.
inline void fast_write_mesh(const std::string& prefix, const std::vector<Point>& pts,
                            const std::vector<std::array<std::uint32_t, 3>>& tris) {
  std::string buf;
  buf.reserve(pts.size() * 48 + 64);
  char tmp[128];
  auto put = [&](auto v) {
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
    buf.append(tmp, r.ptr);
  };
  put(pts.size());
  buf += " 2 0 0\n";
  for (std::size_t i = 0; i < pts.size(); ++i) {
    put(i + 1);
    buf += ' ';
    put(pts[i].x);
    buf += ' ';
    put(pts[i].y);
    buf += '\n';
  }
  std::ofstream(prefix + ".node", std::ios::binary) << buf;
  buf.clear();
  put(tris.size());
  buf += " 3 0\n";
  for (std::size_t t = 0; t < tris.size(); ++t) {
    put(t + 1);
    for (std::uint32_t v : tris[t]) {
      buf += ' ';
      put(v + 1);
    }
    buf += '\n';
  }
  std::ofstream(prefix + ".ele", std::ios::binary) << buf;
}

}  // namespace mwst::bench
