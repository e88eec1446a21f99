#include "common/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace common {

void write_line_plot(const std::string& path, const std::string& title, const std::string& x_label,
                     const std::string& y_label, const std::vector<PlotSeries>& series,
                     bool log_y) {
  const double W = 720, H = 420, left = 80, right = 150, top = 40, bottom = 50;
  auto ty = [&](double y) { return log_y ? std::log10(y) : y; };
  double x0 = std::numeric_limits<double>::max(), x1 = std::numeric_limits<double>::lowest();
  double y0 = x0, y1 = x1;
  for (const auto& s : series)
    for (size_t k = 0; k < s.x.size(); ++k) {
      if (!std::isfinite(s.y[k]) || (log_y && s.y[k] <= 0)) continue;
      x0 = std::min(x0, s.x[k]);
      x1 = std::max(x1, s.x[k]);
      y0 = std::min(y0, ty(s.y[k]));
      y1 = std::max(y1, ty(s.y[k]));
    }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x1 == x0) x1 = x0 + 1;
  if (y1 == y0) y1 = y0 + 1;
  auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * (W - left - right); };
  auto py = [&](double y) { return H - bottom - (ty(y) - y0) / (y1 - y0) * (H - top - bottom); };
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
       "fill=\"white\"/>\n<text x=\""
    << W / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << title << "</text>\n";
  s << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << W - left - right
    << "\" height=\"" << H - top - bottom << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (int k = 0; k <= 4; ++k) {
    const double fx = x0 + (x1 - x0) * k / 4, fy = y0 + (y1 - y0) * k / 4;
    const double yv = log_y ? std::pow(10.0, fy) : fy;
    s << "<text x=\"" << px(fx) << "\" y=\"" << H - bottom + 16 << "\" text-anchor=\"middle\">"
      << fx << "</text>\n";
    s << "<text x=\"" << left - 6 << "\" y=\"" << py(yv) + 4 << "\" text-anchor=\"end\">" << yv
      << "</text>\n<line x1=\"" << left << "\" x2=\"" << W - right << "\" y1=\"" << py(yv)
      << "\" y2=\"" << py(yv) << "\" stroke=\"#ddd\"/>\n";
  }
  s << "<text x=\"" << (left + W - right) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">"
    << x_label << "</text>\n<text x=\"18\" y=\"" << H / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 " << H / 2 << ")\">" << y_label
    << (log_y ? " (log)" : "") << "</text>\n";
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#333333"};
  for (size_t k = 0; k < series.size(); ++k) {
    const auto& ser = series[k];
    s << "<polyline fill=\"none\" stroke-width=\"1.8\" stroke=\"" << colours[k % 6]
      << "\" points=\"";
    for (size_t i = 0; i < ser.x.size(); ++i)
      if (std::isfinite(ser.y[i]) && !(log_y && ser.y[i] <= 0))
        s << px(ser.x[i]) << "," << py(ser.y[i]) << " ";
    s << "\"/>\n<text x=\"" << W - right + 10 << "\" y=\"" << top + 16 + 18 * double(k)
      << "\" fill=\"" << colours[k % 6] << "\">" << ser.name << "</text>\n";
  }
  s << "</svg>\n";
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << s.str();
    if (!out) throw std::runtime_error(path + ": cannot write the plot");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace common
