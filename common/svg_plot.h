#pragma once
// Line plots as SVG (loss curves, error against horizon, spill metrics over time): no plotting
// library needed, and a browser or the README shows them directly. The one plotter of the
// project: every figure is panels of line series.

#include <string>
#include <vector>

namespace common {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
};

struct PlotPanel {
  std::string x_label, y_label;
  std::vector<PlotSeries> series;
  bool log_y = false;  // non-positive values are skipped on a log axis
};

// Panels stacked under one title, as an SVG document's text.
std::string panels_svg(const std::string& title, const std::vector<PlotPanel>& panels);

// The same, written atomically (a temporary file renamed into place).
void write_panels(const std::string& path, const std::string& title,
                  const std::vector<PlotPanel>& panels);

// One panel.
void write_line_plot(const std::string& path, const std::string& title, const std::string& x_label,
                     const std::string& y_label, const std::vector<PlotSeries>& series, bool log_y);

}  // namespace common
