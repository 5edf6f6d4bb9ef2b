// The command line's limits (src/cli/commands.hpp): the memory budget — --max-memory, by default
// 75% of the machine's memory (or less if the process or its control group is allowed less) —
// enforced as the process's address-space limit, so that a runaway gets std::bad_alloc (exit code
// 4) instead of the kernel's out-of-memory killer; the process's start, from which --time-limit
// counts; and the progress line of long runs on a terminal.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "cli/commands.hpp"

// Sanitizers reserve terabytes of address space for their shadow memory: an address-space limit
// would stop them at start-up, so their builds do not set one (the --max-area estimate still
// refuses what cannot fit).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MWST_ADDRESS_LIMIT 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define MWST_ADDRESS_LIMIT 0
#endif
#endif
#ifndef MWST_ADDRESS_LIMIT
#define MWST_ADDRESS_LIMIT 1
#endif

namespace mwst::cli {

namespace {

double g_memory_budget = 0.0;  // set_memory_budget's; 0: none

// MemTotal of /proc/meminfo in bytes, or 0 if unknown.
double physical_memory() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0.0;
  std::string unit;
  while (in >> key >> kb >> unit) {
    if (key == "MemTotal:") return kb * 1024.0;
  }
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

// The cgroup v2 memory limit of this process (memory.max), or 0 if none or unknown.
double cgroup_memory_limit() {
  std::ifstream self("/proc/self/cgroup");
  std::string line;
  while (std::getline(self, line)) {
    if (line.rfind("0::", 0) != 0) continue;
    std::ifstream max("/sys/fs/cgroup" + line.substr(3) + "/memory.max");
    std::string value;
    if (max >> value && value != "max") {
      try {
        return std::stod(value);
      } catch (const std::exception&) {
      }
    }
  }
  return 0.0;
}

}  // namespace

std::optional<double> parse_bytes(std::string_view text) {
  if (text.empty()) return std::nullopt;
  double scale = 1.0;
  std::string digits(text);
  switch (digits.back()) {
    case 'k': case 'K': scale = 1024.0; break;
    case 'm': case 'M': scale = 1024.0 * 1024.0; break;
    case 'g': case 'G': scale = 1024.0 * 1024.0 * 1024.0; break;
    case 't': case 'T': scale = 1024.0 * 1024.0 * 1024.0 * 1024.0; break;
    default: break;
  }
  if (scale != 1.0) digits.pop_back();
  if (digits.empty() || !(std::isdigit(static_cast<unsigned char>(digits[0])) || digits[0] == '.')) return std::nullopt;
  try {
    std::size_t used = 0;
    const double v = std::stod(digits, &used);
    if (used != digits.size() || !std::isfinite(v) || !(v > 0.0)) return std::nullopt;
    const double bytes = v * scale;
    if (!(bytes >= 1.0 && bytes < 9.2e18)) return std::nullopt;
    return bytes;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

CLI::Validator byte_count() {
  return CLI::Validator(
      [](const std::string& s) -> std::string {
        if (parse_bytes(s)) return {};
        return "must be a number of bytes > 0, with an optional suffix K, M, G or T (powers of 1024), found '" + s +
               "'";
      },
      "BYTES");
}

double default_memory_budget() {
  double budget = 0.75 * physical_memory();
  const double cgroup = cgroup_memory_limit();
  if (cgroup > 0.0 && (budget <= 0.0 || cgroup < budget)) budget = cgroup;
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const auto current = static_cast<double>(limit.rlim_cur);
    if (budget <= 0.0 || current < budget) budget = current;
  }
  return budget;
}

void set_memory_budget(double bytes) {
  g_memory_budget = bytes;
#if MWST_ADDRESS_LIMIT
  rlimit limit{};
  if (bytes > 0.0 && ::getrlimit(RLIMIT_AS, &limit) == 0) {
    auto wanted = static_cast<rlim_t>(bytes);
    if (limit.rlim_max != RLIM_INFINITY && wanted > limit.rlim_max) wanted = limit.rlim_max;
    limit.rlim_cur = wanted;
    ::setrlimit(RLIMIT_AS, &limit);  // a refusal leaves the old limit; the estimate still applies
  }
#endif
}

double memory_budget() { return g_memory_budget; }

// ---- the progress line ---------------------------------------------------------------------------

struct ProgressLine::State {
  std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;
  bool drawn = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point updated = start;
  std::string method, phase;
  Progress last;
};

namespace {
const std::chrono::steady_clock::time_point kProcessStart = std::chrono::steady_clock::now();
}  // namespace

std::chrono::steady_clock::time_point process_start() { return kProcessStart; }

ProgressLine::ProgressLine(bool enabled) {
  if (!enabled || ::isatty(STDERR_FILENO) == 0) return;
  state_ = std::make_shared<State>();
  ticker_ = std::thread([state = state_] {
    std::unique_lock lock(state->mutex);
    while (!state->stop) {
      state->wake.wait_for(lock, std::chrono::milliseconds(200));
      if (state->stop) break;
      const auto now = std::chrono::steady_clock::now();
      Progress p = state->last;
      p.method = state->method;
      p.phase = state->phase;
      p.elapsed_seconds = std::chrono::duration<double>(now - state->start).count();
      if (p.seconds_left >= 0.0) {
        p.seconds_left = std::max(0.0, p.seconds_left - std::chrono::duration<double>(now - state->updated).count());
      }
      if (p.elapsed_seconds < kProgressAfterSeconds || p.phase.empty()) continue;
      std::cerr << '\r' << format_progress(p) << "\x1b[K" << std::flush;
      state->drawn = true;
    }
  });
}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::finish() {
  if (!state_) return;
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->wake.notify_all();
  if (ticker_.joinable()) ticker_.join();
  if (state_->drawn) std::cerr << "\r\x1b[K" << std::flush;
  state_.reset();
}

ProgressCallback ProgressLine::callback() {
  if (!state_) return {};
  return [state = state_](const Progress& p) {
    std::lock_guard lock(state->mutex);
    state->method = std::string(p.method);
    state->phase = std::string(p.phase);
    state->last = p;
    state->updated = std::chrono::steady_clock::now();
  };
}

}  // namespace mwst::cli
