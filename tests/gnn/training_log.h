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
    while (cells.size() < 7) cells.push_back("");
    rows.push_back(cells[0] + "," + cells[1] + "," + cells[2] + "," + cells[5] + "," + cells[6]);
  }
  return rows;
}

}  // namespace training_log
