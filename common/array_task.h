#pragma once
// One task of a job split N ways: given as "I/N" on a command line (--shard), or the Slurm job
// array task this process is (SLURM_ARRAY_TASK_ID less SLURM_ARRAY_TASK_MIN, of
// SLURM_ARRAY_TASK_COUNT), so that an array job needs no option.

#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

#include "common/exit_codes.h"

namespace common {

struct ArrayTask {
  int index = 0, count = 1;  // task I of N, 0 <= I < N
};

// "I/N"; throws InputError naming `option` (e.g. "--shard") unless 0 <= I < N.
inline ArrayTask parse_array_task(const std::string& text, const std::string& option) {
  ArrayTask task;
  char slash = 0;
  std::istringstream in(text);
  if (!(in >> task.index >> slash >> task.count) || slash != '/' || !in.eof() || task.count < 1 ||
      task.index < 0 || task.index >= task.count)
    throw InputError(option + " " + text +
                     ": expected I/N, the shard I of N with 0 <= I < N (e.g. 0/4)");
  return task;
}

// The Slurm array task this process is, if it is one; throws InputError for variables that do
// not read as one.
inline std::optional<ArrayTask> slurm_array_task() {
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  if (!id || !count) return std::nullopt;
  const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
  const auto number = [](const char* name, const char* text) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (*text == '\0' || *end != '\0')
      throw InputError(std::string(name) + "=" + text + ": not a whole number");
    return v;
  };
  const long index =
      number("SLURM_ARRAY_TASK_ID", id) - (min ? number("SLURM_ARRAY_TASK_MIN", min) : 0);
  const long n = number("SLURM_ARRAY_TASK_COUNT", count);
  if (index < 0 || index >= n)
    throw InputError("SLURM_ARRAY_TASK_ID=" + std::string(id) + ": not a task of an array of " +
                     count + " (give --array=0-" + std::to_string(n - 1) + ", or --shard I/N)");
  return ArrayTask{int(index), int(n)};
}

}  // namespace common
