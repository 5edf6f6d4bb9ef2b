// src/algorithms/bundle/lists.cpp — the bundle number's workers and candidate lists (lists.hpp).
#include "algorithms/bundle/lists.hpp"

#include <algorithm>
#include <functional>
#include <utility>

#include "mwst/error.hpp"

namespace mwst::bundle {

unsigned worker_threads(unsigned requested, std::size_t work) {
  if (work < 20000) return 1;  // small inputs: threads cost more than they save
  return std::min(support::worker_count(requested), 16u);
}

std::vector<std::unique_ptr<Worker>> make_workers(const Shared& sh, unsigned threads, bool per_triangle,
                                                  bool prune) {
  std::vector<std::unique_ptr<Worker>> workers;
  for (unsigned k = 0; k < threads; ++k) workers.push_back(std::make_unique<Worker>(sh, per_triangle, prune));
  return workers;
}

// ---- candidate lists begin here -------------------------------------------------------------------

namespace {

// One thread's candidate lists, in chunks (a list never straddles two), which become the lists'
// storage in Shared (list_chunks): no list is copied, and no growing array is ever copied. The
// chunks grow from kFirstChunk to kChunk triangles, each twice the one before: a small mesh does
// not pay for a 4 MB chunk per thread (BRH builds lists for many small regions); the last chunk
// is cut to what it holds.
class ListChunks {
 public:
  static constexpr std::size_t kFirstChunk = std::size_t{1} << 12;
  static constexpr std::size_t kChunk = std::size_t{1} << 20;

  std::size_t size() const { return size_; }

  void append(const std::vector<TriangleId>& one) {
    if (one.empty()) return;
    if (chunks_.empty() || chunks_.back().size() + one.size() > chunks_.back().capacity()) {
      const std::size_t next = chunks_.empty() ? kFirstChunk : std::min(kChunk, 2 * chunks_.back().capacity());
      chunks_.emplace_back();
      chunks_.back().reserve(std::max(next, one.size()));
    }
    chunks_.back().insert(chunks_.back().end(), one.begin(), one.end());
    size_ += one.size();
  }

  // Hands the chunks to sh.list_chunks, the first starting at offset `offset` of the lists.
  void move_into(Shared& sh, std::size_t offset) {
    if (!chunks_.empty()) chunks_.back().shrink_to_fit();
    for (auto& chunk : chunks_) {
      sh.list_chunk_first.push_back(static_cast<std::uint32_t>(offset));
      offset += chunk.size();
      sh.list_chunks.push_back(std::move(chunk));
    }
    chunks_.clear();
    size_ = 0;
  }

 private:
  std::vector<std::vector<TriangleId>> chunks_;
  std::size_t size_ = 0;
};

}  // namespace

void build_lists(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers, const std::vector<std::uint8_t>* needed,
                 FloodBoxes* boxes, std::uint32_t cap) {
  sh.release_lists();
  const std::size_t slots = sh.dt.triangle_slots();
  // The slots flooded: live, finite, needed, and their own disk's.
  auto flooded = [&](TriangleId d) {
    return !sh.dt.is_dead(d) && !sh.dt.is_ghost(d) && (needed == nullptr || (*needed)[d] != 0) && sh.disk(d) == d;
  };
  if (boxes) boxes->reset(slots, flooded);
  for (auto& w : workers) w->want_flood_box = boxes != nullptr;
  std::vector<ListChunks> parts(workers.size());
  std::vector<std::uint32_t> local_begin(slots + 1, 0);
  for_ranges(workers, slots, [&](Worker& w, std::size_t begin, std::size_t end, std::size_t k) {
    ListChunks& part = parts[k];
    std::vector<TriangleId> one;
    for (std::size_t t = begin; t < end; ++t) {
      sh.check_deadline();
      local_begin[t] = static_cast<std::uint32_t>(part.size());
      const auto dtt = static_cast<TriangleId>(t);
      if (!flooded(dtt)) continue;
      if (cap == std::numeric_limits<std::uint32_t>::max()) {
        w.flood(dtt, one);
      } else {
        one.clear();
        bool over = false;
        w.flood_each(dtt, [&](TriangleId c) {
          if (one.size() == cap) {
            over = true;
            return false;
          }
          one.push_back(c);
          return true;
        });
        sh.truncated[t] = over ? 1 : 0;
      }
      if (boxes) boxes->set(dtt, w.flood_box);
      part.append(one);
    }
  });
  std::size_t total = 0;
  for (const auto& part : parts) total += part.size();
  if (total > 0xFFFFFFF0u) throw InternalError("bundle: candidate lists too long");
  sh.list_begin.assign(slots + 1, 0);
  std::size_t offset = 0;
  for (std::size_t k = 0; k < workers.size(); ++k) {
    const std::size_t begin = slots * k / workers.size(), end = slots * (k + 1) / workers.size();
    for (std::size_t t = begin; t < end; ++t) sh.list_begin[t] = local_begin[t] + static_cast<std::uint32_t>(offset);
    const std::size_t size = parts[k].size();
    parts[k].move_into(sh, offset);
    offset += size;
  }
  sh.list_begin[slots] = static_cast<std::uint32_t>(offset);
}

bool build_lists_within_budget(Shared& sh, std::vector<std::unique_ptr<Worker>>& workers, std::size_t budget) {
  const std::size_t slots = sh.dt.triangle_slots();
  std::size_t disks = 0;
  for (TriangleId d = 0; d < slots; ++d) disks += sh.dt.is_dead(d) || sh.dt.is_ghost(d) || sh.disk(d) != d ? 0 : 1;
  const auto share = [](std::size_t total, std::size_t parts) {
    return static_cast<std::uint32_t>(std::min<std::size_t>(total / std::max<std::size_t>(parts, 1), 0xFFFFFFF0u));
  };
  const std::uint32_t first_cap = std::max<std::uint32_t>(1, share(budget, disks));
  sh.truncated.assign(slots, 0);
  // Room for the budget: the second pass's lists then replace the cut ones in place.
  build_lists(sh, workers, nullptr, nullptr, first_cap);
  // (At most twice the lists: the room is address space, which --max-memory limits.)
  sh.flatten_lists(std::min<std::size_t>(budget, 0xFFFFFFF0u));
  std::vector<std::uint8_t> again(slots, 0);
  std::size_t cut = 0;
  for (TriangleId d = 0; d < slots; ++d) {
    again[d] = sh.truncated[d];
    cut += again[d];
  }
  if (cut == 0) {
    sh.truncated.clear();
    return true;
  }
  const std::size_t used = sh.list.size();
  const std::uint32_t second_cap = share(budget > used ? budget - used : 0, cut);
  if (second_cap > first_cap) {
    std::vector<TriangleId> list = std::move(sh.list);  // the first lists, with room for the budget
    std::vector<std::uint32_t> first_begin = std::move(sh.list_begin);
    build_lists(sh, workers, &again, nullptr, second_cap);
    sh.flatten_lists();
    // The second lists replace the cut ones in place: each list only grows (a cut list held
    // first_cap triangles and its flood had more), so every list moves towards the end, and
    // moving them from the last one down overwrites none not yet moved. The room reserved for
    // the budget holds them all (the first lists not cut fit the budget, and the second ones its
    // rest) unless that is over twice the first lists: the lists are held once, not three times.
    std::vector<std::uint32_t> begin(slots + 1, 0);
    cut = 0;
    for (TriangleId d = 0; d < slots; ++d) {
      const std::uint32_t size = again[d] ? sh.list_begin[d + 1] - sh.list_begin[d] : first_begin[d + 1] - first_begin[d];
      begin[d + 1] = begin[d] + size;
      cut += again[d] ? sh.truncated[d] : 0;
    }
    list.resize(begin[slots]);
    for (std::size_t d = slots; d-- > 0;) {
      if (again[d]) {
        std::copy(sh.list.begin() + sh.list_begin[d], sh.list.begin() + sh.list_begin[d + 1], list.begin() + begin[d]);
      } else {
        std::copy_backward(list.begin() + first_begin[d], list.begin() + first_begin[d + 1], list.begin() + begin[d + 1]);
      }
    }
    sh.list = std::move(list);
    sh.list_begin = std::move(begin);
    for (TriangleId d = 0; d < slots; ++d) {
      if (!again[d]) sh.truncated[d] = 0;
    }
  }
  if (cut == 0) sh.truncated.clear();
  return cut == 0;
}

// ---- the counts of cut lists begin here ----------------------------------------------------------

// In slot order, in blocks (each split over the workers, each disk on its own: the counts do not
// depend on the threads), each block twice the one before.
std::size_t count_cut_lists(const Shared& sh, std::vector<std::unique_ptr<Worker>>& workers,
                            std::vector<std::pair<std::uint32_t, TriangleId>>& cut, std::size_t full) {
  constexpr std::size_t kFirstBlock = std::size_t{1} << 12;
  std::vector<std::uint32_t> longest_left(cut.size() + 1, 0);  // the longest list from index i on
  for (std::size_t i = cut.size(); i-- > 0;) longest_left[i] = std::max(longest_left[i + 1], sh.list_size(cut[i].second));
  std::vector<std::uint32_t> largest;  // the `full` largest counts so far, descending
  std::size_t done = 0;
  for (std::size_t block = kFirstBlock; done < cut.size(); block *= 2) {
    if (largest.size() == full && full > 0 && largest.back() >= longest_left[done]) break;
    const std::size_t end = std::min(cut.size(), done + block);
    for_ranges(workers, end - done, [&](Worker& w, std::size_t begin, std::size_t stop, std::size_t) {
      for (std::size_t i = done + begin; i < done + stop; ++i) {
        const TriangleId d = cut[i].second;
        cut[i].first = w.circumdisk_count(d, sh.list_data(d), sh.list_size(d), nullptr);
      }
    });
    for (std::size_t i = done; i < end; ++i) {
      largest.push_back(cut[i].first);
      std::sort(largest.begin(), largest.end(), std::greater<>());
      if (largest.size() > full) largest.pop_back();
    }
    done = end;
  }
  return done;
}

}  // namespace mwst::bundle
