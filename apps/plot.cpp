#include "apps/plot.hpp"

#include <cstdlib>
#include <iostream>
#include <sstream>

#include "libsph/core/communicator.hpp"
#include "libsph/io/atomic_file.hpp"

namespace cardiosph {

namespace {
/// Runs the gnuplot script that writes png + ".partial", then renames it; `data` names the files
/// that stay complete without the picture. On several ranks, rank 0 alone draws (its files are the
/// run's; the others report success).
bool run_gnuplot(const std::filesystem::path& folder, const std::string& png, const std::string& script,
                 const std::string& data) {
  namespace fs = std::filesystem;
  if (!sph::Communicator::world().is_root()) return true;
  const std::string partial = png + ".partial", script_name = png + ".gp";
  sph::write_file_atomically(folder / script_name, script);
  const std::string command = "cd '" + folder.string() + "' && gnuplot '" + script_name + "' 2> gnuplot.log";
  if (std::system(command.c_str()) == 0) {
    sph::commit_temporary(folder / partial, folder / png);
    fs::remove(folder / "gnuplot.log");
    return true;
  }
  fs::remove(folder / partial);
  std::cerr << "the plot " << png << " was not made (is gnuplot installed? see " << (folder / "gnuplot.log").string()
            << "); " << (data.empty() ? std::string("the CSV files are") : data + " is") << " complete\n";
  return false;
}
}  // namespace

bool plot_csv(const std::filesystem::path& folder, const CsvPlot& plot) {
  const std::string partial = plot.png + ".partial";
  bool long_titles = false;  // long legends go below the plot, where they do not squeeze it
  for (const auto& series : plot.series) long_titles = long_titles || series.title.size() > 30;
  std::ostringstream script;
  const bool panels = plot.panel_columns > 0;
  const std::size_t rows = panels ? (plot.series.size() + std::size_t(plot.panel_columns) - 1) / std::size_t(plot.panel_columns) : 1;
  script << "set terminal pngcairo size " << (panels ? 1100 : 900) << "," << (panels ? 60 + 170 * rows : 650)
         << " enhanced font 'sans," << (panels ? 9 : 11) << "'\n"
         << "set output '" << partial << "'\n"
         << "set datafile separator ','\n"
         << (plot.logarithmic ? "set logscale xy\n" : "")
         << "set grid\n";
  auto series_source = [&](const PlotSeries& series) {
    std::ostringstream s;
    s << "'" << (series.csv.empty() ? plot.csv : series.csv) << "' using " << series.x_column << ":" << series.y_column
      << " skip 1 with " << plot.style << (plot.style == "linespoints" ? " lw 2 pt 7" : " lw 2");
    return s.str();
  };
  if (panels) {
    script << "set multiplot layout " << rows << "," << plot.panel_columns << " title '" << plot.title << "' noenhanced\n"
           << "set xlabel '" << plot.x_label << "' noenhanced\nset ylabel '" << plot.y_label << "' noenhanced\n";
    for (const auto& series : plot.series)
      script << "set title '" << series.title << "' noenhanced\nplot " << series_source(series) << " notitle\n";
    script << "unset multiplot\n";
  } else {
    script << (long_titles ? "set key below\n" : "set key outside right top\n")
           << "set title '" << plot.title << "' noenhanced\n"
           << "set xlabel '" << plot.x_label << "' noenhanced\nset ylabel '" << plot.y_label << "' noenhanced\n"
           << "plot ";
    for (std::size_t s = 0; s < plot.series.size(); ++s)
      script << (s ? ", " : "") << series_source(plot.series[s]) << " title '" << plot.series[s].title << "' noenhanced";
    script << "\n";
  }
  return run_gnuplot(folder, plot.png, script.str(), plot.csv);
}

bool plot_scatter(const std::filesystem::path& folder, const CsvScatter& scatter) {
  std::ostringstream script;
  script << "set terminal pngcairo size 900,800 enhanced font 'sans,11'\n"
         << "set output '" << scatter.png << ".partial'\n"
         << "set datafile separator ','\n"
         << "set view " << scatter.view_rotation_x << "," << scatter.view_rotation_z << "\nset view equal xyz\nset ticslevel 0\n"
         << "set xlabel 'x [mm]'\nset ylabel 'y [mm]'\nset zlabel 'z [mm]'\n"
         << "set palette rgb 33,13,10\nset cblabel '" << scatter.colour_label << "' noenhanced\n"
         << "set title '" << scatter.title << "' noenhanced\n"
         << "splot '" << scatter.csv << "' using 1:2:3:($" << scatter.colour_column << " >= 0 ? $" << scatter.colour_column
         << " : 1/0) skip 1 with points pt 7 ps 0.7 palette notitle\n";
  return run_gnuplot(folder, scatter.png, script.str(), scatter.csv);
}

}  // namespace cardiosph
