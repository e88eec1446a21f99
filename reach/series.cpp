#include "reach/series.h"

#include <cctype>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace reach {

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  return cells;
}

// Seconds since the epoch of `text` read with the strftime `format`, as if UTC (only
// differences are used, so the zone does not matter).
bool parse_date(const std::string& text, const std::string& format, double& seconds) {
  std::tm tm{};
  std::istringstream in(text);
  in >> std::ws >> std::get_time(&tm, format.c_str());
  if (in.fail()) return false;
  seconds = double(timegm(&tm));
  return true;
}

bool parse_number(const std::string& text, double& value) {
  try {
    size_t used = 0;
    value = std::stod(text, &used);
    for (size_t k = used; k < text.size(); ++k)
      if (!std::isspace(static_cast<unsigned char>(text[k]))) return false;
    return std::isfinite(value);
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

Hydrograph load_series(const SeriesConfig& s, const std::string& config_file,
                       const std::string& pointer) {
  if (s.value) return Hydrograph(*s.value);
  std::vector<std::pair<double, double>> points;
  if (!s.points.empty()) {
    for (const auto& p : s.points) points.push_back({p[0], p[1]});
  } else {
    std::ifstream in(s.file);
    if (!in) throw ConfigError(config_file, pointer + "/file", "cannot open " + s.file);
    std::string line;
    std::getline(in, line);  // the header
    int number = 1;
    double first = 0;
    const bool from_given = !s.from.empty();
    if (from_given) {
      const bool ok = s.time_format == "seconds" ? parse_number(s.from, first)
                                                 : parse_date(s.from, s.time_format, first);
      if (!ok)
        throw ConfigError(config_file, pointer + "/from",
                          "\"" + s.from + "\" does not read as " + s.time_format);
    }
    while (std::getline(in, line)) {
      ++number;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const auto cells = split_csv(line);
      const auto where = s.file + ":" + std::to_string(number);
      if (int(cells.size()) <= std::max(s.time_column, s.value_column))
        throw ConfigError(config_file, pointer + "/file",
                          where + ": expected at least " +
                              std::to_string(std::max(s.time_column, s.value_column) + 1) +
                              " columns, got " + std::to_string(cells.size()));
      double t = 0, v = 0;
      const bool time_ok = s.time_format == "seconds"
                               ? parse_number(cells[size_t(s.time_column)], t)
                               : parse_date(cells[size_t(s.time_column)], s.time_format, t);
      if (!time_ok)
        throw ConfigError(config_file, pointer + "/time_format",
                          where + ": time \"" + cells[size_t(s.time_column)] +
                              "\" does not read as " + s.time_format);
      if (!parse_number(cells[size_t(s.value_column)], v))
        throw ConfigError(
            config_file, pointer + "/file",
            where + ": value \"" + cells[size_t(s.value_column)] + "\" is not a number");
      if (points.empty() && !from_given) first = t;
      points.push_back({t - first, v * s.scale});
    }
    if (points.empty()) throw ConfigError(config_file, pointer + "/file", s.file + ": no rows");
  }
  try {
    return Hydrograph(points);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(config_file, pointer, e.what());
  }
}

}  // namespace reach
