#pragma once
// Observer (probe) time series as CSV: one header line, one row per recorded time. Rows are
// appended to <path>.partial as they come (flushed, so a long run can be watched) and the file
// takes its final name when the series is closed or destroyed, so a file under the final name is
// always complete.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "libsph/core/state_archive.hpp"

namespace sph {

class TimeSeriesCsv {
 public:
  TimeSeriesCsv(std::filesystem::path path, std::vector<std::string> columns);
  ~TimeSeriesCsv();
  TimeSeriesCsv(const TimeSeriesCsv&) = delete;
  TimeSeriesCsv& operator=(const TimeSeriesCsv&) = delete;

  /// Appends a row (one value per column).
  void record(const std::vector<double>& row);
  std::size_t n_rows() const { return n_rows_; }
  /// Saves the rows written so far, or loads them: the file then holds exactly those rows and
  /// continues after them (checkpoints).
  void checkpoint(StateArchive& archive);
  /// Finishes the file and gives it its final name (also done by the destructor).
  void close();

 private:
  std::filesystem::path path_, partial_;
  std::size_t n_columns_;
  std::ofstream out_;
  std::size_t n_rows_ = 0;
};

}  // namespace sph
