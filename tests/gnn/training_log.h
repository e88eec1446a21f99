#pragma once
// Reading a training run's RUN/log.csv in tests.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace training_log {

// log.csv rows without the timing columns (elapsed_s, steps_per_s): what two runs that train
// alike must share row for row.
inline std::vector<std::string> rows_without_timing(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
    while (cells.size() < 8) cells.push_back("");
    rows.push_back(cells[0] + "," + cells[1] + "," + cells[2] + "," + cells[5] + "," + cells[6] +
                   "," + cells[7]);
  }
  return rows;
}

// One column of log.csv by its header name: a cell per row ("" where the row has none).
inline std::vector<std::string> column(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file);
  std::vector<std::string> out;
  long index = -1;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
    if (index < 0) {
      for (size_t k = 0; k < cells.size(); ++k)
        if (cells[k] == name) index = long(k);
      if (index < 0) return out;
      continue;
    }
    out.push_back(size_t(index) < cells.size() ? cells[size_t(index)] : "");
  }
  return out;
}

}  // namespace training_log
