#pragma once
// Plots of CSV columns as PNG (log-log by default), drawn by gnuplot when it is installed. A missing gnuplot
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

struct CsvPlot {
  std::string csv;    ///< file name inside the folder (the series' default)
  std::string png;    ///< file name inside the folder
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  bool logarithmic = true;             ///< log-log axes (false: linear)
  std::string style = "linespoints";   ///< gnuplot style of every series
  int panel_columns = 0;  ///< > 0: one panel per series (titled by it), in this many columns
};

/// Points x, y, z of a CSV coloured by a column, drawn in 3D (e.g. particles by activation time);
/// points with a negative colour value (none) are left out.
struct CsvScatter {
  std::string csv, png, title, colour_label;
  int colour_column = 4;  ///< 1-based; x, y, z are columns 1-3
  double view_rotation_x = 60, view_rotation_z = 30;  ///< gnuplot's `set view` angles [degrees]
};

/// Draws the scatter into folder/png (atomically); false, with a note, if gnuplot failed or is missing.
bool plot_scatter(const std::filesystem::path& folder, const CsvScatter& scatter);

/// Draws the plot into folder/png (written atomically); returns false, with a note on stderr, if
/// gnuplot failed or is missing. Under mpirun only rank 0 draws (as for every file of a run).
bool plot_csv(const std::filesystem::path& folder, const CsvPlot& plot);

}  // namespace cardiosph
