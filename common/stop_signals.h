#pragma once
// Ctrl-C and SIGTERM as a request that long work polls (common/exit_codes.h's 130). The handler
// only sets a flag: the command finishes the write it is in (a checkpoint, an HDF5 frame, a
// trajectory), removes its staging folder and exits 130 with a message saying what was kept.
// Killed by the signal instead, it would leave `.OUT.partial-PID` folders and say nothing.

#include <atomic>
#include <string>

#include "common/exit_codes.h"

namespace common {

// The flag the handlers set. A signal handler can reach only static storage, so this is the
// process's one flag, as the signals are the process's.
const std::atomic<bool>* stop_flag();

// Installs the handlers of SIGINT and SIGTERM that set stop_flag(). A command calls it once it
// polls the flag; before, a signal ends the process at once (nothing was written yet).
void catch_stop_signals();

// Throws Interrupted("interrupted " + message()) when `stop` is set; null never stops. The
// message ("at step 9 of 100; RUN/last.pt keeps step 5") is built only then: loops poll this
// every training step or rollout frame.
template <class Message>
void throw_if_stopped(const std::atomic<bool>* stop, const Message& message) {
  if (stop && stop->load()) throw Interrupted("interrupted " + message());
}

}  // namespace common
