#include "common/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/checked_file.h"

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
  if (x1 == x0) x1 = x0 + 1;
  if (y1 == y0) y1 = y0 + 1;
  const double top = offset + kTop, bottom = offset + kPanelHeight - kBottom;
  auto px = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * (kWidth - kLeft - kRight); };
  auto py = [&](double y) { return bottom - (ty(y) - y0) / (y1 - y0) * (bottom - top); };
  s << "<rect x=\"" << kLeft << "\" y=\"" << top << "\" width=\"" << kWidth - kLeft - kRight
    << "\" height=\"" << bottom - top << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (int k = 0; k <= 4; ++k) {
    const double fx = x0 + (x1 - x0) * k / 4, fy = y0 + (y1 - y0) * k / 4;
    const double yv = log_y ? std::pow(10.0, fy) : fy;
    s << "<text x=\"" << px(fx) << "\" y=\"" << bottom + 16 << "\" text-anchor=\"middle\">" << fx
      << "</text>\n";
    s << "<text x=\"" << kLeft - 6 << "\" y=\"" << py(yv) + 4 << "\" text-anchor=\"end\">" << yv
      << "</text>\n<line x1=\"" << kLeft << "\" x2=\"" << kWidth - kRight << "\" y1=\"" << py(yv)
      << "\" y2=\"" << py(yv) << "\" stroke=\"#ddd\"/>\n";
  }
  const double middle = (top + bottom) / 2;
  s << "<text x=\"" << (kLeft + kWidth - kRight) / 2 << "\" y=\"" << bottom + 36
    << "\" text-anchor=\"middle\">" << panel.x_label << "</text>\n<text x=\"18\" y=\"" << middle
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 " << middle << ")\">" << panel.y_label
    << (log_y ? " (log)" : "") << "</text>\n";
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#333333"};
  for (size_t k = 0; k < panel.series.size(); ++k) {
    const auto& ser = panel.series[k];
    s << "<polyline fill=\"none\" stroke-width=\"1.8\" stroke=\"" << colours[k % 6]
      << "\" points=\"";
    for (size_t i = 0; i < ser.x.size(); ++i)
      if (std::isfinite(ser.y[i]) && !(log_y && ser.y[i] <= 0))
        s << px(ser.x[i]) << "," << py(ser.y[i]) << " ";
    s << "\"/>\n<text x=\"" << kWidth - kRight + 10 << "\" y=\"" << top + 16 + 18 * double(k)
      << "\" fill=\"" << colours[k % 6] << "\">" << ser.name << "</text>\n";
  }
}

}  // namespace

void write_panels(const std::string& path, const std::string& title,
                  const std::vector<PlotPanel>& panels) {
  const double height = kTitleHeight + kPanelHeight * double(std::max<size_t>(1, panels.size()));
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
       "fill=\"white\"/>\n<text x=\""
    << kWidth / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << title << "</text>\n";
  for (size_t k = 0; k < panels.size(); ++k)
    draw_panel(s, panels[k], kTitleHeight + kPanelHeight * double(k));
  s << "</svg>\n";
  write_file_atomically(path, s.str());
}

void write_line_plot(const std::string& path, const std::string& title, const std::string& x_label,
                     const std::string& y_label, const std::vector<PlotSeries>& series,
                     bool log_y) {
  write_panels(path, title, {PlotPanel{x_label, y_label, series, log_y}});
}

}  // namespace common
