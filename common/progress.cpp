#include "common/progress.h"

#include <cstdio>

namespace common {

namespace {
std::string format_seconds(double s) {
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600), int(s / 60) % 60);
  else if (s >= 60)
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%.1fs", s);
  return buf;
}
}  // namespace

ProgressReporter::ProgressReporter(std::ostream& out, bool terminal, long total, std::string what)
    : out_(out),
      terminal_(terminal),
      total_(total > 0 ? total : 1),
      what_(std::move(what)),
      start_(std::chrono::steady_clock::now()),
      last_line_(start_) {}

void ProgressReporter::update(long done, const std::string& detail) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction = double(done) / double(total_);
  // Nothing done yet gives no rate to extrapolate: say so rather than a zero.
  const std::string eta =
      done > 0 ? format_seconds(elapsed * (1 - fraction) / fraction) : std::string("unknown");
  const std::string timing = " elapsed " + format_seconds(elapsed) + " eta " + eta;
  if (terminal_) {
    const int width = 30, filled = int(fraction * width + 0.5);
    out_ << "\r" << what_ << " [" << std::string(size_t(filled), '#')
         << std::string(size_t(width - filled), ' ') << "] " << int(fraction * 100 + 0.5) << "% "
         << done << "/" << total_ << " " << detail << timing << "\033[K" << std::flush;
    return;
  }
  const int decile = int(fraction * 10);
  if (decile != last_decile_ || std::chrono::duration<double>(now - last_line_).count() > 30) {
    last_decile_ = decile;
    last_line_ = now;
    out_ << what_ << ": " << done << "/" << total_ << " (" << int(fraction * 100 + 0.5) << "%) "
         << detail << timing << "\n"
         << std::flush;
  }
}

void ProgressReporter::finish(const std::string& detail) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) out_ << "\n";
  out_ << what_ << ": done in " << format_seconds(elapsed) << " " << detail << "\n" << std::flush;
}

}  // namespace common
