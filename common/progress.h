#pragma once
// Progress of a long run: a redrawn bar on a terminal, plain lines (every 10 % or 30 s) otherwise.

#include <chrono>
#include <ostream>
#include <string>

namespace common {

class ProgressReporter {
 public:
  ProgressReporter(std::ostream& out, bool terminal, long total, std::string what);
  // `done` of `total` units finished; `detail` is shown after the bar.
  void update(long done, const std::string& detail);
  void finish(const std::string& detail);

 private:
  std::ostream& out_;
  bool terminal_;
  long total_;
  std::string what_;
  std::chrono::steady_clock::time_point start_, last_line_;
  int last_decile_ = -1;
};

}  // namespace common
