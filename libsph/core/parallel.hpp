#pragma once
// The one wrapper through which particle loops run in parallel (oneTBB underneath).
//
// Every loop is a gather: the body for index i writes only entries of i, so results do not depend
// on the number of threads. Reductions over particles use fixed blocks summed in block order
// (parallel_sum), which makes them bitwise reproducible for any thread count as well.

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sph {

/// Limits the worker threads of every parallel loop for as long as it lives; 0 means "all cores",
/// 1 runs every loop sequentially on the calling thread.
class ThreadLimit {
 public:
  explicit ThreadLimit(std::size_t n_threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Number of threads parallel loops use now.
std::size_t active_thread_count();

/// body(i) for i in [0, n), in parallel.
template <class Body>
void parallel_for(std::size_t n, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) body(i);
  });
}

/// Sequential counterpart with the same signature (debugging, reference results in tests).
template <class Body>
void sequential_for(std::size_t n, Body&& body) {
  for (std::size_t i = 0; i != n; ++i) body(i);
}

/// Sum of term(i) over [0, n), reproducible bit for bit for any thread count: the range is cut into
/// fixed blocks, each block is summed in index order, then the block sums are added in block order.
template <class T, class Term>
T parallel_sum(std::size_t n, T zero, Term&& term) {
  constexpr std::size_t block = 4096;
  const std::size_t n_blocks = (n + block - 1) / block;
  std::vector<T> partial(n_blocks, zero);
  parallel_for(n_blocks, [&](std::size_t b) {
    T sum = zero;
    const std::size_t end = std::min(n, (b + 1) * block);
    for (std::size_t i = b * block; i < end; ++i) sum += term(i);
    partial[b] = sum;
  });
  T total = zero;
  for (const T& p : partial) total += p;
  return total;
}

/// Maximum of term(i) over [0, n) (order-independent, hence reproducible); `lowest` if n == 0.
template <class T, class Term>
T parallel_max(std::size_t n, T lowest, Term&& term) {
  constexpr std::size_t block = 4096;
  const std::size_t n_blocks = (n + block - 1) / block;
  std::vector<T> partial(n_blocks, lowest);
  parallel_for(n_blocks, [&](std::size_t b) {
    T m = lowest;
    const std::size_t end = std::min(n, (b + 1) * block);
    for (std::size_t i = b * block; i < end; ++i) m = std::max(m, term(i));
    partial[b] = m;
  });
  T result = lowest;
  for (const T& p : partial) result = std::max(result, p);
  return result;
}

}  // namespace sph

namespace sph {

/// Smallest i in [0, n) with predicate(i) true, or n if there is none (reproducible: the lowest
/// index wins whatever the thread count). Used to name the first particle whose state is invalid.
template <class Predicate>
std::size_t first_index_where(std::size_t n, Predicate&& predicate) {
  constexpr std::size_t block = 4096;
  const std::size_t n_blocks = (n + block - 1) / block;
  std::vector<std::size_t> first(n_blocks, n);
  parallel_for(n_blocks, [&](std::size_t b) {
    const std::size_t end = std::min(n, (b + 1) * block);
    for (std::size_t i = b * block; i < end; ++i)
      if (predicate(i)) {
        first[b] = i;
        return;
      }
  });
  for (std::size_t f : first)
    if (f < n) return f;
  return n;
}

}  // namespace sph
