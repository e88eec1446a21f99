#pragma once
// Wall-clock timing of the simulator's parts (TimeSplit, run and benchmark summaries).

#include <chrono>

namespace common {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Adds the seconds between its construction and its end of scope to `total`.
class ScopedTimer {
 public:
  explicit ScopedTimer(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() { total_ += seconds_since(t0_); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace common
