#pragma once
// Command-line parsing under the one exit-code policy (exit_codes.h): CLI11 gives each kind of
// parse error its own exit code (105, 106, 114, ...); a malformed command line is bad input, so
// it exits 2 like every other bad input, and --help exits 0. Header-only: the executables link
// CLI11, the libraries do not.

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common/exit_codes.h"
#include "common/number_text.h"

namespace common {

namespace detail {

// The whole of `text` as a number (std::stod) or a whole number (std::stol); nothing when it is
// not one ("abc", "2x", "", out of the type's range).
inline std::optional<double> parse_number(const std::string& text) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}
inline std::optional<long> parse_whole_number(const std::string& text) {
  try {
    size_t used = 0;
    const long value = std::stol(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// Checks that `input` is a number above (or, with `inclusive`, at least) `bound`; "" when it is,
// else what a person reads. A word is "not a number", not "out of range", and the bound reads
// "0" or "0.5" (CLI11's own checks print the largest double, 309 digits, as the upper bound).
inline CLI::Validator number_from(double bound, bool inclusive) {
  const std::string wanted =
      (inclusive ? "a number of at least " : "a number above ") + number_text(bound);
  return CLI::Validator(
      [bound, inclusive, wanted](std::string& input) -> std::string {
        const std::optional<double> value = parse_number(input);
        if (!value) return "expected " + wanted + ", got \"" + input + "\" (not a number)";
        if (inclusive ? !(*value >= bound) : !(*value > bound))
          return "expected " + wanted + ", got " + input;
        return "";
      },
      inclusive ? ">= " + number_text(bound) : "> " + number_text(bound));
}

}  // namespace detail

// Validators of counts, times and sizes with readable messages (instead of CLI::PositiveNumber
// and CLI::NonNegativeNumber).
inline CLI::Validator positive() {
  return detail::number_from(0, false);
}
inline CLI::Validator non_negative() {
  return detail::number_from(0, true);
}

// The comma-separated items of an option's value ("wcsph,dfsph"). An empty item ("dfsph,,wcsph",
// a trailing comma, or nothing at all) is refused: CLI11's own splitting dropped it silently.
// Throws InputError naming the option.
inline std::vector<std::string> split_list(const std::string& text, const std::string& option) {
  std::vector<std::string> items;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
    if (items.back().empty())
      throw InputError(option + " " + text + ": item " + std::to_string(items.size()) +
                       " is empty; expected comma-separated items without empty ones");
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

// split_list's items as whole numbers. Throws InputError naming the option and the item.
inline std::vector<int> split_int_list(const std::string& text, const std::string& option) {
  std::vector<int> numbers;
  for (const std::string& item : split_list(text, option)) {
    const std::optional<long> value = detail::parse_whole_number(item);
    if (!value || *value != long(int(*value)))
      throw InputError(option + " " + text + ": \"" + item + "\" is not a whole number");
    numbers.push_back(int(*value));
  }
  return numbers;
}

// Checks that `input` is a whole number from `lo` to `hi` (counts with a sensible ceiling, such as
// iterations per frame: a huge one ran for minutes with no output).
inline CLI::Validator whole_number_in(long lo, long hi) {
  const std::string wanted =
      "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, wanted](std::string& input) -> std::string {
        const std::optional<long> value = detail::parse_whole_number(input);
        if (!value) return "expected " + wanted + ", got \"" + input + "\"";
        if (*value < lo || *value > hi) return "expected " + wanted + ", got " + input;
        return "";
      },
      std::to_string(lo) + ".." + std::to_string(hi));
}

// Parses the command line; returns the exit code when the program must stop (help shown, or an
// error printed), nothing when it goes on. Errors are printed as every other error is,
// "PROGRAM: error: WHAT" (exit_codes.h's report_error), with a pointer to --help.
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string program = std::filesystem::path(argc > 0 ? argv[0] : "").filename().string();
    std::cerr << program << ": error: " << e.what() << "\nRun with --help for the options.\n";
    return 2;
  }
}

}  // namespace common
