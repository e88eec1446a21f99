#pragma once
// Command-line parsing under the one exit-code policy (exit_codes.h): CLI11 gives each kind of
// parse error its own exit code (105, 106, 114, ...); a malformed command line is bad input, so
// it exits 2 like every other bad input, and --help exits 0. Header-only: the executables link
// CLI11, the libraries do not.

#include <CLI/CLI.hpp>
#include <optional>

namespace common {

// Parses the command line; returns the exit code when the program must stop (help shown, or an
// error printed), nothing when it goes on.
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
}

}  // namespace common
