#include "libsph/io/time_series.hpp"

#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "libsph/io/atomic_file.hpp"

namespace sph {

TimeSeriesCsv::TimeSeriesCsv(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {}

void TimeSeriesCsv::record(const std::vector<double>& row) {
  if (row.size() != columns_.size()) throw std::logic_error("time series '" + path_.string() + "': wrong row size");
  rows_.push_back(row);
  std::ostringstream s;
  for (std::size_t c = 0; c < columns_.size(); ++c) s << (c ? "," : "") << columns_[c];
  s << '\n' << std::setprecision(12);
  for (const auto& r : rows_) {
    for (std::size_t c = 0; c < r.size(); ++c) s << (c ? "," : "") << r[c];
    s << '\n';
  }
  write_file_atomically(path_, s.str());
}

}  // namespace sph
