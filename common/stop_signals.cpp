#include "common/stop_signals.h"

#include <csignal>

#include "common/exit_codes.h"

namespace common {

namespace {

std::atomic<bool> stop_requested{false};

void request_stop(int) {
  stop_requested.store(true);
}

}  // namespace

const std::atomic<bool>* stop_flag() {
  return &stop_requested;
}

void catch_stop_signals() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

void throw_if_stopped(const std::atomic<bool>* stop, const std::string& where,
                      const std::string& kept) {
  if (stop && stop->load())
    throw Interrupted("interrupted " + where + (kept.empty() ? "" : "; " + kept));
}

}  // namespace common
