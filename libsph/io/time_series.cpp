#include "libsph/io/time_series.hpp"

#include <iomanip>
#include <iterator>
#include <stdexcept>

#include "libsph/io/atomic_file.hpp"

namespace sph {

TimeSeriesCsv::TimeSeriesCsv(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), partial_(path_.string() + ".partial"), n_columns_(columns.size()) {
  out_.open(partial_, std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write the time series '" + partial_.string() + "'");
  for (std::size_t c = 0; c < columns.size(); ++c) out_ << (c ? "," : "") << columns[c];
  out_ << '\n' << std::setprecision(12);
  out_.flush();
}

TimeSeriesCsv::~TimeSeriesCsv() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; the .partial file is left for inspection.
  }
}

void TimeSeriesCsv::record(const std::vector<double>& row) {
  if (row.size() != n_columns_) throw std::logic_error("time series '" + path_.string() + "': wrong row size");
  for (std::size_t c = 0; c < row.size(); ++c) out_ << (c ? "," : "") << row[c];
  out_ << '\n';
  out_.flush();
  ++n_rows_;
}

void TimeSeriesCsv::checkpoint(StateArchive& archive) {
  std::string rows;
  if (archive.saving()) {
    out_.flush();
    std::ifstream in(partial_, std::ios::binary);
    rows.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) throw std::runtime_error("cannot read back the time series '" + partial_.string() + "'");
  }
  archive.io("rows", rows);
  archive.io("row_count", n_rows_);
  if (archive.loading()) {
    out_.close();
    out_.open(partial_, std::ios::binary | std::ios::trunc);
    out_ << rows;
    out_.flush();
    if (!out_) throw std::runtime_error("cannot write the time series '" + partial_.string() + "'");
  }
}

void TimeSeriesCsv::close() {
  if (!out_.is_open()) return;
  out_.close();
  commit_temporary(partial_, path_);
}

}  // namespace sph
