#include "common/stop_signals.h"

#include <csignal>

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

}  // namespace common
