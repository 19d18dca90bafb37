#pragma once
// Observer (probe) time series as CSV: one header line, one row per recorded time. The whole file
// is rewritten atomically at each flush, so it is always complete.

#include <filesystem>
#include <string>
#include <vector>

namespace sph {

class TimeSeriesCsv {
 public:
  TimeSeriesCsv(std::filesystem::path path, std::vector<std::string> columns);
  /// Appends a row (one value per column) and rewrites the file.
  void record(const std::vector<double>& row);
  std::size_t n_rows() const { return rows_.size(); }

 private:
  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> rows_;
};

}  // namespace sph
