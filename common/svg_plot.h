#pragma once
// Line plots as SVG (loss curves, error against horizon): no plotting library needed, and a
// browser or the README shows them directly.

#include <string>
#include <vector>

namespace common {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
};

// Writes the plot atomically; non-positive values are skipped on a log axis.
void write_line_plot(const std::string& path, const std::string& title, const std::string& x_label,
                     const std::string& y_label, const std::vector<PlotSeries>& series, bool log_y);

}  // namespace common
