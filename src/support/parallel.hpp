// support/parallel.hpp — the one way mwst spreads work over threads. Internal (not installed).
//   worker_count(requested)          — 0 means one per hardware thread; never less than 1.
//   parallel_for(count, workers, f)  — f(i) for every i in [0, count), indices handed out one at a
//                                      time to `workers` threads (the caller is one of them).
//   parallel_ranges(workers, n, f)   — f(k, begin, end) on `workers` contiguous ranges of [0, n).
// Either way the first exception thrown by f (by index order for parallel_for, by range for
// parallel_ranges) is rethrown in the caller after every thread has joined. A thread that cannot
// be started (no memory for its stack, as under an address-space limit) leaves its work to the
// calling thread: fewer threads, the same results.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace mwst::support {

inline unsigned worker_count(unsigned requested) {
  return requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

template <class Task>
void parallel_for(std::size_t count, std::size_t workers, Task&& task) {
  workers = std::max<std::size_t>(1, std::min(workers, count));
  std::vector<std::exception_ptr> errors(count);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) {
      try {
        task(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  threads.reserve(workers - 1);
  for (std::size_t w = 1; w < workers; ++w) {
    try {
      threads.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // the threads started (and this one) share the indices
    }
  }
  work();
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

template <class Body>
void parallel_ranges(std::size_t workers, std::size_t n, Body&& body) {
  workers = std::max<std::size_t>(1, workers);
  if (workers == 1) {
    body(std::size_t{0}, std::size_t{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(workers);
  std::vector<std::thread> threads;
  threads.reserve(workers);
  const auto range = [&](std::size_t k) {
    try {
      body(k, n * k / workers, n * (k + 1) / workers);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  };
  for (std::size_t k = 0; k < workers; ++k) {
    try {
      threads.emplace_back(range, k);
    } catch (const std::system_error&) {
      range(k);  // no thread for it: this one does it
    }
  }
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace mwst::support
