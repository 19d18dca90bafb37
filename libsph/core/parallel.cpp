#include "libsph/core/parallel.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

namespace sph {

struct ThreadLimit::Impl {
  std::unique_ptr<tbb::global_control> control;
};

ThreadLimit::ThreadLimit(std::size_t n_threads) : impl_(std::make_unique<Impl>()) {
  if (n_threads > 0)
    impl_->control = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, n_threads);
}

ThreadLimit::~ThreadLimit() = default;

std::size_t active_thread_count() {
  return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
}

}  // namespace sph
