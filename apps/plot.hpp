#pragma once
// Log-log plots of CSV columns as PNG, drawn by gnuplot when it is installed. A missing gnuplot
// costs the picture only: the CSV is the result, and a note says where the plot would have been.

#include <filesystem>
#include <string>
#include <vector>

namespace cardiosph {

struct PlotSeries {
  int x_column = 1;  ///< 1-based CSV columns
  int y_column = 2;
  std::string title;
  std::string csv;  ///< data file relative to the folder; empty: the plot's csv
};

struct LogLogPlot {
  std::string csv;    ///< file name inside the folder (the series' default)
  std::string png;    ///< file name inside the folder
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
};

/// Draws the plot into folder/png (written atomically); returns false, with a note on stderr, if
/// gnuplot failed or is missing.
bool plot_log_log(const std::filesystem::path& folder, const LogLogPlot& plot);

}  // namespace cardiosph
