#include "common/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/axis_ticks.h"
#include "common/checked_file.h"
#include "common/html_report.h"

namespace common {

namespace {

constexpr double kWidth = 720, kPanelHeight = 380, kTitleHeight = 40;
constexpr double kLeft = 80, kRight = 150, kTop = 20, kBottom = 50;

// Draws `panel` into `s` with its top edge at `offset`.
void draw_panel(std::ostringstream& s, const PlotPanel& panel, double offset) {
  const bool log_y = panel.log_y;
  auto ty = [&](double y) { return log_y ? std::log10(y) : y; };
  double x0 = std::numeric_limits<double>::max(), x1 = std::numeric_limits<double>::lowest();
  double y0 = x0, y1 = x1;
  for (const auto& ser : panel.series)
    for (size_t k = 0; k < ser.x.size(); ++k) {
      if (!std::isfinite(ser.y[k]) || (log_y && ser.y[k] <= 0)) continue;
      x0 = std::min(x0, ser.x[k]);
      x1 = std::max(x1, ser.x[k]);
      y0 = std::min(y0, ty(ser.y[k]));
      y1 = std::max(y1, ty(ser.y[k]));
    }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  // Round ticks, the axes widened to whole steps around the data.
  const AxisTicks xt = linear_ticks(x0, x1);
  const AxisTicks yt = log_y ? log_ticks(y0, y1) : linear_ticks(y0, y1);
  x0 = xt.lo, x1 = xt.hi, y0 = yt.lo, y1 = yt.hi;
  const double top = offset + kTop, bottom = offset + kPanelHeight - kBottom;
  auto px = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * (kWidth - kLeft - kRight); };
  auto py_axis = [&](double v) { return bottom - (v - y0) / (y1 - y0) * (bottom - top); };
  auto py = [&](double y) { return py_axis(ty(y)); };
  s << "<rect x=\"" << kLeft << "\" y=\"" << top << "\" width=\"" << kWidth - kLeft - kRight
    << "\" height=\"" << bottom - top << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (size_t k = 0; k < xt.values.size(); ++k)
    s << "<text x=\"" << px(xt.values[k]) << "\" y=\"" << bottom + 16
      << "\" text-anchor=\"middle\">" << xt.labels[k] << "</text>\n";
  for (size_t k = 0; k < yt.values.size(); ++k) {
    const double y = py_axis(yt.values[k]);
    s << "<text x=\"" << kLeft - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
      << yt.labels[k] << "</text>\n<line x1=\"" << kLeft << "\" x2=\"" << kWidth - kRight
      << "\" y1=\"" << y << "\" y2=\"" << y << "\" stroke=\"#ddd\"/>\n";
  }
  const double middle = (top + bottom) / 2;
  s << "<text x=\"" << (kLeft + kWidth - kRight) / 2 << "\" y=\"" << bottom + 36
    << "\" text-anchor=\"middle\">" << html_escape(panel.x_label) << "</text>\n<text x=\"18\" y=\""
    << middle << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 " << middle << ")\">"
    << html_escape(panel.y_label) << (log_y ? " (log)" : "") << "</text>\n";
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#333333"};
  for (size_t k = 0; k < panel.series.size(); ++k) {
    const auto& ser = panel.series[k];
    s << "<polyline fill=\"none\" stroke-width=\"1.8\" stroke=\"" << colours[k % 6]
      << "\" points=\"";
    for (size_t i = 0; i < ser.x.size(); ++i)
      if (std::isfinite(ser.y[i]) && !(log_y && ser.y[i] <= 0))
        s << px(ser.x[i]) << "," << py(ser.y[i]) << " ";
    s << "\"/>\n<text x=\"" << kWidth - kRight + 10 << "\" y=\"" << top + 16 + 18 * double(k)
      << "\" fill=\"" << colours[k % 6] << "\">" << html_escape(ser.name) << "</text>\n";
  }
}

}  // namespace

std::string panels_svg(const std::string& title, const std::vector<PlotPanel>& panels) {
  const double height = kTitleHeight + kPanelHeight * double(std::max<size_t>(1, panels.size()));
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
       "fill=\"white\"/>\n<text x=\""
    << kWidth / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << html_escape(title)
    << "</text>\n";
  for (size_t k = 0; k < panels.size(); ++k)
    draw_panel(s, panels[k], kTitleHeight + kPanelHeight * double(k));
  s << "</svg>\n";
  return s.str();
}

void write_panels(const std::string& path, const std::string& title,
                  const std::vector<PlotPanel>& panels) {
  write_file_atomically(path, panels_svg(title, panels));
}

void write_line_plot(const std::string& path, const std::string& title, const std::string& x_label,
                     const std::string& y_label, const std::vector<PlotSeries>& series,
                     bool log_y) {
  write_panels(path, title, {PlotPanel{x_label, y_label, series, log_y}});
}

}  // namespace common
