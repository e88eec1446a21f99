#pragma once
// Runs one command of a fuzzing case as a child process: its output to a log file, a wall-clock
// bound (the whole process group is killed past it), a memory limit (RLIMIT_DATA, so that the
// scene size estimate refuses what does not fit, as on a small machine) and one OpenMP thread.

#include <filesystem>
#include <string>
#include <vector>

namespace fuzz {

struct ChildOutcome {
  enum class Kind { kExited, kSignalled, kTimedOut } kind = Kind::kExited;
  int code = 0;  // exit code, or the signal's number
  double seconds = 0;
};

ChildOutcome run_child(const std::vector<std::string>& argv, const std::filesystem::path& log,
                       double timeout_s, double memory_bytes);

// "exit 2", "signal 11", "timeout after 60 s": for reports.
std::string describe(const ChildOutcome& outcome);

}  // namespace fuzz
