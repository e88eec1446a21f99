#pragma once
// One exit-code policy for spill-sim, spill-train and spill-infer: the same kind of error exits
// with the same code from every executable.
//   0   success
//   1   the work failed (a simulation that blew up, an I/O failure, a bug)
//   2   bad input: a config, scene, dataset, checkpoint, state file or output path the user gave
//   130 interrupted (Ctrl-C, SIGTERM); nothing half-written is left
// Libraries throw; only main() catches and calls report_error.

#include <new>
#include <ostream>
#include <stdexcept>
#include <string>

namespace common {

// Base of every error caused by what the user gave us (exit code 2). ConfigError,
// OutputPathError, and the learning stack's DatasetError and CheckpointError derive from it.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A run stopped on request (exit code 130).
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline int exit_code(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return 2;
  if (dynamic_cast<const Interrupted*>(&e)) return 130;
  return 1;
}

// Prints "PROGRAM: error: WHAT" (or "PROGRAM: WHAT" for an interruption) and returns the code.
// Running out of memory is said in words, with `smaller` saying how to make this command's work
// smaller (what it allocates: particles, a reach's cells, a forecast's elements).
inline int report_error(std::ostream& out, const std::string& program, const std::exception& e,
                        const std::string& smaller = "use fewer or larger particles") {
  const int code = exit_code(e);
  // The size checks estimate memory from below; what still does not fit ends here.
  const std::string what = dynamic_cast<const std::bad_alloc*>(&e)
                               ? "out of memory: the work needs more than this process may use "
                                 "(std::bad_alloc); " +
                                     smaller + ", or a machine with more memory"
                               : std::string(e.what());
  out << "\n" << program << (code == 130 ? ": " : ": error: ") << what << "\n";
  return code;
}

}  // namespace common
