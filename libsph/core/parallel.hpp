#pragma once
// The one wrapper through which particle loops run in parallel (oneTBB underneath).
//
// Every loop is a gather: the body for index i writes only entries of i, so results do not depend
// on the number of threads. Reductions over particles use fixed blocks summed in block order
// (parallel_sum), which makes them bitwise reproducible for any thread count as well.

#include <algorithm>
#include <array>
#include <cstddef>
#include <memory>
#include <utility>
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

/// Reduction of term(i) over [0, n) with an associative `combine`, reproducible bit for bit for
/// any thread count: the range is cut into fixed blocks, each block is reduced in index order,
/// then the block results are combined in block order.
template <class T, class Term, class Combine>
T parallel_reduce(std::size_t n, T identity, Term&& term, Combine&& combine) {
  // Blocks small enough to balance heavy terms (a particle's whole force sum) over the threads.
  constexpr std::size_t block = 1024;
  // Up to about a million terms the block results live on the stack (no allocation in a step).
  constexpr std::size_t stack_blocks = 1024;
  const std::size_t n_blocks = (n + block - 1) / block;
  std::array<T, stack_blocks> on_stack;
  std::vector<T> on_heap;
  T* partial = on_stack.data();
  if (n_blocks > stack_blocks) {
    on_heap.assign(n_blocks, identity);
    partial = on_heap.data();
  }
  // One task per block (grain 1): parallel_for's grain of 256 would put every block in one task.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_blocks, 1), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      T value = identity;
      const std::size_t end = std::min(n, (b + 1) * block);
      for (std::size_t i = b * block; i < end; ++i) value = combine(value, term(i));
      partial[b] = value;
    }
  });
  T total = identity;
  for (std::size_t b = 0; b < n_blocks; ++b) total = combine(total, partial[b]);
  return total;
}

/// Sum of term(i) over [0, n) (reproducible, see parallel_reduce).
template <class T, class Term>
T parallel_sum(std::size_t n, T zero, Term&& term) {
  return parallel_reduce(n, zero, std::forward<Term>(term), [](const T& a, const T& b) { return a + b; });
}

/// Maximum of term(i) over [0, n); `lowest` if n == 0.
template <class T, class Term>
T parallel_max(std::size_t n, T lowest, Term&& term) {
  return parallel_reduce(n, lowest, std::forward<Term>(term), [](const T& a, const T& b) { return std::max(a, b); });
}

/// Smallest i in [0, n) with predicate(i) true, or n if there is none (the lowest index wins
/// whatever the thread count). Used to name the first particle whose state is invalid.
template <class Predicate>
std::size_t first_index_where(std::size_t n, Predicate&& predicate) {
  return parallel_reduce(
      n, n, [&](std::size_t i) { return predicate(i) ? i : n; },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
}

}  // namespace sph
